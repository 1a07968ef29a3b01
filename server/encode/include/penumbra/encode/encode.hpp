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

// The JPEG qualities an image may be written at, both ends included (libjpeg's scale): the
// protocol's `output.jpeg_quality` (scene's row, which session holds to these) and
// `penumbra render --quality`.
inline constexpr int kMinJpegQuality = 1;
inline constexpr int kMaxJpegQuality = 100;

// Errors: encode_failed for an empty image, invalid_value for a quality out of range.
base::Status check_encodable(const base::ImageRgba8& image, int jpeg_quality);

std::optional<ImageFormat> format_for_path(const std::filesystem::path& path);

// Text kept with an image (what drew it): PNG writes each as a text chunk, compressed when long;
// JPEG keeps none. A keyword is 1..79 printable Latin-1 characters, as PNG allows.
struct ImageText {
    std::string keyword;
    std::string text;
};

// What a still that Penumbra writes keeps of what drew it: the software, the volume's name and the
// state a `set` takes to draw it again (the protocol's JSON).
std::vector<ImageText> still_text(const std::string& source, const std::string& state_json);

// Frames are opaque, so both formats store RGB. `jpeg_quality` is within
// kMinJpegQuality..kMaxJpegQuality. JPEG through TurboJPEG straight from the RGBA pixels (4:2:0,
// the accurate DCT), PNG through libpng.
base::Result<std::vector<std::uint8_t>> encode_image(const base::ImageRgba8& image,
                                                     ImageFormat format, int jpeg_quality = 90,
                                                     std::span<const ImageText> text = {});

// Writes the image to a .png, .jpg or .jpeg file through the same encoders.
base::Status write_image(const std::filesystem::path& path, const base::ImageRgba8& image,
                         int jpeg_quality = 90, std::span<const ImageText> text = {});

}  // namespace penumbra::encode
