// A session's viewers: who hears of a state change, and in which order; its owner leaving and
// resuming.

#include <penumbra/session/session.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace penumbra::session {
namespace {

constexpr ViewerId owner = 1;
constexpr ViewerId first_viewer = 2;
constexpr ViewerId second_viewer = 3;
constexpr ViewerId resuming = 4;

// Renders nothing: the registry's tests only need a scheduler to withdraw frames from.
class NoRenderer final : public render::FrameRenderer {
public:
    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest&,
                                       const render::CancelPredicate&) override {
        return base::make_error(base::ErrorCode::internal_error, "these tests render nothing",
                                "render");
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
};

std::unique_ptr<Scheduler> idle_scheduler(metrics::Registry& metrics) {
    auto created = Scheduler::create(
            []() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                return std::unique_ptr<render::FrameRenderer>(std::make_unique<NoRenderer>());
            },
            {}, metrics);
    EXPECT_TRUE(created.ok());
    return created.ok() ? std::move(created.value()) : nullptr;
}

scene::State state_with_mode(scene::Mode mode) {
    scene::State state;
    state.frame.settings.mode = mode;
    return state;
}

// What one viewer was told, in order: "welcome:<mode>" or "changed:<mode>".
struct Heard {
    std::vector<std::string> events;

    StateSink sink(const std::string& what) {
        return [this, what](const scene::State& state, const DrawnLabels* /*labels*/) {
            events.push_back(what + ":" + scene::to_string(state.frame.settings.mode));
        };
    }
};

// The viewers are given the label map with the state it changes (its names and colours, which
// the styles do not carry), a viewer who joins is welcomed with it, and a plain change carries
// none.
TEST(Session, TheLabelMapDrawnReachesTheViewersWithItsState) {
    const std::filesystem::path templates = "/usr/share/mricron/templates";
    auto ch2 = volume::load_volume(templates / "ch2.nii.gz");
    auto aal = volume::load_label_map(templates / "aal.nii.gz");
    ASSERT_TRUE(ch2.ok() && aal.ok());
    Session session("s", "v", std::make_shared<const volume::Volume>(std::move(ch2.value())), {},
                    owner);
    std::vector<std::string> heard;
    const auto sink = [&heard](const std::string& who) {
        return [&heard, who](const scene::State& state, const DrawnLabels* labels) {
            heard.push_back(
                    who + ":" + std::to_string(state.frame.labels.styles.size()) + ":" +
                    (labels == nullptr ? "-"
                     : labels->map == nullptr
                             ? "none"
                             : labels->id + "/" + std::to_string(labels->map->labels.size())));
        };
    };
    ASSERT_TRUE(session.add_viewer(owner, {}, sink("owner"), {}));
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, sink("first"), sink("first welcome")));
    const auto map = std::make_shared<const volume::LabelMap>(std::move(aal.value()));
    ASSERT_TRUE(session.set_labels(owner, "aal.nii.gz", map).ok());
    ASSERT_TRUE(session.change_state(owner, [](scene::State& state) {
        state.frame.labels.styles.front().visible = false;
        return base::Status{base::Ok{}};
    }));
    ASSERT_TRUE(session.add_viewer(second_viewer, {}, sink("second"), sink("second welcome")));
    ASSERT_TRUE(session.set_labels(owner, "", nullptr).ok());
    EXPECT_EQ(heard, (std::vector<std::string>{"first welcome:0:-", "first:116:aal.nii.gz/116",
                                               "first:116:-", "second welcome:116:aal.nii.gz/116",
                                               "first:0:none", "second:0:none"}));
    EXPECT_FALSE(session.set_labels(first_viewer, "aal.nii.gz", map).ok());
}

