#pragma once

#include <penumbra/base/result.hpp>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace penumbra::volume {

// The voxel types kept in memory and on the GPU without losing precision. Files with other types
// (int8, int32, float64), or with a rescale that is not a pair of integers, are converted to
// float32 at load time.
enum class VoxelType { uint8, uint16, int16, float32 };

// How stored voxels become real values (a DICOM or NIfTI rescale): real = stored * slope +
// intercept. Integer types keep their stored values and this mapping, so a CT of int16 stays
// int16 while its values are Hounsfield units.
struct Rescale {
    double slope = 1.0;
    double intercept = 0.0;

    [[nodiscard]] double apply(double stored) const { return stored * slope + intercept; }

    [[nodiscard]] bool identity() const { return slope == 1.0 && intercept == 0.0; }
};

[[nodiscard]] std::size_t bytes_per_voxel(VoxelType type);

[[nodiscard]] const char* to_string(VoxelType type);

struct ValueRange {
    double min = 0.0;
    double max = 0.0;
};

struct Histogram {
    ValueRange range;                 // the range the bins cover (the volume's finite range)
    std::vector<std::uint64_t> bins;  // equal-width bins over [range.min, range.max]
};

// A scalar volume in memory: x varies fastest, then y, then z (the order of raw, NRRD and NIfTI).
struct Volume {
    std::string name;         // shown to users, e.g. the file stem
    glm::uvec3 dims{0};       // voxels per axis
    glm::dvec3 spacing{1.0};  // physical size of one voxel (mm for medical data)
    VoxelType type = VoxelType::uint8;
    std::vector<std::byte> data;  // dims.x * dims.y * dims.z * bytes_per_voxel(type), little endian
    Rescale rescale;              // stored data -> real values
    ValueRange range;             // real values, over finite voxels
    std::uint64_t nonfinite_voxels = 0;  // NaN/Inf voxels found at load and replaced by range.min

    // Where the voxels lie in patient space, in Penumbra's one convention, RAS (+x toward the
    // patient's right, +y anterior, +z superior; millimetres for medical data): the centre of
    // voxel (i, j, k) lies at origin + axes * (spacing * (i, j, k)). The columns of `axes` are
    // unit vectors (a rotation, possibly with a reflection); identity for files that carry no
    // orientation (raw), which render as if stored RAS.
    glm::dmat3 axes{1.0};
    glm::dvec3 origin{0.0};

    // The values are Hounsfield units (a DICOM CT, a rescale type of HU, or a NIfTI/NRRD marked
    // so), which lets CT presets be given in HU rather than as fractions of the range.
    bool hounsfield = false;

    // The file marks its values as label ids (NIfTI's intent code NIFTI_INTENT_LABEL, as atlases
    // and segmentations are written): a label map rather than intensities (label_map.hpp).
    bool label_intent = false;

    // How many volumes the file held (a 4-D file's time points or components); the first was
    // loaded. A label map must hold one: the volumes of a probabilistic atlas are no labels.
    std::uint64_t volumes_in_file = 1;

    // What the loader chose for the user and they should know, one line each (a DICOM series
    // holding several volumes opened at its first); `info` prints them.
    std::vector<std::string> notes;

    [[nodiscard]] std::size_t voxel_count() const {
        return static_cast<std::size_t>(dims.x) * dims.y * dims.z;
    }

    // Physical size of the volume: dims * spacing.
    [[nodiscard]] glm::dvec3 extent() const { return glm::dvec3(dims) * spacing; }

    // The real value (rescale applied) of the voxel at integer coordinates, as a double (no
    // normalisation).
    [[nodiscard]] double value(std::uint32_t x, std::uint32_t y, std::uint32_t z) const;
};

// Builds a Volume from values already in memory (tests, synthetic data, converters): checks the
// size and the rescale (finite, slope non-zero), replaces non-finite float voxels and computes
// the range of real values.
base::Result<Volume> make_volume(std::string name, glm::uvec3 dims, glm::dvec3 spacing,
                                 VoxelType type, std::vector<std::byte> data, Rescale rescale = {});

// Convenience for float data.
base::Result<Volume> make_volume(std::string name, glm::uvec3 dims, glm::dvec3 spacing,
                                 const std::vector<float>& values);

// The smallest box in patient space (RAS millimetres, faces perpendicular to its axes) that holds
// the volume's voxels whole, outer faces included: what a crop box that cuts nothing spans.
struct PatientBounds {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
};

[[nodiscard]] PatientBounds patient_bounds(const Volume& volume);

// Penumbra's patient convention is RAS; DICOM and ITK write LPS. The conversion negates x and y
// (its own inverse).
[[nodiscard]] glm::dvec3 lps_to_ras(glm::dvec3 lps);

