// The JSON Schemas of proto/v1 against the C++ tables they restate for clients that cannot read
// C++: scene's mode table, its setting ranges and the client message types, which
// scripts/update-schema.sh writes into common.schema.json; and the hello the web client's tests
// take their ranges from. A mode or a limit changed in one and not the other fails here.

#include "examples.hpp"

#include <penumbra/codegen/schema_generator.hpp>
#include <penumbra/protocol/messages.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/enum_names.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/mode.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <type_traits>
#include <variant>
#include <vector>

namespace penumbra::protocol {
namespace {

using nlohmann::json;

json schema(const std::string& name) {
    return json::parse(test::read_text(std::filesystem::path(PENUMBRA_PROTO_DIR) / "v1" / name));
}

// The schema node a range's field names: "settings/scattering/shell_rings" is
// $defs/settings/properties/scattering/properties/shell_rings; "vec3" and "rgb" are the items of
// those $defs.
// The definition a "$ref": "common.schema.json#/$defs/NAME" names.
json schema_definition(const json& reference) {
    const std::string ref = reference.at("$ref").get<std::string>();
    const std::string prefix = "common.schema.json#/$defs/";
    EXPECT_TRUE(ref.starts_with(prefix)) << ref;
    return schema("common.schema.json").at("$defs").at(ref.substr(prefix.size()));
}

const json& schema_node(const json& defs, std::string_view field) {
    if (field == "vec3" || field == "rgb") {
        return defs.at(std::string(field)).at("items");
    }
    std::istringstream parts{std::string(field)};
    std::string part;
    std::getline(parts, part, '/');
    const json* node = &defs.at(part);
    while (std::getline(parts, part, '/')) {
        node = &node->at("properties").at(part);
    }
    return *node;
}

// The schema's copies of the tables are written by the generator, never by hand: a mode, a range or
// a client message type changed in C++ changes what it writes, and the committed file must follow.
TEST(SchemaAgreement, CommonSchemaIsGenerated) {
    const std::string committed = test::read_text(std::filesystem::path(PENUMBRA_PROTO_DIR) / "v1" /
                                                  "common.schema.json");
    const auto generated = codegen::generated_common_schema(committed);
    ASSERT_TRUE(generated.ok()) << generated.error().to_string();
    EXPECT_TRUE(*generated == committed)
            << "proto/v1/common.schema.json differs from what the C++ tables make of it: run "
               "scripts/update-schema.sh";
}

// proto/README.md's table of the client messages is their schemas' members and descriptions: a new
// message's schema brings its row.
TEST(SchemaAgreement, ReadmeMessageTableIsGenerated) {
    const std::filesystem::path proto(PENUMBRA_PROTO_DIR);
    const std::string committed = test::read_text(proto / "README.md");
    const auto generated = codegen::generated_readme(committed, proto / "v1");
    ASSERT_TRUE(generated.ok()) << generated.error().to_string();
    EXPECT_TRUE(*generated == committed)
            << "proto/README.md's table of the client messages differs from their schemas: run "
               "scripts/update-schema.sh";
    for (const std::string_view type : kClientMessageTypes) {
        EXPECT_NE(generated->find("| `" + std::string(type) + "` |"), std::string::npos) << type;
    }
    // The limits' table (§8) states the values a server configured with nothing else sends.
    const Limits limits;
    EXPECT_NE(
            generated->find("| `max_image_side` | " + std::to_string(limits.max_image_side) + " |"),
            std::string::npos);
    EXPECT_NE(generated->find("| `max_transfer_function_points` | " +
                              std::to_string(max_transfer_function_points) + " |"),
              std::string::npos);
    const auto stale = codegen::generated_readme(std::string(codegen::kTableBegin) + "\n" +
                                                         std::string(codegen::kTableEnd) +
                                                         "\n| `max_slices` | 7 | slices |\n",
                                                 proto / "v1");
    ASSERT_TRUE(stale.ok()) << stale.error().to_string();
    EXPECT_TRUE(stale->ends_with("| `max_slices` | " + std::to_string(limits.max_slices) +
                                 " | slices |\n"));
    // §5's last column states what a new session starts from, and the JPEG quality's range cell
    // the one the parser holds a patch to, whatever the committed cells say.
    const scene::FrameRequest start = scene::starting_frame(scene_limits(limits));
    const auto settings = codegen::generated_readme(
            std::string(codegen::kTableBegin) + "\n" + std::string(codegen::kTableEnd) +
                    "\n**`settings`**\n\n| `mode` | string | a mode | `dvr` |\n| `phong` | "
                    "boolean | | |\n\n**`output`**\n\n| `jpeg_quality` | int | 2..7 | 7 |\n",
            proto / "v1");
    ASSERT_TRUE(settings.ok()) << settings.error().to_string();
    EXPECT_NE(settings->find("| `mode` | string | a mode | `" +
                             std::string(scene::to_string(start.settings.mode)) + "` |"),
              std::string::npos);
    EXPECT_NE(settings->find(std::string("| `phong` | boolean | | `") +
                             (start.settings.phong ? "true" : "false") + "` |"),
              std::string::npos);
    EXPECT_NE(settings->find("| `jpeg_quality` | int | " +
                             std::to_string(static_cast<int>(scene::setting::jpeg_quality.min)) +
                             ".." +
                             std::to_string(static_cast<int>(scene::setting::jpeg_quality.max)) +
                             " | " + std::to_string(scene::kDefaultFrameJpegQuality) + " |"),
              std::string::npos);
}

template <scene::NamedEnum Enum>
json names_in_table() {
    json names = json::array();
    for (const scene::EnumName<Enum>& row : scene::names<Enum>()) {
        names.push_back(row.name);
    }
    return names;
}

// A setting added to the table reaches the schema with nothing written by hand: from a schema
// without it, the generator makes its node (by its kind: a range, a boolean, names, a vector's or
// a size's items), and its place in the state.
TEST(SchemaAgreement, GeneratorWritesEverySettingFromTheTable) {
    const auto generated = codegen::generated_common_schema(
            R"({"$defs": {"state": {"properties": {"camera": {"allOf": [{}, {}]},
               "light": {"allOf": [{}, {}]}, "settings": {"allOf": [{}, {}]},
               "output": {"allOf": [{}, {}]}}}}})");
    ASSERT_TRUE(generated.ok()) << generated.error().to_string();
    const json defs = json::parse(*generated).at("$defs");
    const scene::Limits limits = scene_limits(Limits{});
    for (const scene::Setting* setting : scene::kSettings) {
        SCOPED_TRACE(std::string(setting->path));
        const json& node = schema_node(defs, setting->path);
        const double max = setting->max_under(limits);
        switch (setting->kind) {
            case scene::SettingKind::number:
            case scene::SettingKind::whole:
                EXPECT_EQ(node.at("minimum").get<double>(), setting->min);
                EXPECT_EQ(node.at("maximum").get<double>(), max);
                EXPECT_EQ(node.at("type"), setting->integer() ? "integer" : "number");
                break;
            case scene::SettingKind::boolean:
                EXPECT_EQ(node.at("type"), "boolean");
                break;
            case scene::SettingKind::choice:
                EXPECT_EQ(
                        node.at("enum").get<std::vector<std::string>>(),
                        std::vector<std::string>(setting->choices.begin(), setting->choices.end()));
                break;
            case scene::SettingKind::vector:
            case scene::SettingKind::size: {
                const int count = setting->kind == scene::SettingKind::vector ? 3 : 2;
                EXPECT_EQ(node.at("minItems"), count);
                EXPECT_EQ(node.at("maxItems"), count);
                EXPECT_EQ(node.at("items").at("minimum").get<double>(), setting->min);
                EXPECT_EQ(node.at("items").at("maximum").get<double>(), max);
                EXPECT_EQ(node.at("items").at("type"), setting->integer() ? "integer" : "number");
                break;
            }
        }
        if (!setting->summary.empty()) {
            EXPECT_TRUE(node.at("description").get<std::string>().starts_with(setting->summary));
        }
    }
    // Each setting that a state holds is required there, where the state's part lists them.
    for (const scene::Setting* setting : scene::kSettings) {
        if (!setting->held()) {
            continue;
        }
        SCOPED_TRACE(std::string(setting->path));
        const std::string field(setting->path);
        const std::size_t part_end = field.find('/');
        const std::size_t leaf_start = field.rfind('/') + 1;
        const json* node =
                &defs.at("state").at("properties").at(field.substr(0, part_end)).at("allOf").at(1);
        std::istringstream middle(field.substr(part_end + 1, leaf_start - part_end - 1));
        for (std::string part; std::getline(middle, part, '/');) {
            node = &node->at("properties").at(part);
        }
        const auto required = node->at("required").get<std::vector<std::string>>();
        EXPECT_NE(std::find(required.begin(), required.end(), field.substr(leaf_start)),
                  required.end());
    }
    std::vector<std::string> modes;
    for (const scene::ModeInfo& mode : scene::modes()) {
        modes.emplace_back(mode.name);
    }
    EXPECT_EQ(defs.at("mode").at("enum").get<std::vector<std::string>>(), modes);
    EXPECT_EQ(defs.at("client_type").at("enum").get<std::vector<std::string>>(),
              std::vector<std::string>(kClientMessageTypes.begin(), kClientMessageTypes.end()));
    EXPECT_EQ(defs.at("camera").at("properties").at("view").at("enum"),
              names_in_table<scene::View>());
    EXPECT_EQ(defs.at("light").at("properties").at("type").at("enum"),
              names_in_table<scene::LightType>());
    const json& settings = defs.at("settings").at("properties");
    EXPECT_EQ(settings.at("compositing").at("enum"), names_in_table<scene::Compositing>());
    EXPECT_EQ(settings.at("stage").at("enum"), names_in_table<scene::RaycastStage>());
    const json& light_buffer = settings.at("light_buffer").at("properties");
    EXPECT_EQ(light_buffer.at("builder").at("enum"), names_in_table<scene::LightBufferBuilder>());
    EXPECT_EQ(light_buffer.at("lookup").at("enum"), names_in_table<scene::LightLookup>());
}

