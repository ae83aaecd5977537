"""Steady sliding: linear stability, Hopf points and their criticality, for any law.

Near steady sliding ``(s, w) = (f(nu), nu)`` the slip dynamics is the Liénard
oscillator ``x'' + f'(nu + x) x' + x = 0`` with ``x = w - nu`` (PHYSICS.md §3).
Linearised, steady sliding has eigenvalues ``(-f' +- sqrt(f'^2 - 4))/2`` and is
stable exactly when ``f'(nu) > 0``; a Hopf bifurcation sits where ``f'(nu_H) = 0``.
First-order averaging of ``x = a cos t`` gives the amplitude equation

    a' = -(a/2) f'(nu) - (f'''(nu)/16) a^3,

so the first Lyapunov coefficient (the cubic coefficient) is
``l1 = -f'''(nu_H)/16``: negative (``f''' > 0``) means supercritical, a small
stable pure-slip cycle of amplitude ``a = sqrt(-8 f'(nu)/f'''(nu))`` on the
unstable side; positive means subcritical, an unstable small cycle on the stable
side (bistability). The analysis is local; the regimes far from ``nu_H`` need
the engine (``stickslip.cycle``), which the tests use to check these claims.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.checks import driving_velocity
from ..laws import DimensionlessLaw, require_dimensionless_law
from ..units import check_number

__all__ = [
    "HOPF_GRID_PER_DECADE",
    "Hopf",
    "averaged_amplitude",
    "check_nu_range",
    "eigenvalues_at_slope",
    "hopf_points",
    "steady_sliding_eigenvalues",
]


@dataclass(frozen=True)
class Hopf:
    """A Hopf point of steady sliding.

    Attributes
    ----------
    nu : float
        Driving velocity where ``f'(nu) = 0``.
    l1 : float
        First Lyapunov coefficient, ``-f'''(nu)/16`` (cubic coefficient of the
        averaged amplitude equation).
    criticality : str
        ``supercritical`` (``l1 < 0``) or ``subcritical`` (``l1 > 0``);
        ``degenerate`` when ``f'''(nu) = 0``. At a kink (below) it is the sign
        of the quadratic term instead: ``supercritical`` when ``kink > 0``.
    stable_side : str
        ``above`` when steady sliding is stable for larger ``nu`` (``f'' > 0``), else ``below``.
    kink : float
        The jump ``f''(nu+) - f''(nu-)`` where the Hopf point lies on a
        breakpoint of the law (a table's row); 0 elsewhere. Averaging then gives
        ``a' = -(a/2) f'(nu) - (kink/(3 pi)) a^2 + ...``: the quadratic term
        decides the criticality, the amplitude grows linearly in ``nu - nu_H``,
        and ``l1`` (which needs a ``f'''`` that jumps there too) is NaN.

    """

    nu: float
    l1: float
    criticality: str
    stable_side: str
    kink: float = 0.0


def _d(law: DimensionlessLaw, nu: float, order: int) -> float:
    return law.at(nu, order) if nu > 0 else float(law.derivative(np.array([nu]), order)[0])


def eigenvalues_at_slope(slope: float) -> tuple[complex, complex]:
    """Return the eigenvalues ``(-f' +- sqrt(f'^2 - 4))/2`` of steady sliding where ``f' = slope``."""
    root = complex(slope * slope - 4.0) ** 0.5
    return ((-slope + root) / 2, (-slope - root) / 2)


def steady_sliding_eigenvalues(law: DimensionlessLaw, nu: float) -> tuple[complex, complex]:
    """Return the eigenvalues of steady sliding at ``nu`` (units of ``sqrt(k/m)``)."""
    law = require_dimensionless_law(law)
    nu = check_number(nu, "nu")
    return eigenvalues_at_slope(_d(law, nu, 1))


def check_nu_range(
    nu_min: float, nu_max: float, *, reversed_says: str = " must exceed"
) -> tuple[float, float]:
    """Return ``(nu_min, nu_max)`` as floats: driving velocities from ``NU_MIN`` to ``NU_MAX``, in order.

    Raises
    ------
    ValueError
        For a velocity out of that range, or ``nu_max <= nu_min`` (the message reads
        ``nu_max=... <reversed_says> nu_min=...``).

    """
    lo = driving_velocity("nu_min", check_number(nu_min, "nu_min"))
    hi = check_number(nu_max, "nu_max")
    if hi <= lo:
        raise ValueError(f"nu_max={nu_max!r}{reversed_says} nu_min={nu_min!r}")
    return lo, driving_velocity("nu_max", hi)


#: points per decade of the grid that brackets the Hopf points: a weakening band (two Hopf
#: points) narrower than about two spacings, 2.3e-4 of its velocity, can be missed
HOPF_GRID_PER_DECADE = 20000


def hopf_points(
    law: DimensionlessLaw, nu_min: float = 1e-6, nu_max: float = 1e3, n_grid: int | None = None
) -> list[Hopf]:
    """Find the Hopf points ``f'(nu) = 0`` in ``[nu_min, nu_max]`` and their criticality.

    Roots are bracketed on a logarithmic grid of ``n_grid`` points (default
    :data:`HOPF_GRID_PER_DECADE` per decade, at least 4000), to which a table's
    rows are added, and refined by Brent's method. Between two grid points where
    ``f'`` keeps its sign but ``f''`` changes it, the extremum of ``f'`` is located: a
    dip of ``f'`` below zero narrower than the grid gives its two roots too.

    Raises
    ------
    ValueError
        For a non-positive or reversed range.

    """
    law = require_dimensionless_law(law)
    lo, hi = check_nu_range(nu_min, nu_max)
    if n_grid is None:
        n_grid = max(4000, math.ceil(HOPF_GRID_PER_DECADE * math.log10(hi / lo)))
    knots = np.asarray(law.breakpoints(), dtype=float)
    grid = np.union1d(np.geomspace(lo, hi, n_grid), knots[(knots > lo) & (knots < hi)])
    g = np.asarray(law.derivative(grid, 1), dtype=np.float64)
    if np.all(g == 0.0):
        return []  # f' vanishes identically (Coulomb): steady sliding is neutral, no Hopf point
    # a root on the grid itself, isolated: the neighbours have opposite signs
    roots = [
        float(grid[i]) for i in np.flatnonzero(g == 0.0) if 0 < i < grid.size - 1 and g[i - 1] * g[i + 1] < 0
    ]
    from scipy import optimize  # here: scipy.optimize takes 0.3 s to import, and a cycle needs none

    brackets = [
        (float(grid[i]), float(grid[i + 1])) for i in np.flatnonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0)
    ]
    brackets += _dips(law, grid, g)
    for a, b in brackets:
        root = optimize.brentq(lambda v: _d(law, v, 1), a, b, xtol=1e-14, rtol=1e-14)
        roots.append(float(root))
    out = []
    for nu_h in sorted(roots):
        side = "above" if _d(law, nu_h, 2) > 0 else "below"
        near = knots[np.abs(knots - nu_h) <= 1e-9 * nu_h] if knots.size else knots
        if near.size:  # on a breakpoint: f'' may jump there (pchip puts a minimum on a row)
            knot = float(near[0])
            left, right = _d(law, knot * (1 - 1e-12), 2), _d(law, knot * (1 + 1e-12), 2)
            jump = right - left
            if abs(jump) > 1e-9 * max(abs(left), abs(right)):
                crit = "supercritical" if jump > 0 else "subcritical"
                side = "above" if left + right > 0 else "below"
                out.append(Hopf(knot, math.nan, crit, side, jump))
                continue
        f3 = _d(law, nu_h, 3)
        l1 = -f3 / 16.0
        crit = "degenerate" if f3 == 0 else ("supercritical" if l1 < 0 else "subcritical")
        out.append(Hopf(nu_h, l1, crit, side))
    return out


def _dips(law: DimensionlessLaw, grid: np.ndarray, g: np.ndarray) -> list[tuple[float, float]]:
    """Brackets of the two roots of ``f'`` in a dip (or a bump) narrower than the grid.

    Where ``f'`` keeps its sign from one grid point to the next but ``f''`` changes sign,
    ``f'`` has an extremum between them; if ``f'`` has the other sign there, it crosses zero
    on either side of it (a weakening band narrower than the grid's spacing). ``f''`` is
    compared across its exact zeros (a linear stretch of the law, or a derivative that
    rounds to zero far from the dip); a dip so narrow that ``f''`` rounds to zero at the
    grid points on both sides is not seen.
    """
    from scipy import optimize

    g2 = np.asarray(law.derivative(grid, 2), dtype=np.float64)
    nz = np.flatnonzero(np.isfinite(g2) & (g2 != 0.0))
    out = []
    turns = np.flatnonzero(g2[nz[:-1]] * g2[nz[1:]] < 0)  # f' has an extremum in between
    for a, b in zip(nz[turns], nz[turns + 1], strict=True):
        if g[a] == 0.0 or not np.all(np.sign(g[a : b + 1]) == np.sign(g[a])):
            continue  # a root of f' that the grid has bracketed already
        w = optimize.brentq(lambda v: _d(law, v, 2), grid[a], grid[b], xtol=1e-15, rtol=1e-15)
        if _d(law, w, 1) * g[a] < 0:
            out += [(float(grid[a]), float(w)), (float(w), float(grid[b]))]
    return out


def averaged_amplitude(law: DimensionlessLaw, nu: float) -> float:
    """Return the first-order averaging amplitude of the small cycle near a Hopf point.

    ``a = sqrt(-8 f'(nu)/f'''(nu))``, the amplitude of ``w - nu`` (and, at unit
    frequency, of ``s``); NaN where no small cycle exists (``f'/f''' > 0``).
    """
    law = require_dimensionless_law(law)
    g1, g3 = _d(law, nu, 1), _d(law, nu, 3)
    if g3 == 0 or g1 / g3 >= 0:
        return math.nan
    return math.sqrt(-8.0 * g1 / g3)
