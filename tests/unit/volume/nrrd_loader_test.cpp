#include "fixture_files.hpp"

#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <bzlib.h>

namespace penumbra::volume {
namespace {

using fixtures::as_bytes;
using fixtures::concat;
using fixtures::text_bytes;

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// The 2x2x2 uint8 volume 1..8 most tests attach behind their header.
std::vector<std::byte> cube_uint8() {
    return as_bytes(std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 8});
}

constexpr const char* cube_header =
        "NRRD0004\n"
        "type: uint8\n"
        "dimension: 3\n"
        "sizes: 2 2 2\n"
        "encoding: raw\n";

// Writes `header` + blank line + `data` as an attached .nrrd and loads it.
base::Result<Volume> load_attached(const fixtures::TempDir& dir, const std::string& header,
                                   std::span<const std::byte> data,
                                   const char* name = "cube.nrrd") {
    fixtures::write_bytes(dir / name, concat(text_bytes(header + "\n"), data));
    return load_nrrd(dir / name);
}

TEST(NrrdLoader, AttachedRawUint8) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir, cube_header, cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "cube");
    EXPECT_EQ(volume->dims, glm::uvec3(2, 2, 2));
    EXPECT_EQ(volume->type, VoxelType::uint8);
    EXPECT_EQ(volume->spacing, glm::dvec3(1.0));
    EXPECT_EQ(volume->data, cube_uint8());
    EXPECT_EQ(volume->value(1, 0, 1), 6.0);
    EXPECT_EQ(volume->range.min, 1.0);
    EXPECT_EQ(volume->range.max, 8.0);
}

TEST(NrrdLoader, AttachedGzipFloat) {
    fixtures::TempDir dir;
    std::vector<float> values(4 * 3 * 2);
    for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = static_cast<float>(i) * 0.5f - 3.0f;
    }
    auto volume = load_attached(dir,
                                "NRRD0005\n"
                                "type: float\n"
                                "dimension: 3\n"
                                "sizes: 4 3 2\n"
                                "endian: little\n"
                                "encoding: gzip\n",
                                fixtures::gzip_bytes(as_bytes(values)));
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::float32);
    EXPECT_EQ(volume->dims, glm::uvec3(4, 3, 2));
    EXPECT_EQ(volume->data, as_bytes(values));
    EXPECT_EQ(volume->range.min, -3.0);
}

TEST(NrrdLoader, GzSpellingAndByteSkipAppliesToDecompressedData) {
    fixtures::TempDir dir;
    const auto data = concat(text_bytes("JUNK"), cube_uint8());
    auto volume = load_attached(dir,
                                "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n"
                                "encoding: gz\nbyte skip: 4\n",
                                fixtures::gzip_bytes(data));
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->data, cube_uint8());
}

TEST(NrrdLoader, DetachedHeaderReadsTheDataFileNextToIt) {
    fixtures::TempDir dir;
    std::filesystem::create_directory(dir / "data");
    const std::vector<std::uint16_t> values{10, 20, 30, 40, 50, 60, 70, 80};
    fixtures::write_bytes(dir / "data" / "cube.raw", as_bytes(values));
    fixtures::write_text(dir / "data" / "cube.nhdr",
                         "NRRD0004\n"
                         "type: unsigned short\n"
                         "dimension: 3\n"
                         "sizes: 2 2 2\n"
                         "endian: little\n"
                         "encoding: raw\n"
                         "data file: cube.raw\n");
    auto volume = load_nrrd(dir / "data" / "cube.nhdr");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "cube");
    EXPECT_EQ(volume->type, VoxelType::uint16);
    EXPECT_EQ(volume->data, as_bytes(values));

    // The same through load_volume, and with an absolute data file path.
    fixtures::write_text(dir / "absolute.nhdr",
                         "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 2 2 2\n"
                         "endian: little\nencoding: raw\ndatafile: " +
                                 (dir / "data" / "cube.raw").string() + "\n");
    auto absolute = load_volume(dir / "absolute.nhdr");
    ASSERT_TRUE(absolute.ok()) << absolute.error().to_string();
    EXPECT_EQ(absolute->data, as_bytes(values));
}

TEST(NrrdLoader, DetachedGzipData) {
    fixtures::TempDir dir;
    fixtures::write_gzip_file(dir / "cube.raw.gz", cube_uint8());
    fixtures::write_text(dir / "cube.nhdr",
                         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\n"
                         "data file: ./cube.raw.gz\n");
    auto volume = load_nrrd(dir / "cube.nhdr");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->data, cube_uint8());
}

TEST(NrrdLoader, BigEndianSamplesAreSwapped) {
    fixtures::TempDir dir;
    const std::vector<std::byte> big{std::byte{0x01}, std::byte{0x02}, std::byte{0xff},
                                     std::byte{0x00}};
    auto volume = load_attached(dir,
                                "NRRD0004\ntype: ushort\ndimension: 3\nsizes: 2 1 1\n"
                                "endian: big\nencoding: raw\n",
                                big);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->value(0, 0, 0), 0x0102);
    EXPECT_EQ(volume->value(1, 0, 0), 0xff00);

    // float 1.5 is 0x3fc00000; big endian puts 0x3f first.
    const std::vector<std::byte> big_float{std::byte{0x3f}, std::byte{0xc0}, std::byte{0x00},
                                           std::byte{0x00}};
    auto floats = load_attached(dir,
                                "NRRD0004\ntype: float\ndimension: 3\nsizes: 1 1 1\n"
                                "endian: big\nencoding: raw\n",
                                big_float, "float.nrrd");
    ASSERT_TRUE(floats.ok()) << floats.error().to_string();
    EXPECT_EQ(floats->value(0, 0, 0), 1.5);
}

TEST(NrrdLoader, Int16BigEndianIsKeptAsInt16) {
    fixtures::TempDir dir;
    const std::vector<std::byte> big{std::byte{0xff}, std::byte{0xfe}, std::byte{0x01},
                                     std::byte{0x00}};
    auto volume = load_attached(dir,
                                "NRRD0004\ntype: signed short int\ndimension: 3\n"
                                "sizes: 1 2 1\nendian: big\nencoding: raw\n",
                                big);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::int16);
    EXPECT_EQ(volume->value(0, 0, 0), -2.0);
    EXPECT_EQ(volume->value(0, 1, 0), 256.0);
}

