#include "fixture_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <string_view>

namespace penumbra::volume {
namespace {

using fixtures::as_bytes;

TEST(VolumeFileName, SuffixesMatchInAnyCaseAndDicomFilesAreNotVolumesByThemselves) {
    for (const char* name : {"head.nii", "HEAD.NII.GZ", "a/b/Brain.Nrrd", "x.nhdr",
                             "ct_2x2x2_uint8.RAW", "ct_2x2x2_uint8.raw.Gz"}) {
        EXPECT_TRUE(is_volume_file_name(name)) << name;
    }
    for (const char* name : {"notes.txt", "slice.dcm", "IM0001", "head.nii.bak", "nii"}) {
        EXPECT_FALSE(is_volume_file_name(name)) << name;
    }
    for (const std::string_view suffix : volume_suffixes()) {
        EXPECT_TRUE(is_volume_file_name("volume" + std::string(suffix))) << suffix;
    }
}

TEST(VoxelType, SizesAndNames) {
    EXPECT_EQ(bytes_per_voxel(VoxelType::uint8), 1u);
    EXPECT_EQ(bytes_per_voxel(VoxelType::uint16), 2u);
    EXPECT_EQ(bytes_per_voxel(VoxelType::float32), 4u);
    EXPECT_STREQ(to_string(VoxelType::uint8), "uint8");
    EXPECT_STREQ(to_string(VoxelType::uint16), "uint16");
    EXPECT_STREQ(to_string(VoxelType::float32), "float32");
}

TEST(MakeVolume, KeepsDataAndComputesIntegerRange) {
    const std::vector<std::uint16_t> values{7, 300, 65535, 12, 9, 1000};
    auto volume = make_volume("v", {3, 2, 1}, glm::dvec3(0.5, 1.0, 2.0), VoxelType::uint16,
                              as_bytes(values));
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "v");
    EXPECT_EQ(volume->voxel_count(), 6u);
    EXPECT_EQ(volume->range.min, 7.0);
    EXPECT_EQ(volume->range.max, 65535.0);
    EXPECT_EQ(volume->nonfinite_voxels, 0u);
    EXPECT_EQ(volume->extent(), glm::dvec3(1.5, 2.0, 2.0));
}

TEST(MakeVolume, RejectsZeroDimension) {
    auto volume = make_volume("v", {4, 0, 4}, glm::dvec3(1.0), VoxelType::uint8, {});
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::invalid_volume);
    EXPECT_NE(volume.error().message.find("4x0x4"), std::string::npos);
}

TEST(MakeVolume, RejectsMoreThanMaxVoxelsBeforeLookingAtData) {
    auto volume = make_volume("v", {2048, 2048, 1024}, glm::dvec3(1.0), VoxelType::uint8, {});
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::too_large);
}

TEST(MakeVolume, RejectsDataOfTheWrongSize) {
    auto volume = make_volume("v", {2, 2, 2}, glm::dvec3(1.0), VoxelType::uint16,
                              std::vector<std::byte>(8));
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::invalid_volume);
    EXPECT_NE(volume.error().message.find("16 bytes expected"), std::string::npos)
            << volume.error().message;
}

TEST(MakeVolume, RejectsSpacingThatIsNotFiniteAndPositive) {
    const double bad[] = {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()};
    for (double spacing : bad) {
        auto volume = make_volume("v", {1, 1, 1}, glm::dvec3(1.0, spacing, 1.0), VoxelType::uint8,
                                  std::vector<std::byte>(1));
        ASSERT_FALSE(volume.ok()) << spacing;
        EXPECT_EQ(volume.error().code, base::ErrorCode::invalid_volume);
    }
}

TEST(MakeVolume, ReplacesNonFiniteFloatsByTheFiniteMinimum) {
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> values{3.0f, std::nanf(""), -2.0f, inf, 5.0f, -inf};
    auto volume = make_volume("v", {6, 1, 1}, glm::dvec3(1.0), values);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::float32);
    EXPECT_EQ(volume->nonfinite_voxels, 3u);
    EXPECT_EQ(volume->range.min, -2.0);
    EXPECT_EQ(volume->range.max, 5.0);
    const double expected[] = {3.0, -2.0, -2.0, -2.0, 5.0, -2.0};
    for (std::uint32_t x = 0; x < 6; ++x) {
        EXPECT_EQ(volume->value(x, 0, 0), expected[x]) << "x=" << x;
    }
}