// The label map drawn alone: the session asks for surfaces when the state draws the map alone and
// whenever the labels' visibility changes then (not for an opacity or a colour); once given them,
// its jobs draw the surfaces (their indicator as the volume, their labels, the surfaces' transfer
// function, colours whole); a new map drops them; inside the scan the jobs draw the scan.
TEST(Session, ALabelMapDrawnAloneAsksForItsSurfacesAndItsJobsDrawThem) {
    const std::filesystem::path templates = "/usr/share/mricron/templates";
    auto ch2 = volume::load_volume(templates / "ch2.nii.gz");
    auto aal = volume::load_label_map(templates / "aal.nii.gz");
    ASSERT_TRUE(ch2.ok() && aal.ok());
    const auto scan = std::make_shared<const volume::Volume>(std::move(ch2.value()));
    Session session("s", "v", scan, {}, owner);
    ASSERT_TRUE(session.add_viewer(owner, {}, {}, {}));
    const auto map = std::make_shared<const volume::LabelMap>(std::move(aal.value()));
    ASSERT_TRUE(session.set_labels(owner, "aal.nii.gz", map).ok());
    const auto change = [&](const std::function<void(scene::Labels&)>& edit) {
        ASSERT_TRUE(session.change_state(owner, [&](scene::State& state) {
            edit(state.frame.labels);
            return base::Status{base::Ok{}};
        }));
    };
    EXPECT_FALSE(session.surfaces_wanted());
    change([](scene::Labels& labels) { labels.alone = true; });
    auto wanted = session.surfaces_wanted();
    ASSERT_TRUE(wanted);
    EXPECT_EQ(wanted->map, map);
    EXPECT_EQ(wanted->visible, std::vector<bool>(116, true));
    // Until they come, the jobs draw the map inside the scan.
    EXPECT_EQ(session.make_job(1, false).volume, scan);

    auto made = volume::label_surfaces(*map, wanted->visible);
    ASSERT_TRUE(made.ok());
    const auto surfaces = std::make_shared<const volume::LabelSurfaces>(std::move(made.value()));
    session.set_surfaces(*wanted, surfaces);
    EXPECT_FALSE(session.surfaces_wanted());
    const RenderJob job = session.make_job(2, false);
    EXPECT_EQ(job.volume.get(), &surfaces->indicator);
    EXPECT_EQ(job.labels.get(), &surfaces->labels);
    EXPECT_EQ(job.request.transfer_function, scene::label_surface_transfer_function());
    EXPECT_EQ(job.request.labels.blend, 1.0);
    EXPECT_EQ(session.make_job(3, true).volume.get(), &surfaces->indicator);

    change([](scene::Labels& labels) { labels.styles[3].opacity = 0.5; });
    EXPECT_FALSE(session.surfaces_wanted()) << "an opacity leaves the surfaces as they are";
    change([](scene::Labels& labels) { labels.styles[3].visible = false; });
    wanted = session.surfaces_wanted();
    ASSERT_TRUE(wanted);
    EXPECT_FALSE(wanted->visible[3]);
    EXPECT_EQ(session.make_job(4, false).volume.get(), &surfaces->indicator)
            << "the surfaces made last, until the new ones come";

    change([](scene::Labels& labels) { labels.alone = false; });
    EXPECT_FALSE(session.surfaces_wanted());
    const RenderJob inside = session.make_job(5, false);
    EXPECT_EQ(inside.volume, scan);
    EXPECT_EQ(inside.labels, map);
    EXPECT_NE(inside.request.transfer_function, scene::label_surface_transfer_function());

    // The same map drawn again, every label visible: the surfaces made for that still serve. Those
    // of a map no longer drawn are not kept.
    ASSERT_TRUE(session.set_labels(owner, "aal.nii.gz", map).ok());
    change([](scene::Labels& labels) { labels.alone = true; });
    EXPECT_FALSE(session.surfaces_wanted());
    ASSERT_TRUE(session.set_labels(owner, "", nullptr).ok());
    EXPECT_FALSE(session.surfaces_wanted());
    session.set_surfaces({map, std::vector<bool>(116, true)}, surfaces);
    EXPECT_EQ(session.make_job(6, false).volume, scan);
}

