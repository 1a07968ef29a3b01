// What one request may cost the render thread: the work ceiling checked before a frame runs, the
// light-buffer cache keyed by what the buffer holds and kept under its memory budget, frames
// cancelled between their chunks, and chunked frames giving the unchunked image.

#include "synthetic_volumes.hpp"

#include <penumbra/optics/light_slicing.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/scene/frame_work.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

using Clock = std::chrono::steady_clock;
using Builder = scene::LightBufferBuilder;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

class FrameBudgetTest : public ::testing::Test {
protected:
    void SetUp() override { create({}); }

    // Options with one member changed from its default.
    template <class T>
    static RendererOptions with(T RendererOptions::*member, T value) {
        RendererOptions options;
        options.*member = value;
        return options;
    }

    void create(const RendererOptions& options) {
        renderer_.reset();  // one GL context at a time
        auto created = Renderer::create(options);
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
        if (volume_) {
            ASSERT_TRUE(renderer_->set_volume(volume_).ok());
        }
    }

    void use(const volume::Volume& volume) {
        volume_ = std::make_shared<const volume::Volume>(volume);
        ASSERT_TRUE(renderer_->set_volume(volume_).ok());
    }

    Frame render(const scene::FrameRequest& request, const CancelPredicate& cancelled = {}) {
        auto frame = renderer_->render(request, cancelled);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame.value()) : Frame{};
    }

    LightBufferState light_buffer_after(const scene::FrameRequest& request) {
        return render(request).report.light_buffer;
    }

    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
};

scene::FrameRequest soft_scene(scene::Mode mode, int width = 24, int height = 20) {
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(20.0, 25.0, 2.4);
    request.light.direction = scene::direction_from_angles(-70.0, 30.0);
    request.light.ambient = 0.1;
    request.settings.mode = mode;
    request.settings.width = width;
    request.settings.height = height;
    request.settings.sample_distance = 1.0 / 64.0;
    request.settings.light_buffer.slices = 16;
    request.settings.light_buffer.resolution = 32;
    request.transfer_function = {"soft",
                                 {{0.0, {1.0, 0.9, 0.8}}, {1.0, {1.0, 1.0, 1.0}}},
                                 {{0.0, 0.0}, {0.3, 0.0}, {1.0, 0.08}}};
    return request;
}

// ---- the work ceiling ----

TEST_F(FrameBudgetTest, RequestOverTheCeilingIsRefusedBeforeAnythingRuns) {
    create(with(&RendererOptions::max_frame_work, 1e6));
    use(test::radial_volume(16));
    scene::FrameRequest small = soft_scene(scene::Mode::sbrc, 8, 8);
    small.settings.light_buffer.slab_samples = 1;
    // 64 px x 112 samples x 3 + 32^2 x 16 x 1 = 4e4: well inside.
    scene::FrameRequest large = small;
    large.settings.width = 256;
    large.settings.height = 256;  // 6.6e4 px x 112 x 3 = 2.2e7
    large.transfer_function.colors.front().rgb = {0.0, 1.0, 0.0};

    auto refused = renderer_->render(large);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::too_much_work);
    EXPECT_EQ(refused.error().where, "settings");
    EXPECT_NE(refused.error().message.find("2.2e+07"), std::string::npos)
            << refused.error().message;
    EXPECT_NE(refused.error().message.find("1e+06"), std::string::npos) << refused.error().message;
    EXPECT_EQ(renderer_->light_buffer_builds(), 0u);
    EXPECT_EQ(renderer_->gpu_bytes_held(), volume_->data.size());

    // Nothing of the refused request reached the GPU: its transfer function is uploaded by the
    // first frame that uses it, and that frame builds the first light buffer.
    large.settings.width = small.settings.width;
    large.settings.height = small.settings.height;
    const Frame frame = render(large);
    EXPECT_EQ(frame.report.light_buffer, render::LightBufferState::built);
    EXPECT_TRUE(std::any_of(frame.report.passes.begin(), frame.report.passes.end(),
                            [](const PassTiming& p) { return p.name == "transfer_function"; }));
}