// The numbers the schema states of the defaults: an orbit's members left out (the default camera's)
// and the maxima hello.limits announces for a server configured with nothing else; and the names
// of the formats frames are written in.
TEST(SchemaAgreement, GeneratorWritesTheDefaults) {
    const auto generated = codegen::generated_common_schema(R"({"$defs": {}})");
    ASSERT_TRUE(generated.ok()) << generated.error().to_string();
    const json defs = json::parse(*generated).at("$defs");
    const json& orbit = schema_node(defs, "camera/orbit").at("properties");
    const scene::Camera from_defaults =
            scene::orbit_camera(orbit.at("azimuth").at("default").get<double>(),
                                orbit.at("elevation").at("default").get<double>(),
                                orbit.at("distance").at("default").get<double>());
    EXPECT_LT(glm::length(from_defaults.eye - scene::Camera{}.eye), 1e-12);
    const Limits limits;
    EXPECT_EQ(schema_node(defs, "settings/size").at("items").at("maximum"), limits.max_image_side);
    EXPECT_EQ(defs.at("encoding").at("enum").get<std::vector<std::string>>(),
              std::vector<std::string>(scene::setting::encoding.choices.begin(),
                                       scene::setting::encoding.choices.end()));
    EXPECT_EQ(schema_node(defs, "settings/light_buffer/slices").at("maximum"), limits.max_slices);
    EXPECT_EQ(schema_node(defs, "settings/light_buffer/resolution").at("maximum"),
              limits.max_light_resolution);
}

