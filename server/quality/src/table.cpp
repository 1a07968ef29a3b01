#include "penumbra/quality/table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <utility>

namespace penumbra::quality {

const char* timing_name(const Table& table) {
    return table.gpu_timers ? "gpu" : "wall";
}

bool SettingKey::plain() const {
    return empty_space_skipping && !jitter && refinement_steps == 0;
}

std::vector<Setting> aggregate(const std::vector<Point>& points,
                               const std::optional<std::string>& volume) {
    std::map<SettingKey, Setting> settings;
    for (const Point& p : points) {
        if (volume && p.volume != *volume) {
            continue;
        }
        const SettingKey key{p.mode,
                             p.slices,
                             p.resolution,
                             p.sample_distance,
                             p.empty_space_skipping,
                             p.jitter,
                             p.refinement_steps};
        Setting& s = settings[key];
        s.key = key;
        ++s.count;
        s.psnr += p.psnr;
        s.ssim += p.ssim;
        s.psnr_truth += p.psnr_truth;
        s.ssim_truth += p.ssim_truth;
        s.frame_ms += p.frame_ms;
        s.worst_frame_ms = std::max(s.worst_frame_ms, p.frame_ms);
        s.light_buffer_ms += p.light_buffer_ms;
    }
    std::vector<Setting> result;
    for (auto& [key, s] : settings) {
        const double n = static_cast<double>(s.count);
        s.psnr /= n;
        s.ssim /= n;
        s.psnr_truth /= n;
        s.ssim_truth /= n;
        s.frame_ms /= n;
        s.light_buffer_ms /= n;
        result.push_back(s);
    }
    return result;
}

bool more_accurate(const Setting& a, const Setting& b) {
    if (a.psnr_truth != b.psnr_truth) {
        return a.psnr_truth > b.psnr_truth;
    }
    if (a.ssim_truth != b.ssim_truth) {
        return a.ssim_truth > b.ssim_truth;
    }
    return a.worst_frame_ms < b.worst_frame_ms;
}

std::vector<Setting> candidates(const std::vector<Point>& points) {
    std::set<std::pair<std::string, LightAngles>> views;
    for (const Point& p : points) {
        views.insert({p.volume, p.light});
    }
    const int complete = static_cast<int>(views.size());
    std::vector<Setting> result;
    for (const Setting& s : aggregate(points)) {
        if (s.count == complete && !s.key.jitter && s.key.refinement_steps == 0) {
            result.push_back(s);
        }
    }
    std::sort(result.begin(), result.end(), more_accurate);
    return result;
}

std::string Choice::describe(double budget_ms) const {
    const SettingKey& key = setting.key;
    char text[256];
    std::snprintf(text, sizeof text,
                  "budget %.0f ms: %s n=%d R=%d dt=1/%.0f%s, about %.0f ms, %.1f dB%s", budget_ms,
                  scene::to_string(key.mode), key.slices, key.resolution, 1.0 / key.sample_distance,
                  key.empty_space_skipping ? "" : " no skipping", estimated_ms, setting.psnr_truth,
                  fits ? "" : " (nothing measured fits; the fastest)");
    return text;
}

std::optional<Choice> choose(const Table& table, double budget_ms, int width, int height) {
    const std::vector<Setting> ranked = candidates(table.points);
    if (ranked.empty()) {
        return std::nullopt;
    }
    // Ray casting and slicing both scale with the pixel count; the light buffer does not, but a
    // cached frame does not build it.
    const double measured_pixels =
            static_cast<double>(std::max(1, table.width)) * std::max(1, table.height);
    const double scale = static_cast<double>(width) * height / measured_pixels;
    const Setting* fastest = &ranked.front();
    for (const Setting& s : ranked) {
        if (s.worst_frame_ms * scale <= budget_ms) {
            return Choice{s, s.worst_frame_ms * scale, true};
        }
        if (s.worst_frame_ms < fastest->worst_frame_ms) {
            fastest = &s;
        }
    }
    return Choice{*fastest, fastest->worst_frame_ms * scale, false};
}

scene::FrameRequest apply(scene::FrameRequest request, const SettingKey& setting) {
    scene::RenderSettings& s = request.settings;
    s.mode = setting.mode;
    if (setting.slices > 0) {
        s.light_buffer.slices = setting.slices;
    }
    if (setting.resolution > 0) {
        s.light_buffer.resolution = setting.resolution;
    }
    s.sample_distance = setting.sample_distance;
    s.empty_space_skipping = setting.empty_space_skipping;
    return request;
}

std::vector<Preset> choose_presets(const Table& table, const std::vector<double>& budgets) {
    std::vector<Preset> presets;
    for (const double budget : budgets) {
        const auto choice = choose(table, budget, table.width, table.height);
        presets.push_back(
                {budget, choice && choice->fits ? std::optional(choice->setting) : std::nullopt});
    }
    return presets;
}

// Six budgets from the fastest setting to the slowest reference, evenly spaced in log time and
// rounded up to two significant digits: past the reference's time the answer is always the
// reference, so budgets beyond it say nothing.
std::vector<double> default_budgets(const std::vector<Point>& points) {
    const std::vector<Setting> settings = aggregate(points);
    if (settings.empty()) {
        return {};
    }
    double low = infinity;
    double slowest = 0.0;
    double reference = 0.0;
    for (const Setting& s : settings) {
        if (s.key.jitter) {
            continue;  // never chosen
        }
        low = std::min(low, s.worst_frame_ms);
        slowest = std::max(slowest, s.worst_frame_ms);
        if (s.key.mode == scene::Mode::reference) {
            reference = std::max(reference, s.worst_frame_ms);
        }
    }
    double high = reference > 0.0 ? reference : slowest;
    high *= 1.05;
    low = std::max(low, 1e-3);
    std::vector<double> budgets;
    constexpr int count = 6;
    for (int i = 0; i < count; ++i) {
        const double t = static_cast<double>(i) / (count - 1);
        const double value = low * std::pow(high / low, t);
        const double magnitude = std::pow(10.0, std::floor(std::log10(value)) - 1.0);
        const double rounded = std::ceil(value / magnitude) * magnitude;
        if (budgets.empty() || rounded > budgets.back()) {
            budgets.push_back(rounded);
        }
    }
    return budgets;
}

}  // namespace penumbra::quality
