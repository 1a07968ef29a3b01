#include "penumbra/quality/table_json.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>
#include <utility>

namespace penumbra::quality {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* table_format = "penumbra-accuracy-1";

// Deeper than any table: a document nested beyond this is refused before it is parsed.
constexpr int max_depth = 16;

// JSON has no infinity: an identical image's PSNR is null.
Json psnr_json(double psnr) {
    return std::isinf(psnr) ? Json(nullptr) : Json(psnr);
}

Json camera_json(const scene::Camera& c) {
    return {{"eye", {c.eye.x, c.eye.y, c.eye.z}},
            {"target", {c.target.x, c.target.y, c.target.z}},
            {"up", {c.up.x, c.up.y, c.up.z}},
            {"fov_y_degrees", c.fov_y_degrees}};
}

Json point_json(const Point& p) {
    return {{"volume", p.volume},
            {"light", {p.light.azimuth, p.light.elevation}},
            {"mode", scene::to_string(p.mode)},
            {"slices", p.slices},
            {"resolution", p.resolution},
            {"sample_distance", p.sample_distance},
            {"empty_space_skipping", p.empty_space_skipping},
            {"jitter", p.jitter},
            {"refinement_steps", p.refinement_steps},
            {"frame_ms", p.frame_ms},
            {"light_buffer_ms", p.light_buffer_ms},
            {"rmse_truth", p.rmse_truth},
            {"psnr_truth", psnr_json(p.psnr_truth)},
            {"ssim_truth", p.ssim_truth},
            {"rmse", p.rmse},
            {"psnr", psnr_json(p.psnr)},
            {"ssim", p.ssim}};
}

// The reference mode, jittered, at this distance over this many frames; null: the reference at
// the finest sample distance swept.
Json truth_json(const std::optional<TruthMethod>& truth) {
    if (!truth) {
        return nullptr;
    }
    return {{"sample_distance", truth->sample_distance}, {"frames", truth->frames}};
}

Json preset_json(const Preset& preset) {
    if (!preset.setting) {
        return {{"budget_ms", preset.budget_ms}, {"mode", nullptr}};
    }
    const Setting& s = *preset.setting;
    return {{"budget_ms", preset.budget_ms},
            {"mode", scene::to_string(s.key.mode)},
            {"slices", s.key.slices},
            {"resolution", s.key.resolution},
            {"sample_distance", s.key.sample_distance},
            {"empty_space_skipping", s.key.empty_space_skipping},
            {"psnr", psnr_json(s.psnr_truth)},
            {"ssim", s.ssim_truth},
            {"frame_ms", s.worst_frame_ms},
            {"light_buffer_ms", s.light_buffer_ms}};
}

// A reading error: the JSON pointer of the member and what is wrong with it.
struct Malformed {
    std::string pointer;
    std::string message;
};

// Reads members with their JSON pointers, throwing Malformed (caught in parse_table only).
struct Field {
    const Json& value;
    std::string pointer;

    Field operator[](const char* key) const {
        if (!value.is_object()) {
            throw Malformed{pointer, "expected an object"};
        }
        const auto found = value.find(key);
        if (found == value.end()) {
            throw Malformed{pointer + "/" + key, std::string("missing '") + key + "'"};
        }
        return {*found, pointer + "/" + key};
    }

    Field at(std::size_t index) const {
        if (!value.is_array() || index >= value.size()) {
            throw Malformed{pointer, "expected an array of at least " + std::to_string(index + 1) +
                                             " elements"};
        }
        return {value[index], pointer + "/" + std::to_string(index)};
    }

    [[nodiscard]] bool has(const char* key) const {
        return value.is_object() && value.contains(key);
    }

    [[nodiscard]] std::string text() const {
        if (!value.is_string()) {
            throw Malformed{pointer, "expected a string"};
        }
        return value.get<std::string>();
    }

    [[nodiscard]] bool boolean() const {
        if (!value.is_boolean()) {
            throw Malformed{pointer, "expected true or false"};
        }
        return value.get<bool>();
    }

    [[nodiscard]] double number() const {
        if (!value.is_number() || !std::isfinite(value.get<double>())) {
            throw Malformed{pointer, "expected a finite number"};
        }
        return value.get<double>();
    }

    [[nodiscard]] int whole(int min = 0) const {
        if (!value.is_number_integer() || value.get<std::int64_t>() < min ||
            value.get<std::int64_t>() > std::numeric_limits<int>::max()) {
            throw Malformed{pointer, "expected an integer of at least " + std::to_string(min)};
        }
        return static_cast<int>(value.get<std::int64_t>());
    }

