// The tricubic B-spline of the CPU reference: exact on linear fields and on the gradient of
// quadratic ones, the known offset of its value on a quadratic, the (1 4 1)/6 smoothing at voxel
// centres, and continuity of its value, gradient and second derivative across voxel faces.

#include <penumbra/reference/volume_sampler.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

namespace penumbra::reference {
namespace {

constexpr glm::uvec3 kDims{9, 8, 10};
constexpr glm::dvec3 kSpacing{1.0, 1.0, 2.5};  // thick slices along z

using Field = std::function<double(glm::dvec3)>;  // of the continuous voxel index

volume::Volume volume_of(const Field& field) {
    std::vector<float> values;
    for (unsigned z = 0; z < kDims.z; ++z) {
        for (unsigned y = 0; y < kDims.y; ++y) {
            for (unsigned x = 0; x < kDims.x; ++x) {
                values.push_back(static_cast<float>(field({x, y, z})));
            }
        }
    }
    auto made = volume::make_volume("field", kDims, kSpacing, values);
    EXPECT_TRUE(made.ok());
    return std::move(made.value());
}

// The world point of continuous voxel index `index` (voxel i's centre at i).
glm::dvec3 world_at(const VolumeSampler& sampler, glm::dvec3 index) {
    const scene::Box& box = sampler.box();
    return box.to_world(box.min + (index + 0.5) * sampler.voxel_size());
}

// Points whose 4 x 4 x 4 voxels all lie inside (no clamped border voxel).
std::vector<glm::dvec3> interior_points() {
    std::mt19937 random(7);
    std::vector<glm::dvec3> points;
    for (int n = 0; n < 50; ++n) {
        glm::dvec3 p;
        for (int axis = 0; axis < 3; ++axis) {
            std::uniform_real_distribution<double> along(1.0, kDims[axis] - 2.0 - 1e-9);
            p[axis] = along(random);
        }
        points.push_back(p);
    }
    return points;
}

struct Normalised {
    double min = 0.0;
    double width = 1.0;
};

Normalised normalisation(const volume::Volume& volume) {
    return {volume.range.min, volume.range.max - volume.range.min};
}

TEST(VolumeSamplerTricubic, ReproducesALinearFieldAndItsGradient) {
    const auto linear = [](glm::dvec3 i) { return 2.0 * i.x - i.y + 0.5 * i.z + 100.0; };
    const volume::Volume volume = volume_of(linear);
    const Normalised n = normalisation(volume);
    const VolumeSampler sampler(volume, scene::Reconstruction::tricubic);
    const glm::dvec3 gradient = glm::dvec3(2.0, -1.0, 0.5) / sampler.voxel_size() / n.width;
    for (const glm::dvec3& p : interior_points()) {
        const glm::dvec3 world = world_at(sampler, p);
        EXPECT_NEAR(sampler.value(world), (linear(p) - n.min) / n.width, 1e-9);
        const glm::dvec3 g = sampler.gradient(world);
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_NEAR(g[axis], gradient[axis], 1e-9 * std::abs(gradient.x));
        }
    }
}

// The B-spline of x^2 sampled at the integers is x^2 + 1/3 (h = 1 voxel): the value is offset,
// the derivative 2x is exact.
TEST(VolumeSamplerTricubic, ValueOfAQuadraticIsOffsetByAThirdOfAVoxelSquaredItsGradientIsExact) {
    const auto quadratic = [](glm::dvec3 i) { return i.x * i.x + 2.0 * i.y * i.y - i.z * i.z; };
    const volume::Volume volume = volume_of(quadratic);
    const Normalised n = normalisation(volume);
    const VolumeSampler sampler(volume, scene::Reconstruction::tricubic);
    for (const glm::dvec3& p : interior_points()) {
        const glm::dvec3 world = world_at(sampler, p);
        const double offset = (1.0 + 2.0 - 1.0) / 3.0;
        EXPECT_NEAR(sampler.value(world), (quadratic(p) + offset - n.min) / n.width, 1e-9);
        const glm::dvec3 exact =
                glm::dvec3(2.0 * p.x, 4.0 * p.y, -2.0 * p.z) / sampler.voxel_size() / n.width;
        const glm::dvec3 g = sampler.gradient(world);
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_NEAR(g[axis], exact[axis], 1e-9);
        }
    }
}

volume::Volume random_volume() {
    std::mt19937 random(11);
    std::uniform_real_distribution<double> value(0.0, 1.0);
    return volume_of([&](glm::dvec3) { return value(random); });
}

