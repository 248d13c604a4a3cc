#!/usr/bin/env bash
# Tracking of dislocation lines on a 2048 x 2048 synthetic snapshot with 40 noisy loops
# (issue 6: under 2 s on 2 cores), and the stress held along them (front_stresses) at three
# spans beside its error in loaded cells. Records the section "Tracking" in docs/benchmarks.md.
# Usage: bench/run_tracking.sh [build dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib.sh
build=${1:-build}
cmake --build "$build" --target bench_tracking -j 2 >/dev/null
commit=$(bench_commit tracking bench)
cpu=$(bench_cpu)
# JSON, not CSV: the benchmarks have different counters, which Google Benchmark's CSV
# reporter refuses (it aborts at the first run whose counters differ from the first's).
table=$("$build/bin/bench_tracking" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_format=json 2>/dev/null | python3 -c "
import json, sys
runs = json.load(sys.stdin)['benchmarks']
out = ['| benchmark | statistic | wall (ms) | points | resolved | error in loaded cells (tau_P) |',
       '|---|---|---|---|---|---|']
for r in runs:
    stat = r.get('aggregate_name', '')
    if stat not in ('mean', 'median', 'stddev'):
        continue
    more = [f'{r[c]:.4g}' if c in r and stat != 'stddev' else ''
            for c in ('points', 'resolved', 'cell_error_tau_P')]
    out.append(f'| {r[\"run_name\"]} | {stat} | {r[\"real_time\"]:.1f} | ' + ' | '.join(more) + ' |')
print('\\n'.join(out))")
section=$(cat <<EOT
## Tracking (bench/bench_tracking.cpp)

Provenance: commit $commit, $(date -u +%Y-%m-%d), $cpu, $(nproc) cores; command
\`bench/run_tracking.sh\`. A 2048 x 2048 synthetic snapshot with 40 elliptical loops (PN
profiles, noise on s and tau): line detection alone, and detection plus tracking against a
second frame; 5 repetitions. Target (issue 6): under 2 s. All 40 loops are found
(tests/analytic/test_tracking_synthetic.cpp checks the accuracy on smaller fields).
BM_Front2048/<span>: the stress held along the lines (\`tracking::front_stresses\`, span 8,
16 and 32 d) on the same loops with narrow cores (tau_peak 0.56 G, b_core about 1.8 d, as at
R = 800 d, a = 300 d), its points and resolved points, beside its error: the worst resolved
point's miss of the load in loaded Peierls cells of lines (1, 0), (2, 1), (4, 1), (8, 1) and
(1, 8) at b_core = 2 d, in units of each cell's tau_P (a span shorter than a direction's
period |m| d misses it; the rest is the window's left-out tail).

$table
EOT
)
echo "$section" | bench/record_section.sh "## Tracking"
