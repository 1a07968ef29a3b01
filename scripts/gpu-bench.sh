#!/usr/bin/env bash
# Every figure a GPU host should give, in one go, from the portable bundle (scripts/bundle.sh) on
# a bare x86-64 host: nothing but bash, coreutils, awk, sed, grep and tar is used, no Python.
#   bash gpu-bench.sh BUNDLE OUTDIR [VOLUME] [--quick] [--tar FILE.tgz]
# BUNDLE: the bundle's archive (.tar.xz or .tar.gz, unpacked to a temporary folder) or its
# unpacked `penumbra` folder, which is not changed. VOLUME: default the bundle's
# share/penumbra/volumes/ch2.nii.gz. --quick: tiny frames and short runs, to prove the script on a
# software rasteriser (tests/deploy/bundle_test.sh runs it so). --tar: OUTDIR packed into one file
# at the end, however the run ends (a host that returns few files).
# Sets the NVIDIA EGL vendor where the driver has one (a glvnd JSON file naming its
# libEGL_nvidia, written here with the library's absolute path), else leaves the host's (Mesa) and
# says so; a first 64x64 frame stops the run early where a GPU is present but llvmpipe draws.
# Within $PENUMBRA_GPU_BENCH_SECONDS (480), each step capped so that the later ones keep their
# turn, it writes to OUTDIR: host.txt (uname, CPUs, nvidia-smi, the EGL vendor, glibc),
# stills/MODE.png and stills/MODE.txt (one converged still per mode, 512x512, the GL strings),
# modes-SIZE.{txt,csv} (`bench modes`: every mode with the light buffer cached and rebuilt at
# n = 64/128/256 and R = 256/512, both builders, the light lookups, empty-space skipping on and off,
# cuts) at 512 and 1024, load-MODE-N.txt (`penumbra load` on loopback, 512x512 JPEG, N = 1, 4, 16,
# 64 clients), modes-512-fragment.{txt,csv} (dvr, phong and sbrc with the ray caster as a fragment
# shader), steps.txt (each step's status and seconds), and summary.txt: one table of it all.
set -uo pipefail
quick=0
tar_file=""
positional=()
while [ $# -gt 0 ]; do
    case "$1" in
        --quick) quick=1 ;;
        --tar) tar_file="$2"; shift ;;
        *) positional+=("$1") ;;
    esac
    shift
done
[ "${#positional[@]}" -ge 2 ] || { echo "usage: gpu-bench.sh BUNDLE OUTDIR [VOLUME] [--quick] [--tar FILE.tgz]" >&2; exit 2; }
bundle="${positional[0]}"
out="${positional[1]}"
mkdir -p "$out/stills" || exit 1
out="$(cd "$out" && pwd)"
started=$(date +%s)
budget="${PENUMBRA_GPU_BENCH_SECONDS:-480}"
elapsed() { echo $(($(date +%s) - started)); }
note() { echo "gpu-bench [$(elapsed) s]: $*" | tee -a "$out/steps.log" >&2; }
scratch=$(mktemp -d)
server=""
finish() {
    if [ -n "$server" ]; then
        kill "$server" 2>/dev/null
        for _ in $(seq 1 50); do kill -0 "$server" 2>/dev/null || break; sleep 0.2; done
        kill -9 "$server" 2>/dev/null
        server=""
    fi
    if [ -n "$tar_file" ]; then
        tar -czf "$tar_file" -C "$out" . 2>/dev/null
    fi
    rm -rf --one-file-system "$scratch"
}
trap finish EXIT
: > "$out/steps.txt"
{
    echo "date:     $(date -u +%FT%TZ)"
    echo "host:     $(uname -a)"
    echo "cpus:     $(nproc)"
} > "$out/host.txt"

if [ -f "$bundle" ]; then
    note "unpacking $bundle"
    case "$bundle" in
        *.gz) tar -C "$scratch" -xzf "$bundle" ;;
        *) tar -C "$scratch" -xJf "$bundle" ;;
    esac || { echo "gpu-bench: cannot unpack $bundle" | tee -a "$out/steps.txt" >&2; exit 1; }
    bundle="$scratch/penumbra"
