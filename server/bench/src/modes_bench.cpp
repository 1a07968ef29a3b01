#include "penumbra/bench/modes_bench.hpp"

#include <penumbra/bench/mode_bench.hpp>
#include <penumbra/bench/optimisation_bench.hpp>

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::bench {
namespace {

constexpr scene::LightBufferBuilder builders[] = {scene::LightBufferBuilder::per_slice,
                                                  scene::LightBufferBuilder::multi_slice};

// "      12.345       n/a": wall then gpu milliseconds.
std::string cells(const Measurement& m) {
    char text[48];
    if (m.gpu_ms) {
        std::snprintf(text, sizeof text, "%12.3f %9.3f", m.wall_ms, *m.gpu_ms);
    } else {
        std::snprintf(text, sizeof text, "%12.3f %9s", m.wall_ms, "n/a");
    }
    return text;
}

// a / b on wall times, with the gpu ratio alongside where both have one.
std::string ratio(const Measurement* a, const Measurement* b) {
    if (a == nullptr || b == nullptr || b->wall_ms <= 0.0) {
        return "n/a";
    }
    char text[64];
    if (a->gpu_ms && b->gpu_ms && *b->gpu_ms > 0.0) {
        std::snprintf(text, sizeof text, "%.2f (gpu %.2f)", a->wall_ms / b->wall_ms,
                      *a->gpu_ms / *b->gpu_ms);
    } else {
        std::snprintf(text, sizeof text, "%.2f", a->wall_ms / b->wall_ms);
    }
    return text;
}

bool contains(const std::vector<scene::Mode>& modes, scene::Mode mode) {
    return std::find(modes.begin(), modes.end(), mode) != modes.end();
}

// One run of `bench modes`: what it sweeps, and its results so far.
struct ModesRun {
    ModeBench& bench;
    TimedResults& results;
    std::vector<scene::Mode> modes;
    std::vector<int> slices;
    std::vector<int> resolutions;
    std::string builder;  // the builder in use
    std::FILE* out;
    bool any_light_buffer_mode = false;

    [[nodiscard]] int middle_resolution() const { return resolutions[resolutions.size() / 2]; }

    base::Status record(TimedPoint point, const scene::FrameRequest& request, LightBufferUse use,
                        const std::string& pass) {
        auto measured = bench.measure(point, request, use, pass);
        if (!measured) {
            return measured.error();
        }
        point.measurement = *measured;
        results.add(point);
        return base::Ok{};
    }
};

// The modes without a light buffer: one frame series each, half_angle over the grid.
base::Status measure_frames(ModesRun& run) {
    std::fprintf(run.out, "\nframe time (ms)\n  %-11s %5s %5s %12s %9s\n", "mode", "n", "R", "wall",
                 "gpu");
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!contains(run.modes, mode) || mode == scene::Mode::half_angle ||
            scene::uses_light_buffer(mode)) {
            continue;
        }
        const TimedPoint point{mode, "frame", "", 0, 0, {}};
        if (auto status =
                    run.record(point, run.bench.request(mode, 0, 0), LightBufferUse::none, {});
            !status) {
            return status;
        }
        std::fprintf(run.out, "  %-11s %5s %5s %s\n", scene::to_string(mode), "-", "-",
                     cells(*run.results.find(mode, "frame")).c_str());
        std::fflush(run.out);
    }
    if (contains(run.modes, scene::Mode::half_angle)) {
        for (const int n : run.slices) {
            for (const int r : run.resolutions) {
                const scene::Mode mode = scene::Mode::half_angle;
                const TimedPoint point{mode, "frame", "", n, r, {}};
                if (auto status = run.record(point, run.bench.request(mode, n, r),
                                             LightBufferUse::none, {});
                    !status) {
                    return status;
                }
                std::fprintf(run.out, "  %-11s %5d %5d %s\n", scene::to_string(mode), n, r,
                             cells(*run.results.find(mode, "frame", n, r)).c_str());
                std::fflush(run.out);
            }
        }
    }
    return base::Ok{};
}

