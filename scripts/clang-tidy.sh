#!/usr/bin/env bash
# Runs clang-tidy (Debian's clang-tidy-14) with the checks of .clang-tidy over the server's
# sources, or over the files given, and fails on any finding. Needs the release build's
# compile_commands.json (cmake --preset release). CTest's arch.tidy runs it over the modules a
# stranger's bytes reach; the whole server takes about 6.5 CPU-minutes, so that stays a check to
# run on the files one changes. -j N runs N files at once (default: the number of cores); -p DIR
# reads DIR's compile database instead of build/release's.
set -euo pipefail
cd "$(dirname "$0")/.."
runner=$(command -v run-clang-tidy-14 || command -v run-clang-tidy || true)
tidy=$(command -v clang-tidy-14 || command -v clang-tidy || true)
if [ -z "$runner" ] || [ -z "$tidy" ]; then
    echo "clang-tidy: clang-tidy-14 is not installed (scripts/install-deps.sh installs it)" >&2
    exit 2
fi
jobs=$(nproc)
build=build/release
while [ "${1:-}" = "-j" ] || [ "${1:-}" = "-p" ]; do
    if [ "$1" = "-j" ]; then jobs=$2; else build=$2; fi
    shift 2
done
if [ ! -f "$build/compile_commands.json" ]; then
    echo "clang-tidy: no $build/compile_commands.json: run cmake --preset release" >&2
    exit 2
fi
if [ $# -eq 0 ]; then
    set -- "$(pwd)/server/"
fi
# run-clang-tidy takes regular expressions matched against the compile database's file names.
"$runner" -clang-tidy-binary "$tidy" -p "$build" -j "$jobs" -quiet "$@"
