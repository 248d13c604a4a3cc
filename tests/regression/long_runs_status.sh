#!/usr/bin/env bash
# scripts/long_runs.sh status on a made-up run folder (RUNS): a point's slips.csv is read by
# column name (so that columns added at its end, as Dx_before was, change nothing), its latest
# slip, cost and pace are printed, and so are the slip figures that exist and whether the slips
# retrace a reference table (r800's committed first run); a run without a log or a
# binary says so; peek of a run without its scene copy says so. Nothing is started: status and
# peek only read.
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  echo "--- status printed:" >&2
  cat "$work/out" >&2
  exit 1
}
# status on the made-up folder, its output in $work/out.
run_status() {
  (cd "$repo" && RUNS="$work" bash scripts/long_runs.sh status) >"$work/out" 2>&1 ||
    fail "status exited non-zero"
}
dir="$work/issue23/regime3_R800_g/points/a300_R800/largest_slip"
mkdir -p "$dir"
# The columns of friction_sweep's table in an order of their own, and one more at the end.
cat >"$dir/slips.csv" <<'CSV'
slip,Dx,Fx_before,Fx_after,Fz,slipped_sites,loops,loop_area,slipped_area,gf_applications,wall_s,Dx_before,later
1,4.19375,6587.06,5266.85,179999,207953,1,74290.6,208409,109233,26604,4.1875,x
2,4.21375,5282.6,5298.1,179999,6,1,74241,208457,118000,28584,4.20375,x
CSV
run_status
grep -q "a300_R800: 2 slips; last: slip 2 at Dx = 4.2138 d, Fx 5282.6 -> 5298.1, 6 sites, 1 loops (area 74241 d^2), slipped area 208457 d^2, at 118000 GF, 7.94 h" "$work/out" ||
  fail "the latest slip of a300_R800"
# The pace from the cost columns: 1 cycle of 1 980 s, 0.02 d and 8 767 GF.
grep -q "^    pace over slips 2-2: 1.82 slips/h, 0.0364 d of Dx/h, 8767 GF a slip$" "$work/out" ||
  fail "the pace of a300_R800"
grep -q "figures:" "$work/out" && fail "figures named where there are none"
# A replayed slip (replay_of not 0) is not a slip computed: slips 2-3 took 3 600 s and 10 000 GF
# (4 of them the replay's), so the pace is 1 slip and 1.02 d an hour, 10 000 GF a slip. (Counted,
# the replay would double the slips an hour and halve the GF a slip.)
cp "$dir/slips.csv" "$work/keep.csv"
cat >"$dir/slips.csv" <<'CSV'
slip,Dx,Fx_before,Fx_after,Fz,slipped_sites,loops,loop_area,slipped_area,gf_applications,wall_s,Dx_before,replay_of
1,4.19375,6587.06,5266.85,179999,207953,1,74290.6,208409,100000,20000,4.1875,0
2,4.21375,5282.6,5298.1,179999,6,1,74241,208457,109996,23599,4.20375,0
3,5.21375,5282.6,5298.1,179999,6,1,74241,208457,110000,23600,5.20375,2
CSV
run_status
grep -q "^    pace over slips 2-3: 1 slips/h, 1.02 d of Dx/h (1 replayed slips left out of the count; their Dx is in), 10000 GF a slip$" "$work/out" ||
  fail "the pace of a table with a replayed slip"
# A replayed row of an earlier build (replay_of -1: replayed, source unknown) counts as replayed.
sed -i '$ s/,2$/,-1/' "$dir/slips.csv"
run_status
grep -q "^    pace over slips 2-3: 1 slips/h, 1.02 d of Dx/h (1 replayed slips" "$work/out" ||
  fail "the pace of a table with a replayed slip of unknown source"
mv "$work/keep.csv" "$dir/slips.csv"
# The stress the held loop's cores hold on the axes, where the table has it; none where the last
# row has no loop crossing (nan), nor from a table without the columns (above).
cp "$dir/slips.csv" "$work/keep.csv"
cat >"$dir/slips.csv" <<'CSV'
slip,Dx,Fx_before,Fx_after,Fz,slipped_sites,loops,loop_area,slipped_area,gf_applications,wall_s,Dx_before,replay_of,loop_stress_x,loop_tau_max_x,loop_stress_y,loop_tau_max_y
1,4.19375,6587.06,5266.85,179999,207953,1,74290.6,208409,100000,20000,4.1875,0,0.014260,0.5538,0.026688,0.5827
CSV
run_status
grep -q "^    held loop cores (x: 0.01426 G at tau_max 0.5538 G, y: 0.02669 G at tau_max 0.5827 G)$" "$work/out" ||
  fail "the loops' held stress"
