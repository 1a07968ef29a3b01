#pragma once

// Where the files the binary reads at run time lie (shaders, the built web client, the accuracy
// tables): `share/penumbra/<part>` under the nearest folder above the running binary that has it.
// An install puts the binary in PREFIX/bin and those files in PREFIX/share/penumbra; a build tree
// gets BUILD/share/penumbra/* as links into the source tree at configure time. No path is compiled
// in, so an installed tree works wherever it is moved.

#include <filesystem>
#include <optional>
#include <string_view>

namespace penumbra::base {

// Nothing when no folder above the binary has share/penumbra/<part>.
std::optional<std::filesystem::path> data_dir(std::string_view part);

// The user's cache folder for Penumbra, where what is measured or converted once is kept (the
// start-up quality table, the CT converted by scripts/cranium-ct.py): $XDG_CACHE_HOME/penumbra,
// else ~/.cache/penumbra; nothing without either variable. It may not exist yet.
std::optional<std::filesystem::path> user_cache_dir();

// The demo data folder that scripts/demo-data.sh makes in the user's cache folder: the CT it
// converts beside links to the MRI heads. It may not exist.
std::optional<std::filesystem::path> demo_data_dir();

// InVesalius' head CT (Debian's invesalius-examples) where scripts/demo-data.sh converted it into
// the demo data folder; nothing before that ran.
std::optional<std::filesystem::path> demo_ct_path();

}  // namespace penumbra::base