TEST(NrrdLoader, SpacingsGiveTheVoxelSize) {
    fixtures::TempDir dir;
    auto volume =
            load_attached(dir, std::string(cube_header) + "spacings: 0.5 2 -3\n", cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->spacing, glm::dvec3(0.5, 2.0, 3.0));

    auto with_nan =
            load_attached(dir, std::string(cube_header) + "spacings: 0.5 NaN 2\n", cube_uint8());
    ASSERT_TRUE(with_nan.ok()) << with_nan.error().to_string();
    EXPECT_EQ(with_nan->spacing, glm::dvec3(0.5, 1.0, 2.0));
}

TEST(NrrdLoader, SpaceDirectionsGiveTheVectorLengths) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir,
                                std::string(cube_header) +
                                        "space: right-anterior-superior\n"
                                        "space directions: (0.6,0.8,0) (1.6,-1.2,0) (0,0,0.25)\n"
                                        "space origin: (1,2,3)\n",
                                cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_DOUBLE_EQ(volume->spacing.x, 1.0);
    EXPECT_DOUBLE_EQ(volume->spacing.y, 2.0);
    EXPECT_DOUBLE_EQ(volume->spacing.z, 0.25);
}

void expect_axes(const Volume& volume, glm::dvec3 i, glm::dvec3 j, glm::dvec3 k) {
    for (int row = 0; row < 3; ++row) {
        EXPECT_NEAR(volume.axes[0][row], i[row], 1e-12) << "axis i, component " << row;
        EXPECT_NEAR(volume.axes[1][row], j[row], 1e-12) << "axis j, component " << row;
        EXPECT_NEAR(volume.axes[2][row], k[row], 1e-12) << "axis k, component " << row;
    }
}

TEST(NrrdLoader, RasSpaceDirectionsAreTheAxesAndOrigin) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir,
                                std::string(cube_header) +
                                        "space: right-anterior-superior\n"
                                        "space directions: (0.6,0.8,0) (1.6,-1.2,0) (0,0,0.25)\n"
                                        "space origin: (1,2,3)\n",
                                cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_axes(*volume, {0.6, 0.8, 0.0}, {0.8, -0.6, 0.0}, {0.0, 0.0, 1.0});
    EXPECT_EQ(volume->origin, glm::dvec3(1.0, 2.0, 3.0));
    EXPECT_EQ(orientation_code(volume->axes), "ARS");
}

TEST(NrrdLoader, LpsSpaceIsConvertedToRas) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir,
                                std::string(cube_header) +
                                        "space: left-posterior-superior\n"
                                        "space directions: (2,0,0) (0,3,0) (0,0,4)\n"
                                        "space origin: (10,-20,30)\n",
                                cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_axes(*volume, {-1.0, 0.0, 0.0}, {0.0, -1.0, 0.0}, {0.0, 0.0, 1.0});
    EXPECT_EQ(volume->spacing, glm::dvec3(2.0, 3.0, 4.0));
    EXPECT_EQ(volume->origin, glm::dvec3(-10.0, 20.0, 30.0));
    EXPECT_EQ(orientation_code(volume->axes), "LPS");
}

TEST(NrrdLoader, LasSpaceMirrorsX) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir,
                                std::string(cube_header) +
                                        "space: LAS\n"
                                        "space directions: (1,0,0) (0,1,0) (0,0,1)\n",
                                cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(orientation_code(volume->axes), "LAS");
    EXPECT_EQ(volume->origin, glm::dvec3(0.0));
}

TEST(NrrdLoader, ObliqueDirectionsAreKept) {
    fixtures::TempDir dir;
    // 30 degrees about the patient's z axis, in LPS.
    const double c = std::sqrt(3.0) / 2.0;
    const std::string directions = "space directions: (" + std::to_string(c) + ",0.5,0) (-0.5," +
                                   std::to_string(c) + ",0) (0,0,1)\n";
    auto volume = load_attached(
            dir, std::string(cube_header) + "space: left-posterior-superior\n" + directions,
            cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    for (int row = 0; row < 2; ++row) {
        EXPECT_NEAR(volume->axes[0][row], (row == 0 ? -c : -0.5), 1e-6);
        EXPECT_NEAR(volume->axes[1][row], (row == 0 ? 0.5 : -c), 1e-6);
    }
    EXPECT_EQ(orientation_code(volume->axes), "LPS");
}

// Slices stepping along a tilted axis (as a gantry-tilted CT's do): resampled onto an orthogonal
// grid (volume_test has the resampling's exactness), with a note; a label map refuses it.
TEST(NrrdLoader, ShearedDirectionsAreResampledOntoAnOrthogonalGrid) {
    fixtures::TempDir dir;
    const std::string header = std::string(cube_header) +
                               "space: left-posterior-superior\n"
                               "space directions: (1,0,0) (0,1,0) (0,0.5,1)\n";
    auto volume = load_attached(dir, header, cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(2, 3, 2));  // the second slice moved by half a row
    EXPECT_EQ(orientation_code(volume->axes), "LPS");
    ASSERT_FALSE(volume->notes.empty());
    EXPECT_TRUE(contains(volume->notes.back(), "degrees apart")) << volume->notes.back();

    fixtures::write_bytes(dir / "labels.nrrd", concat(text_bytes(header + "\n"), cube_uint8()));
    auto labels = load_label_map(dir / "labels.nrrd", {}, {});
    ASSERT_FALSE(labels.ok());
    EXPECT_EQ(labels.error().code, base::ErrorCode::sheared_transform);
    EXPECT_TRUE(contains(labels.error().message, "cannot be resampled")) << labels.error().message;
}

TEST(NrrdLoader, UnknownSpaceIsRefused) {
    fixtures::TempDir dir;
    auto volume =
            load_attached(dir, std::string(cube_header) + "space: upside-down\n", cube_uint8());
    ASSERT_FALSE(volume.ok());
    EXPECT_TRUE(contains(volume.error().message, "unknown space")) << volume.error().message;
}

TEST(NrrdLoader, SpacingsWithoutSpaceGiveIdentityAxes) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir, std::string(cube_header) + "spacings: 2 3 4\n", cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->axes, glm::dmat3(1.0));
    EXPECT_EQ(volume->spacing, glm::dvec3(2.0, 3.0, 4.0));
    EXPECT_EQ(orientation_code(volume->axes), "RAS");
}

