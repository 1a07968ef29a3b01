// The service end to end: a real server on 127.0.0.1 and a free port, real WebSocket clients.

#include "dicom_writer.hpp"
#include "movie_reader.hpp"

#include <penumbra/encode/encode.hpp>
#include <penumbra/encode/stream.hpp>
#include <penumbra/imageio/compare.hpp>
#include <penumbra/imageio/imageio.hpp>
#include <penumbra/metrics/registry.hpp>
#include <penumbra/net/client.hpp>
#include <penumbra/net/load.hpp>
#include <penumbra/net/server.hpp>
#include <penumbra/protocol/frame_header.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/session/scheduler.hpp>
#include <penumbra/session/session.hpp>
#include <penumbra/session/volume_store.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <thread>

namespace penumbra::integration {
namespace {

namespace fs = std::filesystem;

// Appends every message the server sent to a JSONL file that a later CTest validates against
// proto/v1's schemas. A test's first message starts its file afresh, so messages from an older
// build never reach the validation.
void record(const std::string& kind, const std::string& json) {
    static std::mutex mutex;
    static std::set<fs::path> started;
    const std::lock_guard lock(mutex);
    const fs::path dir = PENUMBRA_SENT_MESSAGES;
    fs::create_directories(dir);
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path file =
            dir / (std::string(test->test_suite_name()) + "." + test->name() + ".jsonl");
    std::ofstream out(file, started.insert(file).second ? std::ios::trunc : std::ios::app);
    out << R"({"kind":")" << kind << R"(","message":)" << json << "}\n";
}

// A top-level string member of a JSON message ("" when absent or not a string).
std::string field(const std::string& text, const std::string& name) {
    const auto json = nlohmann::json::parse(text, nullptr, false);
    if (!json.is_object() || !json.contains(name) || !json.at(name).is_string()) {
        return "";
    }
    return json.at(name).get<std::string>();
}

class TestClient {
public:
    // `from`: the local address, to play another client (any of 127.0.0.0/8 on Linux).
    explicit TestClient(unsigned short port, const std::string& from = {}) {
        auto connected =
                net::Client::connect("127.0.0.1", port, "/ws", std::chrono::seconds(10), from);
        EXPECT_TRUE(connected.ok()) << connected.error().to_string();
        client_ = std::move(connected.value());
        hello = next_text();
    }

    void send(const std::string& text) {
        auto status = client_->send_text(text);
        ASSERT_TRUE(status.ok()) << status.error().to_string();
    }

    // The next text message (frames in between are kept for next_frame).
    std::string next_text(std::chrono::milliseconds timeout = std::chrono::seconds(30)) {
        while (true) {
            auto message = client_->receive(timeout);
            if (!message.ok()) {
                ADD_FAILURE() << message.error().to_string();
                return {};
            }
            if (message->binary) {
                frames_.push_back(std::move(message->bytes));
                continue;
            }
            record("text", message->text);
            return message->text;
        }
    }

    // Whether next_frame passes on the refinement steps of a still (frames with `refinement` > 0),
    // which every still of a new session is followed by, and the preview of a costly still; most
    // tests wait for the frame of a request and pass them by.
    enum class Steps { passed_by, returned };

    protocol::UnpackedFrame next_frame(std::chrono::milliseconds timeout = std::chrono::seconds(60),
                                       Steps steps = Steps::passed_by) {
        while (true) {
            auto frame = next_frame_or_step(timeout);
            if (steps == Steps::returned ||
                (frame.header.refinement == 0 && !frame.header.preview)) {
                return frame;
            }
        }
    }

    // The first frame that answers `request`, the still or one of its refinement steps: while a
    // reader is slow, the server's send queue lets a step take the place of the still it refines
    // (the newest view wins), so the still itself may never come. Steps and previews of other
    // requests are passed by; any other frame is returned, for the caller to see it is not the
    // answer.
    protocol::UnpackedFrame frame_answering(std::int64_t request) {
        while (true) {
            auto frame = next_frame_or_step(std::chrono::seconds(60));
            const bool answer = frame.header.request == request && !frame.header.preview;
            const bool passed_by = frame.header.refinement > 0 || frame.header.preview;
            if (frame.header.session.empty() || answer || !passed_by) {
                return frame;
            }
        }
    }

    protocol::UnpackedFrame next_frame_or_step(std::chrono::milliseconds timeout) {
        while (frames_.empty()) {
            auto message = client_->receive(timeout);
            if (!message.ok()) {
                ADD_FAILURE() << message.error().to_string();
                return {};
            }
            if (message->binary) {
                frames_.push_back(std::move(message->bytes));
            } else {
                record("text", message->text);
                texts_.push_back(message->text);
            }
        }
        auto frame = protocol::unpack_frame(frames_.front());
        frames_.erase(frames_.begin());
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        if (!frame.ok()) {
            return {};
        }
        record("frame_header", frame->header_json);
        return std::move(frame.value());
    }

    // Sends a request and returns the reply (text).
    std::string request(const std::string& text) {
        send(text);
        if (!texts_.empty()) {
            std::string first = texts_.front();
            texts_.erase(texts_.begin());
            return first;
        }
        return next_text();
    }

    std::string open(const std::string& volume, int size = 64) {
        const std::string opened =
                request(R"({"v":1,"type":"open","id":1,"volume":")" + volume + "\"}");
        session = field(opened, "session");
        EXPECT_FALSE(session.empty()) << opened;
        const std::string ack = request(R"({"v":1,"type":"set","id":2,"settings":{"size":[)" +
                                        std::to_string(size) + "," + std::to_string(size) +
                                        R"(],"light_buffer":{"slices":32,"resolution":64}}})");
        EXPECT_EQ(field(ack, "type"), "ack") << ack;
        return opened;
    }

    net::Client& raw() { return *client_; }

    std::string hello;
    std::string session;

private:
    std::unique_ptr<net::Client> client_;
    std::vector<std::vector<std::uint8_t>> frames_;
    std::vector<std::string> texts_;
};

class ServerTest : public ::testing::Test {
protected:
    void SetUp() override {
        data_ = fs::temp_directory_path() /
                ("penumbra_it_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(data_ / "heads");
        const fs::path ch2 = "/usr/share/mricron/templates/ch2.nii.gz";
        ASSERT_TRUE(fs::exists(ch2)) << "install mricron-data (scripts/install-deps.sh does)";
        fs::copy_file(ch2, data_ / "heads" / "ch2.nii.gz");
        std::ofstream(data_ / "broken_4x4x4_uint8.raw") << "too short";
        start(protocol::Limits{});
    }

    // `configure` adjusts the rest of the server's configuration (pings, per-client limits).
    void start(protocol::Limits limits,
               const std::function<void(net::ServerConfig&)>& configure = {}) {
        server_.reset();
        scheduler_.reset();
        volumes_ = std::make_unique<session::VolumeStore>(data_, std::size_t{1} << 30);
        ASSERT_TRUE(volumes_->scan().ok());
        metrics_ = std::make_unique<metrics::Registry>();
        render::RendererOptions renderer_options;
        renderer_options.max_frame_work = limits.max_frame_work;
        auto scheduler = session::Scheduler::create(
                [renderer_options]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                    auto renderer = render::Renderer::create(renderer_options);
                    if (!renderer) {
                        return renderer.error();
                    }
                    return std::unique_ptr<render::FrameRenderer>(std::move(renderer.value()));
                },
                // Two frames in flight, as on a GPU, although llvmpipe would take one: every test
                // here then also proves the pipelined path with the real renderer.
                session::SchedulerOptions{.frames_in_flight = 2}, *metrics_);
        ASSERT_TRUE(scheduler.ok()) << scheduler.error().to_string();
        scheduler_ = std::move(scheduler.value());
        // A small measured table: sbrc at n=32 fits 50 ms at 64x64, the reference does not.
        auto table = std::make_shared<quality::Table>();
        table->width = 64;
        table->height = 64;
        const auto point = [](scene::Mode mode, int slices, int resolution, double frame_ms,
                              double psnr) {
            quality::Point p;
            p.volume = "ch2";
            p.mode = mode;
            p.slices = slices;
            p.resolution = resolution;
            p.sample_distance = 1.0 / 256;
            p.frame_ms = frame_ms;
            p.psnr = p.psnr_truth = psnr;
            return p;
        };
        table->points = {point(scene::Mode::phong, 0, 0, 20.0, 18.0),
                         point(scene::Mode::sbrc, 32, 64, 40.0, 24.0),
                         point(scene::Mode::reference, 0, 0, 400.0, quality::infinity)};
        sessions_ = std::make_unique<session::SessionRegistry>(
                limits.max_sessions, owner_tokens_, limits.max_sessions_per_client,
                limits.max_sessions_per_connection, std::move(table));
        net::ServerConfig config;
        config.port = 0;
        config.limits = limits;
        if (configure) {
            configure(config);
        }
        auto server = net::Server::start(config, {*volumes_, *sessions_, *scheduler_, *metrics_});
        ASSERT_TRUE(server.ok()) << server.error().to_string();
        server_ = std::move(server.value());
        port_ = server_->port();
    }

    void TearDown() override {
        if (server_) {
            server_->stop();
        }
        if (scheduler_) {
            scheduler_->stop();
        }
        std::error_code ec;
        fs::remove_all(data_, ec);
    }

    fs::path data_;
    std::unique_ptr<session::VolumeStore> volumes_;
    std::unique_ptr<metrics::Registry> metrics_;
    std::unique_ptr<session::Scheduler> scheduler_;
    std::unique_ptr<session::SessionRegistry> sessions_;
    session::OwnerTokens owner_tokens_;  // set before start(): a cluster's derived tokens
    std::unique_ptr<net::Server> server_;
    unsigned short port_ = 0;
};

TEST_F(ServerTest, HelloAnnouncesLimitsAndListVolumesFindsTheData) {
    TestClient client(port_);
    EXPECT_EQ(field(client.hello, "type"), "hello");
    EXPECT_NE(client.hello.find("\"max_image_side\""), std::string::npos);
    EXPECT_NE(client.hello.find("sbrc_cone"), std::string::npos);
    const std::string volumes = client.request(R"({"v":1,"type":"list_volumes","id":7})");
    EXPECT_EQ(field(volumes, "type"), "volumes");
    EXPECT_NE(volumes.find("\"heads/ch2.nii.gz\""), std::string::npos) << volumes;
    EXPECT_NE(volumes.find("\"id\":7"), std::string::npos);
}

TEST_F(ServerTest, HelloAnnouncesNoMoreThanTheRendererCanAllocate) {
    protocol::Limits limits;
    limits.max_image_side = 1 << 30;
    limits.max_slices = 1 << 30;
    limits.max_light_resolution = 1 << 30;
    start(limits);
    const render::RendererInfo& info = scheduler_->renderer_info();
    TestClient client(port_);
    const auto hello = nlohmann::json::parse(client.hello);
    const auto& announced = hello.at("limits");
    EXPECT_EQ(announced.at("max_image_side").get<int>(), info.max_texture_size) << client.hello;
    EXPECT_EQ(announced.at("max_light_resolution").get<int>(), info.max_texture_size);
    EXPECT_EQ(announced.at("max_slices").get<int>(), info.max_array_texture_layers);
}

// A clinic's export folder holding two series: the list shows each under its own id, named by
// description and number, and each id opens its own series.
TEST_F(ServerTest, ADicomFolderOfTwoSeriesListsTwoVolumes) {
    fs::create_directories(data_ / "study");
    for (const auto& [number, dims] :
         {std::pair{"2", glm::uvec3(8, 8, 4)}, std::pair{"7", glm::uvec3(6, 6, 3)}}) {
        volume::fixtures::SeriesSpec spec;
        spec.dims = dims;
        spec.series_number = number;
        spec.series_description = std::string("series ") + number + " head";
        const auto files = volume::fixtures::write_series(
                data_ / "export" / number, spec,
                std::vector<std::uint16_t>(std::size_t{dims.x} * dims.y * dims.z, 100));
        for (const auto& file : files) {
            fs::rename(file, data_ / "study" / (std::string(number) + file.filename().string()));
        }
    }
    fs::remove_all(data_ / "export");
    start(protocol::Limits{});
    TestClient client(port_);
    const std::string volumes = client.request(R"({"v":1,"type":"list_volumes","id":3})");
    for (const char* expected : {R"("id":"study#2")", R"x("name":"series 2 head (series 2)")x",
                                 R"("id":"study#7")", R"x("name":"series 7 head (series 7)")x"}) {
        EXPECT_NE(volumes.find(expected), std::string::npos) << expected << " in " << volumes;
    }
    EXPECT_EQ(volumes.find(R"("id":"study")"), std::string::npos) << volumes;
    const std::string opened = client.open("study#7");
    EXPECT_NE(opened.find(R"("dims":[6,6,3])"), std::string::npos) << opened.substr(0, 300);
}

// A session on a CT (values in Hounsfield units) starts from the CT bone preset, one on an MRI
// from the server's default.
TEST_F(ServerTest, ASessionOnACtStartsWithTheCtBonePreset) {
    {
        std::ofstream ct(data_ / "ct.nrrd", std::ios::binary);
        ct << "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n"
              "endian: little\npenumbra_units:=HU\n\n";
        for (int i = 0; i < 64; ++i) {
            const std::int16_t hu = static_cast<std::int16_t>(i % 2 == 0 ? -1000 : 700);
            ct.write(reinterpret_cast<const char*>(&hu), sizeof hu);
        }
    }
    start(protocol::Limits{});
    TestClient ct(port_);
    const std::string on_ct = ct.open("ct.nrrd");
    EXPECT_NE(on_ct.find(R"("hounsfield":true)"), std::string::npos) << on_ct.substr(0, 300);
    EXPECT_NE(on_ct.find(R"("name":"ct_bone")"), std::string::npos) << on_ct;
    TestClient mri(port_);
    const std::string on_mri = mri.open("heads/ch2.nii.gz");
    EXPECT_NE(on_mri.find(R"("name":"mri_skin")"), std::string::npos) << on_mri.substr(0, 300);
}

TEST_F(ServerTest, OpensCh2AndRendersADecodableNonBlankFrame) {
    TestClient client(port_);
    const std::string opened = client.open("heads/ch2.nii.gz");
    EXPECT_NE(opened.find("\"dims\":[181,217,181]"), std::string::npos) << opened.substr(0, 300);
    client.send(R"({"v":1,"type":"render","id":42})");
    const auto frame = client.next_frame();
    EXPECT_EQ(frame.header.request, 42);
    EXPECT_EQ(frame.header.width, 64);
    EXPECT_EQ(frame.header.encoding, "jpeg");
    EXPECT_EQ(frame.header.mode, "sbrc");
    EXPECT_EQ(frame.header.light_buffer, "built");
    EXPECT_GT(frame.header.render_ms, 0.0);
    auto image = imageio::decode_image(frame.image);
    ASSERT_TRUE(image.ok()) << image.error().to_string();
    EXPECT_EQ(image->width, 64);
    EXPECT_EQ(image->height, 64);
    int lit = 0;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            lit += image->pixel(x, y)[0] > 40 ? 1 : 0;
        }
    }
    EXPECT_GT(lit, 64 * 64 / 5) << "the head should cover a good part of the frame";
}

