"""Benchmark: a stroboscopic bifurcation diagram of the forced oscillator against SciPy at equal accuracy.

Work: the forced one-block oscillator (``stickslip.core.forced``)::

    s' = nu0 + nu1 cos(omega t + phi) - w
    w' = s + q cos(omega t) - delta w - f(w)      (slip; stick while |s + q cos(omega t)| <= 1)

with the weakening law ``f_+(w) = 1/(1 + 3 w)``, ``q = 0.5``, ``nu0 = 0.3``, ``delta = 0.05``
(period doubling into chaos), and its bifurcation diagram against ``omega``: ``--values``
frequencies evenly spaced in [0.5, 2.5], ``--transient`` periods from ``(s, w) = (0, 0)``,
then ``--record`` stroboscopic sections (``bifurcation_diagram``, on all of numba's threads).

* stickslip: ``bifurcation_diagram(system, omegas, rtol=RTOL)`` (absolute tolerance
  ``RTOL / 100``), after a small warm-up call so that compilation and the loading of the
  kernel cache are not timed.
* SciPy: :func:`reference_strobe`, an event-based reference written from the model alone:
  slip phases by ``solve_ivp`` (DOP853) with a terminal event at ``w = 0``; stick in closed
  form, its breakaway found by ``brentq`` after a scan of a fine grid for the first
  crossing of ``|s + q cos(omega t)| = 1``.

Equal accuracy: the state after ``--error-periods`` sections, from sections of the
diagram's attractors at ``--subset`` frequencies, against the tight reference (SciPy at
rtol = atol = 1e-12); SciPy's tolerance is the loosest of a ladder whose largest error is
no larger than stickslip's at ``RTOL``. SciPy at that tolerance is timed on the subset of
``--subset`` frequencies x ``--subset-periods`` periods, from sections on the attractor, and
extrapolated per period to the whole job; stickslip is timed on the same subset too, to
show its per-period cost there against the full job's. Usage::

    python benchmarks/bench_forced.py [--values 1000] [--transient 500] [--record 200]
        [--subset 4] [--subset-periods 50] [--error-periods 5] [--rtol 1e-8]
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

#: the static threshold of the dimensionless model: stick while |s + q cos(omega t)| <= 1
THRESHOLD = 1.0
#: points per forcing period of the grid scanned for the breakaway (a tangency that
#: dips between two of them, T/4000 apart, would be missed)
GRID_PER_PERIOD = 4000


@dataclass
class Counts:
    """Transitions of a reference run."""

    stops: int = 0
    breakaways: int = 0
    reversals: int = 0
    touches: int = 0
    stick_time: float = 0.0
    slip_evaluations: int = field(default=0, repr=False)


def weakening_fplus(c: float, p: float = 0.0) -> Callable[[float], float]:
    """Return ``f_+(u) = 1/(1 + c u) + p u`` of the weakening law."""
    return lambda u: 1.0 / (1.0 + c * u) + p * u


def coulomb_fplus(kinetic: float) -> Callable[[float], float]:
    """Return ``f_+(u) = kinetic`` of the Coulomb law (static friction 1)."""
    return lambda u: kinetic


def reference_strobe(
    fplus: Callable[[float], float],
    fp: tuple[float, float, float, float, float, float],
    x0: tuple[float, float],
    periods: int,
    *,
    t0: float = 0.0,
    rtol: float = 1e-12,
    atol: float = 1e-12,
    method: str = "DOP853",
) -> tuple[np.ndarray, Counts]:
    """Return the states ``(s, w)`` at the sections ``t0 + k T``, ``k = 1..periods``, and the transitions.

    ``fp = (nu0, nu1, omega, phi, q, delta)``; ``f_+`` the forward branch of the
    friction (``f(w) = sign(w) f_+(|w|)``). A start with ``w = 0`` is stuck (breaking
    away at once where ``|s + q cos(omega t0)| > 1``). Independent of the engine: slip
    by ``solve_ivp`` with a terminal event where ``d w`` falls through 0 (``d`` the slip
    direction); at a stop the block sticks if ``|g| <= 1`` (``g = s + q cos(omega t)``),
    else slips in direction ``-d``; in stick ``s`` is the closed form and the breakaway
    the first crossing of ``|g| = 1``, scanned on a grid of ``GRID_PER_PERIOD`` points
    per period and refined by ``brentq``.
    """
    nu0, nu1, om, ph, q, delta = (float(v) for v in fp)
    period = 2.0 * math.pi / om
    counts = Counts()

    def stick_s(s0: float, ts: float, t: np.ndarray | float) -> np.ndarray | float:
        return s0 + nu0 * (t - ts) + (nu1 / om) * (np.sin(om * t + ph) - math.sin(om * ts + ph))

    def net(s0: float, ts: float, t: np.ndarray | float) -> np.ndarray | float:
        return stick_s(s0, ts, t) + q * np.cos(om * t)

    def breakaway(s0: float, ts: float, t_end: float) -> tuple[float, int]:
        """Return the first time in ``[ts, t_end]`` where ``|g|`` reaches 1 and the slip direction, or 0."""
        g0 = float(net(s0, ts, ts))
        if abs(g0) > THRESHOLD:
            return ts, 1 if g0 > 0 else -1
        n = max(2, math.ceil((t_end - ts) / period * GRID_PER_PERIOD) + 1)
        grid = np.linspace(ts, t_end, n)
        out = np.flatnonzero(np.abs(net(s0, ts, grid)) >= THRESHOLD)
        if out.size == 0:
            return t_end, 0
        i = int(out[0])
        if i == 0:
            return ts, 1 if g0 > 0 else -1
        d = 1 if float(net(s0, ts, grid[i])) > 0 else -1
        tb = brentq(
            lambda t: d * float(net(s0, ts, t)) - THRESHOLD, grid[i - 1], grid[i], xtol=1e-15, rtol=8.9e-16
        )
        # the slip starts on the far side of the threshold, so that d w' >= 0 at its start
        for _ in range(64):
            if d * float(net(s0, ts, tb)) >= THRESHOLD:
                break
            tb = math.nextafter(tb, math.inf)
        return tb, d

    def slip(d: int, t: float, s: float, w: float, t_end: float) -> tuple[float, float, float, bool]:
        """Integrate a slip phase in direction ``d``; return ``(t, s, w, stopped)``."""

        def rhs(tt: float, y: np.ndarray) -> list[float]:
            return [
                nu0 + nu1 * math.cos(om * tt + ph) - y[1],
                y[0] + q * math.cos(om * tt) - delta * y[1] - d * fplus(d * y[1]),
            ]

        def stop(tt: float, y: np.ndarray) -> float:
            return d * y[1]

        stop.terminal = True  # type: ignore[attr-defined]
        stop.direction = -1  # type: ignore[attr-defined]
        sol = solve_ivp(rhs, (t, t_end), [s, w], method=method, rtol=rtol, atol=atol, events=stop)
        counts.slip_evaluations += sol.nfev
        if sol.status == 1:
            return float(sol.t_events[0][0]), float(sol.y_events[0][0][0]), 0.0, True
        if sol.status != 0:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        return float(sol.t[-1]), float(sol.y[0, -1]), float(sol.y[1, -1]), False

    t, s, w = float(t0), float(x0[0]), float(x0[1])
    mode = 0 if w == 0.0 else (1 if w > 0 else -1)
    out = np.empty((periods, 2))
    for k in range(periods):
        t_end = t0 + (k + 1) * period
        while t < t_end:
            if mode == 0:
                tb, d = breakaway(s, t, t_end)
                counts.stick_time += tb - t
                s = float(stick_s(s, t, tb))
                t = tb
                if d != 0:
                    counts.breakaways += 1
                    mode, w = d, 0.0
                continue
            t, s, w, stopped = slip(mode, t, s, w, t_end)
            if stopped:
                w = 0.0
                g = s + q * math.cos(om * t)
                if abs(g) <= THRESHOLD:
                    mode = 0
                    counts.stops += 1
                elif mode * g < 0:
                    mode = -mode
                    counts.reversals += 1
                else:
                    counts.touches += 1
        out[k] = (s, w)
    return out, counts


#: the example system: the weakening law c = 3, q = 0.5, nu0 = 0.3, delta = 0.05
C_LAW = 3.0
OMEGA_RANGE = (0.5, 2.5)
#: the tight reference: SciPy's DOP853 at its tightest usual tolerances
TIGHT = {"rtol": 1e-12, "atol": 1e-12}
#: the engine at its tightest, to show the tight reference's own error
ENGINE_TIGHT = {"rtol": 1e-12, "atol": 1e-14}
#: SciPy's tolerances tried for equal accuracy (absolute: rtol / 100, as the engine's)
LADDER = (1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10)


def scipy_sections(fps: np.ndarray, xs: np.ndarray, periods: int, rtol: float, atol: float) -> tuple:
    """Return SciPy's sections of every row (rows, periods, 2), its right-hand sides and its time."""
    fplus = weakening_fplus(C_LAW)
    out = np.empty((len(fps), periods, 2))
    nfev = 0
    t0 = time.perf_counter()
    for i, (f, x) in enumerate(zip(fps, xs, strict=True)):
        out[i], c = reference_strobe(
            fplus, tuple(f), (float(x[0]), float(x[1])), periods, rtol=rtol, atol=atol
        )
        nfev += c.slip_evaluations
    return out, nfev, time.perf_counter() - t0


