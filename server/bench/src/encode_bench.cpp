#include "penumbra/bench/encode_bench.hpp"

#include <penumbra/encode/encode.hpp>
#include <penumbra/imageio/imageio.hpp>

#include <algorithm>
#include <array>
#include <chrono>

namespace penumbra::bench {
namespace {

using Clock = std::chrono::steady_clock;
using Encoder = base::Result<std::vector<std::uint8_t>> (*)(const base::ImageRgba8&,
                                                            encode::ImageFormat, int);

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

}  // namespace

base::Status bench_encoders(const std::vector<EncodeFrame>& frames, int jpeg_quality, int repeat,
                            std::FILE* out) {
    std::fprintf(out, "%-22s %-5s %11s %11s %7s %11s %11s %7s\n", "frame", "", "codec ms",
                 "OIIO ms", "ratio", "codec B", "OIIO B", "ratio");
    for (const EncodeFrame& frame : frames) {
        for (const auto format : {encode::ImageFormat::jpeg, encode::ImageFormat::png}) {
            const std::array<Encoder, 2> encoders{
                    [](const base::ImageRgba8& image, encode::ImageFormat f, int quality) {
                        return encode::encode_image(image, f, quality);
                    },
                    &imageio::encode_image_openimageio};
            std::array<std::vector<double>, 2> ms;
            std::array<std::size_t, 2> bytes{};
            // In turn, so that the machine's load falls on both alike; one warm-up each.
            for (int run = -1; run < repeat; ++run) {
                for (std::size_t e = 0; e < encoders.size(); ++e) {
                    const auto start = Clock::now();
                    auto encoded = encoders[e](frame.image, format, jpeg_quality);
                    const double elapsed =
                            std::chrono::duration<double, std::milli>(Clock::now() - start).count();
                    if (!encoded) {
                        return encoded.error();
                    }
                    bytes[e] = encoded->size();
                    if (run >= 0) {
                        ms[e].push_back(elapsed);
                    }
                }
            }
            const double codec = median(ms[0]);
            const double oiio = median(ms[1]);
            std::fprintf(out, "%-22s %-5s %11.3f %11.3f %7.3f %11zu %11zu %7.3f\n",
                         frame.name.c_str(), format == encode::ImageFormat::jpeg ? "jpeg" : "png",
                         codec, oiio, codec / oiio, bytes[0], bytes[1],
                         static_cast<double>(bytes[0]) / static_cast<double>(bytes[1]));
        }
    }
    std::fprintf(out,
                 "ratio: codec libraries / OpenImageIO (below 1: the codec libraries are "
                 "faster or smaller); JPEG quality %d, median of %d\n",
                 jpeg_quality, repeat);
    return base::Ok{};
}

}  // namespace penumbra::bench
