#include "fixture_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <gtest/gtest.h>
#include <nifti2_io.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>

namespace penumbra::volume {
namespace {

using fixtures::as_bytes;

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

struct NiftiSpec {
    glm::ivec3 dims{2, 2, 2};
    std::int64_t volumes = 1;  // > 1 writes a 4-D file
    int datatype = DT_UINT8;
    glm::dvec3 spacing{1.0};
    double slope = 0.0;
    double inter = 0.0;
    int nifti_type = NIFTI_FTYPE_NIFTI1_1;
    // The qform as quaternion (b, c, d), qfac and offset; written when qform_code > 0.
    int qform_code = 0;
    glm::dvec3 quatern{0.0};
    double qfac = 1.0;
    glm::dvec3 qoffset{0.0};
    // The sform's first three rows (each: three columns, then the offset); written when
    // sform_code > 0.
    int sform_code = 0;
    std::array<std::array<double, 4>, 3> sform{};
};

// Writes a NIfTI file with the nifti library itself; the extension of `path` (.nii or .nii.gz)
// chooses compression.
void write_nifti(const std::filesystem::path& path, const NiftiSpec& spec,
                 std::span<const std::byte> data) {
    std::int64_t dims[8] = {
            spec.volumes > 1 ? 4 : 3, spec.dims.x, spec.dims.y, spec.dims.z, spec.volumes, 1, 1, 1};
    nifti_image* image = nifti_make_new_nim(dims, spec.datatype, 1);
    ASSERT_NE(image, nullptr);
    const std::size_t bytes =
            static_cast<std::size_t>(image->nvox) * static_cast<std::size_t>(image->nbyper);
    ASSERT_EQ(bytes, data.size()) << "fixture data does not match the NIfTI dims";
    std::memcpy(image->data, data.data(), bytes);
    image->dx = image->pixdim[1] = spec.spacing.x;
    image->dy = image->pixdim[2] = spec.spacing.y;
    image->dz = image->pixdim[3] = spec.spacing.z;
    image->scl_slope = spec.slope;
    image->scl_inter = spec.inter;
    image->nifti_type = spec.nifti_type;
    image->qform_code = spec.qform_code;
    image->quatern_b = spec.quatern.x;
    image->quatern_c = spec.quatern.y;
    image->quatern_d = spec.quatern.z;
    image->qfac = spec.qfac;
    image->qoffset_x = spec.qoffset.x;
    image->qoffset_y = spec.qoffset.y;
    image->qoffset_z = spec.qoffset.z;
    image->sform_code = spec.sform_code;
    for (int row = 0; row < 3; ++row) {
        for (int column = 0; column < 4; ++column) {
            image->sto_xyz.m[row][column] =
                    spec.sform[static_cast<std::size_t>(row)][static_cast<std::size_t>(column)];
        }
    }
    ASSERT_EQ(nifti_set_filenames(image, path.c_str(), 0, 1), 0);
    nifti_image_write(image);
    nifti_image_free(image);
    ASSERT_TRUE(std::filesystem::exists(path)) << "the nifti library did not write " << path;
}

std::vector<std::byte> sequence_uint8(std::size_t count) {
    std::vector<std::uint8_t> values(count);
    for (std::size_t i = 0; i < count; ++i) {
        values[i] = static_cast<std::uint8_t>(3 * i + 1);
    }
    return as_bytes(values);
}

TEST(NiftiLoader, Uint8RoundTrip) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.dims = {4, 3, 2};
    spec.spacing = {0.5, 2.0, 3.0};
    const auto data = sequence_uint8(24);
    write_nifti(dir / "head.nii", spec, data);

    auto volume = load_nifti(dir / "head.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "head");
    EXPECT_EQ(volume->dims, glm::uvec3(4, 3, 2));
    EXPECT_EQ(volume->type, VoxelType::uint8);
    EXPECT_EQ(volume->spacing, glm::dvec3(0.5, 2.0, 3.0));
    EXPECT_EQ(volume->data, data);
    EXPECT_EQ(volume->value(3, 2, 1), 70.0);
    EXPECT_EQ(volume->range.min, 1.0);
    EXPECT_EQ(volume->range.max, 70.0);
}

TEST(NiftiLoader, GzipInt16IsKept) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.datatype = DT_INT16;
    const std::vector<std::int16_t> values{-1000, -1, 0, 1, 2, 3, 4, 2000};
    write_nifti(dir / "ct.nii.gz", spec, as_bytes(values));

