#pragma once

// The geometry of the light attenuation buffer (the paper's §3.2), GL-free, shared by the
// renderer, the CPU reference and the tests, and mirrored by shaders/include/light_buffer.glsl.

#include <penumbra/base/result.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/scene/light.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace penumbra::optics {

// The eight corners of a box, in world space; corner i has bit 0 set at the box's max x (box
// space), bit 1 at max y, bit 2 at max z, so corners differing in one bit share an edge.
std::array<glm::dvec3, 8> box_corners(const scene::Box& box);

// The direction light travels through the volume: away from a directional light's `direction`
// (which points toward the light), or from a point light toward the box centre.
glm::dvec3 light_travel_direction(const scene::Light& light, const scene::Box& box);

// Slices perpendicular to the travel direction L between the nearest and farthest box corner
// (paper eq. 7): min/max of L·V over the corners. Slice k lies at L·x = min + (k + 0.5)·spacing.
struct LightSlicing {
    glm::dvec3 travel{0.0, 0.0, -1.0};  // L, unit
    double min = 0.0;
    double max = 1.0;
    int count = 1;

    [[nodiscard]] double spacing() const { return (max - min) / count; }

    [[nodiscard]] double plane_distance(int k) const { return min + (k + 0.5) * spacing(); }

    // The paper's eq. 8: the continuous slice index n(L·S - min)/(max - min) of a world point.
    [[nodiscard]] double index(glm::dvec3 world) const;
};

LightSlicing make_light_slicing(const scene::Box& box, glm::dvec3 travel, int count);

// The polygon where the plane L·x = d cuts the box: 3 to 6 vertices ordered around their
// centroid (a triangle fan), or none when the plane misses the box.
std::vector<glm::dvec3> slice_polygon(const scene::Box& box, glm::dvec3 normal, double d);

// Which two layers a continuous slice index reads and how to blend them. Layer k holds the light
// that reaches slice k's plane (index k + 0.5); array textures do not filter across layers, so the
// lookup interpolates by hand, clamped to the first and last layer.
struct LayerBlend {
    int lower = 0;
    int upper = 0;
    double weight = 0.0;  // of `upper`
};

LayerBlend layer_blend(double index, int count);

// The light's view and projection (paper eq. 9): orthographic along L for a directional light,
// perspective from a point light, each fitted tightly around the box. Maps world points to clip
// space; x and y in [-1, 1] cover the light buffer.
struct LightView {
    glm::dmat4 view_projection{1.0};
    glm::dmat4 inverse_view_projection{1.0};
    bool perspective = false;
    glm::dvec3 position{0.0};  // point light position (perspective only)
};

// Fails for a point light inside (or touching) the box: no single projection from there covers
// the volume.
base::Result<LightView> make_light_view(const scene::Light& light, const scene::Box& box);

// Light-buffer texture coordinates in [0, 1]^2 of a world point (eq. 9).
glm::dvec2 light_uv(const LightView& view, glm::dvec3 world);

// How many points sample each slice's slab along the light: `requested` when it is positive,
// otherwise enough that they lie no farther apart than the smallest voxel side, at most
// scene::kMaxSlabSamples. A surface inside a slab then darkens the light in proportion to how
// much of the slab it fills, instead of all at once at the slice plane.
int resolve_slab_samples(const LightSlicing& slicing, glm::dvec3 voxel_size, int requested);

// The paper's darkening compensation: a slice of opacity a transmits (1 - a)(1 + a)^n instead of
// (1 - a), never more than 1 (n = 0 turns it off).
double compensated_transmittance(double alpha, double compensation);

}  // namespace penumbra::optics
