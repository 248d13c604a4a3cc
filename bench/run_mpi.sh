#!/usr/bin/env bash
# One GF application on the FFTW-MPI engine (issue 26) at 2048^2 and 4096^2 padded grids
# (regions 1024^2 and 2048^2), 1 and 2 ranks of one FFTW thread each, 5 repeats: JSON lines on
# stdout (bench/bench_gf_mpi.cpp says what each field is). Usage: bench/run_mpi.sh [build dir]
set -euo pipefail
build=${1:-build}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "# commit $(git rev-parse --short HEAD), $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
for n in 1024 2048; do
  for np in 1 2; do
    mpirun -np "$np" --oversubscribe "$build/bin/bench_gf_mpi" "$n" "$n" 5 1
  done
done
