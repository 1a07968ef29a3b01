#include "dicom_writer.hpp"
#include "fixture_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <random>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcdatset.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcpixel.h>
#include <dcmtk/dcmdata/dcpixseq.h>
#include <dcmtk/dcmdata/dcpxitem.h>

namespace penumbra::volume {
namespace {

using fixtures::SeriesSpec;

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// A box of the ch2 head: not square, so a swap of rows and columns shows.
constexpr glm::uvec3 box_first{60, 80, 70};
constexpr glm::uvec3 box_dims{64, 48, 24};

SeriesSpec ch2_spec() {
    SeriesSpec spec;
    spec.dims = box_dims;
    spec.spacing = {0.75, 0.5, 1.25};  // distinct, so a swap of x and y spacing shows
    spec.origin = {-40.0, 12.5, -7.0};
    return spec;
}

// Every voxel of `volume` equals `expected(word)` for the words written, x fastest.
template <class Expected>
void expect_voxels(const Volume& volume, const std::vector<std::uint16_t>& words,
                   Expected expected) {
    ASSERT_EQ(volume.voxel_count(), words.size());
    std::size_t mismatches = 0;
    std::size_t i = 0;
    for (std::uint32_t z = 0; z < volume.dims.z; ++z) {
        for (std::uint32_t y = 0; y < volume.dims.y; ++y) {
            for (std::uint32_t x = 0; x < volume.dims.x; ++x, ++i) {
                if (volume.value(x, y, z) != expected(words[i]) && ++mismatches <= 3) {
                    ADD_FAILURE() << "voxel " << x << "," << y << "," << z << " is "
                                  << volume.value(x, y, z) << ", expected " << expected(words[i]);
                }
            }
        }
    }
    EXPECT_EQ(mismatches, 0u);
}

void expect_ch2_voxels(const Volume& volume, const std::vector<std::uint16_t>& words) {
    expect_voxels(volume, words, [](std::uint16_t word) { return static_cast<double>(word); });
}

TEST(DicomLoader, SeriesFolderRoundTripsTheVoxelsDimsAndSpacing) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    fixtures::write_series(dir / "head", ch2_spec(), words);

    auto volume = load_volume(dir / "head");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "head");
    EXPECT_EQ(volume->dims, box_dims);
    EXPECT_EQ(volume->type, VoxelType::uint16);
    EXPECT_DOUBLE_EQ(volume->spacing.x, 0.75);
    EXPECT_DOUBLE_EQ(volume->spacing.y, 0.5);
    EXPECT_NEAR(volume->spacing.z, 1.25, 1e-9);
    expect_ch2_voxels(*volume, words);
    const auto [lo, hi] = std::minmax_element(words.begin(), words.end());
    EXPECT_EQ(volume->range.min, *lo);
    EXPECT_EQ(volume->range.max, *hi);
}

TEST(DicomLoader, ShuffledFileNamesAndWriteOrderAreSortedByPosition) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    SeriesSpec spec = ch2_spec();
    spec.series_uid = fixtures::make_uid();
    std::vector<std::uint32_t> order(box_dims.z);
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), std::mt19937(7));
    std::filesystem::create_directories(dir / "series");
    for (std::size_t i = 0; i < order.size(); ++i) {
        // Bare UID-like names with no extension, and instance numbers that disagree with the
        // positions: only the positions may decide.
        const std::string name = "1.3.12." + std::to_string(1000 - 37 * i);
        fixtures::write_slice(dir / "series" / name, spec, order[i], words,
                              static_cast<std::int32_t>(i + 1));
    }

    auto volume = load_volume(dir / "series");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, box_dims);
    expect_ch2_voxels(*volume, words);
}

TEST(DicomLoader, ObliqueOrientationSortsAlongTheSliceNormal) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    SeriesSpec spec = ch2_spec();
    // Rows run 30 degrees off the x axis, columns head to foot: an oblique sagittal-ish series
    // whose slices step along -x and +y, where neither z nor the file order helps.
    const double c = std::cos(M_PI / 6.0);
    const double s = std::sin(M_PI / 6.0);
    spec.orientation = {s, c, 0.0, 0.0, 0.0, -1.0};
    std::filesystem::create_directories(dir / "oblique");
    spec.series_uid = fixtures::make_uid();
    for (std::uint32_t z = 0; z < box_dims.z; ++z) {
        fixtures::write_slice(dir / "oblique" / ("im" + std::to_string(box_dims.z - z)), spec, z,
                              words, 1);
    }

    auto volume = load_volume(dir / "oblique");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_NEAR(volume->spacing.z, 1.25, 1e-6);
    expect_ch2_voxels(*volume, words);
}

TEST(DicomLoader, CtStaysInt16WithItsRescaleGivingHounsfieldUnits) {
    fixtures::TempDir dir;
    auto words = fixtures::ch2_box(box_first, box_dims);
    for (auto& word : words) {
        // Signed stored values from -1000 to about 3000, as a CT scanner writes them.
        word = static_cast<std::uint16_t>(static_cast<std::int16_t>(word * 16 - 1000));
    }
    SeriesSpec spec = ch2_spec();
    spec.is_signed = true;
    spec.slope = 1.0;
    spec.intercept = -1024.0;
    fixtures::write_series(dir / "ct", spec, words);

    auto volume = load_volume(dir / "ct");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::int16);
    EXPECT_EQ(volume->data.size(), words.size() * 2);  // half of float32
    EXPECT_EQ(volume->rescale.slope, 1.0);
    EXPECT_EQ(volume->rescale.intercept, -1024.0);
    expect_voxels(*volume, words, [](std::uint16_t word) {
        return static_cast<double>(static_cast<std::int16_t>(word)) - 1024.0;
    });
    EXPECT_LT(volume->range.min, -1024.0);
    EXPECT_FALSE(volume->hounsfield);  // the fixture's modality is MR and it has no RescaleType
}

TEST(DicomLoader, ModalityCtOrRescaleTypeHuMarksHounsfieldUnits) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 2});
    for (const char* tag : {"modality", "rescale type"}) {
        SeriesSpec spec;
        spec.dims = {16, 8, 2};
        spec.edit = [&](DcmDataset& dataset) {
            if (std::string(tag) == "modality") {
                dataset.putAndInsertString(DCM_Modality, "CT");
            } else {
                dataset.putAndInsertString(DCM_RescaleType, "HU");
            }
        };
        const auto folder = dir / (std::string(tag) == "modality" ? "ct" : "hu");
        fixtures::write_series(folder, spec, words);
        auto volume = load_volume(folder);
        ASSERT_TRUE(volume.ok()) << volume.error().to_string();
        EXPECT_TRUE(volume->hounsfield) << tag;
    }
}

TEST(DicomLoader, Monochrome1IsInverted) {
    fixtures::TempDir dir;
    const std::vector<std::uint16_t> words{0, 1, 100, 4095, 7, 8, 9, 10};
    SeriesSpec spec;
    spec.dims = {4, 2, 1};
    spec.bits_stored = 12;
    spec.edit = [](DcmDataset& dataset) {
        dataset.putAndInsertString(DCM_PhotometricInterpretation, "MONOCHROME1");
    };
    fixtures::write_series(dir / "film", spec, words);
    auto volume = load_volume(dir / "film");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_voxels(*volume, words, [](std::uint16_t word) { return 4095.0 - word; });
}

TEST(DicomLoader, FractionalSlopeIsAppliedInFloat32) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 3});
    SeriesSpec spec;
    spec.dims = {16, 8, 3};
    spec.slope = 0.5;
    spec.intercept = 10.0;
    fixtures::write_series(dir / "pet", spec, words);

    auto volume = load_volume(dir / "pet");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::float32);
    expect_voxels(*volume, words, [](std::uint16_t word) { return word * 0.5 + 10.0; });
}

TEST(DicomLoader, IntegerInterceptIsKeptAsTheRescaleOfSignedData) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 3});
    SeriesSpec spec;
    spec.dims = {16, 8, 3};
    spec.is_signed = true;
    spec.intercept = 100.0;
    fixtures::write_series(dir / "mr", spec, words);

    auto volume = load_volume(dir / "mr");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::int16);
    EXPECT_EQ(volume->rescale.intercept, 100.0);
    expect_voxels(*volume, words, [](std::uint16_t word) { return word + 100.0; });
}

TEST(DicomLoader, BitsStoredMasksHighBitsAndSignExtends) {
    fixtures::TempDir dir;
    // 12-bit two's complement values with junk (an overlay, say) in the 4 unused bits.
    const std::vector<std::int16_t> values{-2048, -1, 0, 1, 2047, -100, 7, 1000};
    std::vector<std::uint16_t> words;
    for (const std::int16_t value : values) {
        words.push_back(static_cast<std::uint16_t>((value & 0x0fff) | 0xa000));
    }
    SeriesSpec spec;
    spec.dims = {4, 2, 1};
    spec.bits_stored = 12;
    spec.is_signed = true;
    fixtures::write_series(dir / "s12", spec, words);

    auto volume = load_volume(dir / "s12");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::int16);
    for (std::uint32_t i = 0; i < values.size(); ++i) {
        EXPECT_EQ(volume->value(i % 4, i / 4, 0), values[i]) << i;
    }
}

