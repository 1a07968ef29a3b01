#include <penumbra/scene/frame_request.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace penumbra::scene {
namespace {

FrameRequest valid_request() {
    FrameRequest request;
    request.transfer_function = preset("grey_ramp").value();
    return request;
}

TEST(FrameRequest, DefaultsAreValid) {
    EXPECT_TRUE(validate(valid_request()).ok());
}

// A new session starts from a frame that the device's limits admit, however small they are.
TEST(FrameRequest, StartingFrameFitsTheLimits) {
    const auto with_preset = [](FrameRequest frame) {
        frame.transfer_function = preset("grey_ramp").value();
        return frame;
    };
    EXPECT_TRUE(validate(with_preset(starting_frame({})), {}).ok());
    const Limits small{64, 16, 32};
    const FrameRequest frame = with_preset(starting_frame(small));
    EXPECT_EQ(frame.settings.width, 64);
    EXPECT_EQ(frame.settings.height, 64);
    EXPECT_EQ(frame.settings.light_buffer.slices, 16);
    EXPECT_EQ(frame.settings.light_buffer.resolution, 32);
    EXPECT_TRUE(validate(frame, small).ok());
}

// A new session's frames are jittered, so that its stills refine by default.
TEST(FrameRequest, StartingFrameIsJitteredSoItsStillsRefine) {
    const FrameRequest frame = starting_frame({});
    EXPECT_TRUE(frame.settings.jitter);
    EXPECT_TRUE(is_ray_cast(frame.settings.mode));
    EXPECT_GT(State{}.refinement_steps, 0);
    EXPECT_GT(State{}.refinement_threshold, 0.0);
}

TEST(Refinement, GoesOnUntilAStepChangesTheImageByTheThresholdOrTheLimit) {
    // The still frame has no image before it: it refines whenever steps are allowed.
    EXPECT_TRUE(refines_after(0, std::nullopt, 8, 0.25));
    EXPECT_FALSE(refines_after(0, std::nullopt, 0, 0.25));
    EXPECT_TRUE(refines_after(3, 0.26, 8, 0.25));
    EXPECT_FALSE(refines_after(3, 0.25, 8, 0.25));
    EXPECT_FALSE(refines_after(3, 0.0, 8, 0.25));
    // The limit stops it however much the image still changes.
    EXPECT_FALSE(refines_after(8, 10.0, 8, 0.25));
    // A threshold of 0: only the limit.
    EXPECT_TRUE(refines_after(7, 0.0, 8, 0.0));
    EXPECT_FALSE(refines_after(8, 0.0, 8, 0.0));
}

TEST(FrameRequest, RejectsEachBadFieldByName) {
    struct Case {
        const char* field;
        void (*spoil)(FrameRequest&);
    };

    const Case cases[] = {
            {"size", [](FrameRequest& r) { r.settings.width = 0; }},
            {"size", [](FrameRequest& r) { r.settings.height = 100000; }},
            {"sample_distance", [](FrameRequest& r) { r.settings.sample_distance = 0.0; }},
            {"sample_distance",
             [](FrameRequest& r) {
                 r.settings.sample_distance = std::numeric_limits<double>::infinity();
             }},
            {"opacity_unit_distance",
             [](FrameRequest& r) { r.settings.opacity_unit_distance = -1.0; }},
            {"early_termination", [](FrameRequest& r) { r.settings.early_termination = 1.5; }},
            {"camera.eye",
             [](FrameRequest& r) { r.camera.eye.x = std::numeric_limits<double>::quiet_NaN(); }},
            {"camera", [](FrameRequest& r) { r.camera.target = r.camera.eye; }},
            {"camera.fov", [](FrameRequest& r) { r.camera.fov_y_degrees = 180.0; }},
            {"light.direction", [](FrameRequest& r) { r.light.direction = glm::dvec3(0.0); }},
            {"light.intensity", [](FrameRequest& r) { r.light.intensity = -1.0; }},
            {"shading.shininess", [](FrameRequest& r) { r.settings.shading.shininess = 0.0; }},
            {"tile",
             [](FrameRequest& r) {
                 r.tile = {r.settings.width - 1, r.settings.height};
             }},
            {"tile",
             [](FrameRequest& r) {
                 r.tile = {r.settings.width + 8, r.settings.height, 9, 0};
             }},
            {"tile",
             [](FrameRequest& r) {
                 r.tile = {1000, 1000, -1, 0};
             }},
            {"tile",
             [](FrameRequest& r) {
                 r.tile = {kMaxTiledImageSide + 1, 1000, 0, 0};
             }},
    };
    for (const auto& c : cases) {
        FrameRequest request = valid_request();
        c.spoil(request);
        const auto status = validate(request);
        ASSERT_FALSE(status.ok()) << c.field;
        EXPECT_EQ(status.error().where, c.field);
        EXPECT_EQ(status.error().code, base::ErrorCode::invalid_value);
    }
}

TEST(Tile, TheTilesCoverTheImageOncePixelForPixelWithTheWholeImagesRays) {
    FrameRequest whole = valid_request();
    whole.camera = orbit_camera(20.0, 10.0, 2.5);
    whole.settings.width = 70;
    whole.settings.height = 33;
    const std::vector<FrameRequest> tiles = image_tiles(whole, 32);
    ASSERT_EQ(tiles.size(), 6u);  // 32 + 32 + 6 by 32 + 1
    std::vector<int> covered(70 * 33, 0);
    const CameraFrame whole_rays = pixel_frame(whole);
    for (const FrameRequest& tile : tiles) {
        ASSERT_TRUE(validate(tile).ok());
        const CameraFrame rays = pixel_frame(tile);
        const int w = tile.settings.width;
        const int h = tile.settings.height;
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                ++covered[static_cast<std::size_t>((tile.tile.y + y) * 70 + tile.tile.x + x)];
                // The ray through the tile's pixel centre is the whole image's (ray.glsl's ndc).
                const auto ray = [](const CameraFrame& f, int px, int py, int width, int height) {
                    return glm::normalize(f.forward + ((px + 0.5) / width * 2.0 - 1.0) * f.right +
                                          (1.0 - (py + 0.5) / height * 2.0) * f.up);
                };
                const glm::dvec3 a = ray(rays, x, y, w, h);
                const glm::dvec3 b = ray(whole_rays, tile.tile.x + x, tile.tile.y + y, 70, 33);
                ASSERT_LT(glm::length(a - b), 1e-12) << x << "," << y;
            }
        }
    }
    EXPECT_TRUE(std::ranges::all_of(covered, [](int n) { return n == 1; }));
    EXPECT_TRUE(image_tiles(tiles[0], 8).empty());  // a tile is not tiled again
    EXPECT_TRUE(image_tiles(whole, 0).empty());
}

