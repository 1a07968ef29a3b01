#pragma once

// The converged ground truth of `penumbra bench accuracy`: an estimate of the continuous volume
// rendering integral that every mode, sample distance and light-buffer setting is measured
// against. It is the `reference` mode (a shadow ray marched to the light from every sample) at a
// sample distance fine enough that halving it no longer changes the image, jittered, averaged over
// a still and its refinement steps (the renderer's own progressive refinement). It costs more
// than the whole sweep of a view on llvmpipe, so it is kept per case: in memory for the run and,
// where a folder is given, on disk for the runs after it. Pixels are sampled at their centres, as
// every mode samples them.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/quality/table.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::bench {

// Chosen by measurement (`penumbra bench truth --size 256x256 --phong`, anterior view, light
// 10,45, llvmpipe): PSNR (SSIM) of the truth at a sample distance against the truth at half of it,
// both of 16 frames, and of 8 and 16 frames against twice as many, at 1/1024:
//
//   case                 1/512 vs 1/1024   1/1024 vs 1/2048   8 vs 16 frames   16 vs 32 frames
//   ch2, mri_skin        59.2 dB (0.9996)  63.1 dB (0.9998)   65.3 dB          67.1 dB
//   head CT, ct_bone     58.1 dB (0.9998)  64.2 dB (0.9999)   69.7 dB          71.9 dB
//
// Two 8-bit images that differ only by independent rounding are about 56 dB apart, so past 1/1024
// halving the distance moves almost no pixel by a level: the jittered frames already sample each
// step at 16 offsets, and what a step leaves after that (the mean of the transmittances over the
// offsets is not the transmittance of the mean optical depth) shrinks with the step. The default
// step (1/256) is 4x coarser. One truth costs 16 reference frames at 1/1024: about 40 s at
// 256x256 on llvmpipe.
inline constexpr quality::TruthMethod kTruth{1.0 / 1024.0, 16};

// The request the truth renders for the frame `view`: the reference mode at the method's sample
// distance, jittered, empty-space skipping on (the image is the same; it only saves time), the
// light-buffer and scattering settings at their defaults (the reference reads none of them).
// Every other setting is the view's.
scene::FrameRequest truth_request(scene::FrameRequest view, const quality::TruthMethod& method);

// The cache key of the truth of `view` on `volume`: the volume (its name, geometry, value mapping
// and a digest of its voxels), the truth request's every frame setting by its row in
// scene::kSettings (camera, light, size, compositing, shading...), its transfer function, and the
// method. Two views that differ in anything the image depends on have different keys.
std::string truth_key(const volume::Volume& volume, const scene::FrameRequest& view,
                      const quality::TruthMethod& method);

// Renders the truth of `view` on the bench's renderer (whose volume must be set): the still and
// method.frames - 1 refinement steps, the last one's image (the mean of all of them).
base::Result<base::ImageRgba8> render_truth(quality::AccuracyBench& bench,
                                            const scene::FrameRequest& view,
                                            const quality::TruthMethod& method);

// Truths kept by their key: in memory, and in `folder` (KEY_DIGEST.png beside the key in
// KEY_DIGEST.key, checked on reading, so that a digest's collision renders anew) where one is
// given.
class TruthCache {
public:
    explicit TruthCache(std::optional<std::filesystem::path> folder)
        : folder_(std::move(folder)) {}

    enum class Source { memory, disk, rendered };

    struct Found {
        base::ImageRgba8 image;
        Source source = Source::rendered;
        double seconds = 0.0;                       // the render's wall time where it was rendered
        std::optional<std::filesystem::path> file;  // where it is kept on disk
        std::optional<base::Error> not_kept;        // why it could not be written there
    };

    // The truth of `view` on `volume` (set on the bench's renderer), rendered where no cache
    // holds it.
    base::Result<Found> truth(quality::AccuracyBench& bench, const volume::Volume& volume,
                              const scene::FrameRequest& view, const quality::TruthMethod& method);

    [[nodiscard]] const std::optional<std::filesystem::path>& folder() const { return folder_; }

private:
    std::optional<std::filesystem::path> folder_;
    std::map<std::string, base::ImageRgba8> memory_;
};

// "from memory", "from FILE" or "rendered in 123.4 s, kept in FILE".
std::string describe(const TruthCache::Found& found);

// "reference at 1/2048, jittered, mean of 16 frames".
std::string describe(const quality::TruthMethod& method);

// `penumbra bench truth`: the truth of `view` at each of `distances` and each of `frames`, each
// printed as it comes (rendered or cached, and its time), then each with its PSNR and SSIM
// against the truth at the next finer distance (the same frames) and at the next larger frame
// count (the same distance): where halving the distance no longer changes the image, the truth
// has converged.
base::Status bench_truth(quality::AccuracyBench& bench, TruthCache& cache,
                         const volume::Volume& volume, const scene::FrameRequest& view,
                         const std::vector<double>& distances, const std::vector<int>& frames,
                         std::FILE* out);

}  // namespace penumbra::bench
