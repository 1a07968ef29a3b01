// A session's viewers: who hears of a state change, and in which order.

#include <penumbra/session/session.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace penumbra::session {
namespace {

constexpr ViewerId owner = 1;
constexpr ViewerId first_viewer = 2;
constexpr ViewerId second_viewer = 3;

SessionState state_with_mode(scene::Mode mode) {
    SessionState state;
    state.frame.settings.mode = mode;
    return state;
}

// What one viewer was told, in order: "welcome:<mode>" or "changed:<mode>".
struct Heard {
    std::vector<std::string> events;

    StateSink sink(const std::string& what) {
        return [this, what](const SessionState& state) {
            events.push_back(what + ":" + scene::to_string(state.frame.settings.mode));
        };
    }
};

TEST(Session, AStateChangeReachesEveryViewerButTheOneWhoMadeIt) {
    Session session("s", "v", nullptr, state_with_mode(scene::Mode::sbrc), owner);
    Heard by_owner;
    Heard by_first;
    Heard by_second;
    session.add_viewer(owner, {}, by_owner.sink("changed"), by_owner.sink("welcome"));
    session.add_viewer(first_viewer, {}, by_first.sink("changed"), by_first.sink("welcome"));
    session.set_state(state_with_mode(scene::Mode::dvr), owner);
    session.add_viewer(second_viewer, {}, by_second.sink("changed"), by_second.sink("welcome"));
    session.set_state(state_with_mode(scene::Mode::phong), owner);

    EXPECT_EQ(by_owner.events, std::vector<std::string>{"welcome:sbrc"});
    EXPECT_EQ(by_first.events,
              (std::vector<std::string>{"welcome:sbrc", "changed:dvr", "changed:phong"}));
    EXPECT_EQ(by_second.events, (std::vector<std::string>{"welcome:dvr", "changed:phong"}));
    EXPECT_EQ(session.state().frame.settings.mode, scene::Mode::phong);
}

TEST(Session, AViewerWhoLeftHearsNoMoreAndOneWhoReturnsIsWelcomedAgain) {
    Session session("s", "v", nullptr, state_with_mode(scene::Mode::sbrc), owner);
    Heard heard;
    session.add_viewer(owner, {}, {}, {});
    session.add_viewer(first_viewer, {}, heard.sink("changed"), heard.sink("welcome"));
    EXPECT_EQ(session.remove_viewer(first_viewer), 1U);
    session.set_state(state_with_mode(scene::Mode::dvr), owner);
    session.add_viewer(first_viewer, {}, heard.sink("changed"), heard.sink("welcome"));
    // Re-adding replaces the sinks: one welcome each time, never two change reports.
    session.add_viewer(first_viewer, {}, heard.sink("changed"), heard.sink("welcome"));
    session.set_state(state_with_mode(scene::Mode::phong), owner);
    EXPECT_EQ(heard.events, (std::vector<std::string>{"welcome:sbrc", "welcome:dvr", "welcome:dvr",
                                                      "changed:phong"}));
    EXPECT_EQ(session.viewer_count(), 2U);
}

TEST(Session, FramesGoToEveryViewerWithOneNumber) {
    Session session("s", "v", nullptr, {}, owner);
    std::vector<std::pair<ViewerId, std::uint64_t>> delivered;
    for (const ViewerId viewer : {owner, first_viewer}) {
        session.add_viewer(
                viewer,
                [&delivered, viewer](const base::Result<std::shared_ptr<const EncodedFrame>>&,
                                     std::uint64_t number) {
                    delivered.emplace_back(viewer, number);
                },
                {}, {});
    }
    session.deliver(std::make_shared<const EncodedFrame>());
    EXPECT_EQ(delivered,
              (std::vector<std::pair<ViewerId, std::uint64_t>>{{owner, 1}, {first_viewer, 1}}));
    EXPECT_EQ(session.frame_count(), 1U);
}

}  // namespace
}  // namespace penumbra::session
