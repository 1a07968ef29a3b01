#include <penumbra/optics/light_slicing.hpp>
#include <penumbra/optics/region.hpp>

#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
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

// Half-spaces that hold the whole box cut nothing and are left out: a crop box around the
// volume, or at its bounds exactly (the client's box when the crop is turned on), is no cut.
TEST(Region, LeavesOutWhatCutsNothing) {
    const TiltedVolume v;
    glm::dvec3 low(std::numeric_limits<double>::infinity());
    glm::dvec3 high(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& corner : box_corners(v.box)) {
        low = glm::min(low, v.placement.to_patient(corner));
        high = glm::max(high, v.placement.to_patient(corner));
    }
    scene::Cut cut;
    cut.crop = {true, low - 1.0, high + 1.0};
    EXPECT_EQ(region_of(v.box, cut, v.placement).count, 0);
    cut.crop = {true, low, high};
    EXPECT_EQ(region_of(v.box, cut, v.placement).count, 0) << "a box at the bounds";
    cut.crop.min.x = 0.5 * (low.x + high.x);
    const Region half = region_of(v.box, cut, v.placement);
    ASSERT_EQ(half.count, 1);
    EXPECT_EQ(half.light_count, 1);
    EXPECT_EQ(half.half_spaces[0].normal, glm::dvec3(1.0, 0.0, 0.0));
    // A plane beside the volume keeping all of it is left out; one keeping none of it stays.
    scene::Cut beside;
    beside.planes[0] = {true, high + 5.0, {0.0, 0.0, -1.0}};
    EXPECT_EQ(region_of(v.box, beside, v.placement).count, 0);
    beside.planes[0].normal = {0.0, 0.0, 1.0};
    EXPECT_EQ(region_of(v.box, beside, v.placement).count, 1);
}

// A random cut of the tilted volume: a crop box (on in most trials) and up to six planes through
// points near it, turned every way, the normal of any length.
scene::Cut random_cut(const TiltedVolume& v, std::mt19937& random, int trial) {
    std::uniform_real_distribution<double> millimetres(-150.0, 150.0);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    scene::Cut cut;
    cut.crop.enabled = trial % 5 != 4;
    for (int axis = 0; axis < 3; ++axis) {
        const double a = millimetres(random);
        const double b = millimetres(random);
        cut.crop.min[axis] = std::min(a, b);
        cut.crop.max[axis] = std::max(a, b) + 1e-3;
    }
    const int planes = trial % (scene::kMaxClipPlanes + 1);
    for (int i = 0; i < planes; ++i) {
        scene::ClipPlane& plane = cut.planes[static_cast<std::size_t>(i)];
        plane.enabled = true;
        plane.point =
                v.placement.centre +
                glm::dvec3(millimetres(random), millimetres(random), millimetres(random)) * 0.5;
        plane.normal = glm::dvec3(unit(random), unit(random), unit(random));
        if (glm::length(plane.normal) < 1e-3) {
            plane.normal = glm::dvec3(0.0, 0.0, 1.0);
        }
    }
    cut.casts_shadows = trial % 2 == 0;
    return cut;
}

// What the cut keeps, by its definition in patient space: inside the crop box (when on) and on
// the side of each plane (that is on) its normal points to.
bool kept_in_patient_space(const scene::Cut& cut, glm::dvec3 patient) {
    if (cut.crop.enabled) {
        for (int axis = 0; axis < 3; ++axis) {
            if (patient[axis] < cut.crop.min[axis] || patient[axis] > cut.crop.max[axis]) {
                return false;
            }
        }
    }
    for (const scene::ClipPlane& plane : cut.planes) {
        if (plane.enabled && glm::dot(plane.normal, patient - plane.point) < 0.0) {
            return false;
        }
    }
    return true;
}

// The distance in millimetres from `world` to the nearest face of the volume's box, the crop box
// or a plane.
double distance_to_a_face(const TiltedVolume& v, const scene::Cut& cut, glm::dvec3 world) {
    const glm::dvec3 patient = v.placement.to_patient(world);
    const glm::dvec3 in_box = v.box.to_box(world);
    double nearest = 1e30;
    for (int axis = 0; axis < 3; ++axis) {
        for (const double face : {v.box.min[axis], v.box.max[axis]}) {
            nearest = std::min(nearest,
                               std::abs(in_box[axis] - face) * v.placement.millimetres_per_unit);
        }
        for (const double face : {cut.crop.min[axis], cut.crop.max[axis]}) {
            nearest = std::min(nearest, std::abs(patient[axis] - face));
        }
    }
    for (const scene::ClipPlane& plane : cut.planes) {
        nearest = std::min(nearest,
                           std::abs(glm::dot(glm::normalize(plane.normal), patient - plane.point)));
    }
    return nearest;
}

// The region's point test against the cut's definition in patient space, away from the faces by
// a hair: random cuts, random points of world space around the box.
TEST(Region, ContainsWhatTheCutKeepsInPatientSpace) {
    const TiltedVolume v;
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int kept = 0;
    int removed = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const scene::Cut cut = random_cut(v, random, trial);
        const Region region = region_of(v.box, cut, v.placement);
        for (int i = 0; i < 200; ++i) {
            const glm::dvec3 world(0.7 * unit(random), 0.7 * unit(random), 0.7 * unit(random));
            const glm::dvec3 patient = v.placement.to_patient(world);
            // Skip points within a micrometre of a face, where rounding may decide.
            if (distance_to_a_face(v, cut, world) < 1e-3) {
                continue;
            }
            const bool expected = v.box.contains(world) && kept_in_patient_space(cut, patient);
            ASSERT_EQ(contains(region, world, RegionUser::camera), expected)
                    << "trial " << trial << " point " << i;
            ASSERT_EQ(contains(region, world, RegionUser::light),
                      cut.casts_shadows ? v.box.contains(world) : expected)
                    << "trial " << trial << " point " << i;
            (expected ? kept : removed) += 1;
        }
    }
    EXPECT_GT(kept, 200);
    EXPECT_GT(removed, 1000);
}