TEST(DicomLoader, EightBitImplicitVrSeriesStaysUint8) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 4});
    SeriesSpec spec;
    spec.dims = {16, 8, 4};
    spec.bits_allocated = 8;
    spec.bits_stored = 8;
    spec.explicit_vr = false;
    fixtures::write_series(dir / "u8", spec, words);

    auto volume = load_volume(dir / "u8");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->type, VoxelType::uint8);
    expect_ch2_voxels(*volume, words);
}

TEST(DicomLoader, MultiFrameFileWithFramesOutOfOrder) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    std::vector<std::uint32_t> order(box_dims.z);
    std::iota(order.rbegin(), order.rend(), 0u);  // head to foot: the reverse of z
    std::swap(order[3], order[10]);
    fixtures::write_multiframe(dir / "enhanced.dcm", ch2_spec(), words, order);

    auto volume = load_volume(dir / "enhanced.dcm");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->name, "enhanced");
    EXPECT_EQ(volume->dims, box_dims);
    EXPECT_DOUBLE_EQ(volume->spacing.x, 0.75);
    EXPECT_DOUBLE_EQ(volume->spacing.y, 0.5);
    EXPECT_NEAR(volume->spacing.z, 1.25, 1e-9);
    expect_ch2_voxels(*volume, words);

    // The same file alone in a folder is the same volume.
    auto in_folder = load_volume(dir.path());
    ASSERT_TRUE(in_folder.ok()) << in_folder.error().to_string();
    EXPECT_EQ(in_folder->data, volume->data);
}

// JPEG 2000 pixel data (which Debian's DCMTK cannot decode) through OpenJPEG: a multi-frame file
// of the ch2 head, frames out of order, each codestream split over fragments with no offset
// table. Lossless gives back every voxel; lossy (10:1) stays close and is no copy.
TEST(DicomLoader, JpegTwoThousandMultiFrameFilesDecodeLosslessExactlyAndLossyClosely) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    std::vector<std::uint32_t> order(box_dims.z);
    std::iota(order.rbegin(), order.rend(), 0u);
    std::swap(order[2], order[7]);
    SeriesSpec spec = ch2_spec();
    spec.jpeg2000_fragments = 3;
    fixtures::write_multiframe(dir / "lossless.dcm", spec, words, order);
    auto lossless = load_volume(dir / "lossless.dcm");
    ASSERT_TRUE(lossless.ok()) << lossless.error().to_string();
    EXPECT_EQ(lossless->dims, box_dims);
    expect_ch2_voxels(*lossless, words);

    // Some writers wrap each codestream in a JP2 file.
    spec.jpeg2000_jp2 = true;
    fixtures::write_multiframe(dir / "jp2.dcm", spec, words, order);
    auto jp2 = load_volume(dir / "jp2.dcm");
    ASSERT_TRUE(jp2.ok()) << jp2.error().to_string();
    expect_ch2_voxels(*jp2, words);
    spec.jpeg2000_jp2 = false;

    spec.jpeg2000_fragments = 1;
    spec.jpeg2000_ratio = 10.0;
    fixtures::write_multiframe(dir / "lossy.dcm", spec, words, order);
    auto lossy = load_volume(dir / "lossy.dcm");
    ASSERT_TRUE(lossy.ok()) << lossy.error().to_string();
    ASSERT_EQ(lossy->dims, box_dims);
    double error = 0.0;
    std::size_t differing = 0;
    std::size_t i = 0;
    for (std::uint32_t z = 0; z < box_dims.z; ++z) {
        for (std::uint32_t y = 0; y < box_dims.y; ++y) {
            for (std::uint32_t x = 0; x < box_dims.x; ++x, ++i) {
                const double difference = lossy->value(x, y, z) - words[i];
                error += difference * difference;
                differing += difference != 0.0 ? 1 : 0;
            }
        }
    }
    const double rms = std::sqrt(error / static_cast<double>(words.size()));
    EXPECT_GT(differing, 0u) << "10:1 cannot be lossless";
    EXPECT_LT(rms, 6.0) << "of ch2's 0..255";
    std::printf("[ measured ] JPEG 2000 at 10:1: RMS error %.2f levels, %zu of %zu voxels differ\n",
                rms, differing, words.size());
}

TEST(DicomLoader, WithoutPositionsInstanceNumberOrdersAndSliceThicknessSpaces) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 5});
    SeriesSpec spec;
    spec.dims = {16, 8, 5};
    spec.spacing = {1.0, 1.0, 2.5};
    spec.positions = false;
    spec.series_uid = fixtures::make_uid();
    std::filesystem::create_directories(dir / "old");
    for (std::uint32_t z = 0; z < 5; ++z) {
        fixtures::write_slice(dir / "old" / ("z" + std::to_string(4 - z)), spec, z, words,
                              static_cast<std::int32_t>(z + 1));
    }

    auto volume = load_volume(dir / "old");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->spacing.z, 2.5);
    expect_ch2_voxels(*volume, words);
}

// A clinic's export puts a localizer beside the series: each is a series of its own, listed by
// description and number; a load names the one it wants, and without a name gets the list.
TEST(DicomLoader, FolderWithSeveralSeriesListsThemAndOpensTheOneChosen) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 6});
    SeriesSpec t1;
    t1.dims = {16, 8, 6};
    t1.series_number = "3";
    t1.series_description = "T1 axial";
    fixtures::write_series(dir / "study", t1, words);
    SeriesSpec scout;
    scout.dims = {8, 8, 2};
    scout.series_uid = fixtures::make_uid();
    scout.series_number = "1";
    scout.series_description = "Localizer";
    for (std::uint32_t z = 0; z < 2; ++z) {
        fixtures::write_slice(dir / "study" / ("scout" + std::to_string(z)), scout, z,
                              std::vector<std::uint16_t>(128, 9), static_cast<std::int32_t>(z));
    }

    auto series = list_dicom_series(dir / "study");
    ASSERT_TRUE(series.ok()) << series.error().to_string();
    ASSERT_EQ(series->size(), 2u);
    EXPECT_EQ((*series)[0].label(), "Localizer (series 1)");
    EXPECT_EQ((*series)[0].uid, scout.series_uid);
    EXPECT_EQ((*series)[0].frames, 2u);
    EXPECT_EQ((*series)[1].label(), "T1 axial (series 3)");
    EXPECT_EQ((*series)[1].images, 6u);

    auto unchosen = load_volume(dir / "study");
    ASSERT_FALSE(unchosen.ok());
    EXPECT_EQ(unchosen.error().code, base::ErrorCode::several_series);
    EXPECT_TRUE(contains(unchosen.error().message, "Localizer (series 1)"))
            << unchosen.error().message;
    EXPECT_TRUE(contains(unchosen.error().message, "T1 axial (series 3)"));
    EXPECT_TRUE(contains(unchosen.error().message, scout.series_uid));

    LoadOptions by_number;
    by_number.dicom_series = "3";
    auto t1_volume = load_volume(dir / "study", by_number);
    ASSERT_TRUE(t1_volume.ok()) << t1_volume.error().to_string();
    EXPECT_EQ(t1_volume->dims, glm::uvec3(16, 8, 6));
    EXPECT_EQ(t1_volume->name, "T1 axial (series 3)");
    expect_ch2_voxels(*t1_volume, words);

    LoadOptions by_uid;
    by_uid.dicom_series = scout.series_uid;
    auto scout_volume = load_volume(dir / "study", by_uid);
    ASSERT_TRUE(scout_volume.ok()) << scout_volume.error().to_string();
    EXPECT_EQ(scout_volume->dims, glm::uvec3(8, 8, 2));
    EXPECT_EQ(scout_volume->value(3, 3, 1), 9.0);

    LoadOptions missing;
    missing.dicom_series = "7";
    auto none = load_volume(dir / "study", missing);
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().code, base::ErrorCode::unknown_series);
    EXPECT_TRUE(contains(none.error().message, "T1 axial (series 3)")) << none.error().message;
}

