#pragma once

// The emission–absorption formulas, written once for the CPU reference and the tests and mirrored
// line for line by shaders/include/compositing.glsl.

#include <penumbra/scene/frame_request.hpp>

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cmath>

namespace penumbra::optics {

// Opacity correction: a TF opacity `alpha` that holds for a step of `unit_distance` becomes
// 1 - (1 - alpha)^(step / unit_distance) for a step of length `step`.
template <class T>
T corrected_opacity(T alpha, T step, T unit_distance) {
    return T(1) - std::pow(T(1) - glm::clamp(alpha, T(0), T(1)), step / unit_distance);
}

// Extinction compositing (paper eq. 6): the TF opacity is read as an extinction coefficient
// tau = alpha / unit_distance, and the segment transmits exp(-tau * step).
template <class T>
T extinction_opacity(T alpha, T step, T unit_distance) {
    return T(1) - std::exp(-glm::clamp(alpha, T(0), T(1)) / unit_distance * step);
}

// A sample's opacity over a step of length `step` as the frame composites it (the compositing
// and opacity unit distance of `settings`): sample_opacity in shaders/include/compositing.glsl.
inline double sample_opacity(double alpha, double step, const scene::RenderSettings& settings) {
    return settings.compositing == scene::Compositing::extinction
                   ? extinction_opacity(alpha, step, settings.opacity_unit_distance)
                   : corrected_opacity(alpha, step, settings.opacity_unit_distance);
}

// Front-to-back "over": accumulated premultiplied colour/opacity `dst` receives a sample of
// colour `color` (not premultiplied) and opacity `alpha` behind it (paper eq. 3).
template <class T>
void composite_front_to_back(glm::vec<4, T>& dst, glm::vec<3, T> color, T alpha) {
    const T weight = (T(1) - dst.a) * alpha;
    dst.r += weight * color.r;
    dst.g += weight * color.g;
    dst.b += weight * color.b;
    dst.a += weight;
}

}  // namespace penumbra::optics