TEST(FrameRequest, ModeNamesRoundTrip) {
    for (const ModeInfo& row : modes()) {
        EXPECT_EQ(parse_mode(to_string(row.mode)), row.mode);
        EXPECT_EQ(&describe(row.mode), &row);
    }
    EXPECT_EQ(mode_names(), "dvr, phong, half_angle, sbrc, sbrc_shell, sbrc_cone, reference");
    EXPECT_FALSE(parse_mode("raytrace").has_value());
}

// Every value of every named enum has a name that reads back as that value, and the names differ.
template <NamedEnum Enum>
void expect_names_round_trip() {
    std::set<std::string_view> seen;
    for (const EnumName<Enum>& row : names<Enum>()) {
        EXPECT_EQ(parse_name<Enum>(to_string(row.value)), row.value) << row.name;
        EXPECT_EQ(name_of(row.value), row.name);
        EXPECT_TRUE(seen.insert(row.name).second) << row.name << " twice";
    }
    EXPECT_FALSE(parse_name<Enum>("").has_value());
    EXPECT_FALSE(parse_name<Enum>("raytrace").has_value());
}

TEST(EnumNames, EveryValueRoundTrips) {
    expect_names_round_trip<Compositing>();
    expect_names_round_trip<RaycastStage>();
    expect_names_round_trip<LightBufferBuilder>();
    expect_names_round_trip<LightLookup>();
    expect_names_round_trip<Technique>();
    expect_names_round_trip<ShadowKind>();
    expect_names_round_trip<ScatteringKind>();
    expect_names_round_trip<Gradients>();
    expect_names_round_trip<LightType>();
    expect_names_round_trip<View>();
}

