#pragma once

// Shared pieces of the stability suite (DESIGN.md §1 "Hard cases that must stay numerically
// stable"): the fixture, the checks every frame must pass, volume generators and seeded random
// directions for the property tests.

#include <penumbra/reference/cpu_renderer.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace penumbra::stability {

// The modes of scene's mode table that `keep` selects, in its order.
template <typename Keep>
[[nodiscard]] std::vector<scene::Mode> modes_where(Keep&& keep) {
    std::vector<scene::Mode> selected;
    for (const scene::ModeInfo& row : scene::modes()) {
        if (keep(row)) {
            selected.push_back(row.mode);
        }
    }
    return selected;
}

inline const std::vector<scene::Mode> all_modes =
        modes_where([](const scene::ModeInfo&) { return true; });

// The modes whose shadows come from a light buffer, from slicing toward the light or from rays.
inline const std::vector<scene::Mode> shadow_modes = modes_where([](const scene::ModeInfo& row) {
    return scene::uses_light_view(row.mode) || row.shadows != scene::ShadowKind::none;
});

// dvr, phong and reference have a double-precision CPU twin (server/reference).
[[nodiscard]] bool has_cpu_reference(scene::Mode mode);

struct Tolerance {
    double max_error;   // largest channel difference, [0, 1]
    double mean_error;  // mean channel difference, [0, 1]
};

// What the existing GPU-vs-CPU tests allow for float (and 16-bit) volumes: float vs double
// arithmetic and the final rounding to 8 bits.
inline constexpr Tolerance cpu_tolerance{3.0 / 255.0, 0.6 / 255.0};

// The background every stability request uses; no TF colour in this suite equals it.
inline constexpr glm::dvec3 background{0.2, 0.4, 0.6};

// A small request: `size` x `size` pixels, a generic orbit camera and light, a soft coloured TF
// that hides value 0 (so the box's empty corners show the background), few slices; pre-integrated
// where PENUMBRA_STABILITY_PREINTEGRATION is 1.
scene::FrameRequest base_request(scene::Mode mode, int size = 16);

// Transfer functions.
scene::TransferFunction soft_tf();          // transparent at 0, rising to 0.35 at 1
scene::TransferFunction visible_at_zero();  // every value, 0 included, has opacity 0.06
scene::TransferFunction opaque_tf();        // opacity 1 for every value
scene::TransferFunction transparent_tf();   // colours but opacity 0 everywhere

// A float volume whose voxel (x, y, z) holds f(p), p the voxel centre in [0,1]^3.
volume::Volume float_volume(glm::uvec3 dims, glm::dvec3 spacing,
                            const std::function<float(glm::dvec3)>& f);

// max(0, 1 - |p - centre| / 0.5) over any dims: smooth, 1 at the centre, 0 at the faces' centres.
float radial(glm::dvec3 p);

// How every request reconstructs the volume: PENUMBRA_STABILITY_RECONSTRUCTION when set (the suite
// runs once more with tricubic, tests/stability/CMakeLists.txt), otherwise trilinear.
scene::Reconstruction reconstruction();

// The seed of a property test: PENUMBRA_STABILITY_SEED when set (to replay a failure with another
// seed or explore more), otherwise `fallback`, so CI runs are reproducible.
std::uint64_t property_seed(std::uint64_t fallback);

// A direction uniformly distributed on the unit sphere.
glm::dvec3 random_direction(std::mt19937_64& rng);

std::string describe(glm::dvec3 v);

// One line naming what a frame depended on, for SCOPED_TRACE.
std::string describe(const scene::FrameRequest& request);

struct CheckOptions {
    // The TF shows something: at least this fraction of pixels differs from the background.
    double min_visible_fraction = 0.02;
    // The TF is fully transparent: the image must equal the background exactly.
    bool expect_background = false;
    // Compare with the CPU reference where the mode has one.
    bool compare_cpu = true;
    Tolerance tolerance = cpu_tolerance;
    // Read the light buffer back after sbrc frames and check it (off for huge buffers).
    bool check_light_buffer = true;
};

class StabilityTest : public ::testing::Test {
protected:
    void SetUp() override;

    void use(const volume::Volume& volume);

    // Renders; a failed render is a test failure and gives nullopt.
    std::optional<render::Frame> render(const scene::FrameRequest& request);

    // Renders and checks what every frame of the suite must satisfy: the render succeeds, alpha
    // is 255 everywhere, the background shows exactly where the TF is transparent and not
    // everywhere where it is visible, the light buffer (sbrc modes) is finite, within [0, 1],
    // 1 in its first layer and never brightening from layer to layer, and where the mode has a
    // CPU twin, the image is within `tolerance` of it.
    std::optional<render::Frame> render_and_check(const scene::FrameRequest& request,
                                                  const CheckOptions& options = {});

    // The light buffer of the last sbrc frame, checked as above.
    void check_light_buffer(const scene::FrameRequest& request);

    // The GPU image against render_cpu; the caller has checked has_cpu_reference().
    void expect_matches_cpu(const render::Frame& frame, const scene::FrameRequest& request,
                            Tolerance tolerance);

    std::unique_ptr<render::Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
};

// The fixture for tests that run once per mode: one test (one process under CTest, which pays
// for a GL context each) loops over the modes, and every failure message names the mode.
class ModeTest : public StabilityTest {
protected:
    [[nodiscard]] scene::Mode mode() const { return mode_; }

    template <class Modes, class Body>
    void for_each_mode(const Modes& modes, Body&& body) {
        for (const scene::Mode mode : modes) {
            SCOPED_TRACE(std::string("mode ") + scene::to_string(mode));
            mode_ = mode;
            body();
        }
    }

private:
    scene::Mode mode_ = scene::Mode::dvr;
};

// RMS difference of two 8-bit frames over RGB, in [0, 1].
double rms_difference(const base::ImageRgba8& a, const base::ImageRgba8& b);

// Mean of channel `channel` over the pixels [x0, x1] x [y0, y1] (inclusive), in 8-bit levels.
double mean_channel(const base::ImageRgba8& image, int channel, int x0, int x1, int y0, int y1);

// How many pixels differ from the background by more than `levels` in some channel.
int pixels_off_background(const base::ImageRgba8& image, int levels = 2);

}  // namespace penumbra::stability
