#include <penumbra/encode/movie.hpp>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <array>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

namespace penumbra::encode {
namespace {

constexpr int kMaxMovieSide = 8192;

base::Error movie_error(const std::string& what, int code = 0) {
    std::string message = what;
    if (code < 0) {
        std::array<char, AV_ERROR_MAX_STRING_SIZE> text{};
        av_strerror(code, text.data(), text.size());
        message += std::string(": ") + text.data();
    }
    return base::make_error(base::ErrorCode::encode_failed, message, "movie");
}

// Where a movie made in memory goes: libavformat writes and seeks in it as in a file (the MP4's
// index is written last and points back into it).
struct MemoryOutput {
    std::vector<std::uint8_t> bytes;
    std::size_t position = 0;
    std::size_t max_bytes = 0;
    bool too_large = false;
};

// libavformat 61 made the buffer written const.
#if LIBAVFORMAT_VERSION_MAJOR >= 61
using WrittenBytes = const std::uint8_t*;
#else
using WrittenBytes = std::uint8_t*;
#endif

int write_to_memory(void* opaque, WrittenBytes data, int size) {
    auto& out = *static_cast<MemoryOutput*>(opaque);
    const std::size_t end = out.position + static_cast<std::size_t>(size);
    if (end > out.max_bytes) {
        out.too_large = true;
        return AVERROR(EFBIG);
    }
    if (end > out.bytes.size()) {
        out.bytes.resize(end);
    }
    std::memcpy(out.bytes.data() + out.position, data, static_cast<std::size_t>(size));
    out.position = end;
    return size;
}

std::int64_t seek_in_memory(void* opaque, std::int64_t offset, int whence) {
    auto& out = *static_cast<MemoryOutput*>(opaque);
    const auto size = static_cast<std::int64_t>(out.bytes.size());
    std::int64_t position = 0;
    switch (whence & ~AVSEEK_FORCE) {
        case AVSEEK_SIZE:
            return size;
        case SEEK_SET:
            position = offset;
            break;
        case SEEK_CUR:
            position = static_cast<std::int64_t>(out.position) + offset;
            break;
        case SEEK_END:
            position = size + offset;
            break;
        default:
            return AVERROR(EINVAL);
    }
    if (position < 0) {
        return AVERROR(EINVAL);
    }
    out.position = static_cast<std::size_t>(position);
    return position;
}

}  // namespace

struct MovieWriter::Impl {
    AVFormatContext* format = nullptr;
    AVCodecContext* codec = nullptr;
    AVStream* stream = nullptr;
    SwsContext* convert = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* packet = nullptr;
    int width = 0;
    int height = 0;
    int frames = 0;
    bool finished = false;
    std::unique_ptr<MemoryOutput> memory;  // a movie made in memory

    ~Impl() {
        sws_freeContext(convert);
        av_frame_free(&frame);
        av_packet_free(&packet);
        avcodec_free_context(&codec);
        if (format != nullptr) {
            close_output();
            avformat_free_context(format);
        }
    }

    int close_output() {
        if (format->pb == nullptr) {
            return 0;
        }
        if (!memory) {
            return avio_closep(&format->pb);
        }
        avio_flush(format->pb);
        const int failed = format->pb->error;
        av_freep(&format->pb->buffer);
        avio_context_free(&format->pb);
        return failed;
    }

    // An error of libavformat's, or the memory's limit reached.
    base::Error output_error(const std::string& what, int code) const {
        if (memory && memory->too_large) {
            return base::make_error(base::ErrorCode::too_large,
                                    "the movie is larger than " +
                                            std::to_string(memory->max_bytes >> 20) +
                                            " MiB: fewer frames, smaller, or a lower quality",
                                    "movie");
        }
        return movie_error(what, code);
    }