// Series numbers are not unique in every export: the UID still picks one.
TEST(DicomLoader, SeriesSharingANumberArePickedByUid) {
    fixtures::TempDir dir;
    SeriesSpec a;
    a.dims = {4, 4, 2};
    a.series_uid = fixtures::make_uid();
    a.series_number = "5";
    fixtures::write_series(dir / "s" / "a", a, std::vector<std::uint16_t>(32, 1));
    SeriesSpec b = a;
    b.series_uid = fixtures::make_uid();
    b.dims = {4, 4, 3};
    fixtures::write_series(dir / "s" / "b", b, std::vector<std::uint16_t>(48, 2));
    LoadOptions five;
    five.dicom_series = "5";
    auto ambiguous = load_volume(dir / "s", five);
    ASSERT_FALSE(ambiguous.ok());
    EXPECT_EQ(ambiguous.error().code, base::ErrorCode::several_series);
    LoadOptions by_uid;
    by_uid.dicom_series = b.series_uid;
    auto volume = load_volume(dir / "s", by_uid);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(4, 4, 3));
    EXPECT_EQ(volume->value(0, 0, 0), 2.0);
}

// A CD or PACS export: a DICOMDIR at the root and the images four folders down under names
// without extensions, as dcmmkdir writes them; a study folder with one folder per series. Both
// open from their root; a folder deeper than the search reaches is not searched.
TEST(DicomLoader, AnExportRootFindsTheImagesInItsSubFolders) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 4});
    const std::filesystem::path root = dir / "cdrom";
    SeriesSpec spec;
    spec.dims = {16, 8, 4};
    spec.series_number = "2";
    spec.series_description = "T2";
    const auto files =
            fixtures::write_series(root / "DICOM" / "PAT1" / "STU1" / "SER2", spec, words);
    std::vector<std::filesystem::path> renamed;
    for (std::size_t i = 0; i < files.size(); ++i) {
        renamed.push_back(files[i].parent_path() / ("IM" + std::to_string(i)));
        std::filesystem::rename(files[i], renamed.back());
    }
    fixtures::write_dicomdir(root, renamed);
    ASSERT_TRUE(is_dicom_file(root / "DICOMDIR"));

    auto volume = load_volume(root);
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(16, 8, 4));
    expect_ch2_voxels(*volume, words);

    // Without sub-folders (how `serve` opens a folder it walks itself) the root holds no image.
    LoadOptions flat;
    flat.dicom_subfolders = false;
    auto only_root = load_volume(root, flat);
    ASSERT_FALSE(only_root.ok());
    EXPECT_EQ(only_root.error().code, base::ErrorCode::no_dicom_images);

    SeriesSpec other;
    other.dims = {4, 4, 2};
    other.series_number = "4";
    fixtures::write_series(dir / "study" / "4_t1", other, std::vector<std::uint16_t>(32, 3));
    fixtures::write_series(dir / "study" / "2_t2", spec, words);
    auto series = list_dicom_series(dir / "study");
    ASSERT_TRUE(series.ok()) << series.error().to_string();
    EXPECT_EQ(series->size(), 2u);
    LoadOptions t1;
    t1.dicom_series = "4";
    auto t1_volume = load_volume(dir / "study", t1);
    ASSERT_TRUE(t1_volume.ok()) << t1_volume.error().to_string();
    EXPECT_EQ(t1_volume->dims, glm::uvec3(4, 4, 2));

    fixtures::write_series(dir / "deep" / "a" / "b" / "c" / "d" / "e" / "f", other,
                           std::vector<std::uint16_t>(32, 3));
    auto too_deep = load_volume(dir / "deep");
    ASSERT_FALSE(too_deep.ok());
    EXPECT_EQ(too_deep.error().code, base::ErrorCode::no_dicom_images);
}

// Two echoes in one series: every position twice. The first echo opens, with a note, whatever
// order the files come in; neither are they interleaved nor is the series refused.
TEST(DicomLoader, ASeriesOfSeveralVolumesOpensTheFirstWithANote) {
    fixtures::TempDir dir;
    const glm::uvec3 dims{16, 8, 5};
    const auto first_echo = fixtures::ch2_box(box_first, dims);
    auto second_echo = first_echo;
    for (auto& word : second_echo) {
        word = static_cast<std::uint16_t>(word + 1000);
    }
    SeriesSpec spec;
    spec.dims = dims;
    spec.spacing = {1.0, 1.0, 2.0};
    spec.series_uid = fixtures::make_uid();
    std::filesystem::create_directories(dir / "me");
    for (std::uint32_t z = 0; z < dims.z; ++z) {
        for (int echo : {2, 1}) {
            SeriesSpec echo_spec = spec;
            echo_spec.edit = [echo](DcmDataset& dataset) {
                dataset.putAndInsertString(DCM_EchoNumbers, std::to_string(echo).c_str());
            };
            // Instance numbers put the second echo first, so only the echo number orders them.
            fixtures::write_slice(
                    dir / "me" / ("e" + std::to_string(echo) + "z" + std::to_string(z)), echo_spec,
                    z, echo == 1 ? first_echo : second_echo,
                    static_cast<std::int32_t>(echo == 2 ? z : 100 + z));
        }
    }
    auto volume = load_volume(dir / "me");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, dims);
    EXPECT_EQ(volume->spacing.z, 2.0);
    expect_ch2_voxels(*volume, first_echo);
    ASSERT_EQ(volume->notes.size(), 1u);
    EXPECT_TRUE(contains(volume->notes.front(), "2 volumes")) << volume->notes.front();

    // Positions repeated unevenly are a broken series, named as such.
    std::filesystem::remove(dir / "me" / "e2z3");
    auto uneven = load_volume(dir / "me");
    ASSERT_FALSE(uneven.ok());
    EXPECT_EQ(uneven.error().code, base::ErrorCode::inconsistent_series);
}

// Siemens' NumberOfImagesInMosaic: a private element of its "SIEMENS MR HEADER" block.
void put_images_in_mosaic(DcmDataset& dataset, std::uint16_t count) {
    ASSERT_TRUE(
            dataset.putAndInsertString(DcmTag(0x0019, 0x0010, EVR_LO), "SIEMENS MR HEADER").good());
    ASSERT_TRUE(dataset.putAndInsertUint16(DcmTag(0x0019, 0x100a, EVR_US), count).good());
    ASSERT_TRUE(
            dataset.putAndInsertString(DCM_ImageType, "ORIGINAL\\PRIMARY\\M\\ND\\MOSAIC").good());
}

// A Siemens mosaic: five 16x8 slices of the ch2 head tiled three a side in one 48x24 image, whose
// ImagePositionPatient is that of the tiled image's corner as Siemens writes it. It opens as the
// five slices, the first tile's corner as origin. (Heudiconv's real mosaics are compared with
// nibabel's unpacking in the conformance test.)
TEST(DicomLoader, ASiemensMosaicIsUnpackedIntoItsSlices) {
    fixtures::TempDir dir;
    const glm::uvec3 tile{16, 8, 5};
    const auto slices = fixtures::ch2_box(box_first, tile);
    constexpr unsigned tiles = 3;
    std::vector<std::uint16_t> tiled(std::size_t{tile.x} * tiles * tile.y * tiles, 0);
    for (unsigned f = 0; f < tile.z; ++f) {
        for (unsigned y = 0; y < tile.y; ++y) {
            for (unsigned x = 0; x < tile.x; ++x) {
                tiled[((f / tiles) * tile.y + y) * tile.x * tiles + (f % tiles) * tile.x + x] =
                        slices[(std::size_t{f} * tile.y + y) * tile.x + x];
            }
        }
    }
    SeriesSpec spec;
    spec.dims = {tile.x * tiles, tile.y * tiles, 1};
    spec.spacing = {0.75, 0.5, 2.0};
    const glm::dvec3 corner{-10.0, 5.0, 3.0};  // LPS: the first tile's first pixel
    // Siemens writes the tiled image's corner: a whole tile grid's half-difference away.
    spec.origin = corner - glm::dvec3(0.75 * (48 - 16) / 2.0, 0.5 * (24 - 8) / 2.0, 0.0);
    spec.edit = [](DcmDataset& dataset) { put_images_in_mosaic(dataset, 5); };
    fixtures::write_slice(dir / "mosaic.dcm", spec, 0, tiled, 1);

    auto volume = load_volume(dir / "mosaic.dcm");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, tile);
    EXPECT_EQ(volume->spacing, glm::dvec3(0.75, 0.5, 2.0));
    EXPECT_EQ(orientation_code(volume->axes), "LPS");
    EXPECT_NEAR(glm::length(volume->origin - lps_to_ras(corner)), 0.0, 1e-9);
    expect_ch2_voxels(*volume, slices);
}

// One element of a Siemens CSA header: its name, multiplicity and text items (as many as
// `items`; those past the given values are empty, as Syngo pads its elements to six items).
struct CsaElement {
    std::string name;
    std::vector<std::string> values;
    std::int32_t items = 6;
};

enum class CsaLayout { sv10, csa1 };

