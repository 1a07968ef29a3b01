#include "penumbra/scene/quality.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

namespace penumbra::scene {
namespace {

// PSNR of the reference itself is infinite; as a mean it stands for "exact".
constexpr double exact_psnr = 99.0;

}  // namespace

std::string QualityChoice::describe(double budget_ms) const {
    char text[256];
    std::snprintf(text, sizeof text,
                  "budget %.0f ms: %s n=%d R=%d dt=1/%.0f, about %.0f ms, %.1f dB%s", budget_ms,
                  to_string(mode), slices, resolution, 1.0 / sample_distance, estimated_ms, psnr,
                  fits ? "" : " (nothing measured fits; the fastest)");
    return text;
}

std::optional<QualityChoice> choose_quality(const std::vector<QualitySample>& table,
                                            double budget_ms, int width, int height) {
    struct Aggregate {
        double slowest_ms = 0.0;
        double psnr_sum = 0.0;
        int count = 0;
    };
    using Key = std::tuple<Mode, int, int, double>;
    std::map<Key, Aggregate> settings;
    for (const QualitySample& s : table) {
        const double pixels = static_cast<double>(width) * height;
        const double measured_pixels = static_cast<double>(std::max(1, s.width)) *
                                       static_cast<double>(std::max(1, s.height));
        // Ray casting and slicing both scale with the pixel count; the light buffer does not,
        // but a cached frame does not build it.
        Aggregate& a = settings[Key{s.mode, s.slices, s.resolution, s.sample_distance}];
        a.slowest_ms = std::max(a.slowest_ms, s.frame_ms * pixels / measured_pixels);
        a.psnr_sum += std::isfinite(s.psnr) ? s.psnr : exact_psnr;
        ++a.count;
    }
    if (settings.empty()) {
        return std::nullopt;
    }
    std::optional<QualityChoice> best;
    std::optional<QualityChoice> fastest;
    for (const auto& [key, a] : settings) {
        QualityChoice c{std::get<0>(key), std::get<1>(key), std::get<2>(key), std::get<3>(key),
                        a.slowest_ms, a.psnr_sum / a.count, true};
        if (!fastest || c.estimated_ms < fastest->estimated_ms) {
            fastest = c;
        }
        if (c.estimated_ms <= budget_ms &&
            (!best || c.psnr > best->psnr ||
             (c.psnr == best->psnr && c.estimated_ms < best->estimated_ms))) {
            best = c;
        }
    }
    if (best) {
        return best;
    }
    fastest->fits = false;
    return fastest;
}

FrameRequest apply_quality(FrameRequest request, const QualityChoice& choice) {
    RenderSettings& s = request.settings;
    s.mode = choice.mode;
    if (choice.slices > 0) {
        s.light_buffer.slices = choice.slices;
    }
    if (choice.resolution > 0) {
        s.light_buffer.resolution = choice.resolution;
    }
    s.sample_distance = choice.sample_distance;
    return request;
}

}  // namespace penumbra::scene
