#include "penumbra/codegen/schema_generator.hpp"

#include <penumbra/protocol/limits.hpp>
#include <penumbra/protocol/messages.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/enum_names.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/mode.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

namespace penumbra::codegen {

// What the generator restates: the protocol's messages, limits and state as the server sends them.
using protocol::apply_patch;
using protocol::hello_message;
using protocol::kClientMessageTypes;
using protocol::kWireCodes;
using protocol::Limits;
using protocol::max_transfer_function_name_bytes;
using protocol::max_transfer_function_points;
using protocol::scene_limits;
using protocol::Set;
using protocol::state_to_json;
using protocol::unnamed_transfer_function;

namespace {

// Keeps the hand-written members in the order they are written.
using json = nlohmann::ordered_json;

// Whole numbers as JSON integers (1000, not 1000.0), as a person writes them.
json number(double value) {
    if (value == std::trunc(value) && std::abs(value) < 9.0e15) {
        return static_cast<std::int64_t>(value);
    }
    return value;
}

std::vector<std::string> parts_of(std::string_view field) {
    std::vector<std::string> parts;
    std::istringstream in{std::string(field)};
    for (std::string part; std::getline(in, part, '/');) {
        parts.push_back(part);
    }
    return parts;
}

// The node of a range's field, made where it is missing: "settings/scattering/shell_rings" is
// $defs/settings/properties/scattering/properties/shell_rings; "vec3" and "rgb" are the items of
// those $defs. An object made on the way ("cut/plane_1") takes only the members its rows declare.
json& node_of(json& defs, std::string_view field) {
    if (field == "vec3" || field == "rgb") {
        return defs[std::string(field)]["items"];
    }
    const std::vector<std::string> parts = parts_of(field);
    json* node = &defs[parts.front()];
    for (std::size_t i = 1; i < parts.size(); ++i) {
        node = &(*node)["properties"][parts[i]];
        if (i + 1 < parts.size() && node->is_null()) {
            *node = {{"type", "object"}, {"additionalProperties", false}};
        }
    }
    return *node;
}

// "; at most hello.limits.max_slices (its default here)" for a setting the device and the
// server's configuration bound; empty for another.
std::string bounded_by(const scene::Setting& setting) {
    const std::pair<int scene::Limits::*, const char*> names[] = {
            {&scene::Limits::max_image_side, "max_image_side"},
            {&scene::Limits::max_slices, "max_slices"},
            {&scene::Limits::max_light_resolution, "max_light_resolution"},
    };
    for (const auto& [limit, name] : names) {
        if (setting.limit == limit) {
            return std::string("; at most hello.limits.") + name + " (its default here)";
        }
    }
    return "";
}

// What the schema says of a setting, written from its row: its description (the summary), then
// its type and range by kind (a choice's names; a vector's or a size's items), then whatever else
// the node says by hand. A setting bounded by the device and the server's configuration has the
// default limit as its maximum.
void write_setting(json& node, const scene::Setting& setting) {
    const double max = setting.max_under(scene_limits(Limits{}));
    json written = json::object();
    if (!setting.summary.empty()) {
        written["description"] = std::string(setting.summary) + bounded_by(setting);
    } else if (node.is_object() && node.contains("description")) {
        written["description"] = node.at("description");
    }
    const auto items = [&](const char* type, int count) {
        written["type"] = "array";
        written["items"] = {
                {"type", type}, {"minimum", number(setting.min)}, {"maximum", number(max)}};
        written["minItems"] = count;
        written["maxItems"] = count;
    };
    switch (setting.kind) {
        case scene::SettingKind::number:
        case scene::SettingKind::whole:
            written["type"] = setting.integer() ? "integer" : "number";
            written["minimum"] = number(setting.min);
            written["maximum"] = number(max);
            break;
        case scene::SettingKind::boolean:
            written["type"] = "boolean";
            break;
        case scene::SettingKind::choice:
            written["enum"] = json::array();
            for (const std::string_view name : setting.choices) {
                written["enum"].push_back(name);
            }
            break;
        case scene::SettingKind::vector:
            items("number", 3);
            break;
        case scene::SettingKind::size:
            items("integer", 2);
            break;
    }
    if (node.is_object()) {
        for (const auto& [key, value] : node.items()) {
            // The row says what the value is: a reference to a shared shape would say it twice.
            if (!written.contains(key) && key != "$ref") {
                written[key] = value;
            }
        }
    }
    node = std::move(written);
}

// A setting that a request holds is a member of every state: required at its place in
// $defs/state (each part's second allOf entry lists what the state adds to the patch's shape).
void require_in_state(json& defs, std::string_view field) {
    const std::vector<std::string> parts = parts_of(field);
    json* node = &defs["state"]["properties"][parts.front()]["allOf"][1];
    for (std::size_t i = 1; i + 1 < parts.size(); ++i) {
        node = &(*node)["properties"][parts[i]];
    }
    json& required = (*node)["required"];
    if (std::find(required.begin(), required.end(), parts.back()) == required.end()) {
        required.push_back(parts.back());
    }
}

// A table cell: '|' escaped, as Markdown tables need.
std::string cell(std::string_view text) {
    std::string out;
    for (const char c : text) {
        if (c == '|') {
            out += '\\';
        }
        out += c;
    }
    return out;
}

// What the schema says of a member's value: "string ≤ 256 bytes", "boolean, default false"; empty
// for a $ref.
std::string value_kind(const json& member) {
    if (!member.contains("type") || !member.at("type").is_string()) {
        return "";
    }
    std::string kind = member.at("type").get<std::string>();
    if (member.contains("maxLength")) {
        kind += " ≤ " + member.at("maxLength").dump() + " bytes";
    }
    if (member.contains("default")) {
        kind += ", default " + member.at("default").dump();
    }
    return kind;
}

// "`volume` (required, string ≤ 256 bytes): an id from volumes; `interactive` (boolean): ..."
std::string members_cell(const json& request) {
    std::string out;
    const json required = request.value("required", json::array());
    for (const auto& [name, member] : request.at("properties").items()) {
        if (name == "v" || name == "type" || name == "id") {
            continue;
        }
        if (!out.empty()) {
            out += "; ";
        }
        out += "`" + name + "`";
        std::string notes;
        if (std::find(required.begin(), required.end(), name) != required.end()) {
            notes = "required";
        }
        if (const std::string kind = value_kind(member); !kind.empty()) {
            notes += (notes.empty() ? "" : ", ") + kind;
        }
        if (!notes.empty()) {
            out += " (" + notes + ")";
        }
        if (member.contains("description")) {
            std::string description = member.at("description").get<std::string>();
            if (description.ends_with('.')) {
                description.pop_back();
            }
            out += ": " + description;
        }
    }
    return out.empty() ? "–" : cell(out);
}

base::Result<std::string> message_table(const std::filesystem::path& schema_dir) {
    std::string table =
            "| `type` | members besides `v`, `type`, `id` | what it does |\n"
            "|---|---|---|\n";
    for (const std::string_view type : kClientMessageTypes) {
        const std::filesystem::path path = schema_dir / (std::string(type) + ".schema.json");
        std::ifstream in(path, std::ios::binary);
        const json schema = json::parse(in, nullptr, false);
        if (schema.is_discarded() || !schema.is_object()) {
            return base::make_error(base::ErrorCode::invalid_value,
                                    "no JSON schema for " + std::string(type), path.string());
        }
        // A schema for both directions (stats) keeps the request in $defs/request.
        const json& request = schema.contains("$defs") && schema.at("$defs").contains("request")
                                      ? schema.at("$defs").at("request")
                                      : schema;
        if (!request.contains("properties") || !request.contains("description")) {
            return base::make_error(base::ErrorCode::invalid_value,
                                    "the request has no properties or no description",
                                    path.string());
        }
        table += "| `" + std::string(type) + "` | " + members_cell(request) + " | " +
                 cell(request.at("description").get<std::string>()) + " |\n";
    }
    return table;
}

// A limit's value as the README writes it: "65536", "1e11", `{"join/session": 64, ...}`.
std::string readme_value(const nlohmann::json& value) {
    if (value.is_object()) {
        std::string text;
        for (const auto& [key, member] : value.items()) {
            text += (text.empty() ? "" : ", ") + nlohmann::json(key).dump() + ": " + member.dump();
        }
        return "`{" + text + "}`";
    }
    const double number = value.get<double>();
    if (number == std::trunc(number) && std::abs(number) < 1e9) {
        return std::to_string(static_cast<std::int64_t>(number));
    }
    std::array<char, 32> text{};
    std::snprintf(text.data(), text.size(), "%g", number);
    std::string written = text.data();
    if (const std::size_t plus = written.find("e+"); plus != std::string::npos) {
        written.erase(plus + 1, 1);
    }
    return written;
}

// The README's limit tables (§8) with each row's value (its second cell) as the hello of a server
// configured with nothing else states it; the rows and the other cells are written by hand.
std::string with_limit_values(const std::string& text) {
    const auto hello = nlohmann::json::parse(hello_message(Limits{}, {"", "", "", true}));
    std::istringstream in(text);
    std::string out;
    for (std::string line; std::getline(in, line);) {
        for (const auto& [name, value] : hello.at("limits").items()) {
            const std::string row = "| `" + name + "` | ";
            const std::size_t cell_end = line.find(" | ", row.size());
            if (line.starts_with(row) && cell_end != std::string::npos) {
                line = row + readme_value(value) + line.substr(cell_end);
                break;
            }
        }
        out += line + "\n";
    }
    if (!text.ends_with('\n') && !out.empty()) {
        out.pop_back();
    }
    return out;
}

// A new session's state as `state` sends it, on a server configured with nothing else.
nlohmann::json starting_state() {
    const Limits limits;
    scene::State state;
    state.frame = scene::starting_frame(scene_limits(limits));
    return nlohmann::json::parse(state_to_json(state));
}

// A state's value as the README writes it: `multi_slice`, 0.99, `[512, 512]`, an object's
// members "`slices` 128, `lookup` `local`".
std::string readme_state_value(const nlohmann::json& value) {
    if (value.is_object()) {
        std::string text;
        for (const auto& [key, member] : value.items()) {
            text += (text.empty() ? "`" : ", `") + key + "` " + readme_state_value(member);
        }
        return text;
    }
    if (value.is_array()) {
        std::string text;
        for (const auto& item : value) {
            text += (text.empty() ? "" : ", ") + readme_value(item);
        }
        return "`[" + text + "]`";
    }
    if (value.is_number()) {
        return readme_value(value);
    }
    return "`" + (value.is_string() ? value.get<std::string>() : value.dump()) + "`";
}

// §5's tables of `settings` and `output` with each member's last cell (a new session's value) as
// a new session's state holds it; the rows and the other cells are written by hand.
std::string with_state_values(const std::string& text) {
    const nlohmann::json state = starting_state();
    std::istringstream in(text);
    std::string out;
    std::string part;
    for (std::string line; std::getline(in, line);) {
        if (line.starts_with("**`") || line.starts_with("#")) {
            part.clear();
            for (const char* name : {"settings", "output"}) {
                if (line.starts_with("**`" + std::string(name) + "`**")) {
                    part = name;
                }
            }
        }
        const std::size_t name_end = line.find("` | ");
        const std::size_t last_cell = line.rfind(" | ");
        if (!part.empty() && line.starts_with("| `") && line.ends_with(" |") &&
            name_end != std::string::npos && last_cell > name_end) {
            const std::string name = line.substr(3, name_end - 3);
            std::string cells = line.substr(0, last_cell);
            std::string last = line.substr(last_cell);
            // The output's ranges (whole numbers) are written as "1..100" in the third cell.
            const std::size_t type_end = cells.find(" | ", name_end + 4);
            for (const scene::Setting* setting : scene::kSettings) {
                if (part == "output" && setting->path == part + "/" + name &&
                    setting->kind == scene::SettingKind::whole && type_end != std::string::npos) {
                    cells = cells.substr(0, type_end + 3) + readme_value(setting->min) + ".." +
                            readme_value(setting->max);
                }
            }
            if (state.at(part).contains(name)) {
                last = " | " + cell(readme_state_value(state.at(part).at(name))) + " |";
            }
            line = cells + last;
        }
        out += line + "\n";
    }
    if (!text.ends_with('\n') && !out.empty()) {
        out.pop_back();
    }
    return out;
}

}  // namespace

base::Result<std::string> generated_readme(std::string_view committed,
                                           const std::filesystem::path& schema_dir) {
    const std::size_t begin = committed.find(kTableBegin);
    const std::size_t end = committed.find(kTableEnd);
    if (begin == std::string_view::npos || end == std::string_view::npos || end < begin) {
        return base::make_error(base::ErrorCode::invalid_value,
                                "no table between \"" + std::string(kTableBegin) + "\" and \"" +
                                        std::string(kTableEnd) + "\"");
    }
    auto table = message_table(schema_dir);
    if (!table) {
        return table.error();
    }
    const std::size_t table_start = begin + kTableBegin.size();
    return with_state_values(with_limit_values(std::string(committed.substr(0, table_start)) +
                                               "\n" + *table + std::string(committed.substr(end))));
}

// `Enum`'s names from scene's name table, in its order.
template <scene::NamedEnum Enum>
json names_of_enum() {
    json names = json::array();
    for (const scene::EnumName<Enum>& row : scene::names<Enum>()) {
        names.push_back(row.name);
    }
    return names;
}

// The enum of the field that holds one of `Enum`'s values.
template <scene::NamedEnum Enum>
void write_names(json& defs, std::string_view field) {
    node_of(defs, field)["enum"] = names_of_enum<Enum>();
}

// What $defs/transfer_function's points form restates: the preset names, the position spaces,
// the longest name, the most points and how far a Hounsfield position reaches.
void write_transfer_function(json& defs) {
    json presets = json::array();
    for (const std::string& name : scene::preset_names()) {
        presets.push_back(name);
    }
    defs["preset"]["enum"] = std::move(presets);
    json& oneof = defs["transfer_function"]["oneOf"];
    if (!oneof.is_array() || oneof.size() < 2) {
        oneof = json::array({json::object(), json::object()});
    }
    json& points = oneof[1]["properties"];
    points["name"]["type"] = "string";
    points["name"]["maxLength"] = max_transfer_function_name_bytes;
    points["name"]["default"] = unnamed_transfer_function;
    points["space"]["enum"] = names_of_enum<scene::PositionSpace>();
    points["space"]["default"] = scene::name_of(scene::TransferFunction{}.space);
    for (const char* list : {"colors", "opacities"}) {
        json& node = points[list];
        node["type"] = "array";
        node["maxItems"] = max_transfer_function_points;
        json& x = node["items"]["properties"]["x"];
        x["type"] = "number";
        x["minimum"] = number(-scene::max_hounsfield_position);
        x["maximum"] = number(scene::max_hounsfield_position);
    }
}

// What an orbit's members are when a patch leaves them out: the default camera's angles and
// distance, as the parser takes them.
void write_orbit_defaults(json& defs) {
    const scene::Camera camera;
    const glm::dvec3 offset = camera.eye - camera.target;
    const double distance = glm::length(offset);
    json& orbit = node_of(defs, "camera/orbit")["properties"];
    orbit["azimuth"]["default"] = number(glm::degrees(std::atan2(offset.x, offset.y)));
    orbit["elevation"]["default"] = number(glm::degrees(std::asin(offset.z / distance)));
    orbit["distance"]["default"] = number(distance);
}

base::Result<std::string> generated_common_schema(std::string_view committed) {
    json schema = json::parse(committed, nullptr, false);
    if (schema.is_discarded() || !schema.is_object() || !schema.contains("$defs") ||
        !schema.at("$defs").is_object()) {
        return base::make_error(base::ErrorCode::invalid_value, "not a JSON object with $defs",
                                "/$defs");
    }
    json& defs = schema["$defs"];

    // The names other schemas refer to (hello's modes and encodings).
    for (const scene::Setting* named : {&scene::setting::mode, &scene::setting::encoding}) {
        json names = json::array();
        for (const std::string_view name : named->choices) {
            names.push_back(name);
        }
        defs[std::string(named->path.substr(named->path.rfind('/') + 1))]["enum"] =
                std::move(names);
    }
    write_names<scene::View>(defs, "camera/view");
    write_names<protocol::Listing>(defs, "listing");
    defs["error_code"]["enum"] = json::array();
    for (const base::ErrorCode code : kWireCodes) {
        defs["error_code"]["enum"].push_back(base::name_of(code));
    }
    write_transfer_function(defs);
    write_orbit_defaults(defs);

    json client_types = json::array();
    for (const std::string_view type : kClientMessageTypes) {
        client_types.push_back(type);
    }
    defs["client_type"]["enum"] = std::move(client_types);

    for (const scene::Setting* setting : scene::kSettings) {
        write_setting(node_of(defs, setting->path), *setting);
        if (setting->held()) {
            require_in_state(defs, setting->path);
        }
    }
    return schema.dump(2) + "\n";
}

base::Result<std::string> generated_hello_schema(std::string_view committed) {
    json schema = json::parse(committed, nullptr, false);
    if (schema.is_discarded() || !schema.is_object()) {
        return base::make_error(base::ErrorCode::invalid_value, "not a JSON object", "/");
    }
    json& capabilities = schema["properties"]["modes"]["items"]["properties"];
    capabilities["technique"]["enum"] = names_of_enum<scene::Technique>();
    capabilities["shadows"]["enum"] = names_of_enum<scene::ShadowKind>();
    capabilities["scattering"]["enum"] = names_of_enum<scene::ScatteringKind>();
    capabilities["gradients"]["enum"] = names_of_enum<scene::Gradients>();
    // Each limit as a server configured with nothing else sends it (and the fixed ones as every
    // server does).
    const auto hello = nlohmann::json::parse(hello_message(Limits{}, {"", "", "", true}));
    json& limits = schema["properties"]["limits"]["properties"];
    for (const auto& [name, value] : hello.at("limits").items()) {
        if (value.is_number()) {
            limits[name]["default"] = number(value.get<double>());
        }
    }
    return schema.dump(2) + "\n";
}

base::Result<std::string> generated_recorded_hello(std::string_view committed) {
    const std::size_t line_end = std::min(committed.find('\n'), committed.size());
    // The server writes its messages with nlohmann's default (sorted) objects; so is the recording.
    const auto recorded = nlohmann::json::parse(committed.substr(0, line_end), nullptr, false);
    if (!recorded.is_object() || recorded.value("type", "") != "hello") {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "the first recorded message is not a hello", "1");
    }
    // Everything but the renderer, which says what the recording's machine drew with.
    auto hello = nlohmann::json::parse(hello_message(Limits{}, {"", "", "", true}));
    hello["renderer"] = recorded.value("renderer", nlohmann::json::object());
    std::string out = hello.dump();
    // Each recorded state as the server reports it now: its values kept, a setting added since
    // at a new state's value; a set's ack with the state it answers (the last one recorded).
    nlohmann::json last_state;
    std::size_t number = 1;
    for (std::size_t start = line_end; start < committed.size();) {
        std::size_t end = std::min(committed.find('\n', start + 1), committed.size());
        const std::string_view line = committed.substr(start + 1, end - start - 1);
        start = end;
        ++number;
        if (line.empty()) {
            out += "\n";
            continue;
        }
        auto message = nlohmann::json::parse(line, nullptr, false);
        if (!message.is_object()) {
            return base::make_error(base::ErrorCode::invalid_argument, "not a JSON object",
                                    std::to_string(number));
        }
        if (message.contains("state")) {
            scene::State state;
            if (auto applied = apply_patch(message.at("state").dump(), state, Limits{}); !applied) {
                return base::make_error(base::ErrorCode::invalid_argument,
                                        "a recorded state the server no longer takes: " +
                                                applied.error().to_string(),
                                        std::to_string(number));
            }
            message["state"] = nlohmann::json::parse(state_to_json(state));
        }
        if (message.value("type", "") == "ack" && message.value("of", "") == Set::type) {
            message["state"] = last_state;
        }
        if (message.contains("state")) {
            last_state = message.at("state");
        }
        out += "\n" + message.dump();
    }
    return out;
}

