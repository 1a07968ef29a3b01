// DICOM through DCMTK (Debian's libdcmtk): a folder holding the slices of one or more series, or
// one file (a multi-frame image, or a single slice).
//
// Rules this loader adds on top of the library:
//   - In a folder, only DICOM Part 10 files (the "DICM" marker after the 128-byte preamble) are
//     read; other files (README.txt, .DS_Store, thumbnails) and DICOM objects without pixel data
//     (DICOMDIR, reports) are skipped and counted in the log, and images of another kind (colour
//     secondary captures, float or odd bit depths, mosaics that cannot be unpacked) are skipped
//     with a warning naming each, so the series beside them opens; a folder of nothing else is that
//     image's error. Damaged files (cut short, unreadable headers) are skipped too, each named in
//     a note on the volume; a slice of the series lost with one is a gap, which refuses the series
//     (the spacing check, or the damaged file's own position where DCMTK read that far).
//     Sub-folders are searched too (unless LoadOptions says not), at most max_folder_depth levels
//     and max_folder_files files deep: a DICOMDIR export root keeps its images in
//     DICOM/<patient>/<study>/<series>/ and a study folder has one folder per series. The DICOMDIR
//     itself is not needed: every image file names its own series.
//   - Several series in one folder: LoadOptions::dicom_series picks one by SeriesNumber or
//     SeriesInstanceUID; without it the error "several_series" lists them (a scout beside a
//     series is a series of its own, and guessing would open the wrong one silently).
//   - A series holding several volumes (echoes, acquisitions, time points: each position
//     repeated as often) opens its first volume, the lowest (TemporalPositionIdentifier,
//     EchoNumbers, AcquisitionNumber, InstanceNumber) at each position, with a note saying so.
//   - Siemens mosaics (ImageType MOSAIC, or NumberOfImagesInMosaic (0019,100a)) tile a volume's
//     slices in one image: unpacked into the slices as nibabel and dcm2niix do (the corner
//     position corrected, slices along the CSA header's SliceNormalVector); one whose number of
//     slices is missing or does not tile the image is refused saying "mosaic".
//   - Slices (and the frames of multi-frame files, whose positions may sit in the functional
//     groups) are ordered by their position along the slice normal, ImageOrientationPatient's
//     row x column direction dotted with ImagePositionPatient. The z spacing is the gap between
//     neighbours, which must be the same within 1 % (else an error names the two slices). Where
//     any slice lacks position or orientation, InstanceNumber orders them and the z spacing is
//     SpacingBetweenSlices, else SliceThickness, else 1 (with a log warning).
//   - The voxel grid is the image grid: x along a row, y down the columns, z along the normal;
//     Volume::axes and origin place it in patient space (converted from DICOM's LPS to RAS), so
//     a sagittal series keeps its anatomy. A gantry-tilted series (slices stepping off their
//     normal) is refused as sheared.
//   - Spacing x is PixelSpacing's second value (between columns), y its first (between rows).
//   - When every slice has the same RescaleSlope and RescaleIntercept, both whole numbers, the
//     stored values are kept (uint8 for 8-bit unsigned data, uint16 for unsigned, int16 for
//     signed) and the rescale becomes Volume::rescale, so a CT stays 16-bit with its values in
//     Hounsfield units. Otherwise the rescale is applied per slice into float32.
//   - Modality CT or RescaleType HU sets Volume::hounsfield. MONOCHROME1 is inverted.
//   - Pixel data must be one sample per pixel, 8 or 16 bits allocated; BitsStored, HighBit and
//     PixelRepresentation (two's complement) are honoured. Compressed transfer syntaxes are
//     decoded by DCMTK's JPEG, JPEG-LS and RLE codecs; others (JPEG 2000) are an error naming
//     the transfer syntax.

#include "file_io.hpp"
#include "file_name.hpp"
#include "memory_budget.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcdict.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcrledrg.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmdata/dcxfer.h>
#include <dcmtk/dcmjpeg/djdecode.h>
#include <dcmtk/dcmjpls/djdecode.h>
#include <dcmtk/oflog/oflog.h>

namespace penumbra::volume {
namespace {

constexpr std::string_view log_component = "volume";

// Slice gaps may differ from the median gap by this fraction: scanners write positions
// rounded to a few decimals, while a missing slice changes a gap by 100 %.
constexpr double gap_tolerance = 0.01;

// Frames of one volume: far beyond any scanner's series, and small enough that their positions
// (a few hundred bytes each) cost little.
constexpr std::uint64_t max_frames = std::uint64_t{1} << 16;

// Orientation cosines of two slices of one series agree to this much.
constexpr double orientation_tolerance = 1e-4;

// Codecs are registered once per process and never cleaned up: cleanup would race with another
// thread's load, and the process ends anyway. DCMTK's own log goes to stderr at warning level;
// failures reach the user as Errors instead, so it is silenced.
void prepare_library() {
    static std::once_flag once;
    std::call_once(once, [] {
        OFLog::configure(OFLogger::OFF_LOG_LEVEL);
        DJDecoderRegistration::registerCodecs();
        DJLSDecoderRegistration::registerCodecs();
        DcmRLEDecoderRegistration::registerCodecs();
    });
}

std::string millimetres(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g mm", value);
    return text;
}

std::string tag_label(const DcmTagKey& key) {
    DcmTag tag(key);  // getTagName() is not const: it looks the name up on first use
    return std::string(tag.getTagName()) + " " + key.toString().c_str();
}

base::Error missing_tag(const DcmTagKey& key, const std::filesystem::path& path) {
    return base::make_error("bad_header", "missing or unreadable tag " + tag_label(key),
                            detail::at_file(path));
}

std::optional<double> get_double(DcmItem& item, const DcmTagKey& key, unsigned long pos = 0) {
    Float64 value = 0.0;
    if (item.findAndGetFloat64(key, value, pos).good() && std::isfinite(value)) {
        return value;
    }
    return std::nullopt;
}

template <std::size_t N>
std::optional<std::array<double, N>> get_doubles(DcmItem& item, const DcmTagKey& key) {
    std::array<double, N> values{};
    for (std::size_t i = 0; i < N; ++i) {
        const auto value = get_double(item, key, i);
        if (!value) {
            return std::nullopt;
        }
        values[i] = *value;
    }
    return values;
}

std::optional<std::int32_t> get_int(DcmItem& item, const DcmTagKey& key) {
    Sint32 value = 0;
    if (item.findAndGetSint32(key, value).good()) {
        return value;
    }
    return std::nullopt;
}

std::optional<std::uint16_t> get_uint16(DcmItem& item, const DcmTagKey& key) {
    Uint16 value = 0;
    if (item.findAndGetUint16(key, value).good()) {
        return value;
    }
    return std::nullopt;
}

std::string get_string(DcmItem& item, const DcmTagKey& key) {
    OFString value;
    if (item.findAndGetOFString(key, value).good()) {
        return value.c_str();
    }
    return {};
}

// The item of functional group `group` (e.g. PlanePositionSequence) that applies to `frame` of
// an enhanced multi-frame image: the frame's own, else the shared one; null in other images.
DcmItem* functional_group(DcmItem& dataset, std::uint32_t frame, const DcmTagKey& group) {
    DcmItem* groups = nullptr;
    DcmItem* item = nullptr;
    if (dataset.findAndGetSequenceItem(DCM_PerFrameFunctionalGroupsSequence, groups,
                                       static_cast<signed long>(frame))
                .good() &&
        groups->findAndGetSequenceItem(group, item).good()) {
        return item;
    }
    if (dataset.findAndGetSequenceItem(DCM_SharedFunctionalGroupsSequence, groups).good() &&
        groups->findAndGetSequenceItem(group, item).good()) {
        return item;
    }
    return nullptr;
}

// A tag of one frame: from its functional group where the image has them, else from the top
// level, where classic single-frame images keep it.
template <class Get>
auto frame_value(DcmItem& dataset, std::uint32_t frame, const DcmTagKey& group, Get get)
        -> decltype(get(dataset)) {
    if (DcmItem* item = functional_group(dataset, frame, group)) {
        if (auto value = get(*item)) {
            return value;
        }
    }
    return get(dataset);
}

// How the stored pixel values are laid out; every image of a series must agree.
struct PixelFormat {
    std::uint16_t rows = 0;
    std::uint16_t columns = 0;
    std::uint16_t samples_per_pixel = 1;
    std::uint16_t bits_allocated = 0;
    std::uint16_t bits_stored = 0;
    std::uint16_t high_bit = 0;
    bool is_signed = false;
    bool inverted = false;  // MONOCHROME1: the lowest value is displayed brightest

