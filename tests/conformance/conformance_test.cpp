// Every volume file that Debian's packages of other projects ship in a format Penumbra reads
// (nibabel's and pydicom's test data, ITK's examples, heudiconv's Siemens DICOM) either opens
// with the dimensions, spacing, orientation (axes and origin in RAS) and values that nibabel or
// pydicom read from it, or is refused with the reason listed below. The expected values come from
// expected_values.py, run with Debian's Python. Prints the counts per package.

#include <penumbra/volume/volume.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

namespace penumbra::volume {
namespace {

using nlohmann::json;

constexpr const char* reference_python = "/usr/bin/python3";

// Files Penumbra refuses, by file name, with the error code it gives (empty: whichever the
// loader gives, where the file itself is missing a part) and why.
struct Refusal {
    const char* code;
    const char* reason;
};

constexpr Refusal impossible_jpeg_2000{
        "decode_failed",
        "a JPEG 2000 codestream whose SIZ marker declares a width of 0xFEFFDDE0 pixels (the bytes "
        "of "
        "a sequence delimiter: the file tests a DICOM parser's framing), which OpenJPEG refuses"};
constexpr Refusal no_pixel_data{
        "bad_header",
        "a DICOM object without pixel data (a report, RT plan or structure set, waveform, "
        "DICOMDIR, a bare data set whose header DCMTK cannot place)"};
constexpr Refusal two_dimensional{"unsupported_dimension",
                                  "a 2-D image (dimension 2), not a volume"};
constexpr Refusal colour{"unsupported_type",
                         "a colour image (3 samples per pixel), not a scalar volume"};
constexpr Refusal damaged{"truncated",
                          "the file ends before its last element (damaged, as its test says)"};
constexpr Refusal header_without_image{
        "", "Debian ships the .hdr without its .img (nibabel cannot open it either)"};
constexpr Refusal bits_1{"unsupported_type", "1-bit pixels (a segmentation bitmap)"};
constexpr Refusal no_image{"bad_header",
                           "a DICOM object without an image (no Rows: private sequences, a test of "
                           "a missing transfer syntax)"};
constexpr Refusal untiled_mosaic{
        "unsupported_type",
        "a Siemens mosaic whose 48 slices do not tile its 256x256 image (7 tiles a side of 36.6 "
        "pixels; nibabel cannot unpack it either)"};
constexpr Refusal not_a_volume_intent{
        "unsupported_dimension",
        "a NIfTI intent that holds no image of space (a CIFTI-2 connectivity matrix, 10x10)"};
constexpr Refusal not_dicom{"not_dicom", "no DICOM preamble nor a data set DCMTK can read bare"};

const std::map<std::string, Refusal>& expected_refusals() {
    static const std::map<std::string, Refusal> refusals{
            {"0.dcm", untiled_mosaic},
            {"1.dcm", untiled_mosaic},
            {"99+PhoenixDocument+00001.dcm", no_pixel_data},
            {"BrainProtonDensitySliceBorder20.nhdr", two_dimensional},
            {"BrainProtonDensitySliceBorder20DirectionPlus30.nhdr", two_dimensional},
            {"BrainProtonDensitySliceShifted13x17y.nhdr", two_dimensional},
            {"BrainProtonDensitySliceShifted13x17yDirectionPlus30.nhdr", two_dimensional},
            {"BrainT1SliceBorder20DirectionPlus30.nhdr", two_dimensional},
            {"DICOMDIR-empty.dcm", no_pixel_data},
            {"ExplVR_BigEnd.dcm", colour},
            {"ExplVR_BigEndNoMeta.dcm", no_pixel_data},
            {"ExplVR_LitEndNoMeta.dcm", no_pixel_data},
            {"GDCMJ2K_TextGBR.dcm", colour},
            {"JPEG2000-embedded-sequence-delimiter.dcm", impossible_jpeg_2000},
            {"MR_truncated.dcm", damaged},
            {"SC_jpeg_no_color_transform.dcm", colour},
            {"SC_jpeg_no_color_transform_2.dcm", colour},
            {"SC_rgb_dcmtk_+eb+cr.dcm", colour},
            {"SC_rgb_dcmtk_+eb+cy+n1.dcm", colour},
            {"SC_rgb_dcmtk_+eb+cy+n2.dcm", colour},
            {"SC_rgb_dcmtk_+eb+cy+np.dcm", colour},
            {"SC_rgb_dcmtk_+eb+cy+s2.dcm", colour},
            {"SC_rgb_dcmtk_+eb+cy+s4.dcm", colour},
            {"SC_rgb_gdcm_KY.dcm", colour},
            {"SC_rgb_jpeg.dcm", damaged},
            {"SC_rgb_jpeg_app14_dcmd.dcm", colour},
            {"SC_rgb_jpeg_dcmd.dcm", colour},
            {"SC_rgb_jpeg_dcmtk.dcm", colour},
            {"SC_rgb_jpeg_gdcm.dcm", colour},
            {"SC_rgb_jpeg_lossy_gdcm.dcm", colour},
            {"SC_rgb_rle.dcm", colour},
            {"SC_rgb_rle_16bit.dcm", colour},
            {"SC_rgb_rle_16bit_2frame.dcm", colour},
            {"SC_rgb_rle_2frame.dcm", colour},
            {"SC_rgb_rle_32bit.dcm", colour},
            {"SC_rgb_rle_32bit_2frame.dcm", colour},
            {"SC_rgb_small_odd.dcm", colour},
            {"SC_rgb_small_odd_jpeg.dcm", colour},
            {"SC_ybr_full_422_uncompressed.dcm", colour},
            {"UN_sequence.dcm", no_pixel_data},
            {"analyze.hdr", header_without_image},
            {"empty_charset_LEI.dcm", no_pixel_data},
            {"liver_1frame.dcm", bits_1},
            {"liver_expb_1frame.dcm", bits_1},
            {"meta_missing_tsyntax.dcm", no_image},
            {"nested_priv_SQ.dcm", no_image},
            {"nifti1.hdr", header_without_image},
            {"nifti2.hdr", header_without_image},
            {"no_meta.dcm", not_dicom},
            {"no_meta_group_length.dcm", no_pixel_data},
            {"priv_SQ.dcm", no_pixel_data},
            {"reportsi.dcm", no_pixel_data},
            {"reportsi_with_empty_number_tags.dcm", no_pixel_data},
            {"row_major.dconn.nii", not_a_volume_intent},
            {"rtplan.dcm", no_pixel_data},
            {"rtplan_truncated.dcm", damaged},
            {"rtstruct.dcm", no_pixel_data},
            {"test-SR.dcm", no_pixel_data},
            {"waveform_ecg.dcm", no_pixel_data},
    };
    return refusals;
}

json read_expected_values() {
    const std::string command =
            std::string(reference_python) + " " + PENUMBRA_EXPECTED_VALUES_SCRIPT + " 2>/dev/null";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    if (!pipe) {
        return json::array();
    }
    std::string text;
    std::array<char, 65536> buffer{};
    while (const std::size_t got = std::fread(buffer.data(), 1, buffer.size(), pipe.get())) {
        text.append(buffer.data(), got);
    }
    return json::parse(text, nullptr, false);
}

bool near(double a, double b, double tolerance) {
    return std::abs(a - b) <= tolerance * std::max(1.0, std::max(std::abs(a), std::abs(b)));
}

// Compares one opened volume with what the reference reader read; returns the mismatches.
std::vector<std::string> compare(const Volume& volume, const json& expected, bool dicom) {
    std::vector<std::string> problems;
    const auto check = [&](bool ok, const std::string& what) {
        if (!ok) {
            problems.push_back(what);
        }
    };
    const auto& dims = expected.at("dims");
    check(volume.dims.x == dims[0].get<std::uint32_t>() &&
                  volume.dims.y == dims[1].get<std::uint32_t>() &&
                  volume.dims.z == dims[2].get<std::uint32_t>(),
          "dims " + std::to_string(volume.dims.x) + "x" + std::to_string(volume.dims.y) + "x" +
                  std::to_string(volume.dims.z) + ", expected " + dims.dump());
    if (expected.contains("spacing")) {
        for (int a = 0; a < 3; ++a) {
            check(near(volume.spacing[a], expected["spacing"][a].get<double>(), 1e-4),
                  "spacing " + std::to_string(a) + " " + std::to_string(volume.spacing[a]) +
                          ", expected " + expected["spacing"][a].dump());
        }
    }
    if (expected.contains("pixel_spacing")) {
        for (int a = 0; a < 2; ++a) {
            check(near(volume.spacing[a], expected["pixel_spacing"][a].get<double>(), 1e-4),
                  "pixel spacing " + std::to_string(a) + " " + std::to_string(volume.spacing[a]) +
                          ", expected " + expected["pixel_spacing"][a].dump());
        }
    }
    const char* axes_key = expected.contains("axes") ? "axes" : "axes_ij";
    if (expected.contains(axes_key)) {
        for (std::size_t a = 0; a < expected[axes_key].size(); ++a) {
            for (int row = 0; row < 3; ++row) {
                const double want = expected[axes_key][a][static_cast<std::size_t>(row)];
                check(std::abs(volume.axes[static_cast<int>(a)][row] - want) < 1e-4,
                      "axis " + std::to_string(a) + " is " + orientation_code(volume.axes) +
                              ", expected " + expected[axes_key][a].dump());
            }
        }
    }
    if (expected.contains("origin")) {
        for (int row = 0; row < 3; ++row) {
            check(near(volume.origin[row], expected["origin"][static_cast<std::size_t>(row)], 1e-4),
                  "origin " + std::to_string(volume.origin[row]) + " on axis " +
                          std::to_string(row) + ", expected " + expected["origin"].dump());
        }
    }
    // MONOCHROME1 is inverted by Penumbra and not by pydicom's modality LUT: only the geometry
    // is compared.
    if (expected.value("monochrome1", false)) {
        return problems;
    }
    if (expected.contains("range") && !expected["range"].is_null()) {
        check(near(volume.range.min, expected["range"][0], 1e-5) &&
                      near(volume.range.max, expected["range"][1], 1e-5),
              "range " + std::to_string(volume.range.min) + ".." +
                      std::to_string(volume.range.max) + ", expected " + expected["range"].dump());
    }
    if (expected.contains("samples")) {
        for (const auto& sample : expected["samples"]) {
            if (sample[3].is_null()) {
                continue;  // NaN: replaced by the minimum, as the README says
            }
            const auto i = sample[0].get<std::uint32_t>();
            const auto j = sample[1].get<std::uint32_t>();
            const auto k = sample[2].get<std::uint32_t>();
            if (i >= volume.dims.x || j >= volume.dims.y || k >= volume.dims.z) {
                continue;  // reported as a dims mismatch
            }
            const double got = volume.value(i, j, k);
            // DICOM integers are kept exactly; what a rescale turns into float32 (a dose grid in
            // Gy) holds 24 bits of mantissa.
            const bool exact = dicom && volume.type != VoxelType::float32;
            check(near(got, sample[3].get<double>(), exact ? 1e-9 : 1e-6),
                  "voxel " + sample.dump() + " is " + std::to_string(got));
        }
    }
    return problems;
}

struct Counts {
    int candidates = 0;
    int opened = 0;
    int compared = 0;  // opened and compared with the reference reader's values
    int refused = 0;
};

TEST(Conformance,
     DebianPackagesVolumeFilesOpenAsTheReferenceReadersReadThemOrAreRefusedWithAReason) {
    if (!std::filesystem::exists(reference_python)) {
        FAIL() << "Debian's python3 (with nibabel, pydicom) is not installed "
                  "(scripts/install-deps.sh --only test)";
    }
    const json entries = read_expected_values();
    ASSERT_TRUE(entries.is_array()) << "expected_values.py gave no JSON";
    if (entries.empty()) {
        FAIL() << "none of the packages is installed (scripts/install-deps.sh --only test)";
    }
    std::map<std::string, Counts> counts;
    std::map<std::string, std::vector<std::string>> refused_by_reason;
    for (const auto& entry : entries) {
        const std::filesystem::path path = entry.at("path").get<std::string>();
        const std::string package = entry.at("package");
        const std::string name = path.filename().string();
        Counts& count = counts[package];
        ++count.candidates;
        auto volume = load_volume(path);
        const auto refusal = expected_refusals().find(name);
        if (refusal != expected_refusals().end()) {
            EXPECT_FALSE(volume.ok())
                    << name
                    << " opens, but the table says it is refused: " << refusal->second.reason;
            if (!volume.ok()) {
                ++count.refused;
                if (*refusal->second.code != '\0') {
                    EXPECT_EQ(base::name_of(volume.error().code), refusal->second.code)
                            << name << ": " << volume.error().to_string();
                }
                refused_by_reason[std::string(base::name_of(volume.error().code)) + ": " +
                                  refusal->second.reason]
                        .push_back(package + "/" + name);
            }
            continue;
        }
        if (!volume.ok()) {
            ADD_FAILURE() << package << "/" << name
                          << " is refused: " << volume.error().to_string();
            continue;
        }
        ++count.opened;
        if (!entry.contains("expected") || entry.contains("reference_error") ||
            entry["expected"].contains("reference_error")) {
            continue;  // no reference reading (NRRD, or a file the reference cannot read)
        }
        ++count.compared;
        const auto problems =
                compare(*volume, entry["expected"], entry.value("reader", "") == "pydicom");
        for (const auto& problem : problems) {
            ADD_FAILURE() << package << "/" << name << ": " << problem;
        }
    }
    std::printf("\n%-26s %10s %8s %9s %8s\n", "package", "candidates", "opened", "compared",
                "refused");
    Counts total;
    for (const auto& [package, c] : counts) {
        std::printf("%-26s %10d %8d %9d %8d\n", package.c_str(), c.candidates, c.opened, c.compared,
                    c.refused);
        total.candidates += c.candidates;
        total.opened += c.opened;
        total.compared += c.compared;
        total.refused += c.refused;
    }
    std::printf("%-26s %10d %8d %9d %8d\n", "total", total.candidates, total.opened, total.compared,
                total.refused);
    std::puts("\nrefused:");
    for (const auto& [reason, files] : refused_by_reason) {
        std::printf("  %s (%zu)\n", reason.c_str(), files.size());
        for (const auto& file : files) {
            std::printf("    %s\n", file.c_str());
        }
    }
}

}  // namespace
}  // namespace penumbra::volume
