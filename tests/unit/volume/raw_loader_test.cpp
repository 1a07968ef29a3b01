#include "fixture_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace penumbra::volume {
namespace {

using fixtures::as_bytes;

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(RawLoader, Uint8RoundTrip) {
    fixtures::TempDir dir;
    std::vector<std::uint8_t> values(4 * 3 * 2);
    for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = static_cast<std::uint8_t>(10 * i);
    }
    const auto path = dir / "engine_4x3x2_uint8.raw";
    fixtures::write_bytes(path, as_bytes(values));

    auto volume = load_raw(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "engine");
    EXPECT_EQ(volume->dims, glm::uvec3(4, 3, 2));
    EXPECT_EQ(volume->spacing, glm::dvec3(1.0));
    EXPECT_EQ(volume->type, VoxelType::uint8);
    EXPECT_EQ(volume->data, as_bytes(values));
    EXPECT_EQ(volume->range.min, 0.0);
    EXPECT_EQ(volume->range.max, 230.0);
    EXPECT_EQ(volume->value(3, 2, 1), 230.0);
    EXPECT_EQ(volume->value(1, 1, 0), 50.0);
}

TEST(RawLoader, Uint16RoundTrip) {
    fixtures::TempDir dir;
    const std::vector<std::uint16_t> values{0, 1, 256, 4095, 65535, 42, 7, 9};
    const auto path = dir / "foot_2x2x2_uint16.raw";
    fixtures::write_bytes(path, as_bytes(values));

    auto volume = load_raw(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::uint16);
    EXPECT_EQ(volume->data, as_bytes(values));
    EXPECT_EQ(volume->range.max, 65535.0);
    EXPECT_EQ(volume->value(0, 0, 1), 65535.0);
}

TEST(RawLoader, Float32RoundTripReplacesNonFinite) {
    fixtures::TempDir dir;
    const std::vector<float> values{-1.5f, 0.25f, std::nanf(""), 8.0f};
    const auto path = dir / "field_4x1x1_float32.raw";
    fixtures::write_bytes(path, as_bytes(values));

    auto volume = load_raw(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::float32);
    EXPECT_EQ(volume->nonfinite_voxels, 1u);
    EXPECT_EQ(volume->range.min, -1.5);
    EXPECT_EQ(volume->range.max, 8.0);
    EXPECT_EQ(volume->value(1, 0, 0), 0.25);
    EXPECT_EQ(volume->value(2, 0, 0), -1.5);
}

TEST(RawLoader, GzipRoundTrip) {
    fixtures::TempDir dir;
    std::vector<std::uint16_t> values(32 * 16 * 8);
    for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = static_cast<std::uint16_t>(i * 7);
    }
    const auto path = dir / "bonsai_32x16x8_uint16.raw.gz";
    fixtures::write_gzip_file(path, as_bytes(values));

    auto volume = load_raw(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "bonsai");
    EXPECT_EQ(volume->dims, glm::uvec3(32, 16, 8));
    EXPECT_EQ(volume->type, VoxelType::uint16);
    EXPECT_EQ(volume->data, as_bytes(values));
}

TEST(RawLoader, Int16IsKept) {
    fixtures::TempDir dir;
    const std::vector<std::int16_t> values{-1024, -1, 0, 3071};
    const auto path = dir / "ct_2x2x1_int16.raw";
    fixtures::write_bytes(path, as_bytes(values));

    auto volume = load_raw(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::int16);
    EXPECT_EQ(volume->data, as_bytes(values));
    EXPECT_EQ(volume->range.min, -1024.0);
    EXPECT_EQ(volume->range.max, 3071.0);
    EXPECT_EQ(volume->value(1, 0, 0), -1.0);
    EXPECT_EQ(volume->value(1, 1, 0), 3071.0);
}