// The three letters naming the patient direction each index axis (i, j, k) points closest to,
// as nibabel's aff2axcodes and ITK's orientation codes do: "RAS" for identity axes, "LPS" for a
// DICOM axial series, "LAS" for an FSL-style left-right reversed NIfTI, "LSA" for a coronal one.
[[nodiscard]] std::string orientation_code(const glm::dmat3& axes);

// The geometry of a file's index-to-patient transform: the columns of `steps` are the RAS
// vectors from one voxel centre to the next along i, j and k, so their lengths are the spacing
// and their directions the axes. A transform whose columns are not perpendicular (a gantry-tilted
// CT, a sheared registration result) is an Error with code "sheared_transform" and the angle: a
// Volume is only rotated or reflected (placed_geometry and place_volume resample such a volume).
// Zero or non-finite columns are an Error too.
struct Geometry {
    glm::dvec3 spacing{1.0};
    glm::dmat3 axes{1.0};
    glm::dvec3 origin{0.0};
    // Where the file's steps are not perpendicular (placed_geometry): the steps themselves, which
    // place_volume resamples the voxels from. `spacing` and `axes` are then the columns' lengths
    // and directions as they are.
    std::optional<glm::dmat3> sheared_steps;
    // What the loader chose for the user about the transform (a NIfTI's qform used in place of
    // a sheared sform); place_volume adds it to the volume's notes.
    std::string note;
};

base::Result<Geometry> geometry_from_steps(const glm::dmat3& steps, glm::dvec3 origin);

// As geometry_from_steps, but steps that are not perpendicular give a Geometry with
// `sheared_steps` (place_volume resamples such a volume) unless they are degenerate: so nearly
// coplanar that the voxels span almost no volume (an Error "sheared_transform" still).
base::Result<Geometry> placed_geometry(const glm::dmat3& steps, glm::dvec3 origin);

struct LoadOptions;

// Puts a loaded volume where `geometry` says: its spacing, axes and origin; or, for a sheared
// geometry (a gantry-tilted CT, a sheared registration result), its voxels resampled onto an
// orthogonal grid that holds them all, as 3D Slicer's "harden transform" and dcm2niix's tilt
// correction do: the grid's first axis is i's, its second j's made perpendicular to i, its third
// their normal, so the slices of a tilted series stay whole planes of the grid and only move
// within them (interpolation trilinear, exact across slices there); where the grid reaches past
// the stored voxels it holds the volume's lowest value; a note says what was done. Fails with
// "sheared_transform" where `options` refuses resampling (label maps, whose ids must not mix),
// and with "out_of_memory" when the grid would hold more than options.max_bytes or eight times
// the stored voxels.
base::Status place_volume(Volume& volume, const Geometry& geometry, const LoadOptions& options);

// Columns of unit axes may differ from perpendicular by this much (the cosine of their angle):
// files store directions as float32 or as decimal strings of a few digits, while a gantry tilt
// of even half a degree is ten times larger.
inline constexpr double max_axis_cosine = 1e-3;

[[nodiscard]] Histogram compute_histogram(const Volume& volume, std::size_t bin_count = 256);

// What one load may hold in memory. Checked before any allocation a file asks for, against what
// the file declares: its voxels x the bytes each is kept in (float32 where the file's type is
// converted), plus what the loader holds beside the volume (a DICOM file's pixel data). A load
// holds about one copy of the volume: samples are converted chunk by chunk, never as a second
// whole copy. An allocation that fails all the same is an "out_of_memory" Error, never a crash.
struct LoadOptions {
    std::uint64_t max_bytes = std::uint64_t{8} << 30;
    // Also refuse what the machine cannot give now (MemAvailable in /proc/meminfo).
    bool within_available_memory = true;
    // DICOM: the series to open from a folder holding several, by SeriesNumber or
    // SeriesInstanceUID (as list_dicom_series gives them); empty opens the folder's only series.
    std::string dicom_series;
    // DICOM: a folder's sub-folders are searched too (a DICOMDIR export root, a study folder
    // with a folder per series), a few levels deep; `serve` walks sub-folders itself.
    bool dicom_subfolders = true;
    // A sheared index-to-patient transform is resampled onto an orthogonal grid (place_volume);
    // false refuses it instead (label maps: interpolation would mix their ids).
    bool resample_sheared = true;
};

// The memory the machine has available now (MemAvailable), or nullopt where it cannot tell.
[[nodiscard]] std::optional<std::uint64_t> available_memory();

