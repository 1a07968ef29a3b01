#include "penumbra/bench/optimisation_bench.hpp"

#include <penumbra/bench/report.hpp>
#include <penumbra/imageio/compare.hpp>
#include <penumbra/imageio/imageio.hpp>
#include <penumbra/reference/pick.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <tuple>
#include <utility>

namespace penumbra::bench {
namespace {

// The light buffer does not depend on the image size, so its build is timed on small frames
// whose ray casting adds little to the run.
constexpr int build_frame_side = 32;

struct SkippingCase {
    std::string label;
    scene::Mode mode;
    bool phong;
};

std::vector<SkippingCase> skipping_cases(const std::vector<scene::Mode>& modes) {
    std::vector<SkippingCase> cases;
    for (const scene::Mode mode : modes) {
        if (mode == scene::Mode::half_angle) {
            continue;
        }
        const bool shadows = mode != scene::Mode::dvr && mode != scene::Mode::phong;
        const std::string name = scene::to_string(mode);
        cases.push_back({scene::uses_light_buffer(mode) ? name + " cached" : name, mode, shadows});
        if (mode == scene::Mode::sbrc) {
            cases.push_back({"sbrc cached, no phong", mode, false});
        }
    }
    return cases;
}

// NaN (printed "nan") where the build has no image comparison: the times still stand.
base::Result<double> psnr_between(const base::ImageRgba8& a, const base::ImageRgba8& b) {
    if (!imageio::available()) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    auto difference = imageio::compare_images(base::to_rgba_f(a), base::to_rgba_f(b));
    if (!difference) {
        return difference.error();
    }
    return difference->psnr;
}

base::Result<SkippingRow> measure_skipping(ModeBench& bench, const SkippingCase& c) {
    scene::FrameRequest request = bench.request(c.mode, 0, 0);
    request.settings.phong = c.phong;
    const LightBufferUse use =
            scene::uses_light_buffer(c.mode) ? LightBufferUse::cached : LightBufferUse::none;
    SkippingRow row{c.label, {}, {}, 0.0};
    for (const bool skipping : {true, false}) {
        request.settings.empty_space_skipping = skipping;
        const TimedPoint point{c.mode, skipping ? "skipping_on" : "skipping_off", "", 0, 0, {}};
        auto series = bench.measure_series(point, request, use, "raycast");
        if (!series) {
            return series.error();
        }
        (skipping ? row.on : row.off) = std::move(series.value());
    }
    auto psnr = psnr_between(row.on.last_image, row.off.last_image);
    if (!psnr) {
        return psnr.error();
    }
    row.psnr = *psnr;
    return row;
}

// The light-buffer pass alone, rebuilt every frame, for two variants of sbrc's request: `vary`
// makes the first (its flag true) and the second (false); `series` names each.
template <class Vary>
base::Result<std::pair<Measurement, Measurement>> measure_builds(
        ModeBench& bench, const std::array<const char*, 2>& series, Vary vary) {
    scene::FrameRequest request = bench.request(scene::Mode::sbrc, 0, 0);
    request.settings.width = build_frame_side;
    request.settings.height = build_frame_side;
    const auto& light_buffer = request.settings.light_buffer;
    const std::string builder = scene::to_string(light_buffer.builder);
    std::array<Measurement, 2> built;
    for (std::size_t i = 0; i < built.size(); ++i) {
        vary(request, i == 0);
        const TimedPoint point{scene::Mode::sbrc,       series[i], builder, light_buffer.slices,
                               light_buffer.resolution, {}};
        auto measured =
                bench.measure(point, request, LightBufferUse::rebuild, "light_buffer_" + builder);
        if (!measured) {
            return measured.error();
        }
        built[i] = *measured;
    }
    return std::pair{built[0], built[1]};
}

// The light-buffer pass alone with skipping on, then off.
base::Result<std::pair<Measurement, Measurement>> measure_build(ModeBench& bench) {
    return measure_builds(bench, {"light_buffer_pass", "light_buffer_pass"},
                          [](scene::FrameRequest& request, bool first) {
                              request.settings.empty_space_skipping = first;
                          });
}

void print_row(std::FILE* out, const SkippingRow& row) {
    std::fprintf(out, "  %-30s %10.1f %10.1f %7.3f %9s   %.1f | %.1f\n", row.label.c_str(),
                 row.on.frame.wall_ms, row.off.frame.wall_ms,
                 row.on.frame.wall_ms / row.off.frame.wall_ms, psnr_text(row.psnr).c_str(),
                 row.on.pass->wall_ms, row.off.pass->wall_ms);
    std::fflush(out);
}

const SkippingRow* find_row(const OptimisationTable& table, const std::string& label) {
    const auto row = std::find_if(table.rows.begin(), table.rows.end(),
                                  [&](const SkippingRow& r) { return r.label == label; });
    return row == table.rows.end() ? nullptr : &*row;
}

// What the targets compare: the shadows' cost over phong, and the light buffer's
// lookup (without Blinn-Phong) over the plain ray cast.
void print_ratios(std::FILE* out, const OptimisationTable& table) {
    const auto print = [&](const char* what, const SkippingRow* a, const SkippingRow* b) {
        if (a != nullptr && b != nullptr) {
            std::fprintf(out, "  %s, skipping on: %.2f (off: %.2f)\n", what,
                         a->on.frame.wall_ms / b->on.frame.wall_ms,
                         a->off.frame.wall_ms / b->off.frame.wall_ms);
        }
    };
    print("sbrc cached / phong", find_row(table, "sbrc cached"), find_row(table, "phong"));
    print("sbrc without Blinn-Phong / dvr", find_row(table, "sbrc cached, no phong"),
          find_row(table, "dvr"));
    std::fflush(out);
}

// The cuts of the cut table. One cuts the six corners of the volume's box that lie on the
// left, right, anterior or posterior side of the top and bottom: a plane across each, a tenth of
// the way to the centre, keeping the centre's side. A head's box holds air there, so what shows
// is unchanged, while every ray clips by six half-spaces and every sample near one of them asks it
// (a crop box even a millimetre inside the bounds cuts the neck and the crown of a head, which
// changes the picture; one at or beyond them cuts nothing and is left out of the region). The other
// keeps the right half (x past the middle).
std::pair<scene::Cut, scene::Cut> cut_table_cuts(const volume::Volume& volume) {
    const volume::PatientBounds bounds = volume::patient_bounds(volume);
    const glm::dvec3 centre = 0.5 * (bounds.min + bounds.max);
    scene::Cut corners;
    for (int i = 0; i < scene::kMaxClipPlanes; ++i) {
        const glm::dvec3 corner{(i & 1) != 0 ? bounds.max.x : bounds.min.x,
                                (i & 2) != 0 ? bounds.max.y : bounds.min.y,
                                i < 4 ? bounds.min.z : bounds.max.z};
        corners.planes[static_cast<std::size_t>(i)] = {true, corner + 0.1 * (centre - corner),
                                                       glm::normalize(centre - corner)};
    }
    scene::Cut half;
    half.crop = {true, bounds.min - 1.0, bounds.max + 1.0};
    half.crop.min.x = centre.x;
    return {corners, half};
}

base::Result<CutRow> measure_cut(ModeBench& bench, scene::Mode mode, const volume::Volume& volume) {
    scene::FrameRequest request = bench.request(mode, 0, 0);
    request.settings.phong = mode != scene::Mode::dvr;
    const LightBufferUse use =
            scene::uses_light_buffer(mode) ? LightBufferUse::cached : LightBufferUse::none;
    const auto [corners, half] = cut_table_cuts(volume);
    std::vector<std::pair<TimedPoint, scene::FrameRequest>> variants;
    for (const auto& [cut, name] :
         {std::pair{scene::Cut{}, "uncut"}, std::pair{corners, "corners_cut"},
          std::pair{half, "crop_half"}}) {
        request.cut = cut;
        variants.emplace_back(TimedPoint{mode, name, "", 0, 0, {}}, request);
    }
    // In turn, frame by frame: the ratios of a few percent that the table is for would otherwise
    // drown in the drift of this machine's speed from one series to the next.
    auto measured = bench.measure_interleaved(std::move(variants), use);
    if (!measured) {
        return measured.error();
    }
    CutRow row{scene::to_string(mode), std::move((*measured)[0]), std::move((*measured)[1]),
               std::move((*measured)[2]), 0.0};
    auto psnr = psnr_between(row.uncut.last_image, row.corners.last_image);
    if (!psnr) {
        return psnr.error();
    }
    row.psnr = *psnr;
    return row;
}

// The light-buffer pass alone, rebuilt every frame, uncut and with the half crop.
base::Result<std::pair<Measurement, Measurement>> measure_cut_build(ModeBench& bench,
                                                                    const volume::Volume& volume) {
    const scene::Cut half = cut_table_cuts(volume).second;
    return measure_builds(bench, {"build_uncut", "build_crop_half"},
                          [&](scene::FrameRequest& request, bool first) {
                              request.cut = first ? scene::Cut{} : half;
                          });
}

base::Status measure_cuts(ModeBench& bench, const std::vector<scene::Mode>& modes,
                          const volume::Volume& volume, OptimisationTable& table, std::FILE* out) {
    std::fprintf(out,
                 "\ncut on %s (ms, wall; six planes cutting off corners of the box, which hold "
                 "air, and a crop box keeping\nthe right half; PSNR between the uncut and the "
                 "corners' images)\n"
                 "  %-30s %10s %10s %10s %11s %10s %9s\n",
                 volume.name.c_str(), "mode", "uncut", "corners", "crop half", "corners/uncut",
                 "half/uncut", "PSNR dB");
    for (const scene::Mode mode : modes) {
        auto row = measure_cut(bench, mode, volume);
        if (!row) {
            return row.error();
        }
        std::fprintf(out, "  %-30s %10.1f %10.1f %10.1f %11.3f %10.3f %9s\n", row->label.c_str(),
                     row->uncut.frame.wall_ms, row->corners.frame.wall_ms, row->half.frame.wall_ms,
                     row->corners.frame.wall_ms / row->uncut.frame.wall_ms,
                     row->half.frame.wall_ms / row->uncut.frame.wall_ms,
                     psnr_text(row->psnr).c_str());
        std::fflush(out);
        table.cut_rows.push_back(std::move(row.value()));
    }
    if (std::find(modes.begin(), modes.end(), scene::Mode::sbrc) != modes.end()) {
        auto built = measure_cut_build(bench, volume);
        if (!built) {
            return built.error();
        }
        table.build_uncut = built->first;
        table.build_half = built->second;
        std::fprintf(out, "  %-30s %10.1f %10s %10.1f %11s %10.3f\n", "light-buffer build",
                     built->first.wall_ms, "-", built->second.wall_ms, "-",
                     built->second.wall_ms / built->first.wall_ms);
        std::fflush(out);
    }
    return base::Ok{};
}

// Every fifth label hidden: regions of an atlas a user turned off.
scene::Labels hidden_labels(scene::Labels labels) {
    for (std::size_t i = 0; i < labels.styles.size(); i += 5) {
        labels.styles[i].visible = false;
    }
    return labels;
}

base::Result<LabelRow> measure_label_row(ModeBench& bench, scene::Mode mode,
                                         const scene::Labels& shown) {
    scene::FrameRequest request = bench.request(mode, 0, 0);
    request.settings.phong = mode != scene::Mode::dvr;
    const LightBufferUse use =
            scene::uses_light_buffer(mode) ? LightBufferUse::cached : LightBufferUse::none;
    std::vector<std::pair<TimedPoint, scene::FrameRequest>> variants;
    for (const auto& [labels, name] :
         {std::pair{scene::Labels{}, "alone"}, std::pair{shown, "labelled"},
          std::pair{hidden_labels(shown), "labels_hidden"}}) {
        request.labels = labels;
        variants.emplace_back(TimedPoint{mode, name, "", 0, 0, {}}, request);
    }
    auto measured = bench.measure_interleaved(std::move(variants), use);
    if (!measured) {
        return measured.error();
    }
    return LabelRow{scene::to_string(mode), std::move((*measured)[0]), std::move((*measured)[1]),
                    std::move((*measured)[2])};
}

// How many light-buffer builds `changes` frames cause, each changing the request by `change`.
template <class Change>
base::Result<std::uint64_t> builds_over(render::Renderer& renderer, scene::FrameRequest request,
                                        int changes, Change change) {
    if (auto first = renderer.render(request); !first) {
        return first.error();
    }
    const std::uint64_t before = renderer.light_buffer_builds();
    for (int i = 0; i < changes; ++i) {
        change(request, i);
        if (auto frame = renderer.render(request); !frame) {
            return frame.error();
        }
    }
    return renderer.light_buffer_builds() - before;
}

struct GradientSeries {
    Series series;
    double build_ms = 0.0;  // the texture's build in the first frame; 0 for central differences
};

base::Result<GradientSeries> measure_gradient_source(
        const std::shared_ptr<const volume::Volume>& volume, const scene::FrameRequest& request,
        int repeat, render::GradientSource source) {
    auto renderer = render::Renderer::create({.shader_dir = {}, .gradients = source});
    if (!renderer) {
        return renderer.error();
    }
    if (auto status = (*renderer)->set_volume(volume); !status) {
        return status.error();
    }
    // The texture is built by a volume's first frame only, which the series' warm-up would hide.
    auto first = (*renderer)->render(request);
    if (!first) {
        return first.error();
    }
    GradientSeries measured;
    for (const auto& timing : first->report.passes) {
        if (timing.name == "build_gradients") {
            measured.build_ms += timing.wall_ms;
        }
    }
    ModeBench bench(**renderer, request, repeat);
    const TimedPoint point{scene::Mode::phong, "gradients", "", 0, 0, {}};
    auto series = bench.measure_series(point, request, LightBufferUse::none);
    if (!series) {
        return series.error();
    }
    measured.series = std::move(series.value());
    return measured;
}

// The median time of `count` picks through the view's middle, in milliseconds.
base::Result<double> median_pick_ms(const volume::Volume& volume,
                                    const scene::FrameRequest& request,
                                    const volume::LabelMap& labels, int count) {
    std::vector<double> times;
    for (int i = 0; i < count; ++i) {
        const auto start = std::chrono::steady_clock::now();
        auto picked = reference::pick(volume, request, &labels, request.settings.width / 2,
                                      request.settings.height / 2);
        const std::chrono::duration<double, std::milli> took =
                std::chrono::steady_clock::now() - start;
        if (!picked) {
            return picked.error();
        }
        times.push_back(took.count());
    }
    const auto middle = times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2);
    std::nth_element(times.begin(), middle, times.end());
    return *middle;
}

}  // namespace