TEST(MakeVolume, AllNonFiniteBecomesZero) {
    const std::vector<float> values(8, std::nanf(""));
    auto volume = make_volume("v", {2, 2, 2}, glm::dvec3(1.0), values);
    ASSERT_TRUE(volume.ok());
    EXPECT_EQ(volume->nonfinite_voxels, 8u);
    EXPECT_EQ(volume->range.min, 0.0);
    EXPECT_EQ(volume->range.max, 0.0);
    EXPECT_EQ(volume->value(1, 1, 1), 0.0);
}

TEST(Volume, ValueIndexesXFastestThenYThenZ) {
    const glm::uvec3 dims{3, 4, 5};
    std::vector<float> values;
    for (unsigned z = 0; z < dims.z; ++z) {
        for (unsigned y = 0; y < dims.y; ++y) {
            for (unsigned x = 0; x < dims.x; ++x) {
                values.push_back(static_cast<float>(x + 10 * y + 100 * z));
            }
        }
    }
    auto volume = make_volume("v", dims, glm::dvec3(1.0), values);
    ASSERT_TRUE(volume.ok());
    EXPECT_EQ(volume->value(0, 0, 0), 0.0);
    EXPECT_EQ(volume->value(2, 0, 0), 2.0);
    EXPECT_EQ(volume->value(0, 3, 0), 30.0);
    EXPECT_EQ(volume->value(0, 0, 4), 400.0);
    EXPECT_EQ(volume->value(2, 3, 4), 432.0);
    EXPECT_EQ(volume->value(1, 2, 3), 321.0);
}

TEST(VolumeDeathTest, ValueOutsideTheVolumeAborts) {
    auto volume = make_volume("v", {2, 2, 2}, glm::dvec3(1.0), std::vector<float>(8, 0.0f));
    ASSERT_TRUE(volume.ok());
    EXPECT_DEATH((void)volume->value(2, 0, 0), "outside the volume");
}

TEST(Histogram, EqualWidthBinsOverTheRange) {
    auto volume = make_volume("v", {5, 1, 1}, glm::dvec3(1.0),
                              std::vector<float>{0.0f, 1.0f, 2.0f, 3.0f, 4.0f});
    ASSERT_TRUE(volume.ok());
    const Histogram histogram = compute_histogram(*volume, 4);
    EXPECT_EQ(histogram.range.min, 0.0);
    EXPECT_EQ(histogram.range.max, 4.0);
    // Width 1: 0, 1, 2 fall in their own bins; 3 and the maximum 4 share the last one.
    EXPECT_EQ(histogram.bins, (std::vector<std::uint64_t>{1, 1, 1, 2}));
}

TEST(Histogram, Uint8VolumeWithEveryValueOnce) {
    std::vector<std::uint8_t> values(256);
    std::iota(values.begin(), values.end(), std::uint8_t{0});
    auto volume =
            make_volume("v", {16, 16, 1}, glm::dvec3(1.0), VoxelType::uint8, as_bytes(values));
    ASSERT_TRUE(volume.ok());
    const Histogram histogram = compute_histogram(*volume, 4);
    EXPECT_EQ(histogram.bins, (std::vector<std::uint64_t>{64, 64, 64, 64}));
    EXPECT_EQ(compute_histogram(*volume).bins, std::vector<std::uint64_t>(256, 1));
}

TEST(Histogram, Uint16UsesTheVolumeRangeNotTheTypeRange) {
    const std::vector<std::uint16_t> values{1000, 1000, 1001, 2000};
    auto volume = make_volume("v", {2, 2, 1}, glm::dvec3(1.0), VoxelType::uint16, as_bytes(values));
    ASSERT_TRUE(volume.ok());
    const Histogram histogram = compute_histogram(*volume, 2);
    EXPECT_EQ(histogram.range.min, 1000.0);
    EXPECT_EQ(histogram.range.max, 2000.0);
    EXPECT_EQ(histogram.bins, (std::vector<std::uint64_t>{3, 1}));
}

TEST(Histogram, ConstantVolumePutsEverythingInBinZero) {
    auto volume = make_volume("v", {2, 2, 2}, glm::dvec3(1.0), std::vector<float>(8, 7.5f));
    ASSERT_TRUE(volume.ok());
    const Histogram histogram = compute_histogram(*volume, 16);
    ASSERT_EQ(histogram.bins.size(), 16u);
    EXPECT_EQ(histogram.bins[0], 8u);
    EXPECT_EQ(std::accumulate(histogram.bins.begin(), histogram.bins.end(), std::uint64_t{0}), 8u);
}

