#include "penumbra/imageio/imageio.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

namespace penumbra::imageio {
namespace {

namespace oiio = OIIO;

// OIIO picks the writer from a file name even when the bytes go to memory.
const char* nominal_file_name(encode::ImageFormat format) {
    return format == encode::ImageFormat::png ? "frame.png" : "frame.jpg";
}

std::vector<std::uint8_t> rgb_of(const base::ImageRgba8& image) {
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(image.width) * image.height * 3);
    for (std::size_t i = 0, n = rgb.size() / 3; i < n; ++i) {
        rgb[i * 3 + 0] = image.pixels[i * 4 + 0];
        rgb[i * 3 + 1] = image.pixels[i * 4 + 1];
        rgb[i * 3 + 2] = image.pixels[i * 4 + 2];
    }
    return rgb;
}

base::Result<base::ImageRgba8> read_from(oiio::ImageInput* input, const std::string& what) {
    if (input == nullptr) {
        return base::make_error(base::ErrorCode::decode_failed,
                                "not a readable image: " + oiio::geterror(), what);
    }
    const oiio::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
        return base::make_error(base::ErrorCode::decode_failed, "image has no pixels", what);
    }
    base::ImageRgba8 image(spec.width, spec.height);
    std::vector<std::uint8_t> channels(static_cast<std::size_t>(spec.width) * spec.height *
                                       spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, oiio::TypeDesc::UINT8, channels.data())) {
        return base::make_error(base::ErrorCode::decode_failed, input->geterror(), what);
    }
    for (std::size_t i = 0, n = static_cast<std::size_t>(spec.width) * spec.height; i < n; ++i) {
        const std::uint8_t* src = &channels[i * spec.nchannels];
        for (int c = 0; c < 3; ++c) {
            image.pixels[i * 4 + c] = src[spec.nchannels >= 3 ? c : 0];
        }
        image.pixels[i * 4 + 3] = spec.nchannels == 4 ? src[3] : 255;
    }
    return image;
}

}  // namespace

bool available() {
    return true;
}

base::Result<std::vector<std::uint8_t>> encode_image_openimageio(const base::ImageRgba8& image,
                                                                 encode::ImageFormat format,
                                                                 int jpeg_quality) {
    if (auto checked = encode::check_encodable(image, jpeg_quality); !checked) {
        return checked.error();
    }
    std::vector<unsigned char> bytes;
    oiio::Filesystem::IOVecOutput memory(bytes);
    auto output = oiio::ImageOutput::create(nominal_file_name(format), &memory);
    if (!output) {
        return base::make_error(base::ErrorCode::encode_failed, "no writer: " + oiio::geterror(),
                                nominal_file_name(format));
    }
    oiio::ImageSpec spec(image.width, image.height, 3, oiio::TypeDesc::UINT8);
    if (format == encode::ImageFormat::jpeg) {
        spec.attribute("Compression", "jpeg:" + std::to_string(jpeg_quality));
    }
    const std::vector<std::uint8_t> rgb = rgb_of(image);
    if (!output->open(nominal_file_name(format), spec) ||
        !output->write_image(oiio::TypeDesc::UINT8, rgb.data()) || !output->close()) {
        return base::make_error(base::ErrorCode::encode_failed, output->geterror(),
                                nominal_file_name(format));
    }
    return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
}

base::Result<base::ImageRgba8> decode_image(std::span<const std::uint8_t> bytes) {
    if (bytes.size() < 8) {
        return base::make_error(base::ErrorCode::decode_failed, "too few bytes for an image",
                                "image");
    }
    // The signature decides the reader; the name only selects it.
    const bool png = bytes[0] == 0x89 && bytes[1] == 'P' && bytes[2] == 'N' && bytes[3] == 'G';
    const bool jpeg = bytes[0] == 0xFF && bytes[1] == 0xD8;
    if (!png && !jpeg) {
        return base::make_error(base::ErrorCode::decode_failed, "neither PNG nor JPEG data",
                                "image");
    }
    oiio::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
    auto input = oiio::ImageInput::open(png ? "frame.png" : "frame.jpg", nullptr, &memory);
    return read_from(input.get(), "image");
}

base::Result<base::ImageRgba8> read_image(const std::filesystem::path& path) {
    auto input = oiio::ImageInput::open(path.string());
    return read_from(input.get(), path.string());
}

}  // namespace penumbra::imageio
