#!/usr/bin/env bash
# Work-precision of whole slides (issue 7): a = 16, 43 d (all solvers) and a = 138 d (L-BFGS,
# CG, classic) at R = 535 d; error of mu against a converged reference versus wall time, one
# curve per solver/protocol family. Figures in docs/figures/, tables and provenance in
# docs/benchmarks.md (section "Work-precision").
# Usage: bench/run_work_precision.sh [build dir] [threads] [sizes]   (defaults: build, 2, "16 43 138")
# REUSE_SIZES="138" redraws that scene from its CSV in docs/figures instead of re-running it.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib.sh
build=${1:-build}
threads=${2:-2}
sizes=${3:-16 43 138}
cmake --build "$build" --target bench_work_precision -j 2 >/dev/null
mkdir -p docs/figures
commit=$(bench_commit core bench)
cpu=$(bench_cpu)
body=""
for a in $sizes; do
  mode=""
  [ "$a" -ge 100 ] && mode=small
  csv="docs/figures/work_precision_a$a.csv"
  # REUSE_SIZES="138": keep that scene's committed CSV (it takes half an hour) and only redraw.
  if [[ " ${REUSE_SIZES:-} " == *" $a "* ]] && [ -s "$csv" ]; then
    :
  else
    "$build/bin/bench_work_precision" "$a" 535 "$threads" $mode >"$csv"
  fi
  # Issue 7: running twice gives figures within noise. The smaller scenes run a second time
  # and the reading reports the spread (the large one would double half an hour).
  csv2=""
  if [ -z "$mode" ]; then
    csv2=$(mktemp)
    "$build/bin/bench_work_precision" "$a" 535 "$threads" >"$csv2"
  fi
  png="docs/figures/work_precision_a$a.png"
  body+=$(python3 - "$csv" "$png" "$a" "$csv2" <<'PY'
import csv, io, subprocess, sys
path, png, a, path2 = sys.argv[1:5]
lines = open(path).read().splitlines()
head = [l for l in lines if l.startswith("#")]
rows = list(csv.DictReader(io.StringIO("\n".join(l for l in lines if not l.startswith("#")))))
fams = []
for r in rows:
    if r["family"] not in fams: fams.append(r["family"])
floor = 1e-8
script = [f"set terminal pngcairo size 900,600 noenhanced", f"set output '{png}'", "set logscale xy",
          "set xlabel 'wall time (s)'", "set ylabel '|mu / mu_converged - 1|'",
          f"set title 'Work-precision, a = {a} d, R = 535 d (errors below 1e-8 drawn at 1e-8)'",
          "set key outside right", "set grid"]
plots, data = [], []
for f in fams:
    pts = sorted((float(r["wall_s"]), max(float(r["error"]), floor)) for r in rows if r["family"] == f)
    plots.append(f"'-' with linespoints pt 7 title '{f}'")
    data.append("\n".join(f"{x} {y}" for x, y in pts) + "\ne")
d = [r for r in rows if r["default"] == "1"]
if d:
    plots.append("'-' with points pt 6 ps 3 lw 2 lc 'black' title 'default'")
    data.append(f"{d[0]['wall_s']} {max(float(d[0]['error']), floor)}\ne")
script.append("plot " + ", ".join(plots))
subprocess.run(["gnuplot"], input="\n".join(script + data) + "\n", text=True, check=True)
# Pareto check: no setting both faster and more accurate than the default beyond noise
# (wall 20%, error 2x or 1e-6 absolute).
note = ""
if d:
    dw, de = float(d[0]["wall_s"]), float(d[0]["error"])
    better = [r for r in rows if float(r["wall_s"]) < 0.8 * dw and float(r["error"]) < min(0.5 * de, max(de - 1e-6, 0))]
    note = "default on the Pareto front" if not better else "dominated by: " + ", ".join(r["family"] + " " + r["setting"] for r in better)
classic = [r for r in rows if r["family"].startswith("classic")]
ratio = ""
if d and classic:
    fft = lambda r: int(r['gf_applications']) + int(r.get('filter_applications') or 0)
    ratio = f"; classic / default wall time: {float(classic[0]['wall_s']) / float(d[0]['wall_s']):.1f}x, FFT pairs (GF applications + filter passes) {fft(classic[0]) / fft(d[0]):.1f}x"
spread = ""
if path2:
    lines2 = open(path2).read().splitlines()
    rows2 = {(r["family"], r["setting"]): r for r in csv.DictReader(io.StringIO("\n".join(l for l in lines2 if not l.startswith("#"))))}
    same = all(k in rows2 and rows2[k]["mu_over_alpha"] == r["mu_over_alpha"] and rows2[k]["gf_applications"] == r["gf_applications"] for r in rows for k in [(r["family"], r["setting"])])
    q = sorted(float(rows2[(r["family"], r["setting"])]["wall_s"]) / float(r["wall_s"]) for r in rows if (r["family"], r["setting"]) in rows2)
    spread = f" Second run of the script: mu and GF applications {'identical in every row' if same else 'DIFFER'}; wall time second/first {q[0]:.2f} to {q[-1]:.2f} (median {q[len(q)//2]:.2f})"
    if d and classic:
        d2, c2 = rows2.get((d[0]["family"], d[0]["setting"])), rows2.get((classic[0]["family"], classic[0]["setting"]))
        if d2 and c2:
            spread += f", classic / default {float(c2['wall_s']) / float(d2['wall_s']):.1f}x"
    spread += "."
out = [f"### a = {a} d", "", head[0].lstrip("# ") if head else "", "",
       "| family | setting | mu/alpha | error | wall (s) | GF applications | filter passes | gradient evaluations | steps | slips |",
       "|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    mark = " **(default)**" if r["default"] == "1" else ""
    fail = " (failed)" if r["failed"] == "1" else ""
    out.append(f"| {r['family']} | {r['setting']}{mark} | {float(r['mu_over_alpha']):.6f} | {float(r['error']):.1e} | {float(r['wall_s']):.2f} | {r['gf_applications']} | {r.get('filter_applications') or 0} | {r['gradient_evaluations']} | {r['steps']} | {r['slips']}{fail} |")
out += ["", f"![work-precision a = {a}](figures/work_precision_a{a}.png)", "", f"Reading: {note}{ratio}.{spread}", ""]
print("\n".join(out))
PY
)$'\n\n'
  [ -n "$csv2" ] && rm -f "$csv2"
done
section=$(cat <<EOT
## Work-precision of whole slides (bench/run_work_precision.sh)

Provenance: commit $commit, $(date -u +%Y-%m-%d), $cpu, $(nproc) cores, $threads FFT threads;
command \`bench/run_work_precision.sh\`. R = 535 d, alpha = 0.7, nu = 0.5, automatic distance
(through the second slip). Error: |mu / mu_converged - 1|, the reference converged by the
adaptive protocol at tolerance 1e-8 with instabilities bracketed to 1e-4 d (its own change
when both are refined is given per scene). All settings of a scene run in one process, one
after the other; wall times on this shared 2-core machine vary by +-30% between runs (GF
applications and gradient evaluations do not), so a = 16 and 43 d report the fastest of three
runs of each setting, and a = 138 d a single run. Raw rows: docs/figures/work_precision_a*.csv.
The default preconditioner is automatic (docs/solvers.md): G alone below a/b_core^0 = 10, the
interface filter above; the "(elastic preconditioner)" and "(interface preconditioner)" rows
force one of them. A filter pass is an FFT pair like a GF application, so the cost ratios count
both. "steps" counts computed steps: the adaptive protocol replays the second stick-slip cycle
once it is shown to repeat (docs/solvers.md), and those rows cost nothing.

$body
EOT
)
echo "$section" | bench/record_section.sh "## Work-precision of whole slides"
