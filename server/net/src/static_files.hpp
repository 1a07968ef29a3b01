#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace penumbra::net {

struct StaticFile {
    std::string body;
    std::string content_type;
};

// The file a request path names under `root`, or nothing: paths with "..", backslashes, NUL or
// anything resolving outside `root` are refused. "/" serves index.html.
std::optional<StaticFile> read_static_file(const std::filesystem::path& root,
                                           std::string_view target);

std::string content_type_for(const std::filesystem::path& path);

// Shown at "/" when the server has no built web client.
std::string built_in_index_page();

}  // namespace penumbra::net
