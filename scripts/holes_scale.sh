#!/usr/bin/env bash
# Scale of `clothfit holes analyze --distances`: wall time and peak
# resident memory (GNU time) on random masks of 1024^2, 2048^2 and 4096^2
# texels (half opaque, uniform noise), the median of RUNS runs with the
# smallest and largest, for build/apps/clothfit-full and, when given, a
# second clothfit-full (e.g. one built from an older commit) on the same
# masks in the same run, the two alternating; their files must be
# identical, byte for byte (cmp). Prints a Markdown table. Results:
# docs/bench.md.
#   bash scripts/holes_scale.sh [OTHER_CLOTHFIT_FULL]
# Environment: SIZES ("1024 2048 4096"), RUNS (3), HOLES_SCALE_DIR (the
# masks and outputs; a temporary folder, removed at the end, by default).
# Needs GNU time (apt-get install time) and oiiotool (openimageio-tools);
# about 1 GB of memory and 0.5 GB of disk at 4096^2 (9 GB of memory with
# a clothfit-full from before commit c735b1a as the other).
set -euo pipefail
cd "$(dirname "$0")/.."
CURRENT="${BUILD_DIR:-build}/apps/clothfit-full"
OTHER="${1:-}"
OTHER_NAME="${1:-}"
SIZES="${SIZES:-1024 2048 4096}"
RUNS="${RUNS:-3}"
for tool in /usr/bin/time oiiotool "$CURRENT" ${OTHER:+"$OTHER"}; do
  if ! command -v "$tool" >/dev/null; then
    echo "holes_scale: $tool not found (GNU time: apt-get install time;" \
      "oiiotool: openimageio-tools; clothfit-full: cmake --build build" \
      "--target clothfit-full)" >&2
    exit 2
  fi
done
CURRENT="$(realpath "$CURRENT")"
if [ -n "$OTHER" ]; then OTHER="$(realpath "$(command -v "$OTHER")")"; fi
if [ -n "${HOLES_SCALE_DIR:-}" ]; then
  mkdir -p "$HOLES_SCALE_DIR"
  DIR="$(realpath "$HOLES_SCALE_DIR")"
else
  DIR="$(mktemp -d)"
  trap 'rm -rf "$DIR"' EXIT
fi

# run NAME BINARY MASK: one analysis in $DIR/NAME/, "wall_s peak_kib"
# appended to $DIR/NAME.times.
run() {
  local name=$1 binary=$2 mask=$3
  mkdir -p "$DIR/$name"
  (cd "$DIR/$name" &&
    /usr/bin/time -f "%e %M" -o time.txt "$binary" holes analyze \
      --mask "$mask" --out c.exr --distances d.exr >log.txt 2>&1)
  cat "$DIR/$name/time.txt" >>"$DIR/$name.times"
}

# stats FILE COLUMN SCALE FORMAT: "median (min-max)" of a column times
# SCALE, each printed with FORMAT.
stats() {
  awk -v c="$2" -v s="$3" '{ print $c * s }' "$1" | sort -g | awk -v f="$4" '
    { v[NR] = $1 }
    END { printf f " (" f "-" f ")", v[int((NR + 1) / 2)], v[1], v[NR] }'
}

echo "| mask | clothfit-full | wall s, median (min-max) | peak RSS MiB, median (min-max) |"
echo "|---|---|---|---|"
for size in $SIZES; do
  mask="$DIR/mask$size.png"
  oiiotool --pattern noise:type=uniform:min=0:max=1:seed="$size" \
    "${size}x${size}" 1 -d uint8 -o "$mask"
  rm -f "$DIR"/*"$size".times
  for ((i = 0; i < RUNS; ++i)); do
    if [ -n "$OTHER" ]; then run "other$size" "$OTHER" "$mask"; fi
    run "current$size" "$CURRENT" "$mask"
  done
  if [ -n "$OTHER" ]; then
    for f in c.exr c.exr.json d.exr d.exr.json; do
      if ! cmp -s "$DIR/other$size/$f" "$DIR/current$size/$f"; then
        echo "holes_scale: $size^2: $f differs between $OTHER and $CURRENT" >&2
        exit 1
      fi
    done
    echo "| ${size}^2 | $OTHER_NAME | $(stats "$DIR/other$size.times" 1 1 %.1f) |" \
      "$(stats "$DIR/other$size.times" 2 0.0009765625 %.0f) |"
  fi
  echo "| ${size}^2 | ${BUILD_DIR:-build} |" \
    "$(stats "$DIR/current$size.times" 1 1 %.1f) |" \
    "$(stats "$DIR/current$size.times" 2 0.0009765625 %.0f) |"
done
