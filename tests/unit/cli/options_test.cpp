#include "synthetic_volumes.hpp"

#include <penumbra/base/text.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::cli {
namespace {

po::options_description test_options() {
    po::options_description options = option_group("test");
    options.add_options()("help", "help")("size", po::value<ImageSize>(), "size")(
            "fov", po::value<Number>(), "fov")("eye", po::value<Triple>(), "eye");
    return options;
}

TEST(Options, ParsesValuesFlagsAndInlineValues) {
    auto args = parse_options({"--size", "64x32", "--fov=45", "--eye", "-1,2,3/4", "--help"},
                              test_options());
    ASSERT_TRUE(args.ok()) << args.error().to_string();
    EXPECT_EQ(args->count("help"), 1U);
    EXPECT_EQ((*args)["size"].as<ImageSize>().width, 64);
    EXPECT_EQ((*args)["size"].as<ImageSize>().height, 32);
    EXPECT_DOUBLE_EQ((*args)["fov"].as<Number>().value, 45.0);
    EXPECT_EQ((*args)["eye"].as<Triple>().value, glm::dvec3(-1.0, 2.0, 0.75));
}

// Each mistake is an error naming the option (or the stray argument).
TEST(Options, RejectsUnknownMissingAndMalformedValues) {
    const auto error = [](const std::vector<std::string>& args) {
        auto parsed = parse_options(args, test_options());
        EXPECT_FALSE(parsed.ok());
        return parsed.ok() ? base::Error{} : parsed.error();
    };
    EXPECT_EQ(error({"--colour", "red"}).where, "--colour");
    EXPECT_EQ(error({"--colour", "red"}).message, "unknown option");
    EXPECT_EQ(error({"--colour=red"}).where, "--colour");
    // An abbreviation is not guessed: a misspelt option must not pick another.
    EXPECT_EQ(error({"--si", "64x32"}).where, "--si");
    EXPECT_EQ(error({"--size"}).message, "needs a value");
    EXPECT_EQ(error({"--size"}).where, "--size");
    EXPECT_EQ(error({"stray"}).message, "unexpected argument 'stray'");
    EXPECT_EQ(error({"--help=yes"}).where, "--help");
    for (const std::vector<std::string>& args : {std::vector<std::string>{"--size", "64by32"},
                                                 {"--size", "0x32"},
                                                 {"--fov", "nan"},
                                                 {"--eye", "1,2"}}) {
        EXPECT_EQ(error(args).where, args[0]) << args[1];
    }
}

TEST(Options, NumbersMayBeFractions) {
    auto args = parse_options({"--fov", "1/512"}, test_options());
    ASSERT_TRUE(args.ok()) << args.error().to_string();
    EXPECT_DOUBLE_EQ((*args)["fov"].as<Number>().value, 1.0 / 512.0);
    for (const char* bad : {"1/0", "1/", "/2", "1/2/3"}) {
        EXPECT_FALSE(parse_options({"--fov", bad}, test_options()).ok()) << bad;
    }
}

// A whole number outside its range is refused naming the option; within, it reaches its target.
TEST(Options, WholeNumbersAreCheckedAgainstTheirRange) {
    int repeat = 1;
    po::options_description options = option_group("test");
    options.add_options()("repeat", whole_number(&repeat, 1, 100), "repeat");
    ASSERT_TRUE(parse_options({"--repeat", "7"}, options).ok());
    EXPECT_EQ(repeat, 7);
    for (const char* bad : {"0", "101", "2.5", "x"}) {
        auto refused = parse_options({"--repeat", bad}, options);
        ASSERT_FALSE(refused.ok()) << bad;
        EXPECT_EQ(refused.error().where, "--repeat") << bad;
    }
    EXPECT_EQ(parse_options({"--repeat", "0"}, options).error().message, "must be within 1..100");
}

// Each number of the table has its option, named in the help with its range, which sets it
// alone and refuses a value beyond the range naming the option. A row that the command line leaves
// out fails here.
TEST(RenderOptions, EveryTableSettingIsAnOption) {
    const volume::Volume volume = test::constant_volume({4, 4, 4}, 1.0f);
    // The help as one line: it wraps descriptions at its width.
    std::ostringstream help_text;
    help_text << frame_options();
    std::string help;
    for (const char c : help_text.str()) {
        if (!std::isspace(static_cast<unsigned char>(c)) || (!help.empty() && help.back() != ' ')) {
            help += std::isspace(static_cast<unsigned char>(c)) ? ' ' : c;
        }
    }
    for (const scene::Setting* range : scene::kSettings) {
        const bool numeric = range->kind == scene::SettingKind::number ||
                             range->kind == scene::SettingKind::whole;
        if (!numeric || !range->in_frame() || range->limit != nullptr ||
            range->command_line != scene::CommandLine::option) {
            continue;
        }
        const std::string option = "--" + scene::option_name(*range);
        SCOPED_TRACE(option);
        EXPECT_NE(help.find(option + (range->integer() ? " N" : " X")), std::string::npos);
        EXPECT_NE(help.find(range->describe()), std::string::npos);
        const double value =
                range->integer() ? range->max : range->min + 0.375 * (range->max - range->min);
        char text[64];
        std::snprintf(text, sizeof text, "%.17g", value);
        auto args = parse_options({option, text}, frame_options());
        ASSERT_TRUE(args.ok()) << args.error().to_string();
        auto request = frame_request_from(*args, volume);
        ASSERT_TRUE(request.ok()) << request.error().to_string();
        EXPECT_EQ(range->read_frame(*request).x, value);
        auto defaults = frame_request_from(*parse_options({}, frame_options()), volume);
        ASSERT_TRUE(defaults.ok());
        EXPECT_NE(range->read_frame(*defaults).x, value);
        scene::State state;
        state.frame = *defaults;
        range->write(state, scene::SettingValue(value, 0.0, 0.0));
        EXPECT_EQ(state.frame, *request);

        std::snprintf(text, sizeof text, "%.17g", range->max + 1.0);
        auto beyond = parse_options({option, text}, frame_options());
        ASSERT_TRUE(beyond.ok());
        const auto refused = frame_request_from(*beyond, volume);
        ASSERT_FALSE(refused.ok());
        EXPECT_EQ(refused.error().where, option);
        EXPECT_NE(refused.error().message.find(range->describe()), std::string::npos);
    }
}

// Every other setting the command line takes from the table: a flag turns a boolean from its
// default (`--phong`, `--no-empty-space-skipping`), a choice takes a name, a vector "x,y,z", a
// size "WxH"; each sets its setting alone.
TEST(RenderOptions, EveryBooleanChoiceVectorAndSizeIsAnOption) {
    const volume::Volume volume = test::constant_volume({4, 4, 4}, 1.0f);
    const auto defaults = frame_request_from(*parse_options({}, frame_options()), volume);
    ASSERT_TRUE(defaults.ok());
    int seen = 0;
    for (const scene::Setting* row : scene::kSettings) {
        const bool numeric =
                row->kind == scene::SettingKind::number || row->kind == scene::SettingKind::whole;
        if (numeric || !row->in_frame() || row->command_line != scene::CommandLine::option) {
            continue;
        }
        const scene::SettingValue before = row->read_frame(*defaults);
        scene::SettingValue wanted = before;
        std::vector<std::string> args;
        const std::string name = scene::option_name(*row);
        switch (row->kind) {
            case scene::SettingKind::boolean:
                wanted.x = before.x != 0.0 ? 0.0 : 1.0;
                args = {"--" + std::string(before.x != 0.0 ? "no-" : "") + name};
                break;
            case scene::SettingKind::choice:
                wanted.x = before.x == 0.0 ? 1.0 : 0.0;
                args = {"--" + name, std::string(row->choices[static_cast<std::size_t>(wanted.x)])};
                break;
            case scene::SettingKind::vector:
                wanted = scene::SettingValue(0.25, 0.5, 0.75);
                args = {"--" + name, "0.25,0.5,0.75"};
                break;
            case scene::SettingKind::size:
                wanted = scene::SettingValue(40, 24, 0);
                args = {"--" + name, "40x24"};
                break;
            case scene::SettingKind::number:
            case scene::SettingKind::whole:
                break;
        }
        SCOPED_TRACE(args.front());
        auto parsed = parse_options(args, frame_options());
        ASSERT_TRUE(parsed.ok()) << parsed.error().to_string();
        auto request = frame_request_from(*parsed, volume);
        ASSERT_TRUE(request.ok()) << request.error().to_string();
        EXPECT_EQ(row->read_frame(*request), wanted);
        scene::State state;
        state.frame = *defaults;
        row->write(state, wanted);
        EXPECT_EQ(state.frame, *request);
        ++seen;
    }
    // mode, compositing, stage, size, background, phong, empty-space skipping, jitter, builder,
    // lookup and the light's colour at least.
    EXPECT_GE(seen, 11);
}

TEST(RenderOptions, LightBufferRefinementsAreOptions) {
    const volume::Volume volume = test::constant_volume({4, 4, 4}, 1.0f);
    auto args = parse_options({"--mode", "sbrc", "--light-lookup", "interpolate", "--slab-samples",
                               "3", "--sample-distance", "1/512"},
                              frame_options());
    ASSERT_TRUE(args.ok()) << args.error().to_string();
    auto request = frame_request_from(*args, volume);
    ASSERT_TRUE(request.ok()) << request.error().to_string();
    EXPECT_EQ(request->settings.light_buffer.lookup, scene::LightLookup::interpolate);
    EXPECT_EQ(request->settings.light_buffer.slab_samples, 3);
    EXPECT_DOUBLE_EQ(request->settings.sample_distance, 1.0 / 512.0);
    auto bad_lookup = parse_options({"--light-lookup", "nearest"}, frame_options());
    EXPECT_EQ(frame_request_from(*bad_lookup, volume).error().where, "--light-lookup");
    auto bad_samples = parse_options({"--slab-samples", "99"}, frame_options());
    EXPECT_EQ(frame_request_from(*bad_samples, volume).error().where, "--slab-samples");
}

TEST(RenderOptions, BuildsAValidRequestAndReportsBadOptions) {
    const volume::Volume volume = test::constant_volume({4, 4, 4}, 1.0f);
    auto args = parse_options({"--mode", "dvr", "--size", "64x48", "--camera", "90,10,3", "--tf",
                               "grey_ramp", "--light-position", "1,2,3"},
                              frame_options());
    ASSERT_TRUE(args.ok()) << args.error().to_string();
    auto request = frame_request_from(*args, volume);
    ASSERT_TRUE(request.ok()) << request.error().to_string();
    EXPECT_EQ(request->settings.mode, scene::Mode::dvr);
    EXPECT_EQ(request->settings.width, 64);
    EXPECT_EQ(request->light.type, scene::LightType::point);
    EXPECT_NEAR(request->camera.eye.x, 3.0 * std::cos(10.0 * M_PI / 180.0), 1e-9);

    auto bad_mode = parse_options({"--mode", "magic"}, frame_options());
    EXPECT_EQ(frame_request_from(*bad_mode, volume).error().where, "--mode");
    auto bad_tf = parse_options({"--tf", "nope"}, frame_options());
    EXPECT_EQ(frame_request_from(*bad_tf, volume).error().code, base::ErrorCode::unknown_preset);
    auto bad_distance = parse_options({"--sample-distance", "0"}, frame_options());
    // The option is checked against its setting's range (scene::setting) and named.
    const auto distance_error = frame_request_from(*bad_distance, volume).error();
    EXPECT_EQ(distance_error.where, "--sample-distance");
    EXPECT_NE(distance_error.message.find(scene::setting::sample_distance.describe()),
              std::string::npos)
            << distance_error.message;
}

// --crop takes each axis's range in either order; each --clip-plane fills the next plane, its
// normal made unit length; bad counts, zero normals, values beyond the range and more planes than
// the cut holds are refused naming the option.
TEST(RenderOptions, CropAndClipPlanesAreReadInPatientMillimetres) {
    const volume::Volume volume = test::constant_volume({4, 4, 4}, 1.0f);
    auto args = parse_options({"--crop", "10,-20,0,5,-3,30", "--clip-plane", "1,2,3,0,0,-2",
                               "--clip-plane", "-4,0,0,3,4,0", "--cut-shadows"},
                              frame_options());
    ASSERT_TRUE(args.ok()) << args.error().to_string();
    auto request = frame_request_from(*args, volume);
    ASSERT_TRUE(request.ok()) << request.error().to_string();
    const scene::Cut& cut = request->cut;
    EXPECT_TRUE(cut.crop.enabled);
    EXPECT_EQ(cut.crop.min, glm::dvec3(-20.0, 0.0, -3.0));
    EXPECT_EQ(cut.crop.max, glm::dvec3(10.0, 5.0, 30.0));
    EXPECT_TRUE(cut.casts_shadows);
    EXPECT_EQ(cut.planes[0], (scene::ClipPlane{true, {1.0, 2.0, 3.0}, {0.0, 0.0, -1.0}}));
    EXPECT_EQ(cut.planes[1].point, glm::dvec3(-4.0, 0.0, 0.0));
    EXPECT_NEAR(glm::distance(cut.planes[1].normal, glm::dvec3(0.6, 0.8, 0.0)), 0.0, 1e-12);
    EXPECT_FALSE(cut.planes[2].enabled);

    const auto error_of = [&](std::vector<std::string> options) {
        auto parsed = parse_options(options, frame_options());
        EXPECT_TRUE(parsed.ok());
        auto made = frame_request_from(*parsed, volume);
        return made.ok() ? base::Error{} : made.error();
    };
    EXPECT_EQ(error_of({"--crop", "1,2,3"}).where, "--crop");
    EXPECT_EQ(error_of({"--crop", "0,1,0,1,0,20000"}).where, "--crop");
    EXPECT_EQ(error_of({"--crop", "0,1,0,0,0,1"}).where, "cut.crop");
    EXPECT_EQ(error_of({"--clip-plane", "1,2,3,0,0"}).where, "--clip-plane");
    EXPECT_EQ(error_of({"--clip-plane", "1,2,3,0,0,0"}).where, "--clip-plane");
    EXPECT_EQ(error_of({"--clip-plane", "1,2,30000,0,0,1"}).where, "--clip-plane");
    std::vector<std::string> seven;
    for (int i = 0; i <= scene::kMaxClipPlanes; ++i) {
        seven.insert(seven.end(), {"--clip-plane", "0,0,0,1,0,0"});
    }
    const base::Error too_many = error_of(seven);
    EXPECT_EQ(too_many.where, "--clip-plane");
    EXPECT_NE(too_many.message.find("at most 6"), std::string::npos) << too_many.message;
}

// Without --tf a CT (values in HU) shows its bone, as a new serve session on it does; any other
// volume the MRI skin.
TEST(RenderOptions, TheDefaultTransferFunctionFollowsTheVolumesUnits) {
    volume::Volume ct = test::constant_volume({4, 4, 4}, 1.0f);
    ct.hounsfield = true;
    const auto on_ct = default_frame_request(ct);
    ASSERT_TRUE(on_ct.ok()) << on_ct.error().to_string();
    EXPECT_EQ(on_ct->transfer_function.name, "ct_bone");
    EXPECT_EQ(on_ct->settings.mode, scene::Mode::phong);
    const auto on_mri = default_frame_request(test::constant_volume({4, 4, 4}, 1.0f));
    ASSERT_TRUE(on_mri.ok()) << on_mri.error().to_string();
    EXPECT_EQ(on_mri->transfer_function.name, "mri_skin");
    auto named = parse_options({"--tf", "grey_ramp"}, frame_options());
    EXPECT_EQ(frame_request_from(*named, ct)->transfer_function.name, "grey_ramp");
}

// A benchmark's frame options leave out what it sweeps; giving one says what to give instead.
TEST(RenderOptions, SweptOptionsAreRefusedWithWhatToGiveInstead) {
    const SweptOptions swept = {{"slices", "--slices-list LIST"}};
    const po::options_description options = frame_options(names_of(swept));
    EXPECT_EQ(options.find_nothrow("slices", false), nullptr);
    EXPECT_NE(options.find_nothrow("light-res", false), nullptr);
    auto refused = parse_options({"--slices", "64"}, options);
    ASSERT_FALSE(refused.ok());
    const base::Error error = explain_swept(refused.error(), swept, "bench modes");
    EXPECT_EQ(error.where, "--slices");
    EXPECT_EQ(error.message, "bench modes sweeps this; use --slices-list LIST");
}

// A list of a module's own kind: "a,b" read by its parser, whose error names the option.
base::Result<std::vector<std::string>> parse_letters(std::string_view text) {
    std::vector<std::string> letters = base::split_list(text);
    for (const std::string& letter : letters) {
        if (letter.size() != 1) {
            return base::make_error(base::ErrorCode::invalid_argument,
                                    "'" + letter + "' is not one letter");
        }
    }
    return letters;
}

using Letters = ListOf<&parse_letters>;

po::options_description list_options() {
    po::options_description options = option_group("test");
    options.add_options()("letters", po::value<Letters>(), "letters")(
            "modes", po::value<Modes>(), "modes")("budget-ms", po::value<Numbers>(), "numbers");
    return options;
}

TEST(ListOptions, ListsAreReadByTheirParserAndItsErrorsNameTheOption) {
    auto parsed = parse_options({"--letters", "a, b"}, list_options());
    ASSERT_TRUE(parsed.ok()) << parsed.error().to_string();
    EXPECT_EQ((*parsed)["letters"].as<Letters>().values, (std::vector<std::string>{"a", "b"}));
    auto refused = parse_options({"--letters", "a,bc"}, list_options());
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().message, "'bc' is not one letter");
    EXPECT_EQ(refused.error().where, "--letters");
}

TEST(ListOptions, ModesAreKnownNamesEachOnce) {
    EXPECT_EQ(parsed<Modes>("sbrc, dvr,sbrc").values,
              (std::vector<scene::Mode>{scene::Mode::sbrc, scene::Mode::dvr}));
    auto unknown = parse_options({"--modes", "dvr,shiny"}, list_options());
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("'shiny'"), std::string::npos);
    EXPECT_EQ(unknown.error().where, "--modes");
}

TEST(ListOptions, NumbersMayBeFractions) {
    EXPECT_EQ(parsed<Numbers>("1/2,3").values, (std::vector<double>{0.5, 3.0}));
    auto bad = parse_options({"--budget-ms", "1,x"}, list_options());
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().where, "--budget-ms");
}

}  // namespace
}  // namespace penumbra::cli
