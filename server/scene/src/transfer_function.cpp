#include "penumbra/scene/transfer_function.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace penumbra::scene {
namespace {

template <class Point, class Value>
Value interpolate(const std::vector<Point>& points, double x, Value Point::*member, Value empty) {
    if (points.empty()) {
        return empty;
    }
    if (x <= points.front().x) {
        return points.front().*member;
    }
    if (x >= points.back().x) {
        return points.back().*member;
    }
    const auto upper = std::upper_bound(points.begin(), points.end(), x,
                                        [](double v, const Point& p) { return v < p.x; });
    const auto lower = upper - 1;
    const double width = upper->x - lower->x;
    const double t = width > 0.0 ? (x - lower->x) / width : 1.0;
    return glm::mix((*lower).*member, (*upper).*member, t);
}

bool in_unit(double v) {
    return std::isfinite(v) && v >= 0.0 && v <= 1.0;
}

base::Error bad_point(const std::string& list, std::size_t index, const std::string& message) {
    return base::make_error(base::ErrorCode::invalid_transfer_function, message,
                            "transfer_function." + list + "[" + std::to_string(index) + "]");
}

template <class Point>
base::Status validate_positions(const std::vector<Point>& points, PositionSpace space,
                                const std::string& list) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (space == PositionSpace::normalized && !in_unit(points[i].x)) {
            return bad_point(list, i, "position must be finite and within [0, 1]");
        }
        if (space == PositionSpace::hounsfield &&
            !(std::isfinite(points[i].x) && std::abs(points[i].x) <= max_hounsfield_position)) {
            return bad_point(list, i,
                             "position must be finite and within +-" +
                                     std::to_string(static_cast<int>(max_hounsfield_position)) +
                                     " HU");
        }
        if (i > 0 && points[i].x < points[i - 1].x) {
            return bad_point(list, i, "positions must not decrease");
        }
    }
    return base::Ok{};
}

TransferFunction make(std::string name, std::vector<ColorPoint> colors,
                      std::vector<OpacityPoint> opacities) {
    return TransferFunction{std::move(name), std::move(colors), std::move(opacities),
                            PositionSpace::normalized};
}

// A CT preset: positions in Hounsfield units.
TransferFunction make_hu(std::string name, std::vector<ColorPoint> colors,
                         std::vector<OpacityPoint> opacities) {
    return TransferFunction{std::move(name), std::move(colors), std::move(opacities),
                            PositionSpace::hounsfield};
}

}  // namespace

glm::dvec4 TransferFunction::evaluate(double x) const {
    const glm::dvec3 rgb = interpolate(colors, x, &ColorPoint::rgb, glm::dvec3(0.0));
    const double alpha = interpolate(opacities, x, &OpacityPoint::alpha, 0.0);
    return {rgb, alpha};
}

base::Status validate(const TransferFunction& tf) {
    if (auto status = validate_positions(tf.colors, tf.space, "colors"); !status) {
        return status;
    }
    if (auto status = validate_positions(tf.opacities, tf.space, "opacities"); !status) {
        return status;
    }
    for (std::size_t i = 0; i < tf.colors.size(); ++i) {
        const glm::dvec3 c = tf.colors[i].rgb;
        if (!in_unit(c.r) || !in_unit(c.g) || !in_unit(c.b)) {
            return bad_point("colors", i, "colour components must be within [0, 1]");
        }
    }
    for (std::size_t i = 0; i < tf.opacities.size(); ++i) {
        if (!in_unit(tf.opacities[i].alpha)) {
            return bad_point("opacities", i, "opacity must be within [0, 1]");
        }
    }
    return base::Ok{};
}

std::vector<glm::vec4> bake(const TransferFunction& tf, int size, const ValueDomain& values) {
    std::vector<glm::vec4> table(static_cast<std::size_t>(std::max(size, 1)));
    const double last = static_cast<double>(std::max(size - 1, 1));
    const ValueDomain& domain = values.hounsfield ? values : nominal_ct_domain;
    for (std::size_t i = 0; i < table.size(); ++i) {
        const double t = static_cast<double>(i) / last;
        const double x = tf.space == PositionSpace::normalized
                                 ? t
                                 : domain.min + t * (domain.max - domain.min);
        table[i] = glm::vec4(tf.evaluate(x));
    }
    return table;
}

std::vector<std::string> preset_names() {
    std::vector<std::string> names{"grey_ramp", "mri_skin", "mri_brain"};
    for (auto& name : hounsfield_preset_names()) {
        names.push_back(std::move(name));
    }
    return names;
}

std::vector<std::string> hounsfield_preset_names() {
    return {"ct_bone", "ct_skin", "ct_soft_tissue", "ct_lung", "ct_angio"};
}

