// Deeply nested JSON: refused while parsing, at the first container beyond the limit, without
// recursion that a hostile depth could turn into a stack overflow.

#include <penumbra/protocol/messages.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <gtest/gtest.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <variant>

#include <pthread.h>

namespace penumbra::protocol {
namespace {

// `depth` arrays nested in each other around a 1: "[[[1]]]" for 3.
std::string nested_arrays(std::size_t depth) {
    return std::string(depth, '[') + "1" + std::string(depth, ']');
}

std::string deep_set(std::size_t depth) {
    return R"({"v":1,"type":"set","id":5,"camera":{"eye":)" + nested_arrays(depth) + "}}";
}

// Runs `work` on a thread with a 256 KiB stack (network threads' stacks are not larger than the
// default 8 MiB, and a recursion per nesting level overflows this one within a few thousand).
void on_small_stack(const std::function<void()>& work) {
    pthread_attr_t attributes;
    ASSERT_EQ(pthread_attr_init(&attributes), 0);
    ASSERT_EQ(pthread_attr_setstacksize(&attributes, 256 * 1024), 0);
    pthread_t thread;
    const auto run = [](void* argument) -> void* {
        (*static_cast<const std::function<void()>*>(argument))();
        return nullptr;
    };
    ASSERT_EQ(pthread_create(&thread, &attributes, run,
                             const_cast<std::function<void()>*>(&work)),  // NOLINT: C API
              0);
    pthread_attr_destroy(&attributes);
    ASSERT_EQ(pthread_join(thread, nullptr), 0);
}

TEST(JsonDepth, TheDeepestValidMessageIsWithinTheDefaultLimit) {
    const auto request = parse_request(
            R"({"v":1,"type":"set","transfer_function":{"colors":[{"x":0,"rgb":[1,1,1]}]}})",
            Limits{});
    EXPECT_TRUE(request.ok()) << request.error().to_string();
}

TEST(JsonDepth, ASetNestedBeyondTheLimitIsOutOfRangeAtTheFirstContainerBeyondIt) {
    Limits limits;
    limits.max_json_depth = 6;
    // The message (1), camera (2), eye (3) and the arrays in it (4..7): the 7th level is beyond.
    const auto request = parse_request(deep_set(5), limits);
    ASSERT_FALSE(request.ok());
    EXPECT_EQ(request.error().code, base::ErrorCode::out_of_range);
    EXPECT_EQ(request.error().where, "/camera/eye/0/0/0/0");
    EXPECT_EQ(request_id_of(deep_set(5)), 5) << "the id of a refused message is still echoed";

    // Depth 6 is allowed, so the value itself is judged, when the patch is applied.
    const auto within = parse_request(deep_set(4), limits);
    ASSERT_TRUE(within.ok()) << within.error().to_string();
    scene::State state;
    state.frame.transfer_function = scene::preset("grey_ramp").value();
    const auto applied = apply_patch(std::get<Set>(within->message).patch, state, limits);
    ASSERT_FALSE(applied.ok());
    EXPECT_EQ(applied.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(applied.error().where, "/camera/eye");
}

TEST(JsonDepth, PointersCountArrayElementsAndEscapeKeys) {
    Limits limits;
    limits.max_json_depth = 3;
    const auto request =
            parse_request(R"({"v":1,"type":"set","a/b~c":[1,{"x":2},[2],[[3]]]})", limits);
    ASSERT_FALSE(request.ok());
    EXPECT_EQ(request.error().code, base::ErrorCode::out_of_range);
    EXPECT_EQ(request.error().where, "/a~1b~0c/3/0");
}

TEST(JsonDepth, MalformedJsonIsReportedAsSuchEvenWhenDeep) {
    const auto request = parse_request(std::string(100, '[') + "1,", Limits{});
    ASSERT_FALSE(request.ok());
    EXPECT_EQ(request.error().code, base::ErrorCode::malformed_json);
}

// Finding: a `set` nested some thousand levels deep overflowed a network thread's stack while
// parse_request copied and printed it. 100 000 levels, far beyond the default message size (the
// limit raised to let them through) and 30 000 levels within it, on a 256 KiB stack.
TEST(JsonDepth, HundredThousandLevelsAreRefusedWithoutCrashingASmallStack) {
    Limits large;
    large.max_message_bytes = 1 << 20;
    const std::string deepest = deep_set(100000);
    const std::string within_size = deep_set(30000);
    ASSERT_LE(within_size.size(), Limits{}.max_message_bytes);

    base::Result<Request> deepest_result = base::make_error(base::ErrorCode::internal_error, "");
    base::Result<Request> within_size_result =
            base::make_error(base::ErrorCode::internal_error, "");
    std::optional<std::int64_t> id;
    base::Status patch_status = base::Ok{};
    base::Status tf_status = base::Ok{};
    on_small_stack([&] {
        deepest_result = parse_request(deepest, large);
        within_size_result = parse_request(within_size, Limits{});
        id = request_id_of(deepest);
        scene::State state;
        patch_status =
                apply_patch(R"({"camera":{"eye":)" + nested_arrays(100000) + "}}", state, large);
        auto tf = parse_transfer_function(R"({"colors":)" + nested_arrays(100000) + "}",
                                          std::nullopt, "tf.json");
        tf_status = tf ? base::Status(base::Ok{}) : base::Status(tf.error());
    });
    // The message (1), camera (2), eye (3): the 17th level is the 15th array, at /0 x 14.
    std::string expected_pointer = "/camera/eye";
    for (int level = 4; level <= 17; ++level) {
        expected_pointer += "/0";
    }
    for (const auto* result : {&deepest_result, &within_size_result}) {
        ASSERT_FALSE(result->ok());
        EXPECT_EQ(result->error().code, base::ErrorCode::out_of_range);
        EXPECT_EQ(result->error().where, expected_pointer);
    }
    EXPECT_EQ(id, 5);
    ASSERT_FALSE(patch_status.ok());
    EXPECT_EQ(patch_status.error().code, base::ErrorCode::out_of_range);
    ASSERT_FALSE(tf_status.ok());
    EXPECT_EQ(tf_status.error().code, base::ErrorCode::out_of_range);
    EXPECT_EQ(tf_status.error().where.rfind("tf.json/colors/0", 0), 0u) << tf_status.error().where;
}

}  // namespace
}  // namespace penumbra::protocol
