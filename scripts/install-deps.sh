#!/usr/bin/env bash
# Installs what the project needs from Debian's packages and the npm registry. Idempotent:
# installs only what is missing, so a second run costs a second.
#   scripts/install-deps.sh          build + run dependencies
#   scripts/install-deps.sh --test   also the test tools (gltf-validator, clang's fuzzer runtime,
#                                    chromium for the viewer's browser test)
# Both install web/node_modules (`npm ci --prefix web`): three.js and esbuild, which the build
# bundles into seamd's viewer, and the viewer's test tools (playwright-core, swagger-parser).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

packages=(build-essential cmake ninja-build pkg-config ccache
          libcpp-httplib-dev nlohmann-json3-dev libtinygltf-dev libdraco-dev draco libembree-dev
          libspdlog-dev doctest-dev libeigen3-dev libsuitesparse-dev libmetis-dev libopenblas0-pthread
          curl ca-certificates)
# Node.js may come from elsewhere than Debian (Debian's npm then conflicts with it): only
# install Debian's when the commands are missing. The build bundles the viewer with it.
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)
if [[ "${1:-}" == "--test" ]]; then
  # chromium: Debian's browser, which the viewer's test drives headless (never a download).
  packages+=(clang libclang-rt-14-dev nginx chromium)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# npm test tools (tests/package.json): the glTF-Validator, Kubernetes schemas, a YAML parser.
if [[ "${1:-}" == "--test" && -f "$root/tests/package.json" ]]; then
  for module in gltf-validator kubernetes-models yaml @gltf-transform/core @gltf-transform/extensions @gltf-transform/functions draco3dgltf; do
    if [[ ! -d "$root/tests/node_modules/$module" ]]; then
      echo "installing npm test tools into tests/node_modules"
      (cd "$root/tests" && npm install --no-audit --no-fund --loglevel=error)
      break
    fi
  done
fi

# The viewer's packages (web/package-lock.json): three.js and esbuild for the build, and
# playwright-core (driving Debian's chromium; its own browser download is switched off) and
# swagger-parser for the tests. Reinstalled when the lock file is newer than the install.
if [[ -f "$root/web/package-lock.json" ]] && command -v npm >/dev/null 2>&1; then
  marker="$root/web/node_modules/.package-lock.json"
  if [[ ! -f "$marker" || "$root/web/package-lock.json" -nt "$marker" ]]; then
    echo "installing the viewer's npm packages into web/node_modules"
    PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --prefix "$root/web" --no-audit --no-fund --loglevel=error
  fi
fi