fi
penumbra="$bundle/bin/penumbra"
[ -x "$penumbra" ] || { echo "gpu-bench: no $penumbra" | tee -a "$out/steps.txt" >&2; exit 1; }
volume="${positional[2]:-$bundle/share/penumbra/volumes/ch2.nii.gz}"
[ -f "$volume" ] || { echo "gpu-bench: no volume $volume" | tee -a "$out/steps.txt" >&2; exit 1; }

if [ "$quick" = 1 ]; then
    size=64 large=96 slices=16,32 resolutions=32,64 repeat=1 clients_list="1 2" load_seconds=2
    # llvmpipe stops a fragment shader after 65535 loop iterations, which the light-buffer rays
    # pass; dvr and phong show the two stages side by side there.
    fragment=(--modes dvr,phong --slices-list 16 --light-res-list 32)
    cap_still=60 cap_modes=120 cap_load=30 cap_fragment=60
else
    size=512 large=1024 slices=64,128,256 resolutions=256,512 repeat=5 clients_list="1 4 16 64"
    load_seconds=8
    fragment=(--modes dvr,phong,sbrc --slices-list 128 --light-res-list 256)
    cap_still=40 cap_modes=150 cap_load=25 cap_fragment=90
fi

# Libraries of the host put before the bundle's (RUNPATH lets LD_LIBRARY_PATH do that): links in
# a private folder, so the bundle itself is never changed.
host_first="$scratch/host-first"
mkdir -p "$host_first"
prepend_library_path() { export LD_LIBRARY_PATH="$1${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"; }
# Where a library of the host is, by the loader's cache (x86-64 entries) or the usual folders.
host_library() {
    local pattern="$1" found
    found=$( (ldconfig -p 2>/dev/null || /sbin/ldconfig -p 2>/dev/null) \
        | awk -v p="$pattern" 'index($1, p) == 1 && /x86-64/ {print $NF; exit}')
    if [ -z "$found" ]; then
        found=$(find /usr/local/nvidia/lib64 /usr/lib/x86_64-linux-gnu /usr/lib64 /lib64 /usr/lib \
            /usr/local/lib -maxdepth 1 -name "$pattern*" 2>/dev/null | sort | head -n 1)
    fi
    echo "$found"
}

# The bundle's libstdc++ is GCC 12's (Debian 12) and needs glibc 2.36. Where the host has a
# libstdc++ of GCC 12 or newer, that one is used instead: it runs on the host's glibc (Ubuntu
# 22.04 has 2.35, which everything else in the bundle runs on), and the host's own libraries
# (its Mesa's LLVM) may need it. PENUMBRA_HOST_LIBSTDCXX=no keeps the bundle's.
glibc=$(getconf GNU_LIBC_VERSION 2>/dev/null | awk '{print $2}')
host_cxx=$(host_library libstdc++.so.6)
cxx_text="the bundle's"
if [ "${PENUMBRA_HOST_LIBSTDCXX:-auto}" != no ] && [ -n "$host_cxx" ] \
        && grep -qa GLIBCXX_3.4.30 "$host_cxx"; then
    ln -sf "$host_cxx" "$host_first/libstdc++.so.6"
    host_gcc=$(host_library libgcc_s.so.1)
    [ -n "$host_gcc" ] && ln -sf "$host_gcc" "$host_first/libgcc_s.so.1"
    prepend_library_path "$host_first"
    cxx_text="the host's ($host_cxx)"
elif [ -n "$glibc" ] && [ "$(printf '%s\n' 2.36 "$glibc" | sort -V | head -n 1)" != 2.36 ]; then
    echo "gpu-bench: glibc $glibc is older than the 2.36 the bundle's libstdc++ needs, and the host" \
         "has no libstdc++ of GCC 12 or newer to use instead" | tee -a "$out/steps.txt" >&2
    exit 1
fi