namespace {

// A number as TypeScript reads it back exactly: whole numbers without a point, no "-0".
std::string ts_number(double value) {
    if (value == 0.0) {
        return "0";
    }
    return number(value).dump();
}

std::string ts_vec3(glm::dvec3 v) {
    return "[" + ts_number(v.x) + ", " + ts_number(v.y) + ", " + ts_number(v.z) + "]";
}

std::string ts_names(std::string_view constant, std::string_view summary,
                     const std::vector<std::string_view>& names) {
    std::string out =
            "/** " + std::string(summary) + " */\nexport const " + std::string(constant) + " = [";
    for (std::size_t i = 0; i < names.size(); ++i) {
        out += (i > 0 ? ", '" : "'") + std::string(names[i]) + "'";
    }
    return out + "] as const;\n";
}

// A JSON value as a TypeScript literal, objects a member a line at `indent`.
std::string ts_value(const nlohmann::json& value, const std::string& indent) {
    if (value.is_object()) {
        std::string out = "{\n";
        for (const auto& [key, member] : value.items()) {
            out += indent + "  " + key + ": " + ts_value(member, indent + "  ") + ",\n";
        }
        return out + indent + "}";
    }
    if (value.is_array()) {
        std::string out = "[";
        for (std::size_t i = 0; i < value.size(); ++i) {
            out += (i > 0 ? ", " : "") + ts_value(value[i], indent);
        }
        return out + "]";
    }
    if (value.is_string()) {
        return "'" + value.get<std::string>() + "'";
    }
    if (value.is_number()) {
        return ts_number(value.get<double>());
    }
    return value.dump();
}

template <scene::NamedEnum Enum>
std::string ts_enum(std::string_view constant, std::string_view summary) {
    std::vector<std::string_view> names;
    for (const scene::EnumName<Enum>& row : scene::names<Enum>()) {
        names.push_back(row.name);
    }
    return ts_names(constant, summary, names);
}

// A setting's type in TypeScript: number, boolean, a union of a choice's names, a tuple.
std::string ts_type(const scene::Setting& setting) {
    switch (setting.kind) {
        case scene::SettingKind::number:
        case scene::SettingKind::whole:
            return "number";
        case scene::SettingKind::boolean:
            return "boolean";
        case scene::SettingKind::choice: {
            std::string names;
            for (const std::string_view name : setting.choices) {
                names += (names.empty() ? "'" : " | '") + std::string(name) + "'";
            }
            return names;
        }
        case scene::SettingKind::vector:
            return "Vec3";
        case scene::SettingKind::size:
            return "Size";
    }
    return "never";
}

// The members of the state's object at `path` ("" for the state itself, "settings/light_buffer"),
// a line each at `indent`, a part as a nested object: each setting of the table that a state holds.
std::string ts_members(const std::string& path, const std::string& indent) {
    std::string out;
    std::vector<std::string> parts;
    for (const scene::Setting* setting : scene::kSettings) {
        const std::string_view full = setting->path;
        if (!setting->held() || (!path.empty() && !full.starts_with(path + "/"))) {
            continue;
        }
        const std::string_view rest = full.substr(path.empty() ? 0 : path.size() + 1);
        const std::size_t slash = rest.find('/');
        if (slash == std::string_view::npos) {
            if (!setting->summary.empty()) {
                out += indent + "/** " + std::string(setting->summary) + " */\n";
            }
            out += indent + std::string(rest) + ": " + ts_type(*setting) + ";\n";
            continue;
        }
        const std::string part(rest.substr(0, slash));
        if (std::find(parts.begin(), parts.end(), part) == parts.end()) {
            parts.push_back(part);
            const std::string inner = path.empty() ? part : path + "/" + part;
            out += indent + part + ": {\n" + ts_members(inner, indent + "  ") + indent + "};\n";
        }
    }
    return out;
}

// A setting as SETTINGS describes it: its kind, range or names and summary.
std::string ts_setting(const scene::Setting& setting) {
    const double max = setting.max_under(scene_limits(Limits{}));
    std::string out = "{ kind: '" + std::string(scene::name_of(setting.kind)) + "'";
    switch (setting.kind) {
        case scene::SettingKind::number:
        case scene::SettingKind::whole:
        case scene::SettingKind::vector:
        case scene::SettingKind::size:
            out += ", min: " + ts_number(setting.min) + ", max: " + ts_number(max);
            break;
        case scene::SettingKind::choice: {
            out += ", choices: [";
            for (std::size_t i = 0; i < setting.choices.size(); ++i) {
                out += (i > 0 ? ", '" : "'") + std::string(setting.choices[i]) + "'";
            }
            out += "]";
            break;
        }
        case scene::SettingKind::boolean:
            break;
    }
    if (setting.limit != nullptr) {
        out += ", limited: true";
    }
    return out + ", summary: " + nlohmann::json(setting.summary).dump() + " }";
}

// The settings a state holds: each with its kind, range and summary (SETTINGS), and the state's
// type made of them (StateSettings; the transfer function is typed by hand).
std::string client_settings() {
    std::string out =
            "\n/** A point or a direction in world space (RAS), or a colour's channels. */\n"
            "export type Vec3 = [number, number, number];\n"
            "/** An image's width and height in pixels. */\n"
            "export type Size = [number, number];\n"
            "\n/**\n"
            " * Every setting a session's state holds, by its path: its kind, its range (each "
            "component's; `limited`:\n"
            " * bounded by hello.limits instead, at its default here) or its names, and what it "
            "does.\n"
            " */\n"
            "export const SETTINGS = {\n";
    for (const scene::Setting* setting : scene::kSettings) {
        if (setting->held()) {
            out += "  '" + std::string(setting->path) + "': " + ts_setting(*setting) + ",\n";
        }
    }
    out += "} as const;\n"
           "\n/** A session's state as `state` carries it, but for the transfer function. */\n"
           "export interface StateSettings {\n" +
           ts_members("", "  ") + "}\n";
    return out;
}

}  // namespace

