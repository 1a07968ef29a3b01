#include <penumbra/protocol/messages.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <set>
#include <string>
#include <tuple>
#include <type_traits>
#include <variant>
#include <vector>

namespace penumbra::protocol {
namespace {

using nlohmann::json;

TEST(ParseRequest, ReadsTheMembersOfEachMessage) {
    const Limits limits;
    const auto open = parse_request(R"({"v":1,"type":"open","id":7,"volume":"colin27"})", limits);
    ASSERT_TRUE(open.ok());
    EXPECT_EQ(open->id, 7);
    EXPECT_EQ(std::get<Open>(open->message).volume, "colin27");

    const auto join = parse_request(R"({"v":1,"type":"join","session":"s9"})", limits);
    ASSERT_TRUE(join.ok());
    EXPECT_FALSE(join->id.has_value());
    EXPECT_EQ(std::get<Join>(join->message).session, "s9");

    const auto resume = parse_request(
            R"({"v":1,"type":"resume","id":2,"session":"s9","owner_token":"0f1e"})", limits);
    ASSERT_TRUE(resume.ok());
    EXPECT_EQ(std::get<Resume>(resume->message).session, "s9");
    EXPECT_EQ(std::get<Resume>(resume->message).owner_token, "0f1e");
    EXPECT_FALSE(std::get<Resume>(resume->message).volume.has_value());
    const auto resume_on = parse_request(
            R"({"v":1,"type":"resume","session":"s9","owner_token":"0f1e","volume":"ch2.nii.gz"})",
            limits);
    ASSERT_TRUE(resume_on.ok());
    EXPECT_EQ(std::get<Resume>(resume_on->message).volume, "ch2.nii.gz");

    const auto still = parse_request(R"({"v":1,"type":"render"})", limits);
    ASSERT_TRUE(still.ok());
    EXPECT_FALSE(std::get<Render>(still->message).interactive);
    const auto drag = parse_request(R"({"v":1,"type":"render","interactive":true})", limits);
    ASSERT_TRUE(drag.ok());
    EXPECT_TRUE(std::get<Render>(drag->message).interactive);
}

TEST(ParseRequest, SetCarriesOnlyThePatch) {
    const auto request = parse_request(
            R"({"v":1,"type":"set","id":3,"light":{"intensity":2},"output":{"encoding":"png"}})",
            Limits{});
    ASSERT_TRUE(request.ok());
    scene::State state;
    ASSERT_TRUE(apply_patch(std::get<Set>(request->message).patch, state, Limits{}).ok());
    scene::State expected;
    ASSERT_TRUE(apply_patch(R"({"light":{"intensity":2},"output":{"encoding":"png"}})", expected,
                            Limits{})
                        .ok());
    EXPECT_EQ(state_to_json(state), state_to_json(expected));
    EXPECT_NE(state_to_json(state), state_to_json(scene::State{}));
}

TEST(ParseRequest, AcceptsTheExtremeIds) {
    for (const char* id : {"-9223372036854775808", "9223372036854775807", "0"}) {
        const auto request =
                parse_request(std::string(R"({"v":1,"type":"stats","id":)") + id + "}", Limits{});
        ASSERT_TRUE(request.ok()) << id;
        EXPECT_EQ(std::to_string(*request->id), id);
    }
}

TEST(ParseRequest, RejectsMessagesLongerThanTheLimit) {
    Limits limits;
    const std::string message = R"({"v":1,"type":"render","id":12345})";
    limits.max_message_bytes = message.size();
    EXPECT_TRUE(parse_request(message, limits).ok()) << "a message of exactly the limit passes";

    limits.max_message_bytes = message.size() - 1;
    const auto request = parse_request(message, limits);
    ASSERT_FALSE(request.ok());
    EXPECT_EQ(request.error().code, base::ErrorCode::message_too_large);
    EXPECT_EQ(request.error().where, "/");
}

// A `set` is parsed once, by parse_request, and checked once, when it is applied to the session's
// state: parse_request takes a patch whose values are out of range, and applying it refuses it.
base::Status parsed_then_applied(const std::string& text, const Limits& limits) {
    const auto request = parse_request(text, limits);
    if (!request) {
        ADD_FAILURE() << "a set is not checked when it is parsed: " << request.error().to_string();
        return request.error();
    }
    scene::State state;
    state.frame.transfer_function = scene::preset("grey_ramp").value();
    state.frame.settings.width = std::min(state.frame.settings.width, limits.max_image_side);
    state.frame.settings.height = std::min(state.frame.settings.height, limits.max_image_side);
    state.frame.settings.light_buffer.slices =
            std::min(state.frame.settings.light_buffer.slices, limits.max_slices);
    return apply_patch(std::get<Set>(request->message).patch, state, limits);
}

TEST(ParseRequest, ASetIsCheckedWhenAppliedNotWhenParsed) {
    const std::string unknown = R"({"v":1,"type":"set","id":3,"teleport":{}})";
    const std::string out_of_range = R"({"v":1,"type":"set","camera":{"fov":400}})";
    for (const std::string& text : {unknown, out_of_range}) {
        SCOPED_TRACE(text);
        EXPECT_TRUE(parse_request(text, Limits{}).ok());
    }
    const auto refused_unknown = parsed_then_applied(unknown, Limits{});
    ASSERT_FALSE(refused_unknown.ok());
    EXPECT_EQ(refused_unknown.error().code, base::ErrorCode::unknown_field);
    EXPECT_EQ(refused_unknown.error().where, "/teleport");
    const auto refused_range = parsed_then_applied(out_of_range, Limits{});
    ASSERT_FALSE(refused_range.ok());
    EXPECT_EQ(refused_range.error().where, "/camera/fov");
}

TEST(ParseRequest, ChecksSizeAgainstTheGivenLimitsNotTheDefaults) {
    Limits small;
    small.max_image_side = 256;
    small.max_slices = 16;
    const std::string size = R"({"v":1,"type":"set","settings":{"size":[512,128]}})";
    const std::string slices = R"({"v":1,"type":"set","settings":{"light_buffer":{"slices":32}}})";
    EXPECT_TRUE(parsed_then_applied(size, Limits{}).ok());
    EXPECT_TRUE(parsed_then_applied(slices, Limits{}).ok());
    const auto big_size = parsed_then_applied(size, small);
    ASSERT_FALSE(big_size.ok());
    EXPECT_EQ(big_size.error().code, base::ErrorCode::out_of_range);
    EXPECT_EQ(big_size.error().where, "/settings/size/0");
    const auto many_slices = parsed_then_applied(slices, small);
    ASSERT_FALSE(many_slices.ok());
    EXPECT_EQ(many_slices.error().where, "/settings/light_buffer/slices");

    Limits large;
    large.max_image_side = 4096;
    EXPECT_TRUE(
            parsed_then_applied(R"({"v":1,"type":"set","settings":{"size":[4096,4096]}})", large)
                    .ok());
}

TEST(ParseRequest, RejectsTooManyTransferFunctionPoints) {
    json points = json::array();
    for (int i = 0; i <= 256; ++i) {
        points.push_back({{"x", i / 256.0}, {"alpha", 0.5}});
    }
    json message = {{"v", 1}, {"type", "set"}, {"transfer_function", {{"opacities", points}}}};
    auto refused = parsed_then_applied(message.dump(), Limits{});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::out_of_range);
    EXPECT_EQ(refused.error().where, "/transfer_function/opacities");

