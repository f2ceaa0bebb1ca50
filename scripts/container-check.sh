#!/usr/bin/env bash
# Builds the seamd image with buildah, runs it with podman, runs scripts/smoke.sh against it,
# checks non-root + HEALTHCHECK + SIGTERM exit 0, and validates docker/compose.yaml and
# docker/k8s/*.yaml offline. Not part of the test command (minutes, needs podman/buildah).
#
#   scripts/container-check.sh [--compose-up] [--no-build] [--clean]
#
# --no-build checks the image built before (localhost/seamd:<version>) instead of building it.
# --compose-up also starts docker/compose.yaml (replicas + nginx) through a podman API
# socket, runs the smoke test through the load balancer, counts which replicas answered
# (from nginx's access log, its stdout), and measures req/s through nginx with 1 and with 2 replicas.
# --clean removes the state folder (images, containers, ~6 GB) and exits.
#
# Prerequisites (installed here when missing, from Debian): podman buildah runc
# golang-github-containernetworking-plugin-dnsname docker-compose debootstrap yamllint curl
# wrk; node + npm for the manifest schemas
# (scripts/install-deps.sh --test).
#
# This machine kind has no container registry and hybrid cgroups, so: the base image is made
# with debootstrap and imported as debian:bookworm-slim; podman runs with runc, cgroupfs and
# the vfs driver; all of that is configured by files in the state folder named through
# CONTAINERS_CONF / CONTAINERS_STORAGE_CONF, nothing under /etc changes. The state folder
# (SEAM_CONTAINER_STATE, default /var/tmp/seam-containers) keeps the images between runs; to
# use them afterwards: `source /var/tmp/seam-containers/env.sh && podman images`.
set -uo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
state="${SEAM_CONTAINER_STATE:-/var/tmp/seam-containers}"
mirror="${DEBIAN_MIRROR:-$(grep -rhoE '^(URIs:|deb) +https?://[^ ]+/debian/?( |$)' /etc/apt/sources.list /etc/apt/sources.list.d/ 2>/dev/null | head -1 | awk '{print $2}')}"
mirror="${mirror:-http://deb.debian.org/debian}"
version="$(sed -n 's/^project(seam_service VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)"
image="localhost/seamd:$version"
port="${SEAM_CHECK_PORT:-18080}"
compose_up=0
build=1
for arg in "$@"; do
  case "$arg" in
    --compose-up) compose_up=1 ;;
    --no-build) build=0 ;;
    --clean)
      if [[ -d "$state" ]]; then
        CONTAINERS_CONF="$state/containers.conf" CONTAINERS_STORAGE_CONF="$state/storage.conf" \
          podman system reset --force > /dev/null 2>&1
        rm -rf "$state"
      fi
      echo "container-check: removed $state"; exit 0 ;;
    *) echo "usage: scripts/container-check.sh [--compose-up] [--clean]"; exit 2 ;;
  esac
done
failures=0
step() { printf '\n== %s\n' "$*"; }
ok() { printf 'ok    %s\n' "$*"; }
bad() { printf 'FAIL  %s\n' "$*"; failures=$((failures + 1)); }

mkdir -p "$state/storage" "$state/run"
cat > "$state/containers.conf" <<EOF
[containers]
default_ulimits = ["nofile=1024:1024", "nproc=1024:1024"]
[engine]
cgroup_manager = "cgroupfs"
runtime = "runc"
events_logger = "file"
EOF
cat > "$state/storage.conf" <<EOF
[storage]
driver = "vfs"
graphroot = "$state/storage"
runroot = "$state/run"
EOF
export CONTAINERS_CONF="$state/containers.conf" CONTAINERS_STORAGE_CONF="$state/storage.conf"
printf 'export CONTAINERS_CONF=%q CONTAINERS_STORAGE_CONF=%q\n' "$CONTAINERS_CONF" "$CONTAINERS_STORAGE_CONF" > "$state/env.sh"

