#!/usr/bin/env bash
# Makes the portable bundle: one archive holding `penumbra` (built by the bundle preset: no tests,
# no OpenImageIO), its shaders, the web client, its accuracy tables and every shared library it
# needs but the C library and the GL vendor drivers, found through $ORIGIN. It runs on any x86-64
# Linux with glibc 2.36 or newer and an EGL vendor library: Mesa's (llvmpipe, or a GPU) or the
# NVIDIA driver's, which a bare GPU host has even without libglvnd, since the bundle carries
# libglvnd's loaders (libEGL, libOpenGL, libGLdispatch).
#   bash scripts/bundle.sh OUT.tar.xz
# Unpacked, `penumbra/bin/penumbra` runs as it is; `penumbra/BUNDLE.txt` lists what is inside, and
# `penumbra/gpu-bench.sh` (scripts/gpu-bench.sh) measures a GPU host with it.
# Needs what scripts/install-deps.sh installs (its build and deploy groups); builds the web client
# first where it is missing.
set -euo pipefail
unset LD_LIBRARY_PATH  # ldd must see what the loader finds without it
out="$(realpath -m "${1:?usage: bundle.sh OUT.tar.xz}")"
cd "$(dirname "$0")/.."
most_bytes=$((60 * 1024 * 1024))

if [ ! -f client_web/dist/index.html ]; then
    bash scripts/build-web.sh
fi
cmake --preset bundle > /dev/null
cmake --build --preset bundle

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
root="$stage/penumbra"
cmake --install build/bundle --prefix "$root" --strip > /dev/null
mkdir -p "$root/lib"
# The GPU host's one script, and a volume to serve and measure: Colin27's MRI head from Debian's
# mricron-data, with its copyright file.
cp scripts/gpu-bench.sh "$root/gpu-bench.sh"
templates=/usr/share/mricron/templates
if [ -f "$templates/ch2.nii.gz" ]; then
    mkdir -p "$root/share/penumbra/volumes"
    cp "$templates/ch2.nii.gz" "$root/share/penumbra/volumes/"
    cp /usr/share/doc/mricron-data/copyright "$root/share/penumbra/volumes/ch2.copyright"
else
    echo "bundle: no $templates/ch2.nii.gz (mricron-data): the bundle carries no volume" >&2
fi

# The C library (glibc's parts, which must match the host's dynamic loader) and the GL vendor
# drivers (the host's: Mesa or NVIDIA) stay the host's.
host_only='^(ld-linux.*|libc|libm|libdl|libpthread|librt|libresolv|libutil|libanl|libmvec)\.so|^lib(EGL|GLX)_|^libnvidia-|^libcuda'
# What libepoxy opens at run time rather than links: libglvnd's EGL and desktop-GL loaders.
loaders=(libEGL.so.1 libOpenGL.so.0)

copy_closure() {
    local file="$1" library name
    while read -r library; do
        name=$(basename "$library")
        if [[ "$name" =~ $host_only ]] || [ -e "$root/lib/$name" ]; then
            continue
        fi
        # Named by the soname the loader asks for, the file behind any links.
        cp -L "$library" "$root/lib/$name"
        chmod 0644 "$root/lib/$name"
    done < <(ldd "$file" | awk '/=> \// {print $3}')
    if grep -q "not found" <<< "$(ldd "$file")"; then
        echo "bundle: $file needs a library this host lacks:" >&2
        ldd "$file" | grep "not found" >&2
        exit 1
    fi
}

copy_closure "$root/bin/penumbra"
multiarch=$(gcc -print-multiarch)
for loader in "${loaders[@]}"; do
    path="/usr/lib/$multiarch/$loader"
    [ -e "$path" ] || { echo "bundle: $path is missing (libegl1, libopengl0)" >&2; exit 1; }
    cp -L "$path" "$root/lib/$loader"
    copy_closure "$path"
done
strip --strip-unneeded "$root"/lib/*.so*
# Each library finds its neighbours by itself (RUNPATH $ORIGIN), also when it is opened rather than
# linked (libepoxy opening libEGL, libEGL its libGLdispatch).
for library in "$root"/lib/*.so*; do
    patchelf --set-rpath '$ORIGIN' "$library"
done

# Every library found inside: the executable's RUNPATH ($ORIGIN/../lib) and each library's
# ($ORIGIN) must resolve each one there, none on the host but those left to it. RUNPATH, not the
# older RPATH: a host's own libraries (its EGL vendor's) keep finding theirs on the host, and
# LD_LIBRARY_PATH still wins where a host sets it to its driver's libglvnd.
check_inside() {
    local file="$1"
    ldd "$file" | awk '/=> \// {print $1, $3}' | while read -r name path; do
        if ! [[ "$name" =~ $host_only ]] && [ "$(realpath "$(dirname "$path")")" != "$(realpath "$root/lib")" ]; then
            echo "bundle: $file finds $name at $path, not in the bundle" >&2
            exit 1
        fi
    done
}
check_inside "$root/bin/penumbra"

{
    echo "penumbra $(git describe --always --dirty 2>/dev/null || echo unknown), built $(date -u +%F)"
    echo "on $(. /etc/os-release && echo "$PRETTY_NAME"), glibc $(ldd --version | awk 'NR==1 {print $NF}')"
    echo
    echo "bin/penumbra: serve, render, load, info, bench (image comparison left out: bench accuracy"
    echo "  times frames and writes them with --images; errors and truths need a full build)"
    echo "share/penumbra: shaders, web client, accuracy tables, plot scripts, volumes/ch2.nii.gz"
    echo "gpu-bench.sh: every GPU figure in one go: bash penumbra/gpu-bench.sh penumbra OUTDIR"
    echo "lib: the shared libraries it needs, found through \$ORIGIN; the host supplies glibc and"
    echo "  the EGL vendor library (Mesa's libEGL_mesa.so.0 or NVIDIA's libEGL_nvidia.so.0 with its"
    echo "  glvnd vendor file; __EGL_VENDOR_LIBRARY_FILENAMES picks one)"
    echo "glibc: 2.34 or newer; the bundled libstdc++ (GCC 12) needs 2.36. On an older one (Ubuntu"
    echo "  22.04) put links to the host's libstdc++.so.6 and libgcc_s.so.1 (GCC 12 or newer) in a"
    echo "  folder and name it in LD_LIBRARY_PATH, which the bundle's RUNPATH yields to; gpu-bench.sh"
    echo "  does so by itself"
    echo
    (cd "$root" && find lib -type f -printf '%s %p\n' | sort -k2 | awk '{printf "%10d  %s\n", $1, $2}')
} > "$root/BUNDLE.txt"

mkdir -p "$(dirname "$out")"
tar -C "$stage" -cf - penumbra | xz -T0 -6 > "$out.tmp"
mv "$out.tmp" "$out"
bytes=$(stat -c %s "$out")
unpacked=$(du -sb "$root" | cut -f1)
echo "bundle: $out: $((bytes / 1024 / 1024)) MiB ($bytes bytes; $((unpacked / 1024 / 1024)) MiB unpacked, $(ls "$root/lib" | wc -l) libraries)"
if [ "$bytes" -gt "$most_bytes" ]; then
    echo "bundle: larger than $((most_bytes / 1024 / 1024)) MiB, which a GPU host takes" >&2
    exit 1
fi
