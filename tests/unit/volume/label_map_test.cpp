// Label maps from the atlases of Debian's mricron-data (part of the install step): ids turned into
// indices as nibabel reads the same files, the checks that refuse what is no label map, and the
// overlap a label map must have with its scan.

#include "fixture_files.hpp"

#include <penumbra/volume/label_map.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

namespace penumbra::volume {
namespace {

const std::filesystem::path templates = "/usr/share/mricron/templates";

std::uint16_t index_at(const Volume& indices, glm::uvec3 voxel) {
    const std::size_t i =
            voxel.x + static_cast<std::size_t>(indices.dims.x) *
                              (voxel.y + static_cast<std::size_t>(indices.dims.y) * voxel.z);
    if (indices.type == VoxelType::uint8) {
        return std::to_integer<std::uint8_t>(indices.data[i]);
    }
    std::uint16_t index = 0;
    std::memcpy(&index, indices.data.data() + 2 * i, 2);
    return index;
}

TEST(LabelMap, AalKeepsItsIdsAsIndicesWithItsNamesAndGrid) {
    auto aal = load_label_map(templates / "aal.nii.gz");
    ASSERT_TRUE(aal.ok()) << aal.error().to_string();
    ASSERT_EQ(aal->labels.size(), 116U);  // ids 1..116 and the background, 0
    EXPECT_TRUE(aal->warnings.empty());
    EXPECT_EQ(aal->indices.type, VoxelType::uint8);
    EXPECT_EQ(aal->indices.dims, glm::uvec3(181, 217, 181));
    EXPECT_TRUE(aal->indices.label_intent);
    EXPECT_EQ(aal->labels[44].id, 45);
    EXPECT_EQ(aal->labels[44].name, "Cuneus_L");
    EXPECT_EQ(aal->voxels[0], 28174U);
    auto stored = load_volume(templates / "aal.nii.gz");
    ASSERT_TRUE(stored.ok());
    EXPECT_TRUE(stored->label_intent);  // NIfTI intent_code 1002
    EXPECT_EQ(aal->indices.origin, stored->origin);
    EXPECT_EQ(aal->indices.axes, stored->axes);
    for (std::size_t i = 0; i < stored->voxel_count(); i += 997) {
        ASSERT_EQ(std::to_integer<int>(aal->indices.data[i]), std::to_integer<int>(stored->data[i]))
                << "voxel " << i;
    }
}

TEST(LabelMap, SparseSixteenBitIdsBecomeConsecutiveIndices) {
    // inia19-NeuroMaps: int16 ids up to 1605, 724 labels besides the background (nibabel).
    auto inia = load_label_map(templates / "inia19-NeuroMaps.nii.gz");
    ASSERT_TRUE(inia.ok()) << inia.error().to_string();
    ASSERT_EQ(inia->labels.size(), 724U);
    EXPECT_EQ(inia->indices.type, VoxelType::uint16);
    EXPECT_EQ(inia->labels.back().id, 1605);
    EXPECT_EQ(inia->labels.back().name, "label 1605");      // no names file beside it
    EXPECT_EQ(index_at(inia->indices, {92, 80, 30}), 724);  // id 1605
    EXPECT_EQ(inia->labels[99].id, 115);
    EXPECT_EQ(inia->voxels[99], 14U);
    EXPECT_EQ(index_at(inia->indices, {68, 88, 51}), 100);  // id 115
    EXPECT_EQ(index_at(inia->indices, {0, 0, 0}), 0);
}

TEST(LabelMap, FloatVolumesAndFilesOfSeveralVolumesAreRefused) {
    auto values = make_volume("float", {2, 2, 2}, glm::dvec3(1.0), std::vector<float>(8, 1.0f));
    ASSERT_TRUE(values.ok());
    auto refused = make_label_map(*values, {});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::invalid_volume);
    EXPECT_NE(refused.error().message.find("integer ids"), std::string::npos);

    auto ids = make_volume("probabilistic", {2, 2, 2}, glm::dvec3(1.0), VoxelType::uint8,
                           std::vector<std::byte>(8, std::byte{3}));
    ASSERT_TRUE(ids.ok());
    ids->volumes_in_file = 48;
    refused = make_label_map(*ids, {});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::unsupported_dimension);
    EXPECT_NE(refused.error().message.find("48"), std::string::npos);
}

