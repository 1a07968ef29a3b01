#pragma once

// The accuracy table's file form, "penumbra-accuracy-1" (docs/accuracy/README.md): written by
// `penumbra bench accuracy --json` and by `penumbra serve`'s start-up measurement, read by both.

#include <penumbra/base/result.hpp>
#include <penumbra/quality/table.hpp>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::quality {

// The table and the presets chosen from it, as JSON text.
std::string table_json(const Table& table, const std::vector<Preset>& presets);

// Reads a table from JSON text. Every error is "invalid_table" and its `where` is `where`
// followed by the JSON pointer of the offending member. Points of a mode this build does not
// know are skipped (a table from a newer build still serves with the modes it shares).
base::Result<Table> parse_table(std::string_view json_text, const std::string& where);

// Reads the file at `path`: "not_found" when it cannot be opened, else as parse_table with the
// path as `where`.
base::Result<Table> read_table_file(const std::filesystem::path& path);

// Writes table_json through a temporary file and a rename, so that a reader (a server starting
// at the same time) never sees half a table; the folder is created. Errors name `where`.
base::Status write_table_file(const std::filesystem::path& path, const Table& table,
                              const std::vector<Preset>& presets, const std::string& where);

}  // namespace penumbra::quality
