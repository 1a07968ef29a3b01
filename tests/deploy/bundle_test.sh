#!/usr/bin/env bash
# The portable bundle (scripts/bundle.sh) in a clean root filesystem: Debian 12's debootstrap
# minbase (scripts/debian-base.sh) with only Mesa's EGL vendor library and its DRI driver added
# (no libglvnd, no development package, none of Penumbra's libraries), entered with chroot. Inside:
# ldd finds every library of the binary and of libglvnd's loaders in the bundle, `render` draws a
# frame on llvmpipe through the bundle's libEGL, `serve` answers `load` (both the bundle's) over
# WebSocket, and `bench accuracy` writes its images without image comparison.
# usage: bundle_test.sh SOURCE_DIR WORK_DIR VOLUME
# Needs root (chroot, mounts) and the Debian mirror (the root and Mesa's packages, made once and
# kept in $PENUMBRA_DEPLOY_CACHE).
set -euo pipefail
source_dir="$1"
work="$2"
volume="$3"
started=$(date +%s)
step() { echo "[$(($(date +%s) - started)) s] $*"; }
[ "$(id -u)" = 0 ] || { echo "bundle test: needs root (chroot)" >&2; exit 1; }

root="$work/root"
# The rest runs in a mount namespace of its own: the root's /proc and /dev go with it however it
# ends (a CTest timeout kills it), so nothing can ever delete through them.
# (The marker is the host's mount namespace, so one inherited from elsewhere cannot skip this.)
if [ "${PENUMBRA_BUNDLE_TEST_HOST_NAMESPACE:-}" = "" ] \
        || [ "$PENUMBRA_BUNDLE_TEST_HOST_NAMESPACE" = "$(readlink /proc/self/ns/mnt)" ]; then
    exec env PENUMBRA_BUNDLE_TEST_HOST_NAMESPACE="$(readlink /proc/self/ns/mnt)" \
        unshare --mount --propagation private bash "$0" "$@"
fi
server=""
stop_server() {
    if [ -n "$server" ]; then
        kill "$server" 2>/dev/null || true
        for _ in $(seq 1 50); do
            kill -0 "$server" 2>/dev/null || break
            sleep 0.2
        done
        kill -9 "$server" 2>/dev/null || true
        wait "$server" 2>/dev/null || true
        server=""
    fi
}
trap stop_server EXIT
if [ -d "$work" ] && findmnt -rn -o TARGET | awk -v w="$work/" 'index($0, w) == 1 {found = 1} END {exit !found}'; then
    echo "bundle test: something is mounted under $work; unmount it first" >&2
    exit 1
fi
rm -rf --one-file-system "$work"
mkdir -p "$work"

step "the bundle"
bash "$source_dir/scripts/bundle.sh" "$work/penumbra.tar.xz" > "$work/bundle.log" 2>&1 \
    || { tail -n 30 "$work/bundle.log" >&2; exit 1; }
tail -n 1 "$work/bundle.log"

