"""The branches of a regime diagram, its intervals, and the pure-slip orbits read off it.

:class:`Branch` (steady sliding, pure slip or stick slip against ``nu``),
:class:`SpecialPoint` (a bifurcation on a branch), :class:`Interval` (a range of ``nu``
with one set of attractors, named by :func:`interval_regime`) and
:class:`RegimeDiagram` (all of them for one law, as :func:`~.regimes.regimes`
returns it). The pure-slip orbits at one ``nu`` are read off the continued branches
by linear interpolation (:func:`stable_pure_slip_at`) or solved from them by
shooting (:func:`pure_slip_orbits_at`).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ..core.results import AttractorRows, Regime
from ..io.jsonable import json_clean
from ..laws import DimensionlessLaw
from ..models.parameters import DimensionlessParameters
from ..orbits.attractors import OrbitKey, same_orbit
from ..orbits.periodic import PeriodicOrbit, pure_slip_orbit
from ..orbits.stability import Hopf

__all__ = [
    "REGIME_NAMES",
    "Branch",
    "Interval",
    "RegimeDiagram",
    "SpecialPoint",
    "interval_regime",
    "pure_slip_orbits_at",
    "stable_pure_slip_at",
]

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
    #: the engine's output from each probe (:data:`~.probes.PROBE_PUSHES`) at each grid ``nu``, polished:
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
        is the attractor (so a regime map's cell on the Hopf point of a linear grid reads
        steady sliding, not pure slip).
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


# ----------------------------------------------------------------------------- orbits on the branches


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
