#!/bin/sh
# The nginx container's entry point: a self-signed certificate on first start when none is
# mounted, the configuration rendered for the replicas in PENUMBRA_UPSTREAMS (see
# render-nginx-conf.sh), then nginx in the foreground. Arguments go to nginx.
#
#   PENUMBRA_NGINX_CONF  where the rendered configuration goes (/etc/nginx/nginx.conf)
#   PENUMBRA_TLS_NAME    the host name the self-signed certificate is made for (localhost)
#   PENUMBRA_NGINX_TEMPLATE  the template (nginx.conf.template next to this script)
#
# Real certificates: mount them at PENUMBRA_TLS_CERT and PENUMBRA_TLS_KEY (by default
# /etc/nginx/tls/tls.crt and tls.key); nothing is generated then.
set -eu

here=$(dirname "$0")
conf=${PENUMBRA_NGINX_CONF:-/etc/nginx/nginx.conf}
cert=${PENUMBRA_TLS_CERT:-/etc/nginx/tls/tls.crt}
key=${PENUMBRA_TLS_KEY:-/etc/nginx/tls/tls.key}
name=${PENUMBRA_TLS_NAME:-localhost}

if [ ! -s "$cert" ] || [ ! -s "$key" ]; then
    if [ -e "$cert" ] || [ -e "$key" ]; then
        echo "nginx-entrypoint: only one of $cert and $key is there; mount both or neither" >&2
        exit 1
    fi
    echo "nginx-entrypoint: no certificate at $cert: making a self-signed one for $name" >&2
    mkdir -p "$(dirname "$cert")" "$(dirname "$key")"
    # The key is readable by its owner only, and written before the certificate names it.
    umask 077
    openssl req -x509 -newkey rsa:2048 -nodes -days 825 -subj "/CN=$name" \
        -addext "subjectAltName=DNS:$name,DNS:localhost,IP:127.0.0.1" \
        -keyout "$key.tmp" -out "$cert.tmp" 2>/dev/null
    mv "$key.tmp" "$key"
    mv "$cert.tmp" "$cert"
    umask 022
fi

mkdir -p "${PENUMBRA_NGINX_STATE_DIR:-/var/lib/nginx}"
"$here/render-nginx-conf.sh" "${PENUMBRA_NGINX_TEMPLATE:-$here/nginx.conf.template}" "$conf"
exec nginx -c "$conf" -e "${PENUMBRA_NGINX_ERROR_LOG:-stderr}" -g 'daemon off;' "$@"