step "the clean root: Debian 12 minbase with Mesa's EGL vendor library"
cache="${PENUMBRA_DEPLOY_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/penumbra/deploy}"
mesa_root="$cache/debian-12-minbase-mesa-egl.tar"
if [ ! -s "$mesa_root" ]; then
    base=$(bash "$source_dir/scripts/debian-base.sh" "$work")
    mkdir -p "$root"
    tar -C "$root" -xf "$base"
    cp /etc/resolv.conf "$root/etc/resolv.conf"
    chroot "$root" apt-get update -qq > "$work/apt.log" 2>&1
    # Mesa's EGL vendor library and the driver llvmpipe lives in; libglvnd (libegl1) is not
    # installed: the bundle's loaders must do.
    DEBIAN_FRONTEND=noninteractive chroot "$root" apt-get install -y -qq --no-install-recommends \
        libegl-mesa0 libgl1-mesa-dri >> "$work/apt.log" 2>&1 \
        || { tail -n 20 "$work/apt.log" >&2; exit 1; }
    chroot "$root" apt-get clean
    rm -rf "$root"/var/lib/apt/lists/*
    tar -C "$root" -cf "$mesa_root.tmp" .
    mv "$mesa_root.tmp" "$mesa_root"
    rm -rf --one-file-system "$root"
fi
mkdir -p "$root"
tar -C "$root" -xf "$mesa_root"
for package in libegl1 libopengl0 libglvnd0 libepoxy0 libdcmtk17 libturbojpeg0; do
    status=$(chroot "$root" dpkg-query -W -f '${Status}' "$package" 2>/dev/null || true)
    if grep -q installed <<< "$status"; then
        echo "bundle test: the clean root has $package" >&2
        exit 1
    fi
done
# A /proc of its own and a /dev with only what the binary and Mesa open (llvmpipe needs no device).
mount -t proc proc "$root/proc"
mount -t tmpfs -o mode=755,size=1m tmpfs "$root/dev"
for node in "null 1 3" "zero 1 5" "random 1 8" "urandom 1 9"; do
    set -- $node
    mknod -m 666 "$root/dev/$1" c "$2" "$3"
done
tar -C "$root/opt" -xJf "$work/penumbra.tar.xz"
mkdir -p "$root/data"
cp "$volume" "$root/data/"
penumbra=/opt/penumbra/bin/penumbra
inside() { chroot "$root" "$@"; }

step "ldd inside: every library in the bundle but glibc's"
for file in "$penumbra" /opt/penumbra/lib/libEGL.so.1 /opt/penumbra/lib/libOpenGL.so.0; do
    inside ldd "$file" > "$work/ldd.txt"
    if grep -q "not found" "$work/ldd.txt"; then
        echo "bundle test: $file:" >&2
        cat "$work/ldd.txt" >&2
        exit 1
    fi
    outside=$(awk '/=> \// && $3 !~ "^/opt/penumbra/" {print $1}' "$work/ldd.txt" \
        | grep -Ev '^(libc|libm|libdl|libpthread|librt)\.so' || true)
    if [ -n "$outside" ]; then
        echo "bundle test: $file finds outside the bundle: $outside" >&2
        exit 1
    fi
done
echo "ldd:      $(grep -c "=> /opt/penumbra/" "$work/ldd.txt" || true) of libOpenGL's and $(inside ldd "$penumbra" | grep -c "=> /opt/penumbra/") of penumbra's libraries from the bundle"

step "render a frame"
inside "$penumbra" render --volume "/data/$(basename "$volume")" --mode sbrc --size 64x64 \
    --out /tmp/frame.png > "$work/render.log" 2>&1 || { cat "$work/render.log" >&2; exit 1; }
grep -E "^(gl|renderer|device):" "$work/render.log" || true
grep -qi "llvmpipe" "$work/render.log" \
    || { echo "bundle test: render does not say it drew on llvmpipe" >&2; cat "$work/render.log" >&2; exit 1; }
test -s "$root/tmp/frame.png"
cp "$root/tmp/frame.png" "$work/frame.png"

step "serve, and load over WebSocket"
# `load` asks for frames as fast as they come, two requests each: the per-connection rate limit
# would answer some with rate_limited on a fast machine.
# chroot itself in the background (not a function's subshell), so that $! is the server.
chroot "$root" "$penumbra" serve --port 0 --data /data --no-quality-measure \
    --max-requests-per-second 10000 > "$work/serve.log" 2>&1 &
server=$!
for _ in $(seq 1 300); do
    grep -q "^serving:" "$work/serve.log" && break
    kill -0 "$server" 2>/dev/null || { cat "$work/serve.log" >&2; exit 1; }
    sleep 0.2
done
port=$(sed -n 's|^serving: *http://[^:]*:\([0-9]*\)/.*|\1|p' "$work/serve.log")
[ -n "$port" ] || { cat "$work/serve.log" >&2; exit 1; }
inside "$penumbra" load --port "$port" --volume "$(basename "$volume")" --clients 2 --seconds 3 \
    --size 64 > "$work/load.log" 2>&1 || { cat "$work/load.log" "$work/serve.log" >&2; exit 1; }
cat "$work/load.log"
/usr/bin/python3 - "$work/load.log" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
frames = re.search(r"^frames: +(\d+) ", text, re.M)
errors = re.search(r"errors (\d+)", text)
if not frames or int(frames.group(1)) == 0:
    sys.exit("bundle test: load received no frames")
if not errors or int(errors.group(1)) != 0:
    sys.exit("bundle test: load saw errors")
PY
stop_server
grep -q "session: closed" "$work/serve.log"

step "bench accuracy writes its images"
inside "$penumbra" bench accuracy --volumes "/data/$(basename "$volume")" --modes dvr,sbrc \
    --size 32x32 --sample-distances 0.0078125 --slices-list 32 --light-res-list 32 --repeat 1 \
    --images /tmp/accuracy > "$work/accuracy.log" 2>&1 || { cat "$work/accuracy.log" >&2; exit 1; }
grep -q "without OpenImageIO" "$work/accuracy.log"
images=$(find "$root/tmp/accuracy" -name '*.png' | wc -l)
[ "$images" -eq 3 ] || { echo "bundle test: $images images from bench accuracy, not 3" >&2; exit 1; }

step "gpu-bench.sh --quick, as on a bare GPU host, on the bundle's own volume"
inside bash /opt/penumbra/gpu-bench.sh /opt/penumbra /tmp/gpu-bench --quick \
    --tar /tmp/gpu-bench.tgz > "$work/gpu-bench.log" 2>&1 || { cat "$work/gpu-bench.log" >&2; exit 1; }
tar -tzf "$root/tmp/gpu-bench.tgz" > "$work/gpu-bench-tar.txt"
grep -q "summary.txt" "$work/gpu-bench-tar.txt" \
    || { echo "bundle test: gpu-bench --tar packed no summary" >&2; exit 1; }
cp -r "$root/tmp/gpu-bench" "$work/gpu-bench"
cat "$work/gpu-bench/summary.txt"
for file in host.txt stills/sbrc.png stills/reference.png modes-64.csv modes-96.csv \
        modes-64-fragment.csv load-sbrc-2.txt; do
    test -s "$work/gpu-bench/$file" || { echo "bundle test: gpu-bench wrote no $file" >&2; exit 1; }
done
grep -Eq "^  sbrc +[0-9.]+ " "$work/gpu-bench/summary.txt" \
    || { echo "bundle test: gpu-bench's summary has no sbrc time" >&2; exit 1; }
step "bundle test passed: $(tail -n 1 "$work/bundle.log" | sed 's/^bundle: //')"