// `penumbra load`'s generator: each simulated client opens the volume named in its URL and gets
// the frames it asks for, one in flight; the report splits their latency.
TEST_F(ServerTest, LoadClientsEachGetTheirFramesAndTheReportSplitsTheLatency) {
    // Small frames come faster than a person's requests; the rate limit is not what is tested.
    protocol::Limits limits;
    limits.max_requests_per_second = 1e6;
    start(limits);
    net::LoadConfig config;
    config.port = port_;
    config.clients = 2;
    config.seconds = 1.0;
    config.volume = "heads/ch2.nii.gz";
    config.mode = "dvr";
    config.size = 32;
    config.encoding = "png";
    const net::LoadReport report = net::run_load(config);
    EXPECT_TRUE(report.ok()) << (report.error_texts.empty() ? "" : report.error_texts.front());
    EXPECT_GE(report.samples.size(), 2u);
    EXPECT_GE(report.elapsed_s, 1.0);
    for (const net::LoadSample& sample : report.samples) {
        EXPECT_GE(sample.latency_ms, sample.render_ms);
        EXPECT_GT(sample.bytes, 0u);
    }
    std::FILE* out = std::tmpfile();
    ASSERT_NE(out, nullptr);
    net::print_load_report(config, report, out);
    std::rewind(out);
    std::string printed(4096, '\0');
    printed.resize(std::fread(printed.data(), 1, printed.size(), out));
    std::fclose(out);
    EXPECT_NE(printed.find("load:     2 client(s), dvr 32x32 png"), std::string::npos) << printed;
    EXPECT_NE(printed.find("latency (client)"), std::string::npos) << printed;
    EXPECT_EQ(printed.find("error:"), std::string::npos) << printed;
}

TEST_F(ServerTest, LoadClientsReportAVolumeTheServerRefuses) {
    net::LoadConfig config;
    config.port = port_;
    config.clients = 1;
    config.seconds = 0.5;
    config.volume = "no such volume.nii";
    config.size = 32;
    const net::LoadReport report = net::run_load(config);
    EXPECT_FALSE(report.ok());
    EXPECT_EQ(report.errors, 1u);
    ASSERT_EQ(report.error_texts.size(), 1u);
    EXPECT_EQ(report.error_texts.front().rfind("client 0: ", 0), 0u) << report.error_texts.front();
}

TEST(LoadPath, NamesTheVolumeAndTokenEncodedAsABrowserWould) {
    EXPECT_EQ(net::load_path("heads/ch2.nii.gz", ""), "/ws?volume=heads%2Fch2.nii.gz");
    EXPECT_EQ(net::load_path("a b+c", "t/k=1"), "/ws?volume=a+b%2Bc&token=t%2Fk%3D1");
}

TEST_F(ServerTest, CameraOnlyChangesReuseTheLightBuffer) {
    TestClient client(port_);
    client.open("heads/ch2.nii.gz", 48);
    client.send(R"({"v":1,"type":"render","id":1})");
    EXPECT_EQ(client.next_frame().header.light_buffer, "built");
    for (int i = 0; i < 3; ++i) {
        const std::string ack =
                client.request(R"({"v":1,"type":"set","camera":{"orbit":{"azimuth":)" +
                               std::to_string(40 * i) + R"(,"elevation":10,"distance":2.5}}})");
        ASSERT_EQ(field(ack, "type"), "ack") << ack;
        client.send(R"({"v":1,"type":"render"})");
        EXPECT_EQ(client.next_frame().header.light_buffer, "reused");
    }
    client.request(R"({"v":1,"type":"set","light":{"direction":[1,0,0]}})");
    client.send(R"({"v":1,"type":"render"})");
    EXPECT_EQ(client.next_frame().header.light_buffer, "built");
}

TEST_F(ServerTest, TwoSessionsOnOneVolumeLoadItOnce) {
    TestClient first(port_);
    TestClient second(port_);
    first.open("heads/ch2.nii.gz", 32);
    second.open("heads/ch2.nii.gz", 32);
    EXPECT_NE(first.session, second.session);
    EXPECT_EQ(volumes_->loads(), 1u);
    first.send(R"({"v":1,"type":"render"})");
    second.send(R"({"v":1,"type":"render"})");
    EXPECT_EQ(first.next_frame().header.session, first.session);
    EXPECT_EQ(second.next_frame().header.session, second.session);
}

TEST_F(ServerTest, JoinedViewerReceivesTheSameFramesAndTheSessionSurvivesViewersLeaving) {
    TestClient owner(port_);
    owner.open("heads/ch2.nii.gz", 32);
    {
        TestClient viewer(port_);
        const std::string joined = viewer.request(R"({"v":1,"type":"join","id":3,"session":")" +
                                                  owner.session + "\"}");
        EXPECT_EQ(field(joined, "type"), "joined") << joined;
        const std::string refused =
                viewer.request(R"({"v":1,"type":"set","id":4,"camera":{"fov":40}})");
        EXPECT_EQ(field(refused, "type"), "error");
        owner.send(R"({"v":1,"type":"render","id":9})");
        const auto mine = owner.next_frame();
        const auto theirs = viewer.next_frame();
        EXPECT_EQ(mine.header.frame, theirs.header.frame);
        EXPECT_EQ(mine.image, theirs.image);
        viewer.raw().close();
    }
    owner.send(R"({"v":1,"type":"render","id":10})");
    EXPECT_EQ(owner.frame_answering(10).header.request, 10);
    // The viewer's goodbye reaches the server asynchronously.
    std::string stats;
    for (int i = 0; i < 50 && stats.find("\"viewers\":1") == std::string::npos; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        stats = owner.request(R"({"v":1,"type":"stats","id":11})");
    }
    EXPECT_NE(stats.find("\"viewers\":1"), std::string::npos) << stats;
}

// A label map in a session: the AAL atlas (its names and colours beside it) drawn inside ch2,
// styled with `set`, seen by a viewer who joins, refused to a viewer, taken away again.
TEST_F(ServerTest, TheOwnerDrawsAnAtlasInsideItsVolumeAndViewersSeeItsLabels) {
    for (const char* file : {"aal.nii.gz", "aal.nii.txt", "aal.nii.lut"}) {
        fs::copy_file(fs::path("/usr/share/mricron/templates") / file, data_ / "heads" / file);
    }
    ASSERT_TRUE(volumes_->scan().ok());
    TestClient owner(port_);
    owner.open("heads/ch2.nii.gz", 32);
    const auto added = nlohmann::json::parse(
            owner.request(R"({"v":1,"type":"add_labels","id":3,"volume":"heads/aal.nii.gz"})"));
    ASSERT_EQ(added.at("type"), "labels") << added;
    EXPECT_EQ(added.at("id"), 3);
    EXPECT_EQ(added.at("volume"), "heads/aal.nii.gz");
    ASSERT_EQ(added.at("labels").size(), 116U);
    EXPECT_EQ(added.at("labels")[0].at("name"), "Precentral_L");
    EXPECT_EQ(added.at("labels")[0].at("voxels"), 28174);
    EXPECT_EQ(added.at("labels")[0].at("color"), nlohmann::json::parse("[204,204,204]"));
    const auto& styles = added.at("state").at("labels").at("styles");
    ASSERT_EQ(styles.size(), 116U);
    EXPECT_EQ(styles.at("45").at("visible"), true);

    TestClient viewer(port_);
    const std::string joined =
            viewer.request(R"({"v":1,"type":"join","id":4,"session":")" + owner.session + "\"}");
    ASSERT_EQ(field(joined, "type"), "joined") << joined;
    const auto told = nlohmann::json::parse(viewer.next_text(std::chrono::seconds(10)));
    EXPECT_EQ(told.at("type"), "labels") << told;
    EXPECT_FALSE(told.contains("id"));
    EXPECT_EQ(told.at("labels").size(), 116U);
    const std::string refused =
            viewer.request(R"({"v":1,"type":"add_labels","id":5,"volume":"heads/aal.nii.gz"})");
    EXPECT_EQ(field(refused, "code"), "invalid_message") << refused;

    const auto only = nlohmann::json::parse(owner.request(
            R"({"v":1,"type":"set","id":6,"labels":{"only":[45,46],"styles":{"46":{"opacity":0.5}}}})"));
    ASSERT_EQ(only.at("type"), "ack") << only;
    const auto& shown = only.at("state").at("labels").at("styles");
    EXPECT_EQ(shown.at("45").at("visible"), true);
    EXPECT_EQ(shown.at("46").at("opacity"), 0.5);
    EXPECT_EQ(shown.at("1").at("visible"), false);
    const auto pushed = nlohmann::json::parse(viewer.next_text(std::chrono::seconds(10)));
    EXPECT_EQ(pushed.at("type"), "state");
    EXPECT_EQ(pushed.at("state").at("labels"), only.at("state").at("labels"));
    owner.send(R"({"v":1,"type":"render","id":7})");
    EXPECT_EQ(owner.frame_answering(7).header.request, 7);
    viewer.next_frame();

    const std::string unknown = owner.request(
            R"({"v":1,"type":"set","id":8,"labels":{"styles":{"9999":{"visible":false}}}})");
    EXPECT_EQ(field(unknown, "code"), "invalid_value") << unknown;
    EXPECT_EQ(field(unknown, "field"), "/labels/styles/9999") << unknown;
    const std::string broken = owner.request(
            R"({"v":1,"type":"add_labels","id":9,"volume":"broken_4x4x4_uint8.raw"})");
    EXPECT_EQ(field(broken, "code"), "volume_unreadable") << broken;
    // A scan is no label map, though its integers would make one; asked again, it is not read
    // again.
    for (int i = 0; i < 2; ++i) {
        const std::string scan =
                owner.request(R"({"v":1,"type":"add_labels","id":9,"volume":"heads/ch2.nii.gz"})");
        EXPECT_EQ(field(scan, "code"), "volume_unreadable") << scan;
        EXPECT_NE(field(scan, "message").find("not a label map"), std::string::npos) << scan;
    }

    const auto removed =
            nlohmann::json::parse(owner.request(R"({"v":1,"type":"remove_labels","id":10})"));
    ASSERT_EQ(removed.at("type"), "labels") << removed;
    EXPECT_EQ(removed.at("volume"), "");
    EXPECT_TRUE(removed.at("labels").empty());
    EXPECT_FALSE(removed.at("state").contains("labels"));
    // The viewer, there all along, is told that the map is gone and, when one is drawn again,
    // its labels' names, not only their styles.
    const auto gone = nlohmann::json::parse(viewer.next_text(std::chrono::seconds(10)));
    EXPECT_EQ(gone.at("type"), "labels") << gone;
    EXPECT_FALSE(gone.contains("id"));
    EXPECT_EQ(gone.at("volume"), "");
    EXPECT_TRUE(gone.at("labels").empty());
    ASSERT_EQ(field(owner.request(
                            R"({"v":1,"type":"add_labels","id":13,"volume":"heads/aal.nii.gz"})"),
                    "type"),
              "labels");
    const auto again = nlohmann::json::parse(viewer.next_text(std::chrono::seconds(10)));
    EXPECT_EQ(again.at("type"), "labels") << again;
    ASSERT_EQ(again.at("labels").size(), 116U);
    EXPECT_EQ(again.at("labels")[44].at("name"), "Cuneus_L");
    EXPECT_EQ(again.at("state").at("labels").at("styles").size(), 116U);
    ASSERT_EQ(field(owner.request(R"({"v":1,"type":"remove_labels","id":14})"), "type"), "labels");
    const std::string none =
            owner.request(R"({"v":1,"type":"set","id":11,"labels":{"blend":0.5}})");
    EXPECT_EQ(field(none, "code"), "invalid_value") << none;
    EXPECT_EQ(field(none, "field"), "/labels") << none;
    owner.send(R"({"v":1,"type":"render","id":12})");
    EXPECT_EQ(owner.frame_answering(12).header.request, 12);
}

