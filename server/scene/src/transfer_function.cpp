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

bool in_unit(double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; }

base::Error bad_point(const std::string& list, std::size_t index, const std::string& message) {
    return base::make_error("invalid_transfer_function", message,
                            "transfer_function." + list + "[" + std::to_string(index) + "]");
}

template <class Point>
base::Status validate_positions(const std::vector<Point>& points, const std::string& list) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!in_unit(points[i].x)) {
            return bad_point(list, i, "position must be finite and within [0, 1]");
        }
        if (i > 0 && points[i].x < points[i - 1].x) {
            return bad_point(list, i, "positions must not decrease");
        }
    }
    return base::Ok{};
}

TransferFunction make(std::string name, std::vector<ColorPoint> colors,
                      std::vector<OpacityPoint> opacities) {
    return TransferFunction{std::move(name), std::move(colors), std::move(opacities)};
}

}  // namespace

glm::dvec4 TransferFunction::evaluate(double x) const {
    const glm::dvec3 rgb = interpolate(colors, x, &ColorPoint::rgb, glm::dvec3(0.0));
    const double alpha = interpolate(opacities, x, &OpacityPoint::alpha, 0.0);
    return {rgb, alpha};
}

base::Status validate(const TransferFunction& tf) {
    if (auto status = validate_positions(tf.colors, "colors"); !status) {
        return status;
    }
    if (auto status = validate_positions(tf.opacities, "opacities"); !status) {
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

std::vector<glm::vec4> bake(const TransferFunction& tf, int size) {
    std::vector<glm::vec4> table(static_cast<std::size_t>(std::max(size, 1)));
    const double last = static_cast<double>(std::max(size - 1, 1));
    for (std::size_t i = 0; i < table.size(); ++i) {
        table[i] = glm::vec4(tf.evaluate(static_cast<double>(i) / last));
    }
    return table;
}

std::vector<std::string> preset_names() {
    return {"grey_ramp", "mri_skin", "mri_brain", "ct_skin", "ct_bone"};
}

base::Result<TransferFunction> preset(std::string_view name) {
    // Positions are fractions of the value range. The MRI presets were chosen on the Colin27 head
    // (values 0..254): air and noise below ~0.12, skin/scalp around 0.15-0.3, grey and white
    // matter 0.35-0.8. The CT presets assume a range of about -1024..3071 HU.
    if (name == "grey_ramp") {
        return make("grey_ramp", {{0.0, glm::dvec3(0.0)}, {1.0, glm::dvec3(1.0)}},
                    {{0.0, 0.0}, {1.0, 1.0}});
    }
    if (name == "mri_skin") {
        return make("mri_skin",
                    {{0.0, {0.55, 0.35, 0.25}}, {0.2, {0.93, 0.72, 0.6}}, {0.5, {0.98, 0.86, 0.78}},
                     {1.0, {1.0, 1.0, 1.0}}},
                    {{0.0, 0.0}, {0.12, 0.0}, {0.2, 0.6}, {1.0, 0.9}});
    }
    if (name == "mri_brain") {
        return make("mri_brain",
                    {{0.0, {0.2, 0.1, 0.1}}, {0.35, {0.75, 0.45, 0.4}}, {0.6, {0.95, 0.8, 0.7}},
                     {1.0, {1.0, 1.0, 0.95}}},
                    {{0.0, 0.0}, {0.3, 0.0}, {0.45, 0.05}, {0.7, 0.35}, {1.0, 0.6}});
    }
    if (name == "ct_skin") {
        // -1024..3071 HU: skin at about -500..0 HU.
        return make("ct_skin",
                    {{0.0, {0.6, 0.4, 0.3}}, {0.13, {0.9, 0.7, 0.6}}, {0.3, {1.0, 0.95, 0.9}},
                     {1.0, {1.0, 1.0, 1.0}}},
                    {{0.0, 0.0}, {0.12, 0.0}, {0.15, 0.5}, {0.3, 0.7}, {1.0, 0.9}});
    }
    if (name == "ct_bone") {
        // Bone from about 200 HU upward.
        return make("ct_bone",
                    {{0.0, {0.5, 0.3, 0.2}}, {0.3, {0.9, 0.8, 0.65}}, {0.5, {1.0, 0.98, 0.92}},
                     {1.0, {1.0, 1.0, 1.0}}},
                    {{0.0, 0.0}, {0.29, 0.0}, {0.33, 0.4}, {0.5, 0.85}, {1.0, 1.0}});
    }
    std::string known;
    for (const auto& n : preset_names()) {
        known += (known.empty() ? "" : ", ") + n;
    }
    return base::make_error("unknown_preset",
                            "unknown transfer-function preset '" + std::string(name) +
                                    "' (known: " + known + ")",
                            "transfer_function");
}

}  // namespace penumbra::scene
