#include "commands.hpp"
#include "options.hpp"

#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::app {

namespace {

// A DICOM folder holding several series lists them instead of opening one; true when it did.
bool listed_series(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_directory(path, ec)) {
        return false;
    }
    auto series = volume::list_dicom_series(path);
    if (!series || series->size() <= 1) {
        return false;
    }
    std::printf("DICOM folder: %s\n%zu series (open one with --series NUMBER|UID):\n", path.c_str(),
                series->size());
    std::printf("  %-8s %-10s %8s  %-40s %s\n", "number", "modality", "slices", "description",
                "UID");
    for (const volume::DicomSeries& one : *series) {
        std::printf("  %-8s %-10s %8llu  %-40s %s\n", one.number.c_str(), one.modality.c_str(),
                    static_cast<unsigned long long>(one.slices), one.description.c_str(),
                    one.uid.c_str());
    }
    return true;
}

void print_volume(const volume::Volume& v, const std::string& path) {
    std::printf("volume:      %s (%s)\n", v.name.c_str(), path.c_str());
    std::printf("dimensions:  %u x %u x %u (%zu voxels)\n", v.dims.x, v.dims.y, v.dims.z,
                v.voxel_count());
    std::printf("spacing:     %g x %g x %g\n", v.spacing.x, v.spacing.y, v.spacing.z);
    std::printf("extent:      %g x %g x %g\n", v.extent().x, v.extent().y, v.extent().z);
    // The index-to-patient transform in RAS millimetres: the rows of a 3x4 matrix whose columns
    // are the steps along i, j, k (axes scaled by the spacing) and the origin.
    std::printf("orientation: %s (index axes i, j, k toward these patient directions; RAS)\n",
                volume::orientation_code(v.axes).c_str());
    std::puts("transform:   voxel (i, j, k) -> RAS mm");
    for (int row = 0; row < 3; ++row) {
        std::printf("  %c = %10.4f i %+10.4f j %+10.4f k %+10.4f\n", "xyz"[row],
                    v.axes[0][row] * v.spacing.x, v.axes[1][row] * v.spacing.y,
                    v.axes[2][row] * v.spacing.z, v.origin[row]);
    }
    std::printf("voxel type:  %s\n", volume::to_string(v.type));
    if (!v.rescale.identity()) {
        std::printf("rescale:     value = stored x %g %+g\n", v.rescale.slope, v.rescale.intercept);
    }
    std::printf("range:       %g .. %g%s\n", v.range.min, v.range.max,
                v.hounsfield ? " (Hounsfield units)" : "");
    for (const std::string& note : v.notes) {
        std::printf("note:        %s\n", note.c_str());
    }
    if (v.nonfinite_voxels > 0) {
        std::printf("non-finite:  %llu voxels replaced by the minimum\n",
                    static_cast<unsigned long long>(v.nonfinite_voxels));
    }
}

void print_histogram(const volume::Volume& v) {
    const volume::Histogram histogram = volume::compute_histogram(v, 16);
    const std::uint64_t peak = *std::max_element(histogram.bins.begin(), histogram.bins.end());
    std::puts("histogram (16 bins, log-free bar length relative to the fullest bin):");
    const double bin_width = (histogram.range.max - histogram.range.min) / 16.0;
    for (std::size_t i = 0; i < histogram.bins.size(); ++i) {
        const int bar = peak > 0 ? static_cast<int>(50.0 * static_cast<double>(histogram.bins[i]) /
                                                    static_cast<double>(peak))
                                 : 0;
        std::printf("  %10.4g %12llu %s\n",
                    histogram.range.min + bin_width * static_cast<double>(i),
                    static_cast<unsigned long long>(histogram.bins[i]),
                    std::string(static_cast<std::size_t>(bar), '#').c_str());
    }
}

}  // namespace

int run_info(const std::vector<std::string>& args) {
    std::string path = default_volume_path;
    volume::LoadOptions options;
    po::options_description described = option_group("options");
    described.add_options()("help", "this text")(
            "volume", po::value(&path)->value_name("FILE|DICOM-FOLDER")->default_value(path),
            "the volume; a DICOM folder holding several series (sub-folders included) lists "
            "them")("series", po::value(&options.dicom_series)->value_name("NUMBER|UID"),
                    "one series of a DICOM folder");
    auto parsed = parse_options(args, described);
    if (!parsed) {
        return report_usage_error("info", parsed.error());
    }
    if (parsed->count("help") != 0) {
        print_help("info [options]", "A volume's dimensions, spacing, type, range and histogram.",
                   described);
        return 0;
    }
    if (options.dicom_series.empty() && listed_series(path)) {
        return 0;
    }
    auto volume = volume::load_volume(path, options);
    if (!volume) {
        return report_failure("info", volume.error());
    }
    print_volume(*volume, path);
    print_histogram(*volume);
    return 0;
}

}  // namespace penumbra::app