TEST_F(FrameBudgetTest, CeilingCountsTheLightBufferAndHalfAngleSlices) {
    create(with(&RendererOptions::max_frame_work, 1e6));
    use(test::radial_volume(16));
    for (const scene::Mode mode : {scene::Mode::sbrc, scene::Mode::half_angle}) {
        scene::FrameRequest request = soft_scene(mode, 8, 8);
        request.settings.light_buffer.slab_samples = 1;
        EXPECT_TRUE(renderer_->render(request).ok()) << scene::to_string(mode);
        request.settings.light_buffer.resolution = 512;  // 512^2 x 16 = 4.2e6
        auto refused = renderer_->render(request);
        ASSERT_FALSE(refused.ok()) << scene::to_string(mode);
        EXPECT_EQ(refused.error().code, base::ErrorCode::too_much_work);
    }
}

// A small sphere in a 64^3 volume: 8 of its 512 bricks hold values a TF that is transparent
// below 0.5 shows, so a ray marches few samples and leaps the rest.
struct MostlyEmpty {
    volume::Volume volume = test::sphere_volume(64, 0.2f);
    scene::FrameRequest request = soft_scene(scene::Mode::dvr, 64, 64);

    MostlyEmpty() {
        request.transfer_function.opacities = {{0.0, 0.0}, {0.5, 0.0}, {0.51, 0.6}, {1.0, 0.6}};
    }

    // The estimate that knows nothing of empty space: what admission counted before it did.
    [[nodiscard]] double every_sample_work() const {
        const scene::Box box = scene::box_for_extent(volume.extent(), volume.axes);
        return scene::estimate_work(request, box, 0).total();
    }
};

TEST_F(FrameBudgetTest, AMostlyEmptyVolumeIsAdmittedForTheWorkItsRaysDo) {
    const MostlyEmpty scene;
    // Half what marching every sample costs: with skipping a ray marches at most the samples
    // along the longest line through the 2 x 2 x 2 block of visible bricks and one per brick it
    // leaps: 49 of its 112.
    create(with(&RendererOptions::max_frame_work, scene.every_sample_work() / 2.0));
    use(scene.volume);
    EXPECT_TRUE(renderer_->render(scene.request).ok());

    scene::FrameRequest unskipped = scene.request;
    unskipped.settings.empty_space_skipping = false;
    auto refused = renderer_->render(unskipped);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::too_much_work);
}

// Found in review: admission counted the volume-wide fraction of visible bricks, an average. One
// visible column of an 8^3 brick grid (1/64 of its bricks) seen down its length at a fine sample
// distance: every ray samples the whole column, 512 samples, while the fraction counted 29 per
// ray, so a frame far over the ceiling ran.
TEST_F(FrameBudgetTest, AVisibleColumnSeenAlongItIsCountedForTheSamplesItsRaysTake) {
    // Visible only inside brick column (3, 3): voxels 25..30 of x and y, clear of the one-voxel
    // border that the neighbouring bricks' ranges include.
    const glm::uvec3 dims(64);
    std::vector<float> values(std::size_t{64} * 64 * 64, 0.0f);
    for (unsigned z = 0; z < dims.z; ++z) {
        for (unsigned y = 25; y <= 30; ++y) {
            for (unsigned x = 25; x <= 30; ++x) {
                values[(std::size_t(z) * dims.y + y) * dims.x + x] = 1.0f;
            }
        }
    }
    const volume::Volume column =
            volume::make_volume("column", dims, glm::dvec3(1.0), values).value();
    const scene::Box box = scene::box_for_extent(column.extent(), column.axes);

    scene::FrameRequest request = soft_scene(scene::Mode::dvr, 32, 32);
    request.transfer_function.opacities = {{0.0, 0.0}, {0.5, 0.0}, {0.51, 0.001}, {1.0, 0.001}};
    request.settings.sample_distance = box.size().z / 512.0;
    // A narrow view down the middle of the column: every pixel's ray stays inside it from the
    // box's near face to its far face.
    const glm::dvec3 middle =
            box.to_world(box.min + glm::dvec3(28.0 / 64.0, 28.0 / 64.0, 0.5) * box.size());
    request.camera.eye = middle - glm::dvec3(0.0, 0.0, 3.0 * box.size().z);
    request.camera.target = middle;
    request.camera.up = {0.0, 1.0, 0.0};
    request.camera.fov_y_degrees = 1.0;
    const double samples_down_the_column =
            32.0 * 32.0 * std::ceil(box.size().z / request.settings.sample_distance);

    create(with(&RendererOptions::max_frame_work, 0.9 * samples_down_the_column));
    use(column);
    auto refused = renderer_->render(request);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::too_much_work);
    // The bound is close: the longest line through the column is hardly longer than the column.
    create(with(&RendererOptions::max_frame_work, 1.1 * samples_down_the_column));
    EXPECT_TRUE(renderer_->render(request).ok());
}