TEST(NrrdLoader, CommentsKeyValuesAndOtherFieldsAreIgnored) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir,
                                "NRRD0004\r\n"
                                "# Complete NRRD file format specification at:\r\n"
                                "type: unsigned char\r\n"
                                "content: a head: with colons\r\n"
                                "dimension: 3\r\n"
                                "DWMRI_b-value:=1000\r\n"
                                "sizes: 2 2 2\r\n"
                                "kinds: domain domain domain\r\n"
                                "encoding: raw\r\n",
                                cube_uint8());
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->data, cube_uint8());
}

TEST(NrrdLoader, TypeSpellingsAreAllAccepted) {
    fixtures::TempDir dir;

    struct Case {
        const char* spelling;
        std::size_t size;
        VoxelType stored;
    };

    const Case cases[] = {
            {"uchar", 1, VoxelType::uint8},           {"unsigned char", 1, VoxelType::uint8},
            {"uint8_t", 1, VoxelType::uint8},         {"signed char", 1, VoxelType::float32},
            {"int8", 1, VoxelType::float32},          {"short", 2, VoxelType::int16},
            {"int16_t", 2, VoxelType::int16},         {"unsigned short int", 2, VoxelType::uint16},
            {"uint16", 2, VoxelType::uint16},         {"int", 4, VoxelType::float32},
            {"unsigned int", 4, VoxelType::float32},  {"uint32_t", 4, VoxelType::float32},
            {"long long int", 8, VoxelType::float32}, {"ulonglong", 8, VoxelType::float32},
            {"float", 4, VoxelType::float32},         {"double", 8, VoxelType::float32},
    };
    for (const Case& c : cases) {
        std::vector<std::byte> data(8 * c.size, std::byte{0});
        for (std::size_t i = 0; i < 8; ++i) {
            // Small integers 0..7 for the integer types; the float types read them as tiny
            // denormals or zero, which is fine: only the type mapping is checked here.
            data[i * c.size] = static_cast<std::byte>(i);
        }
        auto volume = load_attached(dir,
                                    std::string("NRRD0004\ntype: ") + c.spelling +
                                            "\ndimension: 3\nsizes: 2 2 2\nendian: little\n"
                                            "encoding: raw\n",
                                    data);
        ASSERT_TRUE(volume.ok()) << c.spelling << ": " << volume.error().to_string();
        EXPECT_EQ(volume->type, c.stored) << c.spelling;
        if (std::string(c.spelling) != "float" && std::string(c.spelling) != "double") {
            EXPECT_EQ(volume->value(1, 1, 1), 7.0) << c.spelling;
        }
    }
}

TEST(NrrdLoader, AsciiEncoding) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir,
                                "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 1\n"
                                "encoding: ascii\n",
                                text_bytes("1.5 -2\n3e2\t4\n"));
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->value(0, 0, 0), 1.5);
    EXPECT_EQ(volume->value(1, 0, 0), -2.0);
    EXPECT_EQ(volume->value(0, 1, 0), 300.0);

    auto bytes = load_attached(dir,
                               "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 1 1\n"
                               "encoding: text\n",
                               text_bytes("7 255\n"), "bytes.nrrd");
    ASSERT_TRUE(bytes.ok()) << bytes.error().to_string();
    EXPECT_EQ(bytes->type, VoxelType::uint8);
    EXPECT_EQ(bytes->value(1, 0, 0), 255.0);

    auto out_of_range = load_attached(dir,
                                      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 1 1\n"
                                      "encoding: txt\n",
                                      text_bytes("7 256\n"), "range.nrrd");
    ASSERT_FALSE(out_of_range.ok());
    EXPECT_EQ(out_of_range.error().code, base::ErrorCode::bad_data);

    auto short_text = load_attached(dir,
                                    "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 1\n"
                                    "encoding: ascii\n",
                                    text_bytes("1 2 3\n"), "short.nrrd");
    ASSERT_FALSE(short_text.ok());
    EXPECT_EQ(short_text.error().code, base::ErrorCode::truncated);
}

// teem's hex encoding: two digits a byte, either case, whitespace anywhere; the bytes are the raw
// encoding's (endianness applies); byte skip counts bytes of the file before the text, as teem
// reads it.
TEST(NrrdLoader, HexEncoding) {
    fixtures::TempDir dir;
    auto bytes = load_attached(dir,
                               "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\n"
                               "encoding: hex\n",
                               text_bytes("0102 03\n0405\t06 0 7\r\n08\n"));
    ASSERT_TRUE(bytes.ok()) << bytes.error().to_string();
    EXPECT_EQ(bytes->data, cube_uint8());

    auto words = load_attached(dir,
                               "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 1 1\n"
                               "encoding: hex\nendian: big\nbyte skip: 3\n",
                               text_bytes("## FFfe 7fFf\n"), "words.nrrd");
    ASSERT_TRUE(words.ok()) << words.error().to_string();
    EXPECT_EQ(words->value(0, 0, 0), -2.0);
    EXPECT_EQ(words->value(1, 0, 0), 32767.0);

    auto bad_digit = load_attached(dir,
                                   "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 1 1\n"
                                   "encoding: hex\n",
                                   text_bytes("0g 01\n"), "bad.nrrd");
    ASSERT_FALSE(bad_digit.ok());
    EXPECT_EQ(bad_digit.error().code, base::ErrorCode::bad_data);

    auto short_data = load_attached(dir,
                                    "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 1\n"
                                    "encoding: hex\n",
                                    text_bytes("01 02 0\n"), "short.nrrd");
    ASSERT_FALSE(short_data.ok());
    EXPECT_EQ(short_data.error().code, base::ErrorCode::truncated);
}

