#include <penumbra/optics/region.hpp>

#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include <random>

namespace penumbra::optics {
namespace {

// A volume of 90 x 60 x 30 voxels of 2 x 2 x 4 mm (extent 180 x 120 x 120 mm), its index axes
// turned 30 degrees about the z axis and i reversed (a reflection), voxel (0, 0, 0) at `origin`.
struct TiltedVolume {
    glm::dvec3 dims{90.0, 60.0, 30.0};
    glm::dvec3 spacing{2.0, 2.0, 4.0};
    glm::dvec3 origin{-40.0, 25.0, -70.0};
    glm::dmat3 axes = glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(30.0),
                                             glm::dvec3(0.0, 0.0, 1.0))) *
                      glm::dmat3(glm::dvec3(-1.0, 0.0, 0.0), glm::dvec3(0.0, 1.0, 0.0),
                                 glm::dvec3(0.0, 0.0, 1.0));
    scene::Box box = scene::box_for_extent(dims * spacing, axes);
    scene::PatientPlacement placement = scene::patient_placement(origin, axes, spacing, dims);

    // Where the centre of voxel `index` lies in patient space, as volume::Volume defines it.
    [[nodiscard]] glm::dvec3 patient_of(glm::dvec3 index) const {
        return origin + axes * (spacing * index);
    }

    // Where it lies in world space, as the shaders sample it: box space spans the voxels' outer
    // faces, the voxel's centre half a voxel in.
    [[nodiscard]] glm::dvec3 world_of(glm::dvec3 index) const {
        return box.to_world(box.min + (index + 0.5) / dims * box.size());
    }
};

TEST(PatientPlacement, PutsEveryVoxelWhereTheBoxSamplesIt) {
    const TiltedVolume v;
    for (const glm::dvec3 index : {glm::dvec3(0.0), glm::dvec3(89.0, 59.0, 29.0),
                                   glm::dvec3(10.0, 50.0, 3.0), glm::dvec3(44.5, 29.5, 14.5)}) {
        const glm::dvec3 world = v.placement.to_world(v.patient_of(index));
        const glm::dvec3 expected = v.world_of(index);
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_NEAR(world[axis], expected[axis], 1e-12)
                    << "voxel " << index[0] << "," << index[1] << "," << index[2];
        }
        const glm::dvec3 back = v.placement.to_patient(world);
        EXPECT_NEAR(glm::distance(back, v.patient_of(index)), 0.0, 1e-9);
    }
    EXPECT_DOUBLE_EQ(v.placement.millimetres_per_unit, 180.0);
}

TEST(Region, WithoutACutIsTheBoxForEveryUser) {
    const TiltedVolume v;
    const Region region = region_of(v.box, scene::Cut{}, v.placement);
    EXPECT_EQ(region.count, 0);
    const glm::dvec3 origin(0.1, -2.0, 0.05);
    const glm::dvec3 direction = glm::normalize(glm::dvec3(0.05, 1.0, -0.02));
    const BoxHit box = intersect_box(origin, direction, v.box);
    for (const RegionUser user : {RegionUser::camera, RegionUser::light}) {
        const BoxHit hit = intersect_region(region, origin, direction, user);
        EXPECT_EQ(hit.hit, box.hit);
        EXPECT_EQ(hit.t_near, box.t_near);
        EXPECT_EQ(hit.t_far, box.t_far);
    }
}