TEST_F(FrameBudgetTest, AVolumeWhoseBricksAreAllVisibleIsEstimatedAsEverySample) {
    MostlyEmpty scene;
    scene.request.transfer_function.opacities = {{0.0, 0.02}, {1.0, 0.6}};  // nothing transparent
    const double work = scene.every_sample_work();
    create(with(&RendererOptions::max_frame_work, work * 0.99));
    use(scene.volume);
    auto refused = renderer_->render(scene.request);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::too_much_work);
    char expected[32];
    std::snprintf(expected, sizeof expected, "about %.2g shader", work);
    EXPECT_NE(refused.error().message.find(expected), std::string::npos)
            << refused.error().message << " (expected " << expected << ")";

    create(with(&RendererOptions::max_frame_work, work));
    EXPECT_TRUE(renderer_->render(scene.request).ok());
}

// ---- the light-buffer cache ----

TEST_F(FrameBudgetTest, LightBufferLargerThanTheBudgetIsRefused) {
    create(with(&RendererOptions::light_buffer_memory_budget, std::size_t{1} << 20));
    use(test::radial_volume(16));
    scene::FrameRequest request = soft_scene(scene::Mode::sbrc);
    request.settings.light_buffer.slices = 32;
    request.settings.light_buffer.resolution = 128;  // 32 x 128^2 x 2 bytes = 1 MiB: fits
    EXPECT_EQ(light_buffer_after(request), render::LightBufferState::built);
    request.settings.light_buffer.slices = 33;
    auto refused = renderer_->render(request);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::light_buffer_too_large);
    EXPECT_EQ(refused.error().where, "light_buffer");
    EXPECT_NE(refused.error().message.find("1 MiB"), std::string::npos) << refused.error().message;
    EXPECT_EQ(renderer_->light_buffer_builds(), 1u);
}

TEST_F(FrameBudgetTest, EvictionKeepsTheCachedBuffersUnderTheBudget) {
    const std::size_t budget = std::size_t{1} << 20;
    create(with(&RendererOptions::light_buffer_memory_budget, budget));
    use(test::radial_volume(16));
    scene::FrameRequest request = soft_scene(scene::Mode::sbrc);
    request.settings.light_buffer.slices = 12;
    request.settings.light_buffer.resolution = 128;  // 384 KiB: two fit, three do not
    for (int i = 0; i < 6; ++i) {
        request.light.direction = scene::direction_from_angles(40.0 * i, 20.0);
        EXPECT_EQ(light_buffer_after(request), render::LightBufferState::built);
        EXPECT_LE(renderer_->gpu_bytes_held() - volume_->data.size(), budget) << "after " << i;
    }
    // The two most recent stay cached.
    EXPECT_EQ(light_buffer_after(request), render::LightBufferState::reused);
    request.light.direction = scene::direction_from_angles(40.0 * 4, 20.0);
    EXPECT_EQ(light_buffer_after(request), render::LightBufferState::reused);
    request.light.direction = scene::direction_from_angles(0.0, 20.0);
    EXPECT_EQ(light_buffer_after(request), render::LightBufferState::built);
}