// A pick over the wire: the brain seen from the left with the AAL atlas drawn names a left
// hemisphere's region under the view's middle, for the owner and a viewer alike; hidden, the same
// point names another region deeper in; a corner is no hit; a point outside the view is refused.
TEST_F(ServerTest, APickNamesTheLabelUnderAPointOfTheView) {
    for (const char* file : {"ch2bet.nii.gz", "aal.nii.gz", "aal.nii.txt", "aal.nii.lut"}) {
        fs::copy_file(fs::path("/usr/share/mricron/templates") / file, data_ / "heads" / file);
    }
    ASSERT_TRUE(volumes_->scan().ok());
    TestClient owner(port_);
    // The listing tells the label maps from the scans.
    const auto listed =
            nlohmann::json::parse(owner.request(R"({"v":1,"type":"list_volumes","id":2})"));
    std::map<std::string, bool> label_maps;
    for (const auto& volume : listed.at("volumes")) {
        label_maps[volume.at("id")] = volume.at("label_map");
    }
    EXPECT_TRUE(label_maps.at("heads/aal.nii.gz"));
    EXPECT_FALSE(label_maps.at("heads/ch2bet.nii.gz"));
    EXPECT_FALSE(label_maps.at("heads/ch2.nii.gz"));
    owner.open("heads/ch2bet.nii.gz", 32);
    const std::string added =
            owner.request(R"({"v":1,"type":"add_labels","id":3,"volume":"heads/aal.nii.gz"})");
    ASSERT_EQ(field(added, "type"), "labels") << added;
    const std::string set = owner.request(
            R"({"v":1,"type":"set","id":4,"camera":{"view":"left"},"transfer_function":{"preset":"mri_skin"}})");
    ASSERT_EQ(field(set, "type"), "ack") << set;
    const auto seen =
            nlohmann::json::parse(owner.request(R"({"v":1,"type":"pick","id":5,"x":0.5,"y":0.5})"));
    ASSERT_EQ(seen.at("type"), "picked") << seen;
    EXPECT_EQ(seen.at("id"), 5);
    EXPECT_EQ(seen.at("session"), owner.session);
    ASSERT_EQ(seen.at("hit"), true) << seen;
    EXPECT_LT(seen.at("position")[0].get<double>(), -40.0) << "left of the midline";
    EXPECT_EQ(seen.at("hounsfield"), false);
    ASSERT_TRUE(seen.contains("label")) << seen;
    const auto label_id = seen.at("label").at("id").get<std::int64_t>();
    EXPECT_TRUE(seen.at("label").at("name").get<std::string>().ends_with("_L")) << seen;

    TestClient viewer(port_);
    const std::string joined =
            viewer.request(R"({"v":1,"type":"join","id":6,"session":")" + owner.session + "\"}");
    ASSERT_EQ(field(joined, "type"), "joined") << joined;
    EXPECT_EQ(field(viewer.next_text(std::chrono::seconds(10)), "type"), "labels");
    const auto theirs = nlohmann::json::parse(
            viewer.request(R"({"v":1,"type":"pick","id":7,"x":0.5,"y":0.5})"));
    EXPECT_EQ(theirs.at("label"), seen.at("label")) << theirs;
    EXPECT_EQ(theirs.at("position"), seen.at("position"));

    const std::string hidden =
            owner.request(R"({"v":1,"type":"set","id":8,"labels":{"styles":{")" +
                          std::to_string(label_id) + R"(":{"visible":false}}}})");
    ASSERT_EQ(field(hidden, "type"), "ack") << hidden;
    const auto behind =
            nlohmann::json::parse(owner.request(R"({"v":1,"type":"pick","id":9,"x":0.5,"y":0.5})"));
    ASSERT_EQ(behind.at("hit"), true) << behind;
    ASSERT_TRUE(behind.contains("label")) << behind;
    EXPECT_NE(behind.at("label").at("id"), label_id);
    EXPECT_GT(behind.at("position")[0].get<double>(), seen.at("position")[0].get<double>())
            << "deeper along the ray: " << seen << behind;

    const auto corner =
            nlohmann::json::parse(owner.request(R"({"v":1,"type":"pick","id":10,"x":0,"y":1})"));
    EXPECT_EQ(corner.at("hit"), false) << corner;
    EXPECT_FALSE(corner.contains("position"));
    const std::string outside = owner.request(R"({"v":1,"type":"pick","id":11,"x":1.5,"y":0})");
    EXPECT_EQ(field(outside, "code"), "out_of_range") << outside;
    EXPECT_EQ(field(outside, "field"), "/x") << outside;
    TestClient stranger(port_);
    const std::string sessionless =
            stranger.request(R"({"v":1,"type":"pick","id":12,"x":0.5,"y":0.5})");
    EXPECT_EQ(field(sessionless, "code"), "no_session") << sessionless;
}

// How many pixels of a frame are lit (any channel above 40).
int lit_pixels(const base::ImageRgba8& image) {
    int lit = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const auto* p = image.pixel(x, y);
            lit += std::max({p[0], p[1], p[2]}) > 40 ? 1 : 0;
        }
    }
    return lit;
}

// An export's statuses up to its last (not `running`), frames passed by.
std::vector<nlohmann::json> export_statuses(TestClient& client) {
    std::vector<nlohmann::json> statuses;
    while (true) {
        const auto status =
                nlohmann::json::parse(client.next_text(std::chrono::seconds(120)), nullptr, false);
        if (!status.is_object() || status.value("type", "") != "export_status") {
            ADD_FAILURE() << "not an export_status: " << status;
            return statuses;
        }
        statuses.push_back(status);
        if (status.at("state") != "running") {
            return statuses;
        }
    }
}

// A still larger than a frame may be: rendered in tiles (frames of at most max_image_side), its
// statuses rising to done with a URL, the PNG downloaded over HTTP at its size, showing the head
// and keeping the state that drew it; a client watching its own session meanwhile gets its frames;
// a cancelled export ends cancelled and leaves nothing to download; bad exports are refused.
TEST_F(ServerTest, AStillLargerThanAFrameIsExportedInTilesAndDownloaded) {
    protocol::Limits limits;
    limits.max_image_side = 48;
    limits.max_export_side = 160;
    start(limits);
    TestClient owner(port_);
    EXPECT_EQ(nlohmann::json::parse(owner.hello).at("limits").at("max_export_side"), 160);
    owner.open("heads/ch2.nii.gz", 32);
    owner.send(R"({"v":1,"type":"render","id":3})");
    owner.next_frame();
    owner.send(R"({"v":1,"type":"export","id":4,"width":100,"height":80})");
    TestClient watcher(port_, "127.0.0.2");
    watcher.open("heads/ch2.nii.gz", 32);
    watcher.send(R"({"v":1,"type":"render","id":3,"interactive":true})");
    EXPECT_EQ(watcher.frame_answering(3).header.request, 3);
    const auto statuses = export_statuses(owner);
    ASSERT_GE(statuses.size(), 3u);
    const auto& done = statuses.back();
    ASSERT_EQ(done.at("state"), "done") << done;
    EXPECT_EQ(done.at("id"), 4);
    EXPECT_EQ(done.at("tiles"), 6);  // 48 + 48 + 4 by 48 + 32
    EXPECT_EQ(done.at("progress"), 1.0);
    double progress = 0.0;
    for (const auto& status : statuses) {
        EXPECT_EQ(status.at("export"), done.at("export"));
        EXPECT_GE(status.at("progress").get<double>(), progress);
        progress = status.at("progress").get<double>();
    }
    const std::string url = done.at("url");
    EXPECT_EQ(url, "/exports/" + done.at("export").get<std::string>());
    auto download = net::http_get("127.0.0.1", port_, url, std::chrono::seconds(30));
    ASSERT_TRUE(download.ok()) << download.error().to_string();
    ASSERT_EQ(download->status, 200) << download->body;
    EXPECT_EQ(download->content_type, "image/png");
    EXPECT_EQ(download->body.size(), done.at("bytes").get<std::size_t>());
    EXPECT_NE(download->body.find("Penumbra state"), std::string::npos) << "the state drawn";
    const std::vector<std::uint8_t> png(download->body.begin(), download->body.end());
    auto image = imageio::decode_image(png);
    ASSERT_TRUE(image.ok()) << image.error().to_string();
    EXPECT_EQ(image->width, 100);
    EXPECT_EQ(image->height, 80);
    EXPECT_GT(lit_pixels(*image), 100 * 80 / 10) << "the head, not an empty frame";
    EXPECT_EQ(
            net::http_get("127.0.0.1", port_, "/exports/0123456789abcdef0123456789abcdef")->status,
            404);

    // Cancelled after its first tile: nothing to download.
    owner.send(R"({"v":1,"type":"export","id":5,"width":160,"height":160})");
    auto first = nlohmann::json::parse(owner.next_text());
    ASSERT_EQ(first.at("type"), "export_status") << first;
    const std::string busy =
            owner.request(R"({"v":1,"type":"export","id":6,"width":64,"height":64})");
    EXPECT_EQ(field(busy, "code"), "rate_limited") << busy;
    owner.send(R"({"v":1,"type":"cancel_export","id":7,"export":")" +
               first.at("export").get<std::string>() + "\"}");
    const auto cancelled = export_statuses(owner).back();
    EXPECT_EQ(cancelled.at("state"), "cancelled") << cancelled;
    EXPECT_LT(cancelled.at("progress").get<double>(), 1.0);
    EXPECT_EQ(net::http_get("127.0.0.1", port_, "/exports/" + first.at("export").get<std::string>())
                      ->status,
              404);

    for (const auto& [request, code, where] :
         {std::tuple{R"({"v":1,"type":"export","id":8,"width":0,"height":10})", "out_of_range",
                     "/width"},
          std::tuple{R"({"v":1,"type":"export","id":8,"width":10.5,"height":10})", "invalid_value",
                     "/width"},
          std::tuple{R"({"v":1,"type":"export","id":8,"width":10,"height":161})", "out_of_range",
                     "/height"},
          std::tuple{R"({"v":1,"type":"cancel_export","id":8,"export":"feed"})", "invalid_value",
                     "/export"}}) {
        const std::string refused = owner.request(request);
        EXPECT_EQ(field(refused, "code"), code) << request << " " << refused;
        EXPECT_EQ(field(refused, "field"), where) << request << " " << refused;
    }
    TestClient stranger(port_, "127.0.0.3");
    EXPECT_EQ(field(stranger.request(R"({"v":1,"type":"export","id":9,"width":10,"height":10})"),
                    "code"),
              "no_session");
}

// A movie of the session's view turning: its statuses count frames, the MP4 is downloaded and
// read back as a player would, each frame the head seen from further round.
TEST_F(ServerTest, AMovieOfTheViewTurningIsExportedAndDownloadedAsAnMp4) {
    protocol::Limits limits;
    limits.max_movie_side = 64;
    limits.max_movie_frames = 6;
    start(limits);
    TestClient owner(port_);
    const auto hello = nlohmann::json::parse(owner.hello).at("limits");
    EXPECT_EQ(hello.at("max_movie_side"), 64);
    EXPECT_EQ(hello.at("max_movie_frames"), 6);
    owner.open("heads/ch2.nii.gz", 32);
    owner.send(
            R"({"v":1,"type":"export_movie","id":4,"width":48,"height":32,"frames":4,"rock":0})");
    const auto statuses = export_statuses(owner);
    ASSERT_GE(statuses.size(), 2u);
    const auto& done = statuses.back();
    ASSERT_EQ(done.at("state"), "done") << done;
    EXPECT_EQ(done.at("id"), 4);
    EXPECT_EQ(done.at("frames"), 4);
    EXPECT_EQ(done.at("width"), 48);
    double progress = 0.0;
    for (const auto& status : statuses) {
        EXPECT_GE(status.at("progress").get<double>(), progress);
        progress = status.at("progress").get<double>();
    }
    auto download = net::http_get("127.0.0.1", port_, done.at("url"), std::chrono::seconds(30));
    ASSERT_TRUE(download.ok()) << download.error().to_string();
    ASSERT_EQ(download->status, 200) << download->body;
    EXPECT_EQ(download->content_type, "video/mp4");
    EXPECT_EQ(download->body.size(), done.at("bytes").get<std::size_t>());
    const fs::path file = data_ / "turntable.mp4";
    std::ofstream(file, std::ios::binary) << download->body;
    const test::ReadMovie movie = test::read_movie(file);
    EXPECT_EQ(movie.codec, "h264");
    EXPECT_EQ(movie.width, 48);
    EXPECT_EQ(movie.height, 32);
    ASSERT_EQ(movie.frames.size(), 4u);
    for (const base::ImageRgba8& frame : movie.frames) {
        EXPECT_GT(lit_pixels(frame), 48 * 32 / 10) << "the head in every frame";
    }
    // A quarter turn a frame: the head from the side is not the head from the front.
    const auto differ = [](const base::ImageRgba8& a, const base::ImageRgba8& b) {
        int changed = 0;
        for (std::size_t i = 0; i < a.pixels.size(); ++i) {
            changed += std::abs(a.pixels[i] - b.pixels[i]) > 32 ? 1 : 0;
        }
        return changed;
    };
    EXPECT_GT(differ(movie.frames[0], movie.frames[1]), 48 * 32 / 20);

    for (const auto& [request, code, where] :
         {std::tuple{
                  R"({"v":1,"type":"export_movie","id":8,"width":47,"height":32,"frames":4,"rock":0})",
                  "invalid_value", "/width"},
          std::tuple{
                  R"({"v":1,"type":"export_movie","id":8,"width":66,"height":32,"frames":4,"rock":0})",
                  "out_of_range", "/width"},
          std::tuple{
                  R"({"v":1,"type":"export_movie","id":8,"width":48,"height":32,"frames":7,"rock":0})",
                  "out_of_range", "/frames"},
          std::tuple{
                  R"({"v":1,"type":"export_movie","id":8,"width":48,"height":32,"frames":2.5,"rock":0})",
                  "invalid_value", "/frames"},
          std::tuple{
                  R"({"v":1,"type":"export_movie","id":8,"width":48,"height":32,"frames":4,"rock":181})",
                  "out_of_range", "/rock"},
          std::tuple{R"({"v":1,"type":"export_movie","id":8,"width":48,"height":32,"frames":4})",
                     "invalid_message", "/rock"}}) {
        const std::string refused = owner.request(request);
        EXPECT_EQ(field(refused, "code"), code) << request << " " << refused;
        EXPECT_EQ(field(refused, "field"), where) << request << " " << refused;
    }
}

