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

}  // namespace penumbra::bench
