#include "commands.hpp"

#include <penumbra/cli/options.hpp>
#include <penumbra/volume/describe.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::app {

using namespace cli;

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
    std::printf("DICOM folder: %s\n%zu series (open one with --series NUMBER|UID):\n%s",
                path.c_str(), series->size(), volume::describe_series(*series).c_str());
    return true;
}

}  // namespace

int run_info(const std::vector<std::string>& args) {
    std::string path = default_volume_path;
    volume::LoadOptions options;
    std::string label_names;
    po::options_description described = option_group("options");
    described.add_options()("help", "this text")(
            "volume", po::value(&path)->value_name("FILE|DICOM-FOLDER")->default_value(path),
            "the volume; a DICOM folder holding several series (sub-folders included) lists "
            "them")("series", po::value(&options.dicom_series)->value_name("NUMBER|UID"),
                    "one series of a DICOM folder")(
            "label-names", po::value(&label_names)->value_name("FILE"),
            "the volume is a label map these names describe (ITK-SNAP label description, "
            "FreeSurfer colour table)");
    auto parsed = parse_options(args, described);
    if (!parsed) {
        return report_usage_error("info", parsed.error());
    }
    if (parsed->count("help") != 0) {
        print_help("info [options]",
                   "A volume's dimensions, spacing, type, range and histogram; a label map's "
                   "labels (id, colour, voxels, name) when the file marks it as one (NIfTI's "
                   "label intent), names lie beside it (MRIcron's X.nii.txt and X.nii.lut), it "
                   "names its segments (3D Slicer's .seg.nrrd) or --label-names gives them.",
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
    std::fputs(volume::describe(*volume, path).c_str(), stdout);
    // A label map: the file says so, or the user, by giving its names.
    auto declared = volume::declares_labels(path);
    if (!declared) {
        return report_failure("info", declared.error());
    }
    if (*declared || !label_names.empty()) {
        auto names = volume::label_names_for(path, label_names);
        if (!names) {
            return report_failure("info", names.error());
        }
        auto labels = volume::make_label_map(*volume, *names);
        if (!labels) {
            return report_failure("info", labels.error());
        }
        std::fputs(volume::describe_labels(*labels).c_str(), stdout);
    }
    std::fputs(volume::describe_histogram(*volume).c_str(), stdout);
    return 0;
}

}  // namespace penumbra::app
