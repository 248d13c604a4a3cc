#!/usr/bin/env bash
# scripts/keep_slip_states.sh beside a running sweep (the largest_slip fixture's scene, a Regime
# III contact at R = 40 d that slides through several slips in about 5 s), watching the run's
# folder (its point begins after the watcher does):
# - every slip of the point's slips.csv is either kept as a pair whose files carry that slip's
#   labels, or named once in missed.txt; the last slip is kept (the look after the run ends);
#   with a poll of 0.05 s most are kept;
# - a second watcher over the finished run changes no file of the series (same checksums);
# - a table whose rows do not start at slip 1 (a resumed run's, set aside and begun again):
#   the slip is the row's number, not the count of rows;
# - a watcher killed mid-copy leaves a temporary copy and a "before" without its "after": the
#   next one removes both.
# Usage: keep_slip_states.sh FRICTION_SWEEP SCENE SCRIPT WORKDIR
set -euo pipefail
sweep=$1 scene=$2 script=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
label() { ncdump -h "$1" | sed -n 's/^[[:space:]]*:label = "\(.*\)" ;$/\1/p' | head -1; }
"$sweep" "$scene" --largest-slip --out "$work/run" >"$work/run.log" 2>&1 &
run=$!
bash "$script" "$work/run" "$work/series" "$run" 0.05 >"$work/watch.log" 2>&1
wait "$run" || { echo "friction_sweep failed"; cat "$work/run.log"; exit 1; }

point=$(ls -d "$work"/run/points/*/ | head -1)
point=${point%/}
kept="$work/series/$(basename "$point")"
[ -d "$kept" ] || fail "no series for the point begun after the watcher ($kept)"
slips=$(($(wc -l <"$point/largest_slip/slips.csv") - 1))
[ "$slips" -ge 3 ] || fail "the fixture's slide has $slips slips (at least 3 expected)"
n_kept=0
for ((k = 1; k <= slips; ++k)); do
  name=$(printf 'slip_%03d' "$k")
  in_missed=0
  [ -f "$kept/missed.txt" ] && in_missed=$(awk -v k="$k" '$1 == k' "$kept/missed.txt" | wc -l)
  if [ -f "$kept/${name}_after.nc" ]; then
    [ "$in_missed" -eq 0 ] || fail "$name both kept and missed"
    [ -f "$kept/${name}_before.nc" ] || fail "$name: after without before"
    [ "$(label "$kept/${name}_before.nc")" = "${name}_before" ] || fail "$name: before's label"
    [ "$(label "$kept/${name}_after.nc")" = "${name}_after" ] || fail "$name: after's label"
    n_kept=$((n_kept + 1))
  else
    [ "$in_missed" -eq 1 ] || fail "$name neither kept nor missed once (missed $in_missed times)"
  fi
done
last=$(printf 'slip_%03d' "$slips")
[ -f "$kept/${last}_after.nc" ] || fail "the last slip ($last) was not kept"
echo "keep_slip_states: $slips slips, $n_kept kept, $((slips - n_kept)) missed"
[ "$n_kept" -ge $(((slips + 1) / 2)) ] || fail "fewer than half of the slips kept at a 0.05 s poll"

# The series of a finished run is complete: a second watcher (the run gone) changes nothing.
sums() { (cd "$work/series" && find . -type f ! -name '*.log' | sort | xargs md5sum); }
before=$(sums)
bash "$script" "$work/run" "$work/series" 999999999 0.05 >>"$work/watch.log" 2>&1
[ "$(sums)" = "$before" ] || fail "a second watcher changed the series"

# A table that does not start at slip 1: only the last slip's row (slip $slips) and its pair.
fake="$work/fake/points/p"
mkdir -p "$fake/largest_slip"
cp "$point/largest_slip/latest_slip_before.nc" "$point/largest_slip/latest_slip_after.nc" \
  "$fake/largest_slip/"
{ head -1 "$point/largest_slip/slips.csv"; tail -1 "$point/largest_slip/slips.csv"; } \
  >"$fake/largest_slip/slips.csv"
bash "$script" "$work/fake" "$work/fake_series" 999999999 0.05 >>"$work/watch.log" 2>&1
[ -f "$work/fake_series/p/${last}_after.nc" ] ||
  fail "a table of one row, slip $slips: its pair not kept as $last"
[ "$(wc -l <"$work/fake_series/p/missed.txt")" -eq $((slips - 1)) ] ||
  fail "the slips before the table's first row are not each named missed once"

# What a watcher killed mid-copy leaves is removed by the next one.
mkdir -p "$work/fake_series/p/.copy.abc"
touch "$work/fake_series/p/.copy.abc/before.nc" "$work/fake_series/p/slip_999_before.nc"
bash "$script" "$work/fake" "$work/fake_series" 999999999 0.05 >>"$work/watch.log" 2>&1
[ ! -e "$work/fake_series/p/.copy.abc" ] || fail "a temporary copy left"
[ ! -e "$work/fake_series/p/slip_999_before.nc" ] || fail "a before without its after left"
[ -f "$work/fake_series/p/${last}_before.nc" ] || fail "a whole pair removed"
echo "keep_slip_states: OK"
