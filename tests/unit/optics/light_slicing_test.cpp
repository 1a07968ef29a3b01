#include <penumbra/optics/light_slicing.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace penumbra::optics {
namespace {

constexpr double kEps = 1e-9;
constexpr std::uint32_t kSeed = 20240611u;
constexpr int kRandomDirections = 200;

const scene::Box unit_box{glm::dvec3(-0.5), glm::dvec3(0.5)};

std::string describe(glm::dvec3 v) {
    std::ostringstream out;
    out << std::setprecision(17) << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}

struct NamedDirection {
    std::string name;
    glm::dvec3 direction;
};

// Unit directions along the axes, face diagonals and main diagonals (both signs), then
// kRandomDirections uniformly distributed ones from a fixed seed.
std::vector<NamedDirection> test_directions() {
    std::vector<NamedDirection> out = {
            {"axis +x", {1.0, 0.0, 0.0}},
            {"axis -y", {0.0, -1.0, 0.0}},
            {"axis +z", {0.0, 0.0, 1.0}},
            {"axis -z", {0.0, 0.0, -1.0}},
            {"face diagonal xy", glm::normalize(glm::dvec3(1.0, 1.0, 0.0))},
            {"face diagonal -yz", glm::normalize(glm::dvec3(0.0, -1.0, 1.0))},
            {"face diagonal x-z", glm::normalize(glm::dvec3(1.0, 0.0, -1.0))},
            {"main diagonal", glm::normalize(glm::dvec3(1.0, 1.0, 1.0))},
            {"main diagonal -x+y-z", glm::normalize(glm::dvec3(-1.0, 1.0, -1.0))},
    };
    std::mt19937 rng(kSeed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (int i = 0; i < kRandomDirections; ++i) {
        glm::dvec3 v(0.0);
        while (glm::length(v) < 1e-3) {
            v = {gauss(rng), gauss(rng), gauss(rng)};
        }
        out.push_back({"random #" + std::to_string(i) + " of seed " + std::to_string(kSeed),
                       glm::normalize(v)});
    }
    for (auto& d : out) {
        d.name += " " + describe(d.direction);
    }
    return out;
}

struct NamedBox {
    std::string name;
    scene::Box box;
};

std::vector<NamedBox> test_boxes() {
    return {
            {"unit cube", unit_box},
            {"box_for_extent(181, 217, 181)", scene::box_for_extent({181.0, 217.0, 181.0})},
            {"box_for_extent(1, 0.25, 0.02)", scene::box_for_extent({1.0, 0.25, 0.02})},
            {"off-centre box", scene::Box{{1.0, -2.0, 3.0}, {1.5, 0.5, 3.2}}},
    };
}

glm::dvec3 centre_of(const scene::Box& box) {
    return 0.5 * (box.min + box.max);
}

// min and max of L·V over the box, computed per axis rather than from the corners.
double min_projection(const scene::Box& box, glm::dvec3 l) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
        sum += std::min(l[i] * box.min[i], l[i] * box.max[i]);
    }
    return sum;
}

double max_projection(const scene::Box& box, glm::dvec3 l) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
        sum += std::max(l[i] * box.min[i], l[i] * box.max[i]);
    }
    return sum;
}

// The corner with the smallest (or largest) L·V.
glm::dvec3 nearest_corner(const scene::Box& box, glm::dvec3 l) {
    glm::dvec3 c;
    for (int i = 0; i < 3; ++i) {
        c[i] = l[i] >= 0.0 ? box.min[i] : box.max[i];
    }
    return c;
}

glm::dvec3 farthest_corner(const scene::Box& box, glm::dvec3 l) {
    glm::dvec3 c;
    for (int i = 0; i < 3; ++i) {
        c[i] = l[i] >= 0.0 ? box.max[i] : box.min[i];
    }
    return c;
}

// Signed area of a planar polygon, positive when it winds counter-clockwise about `normal`.
double signed_area(const std::vector<glm::dvec3>& polygon, glm::dvec3 normal) {
    glm::dvec3 sum(0.0);
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        sum += glm::cross(polygon[i], polygon[(i + 1) % polygon.size()]);
    }
    return 0.5 * glm::dot(sum, normal);
}

// Checks everything slice_polygon promises for a non-empty cut: 3 to 6 distinct vertices on
// the plane and in the box, ordered around a convex polygon with positive area.
void expect_valid_polygon(const scene::Box& box, glm::dvec3 normal, double d,
                          const std::vector<glm::dvec3>& polygon) {
    ASSERT_GE(polygon.size(), 3u);
    ASSERT_LE(polygon.size(), 6u);
    const std::size_t n = polygon.size();
    for (const glm::dvec3& v : polygon) {
        SCOPED_TRACE("vertex " + describe(v));
        EXPECT_LT(std::abs(glm::dot(normal, v) - d), kEps);
        for (int i = 0; i < 3; ++i) {
            EXPECT_GE(v[i], box.min[i] - kEps);
            EXPECT_LE(v[i], box.max[i] + kEps);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            EXPECT_GT(glm::length(polygon[i] - polygon[j]), 1e-12) << "vertices " << i << ", " << j;
        }
    }
    // Consecutive turns all point the same way along the normal...
    const glm::dvec3 e0 = polygon[1] - polygon[0];
    const glm::dvec3 e1 = polygon[2] - polygon[1];
    const double orientation = glm::dot(glm::cross(e0, e1), normal) > 0.0 ? 1.0 : -1.0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 a = polygon[(i + 1) % n] - polygon[i];
        const glm::dvec3 b = polygon[(i + 2) % n] - polygon[(i + 1) % n];
        EXPECT_GT(orientation * glm::dot(glm::cross(a, b), normal), 0.0) << "turn at " << i + 1;
    }
    // ...and every vertex lies on the inner side of every edge, which rules out star polygons.
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 edge = polygon[(i + 1) % n] - polygon[i];
        for (std::size_t j = 0; j < n; ++j) {
            const double side =
                    orientation * glm::dot(glm::cross(edge, polygon[j] - polygon[i]), normal);
            EXPECT_GT(side, -1e-12) << "vertex " << j << " outside edge " << i;
        }
    }
    EXPECT_GT(orientation * signed_area(polygon, normal), 0.0);
}

