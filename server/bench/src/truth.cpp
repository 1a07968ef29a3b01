// The converged ground truth and its cache (see the header).

#include "penumbra/bench/truth.hpp"

#include <penumbra/bench/report.hpp>
#include <penumbra/encode/encode.hpp>
#include <penumbra/imageio/imageio.hpp>
#include <penumbra/quality/sweep.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <system_error>
#include <utility>

namespace penumbra::bench {
namespace {

// FNV-1a, 64 bits: a digest for a cache's file names and a volume's voxels, not a secret.
class Fnv1a {
public:
    void add(const void* bytes, std::size_t size) {
        const auto* p = static_cast<const unsigned char*>(bytes);
        for (std::size_t i = 0; i < size; ++i) {
            hash_ = (hash_ ^ p[i]) * 0x100000001b3ULL;
        }
    }

    [[nodiscard]] std::string hex() const {
        char text[17];
        std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
        return text;
    }

private:
    std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// Every digit a double holds, so that two values print alike only where they are equal.
std::string exact(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value);
    return text;
}

std::string exact(const glm::dvec3& v) {
    return exact(v.x) + " " + exact(v.y) + " " + exact(v.z);
}

std::string volume_text(const volume::Volume& volume) {
    Fnv1a voxels;
    voxels.add(volume.data.data(), volume.data.size());
    std::string text = "volume " + volume.name + "\ndims " + std::to_string(volume.dims.x) + " " +
                       std::to_string(volume.dims.y) + " " + std::to_string(volume.dims.z) +
                       "\nspacing " + exact(volume.spacing) + "\ntype " +
                       volume::to_string(volume.type) + "\nrescale " + exact(volume.rescale.slope) +
                       " " + exact(volume.rescale.intercept) + "\naxes " + exact(volume.axes[0]) +
                       " " + exact(volume.axes[1]) + " " + exact(volume.axes[2]) + "\norigin " +
                       exact(volume.origin) + "\nhounsfield " + (volume.hounsfield ? "1" : "0") +
                       "\nvoxels " + std::to_string(volume.data.size()) + " bytes, fnv1a64 " +
                       voxels.hex() + "\n";
    return text;
}

base::Status check_method(const quality::TruthMethod& method) {
    if (method.frames < 2 || method.frames > scene::kMaxRefinementSteps + 1) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "the truth averages 2.." +
                                        std::to_string(scene::kMaxRefinementSteps + 1) +
                                        " frames, not " + std::to_string(method.frames),
                                "truth");
    }
    return base::Ok{};
}

// The key file's text where it can be read; empty where it cannot.
std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return in ? text.str() : std::string();
}

// The image and its key, the key last: a key file names a complete image.
base::Status keep(const std::filesystem::path& image_path, const std::filesystem::path& key_path,
                  const base::ImageRgba8& image, const std::string& key) {
    std::error_code error;
    std::filesystem::create_directories(image_path.parent_path(), error);
    if (auto status = encode::write_image(image_path, image); !status) {
        return status;
    }
    std::ofstream out(key_path);
    out << key;
    if (!out) {
        return base::make_error(base::ErrorCode::io_error,
                                "cannot write '" + key_path.string() + "'", "truth cache");
    }
    return base::Ok{};
}

}  // namespace

scene::FrameRequest truth_request(scene::FrameRequest view, const quality::TruthMethod& method) {
    scene::RenderSettings& s = view.settings;
    s.mode = scene::Mode::reference;
    s.sample_distance = method.sample_distance;
    s.jitter = true;
    s.empty_space_skipping = true;
    // Converged by its fine jittered step, per-sample classification: the same truth for views
    // measured with pre-integration and without.
    s.preintegration = false;
    // The reference reads neither: raycast.glsl includes the light buffer's and the scattering's
    // code only where it shadows from the light buffer. Reset, the truth of one view serves every
    // light-buffer setting measured against it.
    s.light_buffer = {};
    s.scattering = {};
    view.refinement = {};
    return view;
}

std::string truth_key(const volume::Volume& volume, const scene::FrameRequest& view,
                      const quality::TruthMethod& method) {
    const scene::FrameRequest request = truth_request(view, method);
    std::string key = "penumbra truth 1\n" + volume_text(volume) + "frames " +
                      std::to_string(method.frames) + "\n";
    for (const scene::Setting* setting : scene::kSettings) {
        if (setting->in_frame()) {
            key += std::string(setting->path) + " " + exact(setting->read_frame(request)) + "\n";
        }
    }
    const scene::TransferFunction& tf = request.transfer_function;
    key += "transfer_function " + tf.name + " " + std::string(scene::to_string(tf.space)) + "\n";
    for (const scene::ColorPoint& point : tf.colors) {
        key += "colour " + exact(point.x) + " " + exact(point.rgb) + "\n";
    }
    for (const scene::OpacityPoint& point : tf.opacities) {
        key += "opacity " + exact(point.x) + " " + exact(point.alpha) + "\n";
    }
    return key;
}

base::Result<base::ImageRgba8> render_truth(quality::AccuracyBench& bench,
                                            const scene::FrameRequest& view,
                                            const quality::TruthMethod& method) {
    if (auto status = check_method(method); !status) {
        return status.error();
    }
    auto refined = bench.refined(truth_request(view, method), {method.frames - 1});
    if (!refined) {
        return refined.error();
    }
    return std::move(refined->front().image);
}