TEST(Histogram, ReplacedNonFiniteVoxelsCountAtTheMinimum) {
    auto volume = make_volume("v", {4, 1, 1}, glm::dvec3(1.0),
                              std::vector<float>{1.0f, std::nanf(""), 2.0f, 3.0f});
    ASSERT_TRUE(volume.ok());
    EXPECT_EQ(compute_histogram(*volume, 2).bins, (std::vector<std::uint64_t>{2, 2}));
}

TEST(LoadVolume, UnknownExtensionListsTheSupportedOnes) {
    fixtures::TempDir dir;
    fixtures::write_text(dir / "head.mha", "not a volume");
    auto volume = load_volume(dir / "head.mha");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::unknown_format);
    for (const char* extension : {".nii", ".nii.gz", ".nrrd", ".nhdr", ".raw", ".raw.gz"}) {
        EXPECT_NE(volume.error().message.find(extension), std::string::npos) << extension;
    }
}

TEST(LoadVolume, MissingFileIsNotFound) {
    fixtures::TempDir dir;
    for (const char* name : {"a_2x2x2_uint8.raw", "a.nrrd", "a.nii.gz"}) {
        auto volume = load_volume(dir / name);
        ASSERT_FALSE(volume.ok()) << name;
        EXPECT_EQ(volume.error().code, base::ErrorCode::not_found) << name;
        EXPECT_NE(volume.error().to_string().find("not found"), std::string::npos);
        EXPECT_NE(volume.error().where.find(name), std::string::npos);
    }
}

TEST(LoadVolume, ChoosesTheLoaderFromTheFileName) {
    fixtures::TempDir dir;
    const std::vector<std::uint8_t> values{1, 2, 3, 4, 5, 6, 7, 8};
    fixtures::write_bytes(dir / "cube_2x2x2_uint8.RAW", as_bytes(values));
    fixtures::write_bytes(dir / "cube.nrrd",
                          fixtures::concat(fixtures::text_bytes("NRRD0004\ntype: uint8\n"
                                                                "dimension: 3\nsizes: 2 2 2\n"
                                                                "encoding: raw\n\n"),
                                           as_bytes(values)));
    for (const char* name : {"cube_2x2x2_uint8.RAW", "cube.nrrd"}) {
        auto volume = load_volume(dir / name);
        ASSERT_TRUE(volume.ok()) << name << ": " << volume.error().to_string();
        EXPECT_EQ(volume->name, "cube");
        EXPECT_EQ(volume->value(1, 1, 1), 8.0);
    }
}

TEST(Orientation, CodeNamesTheNearestPatientDirectionOfEachAxis) {
    EXPECT_EQ(orientation_code(glm::dmat3(1.0)), "RAS");
    EXPECT_EQ(orientation_code(
                      glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1))),
              "LPS");
    EXPECT_EQ(orientation_code(
                      glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0))),
              "LSA");
    // 30 degrees off an axis still names that axis.
    EXPECT_EQ(orientation_code(glm::dmat3(glm::dvec3(0.866, -0.5, 0), glm::dvec3(0.5, 0.866, 0),
                                          glm::dvec3(0, 0, -1))),
              "RAI");
}

TEST(Orientation, StepsGiveSpacingAxesAndOrigin) {
    auto geometry = geometry_from_steps(
            glm::dmat3(glm::dvec3(0, 0, 2), glm::dvec3(-3, 0, 0), glm::dvec3(0, 4, 0)),
            glm::dvec3(1, 2, 3));
    ASSERT_TRUE(geometry.ok()) << geometry.error().to_string();
    EXPECT_EQ(geometry->spacing, glm::dvec3(2, 3, 4));
    EXPECT_EQ(orientation_code(geometry->axes), "SLA");
    EXPECT_EQ(geometry->origin, glm::dvec3(1, 2, 3));
}