base::Result<LabelTable> measure_labels(ModeBench& bench, render::Renderer& renderer,
                                        const std::vector<scene::Mode>& modes,
                                        const volume::Volume& volume,
                                        const volume::LabelMap& labels, std::FILE* out) {
    const scene::Labels shown = render::label_styles(labels);
    std::fprintf(out,
                 "\nlabels: %s (%zu labels) inside the volume (ms, wall; every label shown in "
                 "its colour, then every fifth hidden)\n  %-30s %10s %10s %10s %11s %10s\n",
                 labels.indices.name.c_str(), labels.labels.size(), "mode", "alone", "labelled",
                 "hidden", "labelled/alone", "hidden/alone");
    LabelTable table;
    for (const scene::Mode mode : modes) {
        auto row = measure_label_row(bench, mode, shown);
        if (!row) {
            return row.error();
        }
        std::fprintf(out, "  %-30s %10.1f %10.1f %10.1f %11.3f %10.3f\n", row->label.c_str(),
                     row->alone.frame.wall_ms, row->labelled.frame.wall_ms,
                     row->hidden.frame.wall_ms,
                     row->labelled.frame.wall_ms / row->alone.frame.wall_ms,
                     row->hidden.frame.wall_ms / row->alone.frame.wall_ms);
        std::fflush(out);
        table.rows.push_back(std::move(row.value()));
    }
    if (!table.rows.empty()) {
        const auto cheapest = std::min_element(
                table.rows.begin(), table.rows.end(), [](const LabelRow& a, const LabelRow& b) {
                    return a.labelled.frame.wall_ms < b.labelled.frame.wall_ms;
                });
        scene::FrameRequest request = bench.request(modes.front(), 0, 0);
        request.labels = shown;
        auto pick_ms = median_pick_ms(volume, request, labels, std::max(bench.repeat(), 1));
        if (!pick_ms) {
            return pick_ms.error();
        }
        table.pick_ms = *pick_ms;
        table.cheapest_labelled_frame_ms = cheapest->labelled.frame.wall_ms;
        std::fprintf(out, "  %-30s %10.3f %10.1f %10s %11.4f   (%s's labelled frame)\n",
                     "pick (one ray, CPU)", table.pick_ms, table.cheapest_labelled_frame_ms, "-",
                     table.pick_ms / table.cheapest_labelled_frame_ms, cheapest->label.c_str());
    }
    if (std::find(modes.begin(), modes.end(), scene::Mode::sbrc) == modes.end()) {
        return table;
    }
    auto built = measure_builds(bench, {"build_alone", "build_labelled"},
                                [&](scene::FrameRequest& request, bool first) {
                                    request.labels = first ? scene::Labels{} : shown;
                                });
    if (!built) {
        return built.error();
    }
    table.build_alone = built->first;
    table.build_labelled = built->second;
    std::fprintf(out, "  %-30s %10.1f %10.1f %10s %11.3f\n", "light-buffer build",
                 built->first.wall_ms, built->second.wall_ms, "-",
                 built->second.wall_ms / built->first.wall_ms);
    scene::FrameRequest request = bench.request(scene::Mode::sbrc, 0, 0);
    request.labels = shown;
    table.changes = 4;
    auto visibility =
            builds_over(renderer, request, table.changes, [&](scene::FrameRequest& r, int i) {
                auto& style = r.labels.styles[static_cast<std::size_t>(i)];
                style.visible = !style.visible;
            });
    auto moves = builds_over(renderer, request, table.changes, [](scene::FrameRequest& r, int i) {
        r.camera.eye = glm::dvec3(
                glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.1 * (i + 1), glm::dvec3(0.0, 0.0, 1.0))) *
                r.camera.eye);
    });
    if (!visibility || !moves) {
        return !visibility ? visibility.error() : moves.error();
    }
    table.builds_per_visibility_change = *visibility;
    table.builds_per_camera_move = *moves;
    std::fprintf(out,
                 "  light-buffer builds: %llu over %d visibility changes, %llu over %d camera "
                 "moves\n",
                 static_cast<unsigned long long>(*visibility), table.changes,
                 static_cast<unsigned long long>(*moves), table.changes);
    std::fflush(out);
    return table;
}