TEST(Session, AStateChangeReachesEveryViewerButTheOneWhoMadeIt) {
    Session session("s", "v", nullptr, state_with_mode(scene::Mode::sbrc), owner);
    Heard by_owner;
    Heard by_first;
    Heard by_second;
    ASSERT_TRUE(session.add_viewer(owner, {}, by_owner.sink("changed"), by_owner.sink("welcome")));
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, by_first.sink("changed"),
                                   by_first.sink("welcome")));
    session.set_state(state_with_mode(scene::Mode::dvr), owner);
    ASSERT_TRUE(session.add_viewer(second_viewer, {}, by_second.sink("changed"),
                                   by_second.sink("welcome")));
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
    ASSERT_TRUE(session.add_viewer(owner, {}, {}, {}));
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, heard.sink("changed"), heard.sink("welcome")));
    EXPECT_EQ(session.remove_viewer(first_viewer), 1U);
    session.set_state(state_with_mode(scene::Mode::dvr), owner);
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, heard.sink("changed"), heard.sink("welcome")));
    // Re-adding replaces the sinks: one welcome each time, never two change reports.
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, heard.sink("changed"), heard.sink("welcome")));
    session.set_state(state_with_mode(scene::Mode::phong), owner);
    EXPECT_EQ(heard.events, (std::vector<std::string>{"welcome:sbrc", "welcome:dvr", "welcome:dvr",
                                                      "changed:phong"}));
    EXPECT_EQ(session.viewer_count(), 2U);
}

TEST(Session, FramesGoToEveryViewerWithOneNumber) {
    Session session("s", "v", nullptr, {}, owner);
    std::vector<std::pair<ViewerId, std::uint64_t>> delivered;
    for (const ViewerId viewer : {owner, first_viewer}) {
        ASSERT_TRUE(session.add_viewer(
                viewer,
                [&delivered, viewer](const ViewerOutcome& outcome) {
                    delivered.emplace_back(
                            viewer,
                            std::get<std::shared_ptr<const SharedFrame>>(outcome)->number());
                },
                {}, {}));
    }
    session.deliver(std::make_shared<const EncodedFrame>());
    EXPECT_EQ(delivered,
              (std::vector<std::pair<ViewerId, std::uint64_t>>{{owner, 1}, {first_viewer, 1}}));
    EXPECT_EQ(session.frame_count(), 1U);
}

// A session expects a still's time from its last still (per pixel, in its mode at its sample
// distance, from the passes that go with the pixels: not a light buffer built once): a still
// expected to take longer than the frame budget is rendered first at a smaller size
// (scene::still_preview), then at its own.
TEST(Session, AStillExpectedToTakeLongerThanTheBudgetIsPreviewedFirst) {
    scene::State state = state_with_mode(scene::Mode::sbrc);
    state.frame.settings.width = 400;
    state.frame.settings.height = 400;
    state.frame.settings.sample_distance = 1.0 / 256.0;
    Session session("s", "v", nullptr, state, owner);
    EXPECT_FALSE(session.make_job(1, false).preview) << "no still measured yet";
    const auto delivered = [&session](double raycast_ms, double sample_distance, bool interactive) {
        EncodedFrame frame;
        frame.width = 200;
        frame.height = 200;
        frame.mode = scene::Mode::sbrc;
        frame.sample_distance = sample_distance;
        frame.interactive = interactive;
        frame.report.passes = {{"light_buffer_multi_slice", -1.0, 5000.0},
                               {"raycast", -1.0, raycast_ms},
                               {"readback", 0.0, 10.0}};
        session.deliver(std::make_shared<const EncodedFrame>(frame));
    };
    // 4 s at full size, but said by an interactive frame, or by a still at another step.
    delivered(990.0, 1.0 / 256.0, true);
    delivered(990.0, 1.0 / 128.0, false);
    EXPECT_FALSE(session.make_job(2, false).preview);
    // 250 ms for a quarter of the pixels: 1 s expected, the light buffer's 5 s not counted; a
    // refinement step after it (at half the step) does not replace it.
    delivered(240.0, 1.0 / 256.0, false);
    EncodedFrame step;
    step.width = 200;
    step.height = 200;
    step.mode = scene::Mode::sbrc;
    step.sample_distance = 1.0 / 512.0;
    step.refinement_step = 1;
    step.report.passes = {{"raycast", -1.0, 10.0}};
    session.deliver(std::make_shared<const EncodedFrame>(step));
    const RenderJob job = session.make_job(3, false);
    ASSERT_TRUE(job.preview);
    EXPECT_EQ(job.preview->request.settings.width, 200);
    EXPECT_EQ(job.preview->request.settings.height, 200);
    EXPECT_EQ(job.preview->quality,
              "still preview: 200x200, the still at 400x400 expected in 1000 ms");
    EXPECT_EQ(job.request.settings.width, 400);
    EXPECT_EQ(job.quality, "still: full quality");
    EXPECT_FALSE(session.make_job(4, true).preview) << "interactive frames have none";
    // A budget of its own that the still fits, or a mode not measured: none.
    scene::State generous = state;
    generous.frame_budget_ms = 1000.0;
    session.set_state(generous, owner);
    EXPECT_FALSE(session.make_job(5, false).preview);
    session.set_state(state_with_mode(scene::Mode::dvr), owner);
    EXPECT_FALSE(session.make_job(6, false).preview);
}

