"""Attractors identified by their orbits: what the engine reaches, polished to a periodic orbit.

The engine follows a transient until successive oscillations agree. Near a Hopf
point the approach is as slow as the distance to the bifurcation (the Floquet
multiplier tends to 1), so a transient that has "converged" can still sit
``1e-6`` off the orbit. Every non-sticking attractor the engine reaches is
therefore *polished*: solved as a periodic orbit from the transient's end —

* a pure-slip orbit (``w > 0`` throughout) by Newton shooting with the compiled
  variational equations (:func:`~stickslip.core.api.run_shooting`);
* a slip-reversal orbit (it never sticks, but the velocity changes sign, so the
  flow switches between the forward and the backward branch of the law) as a
  fixed point of the return map on ``w = nu``, computed by the exact non-smooth
  engine (:func:`~.orbits.return_map_orbit`).

Its nontrivial Floquet multiplier is reported; a stick-slip orbit has
multiplier 0 (the stick phase forgets the velocity). A transient that cannot be
polished keeps its values and the status ``not-converged``: never a confident
number off by more than the documented tolerance.

Two attractors are the same when they are of the same kind and their orbits
coincide (spring-force maximum and period within ``1e-6`` relative): the
stick-slip orbit through breakaway and steady sliding are unique, pure-slip and
slip-reversal orbits are told apart by their orbits, not by names.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .. import defaults
from ..core import engine
from ..core import variational as va
from ..core.api import run_attractors, run_shooting
from ..core.laws import N_LAW_PARAMS, f_scalar
from ..models.friction import DimensionlessLaw
from .orbits import law_arrays, return_map_orbit_core

__all__ = ["SAME_ORBIT_RTOL", "SHOOTING_TOL", "OrbitKey", "orbit_key", "polish_rows", "same_orbit"]

#: tolerance of the periodicity residual when polishing (the flow runs at 1/100 of it)
SHOOTING_TOL = 1e-10
#: relative distance under which two orbits of one kind are the same attractor
SAME_ORBIT_RTOL = 1e-6

STICK_SLIP = "stick-slip"
PURE_SLIP = "pure-slip"
SLIP_REVERSAL = "slip-reversal"
STEADY = "steady-sliding"


@dataclass(frozen=True)
class OrbitKey:
    """What identifies an attractor: its kind and, for oscillations, its orbit.

    Attributes
    ----------
    kind : str
        ``stick-slip``, ``pure-slip``, ``slip-reversal`` or ``steady-sliding``.
    s_max : float
        Spring-force maximum (where ``w`` crosses ``nu`` upward); NaN where unique.
    period : float
        Period; NaN where unique.

    """

    kind: str
    s_max: float = math.nan
    period: float = math.nan


def same_orbit(a: OrbitKey, b: OrbitKey, rtol: float = SAME_ORBIT_RTOL) -> bool:
    """Return whether two attractors are the same (same kind, coinciding orbits)."""
    if a.kind != b.kind:
        return False
    if a.kind in (STICK_SLIP, STEADY):
        return True
    return abs(a.s_max - b.s_max) <= rtol * max(1.0, abs(a.s_max), abs(b.s_max)) and abs(
        a.period - b.period
    ) <= rtol * max(a.period, b.period)


def orbit_key(row: np.ndarray) -> OrbitKey | None:
    """Return the key of the attractor in an engine row (layout ``O_*``); None when it failed."""
    if row[engine.O_STATUS] != engine.ST_OK:
        return None
    reg = int(row[engine.O_REGIME])
    if reg == engine.RG_STICK_SLIP:
        return OrbitKey(STICK_SLIP)
    if reg == engine.RG_STEADY:
        return OrbitKey(STEADY)
    if reg == engine.RG_PURE_SLIP:
        kind = SLIP_REVERSAL if row[engine.O_NBACKWARD] > 0 else PURE_SLIP
        return OrbitKey(kind, float(row[engine.O_SMAX]), float(row[engine.O_PERIOD]))
    return None


def distinct(keys: Sequence[OrbitKey]) -> list[OrbitKey]:
    """Return the keys with repeats of one attractor dropped (first kept)."""
    kept: list[OrbitKey] = []
    for k in keys:
        if not any(same_orbit(k, q) for q in kept):
            kept.append(k)
    return kept


_MEASURED_ON_ORBIT = (engine.O_AMPLITUDE, engine.O_SMIN, engine.O_WMIN, engine.O_WMAX, engine.O_NBACKWARD)


def _steady(row: np.ndarray, nu: float, f_nu: float) -> None:
    """Turn an engine row into steady sliding ``(s, w) = (f(nu), nu)``, as the engine writes it."""
    row[engine.O_STATUS] = engine.ST_OK
    row[engine.O_REGIME] = engine.RG_STEADY
    for k in (engine.O_AMPLITUDE, engine.O_STICK_TIME, engine.O_DRIVE_WORK, engine.O_FRICTION_WORK):
        row[k] = 0.0
    row[engine.O_PERIOD] = math.nan
    row[engine.O_SMAX] = row[engine.O_SMIN] = f_nu
    row[engine.O_WMAX] = row[engine.O_WMIN] = nu
    row[engine.O_NBACKWARD] = 0.0


def _accurate(o: np.ndarray) -> bool:
    """Whether a shooting solution meets :data:`~stickslip.defaults.ORBIT_RTOL` (amplitude and period)."""
    amp_err = 2.0 * o[va.SH_ERR_S0]  # the maximum and the minimum of s each move by about that much
    return bool(
        amp_err <= defaults.ORBIT_RTOL * o[va.SH_AMPLITUDE]
        and o[va.SH_ERR_PERIOD] <= defaults.ORBIT_RTOL * o[va.SH_PERIOD]
    )


def polish_rows(
    law: DimensionlessLaw | tuple[np.ndarray, np.ndarray],
    nu: np.ndarray,
    rows: np.ndarray,
    *,
    rerun: bool = False,
    rtol: float = defaults.RTOL,
    atol: float = defaults.ATOL,
) -> tuple[np.ndarray, np.ndarray]:
    """Polish the non-sticking attractors in engine rows; return the new rows and the multipliers.

    Parameters
    ----------
    law : DimensionlessLaw or (law ids, law parameters)
        The law of every row, or per row its compiled id (shape (n,)) and
        parameter vector (shape (n, N_LAW_PARAMS)), as for a sweep.
    nu : ndarray, shape (n,)
        Driving velocity of each row.
    rows : ndarray, shape (n, NOUT)
        Output of :func:`~stickslip.core.api.run_attractors` (not modified).
    rerun : bool, optional
        Restart the engine on each polished orbit to measure the work of the
        drive and of friction over one cycle on it (the engine's own cycle was a
        transient's). Default False.
    rtol, atol : float, optional
        Tolerances of that run.

    Returns
    -------
    rows : ndarray, shape (n, NOUT)
        Pure-slip rows carry the shooting solution (amplitude, period, extremes),
        slip-reversal rows the return-map fixed point. An unfinished transient
        for which shooting finds no orbit but steady sliding, where steady sliding
        is linearly stable, becomes steady sliding (it decays onto it, slowly
        next to a Hopf point). Rows that could not be
        polished, or whose orbit's estimated error exceeds
        :data:`~stickslip.defaults.ORBIT_RTOL` (so close to a Hopf point that the
        orbit is ill-conditioned), have status ``ST_NOT_CONVERGED``.
    multiplier : ndarray, shape (n,)
        Nontrivial Floquet multiplier: 0 for stick-slip, NaN for steady sliding and
        where unknown.

    """
    rows = np.array(rows, dtype=float, copy=True)
    nu = np.asarray(nu, dtype=float)
    n = rows.shape[0]
    mult = np.full(n, math.nan)
    reg = rows[:, engine.O_REGIME]
    measured = reg == engine.RG_PURE_SLIP
    mult[(reg == engine.RG_STICK_SLIP) & (rows[:, engine.O_STATUS] == engine.ST_OK)] = 0.0
    # a transient that ran out of time still has a last oscillation to start from
    startable = measured & np.isfinite(rows[:, engine.O_SMAX]) & np.isfinite(rows[:, engine.O_PERIOD])
    pure = startable & ~(rows[:, engine.O_NBACKWARD] > 0)
    reversal = startable & (rows[:, engine.O_NBACKWARD] > 0)
    rows[measured & ~startable, engine.O_STATUS] = engine.ST_NOT_CONVERGED
    if isinstance(law, tuple):
        law_id = np.broadcast_to(np.asarray(law[0], dtype=np.int64), (n,))
        lp = np.broadcast_to(np.asarray(law[1], dtype=float), (n, N_LAW_PARAMS))
    else:
        one_id, one_lp = law_arrays(law)
        law_id = np.full(n, one_id, dtype=np.int64)
        lp = np.broadcast_to(one_lp, (n, N_LAW_PARAMS))
    polished = np.zeros(n, dtype=bool)
    err_s0 = np.zeros(n)
    if pure.any():
        idx = np.flatnonzero(pure)
        sh = run_shooting(
            law_id[idx],
            lp[idx],
            nu[idx],
            rows[idx, engine.O_SMAX],
            rows[idx, engine.O_PERIOD],
            tol=SHOOTING_TOL,
        )
        for j, i in enumerate(idx):
            o = sh[j]
            if o[va.SH_STATUS] == va.SHOOT_TRIVIAL and rows[i, engine.O_DFNU] > 0.0:
                # no periodic orbit near the oscillation, and steady sliding is linearly stable:
                # the transient is decaying onto it (slowly, next to a Hopf point)
                _steady(rows[i], float(nu[i]), f_scalar(int(law_id[i]), lp[i, 0], lp[i, 1], float(nu[i])))
                continue
            if o[va.SH_STATUS] != va.SHOOT_OK or not abs(o[va.SH_DIV_MULT]) < 1.0 or not _accurate(o):
                rows[i, engine.O_STATUS] = engine.ST_NOT_CONVERGED
                continue
            rows[i, engine.O_AMPLITUDE] = o[va.SH_AMPLITUDE]
            rows[i, engine.O_PERIOD] = o[va.SH_PERIOD]
            rows[i, engine.O_SMAX] = o[va.SH_S0]
            rows[i, engine.O_SMIN] = o[va.SH_S0] - o[va.SH_AMPLITUDE]
            rows[i, engine.O_WMIN] = o[va.SH_W_MIN]
            rows[i, engine.O_WMAX] = o[va.SH_W_MAX]
            rows[i, engine.O_STATUS] = engine.ST_OK
            mult[i] = o[va.SH_DIV_MULT]
            polished[i] = True
    for i in np.flatnonzero(reversal):
        try:
            orb = return_map_orbit_core(
                int(law_id[i]),
                np.ascontiguousarray(lp[i]),
                float(nu[i]),
                (float(rows[i, engine.O_SMAX]), float(rows[i, engine.O_PERIOD])),
            )
        except RuntimeError:
            rows[i, engine.O_STATUS] = engine.ST_NOT_CONVERGED
            continue
        if not abs(orb.multiplier) < 1.0:
            rows[i, engine.O_STATUS] = engine.ST_NOT_CONVERGED
            continue
        # error of the fixed point: the residual over the map's contraction
        err_s0[i] = orb.residual / (1.0 - abs(orb.multiplier))
        rows[i, engine.O_SMAX] = orb.s0
        rows[i, engine.O_PERIOD] = orb.period
        mult[i] = orb.multiplier
        polished[i] = True
    # where the orbit is known, measure one cycle on it with the engine: the work integrals,
    # and for slip reversal (which shooting does not cover) the extremes and the amplitude
    again = polished & (rerun | reversal)
    if again.any():
        idx = np.flatnonzero(again)
        on = run_attractors(
            law_id[idx],
            lp[idx],
            nu[idx],
            rows[idx, engine.O_SMAX],
            nu[idx],
            from_breakaway=False,
            rtol=rtol,
            atol=atol,
            max_slip_time=defaults.MAX_SLIP_TIME,
            conv_tol=defaults.CONV_TOL,
            diag=rerun,
        )
        for j, i in enumerate(idx):
            o = on[j]
            if o[engine.O_REGIME] != engine.RG_PURE_SLIP or not np.isfinite(o[engine.O_AMPLITUDE]):
                rows[i, engine.O_STATUS] = engine.ST_NOT_CONVERGED
                continue
            if rerun:
                rows[i, engine.O_DRIVE_WORK] = o[engine.O_DRIVE_WORK]
                rows[i, engine.O_FRICTION_WORK] = o[engine.O_FRICTION_WORK]
            if reversal[i]:
                for k in (
                    engine.O_AMPLITUDE,
                    engine.O_SMIN,
                    engine.O_WMIN,
                    engine.O_WMAX,
                    engine.O_NBACKWARD,
                ):
                    rows[i, k] = o[k]
                if 2.0 * err_s0[i] > defaults.ORBIT_RTOL * o[engine.O_AMPLITUDE]:
                    rows[i, engine.O_STATUS] = engine.ST_NOT_CONVERGED
                    mult[i] = math.nan
    return rows, mult
