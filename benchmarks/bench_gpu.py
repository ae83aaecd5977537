"""Exact stick-slip cycles per second on a CUDA GPU against the CPU engine, same work, same run.

Work: the steady stick-slip cycle of law F1 (the workload of ``bench_cycles.py``: ``nu``
log-uniform in [1e-5, 1e-1], ``c`` uniform in [0.5, 50], rtol 1e-9, atol 1e-12). The GPU
runs ``run_attractors(..., backend="cuda")``: the CPU engine's own per-row function
compiled by numba-cuda, one parameter set per thread, double precision. The CPU engine
runs a subset on this machine's cores; the two are compared on that subset (statuses
equal, amplitudes to 1e-8). The device is named. Where no GPU is usable, the script
says why and stops: the speed is then unmeasured (the numbers of docs/benchmarks.md
come from a run on a GPU, or say that there was none).

diffrax (JAX) is not compared here: the issue's figure for it on an H100 is quoted
in docs/benchmarks.md; a comparison in this script needs JAX on the GPU's machine.

Run: python benchmarks/bench_gpu.py [--n 10000000] [--n-cpu 200000]
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time

import numpy as np
from bench_cycles import ATOL, RTOL, workload

from stickslip.core import cuda as core_cuda
from stickslip.core.api import run_attractors
from stickslip.laws import WeakeningLaw


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000_000, help="parameter sets on the GPU")
    ap.add_argument("--n-cpu", type=int, default=200_000, help="parameter sets on the CPU (the first ones)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    ok, device = core_cuda.cuda_status()
    if not ok or core_cuda.simulator():
        print(f"no GPU to measure on: {device}; the GPU speed is unmeasured")
        sys.exit(0)
    _, nu, c = workload(args.n, args.seed)
    lp = c[:, None]
    kernel = WeakeningLaw(c=1.0).kernel
    kw = dict(from_breakaway=True, rtol=RTOL, atol=ATOL, max_slip_time=1e4, conv_tol=1e-8)

    t0 = time.perf_counter()
    run_attractors(kernel, lp[:1024], nu[:1024], backend="cuda", **kw)
    t_compile = time.perf_counter() - t0
    t0 = time.perf_counter()
    gpu = run_attractors(kernel, lp, nu, backend="cuda", **kw)
    t_gpu = time.perf_counter() - t0

    m = min(args.n_cpu, args.n)
    run_attractors(kernel, lp[:8], nu[:8], **kw)  # compile or load from the cache
    t0 = time.perf_counter()
    cpu = run_attractors(kernel, lp[:m], nu[:m], **kw)
    t_cpu = time.perf_counter() - t0

    same_status = bool(np.array_equal(gpu.status[:m], cpu.status))
    okm = cpu.status == 0
    rel = np.abs(gpu.amplitude[:m][okm] - cpu.amplitude[okm]) / np.abs(cpu.amplitude[okm])
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; GPU: {device}")
    print(f"work: F1 steady stick-slip cycles, nu log-uniform [1e-5, 1e-1], c in [0.5, 50], rtol {RTOL:g}")
    print(
        f"GPU  : {args.n:10d} cycles in {t_gpu:8.3f} s = {args.n / t_gpu:14.0f} cycles/s"
        f"  (first call incl. compile {t_compile:.1f} s)"
    )
    print(f"CPU  : {m:10d} cycles in {t_cpu:8.3f} s = {m / t_cpu:14.0f} cycles/s ({os.cpu_count()} cores)")
    print(f"ratio: {(args.n / t_gpu) / (m / t_cpu):.1f} x the CPU engine")
    worst = float(rel.max()) if rel.size else float("nan")
    print(
        f"agreement on the {m} common sets: statuses equal {same_status}, amplitude largest relative "
        f"difference {worst:.3e} (median {float(np.median(rel)):.3e})"
    )


if __name__ == "__main__":
    main()
