// Label maps from the atlases of Debian's mricron-data (part of the install step): ids turned into
// indices as nibabel reads the same files, the checks that refuse what is no label map, and the
// overlap a label map must have with its scan.

#include <penumbra/volume/label_map.hpp>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace penumbra::volume