sed -i 's/0.014260,0.5538,0.026688,0.5827/nan,nan,nan,nan/' "$dir/slips.csv"
run_status
grep -q "held loop cores" "$work/out" && fail "a held stress where no loop crosses"
mv "$work/keep.csv" "$dir/slips.csv"
touch "$dir/slips.png"
run_status
grep -q "^    figures: $dir/slips.png$" "$work/out" || fail "the one figure there is"
touch "$dir/slips_loops.png"
run_status
grep -q "^    figures: $dir/slips.png, $dir/slips_loops.png$" "$work/out" || fail "both figures"
grep -q "^r1700_a510 \[stopped, no binary\]: (no log)$" "$work/out" || fail "a run never started"
# No pace from one slip, nor from a table of a build before the cost columns.
head -2 "$dir/slips.csv" >"$work/one.csv" && mv "$work/one.csv" "$dir/slips.csv"
run_status
grep -q "a300_R800: 1 slips" "$work/out" || fail "the one slip"
grep -q "pace" "$work/out" && fail "a pace from one slip"
printf 'slip,Dx,Fx_before,Fx_after,Fz,slipped_sites,loops,loop_area,slipped_area\n1,4.19375,6587.06,5266.85,179999,207953,1,74290.6,208409\n2,4.21375,5282.6,5298.1,179999,6,1,74241,208457\n' >"$dir/slips.csv"
run_status
grep -q "a300_R800: 2 slips" "$work/out" || fail "the table without cost columns"
grep -q "pace" "$work/out" && fail "a pace without cost columns"
# r800's point against its reference table (the committed first run): its first rows, as they
# are, retrace it; a changed cell is named by slip and column; cost columns are not compared.
ref="$repo/data/reference/regime3_R800_a300_slips.csv"
head -4 "$ref" >"$dir/slips.csv"
sed -i '4 s/^\([^,]*,[^,]*,[^,]*\),[^,]*,/\1,5300,/' "$dir/slips.csv"  # slip 3's Fx_after
run_status
grep -q "^    against regime3_R800_a300_slips.csv: slip 3 differs in Fx_after (5300, the reference " "$work/out" ||
  fail "a slip that differs from the reference"
head -3 "$ref" | sed '2,3 s/,,,/,1234,56.7,/' >"$dir/slips.csv"  # other cost cells
run_status
grep -q "^    against regime3_R800_a300_slips.csv: slips 1-2 equal its rows in the 23 columns both have$" "$work/out" ||
  fail "slips that retrace the reference"
# More slips than the reference has: those past it are said to be.
{ cat "$ref"; tail -1 "$ref" | sed 's/^[0-9]*,/999,/'; } >"$dir/slips.csv"
rows=$(($(wc -l <"$ref") - 1))
run_status
grep -q "^    against regime3_R800_a300_slips.csv: slips 1-$rows equal its rows in the 23 columns both have; slips $((rows + 1))-$((rows + 1)) are past its $rows rows$" "$work/out" ||
  fail "slips past the reference"
printf 'slip,Dx,Fx_before,Fx_after,Fz,slipped_sites,loops,loop_area,slipped_area\n1,4.19375,6587.06,5266.85,179999,207953,1,74290.6,208409\n2,4.21375,5282.6,5298.1,179999,6,1,74241,208457\n' >"$dir/slips.csv"
# The states kept around each slip (long_runs.sh series): counted where they were asked for,
# no line where they were not.
grep -q "series:" "$work/out" && fail "a series line without a series"
kept="$work/issue23/regime3_R800_g.series/a300_R800"
mkdir -p "$kept"
touch "$kept/slip_001_before.nc" "$kept/slip_001_after.nc" "$kept/slip_003_before.nc" \
  "$kept/slip_003_after.nc"
echo "2 its states were replaced before they were copied" >"$kept/missed.txt"
run_status
grep -q "^    series: 2 slips' states kept, 1 missed (no watcher): $kept$" "$work/out" ||
  fail "the series kept"
# series starts watchers beside a running run only.
(cd "$repo" && RUNS="$work" bash scripts/long_runs.sh series r800) >"$work/out" 2>&1 &&
  fail "series of a run not running exited zero"
grep -q "^r800: not running: start it first" "$work/out" || fail "series of a run not running"
# peek reads only: a run without its scene copy has nothing to look at, and says so.
(cd "$repo" && RUNS="$work" bash scripts/long_runs.sh peek r800) >"$work/out" 2>&1 ||
  fail "peek exited non-zero"
grep -q "^r800: nothing to look at (no $work/issue23/regime3_R800_g.scene.toml" "$work/out" ||
  fail "peek of a run without its scene copy"
echo "long_runs.sh status: OK"
