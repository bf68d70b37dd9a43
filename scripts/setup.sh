#!/usr/bin/env bash
# Installs what clothfit needs from Debian 12's packages (only what is
# missing), then configures and builds into build/. Idempotent: a second run
# installs nothing and rebuilds only what changed. Run as root (or with sudo
# available) on a fresh machine.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake pkg-config
  libceres-dev libeigen3-dev libglm-dev nlohmann-json3-dev
  libopencv-dev libopenimageio-dev openimageio-tools libopenexr-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-scipy  # the bench's peer (benchmarks/peer/); optional at run time
  python3-distributed  # scripts/dask_fit.py (docs/scale.md) and its test
  clang libclang-rt-14-dev  # libFuzzer for scripts/fuzz.sh (fuzz/)
  chromium  # headless browser tests (tests/browser_render_test.cc)
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
    missing+=("$p")
done
# Node.js and npm for the tests' web tools (web/: the Khronos glTF
# validator, three.js): Debian's, unless a node and npm are there already
# (a NodeSource nodejs bundles npm and conflicts with Debian's npm).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  missing+=(nodejs npm)
fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q \
    --no-install-recommends "${missing[@]}"
fi

# The tests' npm packages (web/package.json), at the versions of
# web/package-lock.json; again only when the lock file changed.
if ! cmp -s web/package-lock.json web/node_modules/.clothfit-lock.json; then
  echo "setup: installing web/'s npm packages"
  (cd web && npm ci --no-audit --no-fund --loglevel=error &&
    cp package-lock.json node_modules/.clothfit-lock.json)
fi

BUILD_DIR=${BUILD_DIR:-build}
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD_DIR" -j"$(nproc)"
