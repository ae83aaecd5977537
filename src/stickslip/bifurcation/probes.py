"""What the exact engine reaches: the stick-slip branch, and the attractors at each ``nu``.

The stick-slip orbit through breakaway exists where the slip from breakaway stops
(:func:`stick_slip_branch`, whose ends are bisected on the engine). The attractors at
one ``nu`` are those the engine reaches from rest and from the :data:`PROBE_PUSHES`
off steady sliding, each polished into its orbit
(:func:`~stickslip.orbits.attractors.polish_rows`), with the stable pure-slip orbits
of the continued branches and steady sliding where it is stable; one orbit found
twice counts once. Where the set changes between two grid points and no bifurcation
was located there, the change is bisected.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence

import numpy as np

from .. import defaults
from ..core.api import run_attractors
from ..core.results import AttractorRows, Regime
from ..laws import DimensionlessLaw, require_dimensionless_law
from ..orbits.attractors import OrbitKey, distinct, orbit_key, polish_rows
from .branches import Branch, SpecialPoint, pure_slip_orbits_at

__all__ = ["PROBE_PUSHES", "identify", "stick_slip_branch"]


def _engine(
    law: DimensionlessLaw, nu: np.ndarray, s0: np.ndarray | None = None, conv_tol: float = defaults.CONV_TOL
) -> AttractorRows:
    """Run the engine with the defaults: from breakaway, or from ``(s0, w = nu)`` when ``s0`` is given."""
    kernel, lp = law.arrays()
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


def identify(law: DimensionlessLaw, nu: float, rows: AttractorRows) -> list[OrbitKey | None]:
    """Polish the attractors in engine rows at ``nu``; return their keys (None where unresolved)."""
    polished, _ = polish_rows(law, np.full(len(rows), nu), rows)
    return [orbit_key(polished[i]) for i in range(len(polished))]


#: spring force above steady sliding of the probes that look for attractors besides the one
#: reached from rest: near steady sliding, and a large push
PROBE_PUSHES = (1e-3, 2.0)


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
