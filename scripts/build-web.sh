#!/usr/bin/env bash
# Builds the web client (client_web/dist) with the locked npm dependencies; `cmake --install`
# installs it as share/penumbra/web.
set -euo pipefail
cd "$(dirname "$0")/../client_web"
npm ci --no-audit --no-fund
npm run build
