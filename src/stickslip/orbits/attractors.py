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
  engine (:func:`~.return_map.return_map_orbit`).

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
import numpy.typing as npt

from .. import defaults
from ..core.api import Kernel, run_attractors, run_return_maps, run_shooting
from ..core.results import AttractorRows, Regime, ReturnMapStatus, ShootingRows, ShootStatus, Status
from ..laws import DimensionlessLaw
from ..userwarnings import warn
from .return_map import ReturnMapOrbit, return_map_orbit_core

__all__ = [
    "POLISH_FIELDS",
    "SAME_ORBIT_RTOL",
    "SHOOTING_TOL",
    "NoisyOrbitWarning",
    "OrbitKey",
    "orbit_key",
    "polish_rows",
    "same_orbit",
]

#: tolerance of the periodicity residual when polishing (the flow runs at 1/100 of it)
SHOOTING_TOL = 1e-10
#: the next tries where the flow's noise keeps Newton from SHOOTING_TOL (see polish_rows)
SHOOTING_TOLS_NOISY = (1e-9, 3e-9, 1e-8)
#: relative distance under which two orbits of one kind are the same attractor
SAME_ORBIT_RTOL = 1e-6


@dataclass(frozen=True)
class OrbitKey:
    """What identifies an attractor: its kind and, for oscillations, its orbit.

    Attributes
    ----------
    kind : Regime
        ``stick-slip``, ``pure-slip``, ``slip-reversal`` or ``steady-sliding``.
    s_max : float
        Spring-force maximum (where ``w`` crosses ``nu`` upward); NaN where unique.
    period : float
        Period; NaN where unique.

    """

    kind: Regime
    s_max: float = math.nan
    period: float = math.nan


def same_orbit(a: OrbitKey, b: OrbitKey, rtol: float = SAME_ORBIT_RTOL) -> bool:
    """Return whether two attractors are the same (same kind, coinciding orbits)."""
    if a.kind != b.kind:
        return False
    if a.kind in (Regime.STICK_SLIP, Regime.STEADY_SLIDING):
        return True
    return abs(a.s_max - b.s_max) <= rtol * max(1.0, abs(a.s_max), abs(b.s_max)) and abs(
        a.period - b.period
    ) <= rtol * max(a.period, b.period)


def orbit_key(row: AttractorRows) -> OrbitKey | None:
    """Return the key of the attractor in one engine row; None when its computation failed."""
    if not row.ok[0]:
        return None
    reg = Regime.from_code(row.regime[0])
    if reg in (Regime.STICK_SLIP, Regime.STEADY_SLIDING):
        return OrbitKey(reg)
    if reg == Regime.PURE_SLIP:
        kind = Regime.SLIP_REVERSAL if row.n_backward[0] > 0 else Regime.PURE_SLIP
        return OrbitKey(kind, float(row.s_max[0]), float(row.period[0]))
    return None


def distinct(keys: Sequence[OrbitKey]) -> list[OrbitKey]:
    """Return the keys with repeats of one attractor dropped (first kept)."""
    kept: list[OrbitKey] = []
    for k in keys:
        if not any(same_orbit(k, q) for q in kept):
            kept.append(k)
    return kept


def _steady(rows: AttractorRows, i: int, nu: float) -> None:
    """Turn row ``i`` into steady sliding ``(s, w) = (f(nu), nu)``, as the engine writes it."""
    r = rows[i]
    r.status = Status.OK.code
    r.regime = Regime.STEADY_SLIDING.code
    r.amplitude = r.stick_time = 0.0
    for name in ("drive_work", "friction_work"):  # rows of a sweep do not keep them
        if r.keeps(name):
            setattr(r, name, 0.0)
    r.period = math.nan
    r.s_max = r.s_min = r.fnu
    r.w_max = r.w_min = nu
    r.n_backward = 0.0
    rows[i] = r


def _accurate(sh: ShootingRows) -> npt.NDArray[np.bool_]:
    """Whether shooting solutions meet :data:`~stickslip.defaults.ORBIT_RTOL` (amplitude and period)."""
    amp_err = 2.0 * sh.err_s0  # the maximum and the minimum of s each move by about that much
    return np.asarray(
        (amp_err <= defaults.ORBIT_RTOL * sh.amplitude) & (sh.err_period <= defaults.ORBIT_RTOL * sh.period)
    )