TEST(Orientation, ShearedAndDegenerateStepsAreRefused) {
    auto sheared = geometry_from_steps(
            glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0.1, 1)),
            glm::dvec3(0));
    ASSERT_FALSE(sheared.ok());
    EXPECT_EQ(sheared.error().code, base::ErrorCode::sheared_transform);
    auto flat = geometry_from_steps(
            glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0), glm::dvec3(0, 0, 1)), glm::dvec3(0));
    ASSERT_FALSE(flat.ok());
    EXPECT_EQ(flat.error().code, base::ErrorCode::bad_transform);
}

// A field linear in patient space, sampled on a grid sheared along every pair of axes (as dipy's
// S0_10slices.nii.gz is), comes back on the orthogonal grid exactly: trilinear interpolation
// reproduces a linear field, so every resampled voxel inside the stored ones holds the field at
// its own centre, and those outside hold the lowest value.
TEST(Placement, AShearedVolumeIsResampledOntoAnOrthogonalGridHoldingTheSameField) {
    const glm::dmat3 steps(glm::dvec3(2, 0, 0.2), glm::dvec3(0.3, 1.5, 0), glm::dvec3(1.2, 0.9, 3));
    const glm::dvec3 origin(-10, 5, 20);
    const glm::dvec3 gradient(0.5, -0.25, 0.125);
    const auto field = [&](glm::dvec3 p) { return 100.0 + glm::dot(gradient, p - origin); };
    const glm::uvec3 dims(9, 7, 5);
    std::vector<float> values;
    for (std::uint32_t k = 0; k < dims.z; ++k) {
        for (std::uint32_t j = 0; j < dims.y; ++j) {
            for (std::uint32_t i = 0; i < dims.x; ++i) {
                values.push_back(static_cast<float>(field(origin + steps * glm::dvec3(i, j, k))));
            }
        }
    }
    auto volume = make_volume("sheared", dims, glm::dvec3(1.0), values);
    ASSERT_TRUE(volume.ok());
    auto geometry = placed_geometry(steps, origin);
    ASSERT_TRUE(geometry.ok()) << geometry.error().to_string();
    ASSERT_TRUE(geometry->sheared_steps.has_value());
    const double lowest = volume->range.min;
    ASSERT_TRUE(place_volume(*volume, *geometry, LoadOptions{}).ok());

    // The grid: i's direction, j's made perpendicular to it, their normal; spacings the steps'
    // lengths along them; a rotation.
    EXPECT_NEAR(glm::dot(volume->axes[0], glm::normalize(steps[0])), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(volume->axes[0], volume->axes[1]), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(volume->axes[1], volume->axes[2]), 0.0, 1e-12);
    EXPECT_NEAR(glm::determinant(volume->axes), 1.0, 1e-12);
    EXPECT_NEAR(volume->spacing.x, glm::length(steps[0]), 1e-12);
    ASSERT_EQ(volume->notes.size(), 1u);
    EXPECT_NE(volume->notes[0].find("resampled onto an orthogonal grid"), std::string::npos)
            << volume->notes[0];
    EXPECT_GT(volume->voxel_count(), std::size_t{dims.x} * dims.y * dims.z);

    const glm::dmat3 to_stored = glm::inverse(steps);
    std::size_t inside = 0;
    std::size_t outside = 0;
    for (std::uint32_t z = 0; z < volume->dims.z; ++z) {
        for (std::uint32_t y = 0; y < volume->dims.y; ++y) {
            for (std::uint32_t x = 0; x < volume->dims.x; ++x) {
                const glm::dvec3 p =
                        volume->origin + volume->axes * (volume->spacing * glm::dvec3(x, y, z));
                const glm::dvec3 index = to_stored * (p - origin);
                const bool within =
                        glm::all(glm::greaterThanEqual(index, glm::dvec3(-1e-9))) &&
                        glm::all(glm::lessThanEqual(index, glm::dvec3(dims) - 1.0 + 1e-9));
                const double want = within ? field(p) : lowest;
                ASSERT_NEAR(volume->value(x, y, z), want, 1e-3)
                        << "voxel " << x << "," << y << "," << z
                        << (within ? " inside" : " outside");
                (within ? inside : outside) += 1;
            }
        }
    }
    EXPECT_GT(inside, 100u);
    EXPECT_GT(outside, 100u);
}