TEST(NrrdLoader, LineSkipAndByteSkipInADetachedFile) {
    fixtures::TempDir dir;
    fixtures::write_bytes(dir / "cube.pgm",
                          concat(text_bytes("P5\n# made by hand\n2 4\n255\nXYZ"), cube_uint8()));
    fixtures::write_text(dir / "cube.nhdr",
                         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                         "data file: cube.pgm\nline skip: 4\nbyte skip: 3\n");
    auto volume = load_nrrd(dir / "cube.nhdr");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->data, cube_uint8());
}

TEST(NrrdLoader, ByteSkipMinusOneReadsTheLastBytes) {
    fixtures::TempDir dir;
    fixtures::write_bytes(dir / "tail.bin", concat(text_bytes("some preamble"), cube_uint8()));
    fixtures::write_text(dir / "tail.nhdr",
                         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                         "data file: tail.bin\nbyte skip: -1\n");
    auto volume = load_nrrd(dir / "tail.nhdr");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->data, cube_uint8());
}

// Malformed headers: each is rejected with a code, the file name and, where there is one, the
// header line.

struct Rejection {
    const char* what;
    std::string header;
    std::string code;
    std::string where;  // expected suffix of Error::where ("" when only the file is named)
};

TEST(NrrdLoader, MalformedHeadersAreRejected) {
    const std::string h = "NRRD0004\n";
    const Rejection cases[] = {
            {"bad magic", "NRRD004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n",
             "bad_header", ":line 1"},
            {"not NRRD at all", "P5\n2 2\n255\n", "bad_header", ":line 1"},
            {"missing sizes", h + "type: uint8\ndimension: 3\nencoding: raw\n", "bad_header",
             "cube.nrrd"},
            {"missing type", h + "dimension: 3\nsizes: 2 2 2\nencoding: raw\n", "bad_header",
             "cube.nrrd"},
            {"missing dimension", h + "type: uint8\nsizes: 2 2 2\nencoding: raw\n", "bad_header",
             "cube.nrrd"},
            {"missing encoding", h + "type: uint8\ndimension: 3\nsizes: 2 2 2\n", "bad_header",
             "cube.nrrd"},
            {"dimension 5", h + "type: uint8\ndimension: 5\nsizes: 1 2 2 2 2\nencoding: raw\n",
             "unsupported_dimension", ":line 3"},
            {"dimension 2", h + "type: uint8\ndimension: 2\nsizes: 4 2\nencoding: raw\n",
             "unsupported_dimension", ":line 3"},
            {"dimension not a number", h + "type: uint8\ndimension: three\n", "bad_header",
             ":line 3"},
            {"unknown type", h + "type: uint12\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n",
             "unsupported_type", ":line 2"},
            {"block type", h + "type: block\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n",
             "unsupported_type", ":line 2"},
            {"zstd encoding", h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: zstd\n",
             "unsupported_encoding", ":line 5"},
            {"sizes count", h + "type: uint8\ndimension: 3\nsizes: 2 2\nencoding: raw\n",
             "bad_header", ":line 4"},
            {"negative size", h + "type: uint8\ndimension: 3\nsizes: 2 -2 2\nencoding: raw\n",
             "bad_header", ":line 4"},
            {"zero size", h + "type: uint8\ndimension: 3\nsizes: 2 0 2\nencoding: raw\n",
             "bad_header", ":line 4"},
            {"size not a number", h + "type: uint8\ndimension: 3\nsizes: 2 x 2\nencoding: raw\n",
             "bad_header", ":line 4"},
            {"absurd sizes",
             h + "type: uint8\ndimension: 3\nsizes: 100000 100000 100000\nencoding: raw\n",
             "too_large", ":line 4"},
            {"sizes beyond int64",
             h + "type: uint8\ndimension: 3\nsizes: 99999999999999999999 2 2\nencoding: raw\n",
             "bad_header", ":line 4"},
            {"missing endian", h + "type: short\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n",
             "bad_header", "cube.nrrd"},
            {"bad endian",
             h + "type: short\ndimension: 3\nsizes: 2 2 2\nencoding: raw\nendian: middle\n",
             "bad_header", ":line 6"},
            {"duplicate field", h + "type: uint8\ntype: uint8\n", "bad_header", ":line 3"},
            {"line without colon", h + "type uint8\n", "bad_header", ":line 2"},
            {"negative byte skip",
             h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\nbyte skip: -2\n",
             "bad_header", ":line 6"},
            {"byte skip -1 with gzip",
             h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\nbyte skip: -1\n",
             "bad_header", ":line 6"},
            {"zero spacing", h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nspacings: 1 0 1\n",
             "bad_header", ":line 5"},
            {"spacings count",
             h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\nspacings: 1 1\n",
             "bad_header", ":line 6"},
            {"bad space direction",
             h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nspace directions: (1,0,0) (0,1)\n",
             "bad_header", ":line 5"},
            {"zero space direction",
             h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                 "space directions: (1,0,0) (0,0,0) (0,0,1)\n",
             "bad_header", ":line 6"},
            {"data file LIST",
             h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: LIST\n",
             "unsupported_data_file", ":line 6"},
            {"numbered data files",
             h + "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                 "data file: slice%03d.raw 0 1 1\n",
             "unsupported_data_file", ":line 6"},
    };
    fixtures::TempDir dir;
    for (const Rejection& c : cases) {
        auto volume = load_attached(dir, c.header, cube_uint8());
        ASSERT_FALSE(volume.ok()) << c.what;
        EXPECT_EQ(base::name_of(volume.error().code), c.code)
                << c.what << ": " << volume.error().to_string();
        const std::string& where = volume.error().where;
        EXPECT_TRUE(contains(where, "cube.nrrd")) << c.what << ": " << where;
        EXPECT_TRUE(where.size() >= c.where.size() &&
                    where.compare(where.size() - c.where.size(), c.where.size(), c.where) == 0)
                << c.what << ": where is '" << where << "', expected it to end in '" << c.where
                << "'";
    }
}

