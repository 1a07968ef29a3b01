#pragma once

// A session's frames as one stream (DESIGN.md §4: each session owns its encoder): every frame of
// the session goes through it in order (the scheduler encodes one session's frames one at a
// time), so that H.264 may send each as the change from the one before. Asked for a keyframe (a
// viewer joined or resumed, a viewer's connection dropped a frame), its next frame decodes alone.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/encode/stream.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <atomic>
#include <memory>
#include <mutex>

namespace penumbra::session {

class SessionStream {
public:
    // The frame encoded as `output` asks: a change of format or quality starts a new stream,
    // whose first frame is a keyframe. A still's last frame (`final_still`: no refinement step
    // follows it) goes as frame_format says, and where that is not the stream's own format the
    // stream's next frame is a keyframe: the still may take the place of stream frames that wait
    // in a slow reader's queue.
    base::Result<encode::StreamFrame> encode(const base::ImageRgba8& image,
                                             const scene::Output& output, bool final_still);

    // The next frame decodes alone, whatever came before it.
    void want_keyframe() { keyframe_wanted_.store(true); }

private:
    std::mutex mutex_;  // encodes of one session never overlap; this keeps that true regardless
    std::unique_ptr<encode::FrameStream> stream_;
    scene::Output made_for_;
    std::atomic<bool> keyframe_wanted_{false};
};

// The stream options `output` asks for.
[[nodiscard]] encode::StreamOptions stream_options(const scene::Output& output);

// The format a frame goes in: the output's, except a still's last frame on an H.264 stream, which
// goes as a JPEG at the output's JPEG quality: the picture a user stops to study keeps the detail
// that the stream's rate factor, made for frames in motion, would blur.
[[nodiscard]] scene::FrameFormat frame_format(const scene::Output& output, bool final_still);

}  // namespace penumbra::session