missing=()
# golang-github-containernetworking-plugin-dnsname: podman 4.3's CNI backend resolves compose
# service names (nginx's upstream "seamd") only with it.
for pkg in podman buildah runc golang-github-containernetworking-plugin-dnsname docker-compose debootstrap yamllint curl wrk; do
  dpkg-query -W -f='${Status}' "$pkg" 2> /dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if ((${#missing[@]})); then
  step "installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq && DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq \
    --no-install-recommends "${missing[@]}" > "$state/apt.log" 2>&1 || { bad "apt-get install failed ($state/apt.log)"; exit 2; }
fi

# --- base image ---------------------------------------------------------------------------
step "base image debian:bookworm-slim (debootstrap, no registry)"
if podman image exists docker.io/library/debian:bookworm-slim; then
  ok "already imported"
else
  t0=$SECONDS
  rm -rf "$state/rootfs"
  if debootstrap --variant=minbase bookworm "$state/rootfs" "$mirror" > "$state/debootstrap.log" 2>&1; then
    tar -C "$state/rootfs" -c . | podman import - localhost/debian:bookworm-slim > /dev/null &&
      podman tag localhost/debian:bookworm-slim docker.io/library/debian:bookworm-slim &&
      ok "debootstrap + import in $((SECONDS - t0)) s"
    rm -rf "$state/rootfs"
  else
    bad "debootstrap failed: tail $state/debootstrap.log"; tail -5 "$state/debootstrap.log"; exit 1
  fi
fi

# --- build --------------------------------------------------------------------------------
if (( build )); then
  step "buildah build (multi-stage Dockerfile)"
  t0=$SECONDS
  # npm ci inside the build reaches the registry through this machine's TLS set-up: its CA
  # bundle goes in as a build secret (not kept in any layer).
  ca="${NODE_EXTRA_CA_CERTS:-$(npm config get cafile 2> /dev/null || true)}"
  [[ -s "$ca" ]] || ca=/etc/ssl/certs/ca-certificates.crt
  secret=()
  [[ -s "$ca" ]] && secret=(--secret "id=npm_ca,src=$ca")
  if buildah build --isolation chroot --pull=never --format docker --layers "${secret[@]}" -t "$image" . > "$state/build.log" 2>&1; then
    ok "image built in $((SECONDS - t0)) s: $(podman image inspect "$image" --format '{{.Size}}' | awk '{printf "%.1f MB", $1/1e6}')"
  else
    bad "buildah build failed ($state/build.log):"; tail -20 "$state/build.log"; exit 1
  fi
else
  step "image $image (built before; --no-build)"
  podman image exists "$image" && ok "$image is there" || { bad "no image $image: run without --no-build"; exit 1; }
fi
user=$(podman image inspect "$image" --format '{{.Config.User}}')
health=$(podman image inspect "$image" --format '{{json .Config.Healthcheck}}' 2>/dev/null)
exposed=$(podman image inspect "$image" --format '{{json .Config.ExposedPorts}}')
[[ "$user" == 10001* ]] && ok "runs as non-root user $user" || bad "image user is '$user'"
[[ "$health" == *healthz* ]] && ok "HEALTHCHECK: $health" || bad "no HEALTHCHECK in the image config"
[[ "$exposed" == *8080* ]] && ok "EXPOSE $exposed" || bad "8080 not exposed"

# --- run + smoke --------------------------------------------------------------------------
step "podman run -p 127.0.0.1:$port:8080 + scripts/smoke.sh"
podman rm -f seamd-check > /dev/null 2>&1
if ! podman run -d --name seamd-check -p "127.0.0.1:$port:8080" "$image" > /dev/null 2> "$state/run.err"; then
  bad "podman run failed: $(cat "$state/run.err")"; exit 1
fi
for _ in $(seq 1 100); do curl -fsS "http://127.0.0.1:$port/healthz" > /dev/null 2>&1 && break; sleep 0.1; done
podman run --rm --entrypoint /bin/sh "$image" -c 'seamd sample --out /tmp/sample.glb > /dev/null && cat /tmp/sample.glb' \
  > "$state/sample.glb" 2> "$state/sample.err" || bad "seamd sample in the image failed: $(cat "$state/sample.err")"
if SAMPLE="$state/sample.glb" "$here/scripts/smoke.sh" "http://127.0.0.1:$port"; then
  ok "smoke test passed against the container"
else
  bad "smoke test failed against the container"
fi
uid=$(podman exec seamd-check id -u 2>/dev/null)
[[ "$uid" == 10001 ]] && ok "process uid in the container: $uid" || bad "process uid is '$uid'"
if podman healthcheck run seamd-check > /dev/null 2>&1; then ok "podman healthcheck run: healthy"; else bad "podman healthcheck run failed"; fi
echo "      last log lines:"; podman logs seamd-check 2>&1 | tail -3 | cut -c1-220 | sed 's/^/      /'
podman stop -t 40 seamd-check > /dev/null
code=$(podman inspect seamd-check --format '{{.State.ExitCode}}')
[[ "$code" == 0 ]] && ok "SIGTERM (podman stop): exit code 0" || bad "exit code after SIGTERM: $code"
podman rm -f seamd-check > /dev/null 2>&1

# --- offline validation ------------------------------------------------------------------
step "compose + Kubernetes manifests, offline"
if docker-compose -f docker/compose.yaml config -q; then ok "docker-compose config -q docker/compose.yaml"; else bad "compose file invalid"; fi
lint_conf='{extends: default, rules: {line-length: {max: 120}, document-start: disable, truthy: {check-keys: false}}}'
if yamllint -d "$lint_conf" docker/compose.yaml docker/k8s/*.yaml; then ok "yamllint docker/compose.yaml docker/k8s/*.yaml"; else bad "yamllint"; fi
if [[ -d tests/node_modules/kubernetes-models ]] || (cd tests && npm install --no-audit --no-fund --loglevel=error > /dev/null 2>&1); then
  if node tests/validate_k8s.mjs docker/k8s/*.yaml | sed 's/^/      /'; then
    ok "Kubernetes manifests valid (API schemas, npm kubernetes-models)"
  else
    bad "Kubernetes manifest validation"
  fi
else
  bad "npm install in tests/ failed: manifests not validated against the schemas"
fi

# --- optional: compose up ------------------------------------------------------------------
if (( compose_up )); then
  step "docker-compose up: replicas behind nginx (podman API socket)"
  sock="$state/podman.sock"
  podman system service --time=0 "unix://$sock" > "$state/service.log" 2>&1 &
  svc=$!
  for _ in $(seq 1 50); do [[ -S "$sock" ]] && break; sleep 0.1; done
  export DOCKER_HOST="unix://$sock"
  compose=(docker-compose --compatibility -f docker/compose.yaml)
  glb="$state/sample.glb"
  # The seamd image is the one built above; only the nginx image is built here (a build through
  # the API socket would not reuse buildah's layers and take the whole compile again).
  "${compose[@]}" build lb > "$state/compose.log" 2>&1 || bad "docker-compose build lb failed ($state/compose.log)"
  for replicas in 3 1 2; do
    if ! "${compose[@]}" up -d --no-build --scale "seamd=$replicas" >> "$state/compose.log" 2>&1; then
      bad "docker-compose up ($replicas replicas) failed"; tail -20 "$state/compose.log"; break
    fi
    up=0
    for _ in $(seq 1 150); do curl -fsS "http://127.0.0.1:8080/healthz" > /dev/null 2>&1 && up=1 && break; sleep 0.2; done
    (( up )) || { bad "nginx did not answer with $replicas replicas"; continue; }
    sleep 2  # every replica up
    if (( replicas == 3 )); then
      SAMPLE="$glb" "$here/scripts/smoke.sh" "http://127.0.0.1:8080" && ok "smoke through nginx" || bad "smoke through nginx"
      for _ in $(seq 1 30); do curl -fsS -o /dev/null -F "mesh=@$glb" 'http://127.0.0.1:8080/seam?method=mst&uv=none'; done
      lb=$(podman ps --format '{{.Names}}' | grep -m1 '_lb_')
      answered=$(podman logs "$lb" 2> /dev/null | grep '"uri":"/seam' |
                 grep -o '"upstream":"[^"]*"' | sort | uniq -c | sed 's/"upstream"://')
      distinct=$(printf '%s\n' "$answered" | grep -c . || true)
      echo "      seam requests per upstream replica (nginx access log):"; printf '%s\n' "$answered" | sed 's/^/      /'
      (( distinct == 3 )) && ok "round-robin: all 3 replicas answered seam requests" || bad "round-robin: $distinct of 3 replicas answered"
    else
      cat > "$state/post.lua" <<LUA
local f = assert(io.open("$glb", "rb")); wrk.method = "POST"; wrk.body = f:read("*a"); f:close()
wrk.headers["Content-Type"] = "model/gltf-binary"
LUA
      rps=$(wrk -t2 -c8 -d15s -s "$state/post.lua" 'http://127.0.0.1:8080/seam?method=mst&uv=none' 2>&1 | awk '/Requests\/sec/ {print $2}')
      ok "through nginx with $replicas replica(s) of 2 workers: ${rps:-?} req/s (wrk, 8 connections, 15 s, sample, mst)"
    fi
  done
  "${compose[@]}" down > /dev/null 2>&1
  kill "$svc" 2> /dev/null
fi

echo
if (( failures > 0 )); then echo "container-check: $failures failure(s)"; exit 1; fi
echo "container-check: all checks passed (images in $state: source $state/env.sh && podman images;"
echo "remove them with scripts/container-check.sh --clean)"
