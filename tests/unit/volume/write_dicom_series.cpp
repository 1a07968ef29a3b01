// write_dicom_series FOLDER [--two-series]: writes a 64x48x24 box of the ch2 MRI head as a DICOM
// series, for the command-line tests of `penumbra info` and `penumbra render` on a folder. With
// --two-series the folder holds a second series beside it, as a clinic's export does: series 2
// "ch2 head" (the box) and series 7 "ch2 lower" (a 32x32x8 box below it).

#include "dicom_writer.hpp"

#include <cstdio>
#include <exception>
#include <string_view>

int main(int argc, char** argv) {
    const bool two_series = argc == 3 && std::string_view(argv[2]) == "--two-series";
    if (argc != 2 && !two_series) {
        std::fputs("usage: write_dicom_series FOLDER [--two-series]\n", stderr);
        return 2;
    }
    try {
        using namespace penumbra::volume::fixtures;
        const std::filesystem::path folder = argv[1];
        SeriesSpec spec;
        spec.dims = {64, 48, 24};
        spec.spacing = {2.0, 2.0, 3.0};
        std::filesystem::remove_all(folder);
        if (!two_series) {
            write_series(folder, spec, ch2_box({58, 60, 60}, spec.dims));
            return 0;
        }
        spec.series_number = "2";
        spec.series_description = "ch2 head";
        write_series(folder / "head", spec, ch2_box({58, 60, 60}, spec.dims));
        SeriesSpec lower;
        lower.dims = {32, 32, 8};
        lower.spacing = {2.0, 2.0, 3.0};
        lower.series_number = "7";
        lower.series_description = "ch2 lower";
        write_series(folder / "lower", lower, ch2_box({74, 70, 30}, lower.dims));
        // One folder, as exported: the two series' files side by side.
        for (const char* sub : {"head", "lower"}) {
            for (const auto& file : std::filesystem::directory_iterator(folder / sub)) {
                std::filesystem::rename(file.path(), folder / (std::string(sub) + "_" +
                                                               file.path().filename().string()));
            }
            std::filesystem::remove(folder / sub);
        }
    } catch (const std::exception& error) {
        std::fprintf(stderr, "write_dicom_series: %s\n", error.what());
        return 1;
    }
    return 0;
}
