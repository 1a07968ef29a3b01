#pragma once

// OpenImageIO where it is the right tool: reading images of any format, decoding frames in tests
// and C++ clients, comparing images (compare.hpp), and the writers frames were encoded with before
// the codec libraries (encode), kept as `penumbra bench encode`'s baseline. The frame path and the
// service need none of it: a build configured with PENUMBRA_WITH_OPENIMAGEIO=OFF (the portable
// bundle, scripts/bundle.sh) leaves OpenImageIO out, and every function here and in compare.hpp
// but ssim() then returns image_io_unavailable.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/encode/encode.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace penumbra::imageio {

// Whether this build has OpenImageIO.
bool available();

// Decodes PNG or JPEG bytes into RGBA with alpha 255.
base::Result<base::ImageRgba8> decode_image(std::span<const std::uint8_t> bytes);

// Any image file OpenImageIO reads, as 8-bit RGBA.
base::Result<base::ImageRgba8> read_image(const std::filesystem::path& path);

// encode::encode_image through OpenImageIO's writers (an RGB copy, then libjpeg or libpng behind
// its ImageOutput), as frames were encoded before.
base::Result<std::vector<std::uint8_t>> encode_image_openimageio(const base::ImageRgba8& image,
                                                                 encode::ImageFormat format,
                                                                 int jpeg_quality = 90);

}  // namespace penumbra::imageio