# NVIDIA's EGL vendor: its library found (any version suffix), a vendor file written naming it by
# its absolute path, and its folder searched first for the driver libraries it loads in turn.
nvidia_egl=$(host_library libEGL_nvidia.so)
if [ -n "$nvidia_egl" ]; then
    printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s"}}\n' "$nvidia_egl" \
        > "$out/10_nvidia.json"
    export __EGL_VENDOR_LIBRARY_FILENAMES="$out/10_nvidia.json"
    # A folder of the driver's own (the container toolkit's /usr/local/nvidia/lib64) is searched
    # first; a system folder is not, which would put every library of the host before the bundle's.
    case "$(dirname "$nvidia_egl")" in
        /lib | /lib64 | /usr/lib | /usr/lib64 | /lib/x86_64-linux-gnu | /usr/lib/x86_64-linux-gnu) ;;
        *) prepend_library_path "$(dirname "$nvidia_egl")" ;;
    esac
    vendor_text="NVIDIA: $nvidia_egl"
else
    vendor_text="no NVIDIA EGL vendor found: the host's default (Mesa)"
fi
note "EGL vendor: $vendor_text; libstdc++ $cxx_text"
{
    echo "egl:      $vendor_text"
    echo "glibc:    $glibc, libstdc++ $cxx_text"
    echo "bundle:   $(head -n 1 "$bundle/BUNDLE.txt" 2>/dev/null)"
    echo "volume:   $volume"
    if command -v nvidia-smi > /dev/null; then
        timeout 20 nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm \
            --format=csv,noheader
        timeout 20 nvidia-smi
    else
        echo "nvidia-smi: not found"
    fi
} >> "$out/host.txt" 2>&1

# Runs one step for at most CAP seconds and never past the budget: its output to FILE, its
# status to steps.txt.
step() {
    local name="$1" cap="$2" file="$3" left status begin
    shift 3
    left=$((budget - $(elapsed)))
    [ "$cap" -lt "$left" ] && left="$cap"
    if [ "$left" -le 5 ]; then
        echo "$name skipped 0 (the budget of ${budget} s was spent)" >> "$out/steps.txt"
        return 1
    fi
    note "$name (at most $left s)"
    begin=$(date +%s)
    timeout --kill-after=5 "$left" "$@" > "$file" 2>&1
    status=$?
    echo "$name $([ "$status" = 0 ] && echo ok || echo "failed($status)") $(($(date +%s) - begin))" \
        >> "$out/steps.txt"
    return "$status"
}

# A first small frame: where nvidia-smi sees a GPU but llvmpipe draws, the figures would be the
# CPU's; stop before spending the budget on them.
step probe 60 "$out/probe.txt" "$penumbra" render --volume "$volume" --size 64x64 \
    --out "$out/probe.png"
probe_gl=$(grep -m 1 "^gl:" "$out/probe.txt")
note "probe: ${probe_gl:-no frame}"
if [ -z "$probe_gl" ]; then
    echo "gpu-bench: the first frame failed:" >&2
    tail -n 20 "$out/probe.txt" >&2
    exit 1
fi
if grep -q "llvmpipe" <<< "$probe_gl" && grep -qi "nvidia" "$out/host.txt" \
        && [ "$quick" = 0 ] && [ "${PENUMBRA_GPU_BENCH_ALLOW_CPU:-0}" != 1 ]; then
    echo "gpu-bench: a GPU is present but llvmpipe drew the first frame; stopping" \
         "(PENUMBRA_GPU_BENCH_ALLOW_CPU=1 goes on)" | tee -a "$out/steps.txt" >&2
    exit 1
fi

modes=$("$penumbra" render --list-modes 2>/dev/null)
for mode in $modes; do
    step "still-$mode" "$cap_still" "$out/stills/$mode.txt" "$penumbra" render --volume "$volume" \
        --mode "$mode" --size "${size}x${size}" --out "$out/stills/$mode.png"
done
step "modes-$size" "$cap_modes" "$out/modes-$size.txt" "$penumbra" bench modes --volume "$volume" \
    --size "${size}x${size}" --slices-list "$slices" --light-res-list "$resolutions" \
    --repeat "$repeat" --csv "$out/modes-$size.csv"

