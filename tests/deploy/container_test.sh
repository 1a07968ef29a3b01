#!/usr/bin/env bash
# The container stack on this machine through scripts/deploy.sh (podman with runc and
# docker-compose on its socket here; docker where it runs): the debian:12 base made with debootstrap
# when no registry answers, the Penumbra and nginx images, two replicas behind nginx with its
# defaults (TLS with a self-signed certificate made on first start, plain HTTP redirected), a
# frame rendered through the proxy over wss:// with the access token deploy.sh made, then `down`.
# usage: container_test.sh SOURCE_DIR BUILD_DIR WORK_DIR
#
# The debootstrap tarball stays in $PENUMBRA_DEPLOY_CACHE (~/.cache/penumbra/deploy) and the
# engine's layer cache persists, so a second run on one machine skips what is unchanged. The
# image's builder copies an install of BUILD_DIR (the Dockerfile's PREBUILT; CTest gives the bundle
# preset's tree, the server without OpenImageIO), so CI compiles the server no third time;
# PENUMBRA_IMAGE_FROM_SOURCE=1 compiles in the builder stage instead (the Dockerfile's default).
set -euo pipefail
source_dir="$1"
build_dir="$2"
work="$3"
started=$(date +%s)
step() { echo "[$(($(date +%s) - started)) s] $*"; }

rm -rf "$work"
mkdir -p "$work"
export PENUMBRA_DEPLOY_STATE="$work"
export PENUMBRA_PROJECT=penumbra-test
free_port() {
    /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
port=$(free_port)
http_port=$(free_port)
export PENUMBRA_HTTPS_PORT="127.0.0.1:$port"
export PENUMBRA_PORT="127.0.0.1:$http_port"
export PENUMBRA_SECRETS="$work/secrets"
export PENUMBRA_DATA=/usr/share/mricron/templates
if [ "${PENUMBRA_IMAGE_FROM_SOURCE:-0}" != 1 ]; then
    export PENUMBRA_PREBUILT_FROM="$build_dir"
fi
deploy="$source_dir/scripts/deploy.sh"
down() {
    local status=$?
    bash "$deploy" logs > "$work/compose.log" 2>&1 || true
    if [ "$status" -ne 0 ]; then
        echo "--- the services' last lines ($work/compose.log):" >&2
        tail -n 40 "$work/compose.log" >&2
    fi
    bash "$deploy" down > "$work/down.log" 2>&1 || true
}
trap down EXIT
bash "$deploy" up

step "through nginx on 127.0.0.1:$port: /healthz and the web client over https, plain HTTP redirected"
/usr/bin/python3 - "$port" "$http_port" <<'PY'
import http.client, ssl, sys, time, urllib.request
port, http_port = sys.argv[1], sys.argv[2]
# The certificate is the self-signed one the nginx container made on its first start.
unverified = ssl.create_default_context()
unverified.check_hostname = False
unverified.verify_mode = ssl.CERT_NONE
# Replicas come up one by one, and nginx skips one that refused for a few seconds: retry.
deadline = time.time() + 180
def get(path):
    while True:
        try:
            with urllib.request.urlopen(f"https://127.0.0.1:{port}{path}", timeout=5,
                                        context=unverified) as response:
                return response.read().decode()
        except OSError as error:
            if time.time() > deadline:
                sys.exit(f"GET {path} through nginx: still {error} after 180 s")
            time.sleep(1)
get("/healthz")
if "<script" not in get("/"):
    sys.exit("GET / through nginx is not the web client")
plain = http.client.HTTPConnection("127.0.0.1", int(http_port), timeout=10)
plain.request("GET", "/healthz")
redirect = plain.getresponse()
if redirect.status != 308 or not redirect.getheader("Location", "").startswith("https://"):
    sys.exit(f"plain HTTP is not redirected to https://: {redirect.status} {redirect.getheader('Location')}")
print(f"proxy:    https /healthz 200, / serves the web client, http -> {redirect.getheader('Location')}")
PY
step "a frame through nginx over wss:// with the access token; none without it"
/usr/bin/python3 "$(dirname "$0")/one_frame.py" "$port" "$PENUMBRA_SECRETS/access_token" ch2.nii.gz \
    "$work/frame.jpg"
# Without a GPU the replicas say they render on the CPU.
bash "$deploy" logs penumbra-1 penumbra-2 > "$work/replicas.log" 2>&1
grep -q "no GPU found: rendering on the CPU" "$work/replicas.log" \
    || { echo "the replicas' logs do not say they render on the CPU:" >&2; tail -n 20 "$work/replicas.log" >&2; exit 1; }
step "down"
trap - EXIT
down
step "container test passed"