    // Writes every packet the encoder has ready.
    base::Status drain() {
        for (;;) {
            const int received = avcodec_receive_packet(codec, packet);
            if (received == AVERROR(EAGAIN) || received == AVERROR_EOF) {
                return base::Ok{};
            }
            if (received < 0) {
                return movie_error("encoding a frame failed", received);
            }
            av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
            packet->stream_index = stream->index;
            const int written = av_interleaved_write_frame(format, packet);
            if (written < 0) {
                return output_error("writing the movie failed", written);
            }
        }
    }
};

MovieWriter::MovieWriter(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

MovieWriter::MovieWriter(MovieWriter&&) noexcept = default;
MovieWriter& MovieWriter::operator=(MovieWriter&&) noexcept = default;
MovieWriter::~MovieWriter() = default;

bool writes_movies() {
    return true;
}

base::Result<MovieWriter> MovieWriter::create(const std::filesystem::path& path, int width,
                                              int height, const MovieOptions& options) {
    if (path.extension() != ".mp4") {
        return base::make_error(
                base::ErrorCode::invalid_argument,
                "a movie is written as .mp4, not '" + path.filename().string() + "'", "movie");
    }
    return open(path, std::nullopt, width, height, options);
}

base::Result<MovieWriter> MovieWriter::create_in_memory(int width, int height,
                                                        const MovieOptions& options,
                                                        std::size_t max_bytes) {
    return open({}, max_bytes, width, height, options);
}

base::Result<MovieWriter> MovieWriter::open(const std::filesystem::path& path,
                                            std::optional<std::size_t> max_bytes_in_memory,
                                            int width, int height, const MovieOptions& options) {
    if (width < 2 || height < 2 || width > kMaxMovieSide || height > kMaxMovieSide ||
        width % 2 != 0 || height % 2 != 0) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "a movie's width and height must be even (its colour is stored at "
                                "half the resolution) and within 2.." +
                                        std::to_string(kMaxMovieSide) + ", not " +
                                        std::to_string(width) + "x" + std::to_string(height),
                                "movie");
    }
    if (options.frames_per_second < 1 || options.frames_per_second > 120) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "frames per second must be within 1..120", "movie");
    }
    if (options.quality < kMinMovieQuality || options.quality > kMaxMovieQuality) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "the movie quality (x264's rate factor) must be within " +
                                        std::to_string(kMinMovieQuality) + ".." +
                                        std::to_string(kMaxMovieQuality),
                                "movie");
    }
    // x264 and the muxer report their settings at the info level: only errors reach the log.
    static std::once_flag quiet;
    std::call_once(quiet, [] { av_log_set_level(AV_LOG_ERROR); });

    auto impl = std::make_unique<Impl>();
    impl->width = width;
    impl->height = height;
    if (max_bytes_in_memory) {
        impl->memory = std::make_unique<MemoryOutput>();
        impl->memory->max_bytes = *max_bytes_in_memory;
    }
    const std::string file = path.string();
    int status = avformat_alloc_output_context2(&impl->format, nullptr, "mp4",
                                                file.empty() ? nullptr : file.c_str());
    if (status < 0 || impl->format == nullptr) {
        return movie_error("no MP4 muxer", status);
    }
    const AVCodec* h264 = avcodec_find_encoder_by_name("libx264");
    if (h264 == nullptr) {
        return movie_error("this libavcodec has no libx264 encoder");
    }
    impl->stream = avformat_new_stream(impl->format, nullptr);
    impl->codec = avcodec_alloc_context3(h264);
    impl->frame = av_frame_alloc();
    impl->packet = av_packet_alloc();
    if (impl->stream == nullptr || impl->codec == nullptr || impl->frame == nullptr ||
        impl->packet == nullptr) {
        return movie_error("out of memory");
    }
    AVCodecContext& codec = *impl->codec;
    codec.width = width;
    codec.height = height;
    codec.time_base = AVRational{1, options.frames_per_second};
    codec.framerate = AVRational{options.frames_per_second, 1};
    codec.pix_fmt = AV_PIX_FMT_YUV420P;
    codec.gop_size = options.frames_per_second * 2;
    // What swscale's default conversion writes: BT.601 in the limited range, so players show the
    // colours the frames had.
    codec.color_range = AVCOL_RANGE_MPEG;
    codec.colorspace = AVCOL_SPC_SMPTE170M;
    codec.color_primaries = AVCOL_PRI_SMPTE170M;
    codec.color_trc = AVCOL_TRC_SMPTE170M;
    if ((impl->format->oformat->flags & AVFMT_GLOBALHEADER) != 0) {
        codec.flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    }
    av_opt_set(codec.priv_data, "preset", "medium", 0);
    av_opt_set_int(codec.priv_data, "crf", options.quality, 0);
    if (options.threads > 0) {
        codec.thread_count = options.threads;
    }
    if (options.lookahead_frames >= 0) {
        av_opt_set_int(codec.priv_data, "rc-lookahead", options.lookahead_frames, 0);
    }
    status = avcodec_open2(&codec, h264, nullptr);
    if (status < 0) {
        return movie_error("opening the H.264 encoder failed", status);
    }
    status = avcodec_parameters_from_context(impl->stream->codecpar, &codec);
    if (status < 0) {
        return movie_error("the stream's parameters", status);
    }
    impl->stream->time_base = codec.time_base;
    impl->stream->avg_frame_rate = codec.framerate;
    if (impl->memory) {
        constexpr int kBufferBytes = 64 << 10;
        auto* buffer = static_cast<unsigned char*>(av_malloc(kBufferBytes));
        impl->format->pb = buffer == nullptr
                                   ? nullptr
                                   : avio_alloc_context(buffer, kBufferBytes, 1, impl->memory.get(),
                                                        nullptr, write_to_memory, seek_in_memory);
        if (impl->format->pb == nullptr) {
            av_free(buffer);
            return movie_error("out of memory");
        }
        impl->format->flags |= AVFMT_FLAG_CUSTOM_IO;
    } else {
        status = avio_open(&impl->format->pb, file.c_str(), AVIO_FLAG_WRITE);
        if (status < 0) {
            return movie_error("cannot write '" + file + "'", status);
        }
    }
    status = avformat_write_header(impl->format, nullptr);
    if (status < 0) {
        return impl->output_error("writing the MP4 header failed", status);
    }
    impl->frame->format = codec.pix_fmt;
    impl->frame->width = width;
    impl->frame->height = height;
    status = av_frame_get_buffer(impl->frame, 0);
    if (status < 0) {
        return movie_error("out of memory for a frame", status);
    }
    impl->convert = sws_getContext(width, height, AV_PIX_FMT_RGBA, width, height,
                                   AV_PIX_FMT_YUV420P, SWS_BICUBIC, nullptr, nullptr, nullptr);
    if (impl->convert == nullptr) {
        return movie_error("no RGBA to YUV 4:2:0 conversion");
    }
    return MovieWriter(std::move(impl));
}

