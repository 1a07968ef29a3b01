#pragma once

// A label map: a segmentation or an atlas, drawn inside a scan (render::Renderer::set_labels).
// Its voxels become indices into its label table, so that the GPU holds at most 16 bits a voxel
// whatever ids the file uses, and a label's style is one entry of a small table.

#include <penumbra/base/result.hpp>
#include <penumbra/volume/label_names.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::volume {

struct LabelMap {
    // The file's grid, spacing, axes and origin; each voxel an index: 0 for no label (id 0, the
    // background of every segmentation format), i for labels[i - 1]. uint8 up to 255 labels, else
    // uint16.
    Volume indices;
    // The labels the volume holds, by id; named and coloured from the files beside it where they
    // say, else "label N" with a colour of its own (label_color).
    std::vector<Label> labels;
    std::vector<std::uint64_t> voxels;  // per label, in the order of `labels`
    std::uint64_t background_voxels = 0;
    // Named by a names file or the file's own keys (not every label need be).
    bool named = false;
    std::vector<std::string> warnings;  // names-file lines skipped; named labels the volume lacks

    // The labels' ids, in their order: what a frame's styles must list (scene::check_styles_match).
    [[nodiscard]] std::vector<std::int64_t> ids() const;
};

// A label's name is kept as valid UTF-8 of at most this many bytes (bytes that are not UTF-8
// become '?'): names come from files and reach JSON messages.
inline constexpr std::size_t max_label_name_bytes = 256;

// The label map of `stored` (its voxels' values are the ids) named by `names`. A floating-point
// volume, one with no label besides the background, more than max_labels labels, or a file of
// several volumes is an Error.
base::Result<LabelMap> make_label_map(const Volume& stored, const LabelNames& names);

// The names of the label map in `path`: from `names` where given (read_label_description), else
// MRIcron's files beside it, else a .seg.nrrd's segments; none where there are none.
base::Result<LabelNames> label_names_for(const std::filesystem::path& path,
                                         const std::filesystem::path& names = {});

// Whether the file in `path` says it holds labels, not a scan: NIfTI's label intent, MRIcron's
// names beside it, a NRRD's segments (a 3D Slicer .seg.nrrd). A scan's integers would make a label
// map too; only a file that says it is one is offered and drawn as one. Reads headers and the
// files beside it, never the voxels: what a listing asks of every file it lists.
base::Result<bool> declares_labels(const std::filesystem::path& path);

// The label table as `penumbra info` prints it: id, colour, voxels, name; then the background's
// voxels and the warnings.
[[nodiscard]] std::string describe_labels(const LabelMap& labels);

// Loads a label map: any volume load_volume reads but DICOM (a DICOM SEG object is refused: it
// says so). Its labels are named by `names` where given (read_label_description: ITK-SNAP,
// FreeSurfer), else by MRIcron's files beside it (find_mricron_labels), else by a .seg.nrrd's
// segments (read_slicer_segments); labels none of them names are "label N".
base::Result<LabelMap> load_label_map(const std::filesystem::path& path,
                                      const LoadOptions& options = {},
                                      const std::filesystem::path& names = {});

// A label map drawn alone, as smooth surfaces ("labels only"), on its own grid:
// - `indicator`: per voxel, how much of its 5x5x5 neighbourhood lies in a visible label, each
//   axis weighted 1 4 6 4 1, as 0..255 (its range set to that whole span, so 255 reads as 1).
//   Where it crosses a level between 0 and 1 runs a surface around a label's voxels, smooth
//   where they make steps; its gradient gives normals without the staircase.
// - `labels`: the map with the voxels of no visible label (the background, hidden labels) within
//   two of a visible label given its index (ring by ring; a face neighbour first, then an edge's,
//   then a corner's), so a sample on that surface outside a label's voxels takes its colour, a
//   hidden neighbour's voxels included; the labels and their counts as in `map`.
// `visible[i]` says whether map.labels[i] is drawn; a hidden label is no surface.
struct LabelSurfaces {
    Volume indicator;
    LabelMap labels;
};

base::Result<LabelSurfaces> label_surfaces(const LabelMap& map, const std::vector<bool>& visible);

// A label map is drawn over a scan in patient space, each on its own grid: it must share some of
// the scan's space. The error ("no_overlap") gives both boxes in RAS millimetres.
base::Status check_overlap(const Volume& scan, const Volume& labels);

}  // namespace penumbra::volume
