#pragma once

// What a frame does to a connection's queue of messages still to send while its client reads
// slowly: its stream says what may be dropped. An independent frame (every JPEG or PNG frame, an
// H.264 keyframe) takes the place of the frames still waiting. A frame that needs the ones before
// it waits behind them; where too many wait it is dropped, and so is every frame after it up to
// the next independent one, which the connection asks its session for (a gap).

#include <algorithm>
#include <cstddef>
#include <deque>

namespace penumbra::net {

struct FrameAdmission {
    bool queued = false;      // the frame is in the queue
    std::size_t dropped = 0;  // frames dropped: waiting ones it superseded, or itself
    bool gap = false;         // the stream broke here: the session should send a keyframe
};

// Offers `frame` to `queue`, whose front is being written while `writing`; at most `max_frames`
// frames may be queued. `awaiting_keyframe` carries the stream's state from one call to the next.
// `Message` has `frame` (true for a frame) and `independent`.
template <class Message>
FrameAdmission admit_frame(std::deque<Message>& queue, bool writing, Message frame,
                           std::size_t max_frames, bool& awaiting_keyframe) {
    if (awaiting_keyframe && !frame.independent) {
        return {.queued = false, .dropped = 1, .gap = false};  // only a keyframe mends it
    }
    const auto is_frame = [](const Message& m) { return static_cast<bool>(m.frame); };
    const auto first_waiting = queue.begin() + (writing && !queue.empty() ? 1 : 0);
    const auto waiting_frame = std::find_if(first_waiting, queue.end(), is_frame);
    if (frame.independent && waiting_frame != queue.end()) {
        // In the place of the first frame waiting, so the messages queued since stay after it.
        awaiting_keyframe = false;
        const auto later = std::remove_if(waiting_frame + 1, queue.end(), is_frame);
        const auto superseded = static_cast<std::size_t>(std::distance(later, queue.end())) + 1;
        queue.erase(later, queue.end());
        *waiting_frame = std::move(frame);
        return {.queued = true, .dropped = superseded, .gap = false};
    }
    // An independent frame that finds no frame waiting supersedes nothing and is queued.
    const auto frames =
            static_cast<std::size_t>(std::count_if(queue.begin(), queue.end(), is_frame));
    if (!frame.independent && frames >= std::max<std::size_t>(1, max_frames)) {
        awaiting_keyframe = true;
        return {.queued = false, .dropped = 1, .gap = true};
    }
    awaiting_keyframe = false;
    queue.push_back(std::move(frame));
    return {.queued = true, .dropped = 0, .gap = false};
}

}  // namespace penumbra::net
