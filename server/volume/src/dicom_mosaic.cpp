// Siemens mosaics (ImageType MOSAIC, or NumberOfImagesInMosaic (0019,100a)) tile a volume's
// slices in one image: unpacked into the slices as nibabel and dcm2niix do (the corner position
// corrected, slices along the CSA header's SliceNormalVector); one whose number of slices is
// missing or does not tile the image is refused saying "mosaic".

#include "dicom_mosaic.hpp"

#include "dicom_tags.hpp"
#include "file_io.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <system_error>

namespace penumbra::volume::detail::dicom {
namespace {

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

}  // namespace

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
        return base::make_error(base::ErrorCode::unsupported_type,
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

}  // namespace penumbra::volume::detail::dicom
