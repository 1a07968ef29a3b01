#pragma once

// One DICOM image file as the loader holds it: its header read once, its pixel data left on disk
// until its series is chosen and its frames ordered, so that a folder of thousands of files can
// be listed, grouped and checked from the headers alone. Private to the volume module.

#include <penumbra/base/result.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcfilefo.h>

namespace penumbra::volume::detail::dicom {

// Frames of one volume: far beyond any scanner's series, and small enough that their positions
// (a few hundred bytes each) cost little.
inline constexpr std::uint64_t max_frames = std::uint64_t{1} << 16;

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
    // Pixel words decoded outside DCMTK (JPEG 2000), which the pixel data is read from then.
    std::vector<std::byte> decoded_words;
};

enum class Opened { image, not_an_image };

// Reads the header of one file; the pixel data stays on disk. A Part 10 file without pixel data
// (DICOMDIR, a structured report) is `not_an_image`, which a folder skips.
base::Result<Opened> open_image(const std::filesystem::path& path, Image& image);

}  // namespace penumbra::volume::detail::dicom
