#include "penumbra/reference/cpu_renderer.hpp"

#include <penumbra/optics/compositing.hpp>
#include <penumbra/optics/labels.hpp>
#include <penumbra/optics/ray.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/optics/shading.hpp>
#include <penumbra/reference/volume_sampler.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <optional>
#include <string>

namespace penumbra::reference {
namespace {

glm::dvec3 direction_to_light(const scene::Light& light, glm::dvec3 position) {
    return light.type == scene::LightType::point ? glm::normalize(light.position - position)
                                                 : glm::normalize(light.direction);
}

// The threshold compares the change per voxel along the volume's own axes (shading.glsl).
glm::dvec3 normal_from_gradient(glm::dvec3 gradient, const VolumeSampler& sampler) {
    if (glm::length(sampler.box().to_box(gradient) * sampler.voxel_size()) <
        optics::min_gradient_per_voxel) {
        return glm::dvec3(0.0);
    }
    return -glm::normalize(gradient);
}

// Below this transmittance a shadow ray stops: the rest cannot matter (shadow_ray.glsl).
constexpr double shadow_ray_cutoff = 1e-4;

using optics::sample_opacity;

// What the marches classify: each sample, or with pre-integration the segment from the value
// before it (shaders/include/preintegration.glsl), in the label at the sample where labels are
// drawn.
class Classifier {
public:
    Classifier(const TransferFunctionTable& tf, const scene::RenderSettings& s,
               const std::optional<LabelLookup>& labels)
        : tf_(tf)
        , labels_(labels) {
        if (s.preintegration) {
            segments_.emplace(tf, s.compositing == scene::Compositing::extinction);
        }
    }

    // Whether it classifies segments (pre-integration) rather than samples.
    [[nodiscard]] bool segments() const { return segments_.has_value(); }

