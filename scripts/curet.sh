#!/usr/bin/env bash
# Fits the thread and cloth models to every CUReT fabric table in
# ../shared/data/curet and writes docs/curet.md: per sample and model, the
# relative RMS error and the fit time (the solver's own wall time, one
# core). One channel, arbitrary scale: every fit also fits a scale factor.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
CLOTHFIT="${BUILD_DIR:-build}/apps/clothfit"
DATA="${CURET_DIR:-../shared/data/curet}"
OUT=data_synthetic/out/curet
DOC=docs/curet.md
mkdir -p "$OUT"

# fit NAME ARGS... -> "relative_rms seconds" from the fit's summary; the
# error gets a dagger when the fit exited non-zero (not converged). Every
# residual weighs alike (--noise absolute): that fit minimises the metric
# reported, RMS(model - data) / RMS(data).
fit() {
  local name=$1
  shift
  local log="$OUT/$name.log" mark=""
  "$CLOTHFIT" fit "$@" --fit-scale --noise absolute --out "$OUT/$name.json" >"$log" 2>&1 || mark="†"
  awk -v m="$mark" '/^fit:/ {t=$(NF-1)} /^cost/ {r=$7} END {printf "%s%s %s", r, m, t}' "$log"
}

tmp=$(mktemp)
for table in "$DATA"/curet_*.csv; do
  sample=$(basename "$table" .csv)
  read -r t_rms t_sec <<<"$(fit "$sample.thread" --model thread --data "$table")"
  read -r c_rms c_sec <<<"$(fit "$sample.cloth" --model cloth --data "$table" \
    --preset linen_plain --generic-start)"
  read -r x_rms x_sec <<<"$(fit "$sample.cloth_ext" --model cloth --data "$table" \
    --preset linen_plain --generic-start \
    --free albedo,kd,gamma_s_deg,gamma_v_deg,eta,offset_scale)"
  read -r s_rms s_sec <<<"$(fit "$sample.satin" --model cloth --data "$table" \
    --preset polyester_satin_charmeuse --generic-start)"
  # The best constant's relative RMS: sqrt(sum (y - mean)^2 / sum y^2).
  const=$(awk -F, '/^[0-9]/ {s += $5; q += $5 * $5; n++}
    END {m = s / n; printf "%.4g", sqrt((q - n * m * m) / q)}' "$table")
  printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "${sample#curet_}" \
    "$const" "$t_rms" "$t_sec" "$c_rms" "$c_sec" "$x_rms" "$x_sec" "$s_rms" "$s_sec" >>"$tmp"
done

{
  cat <<'MD'
# Fits to real measurements: CUReT fabrics

Produced by `bash scripts/curet.sh` (do not edit by hand). Data: the eleven
fabric tables in `../shared/data/curet/` (205 geometries each, one channel,
arbitrary scale; see its README). Every fit also fits a scale factor
(`--fit-scale`). Relative RMS = RMS(model - data) / RMS(data); the
"constant" column is the best constant's score, the bar a model must beat. Time: the fit's own wall
time on one core of the development machine (2 cores, shared), including
the start search; single runs, so expect +-20 % noise. † marks a fit that
exited with status 1: it stopped with a parameter at a search limit (the
model wants a width or eta outside its range) and is not a converged fit;
the logs beside the results in `data_synthetic/out/curet/` say which.

Models:
- **thread**: the thread BSDF alone (surface frame read as the thread
  frame), default multi-start;
- **cloth plain**: plain weave (the `linen_plain` weave: two threads, u and
  v, coverage 0.33 each, tangent offsets -25/25), generic start, default
  free set (per thread kd, gamma_s_deg, gamma_v_deg, albedo);
- **cloth plain+**: the same with eta and the tangent-offset magnitude
  (offset_scale) free as well;
- **cloth satin**: the `polyester_satin_charmeuse` weave, default free set.

| sample | constant rel. RMS | thread rel. RMS | s | cloth plain rel. RMS | s | cloth plain+ rel. RMS | s | cloth satin rel. RMS | s |
|---|---|---|---|---|---|---|---|---|---|
MD
  cat "$tmp"
  cat <<'MD'

Reading: with the weave's tangent offsets fixed, the microcylinder models
do not beat the best constant on most samples: the strong grazing
(forward-scattering) peaks of these fabrics need highlights where the fixed
tangent distribution cannot put them, and the isotropic term of the thread
model falls off as 1/(cos theta_i + cos theta_o) rather than staying flat.
Freeing the tangent-offset magnitude and eta ("plain+") roughly halves the
error and beats the constant on every sample; a satin-like distribution of
several tilts also helps. These are fits of a 2-thread, 2-sample weave to
205 geometries; an honest model of these fabrics needs their measured weave.
MD
} >"$DOC"
rm -f "$tmp"
echo "wrote $DOC"
