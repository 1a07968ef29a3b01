#include "stability.hpp"

#include <penumbra/imageio/compare.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>

namespace penumbra::stability {

bool has_cpu_reference(scene::Mode mode) {
    return mode == scene::Mode::dvr || mode == scene::Mode::phong || mode == scene::Mode::reference;
}

scene::TransferFunction soft_tf() {
    return {"soft",
            {{0.0, {0.1, 0.3, 0.9}}, {0.5, {1.0, 0.6, 0.2}}, {1.0, {1.0, 1.0, 0.9}}},
            {{0.0, 0.0}, {0.15, 0.0}, {0.6, 0.08}, {1.0, 0.35}}};
}

scene::TransferFunction visible_at_zero() {
    return {"visible_at_zero",
            {{0.0, {0.9, 0.8, 0.3}}, {1.0, {1.0, 0.2, 0.1}}},
            {{0.0, 0.06}, {1.0, 0.06}}};
}

scene::TransferFunction opaque_tf() {
    return {"opaque", {{0.0, {0.9, 0.75, 0.2}}, {1.0, {1.0, 1.0, 1.0}}}, {{0.0, 1.0}}};
}

scene::TransferFunction transparent_tf() {
    return {"transparent",
            {{0.0, {1.0, 1.0, 1.0}}, {1.0, {1.0, 0.0, 0.0}}},
            {{0.0, 0.0}, {1.0, 0.0}}};
}

scene::FrameRequest base_request(scene::Mode mode, int size) {
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(30.0, 20.0, 2.4);
    request.light.direction = scene::direction_from_angles(-60.0, 35.0);
    request.light.ambient = 0.2;
    request.transfer_function = soft_tf();
    scene::RenderSettings& s = request.settings;
    s.mode = mode;
    s.width = size;
    s.height = size;
    s.sample_distance = 1.0 / 64.0;
    s.opacity_unit_distance = 1.0 / 64.0;
    s.background = background;
    s.light_buffer.slices = 24;
    s.light_buffer.resolution = 24;
    // Every hard case runs jittered (the CPU reference samples at the same offsets); the golden
    // tests keep the midpoint sampling covered.
    s.jitter = true;
    s.reconstruction = reconstruction();
    // The suite runs a second time with every case pre-integrated (tests/stability/CMakeLists.txt).
    const char* preintegration = std::getenv("PENUMBRA_STABILITY_PREINTEGRATION");
    s.preintegration = preintegration != nullptr && std::string(preintegration) == "1";
    return request;
}

volume::Volume float_volume(glm::uvec3 dims, glm::dvec3 spacing,
                            const std::function<float(glm::dvec3)>& f) {
    std::vector<float> values(static_cast<std::size_t>(dims.x) * dims.y * dims.z);
    std::size_t i = 0;
    for (unsigned z = 0; z < dims.z; ++z) {
        for (unsigned y = 0; y < dims.y; ++y) {
            for (unsigned x = 0; x < dims.x; ++x) {
                values[i++] = f((glm::dvec3(x, y, z) + 0.5) / glm::dvec3(dims));
            }
        }
    }
    auto made = volume::make_volume("stability", dims, spacing, values);
    EXPECT_TRUE(made.ok()) << made.error().to_string();
    return made.ok() ? std::move(made.value()) : volume::Volume{};
}

float radial(glm::dvec3 p) {
    return static_cast<float>(std::max(0.0, 1.0 - glm::length(p - 0.5) / 0.5));
}

scene::Reconstruction reconstruction() {
    const char* text = std::getenv("PENUMBRA_STABILITY_RECONSTRUCTION");
    if (text == nullptr || *text == '\0') {
        return scene::Reconstruction::trilinear;
    }
    const auto parsed = scene::parse_name<scene::Reconstruction>(text);
    EXPECT_TRUE(parsed.has_value()) << "PENUMBRA_STABILITY_RECONSTRUCTION=" << text;
    return parsed.value_or(scene::Reconstruction::trilinear);
}

std::uint64_t property_seed(std::uint64_t fallback) {
    if (const char* text = std::getenv("PENUMBRA_STABILITY_SEED"); text != nullptr && *text) {
        return std::strtoull(text, nullptr, 0);
    }
    return fallback;
}

glm::dvec3 random_direction(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const double z = 2.0 * uniform(rng) - 1.0;
    const double phi = 2.0 * std::numbers::pi * uniform(rng);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

std::string describe(glm::dvec3 v) {
    std::ostringstream out;
    out.precision(17);
    out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}

std::string describe(const scene::FrameRequest& request) {
    const scene::RenderSettings& s = request.settings;
    std::ostringstream out;
    out << "mode " << scene::to_string(s.mode)
        << (s.phong && s.mode != scene::Mode::phong ? "+phong" : "")
        << (s.preintegration ? ", pre-integrated" : "") << ", " << scene::to_string(s.compositing)
        << ", " << scene::to_string(s.stage) << ", " << s.width << "x" << s.height << ", eye "
        << describe(request.camera.eye) << ", target " << describe(request.camera.target)
        << ", light "
        << (request.light.type == scene::LightType::point
                    ? "point at " + describe(request.light.position)
                    : "toward " + describe(request.light.direction))
        << ", tf " << request.transfer_function.name << ", sample distance " << s.sample_distance
        << ", slices " << s.light_buffer.slices << ", resolution " << s.light_buffer.resolution
        << " (" << scene::to_string(s.light_buffer.builder) << "), compensation "
        << s.light_buffer.compensation;
    return out.str();
}

void StabilityTest::SetUp() {
    auto created = render::Renderer::create();
    ASSERT_TRUE(created.ok()) << created.error().to_string();
    renderer_ = std::move(created.value());
}

void StabilityTest::use(const volume::Volume& volume) {
    volume_ = std::make_shared<const volume::Volume>(volume);
    auto status = renderer_->set_volume(volume_);
    ASSERT_TRUE(status.ok()) << status.error().to_string();
}

std::optional<render::Frame> StabilityTest::render(const scene::FrameRequest& request) {
    auto frame = renderer_->render(request);
    EXPECT_TRUE(frame.ok()) << describe(request) << ": " << frame.error().to_string();
    if (!frame.ok()) {
        return std::nullopt;
    }
    EXPECT_EQ(frame->image.width, request.settings.width);
    EXPECT_EQ(frame->image.height, request.settings.height);
    EXPECT_EQ(frame->image.pixels.size(),
              static_cast<std::size_t>(request.settings.width) * request.settings.height * 4);
    return std::move(frame.value());
}

std::optional<render::Frame> StabilityTest::render_and_check(const scene::FrameRequest& request,
                                                             const CheckOptions& options) {
    SCOPED_TRACE(describe(request));
    auto frame = render(request);
    if (!frame) {
        return frame;
    }
    const base::ImageRgba8& image = frame->image;
    const std::uint8_t bg[3] = {static_cast<std::uint8_t>(std::lround(background.r * 255.0)),
                                static_cast<std::uint8_t>(std::lround(background.g * 255.0)),
                                static_cast<std::uint8_t>(std::lround(background.b * 255.0))};
    int opaque_failures = 0;
    int background_failures = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            if (p[3] != 255 && opaque_failures++ == 0) {
                ADD_FAILURE() << "pixel (" << x << ", " << y << ") has alpha " << int{p[3]};
            }
            if (options.expect_background && (p[0] != bg[0] || p[1] != bg[1] || p[2] != bg[2]) &&
                background_failures++ == 0) {
                ADD_FAILURE() << "transparent TF, yet pixel (" << x << ", " << y << ") is ("
                              << int{p[0]} << ", " << int{p[1]} << ", " << int{p[2]}
                              << "), not the background";
            }
        }
    }
    EXPECT_EQ(opaque_failures, 0) << "pixels with alpha below 255";
    EXPECT_EQ(background_failures, 0) << "pixels off the background under a transparent TF";
    if (!options.expect_background && options.min_visible_fraction > 0.0) {
        const int visible = pixels_off_background(image);
        EXPECT_GE(visible, options.min_visible_fraction * image.width * image.height)
                << "the TF is visible, yet only " << visible << " of " << image.width * image.height
                << " pixels differ from the background";
    }
    if (scene::uses_light_buffer(request.settings.mode) && options.check_light_buffer) {
        check_light_buffer(request);
    }
    if (options.compare_cpu && has_cpu_reference(request.settings.mode)) {
        expect_matches_cpu(*frame, request, options.tolerance);
    }
    return frame;
}

