#!/usr/bin/env bash
# Runs the README's first example (the block between <!-- first-example -->
# and <!-- /first-example -->) as a user would, from a copy of the
# repository's root layout: build/apps holds the clothfit executables.
#   readme_example_test.sh README.md APPS_DIR WORK_DIR
set -euo pipefail
readme=$1 apps=$2 work=$3
rm -rf "$work" && mkdir -p "$work/build"
ln -s "$apps" "$work/build/apps"
script=$(awk '/<!-- first-example -->/{on=1; next} /<!-- \/first-example -->/{on=0}
              on && !/^```/' "$readme")
[ -n "$script" ] || { echo "no first example in $readme" >&2; exit 1; }
cd "$work"
bash -euo pipefail -c "$script"
# What the example says it makes.
for f in satin.csv truth.json satin.fit.json satin.eval.csv \
         figures/scatter.png figures/polar.png satin.html satin.glb satin.glsl; do
  [ -s "first/$f" ] || { echo "the example did not write $f" >&2; exit 1; }
done
echo "README example: every step exited 0 and wrote its file"
