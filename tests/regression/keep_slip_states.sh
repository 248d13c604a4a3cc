#!/usr/bin/env bash
# scripts/keep_slip_states.sh beside a running sweep point (the largest_slip fixture's scene, a
# Regime III contact at R = 40 d that slides through several slips in about 5 s): every row of
# the point's slips.csv is either kept as a pair whose files carry that slip's labels, or named
# once in missed.txt; the last slip is kept (the watcher's last look after the run ends); a
# second watcher over the finished run adds nothing. With a poll of 0.05 s most slips are kept.
# Usage: keep_slip_states.sh FRICTION_SWEEP SCENE SCRIPT WORKDIR
set -euo pipefail
sweep=$1 scene=$2 script=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
"$sweep" "$scene" --largest-slip --out "$work/run" >"$work/run.log" 2>&1 &
run=$!
# The point's folder appears once the point begins.
for _ in $(seq 1 200); do
  point=$(ls -d "$work"/run/points/*/ 2>/dev/null | head -1 || true)
  [ -n "$point" ] && break
  sleep 0.05
done
[ -n "$point" ] || { echo "no point folder"; cat "$work/run.log"; exit 1; }
point=${point%/}
bash "$script" "$point" "$work/series" "$run" 0.05 >"$work/watch.log" 2>&1
wait "$run" || { echo "friction_sweep failed"; cat "$work/run.log"; exit 1; }

fail() { echo "FAIL: $*"; exit 1; }
slips=$(($(wc -l <"$point/largest_slip/slips.csv") - 1))
[ "$slips" -ge 3 ] || fail "the fixture's slide has $slips slips (at least 3 expected)"
label() { ncdump -h "$1" | sed -n 's/^[[:space:]]*:label = "\(.*\)" ;$/\1/p' | head -1; }
kept=0
for ((k = 1; k <= slips; ++k)); do
  name=$(printf 'slip_%03d' "$k")
  in_missed=0
  [ -f "$work/series/missed.txt" ] && in_missed=$(awk -v k="$k" '$1 == k' "$work/series/missed.txt" | wc -l)
  if [ -f "$work/series/${name}_after.nc" ]; then
    [ "$in_missed" -eq 0 ] || fail "$name both kept and missed"
    [ -f "$work/series/${name}_before.nc" ] || fail "$name: after without before"
    [ "$(label "$work/series/${name}_before.nc")" = "${name}_before" ] || fail "$name: before's label"
    [ "$(label "$work/series/${name}_after.nc")" = "${name}_after" ] || fail "$name: after's label"
    kept=$((kept + 1))
  else
    [ "$in_missed" -eq 1 ] || fail "$name neither kept nor missed once (missed $in_missed times)"
  fi
done
last=$(printf 'slip_%03d' "$slips")
[ -f "$work/series/${last}_after.nc" ] || fail "the last slip ($last) was not kept"
# The series of a finished run is complete: a second watcher (the run gone) adds nothing.
before=$(ls "$work/series" | sort)
bash "$script" "$point" "$work/series" 999999999 0.05 >>"$work/watch.log" 2>&1
[ "$(ls "$work/series" | sort)" = "$before" ] || fail "a second watcher changed the series"
echo "keep_slip_states: $slips slips, $kept kept, $((slips - kept)) missed"
[ "$kept" -ge $(((slips + 1) / 2)) ] || fail "fewer than half of the slips kept at a 0.05 s poll"
