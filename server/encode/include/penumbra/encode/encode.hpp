#pragma once

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace penumbra::encode {

enum class ImageFormat { png, jpeg };

std::optional<ImageFormat> format_for_path(const std::filesystem::path& path);

const char* to_string(ImageFormat format);

// Frames are opaque, so both formats store RGB. `jpeg_quality` is 1..100.
base::Result<std::vector<std::uint8_t>> encode_image(const base::ImageRgba8& image,
                                                     ImageFormat format, int jpeg_quality = 90);

// Decodes PNG or JPEG bytes (tests, and clients written in C++) into RGBA with alpha 255.
base::Result<base::ImageRgba8> decode_image(std::span<const std::uint8_t> bytes);

// Writes the image to a .png, .jpg or .jpeg file.
base::Status write_image(const std::filesystem::path& path, const base::ImageRgba8& image,
                         int jpeg_quality = 90);

base::Result<base::ImageRgba8> read_image(const std::filesystem::path& path);

}  // namespace penumbra::encode
