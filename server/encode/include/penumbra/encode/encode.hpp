#pragma once

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::encode {

enum class ImageFormat { png, jpeg };

// A format frames are written in, by the name the protocol and `hello` give it.
struct FrameFormat {
    ImageFormat format;
    std::string_view name;
};

// The formats this module writes frames in, the first the default: `hello.encodings`, the
// protocol's `output.encoding` and the frame header's `encoding` are these names.
inline constexpr std::array<FrameFormat, 2> kFrameFormats{{
        {ImageFormat::jpeg, "jpeg"},
        {ImageFormat::png, "png"},
}};

// The JPEG qualities an image may be written at, both ends included: the protocol's
// `output.jpeg_quality` (announced in hello.ranges) and `penumbra render --quality` are held to it.
inline constexpr int kMinJpegQuality = 1;
inline constexpr int kMaxJpegQuality = 100;

// The JPEG quality frames are written at until a client asks for another.
inline constexpr int kDefaultFrameJpegQuality = 85;

// The format `name` names in kFrameFormats; none for another name.
std::optional<ImageFormat> frame_format_named(std::string_view name);

// The formats' names in kFrameFormats' order: "jpeg|png" with separator "|"; with `last`, that
// goes before the last name instead ("jpeg or png"), for help and error texts.
std::string frame_format_names(std::string_view separator, std::string_view last);

std::optional<ImageFormat> format_for_path(const std::filesystem::path& path);

// The format's name in kFrameFormats.
const char* to_string(ImageFormat format);

// Frames are opaque, so both formats store RGB. `jpeg_quality` is within
// kMinJpegQuality..kMaxJpegQuality.
base::Result<std::vector<std::uint8_t>> encode_image(const base::ImageRgba8& image,
                                                     ImageFormat format, int jpeg_quality = 90);

// Decodes PNG or JPEG bytes (tests, and clients written in C++) into RGBA with alpha 255.
base::Result<base::ImageRgba8> decode_image(std::span<const std::uint8_t> bytes);

// Writes the image to a .png, .jpg or .jpeg file.
base::Status write_image(const std::filesystem::path& path, const base::ImageRgba8& image,
                         int jpeg_quality = 90);

base::Result<base::ImageRgba8> read_image(const std::filesystem::path& path);

}  // namespace penumbra::encode
