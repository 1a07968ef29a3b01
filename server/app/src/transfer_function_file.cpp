#include "transfer_function_file.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace penumbra::app {
namespace {

using nlohmann::json;

base::Error bad(const std::string& where, const std::string& message) {
    return base::make_error("invalid_transfer_function", message, where);
}

base::Result<double> number_at(const json& object, const char* key, const std::string& where) {
    if (!object.is_object() || !object.contains(key) || !object[key].is_number()) {
        return bad(where + "." + key, "expected a number");
    }
    return object[key].get<double>();
}

}  // namespace

base::Result<scene::TransferFunction> parse_transfer_function_json(const std::string& text,
                                                                   const volume::ValueRange& range,
                                                                   const std::string& where) {
    const json document = json::parse(text, nullptr, false);
    if (document.is_discarded() || !document.is_object()) {
        return bad(where, "not a JSON object");
    }
    scene::TransferFunction tf;
    tf.name = document.value("name", std::string("custom"));
    const std::string space = document.value("space", std::string("normalized"));
    if (space != "normalized" && space != "data") {
        return bad(where + ".space", "must be \"normalized\" or \"data\"");
    }
    const double width = range.max - range.min;
    const auto position = [&](double x) {
        return space == "data" ? (width > 0.0 ? (x - range.min) / width : 0.0) : x;
    };
    const json colors = document.value("colors", json::array());
    const json opacities = document.value("opacities", json::array());
    if (!colors.is_array() || !opacities.is_array()) {
        return bad(where, "\"colors\" and \"opacities\" must be arrays");
    }
    for (std::size_t i = 0; i < colors.size(); ++i) {
        const std::string at = where + ".colors[" + std::to_string(i) + "]";
        auto x = number_at(colors[i], "x", at);
        if (!x) {
            return x.error();
        }
        const json& rgb = colors[i].value("rgb", json());
        if (!rgb.is_array() || rgb.size() != 3 || !rgb[0].is_number() || !rgb[1].is_number() ||
            !rgb[2].is_number()) {
            return bad(at + ".rgb", "expected three numbers");
        }
        tf.colors.push_back({position(*x), {rgb[0].get<double>(), rgb[1].get<double>(),
                                            rgb[2].get<double>()}});
    }
    for (std::size_t i = 0; i < opacities.size(); ++i) {
        const std::string at = where + ".opacities[" + std::to_string(i) + "]";
        auto x = number_at(opacities[i], "x", at);
        if (!x) {
            return x.error();
        }
        auto alpha = number_at(opacities[i], "alpha", at);
        if (!alpha) {
            return alpha.error();
        }
        tf.opacities.push_back({position(*x), *alpha});
    }
    if (auto status = scene::validate(tf); !status) {
        base::Error error = status.error();
        error.where = where + ": " + error.where;
        return error;
    }
    return tf;
}

base::Result<scene::TransferFunction> load_transfer_function(const std::string& preset_or_path,
                                                             const volume::ValueRange& range) {
    if (preset_or_path.size() < 5 ||
        preset_or_path.compare(preset_or_path.size() - 5, 5, ".json") != 0) {
        return scene::preset(preset_or_path);
    }
    std::ifstream in(preset_or_path);
    if (!in) {
        return base::make_error("not_found", "cannot read the transfer-function file",
                                preset_or_path);
    }
    std::stringstream text;
    text << in.rdbuf();
    return parse_transfer_function_json(text.str(), range, preset_or_path);
}

}  // namespace penumbra::app
