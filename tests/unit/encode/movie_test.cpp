// Movies as a player reads them: the MP4 that MovieWriter writes is opened with libavformat and
// decoded with libavcodec (read_movie), frame by frame, against the frames given.

#include "movie_reader.hpp"
#include "moving_square.hpp"

#include <penumbra/encode/movie.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace penumbra::encode {
namespace {

namespace fs = std::filesystem;
using test::read_movie;
using test::ReadMovie;

class MovieTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra_movie_" +
                std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }

    void TearDown() override { fs::remove_all(dir_); }

    fs::path dir_;
};

TEST_F(MovieTest, AnMp4HoldsEveryFrameAtItsSizeAndRateAsGiven) {
    const fs::path path = dir_ / "square.mp4";
    auto writer = MovieWriter::create(path, 64, 48, {.frames_per_second = 24, .quality = 18});
    ASSERT_TRUE(writer.ok()) << writer.error().to_string();
    constexpr int frames = 12;
    for (int k = 0; k < frames; ++k) {
        ASSERT_TRUE(writer->add(moving_square(64, 48, k)).ok());
    }
    ASSERT_TRUE(writer->finish().ok());
    EXPECT_EQ(writer->frames(), frames);
    EXPECT_FALSE(writer->add(moving_square(64, 48, 0)).ok()) << "nothing after finish";

    const ReadMovie movie = read_movie(path);
    EXPECT_EQ(movie.codec, "h264");
    EXPECT_EQ(movie.width, 64);
    EXPECT_EQ(movie.height, 48);
    EXPECT_NEAR(movie.frames_per_second, 24.0, 1e-6);
    ASSERT_EQ(movie.frames.size(), std::size_t(frames));
    for (int k = 0; k < frames; ++k) {
        // In their order: each frame is nearest the frame given at its place.
        const double own = psnr(movie.frames[k], moving_square(64, 48, k));
        EXPECT_GT(own, 26.0) << "frame " << k;  // 4:2:0 blurs the square's coloured edges
        if (k > 0) {
            EXPECT_GT(own, psnr(movie.frames[k], moving_square(64, 48, k - 1)) + 3.0)
                    << "frame " << k;
        }
    }
}

TEST_F(MovieTest, AMovieMadeInMemoryIsTheSameMp4AndKeepsToItsLimit) {
    constexpr int frames = 8;
    auto in_memory = MovieWriter::create_in_memory(64, 48, {.frames_per_second = 24, .quality = 18},
                                                   std::size_t{1} << 20);
    ASSERT_TRUE(in_memory.ok()) << in_memory.error().to_string();
    auto in_file = MovieWriter::create(dir_ / "file.mp4", 64, 48,
                                       {.frames_per_second = 24, .quality = 18});
    ASSERT_TRUE(in_file.ok());
    EXPECT_TRUE(in_memory->take_bytes().empty()) << "nothing before finish";
    for (int k = 0; k < frames; ++k) {
        ASSERT_TRUE(in_memory->add(moving_square(64, 48, k)).ok());
        ASSERT_TRUE(in_file->add(moving_square(64, 48, k)).ok());
    }
    ASSERT_TRUE(in_memory->finish().ok());
    ASSERT_TRUE(in_file->finish().ok());
    const std::vector<std::uint8_t> bytes = in_memory->take_bytes();
    ASSERT_FALSE(bytes.empty());
    EXPECT_EQ(bytes.size(), fs::file_size(dir_ / "file.mp4")) << "the index points back alike";
    {
        std::ofstream(dir_ / "memory.mp4", std::ios::binary)
                .write(reinterpret_cast<const char*>(bytes.data()),
                       static_cast<std::streamsize>(bytes.size()));
    }
    const ReadMovie movie = read_movie(dir_ / "memory.mp4");
    EXPECT_EQ(movie.width, 64);
    EXPECT_EQ(movie.height, 48);
    ASSERT_EQ(movie.frames.size(), std::size_t(frames));
    for (int k = 0; k < frames; ++k) {
        EXPECT_GT(psnr(movie.frames[k], moving_square(64, 48, k)), 26.0) << "frame " << k;
    }

    // A movie larger than its limit fails as too large, however far it got.
    auto small = MovieWriter::create_in_memory(64, 48, {.quality = 0}, 2048);
    ASSERT_TRUE(small.ok());
    base::Status status = base::Ok{};
    for (int k = 0; k < frames && status.ok(); ++k) {
        status = small->add(moving_square(64, 48, k));
    }
    if (status.ok()) {
        status = small->finish();
    }
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, base::ErrorCode::too_large) << status.error().to_string();
    EXPECT_TRUE(small->take_bytes().empty());
}

TEST_F(MovieTest, BadSizesRatesQualitiesAndFramesAreRefused) {
    const auto refused = [&](const fs::path& path, int width, int height, MovieOptions options) {
        auto writer = MovieWriter::create(path, width, height, options);
        return !writer.ok() && writer.error().code == base::ErrorCode::invalid_argument;
    };
    EXPECT_TRUE(refused(dir_ / "odd.mp4", 63, 48, {}));
    EXPECT_TRUE(refused(dir_ / "huge.mp4", 16384, 48, {}));
    EXPECT_TRUE(refused(dir_ / "movie.avi", 64, 48, {}));
    EXPECT_TRUE(refused(dir_ / "rate.mp4", 64, 48, {.frames_per_second = 0}));
    EXPECT_TRUE(refused(dir_ / "quality.mp4", 64, 48, {.quality = 52}));
    auto unwritable = MovieWriter::create(dir_ / "no" / "such" / "dir.mp4", 64, 48);
    ASSERT_FALSE(unwritable.ok());
    EXPECT_EQ(unwritable.error().code, base::ErrorCode::encode_failed);
    auto writer = MovieWriter::create(dir_ / "sizes.mp4", 64, 48);
    ASSERT_TRUE(writer.ok());
    auto wrong = writer->add(moving_square(48, 64, 0));
    ASSERT_FALSE(wrong.ok());
    EXPECT_NE(wrong.error().message.find("48x64"), std::string::npos) << wrong.error().message;
}

}  // namespace
}  // namespace penumbra::encode