base::Status MovieWriter::add(const base::ImageRgba8& image) {
    Impl& impl = *impl_;
    if (impl.finished) {
        return movie_error("the movie is finished: no frame may be added");
    }
    if (image.width != impl.width || image.height != impl.height) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "a frame of " + std::to_string(image.width) + "x" +
                                        std::to_string(image.height) + " in a movie of " +
                                        std::to_string(impl.width) + "x" +
                                        std::to_string(impl.height),
                                "movie");
    }
    // The encoder may still hold the frame's buffer from the last frame (a reference).
    const int writable = av_frame_make_writable(impl.frame);
    if (writable < 0) {
        return movie_error("out of memory for a frame", writable);
    }
    const std::uint8_t* source[1] = {image.pixels.data()};
    const int stride[1] = {4 * image.width};
    sws_scale(impl.convert, source, stride, 0, image.height, impl.frame->data,
              impl.frame->linesize);
    impl.frame->pts = impl.frames;
    const int sent = avcodec_send_frame(impl.codec, impl.frame);
    if (sent < 0) {
        return movie_error("encoding a frame failed", sent);
    }
    ++impl.frames;
    return impl.drain();
}

base::Status MovieWriter::finish() {
    Impl& impl = *impl_;
    if (impl.finished) {
        return base::Ok{};
    }
    impl.finished = true;
    const int sent = avcodec_send_frame(impl.codec, nullptr);
    if (sent < 0) {
        return movie_error("flushing the encoder failed", sent);
    }
    if (auto status = impl.drain(); !status) {
        return status;
    }
    const int written = av_write_trailer(impl.format);
    if (written < 0) {
        return impl.output_error("writing the MP4 index failed", written);
    }
    const int closed = impl.close_output();
    if (closed < 0) {
        return impl.output_error("closing the movie failed", closed);
    }
    return base::Ok{};
}

int MovieWriter::frames() const {
    return impl_->frames;
}

std::vector<std::uint8_t> MovieWriter::take_bytes() {
    if (!impl_->memory || !impl_->finished || impl_->format->pb != nullptr) {
        return {};
    }
    return std::exchange(impl_->memory->bytes, {});
}

}  // namespace penumbra::encode