class NoisyOrbitWarning(UserWarning):
    """A table law's pure-slip orbit kept at its flow's noise floor, known to less than 1e-8."""


def _say_noisy(error: np.ndarray) -> None:
    """Warn once for the orbits of a call kept at the noise floor beyond ORBIT_RTOL: how well known.

    Such an orbit is an attractor (stable, next to the motion's own), but its amplitude
    and period are known to the table's flow noise over the orbit's contraction, a few
    1e-5 at a multiplier of 0.998, not to :data:`~stickslip.defaults.ORBIT_RTOL`: its
    status ``ok`` comes with this warning. The error is given as its power of ten, so that a
    regime search's or a sweep's many calls repeat few messages (Python shows each once).
    """
    worst = float(np.max(error)) if error.size else 0.0
    if not worst > defaults.ORBIT_RTOL:
        return
    warn(
        f"a pure-slip orbit of this table law is known to about {10.0 ** math.ceil(math.log10(worst)):.0e} "
        f"of its amplitude and period only, not to {defaults.ORBIT_RTOL:g}: it is nearly neutral, as next "
        "to a Hopf point, and the interpolated law's flow is good to 1e-10..1e-8 across its rows, which "
        "the slow contraction multiplies; its regime and stability stand",
        NoisyOrbitWarning,
    )


#: from this many slip-reversal rows on, their return maps run compiled (:func:`_return_maps`):
#: about a second of them in Python, where compiling the map costs some 10 s on a law's first
#: use (at 16, the cold `stickslip reproduce` takes 52 s instead of 42 s; at 1000 its 201-point
#: grids stay in Python, and a sweep of many points goes compiled)
COMPILED_RETURN_MAPS = 1000
#: the fields of the engine's rows that :func:`polish_rows` reads or writes (a sweep keeps these)
POLISH_FIELDS = (
    "status", "regime", "amplitude", "period", "stick_time", "s_max", "s_min", "w_max", "w_min",
    "n_backward", "dfnu", "fnu",
)  # fmt: skip


def _return_maps(
    kernel: Kernel, lp: np.ndarray, nu: np.ndarray, rows: AttractorRows, idx: np.ndarray
) -> list[tuple[int, ReturnMapOrbit | None]]:
    """Return the return-map orbits of rows ``idx`` from their last oscillation (None: there is none).

    From :data:`COMPILED_RETURN_MAPS` rows on (1000), compiled and side by side on the
    threads (20 000 F1 rows with 3041 slip reversals: 0.87 s, against 2.7 s in Python);
    fewer in Python around the engine's trajectories, which costs no compilation of its own
    (the compiled return map adds some 10 s to a law's first use). The same numbers either way.
    """
    if idx.size >= COMPILED_RETURN_MAPS:
        maps = run_return_maps(kernel, lp[idx], nu[idx], rows.s_max[idx], rows.period[idx])
        return [
            (
                int(i),
                ReturnMapOrbit(
                    s0=float(maps.s0[j]),
                    period=float(maps.period[j]),
                    multiplier=float(maps.multiplier[j]),
                    residual=float(maps.residual[j]),
                )
                if maps.status[j] == ReturnMapStatus.OK.code
                else None,
            )
            for j, i in enumerate(idx)
        ]
    out: list[tuple[int, ReturnMapOrbit | None]] = []
    for i in idx:
        try:
            guess = (float(rows.s_max[i]), float(rows.period[i]))
            orb: ReturnMapOrbit | None = return_map_orbit_core(
                kernel, np.ascontiguousarray(lp[i]), float(nu[i]), guess
            )
        except RuntimeError:
            orb = None
        out.append((int(i), orb))
    return out


