// `penumbra serve` as a process: what only a whole process shows (its descriptor limit, its CPU
// time, its log, its exit on a signal).

#include <penumbra/net/client.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
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
    // `max_descriptors` > 0 lowers the child's RLIMIT_NOFILE, as `prlimit --nofile` would.
    ServeProcess(const fs::path& data, const fs::path& log, std::vector<std::string> extra,
                 rlim_t max_descriptors = 0)
        : log_(log) {
        std::vector<std::string> args = {PENUMBRA_CLI,          "serve",  "--data",
                                         data.string(),         "--port", "0",
                                         "--no-quality-measure"};
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
        for (const auto until = Clock::now() + 60s; Clock::now() < until && !exited();) {
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

}  // namespace
}  // namespace penumbra::integration
