#!/usr/bin/env python3
"""Cluster estimate for one contact over MPI ranks (issue 26, item 5), calibrated on this
machine's measurements in docs/benchmarks.md ("One contact over MPI ranks").

Per L-BFGS iteration (2 FFT pairs: a GF application and an interface filter pass), on P ranks:
  T(P) = [2 t_pair(N) + t_site S] / P  +  V(N) / (P B)  +  L log2(P) c
- t_pair(N): one distributed GF application's transforms and products on one core, scaled from
  the measured 4096^2 value as N^2 log N;
- t_site: the solvers' per-site work per iteration (the iteration's time less its FFTs);
- V(N): bytes of the all-to-all transposes per iteration, 2 applications x 2 fields x 2
  transposes (forward, inverse) of the N x (N/2 + 1) complex half-grid;
- B: all-to-all bandwidth per rank (assumed; this 2-core machine cannot measure a network);
- L, c: latency of a collective and collectives per iteration (dot products and maxima).
Memory per rank: the measured bytes per grid point of a whole slide (grid buffers, kernels,
states) / P, plus MPI and the program. Iterations through the first slip: scaled from the
measured a = 430 d slide (issue 22: 5908 iterations) with a range, since the count depends on
the contact's regime (a / b_core^0) and is not measured at these sizes.
Usage: bench/cluster_model.py [--bandwidth GB/s] [--latency us]
"""
import argparse
import math


def seven_smooth_at_least(n):
    m = n
    while True:
        k = m
        for p in (2, 3, 5, 7):
            while k % p == 0:
                k //= p
        if k == 1:
            return m
        m += 1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bandwidth", type=float, default=2.0, help="all-to-all GB/s per rank")
    ap.add_argument("--latency", type=float, default=20.0, help="collective latency, us")
    ap.add_argument("--memory-per-rank", type=float, default=4.0, help="GB a rank may use")
    args = ap.parse_args()
    # Calibration (docs/benchmarks.md, bench_iteration_mpi at 4096^2, FFTW-MPI engine, 1 rank,
    # 1 thread: 1910 ms per iteration, of it 1388 ms in the GF application and filter pass).
    n_cal, t_iter_cal, t_fft_cal, sites_cal = 4096, 1.910, 1.388, 3236500
    t_pair_cal = t_fft_cal / 2
    t_site = (t_iter_cal - t_fft_cal) / sites_cal
    bytes_per_point = 260.0  # slider.hpp estimated_slide_bytes, measured 248-254 (scaling)
    collectives = 12  # dot products and maxima per L-BFGS iteration
    # Iterations through the first slip: a = 430 d took 5908 (issue 22). Assumed, not measured:
    # 2-5x that at a = 1000 d (a / b_core^0 5.4x larger at the same R, the interface filter
    # keeping the growth below linear) and 10-100x at a = 3e4 d.
    iterations_430 = 5908
    iteration_range = {1000.0: (2 * iterations_430, 5 * iterations_430),
                       3.0e4: (10 * iterations_430, 100 * iterations_430)}
    for a in (1000.0, 3.0e4):
        n_block = 2 * (math.ceil(a) + 2) + 1
        N = seven_smooth_at_least(2 * n_block - 1)
        sites = math.pi * a * a
        t_pair = t_pair_cal * (N * N * math.log(N)) / (n_cal * n_cal * math.log(n_cal))
        work = 2 * t_pair + t_site * sites  # core-seconds per iteration
        volume = 2 * 2 * 2 * N * (N // 2 + 1) * 16.0  # bytes per iteration
        total_mem = bytes_per_point * N * N + 35e6
        P = 1
        while total_mem / P > args.memory_per_rank * 1e9:
            P *= 2
        print(f"a = {a:g} d: block {n_block}^2, padded grid {N}^2, {sites:.3g} contact sites, "
              f"memory {total_mem / 1e9:.3g} GB in all")
        for ranks in sorted({P, 4 * P, 16 * P}):
            t = (work / ranks + volume / (ranks * args.bandwidth * 1e9)
                 + args.latency * 1e-6 * math.log2(max(ranks, 2)) * collectives)
            lo, hi = iteration_range[a]
            print(f"  {ranks:6d} ranks: {total_mem / ranks / 1e9:7.3g} GB per rank, "
                  f"{t:8.3g} s per iteration; through the first slip "
                  f"({lo:.3g}-{hi:.3g} iterations): {lo * t / 3600:.3g}-{hi * t / 3600:.3g} h")


if __name__ == "__main__":
    main()
