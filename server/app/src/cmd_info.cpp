#include "commands.hpp"

#include <penumbra/cli/options.hpp>
#include <penumbra/volume/describe.hpp>
#include <penumbra/volume/label_names.hpp>
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
        print_help("info [options]",
                   "A volume's dimensions, spacing, type, range and histogram; an atlas's "
                   "labels (id, colour, voxels, name) when MRIcron's names (X.nii.txt, and "
                   "colours X.nii.lut) lie beside it.",
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
    if (const auto label_files = volume::find_mricron_labels(path)) {
        // An atlas with MRIcron's names beside it: its labels, with what each holds.
        auto names = volume::read_mricron_labels(*label_files);
        if (!names) {
            return report_failure("info", names.error());
        }
        auto counts = volume::count_labels(*volume);
        if (!counts) {
            return report_failure("info", counts.error());
        }
        std::fputs(volume::describe_labels(*names, *counts).c_str(), stdout);
    }
    std::fputs(volume::describe_histogram(*volume).c_str(), stdout);
    return 0;
}

}  // namespace penumbra::app
