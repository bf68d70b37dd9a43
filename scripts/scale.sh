#!/usr/bin/env bash
# Scale check: a 10-million-row measurement table, read and
# fitted. Writes a virtual-gonioreflectometer table of 50 x 50 texels x
# 64 x 64 (light, view) pairs (10.24 M rows, ~2.4 GB of CSV) under
# data_synthetic/out/scale (or $SCALE_DIR), then fits Lafortune lobes
# with lookup tables and mip levels to it and prints the wall time and
# peak memory of each step (GNU time: `apt-get install time`). Needs
# ~6 GB of memory and ~3 GB of disk; takes a few minutes on 2 cores.
# Results: docs/reliability.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
CLOTHFIT="${BUILD_DIR:-build}/apps/clothfit"
DIR="${SCALE_DIR:-data_synthetic/out/scale}"
TEXELS="${SCALE_TEXELS:-50}"
mkdir -p "$DIR"
if [ ! -x /usr/bin/time ]; then
  echo "scale: needs GNU time (/usr/bin/time; apt-get install time)" >&2
  exit 2
fi
measure() {  # measure NAME COMMAND... -> "NAME: W s wall, P MB peak"
  local name=$1
  shift
  /usr/bin/time -f "%e %M" -o "$DIR/$name.time" "$@" >"$DIR/$name.log" 2>&1
  read -r wall kb <"$DIR/$name.time"
  echo "$name: ${wall} s wall, $((kb / 1024)) MB peak"
}
TABLE="$DIR/gonio_${TEXELS}.csv"
if [ ! -f "$TABLE" ]; then
  measure synth "$CLOTHFIT" synth --gonio plain --texels "$TEXELS" \
    --directions 8 --out "$TABLE"
fi
rows=$(($(grep -vc '^#' "$TABLE") - 1))
echo "table: $TABLE, $rows rows, $(du -m "$TABLE" | cut -f1) MB"
measure fit "$CLOTHFIT" fit --model lafortune --data "$TABLE" --lobes 2 \
  --mip --out "$DIR/gonio_${TEXELS}.exr"
grep -E "^lafortune fits|level 0" "$DIR/fit.log"