def main() -> None:
    import numba

    from stickslip.core.forced_api import STAT_FIELDS, forced_strobe
    from stickslip.forced import ForcedSystem
    from stickslip.forced.diagram import bifurcation_diagram
    from stickslip.laws import WeakeningLaw

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--values", type=int, default=1000, help="forcing frequencies in [0.5, 2.5]")
    parser.add_argument("--transient", type=int, default=500, help="periods before the sections")
    parser.add_argument("--record", type=int, default=200, help="sections recorded")
    parser.add_argument("--subset", type=int, default=4, help="frequencies SciPy is timed on (evenly spread)")
    parser.add_argument("--subset-periods", type=int, default=50, help="periods SciPy is timed on")
    parser.add_argument("--error-periods", type=int, default=5, help="periods of the accuracy comparison")
    parser.add_argument("--rtol", type=float, default=1e-8, help="the engine's relative tolerance")
    parser.add_argument("--repeat", type=int, default=3, help="stickslip calls on the subset (the shortest)")
    a = parser.parse_args()

    system = ForcedSystem(WeakeningLaw(c=C_LAW), omega=1.0, q=0.5, nu0=0.3, delta=0.05)
    kernel, lp, fp = system.arrays()
    omegas = np.linspace(*OMEGA_RANGE, a.values)
    engine_tol = {"rtol": a.rtol, "atol": a.rtol * 1e-2}
    periods_full = a.values * (a.transient + a.record)
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
        f"stickslip on numba's {numba.get_num_threads()} threads, SciPy {__import__('scipy').__version__} "
        "on one (Python)"
    )
    print(
        f"work: {system.describe()} (f_+ = 1/(1 + 3 w)); omega in {list(OMEGA_RANGE)}, {a.values} values x "
        f"({a.transient} transient + {a.record} recorded) periods from (s, w) = (0, 0) = {periods_full:,} "
        f"periods; engine rtol {a.rtol:g}, atol {a.rtol * 1e-2:g}"
    )

    t0 = time.perf_counter()
    bifurcation_diagram(
        system, omegas[:: max(1, a.values // 4)], transient=2, record=2, rtol=a.rtol, progress=False
    )
    forced_strobe(kernel, lp, fp, (0.0, 0.0), 1, 1, **engine_tol)
    print(
        "warm-up, not timed below (a 4-value diagram; compilation, cache loading): "
        f"{time.perf_counter() - t0:.2f} s"
    )

    t0 = time.perf_counter()
    ds = bifurcation_diagram(
        system, omegas, transient=a.transient, record=a.record, rtol=a.rtol, progress=False
    )
    t_full = time.perf_counter() - t0
    status = ds.status.values
    print(
        f"stickslip, bifurcation_diagram: {t_full:8.2f} s = {t_full / periods_full * 1e6:.2f} us per period "
        f"(statuses ok: {int(np.sum(status == 0))}/{a.values}; stops per period "
        f"{float(ds.stops_per_period.mean()):.2f}, stick fraction {float(ds.stick_fraction.mean()):.3f}, "
        "averaged over omega)"
    )

    # the subset: evenly spread frequencies, from their first recorded section (on the attractor)
    idx = np.unique(np.linspace(0, a.values - 1, a.subset).round().astype(int))
    fps = np.tile(fp, (idx.size, 1))
    fps[:, 2] = omegas[idx]
    xs = np.stack([ds.s.values[idx, 0], ds.w.values[idx, 0]], axis=-1)
    print(
        f"subset: omega = {', '.join(f'{v:.4f}' for v in omegas[idx])}, "
        "from each one's first recorded section"
    )

    # equal accuracy: the sections of --error-periods periods against the tight reference
    ne = a.error_periods
    tight, _, _ = scipy_sections(fps, xs, ne, **TIGHT)
    eng, _, _ = forced_strobe(kernel, lp, fps, xs, 0, ne, **engine_tol)
    eng_tight, _, _ = forced_strobe(kernel, lp, fps, xs, 0, ne, **ENGINE_TIGHT)
    err_engine = float(np.max(np.abs(eng - tight)))
    print(
        f"accuracy: max |difference| of (s, w) over {idx.size} frequencies x {ne} sections against SciPy at "
        f"rtol {TIGHT['rtol']:g}, atol {TIGHT['atol']:g} (the tight reference; "
        f"stickslip at rtol 1e-12 differs from it by {float(np.max(np.abs(eng_tight - tight))):.1e})"
    )
    print(f"  stickslip, rtol {a.rtol:<7g}: {err_engine:.2e}")
    chosen = None
    for rt in LADDER:
        out, _, _ = scipy_sections(fps, xs, ne, rt, rt * 1e-2)
        err = float(np.max(np.abs(out - tight)))
        mark = ""
        if chosen is None and err <= err_engine:
            chosen = rt
            mark = "  <- the loosest at least as accurate as stickslip: timed"
        print(f"  SciPy DOP853, rtol {rt:<7g}: {err:.2e}{mark}")
    if chosen is None:
        chosen = LADDER[-1]
        print(f"  (no SciPy tolerance of the ladder reached stickslip's error: timed at rtol {chosen:g})")

    np_ = a.subset_periods
    _, nfev, t_sp = scipy_sections(fps, xs, np_, chosen, chosen * 1e-2)
    per_sp = t_sp / (idx.size * np_)
    best = math.inf
    steps = 0.0
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        _, _, st = forced_strobe(kernel, lp, fps, xs, 0, np_, **engine_tol)
        best = min(best, time.perf_counter() - t0)
        steps = float(st[:, STAT_FIELDS.index("steps")].sum())
    per_ss = best / (idx.size * np_)
    print(
        f"subset, {idx.size} frequencies x {np_} periods = {idx.size * np_} periods "
        "(from the attractor's sections):"
    )
    print(
        f"  SciPy DOP853, rtol {chosen:g}: {t_sp:8.3f} s = {per_sp * 1e3:.2f} ms per period "
        f"({nfev / (idx.size * np_):.0f} right-hand sides per period)"
    )
    print(
        f"  stickslip,    rtol {a.rtol:g}: {best:8.4f} s = {per_ss * 1e6:.2f} us per period "
        f"({steps / (idx.size * np_):.0f} steps per period; shortest of {a.repeat}; the full job: "
        f"{t_full / periods_full * 1e6:.2f} us per period)"
    )
    t_sp_full = per_sp * periods_full
    print(
        f"SciPy, the full job: {t_sp_full:,.0f} s = {t_sp_full / 3600:.2f} h, EXTRAPOLATED from the subset "
        f"({per_sp * 1e3:.2f} ms per period x {periods_full:,} periods), not run"
    )
    print(
        f"ratio SciPy / stickslip at equal accuracy: {t_sp_full / t_full:,.0f} x "
        "(the full job, SciPy extrapolated); "
        f"{per_sp / per_ss:,.0f} x per period on the subset"
    )
    print("GPU: not measured (no device lent)")


if __name__ == "__main__":
    main()
