#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang, build-fuzz/) and runs each for
# a bounded time, starting from the seeds in fuzz/corpus/<target>/ and the
# regressions in fuzz/regressions/<target>/. Fails on the first crash,
# sanitizer report or contract violation; the input is saved as
# build-fuzz/artifacts/<target>-crash-<sha1> (add it to
# fuzz/regressions/<target>/ once fixed; docs/reliability.md).
#   bash scripts/fuzz.sh            # 15 s per target (CI)
#   FUZZ_SECONDS=300 bash scripts/fuzz.sh mask
set -euo pipefail
cd "$(dirname "$0")/.."

FUZZ_DIR=${FUZZ_DIR:-build-fuzz}
SECONDS_PER_TARGET=${FUZZ_SECONDS:-15}
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(table params image_stack mask)

if [ ! -f "$FUZZ_DIR/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$FUZZ_DIR" -DCMAKE_BUILD_TYPE=Release \
    -DCLOTHFIT_FUZZ=ON -DCLOTHFIT_BUILD_TESTS=OFF \
    -DCLOTHFIT_BUILD_BENCHMARKS=OFF
fi
cmake --build "$FUZZ_DIR" -j"$(nproc)" \
  --target "${TARGETS[@]/#/fuzz_}"

source scripts/sanitizers/env.sh
mkdir -p "$FUZZ_DIR/artifacts"
for target in "${TARGETS[@]}"; do
  # New inputs go to the build tree's corpus (kept between runs), never to
  # the seed folders in the repository.
  work="$FUZZ_DIR/corpus/$target"
  mkdir -p "$work"
  seeds=(fuzz/corpus/"$target")
  [ -d fuzz/regressions/"$target" ] && seeds+=(fuzz/regressions/"$target")
  log="$FUZZ_DIR/artifacts/$target.log"
  echo "fuzz: $target for ${SECONDS_PER_TARGET} s (log: $log)"
  status=0
  "$FUZZ_DIR/fuzz/fuzz_$target" -max_total_time="$SECONDS_PER_TARGET" \
    -print_final_stats=1 -artifact_prefix="$FUZZ_DIR/artifacts/$target-" \
    "$work" "${seeds[@]}" >"$log" 2>&1 || status=$?
  grep -E "^(stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)|INFO: seed corpus)" "$log" || true
  if [ "$status" -ne 0 ]; then
    tail -n 60 "$log" >&2
    echo "fuzz: $target FAILED (exit $status); the input is in $FUZZ_DIR/artifacts/" >&2
    exit 1
  fi
done
