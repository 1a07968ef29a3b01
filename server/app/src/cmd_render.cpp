#include "commands.hpp"

#include <penumbra/base/text.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/encode/encode.hpp>
#include <penumbra/encode/movie.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/reference/pick.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/turntable.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace penumbra::app {

using namespace cli;

namespace {

int fail(const base::Error& error) {
    return report_failure("render", error);
}

// render's own options, and where they go.
struct RenderOptions {
    std::string volume = default_volume_path;
    volume::LoadOptions load;
    std::string out = "frame.png";
    int quality = 90;
    int repeat = 1;
    // Progressive refinement of the still (jittered ray-cast modes), as a session's.
    int refinement_steps = scene::kDefaultRefinementSteps;
    double refinement_threshold = scene::kDefaultRefinementThreshold;
    // A label map drawn inside the volume, the ids of labels hidden, how much of their colour.
    std::string labels;
    std::string label_names;
    std::string hidden_labels;
    double label_blend = scene::Labels{}.blend;
    // The label map alone, as smooth surfaces: the segmentation's shape without the scan.
    bool labels_only = false;
    // A turntable movie instead of a still: this many frames turning the view about its up
    // direction (a whole turn, or rocking ±rock degrees), each a still, into an MP4.
    int turntable = 0;
    double rock = 0.0;
    // The still rendered in tiles of at most this many pixels a side (0: in one frame).
    int tile = 0;
    encode::MovieOptions movie;
};

po::options_description render_options(RenderOptions& o) {
    po::options_description options = option_group("options");
    options.add_options()("help", "this text")(
            "volume", po::value(&o.volume)->value_name("FILE")->default_value(o.volume),
            ".nii[.gz], .nrrd/.nhdr or name_XxYxZ_type.raw[.gz], a DICOM file or series folder")(
            "series", po::value(&o.load.dicom_series)->value_name("NUMBER|UID"),
            "the series of a DICOM folder holding several")(
            "spacing", po::value<Triple>()->value_name("X,Y,Z"), "override the voxel spacing")(
            "max-load-mb", megabytes(&o.load.max_bytes, 1 << 24),
            "memory the volume load may take (never more than the machine has)")(
            "out", po::value(&o.out)->value_name("FILE")->default_value(o.out),
            ".png or .jpg; .mp4 with --turntable")(
            "quality", whole_number(&o.quality, encode::kMinJpegQuality, encode::kMaxJpegQuality),
            "JPEG quality")("repeat", whole_number(&o.repeat, 1, 10000),
                            "render N times, report median times")(
            "light-inset", po::value<std::string>()->value_name("FILE"),
            "also write the last light-buffer layer (sbrc modes) or half-angle's light buffer "
            "(.png)")("debug-gl", "GL debug output to the log")(
            "list-modes", "print the modes' names, one a line, and exit");
    const scene::Setting& steps = scene::setting::refinement_steps;
    const scene::Setting& threshold = scene::setting::refinement_threshold;
    options.add_options()("refinement-steps",
                          whole_number(&o.refinement_steps, static_cast<int>(steps.min),
                                       static_cast<int>(steps.max)),
                          std::string(steps.summary).c_str())(
            "refinement-threshold",
            number_within(&o.refinement_threshold, threshold.min, threshold.max),
            std::string(threshold.summary).c_str());
    options.add_options()("labels", po::value(&o.labels)->value_name("FILE"),
                          "a label map (segmentation, atlas) drawn inside the volume, on its own "
                          "grid; names and colours from MRIcron's FILE.txt and FILE.lut beside it")(
            "label-names", po::value(&o.label_names)->value_name("FILE"),
            "the --labels' names and colours: an ITK-SNAP label description or a FreeSurfer "
            "colour table (a .seg.nrrd names its segments itself)")(
            "hide-labels", po::value(&o.hidden_labels)->value_name("ID,ID,..."),
            "labels made transparent to the camera and the light")(
            "pick", po::value<std::string>()->value_name("X,Y"),
            "also print what the pixel X,Y of the image (0,0 at the top left) shows: the point "
            "in patient millimetres, the scan's value there, the label")(
            "label-blend", number_within(&o.label_blend, 0.0, 1.0),
            "how much a label's colour replaces the transfer function's (0..1)")(
            "labels-only", po::bool_switch(&o.labels_only),
            "draw the --labels map alone, each visible label a smooth lit surface in its colour "
            "(no scan: --volume and --tf are not used)");
    options.add_options()("turntable", whole_number(&o.turntable, 0, 3600),
                          "write a movie (--out X.mp4) of N frames turning the view a whole turn "
                          "about its up direction, camera and light together, each frame a still "
                          "(0: a still, no movie)")(
            "rock", number_within(&o.rock, 0.0, 180.0),
            "with --turntable: rock the view between -DEG and +DEG instead of a whole turn")(
            "fps", whole_number(&o.movie.frames_per_second, 1, 120),
            "with --turntable: the movie's frames per second")(
            "movie-quality",
            whole_number(&o.movie.quality, encode::kMinMovieQuality, encode::kMaxMovieQuality),
            "with --turntable: x264's rate factor, 0 lossless .. 51 (about 18 looks like the "
            "frames themselves)")(
            "tile", whole_number(&o.tile, 0, scene::kMaxTiledImageSide),
            "render the still in tiles of at most SIDE pixels a side, each a frame of its own "
            "refined as the whole would be, the same pixels as one frame (0: one frame)");
    options.add(frame_options({}, FramePurpose::still));
    return options;
}

// The volume --volume names (a DICOM folder's --series), with --spacing applied.
base::Result<std::shared_ptr<const volume::Volume>> load_for_render(const RenderOptions& o,
                                                                    const po::variables_map& a) {
    auto loaded = volume::load_volume(o.volume, o.load);
    if (!loaded) {
        return loaded.error();
    }
    if (a.count("spacing") != 0) {
        const glm::dvec3 spacing = a["spacing"].as<Triple>().value;
        if (spacing.x <= 0.0 || spacing.y <= 0.0 || spacing.z <= 0.0) {
            return base::make_error(base::ErrorCode::invalid_argument, "spacing must be positive",
                                    "--spacing");
        }
        loaded->spacing = spacing;
    }
    return std::make_shared<const volume::Volume>(std::move(loaded.value()));
}

// Renders `repeat` times and prints each pass's median times, in the order the passes first ran.
base::Result<render::Frame> render_repeated(render::Renderer& renderer,
                                            const scene::FrameRequest& request, int repeat) {
    std::map<std::string, std::vector<double>> gpu_ms;
    std::map<std::string, std::vector<double>> wall_ms;
    std::vector<std::string> order;
    render::Frame frame;
    for (int i = 0; i < repeat; ++i) {
        auto rendered = renderer.render(request);
        if (!rendered) {
            return rendered.error();
        }
        frame = std::move(rendered.value());
        for (const auto& pass : frame.report.passes) {
            if (!gpu_ms.contains(pass.name)) {
                order.push_back(pass.name);
            }
            gpu_ms[pass.name].push_back(pass.gpu_ms);
            wall_ms[pass.name].push_back(pass.wall_ms);
        }
    }
    std::printf("mode:     %s, %dx%d, %s compositing, variant %s\n",
                scene::to_string(request.settings.mode), request.settings.width,
                request.settings.height, scene::to_string(request.settings.compositing),
                frame.report.variant.c_str());
    for (const auto& name : order) {
        const double gpu = quality::median(gpu_ms[name]);
        const std::string gpu_text = gpu < 0.0 ? "      n/a" : std::to_string(gpu).substr(0, 9);
        std::printf("pass:     %-24s gpu %9s ms   wall %9.3f ms   (median of %zu)\n", name.c_str(),
                    gpu_text.c_str(), quality::median(wall_ms[name]), gpu_ms[name].size());
    }
    return frame;
}

// Renders refinement step `step` (1, 2, ...) of the still.
using RefinementStep = std::function<base::Result<render::Frame>(int step)>;

// The still refined as a session refines it (scene::refines_after): jittered frames averaged
// until a step changes the image by no more than the threshold, or the step limit.
base::Result<render::Frame> refine_still(const RefinementStep& step_of, render::Frame still,
                                         const RenderOptions& o) {
    std::optional<double> change;
    int step = 0;
    while (scene::refines_after(step, change, o.refinement_steps, o.refinement_threshold)) {
        ++step;
        auto refined = step_of(step);
        if (!refined) {
            return refined.error();
        }
        auto measured = base::change_in_levels(still.image, refined->image);
        if (!measured) {
            return measured.error();
        }
        change = *measured;
        still = std::move(refined.value());
    }
    if (step > 0) {
        std::printf(
                "refined:  %d step(s), the last changing the image by %.3f levels (RMS; "
                "threshold %g, limit %d)\n",
                step, change.value_or(0.0), o.refinement_threshold, o.refinement_steps);
    }
    return still;
}

// The still (step 0) or its refinement step `step` of `still`, as one frame.
base::Result<render::Frame> render_step(render::Renderer& renderer, scene::FrameRequest still,
                                        int step) {
    if (step > 0) {
        still.refinement = {false, step};
    }
    return renderer.render(still);
}

// --tile: each step of the still rendered tile by tile into one image, every tile's kept mean
// held beside the others' (the renderer's refinement memory), so that the image refines as one
// frame would: the same steps, stopped by the whole image's change.
base::Result<render::Frame> render_tiles(render::Renderer& renderer,
                                         const std::vector<scene::FrameRequest>& tiles,
                                         const scene::RenderSettings& whole, int step) {
    render::Frame frame;
    frame.image = base::ImageRgba8(whole.width, whole.height);
    for (const scene::FrameRequest& tile : tiles) {
        auto part = render_step(renderer, tile, step);
        if (!part) {
            return part.error();
        }
        base::paste(frame.image, part->image, tile.tile.x, tile.tile.y);
        frame.report = std::move(part->report);
    }
    return frame;
}

// The label map --labels names, with the warnings its names files gave.
base::Result<volume::LabelMap> load_labels(const RenderOptions& o) {
    auto loaded = volume::load_label_map(o.labels, o.load, o.label_names);
    if (!loaded) {
        return loaded.error();
    }
    for (const std::string& warning : loaded->warnings) {
        std::printf("warning:  %s\n", warning.c_str());
    }
    return loaded;
}

// The frame's styles of `map`: each label in its file's colour, those --hide-labels lists hidden.
base::Result<scene::Labels> label_styles_for(const volume::LabelMap& map, const RenderOptions& o) {
    scene::Labels labels = render::label_styles(map);
    labels.blend = o.label_blend;
    std::size_t hidden = 0;
    for (const std::string& field : base::split_list(o.hidden_labels)) {
        char* end = nullptr;
        const long long id = std::strtoll(field.c_str(), &end, 10);
        if (field.empty() || end == nullptr || *end != '\0') {
            return base::make_error(
                    base::ErrorCode::invalid_argument,
                    "label ids are whole numbers separated by commas, not '" + field + "'",
                    "--hide-labels");
        }
        bool found = false;
        for (scene::LabelStyle& style : labels.styles) {
            if (style.id == id) {
                style.visible = false;
                found = true;
            }
        }
        if (!found) {
            return base::make_error(base::ErrorCode::invalid_argument,
                                    "the label map holds no label " + field, "--hide-labels");
        }
        ++hidden;
    }
    std::printf("labels:   %s, %zu labels (%zu hidden), %s\n", map.indices.name.c_str(),
                map.labels.size(), hidden, volume::to_string(map.indices.type));
    return labels;
}

// --labels-only: the volume drawn is the label map's surfaces (volume::label_surfaces), and the
// labels are the map with their colours reaching those surfaces.
struct SurfacesDrawn {
    std::shared_ptr<const volume::Volume> indicator;
    std::shared_ptr<const volume::LabelMap> labels;
    scene::Labels styles;
};

base::Result<SurfacesDrawn> label_surfaces_for(const RenderOptions& o) {
    auto map = load_labels(o);
    if (!map) {
        return map.error();
    }
    auto styles = label_styles_for(*map, o);
    if (!styles) {
        return styles.error();
    }
    auto surfaces = volume::label_surfaces(*map, scene::visibility(*styles));
    if (!surfaces) {
        return surfaces.error();
    }
    return SurfacesDrawn{std::make_shared<const volume::Volume>(std::move(surfaces->indicator)),
                         std::make_shared<const volume::LabelMap>(std::move(surfaces->labels)),
                         std::move(styles.value())};
}

// What a PNG written by render keeps of what drew it: the volume and the frame's state as a
// session's `set` takes it, so the picture can be drawn again (and read by what shows PNG text).
std::vector<encode::ImageText> frame_text(const volume::Volume& volume,
                                          const scene::FrameRequest& request,
                                          const RenderOptions& o) {
    scene::State state;
    state.frame = request;
    state.refinement_steps = o.refinement_steps;
    state.refinement_threshold = o.refinement_threshold;
    return encode::still_text(volume.name, protocol::state_to_json(state));
}

// --turntable: each frame the still of the view turned by its angle, into the movie.
base::Status write_turntable(render::Renderer& renderer, const scene::FrameRequest& request,
                             bool refines, const RenderOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    auto movie = encode::MovieWriter::create(o.out, request.settings.width, request.settings.height,
                                             o.movie);
    if (!movie) {
        return movie.error();
    }
    for (int k = 0; k < o.turntable; ++k) {
        const scene::FrameRequest turned = scene::turntable_frame(request, k, o.turntable, o.rock);
        auto frame = renderer.render(turned);
        if (frame && refines) {
            frame = refine_still([&](int step) { return render_step(renderer, turned, step); },
                                 std::move(frame.value()), o);
        }
        if (!frame) {
            return frame.error();
        }
        if (auto status = movie->add(frame->image); !status) {
            return status;
        }
        if ((k + 1) % std::max(1, o.turntable / 10) == 0 || k + 1 == o.turntable) {
            std::printf("frames:   %d of %d\n", k + 1, o.turntable);
            std::fflush(stdout);
        }
    }
    if (auto status = movie->finish(); !status) {
        return status;
    }
    const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(o.out, ec);
    std::printf("movie:    %s (%d frames of %dx%d, %d frames/s, %s, %.0f KiB) in %.1f s\n",
                o.out.c_str(), movie->frames(), request.settings.width, request.settings.height,
                o.movie.frames_per_second,
                o.rock > 0.0
                        ? ("rocking ±" + std::to_string(int(std::lround(o.rock))) + "°").c_str()
                        : "a whole turn",
                ec ? 0.0 : double(bytes) / 1024.0, seconds);
    return base::Ok{};
}

// What --pick X,Y points at in the still's view: printed, as a session's pick answers it.
base::Status print_pick(const volume::Volume& volume, const scene::FrameRequest& request,
                        const volume::LabelMap* labels, const std::string& pixel) {
    const std::vector<std::string> fields = base::split_list(pixel);
    int xy[2] = {0, 0};
    for (std::size_t i = 0; i < 2; ++i) {
        char* end = nullptr;
        const long value = i < fields.size() ? std::strtol(fields[i].c_str(), &end, 10) : -1;
        if (fields.size() != 2 || end == nullptr || *end != '\0' || value < 0 || value > 1 << 20) {
            return base::make_error(base::ErrorCode::invalid_argument,
                                    "expects X,Y, a pixel of the image (0,0 at the top left)",
                                    "--pick");
        }
        xy[i] = static_cast<int>(value);
    }
    const auto start = std::chrono::steady_clock::now();
    auto picked = reference::pick(volume, request, labels, xy[0], xy[1]);
    if (!picked) {
        return picked.error();
    }
    const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                    .count();
    if (!picked->hit) {
        std::printf("pick:     %d,%d: nothing the view shows\n", xy[0], xy[1]);
        return base::Ok{};
    }
    std::printf("pick:     %d,%d: (%.1f, %.1f, %.1f) mm RAS, value %g%s", xy[0], xy[1],
                picked->patient.x, picked->patient.y, picked->patient.z, picked->value,
                picked->hounsfield ? " HU" : "");
    if (picked->label_id != 0) {
        std::printf(", label %lld %s", static_cast<long long>(picked->label_id),
                    picked->label_name.c_str());
    }
    std::printf(" (%.1f ms)\n", ms);
    return base::Ok{};
}

base::Status write_light_inset(render::Renderer& renderer, const std::string& path) {
    auto inset = renderer.light_inset();
    if (!inset) {
        return inset.error();
    }
    if (auto status = encode::write_image(path, *inset); !status) {
        return status;
    }
    std::printf("inset:    %s (%dx%d)\n", path.c_str(), inset->width, inset->height);
    return base::Ok{};
}

}  // namespace

