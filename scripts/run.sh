#!/usr/bin/env bash
# The README's first command: install, build, and start the rendering service on the demo data
# (scripts/demo-data.sh: the MRI heads of Debian's mricron-data, the Colin27 head ch2.nii.gz and
# others, and InVesalius' head CT from invesalius-examples), serving the web
# client and the WebSocket API on http://127.0.0.1:8080/ until Ctrl-C. Extra arguments go to
# `penumbra serve` (e.g. --port 9000 --address 0.0.0.0).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
if [ -f client_web/package.json ]; then
    (cd client_web && npm ci --no-audit --no-fund && npm run build)
fi
# A first frame of the default volume, so a fresh machine shows at once that rendering works.
mkdir -p out
./build/release/server/app/penumbra render --mode sbrc --phong --size 512x512 \
    --out out/ch2_sbrc.png
bash scripts/demo-data.sh
exec ./build/release/server/app/penumbra serve "$@"
