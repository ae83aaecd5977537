"""Continuation in the driving velocity: every branch, its stability, and the regimes.

Three kinds of branch exist for a velocity-dependent law (PHYSICS.md §3):

``steady-sliding``
    ``(s, w) = (f(nu), nu)``, stable exactly where ``f'(nu) > 0``; it changes
    stability at the Hopf points ``f'(nu_H) = 0`` (:func:`~stickslip.orbits.stability.hopf_points`).
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
    (:func:`~stickslip.orbits.periodic.stick_slip_orbit`), has multipliers 1 and 0: where it
    exists it is stable.

The regime at a driving velocity is the set of attractors there: the stable
steady sliding, the stable pure-slip orbits, the stick-slip orbit.
``bistable`` marks two, ``multistable`` three or more. Interval ends are located to ``1e-9`` (Hopf,
grazing of a continued orbit, onset of stick-slip by bisection on the engine,
folds of cycles by Brent on the ``nu`` component of the branch's tangent); a fold
whose refinement fails falls back to the vertex of the quadratic through the
three points around the turn (the continuation's resolution).

This module assembles the diagram (:func:`regimes`) and checks it by direct
simulation (:func:`confirm`); its parts are :mod:`~.branches` (the branch, interval
and diagram types, and the pure-slip orbits read off the branches),
:mod:`~.continuation` (the pure-slip branches) and :mod:`~.probes` (the stick-slip
branch and the attractors the engine reaches), whose names it re-exports.
"""

from __future__ import annotations

import itertools
import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..core.results import AttractorRows, Regime
from ..errors import ArgumentTypeError
from ..laws import DimensionlessLaw, require_dimensionless_law
from ..orbits.attractors import distinct, orbit_key, polish_rows
from ..orbits.stability import Hopf, check_nu_range, eigenvalues_at_slope, hopf_points
from ..userwarnings import warn
from .branches import REGIME_NAMES as REGIME_NAMES
from .branches import (
    Branch,
    Interval,
    RegimeDiagram,
    SpecialPoint,
    interval_regime,
    pure_slip_orbits_at,
    stable_pure_slip_at,
)
from .branches import _orbits_at as _orbits_at
from .continuation import _fold as _fold
from .continuation import continue_pure_slip
from .probes import PROBE_PUSHES as PROBE_PUSHES
from .probes import (
    _attractor_sets,
    _engine,
    _locate_boundary,
    _probe_rows,
    _stick_slip_rows,
    stick_slip_branch,
)
from .probes import identify as identify

# the names of the parts imported with `as` (REGIME_NAMES, PROBE_PUSHES, identify, _fold,
# _orbits_at) are kept at this path too
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
#: interval ends closer than this (relative) are one point
CUT_RTOL = 1e-7


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
    lo, hi = check_nu_range(nu_min, nu_max, reversed_says=": expected a value above")
    if isinstance(n_grid, bool) or not isinstance(n_grid, int | np.integer):
        raise ArgumentTypeError(f"n_grid={n_grid!r}: expected an integer from 5 to {MAX_GRID}")
    if not 5 <= n_grid <= MAX_GRID:  # each point is a run from rest: 1e8 points run for hours
        raise ValueError(f"n_grid={n_grid!r}: expected an integer from 5 to {MAX_GRID}")
    n_grid = int(n_grid)
    # as pure_slip_orbit's: a nan or negative tol would lose the pure-slip branch silently
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
        raise ArgumentTypeError(f"tol={tol!r}: expected a shooting tolerance between 1e-13 and 1e-3")
    if not 1e-13 <= tol <= 1e-3:
        raise ValueError(f"tol={tol!r}: expected a shooting tolerance between 1e-13 and 1e-3")
    tol = float(tol)
    # Hopf points in a wider window: a branch born just outside the range may enter it
    # (and always the range itself, below the window's own 1e-6 bound too, for a range below 1e-7)
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
        multiplier=np.array([max(z.real for z in eigenvalues_at_slope(g)) for g in fp]),
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
