#include "penumbra/reference/pick.hpp"

#include <penumbra/optics/compositing.hpp>
#include <penumbra/optics/ray.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/reference/volume_sampler.hpp>

#include <algorithm>
#include <optional>

namespace penumbra::reference {
namespace {

// A value the sampler gives (the range as [0, 1]) as the volume's real value.
double real_value(const volume::Volume& volume, double normalized) {
    return volume.range.min + normalized * (volume.range.max - volume.range.min);
}

}  // namespace

base::Result<Pick> pick(const volume::Volume& volume, const scene::FrameRequest& request,
                        const volume::LabelMap* labels, int x, int y) {
    if (auto status = scene::validate(request); !status) {
        return status.error();
    }
    const scene::RenderSettings& s = request.settings;
    if (x < 0 || y < 0 || x >= s.width || y >= s.height) {
        return base::make_error(base::ErrorCode::out_of_range,
                                "the pixel lies outside the " + std::to_string(s.width) + "x" +
                                        std::to_string(s.height) + " view",
                                "pick");
    }
    const VolumeSampler sampler(volume, s.reconstruction, VolumeSampler::Reading::in_place);
    const TransferFunctionTable table(request.transfer_function,
                                      {volume.range.min, volume.range.max, volume.hounsfield});
    auto looked_up = lookup_labels(labels, volume, request.labels);
    if (!looked_up) {
        return looked_up.error();
    }
    const std::optional<LabelLookup>& label_lookup = *looked_up;
    const scene::PatientPlacement placement = scene::patient_placement(
            volume.origin, volume.axes, volume.spacing, glm::dvec3(volume.dims));
    const optics::Region region = optics::region_of(sampler.box(), request.cut, placement);
    const scene::CameraFrame camera = scene::pixel_frame(request);
    const glm::dvec3 direction = optics::pixel_ray_direction(camera, x, y, s.width, s.height);
    const optics::BoxHit hit =
            optics::intersect_region(region, camera.eye, direction, optics::RegionUser::camera);
    Pick picked;
    picked.hounsfield = volume.hounsfield;
    if (!hit.hit) {
        return picked;
    }
    // Never finer than half the finest voxel: what a person points at is no finer, and a pick's
    // cost stays bounded by the volume's size whatever step its frames take.
    const glm::dvec3 voxel = sampler.voxel_size();
    const double step = std::max(s.sample_distance, 0.5 * std::min({voxel.x, voxel.y, voxel.z}));
    const optics::Marching marching = optics::plan_marching(hit.t_near, hit.t_far, step);
    double transmittance = 1.0;
    for (int i = 0; i < marching.count; ++i) {
        const glm::dvec3 position =
                camera.eye + (hit.t_near + (i + 0.5) * marching.step) * direction;
        const double normalized = sampler.value(position);
        glm::dvec4 classified = table.classify(normalized);
        if (label_lookup) {
            classified = label_lookup->classify(classified, position);
        }
        transmittance *= 1.0 - optics::sample_opacity(classified.a, marching.step, s);
        if (transmittance > 0.5) {
            continue;
        }
        picked.hit = true;
        picked.patient = placement.to_patient(position);
        picked.value = real_value(volume, normalized);
        if (label_lookup) {
            if (const volume::Label* label =
                        label_lookup->label(label_lookup->index_at(position))) {
                picked.label_id = label->id;
                picked.label_name = label->name;
            }
        }
        break;
    }
    return picked;
}

double value_at(const volume::Volume& volume, glm::dvec3 patient) {
    const VolumeSampler sampler(volume, scene::Reconstruction::trilinear,
                                VolumeSampler::Reading::in_place);
    const scene::PatientPlacement placement = scene::patient_placement(
            volume.origin, volume.axes, volume.spacing, glm::dvec3(volume.dims));
    return real_value(volume, sampler.value(placement.to_world(patient)));
}

}  // namespace penumbra::reference
