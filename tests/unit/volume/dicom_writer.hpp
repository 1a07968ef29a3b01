#pragma once

// Writes DICOM fixtures with DCMTK: no real series ships with Debian, so tests make their own
// from real voxels (the ch2 MRI head). A failure to write throws, which GoogleTest reports as a
// failed test.

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

class DcmDataset;

namespace penumbra::volume::fixtures {

struct SeriesSpec {
    glm::uvec3 dims{4, 3, 2};  // columns, rows, slices
    glm::dvec3 spacing{1.0};   // between columns (x), between rows (y), between slices (z)
    std::array<double, 6> orientation{1, 0, 0, 0, 1, 0};  // row direction, column direction
    glm::dvec3 origin{0.0};                               // ImagePositionPatient of slice 0
    bool positions = true;  // write ImagePositionPatient and ImageOrientationPatient
    std::uint16_t bits_allocated = 16;
    std::uint16_t bits_stored = 16;
    bool is_signed = false;
    std::optional<double> slope;
    std::optional<double> intercept;
    std::string series_uid;          // a fresh UID when empty
    std::string series_number;       // SeriesNumber, written when set
    std::string series_description;  // SeriesDescription, written when set
    bool explicit_vr = true;         // else implicit VR little endian
    // write_multiframe: each frame a JPEG 2000 codestream encoded by OpenJPEG, split over this
    // many fragments (no offset table): 0 writes the pixels uncompressed. Lossless unless
    // `jpeg2000_ratio` (a compression ratio, e.g. 20) makes it lossy.
    int jpeg2000_fragments = 0;
    double jpeg2000_ratio = 0.0;
    bool jpeg2000_jp2 = false;  // a JP2 file per frame instead of the bare codestream
    // Last changes to each dataset before it is saved (delete a tag, break a value).
    std::function<void(DcmDataset&)> edit;
};

// A fresh DICOM UID under DCMTK's demo root.
std::string make_uid();

// The patient position of slice z: origin + z * spacing.z along the slice normal.
glm::dvec3 slice_position(const SeriesSpec& spec, std::uint32_t z);

// Writes slice z of `words` (stored pixel words, x fastest, then y, then z; 8-bit data keeps the
// low byte) as one single-frame MR image. `spec.series_uid` must be set for slices of one series.
void write_slice(const std::filesystem::path& path, const SeriesSpec& spec, std::uint32_t z,
                 const std::vector<std::uint16_t>& words, std::int32_t instance_number);

// Writes every slice as <folder>/slice_NNN.dcm with InstanceNumber z + 1; returns the paths.
std::vector<std::filesystem::path> write_series(const std::filesystem::path& folder,
                                                SeriesSpec spec,
                                                const std::vector<std::uint16_t>& words);

// Writes all slices into one enhanced multi-frame file whose frames come in `frame_order` (slice
// numbers), each frame's position in the per-frame functional groups.
void write_multiframe(const std::filesystem::path& path, const SeriesSpec& spec,
                      const std::vector<std::uint16_t>& words,
                      const std::vector<std::uint32_t>& frame_order);

// Writes <root>/DICOMDIR indexing every file below `root` (whose relative paths must be
// DICOMDIR-legal: upper-case components of at most 8 characters, no extension), as DCMTK's
// dcmmkdir does for a General Purpose CD export.
void write_dicomdir(const std::filesystem::path& root,
                    const std::vector<std::filesystem::path>& files);

// A box of the ch2 MRI head (uint8 voxels) as pixel words, x fastest.
std::vector<std::uint16_t> ch2_box(glm::uvec3 first, glm::uvec3 dims);

}  // namespace penumbra::volume::fixtures