TEST(EnumNames, ListsAndChoicesFollowTheTable) {
    EXPECT_EQ(parse_name<Compositing>("extinction"), Compositing::extinction);
    EXPECT_EQ(parse_name<RaycastStage>("fragment"), RaycastStage::fragment);
    EXPECT_EQ(choices<LightBufferBuilder>(), "per_slice or multi_slice");
    EXPECT_EQ(choices<ScatteringKind>(), "none, shell or cone");
    EXPECT_EQ(name_list<Compositing>("|"), "alpha|extinction");
}

// An enum that grew a value after the last row of its table.
enum class Grown { first, second, added_later };

// The check each table's static_assert makes refuses a missing, misplaced or unnamed row, and a
// value added after the last row (no table names its enum's last value by hand).
TEST(EnumNames, TheCoverageCheckRefusesGaps) {
    EXPECT_TRUE(names_each_value(kShadowKindNames));
    const std::array<EnumName<ShadowKind>, 2> missing{
            {{ShadowKind::none, "none"}, {ShadowKind::light_buffer, "light_buffer"}}};
    EXPECT_FALSE(names_each_value(missing));
    const std::array<EnumName<Grown>, 2> grown{
            {{Grown::first, "first"}, {Grown::second, "second"}}};
    EXPECT_FALSE(names_each_value(grown));
    static_assert(is_enumerator<Grown, 2>() && !is_enumerator<Grown, 3>());
    static_assert(has_values_up_to<Grown, 3>() && !has_values_up_to<Grown, 2>());
    const std::array<EnumName<ShadowKind>, 3> swapped{{{ShadowKind::none, "none"},
                                                       {ShadowKind::rays, "rays"},
                                                       {ShadowKind::light_buffer, "light_buffer"}}};
    EXPECT_FALSE(names_each_value(swapped));
    const std::array<EnumName<ShadowKind>, 3> unnamed{{{ShadowKind::none, "none"},
                                                       {ShadowKind::light_buffer, ""},
                                                       {ShadowKind::rays, "rays"}}};
    EXPECT_FALSE(names_each_value(unnamed));
}

// validate's limits are the setting ranges: each end is accepted, a step beyond it refused.
TEST(FrameRequest, ValidateAcceptsExactlyTheSettingRanges) {
    struct Case {
        const Setting& range;
        std::function<void(FrameRequest&, double)> set;
    };

    const std::vector<Case> cases = {
            {setting::sample_distance,
             [](FrameRequest& r, double v) { r.settings.sample_distance = v; }},
            {setting::early_termination,
             [](FrameRequest& r, double v) { r.settings.early_termination = v; }},
            {setting::fov_degrees, [](FrameRequest& r, double v) { r.camera.fov_y_degrees = v; }},
            {setting::light_ambient, [](FrameRequest& r, double v) { r.light.ambient = v; }},
            {setting::compensation,
             [](FrameRequest& r, double v) { r.settings.light_buffer.compensation = v; }},
            {setting::slab_samples,
             [](FrameRequest& r, double v) { r.settings.light_buffer.slab_samples = int(v); }},
            {setting::shell_rings,
             [](FrameRequest& r, double v) { r.settings.scattering.shell_rings = int(v); }},
            {setting::cone_angle_degrees,
             [](FrameRequest& r, double v) { r.settings.scattering.cone_angle_degrees = v; }},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(std::string(c.range.path));
        const double step = c.range.integer() ? 1.0 : c.range.max * 1e-3;
        for (const double inside : {c.range.min, c.range.max}) {
            FrameRequest request;
            c.set(request, inside);
            EXPECT_TRUE(validate(request).ok()) << inside;
        }
        for (const double outside : {c.range.min - step, c.range.max + step}) {
            FrameRequest request;
            c.set(request, outside);
            EXPECT_FALSE(validate(request).ok()) << outside;
        }
    }
}

