#!/usr/bin/env bash
# Every solver against the reference flow on one instability per scene (issue 21; docs/solvers.md,
# "Path fidelity"): path_check per scene into OUT/<scene>/path_check.json, one at a time (a
# scene already done is skipped, so the script resumes), then the table of docs/benchmarks.md.
# Usage: bench/run_path_tier.sh [OUT] (default results/path_tier). Cost: about 2 hours here, most
# of it the flow at a = 126 and 138 d.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-results/path_tier}"
mkdir -p "$out"
bin="$root/build/bin/path_check"
solvers="lbfgs/auto lbfgs/elastic cg newton/auto fire flow/interface flow/interface@1e-2"
for spec in "45 100 1" "46 100 1" "48 100 1" "50 100 1" "28 40 1" "28 40 3" "16 535 1" \
  "43 535 1" "138 535 1" "80 200 1" "126 404 2"; do
  set -- $spec
  dir="$out/a$1_R$2_slip$3"
  [ -f "$dir/path_check.json" ] && continue
  # shellcheck disable=SC2086
  "$bin" --a "$1" --R "$2" --slip "$3" --solvers $solvers --out "$dir" > "$dir.log" 2>&1
done
python3 "$root/bench/path_table.py" "$out"/*/path_check.json
