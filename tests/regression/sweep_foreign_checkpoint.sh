#!/usr/bin/env bash
# Regression tier: a point checkpoint that friction_sweep cannot continue (damaged, or of another
# build or scene) is not thrown away: the point starts over and the old file is kept as
# checkpoint.replaced.cbor (it may hold hours of a long point that the wrong binary was asked to
# continue). Usage: sweep_foreign_checkpoint.sh FRICTION_SWEEP SCENE OUT
set -euo pipefail
bin=$1 scene=$2 out=$3
rm -rf "$out"
point="$out/points/a4_R535"
mkdir -p "$point"
printf 'not a checkpoint' > "$point/checkpoint.cbor"
"$bin" "$scene" --out "$out" > "$out.log" 2>&1 || { cat "$out.log"; exit 1; }
grep -q "starting the point over (the old checkpoint is kept as $point/checkpoint.replaced.cbor)" \
  "$out.log" || { echo "no message about the kept checkpoint:"; cat "$out.log"; exit 1; }
[ "$(cat "$point/checkpoint.replaced.cbor")" = 'not a checkpoint' ] || { echo "not kept"; exit 1; }
[ ! -e "$point/checkpoint.cbor" ] || { echo "the finished point left its checkpoint"; exit 1; }
# Column a comes first (as sweep_adopt.sh reads it).
grep -q '^4,' "$out/sweep.csv" || { cat "$out/sweep.csv"; exit 1; }
echo "foreign checkpoint kept, point computed"
