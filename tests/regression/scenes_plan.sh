#!/usr/bin/env bash
# Regression tier: every slide and sweep scene committed under data/scenes is read and validated
# by this build's tools: `--plan` says what the run would be without running it. A setting
# renamed or a range narrowed in the code would otherwise leave a committed scene that no longer
# runs, found only when someone next runs it.
# - files with a [sweep] table: friction_sweep SCENE --plan;
# - files with an [explicit] table: contact_slide --model explicit SCENE --plan, and with --slide;
# - other files with a [contact] table: contact_slide SCENE --plan.
# (peierls_default.toml and gf_validation.toml belong to peierls_scan and gf_validate, whose
# tests run them.) Usage: scenes_plan.sh FRICTION_SWEEP CONTACT_SLIDE SCENES_DIR OUT
set -euo pipefail
sweep=$1 slide=$2 scenes=$3 out=$4
rm -rf "$out"
mkdir -p "$out"
n=0
plan() {
  local name=$1 expect=$2
  shift 2
  # An output folder that does not exist: the plan must not create it.
  "$@" --plan --out "$out/$name" > "$out/$name.log" 2>&1 || { echo "$*:"; cat "$out/$name.log"; exit 1; }
  grep -q "$expect" "$out/$name.log" || { echo "$*: no plan"; cat "$out/$name.log"; exit 1; }
  [ ! -e "$out/$name" ] || { echo "$*: --plan wrote $out/$name"; exit 1; }
  n=$((n + 1))
}
for scene in "$scenes"/*.toml; do
  name=$(basename "$scene" .toml)
  if grep -q '^\[sweep\]' "$scene"; then
    plan "$name" '^to run: ' "$sweep" "$scene"
  elif grep -q '^\[explicit\]' "$scene"; then
    plan "$name" 'scene and flags are valid' "$slide" --model explicit "$scene"
    plan "$name.slide" 'scene and flags are valid' "$slide" --model explicit --slide "$scene"
  elif grep -q '^\[contact\]' "$scene"; then
    plan "$name" 'scene and flags are valid' "$slide" "$scene"
  fi
done
[ "$n" -ge 15 ] || { echo "only $n plans from $scenes"; exit 1; }
echo "$n plans of the scenes in $scenes"