// Every setting a state holds, of every kind, is checked by its row: each component at either end
// of its range is accepted, a step beyond either end refused, naming the setting (a choice beyond
// its last name too; a boolean has no value beyond its two).
TEST(State, ValidateHoldsEverySettingToItsRow) {
    const Limits limits;
    for (const Setting* row : kSettings) {
        if (!row->held()) {
            continue;
        }
        SCOPED_TRACE(std::string(row->path));
        const double max = row->max_under(limits);
        const double step = row->integer() || row->kind == SettingKind::choice
                                    ? 1.0
                                    : std::max(1e-6, (max - row->min) * 1e-3);
        const auto with = [&](double component) {
            State state;
            state.frame.camera.eye = {0.0, 3.0, 0.0};
            state.frame.light.direction = {0.0, 0.0, 1.0};
            // Every component at the value, so that a vector or a size is at its end.
            row->write(state, SettingValue(component));
            return state;
        };
        // The camera's eye and target must differ, and a directional light needs a direction.
        const bool degenerate_at_zero = row == &setting::camera_eye ||
                                        row == &setting::camera_target ||
                                        row == &setting::light_direction;
        // A crop corner at the far end of its range meets the other corner there: an empty box.
        const bool empty_at_far_end = row == &setting::crop_min || row == &setting::crop_max;
        for (const double inside : {row->min, max}) {
            const State state = with(inside);
            if (degenerate_at_zero && inside == 0.0) {
                continue;
            }
            if (empty_at_far_end && inside == (row == &setting::crop_min ? max : row->min)) {
                EXPECT_FALSE(validate(state, limits).ok()) << inside;
                continue;
            }
            EXPECT_TRUE(validate(state, limits).ok()) << inside;
        }
        if (row->kind == SettingKind::boolean) {
            continue;
        }
        for (const double outside : {row->min - step, max + step}) {
            const auto status = validate(with(outside), limits);
            ASSERT_FALSE(status.ok()) << outside;
            std::string field(row->path.starts_with("settings/") ? row->path.substr(9) : row->path);
            std::replace(field.begin(), field.end(), '/', '.');
            EXPECT_EQ(status.error().where, field);
        }
    }
}

// A choice's names are its enum's, in order; the frame formats are named both ways.
TEST(State, ChoicesAreTheirEnumsNames) {
    EXPECT_EQ(setting::encoding.choices.size(), kFrameFormatNames.size());
    for (const EnumName<FrameFormat>& row : kFrameFormatNames) {
        EXPECT_EQ(setting::encoding.choices[static_cast<std::size_t>(row.value)], row.name);
        EXPECT_EQ(parse_name<FrameFormat>(row.name), row.value);
    }
    EXPECT_EQ(setting::mode.choices.size(), kModes.size());
    EXPECT_EQ(setting::mode.choices.back(), "reference");
    EXPECT_EQ(setting::mode.choice_summaries.front(), kModes.front().summary);
    EXPECT_EQ(choice_list(setting::compositing, ", ", " or "), "alpha or extinction");
    EXPECT_EQ(parse_name<FrameFormat>("JPEG"), std::nullopt);
}

// What the planner and the work estimate read from the table: the light buffer for the sbrc
// modes only, gradients by the `phong` setting except where a mode fixes them.
TEST(FrameRequest, ModeTableSaysWhatEachModeComputes) {
    EXPECT_FALSE(uses_light_buffer(Mode::half_angle));
    EXPECT_TRUE(uses_light_view(Mode::half_angle));
    EXPECT_TRUE(uses_light_buffer(Mode::sbrc_cone));
    EXPECT_FALSE(uses_light_view(Mode::reference));
    EXPECT_EQ(describe(Mode::sbrc_shell).scattering, ScatteringKind::shell);
    EXPECT_EQ(describe(Mode::reference).shadows, ShadowKind::rays);
    RenderSettings s;
    for (const ModeInfo& row : modes()) {
        s.mode = row.mode;
        s.phong = false;
        EXPECT_EQ(uses_gradients(s), row.mode == Mode::phong) << row.name;
        s.phong = true;
        EXPECT_EQ(uses_gradients(s), row.mode != Mode::dvr) << row.name;
    }
}