TEST(SchemaAgreement, GeneratorRefusesWhatIsNotASchema) {
    EXPECT_FALSE(codegen::generated_common_schema("[1, 2]").ok());
    EXPECT_FALSE(codegen::generated_common_schema("{\"$defs\": 1}").ok());
    EXPECT_FALSE(codegen::generated_common_schema("{").ok());
}

// One member as parse_request reads it and as the schema's `request` part states it: required
// exactly when it is a plain string or a number, its JSON type, a string's length, a number's
// range and a flag's default (what the parser leaves it at when the message leaves it out).
template <class Message, class Value>
void expect_member_in_schema(const json& request, const Member<Message, Value>& member) {
    const std::string name(member.name);
    SCOPED_TRACE(name);
    ASSERT_TRUE(request.at("properties").contains(name)) << "the schema does not list it";
    const json& property = request.at("properties").at(name);
    const auto required = request.at("required").get<std::set<std::string>>();
    EXPECT_EQ(required.contains(name),
              (std::is_same_v<Value, std::string> || std::is_same_v<Value, double>));
    if constexpr (std::is_same_v<Value, double>) {
        EXPECT_EQ(property.at("type"), "number");
        EXPECT_EQ(property.at("minimum").get<double>(), member.range.min);
        EXPECT_EQ(property.at("maximum").get<double>(), member.range.max);
    } else if constexpr (std::is_same_v<Value, bool>) {
        EXPECT_EQ(property.at("type"), "boolean");
        EXPECT_EQ(property.value("default", json()), json(Message{}.*member.pointer));
    } else {
        // A string of its own, or a shared definition of one (owner_token).
        const json string = property.contains("$ref") ? schema_definition(property) : property;
        EXPECT_EQ(string.at("type"), "string");
        EXPECT_EQ(string.at("maxLength").get<std::size_t>(), member.max_bytes);
    }
}