    bool operator==(const PixelFormat&) const = default;

    [[nodiscard]] std::string describe() const {
        return std::to_string(columns) + "x" + std::to_string(rows) + " pixels, " +
               std::to_string(samples_per_pixel) + " sample(s) per pixel, " +
               std::to_string(bits_stored) + " of " + std::to_string(bits_allocated) + " bits " +
               (is_signed ? "signed" : "unsigned");
    }
};

// A Siemens mosaic: `tiles` x `tiles` slices of a volume tiled row by row in one stored image,
// the first `slices` of them in use.
struct Mosaic {
    std::uint32_t tiles = 1;
    std::uint16_t stored_rows = 0;
    std::uint16_t stored_columns = 0;
    std::optional<glm::dvec3> slice_normal;  // CSA SliceNormalVector (LPS)
};

// One 2-D image of the volume: a single-frame file or one frame of a multi-frame file.
struct Frame {
    std::size_t image = 0;    // index into the loaded images
    std::uint32_t index = 0;  // frame number within its image
    std::optional<glm::dvec3> position;
    std::optional<std::array<double, 6>> orientation;
    std::optional<std::array<double, 2>> pixel_spacing;  // between rows, between columns
    std::optional<double> slice_thickness;
    std::optional<double> spacing_between_slices;
    std::int32_t instance_number = 0;
    // Which of several volumes sharing this position the frame belongs to: the lowest is the
    // first volume (temporal position, echo, acquisition, instance number, frame number).
    std::array<std::int64_t, 5> volume_key{};
    double slope = 1.0;
    double intercept = 0.0;
};

struct Image {
    std::filesystem::path path;
    std::unique_ptr<DcmFileFormat> file;  // pixel data stays on disk until it is read
    std::string series_uid;
    std::string series_number;
    std::string series_description;
    std::string modality;
    bool hounsfield = false;  // Modality CT or RescaleType HU
    PixelFormat format;       // of one slice: for a mosaic, of one tile
    std::uint32_t frame_count = 1;
    std::optional<Mosaic> mosaic;
    // Where each frame lies along the slice normal (ImagePositionPatient dotted with the
    // normal of ImageOrientationPatient), read with the header so that a listing can count a
    // series' slices without its pixel data; empty where a frame lacks either.
    std::vector<double> frame_depths;
};

// The pixel words an image stores for all its frames (a mosaic: its whole tiled image).
std::uint64_t stored_pixels(const Image& image) {
    if (image.mosaic) {
        return std::uint64_t{image.mosaic->stored_rows} * image.mosaic->stored_columns;
    }
    return std::uint64_t{image.format.rows} * image.format.columns * image.frame_count;
}

base::Result<PixelFormat> read_pixel_format(DcmDataset& dataset,
                                            const std::filesystem::path& path) {
    PixelFormat format;
    for (auto [key, field] :
         {std::pair{DCM_Rows, &format.rows}, std::pair{DCM_Columns, &format.columns},
          std::pair{DCM_BitsAllocated, &format.bits_allocated}}) {
        const auto value = get_uint16(dataset, key);
        if (!value) {
            return missing_tag(key, path);
        }
        *field = *value;
    }
    format.samples_per_pixel = get_uint16(dataset, DCM_SamplesPerPixel).value_or(1);
    format.bits_stored = get_uint16(dataset, DCM_BitsStored).value_or(format.bits_allocated);
    format.high_bit = get_uint16(dataset, DCM_HighBit).value_or(format.bits_stored - 1);
    format.is_signed = get_uint16(dataset, DCM_PixelRepresentation).value_or(0) == 1;
    format.inverted = get_string(dataset, DCM_PhotometricInterpretation) == "MONOCHROME1";

    const auto unsupported = [&](const std::string& what) {
        return base::make_error("unsupported_type", what, detail::at_file(path));
    };
    if (format.rows == 0 || format.columns == 0) {
        return base::make_error("bad_header",
                                "an image of " + std::to_string(format.columns) + "x" +
                                        std::to_string(format.rows) + " pixels",
                                detail::at_file(path));
    }
    if (format.samples_per_pixel != 1) {
        return unsupported(std::to_string(format.samples_per_pixel) +
                           " samples per pixel (colour images) are not supported; a volume "
                           "needs one sample per pixel");
    }
    if (format.bits_allocated != 8 && format.bits_allocated != 16) {
        return unsupported(std::to_string(format.bits_allocated) +
                           " bits allocated per pixel are not supported; 8 and 16 are");
    }
    if (format.bits_stored == 0 || format.bits_stored > format.bits_allocated ||
        format.high_bit >= format.bits_allocated || format.high_bit + 1 < format.bits_stored) {
        return base::make_error("bad_header",
                                "BitsStored " + std::to_string(format.bits_stored) +
                                        " and HighBit " + std::to_string(format.high_bit) +
                                        " do not fit in BitsAllocated " +
                                        std::to_string(format.bits_allocated),
                                detail::at_file(path));
    }
    return format;
}

// The positions of a mosaic's slices. Its ImagePositionPatient is that of the tiled image's
// first pixel as if it were one slice: the first tile's first pixel lies half the difference of
// the two sizes further along the rows and columns (the correction nibabel and dcm2niix make);
// each next slice steps along the CSA slice normal (else the row x column direction) by
// SpacingBetweenSlices, else SliceThickness. Without position or orientation the slices keep
// their tile order.
void place_mosaic_slices(std::vector<Frame>& frames, const Mosaic& mosaic,
                         const PixelFormat& tile) {
    const Frame& first = frames.front();
    if (!first.position || !first.orientation || !first.pixel_spacing) {
        return;
    }
    const auto& cosines = *first.orientation;
    const glm::dvec3 row(cosines[0], cosines[1], cosines[2]);
    const glm::dvec3 column(cosines[3], cosines[4], cosines[5]);
    glm::dvec3 normal = glm::cross(row, column);
    if (mosaic.slice_normal && glm::length(*mosaic.slice_normal) > 0.5 &&
        std::isfinite(glm::length(*mosaic.slice_normal))) {
        normal = *mosaic.slice_normal;
    }
    if (!(glm::length(normal) > 0.5)) {
        return;  // parallel directions: order_frames names the error
    }
    normal = glm::normalize(normal);
    double gap = 1.0;
    if (first.spacing_between_slices && *first.spacing_between_slices > 0.0) {
        gap = *first.spacing_between_slices;
    } else if (first.slice_thickness && *first.slice_thickness > 0.0) {
        gap = *first.slice_thickness;
    }
    const auto& spacing = *first.pixel_spacing;  // between rows, between columns
    const glm::dvec3 corner =
            *first.position +
            row * spacing[1] * (double(mosaic.stored_columns) - double(tile.columns)) / 2.0 +
            column * spacing[0] * (double(mosaic.stored_rows) - double(tile.rows)) / 2.0;
    for (std::size_t f = 0; f < frames.size(); ++f) {
        frames[f].position = corner + static_cast<double>(f) * gap * normal;
    }
}

glm::dvec3 slice_normal(const std::array<double, 6>& orientation) {
    const glm::dvec3 row(orientation[0], orientation[1], orientation[2]);
    const glm::dvec3 column(orientation[3], orientation[4], orientation[5]);
    return glm::cross(row, column);
}

std::vector<Frame> read_frames(DcmDataset& dataset, std::size_t image_index,
                               std::uint32_t frame_count, const std::optional<Mosaic>& mosaic,
                               const PixelFormat& format) {
    std::vector<Frame> frames(frame_count);
    const auto instance = get_int(dataset, DCM_InstanceNumber).value_or(0);
    const std::int64_t temporal_position =
            get_int(dataset, DCM_TemporalPositionIdentifier).value_or(0);
    const std::int64_t echo = get_int(dataset, DCM_EchoNumbers).value_or(0);
    const std::int64_t acquisition = get_int(dataset, DCM_AcquisitionNumber).value_or(0);
    for (std::uint32_t f = 0; f < frame_count; ++f) {
        Frame& frame = frames[f];
        frame.image = image_index;
        frame.index = f;
        frame.instance_number = instance;
        frame.volume_key = {temporal_position, echo, acquisition, instance, f};
        const auto position = frame_value(dataset, f, DCM_PlanePositionSequence, [](DcmItem& item) {
            return get_doubles<3>(item, DCM_ImagePositionPatient);
        });
        // A legacy multi-frame image has one top-level position, that of its first frame.
        if (position && (f == 0 || functional_group(dataset, f, DCM_PlanePositionSequence))) {
            frame.position = glm::dvec3((*position)[0], (*position)[1], (*position)[2]);
        }
        frame.orientation = frame_value(
                dataset, f, DCM_PlaneOrientationSequence,
                [](DcmItem& item) { return get_doubles<6>(item, DCM_ImageOrientationPatient); });
        const auto measure = [&](auto get) {
            return frame_value(dataset, f, DCM_PixelMeasuresSequence, get);
        };
        frame.pixel_spacing = measure([](DcmItem& item) {
            auto spacing = get_doubles<2>(item, DCM_PixelSpacing);
            return spacing ? spacing : get_doubles<2>(item, DCM_ImagerPixelSpacing);
        });
        frame.slice_thickness =
                measure([](DcmItem& item) { return get_double(item, DCM_SliceThickness); });
        frame.spacing_between_slices =
                measure([](DcmItem& item) { return get_double(item, DCM_SpacingBetweenSlices); });
        const auto rescale = [&](const DcmTagKey& key) {
            return frame_value(dataset, f, DCM_PixelValueTransformationSequence,
                               [&](DcmItem& item) { return get_double(item, key); });
        };
        const auto slope = rescale(DCM_RescaleSlope);
        frame.slope = slope && *slope != 0.0 ? *slope : 1.0;
        frame.intercept = rescale(DCM_RescaleIntercept).value_or(0.0);
    }
    if (mosaic) {
        place_mosaic_slices(frames, *mosaic, format);
    }
    return frames;
}

// A CSA item's text as a whole number: digits only, around blanks, within 32 bits; a header's text
// is untrusted, and a negative or huge count must not pass as a slice count.
bool parse_whole(std::string_view text, std::uint32_t& value) {
    const auto first = text.find_first_not_of(' ');
    const auto last = text.find_last_not_of(' ');
    if (first == std::string_view::npos) {
        return false;
    }
    const std::string_view digits = text.substr(first, last - first + 1);
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    return error == std::errc() && end == digits.data() + digits.size();
}

// Siemens' NumberOfImagesInMosaic and CSA Image Header Info, private tags of its groups.
const DcmTagKey siemens_images_in_mosaic(0x0019, 0x100a);
const DcmTagKey siemens_csa_image_header(0x0029, 0x1010);
// The private creator that reserves (0029,10xx): only under it is (0029,1010) a CSA header; other
// vendors' private groups reuse the numbers, and CSA1 has no signature to tell them apart.
const DcmTagKey siemens_csa_creator(0x0029, 0x0010);
constexpr std::string_view siemens_csa_creator_name = "SIEMENS CSA HEADER";

// The text values of element `name` in a Siemens CSA header, or nothing where the header is
// absent, damaged, or lacks the element. Syngo writes two layouts, both read as SPM's
// spm_dicom_headers reads them (nibabel's csareader offsets CSA1's item lengths by the second
// element's count of items instead of the first's):
//   - "SV10" (CSA2): the signature, 4 unused bytes, a count of elements and an unused word; each
//     element a 64-byte name, its multiplicity, VR, SyngoDT, a count of items and an unused word;
//     each item four words, the second its length, then the text padded to four bytes.
//   - the older CSA1, which archives of older Siemens scanners still hold: no signature, the
//     count of elements first; elements as in CSA2, but an item's length is its
//     first word less the first element's count of items, and an impossible length ends that
//     element's items (the reader goes on with the next element).
std::vector<std::string> csa_values(DcmDataset& dataset, std::string_view name) {
    OFString creator;
    if (dataset.findAndGetOFString(siemens_csa_creator, creator).bad() ||
        std::string_view(creator.c_str()).substr(0, siemens_csa_creator_name.size()) !=
                siemens_csa_creator_name) {
        return {};
    }
    const Uint8* bytes = nullptr;
    unsigned long size = 0;
    if (dataset.findAndGetUint8Array(siemens_csa_image_header, bytes, &size).bad() ||
        bytes == nullptr || size < 16) {
        return {};
    }
    const bool csa2 = std::memcmp(bytes, "SV10", 4) == 0;
    const auto int32_at = [&](std::size_t at) {
        std::int32_t value = 0;
        std::memcpy(&value, bytes + at, 4);
        return value;
    };
    constexpr std::int32_t max_elements = 128;  // nibabel's bound; real headers hold about 100
    const std::int32_t elements = int32_at(csa2 ? 8 : 0);
    if (elements < 1 || elements > max_elements) {
        return {};
    }
    std::size_t at = csa2 ? 16 : 8;
    std::int32_t first_element_items = 0;  // CSA1's item lengths are offset by it
    for (std::int32_t e = 0; e < elements; ++e) {
        if (at + 84 > size) {
            return {};
        }
        const std::string element(reinterpret_cast<const char*>(bytes + at),
                                  strnlen(reinterpret_cast<const char*>(bytes + at), 64));
        const std::int32_t multiplicity = int32_at(at + 64);
        const std::int32_t items = int32_at(at + 76);
        at += 84;
        if (items < 0 || items > 1024) {
            return {};
        }
        if (e == 0) {
            first_element_items = items;
        }
        std::vector<std::string> values;
        for (std::int32_t i = 0; i < items; ++i) {
            if (at + 16 > size) {
                return {};
            }
            const std::int32_t length =
                    csa2 ? int32_at(at + 4) : int32_at(at) - first_element_items;
            at += 16;
            if (length < 0 || at + static_cast<std::size_t>(length) > size) {
                if (csa2) {
                    return {};
                }
                break;
            }
            if (i < multiplicity) {
                const char* text = reinterpret_cast<const char*>(bytes + at);
                values.emplace_back(text, strnlen(text, static_cast<std::size_t>(length)));
            }
            at += static_cast<std::size_t>(length) + (4 - length % 4) % 4;
        }
        if (element == name) {
            return values;
        }
    }
    return {};
}

// Whether the image is a Siemens mosaic: ImageType holds MOSAIC, or NumberOfImagesInMosaic is
// set.
bool is_mosaic(DcmDataset& dataset) {
    if (dataset.tagExists(siemens_images_in_mosaic)) {
        return true;
    }
    OFString image_type;
    if (dataset.findAndGetOFStringArray(DCM_ImageType, image_type).bad()) {
        return false;
    }
    std::string_view rest(image_type.c_str());
    while (!rest.empty()) {
        const auto end = std::min(rest.find('\\'), rest.size());
        if (rest.substr(0, end) == "MOSAIC") {
            return true;
        }
        rest.remove_prefix(std::min(end + 1, rest.size()));
    }
    return false;
}

// A Siemens mosaic tiles every slice of a volume in one image, ceil(sqrt(n)) tiles a side, row by
// row: unpacked into its n slices, whose positions sit along the CSA header's slice normal (see
// read_frames). Refused, saying "mosaic", where the number of slices is missing or does not tile
// the image.
base::Result<std::optional<Mosaic>> read_mosaic(DcmDataset& dataset, PixelFormat& format,
                                                std::uint32_t& frame_count,
                                                const std::filesystem::path& path) {
    if (!is_mosaic(dataset)) {
        return std::optional<Mosaic>();
    }
    std::optional<std::uint32_t> slices = get_uint16(dataset, siemens_images_in_mosaic);
    if (!slices) {
        const auto csa = csa_values(dataset, "NumberOfImagesInMosaic");
        std::uint32_t parsed = 0;
        if (!csa.empty() && parse_whole(csa.front(), parsed)) {
            slices = parsed;
        }
    }
    const auto refuse = [&](const std::string& why) {
        return base::make_error("unsupported_type",
                                "a Siemens mosaic (slices tiled in one " +
                                        std::to_string(format.columns) + "x" +
                                        std::to_string(format.rows) + " image) whose " + why +
                                        "; convert the series with dcm2niix (Debian's dcm2niix) "
                                        "and open its NIfTI",
                                detail::at_file(path));
    };
    if (!slices || *slices == 0) {
        return refuse("number of slices is not given (NumberOfImagesInMosaic)");
    }
    // Each tile holds at least one pixel, which also bounds the search for the tiles a side.
    if (std::uint64_t{*slices} > std::uint64_t{format.rows} * format.columns) {
        return refuse("number of slices (" + std::to_string(*slices) +
                      ") is more than the image has pixels");
    }
    Mosaic mosaic;
    while (std::uint64_t{mosaic.tiles} * mosaic.tiles < *slices) {
        ++mosaic.tiles;
    }
    if (frame_count != 1 || format.rows % mosaic.tiles != 0 || format.columns % mosaic.tiles != 0) {
        return refuse(std::to_string(*slices) + " slices do not tile the image evenly");
    }
    const auto normal = csa_values(dataset, "SliceNormalVector");
    if (normal.size() == 3) {
        mosaic.slice_normal = glm::dvec3(std::atof(normal[0].c_str()), std::atof(normal[1].c_str()),
                                         std::atof(normal[2].c_str()));
    }
    mosaic.stored_rows = format.rows;
    mosaic.stored_columns = format.columns;
    format.rows = static_cast<std::uint16_t>(format.rows / mosaic.tiles);
    format.columns = static_cast<std::uint16_t>(format.columns / mosaic.tiles);
    frame_count = *slices;
    return std::optional<Mosaic>(mosaic);
}

enum class Opened { image, not_an_image };

// Reads the header of one file; the pixel data stays on disk. A Part 10 file without pixel data
// (DICOMDIR, a structured report) is `not_an_image`, which a folder skips.
base::Result<Opened> open_image(const std::filesystem::path& path, Image& image) {
    image.path = path;
    image.file = std::make_unique<DcmFileFormat>();
    const OFCondition status = image.file->loadFile(path.c_str());
    if (status.bad()) {
        const std::string reason = std::string(" (DCMTK: ") + status.text() + ")";
        if (!is_dicom_file(path)) {
            return base::make_error("not_dicom",
                                    "not a DICOM file: no DICM marker after the 128-byte "
                                    "preamble, and not readable as a bare data set" +
                                            reason,
                                    detail::at_file(path));
        }
        // DCMTK reports a file that ends inside an element as one of these two.
        if (status == EC_StreamNotifyClient || status == EC_InvalidStream) {
            return base::make_error("truncated",
                                    "the file ends before the data its elements announce "
                                    "(truncated or damaged)" +
                                            reason,
                                    detail::at_file(path));
        }
        return base::make_error("bad_header", "DCMTK cannot parse the file" + reason,
                                detail::at_file(path));
    }
    DcmDataset& dataset = *image.file->getDataset();
    if (!dataset.tagExists(DCM_PixelData)) {
        if (dataset.tagExists(DCM_FloatPixelData) || dataset.tagExists(DCM_DoubleFloatPixelData)) {
            return base::make_error("unsupported_type",
                                    "float pixel data is not supported; integer PixelData is",
                                    detail::at_file(path));
        }
        return Opened::not_an_image;
    }
    auto format = read_pixel_format(dataset, path);
    if (!format) {
        return format.error();
    }
    image.format = *format;
    const auto frames = get_int(dataset, DCM_NumberOfFrames).value_or(1);
    if (frames < 1) {
        return base::make_error("bad_header", "NumberOfFrames is " + std::to_string(frames),
                                detail::at_file(path));
    }
    // Checked before the frames' positions are read: a header claiming billions of frames must
    // cost no memory.
    const std::uint64_t frame_voxels = std::uint64_t{image.format.rows} * image.format.columns;
    if (static_cast<std::uint64_t>(frames) > max_frames ||
        static_cast<std::uint64_t>(frames) > max_voxels / frame_voxels) {
        return base::make_error("too_large",
                                "NumberOfFrames " + std::to_string(frames) + " of " +
                                        format->describe() + " exceeds the limit of " +
                                        std::to_string(max_frames) + " frames or " +
                                        std::to_string(max_voxels) + " voxels",
                                detail::at_file(path));
    }
    image.frame_count = static_cast<std::uint32_t>(frames);
    auto mosaic = read_mosaic(dataset, image.format, image.frame_count, path);
    if (!mosaic) {
        return mosaic.error();
    }
    image.mosaic = *mosaic;
    for (const Frame& frame :
         read_frames(dataset, 0, image.frame_count, image.mosaic, image.format)) {
        if (!frame.position || !frame.orientation) {
            image.frame_depths.clear();
            break;
        }
        const glm::dvec3 normal = slice_normal(*frame.orientation);
        image.frame_depths.push_back(glm::dot(normal, *frame.position) /
                                     std::max(glm::length(normal), 1e-12));
    }
    image.series_uid = get_string(dataset, DCM_SeriesInstanceUID);
    if (const auto number = get_int(dataset, DCM_SeriesNumber)) {
        image.series_number = std::to_string(*number);
    }
    image.series_description = get_string(dataset, DCM_SeriesDescription);
    image.modality = get_string(dataset, DCM_Modality);
    image.hounsfield = get_string(dataset, DCM_Modality) == "CT" ||
                       get_string(dataset, DCM_RescaleType) == "HU";
    return Opened::image;
}

// How deep and how wide a folder's search for image files goes: a DICOMDIR export keeps its
// images four levels below the root (DICOM/<patient>/<study>/<series>/), and no volume has more
// files than it may have frames; the bounds keep a mistaken `--volume /` from walking a disk.
constexpr int max_folder_depth = 5;
constexpr std::uint64_t max_folder_files = max_frames;

// The files below the folder (in sub-folders too when `subfolders`) that carry the DICOM Part 10
// marker, in path order so that logs and fallbacks are reproducible. Hidden files and folders
// and links to folders are passed over.
base::Result<std::vector<std::filesystem::path>> dicom_files_in(
        const std::filesystem::path& folder, bool subfolders,
        std::vector<std::filesystem::path>& not_dicom) {
    std::error_code ec;
    std::vector<std::filesystem::path> files;
    std::uint64_t seen = 0;
    for (auto it = std::filesystem::recursive_directory_iterator(
                 folder, std::filesystem::directory_options::skip_permission_denied, ec);
         !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (it->is_directory(ec)) {
            if (!subfolders || name.starts_with('.') || it.depth() + 1 >= max_folder_depth) {
                it.disable_recursion_pending();
            }
            continue;
        }
        if (!it->is_regular_file(ec) || name.starts_with('.')) {
            continue;
        }
        if (++seen > max_folder_files) {
            return base::make_error("too_large",
                                    "the folder holds more than " +
                                            std::to_string(max_folder_files) +
                                            " files (sub-folders included); open the series' "
                                            "own folder",
                                    detail::at_file(folder));
        }
        if (is_dicom_file(it->path())) {
            files.push_back(it->path());
        } else {
            not_dicom.push_back(it->path());
        }
    }
    if (ec) {
        return base::make_error("read_failed", "cannot list the folder: " + ec.message(),
                                detail::at_file(folder));
    }
    std::sort(files.begin(), files.end());
    return files;
}

// The image headers of a folder, with what was passed over.
struct FolderImages {
    std::vector<Image> images;
    std::vector<std::filesystem::path> not_dicom;
    std::size_t not_images = 0;
    std::optional<base::Error> other_kind;  // the first image of a kind a volume cannot hold

