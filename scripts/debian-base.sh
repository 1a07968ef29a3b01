#!/usr/bin/env bash
# Prints the path of a Debian 12 minbase root filesystem as a tarball, made once with debootstrap
# from the mirror apt uses and kept in $PENUMBRA_DEPLOY_CACHE (~/.cache/penumbra/deploy): the
# debian:12 base image where no registry answers (scripts/deploy.sh) and the clean root the
# portable bundle is tried in (tests/deploy/bundle_test.sh). Its apt sources are this host's (the
# same suites, so the same library versions).
#   bash scripts/debian-base.sh [WORK_DIR]   (WORK_DIR: where the root is made; a temporary one)
set -euo pipefail
cache="${PENUMBRA_DEPLOY_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/penumbra/deploy}"
tarball="$cache/debian-12-minbase.tar"
if [ ! -s "$tarball" ]; then
    command -v debootstrap >/dev/null || { echo "debian-base: debootstrap is missing: run scripts/install-deps.sh" >&2; exit 1; }
    mkdir -p "$cache"
    work="${1:-}"
    if [ -z "$work" ]; then
        work=$(mktemp -d)
        trap 'rm -rf --one-file-system "$work"' EXIT
    fi
    mkdir -p "$work"
    rootfs="$work/rootfs"
    rm -rf --one-file-system "$rootfs"
    mirror=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources)
    echo "debian-base: debootstrap Debian 12 (minbase) from $mirror" >&2
    debootstrap --variant=minbase bookworm "$rootfs" "$mirror" > "$work/debootstrap.log"
    cp /etc/apt/sources.list.d/debian.sources "$rootfs/etc/apt/sources.list.d/"
    rm -f "$rootfs/etc/apt/sources.list" "$rootfs"/var/cache/apt/archives/*.deb
    rm -rf "$rootfs"/var/lib/apt/lists/*
    tar -C "$rootfs" -cf "$tarball.tmp" .
    mv "$tarball.tmp" "$tarball"
    rm -rf --one-file-system "$rootfs"
fi
echo "$tarball"