def polish_rows(
    law: DimensionlessLaw | tuple[Kernel, np.ndarray],
    nu: np.ndarray,
    rows: AttractorRows,
    *,
    rerun: bool = False,
    rtol: float = defaults.RTOL,
    atol: float = defaults.ATOL,
    inplace: bool = False,
) -> tuple[AttractorRows, np.ndarray]:
    """Polish the non-sticking attractors in engine rows; return the new rows and the multipliers.

    Parameters
    ----------
    law : DimensionlessLaw or (Kernel, law parameters)
        The law of every row, or its compiled kernel and the parameter vector of
        each row (shape (n, k)) or of all (shape (k,)), as for a sweep.
    nu : ndarray, shape (n,)
        Driving velocity of each row.
    rows : AttractorRows
        Output of :func:`~stickslip.core.api.run_attractors` (not modified unless
        ``inplace``), keeping
        at least :data:`POLISH_FIELDS` (and the work integrals with ``rerun``).
    rerun : bool, optional
        Restart the engine on each polished orbit to measure the work of the
        drive and of friction over one cycle on it (the engine's own cycle was a
        transient's). Default False.
    rtol, atol : float, optional
        Tolerances of that run.
    inplace : bool, optional
        Polish ``rows`` themselves and return them (a caller that owns them: a
        sweep's block, whose copy takes as long as the rest of the polish). Default
        False: ``rows`` are not modified.

    Returns
    -------
    rows : AttractorRows
        Pure-slip rows carry the shooting solution (amplitude, period, extremes),
        slip-reversal rows the return-map fixed point. An unfinished transient
        for which shooting finds no orbit but steady sliding, where steady sliding
        is linearly stable, becomes steady sliding (it decays onto it, slowly
        next to a Hopf point). Rows that could not be
        polished, or whose orbit's estimated error exceeds
        :data:`~stickslip.defaults.ORBIT_RTOL` (so close to a Hopf point that the
        orbit is ill-conditioned), have status ``not-converged``; but a table law's stable
        orbit that Newton cannot pin down to ``SHOOTING_TOL`` because the flow is noisier
        (across the rows) is shot again at :data:`SHOOTING_TOLS_NOISY` and kept when it is
        stable and next to the motion's own: it is an attractor, known to that noise only
        (a few 1e-5 of the amplitude of a table's orbit of multiplier 0.998).
    multiplier : ndarray, shape (n,)
        Nontrivial Floquet multiplier: 0 for stick-slip, NaN for steady sliding and
        where unknown.

    """
    need = POLISH_FIELDS + (("drive_work", "friction_work") if rerun else ())
    missing = [x for x in need if not rows.keeps(x)]
    if missing:
        raise ValueError(f"polish_rows: the rows do not keep {', '.join(missing)} (run_attractors' fields)")
    if not inplace:
        rows = rows.copy()
    nu = np.asarray(nu, dtype=float)
    n = len(rows)
    mult = np.full(n, math.nan)
    measured = rows.regime == Regime.PURE_SLIP.code
    mult[rows.is_regime(Regime.STICK_SLIP)] = 0.0
    # a transient that ran out of time still has a last oscillation to start from
    startable = measured & np.isfinite(rows.s_max) & np.isfinite(rows.period)
    pure = startable & ~(rows.n_backward > 0)
    reversal = startable & (rows.n_backward > 0)
    rows.status[measured & ~startable] = Status.NOT_CONVERGED.code
    kernel, lp_any = law if isinstance(law, tuple) else law.arrays()
    lp_a = np.asarray(lp_any, dtype=float)
    lp = np.broadcast_to(lp_a, (n, lp_a.shape[-1]))
    polished = np.zeros(n, dtype=bool)
    err_s0 = np.zeros(n)
    if pure.any():
        idx = np.flatnonzero(pure)
        sh = run_shooting(kernel, lp[idx], nu[idx], rows.s_max[idx], rows.period[idx], tol=SHOOTING_TOL)
        good = _accurate(sh)
        noisy = np.zeros(len(idx))  # the estimated error of an orbit kept at the noise floor
        # a stable orbit that Newton cannot pin down to 1e-10 because the flow itself is noisier
        # (a pchip table: 1e-10 to 1e-8 across its rows, times 1 / (1 - multiplier)) is still an
        # attractor: it is shot again at SHOOTING_TOLS_NOISY, and the first stable orbit found
        # next to the motion's own (1e-3) is kept: otherwise one ulp of nu drops it from `cycle`,
        # and a band of a table's map reads stick-slip alone
        # (a table's only: a smooth law's flow is good to its tolerance, and an orbit it cannot
        # pin down is ill-conditioned, next to a Hopf point, as not-converged says)
        for tol in SHOOTING_TOLS_NOISY if kernel.name.startswith("table") else ():
            retry = np.flatnonzero(
                ((sh.status != ShootStatus.OK.code) & (sh.status != ShootStatus.TRIVIAL.code)) | ~good
            )
            if not retry.size:
                break
            k = idx[retry]
            again = run_shooting(kernel, lp[k], nu[k], rows.s_max[k], rows.period[k], tol=tol)
            near = (np.abs(again.s0 - rows.s_max[k]) <= 1e-3 * np.maximum(1.0, np.abs(rows.s_max[k]))) & (
                np.abs(again.period - rows.period[k]) <= 1e-3 * rows.period[k]
            )
            for j, r in enumerate(retry):
                if (
                    again.status[j] == ShootStatus.OK.code
                    and abs(again.divergence_multiplier[j]) < 1.0
                    and near[j]
                ):
                    sh.raw[r] = again.raw[j]
                    good[r] = True
                    noisy[r] = max(
                        2.0 * again.err_s0[j] / again.amplitude[j], again.err_period[j] / again.period[j]
                    )
        # no periodic orbit near the oscillation, and steady sliding is linearly stable: the
        # transient is decaying onto it (slowly, next to a Hopf point)
        trivial = (sh.status == ShootStatus.TRIVIAL.code) & (rows.dfnu[idx] > 0.0)
        for row in idx[trivial]:
            _steady(rows, int(row), float(nu[row]))
        dm = sh.divergence_multiplier
        # every row at once (a Python loop over them costs 24 us a row; a GPU sweep has millions)
        kept = ~trivial & (sh.status == ShootStatus.OK.code) & (np.abs(dm) < 1.0) & good
        rows.status[idx[~trivial & ~kept]] = Status.NOT_CONVERGED.code
        k, i = np.flatnonzero(kept), idx[kept]
        rows.amplitude[i] = sh.amplitude[k]
        rows.period[i] = sh.period[k]
        rows.s_max[i] = sh.s0[k]
        rows.s_min[i] = sh.s0[k] - sh.amplitude[k]
        rows.w_min[i] = sh.w_min[k]
        rows.w_max[i] = sh.w_max[k]
        rows.status[i] = Status.OK.code
        mult[i] = dm[k]
        polished[i] = True
        _say_noisy(noisy)
    for ri, orb in _return_maps(kernel, lp, nu, rows, np.flatnonzero(reversal)):
        if orb is None or not abs(orb.multiplier) < 1.0:
            rows.status[ri] = Status.NOT_CONVERGED.code
            continue
        # error of the fixed point: the residual over the map's contraction
        err_s0[ri] = orb.residual / (1.0 - abs(orb.multiplier))
        rows.s_max[ri] = orb.s0
        rows.period[ri] = orb.period
        mult[ri] = orb.multiplier
        polished[ri] = True
    # where the orbit is known, measure one cycle on it with the engine: the work integrals,
    # and for slip reversal (which shooting does not cover) the extremes and the amplitude
    again = polished & (rerun | reversal)
    if again.any():
        idx = np.flatnonzero(again)
        on = run_attractors(
            kernel,
            lp[idx],
            nu[idx],
            rows.s_max[idx],
            nu[idx],
            from_breakaway=False,
            rtol=rtol,
            atol=atol,
            max_slip_time=defaults.MAX_SLIP_TIME,
            conv_tol=defaults.CONV_TOL,
            diag=rerun,
        )
        lost = (on.regime != Regime.PURE_SLIP.code) | ~np.isfinite(on.amplitude)
        rows.status[idx[lost]] = Status.NOT_CONVERGED.code
        k, i = np.flatnonzero(~lost), idx[~lost]
        if rerun:
            rows.drive_work[i] = on.drive_work[k]
            rows.friction_work[i] = on.friction_work[k]
        rv = reversal[i]
        k, i = k[rv], i[rv]
        rows.amplitude[i] = on.amplitude[k]
        rows.s_min[i] = on.s_min[k]
        rows.w_min[i] = on.w_min[k]
        rows.w_max[i] = on.w_max[k]
        rows.n_backward[i] = on.n_backward[k]
        worse = 2.0 * err_s0[i] > defaults.ORBIT_RTOL * on.amplitude[k]
        rows.status[i[worse]] = Status.NOT_CONVERGED.code
        mult[i[worse]] = math.nan
    return rows, mult
