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

// A colour for a label that has none: hues spread by the golden ratio, so neighbouring ids differ.
[[nodiscard]] glm::u8vec3 label_color(std::int64_t id);

// How many voxels hold each stored value of a label map (an integer volume; a float one is refused:
// label ids must be exact). At most `max_labels` distinct values.
inline constexpr std::size_t max_labels = 4096;
[[nodiscard]] base::Result<std::map<std::int64_t, std::uint64_t>> count_labels(
        const Volume& volume);

// The label table as `penumbra info` prints it: id, name, colour, voxels; labels present in the
// volume but not named are listed as "label N" with a colour of their own.
[[nodiscard]] std::string describe_labels(const LabelNames& names,
                                          const std::map<std::int64_t, std::uint64_t>& counts);

}  // namespace penumbra::volume
