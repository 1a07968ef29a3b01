// The CPU's pre-integrated classification: a segment whose ends are equal (or within one cell of
// the GPU's table) is the per-sample classification to the bit, and a segment across a thin
// opaque range absorbs what the range holds whatever values its ends have.

#include <penumbra/optics/preintegration.hpp>
#include <penumbra/reference/volume_sampler.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra::reference {
namespace {

const scene::TransferFunction spike = {
        "spike",
        {{0.0, {0.2, 0.4, 1.0}}, {1.0, {1.0, 0.2, 0.1}}},
        {{0.0, 0.0}, {0.49, 0.0}, {0.495, 1.0}, {0.505, 1.0}, {0.51, 0.0}, {0.8, 0.0}, {1.0, 0.1}}};

TEST(SegmentClassifier, EqualEndsAreThePerSampleClassification) {
    const TransferFunctionTable tf(spike, {0.0, 1.0, false});
    for (const bool extinction : {false, true}) {
        const SegmentClassifier segments(tf, extinction);
        for (int i = 0; i <= 1000; ++i) {
            const double value = i / 1000.0;
            EXPECT_EQ(segments.classify(value, value), tf.classify(value)) << value;
        }
    }
}

TEST(SegmentClassifier, ASegmentAcrossAThinOpaqueRangeIsOpaqueInEitherDirection) {
    const TransferFunctionTable tf(spike, {0.0, 1.0, false});
    const SegmentClassifier alpha(tf, false);
    const SegmentClassifier extinction(tf, true);
    // Both ends transparent; the range 0.495..0.505 of opacity 1 is a tenth of the segment.
    for (const auto& [front, back] : {std::pair{0.45, 0.55}, std::pair{0.55, 0.45}}) {
        EXPECT_EQ(tf.classify(front).a, 0.0);
        // Alpha: about a tenth of the segment at optical depth 16.6 per unit (the filtered
        // table's range of opacity 1 is a little narrower, its ramps add a little).
        const double depth = -std::log(1.0 - alpha.classify(front, back).a);
        const double opaque_depth = -std::log(optics::min_unit_transmittance);
        EXPECT_GT(depth, 0.085 * opaque_depth);
        EXPECT_LT(depth, 0.12 * opaque_depth);
        // Extinction: the average of the TF's opacity over the segment: 0.0025 for each ramp,
        // 0.01 for the range, over 0.1.
        EXPECT_NEAR(extinction.classify(front, back).a, 0.15, 0.003);
        // Its colour is the range's, not the ends'.
        EXPECT_NEAR(alpha.classify(front, back).r, tf.classify(0.5).r, 0.02);
    }
}

}  // namespace
}  // namespace penumbra::reference
