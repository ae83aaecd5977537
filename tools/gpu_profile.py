"""Profile one launch of the GPU kernel with Nsight Compute (on a lent GPU machine).

    ncu --launch-skip 1 --launch-count 1 --section ... python3 tools/gpu_profile.py [rows]

The first launch (256 rows) compiles the kernel; the second, ``rows`` F1 rows of
``benchmarks/bench_cycles.py``'s workload, is the one profiled.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from stickslip.core import engine
from stickslip.core.api import run_attractors
from stickslip.laws import WeakeningLaw


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1 << 18
    rng = np.random.default_rng(0)
    nu = 10 ** rng.uniform(-5, -1, n)
    c = rng.uniform(0.5, 50.0, n)
    kw = dict(from_breakaway=True, rtol=1e-9, atol=1e-12, max_slip_time=1e4, conv_tol=1e-8)
    kernel = WeakeningLaw(c=1.0).kernel
    run_attractors(kernel, c[:256, None], nu[:256], backend="cuda", **kw)
    t0 = time.perf_counter()
    out = run_attractors(kernel, c[:, None], nu, backend="cuda", **kw)
    dt = time.perf_counter() - t0
    steps = out.raw[:, engine.O_NSTEP] + out.raw[:, engine.O_NREJECT]
    print(f"{n} rows in {dt:.3f} s; steps a row: mean {np.mean(steps):.1f}, max {np.max(steps):.0f}")


if __name__ == "__main__":
    main()
