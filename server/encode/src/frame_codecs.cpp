#include "frame_codecs.hpp"

#include <memory>
#include <new>
#include <string>
#include <utility>

#include <png.h>
#include <turbojpeg.h>

namespace penumbra::encode {
namespace {

base::Error codec_error(const std::string& message, const char* where) {
    return base::make_error(base::ErrorCode::encode_failed, message, where);
}

}  // namespace

base::Result<std::vector<std::uint8_t>> encode_jpeg(const base::ImageRgba8& image, int quality) {
    const std::unique_ptr<void, int (*)(tjhandle)> compressor(tjInitCompress(), tjDestroy);
    if (!compressor) {
        return codec_error(std::string("TurboJPEG: ") + tjGetErrorStr2(nullptr), "jpeg");
    }
    // Straight from the RGBA readback: TJPF_RGBX skips the fourth byte, so no RGB copy. 4:2:0 and
    // the accurate integer DCT are what libjpeg's defaults gave through OpenImageIO.
    unsigned char* bytes = nullptr;
    unsigned long size = 0;
    const int failed = tjCompress2(compressor.get(), image.pixels.data(), image.width,
                                   image.width * 4, image.height, TJPF_RGBX, &bytes, &size,
                                   TJSAMP_420, quality, TJFLAG_ACCURATEDCT);
    const std::unique_ptr<unsigned char, void (*)(unsigned char*)> owned(bytes, tjFree);
    if (failed != 0) {
        return codec_error(std::string("TurboJPEG: ") + tjGetErrorStr2(compressor.get()), "jpeg");
    }
    return std::vector<std::uint8_t>(bytes, bytes + size);
}

namespace {

struct PngOutput {
    std::vector<std::uint8_t> bytes;
    bool out_of_memory = false;
};

// No exception may cross libpng's C frames: a failed allocation is only noted.
void append_to(png_structp png, png_bytep data, png_size_t length) {
    auto* output = static_cast<PngOutput*>(png_get_io_ptr(png));
    try {
        output->bytes.insert(output->bytes.end(), data, data + length);
    } catch (const std::bad_alloc&) {
        output->out_of_memory = true;
    }
}

void flush_nothing(png_structp) {}

// libpng reports errors by longjmp: nothing with a destructor may live in this frame.
const char* write_png(png_structp png, png_infop info, const base::ImageRgba8& image,
                      PngOutput* output, png_bytepp rows, png_textp text, int text_count) {
    if (setjmp(png_jmpbuf(png)) != 0) {
        return "libpng failed";
    }
    png_set_write_fn(png, output, append_to, flush_nothing);
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
                 static_cast<png_uint_32>(image.height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 6);
    if (text_count > 0) {
        png_set_text(png, info, text, text_count);
    }
    png_write_info(png, info);
    png_set_filler(png, 0, PNG_FILLER_AFTER);  // rows are RGBA: libpng drops the fourth byte
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    return nullptr;
}

}  // namespace

base::Result<std::vector<std::uint8_t>> encode_png(const base::ImageRgba8& image,
                                                   std::span<const ImageText> text) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
    if (info == nullptr) {
        png_destroy_write_struct(&png, nullptr);
        return codec_error("libpng: out of memory", "png");
    }
    std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
    for (int y = 0; y < image.height; ++y) {
        rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(
                image.pixels.data() + static_cast<std::size_t>(y) * image.width * 4);
    }
    // Short text as it is, long text (a frame's settings) compressed.
    std::vector<png_text> chunks(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        chunks[i].compression =
                text[i].text.size() > 256 ? PNG_TEXT_COMPRESSION_zTXt : PNG_TEXT_COMPRESSION_NONE;
        chunks[i].key = const_cast<char*>(text[i].keyword.c_str());
        chunks[i].text = const_cast<char*>(text[i].text.c_str());
        chunks[i].text_length = text[i].text.size();
    }
    PngOutput output;
    const char* failed = write_png(png, info, image, &output, rows.data(), chunks.data(),
                                   static_cast<int>(chunks.size()));
    png_destroy_write_struct(&png, &info);
    if (failed != nullptr || output.out_of_memory) {
        return codec_error(failed != nullptr ? failed : "out of memory", "png");
    }
    return std::move(output.bytes);
}

}  // namespace penumbra::encode
