#include <penumbra/volume/describe.hpp>

#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace penumbra::volume {
namespace {

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        lines.push_back(line);
    }
    return lines;
}

// The Colin27 head of Debian's mricron-data (part of the install step, so never skipped): a
// uint8 NIfTI stored RAS at 1 mm, whose origin puts the anterior commissure near (0, 0, 0).
TEST(Describe, TheColin27HeadLineByLine) {
    const std::string path = "/usr/share/mricron/templates/ch2.nii.gz";
    auto volume = load_volume(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string() << " (Debian package mricron-data)";
    const std::string text = describe(*volume, path);
    ASSERT_FALSE(text.empty());
    EXPECT_EQ(text.back(), '\n');
    EXPECT_EQ(lines_of(text),
              (std::vector<std::string>{
                      "volume:      ch2 (" + path + ")",
                      "dimensions:  181 x 217 x 181 (7109137 voxels)",
                      "spacing:     1 x 1 x 1",
                      "extent:      181 x 217 x 181",
                      "orientation: RAS (index axes i, j, k toward these patient directions; RAS)",
                      "transform:   voxel (i, j, k) -> RAS mm",
                      "  x =     1.0000 i    +0.0000 j    +0.0000 k   -90.0000",
                      "  y =     0.0000 i    +1.0000 j    +0.0000 k  -125.0000",
                      "  z =     0.0000 i    +0.0000 j    +1.0000 k   -71.0000",
                      // Half a voxel beyond the first and last voxel centres.
                      "bounds:      x -90.5..90.5, y -125.5..91.5, z -71.5..109.5 (RAS mm, the "
                      "voxels' outer faces: render --crop takes these)",
                      "voxel type:  uint8",
                      "range:       0 .. 254",
              }));
}

// InVesalius' head CT, converted in the build (tests/CMakeLists.txt): Hounsfield units, with most
// voxels air, and the rest spread up to dense bone.
TEST(Describe, TheHeadCtInHounsfieldUnitsAndItsHistogram) {
    auto ct = load_volume(PENUMBRA_CRANIUM_CT);
    ASSERT_TRUE(ct.ok()) << ct.error().to_string()
                         << " (the build converts it from Debian's invesalius-examples)";
    const std::vector<std::string> lines = lines_of(describe(*ct, PENUMBRA_CRANIUM_CT));
    ASSERT_EQ(lines.size(), 12U);
    EXPECT_EQ(lines[1], "dimensions:  256 x 256 x 108 (7077888 voxels)");
    EXPECT_EQ(lines[2], "spacing:     0.957031 x 0.957031 x 1.5");
    EXPECT_EQ(lines[9].substr(0, 15), "bounds:      x ");
    EXPECT_EQ(lines[10], "voxel type:  int16");
    EXPECT_EQ(lines[11], "range:       -1024 .. 2986 (Hounsfield units)");

    const std::vector<std::string> histogram = lines_of(describe_histogram(*ct, 16));
    ASSERT_EQ(histogram.size(), 17U);
    EXPECT_EQ(histogram[0],
              "histogram (16 bins, log-free bar length relative to the fullest bin):");
    // The fullest bin, air, has the whole bar; a bin is 4010/16 HU wide.
    EXPECT_EQ(histogram[1], "       -1024      4338748 " + std::string(50, '#'));
    EXPECT_EQ(histogram[2], "      -773.4       327591 ###");
    EXPECT_EQ(histogram[16].substr(0, 25), "        2735           35");
}

// The loader's notes, the voxels it replaced and a rescale other than identity each get a line.
TEST(Describe, RescaleNotesAndReplacedVoxelsAreShown) {
    auto volume = make_volume("drops", {2, 1, 1}, {1.0, 1.0, 1.0},
                              {1.0F, std::numeric_limits<float>::quiet_NaN()});
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    volume->rescale = {2.0, -1.5};
    volume->notes = {"opened the first of 2 volumes"};
    const std::vector<std::string> lines = lines_of(describe(*volume, "drops.raw"));
    ASSERT_EQ(lines.size(), 15U);
    EXPECT_EQ(lines[9],
              "bounds:      x -0.5..1.5, y -0.5..0.5, z -0.5..0.5 (RAS mm, the voxels' "
              "outer faces: render --crop takes these)");
    EXPECT_EQ(lines[11], "rescale:     value = stored x 2 -1.5");
    EXPECT_EQ(lines[13], "note:        opened the first of 2 volumes");
    EXPECT_EQ(lines[14], "non-finite:  1 voxels replaced by the minimum");
}

// The slices column counts what a load opens, not the frames (a mosaic's tiles, a second volume).
TEST(Describe, DicomSeriesAreAlignedColumnsOfSlices) {
    DicomSeries head{.uid = "1.2.3.4",
                     .number = "2",
                     .description = "ch2 head",
                     .modality = "MR",
                     .images = 3,
                     .frames = 72,
                     .slices = 24};
    DicomSeries localiser{.uid = "1.2.3.5",
                          .number = "",
                          .description = "",
                          .modality = "CT",
                          .images = 3,
                          .frames = 3,
                          .slices = 3};
    EXPECT_EQ(
            lines_of(describe_series({head, localiser})),
            (std::vector<std::string>{
                    "  number   modality     slices  description                              UID",
                    "  2        MR               24  ch2 head                                 "
                    "1.2.3.4",
                    "           CT                3                                           "
                    "1.2.3.5",
            }));
}

}  // namespace
}  // namespace penumbra::volume