# The server's limits opened for the benchmark: many sessions and connections from one address,
# requests as fast as frames come (two per frame).
threads=$(nproc)
threads=$((threads > 4 ? threads / 2 : 2))
threads=$((threads > 64 ? 64 : threads))
# start_server LOG [SERVE OPTION...]: sets `server` and `port` (empty when it did not start).
start_server() {
    local log=$1
    shift
    "$penumbra" serve --port 0 --data "$(dirname "$volume")" --no-quality-measure \
        --max-sessions 256 --max-sessions-per-client 256 --max-connections-per-client 256 \
        --max-sessions-per-connection 4 --max-requests-per-second 100000 \
        --encode-threads "$threads" "$@" > "$log" 2>&1 &
    server=$!
    port=""
    for _ in $(seq 1 300); do
        port=$(sed -n 's|^serving: *http://[^:]*:\([0-9]*\)/.*|\1|p' "$log" 2>/dev/null)
        [ -n "$port" ] && break
        kill -0 "$server" 2>/dev/null || break
        sleep 0.2
    done
    [ -n "$port" ] || echo "serve failed 0" >> "$out/steps.txt"
}
stop_server() {
    kill "$server" 2>/dev/null
    for _ in $(seq 1 50); do kill -0 "$server" 2>/dev/null || break; sleep 0.2; done
    kill -9 "$server" 2>/dev/null
    server=""
}
# load_step NAME MODE CLIENTS: one `penumbra load` run against `port`.
load_step() {
    step "$1" "$cap_load" "$out/$1.txt" "$penumbra" load --port "$port" \
        --volume "$(basename "$volume")" --clients "$3" --seconds "$load_seconds" --mode "$2" \
        --size "$size" --encoding jpeg
}

start_server "$out/serve.log"
if [ -n "$port" ]; then
    for mode in dvr sbrc; do
        for clients in $clients_list; do
            load_step "load-$mode-$clients" "$mode" "$clients"
        done
    done
fi
stop_server
# The same load with one frame in flight (the render thread waits for each frame before it
# submits the next): what pipelining the GPU frame path buys.
serial_clients=$(awk '{ print $NF }' <<< "$clients_list")
start_server "$out/serve-serial.log" --frames-in-flight 1
if [ -n "$port" ]; then
    load_step "load-sbrc-$serial_clients-serial" sbrc "$serial_clients"
fi
stop_server

step "modes-$large" "$cap_modes" "$out/modes-$large.txt" "$penumbra" bench modes \
    --volume "$volume" --size "${large}x${large}" --slices-list "$slices" \
    --light-res-list "$resolutions" --repeat "$repeat" --csv "$out/modes-$large.csv"
step "modes-$size-fragment" "$cap_fragment" "$out/modes-$size-fragment.txt" "$penumbra" bench modes \
    --volume "$volume" --size "${size}x${size}" --repeat "$repeat" --stage fragment \
    "${fragment[@]}" --csv "$out/modes-$size-fragment.csv"

