#!/usr/bin/env bash
# Regression tier: every sweep scene committed under data/scenes (the files with a [sweep]
# table) is read and validated by this friction_sweep: `--plan` lists its points and what each
# needs without running them. A setting renamed or a range narrowed in the code would otherwise
# leave a committed scene that no longer runs, found only when someone next runs it.
# Usage: sweep_scenes_plan.sh FRICTION_SWEEP SCENES_DIR OUT
set -euo pipefail
bin=$1 scenes=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
n=0
for scene in "$scenes"/*.toml; do
  grep -q '^\[sweep\]' "$scene" || continue
  name=$(basename "$scene" .toml)
  # An output folder that does not exist: the plan reads no table and must not create it.
  "$bin" "$scene" --plan --out "$out/$name" > "$out/$name.log" 2>&1 ||
    { echo "$scene:"; cat "$out/$name.log"; exit 1; }
  grep -q '^to run: ' "$out/$name.log" || { echo "$scene: no plan"; cat "$out/$name.log"; exit 1; }
  [ ! -e "$out/$name" ] || { echo "$scene: --plan wrote $out/$name"; exit 1; }
  n=$((n + 1))
done
[ "$n" -ge 5 ] || { echo "only $n sweep scenes in $scenes"; exit 1; }
echo "$n sweep scenes read and planned"
