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

base::Status validate(const FrameRequest& request, int max_image_side) {
    const RenderSettings& s = request.settings;
    if (s.width < 1 || s.height < 1 || s.width > max_image_side || s.height > max_image_side) {
        return invalid("size", "image size must be within 1.." + std::to_string(max_image_side) +
                                       " pixels per side");
    }
    // A ray needs at least one sample per voxel layer it could cross to be meaningful, and a
    // million samples per unit is more than any GPU can march in a frame.
    if (!std::isfinite(s.sample_distance) || s.sample_distance < 1e-6 || s.sample_distance > 2.0) {
        return invalid("sample_distance", "sample distance must be finite and within [1e-6, 2]");
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
    return validate(request.transfer_function);
}

}  // namespace penumbra::scene
