#!/usr/bin/env bash
# Every figure a GPU host should give, in one go, from the portable bundle (scripts/bundle.sh) on
# a bare x86-64 host: nothing but bash, coreutils, awk, sed, grep and tar is used, no Python.
#   bash gpu-bench.sh BUNDLE OUTDIR [VOLUME] [--quick]
# BUNDLE: the bundle's archive or its unpacked `penumbra` folder. VOLUME: default the bundle's
# share/penumbra/volumes/ch2.nii.gz. --quick: tiny frames and short runs, to prove the script on
# a software rasteriser (tests/deploy/bundle_test.sh runs it so).
# Sets the NVIDIA EGL vendor where the driver has one (its glvnd JSON file, searched for, or one
# written for its libEGL_nvidia.so.0), else leaves the host's (Mesa) and says so. Within
# $PENUMBRA_GPU_BENCH_SECONDS (480) it writes to OUTDIR: host.txt (uname, CPUs, nvidia-smi, the
# EGL vendor), stills/MODE.png and stills/MODE.txt (one converged still per mode, 512x512, the GL
# strings), modes-SIZE[-fragment].{txt,csv} (`bench modes`: every mode with the light buffer
# cached and rebuilt at n = 64/128/256 and R = 256/512, both builders, the light lookups,
# empty-space skipping on and off, cuts; the ray caster as a compute and as a fragment shader),
# load-MODE-N.txt (`penumbra load` on loopback, 512x512 JPEG, N = 1, 4, 16, 64 clients), steps.txt
# (each step's status and seconds), then prints summary.txt: one table of it all.
set -uo pipefail
quick=0
positional=()
for argument in "$@"; do
    case "$argument" in
        --quick) quick=1 ;;
        *) positional+=("$argument") ;;
    esac
done
[ "${#positional[@]}" -ge 2 ] || { echo "usage: gpu-bench.sh BUNDLE OUTDIR [VOLUME] [--quick]" >&2; exit 2; }
bundle="${positional[0]}"
out="${positional[1]}"
mkdir -p "$out/stills"
out="$(cd "$out" && pwd)"
started=$(date +%s)
budget="${PENUMBRA_GPU_BENCH_SECONDS:-480}"
elapsed() { echo $(($(date +%s) - started)); }
note() { echo "gpu-bench [$(elapsed) s]: $*" >&2; }

if [ -f "$bundle" ]; then
    note "unpacking $bundle"
    tar -C "$out" -xJf "$bundle" || exit 1
    bundle="$out/penumbra"
fi
penumbra="$bundle/bin/penumbra"
[ -x "$penumbra" ] || { echo "gpu-bench: no $penumbra" >&2; exit 1; }
# The bundle's libstdc++ is GCC 12's (Debian 12) and needs glibc 2.36. Where the host has a
# libstdc++ of GCC 12 or newer, that one is used instead (moved aside here): it runs on the host's
# glibc (Ubuntu 22.04 has 2.35, which everything else in the bundle runs on), and a newer host's
# own libraries (its Mesa's LLVM) may need it. PENUMBRA_HOST_LIBSTDCXX=no keeps the bundle's.
glibc=$(getconf GNU_LIBC_VERSION | awk '{print $2}')
host_cxx=$( (ldconfig -p 2>/dev/null | awk '/libstdc\+\+\.so\.6 .*x86-64/ {print $NF; exit}') || true)
if [ -e "$bundle/lib/libstdc++.so.6" ] && [ "${PENUMBRA_HOST_LIBSTDCXX:-auto}" != no ]; then
    if [ -n "$host_cxx" ] && grep -qa GLIBCXX_3.4.30 "$host_cxx"; then
        mkdir -p "$bundle/lib/unused"
        mv "$bundle/lib/libstdc++.so.6" "$bundle/lib/libgcc_s.so.1" "$bundle/lib/unused/"
        note "the host's $host_cxx instead of the bundle's libstdc++"
    elif [ "$(printf '%s\n' 2.36 "$glibc" | sort -V | head -n 1)" != 2.36 ]; then
        echo "gpu-bench: glibc $glibc is older than the 2.36 the bundle's libstdc++ needs, and the" \
             "host has no libstdc++ of GCC 12 or newer to use instead" >&2
        exit 1
    fi
fi
volume="${positional[2]:-$bundle/share/penumbra/volumes/ch2.nii.gz}"
[ -f "$volume" ] || { echo "gpu-bench: no volume $volume" >&2; exit 1; }

if [ "$quick" = 1 ]; then
    size=64 large=96 slices=16,32 resolutions=32,64 repeat=1 clients_list="1 2" load_seconds=2
    # llvmpipe stops a fragment shader after 65535 loop iterations, which the light-buffer and
    # reference rays pass; a GPU runs every mode there.
    fragment_modes=(--modes dvr,phong)
else
    size=512 large=1024 slices=64,128,256 resolutions=256,512 repeat=5 clients_list="1 4 16 64"
    load_seconds=8
    fragment_modes=()
