#!/usr/bin/env bash
# Rewrites what proto/v1/common.schema.json restates of the C++ tables (every setting of
# scene::kSettings by its kind, the mode and frame-format names, the error codes the wire carries,
# the preset names, the transfer function's position spaces and limits, the client message types)
# and what hello.schema.json restates (the mode capabilities' names) from the tables themselves,
# proto/README.md's table of the client messages from their schemas (v1/<type>.schema.json), its
# limits' values and a new session's settings and output (§5), the messages the web client's
# tests recorded (client_web/test/fixtures: the hello and every state as the server sends them
# now), and the web client's module of the server's names, settings and views
# (client_web/src/protocol/generated/server_tables.ts: the frame formats, the error codes, the
# settings' enum names, every setting with its kind, range and summary and the state's type, the
# position spaces, the views and their poses, a new session's settings and output) whole. The
# build tool server/codegen (update_schema) writes them. Run it after changing one of the tables;
# SchemaAgreement.*IsGenerated, SchemaAgreement.TheWebClientsRecordedHelloIsTheServers and
# SchemaAgreement.TheWebClientsServerTablesAreGenerated (protocol_test) fail until the committed
# files are what this writes. The rest of each file is written by hand.
#   scripts/update-schema.sh [PRESET]     (default: release; builds the update_schema target)
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-release}
if [ ! -d "build/$preset" ]; then
    cmake --preset "$preset" >/dev/null
fi
cmake --build --preset "$preset" --target update_schema
"build/$preset/server/codegen/update_schema" proto