// The light-buffer modes: the buffer cached against rebuilt every frame.
base::Status measure_light_buffer_modes(ModesRun& run) {
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!scene::uses_light_buffer(mode) || !contains(run.modes, mode)) {
            continue;
        }
        if (!run.any_light_buffer_mode) {
            run.any_light_buffer_mode = true;
            std::fprintf(
                    run.out,
                    "\nlight-buffer modes (ms): cached = buffer reused, only the camera moves; "
                    "rebuild = the light\nmoves %g deg every frame, so the buffer is rebuilt "
                    "(builder %s)\n",
                    light_nudge_degrees, run.builder.c_str());
            std::fprintf(run.out, "  %-11s %5s %5s %12s %9s %12s %9s  %s\n", "mode", "n", "R",
                         "cached wall", "gpu", "rebuild wall", "gpu", "rebuild/cached");
        }
        for (const int n : run.slices) {
            for (const int r : run.resolutions) {
                const scene::FrameRequest request = run.bench.request(mode, n, r);
                const TimedPoint cached{mode, "cached", run.builder, n, r, {}};
                const TimedPoint rebuild{mode, "rebuild", run.builder, n, r, {}};
                if (auto status = run.record(cached, request, LightBufferUse::cached, {});
                    !status) {
                    return status;
                }
                if (auto status = run.record(rebuild, request, LightBufferUse::rebuild, {});
                    !status) {
                    return status;
                }
                const Measurement* c = run.results.find(mode, "cached", n, r);
                const Measurement* b = run.results.find(mode, "rebuild", n, r);
                std::fprintf(run.out, "  %-11s %5d %5d %s %s  %s\n", scene::to_string(mode), n, r,
                             cells(*c).c_str(), cells(*b).c_str(), ratio(b, c).c_str());
                std::fflush(run.out);
            }
        }
    }
    return base::Ok{};
}

// The two builders: the light_buffer pass alone.
base::Status measure_builders(ModesRun& run) {
    if (run.any_light_buffer_mode) {
        std::fprintf(run.out,
                     "\nlight-buffer builders (ms): the light_buffer pass alone, rebuilt every "
                     "frame\n  %5s %5s %12s %9s %12s %9s  %s\n",
                     "n", "R", "per_slice", "gpu", "multi_slice", "gpu", "per/multi");
        for (const int n : run.slices) {
            for (const int r : run.resolutions) {
                for (const auto builder : builders) {
                    scene::FrameRequest request = run.bench.request(scene::Mode::sbrc, n, r);
                    request.settings.light_buffer.builder = builder;
                    const std::string name = scene::to_string(builder);
                    const TimedPoint point{scene::Mode::sbrc, "light_buffer_pass", name, n, r, {}};
                    if (auto status = run.record(point, request, LightBufferUse::rebuild,
                                                 "light_buffer_" + name);
                        !status) {
                        return status;
                    }
                }
                const Measurement* per_slice =
                        run.results.find_builder(scene::LightBufferBuilder::per_slice, n, r);
                const Measurement* multi_slice =
                        run.results.find_builder(scene::LightBufferBuilder::multi_slice, n, r);
                std::fprintf(run.out, "  %5d %5d %s %s  %s\n", n, r, cells(*per_slice).c_str(),
                             cells(*multi_slice).c_str(), ratio(per_slice, multi_slice).c_str());
                std::fflush(run.out);
            }
        }
    }
    return base::Ok{};
}

// The paper's interpolating light lookup against the local one.
base::Status measure_lookups(ModesRun& run) {
    const int r_mid = run.middle_resolution();
    if (contains(run.modes, scene::Mode::sbrc)) {
        std::fprintf(
                run.out,
                "\nlight lookups (ms): sbrc, light buffer cached, R=%d: the paper's interpolation "
                "between layers\nvs the local march through the last slab\n  %5s %12s %9s %12s "
                "%9s  %s\n",
                r_mid, "n", "interpolate", "gpu", "local", "gpu", "local/interpolate");
        for (const int n : run.slices) {
            for (const auto lookup : {scene::LightLookup::interpolate, scene::LightLookup::local}) {
                scene::FrameRequest request = run.bench.request(scene::Mode::sbrc, n, r_mid);
                request.settings.light_buffer.lookup = lookup;
                const TimedPoint point{scene::Mode::sbrc,
                                       std::string("lookup_") + scene::to_string(lookup),
                                       run.builder,
                                       n,
                                       r_mid,
                                       {}};
                if (auto status = run.record(point, request, LightBufferUse::cached, {}); !status) {
                    return status;
                }
            }
            const Measurement* interpolate =
                    run.results.find(scene::Mode::sbrc, "lookup_interpolate", n, r_mid);
            const Measurement* local =
                    run.results.find(scene::Mode::sbrc, "lookup_local", n, r_mid);
            std::fprintf(run.out, "  %5d %s %s  %s\n", n, cells(*interpolate).c_str(),
                         cells(*local).c_str(), ratio(local, interpolate).c_str());
            std::fflush(run.out);
        }
    }
    return base::Ok{};
}