TEST(LabelMap, NamedLabelsTheVolumeLacksAreLeftOutWithAWarning) {
    auto ids = make_volume("two", {2, 1, 1}, glm::dvec3(1.0), VoxelType::uint8,
                           std::vector<std::byte>{std::byte{0}, std::byte{7}});
    ASSERT_TRUE(ids.ok());
    LabelNames names;
    names.labels = {{7, "seven", {1, 2, 3}}, {8, "eight", {4, 5, 6}}};
    auto map = make_label_map(*ids, names);
    ASSERT_TRUE(map.ok()) << map.error().to_string();
    ASSERT_EQ(map->labels.size(), 1U);
    EXPECT_EQ(map->labels[0].name, "seven");
    EXPECT_EQ(map->labels[0].color, glm::u8vec3(1, 2, 3));
    ASSERT_EQ(map->warnings.size(), 1U);
    EXPECT_NE(map->warnings[0].find("1 named label"), std::string::npos);
    EXPECT_EQ(std::to_integer<int>(map->indices.data[1]), 1);
}

TEST(LabelMap, AnAtlasOnAnotherGridOverlapsItsHeadAndOneMovedAwayDoesNot) {
    auto ch2 = load_volume(templates / "ch2.nii.gz");
    auto harvard_oxford = load_label_map(templates / "HarvardOxford-cort-maxprob-thr0-1mm.nii.gz");
    ASSERT_TRUE(ch2.ok() && harvard_oxford.ok());
    EXPECT_FALSE(ch2->label_intent);
    EXPECT_TRUE(check_overlap(*ch2, harvard_oxford->indices).ok());
    harvard_oxford->indices.origin.z += 500.0;
    const auto status = check_overlap(*ch2, harvard_oxford->indices);
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, base::ErrorCode::no_overlap);
    EXPECT_NE(status.error().message.find("share no part of patient space"), std::string::npos)
            << status.error().message;
}

// AAL's voxels of Precentral_L (1) and Cuneus_L (45), the rest background, written as 3D Slicer
// writes a segmentation (labelmap form, LPS, gzip) with `segments` as its header's keys.
std::filesystem::path write_seg_nrrd(const fixtures::TempDir& dir, const Volume& aal,
                                     const std::string& segments) {
    std::vector<std::byte> voxels = aal.data;
    for (std::byte& v : voxels) {
        const int id = std::to_integer<int>(v);
        v = id == 1 || id == 45 ? v : std::byte{0};
    }
    char geometry[256];
    std::snprintf(geometry, sizeof geometry,
                  "sizes: %u %u %u\nspace directions: (-%g,0,0) (0,-%g,0) (0,0,%g)\n"
                  "space origin: (%g,%g,%g)\n",
                  aal.dims.x, aal.dims.y, aal.dims.z, aal.spacing.x, aal.spacing.y, aal.spacing.z,
                  -aal.origin.x, -aal.origin.y, aal.origin.z);
    const std::string header = std::string(
                                       "NRRD0004\ntype: unsigned char\ndimension: 3\n"
                                       "space: left-posterior-superior\n") +
                               geometry +
                               "kinds: domain domain domain\nencoding: gzip\n"
                               "Segmentation_MasterRepresentation:=Binary labelmap\n" +
                               segments + "\n";
    const auto path = dir / "aal_two.seg.nrrd";
    fixtures::write_bytes(
            path, fixtures::concat(fixtures::text_bytes(header), fixtures::gzip_bytes(voxels)));
    return path;
}