TEST(NrrdLoader, ErrorMessagesNameWhatWasWrong) {
    fixtures::TempDir dir;
    auto dimension = load_attached(dir, "NRRD0004\ndimension: 5\n", {});
    ASSERT_FALSE(dimension.ok());
    EXPECT_TRUE(contains(dimension.error().message, "dimension 5")) << dimension.error().message;

    auto encoding = load_attached(dir, "NRRD0004\nencoding: zstd\n", {});
    ASSERT_FALSE(encoding.ok());
    EXPECT_TRUE(contains(encoding.error().message, "'zstd'")) << encoding.error().message;
    EXPECT_TRUE(contains(encoding.error().message, "raw, gzip, bzip2")) << encoding.error().message;

    auto type = load_attached(dir, "NRRD0004\ntype: quaternion\n", {});
    ASSERT_FALSE(type.ok());
    EXPECT_TRUE(contains(type.error().message, "'quaternion'")) << type.error().message;

    auto sizes = load_attached(dir, "NRRD0004\ntype: uint8\ndimension: 3\nencoding: raw\n", {});
    ASSERT_FALSE(sizes.ok());
    EXPECT_TRUE(contains(sizes.error().message, "'sizes'")) << sizes.error().message;
}

TEST(NrrdLoader, TruncatedRawDataReportsExpectedAndActualSizes) {
    fixtures::TempDir dir;
    const std::string header =
            "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 4 4 4\n"
            "endian: little\nencoding: raw\n";
    auto volume = load_attached(dir, header, std::vector<std::byte>(100));
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
    EXPECT_TRUE(contains(volume.error().message, "expected 128 bytes")) << volume.error().message;
    EXPECT_TRUE(contains(volume.error().message, "only 100")) << volume.error().message;
    const std::string offset = std::to_string(header.size() + 1 + 100);
    EXPECT_TRUE(contains(volume.error().where, "cube.nrrd:byte " + offset)) << volume.error().where;
}

TEST(NrrdLoader, TruncatedGzipDataIsRejected) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir,
                                "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\n"
                                "encoding: gzip\n",
                                fixtures::gzip_bytes(std::vector<std::byte>(60)));
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
    EXPECT_TRUE(contains(volume.error().message, "expected 64")) << volume.error().message;
    EXPECT_TRUE(contains(volume.error().message, "got 60")) << volume.error().message;
}

TEST(NrrdLoader, CorruptGzipDataIsRejected) {
    fixtures::TempDir dir;
    auto volume = load_attached(dir,
                                "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\n"
                                "encoding: gzip\n",
                                cube_uint8());
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::corrupt_data);
}

TEST(NrrdLoader, HeaderWithoutDataOrDataFileIsRejected) {
    fixtures::TempDir dir;
    fixtures::write_text(dir / "cube.nrrd",
                         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n");
    auto volume = load_nrrd(dir / "cube.nrrd");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::bad_header);
    EXPECT_TRUE(contains(volume.error().message, "data file")) << volume.error().message;
}

TEST(NrrdLoader, MissingDataFileIsNotFound) {
    fixtures::TempDir dir;
    fixtures::write_text(dir / "cube.nhdr",
                         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                         "data file: nowhere.raw\n");
    auto volume = load_nrrd(dir / "cube.nhdr");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::not_found);
    EXPECT_TRUE(contains(volume.error().where, "nowhere.raw")) << volume.error().where;
    EXPECT_TRUE(contains(volume.error().message, "cube.nhdr")) << volume.error().message;
}

TEST(NrrdLoader, TruncatedDetachedDataNamesTheDataFile) {
    fixtures::TempDir dir;
    fixtures::write_bytes(dir / "cube.raw", std::vector<std::byte>(5));
    fixtures::write_text(dir / "cube.nhdr",
                         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                         "data file: cube.raw\n");
    auto volume = load_nrrd(dir / "cube.nhdr");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
    EXPECT_TRUE(contains(volume.error().where, "cube.raw:byte 5")) << volume.error().where;
}

TEST(NrrdLoader, LineSkipPastTheEndIsTruncated) {
    fixtures::TempDir dir;
    fixtures::write_text(dir / "short.txt", "one line\n");
    fixtures::write_text(dir / "cube.nhdr",
                         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                         "data file: short.txt\nline skip: 3\n");
    auto volume = load_nrrd(dir / "cube.nhdr");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
}

TEST(NrrdLoader, HeaderWithoutEndIsCapped) {
    fixtures::TempDir dir;
    // 17 MiB of text without a newline after the magic: the reader gives up at 16 MiB.
    std::string text = "NRRD0004\n";
    text.append(std::size_t{17} << 20, 'a');
    fixtures::write_text(dir / "endless.nrrd", text);
    auto volume = load_nrrd(dir / "endless.nrrd");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::bad_header);
}

}  // namespace
}  // namespace penumbra::volume

namespace penumbra::volume {
namespace {

// Finding: a detached header's "data file" could name any file the server can read
// ("/etc/passwd", "../x") and expose its bytes as a volume.
TEST(NrrdLoader, DataFileOutsideTheHeadersFolderIsRefused) {
    fixtures::TempDir dir;
    std::filesystem::create_directories(dir / "volumes" / "sub");
    const std::vector<std::byte> bytes(8, std::byte{7});
    fixtures::write_bytes(dir / "outside.raw", bytes);
    fixtures::write_bytes(dir / "volumes" / "sub" / "inside.raw", bytes);
    std::filesystem::create_symlink(dir / "outside.raw", dir / "volumes" / "link.raw");
    const std::string header =
            "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\n"
            "encoding: raw\ndata file: ";
    const auto load_with = [&](const std::string& data_file) {
        fixtures::write_text(dir / "volumes" / "h.nhdr", header + data_file + "\n");
        return load_nrrd(dir / "volumes" / "h.nhdr");
    };
    for (const std::string& refused : {std::string("/etc/passwd"), std::string("../outside.raw"),
                                       std::string("sub/../../outside.raw"),
                                       (dir / "outside.raw").string(), std::string("link.raw")}) {
        const auto volume = load_with(refused);
        ASSERT_FALSE(volume.ok()) << refused;
        EXPECT_EQ(volume.error().code, base::ErrorCode::data_file_outside) << refused;
        EXPECT_EQ(volume.error().where, (dir / "volumes" / "h.nhdr").string() + ":line 6");
    }
    for (const std::string& allowed :
         {std::string("sub/inside.raw"), std::string("sub/../sub/inside.raw"),
          (dir / "volumes" / "sub" / "inside.raw").string()}) {
        const auto volume = load_with(allowed);
        ASSERT_TRUE(volume.ok()) << allowed << ": " << volume.error().to_string();
        EXPECT_EQ(volume->data, bytes);
    }
}

}  // namespace
}  // namespace penumbra::volume