// The label map drawn alone in a session: `labels.alone` is answered once the surfaces are made,
// the next frame shows the atlas without the head around it (fewer pixels lit: the brain, not the
// scalp), a pick names a left region's surface with the scan's value there, hiding that region
// (new surfaces, made before the answer) shows another behind it, a viewer sees the same, and
// drawing the map inside the scan again brings the head back.
TEST_F(ServerTest, TheLabelMapAloneIsDrawnAsSurfacesAndPicksNameTheirLabels) {
    for (const char* file : {"aal.nii.gz", "aal.nii.txt", "aal.nii.lut"}) {
        fs::copy_file(fs::path("/usr/share/mricron/templates") / file, data_ / "heads" / file);
    }
    ASSERT_TRUE(volumes_->scan().ok());
    TestClient owner(port_);
    owner.open("heads/ch2.nii.gz", 48);
    ASSERT_EQ(field(owner.request(
                            R"({"v":1,"type":"add_labels","id":2,"volume":"heads/aal.nii.gz"})"),
                    "type"),
              "labels");
    const std::string view = owner.request(
            R"({"v":1,"type":"set","id":3,"camera":{"view":"left"},"transfer_function":{"preset":"mri_skin"}})");
    ASSERT_EQ(field(view, "type"), "ack") << view;
    const auto frame_lit = [&](TestClient& client, int id) {
        client.send(R"({"v":1,"type":"render","id":)" + std::to_string(id) + "}");
        const auto frame = client.next_frame();
        EXPECT_EQ(frame.header.request, id);
        auto image = imageio::decode_image(frame.image);
        EXPECT_TRUE(image.ok());
        return image.ok() ? lit_pixels(*image) : 0;
    };
    const int inside = frame_lit(owner, 4);

    const auto alone = nlohmann::json::parse(
            owner.request(R"({"v":1,"type":"set","id":5,"labels":{"alone":true}})"));
    ASSERT_EQ(alone.at("type"), "ack") << alone;
    EXPECT_EQ(alone.at("state").at("labels").at("alone"), true);
    const int surfaces = frame_lit(owner, 6);
    EXPECT_LT(surfaces, inside * 85 / 100) << "the brain's surfaces, without the scalp";
    EXPECT_GT(surfaces, 48 * 48 / 10);
    const auto seen =
            nlohmann::json::parse(owner.request(R"({"v":1,"type":"pick","id":7,"x":0.5,"y":0.5})"));
    ASSERT_EQ(seen.at("hit"), true) << seen;
    ASSERT_TRUE(seen.contains("label")) << seen;
    EXPECT_TRUE(seen.at("label").at("name").get<std::string>().ends_with("_L")) << seen;
    EXPECT_LT(seen.at("position")[0].get<double>(), -30.0) << "the left hemisphere's surface";
    EXPECT_GT(seen.at("value").get<double>(), 10.0) << "the scan's value there, not the mask's";
    const auto label_id = seen.at("label").at("id").get<std::int64_t>();

    TestClient viewer(port_);
    const std::string joined =
            viewer.request(R"({"v":1,"type":"join","id":8,"session":")" + owner.session + "\"}");
    ASSERT_EQ(field(joined, "type"), "joined") << joined;
    const auto told = nlohmann::json::parse(viewer.next_text(std::chrono::seconds(10)));
    EXPECT_EQ(told.at("state").at("labels").at("alone"), true) << told;
    EXPECT_EQ(frame_lit(viewer, 9), surfaces);
    owner.next_frame();

    const auto hidden = nlohmann::json::parse(
            owner.request(R"({"v":1,"type":"set","id":10,"labels":{"styles":{")" +
                          std::to_string(label_id) + R"(":{"visible":false}}}})"));
    ASSERT_EQ(hidden.at("type"), "ack") << hidden;
    const auto behind = nlohmann::json::parse(
            owner.request(R"({"v":1,"type":"pick","id":11,"x":0.5,"y":0.5})"));
    ASSERT_EQ(behind.at("hit"), true) << behind;
    ASSERT_TRUE(behind.contains("label")) << behind;
    EXPECT_NE(behind.at("label").at("id"), label_id) << behind;
    EXPECT_GT(behind.at("position")[0].get<double>(), seen.at("position")[0].get<double>())
            << "deeper along the ray: " << seen << behind;

    const auto again = nlohmann::json::parse(
            owner.request(R"({"v":1,"type":"set","id":12,"labels":{"alone":false}})"));
    ASSERT_EQ(again.at("type"), "ack") << again;
    EXPECT_EQ(again.at("state").at("labels").at("alone"), false);
    const int back = frame_lit(owner, 13);
    EXPECT_GT(back, surfaces) << "the head drawn again";
    const std::string refused =
            owner.request(R"({"v":1,"type":"set","id":14,"labels":{"alone":"yes"}})");
    EXPECT_EQ(field(refused, "field"), "/labels/alone") << refused;
}

// Picks as costly as a client can make them (the finest step, the tricubic filter, nothing opaque:
// every ray crosses the whole volume) sent as fast as it may while another client's session is
// served: each pick is answered, off the threads that serve the other, which gets its frames.
TEST_F(ServerTest, CostlyPicksLeaveAnotherSessionServed) {
    TestClient watcher(port_);
    watcher.open("heads/ch2.nii.gz", 32);
    TestClient hostile(port_);
    hostile.open("heads/ch2.nii.gz", 32);
    const std::string set = hostile.request(
            R"({"v":1,"type":"set","id":2,"settings":{"sample_distance":0.0001,"reconstruction":"tricubic"},)"
            R"("transfer_function":{"opacities":[{"x":0,"alpha":0},{"x":1,"alpha":0}],)"
            R"("colors":[{"x":0,"rgb":[1,1,1]},{"x":1,"rgb":[1,1,1]}]}})");
    ASSERT_EQ(field(set, "type"), "ack") << set;
    constexpr int picks = 40;
    for (int i = 0; i < picks; ++i) {
        hostile.send(R"({"v":1,"type":"pick","id":)" + std::to_string(100 + i) +
                     R"(,"x":0.5,"y":0.5})");
    }
    for (int i = 0; i < 5; ++i) {
        watcher.send(R"({"v":1,"type":"render","id":)" + std::to_string(300 + i) + "}");
        EXPECT_EQ(watcher.next_frame().header.request, 300 + i);
    }
    for (int i = 0; i < picks; ++i) {
        const auto reply = nlohmann::json::parse(hostile.next_text(std::chrono::seconds(30)));
        if (reply.at("type") == "error") {
            EXPECT_EQ(reply.at("code"), "rate_limited") << reply;
            continue;
        }
        EXPECT_EQ(reply.at("type"), "picked") << reply;
        EXPECT_EQ(reply.at("hit"), false) << "nothing is opaque";
    }
}

// A file whose error quotes bytes that are no UTF-8 (a NRRD's text data) is refused with a message
// that is valid JSON, and the server serves on.
TEST_F(ServerTest, AnErrorQuotingBytesThatAreNoUtf8StaysValidJson) {
    std::ofstream(data_ / "latin1_4x4x4.nrrd", std::ios::binary)
            << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n\n"
            << "1 2 \xe9t\xe9 4 5 6 7 8\n";
    ASSERT_TRUE(volumes_->scan().ok());
    TestClient client(port_);
    const std::string refused =
            client.request(R"({"v":1,"type":"open","id":2,"volume":"latin1_4x4x4.nrrd"})");
    ASSERT_TRUE(nlohmann::json::accept(refused)) << refused;
    EXPECT_EQ(field(refused, "code"), "volume_unreadable") << refused;
    client.open("heads/ch2.nii.gz", 32);
    client.send(R"({"v":1,"type":"render","id":3})");
    EXPECT_EQ(client.frame_answering(3).header.request, 3);
}

// A hostile owner asks again and again to draw a scan as labels and sends label patches its
// session cannot take, while another client's session is served: each request gets its error,
// the other client gets its frames, and the hostile one's session still renders.
TEST_F(ServerTest, AskingForLabelMapsAgainAndAgainLeavesAnotherSessionServed) {
    TestClient watcher(port_);
    watcher.open("heads/ch2.nii.gz", 32);
    TestClient hostile(port_);
    hostile.open("heads/ch2.nii.gz", 32);
    for (int i = 0; i < 10; ++i) {
        hostile.send(R"({"v":1,"type":"add_labels","id":)" + std::to_string(100 + i) +
                     R"(,"volume":"heads/ch2.nii.gz"})");
        hostile.send(R"({"v":1,"type":"set","id":)" + std::to_string(200 + i) +
                     R"(,"labels":{"only":[1,2,3],"styles":{"x":{"visible":"no"}}}})");
        watcher.send(R"({"v":1,"type":"render","id":)" + std::to_string(300 + i) + "}");
        EXPECT_EQ(watcher.next_frame().header.request, 300 + i);
    }
    for (int i = 0; i < 20; ++i) {
        const std::string reply = hostile.next_text(std::chrono::seconds(30));
        EXPECT_EQ(field(reply, "type"), "error") << reply;
        const std::string code = field(reply, "code");
        EXPECT_TRUE(code == "volume_unreadable" || code == "invalid_value") << reply;
    }
    hostile.send(R"({"v":1,"type":"render","id":400})");
    EXPECT_EQ(hostile.frame_answering(400).header.request, 400);
}

// Frames as an H.264 stream: a session asked for h264 sends its first frame as a keyframe and the
// next ones as changes, which a client's decoder (libavcodec, access unit by access unit) decodes
// in order; a viewer who joins makes the next frame a keyframe it starts from; a resized view
// starts afresh; each header says whether its frame stands alone; a still's last frame comes as a
// JPEG and the stream goes on from a keyframe; back to JPEG, frames are JPEG again.
TEST_F(ServerTest, H264FramesAreOneStreamThatAJoinerStartsAtAKeyframe) {
    TestClient owner(port_);
    owner.open("heads/ch2.nii.gz", 48);
    const std::string set = owner.request(
            R"({"v":1,"type":"set","id":2,"output":{"encoding":"h264"},"settings":{"refinement_steps":0}})");
    ASSERT_EQ(field(set, "type"), "ack") << set;
    auto decoder = encode::StreamDecoder::create();
    ASSERT_TRUE(decoder.ok()) << decoder.error().to_string();
    // Frames while the user drags: the stream's own.
    const auto frame_of = [](TestClient& client, int id) {
        client.send(R"({"v":1,"type":"render","id":)" + std::to_string(id) +
                    R"(,"interactive":true})");
        return client.next_frame();
    };
    const auto decodes = [](encode::StreamDecoder& d, const protocol::UnpackedFrame& frame) {
        auto picture = d.decode(frame.image);
        EXPECT_TRUE(picture.ok()) << "frame " << frame.header.frame << ": "
                                  << (picture.ok() ? "" : picture.error().to_string());
        if (picture.ok()) {
            // Even sides: the frame is the picture's top left.
            EXPECT_EQ(picture->width, frame.header.width + frame.header.width % 2);
            EXPECT_EQ(picture->height, frame.header.height + frame.header.height % 2);
        }
    };
    for (int i = 0; i < 4; ++i) {
        const auto frame = frame_of(owner, 10 + i);
        EXPECT_EQ(frame.header.encoding, "h264");
        EXPECT_EQ(frame.header.independent, i == 0) << "frame " << i;
        decodes(*decoder, frame);
    }

    TestClient viewer(port_);
    const std::string joined =
            viewer.request(R"({"v":1,"type":"join","id":3,"session":")" + owner.session + "\"}");
    ASSERT_EQ(field(joined, "type"), "joined") << joined;
    const auto for_owner = frame_of(owner, 20);
    const auto for_viewer = viewer.next_frame();
    EXPECT_TRUE(for_owner.header.independent) << "a viewer joined: a keyframe";
    EXPECT_EQ(for_viewer.image, for_owner.image);
    auto joiner = encode::StreamDecoder::create();
    ASSERT_TRUE(joiner.ok());
    decodes(*joiner, for_viewer);
    decodes(*decoder, for_owner);
    const auto after = frame_of(owner, 21);
    EXPECT_FALSE(after.header.independent);
    decodes(*joiner, viewer.next_frame());
    decodes(*decoder, after);

    ASSERT_EQ(field(owner.request(R"({"v":1,"type":"set","id":4,"settings":{"size":[51,40]}})"),
                    "type"),
              "ack");
    const auto resized = frame_of(owner, 22);
    viewer.next_frame();
    EXPECT_TRUE(resized.header.independent) << "a new size starts afresh";
    EXPECT_EQ(resized.header.width, 51);
    auto fresh = encode::StreamDecoder::create();
    ASSERT_TRUE(fresh.ok());
    decodes(*fresh, resized);

    // The still the user stops at: a JPEG, for both; the stream goes on from a keyframe.
    owner.send(R"({"v":1,"type":"render","id":30})");
    const auto still = owner.next_frame();
    EXPECT_EQ(still.header.encoding, "jpeg");
    EXPECT_FALSE(still.header.interactive);
    EXPECT_TRUE(still.header.independent);
    EXPECT_TRUE(imageio::decode_image(still.image).ok());
    EXPECT_EQ(viewer.next_frame().header.encoding, "jpeg");
    const auto moving_again = frame_of(owner, 31);
    viewer.next_frame();
    EXPECT_EQ(moving_again.header.encoding, "h264");
    EXPECT_TRUE(moving_again.header.independent) << "after a still, a keyframe";
    decodes(*fresh, moving_again);

    ASSERT_EQ(field(owner.request(R"({"v":1,"type":"set","id":5,"output":{"encoding":"jpeg"}})"),
                    "type"),
              "ack");
    const auto jpeg = frame_of(owner, 23);
    EXPECT_EQ(jpeg.header.encoding, "jpeg");
    EXPECT_TRUE(jpeg.header.independent);
    EXPECT_TRUE(imageio::decode_image(jpeg.image).ok());
}