// Every viewer of a frame gets the one SharedFrame, and the bytes it is packed into are made once,
// by whichever viewer asks first, and are the same bytes for all.
TEST(Session, AFrameIsPackedOnceAndEveryViewerSendsTheSameBytes) {
    Session session("s", "v", nullptr, {}, owner);
    std::atomic<int> packed{0};
    const SharedFrame::Packer pack = [&packed](const SharedFrame& frame) {
        ++packed;
        return std::vector<std::uint8_t>(frame.frame().image.begin(), frame.frame().image.end());
    };
    std::vector<SharedFrame::Bytes> sent;
    for (const ViewerId viewer : {owner, first_viewer, second_viewer}) {
        ASSERT_TRUE(session.add_viewer(
                viewer,
                [&](const ViewerOutcome& outcome) {
                    const auto* frame = std::get_if<std::shared_ptr<const SharedFrame>>(&outcome);
                    ASSERT_NE(frame, nullptr);
                    sent.push_back((*frame)->packed(pack));
                },
                {}, {}));
    }
    auto frame = std::make_shared<EncodedFrame>();
    frame->image = {1, 2, 3};
    session.deliver(std::shared_ptr<const EncodedFrame>(frame));
    ASSERT_EQ(sent.size(), 3U);
    EXPECT_EQ(packed, 1);
    EXPECT_EQ(sent[0], sent[1]);
    EXPECT_EQ(sent[0], sent[2]);
    EXPECT_EQ(*sent[0], (std::vector<std::uint8_t>{1, 2, 3}));
}

TEST(Session, WithdrawnJobsReachNobodyAndFailuresReachEveryViewer) {
    Session session("s", "v", nullptr, {}, owner);
    std::vector<std::string> heard;
    for (const ViewerId viewer : {owner, first_viewer}) {
        ASSERT_TRUE(session.add_viewer(
                viewer,
                [&heard](const ViewerOutcome& outcome) {
                    const auto* failure = std::get_if<FrameFailure>(&outcome);
                    heard.push_back(failure != nullptr
                                            ? std::string(base::name_of(failure->error.code)) +
                                                      " answering " +
                                                      std::to_string(failure->request_id)
                                            : "frame");
                },
                {}, {}));
    }
    session.deliver(Withdrawn::superseded);
    session.deliver(Withdrawn::shutting_down);
    EXPECT_TRUE(heard.empty());
    session.deliver(
            FrameFailure{base::make_error(base::ErrorCode::too_much_work, "over the ceiling"), 7});
    EXPECT_EQ(heard,
              (std::vector<std::string>{"too_much_work answering 7", "too_much_work answering 7"}));
    EXPECT_EQ(session.frame_count(), 0U);
}

// Refuses every frame as the renderer refuses one over the work ceiling: before it runs.
class RefusingRenderer final : public render::FrameRenderer {
public:
    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest&,
                                       const render::CancelPredicate&) override {
        return base::make_error(base::ErrorCode::too_much_work, "over the ceiling", "render");
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
};

