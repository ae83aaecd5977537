"""Benchmark: slip-reversal orbits per second, the compiled return map against plain SciPy.

Work: the non-sticking orbits of law F1, ``f(w) = 1/(1 + c w)`` (odd for backward
slip), whose velocity changes sign without sticking (slip reversal): random ``nu``
log-uniform in [1, 20], ``c`` uniform in [2, 10], the rows whose attractor from
rest is such an orbit. Each is found as a fixed point of the return map on
``w = nu`` from the engine's last oscillation, as a sweep's polish does (secant
iterations to ``|P(s) - s| < 1e-10``, the flow at 1e-12, and the map's derivative).

* stickslip, compiled: ``run_return_maps`` (all rows at once, on all cores);
* stickslip in Python: ``return_map_orbit_core``, the secant in Python around the
  engine's trajectories (what a polish of fewer than 1000 such rows runs);
* SciPy: ``solve_ivp(method="DOP853")`` for the return map, with terminal events at
  ``w = 0`` (the velocity changes sign: the other direction's field from there; a
  stop with ``|s| <= 1`` sticks) and at ``w = nu`` upward, and
  ``scipy.optimize.newton`` (the secant method) for its fixed point; on a subset.

Prints the rates, their ratios and the largest difference of the orbits' ``s0``.
Usage::

    python benchmarks/bench_return_maps.py [--n 20000] [--n-python 300] [--n-scipy 20]
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import newton

from stickslip.core.api import run_attractors, run_return_maps, threads
from stickslip.laws import WeakeningLaw
from stickslip.orbits.return_map import return_map_orbit_core

TOL = 1e-10


def scipy_return_map(
    nu: float, c: float, s0: float, rtol: float = TOL * 1e-2, atol: float = TOL * 1e-4
) -> float:
    """The spring force at the next maximum after ``(s0, w = nu)``: the straightforward SciPy way."""

    def rhs(_t: float, y: np.ndarray, d: float) -> list[float]:
        return [nu - y[1], y[0] - d / (1.0 + c * d * y[1])]

    def stop(_t: float, y: np.ndarray, d: float) -> float:
        return y[1]

    def down(_t: float, y: np.ndarray, d: float) -> float:
        return y[1] - nu

    def up(_t: float, y: np.ndarray, d: float) -> float:
        return y[1] - nu

    stop.terminal = down.terminal = up.terminal = True  # type: ignore[attr-defined]
    down.direction, up.direction = -1, 1  # type: ignore[attr-defined]
    # from the maximum (w = nu, rising): w falls below nu (the force's minimum), then rises
    # through it again (the next maximum); a stop on the way reverses the slip or sticks
    t, y, d, fallen = 0.0, np.array([s0, nu]), 1.0, False
    for _ in range(100):
        cross = up if fallen else down
        stop.direction = -d  # type: ignore[attr-defined]  # |w| falls to 0 (not the restart at w = 0)
        sol = solve_ivp(
            rhs, (t, t + 1e4), y, method="DOP853", rtol=rtol, atol=atol, events=[stop, cross], args=(d,)
        )
        if sol.status != 1:
            raise RuntimeError("no event")
        if sol.t_events[1].size:
            t, y = float(sol.t_events[1][0]), sol.y_events[1][0].copy()
            if fallen:
                return float(y[0])
            fallen = True
            y[1] = nu
            continue
        t, y = float(sol.t_events[0][0]), sol.y_events[0][0].copy()
        y[1] = 0.0
        if abs(y[0]) <= 1.0:
            raise RuntimeError("the motion sticks")
        d = 1.0 if y[0] > 0 else -1.0
    raise RuntimeError("too many phases")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=20_000, help="parameter sets (their slip reversals are solved)")
    ap.add_argument("--n-python", type=int, default=300, help="orbits by the secant in Python")
    ap.add_argument("--n-scipy", type=int, default=20, help="orbits by SciPy")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    nu, c = 10 ** rng.uniform(0.0, 1.3, args.n), rng.uniform(2.0, 10.0, args.n)
    kernel = WeakeningLaw(c=1.0).kernel
    kw = {"from_breakaway": True, "rtol": 1e-9, "atol": 1e-12, "max_slip_time": 1e4, "conv_tol": 1e-8}
    att = run_attractors(kernel, c[:, None], nu, **kw)
    rev = np.flatnonzero((att.regime == 1) & (att.n_backward > 0) & (att.status == 0))
    nu, c, s_guess, t_guess = nu[rev], c[rev], att.s_max[rev], att.period[rev]
    n = rev.size
    run_return_maps(kernel, c[:2, None], nu[:2], s_guess[:2], t_guess[:2])  # compiled, or loaded
    t0 = time.perf_counter()
    got = run_return_maps(kernel, c[:, None], nu, s_guess, t_guess, tol=TOL)
    t_compiled = time.perf_counter() - t0
    ok = got.status == 0

    m = min(args.n_python, n)
    t0 = time.perf_counter()
    py = [
        return_map_orbit_core(kernel, np.array([c[i]]), float(nu[i]), (s_guess[i], t_guess[i]))
        for i in range(m)
    ]
    t_python = time.perf_counter() - t0
    same = all(py[i].s0 == got.s0[i] and py[i].multiplier == got.multiplier[i] for i in range(m))

    k = min(args.n_scipy, n)
    t0 = time.perf_counter()
    s_scipy = np.array(
        [
            newton(lambda s, i=i: scipy_return_map(nu[i], c[i], s) - s, s_guess[i], tol=TOL, maxiter=40)
            for i in range(k)
        ]
    )
    t_scipy = time.perf_counter() - t0
    diff = np.abs(s_scipy - got.s0[:k]) / np.maximum(1.0, np.abs(got.s0[:k]))

    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, {threads()} threads"
    )
    print(
        f"work: {n} slip-reversal orbits of F1 (of {args.n} sets, nu in [1, 20], c in [2, 10]), "
        f"|P(s) - s| < {TOL:g}"
    )
    r_c, r_p, r_s = n / t_compiled, m / t_python, k / t_scipy
    print(f"compiled   : {n:6d} orbits in {t_compiled:8.3f} s = {r_c:10.0f} orbits/s ({ok.sum()} converged)")
    print(
        f"Python     : {m:6d} orbits in {t_python:8.3f} s = {r_p:10.0f} orbits/s "
        f"(bit for bit the same: {same})"
    )
    print(f"SciPy      : {k:6d} orbits in {t_scipy:8.3f} s = {r_s:10.1f} orbits/s")
    print(f"ratios     : compiled / SciPy {r_c / r_s:.0f}x, compiled / Python {r_c / r_p:.1f}x")
    print(
        f"agreement  : s0 of SciPy's orbits against the compiled, largest relative difference "
        f"{diff.max():.2e}"
    )


if __name__ == "__main__":
    main()
