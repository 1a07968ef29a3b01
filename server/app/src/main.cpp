#include "commands.hpp"

#include <penumbra/cli/options.hpp>

#include <string>
#include <vector>

int main(int argc, char** argv) {
    using namespace penumbra::app;
    return penumbra::cli::run_subcommand(
            "penumbra", "command",
            {{"render", "render one frame of a volume to a PNG or JPEG file", run_render},
             {"serve", "run the rendering service (HTTP + WebSocket) on a folder of volumes",
              run_serve},
             {"load", "N simulated clients against a running server: latency p50/p95/p99",
              run_load},
             {"info", "print a volume's dimensions, spacing, type, range and histogram", run_info},
             {"bench",
              "benchmarks: `bench modes` times every mode side by side; `bench accuracy`\n\t"
              "measures error against the converged truth vs frame time",
              run_bench}},
            {argv + 1, argv + argc});
}
