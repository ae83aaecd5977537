"""Benchmark: a pure-slip orbit at nu = 0.995 nu_H by shooting, against the converged transient.

Cubic law alpha = 0.5, gamma = 1/6 (supercritical Hopf at nu_H = 1). Shooting:
``pure_slip_orbit`` to |G| < 1e-10. The straightforward way: ``solve_ivp``
(DOP853, rtol 1e-12) from steady sliding pushed by 1e-3, with an event at every
spring-force maximum, until two successive maxima agree to 1e-10 (relative).
Prints both times, their ratio and the amplitude difference. Usage::

    python benchmarks/bench_orbits.py
"""

from __future__ import annotations

import time

import numpy as np
from scipy.integrate import solve_ivp

from stickslip import CubicLaw, DimensionlessParameters
from stickslip.analysis.orbits import pure_slip_orbit

ALPHA, GAMMA = 0.5, 0.5 / 3
NU = 0.995


def transient() -> tuple[float, float, int]:
    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [NU - y[1], y[0] - (1 - ALPHA * y[1] + GAMMA * y[1] ** 3)]

    def smax(_t: float, y: np.ndarray) -> float:
        return y[1] - NU

    smax.direction = 1  # type: ignore[attr-defined]
    f_nu = 1 - ALPHA * NU + GAMMA * NU**3
    y = np.array([f_nu + 1e-3, NU])
    t = 0.0
    last = None
    n = 0
    while True:
        sol = solve_ivp(rhs, (t, t + 500.0), y, method="DOP853", rtol=1e-12, atol=1e-14, events=smax)
        for ye in np.reshape(sol.y_events[0], (-1, 2)):
            n += 1
            if last is not None and abs(ye[0] - last) <= 1e-10 * abs(ye[0]):
                return float(ye[0]), sol.t_events[0][-1], n
            last = float(ye[0])
        t, y = sol.t[-1], sol.y[:, -1]


def main() -> None:
    p = DimensionlessParameters(nu=NU, law=CubicLaw(alpha=ALPHA, gamma=GAMMA))
    pure_slip_orbit(p)  # warm-up (imports)
    t0 = time.perf_counter()
    o = pure_slip_orbit(p, tol=1e-10)
    t_shoot = time.perf_counter() - t0
    t0 = time.perf_counter()
    s_max, t_end, n_max = transient()
    t_tr = time.perf_counter() - t0
    print(f"cubic law, nu = {NU} nu_H: nontrivial Floquet multiplier {o.multipliers[1].real:.6f}")
    print(f"shooting : {t_shoot:.3f} s, {o.iterations} Newton iterations, |G| = {o.residual:.1e}")
    print(f"transient: {t_tr:.3f} s (solve_ivp, {n_max} oscillations, tau = {t_end:.0f})")
    print(f"ratio transient / shooting: {t_tr / t_shoot:.0f}")
    print(
        f"spring-force maximum: shooting {o.s0:.12f}, transient {s_max:.12f}, "
        f"difference {abs(o.s0 - s_max):.1e}"
    )


if __name__ == "__main__":
    main()