// A hostile owner draws an atlas alone and changes which labels show as fast as it may, each
// change new surfaces to make, while another client's session is served: every change is answered
// (or refused for the rate), in order, the other client gets its frames, and the hostile session
// still renders.
TEST_F(ServerTest, SurfacesToMakeAgainAndAgainLeaveAnotherSessionServed) {
    for (const char* file : {"aal.nii.gz", "aal.nii.txt", "aal.nii.lut"}) {
        fs::copy_file(fs::path("/usr/share/mricron/templates") / file, data_ / "heads" / file);
    }
    ASSERT_TRUE(volumes_->scan().ok());
    TestClient watcher(port_);
    watcher.open("heads/ch2.nii.gz", 32);
    TestClient hostile(port_);
    hostile.open("heads/ch2.nii.gz", 32);
    ASSERT_EQ(field(hostile.request(
                            R"({"v":1,"type":"add_labels","id":2,"volume":"heads/aal.nii.gz"})"),
                    "type"),
              "labels");
    ASSERT_EQ(field(hostile.request(R"({"v":1,"type":"set","id":3,"labels":{"alone":true}})"),
                    "type"),
              "ack");
    constexpr int changes = 12;
    for (int i = 0; i < changes; ++i) {
        hostile.send(R"({"v":1,"type":"set","id":)" + std::to_string(100 + i) +
                     R"(,"labels":{"all":{"visible":true},"styles":{")" + std::to_string(i + 1) +
                     R"(":{"visible":false}}}})");
    }
    for (int i = 0; i < 5; ++i) {
        watcher.send(R"({"v":1,"type":"render","id":)" + std::to_string(300 + i) + "}");
        EXPECT_EQ(watcher.next_frame().header.request, 300 + i);
    }
    int acked = 0;
    for (int i = 0; i < changes; ++i) {
        const auto reply = nlohmann::json::parse(hostile.next_text(std::chrono::seconds(60)));
        if (reply.at("type") == "error") {
            EXPECT_EQ(reply.at("code"), "rate_limited") << reply;
            continue;
        }
        EXPECT_EQ(reply.at("type"), "ack") << reply;
        EXPECT_EQ(reply.at("id"), 100 + i) << "answered in order";
        ++acked;
    }
    EXPECT_GT(acked, 0);
    hostile.send(R"({"v":1,"type":"render","id":400})");
    EXPECT_EQ(hostile.frame_answering(400).header.request, 400);
}

TEST_F(ServerTest, ViewersAreToldEachStateTheOwnerSetsAndTheOwnerOnlyGetsItsAck) {
    TestClient owner(port_);
    owner.open("heads/ch2.nii.gz", 32);
    TestClient viewer(port_);
    const std::string joined =
            viewer.request(R"({"v":1,"type":"join","id":3,"session":")" + owner.session + "\"}");
    ASSERT_EQ(field(joined, "type"), "joined") << joined;
    EXPECT_NE(nlohmann::json::parse(joined).at("state").at("settings").at("mode"), "dvr");

    const std::string ack = owner.request(
            R"({"v":1,"type":"set","id":4,"settings":{"mode":"dvr"},"light":{"direction":[0,-1,0.5]}})");
    EXPECT_EQ(field(ack, "type"), "ack")
            << "the owner gets no state of its own, only its ack: " << ack;
    const auto pushed = nlohmann::json::parse(viewer.next_text(std::chrono::seconds(10)));
    EXPECT_EQ(pushed.at("type"), "state") << pushed;
    EXPECT_EQ(pushed.at("session"), owner.session);
    EXPECT_FALSE(pushed.contains("id")) << "it answers no request of the viewer's";
    EXPECT_EQ(pushed.at("state").at("settings").at("mode"), "dvr");
    EXPECT_EQ(pushed.at("state").at("light").at("direction"), nlohmann::json::parse("[0,-1,0.5]"));
    // The rest of the state is the session's, as a join now would report it.
    const auto rejoined = nlohmann::json::parse(
            viewer.request(R"({"v":1,"type":"join","id":5,"session":")" + owner.session + "\"}"));
    EXPECT_EQ(rejoined.at("type"), "joined");
    EXPECT_EQ(rejoined.at("state"), pushed.at("state"));

    // A viewer still may not change the session.
    const std::string refused =
            viewer.request(R"({"v":1,"type":"set","id":6,"camera":{"fov":40}})");
    EXPECT_EQ(field(refused, "code"), "invalid_message") << refused;
    EXPECT_EQ(field(refused, "field"), "/type") << refused;

    // A second change reaches the viewer too, after the first; the owner's next answer is the
    // one to its next request.
    EXPECT_EQ(field(owner.request(R"({"v":1,"type":"set","id":7,"camera":{"fov":40}})"), "type"),
              "ack");
    const auto second = nlohmann::json::parse(viewer.next_text(std::chrono::seconds(10)));
    EXPECT_EQ(second.at("type"), "state") << second;
    EXPECT_EQ(second.at("state").at("camera").at("fov"), 40);
    EXPECT_EQ(second.at("state").at("settings").at("mode"), "dvr");
    EXPECT_EQ(field(owner.request(R"({"v":1,"type":"stats","id":8})"), "type"), "stats");

    // Frames still reach both; the viewer's text queue holds nothing more.
    owner.send(R"({"v":1,"type":"render","id":9})");
    EXPECT_EQ(owner.next_frame().header.mode, "dvr");
    EXPECT_EQ(viewer.next_frame().header.mode, "dvr");
    EXPECT_EQ(field(viewer.request(R"({"v":1,"type":"stats","id":10})"), "type"), "stats");
}

std::string resume_request(const std::string& session, const std::string& owner_token, int id) {
    return R"({"v":1,"type":"resume","id":)" + std::to_string(id) + R"(,"session":")" + session +
           R"(","owner_token":")" + owner_token + "\"}";
}

// Resumes once the server has noticed that the session's owner left: a closed socket reaches it
// asynchronously, and until then the session is still owned.
std::string resume_once_unowned(TestClient& client, const std::string& session,
                                const std::string& owner_token) {
    std::string reply;
    for (int i = 0; i < 100; ++i) {
        reply = client.request(resume_request(session, owner_token, 20 + i));
        if (field(reply, "code") != "session_owned") {
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return reply;
}

TEST_F(ServerTest, ViewersKeepASessionWhoseOwnerDroppedAndTheOwnerTokenResumesIt) {
    auto owner = std::make_unique<TestClient>(port_);
    const auto opened = nlohmann::json::parse(owner->open("heads/ch2.nii.gz", 32));
    const std::string session = owner->session;
    ASSERT_TRUE(opened.contains("owner_token")) << opened.dump().substr(0, 300);
    const std::string token = opened.at("owner_token");
    EXPECT_EQ(token.size(), 32U);
    TestClient viewer(port_);
    const auto joined = nlohmann::json::parse(
            viewer.request(R"({"v":1,"type":"join","id":3,"session":")" + session + "\"}"));
    ASSERT_EQ(joined.at("type"), "joined");
    EXPECT_FALSE(joined.contains("owner_token")) << "viewers never learn the owner token";

    // While the owner is connected, even the right token does not take the session over.
    TestClient other(port_);
    const std::string owned = other.request(resume_request(session, token, 4));
    EXPECT_EQ(field(owned, "code"), "session_owned") << owned;
    EXPECT_EQ(field(owned, "field"), "/session") << owned;

    owner->raw().close();
    owner.reset();
    // The viewer stays in the session, which keeps its frames coming without an owner.
    viewer.send(R"({"v":1,"type":"render","id":5})");
    EXPECT_EQ(viewer.next_frame().header.session, session);

    std::string wrong_token = token;
    wrong_token.back() = wrong_token.back() == '0' ? '1' : '0';
    const std::string refused = other.request(resume_request(session, wrong_token, 6));
    EXPECT_EQ(field(refused, "type"), "error") << refused;
    EXPECT_EQ(field(refused, "code"), "invalid_value") << refused;
    EXPECT_EQ(field(refused, "field"), "/owner_token") << refused;
    EXPECT_EQ(refused.find(token), std::string::npos) << "an error never shows the token";
    const std::string unknown = other.request(resume_request(std::string(32, 'f'), token, 7));
    EXPECT_EQ(field(unknown, "code"), "unknown_session") << unknown;
    EXPECT_EQ(field(unknown, "field"), "/session") << unknown;
    const std::string still_viewer =
            viewer.request(R"({"v":1,"type":"set","id":8,"camera":{"fov":40}})");
    EXPECT_EQ(field(still_viewer, "code"), "invalid_message") << "nobody owns it now";

    // A new connection with the token owns the same session again.
    TestClient resumed(port_);
    const std::string answer = resume_once_unowned(resumed, session, token);
    ASSERT_EQ(field(answer, "type"), "opened") << answer.substr(0, 300);
    const auto reopened = nlohmann::json::parse(answer);
    EXPECT_EQ(reopened.at("session"), session);
    EXPECT_EQ(reopened.at("owner_token"), token) << "a session keeps its token";
    EXPECT_EQ(reopened.at("state"), joined.at("state")) << "the state the owner left";
    EXPECT_EQ(reopened.at("volume").at("id"), "heads/ch2.nii.gz");
    EXPECT_FALSE(reopened.at("histogram").empty());

    // It may set again; the viewer is told, and both get the frames.
    const std::string ack =
            resumed.request(R"({"v":1,"type":"set","id":9,"settings":{"mode":"dvr"}})");
    EXPECT_EQ(field(ack, "type"), "ack") << ack;
    const auto pushed = nlohmann::json::parse(viewer.next_text(std::chrono::seconds(10)));
    EXPECT_EQ(pushed.at("type"), "state") << pushed;
    EXPECT_EQ(pushed.at("session"), session);
    EXPECT_EQ(pushed.at("state").at("settings").at("mode"), "dvr");
    EXPECT_FALSE(pushed.contains("owner_token"));
    resumed.send(R"({"v":1,"type":"render","id":10})");
    auto mine = resumed.frame_answering(10);
    auto theirs = viewer.frame_answering(10);
    EXPECT_EQ(mine.header.request, 10);
    EXPECT_EQ(theirs.header.request, 10);
    EXPECT_EQ(mine.header.mode, "dvr");
    EXPECT_EQ(theirs.header.mode, "dvr");
    // The same frames: the last step of the still, which no later frame takes the place of in a
    // send queue, reaches both.
    while (mine.header.refining) {
        mine = resumed.next_frame(std::chrono::seconds(60), TestClient::Steps::returned);
    }
    while (theirs.header.refining) {
        theirs = viewer.next_frame(std::chrono::seconds(60), TestClient::Steps::returned);
    }
    EXPECT_EQ(mine.header.frame, theirs.header.frame);
    // The resumed owner is the owner now: another resume is refused while it is connected.
    EXPECT_EQ(field(other.request(resume_request(session, token, 11)), "code"), "session_owned");

    // When the last connection leaves, the session ends and cannot be resumed.
    EXPECT_EQ(field(viewer.request(R"({"v":1,"type":"close","id":12})"), "type"), "ack");
    resumed.raw().close();
    const std::string ended = resume_once_unowned(other, session, token);
    EXPECT_EQ(field(ended, "code"), "unknown_session") << ended;
}

TEST_F(ServerTest, AFrozenOwnerIsDroppedWithinPingIntervalPlusTimeoutAndItsTokenResumes) {
    using namespace std::chrono_literals;
    constexpr auto interval = 500ms;
    constexpr auto timeout = 500ms;
    start(protocol::Limits{}, [&](net::ServerConfig& config) {
        config.ping_interval = interval;
        config.ping_timeout = timeout;
    });
    auto frozen = std::make_unique<TestClient>(port_);
    const auto opened = nlohmann::json::parse(frozen->open("heads/ch2.nii.gz", 32));
    const std::string session = frozen->session;
    const std::string token = opened.at("owner_token");
    // A viewer that waits in a read all along, and so answers every ping, keeps the session.
    TestClient viewer(port_);
    ASSERT_EQ(field(viewer.request(R"({"v":1,"type":"join","id":3,"session":")" + session + "\"}"),
                    "type"),
              "joined");
    std::int64_t viewer_got = -1;
    std::thread viewer_waits([&] { viewer_got = viewer.next_frame(30s).header.request; });
    // From now on the owner reads nothing, so it answers no ping: as if its process froze or its
    // network vanished without a FIN.
    const auto frozen_at = std::chrono::steady_clock::now();
    TestClient other(port_);
    std::string answer;
    for (int i = 0; i < 100; ++i) {
        answer = other.request(resume_request(session, token, 100 + i));
        if (field(answer, "code") != "session_owned") {
            break;
        }
        std::this_thread::sleep_for(50ms);
    }
    const auto noticed_after = std::chrono::steady_clock::now() - frozen_at;
    EXPECT_EQ(field(answer, "type"), "opened") << answer.substr(0, 300);
    EXPECT_EQ(field(answer, "session"), session);
    EXPECT_LE(noticed_after, interval + timeout + 1s)
            << std::chrono::duration<double>(noticed_after).count() << " s";
    // Longer than interval + timeout once more: neither the viewer, answering pings, nor the
    // owner, sending requests, is dropped.
    for (const auto until = std::chrono::steady_clock::now() + interval + timeout + 500ms;
         std::chrono::steady_clock::now() < until;) {
        ASSERT_EQ(field(other.request(R"({"v":1,"type":"stats"})"), "type"), "stats");
        std::this_thread::sleep_for(100ms);
    }
    other.send(R"({"v":1,"type":"render","id":7})");
    EXPECT_EQ(other.frame_answering(7).header.request, 7);
    viewer_waits.join();
    EXPECT_EQ(viewer_got, 7);
    auto metrics = net::http_get("127.0.0.1", port_, "/metrics");
    ASSERT_TRUE(metrics.ok());
    EXPECT_NE(metrics->body.find("penumbra_connections_timed_out_total 1\n"), std::string::npos)
            << metrics->body;
}

