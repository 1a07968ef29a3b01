#pragma once

// The names and colours of a label map's labels (a segmentation, an atlas), as read from the files
// that come with it, and how many voxels each label holds.

#include <penumbra/base/result.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::volume {

struct Label {
    std::int64_t id = 0;  // the value its voxels store
    std::string name;
    glm::u8vec3 color{0};
    // As the file shows the label at first (ITK-SNAP's label opacity and visibility): a user's
    // starting point, which they change.
    double opacity = 1.0;
    bool visible = true;
};

struct LabelNames {
    std::vector<Label> labels;          // in the order of the names file
    std::vector<std::string> warnings;  // lines skipped, each naming its line
};

// MRIcron's label files beside an atlas X.nii or X.nii.gz: X.nii.txt, and X.nii.lut if there.
struct MricronLabelFiles {
    std::filesystem::path names;
    std::optional<std::filesystem::path> colors;
};

// The MRIcron label files beside `volume_path`; nullopt when it has no names file.
[[nodiscard]] std::optional<MricronLabelFiles> find_mricron_labels(
        const std::filesystem::path& volume_path);

// MRIcron's names file holds a label per line, `id name` (more columns, such as AAL's code, are
// ignored; spaces or tabs, CRLF and blank lines are allowed); a line without an integer id and a
// name is skipped with a warning. Its colour table is 768 bytes: the red of ids 0-255, then their
// greens, then their blues. Labels it does not cover, or all of them without one, get a colour of
// their own (label_color).
[[nodiscard]] base::Result<LabelNames> read_mricron_labels(const MricronLabelFiles& files);

// A label description file given beside a label map: ITK-SNAP's (`IDX R G B A VIS MSH "LABEL"`,
// colours 0..255, A the opacity 0..1, VIS 0 or 1; `#` comments) or FreeSurfer's colour table
// (`id name R G B A`, A 0 for opaque), told apart line by line. Lines that are neither are skipped
// with a warning naming the line.
[[nodiscard]] base::Result<LabelNames> read_label_description(const std::filesystem::path& path);

// 3D Slicer's segmentation file (.seg.nrrd, labelmap form) names its segments in the NRRD header:
// SegmentN_Name, SegmentN_Color ("r g b", 0..1), SegmentN_LabelValue (N + 1 where absent, as
// Slicer's older files) and SegmentN_Layer. Segments on several layers overlap, which one label a
// voxel cannot hold: an Error. No Segment keys: no labels, no error.
[[nodiscard]] base::Result<LabelNames> read_slicer_segments(const NrrdKeyValues& keys);

// A colour for a label that has none: hues spread by the golden ratio, so neighbouring ids differ.
[[nodiscard]] glm::u8vec3 label_color(std::int64_t id);

// How many voxels hold each stored value of a label map (an integer volume; a float one is refused:
// label ids must be exact). At most `max_labels` distinct values.
inline constexpr std::size_t max_labels = 4096;
[[nodiscard]] base::Result<std::map<std::int64_t, std::uint64_t>> count_labels(
        const Volume& volume);

}  // namespace penumbra::volume
