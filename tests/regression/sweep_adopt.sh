#!/usr/bin/env bash
# Regression tier: friction_sweep --adopt. A point stopped by SIGINT leaves its checkpoint; the
# sweep run again with another slide setting (slide.step_growth = 2) and --adopt continues it
# from there instead of starting over, keeps the adopted file and records the adoption; the
# finished row carries the new settings. Run again with the first settings and --adopt, the row
# is kept (its settings cell names what made it) rather than recomputed.
# Usage: sweep_adopt.sh FRICTION_SWEEP SCENE OUT
set -euo pipefail
bin=$1 scene=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
grown="$out/grown.toml"
sed 's/^max_slips = 12$/max_slips = 12\nstep_growth = 2/' "$scene" > "$grown"
grep -q '^step_growth = 2' "$grown" || { echo "the scene has no 'max_slips = 12' line"; exit 1; }
sweep="$out/sweep" point="$out/sweep/points/a24_R40"

# The point takes about 5-10 s (more under sanitizers). With --checkpoint-every 0 it writes a
# checkpoint after every step: SIGINT once the first is there stops it with a later one.
"$bin" "$scene" --out "$sweep" --checkpoint-every 0 > "$out/first.log" 2>&1 &
pid=$!
for _ in $(seq 600); do
  [ -f "$point/checkpoint.cbor" ] && break
  kill -0 "$pid" 2> /dev/null || break
  sleep 0.1
done
kill -INT "$pid" 2> /dev/null || true
status=0
wait "$pid" || status=$?
[ "$status" -eq 3 ] || { echo "first run: exit $status, expected 3 (stopped)"; cat "$out/first.log"; exit 1; }
[ -f "$point/checkpoint.cbor" ] || { echo "no checkpoint"; ls -R "$sweep"; exit 1; }

"$bin" "$grown" --out "$sweep" --adopt > "$out/adopt.log" 2>&1 || { cat "$out/adopt.log"; exit 1; }
grep -q "adopting the checkpoint" "$out/adopt.log" || { echo "not adopted:"; cat "$out/adopt.log"; exit 1; }
grep -q "resuming a = 24 d, R = 40 d from its checkpoint" "$out/adopt.log" ||
  { echo "not resumed:"; cat "$out/adopt.log"; exit 1; }
[ -f "$point/checkpoint.adopted.1.cbor" ] || { echo "the adopted file was not kept"; exit 1; }
grep -q '"added": "slide.step_growth=2"' "$point/adopted.json" ||
  { echo "adopted.json:"; cat "$point/adopted.json"; exit 1; }
[ ! -e "$point/checkpoint.cbor" ] || { echo "the finished point left its checkpoint"; exit 1; }
row=$(grep '^24,' "$sweep/sweep.csv") || { cat "$sweep/sweep.csv"; exit 1; }
case "$row" in *"slide.step_growth=2"*) ;; *) echo "row without the new settings: $row"; exit 1 ;; esac
case "$row" in *",12,"*"slip event limit reached"*) ;; *) echo "row: $row"; exit 1 ;; esac

cp "$sweep/sweep.csv" "$out/adopted.csv"
"$bin" "$scene" --out "$sweep" --adopt > "$out/rows.log" 2>&1 || { cat "$out/rows.log"; exit 1; }
grep -q "reused 1 of 1 points .*(1 of another build or other numerical settings, --adopt)" \
  "$out/rows.log" || { echo "row not kept:"; cat "$out/rows.log"; exit 1; }
cmp "$sweep/sweep.csv" "$out/adopted.csv" || { echo "the kept row changed"; exit 1; }
echo "checkpoint adopted under slide.step_growth = 2, row kept under --adopt"
