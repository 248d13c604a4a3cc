#!/usr/bin/env bash
# Scaling of one quasi-static step with the number of contact atoms (issue 7): a from 16 d to
# 512 d at fixed a/b_core^0 = 6.2 (R = c alpha a^2 / (6.2 d): the same physics at every size,
# so that only the numerics scale) and, for comparison, at fixed R = 535 d up to a = 128 d.
# Peak memory per run (GNU time), log-log slopes, and the speed-up of 2 FFT threads on the
# largest case. Records the section "Scaling with contact size" in docs/benchmarks.md.
# Usage: bench/run_scaling.sh [build dir] [largest a]   (defaults: build, 512)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib.sh
build=${1:-build}
amax=${2:-512}
cmake --build "$build" --target bench_scaling -j 2 >/dev/null
bench_workdir
commit=$(bench_commit core bench)
cpu=$(bench_cpu)
run() {  # run a R threads -> appends "csv line,peak_MiB" to $work/rows
  /usr/bin/time -f "%M" -o "$work/mem" "$build/bin/bench_scaling" "$1" "$2" "$3" >"$work/line"
  echo "$(cat "$work/line"),$(($(cat "$work/mem") / 1024))" >>"$work/rows"
}
: >"$work/rows"
for a in 16 32 64 128 256 512; do
  [ "$a" -le "$amax" ] || continue
  R=$(python3 -c "import math; print(round(4/(math.pi*0.5)*0.7*$a*$a/6.2, 1))")
  run "$a" "$R" 1
done
largest=$(tail -1 "$work/rows" | cut -d, -f1,2)
run "${largest%,*}" "${largest#*,}" 2
for a in 16 32 64 128; do
  [ "$a" -le "$amax" ] || continue
  run "$a" 535 1
done
table=$(python3 - "$work/rows" <<'PY'
import csv, math, sys
cols = "a,R,x,sites,unknowns,block,grid,threads,it,gf,step,run,mem".split(",")
rows = [dict(zip(cols, l.strip().split(","))) for l in open(sys.argv[1]) if l.strip()]
def fit(xs, ys):
    lx = [math.log(v) for v in xs]; ly = [math.log(v) for v in ys]
    mx = sum(lx) / len(lx); my = sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)
out = ["| a (d) | R (d) | a/b_core^0 | contact sites N | block | FFT grid | threads | step iterations | step GF | step wall (s) | wall / (N log N iterations) (ns) | peak memory (MiB) |",
       "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    n = int(r["sites"]); it = max(1, int(r["it"])); w = float(r["step"])
    per = w / (n * math.log(n) * it) * 1e9 if w > 0 else float("nan")
    out.append(f"| {r['a']} | {r['R']} | {float(r['x']):.3g} | {n} | {r['block']} | {r['grid']} | {r['threads']} | {r['it']} | {r['gf']} | {w:.4f} | {per:.1f} | {r['mem']} |")
fixed = [r for r in rows if r["threads"] == "1" and abs(float(r["x"]) - 6.2) < 0.2]
if len(fixed) >= 3:
    n = [int(r["sites"]) for r in fixed]
    it = [max(1, int(r["it"])) for r in fixed]
    w = [max(1e-6, float(r["step"])) for r in fixed]
    per_it = [wi / ii for wi, ii in zip(w, it)]
    out.append("")
    out.append(f"Fixed a/b_core^0 = 6.2, log-log slopes against N: step wall {fit(n, w):.2f}, "
               f"wall per iteration {fit(n, per_it):.2f} (N log N: about 1.05-1.1 over this range), "
               f"iterations {fit(n, it):.2f} (target <= 0.25).")
two = [r for r in rows if r["threads"] == "2"]
if two:
    one = [r for r in rows if r["threads"] == "1" and r["a"] == two[0]["a"] and r["R"] == two[0]["R"]][0]
    out.append(f"Threads: a = {one['a']} d, one step {float(one['step']):.3f} s on 1 FFT thread, "
               f"{float(two[0]['step']):.3f} s on 2: speed-up {float(one['step']) / float(two[0]['step']):.2f}.")
print("\n".join(out))
PY
)
section=$(cat <<EOT
## Scaling with contact size (bench/run_scaling.sh)

Provenance: commit $commit, $(date -u +%Y-%m-%d), $cpu, $(nproc) cores; command
\`bench/run_scaling.sh\`. One quasi-static step of 0.05 d (reference protocol, default solver
settings) from the relaxed state at Dx = 0.05 d; wall time of the step alone (a two-step run
minus a one-step run, minimum of repeats for a <= 128 d). The unknowns are the block's sites
(2 components); the FFT grid is the smallest 7-smooth size >= 2n - 1. Rows at R = 535 d change
the physics with a (a/b_core^0 grows as a^2); the fixed a/b_core^0 rows isolate the numerics.

$table
EOT
)
echo "$section" | bench/record_section.sh "## Scaling with contact size"
