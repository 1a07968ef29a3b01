#!/usr/bin/env bash
# Installs what Penumbra needs from Debian 12's packages, in groups:
#   build    compile the server and the web client (the container image's builder stage)
#   ffmpeg   FFmpeg's libraries for the movie writer and the stream decoder (PENUMBRA_WITH_FFMPEG,
#            on in the release build; the bundle and the container image leave them out, with the
#            hundred codec libraries libavcodec brings)
#   test     what the test suite needs on top of build
#   deploy   containers for the container test and scripts/deploy.sh (podman, debootstrap,
#            compose), the portable bundle (scripts/bundle.sh)
# No argument installs every group (a CI machine); `--only GROUP[,GROUP]` installs those.
set -euo pipefail

build=(
    cmake ninja-build g++ pkg-config git python3
    libglm-dev libepoxy-dev libegl-dev libegl1 libegl-mesa0 libgl1-mesa-dri
    libopenimageio-dev libturbojpeg0-dev libpng-dev libnifti2-dev libdcmtk-dev libopenjp2-7-dev
    libx264-dev libyuv-dev
    zlib1g-dev libbz2-dev nlohmann-json3-dev libboost-dev
    libboost-program-options-dev
    libssl-dev nodejs
)
ffmpeg=(libavcodec-dev libavformat-dev libswscale-dev libavutil-dev)
test=(
    libgtest-dev libgmock-dev python3-jsonschema python3-pydicom
    clang-14 libfuzzer-14-dev clang-format-14 clang-tidy-14
    mricron-data gnuplot-nox
    # Other projects' volume files for the conformance test, and the readers it compares with
    # (pydicom decodes JPEG 2000 through GDCM's Python module; teem's unu reads NRRD).
    python3-nibabel python3-gdcm teem-apps insighttoolkit5-examples heudiconv
    # InVesalius' head CT, converted by scripts/cranium-ct.py for the tests, bench and demo data.
    invesalius-examples
    chromium
    # The loopback cluster test: Debian's nginx in front, a certificate made with openssl, and
    # WebSocket clients (also the container test's).
    nginx openssl python3-websocket
)
# runc: podman's default crun refuses hybrid cgroups; the dnsname plugin lets compose services
# find each other by name on podman's CNI network. patchelf and xz: the portable bundle
# (scripts/bundle.sh).
deploy=(
    podman runc golang-github-containernetworking-plugin-dnsname docker-compose debootstrap
    patchelf xz-utils
)

groups="build,ffmpeg,test,deploy"
if [ "${1:-}" = "--only" ] && [ -n "${2:-}" ]; then
    groups="$2"
elif [ $# -ne 0 ]; then
    echo "usage: install-deps.sh [--only build|ffmpeg|test|deploy[,...]]" >&2
    exit 2
fi
packages=()
for group in ${groups//,/ }; do
    case "$group" in
        build) packages+=("${build[@]}") ;;
        ffmpeg) packages+=("${ffmpeg[@]}") ;;
        test) packages+=("${test[@]}") ;;
        deploy) packages+=("${deploy[@]}") ;;
        *) echo "install-deps: unknown group '$group'" >&2; exit 2 ;;
    esac
done
# npm: Debian's package, unless a nodejs that bundles npm (e.g. NodeSource's) is installed already.
if [[ ",$groups," == *,build,* ]] && ! command -v npm >/dev/null 2>&1; then
    packages+=(npm)
fi

missing=()
for package in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$package")
    fi
done
if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} Debian packages present"
    exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
