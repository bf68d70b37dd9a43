#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs ctest; then
# the same suite under ASan+UBSan (scripts/sanitize.sh, build-asan/) and
# each libFuzzer target for 15 s (scripts/fuzz.sh, build-fuzz/). Fails if any
# part fails. SANITIZE=0 or FUZZ=0 skips those parts (local use; CI runs all).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)" "$@"
if [ "${SANITIZE:-1}" != 0 ]; then bash scripts/sanitize.sh "$@"; fi
if [ "${FUZZ:-1}" != 0 ]; then bash scripts/fuzz.sh; fi
