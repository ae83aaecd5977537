"""Two-parameter bifurcation diagrams: the curves continued, their codimension-2 points, the regions.

:func:`two_parameter_diagram` finds, in a :class:`~.planes.Plane`,

1. the Hopf curves of steady sliding (``f'(nu) = 0``), seeded where the sign of ``f'``
   changes along lines of the plane in both directions, and continued by pseudo-arclength
   (:func:`~.arclength.trace`), watching ``f'''`` for Bautin points;
2. along each seed line of constant ``y``, the pure-slip orbits born at each Hopf point,
   continued until they graze (``w_min = 0``) or leave the plane: their folds of cycles and
   grazings seed
3. the fold-of-cycles curves (shooting plus ``ln m = 0``), which end where their orbit
   touches ``w = 0`` (fold-grazing) or shrinks into a Bautin point, watching the return
   map's curvature ``P''(A)`` for cusps (two folds meet, three cycles merge), and
4. the grazing curves (the slip from breakaway returns tangentially to ``w = 0``: the
   stick-slip orbit's birth or death), watching the grazing orbit's multiplier for the
   fold-grazing point, seeded also where the engine's slip from breakaway starts or stops
   stopping on a seed line;
5. the slip-reversal curves (the cycle's backward slip ends exactly at breakaway: no stick
   is left), seeded where the engine's motion from breakaway turns into an oscillation
   that slips backward and never sticks;

and labels the regions between the curves: a raster of the plane is cut along the
curves into connected regions, and each region is named by the attractors at its point
farthest from every curve and at four more of its cells, from the exact engine's runs
from rest and from two pushes off steady sliding (the probes of the one-parameter
analysis) and the sign of ``f'``. A region whose cells disagree is named
``undetermined: ...`` with both sets, and a note says a boundary that is not continued
(slip reversal) crosses it: the diagram does not guess.

The Hopf curve of one block meets a grazing curve only in the limit ``nu -> 0``: the orbit
born at a Hopf point has amplitude 0 about ``w = nu``, and a grazing orbit reaches from
``w = 0`` through ``w = nu``, so its velocity spans at least ``nu``; no orbit is both at
``nu > 0``. A Hopf curve that runs to the plane's lowest ``nu`` ends there on the edge. Two
curves of different orbits may still cross in the plane (a stick-slip onset and a Hopf
curve, four regions meeting); such a crossing is drawn, not located as a point.
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import defaults
from ..core.api import run_attractors
from ..core.results import Regime
from ..io.jsonable import json_clean
from .arclength import TracedCurve, newton, trace
from .branches import interval_regime
from .curves import OneBlockSystems
from .planes import Axes, Plane, check_positive_int

__all__ = ["Curve", "Diagram", "SpecialPoint2", "two_parameter_diagram"]

#: kinds of curve, in drawing order
CURVE_KINDS = ("hopf", "fold", "grazing", "reversal")
#: kinds of codimension-2 point and end
POINT_KINDS = ("bautin", "fold-grazing", "cusp", "end")
#: the smallest amplitude of a fold orbit followed (a fold curve shrinking into a Bautin point)
FOLD_MIN_AMPLITUDE = 2e-3
#: a seed closer than this (unit square) to a curve already traced is on it
SAME_CURVE = 2e-3


@dataclass(frozen=True)
class Curve:
    """One continued curve of the plane.

    Attributes
    ----------
    kind : str
        ``hopf``, ``fold`` or ``grazing``.
    x, y : ndarray
        The curve in axis units.
    u : ndarray, shape (n, 2)
        The curve in the unit square.
    data : dict of ndarray
        Along the curve: ``nu``; for Hopf ``f3`` (``f'''``, sign of the criticality); for a
        fold or a grazing orbit ``period``, ``amplitude`` (fold) and ``log_multiplier``.
    ends : (str, str)
        Why each end stopped (:class:`~.arclength.TracedCurve`).

    """

    kind: str
    x: np.ndarray
    y: np.ndarray
    u: np.ndarray
    data: dict[str, np.ndarray]
    ends: tuple[str, str]

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready dictionary."""
        return {
            "kind": self.kind,
            "ends": list(self.ends),
            "x": json_clean(self.x.tolist()),
            "y": json_clean(self.y.tolist()),
            **{k: json_clean(np.asarray(v).tolist()) for k, v in self.data.items()},
        }


@dataclass(frozen=True)
class SpecialPoint2:
    """A codimension-2 point (or the end of a curve inside the plane).

    Attributes
    ----------
    kind : str
        ``bautin``, ``fold-grazing``, ``cusp`` or ``end``.
    x, y, nu : float
        Where (axis units, and the driving velocity).
    coefficient : str
        What decides its type, and its value (e.g. ``f5 = 4.8`` for a Bautin point: the
        quintic coefficient ``-f^(5)/384`` of the amplitude equation is negative, the
        cycles born subcritically fold back into a stable one).
    value : float
        That coefficient.
    detail : str
        In words.

    """

    kind: str
    x: float
    y: float
    nu: float
    coefficient: str
    value: float
    detail: str


@dataclass(frozen=True)
class Diagram:
    """A two-parameter diagram: curves, codimension-2 points and labelled regions.

    Attributes
    ----------
    plane : Axes
        The :class:`~.planes.Plane` of a one-block diagram (its model at each point), or bare
        :class:`~.planes.Axes` (the inertial rate-and-state slider's diagram).
    curves : list of Curve
    points : list of SpecialPoint2
    region : ndarray of int, shape (ny, nx)
        Region index of each raster cell (-1 on a curve).
    region_names : list of str
        The attractors of each region, e.g. ``stick-slip + steady-sliding``.
    region_regime : list of str
        The regime of each region (``bistable`` for two attractors).
    raster_x, raster_y : ndarray
        Cell centres (axis units).
    notes : list of str

    """

    plane: Axes
    curves: list[Curve]
    points: list[SpecialPoint2]
    region: np.ndarray
    region_names: list[str]
    region_regime: list[str]
    raster_x: np.ndarray
    raster_y: np.ndarray
    notes: list[str] = field(default_factory=list)

    def curves_of(self, kind: str) -> list[Curve]:
        """Return the curves of one kind."""
        return [c for c in self.curves if c.kind == kind]

    def points_of(self, kind: str) -> list[SpecialPoint2]:
        """Return the special points of one kind."""
        return [p for p in self.points if p.kind == kind]

    def regime_at(self, x: float, y: float) -> str:
        """Return the regime of the region that holds ``(x, y)`` (axis units); ``curve`` on a curve."""
        i = int(np.argmin(np.abs(self.raster_y - y)))
        j = int(np.argmin(np.abs(self.raster_x - x)))
        r = int(self.region[i, j])
        return "curve" if r < 0 else self.region_names[r]

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready dictionary (the curves, the points and the regions' names)."""
        return {
            "plane": {
                "describe": self.plane.describe,
                "x": {
                    "name": self.plane.x.name,
                    "lo": self.plane.x.lo,
                    "hi": self.plane.x.hi,
                    "unit": self.plane.x.unit,
                    "log": self.plane.x.log,
                },
                "y": {
                    "name": self.plane.y.name,
                    "lo": self.plane.y.lo,
                    "hi": self.plane.y.hi,
                    "unit": self.plane.y.unit,
                    "log": self.plane.y.log,
                },
            },
            "curves": [c.as_dict() for c in self.curves],
            "points": [json_clean(p.__dict__) for p in self.points],
            "regions": [
                {"attractors": n, "regime": r}
                for n, r in zip(self.region_names, self.region_regime, strict=True)
            ],
            "notes": list(self.notes),
        }

    def to_json(self) -> str:
        """Return the diagram as JSON text."""
        return json.dumps(self.as_dict(), indent=1)


def _box(u: np.ndarray) -> float:
    return float(min(u[0], 1.0 - u[0], u[1], 1.0 - u[1]))


def _near(curves: list[Curve], kind: str, u: np.ndarray, tol: float = SAME_CURVE) -> bool:
    """Whether ``u`` lies within ``tol`` of a traced curve of ``kind`` (distance to its segments)."""
    for c in curves:
        if c.kind != kind or len(c.u) == 0:
            continue
        a, b = c.u[:-1], c.u[1:]
        d = b - a
        t = np.clip(np.einsum("ij,ij->i", u - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
        if len(a) and float(np.min(np.linalg.norm(a + t[:, None] * d - u, axis=1))) < tol:
            return True
        if len(c.u) == 1 and float(np.linalg.norm(c.u[0] - u)) < tol:
            return True
    return False


def _scan(fun: Callable[[float], float], n: int) -> list[float]:
    """Roots of ``fun`` on ``[0, 1]``: sign changes on ``n`` points, refined by Brent."""
    from scipy.optimize import brentq

    grid = np.linspace(0.0, 1.0, n)
    vals = np.array([_safe(fun, g) for g in grid])
    roots = []
    for i in range(n - 1):
        a, b = vals[i], vals[i + 1]
        if math.isfinite(a) and math.isfinite(b) and a * b < 0:
            roots.append(float(brentq(fun, grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15)))
    return roots


#: a located zero of a test is kept where the test, re-read at the curve's points on either side
#: of it converged this much tighter than the continuation's tolerance, still changes sign, and
#: exceeds there NOISE_MARGIN times the change that the tighter solve made in it
CONFIRM_TIGHTER = 1e-3
NOISE_MARGIN = 10.0


def _confirmed(
    fun: Callable[[np.ndarray], np.ndarray],
    test: Callable[[np.ndarray], float],
    tc: TracedCurve,
    index: int,
    tol: float,
) -> bool:
    """Whether ``test`` changes sign across the event at ``tc.x[index]``, beyond its noise.

    The continuation's points solve the defining system to ``tol``; where the test is
    ill-conditioned in them (the grazing orbit's ``ln m`` near ``nu = 0`` is ``0.6 nu^2`` and
    moves by ``1e-6`` for a ``1e-10`` residual) a sign change can be noise. Each neighbour is
    solved again to ``CONFIRM_TIGHTER tol``, the coordinate that changes most between them
    held; the change that made in the test is its noise. The zero is kept where the test's
    signs still differ and both values exceed ``NOISE_MARGIN`` times the larger noise.
    """
    lo, hi = index - 1, index + 1
    if lo < 0 or hi >= len(tc.x):
        return True
    xa, xb = tc.x[lo], tc.x[hi]
    k = int(np.argmax(np.abs(xb - xa)))
    values, noise = [], 0.0
    for x in (xa, xb):
        free = [i for i in range(x.size) if i != k]

        def square(q: np.ndarray, x: np.ndarray = x, free: list[int] = free) -> np.ndarray:
            full = x.copy()
            full[free] = q
            return fun(full)

        res = newton(square, x[free].copy(), tol=tol * CONFIRM_TIGHTER)
        if res is None:
            return True  # no tighter point: the event as the continuation located it
        full = x.copy()
        full[free] = res[0]
        try:
            v, v0 = float(test(full)), float(test(x))
        except (ValueError, RuntimeError, ZeroDivisionError, OverflowError):
            return True
        if not (math.isfinite(v) and math.isfinite(v0)):
            return True
        values.append(v)
        noise = max(noise, abs(v - v0))
    return values[0] * values[1] < 0 and min(abs(v) for v in values) > NOISE_MARGIN * noise


def _safe(fun: Callable[[float], float], x: float) -> float:
    try:
        return float(fun(x))
    except (ValueError, RuntimeError, ZeroDivisionError, OverflowError):
        return math.nan


def two_parameter_diagram(
    plane: Plane,
    *,
    seed_lines: int = 5,
    scan_points: int = 200,
    step: float = 0.02,
    raster: int = 120,
    tol: float = 1e-10,
    label: bool = True,
) -> Diagram:
    """Continue the bifurcation curves of ``plane``, locate the codimension-2 points, label the regions.

    Parameters
    ----------
    plane : Plane
        The plane (:meth:`Plane.dimensionless` or :meth:`Plane.physical`).
    seed_lines : int, optional
        Lines of constant ``y`` (and, for the Hopf curves, of constant ``x``) on which the
        curves are seeded; a curve that crosses none of them is not found.
    scan_points : int, optional
        Points of each seed line where the sign of ``f'`` is read.
    step : float, optional
        Largest continuation step (fraction of the plane).
    raster : int, optional
        Cells per axis of the region raster.
    tol : float, optional
        Newton tolerance of the defining systems.
    label : bool, optional
        Label the regions (runs the engine once per region); else ``region`` is all -1.

    Returns
    -------
    Diagram

    """
    if not isinstance(plane, Plane):
        from ..errors import ArgumentTypeError

        raise ArgumentTypeError(f"plane={plane!r}: expected a Plane (Plane.dimensionless or Plane.physical)")
    seed_lines = check_positive_int(seed_lines, "seed_lines", 1, 200)
    scan_points = check_positive_int(scan_points, "scan_points", 10, 100_000)
    raster = check_positive_int(raster, "raster", 10, 2000)
    sysm = OneBlockSystems(plane, rtol=tol * 1e-2)
    curves: list[Curve] = []
    points: list[SpecialPoint2] = []
    notes: list[str] = []
    lines = np.linspace(0.0, 1.0, seed_lines) if seed_lines > 1 else np.array([0.5])

    # 1. Hopf curves, seeded on lines of constant y and of constant x; 2. the pure-slip
    # branches on the lines of constant y seed the fold and grazing curves (3., 4.); a
    # codimension-2 point found on the way adds lines next to it (a fold curve between a
    # Bautin and a fold-grazing point can be shorter than the lines' spacing)
    f0_one = abs(plane.at((0.5, 0.5)).f(0.0) - 1.0) < 1e-12
    for c in lines:
        for r in _scan(functools.partial(_hopf_on_column, sysm, float(c)), scan_points):
            _hopf_curve(sysm, np.array([c, r]), curves, points, step, tol)
    queue = [float(c) for c in lines]
    done: set[float] = set()
    while queue:
        u2 = queue.pop(0)
        if u2 in done or not 0.0 <= u2 <= 1.0:
            continue
        done.add(u2)
        n_points = len(points)
        for u1 in _scan(functools.partial(_hopf_on_row, sysm, u2), scan_points):
            _hopf_curve(sysm, np.array([u1, u2]), curves, points, step, tol)
            fold_seeds, graze_seeds = _line_seeds(sysm, u1, u2, step, tol, notes, f0_one)
            for z in fold_seeds:
                if not _near(curves, "fold", z[2:4]):
                    _fold_curve(sysm, z, curves, points, step, tol)
            for z in graze_seeds:
                if not _near(curves, "grazing", z[1:3]):
                    _grazing_curve(sysm, z, curves, points, step, tol, notes)
        for p in points[n_points:]:
            if p.kind in ("bautin", "fold-grazing"):
                v = float(plane.y.from_value(p.y))
                queue += [v + d for d in (-0.03, -0.01, 0.01, 0.03)]
    # 5. the stick-slip onset seen by the engine on the seed lines (the slip from breakaway stops
    # on one side, not on the other) where no grazing curve traced so far passes: an onset that no
    # Hopf-born pure-slip branch reaches, or any onset of a law whose f(0+) is not 1
    for u2 in lines:
        onsets, reversals = _line_changes(sysm, float(u2))
        for z in onsets:
            if not _near(curves, "grazing", z[1:3], tol=0.02):
                _grazing_curve(sysm, z, curves, points, step, tol, notes, periodic=f0_one)
        for u1 in reversals:
            rz = _reversal_seed(sysm, u1, float(u2), curves)
            if rz is not None:
                _reversal_curve(sysm, rz, curves, step, tol)
    if not f0_one:
        notes.append(
            "f(0+) differs from the static threshold: no pure-slip orbit grazes into stick-slip; the "
            "grazing curves are the onset of stick-slip (the slip from breakaway touches w = 0)"
        )

    _hopf_meets_grazing(sysm, curves, points)

    rx = np.linspace(0.5 / raster, 1 - 0.5 / raster, raster)
    region, names, regimes = _regions(sysm, curves, rx, label, notes)
    xs, ys = plane.values(np.stack([rx, rx], axis=-1))
    return Diagram(plane, curves, points, region, names, regimes, np.asarray(xs), np.asarray(ys), notes)


def _hopf_on_row(sysm: OneBlockSystems, u2: float, u1: float) -> float:
    return float(sysm.hopf(np.array([u1, u2]))[0])


def _hopf_on_column(sysm: OneBlockSystems, u1: float, u2: float) -> float:
    return float(sysm.hopf(np.array([u1, u2]))[0])


def _at_amplitude(g: Callable[[np.ndarray], np.ndarray], a0: float, z: np.ndarray) -> np.ndarray:
    return g(np.array([a0, z[0], z[1]]))


def _where(plane: Plane, u: tuple[float, float] | np.ndarray) -> str:
    x, y = plane.x.to_unit(float(u[0])), plane.y.to_unit(float(u[1]))
    return f"({plane.x.name} = {x:.6g}, {plane.y.name} = {y:.6g})"


def _curve(
    plane: Plane,
    kind: str,
    tc: TracedCurve,
    u: np.ndarray,
    data: dict[str, np.ndarray],
    ends: tuple[str, str] | None = None,
) -> Curve:
    xs, ys = plane.values(u)
    return Curve(kind, np.asarray(xs), np.asarray(ys), u, data, ends or tc.end)


def _hopf_curve(
    sysm: OneBlockSystems,
    seed: np.ndarray,
    curves: list[Curve],
    points: list[SpecialPoint2],
    step: float,
    tol: float,
) -> None:
    if _near(curves, "hopf", seed):
        return
    plane = sysm.plane
    tc = trace(sysm.hopf, seed, tests=sysm.hopf_tests(), inside=_box, h0=step / 4, h_max=step, tol=tol * 1e-2)
    u = tc.x
    nu = np.array([sysm.point(p).nu for p in u])
    curves.append(_curve(plane, "hopf", tc, u, {"nu": nu, "f3": tc.tests["bautin"]}))
    for e in tc.events:
        if e.name != "bautin":
            continue
        p = sysm.point(e.x)
        f5 = p.f(p.nu, 5)
        c5 = -f5 / 384.0
        kind = "stable" if c5 < 0 else "unstable"
        x, y = plane.values(e.x)
        points.append(
            SpecialPoint2(
                "bautin",
                float(x),
                float(y),
                p.nu,
                "quintic coefficient -f5/384",
                c5,
                f"Bautin (generalized Hopf): l1 = -f'''/16 changes sign; the cycles born on the subcritical "
                f"side fold into a {kind} large cycle (f^(5) = {f5:.6g})",
            )
        )