// A client message's members as parse_request reads them (its members()) and as its schema states
// them: the same names, and each alike. `set`'s members are the state's parts, which its schema
// lists and apply_patch reads.
template <class Message>
void expect_members_in_schema() {
    const std::string type(Message::type);
    SCOPED_TRACE(type);
    const json schema = json::parse(test::read_text(test::schema_path(type)));
    const json& request = test::request_part(schema);
    if constexpr (!std::is_same_v<Message, Set>) {
        std::set<std::string> in_schema;
        for (const auto& [name, property] : request.at("properties").items()) {
            if (name != "v" && name != "type" && name != "id") {
                in_schema.insert(name);
            }
        }
        std::set<std::string> in_struct;
        if constexpr (requires { Message::members(); }) {
            std::apply(
                    [&](const auto&... member) {
                        (in_struct.emplace(member.name), ...);
                        (expect_member_in_schema(request, member), ...);
                    },
                    Message::members());
        }
        EXPECT_EQ(in_struct, in_schema);
    }
}

template <class... Messages>
void expect_members_in_schemas(std::type_identity<std::variant<Messages...>>) {
    (expect_members_in_schema<Messages>(), ...);
}

TEST(SchemaAgreement, ClientMessageMembersAreTheirSchemasProperties) {
    expect_members_in_schemas(std::type_identity<ClientMessage>{});
}

// hello.schema.json's mode capabilities are written from the kinds' name tables, never by hand.
TEST(SchemaAgreement, HelloSchemaIsGenerated) {
    const std::string committed =
            test::read_text(std::filesystem::path(PENUMBRA_PROTO_DIR) / "v1" / "hello.schema.json");
    const auto generated = codegen::generated_hello_schema(committed);
    ASSERT_TRUE(generated.ok()) << generated.error().to_string();
    EXPECT_TRUE(*generated == committed)
            << "proto/v1/hello.schema.json differs from what the C++ tables make of it: run "
               "scripts/update-schema.sh";
    const json written = json::parse(*codegen::generated_hello_schema(R"({"title": "hello"})"));
    const json& item = written.at("properties").at("modes").at("items").at("properties");
    EXPECT_EQ(item.at("technique").at("enum"), names_in_table<scene::Technique>());
    EXPECT_EQ(item.at("gradients").at("enum"), names_in_table<scene::Gradients>());
    // Each limit's default is what hello sends with nothing configured.
    const json& limits = written.at("properties").at("limits").at("properties");
    const Limits defaults;
    EXPECT_EQ(limits.at("max_message_bytes").at("default"), defaults.max_message_bytes);
    EXPECT_EQ(limits.at("max_image_side").at("default"), defaults.max_image_side);
    EXPECT_EQ(limits.at("max_slices").at("default"), defaults.max_slices);
    EXPECT_EQ(limits.at("max_requests_per_second").at("default").get<double>(),
              defaults.max_requests_per_second);
    EXPECT_EQ(limits.at("max_frame_work").at("default").get<double>(), defaults.max_frame_work);
    EXPECT_EQ(limits.at("max_transfer_function_points").at("default"),
              max_transfer_function_points);
    EXPECT_EQ(limits.at("max_hounsfield_position").at("default").get<double>(),
              scene::max_hounsfield_position);
    EXPECT_FALSE(codegen::generated_hello_schema("[1]").ok());
}

