// The accuracy sweep over volumes and lights (see the header).

#include "penumbra/bench/sweep.hpp"

#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <memory>
#include <utility>

namespace penumbra::bench {

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
                           quality::Table& table) {
    quality::AccuracyBench bench(renderer, sweep.repeat);
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
        }
        if (auto status = renderer.set_volume(volume); !status) {
            return status;
        }
        const quality::PointObserver each_point = [&](const quality::Point& p) {
            if (observer.point) {
                observer.point(p, bench.frames());
            }
            return true;
        };
        for (const quality::LightAngles& light : sweep.lights) {
            if (observer.view) {
                observer.view(volume->name, light);
            }
            if (auto measured = quality::measure_view(bench, sweep, *base, volume->name, light,
                                                      each_point, table.points);
                !measured) {
                return measured.error();
            }
        }
    }
    return base::Ok{};
}

}  // namespace penumbra::bench