bool contains_point(const std::vector<glm::dvec3>& points, glm::dvec3 p, double tolerance) {
    return std::any_of(points.begin(), points.end(),
                       [&](const glm::dvec3& q) { return glm::length(q - p) < tolerance; });
}

// ---------------------------------------------------------------------------------------------
// box_corners

TEST(BoxCorners, AreTheEightDistinctCombinationsOfMinAndMax) {
    const scene::Box box{{-1.0, 2.0, -3.0}, {4.0, 5.0, 6.0}};
    const auto corners = box_corners(box);
    const std::vector<glm::dvec3> all(corners.begin(), corners.end());
    for (double x : {box.min.x, box.max.x}) {
        for (double y : {box.min.y, box.max.y}) {
            for (double z : {box.min.z, box.max.z}) {
                EXPECT_TRUE(contains_point(all, {x, y, z}, 1e-15)) << describe({x, y, z});
            }
        }
    }
}

// The corners of an oriented box are its box-space corners taken into world space, and the
// slicing spans them: a box of index axes A, S, R covers the same space as the RAS box with the
// extents permuted accordingly.
TEST(BoxCorners, FollowTheBoxAxes) {
    const glm::dmat3 asr({0, 1, 0}, {0, 0, 1}, {1, 0, 0});
    const scene::Box permuted = scene::box_for_extent({96.0, 90.0, 78.0}, asr);
    const scene::Box ras = scene::box_for_extent({78.0, 96.0, 90.0});
    const auto corners = box_corners(permuted);
    const auto ras_array = box_corners(ras);
    const std::vector<glm::dvec3> ras_corners(ras_array.begin(), ras_array.end());
    for (const auto& corner : corners) {
        EXPECT_TRUE(contains_point(ras_corners, corner, 1e-12)) << describe(corner);
    }
    const glm::dvec3 travel = glm::normalize(glm::dvec3(0.3, -0.5, -0.8));
    const LightSlicing a = make_light_slicing(permuted, travel, 10);
    const LightSlicing b = make_light_slicing(ras, travel, 10);
    EXPECT_NEAR(a.min, b.min, 1e-12);
    EXPECT_NEAR(a.max, b.max, 1e-12);
    // Each slice polygon lies on the turned box: every vertex is inside it.
    const glm::dmat3 turned(glm::rotate(glm::dmat4(1.0), glm::radians(30.0),
                                        glm::normalize(glm::dvec3(1.0, 2.0, 2.0))));
    const scene::Box oblique = scene::box_for_extent(glm::dvec3(1.0, 0.7, 0.5), turned);
    const LightSlicing slicing = make_light_slicing(oblique, travel, 12);
    for (int k = 0; k < slicing.count; ++k) {
        const auto polygon = slice_polygon(oblique, travel, slicing.plane_distance(k));
        ASSERT_GE(polygon.size(), 3u);
        for (const auto& p : polygon) {
            const glm::dvec3 outside = glm::abs(oblique.to_box(p)) - oblique.max;
            EXPECT_LE(std::max({outside.x, outside.y, outside.z}), 1e-12) << describe(p);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// slice_polygon

TEST(SlicePolygon, PlanePerpendicularToAnAxisGivesTheFaceSquare) {
    for (double d : {-0.25, 0.0, 0.3}) {
        SCOPED_TRACE("d = " + std::to_string(d));
        const auto polygon = slice_polygon(unit_box, {0.0, 0.0, 1.0}, d);
        ASSERT_EQ(polygon.size(), 4u);
        expect_valid_polygon(unit_box, {0.0, 0.0, 1.0}, d, polygon);
        for (double x : {-0.5, 0.5}) {
            for (double y : {-0.5, 0.5}) {
                EXPECT_TRUE(contains_point(polygon, {x, y, d}, 1e-12)) << describe({x, y, d});
            }
        }
        EXPECT_NEAR(std::abs(signed_area(polygon, {0.0, 0.0, 1.0})), 1.0, 1e-12);
    }
}

TEST(SlicePolygon, PlaneNearACornerPerpendicularToTheMainDiagonalGivesATriangle) {
    const glm::dvec3 normal = glm::normalize(glm::dvec3(1.0, 1.0, 1.0));
    const double s = 0.1;  // how far along each edge the plane cuts from corner (.5, .5, .5)
    const double d = (1.5 - s) / std::sqrt(3.0);
    const auto polygon = slice_polygon(unit_box, normal, d);
    ASSERT_EQ(polygon.size(), 3u);
    expect_valid_polygon(unit_box, normal, d, polygon);
    EXPECT_TRUE(contains_point(polygon, {0.5 - s, 0.5, 0.5}, 1e-12));
    EXPECT_TRUE(contains_point(polygon, {0.5, 0.5 - s, 0.5}, 1e-12));
    EXPECT_TRUE(contains_point(polygon, {0.5, 0.5, 0.5 - s}, 1e-12));
    // Equilateral with side s·√2.
    EXPECT_NEAR(std::abs(signed_area(polygon, normal)), std::sqrt(3.0) / 2.0 * s * s, 1e-12);
}

TEST(SlicePolygon, PlaneThroughAnLShapeOfThreeCornersGivesAPentagon) {
    // Corners sorted by (1, 2, 4)·V: (-,-,-), (+,-,-), (-,+,-) lie below the plane and form an L.
    const glm::dvec3 normal = glm::normalize(glm::dvec3(1.0, 2.0, 4.0));
    const double d = -1.0 / std::sqrt(21.0);
    const auto polygon = slice_polygon(unit_box, normal, d);
    ASSERT_EQ(polygon.size(), 5u);
    expect_valid_polygon(unit_box, normal, d, polygon);
}

TEST(SlicePolygon, PlaneThroughTheCentrePerpendicularToTheMainDiagonalGivesTheHexagon) {
    const glm::dvec3 normal = glm::normalize(glm::dvec3(1.0, 1.0, 1.0));
    const auto polygon = slice_polygon(unit_box, normal, 0.0);
    ASSERT_EQ(polygon.size(), 6u);
    expect_valid_polygon(unit_box, normal, 0.0, polygon);
    // The midpoints of the six edges the plane crosses.
    for (const glm::dvec3& p :
         {glm::dvec3(0.5, -0.5, 0.0), glm::dvec3(-0.5, 0.5, 0.0), glm::dvec3(0.5, 0.0, -0.5),
          glm::dvec3(-0.5, 0.0, 0.5), glm::dvec3(0.0, 0.5, -0.5), glm::dvec3(0.0, -0.5, 0.5)}) {
        EXPECT_TRUE(contains_point(polygon, p, 1e-12)) << describe(p);
    }
    // A regular hexagon of side √2/2.
    EXPECT_NEAR(std::abs(signed_area(polygon, normal)), 3.0 * std::sqrt(3.0) / 4.0, 1e-12);
}

TEST(SlicePolygon, PlaneThroughTheCentrePerpendicularToAFaceDiagonalContainsFourCorners) {
    // The plane x = y holds two whole edges of the box; the cut is the 1 × √2 rectangle.
    const glm::dvec3 normal = glm::normalize(glm::dvec3(1.0, -1.0, 0.0));
    const auto polygon = slice_polygon(unit_box, normal, 0.0);
    ASSERT_EQ(polygon.size(), 4u);
    expect_valid_polygon(unit_box, normal, 0.0, polygon);
    for (const glm::dvec3& p : {glm::dvec3(0.5, 0.5, 0.5), glm::dvec3(0.5, 0.5, -0.5),
                                glm::dvec3(-0.5, -0.5, 0.5), glm::dvec3(-0.5, -0.5, -0.5)}) {
        EXPECT_TRUE(contains_point(polygon, p, 1e-12)) << describe(p);
    }
    EXPECT_NEAR(std::abs(signed_area(polygon, normal)), std::sqrt(2.0), 1e-12);
}

TEST(SlicePolygon, PlaneMissingTheBoxGivesNoPolygon) {
    EXPECT_TRUE(slice_polygon(unit_box, {0.0, 0.0, 1.0}, 0.75).empty());
    EXPECT_TRUE(slice_polygon(unit_box, {0.0, 0.0, 1.0}, -0.75).empty());
    const glm::dvec3 diagonal = glm::normalize(glm::dvec3(1.0, 1.0, 1.0));
    EXPECT_TRUE(slice_polygon(unit_box, diagonal, 1.0).empty());
    EXPECT_TRUE(slice_polygon(unit_box, diagonal, -1.0).empty());
    const scene::Box off_centre{{1.0, 1.0, 1.0}, {2.0, 2.0, 2.0}};
    EXPECT_TRUE(slice_polygon(off_centre, {1.0, 0.0, 0.0}, 0.0).empty());
}

TEST(SlicePolygon, PlaneTouchingTheBoxOnlyAtACornerGivesNoPolygon) {
    const glm::dvec3 normal = glm::normalize(glm::dvec3(1.0, 1.0, 1.0));
    EXPECT_TRUE(slice_polygon(unit_box, normal, 1.5 / std::sqrt(3.0)).empty());
    EXPECT_TRUE(slice_polygon(unit_box, normal, -1.5 / std::sqrt(3.0)).empty());
}

TEST(SlicePolygon, EveryVertexLiesOnItsPlaneAndInTheBox) {
    const auto directions = test_directions();
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : directions) {
            SCOPED_TRACE(direction.name);
            for (int n : {1, 7, 64}) {
                const LightSlicing slicing = make_light_slicing(box.box, direction.direction, n);
                for (int k = 0; k < n; ++k) {
                    SCOPED_TRACE("n = " + std::to_string(n) + ", k = " + std::to_string(k));
                    const double d = slicing.plane_distance(k);
                    const auto polygon = slice_polygon(box.box, direction.direction, d);
                    expect_valid_polygon(box.box, direction.direction, d, polygon);
                    if (::testing::Test::HasFailure()) {
                        return;  // one traced failure is enough to diagnose
                    }
                }
            }
        }
    }
}

TEST(SlicePolygon, SliceAreasIntegrateToTheBoxVolume) {
    // The midpoint rule over the slices: Σ area(k) · spacing ≈ volume. A polygon that is valid but
    // is the wrong cut (a missing vertex, a wrong edge) breaks the sum.
    const auto directions = test_directions();
    constexpr int n = 256;
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        const glm::dvec3 size = box.box.size();
        const double volume = size.x * size.y * size.z;
        for (const NamedDirection& direction : directions) {
            SCOPED_TRACE(direction.name);
            const LightSlicing slicing = make_light_slicing(box.box, direction.direction, n);
            double sum = 0.0;
            for (int k = 0; k < n; ++k) {
                const auto polygon =
                        slice_polygon(box.box, direction.direction, slicing.plane_distance(k));
                sum += std::abs(signed_area(polygon, direction.direction)) * slicing.spacing();
            }
            EXPECT_NEAR(sum, volume, 1e-3 * volume);
        }
    }
}

