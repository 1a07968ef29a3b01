// A slow reader's send queue as its frames' stream allows: JPEG frames supersede one another, an
// H.264 stream is never left with a frame whose predecessor was dropped, and a gap asks for the
// keyframe that mends it.

#include "send_queue.hpp"

#include <gtest/gtest.h>

#include <deque>
#include <string>

namespace penumbra::net {
namespace {

struct Message {
    std::string name;
    bool frame = true;
    bool independent = true;
};

Message frame(std::string name, bool independent) {
    return {std::move(name), true, independent};
}

Message text(std::string name) {
    return {std::move(name), false, true};
}

std::string names(const std::deque<Message>& queue) {
    std::string out;
    for (const Message& m : queue) {
        out += (out.empty() ? "" : " ") + m.name;
    }
    return out;
}

// JPEG (every frame independent): the newest frame takes the waiting one's place, before the
// replies queued after it; the one being written stays.
TEST(SendQueue, AnIndependentFrameSupersedesTheFramesWaitingInThePlaceOfTheFirst) {
    std::deque<Message> queue;
    bool awaiting = false;
    EXPECT_TRUE(admit_frame(queue, false, frame("f1", true), 4, awaiting).queued);
    queue.push_back(text("ack"));
    const FrameAdmission second = admit_frame(queue, true, frame("f2", true), 4, awaiting);
    EXPECT_TRUE(second.queued);
    EXPECT_EQ(second.dropped, 0u) << "f1 is being written";
    const FrameAdmission third = admit_frame(queue, true, frame("f3", true), 4, awaiting);
    EXPECT_EQ(third.dropped, 1u);
    EXPECT_EQ(names(queue), "f1 ack f3");
}

// H.264: frames that need their predecessors queue up behind one another; once too many wait, the
// next is dropped with a gap, the ones after it are dropped until a keyframe, and the keyframe
// supersedes every frame waiting. The queue never holds a frame after a dropped one.
TEST(SendQueue, AStreamFrameWaitsBehindItsPredecessorsAndAGapWaitsForAKeyframe) {
    std::deque<Message> queue;
    bool awaiting = false;
    admit_frame(queue, false, frame("k0", true), 3, awaiting);
    for (const char* name : {"p1", "p2"}) {
        const FrameAdmission a = admit_frame(queue, true, frame(name, false), 3, awaiting);
        EXPECT_TRUE(a.queued) << name;
        EXPECT_EQ(a.dropped, 0u) << name;
    }
    EXPECT_EQ(names(queue), "k0 p1 p2");
    const FrameAdmission full = admit_frame(queue, true, frame("p3", false), 3, awaiting);
    EXPECT_FALSE(full.queued);
    EXPECT_TRUE(full.gap);
    EXPECT_TRUE(awaiting);
    const FrameAdmission after = admit_frame(queue, true, frame("p4", false), 3, awaiting);
    EXPECT_FALSE(after.queued);
    EXPECT_FALSE(after.gap) << "asked once";
    EXPECT_EQ(names(queue), "k0 p1 p2");

    queue.pop_front();  // k0 written
    const FrameAdmission key = admit_frame(queue, true, frame("k5", true), 3, awaiting);
    EXPECT_TRUE(key.queued);
    EXPECT_EQ(key.dropped, 1u) << "p2 superseded (p1 is being written)";
    EXPECT_FALSE(awaiting);
    EXPECT_EQ(names(queue), "p1 k5");
    EXPECT_TRUE(admit_frame(queue, true, frame("p6", false), 3, awaiting).queued);
    EXPECT_EQ(names(queue), "p1 k5 p6");
}

// A frame that finds no frame waiting goes to the back, after the messages queued before it; a
// keyframe does so even where the one frame allowed is being written (it supersedes nothing, and
// the frames after it need it), a frame that needs its predecessor does not.
TEST(SendQueue, AFrameWhileNoFrameWaitsGoesToTheBack) {
    std::deque<Message> queue;
    bool awaiting = false;
    queue.push_back(text("state"));
    const FrameAdmission a = admit_frame(queue, false, frame("k0", true), 1, awaiting);
    EXPECT_TRUE(a.queued);
    EXPECT_EQ(names(queue), "state k0");
    queue.pop_front();  // the state written; k0 being written
    const FrameAdmission p1 = admit_frame(queue, true, frame("p1", false), 1, awaiting);
    EXPECT_FALSE(p1.queued);
    EXPECT_TRUE(p1.gap);
    const FrameAdmission k2 = admit_frame(queue, true, frame("k2", true), 1, awaiting);
    EXPECT_TRUE(k2.queued);
    EXPECT_FALSE(awaiting);
    EXPECT_EQ(names(queue), "k0 k2");
}

}  // namespace
}  // namespace penumbra::net
