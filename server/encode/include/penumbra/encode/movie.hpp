#pragma once

// Movies to keep (a turntable of the view): frames of one size encoded as H.264 with libavcodec's
// libx264 into an MP4 file with libavformat, the form every player and browser opens.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

namespace penumbra::encode {

// x264's constant rate factors a movie may be written at: 0 lossless .. 51; 23 is x264's default,
// about 18 looks like the frames themselves.
inline constexpr int kMinMovieQuality = 0;
inline constexpr int kMaxMovieQuality = 51;

// Whether this build writes movies: one without FFmpeg's libraries (PENUMBRA_WITH_FFMPEG=OFF, the
// portable bundle) does not, and MovieWriter::create says so.
[[nodiscard]] bool writes_movies();

struct MovieOptions {
    int frames_per_second = 30;
    int quality = 20;  // x264's constant rate factor (kMinMovieQuality..kMaxMovieQuality)
    // x264's threads (0: its own choice, about 1.5 a core) and frames it looks ahead (-1: the
    // preset's, 40): a server that makes movies beside its sessions' frames holds both down.
    int threads = 0;
    int lookahead_frames = -1;
};

class MovieWriter {
public:
    // Opens `path` (an .mp4) for frames of width x height, each even (4:2:0 chroma halves both)
    // and at most 8192. Errors: invalid_argument for a size, rate or quality out of range or
    // another extension, encode_failed where libavcodec has no H.264 encoder or the file cannot
    // be written.
    static base::Result<MovieWriter> create(const std::filesystem::path& path, int width,
                                            int height, const MovieOptions& options = {});
    // The same movie held in memory (take_bytes() once finished), for a server that hands it out:
    // at most `max_bytes`, beyond which add and finish fail with too_large.
    static base::Result<MovieWriter> create_in_memory(int width, int height,
                                                      const MovieOptions& options,
                                                      std::size_t max_bytes);

    MovieWriter(MovieWriter&&) noexcept;
    MovieWriter& operator=(MovieWriter&&) noexcept;
    // Closes the file; unless finished, what it holds is no complete movie.
    ~MovieWriter();

    // Encodes the next frame (RGBA, of the movie's size; alpha is ignored).
    base::Status add(const base::ImageRgba8& frame);

    // Encodes what the encoder still holds and completes the file. Nothing may be added after.
    base::Status finish();

    [[nodiscard]] int frames() const;

    // The finished MP4 of a movie made in memory, handed over (empty for a file, and before
    // finish).
    [[nodiscard]] std::vector<std::uint8_t> take_bytes();

private:
    struct Impl;
    explicit MovieWriter(std::unique_ptr<Impl> impl);
    // Into `path`, or into memory of at most `max_bytes_in_memory`.
    static base::Result<MovieWriter> open(const std::filesystem::path& path,
                                          std::optional<std::size_t> max_bytes_in_memory, int width,
                                          int height, const MovieOptions& options);
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::encode