// A Siemens CSA image header (0029,1010), built byte by byte as Syngo writes one: "SV10" (CSA2)
// with its signature, each item's length its second word; or the older CSA1 without one, each
// item's length its first word less the first element's count of items. Either way a 16-byte
// header per item and the text padded to four bytes.
std::vector<Uint8> csa_header(CsaLayout layout, const std::vector<CsaElement>& elements) {
    std::vector<Uint8> bytes;
    const auto put_int = [&](std::int32_t value) {
        const auto* b = reinterpret_cast<const Uint8*>(&value);
        bytes.insert(bytes.end(), b, b + 4);
    };
    const auto put_text = [&](const std::string& text, std::size_t size) {
        std::vector<Uint8> field(size, 0);
        std::copy(text.begin(), text.end(), field.begin());
        bytes.insert(bytes.end(), field.begin(), field.end());
    };
    if (layout == CsaLayout::sv10) {
        put_text("SV10", 4);
        put_text("\4\3\2\1", 4);
    }
    put_int(static_cast<std::int32_t>(elements.size()));
    put_int(77);  // unused
    const std::int32_t length_offset = layout == CsaLayout::csa1 ? elements.front().items : 0;
    for (const CsaElement& element : elements) {
        put_text(element.name, 64);
        put_int(static_cast<std::int32_t>(element.values.size()));  // multiplicity
        put_text("FD", 4);
        put_int(4);  // SyngoDT
        put_int(element.items);
        put_int(77);
        for (std::int32_t i = 0; i < element.items; ++i) {
            const std::string text =
                    i < static_cast<std::int32_t>(element.values.size()) ? element.values[i] : "";
            // With its NUL; an empty item is no bytes at all.
            const auto length = static_cast<std::int32_t>(text.empty() ? 0 : text.size() + 1);
            const std::int32_t word = length + length_offset;
            for (const std::int32_t field : {word, word, 77, word}) {
                put_int(field);
            }
            put_text(text, static_cast<std::size_t>(length + (4 - length % 4) % 4));
        }
    }
    return bytes;
}

std::vector<Uint8> csa_header(const std::string& name, const std::vector<std::string>& items) {
    return csa_header(CsaLayout::sv10, {{name, items, static_cast<std::int32_t>(items.size())}});
}

// The slice order comes from the CSA header's SliceNormalVector: pointing inferior, against the
// row x column direction, the tiles run from head to foot, so the volume (ordered along +z)
// holds them in reverse, its origin at the last tile.
TEST(DicomLoader, AMosaicsSlicesFollowTheCsaSliceNormal) {
    fixtures::TempDir dir;
    const glm::uvec3 tile{8, 8, 4};
    const auto slices = fixtures::ch2_box(box_first, tile);
    std::vector<std::uint16_t> tiled(std::size_t{16} * 16, 0);
    for (unsigned f = 0; f < tile.z; ++f) {
        for (unsigned y = 0; y < tile.y; ++y) {
            for (unsigned x = 0; x < tile.x; ++x) {
                tiled[((f / 2) * 8 + y) * 16 + (f % 2) * 8 + x] = slices[(f * 8 + y) * 8 + x];
            }
        }
    }
    SeriesSpec spec;
    spec.dims = {16, 16, 1};
    spec.spacing = {1.0, 1.0, 2.5};
    spec.origin = glm::dvec3(-4.0, -4.0, 0.0);  // the first tile's corner at (0, 0, 0)
    spec.edit = [](DcmDataset& dataset) {
        put_images_in_mosaic(dataset, 4);
        const auto csa = csa_header("SliceNormalVector", {"0.00000000", "0.00000000", "-1.0"});
        ASSERT_TRUE(dataset.putAndInsertUint8Array(DcmTag(0x0029, 0x1010, EVR_OB), csa.data(),
                                                   csa.size())
                            .good());
        ASSERT_TRUE(dataset.putAndInsertString(DcmTag(0x0029, 0x0010, EVR_LO), "SIEMENS CSA HEADER")
                            .good());
    };
    fixtures::write_slice(dir / "mosaic.dcm", spec, 0, tiled, 1);

    auto volume = load_volume(dir / "mosaic.dcm");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, tile);
    EXPECT_EQ(orientation_code(volume->axes), "LPS");
    EXPECT_NEAR(glm::length(volume->origin - glm::dvec3(0.0, 0.0, -7.5)), 0.0, 1e-9);
    std::vector<std::uint16_t> reversed;
    for (unsigned k = 0; k < tile.z; ++k) {
        const auto first = slices.begin() + static_cast<std::ptrdiff_t>((tile.z - 1 - k) * 64);
        reversed.insert(reversed.end(), first, first + 64);
    }
    expect_ch2_voxels(*volume, reversed);
}

// The older CSA1 layout (no "SV10" signature) is read as the newer: a mosaic whose number of
// slices and slice normal only its CSA header gives opens alike from either, the header holding
// an element before them whose item count offsets CSA1's item lengths.
TEST(DicomLoader, AMosaicsCsaHeaderIsReadInEitherLayout) {
    const glm::uvec3 tile{8, 8, 4};
    const auto slices = fixtures::ch2_box(box_first, tile);
    std::vector<std::uint16_t> tiled(std::size_t{16} * 16, 0);
    for (unsigned f = 0; f < tile.z; ++f) {
        for (unsigned y = 0; y < tile.y; ++y) {
            for (unsigned x = 0; x < tile.x; ++x) {
                tiled[((f / 2) * 8 + y) * 16 + (f % 2) * 8 + x] = slices[(f * 8 + y) * 8 + x];
            }
        }
    }
    std::vector<std::uint16_t> reversed;  // the normal points against row x column
    for (unsigned k = 0; k < tile.z; ++k) {
        const auto first = slices.begin() + static_cast<std::ptrdiff_t>((tile.z - 1 - k) * 64);
        reversed.insert(reversed.end(), first, first + 64);
    }
    for (const CsaLayout layout : {CsaLayout::sv10, CsaLayout::csa1}) {
        SCOPED_TRACE(layout == CsaLayout::sv10 ? "SV10" : "CSA1");
        fixtures::TempDir dir;
        SeriesSpec spec;
        spec.dims = {16, 16, 1};
        spec.spacing = {1.0, 1.0, 2.5};
        spec.origin = glm::dvec3(-4.0, -4.0, 0.0);
        spec.edit = [layout](DcmDataset& dataset) {
            // MOSAIC in ImageType, but no NumberOfImagesInMosaic (0019,100a): the count comes
            // from the CSA header alone.
            ASSERT_TRUE(dataset.putAndInsertString(DCM_ImageType, "ORIGINAL\\PRIMARY\\M\\MOSAIC")
                                .good());
            const auto csa = csa_header(
                    layout, {{"EchoLinePosition", {"128"}, 6},
                             {"NumberOfImagesInMosaic", {"4"}, 6},
                             {"SliceNormalVector", {"0.00000000", "0.00000000", "-1.0"}, 6}});
            ASSERT_TRUE(dataset.putAndInsertUint8Array(DcmTag(0x0029, 0x1010, EVR_OB), csa.data(),
                                                       csa.size())
                                .good());
            ASSERT_TRUE(
                    dataset.putAndInsertString(DcmTag(0x0029, 0x0010, EVR_LO), "SIEMENS CSA HEADER")
                            .good());
        };
        fixtures::write_slice(dir / "mosaic.dcm", spec, 0, tiled, 1);
        auto volume = load_volume(dir / "mosaic.dcm");
        ASSERT_TRUE(volume.ok()) << volume.error().to_string();
        EXPECT_EQ(volume->dims, tile);
        EXPECT_NEAR(glm::length(volume->origin - glm::dvec3(0.0, 0.0, -7.5)), 0.0, 1e-9);
        expect_ch2_voxels(*volume, reversed);
    }
}

// Mosaics that cannot be unpacked are refused by name: without a number of slices, or with one
// that does not tile the image; in a folder, the series beside them still opens.
TEST(DicomLoader, MosaicsThatCannotBeUnpackedAreRefusedSayingMosaic) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    spec.dims = {8, 8, 1};
    spec.series_uid = fixtures::make_uid();
    spec.edit = [](DcmDataset& dataset) {
        dataset.putAndInsertString(DCM_ImageType, "ORIGINAL\\PRIMARY\\M\\ND\\MOSAIC");
    };
    fixtures::write_slice(dir / "uncounted.dcm", spec, 0, std::vector<std::uint16_t>(64, 4), 1);
    auto uncounted = load_volume(dir / "uncounted.dcm");
    ASSERT_FALSE(uncounted.ok());
    EXPECT_EQ(uncounted.error().code, base::ErrorCode::unsupported_type);
    EXPECT_TRUE(contains(uncounted.error().message, "mosaic")) << uncounted.error().message;

    spec.edit = [](DcmDataset& dataset) { put_images_in_mosaic(dataset, 5); };  // 3 x 3 tiles
    fixtures::write_slice(dir / "untiled.dcm", spec, 0, std::vector<std::uint16_t>(64, 4), 1);
    auto untiled = load_volume(dir / "untiled.dcm");
    ASSERT_FALSE(untiled.ok());
    EXPECT_TRUE(contains(untiled.error().message, "mosaic")) << untiled.error().message;
    EXPECT_TRUE(contains(untiled.error().message, "do not tile")) << untiled.error().message;

    const auto words = fixtures::ch2_box(box_first, {16, 8, 3});
    SeriesSpec series;
    series.dims = {16, 8, 3};
    fixtures::write_series(dir / "s", series, words);
    std::filesystem::copy_file(dir / "uncounted.dcm", dir / "s" / "mosaic.dcm");
    auto volume = load_volume(dir / "s");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_ch2_voxels(*volume, words);
}