void print_ratios(const ModesRun& run) {
    const int r_mid = run.middle_resolution();
    const int n_min = *std::min_element(run.slices.begin(), run.slices.end());
    const int n_max = *std::max_element(run.slices.begin(), run.slices.end());
    std::fprintf(run.out,
                 "\nratios (of median wall times; gpu from timer queries where they work)\n");
    std::fprintf(run.out,
                 "  half_angle / sbrc at equal n, R=%d (sbrc with its light buffer cached | "
                 "rebuilt every frame | cached,\n  read with the paper's interpolating lookup):\n",
                 r_mid);
    for (const int n : run.slices) {
        const Measurement* half_angle =
                run.results.find(scene::Mode::half_angle, "frame", n, r_mid);
        std::fprintf(
                run.out, "    n=%-5d cached %-22s rebuild %-22s interpolate %s\n", n,
                ratio(half_angle, run.results.find(scene::Mode::sbrc, "cached", n, r_mid)).c_str(),
                ratio(half_angle, run.results.find(scene::Mode::sbrc, "rebuild", n, r_mid)).c_str(),
                ratio(half_angle,
                      run.results.find(scene::Mode::sbrc, "lookup_interpolate", n, r_mid))
                        .c_str());
    }
    std::fprintf(run.out,
                 "  cached frame time at n=%d / at n=%d, R=%d (the paper: it barely grows with n; "
                 "GPU target <= 1.20\n  from 64 to 256):\n",
                 n_max, n_min, r_mid);
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!scene::uses_light_buffer(mode)) {
            continue;
        }
        std::fprintf(run.out, "    %-11s %s\n", scene::to_string(mode),
                     ratio(run.results.find(mode, "cached", n_max, r_mid),
                           run.results.find(mode, "cached", n_min, r_mid))
                             .c_str());
    }
    std::fprintf(run.out,
                 "  builder per_slice / multi_slice, the light_buffer pass alone, R=%d (GPU target "
                 ">= 10 at n=256):\n",
                 r_mid);
    for (const int n : run.slices) {
        std::fprintf(
                run.out, "    n=%-5d %s\n", n,
                ratio(run.results.find_builder(scene::LightBufferBuilder::per_slice, n, r_mid),
                      run.results.find_builder(scene::LightBufferBuilder::multi_slice, n, r_mid))
                        .c_str());
    }
}

