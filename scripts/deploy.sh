#!/usr/bin/env bash
# Runs the container stack of docker/compose.yaml: Penumbra replicas behind nginx.
#   bash scripts/deploy.sh up [--gpu] [--metrics]    build the images, start the stack
#   bash scripts/deploy.sh down                      stop it and remove its containers
#   bash scripts/deploy.sh logs [SERVICE...]         what the services printed
# Docker where `docker info` answers, else podman (runc, limits within this host's hard ones, and
# its Docker-compatible socket for docker-compose). Without a registry, the debian:12 base image
# is made with debootstrap from the Debian mirror apt uses (kept in $PENUMBRA_DEPLOY_CACHE).
# The replicas' access token and cluster secret are files in $PENUMBRA_SECRETS (docker/secrets,
# which git ignores); `up` makes them when missing and prints the URL with the token.
# Environment: PENUMBRA_HTTPS_PORT (8443, or ADDRESS:PORT), PENUMBRA_PORT (plain HTTP, redirected
# to https://; 8080, or ADDRESS:PORT), PENUMBRA_DATA (the volumes folder, default
# /usr/share/mricron/templates), PENUMBRA_ALLOWED_ORIGINS (other sites whose pages may open the
# WebSocket), PENUMBRA_PREBUILT_FROM (a build tree of this Debian 12 host, e.g. the bundle preset's: its install is
# copied into the image instead of compiling there), PENUMBRA_PROJECT (the compose project's name).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
state="${PENUMBRA_DEPLOY_STATE:-$root/build/deploy}"
project="${PENUMBRA_PROJECT:-penumbra}"
started=$(date +%s)
step() { echo "deploy [$(($(date +%s) - started)) s]: $*"; }

action="${1:-}"
shift || true
gpu=0
metrics=0
services=()
if [ "$action" = logs ]; then
    services=("$@")
    set --
fi
for option in "$@"; do
    case "$option" in
        --gpu) gpu=1 ;;
        --metrics) metrics=1 ;;
        *) echo "deploy: unknown option $option" >&2; exit 2 ;;
    esac
done
case "$action" in
    up | down | logs) ;;
    *) echo "usage: deploy.sh up [--gpu] [--metrics] | down | logs [SERVICE...]" >&2; exit 2 ;;
esac
mkdir -p "$state"
secrets="${PENUMBRA_SECRETS:-$root/docker/secrets}"
export PENUMBRA_SECRETS="$secrets"
https_port="${PENUMBRA_HTTPS_PORT:-8443}"
# The port browsers see, for nginx's redirect of plain HTTP.
export PENUMBRA_PUBLIC_HTTPS_PORT="${PENUMBRA_PUBLIC_HTTPS_PORT:-${https_port##*:}}"

if command -v docker >/dev/null && docker info >/dev/null 2>&1; then
    engine=docker
    build=(docker build)
else
    engine=podman
    command -v podman >/dev/null || { echo "deploy: neither docker nor podman: run scripts/install-deps.sh" >&2; exit 1; }
    # crun refuses this kind of host's hybrid cgroups, and podman's default limits may exceed the
    # hard ones; the API socket needs both in a containers.conf.
    export CONTAINERS_CONF="$state/containers.conf"
    cat > "$CONTAINERS_CONF" <<'CONF'
[containers]
default_ulimits = ["nofile=20000:20000", "nproc=32768:32768"]
[engine]
runtime = "runc"
cgroup_manager = "cgroupfs"
events_logger = "file"
CONF
    # Docker's image format: OCI's has no HEALTHCHECK.
    build=(podman build --runtime runc --format docker)
fi

if docker compose version >/dev/null 2>&1; then
    compose=(docker compose)
else
    compose=(docker-compose)
fi
compose+=(-p "$project" -f docker/compose.yaml)
if [ "$gpu" = 1 ]; then
    compose+=(-f docker/compose.gpu.yaml)
fi
# `down` takes every service away, Prometheus too.
if [ "$metrics" = 1 ] || [ "$action" = down ]; then
    compose+=(--profile metrics)
fi

