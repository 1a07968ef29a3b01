#!/bin/sh
# Renders docker/nginx.conf.template into an nginx configuration, from the environment:
#
#   PENUMBRA_UPSTREAMS        the replicas, "host:port host:port ..." (required); each its own name
#   PENUMBRA_HTTPS_PORT       TLS port (8443; above 1024, so nginx needs no root to bind it)
#   PENUMBRA_HTTP_PORT        plain HTTP port (8080)
#   PENUMBRA_PLAIN_HTTP       redirect: plain HTTP is sent to https:// (default); proxy: it is
#                             served like TLS (a trusted network only: the token travels in clear)
#   PENUMBRA_PUBLIC_HTTPS_PORT  the TLS port clients see, for the redirect (PENUMBRA_HTTPS_PORT)
#   PENUMBRA_TLS_CERT, PENUMBRA_TLS_KEY  (/etc/nginx/tls/tls.crt, /etc/nginx/tls/tls.key)
#   PENUMBRA_PROXY_READ_TIMEOUT  idle WebSocket limit; above the replicas' --ping-interval (60s)
#   PENUMBRA_PROXY_CONNECT_TIMEOUT  after this a replica counts as down (2s)
#   PENUMBRA_NGINX_STATE_DIR  pid file and temporary files (/var/lib/nginx)
#   PENUMBRA_NGINX_WORKERS    worker processes (auto)
#   PENUMBRA_NGINX_ACCESS_LOG, PENUMBRA_NGINX_ERROR_LOG  (/dev/stdout, stderr)
#
# usage: render-nginx-conf.sh [TEMPLATE] OUTPUT
set -eu

here=$(dirname "$0")
if [ $# -ge 2 ]; then
    template=$1
    output=$2
elif [ $# -eq 1 ]; then
    template=$here/nginx.conf.template
    output=$1
else
    echo "usage: $0 [TEMPLATE] OUTPUT" >&2
    exit 2
fi
if [ -z "${PENUMBRA_UPSTREAMS:-}" ]; then
    echo "$0: PENUMBRA_UPSTREAMS names no replica (\"host:port host:port ...\")" >&2
    exit 2
fi

https_port=${PENUMBRA_HTTPS_PORT:-8443}
public_port=${PENUMBRA_PUBLIC_HTTPS_PORT:-$https_port}
case ${PENUMBRA_PLAIN_HTTP:-redirect} in
    redirect)
        if [ "$public_port" = 443 ]; then
            target='https://$host$request_uri'
        else
            target="https://\$host:$public_port\$request_uri"
        fi
        redirect="        if (\$scheme = http) {
            return 308 $target;
        }"
        ;;
    proxy)
        redirect="        # Plain HTTP is proxied like TLS (PENUMBRA_PLAIN_HTTP=proxy)."
        ;;
    *)
        echo "$0: PENUMBRA_PLAIN_HTTP must be redirect or proxy" >&2
        exit 2
        ;;
esac

servers=""
for upstream in $PENUMBRA_UPSTREAMS; do
    servers="$servers        server $upstream max_fails=1 fail_timeout=10s;
"
done

# awk, not sed: the replacements hold slashes, dollars and newlines.
awk -v servers="$servers" -v redirect="$redirect" \
    -v https_port="$https_port" -v http_port="${PENUMBRA_HTTP_PORT:-8080}" \
    -v cert="${PENUMBRA_TLS_CERT:-/etc/nginx/tls/tls.crt}" \
    -v key="${PENUMBRA_TLS_KEY:-/etc/nginx/tls/tls.key}" \
    -v read_timeout="${PENUMBRA_PROXY_READ_TIMEOUT:-60s}" \
    -v connect_timeout="${PENUMBRA_PROXY_CONNECT_TIMEOUT:-2s}" \
    -v state_dir="${PENUMBRA_NGINX_STATE_DIR:-/var/lib/nginx}" \
    -v workers="${PENUMBRA_NGINX_WORKERS:-auto}" \
    -v access_log="${PENUMBRA_NGINX_ACCESS_LOG:-/dev/stdout}" \
    -v error_log="${PENUMBRA_NGINX_ERROR_LOG:-stderr}" '
    function put(name, value) { gsub("@" name "@", value) }
    /^@UPSTREAM_SERVERS@$/ { printf "%s", servers; next }
    /^@PLAIN_HTTP_REDIRECT@$/ { print redirect; next }
    {
        put("HTTPS_PORT", https_port); put("HTTP_PORT", http_port)
        put("TLS_CERT", cert); put("TLS_KEY", key)
        put("READ_TIMEOUT", read_timeout); put("CONNECT_TIMEOUT", connect_timeout)
        put("STATE_DIR", state_dir); put("WORKERS", workers)
        put("ACCESS_LOG", access_log); put("ERROR_LOG", error_log)
        if ($0 ~ /@[A-Z_]+@/) { print "unfilled field: " $0 > "/dev/stderr"; exit 1 }
        print
    }' "$template" > "$output.tmp"
mv "$output.tmp" "$output"