namespace penumbra::volume {
namespace {

// ASCII data is read a chunk at a time: tokens across chunk boundaries, the end of the file as
// the end of the last value, a value beyond float's range as infinity (counted, not undefined).
TEST(NrrdLoader, AsciiValuesStreamAcrossChunksAndBeyondFloatRangeAreCounted) {
    fixtures::TempDir dir;
    const std::uint32_t values = 20000;
    std::string text;
    for (std::uint32_t i = 0; i + 1 < values; ++i) {
        text += std::to_string(i % 1000) + (i % 7 == 0 ? ",\n" : "   ");
    }
    ASSERT_GT(text.size(), std::size_t{1} << 16) << "the text must span several chunks";
    const std::string last_value_missing = text;
    text += "1e300";  // the last voxel, with no separator after it
    fixtures::write_text(dir / "big.txt", text);
    fixtures::write_text(dir / "big.nhdr",
                         "NRRD0004\ntype: float\ndimension: 3\nsizes: " + std::to_string(values) +
                                 " 1 1\nencoding: ascii\ndata file: big.txt\n");
    const auto volume = load_nrrd(dir / "big.nhdr");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->value(14000, 0, 0), 0.0);
    EXPECT_EQ(volume->value(14321, 0, 0), 321.0);
    EXPECT_EQ(volume->nonfinite_voxels, 1u);

    fixtures::write_text(dir / "big.txt", last_value_missing);
    const auto truncated = load_nrrd(dir / "big.nhdr");
    ASSERT_FALSE(truncated.ok());
    EXPECT_EQ(truncated.error().code, base::ErrorCode::truncated);
}

std::vector<std::byte> bzip2(std::span<const std::byte> data) {
    std::vector<char> source(data.size());
    std::memcpy(source.data(), data.data(), data.size());
    std::vector<char> out(data.size() + data.size() / 100 + 600);
    unsigned length = static_cast<unsigned>(out.size());
    EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &length, source.data(),
                                       static_cast<unsigned>(source.size()), 9, 0, 0),
              BZ_OK);
    out.resize(length);
    std::vector<std::byte> bytes(out.size());
    std::memcpy(bytes.data(), out.data(), out.size());
    return bytes;
}

TEST(NrrdLoader, Bzip2EncodingIsRead) {
    fixtures::TempDir dir;
    std::vector<std::uint16_t> values(4 * 3 * 2);
    for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = static_cast<std::uint16_t>(1000 + 37 * i);
    }
    const std::string header =
            "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 4 3 2\nendian: little\n"
            "encoding: bzip2\n";
    auto volume = load_attached(dir, header, bzip2(as_bytes(values)));
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(4, 3, 2));
    EXPECT_EQ(volume->value(3, 2, 1), 1000.0 + 37.0 * 23.0);
    // Cut short: named as such, not read past.
    auto compressed = bzip2(as_bytes(values));
    compressed.resize(compressed.size() / 2);
    auto cut = load_attached(dir, header, compressed, "cut.nrrd");
    ASSERT_FALSE(cut.ok());
    EXPECT_TRUE(cut.error().code == base::ErrorCode::truncated ||
                cut.error().code == base::ErrorCode::corrupt_data)
            << cut.error().to_string();
}

TEST(NrrdLoader, FourDimensionalFileOpensItsFirstVolume) {
    fixtures::TempDir dir;
    std::vector<std::uint8_t> values(2 * 2 * 2 * 3);
    for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = static_cast<std::uint8_t>(i + 1);
    }
    auto volume = load_attached(dir,
                                "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 2 2 2 3\n"
                                "space: right-anterior-superior\n"
                                "space directions: (2,0,0) (0,2,0) (0,0,3) none\n"
                                "encoding: raw\n",
                                as_bytes(values));
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(2, 2, 2));
    EXPECT_EQ(volume->spacing, glm::dvec3(2.0, 2.0, 3.0));
    EXPECT_EQ(volume->data, as_bytes(std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}));

    // Values per voxel first (DWI), said by a first axis without a direction: each voxel's first
    // value, on the grid the other three axes place.
    auto interleaved = load_attached(dir,
                                     "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 2 2 2\n"
                                     "space directions: none (2,0,0) (0,2,0) (0,0,3)\n"
                                     "encoding: raw\n",
                                     as_bytes(values), "dwi.nrrd");
    ASSERT_TRUE(interleaved.ok()) << interleaved.error().to_string();
    EXPECT_EQ(interleaved->dims, glm::uvec3(2, 2, 2));
    EXPECT_EQ(interleaved->spacing, glm::dvec3(2.0, 2.0, 3.0));
    EXPECT_EQ(interleaved->data, as_bytes(std::vector<std::uint8_t>{1, 4, 7, 10, 13, 16, 19, 22}));
}

