// The accuracy sweep over volumes and lights (see the header).

#include "penumbra/bench/sweep.hpp"

#include <penumbra/base/text.hpp>
#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <utility>

namespace penumbra::bench {
namespace {

bool contains(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

Progress::Progress(std::uint64_t total)
    : total_(total)
    , start_(Clock::now()) {}

std::string Progress::operator()(std::uint64_t done) const {
    const double minutes = std::chrono::duration<double>(Clock::now() - start_).count() / 60.0;
    const double fraction =
            total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
    char text[64];
    std::snprintf(text, sizeof text, "[%3.0f%%, %.1f of ~%.1f min]", 100.0 * fraction, minutes,
                  fraction > 0.0 ? minutes / fraction : 0.0);
    return text;
}

base::Status measure_sweep(render::FrameRenderer& renderer, const quality::Sweep& sweep,
                           const quality::FrameFor& frame_for, const SweepObserver& observer,
                           quality::Table& table, TruthCache* truths,
                           const quality::TruthMethod& method) {
    quality::AccuracyBench bench(renderer, sweep.repeat);
    if (truths != nullptr) {
        table.truth = method;
    }
    // The progress counts the sweep's frames, which frames_per_view foretells, not the truths'.
    std::uint64_t truth_frames = 0;
    for (std::size_t v = 0; v < sweep.volumes.size(); ++v) {
        auto loaded = volume::load_volume(sweep.volumes[v]);
        if (!loaded) {
            return loaded.error();
        }
        auto volume = std::make_shared<const volume::Volume>(std::move(loaded.value()));
        auto base = frame_for(*volume);
        if (!base) {
            return base.error();
        }
        if (v == 0) {
            quality::describe_frame(table, *base);
            if (observer.frame) {
                observer.frame(table);
            }
        } else if (const std::string& tf = base->transfer_function.name;
                   !contains(base::split_list(table.transfer_function), tf)) {
            table.transfer_function += "," + tf;  // a volume of another kind (a CT) has its own
        }
        if (auto status = renderer.set_volume(volume); !status) {
            return status;
        }
        quality::TruthFor truth_for;
        if (truths != nullptr) {
            truth_for = [&](const scene::FrameRequest& view) -> base::Result<base::ImageRgba8> {
                const std::uint64_t before = bench.frames();
                auto found = truths->truth(bench, *volume, view, method);
                truth_frames += bench.frames() - before;
                if (!found) {
                    return found.error();
                }
                if (observer.truth) {
                    observer.truth(*found);
                }
                return std::move(found->image);
            };
        }
        const quality::PointObserver each_point = [&](const quality::Point& p) {
            if (observer.point) {
                observer.point(p, bench.frames() - truth_frames);
            }
            return true;
        };
        for (const quality::LightAngles& light : sweep.lights) {
            if (observer.view) {
                observer.view(volume->name, light);
            }
            if (auto measured = quality::measure_view(bench, sweep, *base, volume->name, light,
                                                      each_point, table.points, truth_for);
                !measured) {
                return measured.error();
            }
        }
    }
    return base::Ok{};
}

}  // namespace penumbra::bench