    auto volume = load_volume(dir / "ct.nii.gz");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "ct");
    EXPECT_EQ(volume->type, VoxelType::int16);
    EXPECT_FALSE(volume->hounsfield);
    EXPECT_EQ(volume->range.min, -1000.0);
    EXPECT_EQ(volume->range.max, 2000.0);
    EXPECT_EQ(volume->value(1, 1, 1), 2000.0);
}

TEST(NiftiLoader, Uint16AndFloat32AreKept) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.datatype = DT_UINT16;
    const std::vector<std::uint16_t> shorts{0, 1, 2, 3, 4, 5, 6, 65535};
    write_nifti(dir / "u16.nii", spec, as_bytes(shorts));
    auto u16 = load_nifti(dir / "u16.nii");
    ASSERT_TRUE(u16.ok()) << u16.error().to_string();
    EXPECT_EQ(u16->type, VoxelType::uint16);
    EXPECT_EQ(u16->data, as_bytes(shorts));

    spec.datatype = DT_FLOAT32;
    const std::vector<float> floats{0.5f, -1.0f, std::nanf(""), 3.0f, 4.0f, 5.0f, 6.0f, 7.0f};
    write_nifti(dir / "f32.nii.gz", spec, as_bytes(floats));
    auto f32 = load_nifti(dir / "f32.nii.gz");
    ASSERT_TRUE(f32.ok()) << f32.error().to_string();
    EXPECT_EQ(f32->type, VoxelType::float32);
    EXPECT_EQ(f32->value(1, 0, 0), -1.0);
    EXPECT_EQ(f32->value(1, 1, 1), 7.0);
    // A NaN voxel becomes the finite minimum and is counted, as in every format.
    EXPECT_EQ(f32->value(0, 1, 0), -1.0);
    EXPECT_EQ(f32->nonfinite_voxels, 1u);
}

TEST(NiftiLoader, Float64BecomesFloat32) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.datatype = DT_FLOAT64;
    const std::vector<double> values{0.25, 1, 2, 3, 4, 5, 6, -7.5};
    write_nifti(dir / "d.nii", spec, as_bytes(values));
    auto volume = load_nifti(dir / "d.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::float32);
    EXPECT_EQ(volume->value(0, 0, 0), 0.25);
    EXPECT_EQ(volume->value(1, 1, 1), -7.5);
}

TEST(NiftiLoader, ScaleSlopeAndInterceptAreAppliedAsFloat32) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.slope = 0.5;
    spec.inter = -10.0;
    write_nifti(dir / "scaled.nii", spec, sequence_uint8(8));
    auto volume = load_nifti(dir / "scaled.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::float32);
    EXPECT_EQ(volume->value(0, 0, 0), 1 * 0.5 - 10.0);
    EXPECT_EQ(volume->value(1, 1, 1), 22 * 0.5 - 10.0);
    EXPECT_EQ(volume->range.min, -9.5);
}

TEST(NiftiLoader, IdentityOrZeroSlopeKeepsTheType) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.slope = 1.0;
    write_nifti(dir / "identity.nii", spec, sequence_uint8(8));
    auto identity = load_nifti(dir / "identity.nii");
    ASSERT_TRUE(identity.ok()) << identity.error().to_string();
    EXPECT_EQ(identity->type, VoxelType::uint8);

    spec.slope = 0.0;
    spec.inter = 5.0;  // ignored: slope 0 means "no scaling" in NIfTI
    write_nifti(dir / "unscaled.nii", spec, sequence_uint8(8));
    auto unscaled = load_nifti(dir / "unscaled.nii");
    ASSERT_TRUE(unscaled.ok()) << unscaled.error().to_string();
    EXPECT_EQ(unscaled->type, VoxelType::uint8);
    EXPECT_EQ(unscaled->value(0, 0, 0), 1.0);
}

TEST(NiftiLoader, Nifti2FileRoundTrip) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.nifti_type = NIFTI_FTYPE_NIFTI2_1;
    spec.dims = {3, 2, 2};
    spec.spacing = {0.75, 0.75, 1.5};
    const auto data = sequence_uint8(12);
    write_nifti(dir / "two.nii.gz", spec, data);
    auto volume = load_nifti(dir / "two.nii.gz");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(3, 2, 2));
    EXPECT_EQ(volume->spacing, glm::dvec3(0.75, 0.75, 1.5));
    EXPECT_EQ(volume->data, data);
}

