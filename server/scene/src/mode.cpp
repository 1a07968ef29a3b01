#include <penumbra/scene/frame_request.hpp>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <string>
#include <utility>

namespace penumbra::scene {
namespace {

constexpr std::array<std::pair<Mode, const char*>, 7> mode_names{{
        {Mode::dvr, "dvr"},
        {Mode::phong, "phong"},
        {Mode::half_angle, "half_angle"},
        {Mode::sbrc, "sbrc"},
        {Mode::sbrc_shell, "sbrc_shell"},
        {Mode::sbrc_cone, "sbrc_cone"},
        {Mode::reference, "reference"},
}};

bool finite(glm::dvec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

base::Error invalid(const std::string& field, const std::string& message) {
    return base::make_error("invalid_value", message, field);
}

}  // namespace

const char* to_string(Mode mode) {
    for (const auto& [m, name] : mode_names) {
        if (m == mode) {
            return name;
        }
    }
    return "?";
}

std::optional<Mode> parse_mode(std::string_view text) {
    for (const auto& [m, name] : mode_names) {
        if (text == name) {
            return m;
        }
    }
    return std::nullopt;
}

const char* to_string(Compositing compositing) {
    return compositing == Compositing::alpha ? "alpha" : "extinction";
}

std::optional<Compositing> parse_compositing(std::string_view text) {
    if (text == "alpha") {
        return Compositing::alpha;
    }
    if (text == "extinction") {
        return Compositing::extinction;
    }
    return std::nullopt;
}

const char* to_string(RaycastStage stage) {
    return stage == RaycastStage::compute ? "compute" : "fragment";
}

std::optional<RaycastStage> parse_raycast_stage(std::string_view text) {
    if (text == "compute") {
        return RaycastStage::compute;
    }
    if (text == "fragment") {
        return RaycastStage::fragment;
    }
    return std::nullopt;
}

const char* to_string(LightBufferBuilder builder) {
    return builder == LightBufferBuilder::per_slice ? "per_slice" : "multi_slice";
}

std::optional<LightBufferBuilder> parse_light_buffer_builder(std::string_view text) {
    if (text == "per_slice") {
        return LightBufferBuilder::per_slice;
    }
    if (text == "multi_slice") {
        return LightBufferBuilder::multi_slice;
    }
    return std::nullopt;
}

const char* to_string(LightLookup lookup) {
    return lookup == LightLookup::interpolate ? "interpolate" : "local";
}

std::optional<LightLookup> parse_light_lookup(std::string_view text) {
    if (text == "interpolate") {
        return LightLookup::interpolate;
    }
    if (text == "local") {
        return LightLookup::local;
    }
    return std::nullopt;
}

bool uses_light_buffer(Mode mode) {
    return mode == Mode::sbrc || mode == Mode::sbrc_shell || mode == Mode::sbrc_cone;
}

bool uses_gradients(const RenderSettings& settings) {
    return settings.mode == Mode::phong || (settings.phong && settings.mode != Mode::dvr);
}

bool is_ray_cast(Mode mode) {
    return mode != Mode::half_angle;
}

base::Status validate(const FrameRequest& request, const Limits& limits) {
    const RenderSettings& s = request.settings;
    const Refinement& r = request.refinement;
    if (r.step < 0 || r.step > kMaxRefinementSteps) {
        return invalid("refinement.step",
                       "refinement step must be within 0.." + std::to_string(kMaxRefinementSteps));
    }
    if ((r.step > 0 || r.keep) && (!s.jitter || !is_ray_cast(s.mode))) {
        return invalid("refinement", "refinement needs a jittered ray-cast mode");
    }
    const int max_image_side = limits.max_image_side;
    if (s.width < 1 || s.height < 1 || s.width > max_image_side || s.height > max_image_side) {
        return invalid("size", "image size must be within 1.." + std::to_string(max_image_side) +
                                       " pixels per side");
    }
    // A ray needs at least one sample per voxel layer it could cross to be meaningful, and a
    // million samples per unit is more than any GPU can march in a frame.
    // Finer than 1/16384 of the box resolves nothing more (volumes have at most a few thousand
    // voxels a side) and only multiplies the work.
    if (!std::isfinite(s.sample_distance) || s.sample_distance < 1.0 / 16384.0 ||
        s.sample_distance > 2.0) {
        return invalid("sample_distance",
                       "sample distance must be finite and within [1/16384, 2]");
    }
    if (!std::isfinite(s.opacity_unit_distance) || s.opacity_unit_distance <= 0.0) {
        return invalid("opacity_unit_distance", "opacity unit distance must be finite and > 0");
    }
    if (!std::isfinite(s.early_termination) || s.early_termination <= 0.0 ||
        s.early_termination > 1.0) {
        return invalid("early_termination", "early ray termination must be within (0, 1]");
    }
    if (!finite(s.background)) {
        return invalid("background", "background colour must be finite");
    }
    const Camera& c = request.camera;
    if (!finite(c.eye) || !finite(c.target) || !finite(c.up) || !std::isfinite(c.fov_y_degrees)) {
        return invalid("camera", "camera vectors and field of view must be finite");
    }
    if (glm::length(c.target - c.eye) < 1e-9) {
        return invalid("camera", "camera eye and target must differ");
    }
    if (c.fov_y_degrees <= 0.1 || c.fov_y_degrees >= 179.0) {
        return invalid("camera.fov_y", "field of view must be within (0.1, 179) degrees");
    }
    const Light& l = request.light;
    if (!finite(l.direction) || !finite(l.position) || !finite(l.color) ||
        !std::isfinite(l.intensity) || !std::isfinite(l.ambient)) {
        return invalid("light", "light parameters must be finite");
    }
    if (l.type == LightType::directional && glm::length(l.direction) < 1e-9) {
        return invalid("light.direction", "a directional light needs a non-zero direction");
    }
    if (l.intensity < 0.0 || l.ambient < 0.0 || l.color.r < 0.0 || l.color.g < 0.0 ||
        l.color.b < 0.0) {
        return invalid("light", "light colour, intensity and ambient must not be negative");
    }
    const Shading& sh = s.shading;
    if (!std::isfinite(sh.diffuse) || !std::isfinite(sh.specular) || !std::isfinite(sh.shininess) ||
        sh.diffuse < 0.0 || sh.specular < 0.0 || sh.shininess < 1.0 || sh.shininess > 1024.0) {
        return invalid("shading", "diffuse/specular must be >= 0 and shininess within [1, 1024]");
    }
    const LightBufferSettings& lb = s.light_buffer;
    if (lb.slices < 1 || lb.slices > limits.max_slices) {
        return invalid("light_buffer.slices",
                       "slices must be within 1.." + std::to_string(limits.max_slices) +
                               " (this GPU's array-texture layer limit)");
    }
    if (lb.resolution < 1 || lb.resolution > limits.max_light_resolution) {
        return invalid("light_buffer.resolution",
                       "light-buffer resolution must be within 1.." +
                               std::to_string(limits.max_light_resolution));
    }
    if (!std::isfinite(lb.compensation) || lb.compensation < 0.0 || lb.compensation > 1000.0) {
        return invalid("light_buffer.compensation", "compensation must be within [0, 1000]");
    }
    if (lb.slab_samples < 0 || lb.slab_samples > kMaxSlabSamples) {
        return invalid("light_buffer.slab_samples",
                       "slab samples must be within 0.." + std::to_string(kMaxSlabSamples) +
                               " (0 = one per voxel)");
    }
    const ScatteringSettings& sc = s.scattering;
    if (!std::isfinite(sc.shell_radius) || sc.shell_radius <= 0.0 || sc.shell_radius > 0.5) {
        return invalid("scattering.shell_radius", "shell radius must be within (0, 0.5]");
    }
    if (sc.shell_rings < 1 || sc.shell_rings > 4) {
        return invalid("scattering.shell_rings", "shell rings must be within 1..4");
    }
    if (!std::isfinite(sc.shell_center_weight) || sc.shell_center_weight < 0.0 ||
        sc.shell_center_weight > 1.0) {
        return invalid("scattering.shell_center_weight", "weight must be within [0, 1]");
    }
    if (!std::isfinite(sc.cone_angle_degrees) || sc.cone_angle_degrees <= 0.0 ||
        sc.cone_angle_degrees > 80.0) {
        return invalid("scattering.cone_angle", "cone angle must be within (0, 80] degrees");
    }
    if (!std::isfinite(sc.cone_center_weight) || sc.cone_center_weight < 0.0 ||
        sc.cone_center_weight > 1.0) {
        return invalid("scattering.cone_center_weight", "weight must be within [0, 1]");
    }
    return validate(request.transfer_function);
}

}  // namespace penumbra::scene