void print_modes_header(const render::RendererInfo& info, const volume::Volume& volume,
                        const ModeBench& bench, int repeat, std::FILE* out) {
    const scene::RenderSettings& s = bench.base().settings;
    std::fprintf(out, "penumbra bench modes\n");
    std::fprintf(out, "gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                 info.platform.c_str());
    if (bench.gpu_timers()) {
        std::fprintf(out,
                     "note:     absolute times mean something only on a GPU; compare the ratios "
                     "across machines\n");
    } else {
        std::fprintf(out,
                     "note:     software rasteriser (no GPU timer queries): absolute times mean "
                     "something\n          only on a GPU; here read only the ratios\n");
    }
    std::fprintf(out, "volume:   %s %ux%ux%u %s\n", volume.name.c_str(), volume.dims.x,
                 volume.dims.y, volume.dims.z, volume::to_string(volume.type));
    std::fprintf(out,
                 "frame:    %dx%d, tf %s, %s compositing, %s stage, sbrc builder %s, light lookup "
                 "%s%s\n",
                 s.width, s.height, bench.base().transfer_function.name.c_str(),
                 scene::to_string(s.compositing), scene::to_string(s.stage),
                 scene::to_string(s.light_buffer.builder), scene::to_string(s.light_buffer.lookup),
                 s.phong ? ", phong" : "");
    std::fprintf(out,
                 "timing:   per point 1 warm-up + %d timed frame(s), the camera orbiting %g deg a "
                 "frame;\n          medians of the frame's summed pass wall_ms (gpu: summed timer "
                 "queries)\n",
                 repeat, orbit_step_degrees);
    std::fflush(out);
}

// A volume of the optimisation table with its frame, kept for the gradient comparison, which
// runs once the bench's renderer is gone.
struct TableVolume {
    std::shared_ptr<const volume::Volume> volume;
    scene::FrameRequest request;
};

base::Result<std::shared_ptr<const volume::Volume>> load_shared(const std::string& path) {
    auto loaded = volume::load_volume(path);
    if (!loaded) {
        return loaded.error();
    }
    return std::make_shared<const volume::Volume>(std::move(loaded.value()));
}

// The optimisation table on each of its volumes; the renderer is left on the last of them.
base::Result<std::vector<TableVolume>> measure_optimisation_tables(
        const ModesBenchConfig& config, render::Renderer& renderer,
        const std::shared_ptr<const volume::Volume>& main, std::FILE* out) {
    std::vector<TableVolume> phong_cases;
    for (const std::string& path : config.volumes) {
        std::shared_ptr<const volume::Volume> table_volume = main;
        if (path != config.volume) {
            auto loaded = load_shared(path);
            if (!loaded) {
                return loaded.error();
            }
            table_volume = std::move(loaded.value());
        }
        auto request = config.frame_for(*table_volume);
        if (!request) {
            return request.error();
        }
        if (auto status = renderer.set_volume(table_volume); !status) {
            return status.error();
        }
        ModeBench bench(renderer, *request, config.repeat);
        if (auto table = measure_optimisations(bench, config.modes, *table_volume, out); !table) {
            return table.error();
        }
        if (path == config.volume && !config.labels.empty()) {
            auto labels = volume::load_label_map(config.labels);
            if (!labels) {
                return labels.error();
            }
            auto shared = std::make_shared<const volume::LabelMap>(std::move(labels.value()));
            if (auto status = renderer.set_labels(shared); !status) {
                return status.error();
            }
            if (auto table =
                        measure_labels(bench, renderer, config.modes, *table_volume, *shared, out);
                !table) {
                return table.error();
            }
            if (auto status = renderer.set_labels(nullptr); !status) {
                return status.error();
            }
        }
        if (contains(config.modes, scene::Mode::phong)) {
            phong_cases.push_back({table_volume, std::move(request.value())});
        }
    }
    return phong_cases;
}

// The sweeps over slices and light-buffer resolutions, on the volume of --volume.
base::Status measure_sweeps(const ModesBenchConfig& config, ModeBench& bench, std::FILE* out) {
    const scene::RenderSettings& s = bench.base().settings;
    TimedResults results(config.csv, s.width, s.height, config.repeat);
    ModesRun run{bench,
                 results,
                 config.modes,
                 config.slices,
                 config.resolutions,
                 scene::to_string(s.light_buffer.builder),
                 out};
    for (const auto measure :
         {measure_frames, measure_light_buffer_modes, measure_builders, measure_lookups}) {
        if (auto status = measure(run); !status) {
            return status;
        }
    }
    print_ratios(run);
    if (config.csv != nullptr) {
        std::fprintf(out, "csv:      %s\n", config.csv_path.c_str());
    }
    return base::Ok{};
}

// Everything measured with the bench's renderer, which is gone when this returns; the volumes
// whose gradient sources are to be compared.
base::Result<std::vector<TableVolume>> measure_with_renderer(const ModesBenchConfig& config,
                                                             std::FILE* out) {
    auto volume = load_shared(config.volume);
    if (!volume) {
        return volume.error();
    }
    auto base_request = config.frame_for(**volume);
    if (!base_request) {
        return base_request.error();
    }
    auto renderer = render::Renderer::create({.shader_dir = {},
                                              .debug_context = config.debug_gl,
                                              .brick_voxels = config.brick_voxels,
                                              .gradients = config.gradients});
    if (!renderer) {
        return renderer.error();
    }
    ModeBench bench(**renderer, std::move(base_request.value()), config.repeat);
    print_modes_header((*renderer)->info(), **volume, bench, config.repeat, out);
    auto phong_cases = measure_optimisation_tables(config, **renderer, *volume, out);
    if (!phong_cases || config.only_table) {
        return phong_cases;
    }
    if (auto status = (*renderer)->set_volume(*volume); !status) {
        return status.error();
    }
    if (auto status = measure_sweeps(config, bench, out); !status) {
        return status.error();
    }
    return phong_cases;
}

}  // namespace

base::Status bench_modes(const ModesBenchConfig& config, std::FILE* out) {
    auto phong_cases = measure_with_renderer(config, out);
    if (!phong_cases) {
        return phong_cases.error();
    }
    for (const auto& [volume, request] : *phong_cases) {
        if (auto compared = compare_gradients(volume, request, config.repeat, out); !compared) {
            return compared.error();
        }
    }
    return base::Ok{};
}

}  // namespace penumbra::bench