TEST(NiftiLoader, FourDimensionalFileLoadsItsFirstVolume) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.volumes = 3;
    const auto data = sequence_uint8(24);
    write_nifti(dir / "series.nii", spec, data);
    auto volume = load_nifti(dir / "series.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(2, 2, 2));
    EXPECT_EQ(volume->data, std::vector<std::byte>(data.begin(), data.begin() + 8));
}

// SPM's default output: a .hdr header with its voxels in the .img beside it.
TEST(NiftiLoader, HdrImgPairOpensThroughItsHeader) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.nifti_type = NIFTI_FTYPE_NIFTI1_2;
    spec.spacing = {2.0, 3.0, 4.0};
    const auto data = sequence_uint8(8);
    write_nifti(dir / "spm.hdr", spec, data);
    ASSERT_TRUE(std::filesystem::exists(dir / "spm.img"));
    auto volume = load_volume(dir / "spm.hdr");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "spm");
    EXPECT_EQ(volume->dims, glm::uvec3(2, 2, 2));
    EXPECT_EQ(volume->spacing, glm::dvec3(2.0, 3.0, 4.0));
    EXPECT_EQ(volume->data, data);
}

TEST(NiftiLoader, ZeroSpacingBecomesOneAndNegativeSpacingItsSize) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.spacing = {0.0, -2.0, 1.25};
    write_nifti(dir / "spacing.nii", spec, sequence_uint8(8));
    auto volume = load_nifti(dir / "spacing.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->spacing, glm::dvec3(1.0, 2.0, 1.25));
}

TEST(NiftiLoader, UnsupportedDatatypeIsRejected) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.datatype = DT_RGB24;
    write_nifti(dir / "rgb.nii", spec, std::vector<std::byte>(8 * 3));
    auto volume = load_nifti(dir / "rgb.nii");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::unsupported_type);
    EXPECT_TRUE(contains(volume.error().message, "RGB")) << volume.error().message;
}

TEST(NiftiLoader, GarbageFileIsRejected) {
    fixtures::TempDir dir;
    fixtures::write_text(dir / "garbage.nii", std::string(600, 'x'));
    auto volume = load_nifti(dir / "garbage.nii");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::bad_header);
    EXPECT_TRUE(contains(volume.error().where, "garbage.nii"));

    fixtures::write_text(dir / "empty.nii.gz", "");
    auto empty = load_nifti(dir / "empty.nii.gz");
    ASSERT_FALSE(empty.ok());
}

TEST(NiftiLoader, TruncatedFileIsRejected) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.dims = {16, 16, 16};
    write_nifti(dir / "cut.nii", spec, sequence_uint8(4096));
    std::filesystem::resize_file(dir / "cut.nii", 352 + 1000);
    auto volume = load_nifti(dir / "cut.nii");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated);
    EXPECT_TRUE(contains(volume.error().message, "4096 bytes")) << volume.error().message;
    EXPECT_TRUE(contains(volume.error().message, "1352 bytes")) << volume.error().message;

    // A cut .nii.gz is only found out by the library while it inflates.
    write_nifti(dir / "cut.nii.gz", spec, sequence_uint8(4096));
    const auto size = std::filesystem::file_size(dir / "cut.nii.gz");
    std::filesystem::resize_file(dir / "cut.nii.gz", size / 2);
    auto compressed = load_nifti(dir / "cut.nii.gz");
    ASSERT_FALSE(compressed.ok());
}

TEST(NiftiLoader, AbsurdDimensionsAreRejectedBeforeReadingData) {
    fixtures::TempDir dir;
    write_nifti(dir / "huge.nii", NiftiSpec{}, sequence_uint8(8));
    // NIfTI-1 keeps dim[8] as little-endian int16 at byte 40: make it 30000^3.
    std::fstream file(dir / "huge.nii", std::ios::in | std::ios::out | std::ios::binary);
    const std::int16_t huge = 30000;
    for (int axis = 1; axis <= 3; ++axis) {
        file.seekp(40 + 2 * axis);
        file.write(reinterpret_cast<const char*>(&huge), sizeof huge);
    }
    file.close();
    auto volume = load_nifti(dir / "huge.nii");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::too_large) << volume.error().to_string();
}