// Slices cut to a region: the unit cube within a crop box (x >= -0.1, y <= 0.2: 0.6 x 0.7 x 1)
// and within a plane through its centre (half of it, the cube being symmetric about its centre),
// each kept by both users when the cut casts no shadow and by the camera only when it does.
TEST(SlicePolygon, SlicesClippedToARegionIntegrateToItsVolume) {
    Region crop;
    crop.box = unit_box;
    crop.half_spaces[0] = {{1.0, 0.0, 0.0}, 0.1};
    crop.half_spaces[1] = {{0.0, -1.0, 0.0}, 0.2};
    crop.count = crop.light_count = 2;
    Region plane;
    plane.box = unit_box;
    plane.half_spaces[0] = {glm::normalize(glm::dvec3(0.3, -0.8, 0.5)), 0.0};
    plane.count = 1;  // light_count 0: the cut casts shadows, the light sees the whole box
    constexpr int n = 256;
    for (const auto& [name, region, user, volume] :
         {std::tuple{"crop box", crop, RegionUser::light, 0.6 * 0.7},
          std::tuple{"plane for the camera", plane, RegionUser::camera, 0.5},
          std::tuple{"plane for the light, which casts shadows", plane, RegionUser::light, 1.0}}) {
        SCOPED_TRACE(name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            const LightSlicing slicing = make_light_slicing(unit_box, direction.direction, n);
            double sum = 0.0;
            for (int k = 0; k < n; ++k) {
                const auto polygon = clip_polygon(
                        region, user,
                        slice_polygon(unit_box, direction.direction, slicing.plane_distance(k)));
                ASSERT_TRUE(polygon.empty() || polygon.size() >= 3);
                for (const glm::dvec3& p : polygon) {
                    for (int i = 0; i < region.count_for(user); ++i) {
                        const HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
                        ASSERT_GE(glm::dot(h.normal, p) + h.offset, -kEps) << describe(p);
                    }
                }
                sum += std::abs(signed_area(polygon, direction.direction)) * slicing.spacing();
            }
            // A face of the cut across the slices falls within one slice: the midpoint rule may
            // miss at most one slice's area (no cross-section of the unit cube exceeds sqrt 2).
            EXPECT_NEAR(sum, volume, std::sqrt(2.0) * slicing.spacing());
        }
    }
}