// Finding 7: the cache keyed on a counter that any other session's transfer function advanced,
// so two sessions with different TFs rebuilt each other's buffer on every frame.
TEST_F(FrameBudgetTest, SessionsWithDifferentTransferFunctionsEachReuseTheirOwnBuffer) {
    use(test::radial_volume(24));
    const scene::FrameRequest first = soft_scene(scene::Mode::sbrc);
    scene::FrameRequest second = first;
    second.transfer_function.opacities.back().alpha = 0.3;
    second.camera = scene::orbit_camera(140.0, -10.0, 2.2);
    EXPECT_EQ(light_buffer_after(first), render::LightBufferState::built);
    EXPECT_EQ(light_buffer_after(second), render::LightBufferState::built);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(light_buffer_after(first), render::LightBufferState::reused) << "frame " << i;
        EXPECT_EQ(light_buffer_after(second), render::LightBufferState::reused) << "frame " << i;
    }
    EXPECT_EQ(renderer_->light_buffer_builds(), 2u);
}

// Every member of the request in turn: the buffer is rebuilt exactly when its content depends on
// what changed, and reused (served from the cache) when it does not.
TEST_F(FrameBudgetTest, LightBufferIsRebuiltExactlyWhenWhatItHoldsChanges) {
    use(test::radial_volume(24));
    const scene::FrameRequest base = soft_scene(scene::Mode::sbrc);
    // What "one per voxel" resolves to for the base request.
    const scene::Box box = scene::box_for_extent(volume_->extent());
    const optics::LightSlicing slicing =
            optics::make_light_slicing(box, optics::light_travel_direction(base.light, box),
                                       base.settings.light_buffer.slices);
    const int per_voxel = optics::resolve_slab_samples(
            slicing, glm::dvec3(glm::vec3(box.size() / glm::dvec3(volume_->dims))), 0);
    ASSERT_GT(per_voxel, 1);

    struct Change {
        std::string what;
        std::function<void(scene::FrameRequest&)> apply;
        bool rebuilds;
    };

    using R = scene::FrameRequest;
    const std::vector<Change> changes = {
            // camera and image
            {"camera eye", [](R& r) { r.camera.eye.x += 0.3; }, false},
            {"camera fov", [](R& r) { r.camera.fov_y_degrees = 40.0; }, false},
            {"width", [](R& r) { r.settings.width = 17; }, false},
            {"height", [](R& r) { r.settings.height = 30; }, false},
            // how the ray caster marches, shades and reads the buffer
            {"mode sbrc_shell", [](R& r) { r.settings.mode = scene::Mode::sbrc_shell; }, false},
            {"mode sbrc_cone", [](R& r) { r.settings.mode = scene::Mode::sbrc_cone; }, false},
            {"stage", [](R& r) { r.settings.stage = scene::RaycastStage::fragment; }, false},
            {"sample distance", [](R& r) { r.settings.sample_distance = 1.0 / 50.0; }, false},
            {"early termination", [](R& r) { r.settings.early_termination = 0.5; }, false},
            {"background",
             [](R& r) {
                 r.settings.background = {0.1, 0.2, 0.3};
             },
             false},
            {"shading", [](R& r) { r.settings.shading.specular = 0.9; }, false},
            {"phong", [](R& r) { r.settings.phong = true; }, false},
            {"scattering", [](R& r) { r.settings.scattering.shell_rings = 3; }, false},
            {"cone angle", [](R& r) { r.settings.scattering.cone_angle_degrees = 10.0; }, false},
            {"lookup",
             [](R& r) { r.settings.light_buffer.lookup = scene::LightLookup::interpolate; }, false},
            // what the light carries, not where it comes from
            {"light colour",
             [](R& r) {
                 r.light.color = {1.0, 0.5, 0.2};
             },
             false},
            {"light intensity", [](R& r) { r.light.intensity = 3.0; }, false},
            {"ambient", [](R& r) { r.light.ambient = 0.6; }, false},
            {"directional light's unused position",
             [](R& r) {
                 r.light.position = {5, 5, 5};
             },
             false},
            {"direction's length", [](R& r) { r.light.direction *= 2.5; }, false},
            // the TF's colour and name: the builders read its opacity only
            {"TF colour",
             [](R& r) {
                 r.transfer_function.colors.back().rgb = {0.0, 0.0, 1.0};
             },
             false},
            {"TF name", [](R& r) { r.transfer_function.name = "renamed"; }, false},
            {"slab samples per voxel written out",
             [per_voxel](R& r) { r.settings.light_buffer.slab_samples = per_voxel; }, false},
            // what the buffer holds
            {"compositing", [](R& r) { r.settings.compositing = scene::Compositing::extinction; },
             true},
            {"opacity unit distance", [](R& r) { r.settings.opacity_unit_distance = 1.0 / 64.0; },
             true},
            {"slices", [](R& r) { r.settings.light_buffer.slices = 20; }, true},
            {"resolution", [](R& r) { r.settings.light_buffer.resolution = 40; }, true},
            {"builder", [](R& r) { r.settings.light_buffer.builder = Builder::per_slice; }, true},
            {"compensation", [](R& r) { r.settings.light_buffer.compensation = 2.0; }, true},
            {"slab samples", [](R& r) { r.settings.light_buffer.slab_samples = 1; }, true},
            {"light direction",
             [](R& r) { r.light.direction = scene::direction_from_angles(10.0, 10.0); }, true},
            {"point light", [](R& r) { r.light.type = scene::LightType::point; }, true},
            {"TF opacity", [](R& r) { r.transfer_function.opacities.back().alpha = 0.2; }, true},
            {"TF opacity position", [](R& r) { r.transfer_function.opacities[1].x = 0.4; }, true},
    };
    EXPECT_EQ(light_buffer_after(base), render::LightBufferState::built);
    for (const Change& change : changes) {
        scene::FrameRequest changed = base;
        change.apply(changed);
        EXPECT_EQ(light_buffer_after(changed), change.rebuilds ? render::LightBufferState::built
                                                               : render::LightBufferState::reused)
                << change.what;
        EXPECT_EQ(light_buffer_after(base), render::LightBufferState::reused)
                << "back from " << change.what;
    }

    // A point light's buffer depends on its position and not on the unused direction.
    scene::FrameRequest point = base;
    point.light.type = scene::LightType::point;
    point.light.position = {2.0, -1.5, 1.0};
    EXPECT_EQ(light_buffer_after(point), render::LightBufferState::built);
    scene::FrameRequest moved = point;
    moved.light.direction = {1.0, 0.0, 0.0};
    EXPECT_EQ(light_buffer_after(moved), render::LightBufferState::reused);
    moved.light.position.z = 1.5;
    EXPECT_EQ(light_buffer_after(moved), render::LightBufferState::built);

    // Another volume is another buffer; the first volume's stays cached.
    const auto first_volume = volume_;
    use(test::radial_volume(20));
    EXPECT_EQ(light_buffer_after(base), render::LightBufferState::built);
    ASSERT_TRUE(renderer_->set_volume(first_volume).ok());
    EXPECT_EQ(light_buffer_after(base), render::LightBufferState::reused);
}

