#include "frame_geometry.hpp"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>

namespace penumbra::render {

base::Result<FrameGeometry> frame_geometry(const scene::FrameRequest& request,
                                           const FramePlan& plan, const volume::Volume& volume) {
    const scene::RenderSettings& s = request.settings;
    FrameGeometry g;
    g.box = scene::box_for_extent(volume.extent(), volume.axes);
    g.region = optics::region_of(g.box, request.cut,
                                 scene::patient_placement(volume.origin, volume.axes,
                                                          volume.spacing, glm::dvec3(volume.dims)));
    g.travel = optics::light_travel_direction(request.light, g.box);
    if (plan.needs_light_view) {
        auto view = optics::make_light_view(request.light, g.box);
        if (!view) {
            return view.error();
        }
        g.light_view = *view;
        g.light_slicing = optics::make_light_slicing(g.box, g.travel, s.light_buffer.slices);
        // The voxel size as the shaders see it (float), so the CPU and GPU resolve alike.
        const glm::dvec3 voxel_size(glm::vec3(g.box.size() / glm::dvec3(volume.dims)));
        g.slab_samples = optics::resolve_slab_samples(g.light_slicing, voxel_size,
                                                      s.light_buffer.slab_samples);
    }
    if (plan.half_angle) {
        // Slice along the half vector of the view and the light; when they point apart, the view
        // vector is flipped and the eye composites back to front.
        const glm::dvec3 view = glm::normalize(request.camera.target - request.camera.eye);
        g.front_to_back = glm::dot(view, g.travel) >= 0.0;
        g.half_angle_axis = glm::normalize(g.front_to_back ? view + g.travel : g.travel - view);
        g.half_angle_slicing =
                optics::make_light_slicing(g.box, g.half_angle_axis, s.light_buffer.slices);
    }
    return g;
}

glm::dmat4 camera_view_projection(const scene::FrameRequest& request, const scene::Box& box) {
    const scene::Camera& camera = request.camera;
    const scene::ImageWindow window = scene::image_window(request);
    const double aspect =
            (request.settings.width / window.scale.x) / (request.settings.height / window.scale.y);
    const scene::CameraFrame frame = scene::camera_frame(camera, aspect);
    double far = 0.0;
    for (const auto& corner : optics::box_corners(box)) {
        far = std::max(far, glm::length(corner - camera.eye));
    }
    const glm::dvec3 up = glm::normalize(frame.up);
    const glm::dmat4 view = glm::lookAt(camera.eye, camera.eye + frame.forward, up);
    const glm::dmat4 projection =
            glm::perspective(glm::radians(camera.fov_y_degrees), aspect, 1e-3, far + 1.0);
    const glm::dmat4 flipped = glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, -1.0, 1.0));
    // Clip space is flipped vertically here, so the tile's window offset changes sign in y.
    const glm::dmat4 to_frame =
            glm::scale(glm::dmat4(1.0), glm::dvec3(1.0 / window.scale, 1.0)) *
            glm::translate(glm::dmat4(1.0), glm::dvec3(-window.offset.x, window.offset.y, 0.0));
    return to_frame * flipped * projection * view;
}

}  // namespace penumbra::render
