"""Benchmark: a pure-slip orbit at nu = 0.995 nu_H by shooting, against the converged transient.

Cubic law alpha = 0.5, gamma = 1/6 (supercritical Hopf at nu_H = 1). Shooting:
``pure_slip_orbit`` to |G| < 1e-10. The straightforward way: ``solve_ivp``
(DOP853, rtol 1e-12) from steady sliding pushed by 1e-3, with an event at every
spring-force maximum, until the distance to the limit of the maxima, estimated from
the geometric decay of their differences (``d_n r / (1 - r)``, ``r = d_n / d_{n-1}``),
is below 1e-10: near the Hopf point successive maxima differ by far less than
their distance to the cycle, so "two maxima agree" is not convergence.
Prints both times, their ratio and the amplitude difference. Usage::

    python benchmarks/bench_orbits.py
"""

from __future__ import annotations

import time

import numpy as np
from scipy.integrate import solve_ivp

from stickslip import CubicLaw, DimensionlessParameters
from stickslip.orbits.periodic import pure_slip_orbit

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
    d_last = None
    n = 0
    while True:
        sol = solve_ivp(rhs, (t, t + 500.0), y, method="DOP853", rtol=1e-12, atol=1e-14, events=smax)
        for ye in np.reshape(sol.y_events[0], (-1, 2)):
            n += 1
            if last is not None:
                d = float(ye[0]) - last
                if d_last is not None and d_last != 0.0:
                    r = d / d_last
                    if 0.0 <= r < 1.0 and abs(d) * r / (1.0 - r) <= 1e-10:
                        return float(ye[0]) + d * r / (1.0 - r), sol.t_events[0][-1], n
                d_last = d
            last = float(ye[0])
        t, y = sol.t[-1], sol.y[:, -1]


def main() -> None:
    p = DimensionlessParameters(nu=NU, law=CubicLaw(alpha=ALPHA, gamma=GAMMA))
    pure_slip_orbit(p)  # warm-up (compilation is cached on disk; imports)
    reps = 20
    t0 = time.perf_counter()
    for _ in range(reps):
        o = pure_slip_orbit(p, tol=1e-10)
    t_shoot = (time.perf_counter() - t0) / reps
    t0 = time.perf_counter()
    s_max, t_end, n_max = transient()
    t_tr = time.perf_counter() - t0
    print(f"cubic law, nu = {NU} nu_H: nontrivial Floquet multiplier {o.multipliers[1].real:.6f}")
    print(f"shooting : {t_shoot * 1e3:.2f} ms, {o.iterations} Newton iterations, |G| = {o.residual:.1e}")
    print(f"transient: {t_tr:.3f} s (solve_ivp, {n_max} oscillations, tau = {t_end:.0f})")
    print(f"ratio transient / shooting: {t_tr / t_shoot:.0f}")
    print(
        f"spring-force maximum: shooting {o.s0:.13f}, transient (extrapolated) {s_max:.13f}, "
        f"difference {abs(o.s0 - s_max):.1e}"
    )


if __name__ == "__main__":
    main()