int run_render(const std::vector<std::string>& args) {
    RenderOptions o;
    const po::options_description options = render_options(o);
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return report_usage_error("render", parsed.error());
    }
    const po::variables_map& a = *parsed;
    if (a.count("help") != 0) {
        print_help("render [options]", "", options);
        return 0;
    }
    if (a.count("list-modes") != 0) {
        for (const scene::ModeInfo& mode : scene::modes()) {
            std::printf("%s\n", mode.name.data());
        }
        return 0;
    }
    if (o.turntable > 0 ? std::filesystem::path(o.out).extension() != ".mp4"
                        : !encode::format_for_path(o.out)) {
        return report_usage_error(
                "render",
                base::make_error(base::ErrorCode::invalid_argument,
                                 o.turntable > 0 ? "a --turntable movie is written as .mp4"
                                                 : "output must end in .png or .jpg (.mp4 "
                                                   "with --turntable)",
                                 "--out"));
    }
    const auto given = [&](const char* option) {
        return a.count(option) != 0 && !a[option].defaulted();
    };
    if (o.turntable > 0 && o.tile > 0) {
        return report_usage_error(
                "render",
                base::make_error(base::ErrorCode::invalid_argument,
                                 "--tile renders a still, not a --turntable movie", "--tile"));
    }
    if (o.turntable == 0 && (given("rock") || given("fps") || given("movie-quality"))) {
        return report_usage_error("render",
                                  base::make_error(base::ErrorCode::invalid_argument,
                                                   "--rock, --fps and --movie-quality need "
                                                   "--turntable",
                                                   "--turntable"));
    }
    if ((o.labels_only || !o.hidden_labels.empty() || !o.label_names.empty()) && o.labels.empty()) {
        return report_usage_error(
                "render",
                base::make_error(base::ErrorCode::invalid_argument,
                                 "--labels-only, --hide-labels and --label-names need --labels",
                                 "--labels"));
    }
    std::optional<SurfacesDrawn> surfaces;
    if (o.labels_only) {
        auto drawn = label_surfaces_for(o);
        if (!drawn) {
            return fail(drawn.error());
        }
        surfaces = std::move(drawn.value());
    }
    auto volume = surfaces
                          ? base::Result<std::shared_ptr<const volume::Volume>>(surfaces->indicator)
                          : load_for_render(o, a);
    if (!volume) {
        return fail(volume.error());
    }
    auto request = frame_request_from(a, **volume, FramePurpose::still);
    if (!request) {
        return fail(request.error());
    }
    // Tiles refine side by side, each keeping its float mean (16 bytes a pixel): room for all.
    render::RendererOptions renderer_options;
    renderer_options.debug_context = a.count("debug-gl") != 0;
    if (o.tile > 0) {
        renderer_options.refinement_memory_budget =
                std::max(renderer_options.refinement_memory_budget,
                         std::size_t{16} * static_cast<std::size_t>(request->settings.width) *
                                 static_cast<std::size_t>(request->settings.height));
    }
    auto renderer = render::Renderer::create(renderer_options);
    if (!renderer) {
        return fail(renderer.error());
    }
    const render::RendererInfo& info = (*renderer)->info();
    std::printf("gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                info.platform.c_str());
    const volume::Volume& v = **volume;
    std::printf("volume:   %s %ux%ux%u %s, range %g..%g\n", v.name.c_str(), v.dims.x, v.dims.y,
                v.dims.z, volume::to_string(v.type), v.range.min, v.range.max);
    if (auto status = (*renderer)->set_volume(*volume); !status) {
        return fail(status.error());
    }
    std::shared_ptr<const volume::LabelMap> labels;
    if (surfaces) {
        labels = surfaces->labels;
        request->labels = surfaces->styles;
        request->labels.alone = true;
        *request = scene::labels_alone_request(std::move(*request));
    } else if (!o.labels.empty()) {
        auto map = load_labels(o);
        if (!map) {
            return fail(map.error());
        }
        auto styles = label_styles_for(*map, o);
        if (!styles) {
            return fail(styles.error());
        }
        request->labels = std::move(styles.value());
        labels = std::make_shared<const volume::LabelMap>(std::move(map.value()));
    }
    if (labels) {
        if (auto status = (*renderer)->set_labels(labels); !status) {
            return fail(status.error());
        }
    }
    const scene::RenderSettings& settings = request->settings;
    const bool refines =
            settings.jitter && scene::is_ray_cast(settings.mode) && o.refinement_steps > 0;
    request->refinement.keep = refines;
    if (o.turntable > 0) {
        if (auto status = write_turntable(**renderer, *request, refines, o); !status) {
            return fail(status.error());
        }
        return 0;
    }
    const std::vector<scene::FrameRequest> tiles = scene::image_tiles(*request, o.tile);
    const RefinementStep step_of = [&](int step) {
        return tiles.empty() ? render_step(**renderer, *request, step)
                             : render_tiles(**renderer, tiles, settings, step);
    };
    auto frame = tiles.empty() ? render_repeated(**renderer, *request, o.repeat) : step_of(0);
    if (!tiles.empty()) {
        std::printf("tiles:    %zu, at most %dx%d each\n", tiles.size(), o.tile, o.tile);
    }
    if (frame && refines) {
        frame = refine_still(step_of, std::move(frame.value()), o);
    }
    if (!frame) {
        return fail(frame.error());
    }
    if (auto status =
                encode::write_image(o.out, frame->image, o.quality, frame_text(v, *request, o));
        !status) {
        return fail(status.error());
    }
    std::printf("light:    buffer %s, %llu build(s) in %d frame(s)\n",
                std::string(render::to_string(frame->report.light_buffer)).c_str(),
                static_cast<unsigned long long>((*renderer)->light_buffer_builds()), o.repeat);
    std::printf("output:   %s (%dx%d)\n", o.out.c_str(), frame->image.width, frame->image.height);
    if (a.count("pick") != 0) {
        if (auto status = print_pick(v, *request, labels.get(), a["pick"].as<std::string>());
            !status) {
            return fail(status.error());
        }
    }
    if (a.count("light-inset") != 0) {
        const auto& inset_path = a["light-inset"].as<std::string>();
        if (auto status = write_light_inset(**renderer, inset_path); !status) {
            return fail(status.error());
        }
    }
    return 0;
}

}  // namespace penumbra::app
