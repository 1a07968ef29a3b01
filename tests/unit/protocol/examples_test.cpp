#include "examples.hpp"

#include <penumbra/protocol/messages.hpp>
#include <penumbra/protocol/scene_json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>
#include <variant>

namespace penumbra::protocol {
namespace {

using nlohmann::json;
using test::invalid_examples;
using test::read_text;
using test::valid_examples;

// The variant alternative each client message type parses to, from the alternatives' own names.
std::size_t expected_index(const std::string& type) {
    const auto found = std::find(kClientMessageTypes.begin(), kClientMessageTypes.end(), type);
    EXPECT_NE(found, kClientMessageTypes.end()) << "no alternative of ClientMessage is " << type;
    return static_cast<std::size_t>(found - kClientMessageTypes.begin());
}

std::set<std::string> client_message_types() {
    return {kClientMessageTypes.begin(), kClientMessageTypes.end()};
}

TEST(ProtocolExamples, EveryValidExampleParsesToItsType) {
    const auto examples = valid_examples();
    ASSERT_GE(examples.size(), 20U);
    std::set<std::string> types;
    for (const auto& [name, text] : examples) {
        SCOPED_TRACE(name);
        const auto request = parse_request(text, Limits{});
        ASSERT_TRUE(request.ok()) << request.error().to_string();
        const auto j = json::parse(text);
        const std::string type = j.at("type").get<std::string>();
        types.insert(type);
        EXPECT_EQ(request->message.index(), expected_index(type));
        if (j.contains("id")) {
            ASSERT_TRUE(request->id.has_value());
            EXPECT_EQ(*request->id, j.at("id").get<std::int64_t>());
        } else {
            EXPECT_FALSE(request->id.has_value());
        }
    }
    EXPECT_EQ(types, client_message_types()) << "every client message type has a valid example";
}

// A message is added by its alternative in ClientMessage; its schema follows its name and holds
// its examples (JSON Schema's `examples`), each a message of that type.
TEST(ProtocolExamples, EveryClientMessageHasItsSchemaAndItsExample) {
    for (const std::string_view type : kClientMessageTypes) {
        const std::string name(type);
        SCOPED_TRACE(name);
        const auto schema_path = test::schema_path(type);
        ASSERT_TRUE(std::filesystem::exists(schema_path)) << schema_path;
        const json schema = json::parse(read_text(schema_path));
        const json& request = test::request_part(schema);
        EXPECT_EQ(request.at("properties").at("type").at("const"), name);
        ASSERT_TRUE(request.contains("examples")) << schema_path << " has no examples";
        ASSERT_FALSE(request.at("examples").empty()) << schema_path << " has no examples";
        for (const json& example : request.at("examples")) {
            const auto parsed = parse_request(example.dump(), Limits{});
            ASSERT_TRUE(parsed.ok()) << example.dump() << ": " << parsed.error().to_string();
            EXPECT_EQ(kClientMessageTypes.at(parsed->message.index()), type) << example.dump();
        }
    }
}

TEST(ProtocolExamples, ValidSetExamplesApplyToADefaultSession) {
    for (const auto& [name, text] : valid_examples()) {
        const auto request = parse_request(text, Limits{});
        ASSERT_TRUE(request.ok());
        if (const auto* set = std::get_if<Set>(&request->message)) {
            SCOPED_TRACE(name);
            scene::State state;
            state.frame.transfer_function = scene::preset("grey_ramp").value();
            const auto status = apply_patch(set->patch, state, Limits{});
            EXPECT_TRUE(status.ok()) << status.error().to_string();
        }
    }
}

// Why a message is refused: by parse_request, or, for a `set` that parses, when its patch is
// applied to a session's state, where a patch is checked.
base::Status refusal(const std::string& text) {
    const auto request = parse_request(text, Limits{});
    if (!request) {
        return request.error();
    }
    const auto* set = std::get_if<Set>(&request->message);
    if (set == nullptr) {
        return base::Ok{};
    }
    scene::State state;
    state.frame.transfer_function = scene::preset("grey_ramp").value();
    return apply_patch(set->patch, state, Limits{});
}

TEST(ProtocolExamples, EveryInvalidExampleFailsWithItsCodeAndField) {
    const auto examples = invalid_examples();
    ASSERT_GE(examples.size(), 30U);
    for (const auto& example : examples) {
        SCOPED_TRACE(example.name + ": " + example.text);
        const auto refused = refusal(example.text);
        ASSERT_FALSE(refused.ok());
        EXPECT_EQ(wire_name(refused.error().code), example.code) << refused.error().to_string();
        EXPECT_EQ(refused.error().where, example.field) << refused.error().to_string();
        EXPECT_FALSE(refused.error().message.empty());
    }
}

TEST(ProtocolExamples, InvalidExamplesUseOnlyDeclaredErrorCodes) {
    std::set<std::string> codes;
    for (const base::ErrorCode code : kWireCodes) {
        codes.emplace(base::name_of(code));
    }
    for (const auto& example : invalid_examples()) {
        EXPECT_TRUE(codes.contains(example.code)) << example.name << ": " << example.code;
    }
}

TEST(ProtocolExamples, InvalidSetPatchesLeaveTheSessionUnchanged) {
    for (const auto& example : invalid_examples()) {
        auto j = json::parse(example.text, nullptr, false);
        if (j.is_discarded() || !j.is_object() || j.value("type", json()) != "set" ||
            example.field == "/v" || example.field == "/id") {
            continue;
        }
        SCOPED_TRACE(example.name);
        j.erase("v");
        j.erase("type");
        j.erase("id");
        scene::State state;
        state.frame.transfer_function = scene::preset("ct_bone").value();
        state.frame.settings.mode = scene::Mode::sbrc;
        const std::string before = state_to_json(state);
        const auto status = apply_patch(j.dump(), state, Limits{});
        ASSERT_FALSE(status.ok());
        EXPECT_EQ(wire_name(status.error().code), example.code);
        EXPECT_EQ(status.error().where, example.field);
        EXPECT_EQ(state_to_json(state), before);
    }
}

}  // namespace
}  // namespace penumbra::protocol