TEST(SlicePolygon, ARegionThatKeepsNothingOfASliceLeavesNoPolygon) {
    Region region;
    region.box = unit_box;
    region.half_spaces[0] = {{0.0, 0.0, 1.0}, -0.2};  // z >= 0.2
    region.count = region.light_count = 1;
    EXPECT_TRUE(
            clip_polygon(region, RegionUser::camera, slice_polygon(unit_box, {0.0, 0.0, 1.0}, 0.1))
                    .empty());
    EXPECT_EQ(
            clip_polygon(region, RegionUser::camera, slice_polygon(unit_box, {0.0, 0.0, 1.0}, 0.3))
                    .size(),
            4u);
}

TEST(SlicePolygon, SeesEveryVertexCountFromThreeToSix) {
    std::vector<int> seen(7, 0);
    for (const NamedDirection& direction : test_directions()) {
        const LightSlicing slicing = make_light_slicing(unit_box, direction.direction, 64);
        for (int k = 0; k < 64; ++k) {
            const std::size_t size =
                    slice_polygon(unit_box, direction.direction, slicing.plane_distance(k)).size();
            ASSERT_LE(size, 6u);
            ++seen[size];
        }
    }
    EXPECT_EQ(seen[0], 0) << "a slice between min and max never misses the box";
    for (int count = 3; count <= 6; ++count) {
        EXPECT_GT(seen[static_cast<std::size_t>(count)], 0) << count << " vertices";
    }
}

// ---------------------------------------------------------------------------------------------
// make_light_slicing and the slice index (eq. 7, eq. 8)

TEST(MakeLightSlicing, MinAndMaxAreTheExtremeCornerProjections) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            const LightSlicing slicing = make_light_slicing(box.box, direction.direction, 7);
            EXPECT_EQ(slicing.count, 7);
            EXPECT_EQ(slicing.travel, direction.direction);
            EXPECT_NEAR(slicing.min, min_projection(box.box, direction.direction), 1e-12);
            EXPECT_NEAR(slicing.max, max_projection(box.box, direction.direction), 1e-12);
            for (const glm::dvec3& corner : box_corners(box.box)) {
                const double p = glm::dot(direction.direction, corner);
                EXPECT_GE(p, slicing.min);
                EXPECT_LE(p, slicing.max);
            }
        }
    }
}

TEST(MakeLightSlicing, SpacingTimesCountIsTheDepthRange) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            for (int n : {1, 7, 64, 2048}) {
                const LightSlicing s = make_light_slicing(box.box, direction.direction, n);
                EXPECT_GT(s.spacing(), 0.0);
                EXPECT_NEAR(s.spacing() * n, s.max - s.min, 1e-12);
                EXPECT_NEAR(s.plane_distance(0), s.min + 0.5 * s.spacing(), 1e-12);
                EXPECT_NEAR(s.plane_distance(n - 1), s.max - 0.5 * s.spacing(), 1e-12);
            }
        }
    }
}

TEST(MakeLightSlicing, NearestCornerHasIndexZeroAndFarthestIndexN) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            for (int n : {1, 7, 64}) {
                const glm::dvec3 l = direction.direction;
                const LightSlicing s = make_light_slicing(box.box, l, n);
                EXPECT_NEAR(s.index(nearest_corner(box.box, l)), 0.0, kEps);
                EXPECT_NEAR(s.index(farthest_corner(box.box, l)), static_cast<double>(n), kEps);
                for (const glm::dvec3& corner : box_corners(box.box)) {
                    EXPECT_GE(s.index(corner), -kEps);
                    EXPECT_LE(s.index(corner), n + kEps);
                }
            }
        }
    }
}

