#include "dicom_writer.hpp"

#include <penumbra/session/volume_store.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace penumbra::session {
namespace {

namespace fs = std::filesystem;

class VolumeStoreTest : public ::testing::Test {
protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "penumbra-store-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        data_ = pattern;
    }

    void TearDown() override {
        std::error_code ec;
        fs::remove_all(data_, ec);
    }

    void write_text(const fs::path& path, const std::string& text) {
        fs::create_directories(path.parent_path());
        std::ofstream(path) << text;
    }

    void write_series(const fs::path& folder, glm::uvec3 dims) {
        volume::fixtures::SeriesSpec spec;
        spec.dims = dims;
        volume::fixtures::write_series(folder, spec,
                                       std::vector<std::uint16_t>(dims.x * dims.y * dims.z, 7));
    }

    std::vector<std::string> ids(const VolumeStore& store) {
        std::vector<std::string> result;
        for (const auto& entry : store.list()) {
            result.push_back(entry.id);
        }
        return result;
    }

    fs::path data_;
};

TEST_F(VolumeStoreTest, ADicomFolderIsOneVolumeAndItsFilesAreNotListed) {
    write_series(data_ / "patients" / "ct_head", {4, 4, 3});
    write_text(data_ / "patients" / "ct_head" / "README.txt", "exported");
    write_series(data_ / "mr", {4, 4, 2});
    write_text(data_ / "mr" / "t1.nrrd", "a NIfTI or NRRD next to the series is its own volume");
    write_text(data_ / "notes" / "plan.txt", "not a volume");
    write_text(data_ / "heads" / "a_2x2x2_uint8.raw", "12345678");

    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"heads/a_2x2x2_uint8.raw", "mr", "mr/t1.nrrd",
                                                    "patients/ct_head"}));
    for (const auto& entry : store.list()) {
        if (entry.id == "patients/ct_head") {
            std::uintmax_t bytes = 0;
            for (const auto& file : fs::directory_iterator(data_ / "patients" / "ct_head")) {
                bytes += file.file_size();
            }
            EXPECT_EQ(entry.file_bytes, bytes);
        }
    }

    auto loaded = store.acquire("patients/ct_head");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
    EXPECT_EQ((*loaded)->dims, glm::uvec3(4, 4, 3));
    EXPECT_EQ((*loaded)->value(1, 2, 2), 7.0);
}

TEST_F(VolumeStoreTest, DicomFilesRightInTheDataFolderAreTheVolumeDot) {
    write_series(data_, {4, 4, 2});
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_EQ(ids(store), (std::vector<std::string>{"."}));
    auto loaded = store.acquire(".");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
    EXPECT_EQ((*loaded)->dims, glm::uvec3(4, 4, 2));
}

TEST_F(VolumeStoreTest, ALinkedFolderIsNotOffered) {
    const fs::path outside = data_.parent_path() / (data_.filename().string() + "-outside");
    write_series(outside, {4, 4, 2});
    fs::create_directory_symlink(outside, data_ / "link");
    VolumeStore store(data_, std::size_t{1} << 20);
    ASSERT_TRUE(store.scan().ok());
    EXPECT_TRUE(store.list().empty());
    fs::remove_all(outside);
}

}  // namespace
}  // namespace penumbra::session