# The summary: plain awk (mawk or gawk) over what the steps wrote; a file a step did not write
# (or left empty when its time ran out) leaves its column empty.
present() { for file in "$@"; do [ -s "$file" ] && echo "$file"; done; }
# load_row MODE CLIENTS FILE NOTE: a row of the load table from what `penumbra load` printed.
load_row() {
    # shellcheck disable=SC2046 # the file if present, one word (no spaces in OUTDIR)
    awk -v mode="$1" -v clients="$2" -v note="$4" '
        /^frames:/ { gsub(/\(/, "", $3); fps = $3; errors = $NF }
        /^latency \(client\)/ { p50 = $3; p99 = $5 }
        END {
            if (fps == "") { printf "  %-6s %8d %10s%s\n", mode, clients, "(no run)", note; exit }
            printf "  %-6s %8d %10s %10s %14.1f %8s%s\n", mode, clients, p50, p99, fps / clients, errors, note }' \
        $(present "$3") /dev/null
}
{
    echo "penumbra gpu-bench, $(date -u +%FT%TZ), $(elapsed) s of ${budget}"
    echo "egl:   $vendor_text"
    echo "libstdc++: $cxx_text"
    grep -m 1 "^gl:" "$out/probe.txt" 2>/dev/null || echo "gl:    (no frame)"
    sed -n '/^nvidia-smi: not found/p; /,.*MiB/{p;q}' "$out/host.txt"
    echo
    echo "frame time, ms (GPU timer where it works, else wall); light-buffer modes at the largest n and R"
    printf "  %-12s %10s %10s %12s %12s %10s\n" mode "$size² comp" "$size² frag" "frag/comp" "$large² comp" "rebuild"
    csvs=$(present "$out/modes-$size.csv" "$out/modes-$large.csv" "$out/modes-$size-fragment.csv")
    for mode in $modes; do
        # shellcheck disable=SC2086 # the present files, one word each (no spaces in OUTDIR)
        awk -F, -v mode="$mode" -v compute="$out/modes-$size.csv" -v large="$out/modes-$large.csv" \
                -v fragment="$out/modes-$size-fragment.csv" '
            function ms(w, g) { return g != "" ? g + 0 : w + 0 }
            FNR == 1 || $1 != mode { next }
            { key = FILENAME == compute ? 1 : FILENAME == large ? 2 : FILENAME == fragment ? 3 : 0 }
            $2 == "frame" || ($2 == "cached" && $4 >= best_n[key] && $5 >= best_r[key]) {
                best_n[key] = $4; best_r[key] = $5; t[key] = ms($9, $10) }
            $2 == "rebuild" && key == 1 && $4 >= rn && $5 >= rr { rn = $4; rr = $5; rebuild = ms($9, $10) }
            END {
                c = (1 in t) ? sprintf("%.3f", t[1]) : "-"
                f = (3 in t) ? sprintf("%.3f", t[3]) : "-"
                ratio = (1 in t) && (3 in t) && t[1] > 0 ? sprintf("%.2f", t[3] / t[1]) : "-"
                l = (2 in t) ? sprintf("%.3f", t[2]) : "-"
                r = rebuild != "" ? sprintf("%.3f", rebuild) : "-"
                printf "  %-12s %10s %10s %12s %12s %10s\n", mode, c, f, ratio, l, r }' $csvs /dev/null
    done
    echo
    echo "light-buffer builders at $size² (the light_buffer pass alone, ms) and half_angle / sbrc cached"
    printf "  %-10s %10s %12s %10s %12s\n" "n,R" per_slice multi_slice per/multi half/sbrc
    awk -F, '
        function ms(w, g) { return g != "" ? g + 0 : w + 0 }
        FNR == 1 { next }
        $1 == "sbrc" && $2 == "light_buffer_pass" { pass[$4 "," $5, $3] = ms($9, $10); keys[$4 "," $5] = 1 }
        $1 == "sbrc" && $2 == "cached" { sbrc[$4 "," $5] = ms($9, $10) }
        $1 == "half_angle" { half[$4 "," $5] = ms($9, $10) }
        END {
            for (k in keys) {
                p = pass[k, "per_slice"]; m = pass[k, "multi_slice"]
                ratio = m > 0 ? sprintf("%.1f", p / m) : "-"
                slicing = (k in half) && sbrc[k] > 0 ? sprintf("%.1f", half[k] / sbrc[k]) : "-"
                printf "  %-10s %10.3f %12.3f %10s %12s\n", k, p, m, ratio, slicing } }' \
        $(present "$out/modes-$size.csv") /dev/null | sort -t, -k1,1n -k2,2n
    echo
    echo "penumbra load on loopback, ${size}² JPEG: latency request -> frame (ms), frames/s per client"
    printf "  %-6s %8s %10s %10s %14s %8s\n" mode clients p50 p99 "frames/s each" errors
    for mode in dvr sbrc; do
        for clients in $clients_list; do
            load_row "$mode" "$clients" "$out/load-$mode-$clients.txt" ""
        done
    done
    load_row sbrc "$serial_clients" "$out/load-sbrc-$serial_clients-serial.txt" \
        "  (one frame in flight)"
    echo
    echo "On an H100 or H200 the graphics pipeline (fragment shaders, rasterised slices: half_angle,"
    echo "the per_slice builder) has a fraction of a graphics GPU's units; read those rows so."
    echo
    echo "steps (status, seconds):"
    sed 's/^/  /' "$out/steps.txt"
} > "$out/summary.txt"
cat "$out/summary.txt"
! grep -q -E " (failed|skipped)" "$out/steps.txt"
