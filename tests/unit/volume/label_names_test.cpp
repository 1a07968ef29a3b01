// The names, colours and voxel counts of the atlases Debian's mricron-data ships beside the ch2
// head (part of the install step, so never skipped), against their files as Python's nibabel and
// a plain reading of the .nii.txt and .nii.lut give them.

#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/label_names.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

namespace penumbra::volume {
namespace {

const std::filesystem::path templates = "/usr/share/mricron/templates";

LabelNames read_beside(const std::string& atlas) {
    const auto files = find_mricron_labels(templates / atlas);
    EXPECT_TRUE(files.has_value()) << atlas << " (Debian package mricron-data)";
    if (!files) {
        return {};
    }
    auto names = read_mricron_labels(*files);
    EXPECT_TRUE(names.ok()) << names.error().to_string();
    return names.ok() ? std::move(names.value()) : LabelNames{};
}

TEST(LabelNames, AalNamesColoursAndVoxelCountsAreTheFilesOwn) {
    const LabelNames aal = read_beside("aal.nii.gz");
    // 116 lines of `id name code` with CRLF, and a blank line at the end.
    ASSERT_EQ(aal.labels.size(), 116U);
    EXPECT_TRUE(aal.warnings.empty());
    EXPECT_EQ(aal.labels[0].id, 1);
    EXPECT_EQ(aal.labels[0].name, "Precentral_L");
    EXPECT_EQ(aal.labels[0].color, glm::u8vec3(204, 204, 204));
    EXPECT_EQ(aal.labels[44].id, 45);
    EXPECT_EQ(aal.labels[44].name, "Cuneus_L");
    EXPECT_EQ(aal.labels[44].color, glm::u8vec3(54, 54, 203));  // planar: R[45], G[301], B[557]
    EXPECT_EQ(aal.labels.back().id, 116);

    auto volume = load_volume(templates / "aal.nii.gz");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    auto counts = count_labels(*volume);
    ASSERT_TRUE(counts.ok()) << counts.error().to_string();
    EXPECT_EQ(counts->size(), 117U);
    EXPECT_EQ(counts->at(0), 5629168U);
    EXPECT_EQ(counts->at(1), 28174U);
    EXPECT_EQ(counts->at(2), 27058U);

    auto map = make_label_map(*volume, aal);
    ASSERT_TRUE(map.ok());
    const std::string table = describe_labels(*map);
    EXPECT_NE(table.find("labels:      116"), std::string::npos) << table;
    EXPECT_NE(table.find("     1  #cccccc       28174  Precentral_L"), std::string::npos) << table;
    EXPECT_NE(table.find("background:  5629168 voxels"), std::string::npos) << table;
}

TEST(LabelNames, JhuNamesAreTabSeparatedWithABackgroundLabel) {
    const LabelNames jhu = read_beside("JHU-WhiteMatter-labels-2mm.nii.gz");
    ASSERT_EQ(jhu.labels.size(), 49U);
    EXPECT_EQ(jhu.labels[0].id, 0);
    EXPECT_EQ(jhu.labels[0].name, "Unclassified");
    EXPECT_EQ(jhu.labels.back().id, 48);
    EXPECT_EQ(jhu.labels.back().name, "Tapetum_L");
    auto volume = load_volume(templates / "JHU-WhiteMatter-labels-2mm.nii.gz");
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    auto counts = count_labels(*volume);
    ASSERT_TRUE(counts.ok());
    EXPECT_EQ(counts->at(0), 881511U);
    EXPECT_EQ(counts->at(1), 1898U);
}

TEST(LabelNames, AColourTableWithoutNamesIsNoLabelFile) {
    // Brodmann ships a .lut but no .nii.txt; ch2, a scan, neither.
    EXPECT_FALSE(find_mricron_labels(templates / "brodmann.nii.gz").has_value());
    EXPECT_FALSE(find_mricron_labels(templates / "ch2.nii.gz").has_value());
}

class LabelFilesTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() /
               ("penumbra_labels_" +
                std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir_);
    }

    void TearDown() override { std::filesystem::remove_all(dir_); }

    std::filesystem::path write(const std::string& name, const std::string& content) {
        const std::filesystem::path path = dir_ / name;
        std::ofstream(path, std::ios::binary) << content;
        return path;
    }

    std::filesystem::path dir_;
};

TEST_F(LabelFilesTest, BadLinesAreSkippedWithAWarningNamingThem) {
    write("atlas.nii.txt", "1 First\r\n\r\nnot-a-number Second\r\n3\r\n4 Fourth extra columns\r\n");
    const auto files = find_mricron_labels(dir_ / "atlas.nii");
    ASSERT_TRUE(files.has_value());
    EXPECT_FALSE(files->colors.has_value());
    auto names = read_mricron_labels(*files);
    ASSERT_TRUE(names.ok()) << names.error().to_string();
    ASSERT_EQ(names->labels.size(), 2U);
    EXPECT_EQ(names->labels[1].id, 4);
    EXPECT_EQ(names->labels[1].name, "Fourth");
    // Without a colour table every label has a colour of its own, and neighbours differ.
    EXPECT_EQ(names->labels[0].color, label_color(1));
    EXPECT_NE(label_color(1), label_color(2));
    ASSERT_EQ(names->warnings.size(), 2U);
    EXPECT_NE(names->warnings[0].find("line 3"), std::string::npos) << names->warnings[0];
    EXPECT_NE(names->warnings[1].find("line 4"), std::string::npos) << names->warnings[1];
}

TEST_F(LabelFilesTest, AColourTableOfTheWrongSizeIsRefused) {
    write("atlas.nii.txt", "1 First\n");
    write("atlas.nii.lut", std::string(767, '\x10'));
    const auto files = find_mricron_labels(dir_ / "atlas.nii.gz");
    ASSERT_TRUE(files.has_value());
    auto names = read_mricron_labels(*files);
    ASSERT_FALSE(names.ok());
    EXPECT_EQ(names.error().code, base::ErrorCode::bad_data);
    EXPECT_NE(names.error().message.find("767"), std::string::npos) << names.error().message;
}

TEST(LabelCounts, AFloatVolumeIsNoLabelMap) {
    auto volume = make_volume("float", glm::uvec3(2, 1, 1), glm::dvec3(1.0),
                              std::vector<float>{1.0f, 2.5f});
    ASSERT_TRUE(volume.ok()) << volume.error().to_string();
    auto counts = count_labels(*volume);
    ASSERT_FALSE(counts.ok());
    EXPECT_EQ(counts.error().code, base::ErrorCode::invalid_volume);
}

}  // namespace
}  // namespace penumbra::volume
