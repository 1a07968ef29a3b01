// Rules for placing a series' frames:
//   - A series holding several volumes (echoes, acquisitions, time points: each position
//     repeated as often) opens its first volume, the lowest (TemporalPositionIdentifier,
//     EchoNumbers, AcquisitionNumber, InstanceNumber) at each position, with a note saying so.
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

#include "dicom_frames.hpp"

#include "dicom_mosaic.hpp"
#include "dicom_tags.hpp"

#include <penumbra/base/log.hpp>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

namespace penumbra::volume::detail::dicom {
namespace {

// Orientation cosines of two slices of one series agree to this much.
constexpr double orientation_tolerance = 1e-4;

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

}  // namespace

std::string millimetres(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g mm", value);
    return text;
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
    // An RT dose grid places its frames by GridFrameOffsetVector, along the slice normal from the
    // top-level position (offsets relative to the first frame's, whether the first is 0 or its z);
    // its values are scaled to Gy by DoseGridScaling where no rescale says otherwise.
    // Read whole, once: DCMTK finds value i of a string by scanning it from its start.
    std::vector<double> grid_offsets;
    if (OFString offsets;
        dataset.findAndGetOFStringArray(DCM_GridFrameOffsetVector, offsets).good()) {
        std::size_t start = 0;
        while (start <= offsets.size() && grid_offsets.size() <= frame_count) {
            const std::size_t end = std::min(offsets.find('\\', start), offsets.size());
            const std::string value(offsets.c_str() + start, end - start);
            char* parsed_end = nullptr;
            const double offset = std::strtod(value.c_str(), &parsed_end);
            if (parsed_end == value.c_str() || !std::isfinite(offset)) {
                grid_offsets.clear();
                break;
            }
            grid_offsets.push_back(offset);
            start = end + 1;
        }
    }
    const auto top_position = get_doubles<3>(dataset, DCM_ImagePositionPatient);
    const auto top_orientation = get_doubles<6>(dataset, DCM_ImageOrientationPatient);
    const bool gridded = frame_count > 1 && grid_offsets.size() == frame_count && top_position &&
                         top_orientation && glm::length(slice_normal(*top_orientation)) > 0.5;
    const auto dose_scaling = get_double(dataset, DCM_DoseGridScaling);
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
        } else if (gridded) {
            frame.position =
                    glm::dvec3((*top_position)[0], (*top_position)[1], (*top_position)[2]) +
                    (grid_offsets[f] - grid_offsets[0]) *
                            glm::normalize(slice_normal(*top_orientation));
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
        auto slope = rescale(DCM_RescaleSlope);
        if (!slope && dose_scaling) {
            slope = dose_scaling;
        }
        frame.slope = slope && *slope != 0.0 ? *slope : 1.0;
        frame.intercept = rescale(DCM_RescaleIntercept).value_or(0.0);
    }
    if (mosaic) {
        place_mosaic_slices(frames, *mosaic, format);
    }
    return frames;
}

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
            return base::make_error(base::ErrorCode::bad_header,
                                    "ImageOrientationPatient has parallel row and column "
                                    "directions",
                                    frame_label(frames.front(), images));
        }
        normal = glm::normalize(normal);
        for (const Frame& frame : frames) {
            for (std::size_t i = 0; i < 6; ++i) {
                if (std::abs((*frame.orientation)[i] - orientation[i]) > orientation_tolerance) {
                    return base::make_error(
                            base::ErrorCode::inconsistent_series,
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
                return base::make_error(base::ErrorCode::inconsistent_series,
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
            return base::make_error(base::ErrorCode::inconsistent_series,
                                    "the slice's PixelSpacing differs from that of " +
                                            frame_label(frames.front(), images),
                                    frame_label(frame, images));
        }
    }
    // PixelSpacing is (between rows, between columns): y first, then x.
    return glm::dvec2((*first)[1], (*first)[0]);
}

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
            return base::make_error(base::ErrorCode::bad_header,
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
    auto geometry = placed_geometry(steps, origin);
    if (!geometry) {
        base::Error error = geometry.error();
        error.where = frame_label(first, images);
        return error;
    }
    return geometry;
}

}  // namespace penumbra::volume::detail::dicom
