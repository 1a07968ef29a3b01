#include "commands.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace {

void print_usage() {
    std::puts(
            "usage: penumbra <command> [options]\n"
            "\n"
            "commands:\n"
            "  render   render one frame of a volume to a PNG or JPEG file\n"
            "  serve    run the rendering service (HTTP + WebSocket) on a folder of volumes\n"
            "  load     N simulated clients against a running server: latency p50/p95/p99\n"
            "  info     print a volume's dimensions, spacing, type, range and histogram\n"
            "  bench    benchmarks: `bench modes` times every mode side by side; `bench accuracy`\n"
            "           measures error against the reference vs frame time\n"
            "\n"
            "`penumbra <command> --help` lists the options of a command.");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        print_usage();
        return 2;
    }
    const std::string command = argv[1];
    const std::vector<std::string> args(argv + 2, argv + argc);
    if (command == "render") {
        return penumbra::app::run_render(args);
    }
    if (command == "load") {
        return penumbra::app::run_load(args);
    }
    if (command == "serve") {
        return penumbra::app::run_serve(args);
    }
    if (command == "info") {
        return penumbra::app::run_info(args);
    }
    if (command == "bench") {
        return penumbra::app::run_bench(args);
    }
    if (command == "--help" || command == "-h" || command == "help") {
        print_usage();
        return 0;
    }
    std::fprintf(stderr, "penumbra: unknown command '%s'\n\n", command.c_str());
    print_usage();
    return 2;
}
