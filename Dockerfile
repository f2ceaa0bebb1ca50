# seamd: the seam service. Multi-stage: build on Debian bookworm, run on bookworm-slim as a
# non-root user. Build: buildah build --format docker --pull=never -t localhost/seamd:0.1.0 .
# (scripts/container-check.sh makes the debian:bookworm-slim base and the podman settings this
# needs here; after it, `source /var/tmp/seam-containers/env.sh` first. --format docker keeps
# the HEALTHCHECK).

FROM debian:bookworm-slim AS build
RUN apt-get update \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
      g++ cmake ninja-build pkg-config nodejs npm \
      libcpp-httplib-dev nlohmann-json3-dev libtinygltf-dev libdraco-dev libembree-dev libspdlog-dev libeigen3-dev \
      libsuitesparse-dev libmetis-dev \
 && rm -rf /var/lib/apt/lists/*
WORKDIR /src
COPY CMakeLists.txt ./
COPY core core
COPY api api
COPY server server
# The viewer: three.js and esbuild from npm (pinned by web/package-lock.json), bundled at build
# time and embedded into seamd; no browser is downloaded.
COPY web/package.json web/package-lock.json web/build.mjs web/
COPY web/src web/src
# Behind a TLS-intercepting proxy, pass its CA bundle as a build secret (never stored in a
# layer): --secret id=npm_ca,src=/etc/ssl/certs/ca-certificates.crt (container-check.sh does).
RUN --mount=type=secret,id=npm_ca \
    if [ -s /run/secrets/npm_ca ]; then export NODE_EXTRA_CA_CERTS=/run/secrets/npm_ca; fi \
 && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --prefix web --no-audit --no-fund --loglevel=error
RUN cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSEAM_WERROR=ON \
      -DSEAM_BUILD_TESTS=OFF -DSEAM_BUILD_SERVER=ON -DSEAM_BUILD_BENCH=OFF \
 && cmake --build build --target seamd -j "$(nproc)" \
 && strip build/server/seamd \
 && ./build/server/seamd --help > /dev/null

FROM debian:bookworm-slim AS runtime
# Runtime libraries only (httplib, spdlog and CHOLMOD are shared libraries in Debian; Draco is
# linked statically); OpenBLAS as the BLAS behind CHOLMOD (seamd runs it single-threaded);
# curl for the HEALTHCHECK.
RUN apt-get update \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
      libcpp-httplib0.11 libspdlog1.10 libcholmod3 libmetis5 libopenblas0-pthread libembree3-3 curl ca-certificates \
 && rm -rf /var/lib/apt/lists/* \
 && useradd --system --uid 10001 --user-group --no-create-home --shell /usr/sbin/nologin seamd
COPY --from=build /src/build/server/seamd /usr/local/bin/seamd
USER 10001:10001
# OpenBLAS (behind CHOLMOD) starts no thread pool of its own: one request per worker per core.
# With it set, seamd does not need to execute itself again (api/process_env.h).
ENV OPENBLAS_NUM_THREADS=1 \
    SEAMD_BIND=0.0.0.0 \
    SEAMD_PORT=8080 \
    SEAMD_LOG_LEVEL=info
EXPOSE 8080
STOPSIGNAL SIGTERM
HEALTHCHECK --interval=10s --timeout=3s --start-period=5s --retries=3 \
  CMD curl -fsS http://127.0.0.1:8080/healthz || exit 1
ENTRYPOINT ["/usr/local/bin/seamd"]
