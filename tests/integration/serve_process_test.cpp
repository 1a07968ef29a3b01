// `penumbra serve` as a process: what only a whole process shows (its descriptor limit, its CPU
// time, its log, its exit on a signal).

#include <penumbra/net/client.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace penumbra::integration {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

std::string read_file(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

int count_lines_containing(const std::string& text, const std::string& needle) {
    int count = 0;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        count += line.find(needle) != std::string::npos ? 1 : 0;
    }
    return count;
}

// A `penumbra serve` child process on a free port of 127.0.0.1, its output in a log file.
class ServeProcess {
public:
    // `max_descriptors` > 0 lowers the child's RLIMIT_NOFILE, as `prlimit --nofile` would. No
    // start-up measurement unless `extra` asks for one.
    ServeProcess(const fs::path& data, const fs::path& log, std::vector<std::string> extra,
                 rlim_t max_descriptors = 0)
        : log_(log) {
        std::vector<std::string> args = {PENUMBRA_CLI,  "serve",  "--data",
                                         data.string(), "--port", "0"};
        if (std::find(extra.begin(), extra.end(), "--quality-measure") == extra.end()) {
            args.emplace_back("--no-quality-measure");
        }
        args.insert(args.end(), extra.begin(), extra.end());
        pid_ = ::fork();
        if (pid_ == 0) {
            const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            ::dup2(out, STDOUT_FILENO);
            ::dup2(out, STDERR_FILENO);
            ::close(out);
            if (max_descriptors > 0) {
                const rlimit limit{max_descriptors, max_descriptors};
                ::setrlimit(RLIMIT_NOFILE, &limit);
            }
            std::vector<char*> argv;
            for (auto& arg : args) {
                argv.push_back(arg.data());
            }
            argv.push_back(nullptr);
            ::execv(argv[0], argv.data());
            ::_exit(127);
        }
        // Start-up creates the GL context; on llvmpipe that takes a second or two.
        const std::regex serving(R"(serving: +http://127\.0\.0\.1:([0-9]+)/)");
        for (const auto until = Clock::now() + 120s; Clock::now() < until && !exited();) {
            std::smatch match;
            const std::string text = read_file(log_);
            if (std::regex_search(text, match, serving)) {
                port_ = static_cast<unsigned short>(std::stoi(match[1]));
                return;
            }
            std::this_thread::sleep_for(50ms);
        }
    }

    ServeProcess(const ServeProcess&) = delete;
    ServeProcess& operator=(const ServeProcess&) = delete;

    ~ServeProcess() {
        if (!exit_status_) {
            ::kill(pid_, SIGKILL);
            int status = 0;
            ::waitpid(pid_, &status, 0);
        }
    }

    [[nodiscard]] unsigned short port() const { return port_; }

    [[nodiscard]] pid_t pid() const { return pid_; }

    [[nodiscard]] std::string log() const { return read_file(log_); }

    // User + system CPU time so far, from /proc.
    [[nodiscard]] double cpu_seconds() const {
        std::istringstream stat(read_file("/proc/" + std::to_string(pid_) + "/stat"));
        std::string field;
        // The command name (field 2) has no spaces here; utime and stime are fields 14 and 15.
        std::vector<std::string> fields;
        while (stat >> field) {
            fields.push_back(field);
        }
        if (fields.size() < 15) {
            return -1.0;
        }
        return static_cast<double>(std::stoll(fields[13]) + std::stoll(fields[14])) /
               static_cast<double>(::sysconf(_SC_CLK_TCK));
    }

    bool exited() {
        if (exit_status_) {
            return true;
        }
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            exit_status_ = status;
            return true;
        }
        return false;
    }

    // The exit status once the process has exited within `timeout`.
    std::optional<int> wait_for_exit(std::chrono::milliseconds timeout) {
        for (const auto until = Clock::now() + timeout; Clock::now() < until;) {
            if (exited()) {
                return exit_status_;
            }
            std::this_thread::sleep_for(10ms);
        }
        return exited() ? exit_status_ : std::nullopt;
    }

private:
    fs::path log_;
    pid_t pid_ = -1;
    unsigned short port_ = 0;
    std::optional<int> exit_status_;
};

class ServeProcessTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra_serve_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_ / "data");
        const fs::path ch2 = "/usr/share/mricron/templates/ch2.nii.gz";
        ASSERT_TRUE(fs::exists(ch2)) << "install mricron-data (scripts/install-deps.sh does)";
        fs::copy_file(ch2, dir_ / "data" / "ch2.nii.gz");
    }

    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    fs::path dir_;
};

// A TCP connection to 127.0.0.1:port that sends nothing; -1 if connect failed.
int open_idle_connection(unsigned short port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
        ::close(fd);
        return -1;
    }
    return fd;
}

TEST_F(ServeProcessTest, OutOfDescriptorsTheListenerBacksOffLogsRarelyAndServesAgainAfter) {
    constexpr rlim_t max_descriptors = 96;
    ServeProcess server(dir_ / "data", dir_ / "serve.log", {}, max_descriptors);
    ASSERT_NE(server.port(), 0) << server.log();
    // More connections than the server has descriptors: the kernel completes them (the listen
    // backlog), the server cannot accept the rest.
    std::vector<int> connections;
    for (rlim_t i = 0; i < max_descriptors + 40; ++i) {
        const int fd = open_idle_connection(server.port());
        ASSERT_GE(fd, 0) << "connection " << i;
        connections.push_back(fd);
    }
    for (const auto until = Clock::now() + 5s;
         Clock::now() < until && server.log().find("accept failed") == std::string::npos;) {
        std::this_thread::sleep_for(20ms);
    }
    ASSERT_NE(server.log().find("accept failed"), std::string::npos)
            << "the server never ran out of descriptors:\n"
            << server.log();
    const double cpu_before = server.cpu_seconds();
    std::this_thread::sleep_for(3s);
    const double cpu_used = server.cpu_seconds() - cpu_before;
    EXPECT_LT(cpu_used, 0.3) << "seconds of CPU in 3 s at the descriptor limit";
    const int log_lines = count_lines_containing(server.log(), "accept failed");
    EXPECT_LE(log_lines, 3) << server.log().substr(0, 2000);

    for (const int fd : connections) {
        ::close(fd);
    }
    // Descriptors free again: the server accepts and answers within its longest back-off.
    std::optional<int> status;
    for (const auto until = Clock::now() + 10s; Clock::now() < until && status != 200;) {
        auto health = net::http_get("127.0.0.1", server.port(), "/healthz", 2s);
        status = health ? std::optional(health->status) : std::nullopt;
    }
    EXPECT_EQ(status, 200) << server.log().substr(0, 2000);
}

// SIGTERM while a frame that takes minutes renders: the server cancels it between two of its
// chunks, closes its connections, joins its threads and exits 0, all within about two seconds.
TEST_F(ServeProcessTest, SigtermStopsALongRenderAndExitsCleanlyWithinTwoSeconds) {
    // A ceiling high enough to admit the frame below (about a minute on llvmpipe).
    ServeProcess server(dir_ / "data", dir_ / "serve.log", {"--max-frame-work", "1e13"});
    ASSERT_NE(server.port(), 0) << server.log();
    auto client = net::Client::connect("127.0.0.1", server.port());
    ASSERT_TRUE(client.ok()) << client.error().to_string();
    auto& ws = **client;
    ASSERT_TRUE(ws.receive().ok());  // hello
    ASSERT_TRUE(ws.send_text(R"({"v":1,"type":"open","id":1,"volume":"ch2.nii.gz"})").ok());
    auto opened = ws.receive();
    ASSERT_TRUE(opened.ok() && opened->text.find("\"opened\"") != std::string::npos);
    // Shadow rays from every sample at a fine step: minutes on a software rasteriser.
    ASSERT_TRUE(ws.send_text(R"({"v":1,"type":"set","id":2,"settings":{"mode":"reference",)"
                             R"("size":[512,512],"sample_distance":0.0009765625}})")
                        .ok());
    auto ack = ws.receive();
    ASSERT_TRUE(ack.ok() && ack->text.find("\"ack\"") != std::string::npos) << ack->text;
    ASSERT_TRUE(ws.send_text(R"({"v":1,"type":"render","id":3})").ok());
    // Give the render thread time to take the frame and be well into it; it neither failed (was
    // refused) nor finished.
    std::this_thread::sleep_for(1500ms);
    ASSERT_FALSE(server.exited());
    auto metrics = net::http_get("127.0.0.1", server.port(), "/metrics");
    ASSERT_TRUE(metrics.ok());
    ASSERT_NE(metrics->body.find("\npenumbra_render_failures_total 0\n"), std::string::npos)
            << metrics->body;
    ASSERT_NE(metrics->body.find("\npenumbra_frames_total 0\n"), std::string::npos);
    const auto signalled = Clock::now();
    ASSERT_EQ(::kill(server.pid(), SIGTERM), 0);
    const auto status = server.wait_for_exit(5s);
    const double seconds = std::chrono::duration<double>(Clock::now() - signalled).count();
    ASSERT_TRUE(status.has_value()) << "still running 5 s after SIGTERM:\n" << server.log();
    RecordProperty("exit_seconds", std::to_string(seconds));
    EXPECT_TRUE(WIFEXITED(*status)) << server.log();
    EXPECT_EQ(WEXITSTATUS(*status), 0) << server.log();
    EXPECT_LT(seconds, 2.0) << server.log();
}

