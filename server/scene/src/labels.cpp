#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/labels.hpp>

#include <algorithm>
#include <string>
#include <unordered_set>

namespace penumbra::scene {
namespace {

base::Error invalid(const std::string& where, std::string message) {
    return base::make_error(base::ErrorCode::invalid_value, std::move(message), where);
}

bool fraction(double value) {
    return value >= 0.0 && value <= 1.0;
}

}  // namespace

base::Status validate(const Labels& labels) {
    if (!fraction(labels.blend)) {
        return invalid("labels.blend", "the label colours' blend must lie within 0..1");
    }
    if (labels.styles.size() > kMaxStyledLabels) {
        return invalid("labels",
                       "at most " + std::to_string(kMaxStyledLabels) + " labels can be styled");
    }
    std::unordered_set<std::int64_t> ids;
    for (const LabelStyle& style : labels.styles) {
        const std::string where = "labels.styles." + std::to_string(style.id);
        if (!ids.insert(style.id).second) {
            return invalid(where, "label " + std::to_string(style.id) + " is styled twice");
        }
        if (!fraction(style.opacity)) {
            return invalid(where + ".opacity", "a label's opacity must lie within 0..1");
        }
        if (!fraction(style.color.r) || !fraction(style.color.g) || !fraction(style.color.b)) {
            return invalid(where + ".color", "a label's colour components must lie within 0..1");
        }
    }
    return base::Ok{};
}

base::Status check_styles_match(const Labels& labels, std::span<const std::int64_t> ids) {
    if (labels.styles.size() != ids.size()) {
        return base::make_error(base::ErrorCode::invalid_frame,
                                "the frame styles " + std::to_string(labels.styles.size()) +
                                        " labels; the label map holds " +
                                        std::to_string(ids.size()),
                                "labels");
    }
    for (std::size_t i = 0; i < ids.size(); ++i) {
        if (labels.styles[i].id != ids[i]) {
            return base::make_error(base::ErrorCode::invalid_frame,
                                    "the frame's label styles are not the label map's labels in "
                                    "its order (style " +
                                            std::to_string(i + 1) + " is label " +
                                            std::to_string(labels.styles[i].id) + ", not " +
                                            std::to_string(ids[i]) + ")",
                                    "labels");
        }
    }
    return base::Ok{};
}

TransferFunction label_surface_transfer_function() {
    TransferFunction tf;
    tf.name = "label_surfaces";
    tf.colors = {{0.0, glm::dvec3(1.0)}, {1.0, glm::dvec3(1.0)}};
    tf.opacities = {{0.0, 0.0}, {0.2, 0.0}, {0.35, 1.0}, {1.0, 1.0}};
    return tf;
}

std::vector<bool> visibility(const Labels& labels) {
    std::vector<bool> visible;
    visible.reserve(labels.styles.size());
    for (const LabelStyle& style : labels.styles) {
        visible.push_back(style.visible);
    }
    return visible;
}

FrameRequest labels_alone_request(FrameRequest request) {
    request.transfer_function = label_surface_transfer_function();
    request.labels.blend = 1.0;
    return request;
}

}  // namespace penumbra::scene
