#pragma once

// `penumbra bench encode`: what a frame costs to encode, the codec libraries themselves
// (TurboJPEG, libpng: encode::encode_image) against the OpenImageIO writers frames went through
// before (imageio::encode_image_openimageio), side by side in one run on rendered frames.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace penumbra::bench {

struct EncodeFrame {
    std::string name;  // what it shows, e.g. "sbrc 512x512"
    base::ImageRgba8 image;
};

// Encodes each frame as JPEG at `jpeg_quality` and as PNG `repeat` times with each encoder in
// turn, and prints per frame and format the median milliseconds of each, their ratio, and the
// bytes of each.
base::Status bench_encoders(const std::vector<EncodeFrame>& frames, int jpeg_quality, int repeat,
                            std::FILE* out);

// Frames a client would receive in a row (an orbit of the view), and what they show.
struct StreamSequence {
    std::string name;  // e.g. "sbrc 512x512, 3 deg a frame"
    std::vector<base::ImageRgba8> frames;
};

// Each sequence as a stream of JPEG frames at `jpeg_quality` and as an H.264 stream
// (encode::FrameStream) at the largest rate factor (fewest bytes) whose decoded frames reach the
// JPEG frames' mean SSIM against the rendered ones, both decoded as a client would; prints per
// sequence the bytes, SSIM and encode milliseconds per frame of each, their ratio of bytes, and
// what the H.264 stream spends on a frame repeated unchanged.
base::Status bench_streams(const std::vector<StreamSequence>& sequences, int jpeg_quality,
                           std::FILE* out);

}  // namespace penumbra::bench