std::string generated_client_tables() {
    const std::vector<std::string_view> encodings(scene::setting::encoding.choices.begin(),
                                                  scene::setting::encoding.choices.end());
    std::string out =
            "// The server's names and views for the web client, written from its C++ tables by\n"
            "// scripts/update-schema.sh; protocol_test (SchemaAgreement.TheWebClientsServerTables"
            "AreGenerated)\n"
            "// fails while this file differs from what they make. Not edited by hand.\n\n";
    out += ts_names("ENCODINGS", "The formats frames are written in, the first the default.",
                    encodings);
    std::vector<std::string_view> wire_codes;
    for (const base::ErrorCode code : kWireCodes) {
        wire_codes.push_back(base::name_of(code));
    }
    out += ts_names("ERROR_CODES", "The codes an `error` message carries.", wire_codes);
    out += ts_enum<protocol::Listing>(
            "LISTINGS", "Where the server's listing of its data folder stands (volumes.listing).");
    out += ts_enum<scene::Compositing>("COMPOSITINGS", "settings.compositing");
    out += ts_enum<scene::Reconstruction>("RECONSTRUCTIONS", "settings.reconstruction");
    out += ts_enum<scene::RaycastStage>("STAGES", "settings.stage: the ray caster's stage.");
    out += ts_enum<scene::LightBufferBuilder>("BUILDERS", "settings.light_buffer.builder");
    out += ts_enum<scene::LightLookup>("LIGHT_LOOKUPS", "settings.light_buffer.lookup");
    out += ts_enum<scene::LightType>("LIGHT_TYPES", "light.type");
    out += ts_enum<scene::PositionSpace>(
            "POSITION_SPACES",
            "Where a transfer function's positions lie: fractions of the volume's range, or "
            "Hounsfield units.");
    out += ts_enum<scene::Technique>("TECHNIQUES", "A mode's technique (hello.modes).");
    out += ts_enum<scene::ShadowKind>("SHADOW_KINDS", "How a mode shadows (hello.modes).");
    out += ts_enum<scene::ScatteringKind>("SCATTERING_KINDS",
                                          "What a mode scatters with (hello.modes).");
    out += ts_enum<scene::Gradients>("GRADIENTS", "When a mode reads gradients (hello.modes).");
    out += ts_enum<scene::View>(
            "VIEWS",
            "The views named by anatomy (world space is RAS: +x right, +y anterior, +z "
            "superior).");
    out += "\n/** Each view's eye direction from its target (a unit vector) and its up, as the "
           "server poses them. */\n"
           "export const VIEW_POSES: Readonly<\n"
           "  Record<(typeof VIEWS)[number], { side: readonly [number, number, number]; up: "
           "readonly [number, number, number] }>\n"
           "> = {\n";
    for (const scene::EnumName<scene::View>& row : scene::names<scene::View>()) {
        const scene::Camera camera = scene::view_camera(row.value, 1.0);
        out += "  " + std::string(row.name) +
               ": { side: " + ts_vec3(glm::normalize(camera.eye - camera.target)) +
               ", up: " + ts_vec3(camera.up) + " },\n";
    }
    out += "};\n\n";
    out += "/** The space of a transfer function's positions when it names none. */\n"
           "export const DEFAULT_POSITION_SPACE: (typeof POSITION_SPACES)[number] = '" +
           std::string(scene::name_of(scene::TransferFunction{}.space)) +
           "';\n"
           "/** The name of a transfer function given by its points that names none. */\n"
           "export const UNNAMED_TRANSFER_FUNCTION = '" +
           std::string(unnamed_transfer_function) + "';\n";
    out += "\n/** How far from the horizon an orbit's eye goes, in degrees (the server keeps it "
           "short of the poles). */\n"
           "export const MAX_ORBIT_ELEVATION = " +
           ts_number(scene::max_orbit_elevation) + ";\n";
    const scene::Camera default_camera;
    out += "/** How far the default camera and the named views stand from the target, in box "
           "units. */\n"
           "export const DEFAULT_CAMERA_DISTANCE = " +
           ts_number(scene::default_camera_distance) +
           ";\n"
           "/** The default camera's vertical field of view, in degrees. */\n"
           "export const DEFAULT_FOV = " +
           ts_number(default_camera.fov_y_degrees) + ";\n";
    out += client_settings();
    // hello.limits' numbers as a server configured with nothing else sends them.
    const auto hello = nlohmann::json::parse(hello_message(Limits{}, {"", "", "", true}));
    out += "\n/** hello.limits' numbers as a server configured with nothing else sends them. */\n"
           "export const DEFAULT_LIMITS = {\n";
    for (const auto& [name, value] : hello.at("limits").items()) {
        if (value.is_number()) {
            out += "  " + name + ": " + ts_number(value.get<double>()) + ",\n";
        }
    }
    out += "} as const;\n";
    const nlohmann::json sent = starting_state();
    out += "\n/** The settings a new session starts from (as its `state` holds them), shown until "
           "its "
           "state arrives. */\n"
           "export const DEFAULT_SETTINGS = " +
           ts_value(sent.at("settings"), "") +
           " as const;\n"
           "/** The output a new session starts from. */\n"
           "export const DEFAULT_OUTPUT = " +
           ts_value(sent.at("output"), "") + " as const;\n";
    return out;
}

}  // namespace penumbra::codegen