// What the transfer function's schema restates of C++: the preset names, the position spaces, the
// most points, the longest name and how far a Hounsfield position reaches.
TEST(SchemaAgreement, GeneratorWritesTheTransferFunctionsNamesAndLimits) {
    const auto generated = codegen::generated_common_schema(R"({"$defs": {}})");
    ASSERT_TRUE(generated.ok()) << generated.error().to_string();
    const json defs = json::parse(*generated).at("$defs");
    EXPECT_EQ(defs.at("preset").at("enum").get<std::vector<std::string>>(), scene::preset_names());
    const json& points = defs.at("transfer_function").at("oneOf").at(1).at("properties");
    EXPECT_EQ(points.at("space").at("enum"), names_in_table<scene::PositionSpace>());
    EXPECT_EQ(points.at("name").at("maxLength"), max_transfer_function_name_bytes);
    EXPECT_EQ(points.at("name").at("default"), unnamed_transfer_function);
    EXPECT_EQ(points.at("space").at("default"), scene::name_of(scene::TransferFunction{}.space));
    for (const char* list : {"colors", "opacities"}) {
        SCOPED_TRACE(list);
        EXPECT_EQ(points.at(list).at("maxItems"), max_transfer_function_points);
        const json& x = points.at(list).at("items").at("properties").at("x");
        EXPECT_EQ(x.at("maximum").get<double>(), scene::max_hounsfield_position);
        EXPECT_EQ(x.at("minimum").get<double>(), -scene::max_hounsfield_position);
    }
}

// hello.schema.json names the mode capabilities as scene's name tables do: every kind, no other.
TEST(SchemaAgreement, HelloModeCapabilitiesNameEveryKind) {
    const json hello = schema("hello.schema.json");
    const json& item = hello.at("properties").at("modes").at("items").at("properties");
    EXPECT_EQ(item.at("technique").at("enum"), names_in_table<scene::Technique>());
    EXPECT_EQ(item.at("shadows").at("enum"), names_in_table<scene::ShadowKind>());
    EXPECT_EQ(item.at("scattering").at("enum"), names_in_table<scene::ScatteringKind>());
    EXPECT_EQ(item.at("gradients").at("enum"), names_in_table<scene::Gradients>());
}

// The other way round: a limit written into the schema for a new setting needs its row in C++.
void collect_bounded(const json& node, const std::string& field, std::set<std::string>& out) {
    if (node.contains("minimum") || node.contains("maximum")) {
        out.insert(field);
    }
    if (node.contains("properties")) {
        for (const auto& [name, child] : node.at("properties").items()) {
            collect_bounded(child, field + "/" + name, out);
        }
    }
}

TEST(SchemaAgreement, EveryBoundedSettingInTheSchemaHasARange) {
    const json defs = schema("common.schema.json").at("$defs");
    std::set<std::string> bounded;
    for (const char* part : {"camera", "light", "settings", "output"}) {
        collect_bounded(defs.at(part), part, bounded);
    }
    std::set<std::string> table;
    for (const scene::Setting* setting : scene::kSettings) {
        const bool bounded_kind = setting->kind == scene::SettingKind::number ||
                                  setting->kind == scene::SettingKind::whole;
        if (bounded_kind && setting->path.find('/') != std::string_view::npos) {
            table.emplace(setting->path);
        }
    }
    EXPECT_EQ(bounded, table);
}

// The web client checks messages with the ranges of a hello (no copy of its own); its tests use
// one recorded from a server, which must announce what the server announces now (its renderer
// aside).
TEST(SchemaAgreement, TheWebClientsRecordedHelloIsTheServers) {
    const std::filesystem::path recorded_file =
            std::filesystem::path(PENUMBRA_PROTO_DIR).parent_path() / "client_web" / "test" /
            "fixtures" / "server_messages.jsonl";
    const std::string committed = test::read_text(recorded_file);
    const auto generated = codegen::generated_recorded_hello(committed);
    ASSERT_TRUE(generated) << generated.error().to_string();
    EXPECT_TRUE(*generated == committed)
            << recorded_file << " records a hello that is not the server's: run "
            << "scripts/update-schema.sh";
}