void StabilityTest::check_light_buffer(const scene::FrameRequest& request) {
    const auto& lb = request.settings.light_buffer;
    auto buffer = renderer_->read_light_buffer();
    ASSERT_TRUE(buffer.ok()) << buffer.error().to_string();
    ASSERT_EQ(buffer->slices, lb.slices);
    ASSERT_EQ(buffer->resolution, lb.resolution);
    const std::size_t layer = static_cast<std::size_t>(lb.resolution) * lb.resolution;
    ASSERT_EQ(buffer->values.size(), layer * static_cast<std::size_t>(lb.slices));
    const std::vector<float>& v = buffer->values;
    for (std::size_t i = 0; i < v.size(); ++i) {
        ASSERT_TRUE(std::isfinite(v[i]) && v[i] >= 0.0f && v[i] <= 1.0f)
                << "light buffer texel " << i % layer << " of layer " << i / layer << " is "
                << v[i];
    }
    // Layer k holds the light that crossed slices 0..k-1: all of it in layer 0, and no slice
    // adds light (compensation is capped at 1). Half floats keep about 3 digits.
    for (std::size_t i = 0; i < layer; ++i) {
        ASSERT_EQ(v[i], 1.0f) << "layer 0, texel " << i;
        for (std::size_t k = 1; k < static_cast<std::size_t>(lb.slices); ++k) {
            ASSERT_LE(v[k * layer + i], v[(k - 1) * layer + i] + 1e-3f)
                    << "texel " << i << " brightens from layer " << k - 1 << " to " << k;
        }
    }
}