// ---- cancellation ----

// A predicate that starts saying "cancelled" `after` seconds after its first call, remembering
// when it first did and how often it was asked.
struct CancelAfter {
    explicit CancelAfter(double seconds)
        : after(seconds) {}

    CancelPredicate predicate() {
        return [this] {
            ++asked;
            const Clock::time_point now = Clock::now();
            if (!started) {
                started = now;
            }
            if (std::chrono::duration<double>(now - *started).count() < after) {
                return false;
            }
            if (!cancelled_at) {
                cancelled_at = now;
            }
            return true;
        };
    }

    double after;
    int asked = 0;
    std::optional<Clock::time_point> started;
    std::optional<Clock::time_point> cancelled_at;
};

// Frames that would hold llvmpipe for minutes (each estimated at 1e9 to 1e12 iterations), in each
// kind of chunked work: ray-cast tiles and step ranges, light-buffer builds with either builder,
// half-angle slices and fragment-stage tiles. Each is cancelled 1 s in (after the first chunk,
// which includes compiling the shader variant) and must return within the bound: a chunk is sized
// to take a few tens of milliseconds on llvmpipe, so the bound (5 s) leaves a wide margin for a
// loaded machine and only catches a frame that ran on to its end.
TEST_F(FrameBudgetTest, CancelledFramesStopBetweenChunks) {
    use(test::radial_volume(64));

    struct Case {
        std::string what;
        scene::FrameRequest request;
    };

    std::vector<Case> cases;
    {
        scene::FrameRequest r = soft_scene(scene::Mode::reference, 256, 256);
        r.settings.sample_distance = 1.0 / 2048.0;
        cases.push_back({"reference ray casting", r});
        r.settings.mode = scene::Mode::dvr;
        r.settings.width = r.settings.height = 2048;
        r.settings.sample_distance = 1.0 / 4096.0;
        cases.push_back({"dvr ray casting", r});
        r.settings.stage = scene::RaycastStage::fragment;
        r.settings.sample_distance = 1.0 / 1024.0;  // within llvmpipe's fragment loop cap
        r.settings.mode = scene::Mode::phong;
        cases.push_back({"fragment-stage tiles", r});
    }
    for (const Builder builder : {Builder::multi_slice, Builder::per_slice}) {
        scene::FrameRequest r = soft_scene(scene::Mode::sbrc, 8, 8);
        r.settings.light_buffer.slices = 256;
        r.settings.light_buffer.resolution = 512;  // 128 MiB
        r.settings.light_buffer.slab_samples = 16;
        r.settings.light_buffer.builder = builder;
        cases.push_back({std::string("light buffer ") + scene::to_string(builder), r});
    }
    {
        scene::FrameRequest r = soft_scene(scene::Mode::half_angle, 1024, 1024);
        r.settings.light_buffer.slices = 2048;
        r.settings.light_buffer.resolution = 2048;
        cases.push_back({"half-angle slices", r});
    }
    const double bound_s = 5.0;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        CancelAfter cancel(1.0);
        const Clock::time_point start = Clock::now();
        auto frame = renderer_->render(c.request, cancel.predicate());
        const double total_s = seconds_since(start);
        ASSERT_FALSE(frame.ok()) << "finished in " << total_s << " s before it was cancelled";
        EXPECT_EQ(frame.error().code, base::ErrorCode::cancelled) << frame.error().to_string();
        ASSERT_TRUE(cancel.cancelled_at.has_value());
        const double after_cancel_s = seconds_since(*cancel.cancelled_at);
        EXPECT_LT(after_cancel_s, bound_s);
        EXPECT_GT(cancel.asked, 2);
        std::printf("[ measured ] %s: cancelled %.3f s in, returned %.3f s later, %d checks\n",
                    c.what.c_str(), total_s - after_cancel_s, after_cancel_s, cancel.asked);
    }
    // The renderer is intact, and the cancelled builds left nothing behind in the cache.
    const std::uint64_t builds = renderer_->light_buffer_builds();
    scene::FrameRequest after = soft_scene(scene::Mode::sbrc, 8, 8);
    after.settings.light_buffer.slices = 1024;
    after.settings.light_buffer.resolution = 8;
    EXPECT_EQ(render(after).report.light_buffer, render::LightBufferState::built);
    EXPECT_EQ(renderer_->light_buffer_builds(), builds + 1);
    EXPECT_EQ(renderer_->gpu_bytes_held(), volume_->data.size() + std::size_t{1024} * 8 * 8 * 2);
}