TEST(MakeLightSlicing, BoxCentreHasIndexHalfOfN) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            for (int n : {1, 7, 64}) {
                const LightSlicing s = make_light_slicing(box.box, direction.direction, n);
                EXPECT_NEAR(s.index(centre_of(box.box)), 0.5 * n, kEps);
            }
        }
    }
}

TEST(MakeLightSlicing, PointsOnSliceKHaveIndexKPlusHalf) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            constexpr int n = 7;
            const LightSlicing s = make_light_slicing(box.box, direction.direction, n);
            for (int k = 0; k < n; ++k) {
                for (const glm::dvec3& v :
                     slice_polygon(box.box, direction.direction, s.plane_distance(k))) {
                    EXPECT_NEAR(s.index(v), k + 0.5, kEps) << "k = " << k << " " << describe(v);
                }
            }
        }
    }
}

TEST(MakeLightSlicing, IndexGrowsLinearlyAlongTheTravelDirection) {
    const glm::dvec3 l = glm::normalize(glm::dvec3(0.3, -0.8, 0.5));
    const LightSlicing s = make_light_slicing(unit_box, l, 64);
    const glm::dvec3 p(0.1, 0.2, -0.3);
    // One spacing along L is one slice; moving perpendicular to L changes nothing.
    EXPECT_NEAR(s.index(p + l * s.spacing()) - s.index(p), 1.0, kEps);
    EXPECT_NEAR(s.index(p + l * (3.5 * s.spacing())) - s.index(p), 3.5, kEps);
    const glm::dvec3 perpendicular = glm::normalize(glm::cross(l, glm::dvec3(1.0, 0.0, 0.0)));
    EXPECT_NEAR(s.index(p + 0.2 * perpendicular), s.index(p), kEps);
}

// ---------------------------------------------------------------------------------------------
// layer_blend

TEST(LayerBlend, IndexHalfReadsTheFirstLayerOnly) {
    for (int count : {1, 2, 7, 64}) {
        SCOPED_TRACE("count = " + std::to_string(count));
        const LayerBlend b = layer_blend(0.5, count);
        EXPECT_EQ(b.lower, 0);
        EXPECT_DOUBLE_EQ(b.weight, 0.0);
        EXPECT_GE(b.upper, 0);
        EXPECT_LT(b.upper, count);
    }
}

TEST(LayerBlend, IndexKPlusHalfReadsLayerKExactly) {
    for (int count : {1, 2, 7, 64}) {
        for (int k = 0; k < count; ++k) {
            SCOPED_TRACE("count = " + std::to_string(count) + ", k = " + std::to_string(k));
            const LayerBlend b = layer_blend(k + 0.5, count);
            EXPECT_EQ(b.lower, k);
            EXPECT_DOUBLE_EQ(b.weight, 0.0);
            EXPECT_LT(b.upper, count);
        }
    }
}

TEST(LayerBlend, IndexBetweenLayerCentresInterpolatesLinearly) {
    const LayerBlend b = layer_blend(3.75, 7);  // a quarter of the way from layer 3 to layer 4
    EXPECT_EQ(b.lower, 3);
    EXPECT_EQ(b.upper, 4);
    EXPECT_DOUBLE_EQ(b.weight, 0.25);

    std::mt19937 rng(kSeed);
    for (int count : {2, 7, 64}) {
        std::uniform_real_distribution<double> index(0.5, count - 0.5);
        for (int i = 0; i < 100; ++i) {
            const double x = index(rng);
            SCOPED_TRACE("count = " + std::to_string(count) + ", index = " + std::to_string(x));
            const LayerBlend blend = layer_blend(x, count);
            EXPECT_GE(blend.lower, 0);
            EXPECT_LT(blend.upper, count);
            // The blended layer position is the index less half a slice.
            EXPECT_NEAR(blend.lower * (1.0 - blend.weight) + blend.upper * blend.weight, x - 0.5,
                        1e-12);
            EXPECT_TRUE(blend.upper == blend.lower + 1 ||
                        (blend.upper == blend.lower && blend.weight == 0.0));
        }
    }
}

TEST(LayerBlend, IndexPastTheLastLayerClampsToIt) {
    for (int count : {1, 2, 7, 64}) {
        SCOPED_TRACE("count = " + std::to_string(count));
        for (double index :
             {count - 0.5, static_cast<double>(count), count + 0.25, count + 10.0, 1e9}) {
            const LayerBlend b = layer_blend(index, count);
            EXPECT_EQ(b.lower, count - 1) << "index " << index;
            EXPECT_EQ(b.upper, count - 1) << "index " << index;
            EXPECT_DOUBLE_EQ(b.weight, 0.0) << "index " << index;
        }
    }
}

TEST(LayerBlend, NegativeIndexClampsToTheFirstLayer) {
    for (int count : {1, 2, 7, 64}) {
        SCOPED_TRACE("count = " + std::to_string(count));
        for (double index : {0.25, 0.0, -1e-12, -0.5, -3.0, -1e9}) {
            const LayerBlend b = layer_blend(index, count);
            EXPECT_EQ(b.lower, 0) << "index " << index;
            EXPECT_DOUBLE_EQ(b.weight, 0.0) << "index " << index;
        }
    }
}

TEST(LayerBlend, WeightsStayWithinZeroAndOneAndLayersInRange) {
    for (int count : {1, 2, 7, 64}) {
        for (double index = -2.0; index <= count + 2.0; index += 0.01) {
            SCOPED_TRACE("count = " + std::to_string(count) + ", index = " + std::to_string(index));
            const LayerBlend b = layer_blend(index, count);
            EXPECT_GE(b.weight, 0.0);
            EXPECT_LE(b.weight, 1.0);
            EXPECT_GE(b.lower, 0);
            EXPECT_LE(b.lower, b.upper);
            EXPECT_LT(b.upper, count);
            if (::testing::Test::HasFailure()) {
                return;
            }
        }
    }
}

