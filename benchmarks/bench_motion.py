"""Benchmark: the slider's motion from a real 375 s record at 2 kHz (750 000 samples), on one core.

The record is ``k168Nm_v42.mat`` of Colas et al., Phys. Rev. E 100, 032803 (2019), read
from ../shared/data/colas2019/. ``measure_motion`` (spikes, stiffness from the stick
slopes, exact TV denoising, events, cycles, regime, mass) is timed against the
straightforward SciPy way of one of its steps alone: total-variation denoising by
``scipy.optimize.minimize`` (L-BFGS-B on the smoothed problem, sqrt(d^2 + eps^2) for
|d|) on the first 20 000 samples, scaled to the whole record, and its distance to the
exact solution. Usage::

    NUMBA_NUM_THREADS=1 python benchmarks/bench_motion.py [--scipy-samples 20000]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from scipy.optimize import minimize

from stickslip.core.tv import tv_denoise
from stickslip.data.motion import measure_motion
from stickslip.io.formats import RecordOptions
from stickslip.io.records import read_record

HERE = os.path.dirname(os.path.abspath(__file__))
RECORD = os.path.join(HERE, "..", "..", "shared", "data", "colas2019", "k168Nm_v42.mat")


def tv_scipy(y: np.ndarray, lam: float, eps: float) -> np.ndarray:
    def objective(x: np.ndarray) -> tuple[float, np.ndarray]:
        d = np.diff(x)
        s = np.sqrt(d * d + eps * eps)
        g = x - y
        w = lam * d / s
        g[:-1] -= w
        g[1:] += w
        return 0.5 * float(np.sum((x - y) ** 2)) + lam * float(np.sum(s)), g

    return minimize(objective, y.copy(), jac=True, method="L-BFGS-B", options={"maxiter": 20000}).x


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scipy-samples", type=int, default=20_000)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    rec = read_record(
        RECORD, mass="30.7 g", load="weight", options=RecordOptions(name_pattern="k{stiffness}Nm_v{v0}")
    )
    measure_motion(rec)  # compiles (cached after the first run)
    times = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        _, motion, s = measure_motion(rec)
        times.append(time.perf_counter() - t0)
    best = min(times)
    print(f"record: {rec.name}, {rec.time.size} samples ({rec.time[-1] - rec.time[0]:.0f} s at 2 kHz)")
    print(f"measure_motion: best {best:.3f} s of {args.repeats} (median {np.median(times):.3f} s)")
    print(
        f"  {s.regime}: {s.n_events} events, recurrence {s.recurrence:.3f} s, stick {s.stick_fraction:.3f}, "
        f"k {s.stiffness:.1f} N/m, m {1e3 * s.mass:.1f} g"
    )
    n = args.scipy_samples
    y = s.v0 * rec.time[:n] - motion.force[:n] / s.stiffness
    lam = s.tv_weight
    t0 = time.perf_counter()
    exact = tv_denoise(y, lam)
    t_exact = time.perf_counter() - t0
    t0 = time.perf_counter()
    smooth = tv_scipy(y, lam, eps=1e-3 * s.noise / s.stiffness)
    t_scipy = time.perf_counter() - t0
    scale = rec.time.size / n
    print(
        f"TV denoising of {n} samples: exact (Condat, numba) {t_exact * 1e3:.2f} ms; "
        f"SciPy L-BFGS-B {t_scipy:.2f} s"
    )
    print(
        f"  ratio {t_scipy / t_exact:.0f}x; SciPy scaled to the whole record {t_scipy * scale:.1f} s; "
        "SciPy's distance to the exact solution "
        f"{np.max(np.abs(smooth - exact)) / (s.noise / s.stiffness):.3g} noise deviations of position (max)"
    )


if __name__ == "__main__":
    main()
