# rollgap HTTP service: multi-stage build on Debian 12 (bookworm).
#   build:   the project's own dependency script, then a Release build of build/rollgap
#   runtime: the shared libraries rollgap links (the job store's SQLite and libpqxx/libpq
#            included), a data directory its user can write (/var/lib/rollgap), and Debian's
#            nginx with the front proxy configuration (deploy/nginx/rollgap.conf), as a non-root
#            user. One container runs both by default (rollgap-container proxied: nginx on 8080
#            in front of the service on the container's loopback), so a published port is always
#            the proxy's; the Kubernetes pod runs the image twice instead, the service and nginx
#            in front of it as two containers (deploy/kubernetes).
# Build with scripts/build-image.sh (buildah, no Docker engine needed) or `docker build .`.

FROM debian:bookworm-slim AS build
WORKDIR /src
# The dependency script alone first, so its layer is reused while only sources change.
COPY scripts/install-deps.sh scripts/install-deps.sh
RUN bash scripts/install-deps.sh </dev/null && rm -rf /var/lib/apt/lists/*
COPY . .
# The release preset of CMakePresets.json (the build flags' one place).
RUN cmake --preset release -B /build -DROLLGAP_WERROR=ON \
 && cmake --build /build -j"$(nproc)" --target rollgap \
 && strip /build/rollgap \
 && /build/rollgap --version

FROM debian:bookworm-slim AS runtime
# Runtime libraries of build/rollgap (ldd → dpkg -S): cpp-httplib (pulls OpenSSL, zlib,
# brotli), spdlog (pulls fmt), SUNDIALS CVODE, and the job store's SQLite and libpqxx (pulls
# libpq). Not the -dev packages, not OpenMPI/PETSc, not a PostgreSQL server.
# nginx: the front proxy, the same Debian package the tests run.
RUN apt-get update \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
      libcpp-httplib0.11 libspdlog1.10 libsundials-cvode6 libsqlite3-0 libpqxx-6.4 libpq5 nginx \
 && rm -rf /var/lib/apt/lists/* \
 && useradd --system --uid 10001 --user-group --no-create-home --shell /usr/sbin/nologin rollgap \
 && install -d -o 10001 -g 10001 -m 0750 /var/lib/rollgap
COPY --from=build /build/rollgap /usr/local/bin/rollgap
# The entrypoint: `proxied` (nginx + the service) or any rollgap command.
COPY deploy/container/entrypoint.sh /usr/local/bin/rollgap-container
# The front proxy's configuration (Kubernetes mounts the same file from a ConfigMap over it).
COPY deploy/nginx/rollgap.conf /etc/rollgap/nginx/rollgap.conf
# Fail the build if a shared library is missing or nginx refuses the configuration.
RUN ! ldd /usr/local/bin/rollgap | grep -q "not found" && rollgap --version \
 && mkdir /tmp/nginx-check \
 && nginx -t -q -p /tmp/nginx-check/ -c /etc/rollgap/nginx/rollgap.conf -e stderr \
 && rm -rf /tmp/nginx-check

USER 10001:10001
# The single-container mode: nginx listens on 8080 (every interface; ROLLGAP_PROXY_LISTEN), the
# service on 127.0.0.1:8090 only (ROLLGAP_SERVICE_PORT), so `docker run -p 8080:8080` publishes
# the proxy, never the service. `rollgap-container serve` runs the service alone, on the
# container's loopback unless ROLLGAP_BIND says otherwise (behind a proxy of your own).
# The data directory (the default SQLite job store, sqlite:/var/lib/rollgap/jobs.db) is the
# image's own, writable by its user; mount a volume there to keep jobs across containers
# (Kubernetes mounts an emptyDir there and keeps the jobs in PostgreSQL instead). nginx's pid
# file and buffered bodies go to /tmp/nginx (with --read-only, mount a tmpfs on /tmp).
ENV ROLLGAP_DATA_DIR=/var/lib/rollgap
VOLUME ["/var/lib/rollgap"]
EXPOSE 8080
# No curl in the image: the binary checks its own /readyz on the admin port
# (127.0.0.1:$ROLLGAP_ADMIN_PORT, default 8081), in either mode.
HEALTHCHECK --interval=10s --timeout=3s --start-period=5s --retries=3 \
  CMD ["/usr/local/bin/rollgap", "healthcheck"]
ENTRYPOINT ["/usr/local/bin/rollgap-container"]
CMD ["proxied"]
