#include "penumbra/bench/encode_bench.hpp"

#include <penumbra/encode/encode.hpp>
#include <penumbra/encode/stream.hpp>
#include <penumbra/imageio/compare.hpp>
#include <penumbra/imageio/imageio.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <optional>

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

namespace {

// One codec's run over a sequence: means per frame.
struct StreamRun {
    double bytes = 0.0;
    double ssim = 0.0;
    double encode_ms = 0.0;
    int quality = 0;
};

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The decoded picture's top left `like`'s size (an H.264 picture has even sides), against it.
base::Result<double> ssim_against(const base::ImageRgba8& decoded, const base::ImageRgba8& like) {
    base::ImageRgba8 cropped(like.width, like.height);
    for (int y = 0; y < like.height; ++y) {
        std::copy_n(decoded.pixel(0, y), std::size_t(4) * like.width, cropped.pixel(0, y));
    }
    return imageio::ssim(base::to_rgba_f(cropped), base::to_rgba_f(like));
}

base::Result<StreamRun> run_stream(const StreamSequence& sequence,
                                   const encode::StreamOptions& options) {
    auto stream = encode::make_stream(options);
    if (!stream) {
        return stream.error();
    }
    std::optional<encode::StreamDecoder> decoder;
    if (options.codec == encode::StreamCodec::h264) {
        auto created = encode::StreamDecoder::create();
        if (!created) {
            return created.error();
        }
        decoder.emplace(std::move(created.value()));
    }
    StreamRun run;
    run.quality = options.codec == encode::StreamCodec::h264 ? options.h264_quality
                                                             : options.jpeg_quality;
    for (const base::ImageRgba8& image : sequence.frames) {
        const auto start = Clock::now();
        auto frame = (*stream)->encode(image, false);
        run.encode_ms += ms_since(start);
        if (!frame) {
            return frame.error();
        }
        run.bytes += double(frame->bytes.size());
        auto decoded =
                decoder ? decoder->decode(frame->bytes) : imageio::decode_image(frame->bytes);
        if (!decoded) {
            return decoded.error();
        }
        auto similar = ssim_against(*decoded, image);
        if (!similar) {
            return similar.error();
        }
        run.ssim += *similar;
    }
    const double n = double(std::max<std::size_t>(1, sequence.frames.size()));
    run.bytes /= n;
    run.ssim /= n;
    run.encode_ms /= n;
    return run;
}

}  // namespace

base::Status bench_streams(const std::vector<StreamSequence>& sequences, int jpeg_quality,
                           std::FILE* out) {
    std::fprintf(out, "%-32s %9s %7s %7s   %4s %9s %7s %7s   %7s %9s\n", "sequence", "JPEG B",
                 "SSIM", "ms", "crf", "H.264 B", "SSIM", "ms", "ratio", "unchanged");
    for (const StreamSequence& sequence : sequences) {
        auto jpeg = run_stream(sequence,
                               {.codec = encode::StreamCodec::jpeg, .jpeg_quality = jpeg_quality});
        if (!jpeg) {
            return jpeg.error();
        }
        // The largest rate factor whose frames are as similar to the rendered ones as the JPEG
        // frames: SSIM falls as the factor grows.
        int low = encode::kMinStreamQuality;
        int high = encode::kMaxStreamQuality;
        std::optional<StreamRun> best;
        while (low <= high) {
            const int crf = (low + high) / 2;
            auto h264 =
                    run_stream(sequence, {.codec = encode::StreamCodec::h264, .h264_quality = crf});
            if (!h264) {
                return h264.error();
            }
            if (h264->ssim >= jpeg->ssim) {
                best = *h264;
                low = crf + 1;
            } else {
                high = crf - 1;
            }
        }
        if (!best) {
            std::fprintf(out, "%-32s %9.0f %7.4f %7.2f   no H.264 rate factor reaches its SSIM\n",
                         sequence.name.c_str(), jpeg->bytes, jpeg->ssim, jpeg->encode_ms);
            continue;
        }
        // A frame repeated unchanged, as a still that did not move would be.
        auto stream = encode::make_stream(
                {.codec = encode::StreamCodec::h264, .h264_quality = best->quality});
        if (!stream) {
            return stream.error();
        }
        std::size_t unchanged = 0;
        for (int k = 0; k < 2; ++k) {
            auto frame = (*stream)->encode(sequence.frames.back(), false);
            if (!frame) {
                return frame.error();
            }
            unchanged = frame->bytes.size();
        }
        std::fprintf(out, "%-32s %9.0f %7.4f %7.2f   %4d %9.0f %7.4f %7.2f   %7.2f %9zu\n",
                     sequence.name.c_str(), jpeg->bytes, jpeg->ssim, jpeg->encode_ms, best->quality,
                     best->bytes, best->ssim, best->encode_ms, jpeg->bytes / best->bytes,
                     unchanged);
    }
    std::fprintf(out,
                 "bytes and encode ms are means per frame (one core each); SSIM of the decoded "
                 "frames against the rendered ones; ratio: JPEG bytes / H.264 bytes at equal or "
                 "better SSIM (JPEG quality %d; H.264 libx264 superfast, zero latency, the rate "
                 "factor searched); unchanged: H.264 bytes of a frame repeated\n",
                 jpeg_quality);
    return base::Ok{};
}

}  // namespace penumbra::bench
