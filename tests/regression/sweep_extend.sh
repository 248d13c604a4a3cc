#!/usr/bin/env bash
# Regression tier: a lower bound stopped at a limit is continued, not recomputed. A point cut at
# 3 slip events (slide.max_slips: mu a lower bound) keeps its last checkpoint as
# checkpoint.capped.cbor; the sweep run again with the limit at 6 and --adopt drops the bound's
# row, continues the point from that checkpoint and writes the row a sweep with 6 from the start
# writes, byte for byte. Without --adopt the point would start over (and keep the checkpoint).
# Then the same where the last checkpoint falls inside the last slip's flow (below).
# Usage: sweep_extend.sh FRICTION_SWEEP SCENE OUT   (SCENE: sweep_adopt.toml, max_slips = 12)
set -euo pipefail
bin=$1 scene=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
short="$out/short.toml" long="$out/long.toml"
sed 's/^max_slips = 12$/max_slips = 3/' "$scene" > "$short"
sed 's/^max_slips = 12$/max_slips = 6/' "$scene" > "$long"
grep -q '^max_slips = 3$' "$short" || { echo "the scene has no 'max_slips = 12' line"; exit 1; }
sweep="$out/sweep" point="$out/sweep/points/a24_R40"

# A checkpoint after every step, so that the point has one whatever the machine's speed.
"$bin" "$short" --out "$sweep" --checkpoint-every 0 > "$out/short.log" 2>&1 ||
  { cat "$out/short.log"; exit 1; }
row=$(grep '^24,' "$sweep/sweep.csv") || { cat "$sweep/sweep.csv"; exit 1; }
case "$row" in *",3,"*"slip event limit reached"*) ;; *) echo "short row: $row"; exit 1 ;; esac
[ -f "$point/checkpoint.capped.cbor" ] || { echo "the capped point kept no checkpoint"; ls "$point"; exit 1; }
[ ! -e "$point/checkpoint.cbor" ] || { echo "the finished point left checkpoint.cbor"; exit 1; }

# --plan says so before anything runs.
"$bin" "$long" --out "$sweep" --adopt --plan > "$out/plan.log" 2>&1 || { cat "$out/plan.log"; exit 1; }
for expected in "a = 24 d, R = 40 d: .*to run on from the checkpoint kept at the limit" \
  "^to run: 1 (1 of them continued from a capped checkpoint, 0 from their checkpoint); kept: 0;"; do
  grep -q "$expected" "$out/plan.log" || { echo "plan lacks '$expected':"; cat "$out/plan.log"; exit 1; }
done

"$bin" "$long" --out "$sweep" --adopt --checkpoint-every 0 > "$out/extend.log" 2>&1 ||
  { cat "$out/extend.log"; exit 1; }
for expected in "1 lower bound at a limit these settings raise continues" \
  "a = 24 d, R = 40 d, a lower bound at its limit, continues from the checkpoint kept there if" \
  "resuming a = 24 d, R = 40 d from its checkpoint"; do
  grep -q "$expected" "$out/extend.log" || { echo "missing '$expected':"; cat "$out/extend.log"; exit 1; }
done
# Stopped at 6 slips, the point is a capped lower bound again: it keeps its newer checkpoint.
[ -f "$point/checkpoint.capped.cbor" ] && [ ! -e "$point/checkpoint.cbor" ] ||
  { echo "checkpoints:"; ls "$point"; exit 1; }

"$bin" "$long" --out "$out/direct" --checkpoint-every 0 > "$out/direct.log" 2>&1 ||
  { cat "$out/direct.log"; exit 1; }
extended=$(grep '^24,' "$sweep/sweep.csv") direct=$(grep '^24,' "$out/direct/sweep.csv")
case "$direct" in *",6,"*"slip event limit reached"*) ;; *) echo "direct row: $direct"; exit 1 ;; esac
[ "$extended" = "$direct" ] || { printf 'extended: %s\ndirect:   %s\n' "$extended" "$direct"; exit 1; }
echo "the 3-slip lower bound continued to 6 slips: the row of a 6-slip sweep, byte for byte"

# The same when the last checkpoint falls inside the last slip's flow (a checkpoint due at every
# chance: 1e-6 s), as it mostly does in Regime III: that one holds the paused flow of the step
# that reached the limit, which a larger limit cannot continue, so the point keeps the last one
# between steps (checkpoint.step.cbor while it runs; the slide writes one after every paused
# checkpoint). A smaller contact (a = 15 d, R = 20 d, Regime III) keeps the writes cheap.
small="--a 15 --R 20" sweep="$out/flow" point="$out/flow/points/a15_R20"
"$bin" "$short" $small --out "$sweep" --checkpoint-every 1e-6 > "$out/flow_short.log" 2>&1 ||
  { cat "$out/flow_short.log"; exit 1; }
grep -q "keeps its last checkpoint between steps (the later one inside a slip's flow is dropped)" \
  "$out/flow_short.log" || { echo "no checkpoint between steps kept:"; cat "$out/flow_short.log"; exit 1; }
[ -f "$point/checkpoint.capped.cbor" ] && [ ! -e "$point/checkpoint.cbor" ] &&
  [ ! -e "$point/checkpoint.step.cbor" ] || { echo "checkpoints:"; ls "$point"; exit 1; }
# --plan names a point in flight (a checkpoint in its folder, no row): here a copy of that one.
mkdir -p "$out/flight/points/a15_R20"
cp "$point/checkpoint.capped.cbor" "$out/flight/points/a15_R20/checkpoint.cbor"
"$bin" "$long" $small --out "$out/flight" --plan > "$out/flight_plan.log" 2>&1 ||
  { cat "$out/flight_plan.log"; exit 1; }
for expected in "a = 15 d, R = 20 d: .*to run on from its checkpoint, if it fits these settings" \
  "^to run: 1 (0 of them continued from a capped checkpoint, 1 from their checkpoint)"; do
  grep -q "$expected" "$out/flight_plan.log" || { echo "plan lacks '$expected':"; cat "$out/flight_plan.log"; exit 1; }
done
"$bin" "$long" $small --out "$sweep" --adopt --checkpoint-every 0 > "$out/flow_extend.log" 2>&1 ||
  { cat "$out/flow_extend.log"; exit 1; }
grep -q "resuming a = 15 d, R = 20 d from its checkpoint" "$out/flow_extend.log" ||
  { echo "not continued:"; cat "$out/flow_extend.log"; exit 1; }
"$bin" "$long" $small --out "$out/flow_direct" --checkpoint-every 0 > "$out/flow_direct.log" 2>&1 ||
  { cat "$out/flow_direct.log"; exit 1; }
extended=$(grep '^15,' "$sweep/sweep.csv") direct=$(grep '^15,' "$out/flow_direct/sweep.csv")
case "$direct" in *",6,"*"slip event limit reached"*) ;; *) echo "direct row: $direct"; exit 1 ;; esac
[ "$extended" = "$direct" ] || { printf 'extended: %s\ndirect:   %s\n' "$extended" "$direct"; exit 1; }
echo "the same from a last checkpoint inside a slip's flow: the checkpoint between steps before it"