// A frame the renderer refuses answers the request that asked for it: every viewer hears the
// failure with that request's id, as a frame would carry it.
TEST(Session, AFrameTheRendererRefusesAnswersItsRequestId) {
    metrics::Registry metrics;
    auto scheduler = Scheduler::create(
            []() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                return std::unique_ptr<render::FrameRenderer>(std::make_unique<RefusingRenderer>());
            },
            {}, metrics);
    ASSERT_TRUE(scheduler.ok()) << scheduler.error().to_string();
    auto session = std::make_shared<Session>("s", "v", nullptr, scene::State{}, owner);
    std::mutex mutex;
    std::condition_variable heard_all;
    std::vector<std::pair<ViewerId, std::string>> heard;
    for (const ViewerId viewer : {owner, first_viewer}) {
        ASSERT_TRUE(session->add_viewer(
                viewer,
                [&, viewer](const ViewerOutcome& outcome) {
                    const auto* failure = std::get_if<FrameFailure>(&outcome);
                    const std::lock_guard lock(mutex);
                    heard.emplace_back(viewer,
                                       failure != nullptr
                                               ? std::string(base::name_of(failure->error.code)) +
                                                         " answering " +
                                                         std::to_string(failure->request_id)
                                               : "frame");
                    heard_all.notify_all();
                },
                {}, {}));
    }
    session->render(**scheduler, 42, false, "10.0.0.1");
    std::unique_lock lock(mutex);
    ASSERT_TRUE(
            heard_all.wait_for(lock, std::chrono::seconds(30), [&] { return heard.size() == 2; }));
    EXPECT_EQ(heard, (std::vector<std::pair<ViewerId, std::string>>{
                             {owner, "too_much_work answering 42"},
                             {first_viewer, "too_much_work answering 42"}}));
    lock.unlock();
    (*scheduler)->stop();
}

TEST(Session, OnlyTheOwnerChangesTheStateAndAFailedChangeLeavesItAsItWas) {
    Session session("s", "v", nullptr, state_with_mode(scene::Mode::sbrc), owner);
    Heard by_viewer;
    ASSERT_TRUE(session.add_viewer(owner, {}, {}, {}));
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, by_viewer.sink("changed"), {}));
    const auto to_dvr = [](scene::State& state) {
        state.frame.settings.mode = scene::Mode::dvr;
        return base::Status(base::Ok{});
    };
    const auto refused = session.change_state(first_viewer, to_dvr);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::invalid_message);
    const auto failed = session.change_state(owner, [](scene::State& state) {
        state.frame.settings.mode = scene::Mode::phong;
        return base::Status(base::make_error(base::ErrorCode::invalid_value, "no", "/settings"));
    });
    EXPECT_FALSE(failed.ok());
    EXPECT_EQ(session.state().frame.settings.mode, scene::Mode::sbrc);
    EXPECT_TRUE(by_viewer.events.empty());
    ASSERT_TRUE(session.change_state(owner, to_dvr).ok());
    EXPECT_EQ(session.state().frame.settings.mode, scene::Mode::dvr);
    EXPECT_EQ(by_viewer.events, std::vector<std::string>{"changed:dvr"});
}

TEST(Session, TheOwnerTokenIsAFreshUnguessableSecret) {
    const Session first("s1", "v", nullptr, {}, owner);
    const Session second("s2", "v", nullptr, {}, owner);
    EXPECT_EQ(first.owner_token().size(), 32U);
    EXPECT_EQ(first.owner_token().find_first_not_of("0123456789abcdef"), std::string::npos);
    EXPECT_NE(first.owner_token(), second.owner_token());
}

TEST(Session, TheOwnerLeavingLeavesTheViewersWatchingASessionWithoutOwner) {
    Session session("s", "v", nullptr, state_with_mode(scene::Mode::sbrc), owner);
    ASSERT_TRUE(session.add_viewer(owner, {}, {}, {}));
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, {}, {}));
    EXPECT_EQ(session.owner(), owner);
    EXPECT_TRUE(session.is_owner(owner));
    EXPECT_FALSE(session.is_owner(first_viewer));
    EXPECT_EQ(session.remove_viewer(owner), 1U);
    EXPECT_EQ(session.owner(), std::nullopt);
    EXPECT_FALSE(session.is_owner(owner));
    EXPECT_FALSE(session.is_owner(first_viewer));
}

