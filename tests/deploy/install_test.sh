#!/usr/bin/env bash
# Installs the build tree into a temporary prefix, moves the prefix, and checks that the moved
# binary renders with its own shaders, serves its own web client and accuracy table, and plots with
# its own gnuplot template: nothing of the build or source tree may be needed once installed.
# usage: install_test.sh BUILD_DIR WORK_DIR VOLUME
set -euo pipefail
build_dir="$1"
work="$2"
volume="$3"

rm -rf "$work"
mkdir -p "$work"
cmake --install "$build_dir" --prefix "$work/first" > "$work/install.log"
mv "$work/first" "$work/moved"
prefix="$work/moved"
for file in bin/penumbra share/penumbra/shaders/raycast.glsl share/penumbra/web/index.html \
        share/penumbra/accuracy/llvmpipe.json share/penumbra/plots/accuracy.gp; do
    test -e "$prefix/$file" || { echo "install: $file missing under the prefix" >&2; exit 1; }
done

# Render: the shaders must come from the moved prefix (nothing else is searched).
unset PENUMBRA_SHADER_DIR
(cd "$work" && "$prefix/bin/penumbra" render --volume "$volume" --mode phong --size 64x64 \
        --out "$work/moved.png") | tee "$work/render.log"
grep -Eq "pass: +raycast" "$work/render.log"
test -s "$work/moved.png"

# The accuracy plot script: the moved prefix's template below the table's data.
mkdir -p "$work/plot"
"$prefix/bin/penumbra" bench accuracy --from "$prefix/share/penumbra/accuracy/llvmpipe.json" \
        --plot "$work/plot/table.png" > "$work/plot.log" 2>&1 || grep -q "gnuplot failed" "$work/plot.log"
grep -q "set multiplot" "$work/plot/table.gp"

# Serve: the web client and the accuracy table of the moved prefix.
"$prefix/bin/penumbra" serve --port 0 --data "$(dirname "$volume")" > "$work/serve.log" 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null; wait "$server" 2>/dev/null || true' EXIT
for _ in $(seq 1 300); do
    grep -q "^serving:" "$work/serve.log" && break
    kill -0 "$server" 2>/dev/null || { cat "$work/serve.log" >&2; exit 1; }
    sleep 0.2
done
cat "$work/serve.log"
grep -q "quality: .* from $prefix/share/penumbra/accuracy/llvmpipe.json" "$work/serve.log"
port=$(sed -n 's|^serving: *http://[^:]*:\([0-9]*\)/.*|\1|p' "$work/serve.log")
/usr/bin/python3 - "$port" "$prefix/share/penumbra/web/index.html" <<'PY'
import sys, urllib.request
page = urllib.request.urlopen(f"http://127.0.0.1:{sys.argv[1]}/", timeout=10).read()
if page != open(sys.argv[2], "rb").read():
    sys.exit("GET / is not the installed web client's index.html")
print("web:      GET / serves the installed index.html")
PY
echo "install test: renders and serves from the moved prefix $prefix"