TEST(LayerBlend, SingleLayerAlwaysReadsLayerZero) {
    for (double index : {-5.0, 0.0, 0.3, 0.5, 0.9, 1.0, 1.5, 100.0}) {
        const LayerBlend b = layer_blend(index, 1);
        EXPECT_EQ(b.lower, 0) << "index " << index;
        EXPECT_EQ(b.upper, 0) << "index " << index;
        EXPECT_DOUBLE_EQ(b.weight, 0.0) << "index " << index;
    }
}

// ---------------------------------------------------------------------------------------------
// light_travel_direction

TEST(LightTravelDirection, DirectionalLightTravelsAwayFromItsDirection) {
    scene::Light light;
    light.type = scene::LightType::directional;
    light.direction = {0.0, 0.0, 2.0};
    const glm::dvec3 t = light_travel_direction(light, unit_box);
    EXPECT_NEAR(glm::length(t - glm::dvec3(0.0, 0.0, -1.0)), 0.0, 1e-15);

    light.direction = {1.0, -2.0, 3.0};
    const glm::dvec3 u =
            light_travel_direction(light, scene::Box{{5.0, 5.0, 5.0}, {6.0, 7.0, 8.0}});
    EXPECT_NEAR(glm::length(u), 1.0, 1e-15);
    EXPECT_NEAR(glm::length(u + glm::normalize(light.direction)), 0.0, 1e-15);
}

TEST(LightTravelDirection, PointLightTravelsFromItsPositionToTheBoxCentre) {
    scene::Light light;
    light.type = scene::LightType::point;
    light.position = {3.0, 0.0, 0.0};
    EXPECT_NEAR(glm::length(light_travel_direction(light, unit_box) - glm::dvec3(-1.0, 0.0, 0.0)),
                0.0, 1e-15);

    const scene::Box box{{1.0, 1.0, 1.0}, {2.0, 3.0, 4.0}};  // centre (1.5, 2, 2.5)
    light.position = {-1.0, 0.5, 7.0};
    const glm::dvec3 t = light_travel_direction(light, box);
    EXPECT_NEAR(glm::length(t), 1.0, 1e-15);
    EXPECT_NEAR(glm::length(t - glm::normalize(glm::dvec3(2.5, 1.5, -4.5))), 0.0, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// make_light_view and light_uv (eq. 9)

scene::Light directional_light(glm::dvec3 direction) {
    scene::Light light;
    light.type = scene::LightType::directional;
    light.direction = direction;
    return light;
}

scene::Light point_light(glm::dvec3 position) {
    scene::Light light;
    light.type = scene::LightType::point;
    light.position = position;
    return light;
}

void expect_inverse(const LightView& view) {
    const glm::dmat4 product = view.inverse_view_projection * view.view_projection;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            EXPECT_NEAR(product[c][r], c == r ? 1.0 : 0.0, kEps) << "[" << c << "][" << r << "]";
        }
    }
}

// Clip-space depth of a world point, in [-1, 1] between the near and far planes.
double ndc_depth(const LightView& view, glm::dvec3 world) {
    const glm::dvec4 clip = view.view_projection * glm::dvec4(world, 1.0);
    return clip.z / clip.w;
}

TEST(MakeLightView, DirectionalLightFitsTheBoxTightlyInUv) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            const auto view = make_light_view(directional_light(direction.direction), box.box);
            ASSERT_TRUE(view.ok()) << view.error().to_string();
            EXPECT_FALSE(view->perspective);
            glm::dvec2 lo(std::numeric_limits<double>::infinity());
            glm::dvec2 hi(-std::numeric_limits<double>::infinity());
            for (const glm::dvec3& corner : box_corners(box.box)) {
                const glm::dvec2 uv = light_uv(*view, corner);
                lo = glm::min(lo, uv);
                hi = glm::max(hi, uv);
                const double z = ndc_depth(*view, corner);
                EXPECT_GT(z, -1.0) << "corner in front of the near plane " << describe(corner);
                EXPECT_LT(z, 1.0) << "corner beyond the far plane " << describe(corner);
            }
            EXPECT_NEAR(lo.x, 0.0, kEps);
            EXPECT_NEAR(lo.y, 0.0, kEps);
            EXPECT_NEAR(hi.x, 1.0, kEps);
            EXPECT_NEAR(hi.y, 1.0, kEps);
            const glm::dvec2 centre = light_uv(*view, centre_of(box.box));
            EXPECT_NEAR(centre.x, 0.5, kEps);
            EXPECT_NEAR(centre.y, 0.5, kEps);
        }
    }
}

TEST(MakeLightView, DirectionalLightIsOrthographicAlongTheTravelDirection) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            const scene::Light light = directional_light(direction.direction);
            const auto view = make_light_view(light, box.box);
            ASSERT_TRUE(view.ok()) << view.error().to_string();
            const glm::dvec3 l = light_travel_direction(light, box.box);
            for (const glm::dvec3& corner : box_corners(box.box)) {
                const glm::dvec3 p = 0.7 * corner + 0.3 * centre_of(box.box);
                const glm::dvec2 uv = light_uv(*view, p);
                for (double t : {-0.4, 0.1, 0.35}) {
                    const glm::dvec2 moved = light_uv(*view, p + t * l);
                    EXPECT_NEAR(moved.x, uv.x, kEps) << "t = " << t;
                    EXPECT_NEAR(moved.y, uv.y, kEps) << "t = " << t;
                }
                // Moving across L does move in uv.
                const glm::dvec3 across = glm::normalize(glm::cross(l, glm::dvec3(0.6, 0.0, 0.8)));
                EXPECT_GT(glm::length(light_uv(*view, p + 0.05 * across) - uv), 1e-3);
            }
        }
    }
}

