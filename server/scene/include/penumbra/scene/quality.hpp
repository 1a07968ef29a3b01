#pragma once

#include <penumbra/scene/frame_request.hpp>

#include <optional>
#include <string>
#include <vector>

namespace penumbra::scene {

// One measured point of `penumbra bench accuracy` (docs/accuracy/*.json): a setting, what a frame
// cost at the measured image size, and how close it came to the reference.
struct QualitySample {
    Mode mode = Mode::dvr;
    int slices = 0;        // 0 where the mode has none
    int resolution = 0;
    double sample_distance = 1.0 / 256.0;
    double frame_ms = 0.0;
    double psnr = 0.0;     // dB; +inf for the reference itself
    int width = 256;       // the image size the time was measured at
    int height = 256;
};

struct QualityChoice {
    Mode mode = Mode::dvr;
    int slices = 0;
    int resolution = 0;
    double sample_distance = 1.0 / 256.0;
    double estimated_ms = 0.0;  // the measured time scaled to the requested image size
    double psnr = 0.0;
    bool fits = true;           // false: nothing fits, this is the fastest setting measured

    [[nodiscard]] std::string describe(double budget_ms) const;
};

// The most accurate measured setting (mean PSNR over the volumes and lights it was measured on)
// whose slowest frame, scaled by pixel count to width x height, fits `budget_ms`; when none
// fits, the fastest. Nothing when the table is empty.
std::optional<QualityChoice> choose_quality(const std::vector<QualitySample>& table,
                                            double budget_ms, int width, int height);

// The request with the chosen setting applied (mode, slices, resolution, sample distance).
FrameRequest apply_quality(FrameRequest request, const QualityChoice& choice);

}  // namespace penumbra::scene