TEST(FrameRequest, AnInteractiveFrameHasHalfTheSidesTwiceTheStepAndHalfTheLightBuffer) {
    FrameRequest full = starting_frame({});
    full.settings.width = 640;
    full.settings.height = 100;
    const auto [reduced, description] = interactive_request(full);
    EXPECT_EQ(reduced.settings.width, 320);
    EXPECT_EQ(reduced.settings.height, 64);  // never below 64 pixels unless the frame is
    EXPECT_DOUBLE_EQ(reduced.settings.sample_distance, 2.0 * full.settings.sample_distance);
    EXPECT_EQ(reduced.settings.light_buffer.resolution, full.settings.light_buffer.resolution / 2);
    EXPECT_EQ(reduced.settings.light_buffer.slices, full.settings.light_buffer.slices);
    EXPECT_EQ(reduced.camera, full.camera);
    EXPECT_EQ(description, "interactive: 320x64, sample distance x2, light buffer 256");
    full.settings.width = 40;
    full.settings.sample_distance = 0.4;
    full.settings.light_buffer.resolution = 100;
    const FrameRequest small = interactive_request(full).first;
    EXPECT_EQ(small.settings.width, 40);
    EXPECT_EQ(small.settings.light_buffer.resolution, 64);
    EXPECT_DOUBLE_EQ(small.settings.sample_distance, 0.5);
}

TEST(FrameRequest, AStillThatWouldTakeLongerThanItsBudgetIsPreviewedAtASizeThatFitsIt) {
    FrameRequest still = starting_frame({});
    still.settings.width = 1536;
    still.settings.height = 2048;
    // Within the budget, or nearly so: no preview.
    EXPECT_FALSE(still_preview(still, 200.0, 250.0));
    EXPECT_FALSE(still_preview(still, 250.0, 250.0));
    EXPECT_FALSE(still_preview(still, 700.0, 250.0));  // 0.36 of the pixels: too dear
    EXPECT_FALSE(still_preview(still, 1000.0, 0.0));
    // A quarter of the time: half of each side, the view and everything else unchanged.
    const auto quarter = still_preview(still, 1000.0, 250.0);
    ASSERT_TRUE(quarter);
    EXPECT_EQ(quarter->settings.width, 768);
    EXPECT_EQ(quarter->settings.height, 1024);
    FrameRequest same = *quarter;
    same.settings.width = still.settings.width;
    same.settings.height = still.settings.height;
    EXPECT_EQ(same, still);
    // 3/10 of the time: the sides scaled by its square root (0.548).
    const auto three_tenths = still_preview(still, 2500.0, 750.0);
    ASSERT_TRUE(three_tenths);
    EXPECT_EQ(three_tenths->settings.width, 841);
    EXPECT_EQ(three_tenths->settings.height, 1122);
    // Small stills: the interactive frame's floor (64 pixels a side) would hold more than a third
    // of the pixels, or all of them.
    FrameRequest small = still;
    small.settings.width = 100;
    small.settings.height = 100;
    EXPECT_FALSE(still_preview(small, 100000.0, 250.0));
    small.settings.width = 64;
    small.settings.height = 48;
    EXPECT_FALSE(still_preview(small, 100000.0, 250.0));
    small.settings.width = 128;
    small.settings.height = 128;
    ASSERT_TRUE(still_preview(small, 100000.0, 250.0));
    EXPECT_EQ(still_preview(small, 100000.0, 250.0)->settings.width, 64);
    // Far over the budget: never below the interactive frame, which is on screen already.
    const auto far = still_preview(still, 100000.0, 250.0);
    ASSERT_TRUE(far);
    EXPECT_EQ(far->settings.width, interactive_request(still).first.settings.width);
    EXPECT_EQ(far->settings.height, interactive_request(still).first.settings.height);
}

}  // namespace
}  // namespace penumbra::scene