base::Result<TransferFunction> preset(std::string_view name) {
    // The MRI presets are fractions of the value range, chosen on the Colin27 head (values
    // 0..254): air and noise below ~0.12, skin/scalp around 0.15-0.3, grey and white matter
    // 0.35-0.8.
    if (name == "grey_ramp") {
        return make("grey_ramp", {{0.0, glm::dvec3(0.0)}, {1.0, glm::dvec3(1.0)}},
                    {{0.0, 0.0}, {1.0, 1.0}});
    }
    if (name == "mri_skin") {
        return make("mri_skin",
                    {{0.0, {0.55, 0.35, 0.25}},
                     {0.2, {0.93, 0.72, 0.6}},
                     {0.5, {0.98, 0.86, 0.78}},
                     {1.0, {1.0, 1.0, 1.0}}},
                    {{0.0, 0.0}, {0.12, 0.0}, {0.2, 0.6}, {1.0, 0.9}});
    }
    if (name == "mri_brain") {
        return make("mri_brain",
                    {{0.0, {0.2, 0.1, 0.1}},
                     {0.35, {0.75, 0.45, 0.4}},
                     {0.6, {0.95, 0.8, 0.7}},
                     {1.0, {1.0, 1.0, 0.95}}},
                    {{0.0, 0.0}, {0.3, 0.0}, {0.45, 0.05}, {0.7, 0.35}, {1.0, 0.6}});
    }
    // The CT presets in Hounsfield units: air -1000, lung -900..-500, fat -100..-50, soft tissue
    // and blood 20..80, contrast-filled vessels 150..500, bone 300 upward (cortical bone above
    // 1000).
    if (name == "ct_bone") {
        // Nothing below 150 HU (soft tissue, fat, air); bone opaque from 300 HU upward.
        return make_hu("ct_bone",
                       {{150.0, {0.75, 0.55, 0.4}},
                        {300.0, {0.93, 0.85, 0.72}},
                        {700.0, {1.0, 0.98, 0.92}},
                        {3000.0, {1.0, 1.0, 1.0}}},
                       {{150.0, 0.0}, {300.0, 0.6}, {700.0, 0.9}, {3000.0, 1.0}});
    }
    if (name == "ct_skin") {
        // The skin's surface against air at about -500 HU; everything denser stays opaque.
        return make_hu("ct_skin",
                       {{-1000.0, {0.6, 0.4, 0.3}},
                        {-500.0, {0.9, 0.7, 0.6}},
                        {200.0, {1.0, 0.95, 0.9}},
                        {3000.0, {1.0, 1.0, 1.0}}},
                       {{-600.0, 0.0}, {-400.0, 0.5}, {100.0, 0.7}, {3000.0, 0.9}});
    }
    if (name == "ct_soft_tissue") {
        // Fat faint and yellow, muscle and organs red, bone white and half transparent.
        return make_hu(
                "ct_soft_tissue",
                {{-150.0, {0.9, 0.8, 0.5}}, {40.0, {0.8, 0.3, 0.25}}, {300.0, {1.0, 0.95, 0.85}}},
                {{-200.0, 0.0},
                 {-100.0, 0.05},
                 {0.0, 0.05},
                 {40.0, 0.25},
                 {80.0, 0.3},
                 {200.0, 0.15},
                 {300.0, 0.4},
                 {1000.0, 0.6}});
    }
    if (name == "ct_lung") {
        // The lung's parenchyma and the vessels and airway walls within it; the chest wall and
        // everything denser transparent.
        return make_hu("ct_lung", {{-950.0, {0.85, 0.5, 0.45}}, {-450.0, {1.0, 0.8, 0.75}}},
                       {{-950.0, 0.0}, {-750.0, 0.1}, {-450.0, 0.3}, {-350.0, 0.0}});
    }
    if (name == "ct_angio") {
        // Contrast-filled vessels red from about 150 HU, bone white above 700.
        return make_hu(
                "ct_angio",
                {{150.0, {0.8, 0.1, 0.1}}, {400.0, {1.0, 0.5, 0.4}}, {1000.0, {1.0, 0.97, 0.92}}},
                {{100.0, 0.0}, {180.0, 0.5}, {400.0, 0.8}, {3000.0, 0.9}});
    }
    std::string known;
    for (const auto& n : preset_names()) {
        known += (known.empty() ? "" : ", ") + n;
    }
    return base::make_error(
            base::ErrorCode::unknown_preset,
            "unknown transfer-function preset '" + std::string(name) + "' (known: " + known + ")",
            "transfer_function");
}

}  // namespace penumbra::scene
