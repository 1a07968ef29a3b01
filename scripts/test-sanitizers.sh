#!/usr/bin/env bash
# The sanitizer part of the test suite (called by scripts/test.sh):
# 1. the `asan` preset (GCC, Debug, -Werror, AddressSanitizer + UndefinedBehaviorSanitizer) runs
#    the unit, stability, GPU and integration tests; any sanitizer report fails the test;
# 2. a ThreadSanitizer build of the session and integration tests (scheduler, registry, volume
#    store, the network server, the load client) runs them;
# 3. the `fuzz` preset (clang-14, ASan + UBSan + libFuzzer) replays the inputs that once crashed a
#    parser and fuzzes every target for PENUMBRA_FUZZ_SECONDS (default 20) from a fixed seed.
# The stability suite's second and third runs (`tricubic.`, `preintegration.`) change only the
# shaders, which run in the GL driver, not in the instrumented code: they stay in the release run.
# The browser, CLI and deploy tests stay in the release run: they drive the binary from outside
# and would only repeat, far slower, what the tests below already cover under the sanitizers; so
# do the `arch` checks, which read the sources, not the build.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
asan_common="abort_on_error=0:detect_stack_use_after_return=1:strict_init_order=1"

cmake --preset asan
cmake --build --preset asan
# Tests that never open a GL context check for leaks too. Those that do load Mesa's driver, which
# is unloaded at exit, so LeakSanitizer cannot name the frames of the driver's own allocations:
# there leaks are not checked, every other ASan and UBSan error still is.
ASAN_OPTIONS="$asan_common:detect_leaks=1" \
LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp:fast_unwind_on_malloc=0" \
    ctest --test-dir build/asan --output-on-failure --parallel "$jobs" --timeout 900 \
        -L unit -E '^(browser|cli|deploy|arch|tricubic|preintegration)\.'
ASAN_OPTIONS="$asan_common:detect_leaks=0" \
    ctest --test-dir build/asan --output-on-failure --parallel "$jobs" --timeout 900 \
        -LE unit -E '^(browser|cli|deploy|arch|tricubic|preintegration)\.'

cmake -S . -B build/tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPENUMBRA_SANITIZE=thread
cmake --build build/tsan --target session_test integration_test load_client_test
TSAN_OPTIONS="halt_on_error=1:suppressions=$PWD/tests/sanitizers/tsan.supp" \
    build/tsan/tests/unit/session/session_test
TSAN_OPTIONS="halt_on_error=1:suppressions=$PWD/tests/sanitizers/tsan.supp" \
    build/tsan/tests/integration/integration_test
TSAN_OPTIONS="halt_on_error=1:suppressions=$PWD/tests/sanitizers/tsan.supp" \
    build/tsan/tests/integration/load_client_test

cmake --preset fuzz -DPENUMBRA_FUZZ_SECONDS="${PENUMBRA_FUZZ_SECONDS:-20}"
cmake --build --preset fuzz --target fuzz_targets
ctest --preset fuzz --parallel "$jobs"
