#pragma once

#include "arguments.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <string>
#include <vector>

namespace penumbra::app {

// The options that describe a frame, shared by every command that renders: those with a value,
// and the flags.
const std::vector<std::string>& frame_option_names();
const std::vector<std::string>& frame_flag_names();
// One line per mode: its name and what it does (the mode table's summary).
std::string modes_help();

// Builds a frame request from those options; defaults give a useful view of a head.
base::Result<scene::FrameRequest> frame_request_from(const Arguments& args,
                                                     const volume::Volume& volume);

// Help text for those options.
const char* frame_options_help();

}  // namespace penumbra::app