TEST(Session, ResumingWithTheTokenMakesANewConnectionTheOwnerWhoseStatesReachTheViewers) {
    Session session("s", "v", nullptr, state_with_mode(scene::Mode::sbrc), owner);
    Heard by_viewer;
    Heard by_resumer;
    ASSERT_TRUE(session.add_viewer(owner, {}, {}, {}));
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, by_viewer.sink("changed"),
                                   by_viewer.sink("welcome")));
    session.set_state(state_with_mode(scene::Mode::dvr), owner);
    session.remove_viewer(owner);

    const auto resumed = session.resume(resuming, session.owner_token(), {},
                                        by_resumer.sink("changed"), by_resumer.sink("welcome"));
    ASSERT_TRUE(resumed.ok()) << resumed.error().to_string();
    EXPECT_EQ(session.owner(), resuming);
    EXPECT_EQ(session.viewer_count(), 2U);
    session.set_state(state_with_mode(scene::Mode::phong), resuming);
    // The resumer starts from the state as it was; the viewer heard of nothing but changes.
    EXPECT_EQ(by_resumer.events, std::vector<std::string>{"welcome:dvr"});
    EXPECT_EQ(by_viewer.events,
              (std::vector<std::string>{"welcome:sbrc", "changed:dvr", "changed:phong"}));
    // Resuming again, as the owner, only replaces its sinks.
    EXPECT_TRUE(session.resume(resuming, session.owner_token(), {}, {}, {}).ok());
    EXPECT_EQ(session.owner(), resuming);
}

TEST(Session, AViewerWithTheTokenMayResumeTooAndFramesStillReachEveryone) {
    Session session("s", "v", nullptr, {}, owner);
    std::vector<ViewerId> delivered;
    const auto frames_to = [&delivered](ViewerId viewer) {
        return [&delivered, viewer](const ViewerOutcome&) { delivered.push_back(viewer); };
    };
    ASSERT_TRUE(session.add_viewer(owner, frames_to(owner), {}, {}));
    ASSERT_TRUE(session.add_viewer(first_viewer, frames_to(first_viewer), {}, {}));
    session.remove_viewer(owner);
    ASSERT_TRUE(session.resume(first_viewer, session.owner_token(), frames_to(first_viewer), {}, {})
                        .ok());
    EXPECT_TRUE(session.is_owner(first_viewer));
    EXPECT_EQ(session.viewer_count(), 1U);
    session.deliver(std::make_shared<const EncodedFrame>());
    EXPECT_EQ(delivered, std::vector<ViewerId>{first_viewer});
}

TEST(Session, AWrongTokenIsRefusedAndChangesNothing) {
    Session session("s", "v", nullptr, {}, owner);
    ASSERT_TRUE(session.add_viewer(owner, {}, {}, {}));
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, {}, {}));
    session.remove_viewer(owner);
    std::string wrong = session.owner_token();
    wrong.back() = wrong.back() == '0' ? '1' : '0';
    for (const std::string& token :
         {wrong, std::string(), session.owner_token() + "0", session.id()}) {
        SCOPED_TRACE(token);
        Heard heard;
        const auto refused = session.resume(resuming, token, {}, {}, heard.sink("welcome"));
        ASSERT_FALSE(refused.ok());
        EXPECT_EQ(refused.error().code, base::ErrorCode::invalid_value);
        EXPECT_EQ(refused.error().where, "/owner_token");
        EXPECT_EQ(refused.error().message.find(session.owner_token()), std::string::npos);
        EXPECT_TRUE(heard.events.empty());
    }
    EXPECT_EQ(session.owner(), std::nullopt);
    EXPECT_EQ(session.viewer_count(), 1U);
}

TEST(Session, ResumingWhileTheOwnerIsConnectedIsRefused) {
    Session session("s", "v", nullptr, {}, owner);
    ASSERT_TRUE(session.add_viewer(owner, {}, {}, {}));
    const auto refused = session.resume(resuming, session.owner_token(), {}, {}, {});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::session_owned);
    EXPECT_EQ(refused.error().where, "/session");
    EXPECT_EQ(session.owner(), owner);
    EXPECT_EQ(session.viewer_count(), 1U);
    // A wrong token says nothing of the owner.
    EXPECT_EQ(session.resume(resuming, "", {}, {}, {}).error().code,
              base::ErrorCode::invalid_value);
}

