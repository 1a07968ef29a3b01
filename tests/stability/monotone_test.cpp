// Monotone where physics says so: a denser medium between the light and a receiver, or a more
// opaque TF for it, never brightens the receiver, and with the light behind the medium it clearly
// darkens it. Checked per pixel for every shadowing mode, for the light along the axis and for
// random light directions (seed printed), and per texel on the light buffer itself.

#include "stability.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace penumbra::stability {
namespace {

constexpr unsigned n = 24;

// A receiver column (value `receiver`) for x in [n/8, 3n/8), and a slab of value `slab` for x in
// [3n/4, 7n/8) covering only y < n/2, so with the light along -x half the receiver lies in the
// slab's shadow. The camera looks down -z, so no pixel sees both.
volume::Volume receiver_and_slab(float slab, float receiver = 1.0f) {
    std::vector<float> values(static_cast<std::size_t>(n) * n * n);
    std::size_t i = 0;
    for (unsigned z = 0; z < n; ++z) {
        for (unsigned y = 0; y < n; ++y) {
            for (unsigned x = 0; x < n; ++x) {
                float v = 0.0f;
                if (x >= n / 8 && x < 3 * n / 8) {
                    v = receiver;
                } else if (x >= 3 * n / 4 && x < 7 * n / 8 && y < n / 2) {
                    v = slab;
                }
                values[i++] = v;
            }
        }
    }
    // The range stays [0, 1] as long as one of the two is 1: empty space is 0.
    auto made = volume::make_volume("receiver_and_slab", glm::uvec3(n), glm::dvec3(1.0), values);
    EXPECT_TRUE(made.ok());
    return made.ok() ? std::move(made.value()) : volume::Volume{};
}

// Pixels whose rays cross only the receiver's interior (a voxel's margin from its sides), split
// into the half the slab can shadow (y < 0) and the other half.
struct ReceiverPixels {
    std::vector<int> shadowed;  // pixel indices
    std::vector<int> lit;
};

class MonotoneTest : public ModeTest {
protected:
    // A nearly orthographic view down -z, so the receiver's columns map to fixed pixel columns.
    scene::FrameRequest request(glm::dvec3 light) const {
        auto r = base_request(mode(), 32);
        r.camera.eye = {0.0, 0.0, 20.0};
        r.camera.target = {0.0, 0.0, 0.0};
        r.camera.up = {0.0, 1.0, 0.0};
        r.camera.fov_y_degrees = 3.2;
        r.light.direction = light;
        r.light.ambient = 0.1;
        r.settings.compositing = scene::Compositing::extinction;
        r.settings.sample_distance = 1.0 / 128.0;
        r.settings.opacity_unit_distance = 1.0 / 256.0;
        r.settings.light_buffer.slices = 64;
        r.settings.light_buffer.resolution = 32;
        r.transfer_function = {"ramp", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 0.0}, {1.0, 0.03}}};
        return r;
    }

    static ReceiverPixels receiver_pixels(const scene::FrameRequest& r) {
        const scene::CameraFrame frame = scene::camera_frame(r.camera, 1.0);
        const double voxel = 1.0 / n;
        const double x0 = -0.5 + (n / 8) * voxel + voxel;
        const double x1 = -0.5 + (3 * n / 8) * voxel - voxel;
        ReceiverPixels out;
        for (int py = 0; py < r.settings.height; ++py) {
            for (int px = 0; px < r.settings.width; ++px) {
                const double ndc_x = (px + 0.5) / r.settings.width * 2.0 - 1.0;
                const double ndc_y = 1.0 - (py + 0.5) / r.settings.height * 2.0;
                const glm::dvec3 d = frame.forward + ndc_x * frame.right + ndc_y * frame.up;
                // Where the ray enters and leaves the box (z = ±0.5).
                const glm::dvec3 top = frame.eye + (frame.eye.z - 0.5) / -d.z * d;
                const glm::dvec3 bottom = frame.eye + (frame.eye.z + 0.5) / -d.z * d;
                const double lo = std::min(top.x, bottom.x);
                const double hi = std::max(top.x, bottom.x);
                if (lo < x0 || hi > x1) {
                    continue;
                }
                const double y = 0.5 * (top.y + bottom.y);
                if (y < -0.1 && y > -0.45) {
                    out.shadowed.push_back(py * r.settings.width + px);
                } else if (y > 0.1 && y < 0.45) {
                    out.lit.push_back(py * r.settings.width + px);
                }
            }
        }
        return out;
    }

    static double mean_red(const base::ImageRgba8& image, const std::vector<int>& pixels) {
        double sum = 0.0;
        for (const int p : pixels) {
            sum += image.pixels[static_cast<std::size_t>(p) * 4];
        }
        return pixels.empty() ? 0.0 : sum / static_cast<double>(pixels.size());
    }

    // Renders the frames of `r` over `volumes` (in order of increasing opacity) and checks that
    // no receiver pixel brightens by more than rounding from one to the next. Returns the mean
    // red of the shadowed and the lit receiver pixels per volume.
    std::vector<std::pair<double, double>> sweep(const std::vector<volume::Volume>& volumes,
                                                 const std::vector<scene::FrameRequest>& requests) {
        const ReceiverPixels pixels = receiver_pixels(requests.front());
        EXPECT_GE(pixels.shadowed.size(), 20u);
        EXPECT_GE(pixels.lit.size(), 20u);
        std::vector<std::pair<double, double>> means;
        std::optional<render::Frame> previous;
        for (std::size_t i = 0; i < requests.size(); ++i) {
            SCOPED_TRACE("step " + std::to_string(i));
            use(volumes[std::min(i, volumes.size() - 1)]);
            auto frame = render_and_check(requests[i]);
            if (!frame) {
                return means;
            }
            if (previous) {
                for (const auto* set : {&pixels.shadowed, &pixels.lit}) {
                    for (const int p : *set) {
                        const auto at = static_cast<std::size_t>(p) * 4;
                        for (std::size_t c = 0; c < 3; ++c) {
                            EXPECT_LE(int{frame->image.pixels[at + c]},
                                      int{previous->image.pixels[at + c]} + 1)
                                    << "receiver pixel (" << p % 32 << ", " << p / 32
                                    << ") brightened as the medium grew denser";
                        }
                    }
                }
            }
            means.emplace_back(mean_red(frame->image, pixels.shadowed),
                               mean_red(frame->image, pixels.lit));
            previous = std::move(frame);
        }
        return means;
    }
};