base::Result<TruthCache::Found> TruthCache::truth(quality::AccuracyBench& bench,
                                                  const volume::Volume& volume,
                                                  const scene::FrameRequest& view,
                                                  const quality::TruthMethod& method) {
    const std::string key = truth_key(volume, view, method);
    Found found;
    if (const auto kept = memory_.find(key); kept != memory_.end()) {
        found.image = kept->second;
        found.source = Source::memory;
        return found;
    }
    std::optional<std::filesystem::path> key_path;
    if (folder_) {
        Fnv1a digest;
        digest.add(key.data(), key.size());
        key_path = *folder_ / (digest.hex() + ".key");
        found.file = *folder_ / (digest.hex() + ".png");
        if (read_text(*key_path) == key) {
            if (auto image = imageio::read_image(*found.file); image) {
                found.image = std::move(*image);
                found.source = Source::disk;
                memory_.emplace(key, found.image);
                return found;
            }
        }
    }
    const auto start = std::chrono::steady_clock::now();
    auto image = render_truth(bench, view, method);
    if (!image) {
        return image.error();
    }
    found.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    found.image = std::move(*image);
    memory_.emplace(key, found.image);
    if (found.file) {
        std::error_code ignored;
        std::filesystem::remove(*key_path, ignored);  // no key names an image half replaced
        if (auto status = keep(*found.file, *key_path, found.image, key); !status) {
            found.not_kept = status.error();
            found.file.reset();
        }
    }
    return found;
}

std::string describe(const TruthCache::Found& found) {
    const std::string file = found.file ? found.file->string() : std::string();
    switch (found.source) {
        case TruthCache::Source::memory:
            return "from memory";
        case TruthCache::Source::disk:
            return "from " + file;
        case TruthCache::Source::rendered: {
            char seconds[32];
            std::snprintf(seconds, sizeof seconds, "%.1f s", found.seconds);
            return "rendered in " + std::string(seconds) +
                   (found.file       ? ", kept in " + file
                    : found.not_kept ? ", not kept: " + found.not_kept->to_string()
                                     : std::string(", kept for this run"));
        }
    }
    return {};
}

std::string describe(const quality::TruthMethod& method) {
    return "reference at " + distance_label(method.sample_distance) + ", jittered, mean of " +
           std::to_string(method.frames) + " frames";
}

base::Status bench_truth(quality::AccuracyBench& bench, TruthCache& cache,
                         const volume::Volume& volume, const scene::FrameRequest& view,
                         const std::vector<double>& distances, const std::vector<int>& frames,
                         std::FILE* out) {
    std::vector<double> coarse_first = distances;
    std::sort(coarse_first.rbegin(), coarse_first.rend());
    std::vector<int> fewest_first = frames;
    std::sort(fewest_first.begin(), fewest_first.end());
    // images[d][f]: the truth at coarse_first[d] of fewest_first[f] frames.
    std::vector<std::vector<base::ImageRgba8>> images(coarse_first.size());
    std::fprintf(out, "%-9s %6s  %s\n", "distance", "frames", "truth");
    for (std::size_t d = 0; d < coarse_first.size(); ++d) {
        for (const int count : fewest_first) {
            const quality::TruthMethod method{coarse_first[d], count};
            auto found = cache.truth(bench, volume, view, method);
            if (!found) {
                return found.error();
            }
            std::fprintf(out, "%-9s %6d  %s\n", distance_label(method.sample_distance).c_str(),
                         count, describe(*found).c_str());
            std::fflush(out);
            images[d].push_back(std::move(found->image));
        }
    }
    // Each truth against its finer and its longer neighbour, once all are at hand.
    const auto compared = [](const base::ImageRgba8& finer,
                             const base::ImageRgba8& image) -> base::Result<std::string> {
        auto errors = quality::errors_against(base::to_rgba_f(finer), image);
        if (!errors) {
            return errors.error();
        }
        char text[64];
        std::snprintf(text, sizeof text, "%s dB, SSIM %.4f", psnr_text(errors->psnr).c_str(),
                      errors->ssim);
        return std::string(text);
    };
    std::fprintf(out, "\n%-9s %6s  %-32s %s\n", "distance", "frames", "vs the next finer distance",
                 "vs the next frame count");
    for (std::size_t d = 0; d < coarse_first.size(); ++d) {
        for (std::size_t f = 0; f < fewest_first.size(); ++f) {
            std::string finer = "-";
            std::string longer = "-";
            if (d + 1 < coarse_first.size()) {
                auto text = compared(images[d + 1][f], images[d][f]);
                if (!text) {
                    return text.error();
                }
                finer = *text;
            }
            if (f + 1 < fewest_first.size()) {
                auto text = compared(images[d][f + 1], images[d][f]);
                if (!text) {
                    return text.error();
                }
                longer = *text;
            }
            std::fprintf(out, "%-9s %6d  %-32s %s\n", distance_label(coarse_first[d]).c_str(),
                         fewest_first[f], finer.c_str(), longer.c_str());
        }
    }
    return base::Ok{};
}

}  // namespace penumbra::bench