    // null: infinite (an identical image).
    [[nodiscard]] double psnr() const { return value.is_null() ? infinity : number(); }

    [[nodiscard]] glm::dvec3 vec3() const {
        return {at(0).number(), at(1).number(), at(2).number()};
    }
};

scene::Camera camera_from(const Field& field) {
    scene::Camera camera;
    camera.eye = field["eye"].vec3();
    camera.target = field["target"].vec3();
    camera.up = field["up"].vec3();
    camera.fov_y_degrees = field["fov_y_degrees"].number();
    return camera;
}

// Nothing for a mode this build does not know.
std::optional<Point> point_from(const Field& field) {
    const auto mode = scene::parse_mode(field["mode"].text());
    if (!mode) {
        return std::nullopt;
    }
    Point p;
    p.volume = field["volume"].text();
    p.light = {field["light"].at(0).number(), field["light"].at(1).number()};
    p.mode = *mode;
    p.slices = field["slices"].whole();
    p.resolution = field["resolution"].whole();
    p.sample_distance = field["sample_distance"].number();
    if (!(p.sample_distance > 0.0)) {
        throw Malformed{field.pointer + "/sample_distance", "expected a positive number"};
    }
    // Points written before skipping, jitter and refinement existed were measured without them.
    p.empty_space_skipping =
            field.has("empty_space_skipping") && field["empty_space_skipping"].boolean();
    p.jitter = field.has("jitter") && field["jitter"].boolean();
    p.refinement_steps = field.has("refinement_steps") ? field["refinement_steps"].whole() : 0;
    if (p.refinement_steps > scene::kMaxRefinementSteps) {
        throw Malformed{field.pointer + "/refinement_steps",
                        "expected at most " + std::to_string(scene::kMaxRefinementSteps)};
    }
    if (p.refinement_steps > 0 && !p.jitter) {
        throw Malformed{field.pointer + "/refinement_steps",
                        "refinement steps average jittered frames: expected jitter true"};
    }
    p.frame_ms = field["frame_ms"].number();
    p.light_buffer_ms = field["light_buffer_ms"].number();
    p.rmse = field["rmse"].number();
    p.psnr = field["psnr"].psnr();
    p.ssim = field["ssim"].number();
    // Tables written before the converged truth compared with the finest reference under these
    // names; that reference was their truth.
    const bool old_names = !field.has("psnr_truth");
    p.rmse_truth = field[old_names ? "rmse_finest" : "rmse_truth"].number();
    p.psnr_truth = field[old_names ? "psnr_finest" : "psnr_truth"].psnr();
    p.ssim_truth = field[old_names ? "ssim_finest" : "ssim_truth"].number();
    return p;
}

Table table_from(const Field& root) {
    if (!root.has("format") || root["format"].value != table_format) {
        throw Malformed{"/format", std::string("not an accuracy table (format \"") + table_format +
                                           "\", as `bench accuracy --json` "
                                           "writes)"};
    }
    Table table;
    table.device = root["device"].text();
    const Field renderer = root["renderer"];
    table.vendor = renderer["vendor"].text();
    table.gl_version = renderer["version"].text();
    table.gpu_timers = renderer["gpu_timer_queries"].boolean();
    table.width = root["size"].at(0).whole(1);
    table.height = root["size"].at(1).whole(1);
    const Field settings = root["settings"];
    table.transfer_function = settings["transfer_function"].text();
    table.compositing = settings["compositing"].text();
    table.stage = settings["stage"].text();
    table.builder = settings["builder"].text();
    // Tables written before these settings existed were measured the paper's way.
    table.light_lookup = settings.has("light_lookup") ? settings["light_lookup"].text()
                                                      : std::string("interpolate");
    table.slab_samples = settings.has("slab_samples") ? settings["slab_samples"].whole() : 1;
    table.phong = settings["phong"].boolean();
    table.repeat = settings["repeat"].whole();
    table.camera = camera_from(settings["camera"]);
    if (settings.has("truth") && !settings["truth"].value.is_null()) {
        const Field truth = settings["truth"];
        table.truth = TruthMethod{truth["sample_distance"].number(), truth["frames"].whole(1)};
        if (!(table.truth->sample_distance > 0.0)) {
            throw Malformed{truth.pointer + "/sample_distance", "expected a positive number"};
        }
    }
    const Field points = root["points"];
    if (!points.value.is_array()) {
        throw Malformed{points.pointer, "expected an array"};
    }
    for (std::size_t i = 0; i < points.value.size(); ++i) {
        if (auto point = point_from(points.at(i))) {
            table.points.push_back(std::move(*point));
        }
    }
    return table;
}

// The nesting depth of a JSON text, strings skipped; a malformed text is the parser's to judge.
int nesting_depth(std::string_view text) {
    int depth = 0;
    int deepest = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') {
                ++i;
            } else if (c == '"') {
                in_string = false;
            }
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return deepest;
}

}  // namespace

