"""An independent generator of rate-and-state velocity-step records, in plain SciPy.

Written from the equations (Dieterich 1979, Ruina 1983), not from stickslip's code:
the state Phi (s) itself as the variable, SciPy's Radau with a finite-difference
Jacobian, the load-point velocity piecewise constant. Units: um, s, 1/um, as a lab's
file has them.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp


def generate(
    *,
    a: float,
    b: list[float],
    dc_um: list[float],
    law: str,
    k_per_um: float,
    mu0: float = 0.6,
    v_ref: float = 1.0,
    steps: list[tuple[float, float]],
    dt: float,
    noise: float,
    trend_per_um: float = 0.0,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return ``(time s, load-point velocity um/s, friction)`` sampled every ``dt``.

    ``steps`` are ``(velocity um/s, duration s)``; the slider starts in steady sliding
    at the first velocity; Gaussian noise of standard deviation ``noise`` and a linear
    trend in load-point displacement are added.
    """
    b_arr = np.array(b)
    dc = np.array(dc_um)

    def rhs(_t: float, y: np.ndarray, vlp: float) -> np.ndarray:
        mu, phi = y[0], y[1:]
        v = v_ref * np.exp((mu - mu0 - np.sum(b_arr * np.log(v_ref * phi / dc))) / a)
        if law == "aging":
            dphi = 1.0 - v * phi / dc
        else:
            dphi = -(v * phi / dc) * np.log(v * phi / dc)
        return np.concatenate([[k_per_um * (vlp - v)], dphi])

    v1 = steps[0][0]
    y = np.concatenate([[mu0 + (a - b_arr.sum()) * np.log(v1 / v_ref)], dc / v1])
    t_all, mu_all, v_all = [], [], []
    t0 = 0.0
    for i, (vlp, dur) in enumerate(steps):
        n = round(dur / dt)
        t_eval = t0 + dt * np.arange(0 if i == 0 else 1, n + 1)
        sol = solve_ivp(
            rhs, (t0, t0 + dur), y, method="Radau", t_eval=t_eval, args=(vlp,), rtol=1e-11, atol=1e-13
        )
        assert sol.status == 0, sol.message
        t_all.append(sol.t)
        mu_all.append(sol.y[0])
        v_all.append(np.full(sol.t.size, vlp))
        y = sol.y[:, -1]
        t0 += dur
    t = np.concatenate(t_all)
    vv = np.concatenate(v_all)
    # the velocity of sample i holds until sample i + 1: shift so that a step starts at its time
    vel = np.concatenate([vv[1:], vv[-1:]])
    x = np.concatenate([[0.0], np.cumsum(vel[:-1] * np.diff(t))])
    mu = np.concatenate(mu_all) + trend_per_um * x
    rng = np.random.default_rng(seed)
    return t, vel, mu + rng.normal(0.0, noise, mu.size)


def write_csv(path, t: np.ndarray, v: np.ndarray, mu: np.ndarray, header: dict[str, str]) -> None:
    """Write a record as a lab would: metadata lines, then time, load-point velocity, friction."""
    lines = [f"# {k} = {val}" for k, val in header.items()]
    lines.append("time [s],load-point velocity [um/s],friction [1]")
    lines += [f"{a:.6f},{b:.6g},{c:.9f}" for a, b, c in zip(t, v, mu, strict=True)]
    path.write_text("\n".join(lines) + "\n")


def damped(
    *,
    a: float,
    b: float,
    dc: float,
    k: float,
    eta: float,
    form: str,
    steps: list[tuple[float, float]],
    times: np.ndarray,
    mu0: float = 0.6,
    v_ref: float = 1e-6,
) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(spring friction, slip velocity m/s)`` at ``times`` (SI) for the aging law.

    The quasi-static slider with radiation damping ``eta`` (s/m): the spring's friction
    ``mu_s = f(v, Phi) + eta v``, solved for ``v`` by ``brentq`` in ``ln v`` at every
    right-hand side; ``f = psi + a ln(v/V_r)`` (``form="log"``) or
    ``a asinh(v/(2 V_r) exp(psi/a))`` (``"regularized"``), ``psi = mu0 + b ln(V_r Phi/dc)``.
    Variables ``(mu_s, ln Phi)``, SciPy's LSODA; ``steps`` are ``(velocity m/s, duration s)``
    from steady sliding at the first velocity.
    """
    from scipy.optimize import brentq

    def f(lu: float, psi: float) -> float:
        if form == "log":
            return psi + a * lu
        return a * float(np.arcsinh(0.5 * np.exp(lu + psi / a)))

    def lnv(mus: float, lphi: float) -> float:
        psi = mu0 + b * (lphi + np.log(v_ref / dc))

        def g(lu: float) -> float:
            return f(lu, psi) + eta * v_ref * np.exp(lu) - mus

        return float(brentq(g, -300.0, 60.0, xtol=1e-14, rtol=1e-15))

    def rhs(_t: float, y: np.ndarray, vlp: float) -> list[float]:
        v = v_ref * np.exp(lnv(y[0], y[1]))
        return [k * (vlp - v), 1.0 / np.exp(y[1]) - v / dc]

    v1 = steps[0][0]
    lphi = np.log(dc / v1)
    y = np.array([f(np.log(v1 / v_ref), mu0 + b * np.log(v_ref / v1)) + eta * v1, lphi])
    mus_at, v_at = np.full(times.size, np.nan), np.full(times.size, np.nan)
    t0 = 0.0
    for vlp, dur in steps:
        sel = (times >= t0) & (times <= t0 + dur)
        sol = solve_ivp(rhs, (t0, t0 + dur), y, method="LSODA", args=(vlp,), rtol=1e-11, atol=1e-14,
                        dense_output=True)  # fmt: skip
        assert sol.status == 0, sol.message
        z = sol.sol(times[sel])
        mus_at[sel] = z[0]
        v_at[sel] = [v_ref * np.exp(lnv(m, lp)) for m, lp in zip(z[0], z[1], strict=True)]
        y = sol.y[:, -1]
        t0 += dur
    return mus_at, v_at