// A CSA header is untrusted text: a slice count that is negative, past 32 bits, not a number, or
// more than the image has pixels is refused saying "mosaic" (a count of 2^32 - 1 once left the
// search for the tiles a side running for ever).
TEST(DicomLoader, AMosaicsImpossibleCsaSliceCountIsRefused) {
    for (const std::string count : {"-1", "4294967295", "99999999999", "4x", "", "257"}) {
        SCOPED_TRACE(count);
        fixtures::TempDir dir;
        SeriesSpec spec;
        spec.dims = {16, 16, 1};
        spec.edit = [&count](DcmDataset& dataset) {
            ASSERT_TRUE(dataset.putAndInsertString(DCM_ImageType, "ORIGINAL\\PRIMARY\\M\\MOSAIC")
                                .good());
            const auto csa = csa_header("NumberOfImagesInMosaic", {count});
            ASSERT_TRUE(dataset.putAndInsertUint8Array(DcmTag(0x0029, 0x1010, EVR_OB), csa.data(),
                                                       csa.size())
                                .good());
            ASSERT_TRUE(
                    dataset.putAndInsertString(DcmTag(0x0029, 0x0010, EVR_LO), "SIEMENS CSA HEADER")
                            .good());
        };
        fixtures::write_slice(dir / "mosaic.dcm", spec, 0, std::vector<std::uint16_t>(256, 4), 1);
        auto volume = load_volume(dir / "mosaic.dcm");
        ASSERT_FALSE(volume.ok());
        EXPECT_EQ(volume.error().code, base::ErrorCode::unsupported_type);
        EXPECT_TRUE(contains(volume.error().message, "mosaic")) << volume.error().message;
    }
}

// (0029,1010) is a CSA header only under the private creator "SIEMENS CSA HEADER": under another
// vendor's, a mosaic's count there is not read, and the mosaic is refused for lacking one.
TEST(DicomLoader, ACsaHeaderUnderAnotherPrivateCreatorIsNotRead) {
    for (const std::string creator : {"SIEMENS CSA HEADER", "ACME PRIVATE"}) {
        SCOPED_TRACE(creator);
        fixtures::TempDir dir;
        SeriesSpec spec;
        spec.dims = {16, 16, 1};
        spec.edit = [&creator](DcmDataset& dataset) {
            ASSERT_TRUE(dataset.putAndInsertString(DCM_ImageType, "ORIGINAL\\PRIMARY\\M\\MOSAIC")
                                .good());
            const auto csa = csa_header("NumberOfImagesInMosaic", {"4"});
            ASSERT_TRUE(dataset.putAndInsertUint8Array(DcmTag(0x0029, 0x1010, EVR_OB), csa.data(),
                                                       csa.size())
                                .good());
            ASSERT_TRUE(dataset.putAndInsertString(DcmTag(0x0029, 0x0010, EVR_LO), creator.c_str())
                                .good());
        };
        fixtures::write_slice(dir / "mosaic.dcm", spec, 0, std::vector<std::uint16_t>(256, 4), 1);
        auto volume = load_volume(dir / "mosaic.dcm");
        if (creator == "SIEMENS CSA HEADER") {
            ASSERT_TRUE(volume.ok()) << volume.error().to_string();
            EXPECT_EQ(volume->dims, glm::uvec3(8, 8, 4));
        } else {
            ASSERT_FALSE(volume.ok());
            EXPECT_TRUE(contains(volume.error().message, "NumberOfImagesInMosaic"))
                    << volume.error().message;
        }
    }
}

// Clinics export a series with an RGB secondary capture (a screenshot) beside it: pydicom's real
// one (Debian's python3-pydicom) is skipped with a warning and the series opens; alone, it is
// refused saying why.
TEST(DicomLoader, AnRgbCaptureInTheFolderIsSkippedAndTheSeriesOpens) {
    const std::filesystem::path rgb =
            "/usr/lib/python3/dist-packages/pydicom/data/test_files/SC_rgb_small_odd.dcm";
    ASSERT_TRUE(std::filesystem::exists(rgb)) << rgb << " comes with Debian's python3-pydicom";
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 3});
    SeriesSpec spec;
    spec.dims = {16, 8, 3};
    fixtures::write_series(dir / "s", spec, words);
    std::filesystem::copy_file(rgb, dir / "s" / "screenshot.dcm");

    auto volume = load_volume(dir / "s");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(16, 8, 3));
    expect_ch2_voxels(*volume, words);

    std::filesystem::create_directories(dir / "only");
    std::filesystem::copy_file(rgb, dir / "only" / "screenshot.dcm");
    auto alone = load_volume(dir / "only");
    ASSERT_FALSE(alone.ok());
    EXPECT_EQ(alone.error().code, base::ErrorCode::unsupported_type);
    EXPECT_NE(alone.error().message.find("samples per pixel"), std::string::npos)
            << alone.error().message;
}

TEST(DicomLoader, FilesThatAreNotDicomAreSkipped) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, {16, 8, 3});
    SeriesSpec spec;
    spec.dims = {16, 8, 3};
    fixtures::write_series(dir / "s", spec, words);
    fixtures::write_text(dir / "s" / "README.txt", "exported by a PACS");
    fixtures::write_text(dir / "s" / ".DS_Store", "junk");

    auto volume = load_volume(dir / "s");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_ch2_voxels(*volume, words);
}

// Errors: each names the file (or folder) and says what is wrong.

TEST(DicomLoader, EmptyFolderIsAnError) {
    fixtures::TempDir dir;
    std::filesystem::create_directories(dir / "empty");
    auto volume = load_volume(dir / "empty");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::no_dicom_images);
    EXPECT_TRUE(contains(volume.error().where, "empty")) << volume.error().to_string();
    EXPECT_TRUE(contains(volume.error().message, "no files")) << volume.error().to_string();
}

TEST(DicomLoader, FolderOfNonDicomFilesIsAnError) {
    fixtures::TempDir dir;
    std::filesystem::create_directories(dir / "notes");
    fixtures::write_text(dir / "notes" / "a.txt", "hello");
    auto volume = load_volume(dir / "notes");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::no_dicom_images);
    EXPECT_TRUE(contains(volume.error().message, "1 other files")) << volume.error().to_string();
}

TEST(DicomLoader, NonDicomFileNamedDcmIsAnError) {
    fixtures::TempDir dir;
    fixtures::write_text(dir / "fake.dcm", "this is not DICOM at all");
    auto volume = load_volume(dir / "fake.dcm");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::not_dicom);
    EXPECT_TRUE(contains(volume.error().where, "fake.dcm")) << volume.error().to_string();
}

TEST(DicomLoader, CorruptFileWithTheDicomMarkerIsSkippedAndNamed) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(24, 1));
    std::vector<std::byte> bytes(200, std::byte{0xff});
    std::memcpy(bytes.data() + 128, "DICM", 4);
    fixtures::write_bytes(dir / "s" / "broken", bytes);
    auto volume = load_volume(dir / "s");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    ASSERT_EQ(volume->notes.size(), 1u);
    EXPECT_TRUE(contains(volume->notes.front(), "broken")) << volume->notes.front();
    EXPECT_TRUE(contains(volume->notes.front(), "bad_header") ||
                contains(volume->notes.front(), "truncated"))
            << volume->notes.front();

    std::filesystem::create_directories(dir / "alone");
    fixtures::write_bytes(dir / "alone" / "broken", bytes);
    auto alone = load_volume(dir / "alone");
    ASSERT_FALSE(alone.ok());
    EXPECT_TRUE(alone.error().code == base::ErrorCode::bad_header ||
                alone.error().code == base::ErrorCode::truncated)
            << alone.error().to_string();
    EXPECT_TRUE(contains(alone.error().where, "broken")) << alone.error().to_string();
}