std::string table_json(const Table& table, const std::vector<Preset>& presets) {
    Json root;
    root["format"] = table_format;
    root["description"] =
            "Accuracy vs frame time of Penumbra's rendering modes (penumbra bench accuracy). "
            "points: one per volume x light x mode x setting; *_truth (rmse, psnr, ssim) "
            "against the truth (settings.truth: the reference mode, shadow rays, at that sample "
            "distance, jittered, the mean of that many frames; null: the reference at the "
            "finest sample distance swept), rmse/psnr/ssim against the reference mode at the "
            "same sample distance, from the same camera; psnr null = identical "
            "(infinite). frame_ms: median frame time with the light buffer cached; "
            "light_buffer_ms: median light-buffer build, 0 where the mode builds none. slices "
            "and resolution 0 where the mode has none. empty_space_skipping and jitter: how "
            "the point was rendered; refinement_steps > 0: the jittered still after that many "
            "refinement steps, frame_ms the median of one step's frame; jittered and refined "
            "points are "
            "never presets. "
            "presets: per budget_ms, the setting with the highest mean psnr_truth over all "
            "volumes and lights whose slowest frame_ms fits (mode null: none fits).";
    root["device"] = table.device;
    root["renderer"] = {{"vendor", table.vendor},
                        {"version", table.gl_version},
                        {"gpu_timer_queries", table.gpu_timers}};
    root["timing"] = timing_name(table);
    root["size"] = {table.width, table.height};
    root["settings"] = {{"transfer_function", table.transfer_function},
                        {"compositing", table.compositing},
                        {"stage", table.stage},
                        {"builder", table.builder},
                        {"light_lookup", table.light_lookup},
                        {"slab_samples", table.slab_samples},
                        {"phong", table.phong},
                        {"repeat", table.repeat},
                        {"camera", camera_json(table.camera)},
                        {"truth", truth_json(table.truth)}};
    Json points = Json::array();
    for (const Point& p : table.points) {
        points.push_back(point_json(p));
    }
    root["points"] = std::move(points);
    Json preset_list = Json::array();
    for (const Preset& preset : presets) {
        preset_list.push_back(preset_json(preset));
    }
    root["presets"] = std::move(preset_list);
    return root.dump(1);
}

base::Result<Table> parse_table(std::string_view json_text, const std::string& where) {
    if (nesting_depth(json_text) > max_depth) {
        return base::make_error(base::ErrorCode::invalid_table,
                                "nested deeper than " + std::to_string(max_depth) + " levels",
                                where);
    }
    const Json root = Json::parse(json_text.begin(), json_text.end(), nullptr, false);
    if (root.is_discarded()) {
        return base::make_error(base::ErrorCode::invalid_table, "not JSON", where);
    }
    try {
        return table_from(Field{root, ""});
    } catch (const Malformed& malformed) {
        return base::make_error(base::ErrorCode::invalid_table, malformed.message,
                                where + malformed.pointer);
    }
}

base::Result<Table> read_table_file(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) {
        return base::make_error(base::ErrorCode::not_found, "cannot read '" + path.string() + "'",
                                path.string());
    }
    std::stringstream text;
    text << in.rdbuf();
    return parse_table(text.str(), path.string());
}

base::Status write_table_file(const std::filesystem::path& path, const Table& table,
                              const std::vector<Preset>& presets, const std::string& where) {
    std::error_code error;
    if (path.has_parent_path()) {
        std::filesystem::create_directories(path.parent_path(), error);
    }
    const std::filesystem::path temporary = path.string() + ".tmp";
    {
        std::ofstream out(temporary);
        out << table_json(table, presets) << '\n';
        if (!out) {
            return base::make_error(base::ErrorCode::io_error,
                                    "cannot write '" + temporary.string() + "'", where);
        }
    }
    std::filesystem::rename(temporary, path, error);
    if (error) {
        std::filesystem::remove(temporary, error);
        return base::make_error(base::ErrorCode::io_error, "cannot write '" + path.string() + "'",
                                where);
    }
    return base::Ok{};
}

}  // namespace penumbra::quality