TEST(SchemaAgreement, TheRecordedHelloIsRewrittenAsTheServerSendsIt) {
    const auto stale = codegen::generated_recorded_hello(
            "{\"ranges\":{},\"renderer\":{\"renderer\":\"r\"},\"type\":\"hello\",\"v\":1}\n"
            "{\"type\":\"opened\"}\n");
    ASSERT_TRUE(stale) << stale.error().to_string();
    const json hello = json::parse(stale->substr(0, stale->find('\n')));
    json sent = json::parse(hello_message(Limits{}, {"llvmpipe", "4.5", "linux", true}));
    sent["renderer"] = {{"renderer", "r"}};
    EXPECT_EQ(hello, sent);
    EXPECT_EQ(stale->substr(stale->find('\n')), "\n{\"type\":\"opened\"}\n");
    EXPECT_FALSE(codegen::generated_recorded_hello("{\"type\":\"opened\"}\n").ok());
}

// The web client's names and views are the server's: a name, a format or a view pose changed in C++
// changes the module the script writes, and the committed one must follow.
TEST(SchemaAgreement, TheWebClientsServerTablesAreGenerated) {
    const std::filesystem::path file = std::filesystem::path(PENUMBRA_PROTO_DIR).parent_path() /
                                       "client_web" / codegen::kClientTablesPath;
    ASSERT_TRUE(std::filesystem::exists(file)) << file << ": run scripts/update-schema.sh";
    EXPECT_TRUE(codegen::generated_client_tables() == test::read_text(file))
            << file << " differs from what the C++ tables make of it: run "
            << "scripts/update-schema.sh";
    // What the method panel shows before a session's state arrives: a new session's settings.
    const Limits limits;
    const scene::FrameRequest start = scene::starting_frame(scene_limits(limits));
    const std::string text = codegen::generated_client_tables();
    const std::size_t settings = text.find("export const DEFAULT_SETTINGS = {\n");
    ASSERT_NE(settings, std::string::npos);
    for (const std::string& member :
         {"  mode: '" + std::string(scene::to_string(start.settings.mode)) + "',\n",
          std::string("  phong: ") + (start.settings.phong ? "true" : "false") + ",\n",
          "    slices: " + std::to_string(start.settings.light_buffer.slices) + ",\n",
          "    builder: '" + std::string(scene::to_string(start.settings.light_buffer.builder)) +
                  "',\n",
          "  size: [" + std::to_string(start.settings.width) + ", " +
                  std::to_string(start.settings.height) + "],\n"}) {
        EXPECT_NE(text.find(member, settings), std::string::npos) << member;
    }
    const std::size_t output = text.find("export const DEFAULT_OUTPUT = {\n");
    ASSERT_NE(output, std::string::npos);
    EXPECT_NE(
            text.find("  encoding: '" + std::string(scene::name_of(scene::FrameFormat{})) + "',\n",
                      output),
            std::string::npos);
    EXPECT_NE(
            text.find("  jpeg_quality: " + std::to_string(scene::kDefaultFrameJpegQuality) + ",\n",
                      output),
            std::string::npos);
}

// The list `constant` as the generated module writes it: "export const NAME = ['a', 'b'] as
// const;".
std::vector<std::string> generated_list(const std::string& text, const std::string& constant) {
    const std::regex list("export const " + constant + R"( = \[([^\]]*)\] as const;)");
    std::smatch match;
    EXPECT_TRUE(std::regex_search(text, match, list)) << constant;
    std::vector<std::string> names;
    const std::string items = match[1].str();
    const std::regex name("'([^']*)'");
    for (auto it = std::sregex_iterator(items.begin(), items.end(), name);
         it != std::sregex_iterator(); ++it) {
        names.push_back((*it)[1].str());
    }
    return names;
}

template <scene::NamedEnum Enum>
std::vector<std::string> table_names() {
    std::vector<std::string> names;
    for (const scene::EnumName<Enum>& row : scene::names<Enum>()) {
        names.emplace_back(row.name);
    }
    return names;
}

glm::dvec3 generated_vec3(const std::string& text) {
    glm::dvec3 v{};
    std::istringstream in(text);
    char separator = 0;
    in >> v.x >> separator >> v.y >> separator >> v.z;
    return v;
}

