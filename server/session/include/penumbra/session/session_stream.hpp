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
    // whose first frame is a keyframe.
    base::Result<encode::StreamFrame> encode(const base::ImageRgba8& image,
                                             const scene::Output& output);

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

}  // namespace penumbra::session
