#!/usr/bin/env bash
# Runs bench_slide (whole slides, speed against error) on the default scene and on a = 138 d,
# and records the tables in docs/benchmarks.md with provenance.
# Usage: bench/run_slide.sh [build dir] [threads]   (defaults: build, 2)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
threads=${2:-2}
cmake --build "$build" --target bench_slide -j 2 >/dev/null
commit=$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- core bench || echo "+changes")
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
table=$("$build/bin/bench_slide" "$threads")
section=$(cat <<EOT
## Whole slides: speed against error (bench/bench_slide.cpp)

Default scene (a = 43 d, R = 535 d, alpha = 0.7, automatic distance through the second slip).
Error: |mu / mu_converged - 1| against a converged run (adaptive, tolerance 1e-8, min_step
1e-4). Gradient evaluations: interface force evaluations, line searches included. Wall times
on this shared virtual machine vary by +-30% between runs; GF applications do not.

Provenance: commit $commit, $(date -u +%Y-%m-%d), $cpu, $(nproc) cores, $threads FFT threads;
command \`bench/run_slide.sh\`.

$table
EOT
)
printf '%s\n' "$section" | bench/record_section.sh "## Whole slides"
