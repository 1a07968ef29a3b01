// Volumes whose boxes are degenerate for slicing, sampling and gradients: one voxel thick along
// each axis, a one-voxel needle, a single voxel, 2x2x2, and strongly anisotropic spacings (a
// needle and a pancake). Every mode, lit along the thin axis, across it and from a generic
// direction; the checks of stability.hpp, including the CPU reference where it applies.

#include "stability.hpp"

#include <glm/geometric.hpp>

#include <functional>
#include <string>
#include <vector>

namespace penumbra::stability {
namespace {

struct DegenerateCase {
    std::string name;
    glm::uvec3 dims;
    glm::dvec3 spacing;
    glm::dvec3 thin_axis;  // the box's shortest side
    double min_visible_fraction;
    int size = 16;          // image side
    double distance = 2.4;  // of the camera from the centre
    std::function<float(glm::dvec3)> value = radial;
    bool opaque = false;  // the opaque TF instead of the soft one
};

class DegenerateVolumeTest : public ModeTest {
protected:
    void check_case(const DegenerateCase& c) {
        SCOPED_TRACE(c.name);
        use(float_volume(c.dims, c.spacing, c.value));
        const glm::dvec3 across = std::abs(c.thin_axis.x) > 0.5 ? glm::dvec3(0.0, 1.0, 0.0)
                                                                : glm::dvec3(1.0, 0.0, 0.0);
        for (const glm::dvec3 light :
             {scene::direction_from_angles(-60.0, 35.0), c.thin_axis, -c.thin_axis, across}) {
            auto request = base_request(mode(), c.size);
            request.camera = scene::orbit_camera(30.0, 20.0, c.distance);
            request.light.direction = light;
            if (c.opaque) {
                request.transfer_function = opaque_tf();
            }
            CheckOptions options;
            options.min_visible_fraction = c.min_visible_fraction;
            if (c.opaque && mode() == scene::Mode::half_angle) {
                // Slice planes 1/24 apart meet a box 1/1000 thick in slivers, which rasterise
                // to no fragments: half-angle slicing cannot see it (the ray casters sample every
                // ray's own segment at least once).
                options.min_visible_fraction = 0.0;
            }
            render_and_check(request, options);
            request.settings.phong = true;
            request.settings.light_buffer.builder = scene::LightBufferBuilder::per_slice;
            render_and_check(request, options);
        }
    }
};

TEST_F(DegenerateVolumeTest, OneVoxelThickVolumesRenderSanely) {
    for_each_mode(all_modes, [&] {
        check_case({"thin z", {16, 16, 1}, glm::dvec3(1.0), {0.0, 0.0, 1.0}, 0.05});
        check_case({"thin y", {16, 1, 16}, glm::dvec3(1.0), {0.0, 1.0, 0.0}, 0.05});
        check_case({"thin x", {1, 16, 16}, glm::dvec3(1.0), {1.0, 0.0, 0.0}, 0.05});
    });
}

TEST_F(DegenerateVolumeTest, OneVoxelNeedleRendersSanely) {
    for_each_mode(all_modes, [&] {
        // A needle 1/24 wide: a closer camera and 32 pixels make it about two pixels wide.
        check_case({"needle 1x1x24", {1, 1, 24}, glm::dvec3(1.0), {1.0, 0.0, 0.0}, 0.01, 32, 1.5});
    });
}

TEST_F(DegenerateVolumeTest, TwoVoxelCubeRendersSanely) {
    for_each_mode(all_modes, [&] {
        // Radial would give all 8 voxels one value; a ramp gives 8 different ones.
        const auto ramp = [](glm::dvec3 p) {
            return static_cast<float>(p.x + 2.0 * p.y + 4.0 * p.z);
        };
        check_case({"2x2x2", {2, 2, 2}, glm::dvec3(1.0), {0.0, 0.0, 1.0}, 0.05, 16, 2.4, ramp});
    });
}

// Radial plus a ramp along every axis, so the gradient never vanishes. A volume symmetric about
// the centre has a zero gradient along the thin axis exactly where thin boxes are sampled (a
// ray's one sample is the midpoint of its segment, on the mid-plane), and radial alone is flat
// beyond its sphere; in both places the normal of a 1/1000-thick box is decided by the last bits
// of the sample position (or by the no-normal threshold), and GPU and CPU legitimately disagree.
float tilted(glm::dvec3 p) {
    return static_cast<float>(0.5 * radial(p) + 0.5 * (p.x + p.y + p.z) / 3.0);
}

TEST_F(DegenerateVolumeTest, StronglyAnisotropicSpacingRendersSanely) {
    for_each_mode(all_modes, [&] {
        check_case({"needle spacing 1:1:20",
                    {16, 16, 16},
                    {1.0, 1.0, 20.0},
                    {1.0, 0.0, 0.0},
                    0.01,
                    32,
                    1.5,
                    tilted});
        check_case({"pancake spacing 1:1:0.05",
                    {16, 16, 16},
                    {1.0, 1.0, 0.05},
                    {0.0, 0.0, 1.0},
                    0.05,
                    16,
                    2.4,
                    tilted});
        // 1/1000 thick: only an opaque TF shows so thin a layer clearly.
        check_case({"pancake spacing 1:1000",
                    {16, 16, 8},
                    {1.0, 1.0, 0.001},
                    {0.0, 0.0, 1.0},
                    0.1,
                    16,
                    2.4,
                    tilted,
                    true});
        check_case({"pancake spacing 1:10000",
                    {16, 16, 8},
                    {1.0, 1.0, 0.0001},
                    {0.0, 0.0, 1.0},
                    0.1,
                    16,
                    2.4,
                    tilted,
                    true});
        check_case({"slab dims 32x32x2",
                    {32, 32, 2},
                    {0.5, 0.5, 3.0},
                    {0.0, 0.0, 1.0},
                    0.05,
                    16,
                    2.4,
                    tilted});
    });
}

// A single voxel is a constant volume: every sample classifies as value 0. A TF hiding 0 shows
// exactly the background; one showing 0 fills the box.
TEST_F(DegenerateVolumeTest, SingleVoxelVolumeIsConstant) {
    for_each_mode(all_modes, [&] {
        use(float_volume(glm::uvec3(1), glm::dvec3(1.0), [](glm::dvec3) { return 42.0f; }));
        ASSERT_EQ(volume_->range.min, volume_->range.max);
        for (const glm::dvec3 light : {scene::direction_from_angles(-60.0, 35.0),
                                       glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(1.0, 1.0, 1.0)}) {
            auto request = base_request(mode(), 16);
            request.light.direction = light;
            CheckOptions hidden;
            hidden.expect_background = true;
            render_and_check(request, hidden);
            request.transfer_function = visible_at_zero();
            CheckOptions shown;
            shown.min_visible_fraction = 0.2;
            render_and_check(request, shown);
        }
    });
}

}  // namespace
}  // namespace penumbra::stability
