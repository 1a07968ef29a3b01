#!/usr/bin/env bash
# The README's first command: install, build, and render the default volume (the Colin27 MRI head
# from Debian's mricron-data) with Blinn-Phong shading into out/ch2_phong.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
./build/release/server/app/penumbra render --mode phong --tf mri_skin --size 512x512 \
    --out out/ch2_phong.png "$@"