    message["transfer_function"]["opacities"].erase(0);
    EXPECT_TRUE(parsed_then_applied(message.dump(), Limits{}).ok()) << "256 points are allowed";
}

TEST(RequestIdOf, EchoesTheIdOfAMessageThatFailedToParse) {
    EXPECT_EQ(request_id_of(R"({"v":1,"type":"teleport","id":42})"), 42);
    EXPECT_EQ(request_id_of(R"({"v":2,"type":"render","id":-5})"), -5);
}

TEST(RequestIdOf, HasNoIdForMalformedOrNonIntegerIds) {
    EXPECT_FALSE(request_id_of(R"({"v":1,"id":4)").has_value());
    EXPECT_FALSE(request_id_of(R"([{"id":4}])").has_value());
    EXPECT_FALSE(request_id_of(R"({"v":1,"id":"4"})").has_value());
    EXPECT_FALSE(request_id_of(R"({"v":1,"id":4.5})").has_value());
    EXPECT_FALSE(request_id_of(R"({"v":1,"id":18446744073709551615})").has_value());
}

TEST(ServerMessages, CarryVersionTypeAndTheRequestId) {
    const json ack = json::parse(ack_message(9, "set"));
    EXPECT_EQ(ack, json::parse(R"({"v":1,"type":"ack","id":9,"of":"set"})"));
    const json no_id = json::parse(ack_message(std::nullopt, "close"));
    EXPECT_FALSE(no_id.contains("id"));

    const json error = json::parse(error_message(
            4, base::make_error(base::ErrorCode::unknown_volume, "no such volume", "/volume")));
    EXPECT_EQ(error, json::parse(R"({"v":1,"type":"error","id":4,"code":"unknown_volume",
                                     "message":"no such volume","field":"/volume"})"));
}

TEST(ServerMessages, HelloAnnouncesTheLimits) {
    Limits limits;
    limits.max_image_side = 1000;
    limits.max_requests_per_second = 30.5;
    const json hello = json::parse(hello_message(limits, {"llvmpipe", "4.5", "linux", true}));
    EXPECT_EQ(hello.at("type"), "hello");
    EXPECT_EQ(hello.at("v"), 1);
    EXPECT_FALSE(hello.contains("id"));
    EXPECT_EQ(hello.at("limits").at("max_image_side"), 1000);
    EXPECT_EQ(hello.at("limits").at("max_message_bytes"), limits.max_message_bytes);
    EXPECT_EQ(hello.at("limits").at("max_requests_per_second"), 30.5);
    EXPECT_EQ(hello.at("limits").at("max_json_depth"), limits.max_json_depth);
    EXPECT_EQ(hello.at("renderer").at("software"), true);
}

// The client's method panel shows and greys out what the server says each mode computes.
TEST(ServerMessages, HelloDescribesEveryModeOfTheModeTable) {
    const json hello = json::parse(hello_message(Limits{}, {"llvmpipe", "4.5", "linux", true}));
    const json& modes = hello.at("modes");
    ASSERT_EQ(modes.size(), scene::modes().size());
    for (std::size_t i = 0; i < modes.size(); ++i) {
        const scene::ModeInfo& row = scene::modes()[i];
        EXPECT_EQ(modes[i].at("name"), row.name);
        EXPECT_EQ(modes[i].at("summary"), row.summary);
        EXPECT_EQ(modes[i].at("technique"), scene::to_string(row.technique));
        EXPECT_EQ(modes[i].at("shadows"), scene::to_string(row.shadows));
        EXPECT_EQ(modes[i].at("scattering"), scene::to_string(row.scattering));
        EXPECT_EQ(modes[i].at("gradients"), scene::to_string(row.gradients));
    }
    EXPECT_EQ(modes[5].at("scattering"), "cone");
    EXPECT_EQ(modes[6].at("shadows"), "rays");
}

// The client checks messages and sizes its sliders from these: it holds no ranges of its own.
TEST(ServerMessages, HelloAnnouncesEverySettingsRangeOfTheTable) {
    const json hello = json::parse(hello_message(Limits{}, {"llvmpipe", "4.5", "linux", true}));
    const json& ranges = hello.at("ranges");
    std::size_t announced_rows = 0;
    for (const scene::Setting* range : scene::kSettings) {
        if (!announces_range(*range)) {
            EXPECT_FALSE(ranges.contains(std::string(range->path))) << range->path;
            continue;
        }
        ++announced_rows;
        SCOPED_TRACE(range->path);
        const json& announced = ranges.at(std::string(range->path));
        EXPECT_EQ(announced.at("min").get<double>(), range->min);
        EXPECT_EQ(announced.at("max").get<double>(), range->max);
        EXPECT_EQ(announced.at("integer").get<bool>(), range->integer());
        // A client's hint for the setting's control; a row without a summary announces none.
        if (range->summary.empty()) {
            EXPECT_FALSE(announced.contains("summary"));
        } else {
            EXPECT_EQ(announced.at("summary").get<std::string>(), range->summary);
        }
    }
    EXPECT_EQ(ranges.size(), announced_rows);
    EXPECT_EQ(ranges.at("settings/light_buffer/slab_samples").at("max"), scene::kMaxSlabSamples);
    EXPECT_EQ(ranges.at("camera/fov").at("summary"), scene::setting::fov_degrees.summary);
    EXPECT_EQ(ranges.at("output/jpeg_quality").at("min"), scene::setting::jpeg_quality.min);
    EXPECT_EQ(ranges.at("output/jpeg_quality").at("max"), scene::setting::jpeg_quality.max);
}

// The client offers and shows the presets from hello: each is what `{"preset": NAME}` sets, in
// the shape a state reports it, so that sending it back as points gives the same function.
TEST(ServerMessages, HelloCarriesEveryPresetAsAStateHoldsIt) {
    const json hello = json::parse(hello_message(Limits{}, {"llvmpipe", "4.5", "linux", true}));
    const json& presets = hello.at("presets");
    const std::vector<std::string> names = scene::preset_names();
    ASSERT_EQ(presets.size(), names.size());
    for (std::size_t i = 0; i < names.size(); ++i) {
        SCOPED_TRACE(names[i]);
        const scene::TransferFunction expected = scene::preset(names[i]).value();
        EXPECT_EQ(presets[i].at("name"), names[i]);
        EXPECT_EQ(presets[i].at("space"), scene::to_string(expected.space));

        scene::State by_name;
        ASSERT_TRUE(apply_patch(json({{"transfer_function", {{"preset", names[i]}}}}).dump(),
                                by_name, Limits{}));
        EXPECT_EQ(presets[i], json::parse(state_to_json(by_name)).at("transfer_function"));
        scene::State by_points;
        ASSERT_TRUE(
                apply_patch(json({{"transfer_function", presets[i]}}).dump(), by_points, Limits{}));
        EXPECT_EQ(by_points.frame.transfer_function, expected);
    }
    EXPECT_EQ(hello.at("nominal_ct_range"),
              json::array({scene::nominal_ct_domain.min, scene::nominal_ct_domain.max}));
}

template <class Message, class Value>
constexpr bool holds_string(const Member<Message, Value>&) {
    return !std::is_same_v<Value, bool> && !std::is_same_v<Value, double>;
}

template <class Message, class Value>
constexpr bool holds_number(const Member<Message, Value>&) {
    return std::is_same_v<Value, double>;
}

// The string members of the client messages as hello's max_string_bytes keys them
// ("type/member"), read from each message's own `members()`.
template <class... Messages>
std::set<std::string> string_member_keys(std::type_identity<std::variant<Messages...>>) {
    std::set<std::string> keys;
    const auto add = [&]<class Message>(std::type_identity<Message>) {
        if constexpr (requires { Message::members(); }) {
            std::apply(
                    [&](const auto&... listed) {
                        ((holds_string(listed) ? void(keys.insert(std::string(Message::type) + "/" +
                                                                  std::string(listed.name)))
                                               : void()),
                         ...);
                    },
                    Message::members());
        }
    };
    (add(std::type_identity<Messages>{}), ...);
    return keys;
}

// A message of `type` that parse_request accepts: each string member its `members()` lists, one
// byte long, and each number its range's least.
template <class... Messages>
json smallest_message(const std::string& type, std::type_identity<std::variant<Messages...>>) {
    json message = {{"v", 1}, {"type", type}};
    const auto fill = [&]<class Message>(std::type_identity<Message>) {
        if constexpr (requires { Message::members(); }) {
            if (type == Message::type) {
                std::apply(
                        [&](const auto&... listed) {
                            ((holds_string(listed) ? void(message[std::string(listed.name)] = "a")
                                                   : void()),
                             ...);
                            ((holds_number(listed)
                                      ? void(message[std::string(listed.name)] = listed.range.min)
                                      : void()),
                             ...);
                        },
                        Message::members());
            }
        }
    };
    (fill(std::type_identity<Messages>{}), ...);
    return message;
}

// The limits a client needs for its own checks that are not configured but fixed by the protocol
// and scene: the points of a transfer function, how far a Hounsfield position reaches, and the
// longest string each string member of a request takes, as parse_request reads it.
TEST(ServerMessages, HelloAnnouncesTheFixedLimitsTheParserApplies) {
    const json hello = json::parse(hello_message(Limits{}, {"llvmpipe", "4.5", "linux", true}));
    const json& limits = hello.at("limits");
    EXPECT_EQ(limits.at("max_transfer_function_points"), max_transfer_function_points);
    EXPECT_EQ(limits.at("max_hounsfield_position").get<double>(), scene::max_hounsfield_position);
    const json& lengths = limits.at("max_string_bytes");
    // Every string member is announced (one declared without a length would be missing), and a
    // transfer function's name, which `set`'s patch carries.
    std::set<std::string> expected_keys = string_member_keys(std::type_identity<ClientMessage>{});
    expected_keys.insert(std::string(Set::type) + "/transfer_function/name");
    std::set<std::string> announced_keys;
    for (const auto& item : lengths.items()) {
        announced_keys.insert(item.key());
    }
    EXPECT_EQ(announced_keys, expected_keys);
    // Each announced length is the one the parser holds the member to.
    for (const auto& [key, bytes] : lengths.items()) {
        SCOPED_TRACE(key);
        const std::size_t slash = key.find('/');
        const std::string type = key.substr(0, slash);
        const std::string pointer = key.substr(slash);
        json message = smallest_message(type, std::type_identity<ClientMessage>{});
        const std::size_t n = bytes.get<std::size_t>();
        message[json::json_pointer(pointer)] = std::string(n, 'a');
        const auto fits = parse_request(message.dump(), Limits{});
        ASSERT_TRUE(fits.ok()) << fits.error().to_string();
        if (type == Set::type) {
            scene::State state;
            EXPECT_TRUE(apply_patch(std::get<Set>(fits->message).patch, state, Limits{}));
        }
        message[json::json_pointer(pointer)] = std::string(n + 1, 'a');
        const auto too_long = parse_request(message.dump(), Limits{});
        if (type == Set::type) {
            ASSERT_TRUE(too_long.ok());
            scene::State state;
            const auto applied =
                    apply_patch(std::get<Set>(too_long->message).patch, state, Limits{});
            ASSERT_FALSE(applied);
            EXPECT_EQ(applied.error().code, base::ErrorCode::out_of_range);
            EXPECT_EQ(applied.error().where, "/transfer_function/name");
        } else {
            ASSERT_FALSE(too_long.ok());
            EXPECT_EQ(too_long.error().code, base::ErrorCode::out_of_range);
            EXPECT_EQ(too_long.error().where, pointer);
        }
    }
}

TEST(ServerMessages, OpenedAndJoinedCarryTheSessionStateAndOnlyOpenedTheOwnerToken) {
    scene::State state;
    state.frame.transfer_function = scene::preset("mri_skin").value();
    VolumeSummary volume;
    volume.id = "colin27";
    const std::string state_json = state_to_json(state);
    const json opened = json::parse(opened_message(1, "s1", volume, {1, 2, 3}, state, "00ff"));
    EXPECT_EQ(opened.at("type"), "opened");
    EXPECT_EQ(opened.at("state"), json::parse(state_json));
    EXPECT_EQ(opened.at("histogram"), json::array({1, 2, 3}));
    EXPECT_EQ(opened.at("owner_token"), "00ff");
    EXPECT_FALSE(opened.contains("recreated"));
    const json recreated =
            json::parse(opened_message(1, "s1", volume, {1, 2, 3}, state, "00ff", true));
    EXPECT_EQ(recreated.at("recreated"), true);
    const json joined = json::parse(joined_message(1, "s1", volume, {}, state));
    EXPECT_EQ(joined.at("type"), "joined");
    EXPECT_EQ(joined.at("state"), json::parse(state_json));
    EXPECT_FALSE(joined.contains("owner_token"));
}

TEST(ParseRequest, EmptySpaceSkippingIsOnUntilASessionTurnsItOff) {
    scene::State state;
    EXPECT_TRUE(state.frame.settings.empty_space_skipping);
    ASSERT_TRUE(
            apply_patch(R"({"settings":{"empty_space_skipping":false}})", state, Limits{}).ok());
    EXPECT_FALSE(state.frame.settings.empty_space_skipping);
    EXPECT_EQ(json::parse(state_to_json(state)).at("settings").at("empty_space_skipping"), false);
    const auto wrong = apply_patch(R"({"settings":{"empty_space_skipping":1}})", state, Limits{});
    ASSERT_FALSE(wrong.ok());
    EXPECT_EQ(wrong.error().where, "/settings/empty_space_skipping");
}

TEST(ServerMessages, StateCarriesTheSessionAndItsFullStateWithoutAnId) {
    scene::State state;
    state.frame.transfer_function = scene::preset("ct_bone").value();
    state.frame.settings.mode = scene::Mode::dvr;
    const std::string state_json = state_to_json(state);
    const json message = json::parse(state_message("s1", state));
    EXPECT_EQ(message.at("v"), 1);
    EXPECT_EQ(message.at("type"), "state");
    EXPECT_EQ(message.at("session"), "s1");
    EXPECT_EQ(message.at("state"), json::parse(state_json));
    EXPECT_EQ(message.at("state").at("settings").at("mode"), "dvr");
    EXPECT_FALSE(message.contains("id"));
}

// An error reaches a client under its code's name when the protocol lists the code, else as
// internal_error: a loader's or a renderer's own codes stay inside the server.
TEST(ServerMessages, ErrorsCarryTheirWireCode) {
    for (const base::ErrorCode code : kWireCodes) {
        EXPECT_EQ(wire_name(code), base::name_of(code));
    }
    EXPECT_EQ(wire_name(base::ErrorCode::bad_header), "internal_error");
    EXPECT_EQ(wire_name(base::ErrorCode::cancelled), "internal_error");
    const json refused = json::parse(
            error_message(4, base::make_error(base::ErrorCode::out_of_range, "m", "/x")));
    EXPECT_EQ(refused.at("code"), "out_of_range");
    const json internal = json::parse(
            error_message(4, base::make_error(base::ErrorCode::gl_error, "driver", "render")));
    EXPECT_EQ(internal.at("code"), "internal_error");
    EXPECT_EQ(internal.at("message"), "driver");
}

// A set is answered with the state as the server made it: an orbit's eye, a view's pose and a
// preset's points as the server puts them, so a client keeps no rules of its own.
TEST(ServerMessages, ASetIsAnsweredWithTheStateAsApplied) {
    scene::State state;
    ASSERT_TRUE(
            apply_patch(
                    R"({"camera":{"orbit":{"azimuth":90}},"transfer_function":{"preset":"ct_bone"}})",
                    state, Limits{})
                    .ok());
    const json message = json::parse(set_ack_message(7, state));
    EXPECT_EQ(message.at("type"), "ack");
    EXPECT_EQ(message.at("of"), "set");
    EXPECT_EQ(message.at("id"), 7);
    EXPECT_EQ(message.at("state"), json::parse(state_to_json(state)));
    EXPECT_GT(message.at("state").at("camera").at("eye").at(0).get<double>(), 1.0);
    EXPECT_EQ(message.at("state").at("transfer_function").at("name"), "ct_bone");
    EXPECT_TRUE(message.at("state").at("transfer_function").contains("opacities"));
}

}  // namespace
}  // namespace penumbra::protocol
