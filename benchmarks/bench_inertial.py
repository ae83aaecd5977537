"""The inertial rate-and-state slider on its limit cycle: the compiled Radau against SciPy's.

The slider of the paper's appendix with a mass (a = 0.01, b = 0.015, Dc = 10 um,
V_r = 1 um/s, mu0 = 0.6, W = 10 N, k = 0.8 k_c, m = 0.01 kg, driven at 1 mm/s):
below the critical stiffness it settles on a stick-slip limit cycle. Ours:
``simulate_rate_state`` (the compiled Radau IIA of ``stickslip.core.radau``).
SciPy the straightforward way: ``solve_ivp(method="Radau")`` with the same compiled
right-hand side and analytic Jacobian called from Python, the same tolerances and
events (spring-force and slip-velocity maxima), the same output times. Both run
the same history; the samples and events are compared.

Run: ``python benchmarks/bench_inertial.py [--seconds 4] [--rtol 1e-9]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
from scipy.integrate import solve_ivp

from stickslip.core import ratestate as core
from stickslip.ratestate.model import RateStateParameters
from stickslip.ratestate.protocols import simulate_rate_state


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=4.0)
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--samples", type=int, default=4001)
    a = parser.parse_args()
    kc = 0.005 / 10e-6
    p = RateStateParameters(
        a=0.01, b=0.015, dc="10 um", v_ref="1 um/s", mu0=0.6,
        stiffness=f"{0.8 * kc * 10} N/m", load="10 N", mass="0.01 kg",
    )  # fmt: skip
    v_lp = 1e-3
    mu0 = float(p.steady_state_friction("1 mm/s")) + 1e-3
    history = [(f"{a.seconds} s", "1 mm/s")]
    init = (mu0, "0.01 s")
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores")
    print(f"work: inertial slider, k = 0.8 k_c, m = 0.01 kg, {a.seconds} s at 1 mm/s, rtol {a.rtol:g}")

    t0 = time.perf_counter()
    simulate_rate_state(p, history, initial=init, n_points=a.samples, rtol=a.rtol)
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    ds = simulate_rate_state(p, history, initial=init, n_points=a.samples, rtol=a.rtol)
    ours = time.perf_counter() - t0

    P, S = p.core_arrays()
    y0 = np.array([mu0, float(ds.slip_velocity.values[0]), float(np.log(0.01 * 1e-6 / 10e-6))])

    def fun(_t: float, y: np.ndarray) -> np.ndarray:
        f = np.empty(3)
        core.in_rhs(y, P, S, 1, v_lp, f)
        return f

    def jac(_t: float, y: np.ndarray) -> np.ndarray:
        j = np.empty((3, 3))
        core.in_jac(y, P, S, 1, j)
        return j

    def spring(_t: float, y: np.ndarray) -> float:
        return float(y[1]) - v_lp

    def velocity(_t: float, y: np.ndarray) -> float:
        return float(y[0]) - core.in_friction(y[1], y, S, 1, P) - P[core.P_ETA] * y[1]

    spring.direction = 1  # type: ignore[attr-defined]
    velocity.direction = -1  # type: ignore[attr-defined]
    atol = np.array([1e-12, 1e-12 * v_lp, 1e-10])
    t0 = time.perf_counter()
    sol = solve_ivp(
        fun, (0.0, a.seconds), y0, method="Radau", jac=jac, rtol=a.rtol, atol=atol,
        t_eval=ds.time.values, events=[spring, velocity],
    )  # fmt: skip
    scipy_s = time.perf_counter() - t0
    mine = np.vstack([ds.spring_friction.values, ds.slip_velocity.values])
    ref = sol.y[:2]
    rel = np.max(np.abs(mine - ref) / (np.abs(ref) + np.array([[1e-6], [1e-6]])))
    n_v = ds.velocity_peak_time.size
    same = n_v == sol.t_events[1].size and ds.spring_peak_time.size == sol.t_events[0].size
    dt = np.max(np.abs(ds.velocity_peak_time.values - sol.t_events[1])) if same else float("nan")
    print(f"stickslip (compiled Radau): {ours:8.3f} s  (first call incl. compile/cache load {first:.2f} s)")
    peaks = sol.t_events[1].size
    print(f"scipy solve_ivp Radau     : {scipy_s:8.3f} s  ({peaks} velocity peaks, {sol.nfev} evaluations)")
    print(f"speed-up                  : {scipy_s / ours:8.1f} x")
    print(f"samples, largest relative difference: {rel:.2e}; events: same count {same}, times to {dt:.1e} s")


if __name__ == "__main__":
    main()
