"""Continuation in the driving velocity: every branch, its stability, and the regimes.

Three kinds of branch exist for a velocity-dependent law (PHYSICS.md §3):

``steady-sliding``
    ``(s, w) = (f(nu), nu)``, stable exactly where ``f'(nu) > 0``; it changes
    stability at the Hopf points ``f'(nu_H) = 0`` (:func:`~.stability.hopf_points`).
``pure-slip``
    Periodic orbits that never stop. Each is born at a Hopf point and followed
    by pseudo-arclength continuation in ``(A, T, nu)`` (``A`` = spring-force
    maximum above ``f(nu)``, ``T`` = period), each point solved by Newton
    shooting with the compiled variational equations
    (:mod:`stickslip.core.variational`), so unstable orbits and folds are
    followed as easily as stable ones. Stability is the nontrivial Floquet
    multiplier ``exp(-integral of f'(w) over a period)``. A branch ends where
    its minimum velocity touches zero (*grazing*: the orbit passes through the
    breakaway point and becomes the stick-slip orbit), where it leaves the range,
    or where its period blows up.
``stick-slip``
    The orbit through breakaway ``(s, w) = (1, 0)``. It exists where the slip
    from breakaway stops, which the exact non-smooth engine decides. Its
    monodromy matrix, built with saltation matrices
    (:func:`~.orbits.stick_slip_orbit`), has multipliers 1 and 0: where it
    exists it is stable.

The regime at a driving velocity is the set of attractors there: the stable
steady sliding, the stable pure-slip orbits, the stick-slip orbit.
``bistable`` marks two, ``multistable`` three or more. Interval ends are located to ``1e-9`` (Hopf,
grazing of a continued orbit, onset of stick-slip by bisection on the engine,
folds of cycles by Brent on the ``nu`` component of the branch's tangent); a fold
whose refinement fails falls back to the vertex of the quadratic through the
three points around the turn (the continuation's resolution).
"""

from __future__ import annotations

import itertools
import json
import math
import numbers
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from .. import defaults
from ..core.api import run_attractors, run_flow
from ..core.checks import NU_MAX, NU_MIN
from ..core.results import AttractorRows, Regime
from ..dynamics.attractors import OrbitKey, distinct, orbit_key, polish_rows, same_orbit
from ..errors import ArgumentTypeError
from ..io.jsonable import json_clean
from ..laws import DimensionlessLaw, law_arrays, require_dimensionless_law
from ..models.parameters import DimensionlessParameters
from ..units import check_number
from ..userwarnings import warn
from .orbits import PeriodicOrbit, pure_slip_orbit
from .stability import Hopf, hopf_points

__all__ = [
    "Branch",
    "Confirmation",
    "Interval",
    "RegimeDiagram",
    "SpecialPoint",
    "confirm",
    "continue_pure_slip",
    "interval_regime",
    "pure_slip_orbits_at",
    "regimes",
    "stable_pure_slip_at",
    "stick_slip_branch",
]

#: the most points of the ``nu`` grid of one diagram (each one a run from rest)
MAX_GRID = 100_000

REGIME_NAMES = (
    "stick-slip",
    "pure-slip",
    "slip-reversal",
    "bistable",
    "multistable",
    "steady-sliding",
    "none",
    "unknown",
)


