#pragma once

#include "frame_planner.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/optics/light_slicing.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace penumbra::render {

// Where the frame's light and slices lie: CPU work that depends only on the request and the box.
struct FrameGeometry {
    scene::Box box;
    optics::Region region;   // the box as the request's cut leaves it
    glm::dvec3 travel{0.0};  // the light's direction of travel
    std::optional<optics::LightView> light_view;
    optics::LightSlicing light_slicing;  // with light_view
    int slab_samples = 0;                // resolved; 0 without light_view
    // Half-angle slicing: the axis the slices are perpendicular to, their range along it, and
    // whether the eye composites front to back (else the view vector was flipped).
    glm::dvec3 half_angle_axis{0.0};
    optics::LightSlicing half_angle_slicing;
    bool front_to_back = true;
};

// The light's view and slicing, and half-angle slicing's axis, for `request` drawn as `plan` says
// on `volume`: everything about where the frame's slices lie, computed before anything is issued.
base::Result<FrameGeometry> frame_geometry(const scene::FrameRequest& request,
                                           const FramePlan& plan, const volume::Volume& volume);

// The camera's view-projection for rasterised slices, flipped vertically so that image row 0 (the
// top) lands in framebuffer row 0, like the ray caster's output; a tile's is the whole image's
// with the tile's part of it stretched over the frame (scene::image_window).
glm::dmat4 camera_view_projection(const scene::FrameRequest& request, const scene::Box& box);

}  // namespace penumbra::render
