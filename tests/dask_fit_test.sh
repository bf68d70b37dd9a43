#!/usr/bin/env bash
# scripts/dask_fit.py on a LocalCluster of 2 worker processes (docs/scale.md):
# a 32 x 32-texel gonio stack in 4 blocks of 16 equals one clothfit fit of
# the whole stack, bit for bit; the first attempt at one block kills its
# own worker process mid-task, and Dask runs the block again on the new
# worker with the same result; a run again keeps every part; a merge with a
# part missing is bad input naming the block.
# usage: dask_fit_test.sh SOURCE_DIR CLOTHFIT WORK_DIR   (exit 77: skipped)
set -u
source_dir=$1
clothfit=$2
work=$3
python=/usr/bin/python3
fail() {
  echo "FAIL: $*"
  exit 1
}
if ! "$python" -c 'import distributed' 2>/dev/null; then
  echo "skipped: $python has no module distributed (scripts/setup.sh installs python3-distributed)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work/one" "$work/dask" "$work/stack"
cd "$work" || exit 1

"$clothfit" synth --gonio plain --texels 32 --directions 4 \
  --stack stack/m.csv >/dev/null || fail "synth"
# Exit 1: written, with texels at a search limit (named); the same for both.
"$clothfit" fit --model lafortune --stack stack/m.csv --mip --lobes 1 \
  --out one/map.exr >one.log 2>&1
one=$?
[ "$one" -le 1 ] && [ -s one/map.exr ] || fail "one fit: exit $one: $(tail -3 one.log)"

CLOTHFIT_DASK_TEST_KILL=16,0 "$python" "$source_dir/scripts/dask_fit.py" \
  --stack stack/m.csv --out dask/map.exr --workers 2 --block 16 \
  --clothfit "$clothfit" --parts-dir parts -- --lobes 1 >dask.log 2>&1
status=$?
[ "$status" -eq "$one" ] || fail "dask_fit.py: exit $status, one fit $one: $(tail -5 dask.log)"
cmp one/map.exr dask/map.exr || fail "the merged map differs from one fit's"
cmp one/map.exr.json dask/map.exr.json || fail "the merged index differs"
[ -e parts/.attempted_16_0 ] || fail "block 16,0 was not attempted by the kill hook"
grep -q "Restarting worker" dask.log || fail "no worker was killed: $(tail -5 dask.log)"
grep -q "4/4 blocks (0 kept from before, 0 failed)" dask.log ||
  fail "not 4 blocks fitted: $(grep blocks dask.log | tail -2)"

# Run again: every part is kept, the map is the same.
rm dask/map.exr dask/map.exr.json
"$python" "$source_dir/scripts/dask_fit.py" --stack stack/m.csv \
  --out dask/map.exr --workers 2 --block 16 --clothfit "$clothfit" \
  --parts-dir parts -- --lobes 1 >again.log 2>&1
[ $? -eq "$one" ] || fail "run again: $(tail -5 again.log)"
grep -q "4/4 blocks (4 kept from before, 0 failed)" again.log ||
  fail "the parts were not kept: $(grep blocks again.log | tail -2)"
cmp one/map.exr dask/map.exr || fail "the map of the run again differs"

# A part missing: bad input (exit 2) naming the block, nothing written.
rm parts/part_16_16.exr parts/part_16_16.exr.json
"$clothfit" merge --parts parts --out missing.exr >missing.out 2>missing.err
status=$?
[ "$status" -eq 2 ] || fail "merge with a part missing: exit $status"
grep -q "^error: block 16,16,16,16 is missing" missing.err ||
  fail "merge with a part missing: $(cat missing.err)"
[ "$(wc -l <missing.err)" -eq 1 ] || fail "more than one line: $(cat missing.err)"
[ ! -e missing.exr ] || fail "merge with a part missing wrote its map"
echo "dask_fit_test: passed"