    // Sample `value` at `world`, the back of the segment from the value classified before it;
    // `front` becomes `value`.
    glm::dvec4 classify(double& front, double value, glm::dvec3 world) const {
        const glm::dvec4 classified =
                segments_ ? segments_->classify(front, value) : tf_.classify(value);
        front = value;
        return labels_ ? labels_->classify(classified, world) : classified;
    }

private:
    const TransferFunctionTable& tf_;
    const std::optional<LabelLookup>& labels_;
    std::optional<SegmentClassifier> segments_;
};

// The ground truth for shadows: the transmittance along a ray from `position` to the light,
// marched with the camera's sample distance and the same opacity correction.
double shadow_ray_transmittance(const VolumeSampler& sampler, const optics::Region& region,
                                const Classifier& tf, const scene::FrameRequest& request,
                                glm::dvec3 position) {
    const glm::dvec3 to_light = direction_to_light(request.light, position);
    double t_end =
            optics::intersect_region(region, position, to_light, optics::RegionUser::light).t_far;
    if (request.light.type == scene::LightType::point) {
        t_end = std::min(t_end, glm::length(request.light.position - position));
    }
    if (!(t_end > 0.0)) {
        return 1.0;
    }
    const optics::Marching marching =
            optics::plan_marching(0.0, t_end, request.settings.sample_distance);
    double transmittance = 1.0;
    // Pre-integrated segments end to end from the lit point, samples at the middle of each step
    // (shadow_ray.glsl says why); either way the ray counts [0, t_end] once.
    const bool segments = tf.segments();
    double front = sampler.value(position);
    for (int i = 0; i < marching.count && transmittance >= shadow_ray_cutoff; ++i) {
        const glm::dvec3 p = position + (i + 0.5) * marching.step * to_light;
        const double value =
                segments ? sampler.value(position + (i + 1.0) * marching.step * to_light)
                         : sampler.value(p);
        transmittance *= 1.0 - sample_opacity(tf.classify(front, value, p).a, marching.step,
                                              request.settings);
    }
    return transmittance;
}

}  // namespace

base::Result<base::ImageRgbaF> render_cpu(const volume::Volume& volume,
                                          const scene::FrameRequest& request,
                                          const volume::LabelMap* labels) {
    if (auto status = scene::validate(request); !status) {
        return status.error();
    }
    if (auto axes = scene::check_axes(volume.axes); !axes) {
        return axes.error();
    }
    const scene::RenderSettings& s = request.settings;
    if (s.mode != scene::Mode::dvr && s.mode != scene::Mode::phong &&
        s.mode != scene::Mode::reference) {
        return base::make_error(base::ErrorCode::unsupported_mode,
                                std::string("the CPU renderer computes dvr, phong and reference, "
                                            "not '") +
                                        scene::to_string(s.mode) + "'",
                                "mode");
    }
    const bool phong = scene::uses_gradients(s);
    const bool shadows = s.mode == scene::Mode::reference;
    const VolumeSampler sampler(volume, s.reconstruction);
    const TransferFunctionTable table(request.transfer_function,
                                      {volume.range.min, volume.range.max, volume.hounsfield});
    auto label_lookup = lookup_labels(labels, volume, request.labels);
    if (!label_lookup) {
        return label_lookup.error();
    }
    const Classifier tf(table, s, *label_lookup);
    const optics::Region region =
            optics::region_of(sampler.box(), request.cut,
                              scene::patient_placement(volume.origin, volume.axes, volume.spacing,
                                                       glm::dvec3(volume.dims)));
    // A cut face's gradient is shaded within a voxel of it (optics::gradient_at_cut).
    const glm::dvec3 voxel = sampler.voxel_size();
    const double reach = std::max({voxel.x, voxel.y, voxel.z});
    const scene::CameraFrame camera = scene::pixel_frame(request);

    base::ImageRgbaF image(s.width, s.height);
    for (int y = 0; y < s.height; ++y) {
        for (int x = 0; x < s.width; ++x) {
            const glm::dvec3 direction =
                    optics::pixel_ray_direction(camera, x, y, s.width, s.height);
            const optics::BoxHit hit = optics::intersect_region(region, camera.eye, direction,
                                                                optics::RegionUser::camera);
            glm::dvec4 accumulated(0.0);
            const optics::Marching marching =
                    hit.hit ? optics::plan_marching(hit.t_near, hit.t_far, s.sample_distance)
                            : optics::Marching{};
            const double offset = optics::ray_start_offset(
                    s.jitter, x + request.tile.x, y + request.tile.y, request.refinement.step);
            // The first segment starts where the ray enters the region (raycast.glsl).
            double front = hit.hit ? sampler.value(camera.eye + hit.t_near * direction) : 0.0;
            for (int i = 0; i < marching.count; ++i) {
                const glm::dvec3 position =
                        camera.eye + (hit.t_near + (i + offset) * marching.step) * direction;
                const glm::dvec4 classified = tf.classify(front, sampler.value(position), position);
                // Pre-integrated, the segment is lit and shaded at its middle, the first at its
                // sample (lit_before in raycast.glsl).
                const glm::dvec3 lit = s.preintegration && i > 0
                                               ? position - 0.5 * marching.step * direction
                                               : position;
                if (classified.a <= 0.0) {
                    continue;
                }
                glm::dvec3 color(classified);
                if (phong || shadows) {
                    optics::LightTerms terms;
                    if (phong) {
                        glm::dvec3 gradient = sampler.gradient(lit);
                        if (region.count > 0) {  // as raycast.glsl: no extra fetch without a cut
                            gradient = optics::gradient_at_cut(region, lit, gradient,
                                                               sampler.value(lit), reach);
                        }
                        const glm::dvec3 normal = normal_from_gradient(gradient, sampler);
                        terms = optics::blinn_phong(normal, direction_to_light(request.light, lit),
                                                    -direction, s.shading.shininess);
                    } else {
                        terms = {1.0, 0.0};
                    }
                    const double light =
                            shadows ? shadow_ray_transmittance(sampler, region, tf, request, lit)
                                    : 1.0;
                    color = optics::shade(color, terms, request.light, s.shading, light);
                }
                optics::composite_front_to_back(accumulated, color,
                                                sample_opacity(classified.a, marching.step, s));
                if (accumulated.a >= s.early_termination) {
                    break;
                }
            }
            float* out = image.pixel(x, y);
            // Clamped like the GPU's UNORM8 frame, so highlights above 1 compare as displayed.
            const glm::dvec3 final_color = glm::clamp(
                    glm::dvec3(accumulated) + (1.0 - accumulated.a) * s.background, 0.0, 1.0);
            out[0] = static_cast<float>(final_color.r);
            out[1] = static_cast<float>(final_color.g);
            out[2] = static_cast<float>(final_color.b);
            out[3] = 1.0f;
        }
    }
    return image;
}

}  // namespace penumbra::reference
