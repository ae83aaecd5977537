"""Benchmark: measuring a force-time record of 10^6 samples.

A synthetic stick-slip record from the model (the paper's zv set-up at 100 um/s,
1 mN noise, 0.05 mN/s drift) is measured by ``measure_record`` and, the
straightforward way, by ``scipy.signal.find_peaks`` on the raw force with the raw
extremes as values. Prints the times, their ratio and the amplitude and period
errors of both against the exact cycle. Usage::

    python benchmarks/bench_records.py [--samples 1000000]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.signal import find_peaks

import stickslip as S
from stickslip.data.records import measure_record, synthetic_record


def straightforward(t: np.ndarray, f: np.ndarray, period_guess: float) -> tuple[float, float]:
    dt = t[1] - t[0]
    pk, _ = find_peaks(f, distance=int(0.5 * period_guess / dt))
    tr, _ = find_peaks(-f, distance=int(0.5 * period_guess / dt))
    amps = [f[p] - f[tr[tr > p][0]] for p in pk[:-1] if np.any(tr > p)]
    return float(np.median(amps)), float(np.median(np.diff(t[pk])))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000)
    args = ap.parse_args()
    p = S.zv_parameters("100 um/s")
    true = S.cycle(p, probe=False)
    duration = 60 * true.period
    rate = (args.samples - 1) / duration
    rec = synthetic_record(
        p,
        duration=f"{duration} s",
        rate=f"{rate} Hz",
        noise="1 mN",
        drift="0.05 mN/s",
        start=f"{true.transient_time} s",
    )
    measure_record(rec)  # warm-up (imports)
    t0 = time.perf_counter()
    _, s = measure_record(rec)
    t_ours = time.perf_counter() - t0
    t0 = time.perf_counter()
    amp_sp, per_sp = straightforward(rec.time, rec.force, true.period)
    t_sp = time.perf_counter() - t0
    print(
        f"record: {rec.time.size} samples, {s.n_cycles} cycles, {rate:.0f} Hz, noise 1 mN "
        f"(amplitude {1e3 * true.amplitude:.1f} mN), drift 0.05 mN/s"
    )
    print(
        f"measure_record  : {t_ours:.3f} s; amplitude error {s.amplitude / true.amplitude - 1:+.2e}, "
        f"period error {s.period / true.period - 1:+.2e}"
    )
    print(
        f"find_peaks (raw): {t_sp:.3f} s; amplitude error {amp_sp / true.amplitude - 1:+.2e}, "
        f"period error {per_sp / true.period - 1:+.2e}"
    )
    print(f"time ratio measure_record / find_peaks: {t_ours / t_sp:.2f}")


if __name__ == "__main__":
    main()
