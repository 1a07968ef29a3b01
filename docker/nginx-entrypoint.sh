#!/bin/sh
# Writes the replicas of $PENUMBRA_UPSTREAMS ("host:port host:port ...") as nginx upstream servers
# next to the configuration, then runs nginx in the foreground.
set -eu
conf_dir=/etc/nginx
: "${PENUMBRA_UPSTREAMS:?set PENUMBRA_UPSTREAMS to the replicas, e.g. penumbra-1:8080 penumbra-2:8080}"
upstreams=$conf_dir/penumbra-upstreams.conf
: > "$upstreams"
for server in $PENUMBRA_UPSTREAMS; do
    echo "server $server;" >> "$upstreams"
done
exec nginx -c "$conf_dir/nginx.conf" -g 'daemon off;'
