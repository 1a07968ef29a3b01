// Several series in one folder: LoadOptions::dicom_series picks one by SeriesNumber or
// SeriesInstanceUID; without it the error "several_series" lists them (a scout beside a series is
// a series of its own, and guessing would open the wrong one silently).

#include "dicom_series.hpp"

#include "dicom_frames.hpp"
#include "file_io.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>

namespace penumbra::volume {
namespace detail::dicom {
namespace {

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

std::string series_choices(const std::vector<DicomSeries>& list) {
    std::string text;
    for (const DicomSeries& series : list) {
        text += (text.empty() ? "" : "; ") + series.label() + ": " + std::to_string(series.slices) +
                " slices, " + (series.number.empty() ? "" : "number " + series.number + ", ") +
                "UID " + series.uid;
    }
    return text;
}

}  // namespace

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
        return base::make_error(wanted.empty() || !matches.empty()
                                        ? base::ErrorCode::several_series
                                        : base::ErrorCode::unknown_series,
                                what + ": " + series_choices(list), detail::at_file(folder));
    }
    const DicomSeries chosen = *matches.front();
    std::erase_if(images, [&](const Image& image) { return image.series_uid != chosen.uid; });
    return chosen;
}

}  // namespace detail::dicom

std::string DicomSeries::label() const {
    std::string text = description;
    if (!number.empty()) {
        text += (text.empty() ? "" : " ") + std::string("(series ") + number + ")";
    }
    return text.empty() ? uid : text;
}

}  // namespace penumbra::volume