TEST(MakeLightView, DirectionalInverseViewProjectionIsTheInverse) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& direction : test_directions()) {
            SCOPED_TRACE(direction.name);
            const auto view = make_light_view(directional_light(direction.direction), box.box);
            ASSERT_TRUE(view.ok()) << view.error().to_string();
            expect_inverse(*view);
            for (const glm::dvec3& corner : box_corners(box.box)) {
                const glm::dvec4 back = view->inverse_view_projection *
                                        (view->view_projection * glm::dvec4(corner, 1.0));
                EXPECT_NEAR(glm::length(glm::dvec3(back) / back.w - corner), 0.0, kEps);
            }
        }
    }
}

std::vector<NamedDirection> point_light_positions(const scene::Box& box) {
    const glm::dvec3 c = centre_of(box);
    const double r = glm::length(box.size());  // twice the bounding radius: always outside
    std::vector<NamedDirection> out = {
            {"on the +z axis", c + glm::dvec3(0.0, 0.0, r)},
            {"on the -y axis", c + glm::dvec3(0.0, -r, 0.0)},
            {"on the +x axis", c + glm::dvec3(r, 0.0, 0.0)},
            {"on the main diagonal", c + glm::dvec3(r)},
            {"on a face diagonal", c + glm::dvec3(0.0, r, -r)},
            {"far away", c + glm::dvec3(30.0 * r, -10.0 * r, 20.0 * r)},
    };
    std::mt19937 rng(kSeed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> distance(1.0, 5.0);
    for (int i = 0; i < 50; ++i) {
        const glm::dvec3 v(gauss(rng), gauss(rng), gauss(rng));
        out.push_back({"random #" + std::to_string(i) + " of seed " + std::to_string(kSeed),
                       c + glm::normalize(v) * r * distance(rng)});
    }
    for (auto& p : out) {
        p.name += " " + describe(p.direction);
    }
    return out;
}

TEST(MakeLightView, PointLightOutsideTheBoxSeesEveryCornerInUv) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& position : point_light_positions(box.box)) {
            SCOPED_TRACE(position.name);
            const auto view = make_light_view(point_light(position.direction), box.box);
            ASSERT_TRUE(view.ok()) << view.error().to_string();
            EXPECT_TRUE(view->perspective);
            EXPECT_EQ(view->position, position.direction);
            double extent = 0.0;  // the largest distance of a corner from the middle
            for (const glm::dvec3& corner : box_corners(box.box)) {
                const glm::dvec2 uv = light_uv(*view, corner);
                EXPECT_GE(uv.x, -kEps) << describe(corner);
                EXPECT_LE(uv.x, 1.0 + kEps) << describe(corner);
                EXPECT_GE(uv.y, -kEps) << describe(corner);
                EXPECT_LE(uv.y, 1.0 + kEps) << describe(corner);
                extent = std::max({extent, std::abs(uv.x - 0.5), std::abs(uv.y - 0.5)});
                const double z = ndc_depth(*view, corner);
                EXPECT_GT(z, -1.0) << "corner in front of the near plane " << describe(corner);
                EXPECT_LT(z, 1.0) << "corner beyond the far plane " << describe(corner);
            }
            // Fitted: some corner reaches the edge of the buffer.
            EXPECT_NEAR(extent, 0.5, kEps);
            const glm::dvec2 centre = light_uv(*view, centre_of(box.box));
            EXPECT_NEAR(centre.x, 0.5, kEps);
            EXPECT_NEAR(centre.y, 0.5, kEps);
            expect_inverse(*view);
        }
    }
}

TEST(MakeLightView, PointLightIsPerspectiveAlongRaysFromTheLight) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        for (const NamedDirection& position : point_light_positions(box.box)) {
            SCOPED_TRACE(position.name);
            const glm::dvec3 light = position.direction;
            const auto view = make_light_view(point_light(light), box.box);
            ASSERT_TRUE(view.ok()) << view.error().to_string();
            for (const glm::dvec3& corner : box_corners(box.box)) {
                const glm::dvec3 target = 0.8 * corner + 0.2 * centre_of(box.box);
                const glm::dvec2 uv = light_uv(*view, target);
                for (double t : {0.5, 0.9, 1.3, 2.0}) {
                    const glm::dvec2 along = light_uv(*view, light + t * (target - light));
                    EXPECT_NEAR(along.x, uv.x, kEps) << "t = " << t;
                    EXPECT_NEAR(along.y, uv.y, kEps) << "t = " << t;
                }
                // A parallel shift (not along the ray) does move in uv: it is not orthographic.
                const glm::dvec3 l = light_travel_direction(point_light(light), box.box);
                const glm::dvec2 shifted = light_uv(*view, target + 0.3 * l);
                if (glm::length(glm::cross(glm::normalize(target - light), l)) > 1e-3) {
                    EXPECT_GT(glm::length(shifted - uv), 1e-6);
                }
            }
        }
    }
}

TEST(MakeLightView, PointLightInsideOrTouchingTheBoxIsUnsupported) {
    for (const NamedBox& box : test_boxes()) {
        SCOPED_TRACE(box.name);
        const glm::dvec3 c = centre_of(box.box);
        const glm::dvec3 h = 0.5 * box.box.size();
        for (const glm::dvec3& position :
             {c, c + 0.3 * h, c - glm::dvec3(0.9, -0.2, 0.5) * h, c + 0.99 * h,
              c + glm::dvec3(h.x, 0.0, 0.0), box.box.max, box.box.min}) {
            SCOPED_TRACE("position " + describe(position));
            const auto view = make_light_view(point_light(position), box.box);
            ASSERT_FALSE(view.ok());
            EXPECT_EQ(view.error().code, base::ErrorCode::unsupported_light);
            EXPECT_EQ(view.error().where, "light.position");
        }
    }
}