// The data folder an operator may be handed: besides a volume linked in from elsewhere, a link to
// "/", a link to the folder itself (a loop), a link to a folder outside holding a DICOM file, a
// FIFO named like a volume and one not, and `stray_files` small files that are not volumes.
void make_hostile_data_folder(const fs::path& data, const fs::path& outside, int stray_files) {
    fs::remove(data / "ch2.nii.gz");
    fs::create_symlink("/usr/share/mricron/templates/ch2.nii.gz", data / "ch2.nii.gz");
    fs::create_directory_symlink("/", data / "rootlink");
    fs::create_directory_symlink(data, data / "loop");
    fs::create_directories(outside);
    fs::copy_file("/usr/lib/python3/dist-packages/pydicom/data/test_files/CT_small.dcm",
                  outside / "CT_small.dcm");
    fs::create_directory_symlink(outside, data / "pacs");
    ASSERT_EQ(::mkfifo((data / "fifo").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo((data / "pipe.nrrd").c_str(), 0600), 0);
    fs::create_directories(data / "stray");
    for (int i = 0; i < stray_files; ++i) {
        const std::string name = (data / "stray" / ("f" + std::to_string(i))).string();
        const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ASSERT_GE(fd, 0) << name;
        ASSERT_EQ(::write(fd, "x", 1), 1);
        ::close(fd);
    }
}

// The text answer of `type` to a request sent on `ws`, frames skipped.
std::string ask(net::Client& ws, const std::string& request, const std::string& type) {
    if (!ws.send_text(request).ok()) {
        return "(not sent)";
    }
    for (int i = 0; i < 100; ++i) {
        auto message = ws.receive(60s);
        if (!message.ok()) {
            return "(no answer: " + message.error().to_string() + ")";
        }
        if (!message->binary &&
            (message->text.find("\"type\":\"" + type + "\"") != std::string::npos ||
             message->text.find("\"type\":\"error\"") != std::string::npos)) {
            return message->text;
        }
    }
    return "(no answer)";
}

double metric(const std::string& text, const std::string& name) {
    const auto at = text.find("\n" + name + " ");
    return at == std::string::npos ? -1.0 : std::stod(text.substr(at + name.size() + 2));
}

// How much longer than its median the slowest frame beside the scans may take, how many frames in
// a hundred may take more than twice it, and how soon a server stops mid-pass. Under the
// sanitizers the walk's many small allocations go through ASan's allocator and checks on one of
// this machine's two cores while llvmpipe wants both for the frame: a pass slows the frames it
// overlaps by a constant share, and a few of them cross twice the median without any lock held.
// The sanitizer run proves memory safety here, the release run the timings; there a pass over
// 100,000 stray files takes longer than the half minute of rendering that must see three passes,
// so the folder holds a fifth of them (every kind of hostile entry is still there). The release
// run allows two frames in a hundred beside the first: sharing the two cores with the bundle
// test's chroot (CTest runs two tests at once), 2 of 46 frames once took over twice the median
// (the second slowest 2.1 times); a stall the scans caused would hold many frames, or one longer.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr double stall_ratio = 4.0;
constexpr double slow_frames_per_hundred = 3.0;
constexpr double exit_budget_s = 5.0;
constexpr int hostile_stray_files = 20'000;
#else
constexpr double stall_ratio = 3.0;
constexpr double slow_frames_per_hundred = 2.0;
constexpr double exit_budget_s = 2.0;
constexpr int hostile_stray_files = 100'000;
#endif

// Seconds from the start of `penumbra serve --data data` to its first answer on /healthz.
double seconds_to_health(const fs::path& data, const fs::path& log,
                         std::unique_ptr<ServeProcess>& server, std::vector<std::string> extra) {
    const auto started = Clock::now();
    server = std::make_unique<ServeProcess>(data, log, std::move(extra));
    if (server->port() == 0) {
        return -1.0;
    }
    auto health = net::http_get("127.0.0.1", server->port(), "/healthz", 2s);
    if (!health.ok() || health->status != 200) {
        return -1.0;
    }
    return std::chrono::duration<double>(Clock::now() - started).count();
}

// A data folder holding a link to "/", a loop, a link leaving it, FIFOs and 100,000 stray files
// (hostile_stray_files):
// the server answers its health check as soon as it does with an empty folder (half a second
// later at most; about half a second in all here), lists and opens nothing from outside, names
// each link that leaves once (not at every rescan), a client rendering throughout the rescans
// sees no frame but one take longer than twice its median, and SIGTERM is not held up by a pass.
TEST_F(ServeProcessTest, AHostileDataFolderNeitherDelaysStartNorLeaksNorStallsFrames) {
    const fs::path data = dir_ / "data";
    make_hostile_data_folder(data, dir_ / "outside", hostile_stray_files);
    // The start-up the folder may not delay: the same server's with an empty folder (its GL
    // context, its tables), measured first.
    fs::create_directories(dir_ / "empty");
    std::unique_ptr<ServeProcess> baseline;
    const double baseline_s = seconds_to_health(dir_ / "empty", dir_ / "empty.log", baseline, {});
    baseline.reset();
    ASSERT_GT(baseline_s, 0.0);
    // Small frames come faster than a person asks: the rate limit is not what is tested.
    std::unique_ptr<ServeProcess> serving;
    const double healthy_after =
            seconds_to_health(data, dir_ / "serve.log", serving,
                              {"--rescan-interval", "0.5", "--max-requests-per-second", "1e6"});
    ServeProcess& server = *serving;
    ASSERT_GT(healthy_after, 0.0) << server.log().substr(0, 2000);
    RecordProperty("healthz_seconds", std::to_string(healthy_after));
    RecordProperty("healthz_seconds_empty_folder", std::to_string(baseline_s));
    EXPECT_LT(healthy_after, baseline_s + 0.5) << server.log().substr(0, 2000);

    // The victim: opens the linked volume at once (the open waits for the scan to list it) and
    // renders small frames one after another through the first pass and a dozen rescans.
    auto client = net::Client::connect("127.0.0.1", server.port());
    ASSERT_TRUE(client.ok()) << client.error().to_string();
    auto& ws = **client;
    ASSERT_TRUE(ws.receive().ok());  // hello
    const std::string opened =
            ask(ws, R"({"v":1,"type":"open","id":1,"volume":"ch2.nii.gz"})", "opened");
    ASSERT_NE(opened.find("\"opened\""), std::string::npos) << opened;
    const std::string ack =
            ask(ws,
                R"({"v":1,"type":"set","id":2,"settings":{"mode":"sbrc","size":[256,256],)"
                R"("refinement_steps":0}})",
                "ack");
    ASSERT_NE(ack.find("\"ack\""), std::string::npos) << ack;
    // A frame every 150 ms at most, as a client paced to its display asks, through several
    // rescans: each frame's time from request to arrival.
    const auto scans = [&] {
        const auto metrics = net::http_get("127.0.0.1", server.port(), "/metrics");
        return metrics.ok() ? metric(metrics->body, "penumbra_volume_scans_total") : -1.0;
    };
    const double scans_before = scans();
    std::vector<double> frame_ms;
    const auto rendering = Clock::now();
    // At least six seconds, and until three passes have run (a sanitizer's build walks slower).
    const auto rendered_enough = [&](std::int64_t id) {
        const auto elapsed = Clock::now() - rendering;
        return elapsed >= 30s || (elapsed >= 6s && id % 10 == 0 && scans() - scans_before >= 3.0);
    };
    for (std::int64_t id = 3; !rendered_enough(id); ++id) {
        const auto sent = Clock::now();
        ASSERT_TRUE(
                ws.send_text(R"({"v":1,"type":"render","id":)" + std::to_string(id) + "}").ok());
        while (true) {
            auto message = ws.receive(10s);
            ASSERT_TRUE(message.ok()) << message.error().to_string();
            ASSERT_EQ(message->text.find("\"type\":\"error\""), std::string::npos) << message->text;
            if (message->binary) {
                break;
            }
        }
        frame_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - sent).count());
        std::this_thread::sleep_until(sent + 150ms);
    }
    const double scans_during = scans() - scans_before;
    EXPECT_GE(scans_during, 3.0) << "the rescans did not run while the client rendered";
    ASSERT_GE(frame_ms.size(), 20U);
    frame_ms.erase(frame_ms.begin());  // the first frame pays for the volume's upload
    std::vector<double> sorted = frame_ms;
    std::sort(sorted.begin(), sorted.end());
    const double median_ms = sorted[sorted.size() / 2];
    const double longest_ms = sorted.back();
    RecordProperty("frame_ms", std::to_string(median_ms));
    RecordProperty("longest_frame_ms", std::to_string(longest_ms));
    RecordProperty("scans_while_rendering", std::to_string(scans_during));
    // Every frame but one (and slow_frames_per_hundred) within twice the median, and the slowest
    // within stall_ratio: a stall the scans caused would hold several frames (the issue's was
    // 9.5 s), while this 2-core machine's scheduler delays a single frame now and then with no
    // scan at all.
    const auto slow_frames_allowed =
            1 + static_cast<std::size_t>(slow_frames_per_hundred *
                                         static_cast<double>(sorted.size()) / 100.0);
    const double slowest_within_twice_ms = sorted[sorted.size() - 1 - slow_frames_allowed];
    EXPECT_LE(slowest_within_twice_ms, 2.0 * median_ms)
            << "frames: " << frame_ms.size() << ", median " << median_ms << " ms, "
            << slow_frames_allowed << " may take longer than twice it";
    EXPECT_LE(longest_ms, stall_ratio * median_ms)
            << "frames: " << frame_ms.size() << ", median " << median_ms << " ms";

    const auto metrics = net::http_get("127.0.0.1", server.port(), "/metrics");
    ASSERT_TRUE(metrics.ok());
    EXPECT_EQ(metric(metrics->body, "penumbra_volume_scans_cut_short_total"), 0.0);
    RecordProperty("scan_seconds",
                   std::to_string(metric(metrics->body, "penumbra_volume_scan_seconds")));

    const std::string listed = ask(ws, R"({"v":1,"type":"list_volumes","id":100})", "volumes");
    EXPECT_NE(listed.find("\"listing\":\"complete\""), std::string::npos) << listed;
    EXPECT_NE(listed.find("\"id\":\"ch2.nii.gz\""), std::string::npos) << listed;
    for (const char* outside : {"rootlink", "pacs", "loop/", "fifo", "pipe.nrrd", "stray"}) {
        EXPECT_EQ(listed.find(std::string("\"id\":\"") + outside), std::string::npos)
                << outside << " listed: " << listed.substr(0, 1000);
    }
    for (const char* id : {"pacs", "rootlink/usr/share/mricron/templates/ch2.nii.gz",
                           "loop/ch2.nii.gz", "../outside/CT_small.dcm"}) {
        const std::string refused =
                ask(ws, std::string(R"({"v":1,"type":"open","id":101,"volume":")") + id + "\"}",
                    "opened");
        EXPECT_NE(refused.find("\"code\":\"unknown_volume\""), std::string::npos)
                << id << ": " << refused;
    }
    const std::string log = server.log();
    EXPECT_EQ(count_lines_containing(log, "skipped rootlink: a link to a folder outside"), 1)
            << log.substr(0, 4000);
    EXPECT_EQ(count_lines_containing(log, "skipped pacs: a link to a folder outside"), 1);
    EXPECT_LE(count_lines_containing(log, "skipped stray/"), 20) << "a flood of skipped files";

    // Shutting down does not wait for a pass to finish its walk.
    const auto signalled = Clock::now();
    ASSERT_EQ(::kill(server.pid(), SIGTERM), 0);
    const auto status = server.wait_for_exit(10s);
    const double exit_seconds = std::chrono::duration<double>(Clock::now() - signalled).count();
    ASSERT_TRUE(status.has_value()) << "still running 10 s after SIGTERM";
    EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 0) << server.log().substr(0, 2000);
    EXPECT_LT(exit_seconds, exit_budget_s);
}