// The kinds of a NRRD's axes: values per voxel (list, vector, ...; or a nan spacing) read as the
// first value of each voxel, in every encoding; a colour axis refused as colour; what leaves fewer
// than three axes of space refused as 2-D; a 4th axis of volumes after the values.
TEST(NrrdLoader, KindsSayWhichAxesAreSpace) {
    fixtures::TempDir dir;
    std::vector<std::int16_t> values(2 * 2 * 2 * 2);
    for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = static_cast<std::int16_t>(i % 2 == 0 ? 100 + i : -7);
    }
    std::vector<std::uint8_t> bytes(values.size() * 2);
    std::memcpy(bytes.data(), values.data(), bytes.size());
    const std::vector<std::byte> firsts = as_bytes(std::vector<std::uint8_t>{
            100, 0, 102, 0, 104, 0, 106, 0, 108, 0, 110, 0, 112, 0, 114, 0});
    auto listed = load_attached(dir,
                                "NRRD0004\ntype: short\ndimension: 4\nsizes: 2 2 2 2\n"
                                "kinds: list domain domain domain\nspacings: nan 1 1 2.5\n"
                                "endian: little\nencoding: raw\n",
                                as_bytes(bytes), "list.nrrd");
    ASSERT_TRUE(listed.ok()) << listed.error().to_string();
    EXPECT_EQ(listed->dims, glm::uvec3(2, 2, 2));
    EXPECT_EQ(listed->spacing, glm::dvec3(1.0, 1.0, 2.5));
    EXPECT_EQ(listed->data, firsts);
    EXPECT_EQ(listed->range.min, 100.0);

    // A nan spacing alone says so too; ASCII reads every value and keeps the firsts.
    std::string text;
    for (const std::int16_t v : values) {
        text += std::to_string(v) + " ";
    }
    auto spaced = load_attached(dir,
                                "NRRD0004\ntype: short\ndimension: 4\nsizes: 2 2 2 2\n"
                                "spacings: nan 1 1 2.5\nencoding: ascii\n",
                                text_bytes(text), "nan.nrrd");
    ASSERT_TRUE(spaced.ok()) << spaced.error().to_string();
    EXPECT_EQ(spaced->data, firsts);

    auto colour = load_attached(dir,
                                "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 2 2 2\n"
                                "kinds: RGB-color domain domain domain\nencoding: raw\n",
                                std::vector<std::byte>(24), "rgb.nrrd");
    ASSERT_FALSE(colour.ok());
    EXPECT_EQ(colour.error().code, base::ErrorCode::unsupported_type);
    EXPECT_TRUE(contains(colour.error().message, "colour")) << colour.error().message;

    auto flat = load_attached(dir,
                              "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 4 4\n"
                              "kinds: vector domain domain\nencoding: raw\n",
                              std::vector<std::byte>(32), "flat.nrrd");
    ASSERT_FALSE(flat.ok());
    EXPECT_EQ(flat.error().code, base::ErrorCode::unsupported_dimension);
    EXPECT_TRUE(contains(flat.error().message, "2-D")) << flat.error().message;

    auto trailing = load_attached(dir,
                                  "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 2\n"
                                  "kinds: domain domain vector\nencoding: raw\n",
                                  std::vector<std::byte>(32), "trailing.nrrd");
    ASSERT_FALSE(trailing.ok());
    EXPECT_EQ(trailing.error().code, base::ErrorCode::unsupported_dimension);

    auto middle = load_attached(dir,
                                "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 2 2 2 2\n"
                                "kinds: domain list domain domain\nencoding: raw\n",
                                std::vector<std::byte>(16), "middle.nrrd");
    ASSERT_FALSE(middle.ok());
    EXPECT_EQ(middle.error().code, base::ErrorCode::unsupported_dimension);

    auto miscounted = load_attached(dir,
                                    "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\n"
                                    "kinds: domain domain\nencoding: raw\n",
                                    cube_uint8(), "kinds.nrrd");
    ASSERT_FALSE(miscounted.ok());
    EXPECT_EQ(miscounted.error().code, base::ErrorCode::bad_header);
}

// teem's `unu` (teem-apps), the NRRD format's reference reader, as the reference: each file is
// rewritten by `unu save` as raw little-endian data, and every voxel Penumbra reads must equal
// what unu read (for values per voxel, the first value of each voxel).
struct UnuReading {
    std::vector<std::size_t> sizes;
    std::vector<double> values;
};

base::Result<UnuReading> read_with_unu(const std::filesystem::path& input,
                                       const std::filesystem::path& output) {
    const std::string command = "teem-unu save -i '" + input.string() +
                                "' -f nrrd -e raw -en little -o '" + output.string() + "' 2>&1";
    if (std::system(command.c_str()) != 0) {
        return base::make_error(base::ErrorCode::read_failed, "unu could not read it",
                                input.filename().string());
    }
    std::ifstream file(output, std::ios::binary);
    std::string line;
    std::string type;
    UnuReading reading;
    while (std::getline(file, line) && !line.empty()) {
        if (line.starts_with("type: ")) {
            type = line.substr(6);
        } else if (line.starts_with("sizes: ")) {
            std::istringstream sizes(line.substr(7));
            for (std::size_t size = 0; sizes >> size;) {
                reading.sizes.push_back(size);
            }
        }
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(file)),
                                  std::istreambuf_iterator<char>());
    const auto take = [&]<class T>(T /*type*/) {
        for (std::size_t at = 0; at + sizeof(T) <= bytes.size(); at += sizeof(T)) {
            T value;
            std::memcpy(&value, bytes.data() + at, sizeof(T));
            reading.values.push_back(static_cast<double>(value));
        }
    };
    if (type == "unsigned char") {
        take(std::uint8_t{});
    } else if (type == "signed char") {
        take(std::int8_t{});
    } else if (type == "short") {
        take(std::int16_t{});
    } else if (type == "unsigned short") {
        take(std::uint16_t{});
    } else if (type == "int") {
        take(std::int32_t{});
    } else if (type == "unsigned int") {
        take(std::uint32_t{});
    } else if (type == "float") {
        take(float{});
    } else if (type == "double") {
        take(double{});
    } else {
        return base::make_error(base::ErrorCode::unsupported_type, "unu wrote type " + type,
                                output.filename().string());
    }
    return reading;
}

