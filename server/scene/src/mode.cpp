#include <penumbra/scene/frame_request.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace penumbra::scene {
namespace {

base::Error invalid(const std::string& field, const std::string& message) {
    return base::make_error(base::ErrorCode::invalid_value, message, field);
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

bool refines_after(int step, std::optional<double> change, int max_steps, double threshold) {
    if (step >= max_steps) {
        return false;
    }
    return !change || threshold <= 0.0 || *change > threshold;
}

FrameRequest refinement_step_request(const FrameRequest& still, int step) {
    FrameRequest request = still;
    request.settings.sample_distance = std::max(
            setting::sample_distance.min, still.settings.sample_distance * kRefinementStepShare);
    request.refinement = {step == 1, step - 1};
    return request;
}

ImageWindow image_window(const FrameRequest& request) {
    const Tile& t = request.tile;
    if (t.whole()) {
        return {};
    }
    const RenderSettings& s = request.settings;
    const glm::dvec2 image(t.image_width, t.image_height);
    const glm::dvec2 size(s.width, s.height);
    // A frame pixel p maps to image pixel tile + p: image ndc x = (2 (x + p) + 1) / W - 1, and y
    // the same from the top down.
    const glm::dvec2 centre = (2.0 * glm::dvec2(t.x, t.y) + size) / image - 1.0;
    return {size / image, {centre.x, -centre.y}};
}

CameraFrame pixel_frame(const FrameRequest& request) {
    const Tile& t = request.tile;
    const RenderSettings& s = request.settings;
    const double aspect = t.whole() ? static_cast<double>(s.width) / s.height
                                    : static_cast<double>(t.image_width) / t.image_height;
    CameraFrame frame = camera_frame(request.camera, aspect);
    const ImageWindow window = image_window(request);
    frame.forward += window.offset.x * frame.right + window.offset.y * frame.up;
    frame.right *= window.scale.x;
    frame.up *= window.scale.y;
    return frame;
}

std::vector<FrameRequest> image_tiles(const FrameRequest& whole, int tile_side) {
    std::vector<FrameRequest> tiles;
    if (tile_side < 1 || !whole.tile.whole()) {
        return tiles;
    }
    const int width = whole.settings.width;
    const int height = whole.settings.height;
    for (int y = 0; y < height; y += tile_side) {
        for (int x = 0; x < width; x += tile_side) {
            FrameRequest& tile = tiles.emplace_back(whole);
            tile.settings.width = std::min(tile_side, width - x);
            tile.settings.height = std::min(tile_side, height - y);
            tile.tile = {width, height, x, y};
        }
    }
    return tiles;
}

FrameRequest starting_frame(const Limits& limits) {
    FrameRequest frame;
    frame.camera = Camera{};
    frame.light.direction = direction_from_angles(10.0, 45.0);
    RenderSettings& s = frame.settings;
    s.mode = Mode::sbrc;
    s.phong = true;
    s.jitter = true;
    s.width = std::min(512, limits.max_image_side);
    s.height = s.width;
    s.light_buffer.slices = std::min(128, limits.max_slices);
    s.light_buffer.resolution =
            std::min(LightBufferSettings{}.resolution, limits.max_light_resolution);
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
    for (const Setting* setting : kSettings) {
        if (setting->in_frame()) {
            if (auto status = validate_value(*setting, setting->read_frame(request), limits);
                !status) {
                return status;
            }
        }
    }
    const CropBox& crop = request.cut.crop;
    for (int axis = 0; axis < 3; ++axis) {
        if (!(crop.min[axis] < crop.max[axis])) {
            return invalid("cut.crop",
                           "the crop box's min must lie below its max on every axis (an inverted "
                           "or empty box); to draw nothing, move the box off the volume");
        }
    }
    for (std::size_t i = 0; i < request.cut.planes.size(); ++i) {
        if (glm::length(request.cut.planes[i].normal) < 1e-9) {
            return invalid("cut.plane_" + std::to_string(i + 1) + ".normal",
                           "a clip plane needs a non-zero normal");
        }
    }
    if (const Tile& t = request.tile; !t.whole()) {
        if (t.image_width < 1 || t.image_height < 1 || t.image_width > kMaxTiledImageSide ||
            t.image_height > kMaxTiledImageSide) {
            return invalid("tile", "a tiled image's sides must lie within 1.." +
                                           std::to_string(kMaxTiledImageSide));
        }
        if (t.x < 0 || t.y < 0 || t.x + s.width > t.image_width ||
            t.y + s.height > t.image_height) {
            return invalid("tile", "a tile must lie inside its image");
        }
    }
    const Camera& c = request.camera;
    if (glm::length(c.target - c.eye) < 1e-9) {
        return invalid("camera", "camera eye and target must differ");
    }
    const Light& l = request.light;
    if (l.type == LightType::directional && glm::length(l.direction) < 1e-9) {
        return invalid("light.direction", "a directional light needs a non-zero direction");
    }
    if (auto status = validate(request.labels); !status) {
        return status;
    }
    return validate(request.transfer_function);
}

base::Status validate_value(const Setting& setting, SettingValue value, const Limits& limits) {
    const double max = setting.max_under(limits);
    const auto within = [&](double component) {
        return component >= setting.min && component <= max;
    };
    bool ok = true;
    switch (setting.kind) {
        case SettingKind::number:
        case SettingKind::whole:
        case SettingKind::boolean:
        case SettingKind::choice:
            ok = within(value.x);
            break;
        case SettingKind::vector:
            ok = within(value.x) && within(value.y) && within(value.z);
            break;
        case SettingKind::size:
            ok = within(value.x) && within(value.y);
            break;
    }
    if (!ok) {
        const bool components =
                setting.kind == SettingKind::vector || setting.kind == SettingKind::size;
        return invalid(field_name(setting.path), std::string(setting.path) +
                                                         (components ? " components" : "") +
                                                         " must be " + setting.describe(limits));
    }
    return base::Ok{};
}

namespace {

// The side of an interactive frame: half the still's, at least 64 pixels (or the still's own).
int interactive_side(int side) {
    return std::max(std::min(side, 64), side / 2);
}

}  // namespace

std::pair<FrameRequest, std::string> interactive_request(const FrameRequest& full) {
    FrameRequest reduced = full;
    RenderSettings& s = reduced.settings;
    s.width = interactive_side(full.settings.width);
    s.height = interactive_side(full.settings.height);
    s.sample_distance = std::min(0.5, full.settings.sample_distance * 2.0);
    s.light_buffer.resolution = interactive_side(full.settings.light_buffer.resolution);
    const std::string description =
            "interactive: " + std::to_string(s.width) + "x" + std::to_string(s.height) +
            ", sample distance x2, light buffer " + std::to_string(s.light_buffer.resolution);
    return {std::move(reduced), description};
}

std::optional<FrameRequest> still_preview(const FrameRequest& still, double expected_ms,
                                          double budget_ms) {
    if (!(expected_ms > budget_ms) || !(budget_ms > 0.0)) {
        return std::nullopt;
    }
    const double scale = std::sqrt(budget_ms / expected_ms);
    FrameRequest preview = still;
    RenderSettings& s = preview.settings;
    const auto shrink = [scale](int side) {
        return std::max(interactive_side(side), static_cast<int>(std::lround(side * scale)));
    };
    s.width = shrink(still.settings.width);
    s.height = shrink(still.settings.height);
    // After the floor: a small still's preview would be nearly the still.
    const double pixels = static_cast<double>(s.width) * s.height;
    if (pixels > kStillPreviewMostPixels * still.settings.width * still.settings.height) {
        return std::nullopt;
    }
    return preview;
}

}  // namespace penumbra::scene