// Each race: a session's only connection closes it while another connection joins it. Whichever
// wins, the joiner is in a session the server still holds, or was refused; never in an ended
// session outside the registry.
TEST_F(ServerTest, AJoinRacingTheLastLeaveNeverRevivesAnEndedSession) {
    TestClient joiner(port_);
    int joined = 0;
    int refused = 0;
    for (int race = 0; race < 40; ++race) {
        SCOPED_TRACE(race);
        TestClient owner(port_);
        owner.open("heads/ch2.nii.gz", 32);
        const std::string session = owner.session;
        std::thread closing([&] { owner.send(R"({"v":1,"type":"close","id":1})"); });
        joiner.send(R"({"v":1,"type":"join","id":2,"session":")" + session + "\"}");
        closing.join();
        EXPECT_EQ(field(owner.next_text(), "type"), "ack");
        const std::string reply = joiner.next_text();
        if (field(reply, "type") == "joined") {
            ++joined;
            EXPECT_NE(sessions_->find(session), nullptr) << "joined a session the server lost";
            EXPECT_EQ(sessions_->count(), 1U);
            EXPECT_EQ(field(joiner.request(R"({"v":1,"type":"close","id":3})"), "type"), "ack");
        } else {
            ++refused;
            EXPECT_EQ(field(reply, "code"), "unknown_session") << reply;
        }
        EXPECT_EQ(sessions_->count(), 0U);
    }
    EXPECT_EQ(joined + refused, 40);
}

TEST_F(ServerTest, HealthzAnswersWhileALargeVolumeLoadsAndJoinsReuseItsHistogram) {
    using namespace std::chrono_literals;
    // 256 x 256 x 768 uint16, 96 MiB: long enough a load to be seen from /healthz.
    {
        std::ofstream out(data_ / "large_256x256x768_uint16.raw", std::ios::binary);
        std::vector<std::uint16_t> slice(256 * 256);
        for (int z = 0; z < 768; ++z) {
            for (std::size_t i = 0; i < slice.size(); ++i) {
                const std::size_t value = i * 7 + static_cast<std::size_t>(z) * 13;
                slice[i] = static_cast<std::uint16_t>(value % 4096);
            }
            out.write(reinterpret_cast<const char*>(slice.data()),
                      static_cast<std::streamsize>(slice.size() * sizeof(std::uint16_t)));
        }
    }
    // One network thread: a load on it would stall every other connection.
    start(protocol::Limits{}, [](net::ServerConfig& config) { config.io_threads = 1; });
    TestClient loader(port_);
    const auto sent = std::chrono::steady_clock::now();
    loader.send(R"({"v":1,"type":"open","id":1,"volume":"large_256x256x768_uint16.raw"})");
    std::atomic<bool> opened{false};
    std::string reply;
    std::thread waiting([&] {
        reply = loader.next_text(60s);
        opened = true;
    });
    std::vector<double> health_ms;
    while (!opened) {
        const auto asked = std::chrono::steady_clock::now();
        auto health = net::http_get("127.0.0.1", port_, "/healthz", 30s);
        health_ms.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - asked)
                        .count());
        ASSERT_TRUE(health.ok());
        EXPECT_EQ(health->status, 200);
        std::this_thread::sleep_for(10ms);
    }
    waiting.join();
    const double load_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent)
                    .count();
    ASSERT_EQ(field(reply, "type"), "opened") << reply.substr(0, 300);
    RecordProperty("load_ms", std::to_string(load_ms));
    RecordProperty("slowest_healthz_ms",
                   std::to_string(*std::max_element(health_ms.begin(), health_ms.end())));
    // Were the load on the network thread, the first /healthz would wait for all of it.
    EXPECT_GE(health_ms.size(), 3U) << "answers to /healthz during a " << load_ms << " ms load";
    EXPECT_LT(*std::max_element(health_ms.begin(), health_ms.end()), std::max(100.0, load_ms / 2))
            << "slowest /healthz while a " << load_ms << " ms load ran";
    // The histogram came with the load; joining and resuming do not compute it again.
    EXPECT_EQ(volumes_->histograms_computed(), 1U);
    const std::string session = field(reply, "session");
    const std::string token = nlohmann::json::parse(reply).at("owner_token");
    for (int i = 0; i < 3; ++i) {
        TestClient viewer(port_);
        const auto joined = nlohmann::json::parse(
                viewer.request(R"({"v":1,"type":"join","id":2,"session":")" + session + "\"}"));
        ASSERT_EQ(joined.at("type"), "joined");
        EXPECT_EQ(joined.at("histogram"), nlohmann::json::parse(reply).at("histogram"));
    }
    TestClient keeper(port_);
    EXPECT_EQ(field(keeper.request(R"({"v":1,"type":"join","id":2,"session":")" + session + "\"}"),
                    "type"),
              "joined");
    loader.raw().close();
    TestClient resumer(port_);
    EXPECT_EQ(field(resume_once_unowned(resumer, session, token), "type"), "opened");
    EXPECT_EQ(volumes_->histograms_computed(), 1U);
}

TEST_F(ServerTest, OneClientCannotTakeEverySessionNorOneConnectionPileThemUp) {
    protocol::Limits limits;
    limits.max_sessions = 10;
    limits.max_sessions_per_client = 3;
    limits.max_sessions_per_connection = 2;
    start(limits);
    const std::string hello = TestClient(port_).hello;
    EXPECT_EQ(nlohmann::json::parse(hello).at("limits").at("max_sessions_per_client"), 3) << hello;
    EXPECT_EQ(nlohmann::json::parse(hello).at("limits").at("max_sessions_per_connection"), 2);
    // One address opens sessions from many connections until its share is reached.
    std::vector<std::unique_ptr<TestClient>> hog;
    for (int i = 0; i < 3; ++i) {
        hog.push_back(std::make_unique<TestClient>(port_, "127.0.0.2"));
        hog.back()->open("heads/ch2.nii.gz", 32);
    }
    TestClient one_more(port_, "127.0.0.2");
    const std::string refused =
            one_more.request(R"({"v":1,"type":"open","id":1,"volume":"heads/ch2.nii.gz"})");
    EXPECT_EQ(field(refused, "code"), "too_many_sessions") << refused;
    EXPECT_EQ(field(refused, "field"), "/volume") << refused;
    // Another address still gets sessions.
    TestClient newcomer(port_, "127.0.0.3");
    newcomer.open("heads/ch2.nii.gz", 32);
    newcomer.send(R"({"v":1,"type":"render","id":5})");
    EXPECT_EQ(newcomer.frame_answering(5).header.request, 5);

    // One connection opening session after session, each kept running by a viewer, holds at most
    // its maximum (the one it leaves for the next is not counted against it).
    TestClient opener(port_, "127.0.0.4");
    std::vector<std::unique_ptr<TestClient>> keepers;
    std::string last;
    for (int i = 0; i < 4; ++i) {
        last = opener.request(R"({"v":1,"type":"open","id":1,"volume":"heads/ch2.nii.gz"})");
        if (field(last, "type") != "opened") {
            break;
        }
        keepers.push_back(std::make_unique<TestClient>(port_, "127.0.0.5"));
        ASSERT_EQ(field(keepers.back()->request(R"({"v":1,"type":"join","id":2,"session":")" +
                                                field(last, "session") + "\"}"),
                        "type"),
                  "joined");
    }
    EXPECT_EQ(field(last, "code"), "too_many_sessions") << last;
    EXPECT_EQ(keepers.size(), 3U) << "two running, plus the one it was leaving";
}

// Finding 6, connections: one address holds at most its share of connections (the address the
// per-client session limit counts), while a client from another address is still served, and a
// connection that closes gives its place back.
TEST_F(ServerTest, OneAddressHoldsAtMostItsConnectionsAndAnotherAddressIsStillServed) {
    start(protocol::Limits{},
          [](net::ServerConfig& config) { config.max_connections_per_client = 3; });
    std::vector<std::unique_ptr<TestClient>> hog;
    for (int i = 0; i < 3; ++i) {
        hog.push_back(std::make_unique<TestClient>(port_, "127.0.0.2"));
    }
    for (int i = 0; i < 5; ++i) {
        EXPECT_FALSE(net::Client::connect("127.0.0.1", port_, "/ws", std::chrono::seconds(10),
                                          "127.0.0.2")
                             .ok());
    }
    const auto metrics = net::http_get("127.0.0.1", port_, "/metrics");
    ASSERT_TRUE(metrics.ok());
    EXPECT_NE(metrics->body.find("penumbra_upgrades_refused_total 5"), std::string::npos);

    TestClient newcomer(port_, "127.0.0.3");
    newcomer.open("heads/ch2.nii.gz", 32);
    newcomer.send(R"({"v":1,"type":"render","id":5})");
    EXPECT_EQ(newcomer.frame_answering(5).header.request, 5);

    // The server notices the close on its own strand: the place comes back soon after.
    hog.pop_back();
    bool admitted = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!admitted && std::chrono::steady_clock::now() < deadline) {
        admitted = net::Client::connect("127.0.0.1", port_, "/ws", std::chrono::seconds(10),
                                        "127.0.0.2")
                           .ok();
        if (!admitted) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
    EXPECT_TRUE(admitted);
}