@dataclass(frozen=True)
class Branch:
    """One branch of steady states or periodic orbits against ``nu`` (dimensionless).

    Attributes
    ----------
    kind : str
        ``steady-sliding``, ``pure-slip`` or ``stick-slip``.
    nu : ndarray
        Driving velocities along the branch (in continuation order).
    amplitude : ndarray
        ``max s - min s`` (0 for steady sliding), units of static friction.
    period : ndarray
        Period (units of ``sqrt(m/k)``); NaN for steady sliding.
    min_velocity : ndarray
        Smallest block velocity on the orbit (``nu`` for steady sliding).
    max_force : ndarray
        Largest spring force on the orbit (``f(nu)`` for steady sliding).
    multiplier : ndarray
        Nontrivial Floquet multiplier (0 for stick-slip); for steady sliding the
        largest real part of the eigenvalues.
    stable : ndarray of bool
        Stability of each point.
    end : str
        Why the branch stops: ``range``, ``grazing``, ``hopf``, ``period`` (blow-up),
        ``points`` (budget), ``failed`` (Newton could not continue).
    log_multiplier : ndarray or None
        Pure slip: the natural log of the multiplier, ``-integral of f'(w)`` over the
        period. An unstable orbit is followed by shooting backward in time however
        unstable it is, and its multiplier can pass the floats' 1.8e308 (``multiplier``
        is then inf; this is not). None for the other kinds.

    """

    kind: str
    nu: np.ndarray
    amplitude: np.ndarray
    period: np.ndarray
    min_velocity: np.ndarray
    max_force: np.ndarray
    multiplier: np.ndarray
    stable: np.ndarray
    end: str
    log_multiplier: np.ndarray | None = None

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready dictionary."""
        return {
            "kind": self.kind,
            "end": self.end,
            "nu": json_clean(self.nu.tolist()),
            "amplitude": json_clean(self.amplitude.tolist()),
            "period": json_clean(self.period.tolist()),
            "min_velocity": json_clean(self.min_velocity.tolist()),
            "max_force": json_clean(self.max_force.tolist()),
            "multiplier": json_clean(self.multiplier.tolist()),
            "stable": [bool(b) for b in self.stable],
            **(
                {}
                if self.log_multiplier is None
                else {"log_multiplier": json_clean(self.log_multiplier.tolist())}
            ),
        }


@dataclass(frozen=True)
class SpecialPoint:
    """A bifurcation on a branch: ``hopf``, ``fold``, ``grazing`` or ``stick-slip-onset``."""

    kind: str
    nu: float
    amplitude: float
    detail: str = ""


def interval_regime(attractors: Sequence[Regime]) -> Regime:
    """Return the regime of an interval with these attractors.

    ``unknown`` where the engine failed; ``bistable`` for two, ``multistable`` for three or
    more; one attractor names the regime (``slip-reversal`` too: an oscillation that never
    sticks but slips backward is not the paper's pure slip); none, ``none``.

    >>> interval_regime([Regime.STICK_SLIP, Regime.PURE_SLIP, Regime.STEADY_SLIDING]).value
    'multistable'
    """
    if Regime.UNKNOWN in attractors:
        return Regime.UNKNOWN
    if len(attractors) > 2:
        return Regime.MULTISTABLE
    if len(attractors) > 1:
        return Regime.BISTABLE
    if attractors:
        return attractors[0]
    return Regime.NONE


@dataclass(frozen=True)
class Interval:
    """A range of ``nu`` with one set of attractors.

    Attributes
    ----------
    regime : str
        ``stick-slip``, ``pure-slip``, ``slip-reversal``, ``steady-sliding``, ``bistable`` (two
        attractors), ``multistable`` (three or more), ``none`` (no attractor: possible only for a law with
        neutral steady sliding) or ``unknown`` (the engine failed there).
    nu_min, nu_max : float
        Ends of the interval (dimensionless).
    attractors : tuple of str
        The attractors present, e.g. ``("stick-slip", "steady-sliding")``.
        ``slip-reversal`` is an oscillation that never sticks but whose velocity
        changes sign (backward slip without a stop), found by the engine from
        rest; alone, it is its interval's regime.

    """

    regime: Regime
    nu_min: float
    nu_max: float
    attractors: tuple[Regime, ...]


@dataclass(frozen=True)
class RegimeDiagram:
    """Branches, bifurcations and regime intervals of one law over ``[nu_min, nu_max]``."""

    law: DimensionlessLaw
    nu_min: float
    nu_max: float
    hopf: tuple[Hopf, ...]
    intervals: tuple[Interval, ...]
    branches: tuple[Branch, ...]
    points: tuple[SpecialPoint, ...]
    #: the engine's output (layout ``O_*``) from breakaway at each ``nu`` of the steady-sliding branch,
    #: non-sticking attractors polished into their orbits
    rest: AttractorRows = field(default_factory=lambda: AttractorRows.empty(0), repr=False)
    #: the engine's output from each probe (:data:`PROBE_PUSHES`) at each grid ``nu``, polished:
    #: one set of rows per push
    probes: tuple[AttractorRows, ...] = field(default_factory=tuple, repr=False)
    units: dict[str, str] = field(default_factory=lambda: {"nu": "1", "amplitude": "mu_s W"})
    #: what the diagram owes to the law's construction (a Hopf point on a pchip row, the
    #: table's extrapolation), also issued as ``UserWarning``
    notes: tuple[str, ...] = ()

    def regime_at(self, nu: float) -> Interval:
        """Return the interval containing ``nu``.

        At an end shared by two intervals, the lower one; but exactly at a supercritical Hopf
        point, the one on its stable side: the cycle there has amplitude 0, and steady sliding
        is the attractor (a regime map's cell on the Hopf point of a linear grid said pure-slip).
        """
        for h in self.hopf:
            if h.criticality == "supercritical" and abs(nu - h.nu) <= 1e-12 * h.nu:
                side = [
                    iv
                    for iv in self.intervals
                    if (iv.nu_min if h.stable_side == "above" else iv.nu_max) == h.nu
                ]
                if side:
                    return side[0]
        for iv in self.intervals:
            if iv.nu_min <= nu <= iv.nu_max:
                return iv
        raise ValueError(f"nu={nu!r}: outside [{self.nu_min}, {self.nu_max}]")

    def as_dict(self) -> dict[str, Any]:
        """Return the JSON-ready dictionary printed by ``stickslip regimes --json``."""
        return {
            "law": {"name": self.law.name, **self.law.params, "description": self.law.describe()},
            "nu_min": self.nu_min,
            "nu_max": self.nu_max,
            "hopf": [
                {
                    "nu": h.nu,
                    "criticality": h.criticality,
                    "l1": h.l1,
                    "stable_side": h.stable_side,
                    "kink": h.kink,
                }
                for h in self.hopf
            ],
            "intervals": [
                {
                    "regime": iv.regime,
                    "nu_min": iv.nu_min,
                    "nu_max": iv.nu_max,
                    "attractors": list(iv.attractors),
                }
                for iv in self.intervals
            ],
            "points": [json_clean(asdict(p)) for p in self.points],
            "branches": [b.as_dict() for b in self.branches],
            "units": dict(self.units),
            "warnings": list(self.notes),
        }

    def to_json(self, **kwargs: Any) -> str:
        """Return :meth:`as_dict` as JSON."""
        return json.dumps(self.as_dict(), **kwargs)


# ----------------------------------------------------------------------------- pure slip


def _kink_ratio(f2_left: float, f2_right: float) -> float:
    """Return ``r = (nu - nu_H) / a`` of the small cycles born at a Hopf point on a kink of ``f'``.

    With ``f'(nu_H) = 0`` and ``f''`` equal to ``f2_left`` below ``nu_H`` and ``f2_right``
    above, the averaged amplitude equation of a cycle ``w = nu + a sin(theta)`` is homogeneous
    of degree 2 in ``(nu - nu_H, a)``; it vanishes where ``G(r)``, the first Fourier sine
    coefficient of ``f2(x) x**2`` with ``x = r + sin(theta)``, does: a root in ``(-1, 1)``
    (the cycle straddles the kink). The small-``r`` expansion ``r = -2 J / (3 pi f2)`` is 2.6
    times too large for a table with ``f''`` of 8747 and 1757 on its two sides.
    """
    from scipy.optimize import brentq

    theta = np.linspace(0.0, 2.0 * math.pi, 4097)[:-1]
    sin = np.sin(theta)

    def g(r: float) -> float:
        x = r + sin
        return float(np.mean(np.where(x > 0, f2_right, f2_left) * x * x * sin))

    lo, hi = g(-1.0), g(1.0)
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo * hi >= 0:
        return 0.0
    return float(brentq(g, -1.0, 1.0, xtol=1e-12))


class _Scaled:
    """A :class:`_Shooter` in scaled coordinates ``y = x / size``, for the continuation's steps.

    The arclength in ``x = (A, T, nu)`` let the period dominate where ``nu`` is small: at
    a Hopf point at ``nu = 0.002`` (a table law) a step of ``0.02 nu`` moved ``T`` by
    ``4e-5`` of its ``2 pi``, and 600 steps went nowhere. Scaled by ``(nu_H, 2 pi, nu_H)``
    (``nu_H`` at least 0.1), each component steps in proportion to its own size.
    """

    def __init__(self, sh: _Shooter, size: np.ndarray) -> None:
        self.sh, self.size = sh, size

    def residual(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        g, j = self.sh.residual(y * self.size)
        return g, j * self.size

    def measure(self, y: np.ndarray) -> dict[str, float]:
        return self.sh.measure(y * self.size)

    def evaluate(self, y: np.ndarray, *, measure: bool) -> tuple[np.ndarray, np.ndarray, dict[str, float]]:
        g, j, m = self.sh.evaluate(y * self.size, measure=measure)
        return g, j * self.size, m


class _Shooter:
    """Residual and Jacobian of the periodic-orbit equations in ``x = (A, T, nu)``.

    With ``reverse`` the period is integrated backward in time from the orbit's spring-force
    maximum: the same orbit, the same unknowns, but an unstable orbit contracts under the
    backward flow. Forward shooting of an orbit with multiplier ``m`` amplifies the
    integration's error by ``m`` (and a pchip table's 1e-10 to 1e-8 across its rows): the
    unstable branch of a table's subcritical Hopf point was lost at ``m = 3200``; backward
    shooting follows it through multipliers of ``exp(5000)`` to its grazing at the
    stick-slip onset. The continuation shoots backward wherever the last orbit was unstable.
    """

    def __init__(self, law: DimensionlessLaw, rtol: float) -> None:
        self.law = law
        self.kernel, self.lp = law_arrays(law)
        self.rtol = rtol
        self.reverse = False

    def f(self, nu: float, order: int = 0) -> float:
        return self.law.at(nu, order)

    def residual(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return ``G(x)`` and its 2 x 3 Jacobian."""
        g, j, _ = self.evaluate(x, measure=False)
        return g, j

    def measure(self, x: np.ndarray) -> dict[str, float]:
        """Return amplitude, minimum velocity and nontrivial multiplier of the orbit at ``x``."""
        return self.evaluate(x, measure=True)[2]

    def evaluate(self, x: np.ndarray, *, measure: bool) -> tuple[np.ndarray, np.ndarray, dict[str, float]]:
        """One integration: residual, Jacobian and (with ``measure``) the orbit's measurements."""
        a, period, nu = float(x[0]), float(x[1]), float(x[2])
        s0 = self.f(nu) + a
        if not (math.isfinite(s0) and math.isfinite(period) and period > 0 and 0 < nu < 1e12):
            raise RuntimeError(f"continuation left the domain (nu={nu!r}, period={period!r})")
        # inside Newton's loop: values of our own, checked just above
        fl = run_flow(
            self.kernel,
            self.lp,
            nu,
            s0,
            nu,
            period,
            rtol=self.rtol,
            measure=measure,
            checked=False,
            reverse=self.reverse,
        )
        y = fl.state
        g = np.array([y[0] - s0, y[1] - nu])
        phi = fl.monodromy
        d0 = np.array([self.f(nu, 1), 1.0])  # d(s0, w0)/d nu
        j = np.empty((2, 3))
        j[:, 0] = phi[:, 0] - np.array([1.0, 0.0])
        # d/dT of the end point: the vector field there, negative backward
        j[:, 1] = np.array([nu - y[1], y[0] - self.f(y[1])]) * (-1.0 if self.reverse else 1.0)
        j[:, 2] = phi @ d0 + fl.d_nu - d0
        meas = {}
        if measure:
            log_m = -fl.integral_dfdw
            meas = {
                "amplitude": s0 - fl.s_min,
                "min_velocity": fl.w_min,
                # beyond the floats (an orbit backward shooting still follows): infinite
                "multiplier": math.exp(log_m) if log_m < 709.0 else math.inf,
                "log_multiplier": log_m,
            }
        return g, j, meas


def _newton(
    fun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    x: np.ndarray,
    tol: float,
    max_iter: int = 12,
) -> tuple[np.ndarray, int] | None:
    """Newton's method on a square system; None when it fails.

    Where the residual stagnates above ``tol`` (the integration's own noise: across
    a pchip table's rows, where ``f''`` jumps, the flow is good to 1e-10 to 1e-8
    however small its tolerance), Newton stops at the noise floor: once the residual is
    within ``1e3 tol`` and the correction no longer shrinks (more than half the last one)
    or is below ``tol``, the iterate is taken, with its count. Wandering in the noise for
    the remaining iterations would have the continuation read the count as a hard step
    and shorten the next one (a table's unstable branch took steps of 1e-7 so). Failing
    that, the best iterate within ``1e3 tol`` that Newton moved by less than ``1e4 tol``
    is taken, with the count of the iteration that first came that close.
    """
    best: tuple[float, np.ndarray, int] | None = None
    dn_last = math.inf
    for it in range(1, max_iter + 1):
        try:
            g, j = fun(x)
        except RuntimeError:
            return None
        if not np.all(np.isfinite(g)):
            return None
        try:
            dx = np.linalg.solve(j, -g)
        except np.linalg.LinAlgError:
            return None
        gn, dn = float(np.linalg.norm(g)), float(np.linalg.norm(dx))
        if gn < 1e3 * tol and dn < 1e4 * tol and (best is None or gn < best[0]):
            best = (gn, x.copy(), it if best is None else best[2])
        if gn < 1e3 * tol and (dn < tol or (dn < 1e4 * tol and dn > 0.5 * dn_last)):
            return (x + dx if gn < tol or dn < tol else x), it
        x = x + dx
        dn_last = dn
        if gn < tol and dn < 1e3 * tol:
            return x, it
        if not np.all(np.isfinite(x)) or x[1] <= 0:
            return None
    if best is not None:
        return best[1], best[2]
    return None


def _null_vector(j: np.ndarray) -> np.ndarray:
    t = np.cross(j[0], j[1])
    return t / np.linalg.norm(t)


def continue_pure_slip(
    law: DimensionlessLaw,
    hopf: Hopf,
    nu_min: float,
    nu_max: float,
    *,
    tol: float = 1e-10,
    max_points: int = 600,
    ds_max: float | None = None,
) -> tuple[Branch, list[SpecialPoint]]:
    """Follow the pure-slip orbits born at ``hopf`` until they graze or leave ``[nu_min, nu_max]``.

    Parameters
    ----------
    law : DimensionlessLaw
        The friction law.
    hopf : Hopf
        Where the branch is born (from :func:`~.stability.hopf_points`).
    nu_min, nu_max : float
        Range in which to follow the branch.
    tol : float, optional
        Newton tolerance on the periodicity residual; the flow is integrated at ``tol / 100``.
    max_points : int, optional
        Budget of continuation points.
    ds_max : float, optional
        Largest arclength step in ``(A, T, nu)``; default ``0.02 * max(nu_H, 0.1)``.

    Returns
    -------
    branch : Branch
    points : list of SpecialPoint
        Folds and the grazing point found on the way.

    """
    law = require_dimensionless_law(law)
    shooter = _Shooter(law, tol * 1e-2)
    nu_h = hopf.nu
    f2, f3 = shooter.f(nu_h, 2), shooter.f(nu_h, 3)
    scale = max(nu_h, 0.1)
    ds_max = 0.02 * scale if ds_max is None else ds_max
    # First two points at fixed small A (natural continuation in A): nu from averaging,
    # a^2 = -8 f'(nu)/f'''(nu) ~ -8 f''(nu_H)(nu - nu_H)/f'''(nu_H).
    # At a Hopf point on a kink of f' (a row of a pchip table, where f' = 0 and f'' jumps) the
    # small cycle grows linearly: nu - nu_H = r a (see _kink_ratio); its first amplitudes are
    # kept within a hundredth of nu_H of it (the cubic guess failed there, and the branch was
    # dropped without a word)
    amplitudes = (0.01 * scale, 0.02 * scale)
    if hopf.kink:
        per_a = _kink_ratio(shooter.f(nu_h * (1 - 1e-9), 2), shooter.f(nu_h * (1 + 1e-9), 2))
        a_small = min(0.01 * scale, 0.01 * nu_h / max(abs(per_a), 1e-3))
        amplitudes = (a_small, 2.0 * a_small)
    xs: list[np.ndarray] = []
    for a in amplitudes:
        if hopf.kink:
            nu0 = nu_h + per_a * a
        else:
            nu0 = nu_h - a * a * f3 / (8.0 * f2) if f2 != 0 else nu_h
        x0 = np.array([a, 2.0 * math.pi, nu0])

        def fixed_a(x: np.ndarray, a: float = a) -> tuple[np.ndarray, np.ndarray]:
            g, j = shooter.residual(x)
            return np.concatenate([g, [x[0] - a]]), np.vstack([j, [1.0, 0.0, 0.0]])

        res = _newton(fixed_a, x0, tol)
        if res is None:
            return _empty_branch("failed"), []
        xs.append(res[0])
    # from here on in scaled coordinates (see _Scaled): steps, tangents and arclength
    size = np.array([scale, 2.0 * math.pi, scale])
    sh = _Scaled(shooter, size)
    xs = [x / size for x in xs]
    ds_max /= scale
    pts: list[np.ndarray] = list(xs)
    meas = [sh.measure(xs[0])]
    _, j_last, m_last = sh.evaluate(xs[1], measure=True)
    meas.append(m_last)
    shooter.reverse = m_last["multiplier"] > 1.0  # unstable: shoot backward (see _Shooter)
    tangent = _null_vector(j_last)
    if np.dot(tangent, xs[1] - xs[0]) < 0:
        tangent = -tangent
    ds = min(ds_max, float(np.linalg.norm(xs[1] - xs[0])))
    special: list[SpecialPoint] = []
    end = "points"

    def corrector(xp: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, int] | None:
        def aug(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            g, j = sh.residual(x)
            return np.concatenate([g, [float(np.dot(t, x - xp))]]), np.vstack([j, t])

        return _newton(aug, xp, tol)

    while len(pts) < max_points:
        x = pts[-1]
        res = corrector(x + ds * tangent, tangent)
        if res is None or res[0][0] <= 0 or res[0][1] > 100.0:  # T > 200 pi
            if res is not None and res[0][1] > 100.0:
                end = "period"
                break
            if res is not None and res[0][0] <= 0:
                end = "hopf"
                break
            ds *= 0.5
            if ds < 1e-9:
                end = "failed"
                break
            continue
        xn, its = res
        _, j_n, m = sh.evaluate(xn, measure=True)
        # the corrector's hyperplane can cut the branch again far away (near grazing, on the
        # unstable part it came along): a step that lands farther than its own length from the
        # prediction, or turns the tangent by more than 25 degrees, is taken again, shorter
        if np.linalg.norm(xn - (x + ds * tangent)) > ds or abs(np.dot(_null_vector(j_n), tangent)) < 0.9:
            ds *= 0.5
            if ds < 1e-9:
                end = "failed"
                break
            continue
        if not (nu_min <= xn[2] * scale <= nu_max):
            # land exactly on the end of the range
            target = (nu_max if xn[2] * scale > nu_max else nu_min) / scale

            def on_bound(z: np.ndarray, target: float = target) -> tuple[np.ndarray, np.ndarray]:
                g, j = sh.residual(z)
                return np.concatenate([g, [z[2] - target]]), np.vstack([j, [0.0, 0.0, 1.0]])

            rb = _newton(on_bound, xn, tol)
            if rb is not None and m["min_velocity"] > 0:
                pts.append(rb[0])
                meas.append(sh.measure(rb[0]))
            end = "range"
            if m["min_velocity"] > 0:
                break
        if m["min_velocity"] <= 0:
            xg = _grazing(sh, x, tangent, ds, corrector, tol)
            if xg is not None:
                pts.append(xg)
                mg = sh.measure(xg)
                meas.append(mg)
                nu_g = float(xg[2]) * scale
                special.append(SpecialPoint("grazing", nu_g, mg["amplitude"], "min velocity 0"))
            end = "grazing"
            break
        if end == "range":
            break
        t_new = _null_vector(j_n)
        if np.dot(t_new, tangent) < 0:
            t_new = -t_new
        pts.append(xn)
        meas.append(m)
        shooter.reverse = m["multiplier"] > 1.0
        if t_new[2] * tangent[2] < 0:  # nu turned back: a fold of cycles between the last points
            fold = _refine_fold(sh, pts[-3:], tol)
            if fold is None:  # the quadratic through the three points (to the step's resolution)
                special.append(_fold([p * size for p in pts[-3:]], meas[-3:]))
            else:  # on the branch too: the orbits between its last points and the fold exist
                xf, mf, k = fold
                pts.insert(len(pts) - 3 + k, xf)
                meas.insert(len(meas) - 3 + k, mf)
                special.append(
                    SpecialPoint(
                        "fold",
                        float(xf[2]) * scale,
                        mf["amplitude"],
                        f"fold of cycles (saddle-node); multiplier {mf['multiplier']:.6f}",
                    )
                )
        tangent = t_new
        ds = min(ds_max, ds * (1.5 if its <= 3 else (1.0 if its <= 5 else 0.5)))
    xa = np.array(pts) * size
    amp = np.array([m["amplitude"] for m in meas])
    mult = np.array([m["multiplier"] for m in meas])
    branch = Branch(
        kind="pure-slip",
        nu=xa[:, 2],
        amplitude=amp,
        period=xa[:, 1],
        min_velocity=np.array([m["min_velocity"] for m in meas]),
        max_force=np.array([shooter.f(float(x[2])) + float(x[0]) for x in xa]),
        multiplier=mult,
        stable=mult < 1.0,
        end=end,
        log_multiplier=np.array([m["log_multiplier"] for m in meas]),
    )
    return branch, special


def _grazing(
    sh: _Shooter | _Scaled,
    x: np.ndarray,
    tangent: np.ndarray,
    ds: float,
    corrector: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, int] | None],
    tol: float,
) -> np.ndarray | None:
    """Locate the orbit with minimum velocity 0 between ``x`` and ``x + ds * tangent`` (secant)."""
    lo, hi = 0.0, ds
    w_lo = sh.measure(x)["min_velocity"]
    res = corrector(x + hi * tangent, tangent)
    if res is None:
        return None
    w_hi = sh.measure(res[0])["min_velocity"]
    best, w_best = res[0], w_hi  # the orbit of the smallest minimum velocity found
    near = 1e-10 * max(1.0, float(x[2]))
    for _ in range(60):
        sig = hi - w_hi * (hi - lo) / (w_hi - w_lo) if w_hi != w_lo else 0.5 * (lo + hi)
        if not (min(lo, hi) < sig < max(lo, hi)):
            sig = 0.5 * (lo + hi)
        r = corrector(x + sig * tangent, tangent)
        if r is None:  # the best so far, where it grazes to 1e-10 (found before the refinement below)
            return best if abs(w_best) < near else None
        wv = sh.measure(r[0])["min_velocity"]
        if abs(wv) <= abs(w_best):
            best, w_best = r[0], wv
        if wv == 0.0:
            return best
        if wv > 0:
            lo, w_lo = sig, wv
        else:
            hi, w_hi = sig, wv
        # done where the minimum velocity is zero to 1e-10 and the secant's next move in nu is
        # below 1e-9 of nu: at a grazing (a tangency) the minimum velocity changes slowly with nu,
        # and 1e-10 of velocity alone left nu 2.3e-6 off the stick-slip onset (numpy 2.4.6); the
        # corrector's own precision leaves a few 1e-9 (2.7e-10 from the onset at nu = 0.0505)
        if abs(wv) < near:
            moves = abs(wv) * abs(hi - lo) / abs(w_hi - w_lo) * abs(float(tangent[2]))
            if moves <= 1e-9 * abs(float(x[2])):
                return best
    return best


