// Rules for pixel data:
//   - When every slice has the same RescaleSlope and RescaleIntercept, both whole numbers, the
//     stored values are kept (uint8 for 8-bit unsigned data, uint16 for unsigned, int16 for
//     signed) and the rescale becomes Volume::rescale, so a CT stays 16-bit with its values in
//     Hounsfield units. Otherwise the rescale is applied per slice into float32.
//   - Modality CT or RescaleType HU sets Volume::hounsfield. MONOCHROME1 is inverted.
//   - Pixel data must be one sample per pixel, 8, 16 or 32 bits allocated; BitsStored, HighBit and
//     PixelRepresentation (two's complement) are honoured. 32-bit data (RT dose grids) is kept as
//     float32 with its rescale applied (DoseGridScaling for a dose grid). Compressed transfer
//     syntaxes are decoded by DCMTK's JPEG, JPEG-LS and RLE codecs, JPEG 2000 by OpenJPEG (whose
//     codestream decides the samples' sign and precision where the header disagrees); others are
//     an error naming the transfer syntax.

#include "dicom_pixels.hpp"

#include "dicom_frames.hpp"
#include "dicom_jpeg2000.hpp"
#include "file_io.hpp"
#include "memory_budget.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <utility>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcxfer.h>

namespace penumbra::volume::detail::dicom {
namespace {

// The pixel words an image stores for all its frames (a mosaic: its whole tiled image).
std::uint64_t stored_pixels(const Image& image) {
    if (image.mosaic) {
        return std::uint64_t{image.mosaic->stored_rows} * image.mosaic->stored_columns;
    }
    return std::uint64_t{image.format.rows} * image.format.columns * image.frame_count;
}

// The raw pixel words of all frames of one image, decoded to native order, in `format` (the
// image's, which a JPEG 2000 codestream may correct: decode_jpeg2000).
base::Result<std::span<const std::byte>> pixel_bytes(Image& image, PixelFormat& format) {
    DcmDataset& dataset = *image.file->getDataset();
    const E_TransferSyntax xfer = dataset.getOriginalXfer();
    const DcmXfer syntax(xfer);
    if (is_jpeg2000(xfer) && image.mosaic) {
        return base::make_error(base::ErrorCode::unsupported_encoding,
                                "a Siemens mosaic stored as JPEG 2000 is not supported",
                                detail::at_file(image.path));
    }
    if (is_jpeg2000(xfer)) {
        auto words = decode_jpeg2000(dataset, image.frame_count, format, image.path);
        if (!words) {
            return words.error();
        }
        image.decoded_words = std::move(words.value());
        return std::span<const std::byte>(image.decoded_words);
    }
    if (syntax.isEncapsulated()) {
        const OFCondition status = dataset.chooseRepresentation(EXS_LittleEndianExplicit, nullptr);
        if (status.bad() || !dataset.canWriteXfer(EXS_LittleEndianExplicit)) {
            return base::make_error(base::ErrorCode::unsupported_encoding,
                                    std::string("pixel data in transfer syntax ") +
                                            syntax.getXferName() + " (" + syntax.getXferID() +
                                            ") cannot be decoded: " + status.text() +
                                            "; supported: uncompressed, JPEG, JPEG-LS, RLE, "
                                            "JPEG 2000",
                                    detail::at_file(image.path));
        }
    }
    const std::uint64_t expected = stored_pixels(image) * (image.format.bits_allocated / 8);
    DcmElement* element = nullptr;
    OFCondition status = dataset.findAndGetElement(DCM_PixelData, element);
    const std::byte* data = nullptr;
    std::uint64_t bytes = 0;
    if (status.good()) {
        // Files disagree with BitsAllocated about the VR (8-bit data as OW in implicit VR, for
        // one), and DCMTK hands out an OB value only as bytes and an OW value only as words;
        // on a little-endian host both views of the decoded value are the same bytes.
        Uint8* byte_values = nullptr;
        Uint16* word_values = nullptr;
        if (element->getUint8Array(byte_values).good() && byte_values != nullptr) {
            data = reinterpret_cast<const std::byte*>(byte_values);
            bytes = element->getLength();
        } else if (status = element->getUint16Array(word_values);
                   status.good() && word_values != nullptr) {
            data = reinterpret_cast<const std::byte*>(word_values);
            bytes = element->getLength();
        }
    }
    if (status.bad() || data == nullptr) {
        return base::make_error(base::ErrorCode::truncated,
                                std::string("cannot read the pixel data: ") + status.text(),
                                detail::at_file(image.path));
    }
    if (image.format.bits_allocated == 32 && !syntax.isEncapsulated() && syntax.isBigEndian() &&
        bytes >= expected) {
        // DCMTK turns OW data into host order 16 bits at a time; a big-endian 32-bit word's two
        // halves then still lie high half first.
        auto* words = const_cast<std::byte*>(data);  // NOLINT: DCMTK's own buffer, decoded for us
        for (std::uint64_t i = 0; i + 4 <= expected; i += 4) {
            std::swap_ranges(words + i, words + i + 2, words + i + 2);
        }
    }
    if (bytes < expected) {
        return base::make_error(base::ErrorCode::truncated,
                                "the pixel data holds " + std::to_string(bytes) + " bytes; " +
                                        image.format.describe() + " x " +
                                        std::to_string(image.frame_count) + " frame(s) need " +
                                        std::to_string(expected),
                                detail::at_file(image.path));
    }
    return std::span<const std::byte>(data, static_cast<std::size_t>(expected));
}

// The stored value of one pixel word: the BitsStored bits ending at HighBit, sign-extended for
// two's complement data. MONOCHROME1 (white at the lowest value, as X-ray film) is inverted into
// MONOCHROME2's sense, so that high values are dense for every image: complementing the bits maps
// the stored range onto itself reversed (max - v unsigned, -1 - v signed).
struct SampleDecoder {
    unsigned shift;
    std::uint64_t mask;  // 64 bits wide, so that 32 stored bits make a mask too
    std::uint64_t sign_bit;
    bool inverted;

