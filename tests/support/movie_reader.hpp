#pragma once

// A movie as a player reads it: an MP4 opened with libavformat and decoded with libavcodec, frame
// by frame, each frame turned back into RGBA (for the tests of what writes movies).

#include <penumbra/base/image.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::test {

struct ReadMovie {
    std::string codec;
    int width = 0;
    int height = 0;
    double frames_per_second = 0.0;
    std::vector<base::ImageRgba8> frames;
};

// Every frame of the movie in `path`; what cannot be read is a test failure.
ReadMovie read_movie(const std::filesystem::path& path);

}  // namespace penumbra::test