TEST(NiftiLoader, MissingFileAndWrongNameAreRejected) {
    fixtures::TempDir dir;
    auto missing = load_nifti(dir / "absent.nii.gz");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, base::ErrorCode::not_found);

    fixtures::write_text(dir / "head.img", "");
    auto wrong = load_nifti(dir / "head.img");
    ASSERT_FALSE(wrong.ok());
    EXPECT_EQ(wrong.error().code, base::ErrorCode::bad_file_name);
}

// The real heads that Debian's mricron-data installs (DESIGN.md §3). They are part of the
// project's install step, so their absence is a broken setup, not a reason to skip.
const std::filesystem::path templates = "/usr/share/mricron/templates";

TEST(NiftiRealData, Colin27Head) {
    const auto path = templates / "ch2.nii.gz";
    ASSERT_TRUE(std::filesystem::exists(path))
            << path << " is missing: install the Debian package mricron-data "
            << "(apt-get install mricron-data), as the project's install step does";
    auto volume = load_volume(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "ch2");
    EXPECT_EQ(volume->dims, glm::uvec3(181, 217, 181));
    EXPECT_EQ(volume->type, VoxelType::uint8);
    EXPECT_EQ(volume->spacing, glm::dvec3(1.0));
    EXPECT_GE(volume->range.min, 0.0);
    EXPECT_LE(volume->range.max, 255.0);
    EXPECT_GE(volume->range.max, 200.0);
    EXPECT_EQ(volume->nonfinite_voxels, 0u);
}

TEST(NiftiRealData, Inia19Brain) {
    const auto path = templates / "inia19-t1-brain.nii.gz";
    ASSERT_TRUE(std::filesystem::exists(path))
            << path << " is missing: install the Debian package mricron-data "
            << "(apt-get install mricron-data), as the project's install step does";
    auto volume = load_volume(path);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(168, 206, 128));
    EXPECT_EQ(volume->type, VoxelType::float32);
    EXPECT_EQ(volume->spacing, glm::dvec3(0.5));
    EXPECT_LT(volume->range.min, volume->range.max);
}

void expect_axes(const Volume& volume, glm::dvec3 i, glm::dvec3 j, glm::dvec3 k) {
    for (int row = 0; row < 3; ++row) {
        EXPECT_NEAR(volume.axes[0][row], i[row], 1e-6) << "axis i, component " << row;
        EXPECT_NEAR(volume.axes[1][row], j[row], 1e-6) << "axis j, component " << row;
        EXPECT_NEAR(volume.axes[2][row], k[row], 1e-6) << "axis k, component " << row;
    }
}

TEST(NiftiLoader, NoTransformCodeGivesIdentityAxesScaledByPixdim) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.spacing = {0.5, 2.0, 3.0};
    write_nifti(dir / "plain.nii", spec, sequence_uint8(8));
    auto volume = load_nifti(dir / "plain.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->axes, glm::dmat3(1.0));
    EXPECT_EQ(volume->origin, glm::dvec3(0.0));
    EXPECT_EQ(volume->spacing, glm::dvec3(0.5, 2.0, 3.0));
}

// FSL's atlases store x reversed: a qform of 180 degrees about y with qfac -1 flips only x.
TEST(NiftiLoader, QformWithQfacGivesLasAxes) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.spacing = {2.0, 3.0, 4.0};
    spec.qform_code = NIFTI_XFORM_SCANNER_ANAT;
    spec.quatern = {0.0, 1.0, 0.0};
    spec.qfac = -1.0;
    spec.qoffset = {90.0, -126.0, -72.0};
    write_nifti(dir / "las.nii", spec, sequence_uint8(8));
    auto volume = load_nifti(dir / "las.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_axes(*volume, {-1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    EXPECT_EQ(orientation_code(volume->axes), "LAS");
    EXPECT_NEAR(volume->spacing.x, 2.0, 1e-6);
    EXPECT_NEAR(volume->spacing.y, 3.0, 1e-6);
    EXPECT_NEAR(volume->spacing.z, 4.0, 1e-6);
    EXPECT_NEAR(volume->origin.x, 90.0, 1e-4);
    EXPECT_NEAR(volume->origin.y, -126.0, 1e-4);
    EXPECT_NEAR(volume->origin.z, -72.0, 1e-4);
}