// One client with many sessions asks for frames as fast as it can; another asks for one frame
// at a time. Render time is shared per client, so the second waits for at most about one frame
// of the first, not one frame of each of its sessions. Queueing is read from the frame headers.
TEST_F(ServerTest, ManySessionsOfOneClientDoNotRaiseAnotherClientsQueueing) {
    protocol::Limits limits;
    limits.max_sessions_per_client = 32;
    start(limits);
    constexpr int hog_sessions = 20;
    std::vector<std::unique_ptr<TestClient>> hog;
    for (int i = 0; i < hog_sessions; ++i) {
        hog.push_back(std::make_unique<TestClient>(port_, "127.0.0.2"));
        hog.back()->open("heads/ch2.nii.gz", 64);
    }
    TestClient polite(port_, "127.0.0.3");
    polite.open("heads/ch2.nii.gz", 64);
    std::atomic<bool> done{false};
    std::vector<double> hog_render_ms;
    std::mutex hog_mutex;
    std::vector<std::thread> hogging;
    for (auto& client : hog) {
        hogging.emplace_back([&, c = client.get()] {
            // Always one request waiting: the next is sent when a frame arrives.
            c->send(R"({"v":1,"type":"render"})");
            while (!done) {
                const auto frame = c->next_frame(std::chrono::seconds(60));
                {
                    const std::lock_guard lock(hog_mutex);
                    hog_render_ms.push_back(frame.header.render_ms + frame.header.readback_ms);
                }
                c->send(R"({"v":1,"type":"render"})");
            }
        });
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    std::vector<double> polite_queued_ms;
    for (int i = 0; i < 8; ++i) {
        polite.send(R"({"v":1,"type":"render","id":)" + std::to_string(i) + "}");
        const auto frame = polite.next_frame(std::chrono::seconds(60));
        EXPECT_EQ(frame.header.request, i);
        polite_queued_ms.push_back(frame.header.queued_ms);
    }
    done = true;
    for (auto& thread : hogging) {
        thread.join();
    }
    const auto median = [](std::vector<double> values) {
        std::sort(values.begin(), values.end());
        return values[values.size() / 2];
    };
    const double frame_ms = median(hog_render_ms);
    const double queued_ms = median(polite_queued_ms);
    RecordProperty("hog_frame_ms", std::to_string(frame_ms));
    RecordProperty("polite_queued_ms", std::to_string(queued_ms));
    // Served in the hog's turn order it would wait ~20 frames; in the clients' turn order at
    // most the frame in progress and one more.
    EXPECT_LT(queued_ms, 4.0 * frame_ms + 20.0)
            << "median queued " << queued_ms << " ms, median hog frame " << frame_ms << " ms";
}

// One session refines its still frame (long frames, each many chunks of work) while another
// client drags. A refinement step yields to any other job between two chunks, so the dragging
// client's frames wait for about one chunk, far less than one refinement frame, and refinement
// goes on in between. Queueing is read from the frame headers.
TEST_F(ServerTest, ARefiningSessionDoesNotDelayAnotherSessionsInteractiveFrames) {
    TestClient refiner(port_, "127.0.0.2");
    refiner.open("heads/ch2.nii.gz", 64);
    EXPECT_EQ(field(refiner.request(R"({"v":1,"type":"set","id":3,"settings":{"mode":"dvr",)"
                                    R"("size":[256,256],"sample_distance":0.001,"jitter":true,)"
                                    R"("refinement_steps":256,"refinement_threshold":0}})"),
                    "type"),
              "ack");
    TestClient dragger(port_, "127.0.0.3");
    dragger.open("heads/ch2.nii.gz", 64);
    refiner.send(R"({"v":1,"type":"render","id":10})");
    const auto still = refiner.next_frame();
    EXPECT_EQ(still.header.request, 10);
    EXPECT_EQ(still.header.refinement, 0);
    EXPECT_TRUE(still.header.refining);
    const auto first_step =
            refiner.next_frame(std::chrono::seconds(60), TestClient::Steps::returned);
    EXPECT_EQ(first_step.header.refinement, 1);
    const double refinement_frame_ms = first_step.header.render_ms;

    std::vector<double> queued_ms;
    for (int i = 0; i < 6; ++i) {
        dragger.send(R"({"v":1,"type":"set","camera":{"orbit":{"azimuth":)" +
                     std::to_string(20 * i) + R"(,"elevation":10,"distance":2.6}}})");
        dragger.send(R"({"v":1,"type":"render","interactive":true,"id":)" + std::to_string(i) +
                     "}");
        const auto frame = dragger.next_frame();
        EXPECT_EQ(frame.header.request, i);
        EXPECT_TRUE(frame.header.interactive);
        queued_ms.push_back(frame.header.queued_ms);
    }
    // Refinement went on between the dragging client's frames, and still goes on.
    int last_step = 1;
    for (int i = 0; i < 2; ++i) {
        const auto step = refiner.next_frame(std::chrono::seconds(60), TestClient::Steps::returned);
        EXPECT_GT(step.header.refinement, last_step);
        EXPECT_EQ(step.header.request, 10);
        last_step = step.header.refinement;
    }
    std::sort(queued_ms.begin(), queued_ms.end());
    const double median = queued_ms[queued_ms.size() / 2];
    RecordProperty("refinement_frame_ms", std::to_string(refinement_frame_ms));
    RecordProperty("interactive_queued_ms", std::to_string(median));
    // Served behind whole refinement frames, a request would wait half of one on average.
    EXPECT_LT(median, 0.25 * refinement_frame_ms)
            << "median queued " << median << " ms, one refinement frame " << refinement_frame_ms
            << " ms";
}

// Once a session has measured what its stills cost, a still expected to take longer than its
// frame budget comes first as a smaller preview of the same view, then at its own size, then its
// refinement steps; the first still of a session, measured by nothing, comes at once.
TEST_F(ServerTest, ACostlyStillIsPreviewedSmallerThenComesAtItsOwnSize) {
    TestClient client(port_);
    client.open("heads/ch2.nii.gz", 64);
    // A budget of a millisecond: every still of this session is costly on any machine.
    EXPECT_EQ(field(client.request(R"({"v":1,"type":"set","id":3,"settings":{"mode":"dvr",)"
                                   R"("size":[160,128],"jitter":true,"refinement_steps":1,)"
                                   R"("frame_budget_ms":1}})"),
                    "type"),
              "ack");
    const auto all_frames = [&client](int request) {
        std::vector<protocol::UnpackedFrame> frames;
        do {
            frames.push_back(
                    client.next_frame(std::chrono::seconds(60), TestClient::Steps::returned));
            EXPECT_EQ(frames.back().header.request, request);
        } while (frames.back().header.refining);
        return frames;
    };
    client.send(R"({"v":1,"type":"render","id":10})");
    const auto first = all_frames(10);
    ASSERT_EQ(first.size(), 2u);
    EXPECT_FALSE(first[0].header.preview) << "nothing measured yet";
    EXPECT_EQ(first[0].header.width, 160);

    client.send(R"({"v":1,"type":"render","id":11})");
    const auto second = all_frames(11);
    ASSERT_EQ(second.size(), 3u);
    const auto& preview = second[0].header;
    EXPECT_TRUE(preview.preview);
    EXPECT_TRUE(preview.refining);
    EXPECT_FALSE(preview.interactive);
    EXPECT_EQ(preview.width, 80);  // the interactive frame's size: no smaller
    EXPECT_EQ(preview.height, 64);
    EXPECT_EQ(preview.quality.rfind("still preview: 80x64, the still at 160x128 expected in", 0),
              0u)
            << preview.quality;
    EXPECT_FALSE(second[1].header.preview);
    EXPECT_EQ(second[1].header.width, 160);
    EXPECT_EQ(second[1].header.refinement, 0);
    EXPECT_EQ(second[2].header.refinement, 1);
    // The preview shows the still's view: stretched to the still's size, it is close to it.
    auto small = imageio::decode_image(second[0].image);
    auto still = imageio::decode_image(second[1].image);
    ASSERT_TRUE(small.ok() && still.ok());
    auto stretched = imageio::stretched(*small, still->width, still->height);
    ASSERT_TRUE(stretched.ok()) << stretched.error().to_string();
    const auto difference = base::change_in_levels(*stretched, *still);
    ASSERT_TRUE(difference.ok()) << difference.error().to_string();
    EXPECT_LT(*difference, 16.0) << "RMS difference in 8-bit levels";
}

// A counter's value in /metrics (-1 when absent).
double metric(unsigned short port, const std::string& name) {
    auto metrics = net::http_get("127.0.0.1", port, "/metrics");
    if (!metrics.ok()) {
        return -1.0;
    }
    const auto at = metrics->body.find("\n" + name + " ");
    return at == std::string::npos ? -1.0 : std::stod(metrics->body.substr(at + name.size() + 2));
}

// Floods of bad text and of binary messages: each message is counted, binary ones take from the
// same allowance as text, and penumbra_errors_total counts exactly the error messages sent.
TEST_F(ServerTest, CountersCountWhatWasSentAndBinaryFloodsAreRateLimited) {
    protocol::Limits limits;
    limits.max_requests_per_second = 20;
    start(limits);
    TestClient client(port_);
    const auto drain = [&](int sentinel) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1100));
        client.send(R"({"v":1,"type":"list_volumes","id":)" + std::to_string(sentinel) + "}");
        std::map<std::string, int> codes;
        while (true) {
            const std::string reply = client.next_text(std::chrono::seconds(10));
            if (reply.empty() || field(reply, "type") == "volumes") {
                return codes;
            }
            ++codes[field(reply, "code")];
        }
    };
    for (int i = 0; i < 200; ++i) {
        client.send(R"({"v":1,"type":"teleport"})");
    }
    auto text_codes = drain(1);
    int text_errors = 0;
    for (const auto& [code, count] : text_codes) {
        text_errors += count;
    }
    EXPECT_GT(text_codes["unknown_type"], 0);
    EXPECT_GT(text_codes["rate_limited"], 0);
    EXPECT_EQ(metric(port_, "penumbra_errors_total"), text_errors)
            << "errors sent: " << text_errors;
    EXPECT_EQ(metric(port_, "penumbra_messages_total"), 201);

    for (int i = 0; i < 200; ++i) {
        ASSERT_TRUE(client.raw().send_binary(std::vector<std::uint8_t>{1, 2, 3}).ok());
    }
    auto binary_codes = drain(2);
    int binary_errors = 0;
    for (const auto& [code, count] : binary_codes) {
        binary_errors += count;
    }
    EXPECT_LE(binary_codes["invalid_message"], 25) << "the allowance, plus what refilled";
    EXPECT_GT(binary_codes["rate_limited"], 0);
    EXPECT_EQ(metric(port_, "penumbra_errors_total"), text_errors + binary_errors);
    EXPECT_EQ(metric(port_, "penumbra_messages_total"), 402);
}

TEST_F(ServerTest, ErrorsNameFilesRelativeToTheDataFolder) {
    TestClient client(port_);
    const std::string reply =
            client.request(R"({"v":1,"type":"open","id":1,"volume":"broken_4x4x4_uint8.raw"})");
    EXPECT_EQ(field(reply, "code"), "volume_unreadable") << reply;
    EXPECT_NE(field(reply, "message").find("broken_4x4x4_uint8.raw"), std::string::npos) << reply;
    EXPECT_EQ(reply.find(data_.string()), std::string::npos) << reply;
    EXPECT_EQ(reply.find(fs::temp_directory_path().string()), std::string::npos) << reply;
}

TEST_F(ServerTest, EveryBadInputGetsItsErrorAndTheConnectionKeepsWorking) {
    TestClient client(port_);
    client.open("heads/ch2.nii.gz", 32);

    struct Case {
        std::string message;
        std::string code;
        std::string field;
    };

    const std::vector<Case> cases = {
            {"{not json", "malformed_json", "/"},
            {"[1,2,3]", "invalid_message", "/"},
            {R"({"type":"stats"})", "invalid_message", "/v"},
            {R"({"v":2,"type":"stats"})", "unsupported_version", "/v"},
            {R"({"v":1,"type":"teleport"})", "unknown_type", "/type"},
            {R"({"v":1,"type":"stats","colour":1})", "unknown_field", "/colour"},
            {R"({"v":1,"type":"set","camera":{"eye":[0,0,1e999]}})", "malformed_json", "/"},
            {R"({"v":1,"type":"set","camera":{"eye":[0,0,"far"]}})", "invalid_value",
             "/camera/eye/2"},
            {R"({"v":1,"type":"set","light":{"intensity":-1}})", "out_of_range",
             "/light/intensity"},
            {R"({"v":1,"type":"set","settings":{"size":[100000,64]}})", "out_of_range",
             "/settings/size/0"},
            {R"({"v":1,"type":"set","settings":{"mode":"raytrace"}})", "invalid_value",
             "/settings/mode"},
            {R"({"v":1,"type":"set","settings":{"light_buffer":{"slices":99999}}})", "out_of_range",
             "/settings/light_buffer/slices"},
            {R"({"v":1,"type":"set","camera":{"eye":[0,0,0],"target":[0,0,0]}})", "invalid_value",
             "/camera"},
            {R"({"v":1,"type":"set","cut":{"crop":{"enabled":true,"min":[0,0,0],"max":[5,-5,5]}}})",
             "invalid_value", "/cut/crop"},
            {R"({"v":1,"type":"set","cut":{"crop":{"min":[0,0,0],"max":[5,0,5]}}})",
             "invalid_value", "/cut/crop"},
            {R"({"v":1,"type":"set","cut":{"crop":{"max":[5,5,20000]}}})", "out_of_range",
             "/cut/crop/max/2"},
            {R"({"v":1,"type":"set","cut":{"casts_shadows":1}})", "invalid_value",
             "/cut/casts_shadows"},
            {R"({"v":1,"type":"set","cut":{"plane":{}}})", "unknown_field", "/cut/plane"},
            {R"({"v":1,"type":"set","cut":{"plane_7":{"enabled":true}}})", "unknown_field",
             "/cut/plane_7"},
            {R"({"v":1,"type":"set","cut":{"plane_2":{"enabled":true,"normal":[0,0,0]}}})",
             "invalid_value", "/cut/plane_2/normal"},
            {R"({"v":1,"type":"set","cut":{"plane_1":{"point":[0,"far",0]}}})", "invalid_value",
             "/cut/plane_1/point/1"},
            {R"({"v":1,"type":"set","cut":{"plane_1":{"normal":[0,-1.5,0]}}})", "out_of_range",
             "/cut/plane_1/normal/1"},
            {R"({"v":1,"type":"open","volume":"nope.nii"})", "unknown_volume", "/volume"},
            {R"({"v":1,"type":"open","volume":"../../etc/passwd"})", "unknown_volume", "/volume"},
            {R"({"v":1,"type":"open","volume":"/etc/passwd"})", "unknown_volume", "/volume"},
            {R"({"v":1,"type":"open","volume":"broken_4x4x4_uint8.raw"})", "volume_unreadable",
             "/volume"},
            {R"({"v":1,"type":"join","session":"0000"})", "unknown_session", "/session"},
            {R"({"v":1,"type":"open","volume":")" + std::string(100000, 'x') + "\"}",
             "message_too_large", "/"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.message.substr(0, 80));
        const std::string reply = client.request(c.message);
        EXPECT_EQ(field(reply, "type"), "error") << reply;
        EXPECT_EQ(field(reply, "code"), c.code) << reply;
        EXPECT_EQ(field(reply, "field"), c.field) << reply;
        const std::string stats = client.request(R"({"v":1,"type":"stats"})");
        EXPECT_EQ(field(stats, "type"), "stats");
    }
    ASSERT_TRUE(client.raw().send_binary(std::vector<std::uint8_t>{1, 2, 3}).ok());
    EXPECT_EQ(field(client.next_text(), "code"), "invalid_message");
    client.send(R"({"v":1,"type":"render","id":5})");
    EXPECT_EQ(client.frame_answering(5).header.request, 5);
}