TEST(SchemaAgreement, TheClientTablesHoldTheServersNamesAndViews) {
    const std::string text = codegen::generated_client_tables();
    const std::vector<std::string> encodings(scene::setting::encoding.choices.begin(),
                                             scene::setting::encoding.choices.end());
    EXPECT_EQ(generated_list(text, "ENCODINGS"), encodings);
    EXPECT_EQ(generated_list(text, "COMPOSITINGS"), table_names<scene::Compositing>());
    EXPECT_EQ(generated_list(text, "STAGES"), table_names<scene::RaycastStage>());
    EXPECT_EQ(generated_list(text, "BUILDERS"), table_names<scene::LightBufferBuilder>());
    EXPECT_EQ(generated_list(text, "LIGHT_LOOKUPS"), table_names<scene::LightLookup>());
    EXPECT_EQ(generated_list(text, "LIGHT_TYPES"), table_names<scene::LightType>());
    EXPECT_EQ(generated_list(text, "POSITION_SPACES"), table_names<scene::PositionSpace>());
    EXPECT_EQ(generated_list(text, "VIEWS"), table_names<scene::View>());
    EXPECT_EQ(generated_list(text, "TECHNIQUES"), table_names<scene::Technique>());
    EXPECT_EQ(generated_list(text, "SHADOW_KINDS"), table_names<scene::ShadowKind>());
    EXPECT_EQ(generated_list(text, "SCATTERING_KINDS"), table_names<scene::ScatteringKind>());
    EXPECT_EQ(generated_list(text, "GRADIENTS"), table_names<scene::Gradients>());
    // Each view's eye direction and up, as the server poses its camera for that view.
    for (const scene::EnumName<scene::View>& row : scene::names<scene::View>()) {
        SCOPED_TRACE(std::string(row.name));
        const std::regex pose("  " + std::string(row.name) +
                              R"(: \{ side: \[([^\]]*)\], up: \[([^\]]*)\] \},)");
        std::smatch match;
        ASSERT_TRUE(std::regex_search(text, match, pose));
        const scene::Camera camera = scene::view_camera(row.value, 3.0, glm::dvec3(0.5, -1, 2));
        const glm::dvec3 side = generated_vec3(match[1].str());
        const glm::dvec3 up = generated_vec3(match[2].str());
        EXPECT_LT(glm::length(camera.target + 3.0 * side - camera.eye), 1e-12);
        EXPECT_LT(glm::length(up - camera.up), 1e-12);
    }
    const auto constant = [&](const std::string& name) {
        const std::regex number("export const " + name + R"( = ([0-9.e+]+);)");
        std::smatch match;
        EXPECT_TRUE(std::regex_search(text, match, number)) << name;
        return match.empty() ? -1.0 : std::stod(match[1].str());
    };
    EXPECT_EQ(constant("DEFAULT_CAMERA_DISTANCE"), scene::default_camera_distance);
    EXPECT_EQ(constant("DEFAULT_FOV"), scene::Camera{}.fov_y_degrees);
    EXPECT_EQ(constant("MAX_ORBIT_ELEVATION"), scene::max_orbit_elevation);
    EXPECT_NE(text.find("export const UNNAMED_TRANSFER_FUNCTION = '" +
                        std::string(unnamed_transfer_function) + "';"),
              std::string::npos);
    EXPECT_NE(text.find("= '" + std::string(scene::name_of(scene::TransferFunction{}.space)) +
                        "';\n/** The name of a transfer function"),
              std::string::npos);
    // The limits a server sends with nothing configured, each as hello has it.
    const Limits defaults;
    const auto limit = [&](const std::string& name) {
        const std::regex number("  " + name + R"(: ([0-9.e+]+),)");
        std::smatch match;
        EXPECT_TRUE(std::regex_search(text, match, number)) << name;
        return match.empty() ? -1.0 : std::stod(match[1].str());
    };
    EXPECT_EQ(limit("max_image_side"), defaults.max_image_side);
    EXPECT_EQ(limit("max_requests_per_second"), defaults.max_requests_per_second);
    EXPECT_EQ(limit("max_frame_work"), defaults.max_frame_work);
    EXPECT_EQ(limit("max_transfer_function_points"), max_transfer_function_points);
}

}  // namespace
}  // namespace penumbra::protocol