TEST(LabelMap, SlicerSegmentationsAreNamedByTheirSegmentKeys) {
    auto aal = load_volume(templates / "aal.nii.gz");
    ASSERT_TRUE(aal.ok());
    const fixtures::TempDir dir;
    // The keys as Slicer's documentation lists them (Segment0_Color as fractions, Layer, ...).
    const auto path = write_seg_nrrd(dir, *aal,
                                     "Segment0_Color:=0.501961 0.682353 0.501961\n"
                                     "Segment0_ColorAutoGenerated:=1\n"
                                     "Segment0_Extent:=0 180 0 216 0 180\n"
                                     "Segment0_ID:=Segment_1\n"
                                     "Segment0_LabelValue:=1\n"
                                     "Segment0_Layer:=0\n"
                                     "Segment0_Name:=Precentral_L\n"
                                     "Segment0_Tags:=TerminologyEntry:Segmentation category\n"
                                     "Segment1_Color:=0.945098 0.839216 0.568627\n"
                                     "Segment1_ID:=Segment_2\n"
                                     "Segment1_LabelValue:=45\n"
                                     "Segment1_Layer:=0\n"
                                     "Segment1_Name:=Cuneus_L\n");
    auto map = load_label_map(path);
    ASSERT_TRUE(map.ok()) << map.error().to_string();
    ASSERT_EQ(map->labels.size(), 2U);
    EXPECT_EQ(map->labels[0].id, 1);
    EXPECT_EQ(map->labels[0].name, "Precentral_L");
    EXPECT_EQ(map->labels[0].color, glm::u8vec3(128, 174, 128));
    EXPECT_EQ(map->labels[1].id, 45);
    EXPECT_EQ(map->labels[1].name, "Cuneus_L");
    EXPECT_EQ(map->labels[1].color, glm::u8vec3(241, 214, 145));
    EXPECT_EQ(map->voxels[0], 28174U);  // as the AAL file's own count
    // The same patient space as the NIfTI it came from, though stored LPS.
    EXPECT_LT(glm::length(map->indices.origin - aal->origin), 1e-6);
    EXPECT_EQ(map->indices.axes, aal->axes);

    // Segments on a second layer overlap: refused, saying what to do.
    const auto layered = write_seg_nrrd(dir, *aal,
                                        "Segment0_LabelValue:=1\nSegment0_Layer:=0\n"
                                        "Segment1_LabelValue:=1\nSegment1_Layer:=1\n");
    auto refused = load_label_map(layered);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::unsupported_dimension);
    EXPECT_NE(refused.error().message.find("export them to a labelmap"), std::string::npos);
}

// What a listing offers as label maps: the files that say they are, read from their headers and
// the files beside them. The templates' intents are nibabel's reading (intent_code 1002 for every
// atlas, 0 for the scans).
TEST(LabelMap, FilesThatSayTheyAreLabelMapsAreTold) {
    for (const char* atlas :
         {"aal.nii.gz", "brodmann.nii.gz", "AICHAmc.nii.gz", "JHU-WhiteMatter-labels-1mm.nii.gz",
          "HarvardOxford-cort-maxprob-thr0-1mm.nii.gz", "inia19-NeuroMaps.nii.gz", "jhu189.nii.gz",
          "natbrainlab.nii.gz"}) {
        const auto declared = declares_labels(templates / atlas);
        ASSERT_TRUE(declared.ok()) << atlas;
        EXPECT_TRUE(*declared) << atlas;
    }
    for (const char* scan :
         {"ch2.nii.gz", "ch2bet.nii.gz", "ch2better.nii.gz", "inia19-t1-brain.nii.gz"}) {
        const auto declared = declares_labels(templates / scan);
        ASSERT_TRUE(declared.ok()) << scan;
        EXPECT_FALSE(*declared) << scan;
    }
    // A scan with MRIcron's names beside it is one; a NRRD says so by its segments.
    auto aal = load_volume(templates / "aal.nii.gz");
    ASSERT_TRUE(aal.ok());
    const fixtures::TempDir dir;
    std::filesystem::copy_file(templates / "ch2.nii.gz", dir / "ch2.nii.gz");
    EXPECT_FALSE(*declares_labels(dir / "ch2.nii.gz"));
    fixtures::write_text(dir / "ch2.nii.txt", "1 Grey\n");
    EXPECT_TRUE(*declares_labels(dir / "ch2.nii.gz"));
    EXPECT_TRUE(*declares_labels(write_seg_nrrd(dir, *aal, "Segment0_LabelValue:=1\n")));
    EXPECT_FALSE(*declares_labels(write_seg_nrrd(dir, *aal, "")));
    // A header that cannot be read is an error, not a scan.
    fixtures::write_text(dir / "broken.nii.gz", "not gzip");
    EXPECT_FALSE(declares_labels(dir / "broken.nii.gz").ok());
}