service=""
if [ "$engine" = podman ]; then
    # In a short temporary folder: a socket path may not be longer than 107 bytes.
    socket_dir=$(mktemp -d "${TMPDIR:-/tmp}/penumbra-podman.XXXXXX")
    socket="$socket_dir/podman.sock"
    podman system service --time=0 "unix://$socket" > "$state/podman-service.log" 2>&1 &
    service=$!
    trap 'kill "$service" 2>/dev/null; wait "$service" 2>/dev/null || true; rm -rf "$socket_dir"' EXIT
    for _ in $(seq 1 100); do
        [ -S "$socket" ] && break
        sleep 0.1
    done
    export DOCKER_HOST="unix://$socket"
fi

if [ "$action" = down ]; then
    "${compose[@]}" down --timeout 10
    exit 0
fi
if [ "$action" = logs ]; then
    "${compose[@]}" logs --no-color "${services[@]}"
    exit 0
fi

# The base the Dockerfiles name: pulled where a registry answers, else made with debootstrap.
if ! $engine image inspect debian:12 >/dev/null 2>&1; then
    if $engine pull docker.io/library/debian:12 >/dev/null 2>&1; then
        $engine tag docker.io/library/debian:12 debian:12
    else
        step "no registry: the Debian 12 minbase made with debootstrap"
        tarball=$(bash scripts/debian-base.sh "$state")
        step "import debian:12"
        $engine import "$tarball" debian:12 > /dev/null
    fi
fi

build_args=()
prebuilt=""
# The certificate authorities this host added to its trust store, for a TLS-inspecting proxy
# between the builder and the npm registry.
extra_ca=$(cat /usr/local/share/ca-certificates/*.crt 2>/dev/null || true)
if [ -n "$extra_ca" ]; then
    build_args+=(--build-arg "EXTRA_CA_CERTS=$extra_ca")
fi
if [ -n "${PENUMBRA_PREBUILT_FROM:-}" ]; then
    # The one folder of build/ that .dockerignore lets into the build context.
    prebuilt=build/image-prefix
    step "install $PENUMBRA_PREBUILT_FROM into $prebuilt"
    rm -rf "$prebuilt"
    cmake --install "$PENUMBRA_PREBUILT_FROM" --prefix "$prebuilt" --strip > "$state/install.log"
    bash docker/runtime-packages.sh "$prebuilt/bin/penumbra" > "$prebuilt/runtime-packages.txt"
    build_args+=(--build-arg "PREBUILT=$prebuilt")
fi
if [ -n "$prebuilt" ]; then
    step "build penumbra:latest from the install of $PENUMBRA_PREBUILT_FROM"
else
    step "build penumbra:latest (compiles in its builder stage the first time; $state/build-penumbra.log)"
fi
"${build[@]}" "${build_args[@]}" -f docker/Dockerfile -t penumbra:latest . > "$state/build-penumbra.log" 2>&1 \
    || { tail -n 40 "$state/build-penumbra.log" >&2; exit 1; }
step "build penumbra-nginx:latest"
"${build[@]}" -f docker/nginx.Dockerfile -t penumbra-nginx:latest docker > "$state/build-nginx.log" 2>&1 \
    || { tail -n 40 "$state/build-nginx.log" >&2; exit 1; }
if [ "$metrics" = 1 ]; then
    step "build penumbra-prometheus:latest"
    "${build[@]}" -f docker/prometheus.Dockerfile -t penumbra-prometheus:latest docker \
        > "$state/build-prometheus.log" 2>&1 || { tail -n 40 "$state/build-prometheus.log" >&2; exit 1; }
fi
$engine image ls --format '{{.Repository}}:{{.Tag}} {{.Size}}' | grep -E '(^|/)(penumbra|debian)' || true
# The secrets every replica shares, made once. The folder is only ours; the files are readable
# by the image's non-root user, to whom compose mounts them.
for name in access_token cluster_secret; do
    if [ ! -s "$secrets/$name" ]; then
        step "make $secrets/$name"
        mkdir -p "$secrets"
        chmod 700 "$secrets"
        head -c 24 /dev/urandom | od -An -tx1 | tr -d ' \n' > "$secrets/$name.tmp"
        chmod 644 "$secrets/$name.tmp"
        mv "$secrets/$name.tmp" "$secrets/$name"
    fi
done
step "compose up"
"${compose[@]}" up -d --no-build
where="$https_port"
[[ "$where" == *:* ]] || where="localhost:$where"
step "up: https://$where/?token=$(cat "$secrets/access_token") (nginx in front of the replicas; a self-signed certificate unless one is mounted, docker/proxy.md)"
