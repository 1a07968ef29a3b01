#include "penumbra/encode/encode.hpp"

#include "frame_codecs.hpp"

#include <penumbra/base/assert.hpp>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <string>

namespace penumbra::encode {
namespace {

std::string lower_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

}  // namespace

base::Status check_encodable(const base::ImageRgba8& image, int jpeg_quality) {
    if (image.width <= 0 || image.height <= 0) {
        return base::make_error(base::ErrorCode::encode_failed, "cannot encode an empty image",
                                "image");
    }
    if (jpeg_quality < kMinJpegQuality || jpeg_quality > kMaxJpegQuality) {
        return base::make_error(base::ErrorCode::invalid_value,
                                "JPEG quality must be within " + std::to_string(kMinJpegQuality) +
                                        ".." + std::to_string(kMaxJpegQuality),
                                "quality");
    }
    return base::Ok{};
}

std::optional<ImageFormat> format_for_path(const std::filesystem::path& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".png") {
        return ImageFormat::png;
    }
    if (ext == ".jpg" || ext == ".jpeg") {
        return ImageFormat::jpeg;
    }
    return std::nullopt;
}

std::vector<ImageText> still_text(const std::string& source, const std::string& state_json) {
    return {{"Software", "Penumbra"}, {"Source", source}, {"Penumbra state", state_json}};
}

base::Result<std::vector<std::uint8_t>> encode_image(const base::ImageRgba8& image,
                                                     ImageFormat format, int jpeg_quality,
                                                     std::span<const ImageText> text) {
    if (auto checked = check_encodable(image, jpeg_quality); !checked) {
        return checked.error();
    }
    for (const ImageText& entry : text) {
        const bool printable = std::all_of(entry.keyword.begin(), entry.keyword.end(), [](char c) {
            const auto u = static_cast<unsigned char>(c);
            return (u >= 32 && u <= 126) || u >= 161;
        });
        if (entry.keyword.empty() || entry.keyword.size() > 79 || !printable) {
            return base::make_error(base::ErrorCode::invalid_value,
                                    "a text keyword is 1..79 printable characters",
                                    "text/" + entry.keyword);
        }
    }
    return format == ImageFormat::jpeg ? encode_jpeg(image, jpeg_quality) : encode_png(image, text);
}

base::Status write_image(const std::filesystem::path& path, const base::ImageRgba8& image,
                         int jpeg_quality, std::span<const ImageText> text) {
    const auto format = format_for_path(path);
    if (!format) {
        return base::make_error(base::ErrorCode::unsupported_format,
                                "output must end in .png, .jpg or .jpeg", path.string());
    }
    auto bytes = encode_image(image, *format, jpeg_quality, text);
    if (!bytes) {
        return bytes.error();
    }
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(bytes->data()),
               static_cast<std::streamsize>(bytes->size()));
    file.close();
    if (!file) {
        return base::make_error(base::ErrorCode::write_failed, "cannot write the file",
                                path.string());
    }
    return base::Ok{};
}

}  // namespace penumbra::encode