TEST(NiftiLoader, SformWinsOverQformAndMayBeOblique) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.qform_code = NIFTI_XFORM_SCANNER_ANAT;
    spec.quatern = {0.0, 1.0, 0.0};
    spec.qfac = -1.0;
    spec.sform_code = NIFTI_XFORM_MNI_152;
    // Coronal slices, then 30 degrees about z: i = (c, s, 0), j = (0, 0, 1) * 2, k = (s, -c, 0).
    const double c = std::sqrt(3.0) / 2.0;
    spec.sform = {{{c, 0.0, 0.5, -5.0}, {0.5, 0.0, -c, 6.0}, {0.0, 2.0, 0.0, 7.0}}};
    write_nifti(dir / "oblique.nii", spec, sequence_uint8(8));
    auto volume = load_nifti(dir / "oblique.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_axes(*volume, {c, 0.5, 0.0}, {0.0, 0.0, 1.0}, {0.5, -c, 0.0});
    EXPECT_EQ(orientation_code(volume->axes), "RSP");
    EXPECT_NEAR(volume->spacing.y, 2.0, 1e-6);
    EXPECT_NEAR(volume->origin.x, -5.0, 1e-5);
    EXPECT_NEAR(volume->origin.y, 6.0, 1e-5);
    EXPECT_NEAR(volume->origin.z, 7.0, 1e-5);
}

TEST(NiftiLoader, ShearedSformWithoutQformIsResampled) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.sform_code = NIFTI_XFORM_ALIGNED_ANAT;
    spec.sform = {{{1.0, 0.0, 0.0, 0.0}, {0.0, 1.0, 0.3, 0.0}, {0.0, 0.0, 1.0, 0.0}}};
    write_nifti(dir / "sheared.nii", spec, sequence_uint8(8));
    auto volume = load_nifti(dir / "sheared.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(orientation_code(volume->axes), "RAS");
    ASSERT_FALSE(volume->notes.empty());
    EXPECT_TRUE(contains(volume->notes.back(), "resampled")) << volume->notes.back();
}

TEST(NiftiLoader, ShearedSformFallsBackToTheQform) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.qform_code = NIFTI_XFORM_SCANNER_ANAT;
    spec.sform_code = NIFTI_XFORM_ALIGNED_ANAT;
    spec.sform = {{{1.0, 0.0, 0.0, 0.0}, {0.0, 1.0, 0.3, 0.0}, {0.0, 0.0, 1.0, 0.0}}};
    write_nifti(dir / "sheared.nii", spec, sequence_uint8(8));
    auto volume = load_nifti(dir / "sheared.nii");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(orientation_code(volume->axes), "RAS");
    ASSERT_EQ(volume->notes.size(), 1u);
    EXPECT_TRUE(contains(volume->notes[0], "the qform places the voxels")) << volume->notes[0];
}

TEST(NiftiLoader, IntegerScaleOnInt16IsKeptAsRescaleAndIntentHuMarksHounsfield) {
    fixtures::TempDir dir;
    NiftiSpec spec;
    spec.datatype = DT_INT16;
    spec.slope = 1.0;
    spec.inter = -1024.0;
    const std::vector<std::int16_t> values{0, 24, 1024, 4000, 5, 6, 7, 8};
    write_nifti(dir / "ct.nii", spec, as_bytes(values));
    auto plain = load_nifti(dir / "ct.nii");
    ASSERT_TRUE(plain.ok()) << plain.error().to_string();
    EXPECT_EQ(plain->type, VoxelType::int16);
    EXPECT_EQ(plain->data, as_bytes(values));
    EXPECT_EQ(plain->value(0, 0, 0), -1024.0);
    EXPECT_EQ(plain->value(1, 1, 0), 4000.0 - 1024.0);
    EXPECT_EQ(plain->range.min, -1024.0);
    EXPECT_FALSE(plain->hounsfield);

    nifti_image* image = nifti_image_read((dir / "ct.nii").c_str(), 1);
    ASSERT_NE(image, nullptr);
    std::strcpy(image->intent_name, "HU");
    ASSERT_EQ(nifti_set_filenames(image, (dir / "marked.nii").c_str(), 0, 1), 0);
    nifti_image_write(image);
    nifti_image_free(image);
    auto marked = load_nifti(dir / "marked.nii");
    ASSERT_TRUE(marked.ok()) << marked.error().to_string();
    EXPECT_TRUE(marked->hounsfield);
}
}  // namespace
}  // namespace penumbra::volume