// Labels alone as surfaces: the indicator is the visible labels' mask filtered 1 4 6 4 1 along each
// axis (a box's is a product of three sums of those weights), a hidden label adds nothing, and the
// voxels of no visible label within two of one (the background, a hidden label's beside it) take
// its index, nearest first.
TEST(LabelMap, LabelSurfacesFilterTheVisibleLabelsAndCarryTheirColoursOutward) {
    constexpr unsigned n = 10;
    std::vector<std::byte> ids(n * n * n);
    const auto at = [&](unsigned x, unsigned y, unsigned z) -> std::byte& {
        return ids[x + n * (y + n * z)];
    };
    for (unsigned z = 3; z <= 6; ++z) {
        for (unsigned y = 3; y <= 6; ++y) {
            for (unsigned x = 3; x <= 6; ++x) {
                at(x, y, z) = std::byte{4};  // a box, voxels 3..6 on each axis
            }
        }
    }
    at(0, 9, 9) = std::byte{7};
    at(2, 4, 4) = std::byte{7};  // the hidden label touching the box
    auto stored = make_volume("two", glm::uvec3(n), glm::dvec3(1.0), VoxelType::uint8, ids);
    ASSERT_TRUE(stored.ok());
    auto map = make_label_map(*stored, {});
    ASSERT_TRUE(map.ok());
    ASSERT_EQ(map->labels.size(), 2U);  // ids 4 and 7: indices 1 and 2
    EXPECT_FALSE(label_surfaces(*map, {true}).ok());
    auto surfaces = label_surfaces(*map, {true, false});
    ASSERT_TRUE(surfaces.ok()) << surfaces.error().to_string();
    const Volume& indicator = surfaces->indicator;
    EXPECT_EQ(indicator.range.min, 0.0);
    EXPECT_EQ(indicator.range.max, 255.0);
    // The weights of one axis that fall on the box's voxels 3..6 around voxel i.
    const auto along = [](int i) {
        const int weights[5] = {1, 4, 6, 4, 1};
        int sum = 0;
        for (int d = -2; d <= 2; ++d) {
            sum += i + d >= 3 && i + d <= 6 ? weights[d + 2] : 0;
        }
        return sum;
    };
    for (const glm::ivec3 v : {glm::ivec3(4, 4, 4), glm::ivec3(3, 5, 6), glm::ivec3(2, 4, 4),
                               glm::ivec3(1, 1, 8), glm::ivec3(0, 9, 9), glm::ivec3(8, 8, 8)}) {
        const unsigned expected = (along(v.x) * along(v.y) * along(v.z) * 255U + 2048U) / 4096U;
        EXPECT_EQ(indicator.value(v.x, v.y, v.z), expected) << v.x << "," << v.y << "," << v.z;
    }
    EXPECT_EQ(indicator.value(0, 9, 9), 0.0) << "the hidden label is no surface";
    const Volume& coloured = surfaces->labels.indices;
    EXPECT_EQ(index_at(coloured, {2, 4, 4}), 1);  // a face away, of the hidden label
    EXPECT_EQ(index_at(coloured, {1, 4, 4}), 1);  // two
    EXPECT_EQ(index_at(coloured, {7, 7, 7}), 1);  // a corner away
    EXPECT_EQ(index_at(coloured, {8, 8, 8}), 1);  // two corners
    EXPECT_EQ(index_at(coloured, {0, 4, 4}), 0);  // beyond the filter's reach
    EXPECT_EQ(index_at(coloured, {0, 9, 9}), 2);  // the hidden label keeps its own voxel
    EXPECT_EQ(index_at(coloured, {4, 4, 4}), 1);
    EXPECT_EQ(surfaces->labels.labels.size(), 2U);
}