def _refine_fold(
    sh: _Shooter | _Scaled, pts: Sequence[np.ndarray], tol: float
) -> tuple[np.ndarray, dict[str, float], int] | None:
    """Locate the fold of cycles between the first and last of three branch points, to ``1e-9``.

    The branch is parametrised by ``sigma``, the position along the chord from
    ``pts[0]`` to ``pts[2]`` (transverse to ``nu`` near a fold); at each ``sigma``
    the orbit is solved by Newton, and the fold is the root of the ``nu``
    component of the branch's tangent (Brent). Returns the fold's ``(A, T, nu)``,
    its measurements and where it goes among the three points (1: after the
    first, 2: after the second); None when a solve fails (the caller falls back
    to the quadratic through the points).
    """
    p = np.array(pts)
    chord = p[2] - p[0]
    length = float(np.linalg.norm(chord))
    if not length > 0:
        return None
    d = chord / length
    sig = p @ d - float(p[0] @ d)
    if not (0.0 < sig[1] < sig[2]):
        return None
    guess = [np.polyfit(sig, p[:, i], 2) for i in range(3)]

    def solve(s: float) -> tuple[np.ndarray, np.ndarray] | None:
        x0 = np.array([np.polyval(c, s) for c in guess])
        xp = p[0] + s * d

        def aug(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            g, j = sh.residual(x)
            return np.concatenate([g, [float(np.dot(d, x - xp))]]), np.vstack([j, d])

        res = _newton(aug, x0, tol)
        if res is None:
            return None
        _, j = sh.residual(res[0])
        t = _null_vector(j)
        return res[0], (t if np.dot(t, d) > 0 else -t)

    def tnu(s: float) -> float:
        r = solve(s)
        if r is None:
            raise RuntimeError("no orbit")
        return float(r[1][2])

    from scipy import optimize

    try:
        t0, t1, t2 = tnu(0.0), tnu(float(sig[1])), tnu(float(sig[2]))
        if t0 * t1 <= 0:
            lo, hi = 0.0, float(sig[1])
        elif t1 * t2 <= 0:
            lo, hi = float(sig[1]), float(sig[2])
        else:
            return None
        s_f = optimize.brentq(tnu, lo, hi, xtol=1e-12 * length, rtol=1e-14)
    except (RuntimeError, ValueError):
        return None
    r = solve(s_f)
    if r is None:
        return None
    return r[0], sh.measure(r[0]), 1 if s_f < sig[1] else 2


def _fold(pts: Sequence[np.ndarray], meas: Sequence[dict[str, float]]) -> SpecialPoint:
    """Extremum of nu through three points, by a quadratic in the arclength."""
    p = np.array(pts)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    c = np.polyfit(s, p[:, 2], 2)
    s_star = -c[1] / (2 * c[0]) if c[0] != 0 else s[1]
    nu_f = float(np.polyval(c, s_star))
    amp = np.array([m["amplitude"] for m in meas])
    a_f = float(np.polyval(np.polyfit(s, amp, 2), s_star))
    return SpecialPoint("fold", nu_f, a_f, "fold of cycles (saddle-node)")


def _empty_branch(end: str) -> Branch:
    e = np.empty(0)
    return Branch("pure-slip", e, e, e, e, e, e, np.empty(0, dtype=bool), end, e)


# ----------------------------------------------------------------------------- stick slip


def _engine(
    law: DimensionlessLaw, nu: np.ndarray, s0: np.ndarray | None = None, conv_tol: float = defaults.CONV_TOL
) -> AttractorRows:
    """Run the engine with the defaults: from breakaway, or from ``(s0, w = nu)`` when ``s0`` is given."""
    kernel, lp = law_arrays(law)
    return run_attractors(
        kernel,
        lp,
        nu,
        s0,
        None if s0 is None else nu,
        from_breakaway=s0 is None,
        rtol=defaults.RTOL,
        atol=defaults.ATOL,
        max_slip_time=defaults.MAX_SLIP_TIME,
        conv_tol=conv_tol,
    )


def _stick_slip_rows(law: DimensionlessLaw, nu: np.ndarray) -> AttractorRows:
    return _engine(law, nu)


def _is_stick_slip(rows: AttractorRows) -> np.ndarray:
    return rows.is_regime(Regime.STICK_SLIP)


def stick_slip_branch(
    law: DimensionlessLaw, nu: np.ndarray, *, refine: bool = True, rows: AttractorRows | None = None
) -> tuple[Branch, list[SpecialPoint]]:
    """Return the stick-slip orbit through breakaway where it exists, on the grid ``nu``.

    Where existence changes between grid points, its end is located by bisection
    on the engine (to ``1e-9`` relative) and added to the branch and to the points.
    ``rows``, the engine's output from breakaway at ``nu``, is computed when not given.
    """
    law = require_dimensionless_law(law)
    nu = np.asarray(nu, dtype=float)
    if rows is None:
        rows = _stick_slip_rows(law, nu)
    ok = _is_stick_slip(rows)
    special: list[SpecialPoint] = []
    extra_nu: list[float] = []
    if refine:
        for i in np.flatnonzero(ok[:-1] != ok[1:]):
            lo, hi = float(nu[i]), float(nu[i + 1])
            ok_lo = bool(ok[i])
            while hi - lo > 1e-9 * hi:
                mid = 0.5 * (lo + hi)
                if bool(_is_stick_slip(_stick_slip_rows(law, np.array([mid])))[0]) == ok_lo:
                    lo = mid
                else:
                    hi = mid
            edge = lo if ok_lo else hi
            extra_nu.append(edge)
    if extra_nu:
        nu = np.concatenate([nu, extra_nu])
        rows = AttractorRows.concat([rows, _stick_slip_rows(law, np.array(extra_nu))])
        order = np.argsort(nu)
        nu, rows = nu[order], rows[order]
        ok = _is_stick_slip(rows)
        for e in extra_nu:
            j = int(np.searchsorted(nu, e))
            special.append(
                SpecialPoint("stick-slip-onset", e, float(rows.amplitude[j]), "slip from breakaway stops")
            )
    sel = ok
    branch = Branch(
        kind="stick-slip",
        nu=nu[sel],
        amplitude=rows.amplitude[sel],
        period=rows.period[sel],
        min_velocity=rows.w_min[sel],
        max_force=rows.s_max[sel],
        multiplier=np.zeros(int(sel.sum())),
        stable=np.ones(int(sel.sum()), dtype=bool),
        end="range",
    )
    return branch, special


# ----------------------------------------------------------------------------- regimes


def _midpoint(lo: float, hi: float) -> float:
    """Middle of ``[lo, hi]``, geometric when it spans more than a factor 20 (as :func:`_grid`)."""
    return 0.5 * (lo + hi) if hi / lo < 20 else math.sqrt(lo * hi)


def _grid(nu_min: float, nu_max: float, n: int) -> np.ndarray:
    if nu_max / nu_min > 20.0:
        return np.geomspace(nu_min, nu_max, n)
    return np.linspace(nu_min, nu_max, n)


def regimes(
    law: DimensionlessLaw,
    nu_min: float,
    nu_max: float,
    *,
    n_grid: int = 201,
    tol: float = 1e-10,
) -> RegimeDiagram:
    """Compute every branch over ``[nu_min, nu_max]`` and the regime intervals.

    Parameters
    ----------
    law : DimensionlessLaw
        The friction law (dimensionless).
    nu_min, nu_max : float
        Range of the dimensionless driving velocity, ``0 < nu_min < nu_max``.
    n_grid : int, optional
        Grid for the steady-sliding and stick-slip branches (the pure-slip
        branches choose their own steps).
    tol : float, optional
        Shooting tolerance.

    Returns
    -------
    RegimeDiagram

    Raises
    ------
    TypeError
        For an argument of the wrong type (:class:`~stickslip.ArgumentTypeError`, or a
        plain :class:`TypeError` for a law that is not a dimensionless law).
    ValueError
        For a non-positive or reversed range, too small a grid or a tolerance out of range.

    Examples
    --------
    >>> from stickslip import CubicLaw
    >>> from stickslip.bifurcation.regimes import regimes
    >>> d = regimes(CubicLaw(alpha=0.5, gamma=1 / 6), 0.5, 1.5)
    >>> [iv.regime.value for iv in d.intervals]
    ['stick-slip', 'pure-slip', 'steady-sliding']

    """
    law = require_dimensionless_law(law)
    lo = check_number(nu_min, "nu_min")
    hi = check_number(nu_max, "nu_max")
    if lo < NU_MIN:
        raise ValueError(f"nu_min={nu_min!r}: expected a driving velocity of at least {NU_MIN:g}")
    if hi <= lo:
        raise ValueError(f"nu_max={nu_max!r}: expected a value above nu_min={nu_min!r}")
    if hi > NU_MAX:
        raise ValueError(f"nu_max={nu_max!r}: expected a driving velocity of at most {NU_MAX:g}")
    if isinstance(n_grid, bool) or not isinstance(n_grid, int | np.integer):
        raise ArgumentTypeError(f"n_grid={n_grid!r}: expected an integer from 5 to {MAX_GRID}")
    if not 5 <= n_grid <= MAX_GRID:  # each point is a run from rest: 1e8 points run for hours
        raise ValueError(f"n_grid={n_grid!r}: expected an integer from 5 to {MAX_GRID}")
    n_grid = int(n_grid)
    # as pure_slip_orbit's: a nan or negative tol once lost the pure-slip branch without a word
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
        raise ArgumentTypeError(f"tol={tol!r}: expected a shooting tolerance between 1e-13 and 1e-3")
    if not 1e-13 <= tol <= 1e-3:
        raise ValueError(f"tol={tol!r}: expected a shooting tolerance between 1e-13 and 1e-3")
    tol = float(tol)
    # Hopf points in a wider window: a branch born just outside the range may enter it
    # (and always the range itself: a range below 1e-7 once met the window's own 1e-6 bound)
    h_all = hopf_points(law, min(max(lo / 10.0, 1e-6), lo), max(min(hi * 10.0, 1e6), hi))
    hopf_in = tuple(h for h in h_all if lo <= h.nu <= hi)
    grid = _grid(lo, hi, n_grid)

    fp = np.asarray(law.forward(grid, 1), dtype=float)
    steady = Branch(
        kind="steady-sliding",
        nu=grid,
        amplitude=np.zeros_like(grid),
        period=np.full_like(grid, math.nan),
        min_velocity=grid.copy(),
        max_force=np.asarray(law.forward(grid), dtype=float),
        multiplier=np.array([max(z.real for z in _eig(g)) for g in fp]),
        stable=fp > 0,
        end="range",
    )
    branches = [steady]
    points: list[SpecialPoint] = [SpecialPoint("hopf", h.nu, 0.0, h.criticality) for h in hopf_in]
    cut_short: list[str] = []  # branches the continuation could not follow to their end
    for h in h_all:
        if h.criticality == "degenerate":
            continue
        b, sp = continue_pure_slip(law, h, min(lo, h.nu), max(hi, h.nu), tol=tol)
        if b.nu.size:
            branches.append(b)
            points.extend(p for p in sp if lo <= p.nu <= hi)
        if b.end == "failed" and lo <= h.nu <= hi:
            cut_short.append(_cut_short(h, b))
    rest, _ = polish_rows(law, grid, _stick_slip_rows(law, grid))
    ss, sp = stick_slip_branch(law, grid, rows=rest)
    branches.append(ss)
    points.extend(sp)

    # Attractor sets on the grid. A change between neighbouring grid points that no located
    # bifurcation explains (an attractor not connected to a branch, e.g. slip reversal
    # coexisting with stick-slip) is located by bisection on the probes.
    probes = _probe_rows(law, grid, PROBE_PUSHES)
    sets = _attractor_sets(law, grid, branches, rest, probes)
    known = sorted(p.nu for p in points)
    for j in range(grid.size - 1):
        g0, g1 = float(grid[j]), float(grid[j + 1])
        if sets[j] == sets[j + 1] or any(g0 <= k <= g1 for k in known):
            continue
        points.append(_locate_boundary(law, branches, g0, g1, sets[j], sets[j + 1]))

    # interval ends: range, Hopf points, folds, grazing, stick-slip onset, attractor boundaries;
    # ends closer than CUT_RTOL are one point computed two ways (grazing and onset)
    cuts = sorted({lo, hi, *(p.nu for p in points if lo < p.nu < hi)})
    cuts = [c for i, c in enumerate(cuts) if i == 0 or c - cuts[i - 1] > CUT_RTOL * c]
    cuts[-1] = hi
    intervals: list[Interval] = []
    for c0, c1 in itertools.pairwise(cuts):
        att = _attractor_sets(law, np.array([_midpoint(c0, c1)]), branches)[0]
        name = interval_regime(att)
        if intervals and intervals[-1].attractors == att:
            intervals[-1] = Interval(name, intervals[-1].nu_min, c1, att)
        else:
            intervals.append(Interval(name, c0, c1, att))
    notes = cut_short + _notes(law, hopf_in, grid, fp, intervals, (rest, *probes))
    for note in notes:
        warn(note, UserWarning)
    return RegimeDiagram(
        law=law,
        nu_min=lo,
        nu_max=hi,
        hopf=hopf_in,
        intervals=tuple(intervals),
        branches=tuple(branches),
        points=tuple(sorted(points, key=lambda p: p.nu)),
        rest=rest,
        probes=probes,
        notes=tuple(notes),
    )


def _cut_short(h: Hopf, b: Branch) -> str:
    """Say where the pure-slip branch born at ``h`` was lost (the intervals do not rest on it)."""
    if not b.nu.size:
        return (
            f"the pure-slip orbits born at the Hopf point nu = {h.nu:.8g} could not be followed "
            "(shooting did not converge on the first small orbit); the figure has no such branch"
        )
    return (
        f"the pure-slip orbits born at the Hopf point nu = {h.nu:.8g} were followed to nu = "
        f"{b.nu[-1]:.8g} only (amplitude {b.amplitude[-1]:.4g}, multiplier {b.multiplier[-1]:.4g}): "
        "Newton's method found no orbit beyond at any step length; the figure draws the branch "
        "that far (the intervals come from the attractors, not from this branch)"
    )


def _notes(
    law: DimensionlessLaw,
    hopf: Sequence[Hopf],
    grid: np.ndarray,
    fp: np.ndarray,
    intervals: Sequence[Interval],
    rows: Sequence[AttractorRows],
) -> list[str]:
    """Return what a diagram owes to the law's construction, one line each.

    A Hopf point on a table's row, a flat stretch (``f' = 0`` on ``grid``, where
    ``f'`` is ``fp``), a constant law, and motions beyond a table's rows (``rows``:
    the engine's, from rest and from the probes).
    """
    notes = [n for h in hopf if h.kink for n in [law.hopf_note(h.nu, h.criticality)] if n]
    flat = fp == 0.0
    if flat.any() and not flat.all():  # a flat stretch (a table's equal rows): no isolated Hopf point
        edges = np.flatnonzero(np.diff(np.concatenate([[0], flat.astype(np.int8), [0]])))
        for a, b in zip(edges[::2], edges[1::2], strict=True):
            if b - a >= 2:
                start = _flat_end(law, grid[a - 1], grid[a]) if a > 0 else float(grid[0])
                end = _flat_end(law, grid[b], grid[b - 1]) if b < grid.size else float(grid[-1])
                notes.append(
                    f"f'(nu) = 0 from nu = {start:.8g} to {end:.8g} (a flat stretch of the law): "
                    "steady sliding is neutrally stable there, with a family of neutral cycles and no "
                    "isolated Hopf point; its stability changes across the stretch"
                )
    if flat.all() and abs(law.kinetic_limit - 1.0) < 1e-9:
        notes.append(
            "friction is constant and equal to the static threshold (no weakening with velocity and no "
            "drop at the onset of slip): steady sliding is neutrally stable, every motion is a neutral "
            "oscillation that touches w = 0 once a period, and no regime is selected"
        )
    # a table: where the motions went beyond its rows, or why they could not be followed
    failed = any(Regime.UNKNOWN in iv.attractors for iv in intervals)
    extra = law.motion_warning(np.concatenate([r.w_max for r in rows]), failed)
    return [*notes, extra] if extra else notes


def _flat_end(law: DimensionlessLaw, outside: float, inside: float) -> float:
    """Bisect for where ``f'`` turns exactly 0, between a point where it is not and one where it is."""
    for _ in range(80):
        mid = 0.5 * (outside + inside)
        if mid in (outside, inside):
            break
        if law.at(mid, 1) == 0.0:
            inside = mid
        else:
            outside = mid
    return float(inside)


def _eig(fprime: float) -> tuple[complex, complex]:
    root = complex(fprime * fprime - 4.0) ** 0.5
    return ((-fprime + root) / 2, (-fprime - root) / 2)


def stable_pure_slip_at(branches: Sequence[Branch], nu: float) -> list[float]:
    """Amplitudes of the stable pure-slip orbits at ``nu``, interpolated along the branches.

    Linear interpolation between continuation points: good for plotting, not for
    telling orbits apart (use :func:`pure_slip_orbits_at`, which solves them).
    """
    return [o[0] for o in _orbits_at(branches, nu, stable_only=True)]


def _orbits_at(branches: Sequence[Branch], nu: float, *, stable_only: bool) -> list[tuple[float, ...]]:
    """``(amplitude, max_force, period)`` of the pure-slip orbits at ``nu``, interpolated linearly."""
    found = []
    for b in branches:
        if b.kind != "pure-slip" or b.nu.size < 2:
            continue
        for i in range(b.nu.size - 1):
            n0, n1 = b.nu[i], b.nu[i + 1]
            if not (min(n0, n1) <= nu <= max(n0, n1)) or n0 == n1:
                continue
            if stable_only and not (b.stable[i] or b.stable[i + 1]):
                continue
            r = (nu - n0) / (n1 - n0)
            found.append(
                tuple(float(a[i] + r * (a[i + 1] - a[i])) for a in (b.amplitude, b.max_force, b.period))
            )
    return found


def pure_slip_orbits_at(
    diagram: RegimeDiagram | tuple[DimensionlessLaw, Sequence[Branch]],
    nu: float,
    *,
    stable_only: bool = False,
) -> list[PeriodicOrbit]:
    """Solve, by shooting, every pure-slip orbit of ``diagram`` at ``nu`` (stable ones only on request).

    The continued branches give the guesses, so unstable orbits are found too;
    each orbit is solved at this very ``nu``, and one orbit reached from two
    branch segments is returned once. ``diagram`` may also be ``(law, branches)``.
    """
    law, branches = (diagram.law, diagram.branches) if isinstance(diagram, RegimeDiagram) else diagram
    params = DimensionlessParameters(nu=nu, law=law)
    out: list[PeriodicOrbit] = []
    for _amp, s0, period in _orbits_at(branches, nu, stable_only=stable_only):
        try:
            o = pure_slip_orbit(params, guess=(s0, period))
        except RuntimeError:
            continue
        if stable_only and not o.stable:
            continue
        key = OrbitKey(Regime.PURE_SLIP, o.s0, o.period)
        if not any(same_orbit(key, OrbitKey(Regime.PURE_SLIP, q.s0, q.period)) for q in out):
            out.append(o)
    return out


def identify(law: DimensionlessLaw, nu: float, rows: AttractorRows) -> list[OrbitKey | None]:
    """Polish the attractors in engine rows at ``nu``; return their keys (None where unresolved)."""
    polished, _ = polish_rows(law, np.full(len(rows), nu), rows)
    return [orbit_key(polished[i]) for i in range(len(polished))]


#: spring force above steady sliding of the probes that look for attractors besides the one
#: reached from rest: near steady sliding, and a large push
PROBE_PUSHES = (1e-3, 2.0)
#: interval ends closer than this (relative) are one point
CUT_RTOL = 1e-7


def _probe_rows(law: DimensionlessLaw, nu: np.ndarray, pushes: Sequence[float]) -> tuple[AttractorRows, ...]:
    """Engine rows from ``(f(nu) + push, nu)``, polished: one set of rows (one per ``nu``) per push."""
    f_nu = np.asarray(law.forward(nu), dtype=float)
    nus = np.repeat(nu, len(pushes))
    s0 = (f_nu[:, None] + np.asarray(pushes, dtype=float)[None, :]).ravel()
    rows = _engine(law, nus, s0)
    polished, _ = polish_rows(law, nus, rows)
    k = len(pushes)
    return tuple(polished[np.arange(nu.size) * k + i] for i in range(k))


def _attractor_sets(
    law: DimensionlessLaw,
    nu: np.ndarray,
    branches: Sequence[Branch],
    rest: AttractorRows | None = None,
    probes: tuple[AttractorRows, ...] | None = None,
) -> list[tuple[Regime, ...]]:
    """Names of the distinct attractors at each ``nu`` (one entry per distinct orbit), in a fixed order.

    The engine from rest and from the :data:`PROBE_PUSHES` (every non-sticking
    attractor polished into its orbit), every stable pure-slip orbit of the
    continued branches solved at this ``nu``, and steady sliding where it is
    stable; an attractor found twice counts once. The set is ``("unknown",)``
    where the motion from rest could not be followed; a probe that did not
    settle is left out (it shows nothing). ``rest`` and ``probes`` are the
    polished rows from breakaway and from the probes at ``nu`` when already computed.
    """
    if rest is None:
        rest, _ = polish_rows(law, nu, _stick_slip_rows(law, nu))
    if probes is None:
        probes = _probe_rows(law, nu, PROBE_PUSHES)
    fp = np.asarray(law.forward(nu, 1), dtype=float)
    out: list[tuple[Regime, ...]] = []
    for j, v in enumerate(nu):
        key = orbit_key(rest[j])
        if key is None:
            out.append((Regime.UNKNOWN,))  # the engine could not follow (or polish) the motion from rest
            continue
        # a probe that did not settle (near a Hopf point it crawls) tells nothing; the probe next
        # to steady sliding is asked only where steady sliding is unstable
        found = [key]
        for push, pr in zip(PROBE_PUSHES, probes, strict=True):
            k = orbit_key(pr[j])
            if k is not None and (push >= 1.0 or fp[j] < 0):
                found.append(k)
        found += [
            OrbitKey(Regime.PURE_SLIP, o.s0, o.period)
            for o in pure_slip_orbits_at((law, branches), float(v), stable_only=True)
        ]
        if fp[j] > 0:
            found.append(OrbitKey(Regime.STEADY_SLIDING))
        out.append(_names(distinct(found)))
    return out


def _locate_boundary(
    law: DimensionlessLaw,
    branches: Sequence[Branch],
    lo: float,
    hi: float,
    set_lo: tuple[Regime, ...],
    set_hi: tuple[Regime, ...],
) -> SpecialPoint:
    """Bisect ``[lo, hi]`` for where the attractor set changes from ``set_lo`` to ``set_hi``.

    Right at such a boundary (a fold of cycles, say) transients crawl and the
    motion from rest may not settle: the bisection then stops, and the detail
    says how well the point is located.
    """
    crawl = False
    while hi - lo > 1e-9 * hi:
        mid = 0.5 * (lo + hi)
        s_mid = _attractor_sets(law, np.array([mid]), branches)[0]
        if s_mid == set_lo:
            lo = mid
        elif s_mid == set_hi:
            hi = mid
        elif s_mid == (Regime.UNKNOWN,):
            crawl = True
            break
        else:  # a third set in between: keep the side that still differs from set_lo
            hi, set_hi = mid, s_mid
    gone = [str(r) for r in sorted((Counter(set_lo) - Counter(set_hi)).elements())] or ["-"]
    new = [str(r) for r in sorted((Counter(set_hi) - Counter(set_lo)).elements())] or ["-"]
    where = f"; located to +-{0.5 * (hi - lo):.2g} (transients crawl there)" if crawl else ""
    return SpecialPoint(
        "attractor-boundary",
        0.5 * (lo + hi),
        math.nan,
        f"attractors {' + '.join(set_lo)} below, {' + '.join(set_hi)} above "
        f"(lost: {', '.join(gone)}; gained: {', '.join(new)}){where}",
    )


_ORDER = (Regime.STICK_SLIP, Regime.SLIP_REVERSAL, Regime.PURE_SLIP, Regime.STEADY_SLIDING, Regime.UNKNOWN)


def _names(keys: Sequence[OrbitKey]) -> tuple[Regime, ...]:
    return tuple(sorted((k.kind for k in keys), key=_ORDER.index))


@dataclass(frozen=True)
class Confirmation:
    """Direct simulations of one interval, from several starts.

    Attributes
    ----------
    interval : Interval
        The interval checked.
    nu : float
        Where it was checked (its midpoint, geometric for wide intervals).
    expected : tuple of str
        Attractors the continuation predicts there, one entry per distinct orbit, sorted.
    found : tuple of str
        Distinct attractors the engine reached, one entry per distinct orbit
        (each non-sticking one polished into its periodic orbit first), sorted.
    pure_slip_amplitude_error : float
        Largest relative difference between a pure-slip attractor reached and the
        continued stable orbit solved at ``nu`` (NaN when none).
    agree : bool
        As many distinct attractors of each kind as expected, and the pure-slip
        amplitudes within ``1e-6``.
    inconclusive : int
        Starts (other than rest) whose motion did not settle within the time
        allowed (near a Hopf point transients crawl): they count for nothing.

    """

    interval: Interval
    nu: float
    expected: tuple[str, ...]
    found: tuple[str, ...]
    pure_slip_amplitude_error: float
    agree: bool
    inconclusive: int = 0


def confirm(diagram: RegimeDiagram) -> list[Confirmation]:
    """Check every interval of ``diagram`` by direct simulation from several initial states.

    Starts: rest (breakaway), pushes of ``1e-3``, ``0.3``, ``2`` and ``6`` off
    steady sliding (spring force ``f(nu) + push``), and each continued pure-slip
    orbit at that ``nu`` (stable or not) scaled by 0.9 and 1.1 (inside and
    outside it).
    Each is followed by the exact engine until it sticks periodically, converges
    to an oscillation or settles on steady sliding; each oscillation reached is
    polished into its periodic orbit, and the distinct orbits are counted.
    """
    if not isinstance(diagram, RegimeDiagram):
        raise TypeError(f"diagram={diagram!r}: expected the RegimeDiagram of regimes(...)")
    law = diagram.law
    out = []
    for iv in diagram.intervals:
        nu = _midpoint(iv.nu_min, iv.nu_max)
        f_nu = law.at(nu)
        amps = [o.amplitude for o in pure_slip_orbits_at(diagram, nu)]
        pushes = [1e-3, 0.3, 2.0, 6.0] + [k * a / 2 for a in amps for k in (0.9, 1.1)]
        s0 = np.array([f_nu + p for p in pushes])
        rows = AttractorRows.concat(
            [
                _stick_slip_rows(law, np.array([nu])),
                _engine(law, np.full(s0.size, nu), s0, conv_tol=1e-10),
            ]
        )
        polished, _ = polish_rows(law, np.full(len(rows), nu), rows)
        keys = [orbit_key(polished[i]) for i in range(len(polished))]
        found_keys = distinct([k for k in keys if k is not None])
        # the motion from rest must be resolved; another start that did not settle is inconclusive
        found = tuple(sorted([k.kind for k in found_keys] + ([Regime.UNKNOWN] if keys[0] is None else [])))
        inconclusive = sum(k is None for k in keys[1:])
        stable = pure_slip_orbits_at(diagram, nu, stable_only=True)
        err = math.nan
        for amp, k in zip(polished.amplitude, keys, strict=True):
            if k is not None and k.kind == Regime.PURE_SLIP and stable:
                e = min(abs(amp - o.amplitude) / o.amplitude for o in stable)
                err = e if math.isnan(err) else max(err, e)
        expected = tuple(sorted(iv.attractors))
        agree = found == expected and not (err > 1e-6)
        out.append(Confirmation(iv, nu, expected, found, err, agree, inconclusive))
    return out
