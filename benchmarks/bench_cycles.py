"""Benchmark: steady stick-slip cycles per second, batched engine against plain SciPy.

Work: the steady stick-slip cycle (amplitude = range of the spring force) of law
F1, ``f(w) = 1/(1 + c w)``, for random parameter sets with ``nu`` log-uniform
in [1e-5, 1e-1] and ``c`` uniform in [0.5, 50], at rtol 1e-9.

* stickslip: ``run_attractors`` (the batched compiled engine, all cores);
* the same law typed as a formula, ``ExpressionLaw("1/(1 + c*w)", c=...)``: the
  engine generated and compiled for it (``stickslip.laws.compiler``), ``c`` a
  parameter per row, on the same work;
* SciPy: ``solve_ivp(method="DOP853")`` from breakaway with events for the stop
  (terminal) and for ``w = nu`` (spring-force extrema), the way one would write
  it by hand; on a random subset, since it is slow.

Prints the rates, their ratios, and the largest relative differences in
amplitude. Usage::

    python benchmarks/bench_cycles.py [--n 200000] [--n-scipy 200] [--seed 0]
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
from scipy.integrate import solve_ivp

from stickslip.core.api import run_attractors
from stickslip.laws import ExpressionLaw, WeakeningLaw

RTOL = 1e-9
ATOL = 1e-12


def scipy_cycle(nu: float, c: float, rtol: float = RTOL, atol: float = ATOL) -> float:
    """Amplitude of the steady stick-slip cycle, the straightforward SciPy way."""

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [nu - y[1], y[0] - 1.0 / (1.0 + c * y[1])]

    def stop(_t: float, y: np.ndarray) -> float:
        return y[1]

    stop.terminal = True  # type: ignore[attr-defined]
    stop.direction = -1  # type: ignore[attr-defined]

    def extremum(_t: float, y: np.ndarray) -> float:
        return y[1] - nu

    sol = solve_ivp(
        rhs, (0.0, 1e4), [1.0, 0.0], method="DOP853", rtol=rtol, atol=atol, events=[stop, extremum]
    )
    s = np.concatenate(
        [[1.0], np.reshape(sol.y_events[1], (-1, 2))[:, 0], np.reshape(sol.y_events[0], (-1, 2))[:, 0]]
    )
    return float(s.max() - s.min())


def workload(n: int, seed: int) -> tuple[np.random.Generator, np.ndarray, np.ndarray]:
    """The benchmark's parameter sets: ``nu`` log-uniform in [1e-5, 1e-1], ``c`` uniform in [0.5, 50]."""
    rng = np.random.default_rng(seed)
    nu = 10 ** rng.uniform(-5, -1, n)
    c = rng.uniform(0.5, 50.0, n)
    return rng, nu, c


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=200_000, help="parameter sets for stickslip")
    ap.add_argument("--n-scipy", type=int, default=200, help="parameter sets for SciPy")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()

    rng, nu, c = workload(args.n, args.seed)
    lp = c[:, None]
    builtin = WeakeningLaw(c=1.0).kernel
    formula = ExpressionLaw("1/(1 + c*w)", c=1.0).kernel  # generated, compiled once, cached

    def engine_run(kernel, k: int | None = None):  # type: ignore[no-untyped-def]
        sl = slice(None) if k is None else slice(0, k)
        return run_attractors(
            kernel,
            lp[sl],
            nu[sl],
            from_breakaway=True,
            rtol=RTOL,
            atol=ATOL,
            max_slip_time=1e4,
            conv_tol=1e-8,
        )

    t0 = time.perf_counter()
    engine_run(builtin, 4)
    t_compile = time.perf_counter() - t0
    t0 = time.perf_counter()
    engine_run(formula, 4)
    t_compile_formula = time.perf_counter() - t0
    t0 = time.perf_counter()
    out = engine_run(builtin)
    t_engine = time.perf_counter() - t0
    t0 = time.perf_counter()
    out_formula = engine_run(formula)
    t_formula = time.perf_counter() - t0
    ok = out.ok
    stick = out.regime == 0
    rate_engine = args.n / t_engine
    rate_formula = args.n / t_formula
    diff_formula = np.max(np.abs(out_formula.amplitude - out.amplitude) / out.amplitude)

    idx = rng.choice(args.n, size=min(args.n_scipy, args.n), replace=False)
    t0 = time.perf_counter()
    amp_scipy = np.array([scipy_cycle(nu[i], c[i]) for i in idx])
    t_scipy = time.perf_counter() - t0
    rate_scipy = len(idx) / t_scipy

    amp_engine = out.amplitude[idx]
    rel = np.abs(amp_engine - amp_scipy) / np.abs(amp_scipy)
    # accuracy of each against a tight SciPy solution, on the first 50 of the subset
    tight = np.array([scipy_cycle(nu[i], c[i], 1e-13, 1e-15) for i in idx[:50]])
    err_engine = np.max(np.abs(amp_engine[:50] - tight) / tight)
    err_scipy = np.max(np.abs(amp_scipy[:50] - tight) / tight)

    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"numba threads {os.environ.get('NUMBA_NUM_THREADS', 'default')}"
    )
    print(
        f"work: F1 steady stick-slip cycles, nu log-uniform [1e-5, 1e-1], c uniform [0.5, 50], "
        f"rtol {RTOL:g}, atol {ATOL:g}"
    )
    print(
        f"stickslip batched : {args.n:8d} cycles in {t_engine:8.3f} s = {rate_engine:12.0f} cycles/s"
        f"  (first call incl. compile/cache load {t_compile:.2f} s)"
    )
    print(
        f"  status ok {ok.mean():.4f}, stick-slip {stick.mean():.4f}, mean steps "
        f"{out.n_steps.mean():.1f} accepted + {out.n_rejected.mean():.1f} "
        "rejected per cycle"
    )
    print(
        f"formula law       : {args.n:8d} cycles in {t_formula:8.3f} s = {rate_formula:12.0f} cycles/s"
        f"  (first call incl. compile/cache load {t_compile_formula:.2f} s); "
        f"{rate_formula / rate_engine:.3f} of the built-in law's rate"
    )
    print(f"  amplitude, largest relative difference formula vs built-in: {diff_formula:.3e}")
    print(f"scipy solve_ivp   : {len(idx):8d} cycles in {t_scipy:8.3f} s = {rate_scipy:12.1f} cycles/s")
    print(f"speed-up          : {rate_engine / rate_scipy:12.0f} x")
    print(
        f"amplitude, largest relative difference stickslip vs scipy: {rel.max():.3e} "
        f"(median {np.median(rel):.3e})"
    )
    print(
        f"amplitude, largest relative error vs rtol 1e-13 SciPy (50 sets): stickslip "
        f"{err_engine:.3e}, scipy {err_scipy:.3e}"
    )


if __name__ == "__main__":
    main()