TEST(Session, OnceTheLastViewerLeftNobodyResumes) {
    Session session("s", "v", nullptr, {}, owner);
    ASSERT_TRUE(session.add_viewer(owner, {}, {}, {}));
    ASSERT_TRUE(session.add_viewer(first_viewer, {}, {}, {}));
    session.remove_viewer(owner);
    EXPECT_EQ(session.remove_viewer(first_viewer), 0U);
    const auto refused = session.resume(resuming, session.owner_token(), {}, {}, {});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::unknown_session);
    EXPECT_EQ(session.viewer_count(), 0U);
}

TEST(SessionRegistry, SessionIdsAreFreshSecretsApartFromTheOwnerTokens) {
    SessionRegistry registry(4);
    const auto first = registry.create("v", nullptr, {}, owner);
    const auto second = registry.create("v", nullptr, {}, owner);
    ASSERT_TRUE(first.ok() && second.ok());
    for (const auto& session : {*first, *second}) {
        EXPECT_EQ(session->id().size(), 32U);
        EXPECT_EQ(session->id().find_first_not_of("0123456789abcdef"), std::string::npos);
        EXPECT_NE(session->id(), session->owner_token());
    }
    EXPECT_NE((*first)->id(), (*second)->id());
}

TEST(SessionRegistry, ASessionEndsWithItsLastConnectionAndIsFoundNoMore) {
    metrics::Registry metrics;
    const auto scheduler = idle_scheduler(metrics);
    SessionRegistry registry(4);
    auto created = registry.create("v", nullptr, {}, owner);
    ASSERT_TRUE(created.ok());
    const std::shared_ptr<Session> session = *created;
    EXPECT_EQ(session->viewer_count(), 1U) << "its owner is its first viewer";
    ASSERT_TRUE(registry.enter(session->id(),
                               [](Session& s) { return s.add_viewer(first_viewer, {}, {}, {}); })
                        .ok());
    EXPECT_FALSE(registry.leave(*session, owner, *scheduler));
    EXPECT_EQ(registry.find(session->id()), session) << "viewers keep it running without owner";
    EXPECT_TRUE(registry.leave(*session, first_viewer, *scheduler));
    EXPECT_EQ(registry.find(session->id()), nullptr);
    EXPECT_EQ(registry.count(), 0U);
    const auto gone = registry.enter(
            session->id(), [](Session& s) { return s.add_viewer(second_viewer, {}, {}, {}); });
    ASSERT_FALSE(gone.ok());
    EXPECT_EQ(gone.error().code, base::ErrorCode::unknown_session);
    EXPECT_EQ(gone.error().where, "/session");
}

TEST(Session, AnEndedSessionTakesNoViewer) {
    Session session("s", "v", nullptr, {}, owner);
    EXPECT_EQ(session.remove_viewer(owner), 0U);
    const auto refused = session.add_viewer(first_viewer, {}, {}, {});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::unknown_session);
    EXPECT_EQ(session.viewer_count(), 0U);
}

// Each race: the session's only viewer leaves while another connection joins it. Whichever wins,
// the joiner is in a session the registry still holds, or was refused; never in an ended one.
TEST(SessionRegistry, AJoinRacingTheLastLeaveNeverRevivesAnEndedSession) {
    metrics::Registry metrics;
    const auto scheduler = idle_scheduler(metrics);
    SessionRegistry registry(4);
    int joined_first = 0;
    int refused = 0;
    for (int race = 0; race < 200; ++race) {
        SCOPED_TRACE(race);
        auto created = registry.create("v", nullptr, {}, owner);
        ASSERT_TRUE(created.ok());
        const std::shared_ptr<Session> session = *created;
        std::atomic<int> ready{0};
        base::Result<std::shared_ptr<Session>> joined =
                base::make_error(base::ErrorCode::internal_error, "", "");
        std::thread joiner([&] {
            ready.fetch_add(1);
            while (ready.load() < 2) {
            }
            joined = registry.enter(session->id(), [](Session& s) {
                return s.add_viewer(first_viewer, {}, {}, {});
            });
        });
        ready.fetch_add(1);
        while (ready.load() < 2) {
        }
        registry.leave(*session, owner, *scheduler);
        joiner.join();
        if (joined.ok()) {
            ++joined_first;
            EXPECT_EQ(registry.find(session->id()), session) << "joined, so it must still run";
            EXPECT_EQ(session->viewer_count(), 1U);
            EXPECT_TRUE(registry.leave(*session, first_viewer, *scheduler));
        } else {
            ++refused;
            EXPECT_EQ(joined.error().code, base::ErrorCode::unknown_session);
            EXPECT_EQ(session->viewer_count(), 0U) << "refused, so nobody is in it";
        }
        EXPECT_EQ(registry.count(), 0U);
    }
    EXPECT_EQ(joined_first + refused, 200);
}

