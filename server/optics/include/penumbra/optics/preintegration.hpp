#pragma once

// Pre-integrated classification (Engel, Kraus & Ertl 2001), written once for the CPU reference and
// the tests and mirrored by shaders/include/preintegration.glsl (which says what it neglects):
// a segment between two samples is a homogeneous sample of the segment's average optical depth.

#include <algorithm>
#include <cmath>

namespace penumbra::optics {

// Entries per side of the GPU's table over (front, back) value, i / (side - 1): 4 MiB of RGBA32F.
// Against the CPU's exact integral, on a spike of opacity 1 whose ramps span 5 of the TF's 1024
// entries, rays that graze it differ by up to 0.16 at 512 and 0.06 at 1024 (a few pixels of
// 48 x 48; everywhere else within 8-bit rounding); a TF whose ramps span tens of entries (bone,
// skin) agrees within 3 levels at 512 (preintegration_test).
inline constexpr int preintegration_table_side = 512;

// An opacity of 1 keeps a finite optical depth (16.6 per opacity unit distance), so averages stay
// finite and an opaque TF entry stays opaque to a float.
inline constexpr double min_unit_transmittance = 5.9604644775390625e-8;  // 2^-24

// The TF opacity as an optical depth per opacity unit distance, read the way sample_opacity reads
// it: alpha compositing -ln(1 - a), extinction compositing a.
template <class T>
T optical_depth_of_opacity(T alpha, bool extinction) {
    const T a = alpha < T(0) ? T(0) : (alpha > T(1) ? T(1) : alpha);
    if (extinction) {
        return a;
    }
    const T transmittance = T(1) - a;
    return -std::log(transmittance > T(min_unit_transmittance) ? transmittance
                                                               : T(min_unit_transmittance));
}

// The TF opacity of a sample of optical depth `depth`: optical_depth_of_opacity's inverse.
template <class T>
T opacity_of_optical_depth(T depth, bool extinction) {
    return extinction ? depth : T(1) - std::exp(-depth);
}

// How much of a segment's classification comes from the table, the rest from the TF at its
// middle: within one cell of the table its bilinear filter would blur the TF to the table's
// resolution, so the middle's share grows from none one cell away to all of it at front == back,
// which is then exactly the per-sample classification. Continuous, so that no segment changes
// abruptly with the rounding of its values.
inline double table_weight(double front, double back) {
    return std::min(1.0, std::abs(back - front) * (preintegration_table_side - 1));
}

}  // namespace penumbra::optics
