#include "dicom_jpeg2000.hpp"

#include "file_io.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <dcmtk/dcmdata/dccodec.h>
#include <dcmtk/dcmdata/dcdatset.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcpixel.h>
#include <dcmtk/dcmdata/dcpixseq.h>
#include <dcmtk/dcmdata/dcpxitem.h>
#include <openjpeg.h>

namespace penumbra::volume::detail::dicom {
namespace {

// OpenJPEG reads from callbacks; this one serves a frame's bytes from memory.
struct MemoryStream {
    std::span<const std::uint8_t> bytes;
    std::size_t offset = 0;
};

OPJ_SIZE_T read_from(void* buffer, OPJ_SIZE_T size, void* user) {
    auto& stream = *static_cast<MemoryStream*>(user);
    const std::size_t left = stream.bytes.size() - stream.offset;
    if (left == 0) {
        return static_cast<OPJ_SIZE_T>(-1);  // OpenJPEG's end of stream
    }
    const std::size_t count = std::min<std::size_t>(size, left);
    std::memcpy(buffer, stream.bytes.data() + stream.offset, count);
    stream.offset += count;
    return count;
}

OPJ_OFF_T skip_in(OPJ_OFF_T count, void* user) {
    auto& stream = *static_cast<MemoryStream*>(user);
    if (count < 0) {
        const std::size_t back =
                std::min<std::size_t>(static_cast<std::size_t>(-count), stream.offset);
        stream.offset -= back;
        return -static_cast<OPJ_OFF_T>(back);
    }
    const std::size_t ahead = std::min<std::size_t>(static_cast<std::size_t>(count),
                                                    stream.bytes.size() - stream.offset);
    stream.offset += ahead;
    return static_cast<OPJ_OFF_T>(ahead);
}

OPJ_BOOL seek_to(OPJ_OFF_T position, void* user) {
    auto& stream = *static_cast<MemoryStream*>(user);
    if (position < 0 || static_cast<std::size_t>(position) > stream.bytes.size()) {
        return OPJ_FALSE;
    }
    stream.offset = static_cast<std::size_t>(position);
    return OPJ_TRUE;
}

// Keeps OpenJPEG's first error message (it reports through callbacks, not return values).
void keep_first_message(const char* message, void* user) {
    auto& kept = *static_cast<std::string*>(user);
    if (kept.empty() && message != nullptr) {
        kept = message;
        while (!kept.empty() && (kept.back() == '\n' || kept.back() == ' ')) {
            kept.pop_back();
        }
    }
}

void ignore_message(const char* /*message*/, void* /*user*/) {}

struct CodecDeleter {
    void operator()(opj_codec_t* codec) const { opj_destroy_codec(codec); }
};

struct StreamDeleter {
    void operator()(opj_stream_t* stream) const { opj_stream_destroy(stream); }
};

struct ImageDeleter {
    void operator()(opj_image_t* image) const { opj_image_destroy(image); }
};

using DecodedImage = std::unique_ptr<opj_image_t, ImageDeleter>;

// A JP2 file (a codestream in boxes) rather than a bare codestream: some writers put one in the
// pixel data although DICOM asks for the codestream alone.
bool is_jp2_file(std::span<const std::uint8_t> bytes) {
    static constexpr std::array<std::uint8_t, 12> signature{0x00, 0x00, 0x00, 0x0C, 0x6A, 0x50,
                                                            0x20, 0x20, 0x0D, 0x0A, 0x87, 0x0A};
    return bytes.size() >= signature.size() &&
           std::equal(signature.begin(), signature.end(), bytes.begin());
}

// What a codestream's SIZ marker says OpenJPEG will allocate for: read by hand before OpenJPEG
// sees the bytes, since reading its header already allocates per tile and component.
struct CodestreamSize {
    std::uint64_t width = 0;
    std::uint64_t height = 0;
    std::uint32_t components = 0;
    std::uint64_t tiles = 0;
    bool subsampled = false;  // the first component on a coarser grid than the image
};

// More tiles than any real frame is cut into: each costs OpenJPEG about a kilobyte per component
// once the header is read.
constexpr std::uint64_t max_tiles = 4096;

std::uint64_t big_endian(std::span<const std::uint8_t> bytes, std::size_t at, std::size_t count) {
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < count; ++i) {
        value = (value << 8) | bytes[at + i];
    }
    return value;
}

// The SIZ marker of a codestream, or of the codestream box (jp2c) of a JP2 file; nothing when
// neither is where it must be.
std::optional<CodestreamSize> read_size(std::span<const std::uint8_t> bytes);

// A fragment that starts a codestream (SOC then SIZ) or a JP2 file: where a frame begins when the
// offset table does not say.
bool starts_a_frame(std::span<const std::uint8_t> bytes) {
    return (bytes.size() >= 4 && bytes[0] == 0xFF && bytes[1] == 0x4F && bytes[2] == 0xFF &&
            bytes[3] == 0x51) ||
           is_jp2_file(bytes);
}

std::optional<CodestreamSize> read_size(std::span<const std::uint8_t> bytes) {
    if (is_jp2_file(bytes)) {
        std::optional<std::span<const std::uint8_t>> codestream;
        for (std::size_t at = 0; at + 8 <= bytes.size();) {
            std::uint64_t length = big_endian(bytes, at, 4);
            std::size_t header = 8;
            if (length == 1 && at + 16 <= bytes.size()) {
                length = big_endian(bytes, at + 8, 8);
                header = 16;
            } else if (length == 0) {
                length = bytes.size() - at;  // the last box runs to the end
            }
            if (length < header || length > bytes.size() - at) {
                return std::nullopt;
            }
            if (big_endian(bytes, at + 4, 4) == 0x6A703263) {  // "jp2c"
                codestream = bytes.subspan(at + header, static_cast<std::size_t>(length) - header);
                break;
            }
            at += static_cast<std::size_t>(length);
        }
        if (!codestream) {
            return std::nullopt;
        }
        bytes = *codestream;
    }
    // SOC, then SIZ: Lsiz Rsiz Xsiz Ysiz XOsiz YOsiz XTsiz YTsiz XTOsiz YTOsiz Csiz, then Ssiz
    // XRsiz YRsiz per component.
    constexpr std::size_t siz = 4;
    if (bytes.size() < siz + 41 || big_endian(bytes, 0, 4) != 0xFF4FFF51) {
        return std::nullopt;
    }
    const auto field = [&](std::size_t offset) { return big_endian(bytes, siz + offset, 4); };
    const std::uint64_t x = field(4);
    const std::uint64_t y = field(8);
    const std::uint64_t x_origin = field(12);
    const std::uint64_t y_origin = field(16);
    const std::uint64_t tile_width = field(20);
    const std::uint64_t tile_height = field(24);
    const std::uint64_t tile_x = field(28);
    const std::uint64_t tile_y = field(32);
    if (x <= x_origin || y <= y_origin || tile_width == 0 || tile_height == 0 ||
        tile_x > x_origin || tile_y > y_origin) {
        return std::nullopt;
    }
    CodestreamSize size;
    size.width = x - x_origin;
    size.height = y - y_origin;
    size.components = static_cast<std::uint32_t>(big_endian(bytes, siz + 36, 2));
    size.tiles = ((x - tile_x + tile_width - 1) / tile_width) *
                 ((y - tile_y + tile_height - 1) / tile_height);
    size.subsampled = bytes[siz + 39] != 1 || bytes[siz + 40] != 1;
    return size;
}

base::Result<DecodedImage> decode_frame(std::span<const std::uint8_t> bytes,
                                        const PixelFormat& format,
                                        const std::filesystem::path& path) {
    const auto failed = [&](const std::string& why) {
        return base::make_error(base::ErrorCode::decode_failed,
                                "the JPEG 2000 pixel data cannot be decoded: " + why,
                                detail::at_file(path));
    };
    const auto size = read_size(bytes);
    if (!size) {
        return failed(
                "no JPEG 2000 codestream (SOC and SIZ markers) starts the frame, or its SIZ "
                "marker is malformed");
    }
    if (size->components != 1) {
        return failed("it holds " + std::to_string(size->components) +
                      " components; a scalar volume has one sample per pixel");
    }
    if (size->width != format.columns || size->height != format.rows) {
        return failed("its image is " + std::to_string(size->width) + "x" +
                      std::to_string(size->height) + ", the header says " +
                      std::to_string(format.columns) + "x" + std::to_string(format.rows));
    }
    if (size->subsampled) {
        return failed("its samples lie on a coarser grid than its pixels (subsampled)");
    }
    if (size->tiles > max_tiles) {
        return failed("it is cut into " + std::to_string(size->tiles) + " tiles, more than " +
                      std::to_string(max_tiles));
    }
    std::unique_ptr<opj_codec_t, CodecDeleter> codec(
            opj_create_decompress(is_jp2_file(bytes) ? OPJ_CODEC_JP2 : OPJ_CODEC_J2K));
    std::unique_ptr<opj_stream_t, StreamDeleter> stream(opj_stream_create(1 << 16, OPJ_TRUE));
    if (!codec || !stream) {
        return failed("OpenJPEG could not start");
    }
    std::string error;
    opj_set_error_handler(codec.get(), keep_first_message, &error);
    opj_set_warning_handler(codec.get(), ignore_message, nullptr);
    opj_set_info_handler(codec.get(), ignore_message, nullptr);
    opj_dparameters_t parameters;
    opj_set_default_decoder_parameters(&parameters);
    // A JP2 file's palette or channel definitions would change the samples after the checks.
    parameters.flags |= OPJ_DPARAMETERS_IGNORE_PCLR_CMAP_CDEF_FLAG;
    if (opj_setup_decoder(codec.get(), &parameters) == OPJ_FALSE) {
        return failed(error.empty() ? "OpenJPEG refused the decoder's setup" : error);
    }
    MemoryStream memory{bytes, 0};
    opj_stream_set_user_data(stream.get(), &memory, nullptr);
    opj_stream_set_user_data_length(stream.get(), bytes.size());
    opj_stream_set_read_function(stream.get(), read_from);
    opj_stream_set_skip_function(stream.get(), skip_in);
    opj_stream_set_seek_function(stream.get(), seek_to);
    opj_image_t* raw = nullptr;
    if (opj_read_header(stream.get(), codec.get(), &raw) == OPJ_FALSE) {
        opj_image_destroy(raw);
        return failed(error.empty() ? "its header is not a JPEG 2000 codestream" : error);
    }
    DecodedImage image(raw);
    // What OpenJPEG read must be what the SIZ marker said, before decoding allocates for it and
    // again after (nothing may have changed the samples' shape on the way).
    const auto check = [&]() -> base::Status {
        if (image->numcomps != 1) {
            return failed("it holds " + std::to_string(image->numcomps) +
                          " components; a scalar volume has one sample per pixel");
        }
        const opj_image_comp_t& component = image->comps[0];
        if (image->x1 - image->x0 != format.columns || image->y1 - image->y0 != format.rows ||
            component.dx != 1 || component.dy != 1 || component.w != format.columns ||
            component.h != format.rows) {
            return failed("OpenJPEG read an image of another size than its SIZ marker gives");
        }
        if (component.prec < 1 || component.prec > format.bits_allocated) {
            return failed(std::to_string(component.prec) + "-bit samples do not fit the " +
                          std::to_string(format.bits_allocated) + " bits allocated");
        }
        return base::Ok{};
    };
    if (auto status = check(); !status) {
        return status.error();
    }
    if (opj_decode(codec.get(), stream.get(), image.get()) == OPJ_FALSE ||
        opj_end_decompress(codec.get(), stream.get()) == OPJ_FALSE) {
        return failed(error.empty() ? "the codestream is damaged" : error);
    }
    if (auto status = check(); !status) {
        return status.error();
    }
    if (image->comps[0].data == nullptr) {
        return failed("no samples came out");
    }
    return image;
}

// The bytes of each frame: its fragments joined.
base::Result<std::vector<std::vector<std::uint8_t>>> frame_bytes(
        DcmDataset& dataset, std::uint32_t frames, const std::filesystem::path& path) {
    DcmElement* element = nullptr;
    DcmPixelSequence* sequence = nullptr;
    if (dataset.findAndGetElement(DCM_PixelData, element).bad() || element == nullptr ||
        OFstatic_cast(DcmPixelData*, element)
                ->getEncapsulatedRepresentation(dataset.getOriginalXfer(), nullptr, sequence)
                .bad() ||
        sequence == nullptr) {
        return base::make_error(base::ErrorCode::truncated,
                                "the JPEG 2000 pixel data holds no fragments",
                                detail::at_file(path));
    }
    std::vector<std::span<const std::uint8_t>> fragments;
    for (unsigned long i = 1; i < sequence->card(); ++i) {  // item 0: the offset table
        DcmPixelItem* item = nullptr;
        Uint8* bytes = nullptr;
        if (sequence->getItem(item, i).bad() || item == nullptr ||
            item->getUint8Array(bytes).bad()) {
            return base::make_error(base::ErrorCode::truncated,
                                    "fragment " + std::to_string(i) + " cannot be read",
                                    detail::at_file(path));
        }
        fragments.emplace_back(bytes, bytes == nullptr ? 0 : item->getLength());
    }
    // Where each frame starts: as DCMTK reads the offset table (or one fragment per frame), else
    // at each fragment that starts a codestream.
    std::vector<std::size_t> starts;
    for (std::uint32_t f = 0; f < frames; ++f) {
        Uint32 item = 0;
        if (DcmCodec::determineStartFragment(f, static_cast<Sint32>(frames), sequence, item)
                    .bad() ||
            item == 0) {
            starts.clear();
            break;
        }
        starts.push_back(item - 1);
    }
    if (starts.empty() ||
        std::adjacent_find(starts.begin(), starts.end(), std::greater_equal<>()) != starts.end()) {
        starts.clear();
        for (std::size_t i = 0; i < fragments.size(); ++i) {
            if (i == 0 || starts_a_frame(fragments[i])) {
                starts.push_back(i);
            }
        }
    }
    if (starts.size() != frames) {
        return base::make_error(base::ErrorCode::corrupt_data,
                                "the JPEG 2000 pixel data holds " + std::to_string(starts.size()) +
                                        " codestreams for " + std::to_string(frames) + " frames",
                                detail::at_file(path));
    }
    std::vector<std::vector<std::uint8_t>> joined(frames);
    for (std::uint32_t f = 0; f < frames; ++f) {
        const std::size_t end = f + 1 < frames ? starts[f + 1] : fragments.size();
        for (std::size_t i = starts[f]; i < end; ++i) {
            joined[f].insert(joined[f].end(), fragments[i].begin(), fragments[i].end());
        }
    }
    return joined;
}

}  // namespace

