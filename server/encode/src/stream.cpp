#include <penumbra/encode/stream.hpp>

#include <cstring>
#include <string>

#include <libyuv/convert.h>

extern "C" {
#include <x264.h>
}

namespace penumbra::encode {
namespace {

// JPEG or PNG: every frame stands alone.
class IntraStream final : public FrameStream {
public:
    IntraStream(ImageFormat format, int jpeg_quality, StreamCodec codec)
        : format_(format)
        , jpeg_quality_(jpeg_quality)
        , codec_(codec) {}

    base::Result<StreamFrame> encode(const base::ImageRgba8& image, bool /*independent*/) override {
        auto bytes = encode_image(image, format_, jpeg_quality_);
        if (!bytes) {
            return bytes.error();
        }
        return StreamFrame{std::move(bytes.value()), true};
    }

    [[nodiscard]] StreamCodec codec() const override { return codec_; }

private:
    ImageFormat format_;
    int jpeg_quality_;
    StreamCodec codec_;
};

base::Error h264_error(const std::string& what) {
    return base::make_error(base::ErrorCode::encode_failed, what, "h264");
}

// H.264 through libx264, at the frame's size rounded up to even (4:2:0 halves both, and H.264
// crops only by whole chroma samples): an odd side gains a copy of its last column or row, which
// the frame's header (its width and height) tells the client to leave out.
class H264Stream final : public FrameStream {
public:
    explicit H264Stream(const StreamOptions& options)
        : options_(options) {}

    H264Stream(const H264Stream&) = delete;
    H264Stream& operator=(const H264Stream&) = delete;

    ~H264Stream() override { close(); }

    base::Result<StreamFrame> encode(const base::ImageRgba8& image, bool independent) override {
        if (image.width <= 0 || image.height <= 0) {
            return h264_error("cannot encode an empty image");
        }
        bool restarted = false;
        if (encoder_ == nullptr || image.width != width_ || image.height != height_) {
            if (auto status = open(image.width, image.height); !status) {
                return status.error();
            }
            restarted = true;
        }
        convert(image);
        picture_.i_pts = frames_++;
        picture_.i_type = independent || restarted ? X264_TYPE_IDR : X264_TYPE_AUTO;
        x264_nal_t* nals = nullptr;
        int nal_count = 0;
        x264_picture_t out;
        const int size = x264_encoder_encode(encoder_, &nals, &nal_count, &picture_, &out);
        if (size < 0) {
            return h264_error("x264 failed to encode a frame");
        }
        if (size == 0 || nal_count == 0) {
            // With no look-ahead and no B-frames every frame comes out at once.
            return h264_error("x264 held a frame back");
        }
        StreamFrame frame;
        // x264 writes the NAL units of one call back to back: the access unit.
        frame.bytes.assign(nals[0].p_payload, nals[0].p_payload + size);
        frame.independent = out.b_keyframe != 0;
        return frame;
    }

    [[nodiscard]] StreamCodec codec() const override { return StreamCodec::h264; }

private:
    base::Status open(int width, int height) {
        close();
        const int even_width = width + width % 2;
        const int even_height = height + height % 2;
        x264_param_t param;
        if (x264_param_default_preset(&param, "superfast", "zerolatency") < 0) {
            return h264_error("x264 lacks the superfast preset");
        }
        param.i_log_level = X264_LOG_ERROR;
        param.i_threads = 1;  // a session's frames are one of many: one core each
        param.i_width = even_width;
        param.i_height = even_height;
        param.i_csp = X264_CSP_I420;
        param.i_fps_num = static_cast<std::uint32_t>(options_.frames_per_second);
        param.i_fps_den = 1;
        param.i_keyint_max = X264_KEYINT_MAX_INFINITE;  // keyframes when asked, or a new size
        param.i_bframe = 0;
        param.b_repeat_headers = 1;
        param.b_annexb = 1;
        param.rc.i_rc_method = X264_RC_CRF;
        param.rc.f_rf_constant = static_cast<float>(options_.h264_quality);
        param.vui.b_fullrange = 0;
        param.vui.i_colmatrix = 6;  // BT.601, what libyuv's RGBA to I420 writes
        if (x264_param_apply_profile(&param, "high") < 0) {
            return h264_error("x264 refused the high profile");
        }
        encoder_ = x264_encoder_open(&param);
        if (encoder_ == nullptr) {
            return h264_error("x264 could not open an encoder of " + std::to_string(width) + "x" +
                              std::to_string(height));
        }
        if (x264_picture_alloc(&picture_, X264_CSP_I420, even_width, even_height) < 0) {
            close();
            return h264_error("out of memory for a picture");
        }
        allocated_ = true;
        width_ = width;
        height_ = height;
        padded_.assign(std::size_t(even_width) * even_height * 4, 0);
        return base::Ok{};
    }

