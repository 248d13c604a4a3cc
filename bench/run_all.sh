#!/usr/bin/env bash
# Every benchmark of the project, one after the other, each recording its section of
# docs/benchmarks.md with provenance (commit, date, machine, threads, command) and its figures
# in docs/figures/. Run it on a quiet machine: the sections report wall times.
# Usage: bench/run_all.sh [build dir]   (default: build). About 50-60 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
bash bench/run_micro.sh "$build"
bash bench/run_padded_sizes.sh "$build"
bash bench/run_threads.sh "$build"
bash bench/run_iteration.sh "$build"
bash bench/run_memory.sh "$build"
bash bench/run_tracking.sh "$build"
bash bench/run_peierls.sh "$build"
bash bench/run_scaling.sh "$build"
bash bench/run_work_precision.sh "$build"
bash bench/run_explicit.sh "$build"
bash bench/run_step_growth.sh "$build"
bash bench/run_flow_first.sh "$build"
# Not here: bench/run_path_tier.sh (every solver against the reference flow, about 2 hours and
# more for the large scenes); it prints its table for docs/benchmarks.md and resumes.
