// write_dicom_series FOLDER: writes a 64x48x24 box of the ch2 MRI head as a DICOM series, for the
// command-line tests of `penumbra info` and `penumbra render` on a folder.

#include "dicom_writer.hpp"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fputs("usage: write_dicom_series FOLDER\n", stderr);
        return 2;
    }
    try {
        using namespace penumbra::volume::fixtures;
        SeriesSpec spec;
        spec.dims = {64, 48, 24};
        spec.spacing = {2.0, 2.0, 3.0};
        std::filesystem::remove_all(argv[1]);
        write_series(argv[1], spec, ch2_box({58, 60, 60}, spec.dims));
    } catch (const std::exception& error) {
        std::fprintf(stderr, "write_dicom_series: %s\n", error.what());
        return 1;
    }
    return 0;
}