// The interval against a point test along the ray: every point strictly inside the interval is in
// the region and every point beyond it is not, for random crops and planes of the tilted volume
// and random rays, some starting inside.
TEST(Region, IntervalAgreesWithThePointTestOnRandomCutsAndRays) {
    const TiltedVolume v;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int hits = 0;
    int misses = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const scene::Cut cut = random_cut(v, random, trial);
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

// Where clip_to_half_spaces says a line lies deeper than d in the half-spaces, every point within
// d of it is in them (so a local lookup's stretch toward the light, no longer than d, needs no test
// of them); just outside that interval some point within d is not.
TEST(Region, ThePartDeeperThanADistanceHasItsNeighbourhoodInside) {
    const TiltedVolume v;
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int deep_points = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const scene::Cut cut = random_cut(v, random, trial);
        const Region region = region_of(v.box, cut, v.placement);
        const glm::dvec3 origin = glm::dvec3(unit(random), unit(random), unit(random)) * 0.5;
        const glm::dvec3 direction =
                glm::normalize(glm::dvec3(unit(random), unit(random), unit(random)));
        const double depth = 0.02 + 0.05 * std::abs(unit(random));
        const LineInterval deep =
                clip_to_half_spaces(region, region.count, origin, direction, {-10.0, 10.0}, depth);
        const auto in_half_spaces = [&](glm::dvec3 p) {
            for (int i = 0; i < region.count; ++i) {
                const HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
                if (glm::dot(h.normal, p) + h.offset < 0.0) {
                    return false;
                }
            }
            return true;
        };
        for (int i = 0; i <= 100; ++i) {
            const double t = -2.0 + 4.0 * i / 100.0;
            if (t < deep.t_near + 1e-9 || t > deep.t_far - 1e-9) {
                continue;
            }
            ++deep_points;
            const glm::dvec3 p = origin + t * direction;
            for (int k = 0; k < 20; ++k) {
                const glm::dvec3 offset =
                        glm::normalize(glm::dvec3(unit(random), unit(random), unit(random))) *
                        depth * std::abs(unit(random));
                ASSERT_TRUE(in_half_spaces(p + offset)) << "trial " << trial << " t " << t;
            }
        }
        // Just before the interval, a point at distance `depth` against the face that bounds it
        // leaves the half-spaces.
        if (region.count > 0 && deep.t_near < deep.t_far && deep.t_near > -10.0) {
            const glm::dvec3 p = origin + (deep.t_near - 1e-6) * direction;
            bool leaves = false;
            for (int i = 0; i < region.count; ++i) {
                const HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
                leaves = leaves || !in_half_spaces(p - depth * h.normal);
            }
            EXPECT_TRUE(leaves) << "trial " << trial;
        }
    }
    EXPECT_GT(deep_points, 500);
}

// A brick called outside holds no point of the region (random cuts, random bricks of the tilted
// volume's box, each sampled on a grid); a brick beyond one crop face is called outside.
TEST(Region, ABrickCalledOutsideHoldsNothingOfTheRegion) {
    const TiltedVolume v;
    std::mt19937 random(5);
    std::uniform_real_distribution<double> fraction(0.0, 1.0);
    int outside = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const scene::Cut cut = random_cut(v, random, trial);
        const Region region = region_of(v.box, cut, v.placement);
        const glm::dvec3 size = v.box.size();
        const glm::dvec3 low =
                v.box.min + size * glm::dvec3(fraction(random), fraction(random), fraction(random));
        const glm::dvec3 high = glm::min(low + 0.1 * size, v.box.max);
        for (const RegionUser user : {RegionUser::camera, RegionUser::light}) {
            if (!outside_region(region, low, high, user)) {
                continue;
            }
            ++outside;
            for (int i = 0; i <= 6; ++i) {
                for (int j = 0; j <= 6; ++j) {
                    for (int k = 0; k <= 6; ++k) {
                        const glm::dvec3 at = low + (high - low) * glm::dvec3(i, j, k) / 6.0;
                        ASSERT_FALSE(contains(region, v.box.to_world(at), user))
                                << "trial " << trial;
                    }
                }
            }
        }
    }
    EXPECT_GT(outside, 50);

    scene::Cut right_half;
    right_half.crop = {true, v.placement.to_patient(glm::dvec3(0.0, -1.0, -1.0)),
                       v.placement.to_patient(glm::dvec3(1.0))};
    const Region region = region_of(v.box, right_half, v.placement);
    // World x < 0 is box x > 0 for the first index axis, which is reversed and turned 30 degrees:
    // take a thin brick at the box's far end along that axis, wholly at world x < 0.
    const glm::dvec3 low(v.box.max.x - 0.05, -0.05, -0.05);
    const glm::dvec3 high(v.box.max.x, 0.05, 0.05);
    ASSERT_LT(v.box.to_world(low).x, 0.0);
    EXPECT_TRUE(outside_region(region, low, high, RegionUser::camera));
    right_half.casts_shadows = true;
    EXPECT_FALSE(outside_region(region_of(v.box, right_half, v.placement), low, high,
                                RegionUser::light));
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
