#!/usr/bin/env bash
# The README's second command: install, build, and run every test through CTest: the release
# build's whole suite, then the sanitizer builds (scripts/test-sanitizers.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
ctest --preset release --parallel "$(nproc)"
bash scripts/test-sanitizers.sh