TEST(MakeLightView, PointLightAlmostTouchingTheBoxIsUnsupported) {
    // Outside, but so close that no perspective under 170° covers the box.
    const auto view = make_light_view(point_light({0.5 + 1e-3, 0.0, 0.0}), unit_box);
    ASSERT_FALSE(view.ok());
    EXPECT_EQ(view.error().code, base::ErrorCode::unsupported_light);
}

// ---------------------------------------------------------------------------------------------
// resolve_slab_samples

TEST(ResolveSlabSamples, AnExplicitCountIsKeptUpToTheMaximum) {
    const LightSlicing slicing = make_light_slicing(unit_box, glm::dvec3(0.0, 0.0, -1.0), 10);
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(0.01), 1), 1);
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(0.01), 7), 7);
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(0.01), 1000), scene::kMaxSlabSamples);
}

TEST(ResolveSlabSamples, AutomaticCountPutsOnePointPerSmallestVoxelSide) {
    // Light along -z through the unit box in 10 slices: slabs 0.1 deep.
    const LightSlicing slicing = make_light_slicing(unit_box, glm::dvec3(0.0, 0.0, -1.0), 10);
    ASSERT_NEAR(slicing.spacing(), 0.1, 1e-12);
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(0.1), 0), 1);
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(0.04, 0.5, 0.5), 0), 3);   // 2.5 -> 3
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(0.5, 0.5, 0.025), 0), 4);  // exactly 4
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(1.0), 0), 1);  // voxels deeper than a slab
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(1e-4), 0), scene::kMaxSlabSamples);
    EXPECT_EQ(resolve_slab_samples(slicing, glm::dvec3(0.0), 0), 1);  // degenerate: the paper's
}

// ---------------------------------------------------------------------------------------------
// compensated_transmittance

const double compensations[] = {0.0, 0.5, 1.0, 4.0, 100.0, 1000.0};

TEST(CompensatedTransmittance, ZeroCompensationIsPlainTransmittance) {
    for (int i = 0; i <= 1000; ++i) {
        const double a = i / 1000.0;
        EXPECT_DOUBLE_EQ(compensated_transmittance(a, 0.0), 1.0 - a) << "a = " << a;
    }
}

TEST(CompensatedTransmittance, MatchesThePaperFormulaBelowOne) {
    EXPECT_DOUBLE_EQ(compensated_transmittance(0.5, 1.0), 0.5 * 1.5);
    EXPECT_DOUBLE_EQ(compensated_transmittance(0.9, 2.0), 0.1 * 1.9 * 1.9);
    EXPECT_DOUBLE_EQ(compensated_transmittance(0.25, 0.5), 0.75 * std::sqrt(1.25));
}

TEST(CompensatedTransmittance, NeverExceedsOneAndIsFinite) {
    for (double n : compensations) {
        for (int i = 0; i <= 1000; ++i) {
            const double a = i / 1000.0;
            const double t = compensated_transmittance(a, n);
            EXPECT_TRUE(std::isfinite(t)) << "a = " << a << ", n = " << n;
            EXPECT_LE(t, 1.0) << "a = " << a << ", n = " << n;
            EXPECT_GE(t, 0.0) << "a = " << a << ", n = " << n;
        }
    }
}

TEST(CompensatedTransmittance, TransparentSliceTransmitsAllAndOpaqueSliceNothing) {
    for (double n : compensations) {
        EXPECT_DOUBLE_EQ(compensated_transmittance(0.0, n), 1.0) << "n = " << n;
        EXPECT_DOUBLE_EQ(compensated_transmittance(1.0, n), 0.0) << "n = " << n;
    }
}

TEST(CompensatedTransmittance, IsMonotoneNonIncreasingInOpacity) {
    // (1 - a)(1 + a)^n rises then falls on [0, 1] and starts at 1, so clamped at 1 it never rises.
    for (double n : compensations) {
        double previous = compensated_transmittance(0.0, n);
        for (int i = 1; i <= 1000; ++i) {
            const double a = i / 1000.0;
            const double t = compensated_transmittance(a, n);
            EXPECT_LE(t, previous) << "a = " << a << ", n = " << n;
            previous = t;
        }
    }
}

TEST(CompensatedTransmittance, CompensationNeverDarkens) {
    for (int i = 0; i <= 100; ++i) {
        const double a = i / 100.0;
        double previous = compensated_transmittance(a, 0.0);
        for (double n : compensations) {
            const double t = compensated_transmittance(a, n);
            EXPECT_GE(t, previous) << "a = " << a << ", n = " << n;
            previous = t;
        }
    }
}

}  // namespace
}  // namespace penumbra::optics

namespace penumbra::optics {
namespace {

TEST(CompensatedTransmittance, OpaqueSliceStaysOpaqueForAnyCompensation) {
    for (const double n : {0.0, 1.0, 1024.0, 1e6}) {
        EXPECT_EQ(compensated_transmittance(1.0, n), 0.0) << n;
    }
}

// A point light beside the axis-aligned box can lie inside the same box turned 45 degrees.
TEST(MakeLightView, RefusesAPointLightInsideTheTurnedBox) {
    const glm::dmat3 turned(glm::rotate(glm::dmat4(1.0), glm::radians(45.0), {0.0, 0.0, 1.0}));
    scene::Light light;
    light.type = scene::LightType::point;
    light.position = {0.65, 0.0, 0.0};
    EXPECT_TRUE(make_light_view(light, unit_box).ok());
    const auto view = make_light_view(light, scene::box_for_extent(glm::dvec3(1.0), turned));
    ASSERT_FALSE(view.ok());
    EXPECT_EQ(view.error().code, base::ErrorCode::unsupported_light);
}

}  // namespace
}  // namespace penumbra::optics
