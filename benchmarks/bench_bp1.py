"""The SEAS BP1 spring-slider over 3000 years: stickslip's integrator against SciPy's Radau.

The quasi-dynamic spring-slider with BP1's frictional parameters (a = 0.010,
b = 0.015, Dc = 8 mm, sigma = 50 MPa, V_pl = 1e-9 m/s, f0 = 0.6, V0 = 1e-6 m/s,
eta = 4.62 MPa s/m, k = k_c / 2). Ours: ``stickslip.ratestate.earthquake_cycles``
(compiled DOP853, the slip rate from the stress by Newton's method, events on the
dense output). SciPy the straightforward way: ``solve_ivp(method="Radau")`` on
(slip, state) with a Python right-hand side that finds the slip rate with
``scipy.optimize.brentq`` at every call and a finite-difference Jacobian, the same
relative tolerance. Both catalogues (events above 1 mm/s) are compared.

Run: ``python benchmarks/bench_bp1.py [--years 3000] [--rtol 1e-8]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from stickslip.ratestate.cycles import BP1, YEAR, earthquake_cycles

# the SciPy reference written from the equations, shared with the tests
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from reference import bp1 as ref


def scipy_bp1(years: float, rtol: float) -> dict[str, float]:
    """BP1 spring-slider by SciPy's Radau, written from the equations; returns its catalogue summary."""
    rhs, slip_rate, theta0 = ref.rhs, ref.slip_rate, ref.THETA0
    started = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, years * YEAR), [0.0, theta0], method="Radau", rtol=rtol, atol=[1e-10, 1e-6])
    seconds = time.perf_counter() - started
    assert sol.status == 0, sol.message
    v = np.array([slip_rate(t, y) for t, y in zip(sol.t, sol.y.T, strict=True)])
    up = np.flatnonzero((v[:-1] < 1e-3) & (v[1:] >= 1e-3))
    t_up = sol.t[up] + (1e-3 - v[up]) / (v[up + 1] - v[up]) * (sol.t[up + 1] - sol.t[up])
    return {
        "seconds": seconds,
        "steps": int(sol.t.size),
        "nfev": int(sol.nfev),
        "events": int(t_up.size),
        "recurrence_yr": float(np.mean(np.diff(t_up[2:]))) / YEAR,
        "slip_m": float(sol.y[0, -1]),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--years", type=float, default=3000.0)
    parser.add_argument("--rtol", type=float, default=1e-8)
    args = parser.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores")
    earthquake_cycles(BP1, "10 yr", rtol=args.rtol)  # compile
    started = time.perf_counter()
    run = earthquake_cycles(BP1, f"{args.years} yr", rtol=args.rtol)
    ours = time.perf_counter() - started
    s = run.summary()
    print(
        f"stickslip: {args.years:g} years in {ours:.3f} s ({run.steps} steps, {run.rejected} rejected), "
        f"{s['events'] + 2} events, recurrence {s['recurrence_yr']:.9g} yr, "
        f"total slip {run.budget['slip']:.9g} m, "
        f"slip rate {float(run.series.slip_rate.min()):.2g} to {float(run.series.slip_rate.max()):.2g} m/s"
    )
    ref = scipy_bp1(args.years, args.rtol)
    print(
        f"SciPy Radau: {args.years:g} years in {ref['seconds']:.2f} s ({ref['steps']} steps, {ref['nfev']} "
        f"right-hand sides), {ref['events']} events, recurrence {ref['recurrence_yr']:.9g} yr, total slip "
        f"{ref['slip_m']:.9g} m"
    )
    print(
        f"ratio (SciPy time / ours): {ref['seconds'] / ours:.0f}x; recurrence differs by "
        f"{abs(ref['recurrence_yr'] / s['recurrence_yr'] - 1):.1e}, total slip by "
        f"{abs(ref['slip_m'] / run.budget['slip'] - 1):.1e} (relative)"
    )


if __name__ == "__main__":
    main()
