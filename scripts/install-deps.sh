#!/usr/bin/env bash
# Installs what Penumbra needs to build, test and run on Debian 12: all from Debian's packages.
set -euo pipefail

packages=(
    cmake ninja-build g++ pkg-config git python3
    libglm-dev libepoxy-dev libegl-dev libegl1 libegl-mesa0 libgl1-mesa-dri
    libopenimageio-dev libnifti2-dev libdcmtk-dev zlib1g-dev nlohmann-json3-dev libboost-dev
    libgtest-dev libgmock-dev libssl-dev python3-jsonschema python3-pydicom
    mricron-data gnuplot-nox
    chromium nodejs
    nginx openssl python3-websocket
)
# npm: Debian's package, unless a nodejs that bundles npm (e.g. NodeSource's) is installed already.
if ! command -v npm >/dev/null 2>&1; then
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