    void close() {
        if (allocated_) {
            x264_picture_clean(&picture_);
            allocated_ = false;
        }
        if (encoder_ != nullptr) {
            x264_encoder_close(encoder_);
            encoder_ = nullptr;
        }
    }

    // RGBA to I420 (libyuv's ABGR: R, G, B, A in memory), the odd column and row repeated.
    void convert(const base::ImageRgba8& image) {
        const int even_width = width_ + width_ % 2;
        const int even_height = height_ + height_ % 2;
        const std::uint8_t* rgba = image.pixels.data();
        int stride = 4 * width_;
        if (even_width != width_ || even_height != height_) {
            for (int y = 0; y < even_height; ++y) {
                const std::uint8_t* row = image.pixel(0, std::min(y, height_ - 1));
                std::uint8_t* to = padded_.data() + std::size_t(y) * even_width * 4;
                std::memcpy(to, row, std::size_t(width_) * 4);
                if (even_width != width_) {
                    std::memcpy(to + std::size_t(width_) * 4, row + std::size_t(width_ - 1) * 4, 4);
                }
            }
            rgba = padded_.data();
            stride = 4 * even_width;
        }
        const x264_image_t& planes = picture_.img;
        libyuv::ABGRToI420(rgba, stride, planes.plane[0], planes.i_stride[0], planes.plane[1],
                           planes.i_stride[1], planes.plane[2], planes.i_stride[2], even_width,
                           even_height);
    }

    StreamOptions options_;
    x264_t* encoder_ = nullptr;
    x264_picture_t picture_{};
    bool allocated_ = false;
    int width_ = 0;
    int height_ = 0;
    std::int64_t frames_ = 0;
    std::vector<std::uint8_t> padded_;
};

}  // namespace

base::Result<std::unique_ptr<FrameStream>> make_stream(const StreamOptions& options) {
    if (options.frames_per_second < 1 || options.frames_per_second > 240) {
        return base::make_error(base::ErrorCode::invalid_value,
                                "a stream's frames per second must be within 1..240", "stream");
    }
    switch (options.codec) {
        case StreamCodec::jpeg:
        case StreamCodec::png:
            if (options.jpeg_quality < kMinJpegQuality || options.jpeg_quality > kMaxJpegQuality) {
                return base::make_error(base::ErrorCode::invalid_value,
                                        "JPEG quality must be within " +
                                                std::to_string(kMinJpegQuality) + ".." +
                                                std::to_string(kMaxJpegQuality),
                                        "stream");
            }
            return std::unique_ptr<FrameStream>(std::make_unique<IntraStream>(
                    options.codec == StreamCodec::jpeg ? ImageFormat::jpeg : ImageFormat::png,
                    options.jpeg_quality, options.codec));
        case StreamCodec::h264:
            if (options.h264_quality < kMinStreamQuality ||
                options.h264_quality > kMaxStreamQuality) {
                return base::make_error(base::ErrorCode::invalid_value,
                                        "the H.264 quality (x264's rate factor) must be within " +
                                                std::to_string(kMinStreamQuality) + ".." +
                                                std::to_string(kMaxStreamQuality),
                                        "stream");
            }
            return std::unique_ptr<FrameStream>(std::make_unique<H264Stream>(options));
    }
    return base::make_error(base::ErrorCode::invalid_value, "unknown stream codec", "stream");
}

}  // namespace penumbra::encode
