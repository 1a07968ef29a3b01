#!/usr/bin/env bash
# Fuzzes for longer than CTest does: builds the fuzz preset (clang-14, ASan + UBSan, libFuzzer),
# then runs each target for SECONDS (default 600), JOBS at a time (default 1), growing the corpus
# in build/fuzz/tests/fuzz/corpus/<target>. A crashing input is written to
# build/fuzz/tests/fuzz/artifacts/<target>/: fix its cause, then keep the input in
# tests/fuzz/regressions/<target>/ so that CTest replays it.
#
#   scripts/fuzz.sh [-t SECONDS] [-j JOBS] [TARGET ...]      (targets: tests/fuzz/fuzz_*.cpp)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=600
jobs=1
while getopts "t:j:h" option; do
    case "$option" in
        t) seconds="$OPTARG" ;;
        j) jobs="$OPTARG" ;;
        *) sed -n '2,9p' "$0"; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    for source in tests/fuzz/fuzz_*.cpp; do
        targets+=("$(basename "$source" .cpp)")
    done
fi

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz --target "${targets[@]}"

out=build/fuzz/tests/fuzz
run() {
    local target=$1
    local seeds=(tests/fuzz/seeds/"${target#fuzz_}")
    case "$target" in
        fuzz_protocol_request) seeds=(proto/examples/v1/valid proto/examples/v1/invalid) ;;
        fuzz_protocol_patch) seeds=(tests/fuzz/seeds/patch) ;;
    esac
    local regressions=tests/fuzz/regressions/$target
    [ -d "$regressions" ] && seeds+=("$regressions")
    mkdir -p "$out/corpus/$target" "$out/artifacts/$target"
    local status=0
    "$out/$target" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=25 -print_final_stats=1 \
        -artifact_prefix="$out/artifacts/$target/" "$out/corpus/$target" "${seeds[@]}" \
        >"$out/artifacts/$target.log" 2>&1 || status=$?
    local execs
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/artifacts/$target.log")
    echo "$target: ${execs:-?} executions in ${seconds} s, exit $status (log: $out/artifacts/$target.log)"
    return $status
}

failed=0
running=0
for target in "${targets[@]}"; do
    run "$target" &
    running=$((running + 1))
    if [ "$running" -ge "$jobs" ]; then
        wait -n || failed=1
        running=$((running - 1))
    fi
done
while [ "$running" -gt 0 ]; do
    wait -n || failed=1
    running=$((running - 1))
done
exit $failed