base::Result<OptimisationTable> measure_optimisations(ModeBench& bench,
                                                      const std::vector<scene::Mode>& modes,
                                                      const volume::Volume& volume,
                                                      std::FILE* out) {
    std::fprintf(out,
                 "\noptimisations on %s %ux%ux%u (ms, wall, timed as above from the default "
                 "view;\nshadow modes with Blinn-Phong unless said; PSNR between the two "
                 "images)\n  %-30s %10s %10s %7s %9s   %s\n",
                 volume.name.c_str(), volume.dims.x, volume.dims.y, volume.dims.z, "mode",
                 "skip on", "skip off", "on/off", "PSNR dB", "raycast pass on | off");
    OptimisationTable table;
    for (const SkippingCase& c : skipping_cases(modes)) {
        auto row = measure_skipping(bench, c);
        if (!row) {
            return row.error();
        }
        print_row(out, *row);
        table.rows.push_back(std::move(row.value()));
    }
    if (std::find(modes.begin(), modes.end(), scene::Mode::sbrc) != modes.end()) {
        auto built = measure_build(bench);
        if (!built) {
            return built.error();
        }
        table.build_on = built->first;
        table.build_off = built->second;
        const std::string label = std::string("light_buffer_") +
                                  scene::to_string(bench.base().settings.light_buffer.builder) +
                                  " build";
        std::fprintf(out, "  %-30s %10.1f %10.1f %7.3f %9s\n", label.c_str(),
                     table.build_on->wall_ms, table.build_off->wall_ms,
                     table.build_on->wall_ms / table.build_off->wall_ms, "-");
    }
    print_ratios(out, table);
    if (auto status = measure_cuts(bench, modes, volume, table, out); !status) {
        return status.error();
    }
    return table;
}