TEST(LabelMap, ItkSnapAndFreeSurferDescriptionsNameTheLabels) {
    const fixtures::TempDir dir;
    const auto names = dir / "aal_labels.txt";
    fixtures::write_text(names,
                         "################################################\n"
                         "# ITK-SnAP Label Description File\n"
                         "# IDX   -R-  -G-  -B-  -A--  VIS MSH  LABEL\n"
                         "################################################\n"
                         "    0     0    0    0        0  0  0    \"Clear Label\"\n"
                         "    1   255    0    0     0.5  1  1    \"Precentral L\"\n"
                         "   45     0  128  255       1  0  1    \"Cuneus L\"\n"
                         "   46   oops\n"
                         "   47   10 20 30 0 Occipital_Sup_L\n"  // not ITK-SNAP, not FreeSurfer
                         "Occipital_Sup_R 1 2 3\n");
    auto map = load_label_map(templates / "aal.nii.gz", {}, names);
    ASSERT_TRUE(map.ok()) << map.error().to_string();
    ASSERT_EQ(map->labels.size(), 116U);
    EXPECT_EQ(map->labels[0].name, "Precentral L");
    EXPECT_EQ(map->labels[0].color, glm::u8vec3(255, 0, 0));
    EXPECT_DOUBLE_EQ(map->labels[0].opacity, 0.5);
    EXPECT_TRUE(map->labels[0].visible);
    EXPECT_EQ(map->labels[44].name, "Cuneus L");
    EXPECT_FALSE(map->labels[44].visible);
    EXPECT_EQ(map->labels[1].name, "label 2");  // named by neither file: MRIcron's is not read
    ASSERT_EQ(map->warnings.size(), 3U);
    EXPECT_NE(map->warnings[0].find("aal_labels.txt line 8"), std::string::npos)
            << map->warnings[0];

    const auto lut = dir / "FreeSurferColorLUT.txt";
    fixtures::write_text(lut,
                         "#No. Label Name:                R   G   B   A\n"
                         "0   Unknown                     0   0   0   0\n"
                         "2   Left-Cerebral-White-Matter  245 245 245 0\n");
    auto freesurfer = read_label_description(lut);
    ASSERT_TRUE(freesurfer.ok());
    ASSERT_EQ(freesurfer->labels.size(), 2U);
    EXPECT_EQ(freesurfer->labels[1].name, "Left-Cerebral-White-Matter");
    EXPECT_EQ(freesurfer->labels[1].color, glm::u8vec3(245, 245, 245));
    EXPECT_DOUBLE_EQ(freesurfer->labels[1].opacity, 1.0);
    EXPECT_TRUE(freesurfer->warnings.empty());
}

TEST(LabelMap, DicomIsRefusedSayingWhy) {
    const fixtures::TempDir dir;  // a folder: a DICOM series
    auto refused = load_label_map(dir.path());
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::unsupported_format);
    EXPECT_NE(refused.error().message.find("DICOM SEG"), std::string::npos);
}

// Names come from files and reach JSON: bytes that are not UTF-8 become '?', a long name is cut
// at a whole character; a map of background alone is no label map; negative ids get a colour.
TEST(LabelMap, NamesAreValidUtf8AndAMapNeedsALabel) {
    auto ids = make_volume("ids", {3, 1, 1}, glm::dvec3(1.0), VoxelType::int16,
                           std::vector<std::byte>{std::byte{0}, std::byte{0}, std::byte{0xFE},
                                                  std::byte{0xFF}, std::byte{7}, std::byte{0}});
    ASSERT_TRUE(ids.ok());
    LabelNames names;
    names.labels = {{-2, "Caf\xe9 noir", {1, 2, 3}},
                    {7, std::string(300, 'a') + "\xc3\xa9", {4, 5, 6}}};
    auto map = make_label_map(*ids, names);
    ASSERT_TRUE(map.ok()) << map.error().to_string();
    ASSERT_EQ(map->labels.size(), 2U);
    EXPECT_EQ(map->labels[0].id, -2);
    EXPECT_EQ(map->labels[0].name, "Caf? noir");
    EXPECT_EQ(map->labels[1].name, std::string(256, 'a'));
    EXPECT_TRUE(map->named);
    EXPECT_NE(label_color(-2), glm::u8vec3(0));
    EXPECT_NE(label_color(-32768), label_color(-32767));

    auto background = make_volume("empty", {2, 1, 1}, glm::dvec3(1.0), VoxelType::uint8,
                                  std::vector<std::byte>(2, std::byte{0}));
    ASSERT_TRUE(background.ok());
    auto refused = make_label_map(*background, {});
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("needs a label"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::volume