// Loaders. Each validates everything it reads and returns an Error naming the file and, where it
// applies, the byte offset or header line that was wrong (in `where`; the message names no path
// but the file's own name).
//   raw:   Open SciVis naming name_XxYxZ_type.raw[.gz], type uint8|uint16|int16|float32|float64;
//          spacing 1 unless the file name carries none (the caller may override it).
//          No orientation: identity axes, origin 0.
//   NRRD:  .nrrd (attached) and .nhdr (detached "data file", which must lie in the header's
//          folder or below it), encodings raw, gzip, bzip2 and ascii, spacings or space
//          directions; axes and origin from space, space directions and space origin; a 4-D
//          file opens its first volume.
//   NIfTI: .nii and .nii.gz, NIfTI-1 (and -2), and .hdr/.img pairs (SPM's output, Analyze 7.5
//          too); the header through the reference nifti library; axes and origin from the
//          sform, else the qform.
//   DICOM: a folder holding the files of a series (any names, in sub-folders too; where it holds
//          several series, LoadOptions::dicom_series picks one, else the error "several_series"
//          lists them), or one file (multi-frame or a single slice), through DCMTK. Slices are
//          ordered along the slice normal; axes and origin from Image Orientation/Position
//          (Patient); rescale slope/intercept kept as Volume::rescale (CT in HU);
//          MONOCHROME1 inverted; Siemens mosaics unpacked into their slices; a series of several
//          volumes (echoes, time points) opens its first, with a note.
base::Result<Volume> load_raw(const std::filesystem::path& path, const LoadOptions& options = {});
base::Result<Volume> load_nrrd(const std::filesystem::path& path, const LoadOptions& options = {});
base::Result<Volume> load_nifti(const std::filesystem::path& path, const LoadOptions& options = {});
base::Result<Volume> load_dicom(const std::filesystem::path& path, const LoadOptions& options = {});

// Whether a NIfTI file's header gives it the label intent (Volume::label_intent) without reading
// its voxels.
base::Result<bool> read_nifti_label_intent(const std::filesystem::path& path);

// A NRRD header's key:=value lines, in order: metadata no field holds (3D Slicer writes a
// segmentation's segments so, `Segment0_Name:=...`). Reads the header alone.
using NrrdKeyValues = std::vector<std::pair<std::string, std::string>>;
base::Result<NrrdKeyValues> read_nrrd_key_values(const std::filesystem::path& path);

// One series of a DICOM folder, as a user chooses among them.
struct DicomSeries {
    std::string uid;          // SeriesInstanceUID
    std::string number;       // SeriesNumber as written (may be empty)
    std::string description;  // SeriesDescription (may be empty)
    std::string modality;
    std::size_t images = 0;  // files
    // 2-D images in all the files: one per single-frame file, each frame of a multi-frame file,
    // each tile of a Siemens mosaic. A series of several volumes (echoes, time points) holds
    // each slice once per volume.
    std::uint64_t frames = 0;
    // The slices a load of the series opens: its distinct positions along the slice normal (a
    // series of several volumes opens its first); its frames where they carry no positions.
    std::uint64_t slices = 0;

    // "T1 MPRAGE (series 3)", or what of it the headers have; the UID where they have nothing.
    [[nodiscard]] std::string label() const;
};

// The image series of a DICOM folder (searching its sub-folders when `subfolders`), ordered by
// SeriesNumber then UID, read from the headers only. Images of another kind (colour captures,
// mosaics) are left out as a load leaves them out; a folder without any image series is the
// error a load of it gives.
base::Result<std::vector<DicomSeries>> list_dicom_series(const std::filesystem::path& folder,
                                                         bool subfolders = true);

// Whether a file carries the DICOM Part 10 marker ("DICM" after a 128-byte preamble), the test
// that decides which files of a folder belong to a series. Cheap: reads 132 bytes.
[[nodiscard]] bool is_dicom_file(const std::filesystem::path& path);

// The file-name suffixes of the formats a single file holds a whole volume in (NIfTI, NRRD, raw),
// in lower case; names are compared case-insensitively. DICOM is not among them: its files are
// the slices of a series, whose folder is the volume.
[[nodiscard]] const std::vector<std::string_view>& volume_suffixes();
// Whether the file's name ends in one of volume_suffixes(), in any case ("HEAD.NII.GZ").
[[nodiscard]] bool is_volume_file_name(const std::filesystem::path& path);

// Chooses the loader: a folder is a DICOM series; files by name (volume_suffixes, .dcm/.dicom are
// DICOM), and a file with another name that carries the DICOM marker is DICOM too.
base::Result<Volume> load_volume(const std::filesystem::path& path,
                                 const LoadOptions& options = {});

// Limits that protect the process from absurd headers (checked before any allocation).
inline constexpr std::uint64_t max_voxels = std::uint64_t{1} << 31;

}  // namespace penumbra::volume
