# Debian's nginx in front of the Penumbra replicas. Build context: docker/.
# The entry point makes a self-signed certificate on first start when none is mounted at
# /etc/nginx/tls (keep that folder on a volume and it is made once), renders nginx.conf.template
# for the replicas in PENUMBRA_UPSTREAMS, and runs nginx (proxy.md).
ARG BASE=debian:12
FROM ${BASE}
RUN apt-get update -qq \
    && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends nginx openssl \
    && apt-get clean && rm -rf /var/lib/apt/lists/* /usr/share/doc /usr/share/man \
       /etc/nginx/sites-enabled /etc/nginx/conf.d
# Side by side: the entry point finds the other two next to itself.
COPY nginx-entrypoint.sh render-nginx-conf.sh nginx.conf.template /usr/local/lib/penumbra-nginx/
EXPOSE 8080 8443
ENTRYPOINT ["/usr/local/lib/penumbra-nginx/nginx-entrypoint.sh"]
