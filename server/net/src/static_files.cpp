#include "static_files.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace penumbra::net {

std::string content_type_for(const std::filesystem::path& path) {
    const std::string ext = path.extension().string();
    if (ext == ".html")
        return "text/html; charset=utf-8";
    if (ext == ".js" || ext == ".mjs")
        return "text/javascript; charset=utf-8";
    if (ext == ".css")
        return "text/css; charset=utf-8";
    if (ext == ".json" || ext == ".map")
        return "application/json";
    if (ext == ".svg")
        return "image/svg+xml";
    if (ext == ".png")
        return "image/png";
    if (ext == ".jpg" || ext == ".jpeg")
        return "image/jpeg";
    if (ext == ".ico")
        return "image/x-icon";
    if (ext == ".wasm")
        return "application/wasm";
    if (ext == ".woff2")
        return "font/woff2";
    return "application/octet-stream";
}

std::optional<StaticFile> read_static_file(const std::filesystem::path& root,
                                           std::string_view target) {
    if (root.empty()) {
        return std::nullopt;
    }
    std::string path(target.substr(0, target.find_first_of("?#")));
    if (path.empty() || path.front() != '/' || path.find("..") != std::string::npos ||
        path.find('\\') != std::string::npos || path.find('\0') != std::string::npos) {
        return std::nullopt;
    }
    if (path.back() == '/') {
        path += "index.html";
    }
    std::error_code ec;
    const std::filesystem::path base = std::filesystem::weakly_canonical(root, ec);
    const std::filesystem::path file = std::filesystem::weakly_canonical(base / path.substr(1), ec);
    if (ec) {
        return std::nullopt;
    }
    // After resolving links, the file must still lie inside the root.
    const auto [end, _] = std::mismatch(base.begin(), base.end(), file.begin(), file.end());
    if (end != base.end() || !std::filesystem::is_regular_file(file, ec)) {
        return std::nullopt;
    }
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        return std::nullopt;
    }
    std::stringstream body;
    body << in.rdbuf();
    return StaticFile{body.str(), content_type_for(file)};
}

std::string built_in_index_page() {
    return "<!doctype html><html><head><meta charset=\"utf-8\"><title>Penumbra</title></head>"
           "<body><h1>Penumbra</h1><p>The rendering service is running. The WebSocket protocol "
           "(proto/README.md) is at <code>/ws</code>; health at <a href=\"/healthz\">/healthz</a>, "
           "metrics at <a href=\"/metrics\">/metrics</a>. The web client is not built on this "
           "server.</p></body></html>";
}

}  // namespace penumbra::net
