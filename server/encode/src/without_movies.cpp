// A build without FFmpeg's libraries (PENUMBRA_WITH_MOVIES=OFF: the portable bundle, the container
// image) writes no movies and says so.

#include <penumbra/encode/movie.hpp>

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
                            "libraries (PENUMBRA_WITH_MOVIES=OFF, as the portable bundle and the "
                            "container image are)",
                            "movie");
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

}  // namespace penumbra::encode