TEST(RawLoader, Float64IsConvertedToFloat32) {
    fixtures::TempDir dir;
    const std::vector<double> values{0.5, -2.25, 1e300, 3.0};
    const auto path = dir / "sim_1x1x4_float64.raw";
    fixtures::write_bytes(path, as_bytes(values));

    auto volume = load_raw(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::float32);
    // 1e300 does not fit a float: it becomes +Inf and is replaced like any non-finite voxel.
    EXPECT_EQ(volume->nonfinite_voxels, 1u);
    EXPECT_EQ(volume->value(0, 0, 1), -2.25);
    EXPECT_EQ(volume->value(0, 0, 2), -2.25);
    EXPECT_EQ(volume->value(0, 0, 3), 3.0);
}

TEST(RawLoader, NameMayContainUnderscores) {
    fixtures::TempDir dir;
    const auto path = dir / "marschner_lobb_2x1x1_uint8.raw";
    fixtures::write_bytes(path, as_bytes(std::vector<std::uint8_t>{1, 2}));
    auto volume = load_raw(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "marschner_lobb");
}

TEST(RawLoader, NamesThatDoNotFollowThePatternAreRejectedWithThePattern) {
    fixtures::TempDir dir;
    const char* names[] = {
            "engine.raw",                // no dims, no type
            "engine_256x256_uint8.raw",  // two sizes
            "engine_4x4x4x4_uint8.raw",  // four sizes
            "engine_4x0x4_uint8.raw",    // a zero size
            "engine_4x-4x4_uint8.raw",   // a negative size
            "engine_4xax4_uint8.raw",    // not a number
            "engine_4x4x4_uint12.raw",   // unknown type
            "engine_4x4x4.raw",          // no type
            "_4x4x4_uint8.raw",          // no name
            "engine_4x4x4_uint8.dat",    // not .raw
    };
    for (const char* name : names) {
        fixtures::write_bytes(dir / name, std::vector<std::byte>(64));
        auto volume = load_raw(dir / name);
        ASSERT_FALSE(volume.ok()) << name;
        EXPECT_EQ(volume.error().code, base::ErrorCode::bad_file_name) << name;
        EXPECT_TRUE(contains(volume.error().message, "name_XxYxZ_type.raw"))
                << name << ": " << volume.error().message;
        EXPECT_TRUE(contains(volume.error().where, name)) << volume.error().where;
    }
}

TEST(RawLoader, UnknownTypeIsNamedInTheError) {
    fixtures::TempDir dir;
    fixtures::write_bytes(dir / "engine_2x2x2_uint12.raw", std::vector<std::byte>(8));
    auto volume = load_raw(dir / "engine_2x2x2_uint12.raw");
    ASSERT_FALSE(volume.ok());
    EXPECT_TRUE(contains(volume.error().message, "'uint12'")) << volume.error().message;
}

TEST(RawLoader, TruncatedFileReportsExpectedAndActualSizes) {
    fixtures::TempDir dir;
    const auto path = dir / "engine_4x4x4_uint16.raw";
    fixtures::write_bytes(path, std::vector<std::byte>(100));
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
    EXPECT_TRUE(contains(volume.error().message, "128")) << volume.error().message;
    EXPECT_TRUE(contains(volume.error().message, "100")) << volume.error().message;
    EXPECT_TRUE(contains(volume.error().where, "engine_4x4x4_uint16.raw:byte 100"))
            << volume.error().where;
}

TEST(RawLoader, LongerFileIsRejected) {
    fixtures::TempDir dir;
    const auto path = dir / "engine_2x2x2_uint8.raw";
    fixtures::write_bytes(path, std::vector<std::byte>(9));
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::too_long);
    EXPECT_TRUE(contains(volume.error().message, "9 bytes")) << volume.error().message;
    EXPECT_TRUE(contains(volume.error().message, "8")) << volume.error().message;
}

