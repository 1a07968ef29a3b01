#pragma once

// The example messages of proto/examples/v1, for the tests of this folder.

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace penumbra::protocol::test {

inline std::filesystem::path examples_dir() {
    return std::filesystem::path(PENUMBRA_PROTO_DIR) / "examples" / "v1";
}

inline std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// The *.json files of examples/v1/<kind> ("valid" or "invalid"), sorted.
inline std::vector<std::filesystem::path> example_files(const std::string& kind) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(examples_dir() / kind)) {
        if (entry.path().extension() == ".json") {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

struct InvalidExample {
    std::string name;
    std::string text;  // what goes on the wire
    std::string code;
    std::string field;
};

inline std::vector<InvalidExample> invalid_examples() {
    std::vector<InvalidExample> out;
    for (const auto& path : example_files("invalid")) {
        const auto entry = nlohmann::json::parse(read_text(path));
        const bool raw = entry.contains("raw");
        out.push_back({path.stem().string(),
                       raw ? entry.at("raw").get<std::string>() : entry.at("message").dump(),
                       entry.at("code").get<std::string>(), entry.at("field").get<std::string>()});
    }
    return out;
}

}  // namespace penumbra::protocol::test