TEST_F(ServerTest, RequestsWithoutASessionAreRefused) {
    TestClient client(port_);
    for (const char* type : {"render", "set"}) {
        const std::string reply =
                client.request(std::string(R"({"v":1,"type":")") + type + R"("})");
        EXPECT_EQ(field(reply, "code"), "no_session") << reply;
    }
}

TEST_F(ServerTest, FloodsAreRateLimitedAndServiceResumes) {
    protocol::Limits limits;
    limits.max_requests_per_second = 20;
    start(limits);
    TestClient client(port_);
    // Enough messages that even a server slowed down (sanitizers, a loaded machine) still reads
    // them faster than its error allowance refills.
    constexpr int flood = 1000;
    const auto flood_start = std::chrono::steady_clock::now();
    for (int i = 0; i < flood; ++i) {
        client.send(R"({"v":1,"type":"stats"})");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    // After a second the allowance is back: a request is answered, behind what the flood got.
    client.send(R"({"v":1,"type":"list_volumes","id":99})");
    int limited = 0;
    int answered = 0;
    std::string reply;
    while (field(reply, "type") != "volumes") {
        reply = client.next_text(std::chrono::seconds(10));
        ASSERT_FALSE(reply.empty());
        limited += field(reply, "code") == "rate_limited" ? 1 : 0;
        answered += field(reply, "type") == "stats" ? 1 : 0;
    }
    EXPECT_GT(limited, 0);
    // The one-second allowance, plus what refilled while the server read the flood.
    const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - flood_start).count();
    EXPECT_LE(answered, limits.max_requests_per_second * (1.0 + elapsed));
    EXPECT_LT(answered, flood / 4);
    // Refusals are answered from their own allowance (64 at once), refilled at the request rate:
    // however slowly the server read the flood, most of it is refused without a reply.
    EXPECT_LE(limited, 64 + limits.max_requests_per_second * (1.0 + elapsed))
            << "a flood gets a bounded number of error replies";
    EXPECT_LT(limited, flood / 4);
}

TEST_F(ServerTest, ClientVanishingMidFrameLeavesTheServerHealthy) {
    {
        TestClient leaving(port_);
        leaving.open("heads/ch2.nii.gz", 64);
        leaving.send(R"({"v":1,"type":"render"})");
        leaving.raw().abort();
    }
    TestClient staying(port_);
    staying.open("heads/ch2.nii.gz", 32);
    staying.send(R"({"v":1,"type":"render","id":2})");
    EXPECT_EQ(staying.frame_answering(2).header.request, 2);
    auto health = net::http_get("127.0.0.1", port_, "/healthz");
    ASSERT_TRUE(health.ok());
    EXPECT_EQ(health->status, 200);
    EXPECT_EQ(health->body, "ok\n");
}

TEST_F(ServerTest, ASlowReaderDoesNotDelayAnotherSession) {
    TestClient slow(port_);
    slow.open("heads/ch2.nii.gz", 128);
    // Many requests, never read: its frames pile up only in its own bounded queue.
    for (int i = 0; i < 30; ++i) {
        slow.send(R"({"v":1,"type":"render"})");
    }
    TestClient fast(port_);
    fast.open("heads/ch2.nii.gz", 32);
    for (int i = 0; i < 3; ++i) {
        fast.send(R"({"v":1,"type":"render","id":)" + std::to_string(i) + "}");
        EXPECT_EQ(fast.next_frame(std::chrono::seconds(30)).header.request, i);
    }
}

TEST_F(ServerTest, AFrameBudgetPicksTheMostAccurateMeasuredSettingThatFits) {
    TestClient client(port_);
    client.open("heads/ch2.nii.gz", 64);
    const std::string ack = client.request(
            R"({"v":1,"type":"set","settings":{"mode":"dvr","frame_budget_ms":50}})");
    ASSERT_EQ(field(ack, "type"), "ack") << ack;
    client.send(R"({"v":1,"type":"render","id":1})");
    const auto frame = client.next_frame();
    EXPECT_EQ(frame.header.mode, "sbrc");
    EXPECT_NE(frame.header.quality.find("budget 50 ms: sbrc n=32 R=64"), std::string::npos)
            << frame.header.quality;
    client.request(R"({"v":1,"type":"set","settings":{"frame_budget_ms":0}})");
    client.send(R"({"v":1,"type":"render","id":2})");
    EXPECT_EQ(client.next_frame().header.mode, "dvr");
}

TEST_F(ServerTest, AFrameOverTheWorkCeilingIsRefusedWithItsEstimateAndTheCeiling) {
    protocol::Limits limits;
    limits.max_frame_work = 1e8;
    start(limits);
    TestClient client(port_);
    EXPECT_EQ(nlohmann::json::parse(client.hello).at("limits").at("max_frame_work"), 1e8);
    client.open("heads/ch2.nii.gz", 64);
    ASSERT_EQ(field(client.request(R"({"v":1,"type":"set","settings":{"size":[1024,1024]}})"),
                    "type"),
              "ack");
    client.send(R"({"v":1,"type":"render","id":1})");
    const std::string refused = client.next_text();
    EXPECT_EQ(field(refused, "code"), "too_much_work") << refused;
    EXPECT_NE(refused.find("1e+08"), std::string::npos) << refused;
    ASSERT_EQ(field(client.request(R"({"v":1,"type":"set","settings":{"size":[64,64]}})"), "type"),
              "ack");
    client.send(R"({"v":1,"type":"render","id":2})");
    EXPECT_EQ(client.frame_answering(2).header.request, 2);
}

// A frame the renderer refuses (here over the work ceiling, which the parser cannot see: it is the
// product of size and sample distance) answers its render request by that request's id, so that a
// client can tell which request failed; a render without id gets an error without one.
TEST_F(ServerTest, AFrameTheRendererRefusesIsAnsweredWithItsRequestsId) {
    protocol::Limits limits;
    limits.max_frame_work = 1e8;
    start(limits);
    TestClient client(port_);
    client.open("heads/ch2.nii.gz", 64);
    ASSERT_EQ(
            field(client.request(R"({"v":1,"type":"set","id":3,"settings":{"size":[1024,1024]}})"),
                  "type"),
            "ack");
    client.send(R"({"v":1,"type":"render","id":41})");
    const auto refused = nlohmann::json::parse(client.next_text());
    EXPECT_EQ(refused.value("code", ""), "too_much_work") << refused;
    ASSERT_TRUE(refused.contains("id")) << refused;
    EXPECT_EQ(refused.at("id"), 41) << refused;
    client.send(R"({"v":1,"type":"render"})");
    const auto anonymous = nlohmann::json::parse(client.next_text());
    EXPECT_EQ(anonymous.value("code", ""), "too_much_work") << anonymous;
    EXPECT_FALSE(anonymous.contains("id")) << anonymous;
}

// Finding 3: a frame that would hold the only render thread for many minutes (2048^2 pixels at
// sample distance 1/4096: about 3e10 iterations, under the default ceiling) gives it up between
// two of its chunks when its session asks for a newer frame, and when its session closes. The
// bound (15 s) is far above what a chunk takes and far below what the frame would.
TEST_F(ServerTest, ANewerRequestOrClosingTheSessionCancelsALongFrame) {
    using namespace std::chrono_literals;
    const std::string long_frame =
            R"({"v":1,"type":"set","settings":{"mode":"dvr","size":[2048,2048],)"
            R"("sample_distance":0.000244140625}})";
    const std::string short_frame =
            R"({"v":1,"type":"set","settings":{"size":[32,32],"sample_distance":0.00390625}})";
    TestClient client(port_);
    client.open("heads/ch2.nii.gz");
    ASSERT_EQ(field(client.request(long_frame), "type"), "ack");
    client.send(R"({"v":1,"type":"render","id":1})");
    std::this_thread::sleep_for(1s);  // rendering now
    ASSERT_EQ(field(client.request(short_frame), "type"), "ack");
    auto start = std::chrono::steady_clock::now();
    client.send(R"({"v":1,"type":"render","id":2})");
    EXPECT_EQ(client.next_frame(15s).header.request, 2);
    std::printf("[ measured ] newer request answered after %.2f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());

    auto hog = std::make_unique<TestClient>(port_);
    hog->open("heads/ch2.nii.gz");
    ASSERT_EQ(field(hog->request(long_frame), "type"), "ack");
    hog->send(R"({"v":1,"type":"render","id":1})");
    std::this_thread::sleep_for(1s);
    client.send(R"({"v":1,"type":"render","id":3})");  // waits behind the hog's frame
    std::this_thread::sleep_for(500ms);
    start = std::chrono::steady_clock::now();
    hog.reset();  // the connection closes, and with it the session
    EXPECT_EQ(client.next_frame(15s).header.request, 3);
    std::printf("[ measured ] frame of another session answered %.2f s after the close\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

TEST_F(ServerTest, HttpServesHealthMetricsAndRefusesPathsOutsideTheRoot) {
    TestClient client(port_);
    client.open("heads/ch2.nii.gz", 32);
    // One frame and no refinement steps after it, so that the counter is exact.
    ASSERT_EQ(field(client.request(
                            R"({"v":1,"type":"set","id":2,"settings":{"refinement_steps":0}})"),
                    "type"),
              "ack");
    client.send(R"({"v":1,"type":"render"})");
    client.next_frame();
    auto metrics = net::http_get("127.0.0.1", port_, "/metrics");
    ASSERT_TRUE(metrics.ok());
    EXPECT_EQ(metrics->status, 200);
    EXPECT_NE(metrics->body.find("penumbra_frames_total 1"), std::string::npos) << metrics->body;
    EXPECT_NE(metrics->body.find("penumbra_render_ms_bucket{le="), std::string::npos);
    EXPECT_NE(metrics->body.find("penumbra_sessions 1"), std::string::npos);
    auto index = net::http_get("127.0.0.1", port_, "/");
    ASSERT_TRUE(index.ok());
    EXPECT_EQ(index->status, 200);
    auto escape = net::http_get("127.0.0.1", port_, "/../../etc/passwd");
    ASSERT_TRUE(escape.ok());
    EXPECT_EQ(escape->status, 404);
}

TEST_F(ServerTest, AnAccessTokenIsAskedOnTheUpgradeAsAPercentEncodedQueryParameter) {
    start(protocol::Limits{}, [](net::ServerConfig& config) { config.access_token = "a+b/c=d"; });
    for (const char* path :
         {"/ws", "/ws?volume=heads%2Fch2.nii.gz", "/ws?token=a+b/c=d", "/ws?token=a%2Bb%2Fc%3De"}) {
        SCOPED_TRACE(path);
        EXPECT_FALSE(net::Client::connect("127.0.0.1", port_, path).ok());
    }
    auto allowed = net::Client::connect("127.0.0.1", port_,
                                        "/ws?volume=heads%2Fch2.nii.gz&token=a%2Bb%2Fc%3Dd");
    ASSERT_TRUE(allowed.ok()) << allowed.error().to_string();
    auto hello = (*allowed)->receive(std::chrono::seconds(10));
    ASSERT_TRUE(hello.ok());
    EXPECT_NE(hello->text.find("\"type\":\"hello\""), std::string::npos);
    auto metrics = net::http_get("127.0.0.1", port_, "/metrics");
    ASSERT_TRUE(metrics.ok());
    EXPECT_NE(metrics->body.find("penumbra_upgrades_refused_total 4"), std::string::npos);
}

// As if the server that held a session died: the session is gone here, and its owner comes with
// the token the cluster's secret derived and the session's volume. The volume loads off the
// network threads, as for open; the session comes back under its id with the default state.
TEST_F(ServerTest, AClusterOwnerRecreatesItsSessionAfterItsVolumeLoadsAndOnlyWithItsToken) {
    owner_tokens_ = session::OwnerTokens("cluster secret");
    protocol::Limits limits;
    limits.max_sessions_per_connection = 1;
    start(limits);
    std::string session;
    std::string token;
    {
        TestClient owner(port_);
        const auto opened = nlohmann::json::parse(owner.open("heads/ch2.nii.gz", 32));
        session = owner.session;
        token = opened.at("owner_token");
        EXPECT_FALSE(opened.contains("recreated"));
        EXPECT_EQ(field(owner.request(R"({"v":1,"type":"close","id":3})"), "type"), "ack");
    }
    ASSERT_EQ(sessions_->find(session), nullptr);
    EXPECT_EQ(token, session::OwnerTokens("cluster secret").token_for(session));
    const auto resume_with_volume = [&](const std::string& owner_token, int id) {
        return R"({"v":1,"type":"resume","id":)" + std::to_string(id) + R"(,"session":")" +
               session + R"(","owner_token":")" + owner_token + R"(","volume":"heads/ch2.nii.gz"})";
    };
    TestClient returning(port_);
    // A forged token and a resume that does not name the volume load nothing and re-create
    // nothing.
    const std::string forged = returning.request(resume_with_volume(std::string(32, '0'), 4));
    EXPECT_EQ(field(forged, "code"), "unknown_session") << forged;
    EXPECT_EQ(field(returning.request(resume_request(session, token, 5)), "code"),
              "unknown_session");
    EXPECT_EQ(sessions_->count(), 0U);
    // The connection already holds its one session: re-creating replaces it, as open does.
    returning.open("heads/ch2.nii.gz", 32);
    // Requests sent while the volume loads wait and are answered after `opened`, in order.
    returning.send(resume_with_volume(token, 6));
    returning.send(R"({"v":1,"type":"render","id":7})");
    const auto recreated = nlohmann::json::parse(returning.next_text());
    ASSERT_EQ(recreated.at("type"), "opened") << recreated.dump().substr(0, 300);
    EXPECT_EQ(recreated.at("id"), 6);
    EXPECT_EQ(recreated.at("session"), session);
    EXPECT_EQ(recreated.at("owner_token"), token);
    EXPECT_EQ(recreated.at("recreated"), true);
    EXPECT_EQ(returning.frame_answering(7).header.request, 7);
    EXPECT_EQ(sessions_->count(), 1U);
    TestClient viewer(port_);
    EXPECT_EQ(field(viewer.request(R"({"v":1,"type":"join","id":8,"session":")" + session + "\"}"),
                    "type"),
              "joined")
            << "its viewers find it under its id";
}

}  // namespace
}  // namespace penumbra::integration