TEST_F(FrameBudgetTest, FrameCancelledBeforeItStartsRunsNothing) {
    use(test::radial_volume(16));
    auto frame = renderer_->render(soft_scene(scene::Mode::sbrc), [] { return true; });
    ASSERT_FALSE(frame.ok());
    EXPECT_EQ(frame.error().code, base::ErrorCode::cancelled);
    EXPECT_EQ(renderer_->light_buffer_builds(), 0u);
}

// ---- chunked and unchunked frames ----

// Chunks of 2e4 iterations cut these frames into dozens to thousands of tiles and step ranges
// (light buffers into tiles of texels or groups of slices). The running sums stay in float32 in
// either case, so the images may differ only by the rounding of the two compiled variants: at
// most one level of 255 per channel (measured: 0); light buffers, built by the same shader over
// other tiles, must be identical.
TEST_F(FrameBudgetTest, ChunkedFramesGiveTheUnchunkedImage) {
    const volume::Volume volume = test::radial_volume(24);

    struct Rendered {
        base::ImageRgba8 image;
        std::string stage;
        std::vector<float> light_buffer;
    };

    const auto render_all = [&](double chunk_work, const CancelPredicate& cancelled) {
        create(with(&RendererOptions::chunk_work, chunk_work));
        use(volume);
        std::vector<Rendered> frames;
        for (const scene::Mode mode :
             {scene::Mode::dvr, scene::Mode::phong, scene::Mode::sbrc, scene::Mode::sbrc_shell,
              scene::Mode::sbrc_cone, scene::Mode::reference, scene::Mode::half_angle}) {
            for (const Builder builder : {Builder::multi_slice, Builder::per_slice}) {
                if (!scene::uses_light_buffer(mode) && builder == Builder::per_slice) {
                    continue;
                }
                scene::FrameRequest request = soft_scene(mode, 36, 28);
                request.settings.light_buffer.builder = builder;
                request.settings.phong = true;
                auto frame = renderer_->render(request, cancelled);
                EXPECT_TRUE(frame.ok()) << frame.error().to_string();
                if (!frame.ok()) {
                    return frames;
                }
                Rendered r{frame->image, frame->report.stage, {}};
                if (scene::uses_light_buffer(mode)) {
                    r.light_buffer = renderer_->read_light_buffer()->values;
                }
                frames.push_back(std::move(r));
            }
        }
        return frames;
    };
    const std::vector<Rendered> chunked = render_all(2e4, [] { return false; });
    const std::vector<Rendered> whole = render_all(0.0, {});
    ASSERT_EQ(chunked.size(), whole.size());
    for (std::size_t i = 0; i < whole.size(); ++i) {
        SCOPED_TRACE("frame " + std::to_string(i) + ", " + chunked[i].stage);
        EXPECT_EQ(whole[i].stage.find("chunks"), std::string::npos) << whole[i].stage;
        if (whole[i].stage != "slices") {
            EXPECT_NE(chunked[i].stage.find("chunks"), std::string::npos) << chunked[i].stage;
        }
        ASSERT_EQ(chunked[i].image.pixels.size(), whole[i].image.pixels.size());
        int worst = 0;
        for (std::size_t p = 0; p < whole[i].image.pixels.size(); ++p) {
            worst = std::max(worst, std::abs(int{chunked[i].image.pixels[p]} -
                                             int{whole[i].image.pixels[p]}));
        }
        EXPECT_LE(worst, 1);
        EXPECT_EQ(chunked[i].light_buffer, whole[i].light_buffer);
        std::printf("[ measured ] %s: largest difference %d of 255\n", chunked[i].stage.c_str(),
                    worst);
    }
}

}  // namespace
}  // namespace penumbra::render
