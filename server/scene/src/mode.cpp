#include <penumbra/scene/frame_request.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace penumbra::scene {
namespace {

bool finite(glm::dvec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

base::Error invalid(const std::string& field, const std::string& message) {
    return base::make_error("invalid_value", message, field);
}

// "settings/light_buffer/compensation" -> "light_buffer.compensation", as validate names fields.
std::string field_name(std::string_view path) {
    std::string name(path.starts_with("settings/") ? path.substr(9) : path);
    std::replace(name.begin(), name.end(), '/', '.');
    return name;
}

}  // namespace

const char* to_string(Mode mode) {
    return describe(mode).name.data();
}

std::optional<Mode> parse_mode(std::string_view text) {
    for (const ModeInfo& info : kModes) {
        if (text == info.name) {
            return info.mode;
        }
    }
    return std::nullopt;
}

std::string mode_names(std::string_view separator) {
    std::string names;
    for (const ModeInfo& info : kModes) {
        if (!names.empty()) {
            names += separator;
        }
        names += info.name;
    }
    return names;
}

bool uses_gradients(const RenderSettings& settings) {
    switch (describe(settings.mode).gradients) {
        case Gradients::never:
            return false;
        case Gradients::with_phong:
            return settings.phong;
        case Gradients::always:
            return true;
    }
    return false;
}

bool is_ray_cast(Mode mode) {
    return mode != Mode::half_angle;
}

FrameRequest starting_frame(const Limits& limits) {
    FrameRequest frame;
    frame.camera = Camera{};
    frame.light.direction = direction_from_angles(10.0, 45.0);
    RenderSettings& s = frame.settings;
    s.mode = Mode::sbrc;
    s.phong = true;
    s.width = std::min(512, limits.max_image_side);
    s.height = s.width;
    s.light_buffer.slices = std::min(128, limits.max_slices);
    s.light_buffer.resolution = std::min(256, limits.max_light_resolution);
    return frame;
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
    const auto check_vec3 = [](glm::dvec3 v, const SettingRange& range) {
        return range.contains(v.x) && range.contains(v.y) && range.contains(v.z);
    };
    for (const SettingRange* range : kSettingRanges) {
        if (range->read != nullptr && !range->contains(range->read(request))) {
            return invalid(field_name(range->field),
                           std::string(range->field) + " must be " + range->describe());
        }
    }
    if (!check_vec3(s.background, setting::colour)) {
        return invalid("background",
                       "background colour channels must be " + setting::colour.describe());
    }
    const Camera& c = request.camera;
    if (!check_vec3(c.eye, setting::coordinate) || !check_vec3(c.target, setting::coordinate) ||
        !finite(c.up)) {
        return invalid("camera", "camera eye and target coordinates must be " +
                                         setting::coordinate.describe() + ", up finite");
    }
    if (glm::length(c.target - c.eye) < 1e-9) {
        return invalid("camera", "camera eye and target must differ");
    }
    const Light& l = request.light;
    if (!finite(l.direction) || !check_vec3(l.position, setting::coordinate)) {
        return invalid("light", "light direction must be finite, its position " +
                                        setting::coordinate.describe());
    }
    if (!check_vec3(l.color, setting::colour)) {
        return invalid("light.color",
                       "light colour channels must be " + setting::colour.describe());
    }
    if (l.type == LightType::directional && glm::length(l.direction) < 1e-9) {
        return invalid("light.direction", "a directional light needs a non-zero direction");
    }
    const LightBufferSettings& lb = s.light_buffer;
    if (lb.slices < 1 || lb.slices > limits.max_slices) {
        return invalid("light_buffer.slices", "slices must be within 1.." +
                                                      std::to_string(limits.max_slices) +
                                                      " (this GPU's array-texture layer limit)");
    }
    if (lb.resolution < 1 || lb.resolution > limits.max_light_resolution) {
        return invalid("light_buffer.resolution",
                       "light-buffer resolution must be within 1.." +
                               std::to_string(limits.max_light_resolution));
    }
    return validate(request.transfer_function);
}

}  // namespace penumbra::scene