TEST(DicomLoader, MixedImageSizesAreAnError) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    spec.dims = {8, 8, 3};
    spec.series_uid = fixtures::make_uid();
    fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(192, 5));
    spec.dims = {8, 4, 1};
    fixtures::write_slice(dir / "s" / "zz_small.dcm", spec, 0, std::vector<std::uint16_t>(32, 5),
                          4);
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::inconsistent_series);
    EXPECT_TRUE(contains(volume.error().where, "zz_small.dcm")) << volume.error().to_string();
    EXPECT_TRUE(contains(volume.error().message, "8x4 pixels")) << volume.error().to_string();
}

TEST(DicomLoader, MismatchedBitsAllocatedAreAnError) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    spec.dims = {8, 8, 3};
    spec.series_uid = fixtures::make_uid();
    fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(192, 5));
    spec.bits_allocated = spec.bits_stored = 8;
    fixtures::write_slice(dir / "s" / "zz_8bit.dcm", spec, 2, std::vector<std::uint16_t>(192, 5),
                          4);
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::inconsistent_series);
    EXPECT_TRUE(contains(volume.error().where, "zz_8bit.dcm")) << volume.error().to_string();
}

TEST(DicomLoader, MissingSliceMakesUnevenSpacingAnError) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    spec.dims = {4, 4, 6};
    const auto paths = fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(96, 5));
    std::filesystem::remove(paths[3]);
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::inconsistent_series);
    EXPECT_TRUE(contains(volume.error().message, "not evenly spaced"))
            << volume.error().to_string();
    EXPECT_TRUE(contains(volume.error().where, "slice_004.dcm")) << volume.error().to_string();
}

TEST(DicomLoader, RepeatedPositionIsAnError) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    spec.dims = {4, 4, 4};
    spec.series_uid = fixtures::make_uid();
    fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(64, 5));
    fixtures::write_slice(dir / "s" / "again.dcm", spec, 2, std::vector<std::uint16_t>(64, 5), 9);
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::inconsistent_series);
    EXPECT_TRUE(contains(volume.error().message, "not evenly spaced"))
            << volume.error().to_string();
}

// A slice cut short inside the series is skipped, and the gap it leaves refuses the series,
// naming it; a file of only that slice is refused as truncated.
TEST(DicomLoader, TruncatedPixelDataIsAnError) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    spec.dims = {32, 32, 3};
    const auto paths = fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(3072, 5));
    const auto size = std::filesystem::file_size(paths[1]);
    std::filesystem::resize_file(paths[1], size - 500);
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::inconsistent_series)
            << volume.error().to_string();
    EXPECT_TRUE(contains(volume.error().to_string(), "slice_001.dcm"))
            << volume.error().to_string();
    auto slice = load_volume(paths[1]);
    ASSERT_FALSE(slice.ok());
    EXPECT_EQ(slice.error().code, base::ErrorCode::truncated) << slice.error().to_string();
    EXPECT_TRUE(contains(slice.error().where, "slice_001.dcm")) << slice.error().to_string();
}

TEST(DicomLoader, MissingRowsTagIsNamed) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    spec.edit = [](DcmDataset& dataset) { dataset.findAndDeleteElement(DCM_Rows); };
    fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(24, 5));
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::bad_header);
    EXPECT_TRUE(contains(volume.error().message, "Rows (0028,0010)")) << volume.error().to_string();
}

TEST(DicomLoader, ColourImagesAreRefused) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    spec.edit = [](DcmDataset& dataset) {
        dataset.putAndInsertUint16(DCM_SamplesPerPixel, 3);
        dataset.putAndInsertString(DCM_PhotometricInterpretation, "RGB");
    };
    fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(24, 5));
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::unsupported_type);
    EXPECT_TRUE(contains(volume.error().message, "3 samples per pixel"))
            << volume.error().to_string();
}

TEST(DicomLoader, MissingFolderIsNotFound) {
    fixtures::TempDir dir;
    auto volume = load_dicom(dir / "nowhere");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::not_found);
}

TEST(DicomLoader, IsDicomFileChecksThePart10Marker) {
    fixtures::TempDir dir;
    SeriesSpec spec;
    const auto paths = fixtures::write_series(dir / "s", spec, std::vector<std::uint16_t>(24, 5));
    EXPECT_TRUE(is_dicom_file(paths[0]));
    fixtures::write_text(dir / "short", "DICM");
    EXPECT_FALSE(is_dicom_file(dir / "short"));
    EXPECT_FALSE(is_dicom_file(dir / "missing"));
}

// Real files written by scanners and other toolkits, shipped by Debian's python3-pydicom. The
// expected values were read with pydicom, an independent decoder.

const std::filesystem::path pydicom_files =
        "/usr/lib/python3/dist-packages/pydicom/data/test_files";

#define SKIP_WITHOUT_PYDICOM_FILES()                                                        \
    if (!std::filesystem::exists(pydicom_files / "CT_small.dcm")) {                         \
        GTEST_SKIP() << "install python3-pydicom (scripts/install-deps.sh) for real DICOM " \
                        "files";                                                            \
    }

TEST(DicomLoader, RealCtSliceInHounsfieldUnits) {
    SKIP_WITHOUT_PYDICOM_FILES();
    auto volume = load_volume(pydicom_files / "CT_small.dcm");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(128, 128, 1));
    EXPECT_EQ(volume->type, VoxelType::int16);
    EXPECT_TRUE(volume->hounsfield);
    EXPECT_DOUBLE_EQ(volume->spacing.x, 0.661468);
    EXPECT_DOUBLE_EQ(volume->spacing.y, 0.661468);
    EXPECT_DOUBLE_EQ(volume->spacing.z, 5.0);  // SliceThickness, for a single slice
    // pydicom: stored values 128..2191, pixel (row 0, column 0) 175, (row 10, column 20) 185,
    // sum 14826310; RescaleIntercept -1024.
    EXPECT_EQ(volume->range.min, 128 - 1024);
    EXPECT_EQ(volume->range.max, 2191 - 1024);
    EXPECT_EQ(volume->value(0, 0, 0), 175 - 1024);
    EXPECT_EQ(volume->value(20, 10, 0), 185 - 1024);
    double sum = 0.0;
    for (std::uint32_t y = 0; y < 128; ++y) {
        for (std::uint32_t x = 0; x < 128; ++x) {
            sum += volume->value(x, y, 0);
        }
    }
    EXPECT_EQ(sum, 14826310.0 - 1024.0 * 128 * 128);
}

TEST(DicomLoader, RealMrSliceDecodesAlikeInEveryTransferSyntax) {
    SKIP_WITHOUT_PYDICOM_FILES();
    auto reference = load_volume(pydicom_files / "MR_small.dcm");
    ASSERT_TRUE(reference.ok()) << reference.error().to_string();
    EXPECT_EQ(reference->dims, glm::uvec3(64, 64, 1));
    EXPECT_EQ(reference->type, VoxelType::int16);  // signed, though every value is positive
    EXPECT_DOUBLE_EQ(reference->spacing.x, 0.3125);
    // pydicom: 127..2145, pixel (row 0, column 0) 905, (row 10, column 20) 316.
    EXPECT_EQ(reference->range.min, 127);
    EXPECT_EQ(reference->range.max, 2145);
    EXPECT_EQ(reference->value(0, 0, 0), 905);
    EXPECT_EQ(reference->value(20, 10, 0), 316);
    for (const char* name :
         {"MR_small_implicit.dcm", "MR_small_bigendian.dcm", "MR_small_expb.dcm",
          "MR_small_padded.dcm", "MR_small_RLE.dcm", "MR_small_jpeg_ls_lossless.dcm"}) {
        auto volume = load_volume(pydicom_files / name);
        ASSERT_TRUE(volume.ok()) << name << ": " << volume.error().to_string();
        EXPECT_EQ(volume->data, reference->data) << name;
    }
}

TEST(DicomLoader, RealTruncatedFileIsReportedAsTruncated) {
    SKIP_WITHOUT_PYDICOM_FILES();
    auto volume = load_volume(pydicom_files / "MR_truncated.dcm");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated) << volume.error().to_string();
}

// A real CT series of five 16x16 slices, 2.5 mm apart (pydicom's DICOMDIR test set).
const std::filesystem::path real_ct_series = pydicom_files / "dicomdirtests/98892001/CT5N";

// Copies the real series into `folder`, its files named as pydicom ships them.
void copy_real_ct_series(const std::filesystem::path& folder) {
    std::filesystem::create_directories(folder);
    for (const auto& entry : std::filesystem::directory_iterator(real_ct_series)) {
        std::filesystem::copy_file(entry.path(), folder / entry.path().filename());
    }
}

