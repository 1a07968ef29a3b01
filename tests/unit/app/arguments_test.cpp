#include "arguments.hpp"

#include "render_options.hpp"
#include "synthetic_volumes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace penumbra::app {
namespace {

TEST(Arguments, ParsesValuesFlagsAndInlineValues) {
    auto args =
            Arguments::parse({"--size", "64x32", "--fov=45", "--help"}, {"size", "fov"}, {"help"});
    ASSERT_TRUE(args.ok());
    EXPECT_TRUE(args->has("help"));
    EXPECT_EQ(args->size("size", {1, 1}).value(), (std::pair{64, 32}));
    EXPECT_DOUBLE_EQ(args->number("fov", 0.0).value(), 45.0);
}

TEST(Arguments, RejectsUnknownMissingAndMalformedValues) {
    EXPECT_EQ(Arguments::parse({"--colour", "red"}, {"size"}, {}).error().where, "--colour");
    EXPECT_EQ(Arguments::parse({"--size"}, {"size"}, {}).error().message, "needs a value");
    EXPECT_FALSE(Arguments::parse({"stray"}, {"size"}, {}).ok());
    auto args = Arguments::parse({"--size", "64by32", "--fov", "nan", "--eye", "1,2"},
                                 {"size", "fov", "eye"}, {});
    ASSERT_TRUE(args.ok());
    EXPECT_FALSE(args->size("size", {1, 1}).ok());
    EXPECT_FALSE(args->number("fov", 0.0).ok());
    EXPECT_FALSE(args->vec3("eye", {}).ok());
}

TEST(Arguments, NumbersMayBeFractions) {
    auto args = Arguments::parse(
            {"--a", "1/512", "--b", "-3/4", "--c", "1/0", "--d", "1/", "--e", "/2", "--f", "1/2/3"},
            {"a", "b", "c", "d", "e", "f"}, {});
    ASSERT_TRUE(args.ok());
    EXPECT_DOUBLE_EQ(args->number("a", 0.0).value(), 1.0 / 512.0);
    EXPECT_DOUBLE_EQ(args->number("b", 0.0).value(), -0.75);
    for (const char* name : {"c", "d", "e", "f"}) {
        EXPECT_FALSE(args->number(name, 0.0).ok()) << name;
    }
}

// Each numeric setting of the table has its option, named in the help with its range, which
// sets it alone and refuses a value beyond the range naming the option. A row that the command
// line leaves out fails here.
TEST(RenderOptions, EveryTableSettingIsAnOption) {
    const volume::Volume volume = test::constant_volume({4, 4, 4}, 1.0f);
    const std::string help = frame_options_help();
    for (const scene::SettingRange* range : scene::kSettingRanges) {
        if (range->write == nullptr) {
            continue;
        }
        const std::string option = "--" + scene::option_name(*range);
        SCOPED_TRACE(option);
        EXPECT_NE(help.find(option + (range->integer ? " N" : " X")), std::string::npos);
        EXPECT_NE(help.find(range->describe()), std::string::npos);
        const double value =
                range->integer ? range->max : range->min + 0.375 * (range->max - range->min);
        char text[64];
        std::snprintf(text, sizeof text, "%.17g", value);
        auto args = Arguments::parse({option, text}, frame_option_names(), {});
        ASSERT_TRUE(args.ok()) << args.error().to_string();
        auto request = frame_request_from(*args, volume);
        ASSERT_TRUE(request.ok()) << request.error().to_string();
        EXPECT_EQ(range->read(*request), value);
        auto defaults = frame_request_from(*Arguments::parse({}, frame_option_names(), {}), volume);
        ASSERT_TRUE(defaults.ok());
        EXPECT_NE(range->read(*defaults), value);
        range->write(*defaults, value);
        EXPECT_EQ(*defaults, *request);

        std::snprintf(text, sizeof text, "%.17g", range->max + 1.0);
        auto beyond = Arguments::parse({option, text}, frame_option_names(), {});
        ASSERT_TRUE(beyond.ok());
        const auto refused = frame_request_from(*beyond, volume);
        ASSERT_FALSE(refused.ok());
        EXPECT_EQ(refused.error().where, option);
        EXPECT_NE(refused.error().message.find(range->describe()), std::string::npos);
    }
}

TEST(RenderOptions, LightBufferRefinementsAreOptions) {
    const volume::Volume volume = test::constant_volume({4, 4, 4}, 1.0f);
    auto args = Arguments::parse({"--mode", "sbrc", "--light-lookup", "interpolate",
                                  "--slab-samples", "3", "--sample-distance", "1/512"},
                                 frame_option_names(), {});
    ASSERT_TRUE(args.ok()) << args.error().to_string();
    auto request = frame_request_from(*args, volume);
    ASSERT_TRUE(request.ok()) << request.error().to_string();
    EXPECT_EQ(request->settings.light_buffer.lookup, scene::LightLookup::interpolate);
    EXPECT_EQ(request->settings.light_buffer.slab_samples, 3);
    EXPECT_DOUBLE_EQ(request->settings.sample_distance, 1.0 / 512.0);
    auto bad_lookup = Arguments::parse({"--light-lookup", "nearest"}, frame_option_names(), {});
    EXPECT_EQ(frame_request_from(*bad_lookup, volume).error().where, "--light-lookup");
    auto bad_samples = Arguments::parse({"--slab-samples", "99"}, frame_option_names(), {});
    EXPECT_EQ(frame_request_from(*bad_samples, volume).error().where, "--slab-samples");
}

TEST(RenderOptions, BuildsAValidRequestAndReportsBadOptions) {
    const volume::Volume volume = test::constant_volume({4, 4, 4}, 1.0f);
    auto args = Arguments::parse({"--mode", "dvr", "--size", "64x48", "--camera", "90,10,3", "--tf",
                                  "grey_ramp", "--light-position", "1,2,3"},
                                 frame_option_names(), {});
    ASSERT_TRUE(args.ok()) << args.error().to_string();
    auto request = frame_request_from(*args, volume);
    ASSERT_TRUE(request.ok()) << request.error().to_string();
    EXPECT_EQ(request->settings.mode, scene::Mode::dvr);
    EXPECT_EQ(request->settings.width, 64);
    EXPECT_EQ(request->light.type, scene::LightType::point);
    EXPECT_NEAR(request->camera.eye.x, 3.0 * std::cos(10.0 * M_PI / 180.0), 1e-9);

    auto bad_mode = Arguments::parse({"--mode", "magic"}, frame_option_names(), {});
    EXPECT_EQ(frame_request_from(*bad_mode, volume).error().where, "--mode");
    auto bad_tf = Arguments::parse({"--tf", "nope"}, frame_option_names(), {});
    EXPECT_EQ(frame_request_from(*bad_tf, volume).error().code, "unknown_preset");
    auto bad_distance = Arguments::parse({"--sample-distance", "0"}, frame_option_names(), {});
    // The option is checked against its setting's range (scene::setting) and named.
    const auto distance_error = frame_request_from(*bad_distance, volume).error();
    EXPECT_EQ(distance_error.where, "--sample-distance");
    EXPECT_NE(distance_error.message.find(scene::setting::sample_distance.describe()),
              std::string::npos)
            << distance_error.message;
}

// Without --tf a CT (values in HU) shows its bone, as a new serve session on it does; any other
// volume the MRI skin.
TEST(RenderOptions, TheDefaultTransferFunctionFollowsTheVolumesUnits) {
    auto args = Arguments::parse({}, frame_option_names(), {});
    ASSERT_TRUE(args.ok()) << args.error().to_string();
    volume::Volume ct = test::constant_volume({4, 4, 4}, 1.0f);
    ct.hounsfield = true;
    const auto on_ct = frame_request_from(*args, ct);
    ASSERT_TRUE(on_ct.ok()) << on_ct.error().to_string();
    EXPECT_EQ(on_ct->transfer_function.name, "ct_bone");
    const auto on_mri = frame_request_from(*args, test::constant_volume({4, 4, 4}, 1.0f));
    ASSERT_TRUE(on_mri.ok()) << on_mri.error().to_string();
    EXPECT_EQ(on_mri->transfer_function.name, "mri_skin");
    auto named = Arguments::parse({"--tf", "grey_ramp"}, frame_option_names(), {});
    EXPECT_EQ(frame_request_from(*named, ct)->transfer_function.name, "grey_ramp");
}

TEST(ListOptions, SplitTrimsItemsAndDropsEmptyOnes) {
    EXPECT_EQ(split_list("a, b,,c "), (std::vector<std::string>{"a", "b", "c"}));
    EXPECT_EQ(split_list("10,45; 100,20", ';'), (std::vector<std::string>{"10,45", "100,20"}));
    EXPECT_TRUE(split_list("").empty());
}

TEST(ListOptions, CountsAreWholeNumbersInRangeEachOnce) {
    EXPECT_EQ(parse_counts("64,128,64", "slices-list").value(), (std::vector<int>{64, 128}));
    for (const char* bad : {"0", "1.5", "65537", "x"}) {
        auto counts = parse_counts(bad, "slices-list");
        ASSERT_FALSE(counts.ok()) << bad;
        EXPECT_EQ(counts.error().where, "--slices-list") << bad;
    }
}

TEST(ListOptions, ModesAreKnownNamesEachOnce) {
    EXPECT_EQ(parse_modes("sbrc, dvr,sbrc", "modes").value(),
              (std::vector<scene::Mode>{scene::Mode::sbrc, scene::Mode::dvr}));
    auto unknown = parse_modes("dvr,shiny", "modes");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("'shiny'"), std::string::npos);
    EXPECT_EQ(unknown.error().where, "--modes");
}

}  // namespace
}  // namespace penumbra::app