    explicit SampleDecoder(const PixelFormat& format)
        : shift(format.high_bit + 1u - format.bits_stored)
        , mask((std::uint64_t{1} << format.bits_stored) - 1u)
        , sign_bit(format.is_signed ? std::uint64_t{1} << (format.bits_stored - 1) : 0u)
        , inverted(format.inverted) {}

    [[nodiscard]] std::int64_t operator()(std::uint32_t word) const {
        std::uint64_t bits = (std::uint64_t{word} >> shift) & mask;
        if (inverted) {
            bits = ~bits & mask;
        }
        if ((bits & sign_bit) != 0) {
            return static_cast<std::int64_t>(bits) - static_cast<std::int64_t>(mask) - 1;
        }
        return static_cast<std::int64_t>(bits);
    }
};

// Writes the values of one frame into `out` (float32 voxels): stored values, or with the frame's
// rescale applied when `apply_rescale`.
// A mosaic's frame is its tile: `tiles` a side, row by row.
void decode_frame(std::span<const std::byte> pixels, const PixelFormat& format,
                  const std::optional<Mosaic>& mosaic, std::uint32_t frame_index,
                  const Frame& frame, bool apply_rescale, float* out) {
    const std::size_t count = std::size_t{format.rows} * format.columns;
    const std::size_t width = format.bits_allocated / 8;
    // Where pixel i of the frame is stored, in words.
    const auto stored_at = [&](std::size_t i) {
        if (!mosaic) {
            return std::size_t{frame_index} * count + i;
        }
        const std::size_t x = i % format.columns;
        const std::size_t y = i / format.columns;
        const std::size_t tile_row = frame_index / mosaic->tiles;
        const std::size_t tile_column = frame_index % mosaic->tiles;
        return (tile_row * format.rows + y) * mosaic->stored_columns +
               tile_column * format.columns + x;
    };
    const std::byte* in = pixels.data();
    const SampleDecoder decode(format);
    const bool identity = !apply_rescale || (frame.slope == 1.0 && frame.intercept == 0.0);
    for (std::size_t i = 0; i < count; ++i) {
        std::uint32_t word = 0;
        const std::size_t at = stored_at(i);
        if (width == 1) {
            word = static_cast<std::uint8_t>(in[at]);
        } else if (width == 2) {
            std::uint16_t value = 0;
            std::memcpy(&value, in + 2 * at, 2);
            word = value;
        } else {
            std::memcpy(&word, in + 4 * at, 4);
        }
        const auto stored = static_cast<double>(decode(word));
        out[i] = static_cast<float>(identity ? stored : stored * frame.slope + frame.intercept);
    }
}

// Narrows float32 voxels that hold stored integers to the type the pixel format needs (uint8,
// uint16 or int16), which halves (or quarters) what the volume costs in memory and on the GPU
// without changing a value.
template <class T>
std::vector<std::byte> narrow_to(std::span<const float> values) {
    std::vector<std::byte> data(values.size() * sizeof(T));
    for (std::size_t i = 0; i < values.size(); ++i) {
        const T value = static_cast<T>(values[i]);
        std::memcpy(data.data() + i * sizeof(T), &value, sizeof(T));
    }
    return data;
}

}  // namespace

base::Result<Volume> assemble(std::vector<Image>& images, const std::string& name,
                              const std::filesystem::path& source, const LoadOptions& options) {
    PixelFormat format = images.front().format;  // as the pixel data turns out to store it
    for (const Image& image : images) {
        if (!(image.format == format)) {
            return base::make_error(base::ErrorCode::inconsistent_series,
                                    "the image is " + image.format.describe() + ", but " +
                                            images.front().path.filename().string() + " is " +
                                            format.describe(),
                                    detail::at_file(image.path));
        }
    }
    // What the load holds at most: every frame's position, the volume as float32 voxels, and
    // beside them either one image's pixel data (while it is decoded) or the volume narrowed to
    // 8 or 16 bits (after the last image is dropped).
    std::uint64_t frame_count = 0;
    std::uint64_t largest_image = 0;
    for (const Image& image : images) {
        frame_count += image.frame_count;
        std::uint64_t held = stored_pixels(image) * (format.bits_allocated / 8u);
        if (is_jpeg2000(image.file->getDataset()->getOriginalXfer())) {
            // Its fragments joined per frame (about its decoded size at most for real data) and
            // OpenJPEG's 32-bit samples of one frame beside the decoded words.
            held = 2 * held + std::uint64_t{format.rows} * format.columns * 4;
        }
        largest_image = std::max(largest_image, held);
    }
    if (frame_count > max_frames) {
        return base::make_error(base::ErrorCode::too_large,
                                std::to_string(frame_count) + " frames exceed the limit of " +
                                        std::to_string(max_frames),
                                detail::at_file(source));
    }
    const std::uint64_t all_voxels = std::uint64_t{format.rows} * format.columns * frame_count;
    if (all_voxels > max_voxels) {
        return base::make_error(base::ErrorCode::too_large,
                                std::to_string(format.columns) + "x" + std::to_string(format.rows) +
                                        "x" + std::to_string(frame_count) +
                                        " voxels exceed the limit of " + std::to_string(max_voxels),
                                detail::at_file(source));
    }
    const std::uint64_t peak = frame_count * sizeof(Frame) + all_voxels * sizeof(float) +
                               std::max(largest_image, all_voxels * 2);
    if (auto status = detail::check_budget(
                peak,
                std::to_string(format.columns) + "x" + std::to_string(format.rows) + "x" +
                        std::to_string(frame_count) + " DICOM voxels (decoded as float32)",
                source, options);
        !status) {
        return status.error();
    }
    std::vector<Frame> frames;
    frames.reserve(static_cast<std::size_t>(frame_count));
    for (std::size_t i = 0; i < images.size(); ++i) {
        auto image_frames = read_frames(*images[i].file->getDataset(), i, images[i].frame_count,
                                        images[i].mosaic, images[i].format);
        frames.insert(frames.end(), image_frames.begin(), image_frames.end());
    }
    std::vector<std::string> notes;
    auto z_spacing = order_frames(frames, images, source, notes);
    if (!z_spacing) {
        return z_spacing.error();
    }
    auto xy_spacing = pixel_spacing(frames, images, source);
    if (!xy_spacing) {
        return xy_spacing.error();
    }
    auto geometry = patient_geometry(frames, *xy_spacing, *z_spacing, images);
    if (!geometry) {
        return geometry.error();
    }

    // One rescale of whole numbers for every frame stays the volume's Rescale over the stored
    // integers; rescales that differ per slice or are fractional are applied into float32.
    const Frame& first = frames.front();
    const bool kept = format.bits_allocated <= 16 &&
                      std::all_of(frames.begin(), frames.end(), [&](const Frame& f) {
                          return f.slope == first.slope && f.intercept == first.intercept &&
                                 f.slope == std::round(f.slope) &&
                                 f.intercept == std::round(f.intercept);
                      });
    // Frame z of the volume is frames[z]; each image's pixel data is read once.
    std::vector<std::vector<std::size_t>> slots(images.size());
    for (std::size_t z = 0; z < frames.size(); ++z) {
        slots[frames[z].image].push_back(z);
    }
    const std::size_t slice_voxels = std::size_t{format.rows} * format.columns;
    const std::uint64_t voxels = std::uint64_t{slice_voxels} * frames.size();
    // Decoded as float32 straight into the bytes the volume keeps when no narrower type fits.
    std::vector<std::byte> decoded(static_cast<std::size_t>(voxels) * sizeof(float));
    auto* values = reinterpret_cast<float*>(decoded.data());
    bool first_read = true;
    for (std::size_t i = 0; i < images.size(); ++i) {
        if (slots[i].empty()) {
            continue;  // a frame of a later volume of the series
        }
        PixelFormat stored = images[i].format;
        auto pixels = pixel_bytes(images[i], stored);
        if (!pixels) {
            return pixels.error();
        }
        if (first_read) {
            format = stored;
            first_read = false;
        } else if (!(stored == format)) {
            return base::make_error(base::ErrorCode::inconsistent_series,
                                    "the pixel data stores " + stored.describe() +
                                            ", the series' first image " + format.describe(),
                                    detail::at_file(images[i].path));
        }
        for (const std::size_t z : slots[i]) {
            decode_frame(*pixels, format, images[i].mosaic, frames[z].index, frames[z], !kept,
                         values + z * slice_voxels);
        }
        images[i].file.reset();  // drops the decoded pixel data
        images[i].decoded_words = {};
    }

    const std::span<const float> all(values, static_cast<std::size_t>(voxels));
    VoxelType type = VoxelType::float32;
    Rescale rescale;
    std::vector<std::byte> data;
    if (kept) {
        rescale = {first.slope, first.intercept};
        if (format.is_signed) {
            type = VoxelType::int16;
            data = narrow_to<std::int16_t>(all);
        } else if (format.bits_allocated == 8) {
            type = VoxelType::uint8;
            data = narrow_to<std::uint8_t>(all);
        } else {
            type = VoxelType::uint16;
            data = narrow_to<std::uint16_t>(all);
        }
    } else {
        data = std::move(decoded);
    }
    decoded = {};

    auto volume = make_volume(
            name,
            glm::uvec3(format.columns, format.rows, static_cast<std::uint32_t>(frames.size())),
            geometry->spacing, type, std::move(data), rescale);
    if (!volume) {
        base::Error error = volume.error();
        error.where = detail::at_file(source);
        return error;
    }
    volume->notes = std::move(notes);
    if (auto placed = place_volume(*volume, *geometry, options); !placed) {
        base::Error error = placed.error();
        error.where = detail::at_file(source);
        return error;
    }
    volume->hounsfield = images.front().hounsfield;
    return volume;
}

}  // namespace penumbra::volume::detail::dicom