// The first `bytes` bytes of a file, as a copy cut short in transfer leaves it.
void write_cut_copy(const std::filesystem::path& from, const std::filesystem::path& to,
                    std::size_t bytes) {
    std::ifstream in(from, std::ios::binary);
    std::vector<char> head(bytes);
    ASSERT_TRUE(in.read(head.data(), static_cast<std::streamsize>(bytes)));
    std::ofstream(to, std::ios::binary).write(head.data(), static_cast<std::streamsize>(bytes));
}

bool any_note_names(const Volume& volume, const std::string& file, const std::string& why) {
    return std::any_of(volume.notes.begin(), volume.notes.end(), [&](const std::string& note) {
        return contains(note, file) && contains(note, why);
    });
}

// A damaged file among the slices (a copy cut short, a file of junk behind a DICOM marker) is
// skipped with a note naming it, and the series opens with every voxel of its intact slices.
TEST(DicomLoader, DamagedFilesBesideARealSeriesAreSkippedWithANote) {
    SKIP_WITHOUT_PYDICOM_FILES();
    fixtures::TempDir dir;
    copy_real_ct_series(dir / "clean");
    auto clean = load_volume(dir / "clean");
    ASSERT_TRUE(clean.ok()) << clean.error().to_string();
    ASSERT_EQ(clean->dims, glm::uvec3(16, 16, 5));
    EXPECT_TRUE(clean->notes.empty());

    copy_real_ct_series(dir / "s");
    write_cut_copy(real_ct_series / "2392", dir / "s" / "2392_copy", 2000);
    std::vector<std::byte> junk(300, std::byte{0x5a});
    std::memcpy(junk.data() + 128, "DICM", 4);
    fixtures::write_bytes(dir / "s" / "junk_with_marker", junk);
    fixtures::write_text(dir / "s" / "junk.txt", "not an image");

    auto volume = load_volume(dir / "s");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, clean->dims);
    EXPECT_EQ(volume->spacing, clean->spacing);
    EXPECT_EQ(volume->data, clean->data);
    EXPECT_TRUE(any_note_names(*volume, "2392_copy", "truncated"))
            << ::testing::PrintToString(volume->notes);
    EXPECT_TRUE(any_note_names(*volume, "junk_with_marker", "skipped"))
            << ::testing::PrintToString(volume->notes);
    EXPECT_TRUE(any_note_names(*volume, "junk.txt", "not DICOM"))
            << ::testing::PrintToString(volume->notes);
}

// A skipped slice inside the series leaves a gap: refused, naming the skipped file as the cause,
// never rendered with a slice silently missing.
TEST(DicomLoader, ADamagedSliceInsideARealSeriesIsRefusedNamingIt) {
    SKIP_WITHOUT_PYDICOM_FILES();
    fixtures::TempDir dir;
    copy_real_ct_series(dir / "s");
    std::filesystem::resize_file(dir / "s" / "2693", 2000);  // the middle slice of five
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::inconsistent_series)
            << volume.error().to_string();
    EXPECT_TRUE(contains(volume.error().message, "not evenly spaced"))
            << volume.error().to_string();
    EXPECT_TRUE(contains(volume.error().message, "2693")) << volume.error().to_string();
}

// A damaged end slice leaves no gap to see: the volume opens one slice shorter, and says why.
TEST(DicomLoader, ADamagedEndSliceOfARealSeriesOpensTheRestWithANote) {
    SKIP_WITHOUT_PYDICOM_FILES();
    fixtures::TempDir dir;
    copy_real_ct_series(dir / "s");
    std::filesystem::resize_file(dir / "s" / "3353", 2000);  // the lowest slice
    auto volume = load_volume(dir / "s");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    EXPECT_EQ(volume->dims, glm::uvec3(16, 16, 4));
    EXPECT_TRUE(any_note_names(*volume, "3353", "not in the volume"))
            << ::testing::PrintToString(volume->notes);
}

// Only damaged files: the folder's error is the first file's own.
TEST(DicomLoader, AFolderOfOnlyDamagedFilesIsTheirError) {
    SKIP_WITHOUT_PYDICOM_FILES();
    fixtures::TempDir dir;
    std::filesystem::create_directories(dir / "s");
    write_cut_copy(real_ct_series / "2392", dir / "s" / "2392", 2000);
    auto volume = load_volume(dir / "s");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::truncated) << volume.error().to_string();
    EXPECT_TRUE(contains(volume.error().where, "2392")) << volume.error().to_string();
}

// A folder of two real series: the CT above, and heudiconv's diffusion series of three Siemens
// mosaics, one per volume, each tiling the same 81 slices. A listing counts what a load opens
// (81 slices) apart from the 2-D images the files hold (243 tiles in 3 files).
TEST(DicomLoader, SeriesListingsCountSlicesApartFromFramesOnRealSeries) {
    SKIP_WITHOUT_PYDICOM_FILES();
    const std::filesystem::path mosaics =
            "/usr/lib/python3/dist-packages/heudiconv/tests/data/b0dwiForFmap";
    ASSERT_TRUE(std::filesystem::exists(mosaics)) << mosaics << " comes with Debian's heudiconv";
    fixtures::TempDir dir;
    copy_real_ct_series(dir / "study" / "ct");
    std::filesystem::create_directories(dir / "study" / "dwi");
    for (const auto& entry : std::filesystem::directory_iterator(mosaics)) {
        std::filesystem::create_symlink(entry.path(),
                                        dir / "study" / "dwi" / entry.path().filename());
    }
    auto series = list_dicom_series(dir / "study");
    ASSERT_TRUE(series.ok()) << series.error().to_string();
    ASSERT_EQ(series->size(), 2u);
    const auto& dwi = series->front().images == 3 ? series->front() : series->back();
    const auto& ct = series->front().images == 3 ? series->back() : series->front();
    EXPECT_EQ(dwi.images, 3u);
    EXPECT_EQ(dwi.frames, 243u);
    EXPECT_EQ(dwi.slices, 81u);
    EXPECT_EQ(ct.images, 5u);
    EXPECT_EQ(ct.frames, 5u);
    EXPECT_EQ(ct.slices, 5u);

    // The choice a load asks for names each series with the slices it would open.
    auto several = load_volume(dir / "study");
    ASSERT_FALSE(several.ok());
    EXPECT_EQ(several.error().code, base::ErrorCode::several_series);
    EXPECT_TRUE(contains(several.error().message, "81 slices")) << several.error().message;
    EXPECT_FALSE(contains(several.error().message, "243")) << several.error().message;
}

// A codestream whose image is not the one the header describes, and one cut short: clear errors
// naming the file (OpenJPEG allocates only after the sizes agree).
TEST(DicomLoader, JpegTwoThousandThatDisagreesWithItsHeaderOrIsCutShortIsRefused) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    std::vector<std::uint32_t> order(box_dims.z);
    std::iota(order.begin(), order.end(), 0u);
    SeriesSpec spec = ch2_spec();
    spec.jpeg2000_fragments = 1;
    spec.edit = [](DcmDataset& dataset) {
        ASSERT_TRUE(dataset.putAndInsertUint16(DCM_Rows, box_dims.y - 8).good());
    };
    fixtures::write_multiframe(dir / "other_size.dcm", spec, words, order);
    auto volume = load_volume(dir / "other_size.dcm");
    ASSERT_FALSE(volume.ok());
    EXPECT_EQ(volume.error().code, base::ErrorCode::decode_failed);
    EXPECT_TRUE(contains(volume.error().message, "64x48, the header says 64x40"))
            << volume.error().to_string();
    EXPECT_TRUE(contains(volume.error().where, "other_size.dcm"));

    // Every frame's codestream ends where its first half ends.
    spec.edit = [](DcmDataset& dataset) {
        DcmElement* element = nullptr;
        DcmPixelSequence* sequence = nullptr;
        ASSERT_TRUE(dataset.findAndGetElement(DCM_PixelData, element).good());
        ASSERT_TRUE(
                OFstatic_cast(DcmPixelData*, element)
                        ->getEncapsulatedRepresentation(EXS_JPEG2000LosslessOnly, nullptr, sequence)
                        .good());
        for (unsigned long i = 1; i < sequence->card(); ++i) {
            DcmPixelItem* item = nullptr;
            Uint8* bytes = nullptr;
            ASSERT_TRUE(sequence->getItem(item, i).good());
            ASSERT_TRUE(item->getUint8Array(bytes).good());
            const std::vector<Uint8> half(bytes, bytes + (item->getLength() / 4) * 2);
            ASSERT_TRUE(item->putUint8Array(half.data(), half.size()).good());
        }
    };
    fixtures::write_multiframe(dir / "cut_short.dcm", spec, words, order);
    auto cut = load_volume(dir / "cut_short.dcm");
    ASSERT_FALSE(cut.ok());
    EXPECT_EQ(cut.error().code, base::ErrorCode::decode_failed) << cut.error().to_string();

    // Tiles of one pixel (XTsiz = YTsiz = 1 in every SIZ marker): OpenJPEG would allocate for
    // each of the 6144 tiles as it reads the header; refused before it does, beyond 4096.
    const glm::uvec3 wide{128, 48, 2};
    const auto wide_words = fixtures::ch2_box({20, 80, 70}, wide);
    SeriesSpec tiled = ch2_spec();
    tiled.dims = wide;
    tiled.jpeg2000_fragments = 1;
    tiled.edit = [](DcmDataset& dataset) {
        DcmElement* element = nullptr;
        DcmPixelSequence* sequence = nullptr;
        ASSERT_TRUE(dataset.findAndGetElement(DCM_PixelData, element).good());
        ASSERT_TRUE(
                OFstatic_cast(DcmPixelData*, element)
                        ->getEncapsulatedRepresentation(EXS_JPEG2000LosslessOnly, nullptr, sequence)
                        .good());
        for (unsigned long i = 1; i < sequence->card(); ++i) {
            DcmPixelItem* item = nullptr;
            Uint8* bytes = nullptr;
            ASSERT_TRUE(sequence->getItem(item, i).good());
            ASSERT_TRUE(item->getUint8Array(bytes).good());
            ASSERT_EQ(bytes[2], 0xFF);  // SIZ follows SOC
            ASSERT_EQ(bytes[3], 0x51);
            std::vector<Uint8> patched(bytes, bytes + item->getLength());
            for (const std::size_t at : {24u, 28u}) {  // XTsiz, YTsiz: 4 bytes each, big endian
                patched[at] = patched[at + 1] = patched[at + 2] = 0;
                patched[at + 3] = 1;
            }
            ASSERT_TRUE(item->putUint8Array(patched.data(), patched.size()).good());
        }
    };
    const std::vector<std::uint32_t> two{0, 1};
    fixtures::write_multiframe(dir / "tiny_tiles.dcm", tiled, wide_words, two);
    auto tiles = load_volume(dir / "tiny_tiles.dcm");
    ASSERT_FALSE(tiles.ok());
    EXPECT_EQ(tiles.error().code, base::ErrorCode::decode_failed);
    EXPECT_TRUE(contains(tiles.error().message, "6144 tiles")) << tiles.error().to_string();
}

