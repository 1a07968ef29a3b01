#include "half_angle_slicer.hpp"

#include <penumbra/gpu/commands.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <vector>

namespace penumbra::render {

HalfAngleSlicer::HalfAngleSlicer(ProgramCache& programs)
    : programs_(programs) {}

void HalfAngleSlicer::cut_slices(const FrameGeometry& g) {
    const optics::LightSlicing& slicing = g.half_angle_slicing;
    eye_slices_.upload(make_slice_geometry(g.region, optics::RegionUser::camera, slicing.travel,
                                           slicing.min, slicing.max, slicing.count, 0.0));
    // A light-pass fragment reads the slab along the light's ray, spacing / cos(ray, axis) long
    // (half_angle.frag): its slices are widened by that, or by a point light's widest ray.
    const double reach = g.light_view && g.light_view->perspective
                                 ? point_light_reach(g.box, g.light_view->position, slicing.travel)
                                 : 1.0 / std::max(glm::dot(slicing.travel, g.travel), 1e-3);
    light_slices_.upload(make_slice_geometry(g.region, optics::RegionUser::light, slicing.travel,
                                             slicing.min, slicing.max, slicing.count, reach));
}

void HalfAngleSlicer::ensure_buffers(int width, int height, int light_resolution) {
    if (!eye_ || width != width_ || height != height_) {
        // Float so that hundreds of blended slices do not band.
        eye_ = gpu::create_texture_2d(GL_RGBA32F, width, height);
        eye_framebuffer_ = gpu::create_framebuffer(eye_);
        width_ = width;
        height_ = height;
    }
    if (!light_ || light_resolution != light_resolution_) {
        light_ = gpu::create_texture_2d(GL_R16F, light_resolution, light_resolution);
        gpu::set_sampling(light_, GL_LINEAR, GL_CLAMP_TO_EDGE);
        light_framebuffer_ = gpu::create_framebuffer(light_);
        light_resolution_ = light_resolution;
    }
}

base::Status HalfAngleSlicer::run(const FrameGeometry& g, int width, int height,
                                  int light_resolution, const gpu::Defines& defines,
                                  FrameTarget& target, gpu::GpuTimer& timer, WorkChunks& chunks) {
    const auto pass_program = [&](bool light_pass) {
        gpu::Defines all = defines;
        all.emplace_back("HALF_ANGLE_LIGHT_PASS", light_pass ? "1" : "0");
        return programs_.graphics("half_angle.vert", "half_angle.frag", all);
    };
    auto eye_program = pass_program(false);
    auto light_program = pass_program(true);
    auto resolve_program = programs_.compute("resolve.comp");
    if (!eye_program || !light_program || !resolve_program) {
        return !eye_program     ? eye_program.error()
               : !light_program ? light_program.error()
                                : resolve_program.error();
    }
    ensure_buffers(width, height, light_resolution);
    target.ensure(width, height);
    cut_slices(g);

    timer.begin();
    gpu::clear(eye_framebuffer_, {0.0f, 0.0f, 0.0f, 0.0f});
    gpu::clear(light_framebuffer_, {1.0f, 1.0f, 1.0f, 1.0f});
    gpu::bind_texture(3, light_);
    const double work_per_slice =
            double(width) * height + double(light_resolution) * light_resolution;
    const int slices_per_chunk = static_cast<int>(std::clamp(
            chunks.work_per_chunk() / work_per_slice, 1.0, double(eye_slices_.slices())));
    base::Status status = base::Ok{};
    for (int k = 0; k < eye_slices_.slices(); ++k) {
        gpu::draw_into(eye_framebuffer_, width, height,
                       g.front_to_back ? gpu::Blend::under : gpu::Blend::over);
        eye_slices_.draw(**eye_program, k);
        gpu::draw_into(light_framebuffer_, light_resolution, light_resolution,
                       gpu::Blend::multiply);
        light_slices_.draw(**light_program, k);
        if ((k + 1) % slices_per_chunk == 0 && k + 1 < eye_slices_.slices() &&
            !chunks.continue_after_chunk()) {
            status = cancelled_error();
            break;
        }
    }
    gpu::end_drawing();
    if (!status) {
        timer.end();
        return status;
    }

    gpu::bind_texture(0, eye_);
    gpu::bind_image(0, target.texture(), GL_WRITE_ONLY, FrameTarget::image_format);
    gpu::dispatch(**resolve_program, gpu::groups_covering(group_side, width, height),
                  GL_TEXTURE_UPDATE_BARRIER_BIT);
    timer.end();
    return base::Ok{};
}

base::ImageRgba8 HalfAngleSlicer::light_image() const {
    std::vector<float> values(static_cast<std::size_t>(light_resolution_) * light_resolution_);
    gpu::read_texture(light_, GL_RED, GL_FLOAT, std::as_writable_bytes(std::span(values)));
    return transmittance_image(values, light_resolution_);
}

}  // namespace penumbra::render