base::Result<GradientComparison> compare_gradients(
        const std::shared_ptr<const volume::Volume>& volume, const scene::FrameRequest& request,
        int repeat, std::FILE* out) {
    scene::FrameRequest phong = request;
    phong.settings.mode = scene::Mode::phong;
    auto central = measure_gradient_source(volume, phong, repeat,
                                           render::GradientSource::central_differences);
    if (!central) {
        return central.error();
    }
    auto texture = measure_gradient_source(volume, phong, repeat, render::GradientSource::texture);
    if (!texture) {
        return texture.error();
    }
    auto psnr = psnr_between(central->series.last_image, texture->series.last_image);
    if (!psnr) {
        return psnr.error();
    }
    GradientComparison comparison{std::move(central->series), std::move(texture->series),
                                  texture->build_ms, *psnr};
    const double central_ms = comparison.central.frame.wall_ms;
    const double texture_ms = comparison.texture.frame.wall_ms;
    std::fprintf(out,
                 "  gradients on %s, phong: central %.1f ms, texture %.1f ms, texture/central "
                 "%.3f, PSNR %s dB; texture built once in %.1f ms\n",
                 volume->name.c_str(), central_ms, texture_ms, texture_ms / central_ms,
                 psnr_text(comparison.psnr).c_str(), comparison.texture_build_ms);
    std::fflush(out);
    return comparison;
}

}  // namespace penumbra::bench