void expect_axes(const Volume& volume, glm::dvec3 i, glm::dvec3 j, glm::dvec3 k) {
    for (int row = 0; row < 3; ++row) {
        EXPECT_NEAR(volume.axes[0][row], i[row], 1e-6) << "axis i, component " << row;
        EXPECT_NEAR(volume.axes[1][row], j[row], 1e-6) << "axis j, component " << row;
        EXPECT_NEAR(volume.axes[2][row], k[row], 1e-6) << "axis k, component " << row;
    }
}

// DICOM's patient space is LPS: an axial series (rows along +x, columns along +y) is LPS, and
// its first slice's position, converted to RAS, is the origin.
TEST(DicomLoader, AxialSeriesIsLpsWithTheFirstSliceAsOrigin) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    fixtures::write_series(dir / "axial", ch2_spec(), words);
    auto volume = load_volume(dir / "axial");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_axes(*volume, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1});
    EXPECT_EQ(orientation_code(volume->axes), "LPS");
    EXPECT_NEAR(volume->origin.x, 40.0, 1e-6);
    EXPECT_NEAR(volume->origin.y, -12.5, 1e-6);
    EXPECT_NEAR(volume->origin.z, -7.0, 1e-6);
}

TEST(DicomLoader, SagittalSeriesKeepsItsAnatomy) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    SeriesSpec spec = ch2_spec();
    spec.orientation = {0, 1, 0, 0, 0, -1};  // rows toward posterior, columns toward inferior
    fixtures::write_series(dir / "sagittal", spec, words);
    auto volume = load_volume(dir / "sagittal");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    // The normal, row x column, is -x in LPS: toward the patient's right.
    expect_axes(*volume, {0, -1, 0}, {0, 0, -1}, {1, 0, 0});
    EXPECT_EQ(orientation_code(volume->axes), "PIR");
    EXPECT_NEAR(volume->spacing.z, 1.25, 1e-9);
    expect_ch2_voxels(*volume, words);
}

TEST(DicomLoader, ObliqueSeriesKeepsItsDirections) {
    fixtures::TempDir dir;
    const auto words = fixtures::ch2_box(box_first, box_dims);
    SeriesSpec spec = ch2_spec();
    const double c = std::sqrt(3.0) / 2.0;
    spec.orientation = {c, 0.5, 0, -0.5, c, 0};  // axial, turned 30 degrees about z
    fixtures::write_series(dir / "oblique", spec, words);
    auto volume = load_volume(dir / "oblique");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    expect_axes(*volume, {-c, -0.5, 0}, {0.5, -c, 0}, {0, 0, 1});
    EXPECT_EQ(orientation_code(volume->axes), "LPS");
}

// Slices of a gantry-tilted CT step along the table, not along their normal: the volume is
// sheared. Here each slice of the ch2 head is acquired one row further along its columns than the
// one before (a tilt of atan(0.5 / 1.25), 21.8 degrees), so the tilted series holds the same
// anatomy as an untilted one of the same rows: resampled onto an orthogonal grid it must equal
// that untilted series voxel for voxel where both hold voxels, at the same place in space.
TEST(DicomLoader, AGantryTiltedSeriesIsResampledOntoTheAnatomyOfItsUntiltedOriginal) {
    fixtures::TempDir dir;
    const glm::uvec3 untilted_dims{box_dims.x, box_dims.y + box_dims.z - 1, box_dims.z};
    const auto untilted_words = fixtures::ch2_box(box_first, untilted_dims);
    std::vector<std::uint16_t> tilted_words;
    for (std::uint32_t z = 0; z < box_dims.z; ++z) {
        for (std::uint32_t y = 0; y < box_dims.y; ++y) {
            for (std::uint32_t x = 0; x < box_dims.x; ++x) {
                tilted_words.push_back(untilted_words[(std::size_t{z} * untilted_dims.y + y + z) *
                                                              untilted_dims.x +
                                                      x]);
            }
        }
    }
    SeriesSpec untilted = ch2_spec();
    untilted.dims = untilted_dims;
    fixtures::write_series(dir / "untilted", untilted, untilted_words);
    SeriesSpec tilted = ch2_spec();
    const double row = tilted.spacing.y;
    const double slice = tilted.spacing.z;
    const double first_z = tilted.origin.z;
    tilted.edit = [row, slice, first_z](DcmDataset& dataset) {
        OFString text;
        ASSERT_TRUE(dataset.findAndGetOFStringArray(DCM_ImagePositionPatient, text).good());
        double x = 0, y = 0, z = 0;
        ASSERT_EQ(std::sscanf(text.c_str(), "%lf\\%lf\\%lf", &x, &y, &z), 3);
        const double shifted = y + row * (z - first_z) / slice;  // one row per slice
        char position[96];
        std::snprintf(position, sizeof position, "%.6f\\%.6f\\%.6f", x, shifted, z);
        ASSERT_TRUE(dataset.putAndInsertString(DCM_ImagePositionPatient, position).good());
    };
    fixtures::write_series(dir / "tilted", tilted, tilted_words);

    auto reference = load_volume(dir / "untilted");
    auto volume = load_volume(dir / "tilted");
    ASSERT_TRUE(reference.ok()) << reference.error().to_string();
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    ASSERT_FALSE(volume->notes.empty());
    EXPECT_TRUE(contains(volume->notes.back(), "gantry tilt")) << volume->notes.back();
    ASSERT_EQ(volume->dims, reference->dims);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(volume->spacing[a], reference->spacing[a], 1e-6);
        EXPECT_NEAR(volume->origin[a], reference->origin[a], 1e-4);
        EXPECT_NEAR(glm::dot(volume->axes[a], reference->axes[a]), 1.0, 1e-9);
    }
    std::size_t compared = 0;
    std::size_t differing = 0;
    for (std::uint32_t z = 0; z < volume->dims.z; ++z) {
        for (std::uint32_t y = 0; y < volume->dims.y; ++y) {
            const bool acquired = y >= z && y < z + box_dims.y;
            for (std::uint32_t x = 0; x < volume->dims.x; ++x) {
                const double want = acquired ? reference->value(x, y, z) : volume->range.min;
                if (volume->value(x, y, z) != want && ++differing <= 3) {
                    ADD_FAILURE() << "voxel " << x << "," << y << "," << z << " is "
                                  << volume->value(x, y, z) << ", expected " << want
                                  << (acquired ? "" : " (outside the tilted slices)");
                }
                compared += acquired ? 1 : 0;
            }
        }
    }
    EXPECT_EQ(differing, 0u);
    EXPECT_EQ(compared, tilted_words.size());
}

}  // namespace
}  // namespace penumbra::volume