    // Files with the DICOM marker that cannot be read as an image (cut short, damaged headers),
    // in path order: each one's error, and what of its header was read before the damage.
    struct Damaged {
        base::Error error;
        std::string series_uid;
        std::optional<std::array<double, 3>> position;  // ImagePositionPatient (LPS)
    };

    std::vector<Damaged> damaged;

    // What a volume of the folder says about the files it passed over, one line each: every
    // damaged file (the volume lacks whatever slices it held), and the files that are not DICOM.
    [[nodiscard]] std::vector<std::string> notes() const;
    // " (skipped as damaged: a, b)" where files were skipped, else empty: the likely cause of a
    // gap in the series.
    [[nodiscard]] std::string damaged_suffix() const;
};

std::vector<std::string> FolderImages::notes() const {
    std::vector<std::string> lines;
    for (const Damaged& file : damaged) {
        lines.push_back("skipped " + file.error.where + " (" + file.error.code + ": " +
                        file.error.message + "); whatever slices it holds are not in the volume");
    }
    if (!not_dicom.empty()) {
        // A few names say what the files are; an export's thousand thumbnails need no list.
        constexpr std::size_t named = 5;
        std::string names;
        for (std::size_t i = 0; i < std::min(named, not_dicom.size()); ++i) {
            names += (i == 0 ? "" : ", ") + not_dicom[i].filename().string();
        }
        if (not_dicom.size() > named) {
            names += ", ...";
        }
        lines.push_back("skipped " + std::to_string(not_dicom.size()) +
                        " file(s) that are not DICOM (no DICM marker): " + names);
    }
    return lines;
}

std::string FolderImages::damaged_suffix() const {
    if (damaged.empty()) {
        return {};
    }
    std::string names;
    for (const Damaged& file : damaged) {
        names += (names.empty() ? "" : ", ") + file.error.where;
    }
    return " (skipped as damaged: " + names + ")";
}

// `keep_files`: keep each image's parsed file for its pixel data (a load), or drop it once its
// header is read (a listing of a folder's series, which may hold thousands of files).
base::Result<FolderImages> read_folder(const std::filesystem::path& folder, bool subfolders,
                                       bool keep_files) {
    FolderImages found;
    auto files = dicom_files_in(folder, subfolders, found.not_dicom);
    if (!files) {
        return files.error();
    }
    for (const auto& path : *files) {
        Image image;
        auto opened = open_image(path, image);
        // An image of another kind (an RGB secondary capture, a screenshot of a dose report) is
        // not a slice of any series here: skipped with a warning, so the series beside it opens.
        if (!opened && opened.error().code == "unsupported_type") {
            base::log_warning(log_component,
                              "skipped " + opened.error().where + ": " + opened.error().message);
            if (!found.other_kind) {
                found.other_kind = opened.error();
            }
            continue;
        }
        // A file carrying the DICOM marker that cannot be read (a copy cut short, a damaged
        // header) is no reason to refuse its neighbours: skipped and noted, and a slice it held
        // inside the series shows as the gap the spacing check refuses.
        if (!opened) {
            base::log_warning(log_component, "skipped " + opened.error().to_string());
            // DCMTK keeps what it parsed before the damage: a file cut short in its pixel data
            // still says where its slice lies, which tells a gap inside the series from a
            // slice missing at an end.
            FolderImages::Damaged damaged{opened.error(), {}, {}};
            if (image.file && image.file->getDataset() != nullptr) {
                DcmDataset& dataset = *image.file->getDataset();
                damaged.series_uid = get_string(dataset, DCM_SeriesInstanceUID);
                damaged.position = get_doubles<3>(dataset, DCM_ImagePositionPatient);
            }
            found.damaged.push_back(std::move(damaged));
            continue;
        }
        if (*opened == Opened::not_an_image) {
            ++found.not_images;
            continue;
        }
        if (!keep_files) {
            image.file.reset();
        }
        found.images.push_back(std::move(image));
    }
    if (found.images.empty() && !found.damaged.empty()) {
        return found.damaged.front().error;
    }
    if (found.images.empty() && found.other_kind) {
        return *found.other_kind;
    }
    if (found.images.empty() && found.not_dicom.empty() && found.not_images == 0) {
        return base::make_error("no_dicom_images", "the folder holds no files",
                                detail::at_file(folder));
    }
    if (found.images.empty()) {
        return base::make_error("no_dicom_images",
                                "the folder holds no DICOM image files (" +
                                        std::to_string(found.not_dicom.size()) + " other files, " +
                                        std::to_string(found.not_images) +
                                        " DICOM files without pixel data)",
                                detail::at_file(folder));
    }
    return found;
}

// Positions this close along the normal are one position repeated, not two slices: scanners
// write them to a micrometre or finer, and no series has slices that close.
constexpr double same_position = 1e-3;  // mm

// The slices a load of the images opens: their frames' distinct positions along the slice
// normal, as a series of several volumes (echoes, time points, a mosaic per time point) repeats
// each position once per volume; every frame where any lacks a position, since a load then keeps
// them all.
std::uint64_t count_slices(const std::vector<const Image*>& images) {
    std::vector<double> depths;
    for (const Image* image : images) {
        if (image->frame_depths.size() != image->frame_count) {
            std::uint64_t frames = 0;
            for (const Image* each : images) {
                frames += each->frame_count;
            }
            return frames;
        }
        depths.insert(depths.end(), image->frame_depths.begin(), image->frame_depths.end());
    }
    std::sort(depths.begin(), depths.end());
    std::uint64_t slices = 0;
    for (std::size_t i = 0; i < depths.size(); ++i) {
        if (i == 0 || depths[i] - depths[i - 1] >= same_position) {
            ++slices;
        }
    }
    return slices;
}

// The series of the images, ordered by SeriesNumber (numerically), then UID.
std::vector<DicomSeries> series_of(const std::vector<Image>& images) {
    std::map<std::string, DicomSeries> by_uid;
    std::map<std::string, std::vector<const Image*>> images_by_uid;
    for (const Image& image : images) {
        images_by_uid[image.series_uid].push_back(&image);
        DicomSeries& series = by_uid[image.series_uid];
        if (series.images == 0) {
            series.uid = image.series_uid;
            series.number = image.series_number;
            series.description = image.series_description;
            series.modality = image.modality;
        }
        ++series.images;
        series.frames += image.frame_count;
    }
    std::vector<DicomSeries> list;
    for (auto& [uid, series] : by_uid) {
        series.slices = count_slices(images_by_uid[uid]);
        list.push_back(std::move(series));
    }
    const auto number = [](const DicomSeries& s) {
        return s.number.empty() ? std::numeric_limits<long long>::max() : std::stoll(s.number);
    };
    std::stable_sort(list.begin(), list.end(), [&](const DicomSeries& a, const DicomSeries& b) {
        return number(a) < number(b);
    });
    return list;
}

std::string series_choices(const std::vector<DicomSeries>& list) {
    std::string text;
    for (const DicomSeries& series : list) {
        text += (text.empty() ? "" : "; ") + series.label() + ": " + std::to_string(series.slices) +
                " slices, " + (series.number.empty() ? "" : "number " + series.number + ", ") +
                "UID " + series.uid;
    }
    return text;
}

// Keeps the images of the series `wanted` names (its number or UID), or of the only series.
base::Result<DicomSeries> select_series(std::vector<Image>& images, const std::string& wanted,
                                        const std::filesystem::path& folder) {
    const std::vector<DicomSeries> list = series_of(images);
    std::vector<const DicomSeries*> matches;
    for (const DicomSeries& series : list) {
        if (wanted.empty() || series.uid == wanted || series.number == wanted) {
            matches.push_back(&series);
        }
    }
    if (matches.size() != 1) {
        std::string what;
        if (wanted.empty()) {
            what = "the folder holds " + std::to_string(list.size()) +
                   " series; choose one by number or UID (--series)";
        } else if (matches.empty()) {
            what = "the folder holds no series numbered '" + wanted + "' nor with that UID";
        } else {
            what = "several series are numbered " + wanted + "; choose one by UID";
        }
        return base::make_error(
                wanted.empty() || !matches.empty() ? "several_series" : "unknown_series",
                what + ": " + series_choices(list), detail::at_file(folder));
    }
    const DicomSeries chosen = *matches.front();
    std::erase_if(images, [&](const Image& image) { return image.series_uid != chosen.uid; });
    return chosen;
}

std::string frame_label(const Frame& frame, const std::vector<Image>& images) {
    std::string label = images[frame.image].path.string();
    if (images[frame.image].frame_count > 1) {
        label += ":frame " + std::to_string(frame.index + 1);
    }
    return label;
}

// Several volumes of one series (echoes, acquisitions, time points) repeat each position as
// often: keeps the first volume's frame at each position of the frames (sorted by `depth`) and
// returns how many volumes there are; 1 where no position repeats, or where positions repeat
// unevenly, which the spacing check then reports at the slice where it happens.
template <class Depth>
std::size_t keep_first_volume(std::vector<Frame>& frames, Depth depth) {
    std::vector<std::pair<std::size_t, std::size_t>> runs;  // [begin, end) of each position
    for (std::size_t begin = 0; begin < frames.size();) {
        std::size_t end = begin + 1;
        while (end < frames.size() &&
               std::abs(depth(frames[end]) - depth(frames[begin])) < same_position) {
            ++end;
        }
        runs.emplace_back(begin, end);
        begin = end;
    }
    const std::size_t volumes = runs.front().second - runs.front().first;
    if (volumes < 2 || std::any_of(runs.begin(), runs.end(), [&](const auto& run) {
            return run.second - run.first != volumes;
        })) {
        return 1;
    }
    std::vector<Frame> first;
    first.reserve(runs.size());
    for (const auto& [begin, end] : runs) {
        first.push_back(*std::min_element(
                frames.begin() + static_cast<std::ptrdiff_t>(begin),
                frames.begin() + static_cast<std::ptrdiff_t>(end),
                [](const Frame& a, const Frame& b) { return a.volume_key < b.volume_key; }));
    }
    frames = std::move(first);
    return volumes;
}

// Sorts the frames into z order and returns the spacing between them; of a series holding
// several volumes, keeps the first and says so in `notes`.
base::Result<double> order_frames(std::vector<Frame>& frames, const std::vector<Image>& images,
                                  const std::filesystem::path& source,
                                  std::vector<std::string>& notes) {
    const bool positioned = std::all_of(frames.begin(), frames.end(),
                                        [](const Frame& f) { return f.position && f.orientation; });
    glm::dvec3 normal(0.0);
    const auto depth = [&](const Frame& f) { return glm::dot(normal, *f.position); };
    if (positioned && frames.size() > 1) {
        const auto& orientation = *frames.front().orientation;
        normal = slice_normal(orientation);
        if (!(glm::length(normal) > 0.5)) {
            return base::make_error("bad_header",
                                    "ImageOrientationPatient has parallel row and column "
                                    "directions",
                                    frame_label(frames.front(), images));
        }
        normal = glm::normalize(normal);
        for (const Frame& frame : frames) {
            for (std::size_t i = 0; i < 6; ++i) {
                if (std::abs((*frame.orientation)[i] - orientation[i]) > orientation_tolerance) {
                    return base::make_error(
                            "inconsistent_series",
                            "the slice's ImageOrientationPatient differs from that of " +
                                    frame_label(frames.front(), images),
                            frame_label(frame, images));
                }
            }
        }
        std::stable_sort(frames.begin(), frames.end(),
                         [&](const Frame& a, const Frame& b) { return depth(a) < depth(b); });
        if (const std::size_t volumes = keep_first_volume(frames, depth); volumes > 1) {
            notes.push_back("the series holds " + std::to_string(volumes) +
                            " volumes (each position repeated: echoes, acquisitions or time "
                            "points); opened the first, " +
                            std::to_string(frames.size()) + " slices");
            base::log_info(log_component, source.string() + ": " + notes.back());
        }
    }
    if (positioned && frames.size() > 1) {
        std::vector<double> gaps;
        for (std::size_t i = 1; i < frames.size(); ++i) {
            gaps.push_back(depth(frames[i]) - depth(frames[i - 1]));
        }
        // The median is the series' own gap even when one slice is missing or doubled, so the
        // error can name the slice where the spacing breaks.
        std::vector<double> sorted_gaps = gaps;
        std::nth_element(sorted_gaps.begin(), sorted_gaps.begin() + sorted_gaps.size() / 2,
                         sorted_gaps.end());
        const double typical_gap = sorted_gaps[sorted_gaps.size() / 2];
        for (std::size_t i = 1; i < frames.size(); ++i) {
            const double gap = gaps[i - 1];
            if (!(typical_gap > 0.0) || std::abs(gap - typical_gap) > gap_tolerance * typical_gap) {
                return base::make_error("inconsistent_series",
                                        "slices are not evenly spaced: " + millimetres(gap) +
                                                " from " + frame_label(frames[i - 1], images) +
                                                " along the slice normal, while the usual gap is " +
                                                millimetres(typical_gap) +
                                                " (a missing slice, a repeated position or several "
                                                "acquisitions in one series)",
                                        frame_label(frames[i], images));
            }
        }
        return (depth(frames.back()) - depth(frames.front())) /
               static_cast<double>(frames.size() - 1);
    }

    if (frames.size() > 1) {
        base::log_warning(log_component,
                          source.string() +
                                  ": some slices lack ImagePositionPatient or "
                                  "ImageOrientationPatient; ordering them by InstanceNumber");
        std::stable_sort(frames.begin(), frames.end(), [](const Frame& a, const Frame& b) {
            return a.instance_number < b.instance_number;
        });
    }
    const Frame& first = frames.front();
    if (first.spacing_between_slices && *first.spacing_between_slices > 0.0) {
        return *first.spacing_between_slices;
    }
    if (first.slice_thickness && *first.slice_thickness > 0.0) {
        return *first.slice_thickness;
    }
    if (frames.size() > 1) {
        base::log_warning(
                log_component,
                source.string() + ": no SpacingBetweenSlices or SliceThickness; using 1 mm");
    }
    return 1.0;
}

base::Result<glm::dvec2> pixel_spacing(const std::vector<Frame>& frames,
                                       const std::vector<Image>& images,
                                       const std::filesystem::path& source) {
    const auto& first = frames.front().pixel_spacing;
    if (!first || !((*first)[0] > 0.0) || !((*first)[1] > 0.0)) {
        base::log_warning(log_component, source.string() + ": no valid PixelSpacing; using 1 mm");
        return glm::dvec2(1.0);
    }
    for (const Frame& frame : frames) {
        const auto& spacing = frame.pixel_spacing;
        if (!spacing || std::abs((*spacing)[0] - (*first)[0]) > 1e-4 * (*first)[0] ||
            std::abs((*spacing)[1] - (*first)[1]) > 1e-4 * (*first)[1]) {
            return base::make_error("inconsistent_series",
                                    "the slice's PixelSpacing differs from that of " +
                                            frame_label(frames.front(), images),
                                    frame_label(frame, images));
        }
    }
    // PixelSpacing is (between rows, between columns): y first, then x.
    return glm::dvec2((*first)[1], (*first)[0]);
}

// Where the ordered frames lie in patient space, in RAS: i along a row (ImageOrientationPatient's
// first direction), j down a column (its second), k from the first frame to the next (the
// positions' mean step, which for a gantry-tilted series leans off the normal and is refused as
// sheared). Without positions k is the slice normal; without orientation the axes are identity.
// DICOM's patient space is LPS, so x and y are negated.
base::Result<Geometry> patient_geometry(const std::vector<Frame>& frames, glm::dvec2 xy_spacing,
                                        double z_spacing, const std::vector<Image>& images) {
    const Frame& first = frames.front();
    glm::dmat3 steps(1.0);
    steps[0] *= xy_spacing.x;
    steps[1] *= xy_spacing.y;
    steps[2] *= z_spacing;
    if (first.orientation) {
        const auto& cosines = *first.orientation;
        const glm::dvec3 row(cosines[0], cosines[1], cosines[2]);
        const glm::dvec3 column(cosines[3], cosines[4], cosines[5]);
        if (!(glm::length(row) > 0.5) || !(glm::length(column) > 0.5) ||
            !(glm::length(glm::cross(row, column)) > 0.5)) {
            return base::make_error("bad_header",
                                    "ImageOrientationPatient holds zero or parallel directions",
                                    frame_label(first, images));
        }
        steps[0] = lps_to_ras(glm::normalize(row)) * xy_spacing.x;
        steps[1] = lps_to_ras(glm::normalize(column)) * xy_spacing.y;
        steps[2] = lps_to_ras(glm::normalize(glm::cross(row, column))) * z_spacing;
        const bool positioned = std::all_of(frames.begin(), frames.end(),
                                            [](const Frame& f) { return f.position.has_value(); });
        if (positioned && frames.size() > 1) {
            steps[2] = lps_to_ras(*frames.back().position - *first.position) /
                       static_cast<double>(frames.size() - 1);
        }
    }
    const glm::dvec3 origin = first.position ? lps_to_ras(*first.position) : glm::dvec3(0.0);
    auto geometry = geometry_from_steps(steps, origin);
    if (!geometry) {
        base::Error error = geometry.error();
        error.where = frame_label(first, images);
        return error;
    }
    return geometry;
}

// The raw pixel words of all frames of one image, decoded to native order.
base::Result<std::span<const std::byte>> pixel_bytes(Image& image) {
    DcmDataset& dataset = *image.file->getDataset();
    const E_TransferSyntax xfer = dataset.getOriginalXfer();
    const DcmXfer syntax(xfer);
    if (syntax.isEncapsulated()) {
        const OFCondition status = dataset.chooseRepresentation(EXS_LittleEndianExplicit, nullptr);
        if (status.bad() || !dataset.canWriteXfer(EXS_LittleEndianExplicit)) {
            return base::make_error("unsupported_encoding",
                                    std::string("pixel data in transfer syntax ") +
                                            syntax.getXferName() + " (" + syntax.getXferID() +
                                            ") cannot be decoded: " + status.text() +
                                            "; supported: uncompressed, JPEG, JPEG-LS, RLE",
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
        return base::make_error("truncated",
                                std::string("cannot read the pixel data: ") + status.text(),
                                detail::at_file(image.path));
    }
    if (bytes < expected) {
        return base::make_error("truncated",
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
    std::uint32_t mask;
    std::uint32_t sign_bit;
    bool inverted;

    explicit SampleDecoder(const PixelFormat& format)
        : shift(format.high_bit + 1u - format.bits_stored)
        , mask((std::uint32_t{1} << format.bits_stored) - 1u)
        , sign_bit(format.is_signed ? std::uint32_t{1} << (format.bits_stored - 1) : 0u)
        , inverted(format.inverted) {}

    [[nodiscard]] std::int32_t operator()(std::uint32_t word) const {
        std::uint32_t bits = (word >> shift) & mask;
        if (inverted) {
            bits = ~bits & mask;
        }
        if ((bits & sign_bit) != 0) {
            return static_cast<std::int32_t>(bits) - static_cast<std::int32_t>(mask) - 1;
        }
        return static_cast<std::int32_t>(bits);
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
        } else {
            std::uint16_t value = 0;
            std::memcpy(&value, in + 2 * at, 2);
            word = value;
        }
        const double stored = decode(word);
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

base::Result<Volume> assemble(std::vector<Image>& images, const std::string& name,
                              const std::filesystem::path& source, const LoadOptions& options) {
    const PixelFormat& format = images.front().format;
    for (const Image& image : images) {
        if (!(image.format == format)) {
            return base::make_error("inconsistent_series",
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
        largest_image =
                std::max(largest_image, stored_pixels(image) * (format.bits_allocated / 8u));
    }
    if (frame_count > max_frames) {
        return base::make_error("too_large",
                                std::to_string(frame_count) + " frames exceed the limit of " +
                                        std::to_string(max_frames),
                                detail::at_file(source));
    }
    const std::uint64_t all_voxels = std::uint64_t{format.rows} * format.columns * frame_count;
    if (all_voxels > max_voxels) {
        return base::make_error("too_large",
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
    const bool kept = std::all_of(frames.begin(), frames.end(), [&](const Frame& f) {
        return f.slope == first.slope && f.intercept == first.intercept &&
               f.slope == std::round(f.slope) && f.intercept == std::round(f.intercept);
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
    for (std::size_t i = 0; i < images.size(); ++i) {
        if (slots[i].empty()) {
            continue;  // a frame of a later volume of the series
        }
        auto pixels = pixel_bytes(images[i]);
        if (!pixels) {
            return pixels.error();
        }
        for (const std::size_t z : slots[i]) {
            decode_frame(*pixels, format, images[i].mosaic, frames[z].index, frames[z], !kept,
                         values + z * slice_voxels);
        }
        images[i].file.reset();  // drops the decoded pixel data
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
    volume->axes = geometry->axes;
    volume->origin = geometry->origin;
    volume->hounsfield = images.front().hounsfield;
    volume->notes = std::move(notes);
    return volume;
}

base::Result<Volume> load_dicom_folder(const std::filesystem::path& folder,
                                       const LoadOptions& options) {
    auto found = read_folder(folder, options.dicom_subfolders, true);
    if (!found) {
        return found.error();
    }
    if (!found->not_dicom.empty() || found->not_images > 0) {
        base::log_info(log_component, folder.string() + ": skipped " +
                                              std::to_string(found->not_dicom.size()) +
                                              " files that are not DICOM and " +
                                              std::to_string(found->not_images) +
                                              " DICOM files without pixel data");
    }
    std::vector<Image>& images = found->images;
    const std::size_t series_count = series_of(images).size();
    auto chosen = select_series(images, options.dicom_series, folder);
    if (!chosen) {
        return chosen.error();
    }
    // One of several series is named for itself, the only one for its folder.
    std::string name = folder.filename().empty() ? folder.parent_path().filename().string()
                                                 : folder.filename().string();
    if (series_count > 1) {
        name = chosen->label();
    }
    auto volume = assemble(images, name, folder, options);
    if (!volume) {
        base::Error error = volume.error();
        if (error.code == "inconsistent_series") {
            error.message += found->damaged_suffix();
        }
        return error;
    }
    // A damaged slice of this series that lay between two slices of the volume leaves a gap that
    // the spacing check cannot see where the slices left are evenly spaced (every other one
    // damaged; two slices have one gap, always "even"): refused, as a gap is. One at a slice's
    // own position (a damaged copy beside the intact file) or past an end takes nothing from
    // between the slices; the note names it.
    const double step = volume->spacing.z;
    const double last_depth = step * static_cast<double>(volume->dims.z - 1);
    for (const FolderImages::Damaged& file : found->damaged) {
        if (file.series_uid != chosen->uid || !file.position || volume->dims.z < 2) {
            continue;
        }
        const glm::dvec3 position((*file.position)[0], (*file.position)[1], (*file.position)[2]);
        const double depth = glm::dot(volume->axes[2], lps_to_ras(position) - volume->origin);
        const double off_grid = std::abs(depth / step - std::round(depth / step));
        if (depth > same_position && depth < last_depth - same_position &&
            off_grid > gap_tolerance) {
            return base::make_error("inconsistent_series",
                                    "the series lacks its slice " + millimetres(depth) +
                                            " from its first along the slice normal, whose "
                                            "file is damaged (" +
                                            file.error.code + ": " + file.error.message + ")",
                                    file.error.where);
        }
    }
    auto notes = found->notes();
    notes.insert(notes.end(), volume->notes.begin(), volume->notes.end());
    volume->notes = std::move(notes);
    return volume;
}

base::Result<Volume> load_dicom_file(const std::filesystem::path& path,
                                     const LoadOptions& options) {
    if (auto size = detail::regular_file_size(path); !size) {
        return size.error();
    }
    std::vector<Image> images(1);
    auto opened = open_image(path, images.front());
    if (!opened) {
        return opened.error();
    }
    if (*opened == Opened::not_an_image) {
        return missing_tag(DCM_PixelData, path);
    }
    const std::string name =
            detail::strip_suffix(path, std::array<std::string_view, 2>{".dcm", ".dicom"});
    return assemble(images, name, path, options);
}

}  // namespace

bool is_dicom_file(const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    std::array<char, 132> head{};
    if (!file.read(head.data(), head.size())) {
        return false;
    }
    return std::string_view(head.data() + 128, 4) == "DICM";
}

namespace {

base::Result<Volume> load_dicom_path(const std::filesystem::path& path,
                                     const LoadOptions& options) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) {
        return base::make_error("not_found", "file or folder not found", detail::at_file(path));
    }
    prepare_library();
    if (!dcmDataDict.isDictionaryLoaded()) {
        return base::make_error("dicom_unavailable",
                                "DCMTK found no DICOM data dictionary (install libdcmtk17 or set "
                                "DCMDICTPATH)",
                                detail::at_file(path));
    }
    if (std::filesystem::is_directory(status)) {
        return load_dicom_folder(path, options);
    }
    return load_dicom_file(path, options);
}

}  // namespace

std::string DicomSeries::label() const {
    std::string text = description;
    if (!number.empty()) {
        text += (text.empty() ? "" : " ") + std::string("(series ") + number + ")";
    }
    return text.empty() ? uid : text;
}

base::Result<std::vector<DicomSeries>> list_dicom_series(const std::filesystem::path& folder,
                                                         bool subfolders) {
    prepare_library();
    auto found = read_folder(folder, subfolders, false);
    if (!found) {
        return found.error();
    }
    return series_of(found->images);
}

base::Result<Volume> load_dicom(const std::filesystem::path& path, const LoadOptions& options) {
    return detail::guard_allocation(path, [&] { return load_dicom_path(path, options); });
}

}  // namespace penumbra::volume
