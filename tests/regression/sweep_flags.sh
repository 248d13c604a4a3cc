#!/usr/bin/env bash
# Regression tier: friction_sweep's slide flags are the scene's keys. The tiny sweep run with
# --alpha 0.6 --tolerance 1e-7 --distance 1.0 gives rows that the same sweep written as a scene
# (contact.alpha = 0.6, solver.tolerance = 1e-7, slide.distance = 1.0) reuses as its own: the
# rows' fingerprints (every setting that changes a result) are equal; --checkpoint-every 120,
# which changes none, is left out of them and echoed under the summary's run.control. The
# summary echoes the flags' values.
# Usage: sweep_flags.sh FRICTION_SWEEP SCENE OUT
set -euo pipefail
bin=$1 scene=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
edited="$out/edited.toml"
sed -e 's/^alpha = 0.7$/alpha = 0.6/' -e 's/^distance = 1.2 /distance = 1.0 /' \
  -e 's/^tolerance = 1e-6$/tolerance = 1e-7/' "$scene" > "$edited"
[ "$(diff "$scene" "$edited" | grep -c '^>')" -eq 3 ] ||
  { echo "the scene has not the three lines this test edits:"; diff "$scene" "$edited"; exit 1; }

"$bin" "$scene" --alpha 0.6 --tolerance 1e-7 --distance 1.0 --checkpoint-every 120 --out "$out/sweep" > "$out/flags.log" 2>&1 ||
  { cat "$out/flags.log"; exit 1; }
grep -q "alpha = 0.6" "$out/flags.log" || { echo "--alpha not applied:"; cat "$out/flags.log"; exit 1; }
# The flags' run's own summary (the scene's run below rewrites it).
cp "$out/sweep/summary.json" "$out/flags_summary.json"
"$bin" "$edited" --out "$out/sweep" > "$out/scene.log" 2>&1 || { cat "$out/scene.log"; exit 1; }
grep -q "reused 2 of 2 points" "$out/scene.log" ||
  { echo "the scene's run did not reuse the flags' rows:"; cat "$out/scene.log"; exit 1; }
# And the scene's own values (alpha = 0.7) are not those rows.
"$bin" "$scene" --plan --out "$out/sweep" > "$out/plan.log" 2>&1 || { cat "$out/plan.log"; exit 1; }
grep -q "kept: 0" "$out/plan.log" || { echo "rows of other settings kept:"; cat "$out/plan.log"; exit 1; }
# The flags' run's summary echoes every setting by its key, the flags' values among them, but
# the points' own contact.a and contact.R.
python3 - "$out/flags_summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["settings"]
assert s["contact.alpha"] == 0.6 and s["solver.tolerance"] == 1e-7 and s["slide.distance"] == 1.0, s
assert s["sweep.a"] == [4.0, 6.0] and s["sweep.R"] == [535.0], s
assert "contact.a" not in s and "contact.R" not in s, s
run = json.load(open(sys.argv[1]))["run"]["control"]
assert run == {"run.checkpoint_every": 120.0, "run.progress_every": 60.0}, run
PY
# A flag mends the scene's slip pair, as contact_slide's do: the scene's cg with slip_method
# "same" is refused alone, and runs with --slip-solver flow.
sed -e 's/^\[solver\]$/[solver]\nmethod = "cg"\nslip_method = "same"/' "$edited" >"$out/pair.toml"
grep -q '^slip_method = "same"' "$out/pair.toml" || { echo "no [solver] table to edit"; exit 1; }
edited="$out/pair.toml"
"$bin" "$edited" --plan --out "$out/mend" >"$out/unmended.log" 2>&1 &&
  { echo "the scene's slip pair was not refused"; cat "$out/unmended.log"; exit 1; }
grep -q "solver.slip_method" "$out/unmended.log" || { cat "$out/unmended.log"; exit 1; }
"$bin" "$edited" --slip-solver flow --plan --out "$out/mend" >"$out/mend.log" 2>&1 ||
  { echo "--slip-solver did not mend the scene's pair:"; cat "$out/mend.log"; exit 1; }
echo "flags = scene keys: rows reused"