fi

# The NVIDIA EGL vendor: the driver's glvnd JSON file where it installed one, else one written
# here naming its libEGL_nvidia.so.0. Without either the host's default vendor (Mesa) draws.
find_nvidia_vendor() {
    local folder file library
    for folder in /usr/local/nvidia/share/glvnd/egl_vendor.d /usr/share/glvnd/egl_vendor.d \
            /etc/glvnd/egl_vendor.d /usr/local/share/glvnd/egl_vendor.d; do
        for file in "$folder"/*nvidia*.json; do
            if [ -f "$file" ]; then
                echo "$file"
                return
            fi
        done
    done
    library=$( (ldconfig -p 2>/dev/null | awk '/libEGL_nvidia\.so\.0/ {print $NF; exit}') || true)
    if [ -z "$library" ]; then
        library=$(find /usr/local/nvidia /usr/lib /usr/lib64 /usr/local/lib -name 'libEGL_nvidia.so.0' \
            2>/dev/null | head -n 1)
    fi
    if [ -n "$library" ]; then
        printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s"}}\n' "$library" \
            > "$out/10_nvidia.json"
        echo "$out/10_nvidia.json"
    fi
}
vendor=$(find_nvidia_vendor)
if [ -n "$vendor" ]; then
    export __EGL_VENDOR_LIBRARY_FILENAMES="$vendor"
    vendor_text="NVIDIA: $vendor"
else
    vendor_text="no NVIDIA EGL vendor found: the host's default (Mesa)"
fi
note "EGL vendor: $vendor_text"
{
    echo "date:     $(date -u +%FT%TZ)"
    echo "host:     $(uname -a)"
    echo "cpus:     $(nproc)"
    echo "egl:      $vendor_text"
    echo "glibc:    $glibc, libstdc++ $([ -e "$bundle/lib/libstdc++.so.6" ] && echo "the bundle's" || echo "the host's ($host_cxx)")"
    echo "bundle:   $(head -n 1 "$bundle/BUNDLE.txt" 2>/dev/null)"
    echo "volume:   $volume"
    if command -v nvidia-smi > /dev/null; then
        nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv
        nvidia-smi
    else
        echo "nvidia-smi: not found"
    fi
} > "$out/host.txt" 2>&1

# Runs one step under what is left of the budget: its output to FILE, its status to steps.txt.
: > "$out/steps.txt"
step() {
    local name="$1" file="$2" left status begin
    shift 2
    left=$((budget - $(elapsed)))
    if [ "$left" -le 5 ]; then
        echo "$name skipped 0 (the budget of ${budget} s was spent)" >> "$out/steps.txt"
        return 1
    fi
    note "$name"
    begin=$(date +%s)
    timeout --kill-after=5 "$left" "$@" > "$file" 2>&1
    status=$?
    echo "$name $([ "$status" = 0 ] && echo ok || echo "failed($status)") $(($(date +%s) - begin))" \
        >> "$out/steps.txt"
    return "$status"
}

modes=$("$penumbra" render --list-modes 2>/dev/null)
for mode in $modes; do
    step "still-$mode" "$out/stills/$mode.txt" "$penumbra" render --volume "$volume" --mode "$mode" \
        --size "${size}x${size}" --out "$out/stills/$mode.png"
done
for side in "$size" "$large"; do
    step "modes-$side" "$out/modes-$side.txt" "$penumbra" bench modes --volume "$volume" \
        --size "${side}x${side}" --slices-list "$slices" --light-res-list "$resolutions" \
        --repeat "$repeat" --csv "$out/modes-$side.csv"
done
step "modes-$size-fragment" "$out/modes-$size-fragment.txt" "$penumbra" bench modes \
    --volume "$volume" --size "${size}x${size}" --slices-list "$slices" \
    --light-res-list "$resolutions" --repeat "$repeat" --stage fragment "${fragment_modes[@]}" \
    --csv "$out/modes-$size-fragment.csv"

# The server's limits opened for the benchmark: many sessions from one address, requests as
# fast as frames come (two per frame).
serve_log="$out/serve.log"
"$penumbra" serve --port 0 --data "$(dirname "$volume")" --no-quality-measure \
    --max-sessions 256 --max-sessions-per-client 256 --max-connections-per-client 256 \
    --max-sessions-per-connection 4 --max-requests-per-second 100000 \
    --encode-threads "$(( $(nproc) > 4 ? $(nproc) / 2 : 2 ))" > "$serve_log" 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null; wait "$server" 2>/dev/null' EXIT
port=""
for _ in $(seq 1 300); do
    port=$(sed -n 's|^serving: *http://[^:]*:\([0-9]*\)/.*|\1|p' "$serve_log" 2>/dev/null)
    [ -n "$port" ] && break
    kill -0 "$server" 2>/dev/null || break
    sleep 0.2
done
if [ -n "$port" ]; then
    for mode in dvr sbrc; do
        for clients in $clients_list; do
            step "load-$mode-$clients" "$out/load-$mode-$clients.txt" "$penumbra" load \
                --port "$port" --volume "$(basename "$volume")" --clients "$clients" \
                --seconds "$load_seconds" --mode "$mode" --size "$size" --encoding jpeg
        done
    done
else
    echo "serve failed 0" >> "$out/steps.txt"
fi
kill "$server" 2>/dev/null
wait "$server" 2>/dev/null
trap - EXIT

# The summary: plain awk over what the steps wrote.
{
    echo "penumbra gpu-bench, $(date -u +%FT%TZ), $(elapsed) s of ${budget}"
    echo "egl:   $vendor_text"
    grep -m 1 "^gl:" "$out/stills/sbrc.txt" 2>/dev/null || echo "gl:    (no still rendered)"
    grep -m 1 -E "^(GPU|NVIDIA|name)" "$out/host.txt" 2>/dev/null | head -n 1
    echo
    echo "frame time, ms (GPU timer where it works, else wall); light-buffer modes at the largest n and R"
    printf "  %-12s %10s %10s %12s %12s %10s\n" mode "$size² comp" "$size² frag" "frag/comp" "$large² comp" "rebuild"
    for mode in $modes; do
        awk -F, -v mode="$mode" -v size="$size" -v large="$large" '
            function ms(w, g) { return g != "" ? g + 0 : w + 0 }
            FNR == 1 { file++; next }
            $1 != mode { next }
            $2 == "frame" || ($2 == "cached" && $4 >= best_n[file] && $5 >= best_r[file]) {
                best_n[file] = $4; best_r[file] = $5; t[file] = ms($9, $10) }
            $2 == "rebuild" && file == 1 && $4 >= rn && $5 >= rr { rn = $4; rr = $5; rebuild = ms($9, $10) }
            END {
                printf "  %-12s %10s %10s %12s %12s %10s\n", mode,
                    (1 in t) ? sprintf("%.3f", t[1]) : "-", (3 in t) ? sprintf("%.3f", t[3]) : "-",
                    (1 in t && 3 in t && t[1] > 0) ? sprintf("%.2f", t[3] / t[1]) : "-",
                    (2 in t) ? sprintf("%.3f", t[2]) : "-", rebuild != "" ? sprintf("%.3f", rebuild) : "-" }' \
            "$out/modes-$size.csv" "$out/modes-$large.csv" "$out/modes-$size-fragment.csv" 2>/dev/null
    done
    echo
    echo "light-buffer builders at $size² (the light_buffer pass alone, ms) and half_angle / sbrc cached"
    printf "  %-10s %10s %12s %10s %12s\n" "n,R" per_slice multi_slice per/multi half/sbrc
    awk -F, '
        function ms(w, g) { return g != "" ? g + 0 : w + 0 }
        NR == 1 { next }
        $1 == "sbrc" && $2 == "light_buffer_pass" { pass[$4 "," $5, $3] = ms($9, $10); keys[$4 "," $5] = 1 }
        $1 == "sbrc" && $2 == "cached" { sbrc[$4 "," $5] = ms($9, $10) }
        $1 == "half_angle" { half[$4 "," $5] = ms($9, $10) }
        END {
            for (k in keys) {
                p = pass[k, "per_slice"]; m = pass[k, "multi_slice"]
                ratio = m > 0 ? sprintf("%.1f", p / m) : "-"
                slicing = (k in half) && sbrc[k] > 0 ? sprintf("%.1f", half[k] / sbrc[k]) : "-"
                printf "  %-10s %10.3f %12.3f %10s %12s\n", k, p, m, ratio, slicing } }' \
        "$out/modes-$size.csv" 2>/dev/null | sort -t, -k1,1n -k2,2n
    echo
    echo "penumbra load on loopback, ${size}² JPEG: latency request -> frame (ms), frames/s per client"
    printf "  %-6s %8s %10s %10s %14s %8s\n" mode clients p50 p99 "frames/s each" errors
    for mode in dvr sbrc; do
        for clients in $clients_list; do
            awk -v mode="$mode" -v clients="$clients" '
                /^frames:/ { gsub(/\(/, "", $3); fps = $3; errors = $NF }
                /^latency \(client\)/ { p50 = $3; p99 = $5 }
                END {
                    if (fps == "") { printf "  %-6s %8d %10s\n", mode, clients, "(no run)"; exit }
                    printf "  %-6s %8d %10s %10s %14.1f %8s\n", mode, clients, p50, p99, fps / clients, errors }' \
                "$out/load-$mode-$clients.txt" 2>/dev/null || printf "  %-6s %8d %10s\n" "$mode" "$clients" "(no run)"
        done
    done
    echo
    echo "steps (status, seconds):"
    sed 's/^/  /' "$out/steps.txt"
} > "$out/summary.txt"
cat "$out/summary.txt"
! grep -q -E " (failed|skipped)" "$out/steps.txt"
