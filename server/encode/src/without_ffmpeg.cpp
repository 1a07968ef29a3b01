// A build without FFmpeg's libraries (PENUMBRA_WITH_FFMPEG=OFF: the portable bundle, the container
// image) writes no movies and decodes no streams, and says so.

#include <penumbra/encode/movie.hpp>
#include <penumbra/encode/stream.hpp>

namespace penumbra::encode {

struct MovieWriter::Impl {};

MovieWriter::MovieWriter(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

MovieWriter::MovieWriter(MovieWriter&&) noexcept = default;
MovieWriter& MovieWriter::operator=(MovieWriter&&) noexcept = default;
MovieWriter::~MovieWriter() = default;

base::Result<MovieWriter> MovieWriter::create(const std::filesystem::path&, int, int,
                                              const MovieOptions&) {
    return base::make_error(base::ErrorCode::unsupported_format,
                            "this build writes no movies: it was built without FFmpeg's "
                            "libraries (PENUMBRA_WITH_FFMPEG=OFF, as the portable bundle and the "
                            "container image are)",
                            "movie");
}

base::Result<MovieWriter> MovieWriter::create_in_memory(int, int, const MovieOptions&,
                                                        std::size_t) {
    return create("movie.mp4", 0, 0, {}).error();
}

bool writes_movies() {
    return false;
}

base::Status MovieWriter::add(const base::ImageRgba8&) {
    return base::make_error(base::ErrorCode::unsupported_format, "this build writes no movies",
                            "movie");
}

base::Status MovieWriter::finish() {
    return add({});
}

int MovieWriter::frames() const {
    return 0;
}

std::vector<std::uint8_t> MovieWriter::take_bytes() {
    return {};
}

struct StreamDecoder::Impl {};

StreamDecoder::StreamDecoder(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

StreamDecoder::StreamDecoder(StreamDecoder&&) noexcept = default;
StreamDecoder& StreamDecoder::operator=(StreamDecoder&&) noexcept = default;
StreamDecoder::~StreamDecoder() = default;

base::Result<StreamDecoder> StreamDecoder::create() {
    return base::make_error(base::ErrorCode::unsupported_format,
                            "this build decodes no H.264: it was built without FFmpeg's libraries "
                            "(PENUMBRA_WITH_FFMPEG=OFF)",
                            "h264");
}

base::Result<base::ImageRgba8> StreamDecoder::decode(std::span<const std::uint8_t>) {
    return create().error();
}

}  // namespace penumbra::encode
