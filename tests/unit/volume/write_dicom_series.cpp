// write_dicom_series FOLDER [--two-series | --jpeg2000]: writes a 64x48x24 box of the ch2 MRI head
// as a DICOM series, for the command-line tests of `penumbra info` and `penumbra render` on a
// folder. With --two-series the folder holds a second series beside it, as a clinic's export does:
// series 2 "ch2 head" (the box) and series 7 "ch2 lower" (a 32x32x8 box below it). With
// --jpeg2000 it holds one small multi-frame file instead (16x12x3, each frame a lossless JPEG 2000
// codestream over two fragments): the DICOM fuzz target's JPEG 2000 seed.

#include "dicom_writer.hpp"

#include <cstdio>
#include <exception>
#include <string_view>

int main(int argc, char** argv) {
    const bool two_series = argc == 3 && std::string_view(argv[2]) == "--two-series";
    const bool jpeg2000 = argc == 3 && std::string_view(argv[2]) == "--jpeg2000";
    if (argc != 2 && !two_series && !jpeg2000) {
        std::fputs("usage: write_dicom_series FOLDER [--two-series | --jpeg2000]\n", stderr);
        return 2;
    }
    try {
        using namespace penumbra::volume::fixtures;
        const std::filesystem::path folder = argv[1];
        SeriesSpec spec;
        spec.dims = {64, 48, 24};
        spec.spacing = {2.0, 2.0, 3.0};
        std::filesystem::remove_all(folder);
        if (jpeg2000) {
            SeriesSpec small;
            small.dims = {16, 12, 3};
            small.spacing = {2.0, 2.0, 3.0};
            small.jpeg2000_fragments = 2;
            std::filesystem::create_directories(folder);
            write_multiframe(folder / "jpeg2000.dcm", small, ch2_box({80, 90, 70}, small.dims),
                             {0, 1, 2});
            return 0;
        }
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