TEST(RawLoader, EmptyFileIsTruncated) {
    fixtures::TempDir dir;
    fixtures::write_bytes(dir / "e_1x1x1_uint8.raw", {});
    auto volume = load_raw(dir / "e_1x1x1_uint8.raw");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
}

TEST(RawLoader, TruncatedGzipReportsDecompressedSize) {
    fixtures::TempDir dir;
    const auto path = dir / "engine_4x4x4_uint8.raw.gz";
    fixtures::write_gzip_file(path, std::vector<std::byte>(60));
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
    EXPECT_TRUE(contains(volume.error().message, "60 bytes")) << volume.error().message;
    EXPECT_TRUE(contains(volume.error().message, "64")) << volume.error().message;
}

TEST(RawLoader, GzipCutShortIsTruncated) {
    fixtures::TempDir dir;
    std::vector<std::uint8_t> values(4096);
    for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = static_cast<std::uint8_t>((i * 2654435761u) >> 24);
    }
    auto compressed = fixtures::gzip_bytes(as_bytes(values));
    compressed.resize(compressed.size() / 2);
    const auto path = dir / "noise_16x16x16_uint8.raw.gz";
    fixtures::write_bytes(path, compressed);
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
}

TEST(RawLoader, GzipMissingOnlyItsTrailerIsTruncated) {
    fixtures::TempDir dir;
    auto compressed = fixtures::gzip_bytes(std::vector<std::byte>(8, std::byte{1}));
    compressed.resize(compressed.size() - 8);  // the CRC32 and length trailer
    const auto path = dir / "ones_2x2x2_uint8.raw.gz";
    fixtures::write_bytes(path, compressed);
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
}

TEST(RawLoader, LongerGzipIsRejected) {
    fixtures::TempDir dir;
    const auto path = dir / "engine_2x2x2_uint8.raw.gz";
    fixtures::write_gzip_file(path, std::vector<std::byte>(9));
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::too_long);
}

TEST(RawLoader, GzipBombIsStoppedAtTheExpectedSize) {
    fixtures::TempDir dir;
    // 64 MiB of zeros compress to about 64 KiB; the loader must stop after 8 bytes + 1.
    const auto path = dir / "bomb_2x2x2_uint8.raw.gz";
    fixtures::write_gzip_file(path, std::vector<std::byte>(std::size_t{64} << 20));
    EXPECT_LT(std::filesystem::file_size(path), std::uintmax_t{1} << 20);
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::too_long);
}

TEST(RawLoader, ConcatenatedGzipMembersAreOneStream) {
    fixtures::TempDir dir;
    const std::vector<std::uint8_t> first{1, 2, 3, 4};
    const std::vector<std::uint8_t> second{5, 6, 7, 8};
    const auto path = dir / "two_2x2x2_uint8.raw.gz";
    fixtures::write_bytes(path, fixtures::concat(fixtures::gzip_bytes(as_bytes(first)),
                                                 fixtures::gzip_bytes(as_bytes(second))));
    auto volume = load_raw(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->value(1, 1, 1), 8.0);
}

TEST(RawLoader, NotGzipDataIsCorrupt) {
    fixtures::TempDir dir;
    const auto path = dir / "plain_2x2x2_uint8.raw.gz";
    fixtures::write_text(path, "this is not gzip data at all");
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::corrupt_data);
    EXPECT_TRUE(contains(volume.error().where, ":byte ")) << volume.error().where;
}

TEST(RawLoader, TooManyVoxelsAreRejectedBeforeReading) {
    fixtures::TempDir dir;
    const auto path = dir / "huge_65536x65536x65536_uint8.raw";
    fixtures::write_bytes(path, std::vector<std::byte>(16));
    auto volume = load_raw(path);
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::too_large);
}

TEST(RawLoader, MissingFileIsNotFound) {
    fixtures::TempDir dir;
    auto volume = load_raw(dir / "absent_2x2x2_uint8.raw");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::not_found);
}

}  // namespace
}  // namespace penumbra::volume