TEST(OwnerTokens, AClusterSecretDerivesTheSameTokenOnEveryServerAndAnotherSecretDoesNot) {
    const OwnerTokens here("shared secret");
    const OwnerTokens there("shared secret");
    const OwnerTokens elsewhere("another secret");
    const std::string token = here.token_for("0123abcd");
    EXPECT_EQ(token.size(), 32U);
    EXPECT_EQ(token.find_first_not_of("0123456789abcdef"), std::string::npos);
    EXPECT_EQ(there.token_for("0123abcd"), token);
    EXPECT_TRUE(there.proves("0123abcd", token));
    EXPECT_FALSE(there.proves("0123abce", token)) << "a token proves its own session only";
    EXPECT_FALSE(elsewhere.proves("0123abcd", token));
    EXPECT_FALSE(OwnerTokens().proves("0123abcd", token)) << "random tokens prove nothing";
    EXPECT_NE(OwnerTokens().token_for("0123abcd"), OwnerTokens().token_for("0123abcd"));
}

TEST(SessionRegistry, AnotherServerOfTheClusterRecreatesASessionForItsOwnerOnly) {
    SessionRegistry died(4, OwnerTokens("cluster"));
    auto created = died.create("v", nullptr, state_with_mode(scene::Mode::sbrc), owner);
    ASSERT_TRUE(created.ok());
    const std::string id = (*created)->id();
    const std::string token = (*created)->owner_token();

    SessionRegistry successor(4, OwnerTokens("cluster"));
    EXPECT_TRUE(successor.proves_owner(id, token));
    EXPECT_FALSE(successor.proves_owner(id, std::string(32, '0')));
    const auto forged = successor.recreate(id, std::string(32, '0'), "v", nullptr, {}, resuming);
    ASSERT_FALSE(forged.ok());
    EXPECT_EQ(forged.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(forged.error().where, "/owner_token");
    EXPECT_EQ(successor.count(), 0U);

    const auto recreated = successor.recreate(id, token, "v", nullptr,
                                              state_with_mode(scene::Mode::dvr), resuming);
    ASSERT_TRUE(recreated.ok());
    EXPECT_TRUE(recreated->created);
    EXPECT_EQ(recreated->session->id(), id);
    EXPECT_EQ(recreated->session->owner_token(), token);
    EXPECT_TRUE(recreated->session->is_owner(resuming));
    EXPECT_EQ(successor.find(id), recreated->session) << "viewers joining the id find it";

    const auto again = successor.recreate(id, token, "v", nullptr, {}, owner);
    ASSERT_TRUE(again.ok());
    EXPECT_FALSE(again->created) << "an existing session is resumed, not replaced";
    EXPECT_EQ(again->session, recreated->session);
}

TEST(SessionRegistry, AServerWithoutClusterSecretRecreatesNothing) {
    SessionRegistry alone(4);
    auto created = alone.create("v", nullptr, {}, owner);
    ASSERT_TRUE(created.ok());
    EXPECT_FALSE(alone.derives_owner_tokens());
    SessionRegistry other(4);
    const auto refused =
            other.recreate((*created)->id(), (*created)->owner_token(), "v", nullptr, {}, resuming);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::unknown_session);
}

TEST(SessionRegistry, RecreatingRespectsTheSessionLimit) {
    SessionRegistry full(1, OwnerTokens("cluster"));
    ASSERT_TRUE(full.create("v", nullptr, {}, owner).ok());
    const OwnerTokens tokens("cluster");
    const auto refused =
            full.recreate("elsewhere", tokens.token_for("elsewhere"), "v", nullptr, {}, resuming);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::too_many_sessions);
}

}  // namespace
}  // namespace penumbra::session