// A label map's ids must not mix: where the options refuse resampling, a shear is refused as
// before; steps so nearly coplanar that they span almost no volume are refused whatever the
// options; a grid that would hold far more than the stored voxels is refused for its size.
TEST(Placement, ShearIsRefusedWhereResamplingIsNotWantedOrWouldNotBeSound) {
    auto volume =
            make_volume("sheared", glm::uvec3(4), glm::dvec3(1.0), std::vector<float>(64, 1.0f));
    ASSERT_TRUE(volume.ok());
    const glm::dmat3 tilt(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0.27, 1));
    auto geometry = placed_geometry(tilt, glm::dvec3(0));
    ASSERT_TRUE(geometry.ok());
    LoadOptions exact;
    exact.resample_sheared = false;
    auto refused = place_volume(*volume, *geometry, exact);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::sheared_transform);
    EXPECT_EQ(volume->dims, glm::uvec3(4));

    auto lost = placed_geometry(tilt, glm::dvec3(0.0, std::nan(""), 0.0));
    ASSERT_FALSE(lost.ok());
    EXPECT_EQ(lost.error().code, base::ErrorCode::bad_transform);

    auto flat = placed_geometry(
            glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(1, 1, 1e-4)),
            glm::dvec3(0));
    ASSERT_FALSE(flat.ok());
    EXPECT_EQ(flat.error().code, base::ErrorCode::sheared_transform);
    EXPECT_NE(flat.error().message.find("nearly coplanar"), std::string::npos)
            << flat.error().message;

    // 89 degrees of shear: the grid along i would be about 57 times the stored voxels.
    auto steep = placed_geometry(
            glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(57.3, 0, 1)),
            glm::dvec3(0));
    ASSERT_TRUE(steep.ok()) << steep.error().to_string();
    auto too_large = place_volume(*volume, *steep, LoadOptions{});
    ASSERT_FALSE(too_large.ok());
    EXPECT_EQ(too_large.error().code, base::ErrorCode::out_of_memory);

    // A grid of more voxels along one axis than any integer holds: refused, not wrapped around.
    auto huge = placed_geometry(
            glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 1e20, 1e20)),
            glm::dvec3(0));
    ASSERT_TRUE(huge.ok()) << huge.error().to_string();
    auto wrapped = place_volume(*volume, *huge, LoadOptions{});
    ASSERT_FALSE(wrapped.ok());
    EXPECT_EQ(wrapped.error().code, base::ErrorCode::out_of_memory);
    EXPECT_EQ(volume->dims, glm::uvec3(4));
}

TEST(Orientation, LpsToRasNegatesXAndY) {
    EXPECT_EQ(lps_to_ras(glm::dvec3(1, 2, 3)), glm::dvec3(-1, -2, 3));
}

TEST(Rescale, Int16WithRescaleGivesRealValuesRangeAndHistogram) {
    const std::vector<std::int16_t> stored{-32768, -1, 0, 32767};
    auto volume = make_volume("ct", {2, 2, 1}, glm::dvec3(1.0), VoxelType::int16, as_bytes(stored),
                              Rescale{2.0, -1024.0});
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->data, as_bytes(stored));
    EXPECT_EQ(volume->value(0, 0, 0), -32768.0 * 2 - 1024);
    EXPECT_EQ(volume->value(1, 0, 0), -2.0 - 1024);
    EXPECT_EQ(volume->value(1, 1, 0), 32767.0 * 2 - 1024);
    EXPECT_EQ(volume->range.min, -32768.0 * 2 - 1024);
    EXPECT_EQ(volume->range.max, 32767.0 * 2 - 1024);
    const Histogram histogram = compute_histogram(*volume, 2);
    EXPECT_EQ(histogram.bins, (std::vector<std::uint64_t>{2, 2}));
}

TEST(Rescale, NegativeSlopeSwapsTheRange) {
    const std::vector<std::uint8_t> stored{0, 10};
    auto volume = make_volume("v", {2, 1, 1}, glm::dvec3(1.0), VoxelType::uint8, as_bytes(stored),
                              Rescale{-1.0, 5.0});
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->range.min, -5.0);
    EXPECT_EQ(volume->range.max, 5.0);
}

TEST(Rescale, ZeroOrNonFiniteSlopeIsRefused) {
    for (const double slope : {0.0, std::nan("")}) {
        auto volume = make_volume("v", {1, 1, 1}, glm::dvec3(1.0), VoxelType::uint8,
                                  std::vector<std::byte>(1), Rescale{slope, 0.0});
        EXPECT_FALSE(volume.ok()) << slope;
    }
}
}  // namespace
}  // namespace penumbra::volume
