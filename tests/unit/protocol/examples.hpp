#pragma once

// The example messages, for the tests of this folder: each client message's own examples in its
// schema (JSON Schema's `examples`, proto/v1/<type>.schema.json), more valid ones in
// proto/examples/v1/valid and the invalid ones with their expected errors in
// proto/examples/v1/invalid.

#include <penumbra/protocol/messages.hpp>

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

inline std::filesystem::path schema_path(std::string_view type) {
    return std::filesystem::path(PENUMBRA_PROTO_DIR) / "v1" / (std::string(type) + ".schema.json");
}

// The part of a message's schema that checks what a client sends: the whole schema, or
// $defs/request where one schema serves both directions (stats).
inline const nlohmann::json& request_part(const nlohmann::json& schema) {
    return schema.contains("$defs") && schema.at("$defs").contains("request")
                   ? schema.at("$defs").at("request")
                   : schema;
}

struct ValidExample {
    std::string name;  // "open.schema.json#/examples/0" or "set_camera_eye.json"
    std::string text;  // what goes on the wire
};

// Every valid client message: the examples in the schema of each type of ClientMessage, then the
// files of examples/v1/valid.
inline std::vector<ValidExample> valid_examples() {
    std::vector<ValidExample> out;
    for (const std::string_view type : kClientMessageTypes) {
        const std::filesystem::path path = schema_path(type);
        const auto schema = nlohmann::json::parse(read_text(path), nullptr, false);
        if (schema.is_discarded() || !request_part(schema).contains("examples")) {
            continue;  // EveryClientMessageHasItsSchemaAndItsExample names what is missing
        }
        const auto& examples = request_part(schema).at("examples");
        const std::string pointer = &request_part(schema) == &schema ? "" : "/$defs/request";
        for (std::size_t i = 0; i < examples.size(); ++i) {
            out.push_back(
                    {path.filename().string() + "#" + pointer + "/examples/" + std::to_string(i),
                     examples.at(i).dump()});
        }
    }
    for (const auto& path : example_files("valid")) {
        out.push_back({path.filename().string(), read_text(path)});
    }
    return out;
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