void StabilityTest::expect_matches_cpu(const render::Frame& frame,
                                       const scene::FrameRequest& request, Tolerance tolerance) {
    ASSERT_TRUE(volume_ != nullptr);
    auto expected = reference::render_cpu(*volume_, request);
    ASSERT_TRUE(expected.ok()) << expected.error().to_string();
    const base::ImageRgbaF& cpu = *expected;
    // The reference is part of what must stay finite.
    for (std::size_t i = 0; i < cpu.pixels.size(); ++i) {
        ASSERT_TRUE(std::isfinite(cpu.pixels[i]))
                << "the CPU reference has a non-finite value at pixel (" << (i / 4) % cpu.width
                << ", " << (i / 4) / cpu.width << ") channel " << i % 4;
    }
    const base::ImageRgbaF gpu = base::to_rgba_f(frame.image);
    auto difference = imageio::compare_images(gpu, cpu);
    ASSERT_TRUE(difference.ok()) << difference.error().to_string();
    // Where the worst pixel is, for the failure message.
    double worst = -1.0;
    int worst_x = 0;
    int worst_y = 0;
    for (int y = 0; y < cpu.height; ++y) {
        for (int x = 0; x < cpu.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const double d = std::abs(double{gpu.pixel(x, y)[c]} - double{cpu.pixel(x, y)[c]});
                if (d > worst) {
                    worst = d;
                    worst_x = x;
                    worst_y = y;
                }
            }
        }
    }
    const auto rgb = [](const float* p) {
        std::ostringstream out;
        out << "(" << p[0] * 255.0f << ", " << p[1] * 255.0f << ", " << p[2] * 255.0f << ")";
        return out.str();
    };
    EXPECT_TRUE(difference->max_error <= tolerance.max_error &&
                difference->mean_error <= tolerance.mean_error)
            << "GPU vs CPU reference: max error " << difference->max_error * 255.0
            << "/255 (allowed " << tolerance.max_error * 255.0 << "), mean error "
            << difference->mean_error * 255.0 << "/255 (allowed " << tolerance.mean_error * 255.0
            << "); worst pixel (" << worst_x << ", " << worst_y << "): GPU "
            << rgb(gpu.pixel(worst_x, worst_y)) << ", CPU " << rgb(cpu.pixel(worst_x, worst_y));
}

double rms_difference(const base::ImageRgba8& a, const base::ImageRgba8& b) {
    EXPECT_EQ(a.pixels.size(), b.pixels.size());
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i) {
        if (i % 4 == 3) {
            continue;
        }
        const double d =
                (static_cast<double>(a.pixels[i]) - static_cast<double>(b.pixels[i])) / 255.0;
        sum += d * d;
        ++count;
    }
    return count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

double mean_channel(const base::ImageRgba8& image, int channel, int x0, int x1, int y0, int y1) {
    double sum = 0.0;
    int count = 0;
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            sum += image.pixel(x, y)[channel];
            ++count;
        }
    }
    return count > 0 ? sum / count : 0.0;
}

int pixels_off_background(const base::ImageRgba8& image, int levels) {
    int count = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            bool off = false;
            for (int c = 0; c < 3; ++c) {
                off = off ||
                      std::abs(int{p[c]} - static_cast<int>(std::lround(background[c] * 255.0))) >
                              levels;
            }
            count += off ? 1 : 0;
        }
    }
    return count;
}

}  // namespace penumbra::stability
