#!/usr/bin/env bash
# Builds the seamd image with buildah, runs it with podman, runs scripts/smoke.sh against it,
# checks non-root + HEALTHCHECK + SIGTERM exit 0, and validates docker/compose.yaml and
# docker/k8s/*.yaml offline. Not part of the test command (minutes, needs podman/buildah).
#
#   scripts/container-check.sh [--compose-up]
#
# --compose-up also starts docker/compose.yaml (3 replicas + nginx) through a podman API
# socket, runs the smoke test through the load balancer and shows the round-robin.
# Facts this follows: ../shared/notes/containers.md (no registry: debootstrap base image;
# runc + cgroupfs + vfs through CONTAINERS_CONF / CONTAINERS_STORAGE_CONF; nothing in /etc).
set -uo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
state="${SEAM_CONTAINER_STATE:-/var/tmp/seam-containers}"
mirror="${DEBIAN_MIRROR:-$(grep -rhoE '^(URIs:|deb) +https?://[^ ]+/debian/?( |$)' /etc/apt/sources.list /etc/apt/sources.list.d/ 2>/dev/null | head -1 | awk '{print $2}')}"
mirror="${mirror:-http://deb.debian.org/debian}"
image="localhost/seamd:test"
port="${SEAM_CHECK_PORT:-18080}"
compose_up=0
[[ "${1:-}" == "--compose-up" ]] && compose_up=1
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

for tool in podman buildah docker-compose debootstrap yamllint curl; do
  command -v "$tool" > /dev/null || { echo "container-check: $tool missing (apt-get install podman buildah docker-compose debootstrap yamllint curl)"; exit 2; }
done

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
step "buildah build (multi-stage Dockerfile)"
t0=$SECONDS
if buildah build --isolation chroot --pull=never --format docker --layers -t "$image" . > "$state/build.log" 2>&1; then
  ok "image built in $((SECONDS - t0)) s: $(podman image inspect "$image" --format '{{.Size}}' | awk '{printf "%.1f MB", $1/1e6}')"
else
  bad "buildah build failed ($state/build.log):"; tail -20 "$state/build.log"; exit 1
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
tools="$here/.cache/node-tools"
if [[ ! -d "$tools/node_modules/kubernetes-models" ]] && command -v npm > /dev/null; then
  npm install --silent --prefix "$tools" kubernetes-models js-yaml > /dev/null 2>&1 || true
fi
if [[ -d "$tools/node_modules/kubernetes-models" ]]; then
  if NODE_PATH="$tools/node_modules" node - docker/k8s/*.yaml <<'JS'
const fs = require('fs');
const yaml = require('js-yaml');
const kinds = {
  Deployment: () => require('kubernetes-models/apps/v1/Deployment').Deployment,
  Service: () => require('kubernetes-models/v1/Service').Service,
  HorizontalPodAutoscaler: () => require('kubernetes-models/autoscaling/v2/HorizontalPodAutoscaler').HorizontalPodAutoscaler,
};
let errors = 0;
for (const file of process.argv.slice(2)) {
  for (const doc of yaml.loadAll(fs.readFileSync(file, 'utf8'))) {
    if (!doc) continue;
    try {
      if (!kinds[doc.kind]) throw new Error('no schema for kind ' + doc.kind);
      new (kinds[doc.kind]())(doc).validate();
      console.log(`      ${file}: ${doc.kind} ${doc.metadata.name} valid`);
    } catch (e) { errors++; console.log(`      ${file}: ${doc.kind}: ${e.message}`); }
  }
}
process.exit(errors ? 1 : 0);
JS
  then ok "Kubernetes manifests valid (kubernetes-models schemas)"; else bad "Kubernetes manifest validation"; fi
else
  echo "      (kubernetes-models not installable here: manifests checked by yamllint only)"
fi

# --- optional: compose up ------------------------------------------------------------------
if (( compose_up )); then
  step "docker-compose up: 3 replicas behind nginx (podman API socket)"
  sock="$state/podman.sock"
  podman system service --time=0 "unix://$sock" > "$state/service.log" 2>&1 &
  svc=$!
  for _ in $(seq 1 50); do [[ -S "$sock" ]] && break; sleep 0.1; done
  export DOCKER_HOST="unix://$sock"
  podman tag "$image" localhost/seamd:latest
  if docker-compose --compatibility -f docker/compose.yaml up -d --build > "$state/compose.log" 2>&1; then
    for _ in $(seq 1 100); do curl -fsS "http://127.0.0.1:8080/healthz" > /dev/null 2>&1 && break; sleep 0.2; done
    SAMPLE="$state/sample.glb" "$here/scripts/smoke.sh" "http://127.0.0.1:8080" && ok "smoke through nginx" || bad "smoke through nginx"
    echo "      replicas: $(podman ps --format '{{.Names}}' | grep -c seamd_) running"
  else
    bad "docker-compose up failed"; tail -20 "$state/compose.log"
  fi
  docker-compose --compatibility -f docker/compose.yaml down > /dev/null 2>&1
  kill "$svc" 2> /dev/null
fi

echo
if (( failures > 0 )); then echo "container-check: $failures failure(s)"; exit 1; fi
echo "container-check: all checks passed"
