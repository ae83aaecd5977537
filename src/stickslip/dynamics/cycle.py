"""The steady oscillation of one parameter set: amplitude, period, regime.

:func:`cycle` follows the block from rest to its attractor and measures one
steady cycle. Stick-slip uses the structure of PHYSICS.md §2: every slip phase
that starts from rest starts at ``(s, w) = (1, 0)``, so one slip integration
from breakaway gives the whole cycle. Pure slip and steady sliding are found
without assuming them: the transient is followed until successive oscillations
agree (or decay, about a linearly stable steady state). Steady sliding is
probed as well, so that a second attractor is reported when there is one.
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
import pint

from .. import defaults
from ..core import checks
from ..core.api import run_attractors
from ..core.results import AttractorRows, Regime, Status, reversal
from ..errors import ArgumentTypeError
from ..io.jsonable import json_clean
from ..laws import law_arrays
from ..models.parameters import (
    DimensionlessParameters,
    PhysicalParameters,
    Scales,
    as_dimensionless,
)
from ..models.scales import UNITS
from ..orbits.attractors import OrbitKey, orbit_key, polish_rows, same_orbit
from ..units import Q_, check_number, parse_quantity
from ..userwarnings import warn

__all__ = ["Attractor", "CycleResult", "cycle", "validate_tolerances"]

#: unit of each result field, by kind
_FIELD_KIND = {
    "amplitude": "force",
    "period": "time",
    "stick_time": "time",
    "stick_fraction": "1",
    "slip_distance": "length",
    "peak_velocity": "velocity",
    "min_velocity": "velocity",
    "max_force": "force",
    "min_force": "force",
    "drive_work": "energy",
    "friction_work": "energy",
    "transient_time": "time",
}
#: the units of a result of each kind, dimensionless (in words) and SI
DIMENSIONLESS_UNITS = {kind: label.scale for kind, label in UNITS.items()}
SI_UNITS = {kind: label.si for kind, label in UNITS.items()}


#: where a run stopped (the step fell below the resolution of the time, or ran out), the law has a
#: pole there when friction or its slope exceeds POLE_GROWTH times its size 0.1 % of the velocity to
#: either side: near a pole of order n at a distance d that ratio is (0.001 w / d)**n (1e10 where the
#: step fails, d about 1e-6 w for a double pole), while a finite law changes by a few times over 0.1 %
POLE_GROWTH = 1e3
#: the statuses with which a run stops where the friction law may have a pole
_STOPPED = (Status.STEP_TOO_SMALL, Status.TOO_MANY_STEPS)


def pole_reached(law: Any, w: float) -> float | None:
    """Return friction at ``|w|`` where a run that stopped at velocity ``w`` met a pole of ``law``, else None.

    NaN when the law cannot be evaluated there. A stiff but finite law (no blow-up at
    ``w``, :data:`POLE_GROWTH`) and a runaway (friction smooth where it stopped) are not poles.
    """
    x = abs(float(w))
    if not (math.isfinite(x) and x > 0.0):
        return None
    h = 1e-3 * x
    friction = math.nan
    for order in (0, 1):
        try:
            with np.errstate(all="ignore"):
                at = float(law.at(x, order))
                side = max(abs(float(law.at(x - h, order))), abs(float(law.at(x + h, order))))
        except (ZeroDivisionError, OverflowError, ValueError):
            return friction
        if order == 0:
            friction = at
        if not math.isfinite(at) or abs(at) > POLE_GROWTH * side:
            return friction
    return None


def pole_message(law: Any, w: float, velocity: Any = None) -> str | None:
    """Say that a run that stopped at velocity ``w`` met a pole of ``law`` (None when it did not).

    ``velocity`` converts ``w`` to m/s for a physical set-up (:func:`_converter`'s ``"velocity"``).
    """
    f = pole_reached(law, w)
    if f is None:
        return None
    at = f"w = {abs(w):.6g}" if velocity is None else f"v = {velocity(abs(w)):.6g} m/s"
    return (
        f"the friction law divides by zero at a velocity the motion reached: f = {f:.3g} at {at}, "
        "where the run stopped (a pole of its formula, or of its derivative); give a law that is "
        "finite, with a finite slope, at every velocity w >= 0"
    )


def validate_tolerances(rtol: float, atol: float) -> tuple[float, float]:
    """Check integration tolerances by the core's rule (:func:`~stickslip.core.checks.tolerances`).

    Raises
    ------
    TypeError
        If a tolerance is not a number.
    ValueError
        If ``rtol`` is not in ``[1e-14, 1e-3]`` or ``atol`` is not in ``[ATOL_MIN, 1]`` (1e-30: a
        subnormal one ended in step-size-too-small, blaming the friction law).

    """
    return checks.tolerances(rtol, atol)


@dataclass(frozen=True)
class Attractor:
    """One attractor reached from one start.

    Attributes
    ----------
    regime : Regime
        ``stick-slip``, ``pure-slip``, ``steady-sliding`` or ``unknown`` (a :class:`Regime`,
        a ``str`` enum: it compares equal to those strings).
    amplitude : float
        Range of the spring force over the cycle (force unit of the result).
    period : float
        Period (time unit of the result); NaN for steady sliding.
    start : str
        Where it was reached from: ``rest`` or ``near steady sliding``.
    status : Status
        ``ok`` or the reason the search did not converge (a ``str`` enum).
    multiplier : float
        Nontrivial Floquet multiplier of the orbit: 0 for stick-slip, between -1
        and 1 for a polished pure-slip or slip-reversal orbit, NaN for steady
        sliding and where unknown.

    """

    regime: Regime
    amplitude: float
    period: float
    start: str
    status: Status
    multiplier: float = math.nan


@dataclass(frozen=True)
class CycleResult:
    """The steady oscillation reached from rest, and every attractor found.

    All values are in the unit system named by :attr:`units`: dimensionless
    (force in static friction force ``mu_s W``, time in ``sqrt(m/k)``) for
    dimensionless parameters, SI for physical ones.

    Attributes
    ----------
    regime : Regime
        ``stick-slip``, ``pure-slip``, ``steady-sliding`` or ``unknown``, reached from rest (a
        ``str`` enum: it compares equal to those strings).
    amplitude : float
        ``max s - min s`` over one steady cycle (force).
    period : float
        Period of the cycle (time); NaN for steady sliding.
    stick_fraction : float
        Fraction of the period the block is at rest.
    stick_time : float
        Duration of the stick phase (time).
    slip_distance : float
        Distance slipped per cycle (length), equal to ``v0`` times the period.
    peak_velocity, min_velocity : float
        Largest and smallest block velocity over the cycle (velocity).
    max_force, min_force : float
        Extremes of the spring force (force).
    backward_slips : int
        Backward slip phases per cycle.
    drive_work, friction_work : float
        Work of the drive and of friction over one cycle (energy); equal on a
        steady cycle (energy balance).
    transient_time : float
        Time from rest until the measured cycle starts (time).
    status : Status
        ``ok`` (a ``str`` enum), or why the attractor could not be pinned down: ``not-converged``
        when a non-sticking transient could not be polished into a periodic orbit
        (its values are then the transient's, not within the tolerance).
    multiplier : float
        Nontrivial Floquet multiplier of the attractor reached from rest (see
        :class:`Attractor`); its distance from 1 is the rate at which
        transients approach it.
    attractors : tuple of Attractor
        Distinct attractors reached from rest and from near steady sliding.
    multistable : bool
        More than one attractor was found.
    steady_sliding_stable : bool
        Steady sliding is linearly stable (``f'(nu) > 0``).
    units : Mapping[str, str]
        Unit of force, time, length, velocity and energy.

    """

    regime: Regime
    amplitude: float
    period: float
    stick_fraction: float
    stick_time: float
    slip_distance: float
    peak_velocity: float
    min_velocity: float
    max_force: float
    min_force: float
    backward_slips: int
    drive_work: float
    friction_work: float
    transient_time: float
    status: Status
    multiplier: float
    attractors: tuple[Attractor, ...]
    multistable: bool
    steady_sliding_stable: bool
    units: Mapping[str, str] = field(default_factory=dict, hash=False)

    def quantity(self, name: str) -> pint.Quantity:
        """Return a result field as a pint quantity (SI results only).

        Raises
        ------
        ArgumentTypeError
            For a ``name`` that is not a str.
        ValueError
            For an unknown field or a dimensionless result.

        """
        if not isinstance(name, str):
            raise ArgumentTypeError(
                f"name={name!r} (type {type(name).__name__}): expected one of {sorted(_FIELD_KIND)}"
            )
        if name not in _FIELD_KIND:
            raise ValueError(f"name={name!r}: expected one of {sorted(_FIELD_KIND)}")
        if self.units.get("force") != "N":
            raise ValueError("quantity() needs a result computed from physical parameters")
        kind = _FIELD_KIND[name]
        return Q_(getattr(self, name), "" if kind == "1" else SI_UNITS[kind])

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready dictionary (NaN becomes ``None``)."""
        return json_clean(asdict(self))

    def to_json(self, **kwargs: Any) -> str:
        """Return :meth:`as_dict` as a JSON string."""
        return json.dumps(self.as_dict(), **kwargs)


def cycle(
    params: DimensionlessParameters | PhysicalParameters,
    *,
    rtol: float = defaults.RTOL,
    atol: float = defaults.ATOL,
    max_slip_time: float = defaults.MAX_SLIP_TIME,
    conv_tol: float = defaults.CONV_TOL,
    probe: bool = True,
) -> CycleResult:
    """Compute the steady oscillation reached from rest, and look for other attractors.

    Parameters
    ----------
    params : DimensionlessParameters or PhysicalParameters
        The set-up. Physical input gives SI output; dimensionless input gives
        dimensionless output.
    rtol, atol : float, optional
        Tolerances of the slip integration (see :mod:`stickslip.defaults`).
    max_slip_time : float, str or pint.Quantity, optional
        Bound on the slip time followed from each start (units of ``sqrt(m/k)``; for physical
        parameters also a time, ``"10 s"``).
    conv_tol : float, optional
        Relative amplitude change at which a non-sticking transient counts as converged.
    probe : bool, optional
        Also start near steady sliding to find a second attractor. Default True.

    Returns
    -------
    CycleResult

    Examples
    --------
    >>> from stickslip import cycle, DimensionlessParameters, WeakeningLaw
    >>> r = cycle(DimensionlessParameters(nu=1e-3, law=WeakeningLaw(c=3.8)))
    >>> r.regime.value
    'stick-slip'

    """
    dp, scales = as_dimensionless(params)
    rtol, atol = validate_tolerances(rtol, atol)
    if not isinstance(probe, bool | np.bool_):  # 'no' is a true string: refused, not taken as True
        raise TypeError(f"probe={probe!r}: expected True or False")
    if scales is not None and isinstance(max_slip_time, str | pint.Quantity):  # '10 s' taken as a time
        bound = parse_quantity(max_slip_time, "max_slip_time", "[time]", "10 s")
        max_slip_time = scales.from_si("time", bound)
    max_slip_time = check_number(max_slip_time, "max_slip_time")
    conv_tol = check_number(conv_tol, "conv_tol", upper=0.1, what="a relative tolerance below 0.1")
    law = dp.law
    nu = dp.nu
    kernel, lp = law_arrays(law)
    dfnu = law.at(nu, 1)
    fnu = law.at(nu)
    steady_stable = dfnu > 0.0

    run = functools.partial(
        run_attractors,
        kernel,
        lp,
        [nu],
        rtol=rtol,
        atol=atol,
        max_slip_time=max_slip_time,
        conv_tol=conv_tol,
        diag=True,
    )
    # From rest the block sticks until s = 1 (closed form, duration 1/nu), then
    # slips from (1, 0): start there and add the stick to the transient.
    out0 = run(from_breakaway=True)
    out0.transient += 1.0 / nu
    rows, starts = [out0], ["rest"]
    if probe and dfnu < 0.0:  # strictly unstable: f'(nu) = 0 (Coulomb) is neutral, no attractor
        rows.append(run([fnu + defaults.STEADY_PERTURBATION], [nu], from_breakaway=False))
        starts.append("near steady sliding")

    # polish every non-sticking attractor into its periodic orbit (exact near a Hopf point,
    # where the transient crawls); measure the work integrals on the polished orbit
    polished, mult = polish_rows(
        law, np.full(len(rows), nu), AttractorRows.concat(rows), rerun=True, rtol=rtol, atol=atol
    )
    conv = _converter(scales)
    keyed = [
        (_attractor(polished[i], start, conv, m), orbit_key(polished[i]))
        for i, (start, m) in enumerate(zip(starts, mult, strict=True))
    ]
    if len(rows) > 1:
        # a probe that never left the neighbourhood of steady sliding (amplitude still about
        # twice the push) found no attractor: steady sliding is (nearly) neutral there
        push = conv("force", 2.0 * defaults.STEADY_PERTURBATION)
        if abs(keyed[1][0].amplitude - push) <= 0.1 * push:
            keyed.pop(1)
    if steady_stable:
        keyed.append(
            (
                Attractor(Regime.STEADY_SLIDING, 0.0, math.nan, "linear stability", Status.OK),
                OrbitKey(Regime.STEADY_SLIDING),
            )
        )
    distinct = _distinct(keyed)

    for i in range(len(rows)):  # a run that stopped at a pole says so, as one that hit it exactly does
        if Status.from_code(polished.status[i]) in _STOPPED:
            speed = None if scales is None else functools.partial(conv, "velocity")
            pole = pole_message(law, float(polished.w[i]), speed)
            if pole is not None:
                raise ValueError(pole)
    o = polished[0]
    # a motion from rest that could not be followed: a table may know why (its extrapolation
    # reaches zero friction); else whether the motions went beyond the table
    note = law.motion_warning(polished.w_max, Status.from_code(o.status[0]) != Status.OK)
    if note:
        warn(note, UserWarning)
    period = float(o.period[0])
    regime = Regime.from_code(reversal(o.regime[0], o.n_backward[0]))
    stick_time = float(o.stick_time[0])
    if regime == Regime.STEADY_SLIDING:
        stick_fraction = 0.0
        slip_distance = math.nan
    else:
        stick_fraction = stick_time / period if period > 0 else math.nan
        slip_distance = nu * period
    return CycleResult(
        regime=regime,
        amplitude=conv("force", o.amplitude[0]),
        period=conv("time", period),
        stick_fraction=float(stick_fraction),
        stick_time=conv("time", stick_time),
        slip_distance=conv("length", slip_distance),
        peak_velocity=conv("velocity", o.w_max[0]),
        min_velocity=conv("velocity", o.w_min[0]),
        max_force=conv("force", o.s_max[0]),
        min_force=conv("force", o.s_min[0]),
        backward_slips=int(o.n_backward[0]) if math.isfinite(o.n_backward[0]) else 0,
        drive_work=conv("energy", o.drive_work[0]),
        friction_work=conv("energy", o.friction_work[0]),
        transient_time=conv("time", o.transient[0]),
        status=Status.from_code(o.status[0]),
        multiplier=float(mult[0]),
        attractors=tuple(distinct),
        multistable=len(distinct) > 1,
        steady_sliding_stable=steady_stable,
        units=dict(SI_UNITS) if scales is not None else dict(DIMENSIONLESS_UNITS),
    )


def _converter(scales: Scales | None) -> Any:
    if scales is None:
        return lambda kind, x: float(x)
    factor = {kind: scales.factor(kind) for kind in UNITS}  # one pint conversion per kind
    return lambda kind, x: float(x) * factor[kind]


def _attractor(o: AttractorRows, start: str, conv: Any, multiplier: float) -> Attractor:
    return Attractor(
        regime=Regime.from_code(reversal(o.regime[0], o.n_backward[0])),
        amplitude=conv("force", o.amplitude[0]),
        period=conv("time", o.period[0]),
        start=start,
        status=Status.from_code(o.status[0]),
        multiplier=float(multiplier),
    )


def _distinct(keyed: list[tuple[Attractor, OrbitKey | None]]) -> list[Attractor]:
    """Keep the attractors that were pinned down, one per distinct orbit."""
    kept: list[tuple[Attractor, OrbitKey]] = []
    for a, key in keyed:
        if key is None or a.status != "ok":
            continue
        if not any(same_orbit(key, k) for _, k in kept):
            kept.append((a, key))
    return [a for a, _ in kept]
