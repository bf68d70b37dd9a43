#!/usr/bin/env bash
# The main job end to end: installs what is missing, builds, writes a
# synthetic measurement table from a preset (2 % noise), fits the cloth
# model to it from a generic start (only the weave is known), and prints the
# recovered parameters beside the true ones. Then the same for one thread.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
CLOTHFIT="$BUILD_DIR/apps/clothfit"
OUT=data_synthetic/out
mkdir -p "$OUT"
PRESET=${1:-polyester_satin_charmeuse}

echo "== cloth: $PRESET, 3000 direction pairs, 2 % noise"
"$CLOTHFIT" preset "$PRESET" --out "$OUT/$PRESET.true.json"
"$CLOTHFIT" synth --preset "$PRESET" --rows 3000 --noise 0.02 --seed 1 \
  --out "$OUT/$PRESET.csv"
"$CLOTHFIT" fit --model cloth --data "$OUT/$PRESET.csv" --preset "$PRESET" \
  --generic-start --truth "$OUT/$PRESET.true.json" --out "$OUT/$PRESET.fit.json"

echo
echo "== thread: the flat polyester thread, 3000 pairs, 2 % noise"
cat > "$OUT/thread.true.json" <<'JSON'
{"model": "thread", "eta": 1.539, "kd": 0.1, "gamma_s_deg": 2.5,
 "gamma_v_deg": 5.0, "albedo": [0.035, 0.01295, 0.0105]}
JSON
"$CLOTHFIT" synth --params "$OUT/thread.true.json" --rows 3000 --noise 0.02 \
  --seed 2 --out "$OUT/thread.csv"
"$CLOTHFIT" fit --model thread --data "$OUT/thread.csv" \
  --truth "$OUT/thread.true.json" --out "$OUT/thread.fit.json"
echo
echo "results: $OUT/$PRESET.fit.json, $OUT/thread.fit.json"
