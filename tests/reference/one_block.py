"""Independent reference: the one-block stick-slip cycle the plain SciPy way.

Written separately from the compiled engine and sharing no code with it:
``scipy.integrate.solve_ivp`` with its own event location (``events=``), the
friction laws typed in again, and the stick/slip switching re-implemented.
Slow, simple and meant to be obviously right.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp


def forward_branch(law: str, params: dict[str, float], w: float) -> float:
    """Friction for forward slip (analytic expression of the law for w > 0)."""
    if law == "weakening":
        return 1.0 / (1.0 + params["c"] * w) + params.get("p", 0.0) * w
    if law == "cubic":
        return 1.0 - params["alpha"] * w + params["gamma"] * w**3
    if law == "coulomb":
        return params["kinetic"]
    if law == "carlson-langer":
        r = 1.0 - params["sigma"]
        return r / (1.0 + 2.0 * params["alpha"] * w / r)
    if law == "stribeck":
        kin, ws = params["kin"], params["ws"]
        return kin + (1.0 - kin) * math.exp(-w / ws) + params.get("eta", 0.0) * w
    raise ValueError(law)


@dataclass
class RefCycle:
    amplitude: float
    period: float
    stick_time: float
    s_stop: float
    w_max: float
    n_backward: int


def reference_cycle(
    law: str,
    params: dict[str, float],
    nu: float,
    rtol: float = 1e-13,
    atol: float = 1e-15,
    t_phase: float = 1e4,
) -> RefCycle:
    """Steady stick-slip cycle from breakaway (s, w) = (1, 0), with solve_ivp events."""
    s, w, t = 1.0, 0.0, 0.0
    direction = 1
    s_values = [1.0]
    w_max = 0.0
    n_back = 0
    for _ in range(100):
        d = direction

        def rhs(_t: float, y: np.ndarray, d: int = d) -> list[float]:
            return [nu - y[1], y[0] - d * forward_branch(law, params, d * y[1])]

        def stop(_t: float, y: np.ndarray) -> float:
            return y[1]

        stop.terminal = True  # type: ignore[attr-defined]
        stop.direction = -d  # type: ignore[attr-defined]

        def extremum(_t: float, y: np.ndarray) -> float:
            return y[1] - nu

        def w_extremum(_t: float, y: np.ndarray, d: int = d) -> float:
            return rhs(_t, y, d)[1]

        def turn(_t: float, y: np.ndarray, d: int = d) -> float:
            return rhs(_t, y, d)[1]

        turn.terminal = True  # type: ignore[attr-defined]
        turn.direction = -d  # type: ignore[attr-defined]
        # A phase starts at rest, where the stop function is zero: integrate first to
        # the turn of the velocity (which must precede the stop), then to the stop, so
        # that a weak slip that ends within one step is not mistaken for no slip.
        part = solve_ivp(
            rhs,
            (t, t + t_phase),
            [s, w],
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=[turn, extremum, w_extremum],
        )
        if part.status != 1:
            raise RuntimeError("reference: slip phase did not turn")
        for ev in np.reshape(part.y_events[1], (-1, 2)):
            s_values.append(float(ev[0]))
        w_max = max(w_max, float(np.max(np.reshape(part.y_events[2], (-1, 2))[:, 1], initial=0.0)))
        t = float(part.t_events[0][0])
        w_max = max(w_max, float(part.y_events[0][0][1]))
        sol = solve_ivp(
            rhs,
            (t, t + t_phase),
            part.y_events[0][0],
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=[stop, extremum, w_extremum],
        )
        if sol.status != 1:
            raise RuntimeError("reference: slip phase did not stop")
        crossings = np.reshape(sol.y_events[1], (-1, 2))
        w_extrema = np.reshape(sol.y_events[2], (-1, 2))
        s_values.extend(crossings[:, 0].tolist())
        if len(w_extrema):
            w_max = max(w_max, float(np.max(w_extrema[:, 1])))
        t = float(sol.t_events[0][0])
        s = float(sol.y_events[0][0, 0])
        w = 0.0
        s_values.append(s)
        if s < -1.0:
            direction = -1
            n_back += 1
            continue
        if s >= 1.0:
            direction = 1
            continue
        stick = (1.0 - s) / nu
        return RefCycle(max(s_values) - min(s_values), t + stick, stick, s, w_max, n_back)
    raise RuntimeError("reference: no stick after 100 phases")


def slip_stops(law: str, params: dict[str, float], nu: float, t_end: float = 50.0) -> bool:
    """Whether the slip phase from breakaway ``(s, w) = (1, 0)`` comes back to rest (``w = 0``).

    Breakaway is where the velocity has its minimum, 0 (``w' = 1 - f(0) = 0``): within its first
    turn the flow either crosses ``w = 0`` (a stop: the stick-slip cycle exists) or turns
    above it, inside the unstable pure-slip orbit of a subcritical Hopf point, and spirals into
    steady sliding, never stopping (``t_end`` is several turns).
    """

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [nu - y[1], y[0] - forward_branch(law, params, y[1])]

    def stop(_t: float, y: np.ndarray) -> float:
        return y[1]

    stop.terminal = True  # type: ignore[attr-defined]
    stop.direction = -1  # type: ignore[attr-defined]
    sol = solve_ivp(rhs, (0.0, t_end), [1.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-14, events=[stop])
    return sol.status == 1


def stick_slip_border(law: str, params: dict[str, float], lo: float, hi: float, tol: float = 1e-8) -> float:
    """The driving velocity where the stick-slip cycle ends: bisection on :func:`slip_stops`.

    The slip phase stops at ``lo`` and not at ``hi``; at the border the unstable pure-slip
    orbit passes through breakaway. Returned to ``tol``.
    """
    if not slip_stops(law, params, lo) or slip_stops(law, params, hi):
        raise ValueError(f"reference: the border is not bracketed by nu = {lo}, {hi}")
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if slip_stops(law, params, mid) else (lo, mid)
    return 0.5 * (lo + hi)


@dataclass
class RefOrbit:
    amplitude: float
    period: float
    s0: float
    w_min: float
    multiplier: float


def pure_slip_orbit_reference(
    f: Callable[[float], float], df: Callable[[float], float], nu: float, guess: tuple[float, float]
) -> RefOrbit:
    """Pure-slip periodic orbit by plain SciPy: ``solve_ivp`` + ``root`` on ``(s0, T)`` from ``(s0, w = nu)``.

    The amplitude comes from the event ``w = nu`` crossed downward (the minimum of ``s``), the
    smallest velocity from ``dw/dt = 0`` crossed upward, and the nontrivial Floquet multiplier
    from ``exp(-integral of f'(w) dt)`` over the period (Liouville, for a planar flow).
    """
    from scipy.optimize import root

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [nu - y[1], y[0] - f(y[1]), df(y[1])]

    def residual(x: np.ndarray) -> np.ndarray:
        s0, period = x
        sol = solve_ivp(rhs, (0.0, period), [s0, nu, 0.0], method="DOP853", rtol=1e-13, atol=1e-15)
        return np.array([sol.y[0, -1] - s0, sol.y[1, -1] - nu])

    sol = root(residual, list(guess), method="hybr", options={"xtol": 1e-14})
    s0, period = (float(x) for x in sol.x)
    if np.linalg.norm(residual(sol.x)) > 1e-11:
        raise RuntimeError(f"reference shooting did not converge: {sol.message}")

    def down(_t: float, y: np.ndarray) -> float:
        return y[1] - nu

    def w_turn(_t: float, y: np.ndarray) -> float:
        return y[0] - f(y[1])

    down.direction = -1  # type: ignore[attr-defined]
    w_turn.direction = 1  # type: ignore[attr-defined]
    run = solve_ivp(
        rhs, (0.0, period), [s0, nu, 0.0], method="DOP853", rtol=1e-13, atol=1e-15, events=[down, w_turn]
    )
    s_min = float(run.y_events[0][0][0])
    w_min = float(run.y_events[1][0][1])
    return RefOrbit(s0 - s_min, period, s0, w_min, math.exp(-float(run.y[2, -1])))


def unstable_orbit_reference(
    f: Callable[[float], float], df: Callable[[float], float], nu: float, s0: float, method: str = "DOP853"
) -> tuple[RefOrbit, float]:
    """A very unstable pure-slip orbit by plain SciPy: the fixed point of the backward return map.

    Forward shooting cannot converge on an orbit whose multiplier is 1e20 (the error grows by
    that much in a period); backward in time the orbit attracts as strongly. From ``(s0, w =
    nu)`` the reversed flow is integrated (``solve_ivp``, DOP853 or ``method``: the backward flow
    of an orbit with multiplier exp(5000) is stiff) to the next point where it
    crosses ``w = nu`` as the forward flow does at the spring force's maximum, until the map
    moves ``s`` by less than 1e-11. The amplitude comes from the crossing of ``w = nu`` the
    other way (the minimum of ``s``), the smallest velocity from the turns of ``w``, and
    the log of the multiplier, returned with the orbit, from minus the integral of ``f'(w)``
    over the period (the multiplier itself overflows; ``multiplier`` is then inf).
    """

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [y[1] - nu, f(y[1]) - y[0], df(y[1])]

    def at_max(_t: float, y: np.ndarray) -> float:  # forward: w crosses nu upward
        return y[1] - nu

    def at_min(_t: float, y: np.ndarray) -> float:  # forward: w crosses nu downward
        return y[1] - nu

    def w_turn(_t: float, y: np.ndarray) -> float:
        return y[0] - f(y[1])

    at_max.direction, at_min.direction = -1, 1  # type: ignore[attr-defined]
    at_max.terminal = 2  # type: ignore[attr-defined]  # (the start may count as the first)
    s, period = s0, math.nan
    for _ in range(20):
        run = solve_ivp(
            rhs, (0.0, 1e4), [s, nu, 0.0], method=method, rtol=1e-12, atol=1e-15,
            events=[at_max, at_min, w_turn], dense_output=True,
        )  # fmt: skip
        times = run.t_events[0][run.t_events[0] > 1e-9]
        if times.size == 0:
            raise RuntimeError("the backward flow did not come back to w = nu")
        period = float(times[0])
        end = run.sol(period)
        done = abs(end[0] - s) < 1e-11 * max(1.0, abs(s))  # the flow's noise across the rows
        s_next = float(end[0])
        if done:
            break
        s = s_next
    else:
        raise RuntimeError("the backward return map did not converge")
    t_min = run.t_events[1][(run.t_events[1] > 0) & (run.t_events[1] < period)]
    turns = run.t_events[2][(run.t_events[2] > 0) & (run.t_events[2] < period)]
    s_min = float(run.sol(t_min[0])[0])
    w_min = min(float(run.sol(t)[1]) for t in turns)
    log_m = -float(end[2])
    return RefOrbit(s - s_min, period, s, w_min, math.exp(log_m) if log_m < 709.0 else math.inf), log_m


def cubic_orbit_reference(nu: float, alpha: float, gamma: float) -> RefOrbit:
    """The pure-slip orbit of the cubic law ``1 - alpha w + gamma w**3``, from the averaging guess."""
    a2 = 4.0 * (alpha - 3.0 * gamma * nu * nu) / (3.0 * gamma)
    f0 = 1.0 - alpha * nu + gamma * nu**3
    return pure_slip_orbit_reference(
        lambda w: 1.0 - alpha * w + gamma * w**3,
        lambda w: -alpha + 3.0 * gamma * w * w,
        nu,
        (f0 + math.sqrt(a2), 2.0 * math.pi),
    )


def coulomb_cycle(nu: float, fk: float) -> dict[str, float]:
    """Closed-form stick-slip cycle of the Coulomb law (static 1, kinetic fk).

    Forward slip from (1, 0): with y = s - fk, w'' = nu - w, so
    w = nu - nu cos t + (1 - fk) sin t = nu + R sin(t - phi) with
    R = hypot(nu, 1 - fk), phi = atan2(nu, 1 - fk); it stops at t = pi + 2 phi
    with s = 2 fk - 1, then sticks for (1 - s)/nu.
    """
    r = math.hypot(nu, 1.0 - fk)
    phi = math.atan2(nu, 1.0 - fk)
    t_slip = math.pi + 2.0 * phi
    stick = 2.0 * (1.0 - fk) / nu
    return {
        "amplitude": 2.0 * r,
        "period": t_slip + stick,
        "stick_time": stick,
        "s_stop": 2.0 * fk - 1.0,
        "w_max": nu + r,
        "max_force": fk + r,
        "min_force": fk - r,
        "slip_time": t_slip,
        # friction does fk times the slip distance, which is nu times the period
        "friction_work": fk * nu * (t_slip + stick),
    }


def reference_record(
    *,
    mu0: float,
    a: float,
    b: float,
    k: float,
    m: float,
    load: float,
    v0: float,
    periods: float,
    rate: float,
    noise: float,
    seed: int,
    phase: float = 0.3,
) -> tuple[np.ndarray, np.ndarray]:
    """A steady stick-slip force record in SI units, made the plain SciPy way.

    The zv-type law ``mu0 W [1/(1 + a v) + b v]``: the dimensionless form is worked out here
    by hand (not by stickslip), one steady cycle comes from :func:`reference_cycle`, its slip
    phase is integrated again by ``solve_ivp`` with dense output, and the cycle is repeated
    and sampled at ``rate`` (Hz), starting ``phase`` of a period after a breakaway, with
    white Gaussian noise of standard deviation ``noise`` (N).

    Returns
    -------
    time : ndarray
        Sample times (s), from 0.
    force : ndarray
        Spring force (N).

    """
    force_unit = mu0 * load
    beta = math.sqrt(k * m) / force_unit
    nu, c, p = beta * v0, a / beta, b / beta
    time_unit = math.sqrt(m / k)
    cyc = reference_cycle("weakening", {"c": c, "p": p}, nu)
    if cyc.n_backward:
        raise ValueError("reference_record: the cycle has backward slip, not covered")
    t_slip = cyc.period - cyc.stick_time

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [nu - y[1], y[0] - forward_branch("weakening", {"c": c, "p": p}, y[1])]

    slip = solve_ivp(
        rhs, (0.0, t_slip), [1.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True
    )
    n = int(periods * cyc.period * time_unit * rate) + 1
    t = np.arange(n) / rate
    tau = np.mod(t / time_unit + phase * cyc.period, cyc.period)
    s = np.where(tau < t_slip, slip.sol(np.minimum(tau, t_slip))[0], cyc.s_stop + nu * (tau - t_slip))
    rng = np.random.default_rng(seed)
    return t, force_unit * s + noise * rng.standard_normal(n)
