#pragma once

// The accuracy sweep of `penumbra bench accuracy`: every volume loaded in turn and measured under
// every light (quality::measure_view, one volume and light) against the converged truth
// (truth.hpp), with what it reports as it goes.

#include <penumbra/base/result.hpp>
#include <penumbra/bench/truth.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/quality/table.hpp>
#include <penumbra/render/renderer.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace penumbra::bench {

// How far a run of `total` frames has come: "[ 12%, 1.2 of ~9.8 min]".
class Progress {
public:
    explicit Progress(std::uint64_t total);

    [[nodiscard]] std::string operator()(std::uint64_t done) const;

private:
    using Clock = std::chrono::steady_clock;
    std::uint64_t total_;
    Clock::time_point start_;
};

// What a whole sweep reports as it goes; every member may be empty.
struct SweepObserver {
    std::function<void(const quality::Table&)> frame;  // once the first volume's frame is described
    std::function<void(const std::string& volume, const quality::LightAngles&)>
            view;  // before a view
    std::function<void(const quality::Point&, std::uint64_t frames_done)> point;
    std::function<void(const TruthCache::Found&)> truth;  // once a view's truth is at hand
};

// Every volume of the sweep, loaded in turn, under every light, into `table.points`; the table's
// frame is described from the first volume's (the transfer functions of all). Each view is
// measured against its truth, rendered by `method` and kept in `truths`; without `truths`, against
// the finest reference swept. Frames: quality::frames_per_view x lights x volumes, and each
// truth not kept yet.
base::Status measure_sweep(render::FrameRenderer& renderer, const quality::Sweep& sweep,
                           const quality::FrameFor& frame_for, const SweepObserver& observer,
                           quality::Table& table, TruthCache* truths,
                           const quality::TruthMethod& method = kTruth);

}  // namespace penumbra::bench