TEST(NrrdLoader, EveryEncodingTypeAndKindReadsAsTeemsUnuReadsIt) {
    ASSERT_EQ(std::system("teem-unu about > /dev/null 2>&1"), 0)
            << "teem's unu is needed as the reference: install teem-apps "
               "(scripts/install-deps.sh does)";
    fixtures::TempDir dir;
    // 5x4x3 voxels of distinct values, some negative, as each type can hold them.
    constexpr std::size_t voxels = 5 * 4 * 3;
    const auto value_at = [](std::size_t i) { return static_cast<double>(i * 7 % 61) - 20.0; };
    const auto samples = [&]<class T>(T /*type*/, std::size_t per_voxel, bool big_endian) {
        std::vector<std::byte> bytes;
        for (std::size_t i = 0; i < voxels * per_voxel; ++i) {
            const T value = static_cast<T>(std::is_signed_v<T> ? value_at(i) : value_at(i) + 20.0);
            std::array<std::byte, sizeof(T)> word;
            std::memcpy(word.data(), &value, sizeof(T));
            if (big_endian) {
                std::reverse(word.begin(), word.end());
            }
            bytes.insert(bytes.end(), word.begin(), word.end());
        }
        return bytes;
    };
    const auto text = [&](std::size_t per_voxel, bool hex_digits) {
        std::string digits;
        for (std::size_t i = 0; i < voxels * per_voxel; ++i) {
            char word[16];
            if (hex_digits) {
                std::snprintf(word, sizeof word, "%02X%c",
                              static_cast<unsigned>(value_at(i) + 20.0), i % 9 == 8 ? '\n' : ' ');
            } else {
                std::snprintf(word, sizeof word, "%g\n", value_at(i) + 0.25);
            }
            digits += word;
        }
        return text_bytes(digits);
    };

    struct Case {
        std::string name;
        std::string fields;  // after the magic line
        std::vector<std::byte> data;
    };

    const std::string grid = "dimension: 3\nsizes: 5 4 3\n";
    const std::vector<Case> cases{
            {"uint8_raw", "type: uint8\n" + grid + "encoding: raw\n",
             samples(std::uint8_t{}, 1, false)},
            {"int16_big_gzip", "type: int16\n" + grid + "endian: big\nencoding: gzip\n",
             fixtures::gzip_bytes(samples(std::int16_t{}, 1, true))},
            {"uint16_bzip2", "type: uint16\n" + grid + "endian: little\nencoding: bzip2\n",
             bzip2(samples(std::uint16_t{}, 1, false))},
            {"int32_big", "type: int32\n" + grid + "endian: big\nencoding: raw\n",
             samples(std::int32_t{}, 1, true)},
            {"float_raw", "type: float\n" + grid + "endian: little\nencoding: raw\n",
             samples(float{}, 1, false)},
            {"double_big", "type: double\n" + grid + "endian: big\nencoding: raw\n",
             samples(double{}, 1, true)},
            {"float_ascii", "type: float\n" + grid + "encoding: ascii\n", text(1, false)},
            {"uint8_hex", "type: uint8\n" + grid + "encoding: hex\n", text(1, true)},
            {"int16_list_kinds",
             "type: int16\ndimension: 4\nsizes: 2 5 4 3\nkinds: list domain domain domain\n"
             "endian: little\nencoding: raw\n",
             samples(std::int16_t{}, 2, false)},
            {"uint8_vector_gzip",
             "type: uint8\ndimension: 4\nsizes: 3 5 4 3\nkinds: vector space space space\n"
             "space: right-anterior-superior\nspace directions: none (1,0,0) (0,1,0) (0,0,2)\n"
             "encoding: gzip\n",
             fixtures::gzip_bytes(samples(std::uint8_t{}, 3, false))},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::filesystem::path input = dir / (c.name + ".nrrd");
        fixtures::write_bytes(input, concat(text_bytes("NRRD0004\n" + c.fields + "\n"), c.data));
        auto ours = load_nrrd(input);
        ASSERT_TRUE(ours.ok()) << ours.error().to_string();
        auto unu = read_with_unu(input, dir / (c.name + "_unu.nrrd"));
        ASSERT_TRUE(unu.ok()) << unu.error().to_string();
        const std::size_t per_voxel = unu->sizes.size() == 4 ? unu->sizes[0] : 1;
        ASSERT_EQ(unu->values.size(), voxels * per_voxel);
        ASSERT_EQ(ours->dims, glm::uvec3(5, 4, 3));
        std::size_t i = 0;
        for (std::uint32_t z = 0; z < 3; ++z) {
            for (std::uint32_t y = 0; y < 4; ++y) {
                for (std::uint32_t x = 0; x < 5; ++x, ++i) {
                    const double want = unu->values[i * per_voxel];
                    ASSERT_NEAR(ours->value(x, y, z), want, 1e-6 * std::max(1.0, std::abs(want)))
                            << "voxel " << x << "," << y << "," << z;
                }
            }
        }
    }
}

TEST(NrrdLoader, PenumbraUnitsKeyMarksHounsfieldUnits) {
    fixtures::TempDir dir;
    auto marked =
            load_attached(dir, std::string(cube_header) + "penumbra_units:=HU\n", cube_uint8());
    ASSERT_TRUE(marked.ok()) << marked.error().to_string();
    EXPECT_TRUE(marked->hounsfield);
    auto other = load_attached(dir, std::string(cube_header) + "penumbra_units:=none\n",
                               cube_uint8(), "other.nrrd");
    ASSERT_TRUE(other.ok()) << other.error().to_string();
    EXPECT_FALSE(other->hounsfield);
}

// InVesalius' head CT, converted from Debian's invesalius-examples by scripts/cranium-ct.py in the
// build (tests/CMakeLists.txt): the voxels of matrix.dat, the spacing of main.plist, marked HU.
TEST(NrrdLoader, ReadsTheConvertedInvesaliusHeadCt) {
    auto ct = load_nrrd(PENUMBRA_CRANIUM_CT);
    ASSERT_TRUE(ct.ok()) << ct.error().to_string()
                         << " (the build converts it from Debian's invesalius-examples)";
    EXPECT_EQ(ct->dims, glm::uvec3(256, 256, 108));
    EXPECT_NEAR(ct->spacing.x, 0.957031, 1e-6);
    EXPECT_NEAR(ct->spacing.y, 0.957031, 1e-6);
    EXPECT_DOUBLE_EQ(ct->spacing.z, 1.5);
    EXPECT_TRUE(ct->hounsfield);
    EXPECT_EQ(ct->range.min, -1024.0);
    EXPECT_GT(ct->range.max, 2000.0);
    // Air around the head, and bone (>= 300 HU) in it.
    EXPECT_LT(ct->value(0, 0, 54), -900.0);
    std::size_t bone = 0;
    for (std::uint32_t y = 0; y < ct->dims.y; ++y) {
        for (std::uint32_t x = 0; x < ct->dims.x; ++x) {
            bone += ct->value(x, y, 54) >= 300.0 ? 1 : 0;
        }
    }
    EXPECT_GT(bone, 1000u);
}

}  // namespace
}  // namespace penumbra::volume
