#!/usr/bin/env bash
# Runs the GF micro-benchmark and records it in docs/benchmarks.md (section "GF application"),
# with provenance. Usage: bench/run_micro.sh [build dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/lib.sh
build=${1:-build}
cmake --build "$build" --target bench_gf -j 2 >/dev/null
json=$(mktemp)
"$build/bin/bench_gf" --benchmark_filter='BM_(Periodic|FreeGF|BareFFT|Lfm|Lbfgs)' \
  --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_format=json >"$json" 2>/dev/null
commit=$(bench_commit core bench)
cpu=$(bench_cpu)
# Median times (ms) per benchmark name, from Google Benchmark's JSON.
median() {
  grep -A12 "\"name\": \"$1/real_time_median\"" "$json" | grep '"real_time"' | head -1 |
    sed 's/.*: *\([0-9.e+-]*\).*/\1/'
}
stddev() {
  grep -A12 "\"name\": \"$1/real_time_stddev\"" "$json" | grep '"real_time"' | head -1 |
    sed 's/.*: *\([0-9.e+-]*\).*/\1/'
}
rows=""
for t in 1 2; do
  gf=$(median "BM_FreeGFInPlane/512/$t"); gfs=$(stddev "BM_FreeGFInPlane/512/$t")
  bare=$(median "BM_BareFFTPair/512/$t"); bares=$(stddev "BM_BareFFTPair/512/$t")
  ratio=$(awk -v a="$gf" -v b="$bare" 'BEGIN{printf "%.3f", a/b}')
  rows+=$(printf '| %s | %.2f +- %.2f | %.2f +- %.2f | %s |' "$t" "$gf" "$gfs" "$bare" "$bares" "$ratio")$'\n'
done
pbuild=$(median "BM_PeriodicGFBuild/256/iterations:2")
papply=$(median "BM_PeriodicGFApply/256"); papplys=$(stddev "BM_PeriodicGFApply/256")
force=$(median "BM_LfmInterfaceForce"); forces=$(stddev "BM_LfmInterfaceForce")
curv=$(median "BM_LfmInterfaceCurvature"); curvs=$(stddev "BM_LfmInterfaceCurvature")
iter=$(median "BM_LbfgsIteration"); iters=$(stddev "BM_LbfgsIteration")
gf43=$(median "BM_FreeGFInPlane/91/1")
section=$(cat <<EOT
## GF application (bench/bench_gf.cpp)

One application of the 2x2 free-boundary GF (512 x 512 loaded sites, 1024 x 1024 padded grid)
against the bare FFTW transforms it needs (forward + inverse of two 1024 x 1024 real fields),
FFTW_MEASURE plans, median of 5 repetitions (+- standard deviation), in ms. The issue requires a
ratio of at most 1.3. The GF is exact (exact linear convolution): its error is not a trade-off
here.

Provenance: commit $commit, $(date -u +%Y-%m-%d), $cpu, $(nproc) cores; command
\`bench/run_micro.sh\`.

| threads | GF apply (ms) | bare FFT pair (ms) | ratio |
|---|---|---|---|
$rows
Periodic GF of a 256 x 256 cell (in-plane, 12 Poisson images per direction: relative truncation
error about 6e-5, see tests/unit/test_surface_gf.cpp): building the kernel
$(printf '%.0f' "$pbuild") ms (once per cell, one thread), one application $(printf '%.3f +- %.3f' "$papply" "$papplys") ms.

Lateral force model on the default scene's block (a = 43 d: 91 x 91 block, 5802 contact sites,
192 x 192 grid; 189 x 189 before 2026-11-27), one thread: interface force and energy $(printf '%.1f +- %.1f' "$force" "$forces") us,
Hessian diagonal $(printf '%.1f +- %.1f' "$curv" "$curvs") us, one GF application $(printf '%.3f' "$gf43") ms, one L-BFGS
iteration (GF application, line search, two-loop recursion; mean over a 40-iteration
relaxation) $(awk -v t="$iter" 'BEGIN{printf "%.3f", t/40}') ms: the GF application is $(awk -v g="$gf43" -v t="$iter" 'BEGIN{printf "%.0f", 100*g/(t/40)}')% of an
iteration, the rest the interface evaluations of the line search and the L-BFGS vector work.
EOT
)
rm -f "$json"
printf '%s\n' "$section" | bench/record_section.sh "## GF application"