// What an operator allows, links may lead to: the folder outside opens through its link.
TEST_F(ServeProcessTest, AnAllowedRootOpensThroughItsLink) {
    const fs::path data = dir_ / "data";
    make_hostile_data_folder(data, dir_ / "outside", 10);
    ServeProcess server(data, dir_ / "serve.log",
                        {"--allow-links-to", (dir_ / "outside").string()});
    ASSERT_NE(server.port(), 0) << server.log();
    auto client = net::Client::connect("127.0.0.1", server.port());
    ASSERT_TRUE(client.ok()) << client.error().to_string();
    auto& ws = **client;
    ASSERT_TRUE(ws.receive().ok());  // hello
    const std::string opened = ask(ws, R"({"v":1,"type":"open","id":1,"volume":"pacs"})", "opened");
    EXPECT_NE(opened.find("\"opened\""), std::string::npos) << opened;
    const std::string refused =
            ask(ws, R"({"v":1,"type":"open","id":2,"volume":"rootlink/etc/hostname"})", "opened");
    EXPECT_NE(refused.find("\"code\":\"unknown_volume\""), std::string::npos) << refused;
}

// A pass that reaches its budget stops, says so in the log, in /metrics and in list_volumes, and
// lists what it found.
TEST_F(ServeProcessTest, AScanCutShortByItsBudgetSaysSo) {
    const fs::path data = dir_ / "data";
    make_hostile_data_folder(data, dir_ / "outside", 3'000);
    ServeProcess server(data, dir_ / "serve.log", {"--scan-max-entries", "1000"});
    ASSERT_NE(server.port(), 0) << server.log();
    std::string log;
    for (const auto until = Clock::now() + 10s;
         Clock::now() < until && log.find("scan cut short") == std::string::npos;) {
        std::this_thread::sleep_for(50ms);
        log = server.log();
    }
    EXPECT_NE(log.find("scan cut short after 1000 entries"), std::string::npos) << log;
    EXPECT_NE(log.find("more than 1000 files and folders (--scan-max-entries)"), std::string::npos);
    const auto metrics = net::http_get("127.0.0.1", server.port(), "/metrics");
    ASSERT_TRUE(metrics.ok());
    EXPECT_GE(metric(metrics->body, "penumbra_volume_scans_cut_short_total"), 1.0) << metrics->body;
    auto client = net::Client::connect("127.0.0.1", server.port());
    ASSERT_TRUE(client.ok()) << client.error().to_string();
    ASSERT_TRUE((*client)->receive().ok());  // hello
    const std::string listed = ask(**client, R"({"v":1,"type":"list_volumes","id":1})", "volumes");
    EXPECT_NE(listed.find("\"listing\":\"cut_short\""), std::string::npos) << listed;
}

// A device without a committed table measures one at start-up, on a volume of the data folder:
// that measurement waits for the folder's first scan (the only start-up step that does).
TEST_F(ServeProcessTest, AStartUpMeasurementWaitsForTheFirstScanToFindItsVolume) {
    const fs::path data = dir_ / "data";
    make_hostile_data_folder(data, dir_ / "outside", 30'000);  // a pass longer than GL's start
    const char* cache = std::getenv("XDG_CACHE_HOME");
    const std::optional<std::string> saved =
            cache ? std::optional<std::string>(cache) : std::nullopt;
    ::setenv("XDG_CACHE_HOME", (dir_ / "cache").c_str(), 1);  // the measured table goes there
    ServeProcess server(data, dir_ / "serve.log", {"--quality-measure"});
    if (saved) {
        ::setenv("XDG_CACHE_HOME", saved->c_str(), 1);
    } else {
        ::unsetenv("XDG_CACHE_HOME");
    }
    ASSERT_NE(server.port(), 0) << server.log();
    EXPECT_NE(server.log().find("quality:  measured "), std::string::npos) << server.log();
    EXPECT_NE(server.log().find(" points on ch2.nii.gz"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::integration