const std::vector<float> densities{0.0f, 0.25f, 0.5f, 0.75f, 1.0f};

std::vector<volume::Volume> density_volumes() {
    std::vector<volume::Volume> out;
    for (const float d : densities) {
        out.push_back(receiver_and_slab(d));
    }
    return out;
}

// Light along -x through the slab (optical depth up to 0.03 / (1/256) * 3/24 = 0.96).
TEST_F(MonotoneTest, DenserSlabDarkensTheShadowAndNothingElse) {
    for_each_mode(shadow_modes, [&] {
        const auto r = request({1.0, 0.0, 0.0});
        const auto means = sweep(density_volumes(), std::vector(densities.size(), r));
        ASSERT_EQ(means.size(), densities.size());
        // The shadow deepens clearly; the receiver's other half does not notice.
        EXPECT_LT(means.back().first, 0.75 * means.front().first)
                << "shadowed receiver: " << means.front().first << " -> " << means.back().first;
        EXPECT_NEAR(means.back().second, means.front().second, 1.0);
        EXPECT_GT(means.front().first, 40.0);
    });
}

// Property: for any light direction, a denser slab never brightens any receiver pixel.
TEST_F(MonotoneTest, DenserSlabNeverBrightensTheReceiverForRandomLights) {
    for_each_mode(shadow_modes, [&] {
        const std::uint64_t seed = property_seed(0xde45e'51ab);
        SCOPED_TRACE("seed " + std::to_string(seed) +
                     " (replay with PENUMBRA_STABILITY_SEED=" + std::to_string(seed) + ")");
        std::mt19937_64 rng(seed);
        const auto volumes = density_volumes();
        for (int i = 0; i < 4; ++i) {
            auto r = request(random_direction(rng));
            r.settings.phong = (rng() & 1) != 0;
            r.settings.light_buffer.builder = (rng() & 1) != 0
                                                      ? scene::LightBufferBuilder::per_slice
                                                      : scene::LightBufferBuilder::multi_slice;
            SCOPED_TRACE("draw " + std::to_string(i) + ": " + describe(r));
            sweep(volumes, std::vector(volumes.size(), r));
        }
    });
}

// The slab's value fixed at 1 and the receiver's at 0.5; the TF's opacity above 0.5 (the slab's
// values) rises to fully opaque while below (the receiver's, its edges included) it stays.
TEST_F(MonotoneTest, MoreOpaqueTransferFunctionNeverBrightensTheShadow) {
    for_each_mode(shadow_modes, [&] {
        std::vector<scene::FrameRequest> requests;
        for (const double alpha : {0.03, 0.05, 0.1, 0.2, 0.5, 1.0}) {
            auto r = request({1.0, 0.0, 0.0});
            r.settings.compositing = scene::Compositing::alpha;
            r.transfer_function.opacities = {{0.0, 0.0}, {0.5, 0.03}, {1.0, alpha}};
            requests.push_back(r);
        }
        const auto means = sweep({receiver_and_slab(1.0f, 0.5f)}, requests);
        ASSERT_EQ(means.size(), requests.size());
        // An opaque slab leaves the shadowed half only its ambient light (about half, here).
        EXPECT_LT(means.back().first, 0.6 * means.front().first)
                << "shadowed receiver: " << means.front().first << " -> " << means.back().first;
        EXPECT_NEAR(means.back().second, means.front().second, 1.0);
    });
}

// The light buffer itself: every texel of every layer is a product of per-slice transmittances,
// each falling with density, so the whole buffer falls elementwise (half-float rounding aside).
class LightBufferMonotoneTest : public StabilityTest,
                                public ::testing::WithParamInterface<scene::LightBufferBuilder> {};

TEST_P(LightBufferMonotoneTest, DenserMediumNeverBrightensAnyTexel) {
    const std::uint64_t seed = property_seed(0x11647'b0f);
    SCOPED_TRACE("seed " + std::to_string(seed) +
                 " (replay with PENUMBRA_STABILITY_SEED=" + std::to_string(seed) + ")");
    std::mt19937_64 rng(seed);
    std::vector<std::vector<float>> previous_by_light(6);
    std::vector<glm::dvec3> lights{{1.0, 0.0, 0.0}};
    for (int i = 1; i < 6; ++i) {
        lights.push_back(random_direction(rng));
    }
    for (const float density : densities) {
        use(receiver_and_slab(density));
        for (std::size_t l = 0; l < lights.size(); ++l) {
            SCOPED_TRACE("density " + std::to_string(density) + ", light " + describe(lights[l]));
            auto r = base_request(scene::Mode::sbrc, 8);
            r.light.direction = lights[l];
            r.settings.light_buffer.builder = GetParam();
            r.settings.light_buffer.slices = 32;
            r.settings.light_buffer.resolution = 24;
            r.transfer_function = {"ramp", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 0.0}, {1.0, 0.1}}};
            ASSERT_TRUE(render(r).has_value());
            auto buffer = renderer_->read_light_buffer();
            ASSERT_TRUE(buffer.ok());
            auto& previous = previous_by_light[l];
            if (!previous.empty()) {
                ASSERT_EQ(previous.size(), buffer->values.size());
                for (std::size_t t = 0; t < previous.size(); ++t) {
                    ASSERT_LE(buffer->values[t], previous[t] + 1e-3f) << "texel " << t;
                }
            }
            previous = buffer->values;
        }
    }
    // With the light along -x the densest slab leaves a clear shadow in the last layer.
    const auto& along_x = previous_by_light[0];
    ASSERT_FALSE(along_x.empty());
    EXPECT_LT(*std::min_element(along_x.end() - 24 * 24, along_x.end()), 0.5f);
}

INSTANTIATE_TEST_SUITE_P(Builders, LightBufferMonotoneTest,
                         ::testing::Values(scene::LightBufferBuilder::multi_slice,
                                           scene::LightBufferBuilder::per_slice),
                         [](const auto& param_info) {
                             return std::string(scene::to_string(param_info.param));
                         });

}  // namespace
}  // namespace penumbra::stability
