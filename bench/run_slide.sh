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

Reading: L-BFGS with H0 = gamma G is the fastest robust minimiser (CG needs 10% more GF
applications and twice the gradient evaluations; FIRE and the Newton-Krylov finish, whose
GMRES is unpreconditioned, are 10x slower). The adaptive protocol gets mu to 1e-6 with a
quarter of the GF applications of the fixed 0.01 d protocol, whose sampled peak is 1e-5 low.
The stability check costs 15% (it is what keeps symmetric saddles from being returned).
Target of the issue, not yet met: 10x faster than the classic protocol at equal error (0.5%);
the default is 3.5-4x faster at 100x smaller error, and 7x with tolerance 1e-5 and min_step
0.01 d (error 3e-4). Per-iteration cost: FFTs 40%, interface evaluation 20%, L-BFGS vector
work 20% (perf, a = 95 d).
EOT
)
printf '%s\n' "$section" | bench/record_section.sh "## Whole slides"