// At a voxel centre each axis weighs the voxel and its two neighbours 1/6, 4/6, 1/6; the
// trilinear filter passes through the voxel.
TEST(VolumeSamplerTricubic, SmoothsVoxelCentresByOneFourOneOverSix) {
    const volume::Volume volume = random_volume();
    const Normalised n = normalisation(volume);
    const VolumeSampler sampler(volume, scene::Reconstruction::tricubic);
    const VolumeSampler trilinear(volume);
    const glm::ivec3 c{4, 3, 5};
    const auto voxel = [&](glm::ivec3 i) {
        return (volume.value(i.x, i.y, i.z) - n.min) / n.width;
    };
    const double w[3] = {1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0};
    double expected = 0.0;
    for (int z = -1; z <= 1; ++z) {
        for (int y = -1; y <= 1; ++y) {
            for (int x = -1; x <= 1; ++x) {
                expected += w[x + 1] * w[y + 1] * w[z + 1] * voxel(c + glm::ivec3(x, y, z));
            }
        }
    }
    const glm::dvec3 world = world_at(sampler, glm::dvec3(c));
    EXPECT_NEAR(sampler.value(world), expected, 1e-12);
    EXPECT_NEAR(trilinear.value(world), voxel(c), 1e-12);
}

// Either side of the face between two voxels' cells (where the weights change polynomial) the
// value, the gradient and the second derivative along the crossing axis meet: C2.
TEST(VolumeSamplerTricubic, IsTwiceContinuouslyDifferentiableAcrossVoxelFaces) {
    const volume::Volume volume = random_volume();
    const VolumeSampler sampler(volume, scene::Reconstruction::tricubic);
    const VolumeSampler trilinear(volume);
    constexpr double e = 1e-5;
    double trilinear_jump = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        for (const double face : {0.0, 3.0, kDims[axis] - 1.0}) {  // borders included
            glm::dvec3 p{4.3, 3.6, 5.2};
            p[axis] = face;
            glm::dvec3 step(0.0);
            step[axis] = e;
            const auto at = [&](double k) { return world_at(sampler, p + k * step); };
            SCOPED_TRACE(testing::Message() << "axis " << axis << " face " << face);
            // The value changes across the face as its gradient there says, to second order.
            const double predicted = glm::dot(sampler.gradient(at(0)), at(1) - at(-1));
            EXPECT_NEAR(sampler.value(at(1)) - sampler.value(at(-1)), predicted, 1e-7);
            const glm::dvec3 below = sampler.gradient(at(-1));
            const glm::dvec3 above = sampler.gradient(at(1));
            const double scale = glm::length(sampler.gradient(at(0))) + 1.0;
            EXPECT_LE(glm::length(above - below), 1e-3 * scale);
            // One-sided second derivatives along the axis.
            const double second_below =
                    (sampler.gradient(at(-1))[axis] - sampler.gradient(at(-3))[axis]) / (2 * e);
            const double second_above =
                    (sampler.gradient(at(3))[axis] - sampler.gradient(at(1))[axis]) / (2 * e);
            EXPECT_NEAR(second_below, second_above, 1e-2 * (std::abs(second_below) + 1.0));
            if (face > 0.0 && face < kDims[axis] - 1.0) {
                const double d_below =
                        (trilinear.value(at(-1)) - trilinear.value(at(-3))) / (2 * e);
                const double d_above = (trilinear.value(at(3)) - trilinear.value(at(1))) / (2 * e);
                trilinear_jump = std::max(trilinear_jump, std::abs(d_above - d_below));
            }
        }
    }
    // The trilinear filter's own derivative jumps at those faces: the test can tell.
    EXPECT_GT(trilinear_jump, 1e-2);
}

// A sampler that reads the volume in place (a pick's) gives what one that copies it gives, in
// both reconstructions, inside and at the clamped border.
TEST(VolumeSamplerReading, InPlaceMatchesCopied) {
    const volume::Volume volume =
            volume_of([](glm::dvec3 i) { return std::sin(i.x) * 40.0 + i.y * i.z - 7.0; });
    for (const auto reconstruction :
         {scene::Reconstruction::trilinear, scene::Reconstruction::tricubic}) {
        const VolumeSampler copied(volume, reconstruction, VolumeSampler::Reading::copied);
        const VolumeSampler in_place(volume, reconstruction, VolumeSampler::Reading::in_place);
        std::vector<glm::dvec3> points = interior_points();
        points.push_back({-0.5, -0.5, -0.5});
        points.push_back(glm::dvec3(kDims) - 0.5);
        for (const glm::dvec3 p : points) {
            const glm::dvec3 world = world_at(copied, p);
            EXPECT_EQ(in_place.value(world), copied.value(world));
            EXPECT_EQ(in_place.gradient(world), copied.gradient(world));
        }
    }
}

}  // namespace
}  // namespace penumbra::reference