// The interval against a point test along the ray: every point strictly inside the interval is in
// the region and every point beyond it is not, for random crops of the tilted volume and random
// rays, some starting inside.
TEST(Region, IntervalAgreesWithThePointTestOnRandomCropsAndRays) {
    const TiltedVolume v;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> millimetres(-150.0, 150.0);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int hits = 0;
    int misses = 0;
    for (int trial = 0; trial < 400; ++trial) {
        scene::Cut cut;
        cut.crop.enabled = true;
        for (int axis = 0; axis < 3; ++axis) {
            const double a = millimetres(random);
            const double b = millimetres(random);
            cut.crop.min[axis] = std::min(a, b);
            cut.crop.max[axis] = std::max(a, b) + 1e-3;
        }
        cut.casts_shadows = trial % 2 == 0;
        const Region region = region_of(v.box, cut, v.placement);
        const glm::dvec3 origin =
                glm::dvec3(unit(random), unit(random), unit(random)) * (trial % 3 == 0 ? 0.3 : 1.5);
        const glm::dvec3 direction =
                glm::normalize(glm::dvec3(unit(random), unit(random), unit(random)));
        for (const RegionUser user : {RegionUser::camera, RegionUser::light}) {
            const BoxHit hit = intersect_region(region, origin, direction, user);
            (hit.hit ? hits : misses) += 1;
            for (int i = 0; i <= 400; ++i) {
                const double t = 3.0 * i / 400.0;
                const bool inside = contains(region, origin + t * direction, user);
                const bool within = hit.hit && t > hit.t_near + 1e-9 && t < hit.t_far - 1e-9;
                const bool beyond = !hit.hit || t < hit.t_near - 1e-9 || t > hit.t_far + 1e-9;
                if (within) {
                    ASSERT_TRUE(inside) << "trial " << trial << " t " << t;
                }
                if (beyond) {
                    ASSERT_FALSE(inside) << "trial " << trial << " t " << t;
                }
            }
        }
    }
    // Both kinds of ray were tried.
    EXPECT_GT(hits, 50);
    EXPECT_GT(misses, 50);
}

TEST(Region, CutTissueThatCastsShadowsIsStillThereForTheLight) {
    const TiltedVolume v;
    scene::Cut cut;
    cut.crop.enabled = true;
    cut.crop.min = v.placement.centre - glm::dvec3(10.0);
    cut.crop.max = v.placement.centre + glm::dvec3(10.0);
    const glm::dvec3 outside_crop(0.3, 0.0, 0.0);  // 54 mm from the centre, inside the box
    for (const bool casts : {false, true}) {
        cut.casts_shadows = casts;
        const Region region = region_of(v.box, cut, v.placement);
        EXPECT_TRUE(contains(region, glm::dvec3(0.0), RegionUser::camera));
        EXPECT_FALSE(contains(region, outside_crop, RegionUser::camera));
        EXPECT_EQ(contains(region, outside_crop, RegionUser::light), casts);
    }
}

TEST(Region, ARayAlongACropFaceIsInsideOnItsInnerSideOnly) {
    const TiltedVolume v;
    scene::Cut cut;
    cut.crop.enabled = true;
    cut.crop.min = v.placement.to_patient(glm::dvec3(-0.1, -1.0, -1.0));
    cut.crop.max = v.placement.to_patient(glm::dvec3(0.1, 1.0, 1.0));
    const Region region = region_of(v.box, cut, v.placement);
    const glm::dvec3 along_y(0.0, 1.0, 0.0);
    EXPECT_TRUE(intersect_region(region, {0.05, -2.0, 0.0}, along_y, RegionUser::camera).hit);
    EXPECT_FALSE(intersect_region(region, {0.15, -2.0, 0.0}, along_y, RegionUser::camera).hit);
    EXPECT_FALSE(intersect_region(region, {-0.15, -2.0, 0.0}, along_y, RegionUser::camera).hit);
}

TEST(Region, ACropBoxBesideTheVolumeLeavesNothing) {
    const TiltedVolume v;
    scene::Cut cut;
    cut.crop.enabled = true;
    cut.crop.min = v.placement.centre + glm::dvec3(500.0);
    cut.crop.max = v.placement.centre + glm::dvec3(600.0);
    const Region region = region_of(v.box, cut, v.placement);
    for (const glm::dvec3 direction : {glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(1.0, 1.0, 1.0)}) {
        EXPECT_FALSE(intersect_region(region, glm::dvec3(-3.0), glm::normalize(direction),
                                      RegionUser::camera)
                             .hit);
    }
    EXPECT_FALSE(contains(region, glm::dvec3(0.0), RegionUser::camera));
}

TEST(Region, ACropThinnerThanAVoxelStillHasItsSlab) {
    const TiltedVolume v;
    scene::Cut cut;
    cut.crop.enabled = true;
    cut.crop.min = v.placement.centre - glm::dvec3(100.0, 100.0, 0.25);
    cut.crop.max = v.placement.centre + glm::dvec3(100.0, 100.0, 0.25);
    const Region region = region_of(v.box, cut, v.placement);
    const BoxHit hit =
            intersect_region(region, {0.0, 0.0, -2.0}, {0.0, 0.0, 1.0}, RegionUser::camera);
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t_far - hit.t_near, 0.5 / 180.0, 1e-12);
}

}  // namespace
}  // namespace penumbra::optics
