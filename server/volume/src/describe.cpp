#include "penumbra/volume/describe.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdint>
#include <cstdio>

namespace penumbra::volume {
namespace {

// printf into `text`: the descriptions are aligned columns of numbers in printf's formats.
[[gnu::format(printf, 2, 3)]] void append(std::string& text, const char* format, ...) {
    std::va_list arguments;
    va_start(arguments, format);
    std::va_list measuring;
    va_copy(measuring, arguments);
    const int length = std::vsnprintf(nullptr, 0, format, measuring);
    va_end(measuring);
    if (length > 0) {
        const std::size_t end = text.size();
        text.resize(end + static_cast<std::size_t>(length) + 1);
        std::vsnprintf(text.data() + end, static_cast<std::size_t>(length) + 1, format, arguments);
        text.resize(end + static_cast<std::size_t>(length));
    }
    va_end(arguments);
}

}  // namespace

std::string describe(const Volume& v, const std::string& source) {
    std::string text;
    append(text, "volume:      %s (%s)\n", v.name.c_str(), source.c_str());
    append(text, "dimensions:  %u x %u x %u (%zu voxels)\n", v.dims.x, v.dims.y, v.dims.z,
           v.voxel_count());
    append(text, "spacing:     %g x %g x %g\n", v.spacing.x, v.spacing.y, v.spacing.z);
    append(text, "extent:      %g x %g x %g\n", v.extent().x, v.extent().y, v.extent().z);
    // The index-to-patient transform in RAS millimetres: the rows of a 3x4 matrix whose columns
    // are the steps along i, j, k (axes scaled by the spacing) and the origin.
    append(text, "orientation: %s (index axes i, j, k toward these patient directions; RAS)\n",
           orientation_code(v.axes).c_str());
    append(text, "transform:   voxel (i, j, k) -> RAS mm\n");
    for (int row = 0; row < 3; ++row) {
        append(text, "  %c = %10.4f i %+10.4f j %+10.4f k %+10.4f\n", "xyz"[row],
               v.axes[0][row] * v.spacing.x, v.axes[1][row] * v.spacing.y,
               v.axes[2][row] * v.spacing.z, v.origin[row]);
    }
    const PatientBounds bounds = patient_bounds(v);
    append(text,
           "bounds:      x %g..%g, y %g..%g, z %g..%g (RAS mm, the voxels' outer faces: "
           "render --crop takes these)\n",
           bounds.min.x, bounds.max.x, bounds.min.y, bounds.max.y, bounds.min.z, bounds.max.z);
    append(text, "voxel type:  %s\n", to_string(v.type));
    if (!v.rescale.identity()) {
        append(text, "rescale:     value = stored x %g %+g\n", v.rescale.slope,
               v.rescale.intercept);
    }
    append(text, "range:       %g .. %g%s\n", v.range.min, v.range.max,
           v.hounsfield ? " (Hounsfield units)" : "");
    for (const std::string& note : v.notes) {
        append(text, "note:        %s\n", note.c_str());
    }
    if (v.nonfinite_voxels > 0) {
        append(text, "non-finite:  %llu voxels replaced by the minimum\n",
               static_cast<unsigned long long>(v.nonfinite_voxels));
    }
    return text;
}

std::string describe_histogram(const Volume& volume, std::size_t bins) {
    const Histogram histogram = compute_histogram(volume, bins);
    const std::uint64_t peak = *std::max_element(histogram.bins.begin(), histogram.bins.end());
    std::string text;
    append(text, "histogram (%zu bins, log-free bar length relative to the fullest bin):\n", bins);
    const double bin_width =
            (histogram.range.max - histogram.range.min) / static_cast<double>(bins);
    for (std::size_t i = 0; i < histogram.bins.size(); ++i) {
        const int bar = peak > 0 ? static_cast<int>(50.0 * static_cast<double>(histogram.bins[i]) /
                                                    static_cast<double>(peak))
                                 : 0;
        append(text, "  %10.4g %12llu %s\n",
               histogram.range.min + bin_width * static_cast<double>(i),
               static_cast<unsigned long long>(histogram.bins[i]),
               std::string(static_cast<std::size_t>(bar), '#').c_str());
    }
    return text;
}

std::string describe_series(const std::vector<DicomSeries>& series) {
    std::string text;
    append(text, "  %-8s %-10s %8s  %-40s %s\n", "number", "modality", "slices", "description",
           "UID");
    for (const DicomSeries& one : series) {
        append(text, "  %-8s %-10s %8llu  %-40s %s\n", one.number.c_str(), one.modality.c_str(),
               static_cast<unsigned long long>(one.slices), one.description.c_str(),
               one.uid.c_str());
    }
    return text;
}

}  // namespace penumbra::volume
