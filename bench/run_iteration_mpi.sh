#!/usr/bin/env bash
# One L-BFGS iteration of a contact spread over MPI ranks (issue 26, item 5): padded grids 2048^2
# and 4096^2 (a = 505 and 1015 d, R = 1700 d), the serial engine on one process, then the
# FFTW-MPI engine on 1 and 2 ranks, one FFTW thread per rank, 12 iterations each: JSON lines on
# stdout (bench/bench_iteration_mpi.cpp says what each field is); docs/benchmarks.md, "One
# contact over MPI ranks". Usage: bench/run_iteration_mpi.sh [build dir] [iterations]
set -euo pipefail
build=${1:-build}
iterations=${2:-12}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
echo "# commit $(git rev-parse --short HEAD), $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
for grid in 2048 4096; do
  mpirun -np 1 "$build/bin/bench_iteration_mpi" "$grid" "$iterations" 1 --serial
  for np in 1 2; do
    mpirun -np "$np" --oversubscribe "$build/bin/bench_iteration_mpi" "$grid" "$iterations" 1
  done
done