bool is_jpeg2000(E_TransferSyntax syntax) {
    return syntax == EXS_JPEG2000LosslessOnly || syntax == EXS_JPEG2000 ||
           syntax == EXS_JPEG2000MulticomponentLosslessOnly || syntax == EXS_JPEG2000Multicomponent;
}

base::Result<std::vector<std::byte>> decode_jpeg2000(DcmDataset& dataset, std::uint32_t frames,
                                                     PixelFormat& format,
                                                     const std::filesystem::path& path) {
    auto streams = frame_bytes(dataset, frames, path);
    if (!streams) {
        return streams.error();
    }
    const std::size_t pixels = std::size_t{format.rows} * format.columns;
    const std::size_t word_bytes = format.bits_allocated / 8u;
    std::vector<std::byte> words(pixels * word_bytes * frames);
    bool first_signed = false;
    std::uint16_t first_bits = 0;
    for (std::uint32_t f = 0; f < frames; ++f) {
        auto image = decode_frame((*streams)[f], format, path);
        if (!image) {
            return image.error();
        }
        const opj_image_comp_t& component = (*image)->comps[0];
        const bool is_signed = component.sgnd != 0;
        const auto bits = static_cast<std::uint16_t>(component.prec);
        if (f == 0) {
            // The header's PixelRepresentation reads the codestream's bits, as GDCM and pydicom
            // read them (an unsigned codestream of a signed image holds two's complement); only
            // negative samples, or more bits than the header says, make the codestream win.
            format.is_signed = format.is_signed || is_signed;
            if (bits > format.bits_stored) {
                format.bits_stored = bits;
                format.high_bit = static_cast<std::uint16_t>(bits - 1u);
            }
            first_signed = is_signed;
            first_bits = bits;
        } else if (is_signed != first_signed || bits != first_bits) {
            return base::make_error(base::ErrorCode::inconsistent_series,
                                    "JPEG 2000 frame " + std::to_string(f + 1) +
                                            " stores its samples unlike the first frame",
                                    detail::at_file(path));
        }
        const unsigned shift = format.high_bit + 1u - format.bits_stored;
        const std::uint32_t mask =
                format.bits_stored >= 32 ? ~0u : (std::uint32_t{1} << format.bits_stored) - 1u;
        std::byte* out = words.data() + std::size_t{f} * pixels * word_bytes;
        for (std::size_t i = 0; i < pixels; ++i) {
            const std::uint32_t word = (static_cast<std::uint32_t>(component.data[i]) & mask)
                                       << shift;
            for (std::size_t b = 0; b < word_bytes; ++b) {
                out[i * word_bytes + b] = static_cast<std::byte>((word >> (8 * b)) & 0xFFu);
            }
        }
    }
    return words;
}

}  // namespace penumbra::volume::detail::dicom
