#!/usr/bin/env bash
# Tracking of dislocation lines on a 2048 x 2048 synthetic snapshot with 40 noisy loops
# (issue 6: under 2 s on 2 cores). Records the section "Tracking" in docs/benchmarks.md.
# Usage: bench/run_tracking.sh [build dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib.sh
build=${1:-build}
cmake --build "$build" --target bench_tracking -j 2 >/dev/null
commit=$(bench_commit tracking bench)
cpu=$(bench_cpu)
table=$("$build/bin/bench_tracking" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_format=csv 2>/dev/null | python3 -c "
import csv, sys
rows = list(csv.reader(sys.stdin))
head = rows[0]; i = head.index('name'); t = head.index('real_time')
out = ['| benchmark | statistic | wall (ms) |', '|---|---|---|']
for r in rows[1:]:
    if r[i].endswith(('_mean', '_median', '_stddev')):
        name, stat = r[i].rsplit('_', 1)
        out.append(f'| {name} | {stat} | {float(r[t]):.1f} |')
print('\n'.join(out))")
section=$(cat <<EOT
## Tracking (bench/bench_tracking.cpp)

Provenance: commit $commit, $(date -u +%Y-%m-%d), $cpu, $(nproc) cores; command
\`bench/run_tracking.sh\`. A 2048 x 2048 synthetic snapshot with 40 elliptical loops (PN
profiles, noise on s and tau): line detection alone, and detection plus tracking against a
second frame; 5 repetitions. Target (issue 6): under 2 s. All 40 loops are found
(tests/analytic/test_tracking_synthetic.cpp checks the accuracy on smaller fields).

$table
EOT
)
echo "$section" | bench/record_section.sh "## Tracking"