def _line_seeds(
    sysm: OneBlockSystems, u1: float, u2: float, step: float, tol: float, notes: list[str], f0_one: bool
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Return the folds and grazings of the pure-slip orbits born at the Hopf point ``(u1, u2)``."""
    pt = sysm.point(np.array([u1, u2]))
    if pt.f(pt.nu, 3) == 0.0:
        return [], []
    br = _branch(sysm, u1, u2, step, tol)
    if br is None:
        notes.append(
            f"the pure-slip orbits born at the Hopf point {_where(sysm.plane, (u1, u2))} "
            "could not be followed"
        )
        return [], []
    # a fold whose orbit reaches w <= 0 is not a pure-slip orbit's (the branch grazed first)
    folds = [
        np.array([e.x[0], e.x[1], e.x[2], u2])
        for e in br.events
        if e.name == "fold" and e.values.get("graze", 1.0) > 0
    ]
    grazes = [np.array([e.x[1], e.x[2], u2]) for e in br.events if e.name == "graze" and f0_one]
    return folds, grazes


def _branch(sysm: OneBlockSystems, u1: float, u2: float, step: float, tol: float) -> TracedCurve | None:
    """Return the pure-slip orbits born at the Hopf point ``(u1, u2)``, traced along ``y = u2``."""
    p = sysm.point(np.array([u1, u2]))
    a0 = 1e-2 * max(min(p.nu, 1.0), 0.02)
    g = sysm.branch(u2)
    sysm.reverse = False
    res = None
    for _ in range(3):
        res = newton(functools.partial(_at_amplitude, g, a0), np.array([1.0, u1]), tol=tol)
        if res is not None:
            break
        a0 *= 0.3
    if res is None:
        return None
    z0 = np.array([a0, res[0][0], res[0][1]])
    sysm.reverse = sysm._orbit(a0, z0[1], np.array([z0[2], u2]))["log_multiplier"] > 0

    def inside(z: np.ndarray) -> float:
        return float(min(z[2], 1.0 - z[2], z[0], 50.0 - z[1]))

    return trace(
        g,
        z0,
        np.array([1.0, 0.0, 0.0]),
        tests=sysm.branch_tests(u2),
        stops=("graze",),
        inside=inside,
        h0=a0,
        h_max=step * 2,
        tol=tol,
        both=False,
        max_points=600,
    )


def _fold_curve(
    sysm: OneBlockSystems,
    z: np.ndarray,
    curves: list[Curve],
    points: list[SpecialPoint2],
    step: float,
    tol: float,
) -> None:
    plane = sysm.plane
    sysm.reverse = False

    def inside(q: np.ndarray) -> float:
        return float(min(_box(q[2:4]), q[0] - FOLD_MIN_AMPLITUDE, 50.0 - q[1]))

    fold_tests = sysm.fold_tests()
    tc = trace(
        sysm.fold,
        z,
        tests=fold_tests,
        stops=("graze",),
        inside=inside,
        h0=step / 4,
        h_max=step,
        tol=tol,
    )
    u = tc.x[:, 2:4]
    meas = [sysm._orbit(float(q[0]), float(q[1]), q[2:4]) for q in tc.x]
    shrinks = [
        end == "edge" and q[0] <= FOLD_MIN_AMPLITUDE * 1.01 and _box(q[2:4]) > 1e-6
        for end, q in zip(tc.end, (tc.x[0], tc.x[-1]), strict=True)
    ]
    ends = (
        "bautin" if shrinks[0] else tc.end[0],
        "bautin" if shrinks[1] else tc.end[1],
    )
    curves.append(
        _curve(
            plane,
            "fold",
            tc,
            u,
            {
                "nu": np.array([m["nu"] for m in meas]),
                "amplitude": np.array([m["amplitude"] for m in meas]),
                "period": 2 * math.pi * tc.x[:, 1],
                "min_velocity": tc.tests["graze"],
            },
            ends,
        )
    )
    for e in tc.events:
        if e.name == "graze":
            x, y = plane.values(e.x[2:4])
            m = sysm._orbit(float(e.x[0]), float(e.x[1]), e.x[2:4])
            points.append(
                SpecialPoint2(
                    "fold-grazing",
                    float(x),
                    float(y),
                    m["nu"],
                    "min velocity of the fold orbit",
                    e.values["graze"],
                    "the fold-of-cycles orbit touches zero velocity: "
                    "the fold curve ends on the grazing curve",
                )
            )
        elif e.name == "cusp" and _confirmed(sysm.fold, fold_tests["cusp"], tc, e.index, tol):
            x, y = plane.values(e.x[2:4])
            points.append(
                SpecialPoint2(
                    "cusp",
                    float(x),
                    float(y),
                    sysm.point(e.x[2:4]).nu,
                    "P''(A), the return map's curvature at the fold",
                    e.values["cusp"],
                    "cusp of the fold-of-cycles curve: two folds meet and three pure-slip orbits "
                    f"merge into one (amplitude {e.x[0]:.6g})",
                )
            )
    for shrink, q in zip(shrinks, (tc.x[0], tc.x[-1]), strict=True):
        if shrink:
            x, y = plane.values(q[2:4])
            points.append(
                SpecialPoint2(
                    "end",
                    float(x),
                    float(y),
                    sysm.point(q[2:4]).nu,
                    "spring-force maximum above f(nu)",
                    float(q[0]),
                    "the fold orbit shrinks to zero amplitude (followed down to this size): "
                    "the fold curve ends at a Bautin point",
                )
            )


#: points of a seed line where the engine runs from breakaway, and of the refinement of a change
ONSET_SCAN = 61
ONSET_REFINE = 41


def _breakaway_rows(sysm: OneBlockSystems, u: np.ndarray) -> Any:
    """Run the engine from breakaway at the plane points ``u`` (shape (n, 2)) in one batched call."""
    pts = [sysm.point(q) for q in u]
    lp = np.array([p.lp() for p in pts])
    return run_attractors(
        sysm.kernel, lp, np.array([p.nu for p in pts]), from_breakaway=True, rtol=defaults.RTOL,
        atol=defaults.ATOL, max_slip_time=defaults.MAX_SLIP_TIME, conv_tol=defaults.CONV_TOL,
    )  # fmt: skip


def _is_reversal(rows: Any) -> np.ndarray:
    return np.asarray(rows.ok & (rows.regime == Regime.PURE_SLIP.code) & (rows.n_backward > 0))


def _line_changes(sysm: OneBlockSystems, u2: float) -> tuple[list[np.ndarray], list[float]]:
    """Where the engine's motion from breakaway changes on ``y = u2``: onsets and reversals.

    The engine runs at :data:`ONSET_SCAN` points of the line; where "the slip stops" or
    "it slips backward and never sticks" changes, :data:`ONSET_REFINE` more points across the
    step narrow it to ``1/2400`` of the axis, enough for Newton on the defining system.
    Returns the stick-slip onsets as ``(tau, u1, u2)`` seeds of the grazing system (the
    slip's duration on the stick-slip side, over ``2 pi``) and the reversals as ``u1``.
    """
    grid = np.linspace(0.0, 1.0, ONSET_SCAN)
    try:
        rows = _breakaway_rows(sysm, np.stack([grid, np.full_like(grid, u2)], axis=-1))
    except (ValueError, RuntimeError):
        return [], []
    onsets: list[np.ndarray] = []
    reversals: list[float] = []
    flags = {"onset": rows.is_regime(Regime.STICK_SLIP), "reversal": _is_reversal(rows)}
    for name, flag in flags.items():
        for i in np.flatnonzero(flag[:-1] != flag[1:]):
            fine = np.linspace(grid[i], grid[i + 1], ONSET_REFINE)
            r2 = _breakaway_rows(sysm, np.stack([fine, np.full_like(fine, u2)], axis=-1))
            f2 = r2.is_regime(Regime.STICK_SLIP) if name == "onset" else _is_reversal(r2)
            j = int(np.flatnonzero(f2 != f2[0])[0]) if np.any(f2 != f2[0]) else 1
            if name == "reversal":
                reversals.append(float(0.5 * (fine[j - 1] + fine[j])))
                continue
            k = j - 1 if f2[0] else j  # the stick-slip side
            slip = float(r2.period[k] - r2.stick_time[k])
            if math.isfinite(slip) and slip > 0:
                onsets.append(np.array([slip / (2.0 * math.pi), float(fine[k]), u2]))
    return onsets, reversals


def _reversal_seed(sysm: OneBlockSystems, u1: float, u2: float, curves: list[Curve]) -> np.ndarray | None:
    """Return ``(tau1, tau2, u1, u2)`` of the reversal system at ``(u1, u2)`` (None on a curve or without)."""
    if _near(curves, "reversal", np.array([u1, u2]), tol=0.02):
        return None
    u = np.array([u1, u2])
    first = sysm.first_stop(u, 1.0)
    if first is None or first[1] >= -1.0:
        return None
    second = sysm.first_stop(u, -first[1], backward=True)
    if second is None:
        return None
    return np.array([first[0] / (2 * math.pi), second[0] / (2 * math.pi), u1, u2])


def _reversal_curve(
    sysm: OneBlockSystems, z: np.ndarray, curves: list[Curve], step: float, tol: float
) -> None:
    plane = sysm.plane
    u2 = float(z[3])
    res = newton(lambda q: sysm.reversal(np.array([q[0], q[1], q[2], u2])), z[:3].copy(), tol=tol)
    if res is None:
        return
    z0 = np.array([*res[0], u2])

    def inside(q: np.ndarray) -> float:
        return float(min(_box(q[2:4]), q[0], q[1], 50.0 - q[0]))

    tc = trace(sysm.reversal, z0, inside=inside, h0=step / 4, h_max=step, tol=tol)
    u = tc.x[:, 2:4]
    curves.append(
        _curve(
            plane,
            "reversal",
            tc,
            u,
            {
                "nu": np.array([sysm.point(q).nu for q in u]),
                "forward_slip_time": 2 * math.pi * tc.x[:, 0],
                "backward_slip_time": 2 * math.pi * tc.x[:, 1],
            },
        )
    )


def _grazing_curve(
    sysm: OneBlockSystems,
    z: np.ndarray,
    curves: list[Curve],
    points: list[SpecialPoint2],
    step: float,
    tol: float,
    notes: list[str],
    *,
    periodic: bool = True,
) -> None:
    plane = sysm.plane
    u2 = float(z[2])
    g = sysm.grazing
    sysm.reverse = False
    res = newton(lambda q: g(np.array([q[0], q[1], u2])), z[:2].copy(), tol=tol)
    if res is None:
        return
    z0 = np.array([res[0][0], res[0][1], u2])
    if _near(curves, "grazing", z0[1:3]):  # a seed off the curve may converge onto one traced
        return
    sysm.reverse = sysm._touch(z0[0], z0[1:3])["log_multiplier"] > 1.0

    def inside(q: np.ndarray) -> float:
        return float(min(_box(q[1:3]), 50.0 - q[0], q[0]))

    tests = sysm.grazing_tests() if periodic else {}
    tc = trace(g, z0, tests=tests, inside=inside, h0=step / 4, h_max=step, tol=tol)
    u = tc.x[:, 1:3]
    curves.append(
        _curve(
            plane,
            "grazing",
            tc,
            u,
            {
                "nu": np.array([sysm.point(q).nu for q in u]),
                "period": 2 * math.pi * tc.x[:, 0],
                "log_multiplier": tc.tests["fold-grazing"] if periodic else np.full(len(u), math.nan),
            },
        )
    )
    for e in tc.events:
        if e.name == "fold-grazing" and not _confirmed(g, tests["fold-grazing"], tc, e.index, tol):
            notes.append(
                f"the grazing orbit's multiplier is within its noise of 1 near {_where(plane, e.x[1:3])}: "
                "no fold-grazing point is claimed there"
            )
        elif e.name == "fold-grazing":
            x, y = plane.values(e.x[1:3])
            points.append(
                SpecialPoint2(
                    "fold-grazing",
                    float(x),
                    float(y),
                    sysm.point(e.x[1:3]).nu,
                    "ln multiplier of the grazing orbit",
                    e.values["fold-grazing"],
                    "the grazing orbit changes stability: on one side a stable pure-slip orbit turns into "
                    "stick-slip, on the other an unstable one collides with the stick-slip orbit",
                )
            )


#: ends of a Hopf and a grazing curve this close (unit square) are one point
MEET = 1e-5


def _hopf_meets_grazing(sysm: OneBlockSystems, curves: list[Curve], points: list[SpecialPoint2]) -> None:
    """Add an end where a Hopf and a grazing curve run into each other (``nu -> 0``, module docstring)."""
    for h in curves:
        if h.kind != "hopf":
            continue
        for hu in (h.u[0], h.u[-1]):
            for c in curves:
                if c.kind != "grazing" or min(np.linalg.norm(c.u[[0, -1]] - hu, axis=1)) >= MEET:
                    continue
                x, y = sysm.plane.values(hu)
                nu = sysm.point(hu).nu
                points.append(
                    SpecialPoint2(
                        "end",
                        float(x),
                        float(y),
                        nu,
                        "nu",
                        nu,
                        "the Hopf and grazing curves run into each other: as nu -> 0 the orbit born at "
                        "the Hopf point and the grazing orbit shrink together to w = 0",
                    )
                )
                break


def _regions(
    sysm: OneBlockSystems, curves: list[Curve], rx: np.ndarray, label: bool, notes: list[str]
) -> tuple[np.ndarray, list[str], list[str]]:
    """Cut the raster along the curves; name each region by the attractors the engine finds in it."""
    from scipy import ndimage

    n = rx.size
    wall = np.zeros((n, n), dtype=bool)
    for c in curves:
        if len(c.u) < 2:
            continue
        seg_len = np.linalg.norm(np.diff(c.u, axis=0), axis=1)
        for a, b, ln in zip(c.u[:-1], c.u[1:], seg_len, strict=True):
            k = max(2, math.ceil(ln * n * 4))
            t = np.linspace(0.0, 1.0, k)
            pts = a[None, :] + t[:, None] * (b - a)[None, :]
            j = np.clip((pts[:, 0] * n).astype(int), 0, n - 1)
            i = np.clip((pts[:, 1] * n).astype(int), 0, n - 1)
            wall[i, j] = True
    # a curve sampled at four points per cell is an 8-connected wall, which the 4-connected
    # labelling below does not cross: a band one cell wide between two curves is a region
    lab, count = ndimage.label(~wall)
    region = lab - 1  # -1 on the walls
    names: list[str] = []
    regimes: list[str] = []
    if not label:
        return region, ["unlabelled"] * count, ["unknown"] * count
    dist = ndimage.distance_transform_edt(~wall)
    from .probes import _attractor_sets

    for r in range(count):
        cells = np.argwhere(region == r)
        d = dist[cells[:, 0], cells[:, 1]]
        # the innermost cell, and four more spread over the region at least two cells from a wall:
        # a region whose cells disagree holds a boundary that is not continued (slip reversal)
        inner = cells[d >= min(2.0, float(d.max()))]
        picks = [cells[int(np.argmax(d))]] + [
            inner[int(q * (len(inner) - 1))] for q in (0.1, 0.35, 0.65, 0.9)
        ]
        found = []
        for cell in picks:
            u = np.array([rx[cell[1]], rx[cell[0]]])
            nu, law = sysm.plane.law_at(u)
            found.append(_attractor_sets(law, np.array([nu]), [])[0])
        words = {" + ".join(str(a) for a in att) for att in found}
        if len(words) == 1:
            names.append(words.pop())
            regimes.append(str(interval_regime(found[0])))
        else:
            names.append("undetermined: " + " | ".join(sorted(words)))
            regimes.append(str(Regime.UNKNOWN))
            notes.append(
                f"region {r}: the engine finds different attractors in it ({' | '.join(sorted(words))}): "
                "a boundary that is not continued (slip reversal, or an attractor of its own) crosses it"
            )
    return region, names, regimes


REGIMES = tuple(str(r) for r in (Regime.STICK_SLIP, Regime.PURE_SLIP, Regime.STEADY_SLIDING))
