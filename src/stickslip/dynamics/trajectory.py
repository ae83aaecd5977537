"""Time series of the block: position, velocity, spring force and phase."""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt
import pint

from .. import defaults
from ..core.api import MAX_PHASES, MAX_TIME, run_attractors, run_trajectory
from ..core.checks import number_pair
from ..core.memory import check_memory
from ..core.results import EventKind, Regime, Status
from ..errors import ArgumentTypeError
from ..laws import law_arrays
from ..models.parameters import DimensionlessParameters, PhysicalParameters, as_dimensionless
from ..models.scales import unit_attrs, unit_label
from ..units import check_number, parse_quantity
from .cycle import DIMENSIONLESS_UNITS, SI_UNITS, cycle, pole_message, validate_tolerances

__all__ = ["Trajectory", "simulate"]

PHASE_NAMES = {0: "stick", 1: "slip", -1: "backward-slip"}

FloatArray = npt.NDArray[np.float64]

#: memory one sample of a trajectory takes on its way to a Trajectory (engine output, unique
#: times, SI columns; the CSV is written in chunks)
BYTES_PER_SAMPLE = 200.0


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A sampled motion of the block.

    Attributes
    ----------
    time : ndarray
        Sample times (s, or units of ``sqrt(m/k)``).
    position : ndarray
        Block position from its start (m, or units of ``mu_s W / k``).
    velocity : ndarray
        Block velocity (m/s, or units of ``mu_s W / sqrt(k m)``).
    spring_force : ndarray
        Spring force ``k (v0 t - x)`` (N, or units of ``mu_s W``).
    phase : ndarray of int
        0 stick, +1 slip, -1 backward slip. A sample at an event's time has the
        phase that the event ends: a stop's sample is ``slip`` (velocity 0 to
        rounding, e.g. -8.7e-17), a breakaway's ``stick``.
    event_time, event_force : ndarray
        Time and spring force of each event.
    event_kind : tuple of str
        ``stop``, ``stick``, ``breakaway``, ``backward-slip``, ``force-maximum``, ``force-minimum``.
    units : Mapping[str, str]
        Units of force, time, length and velocity.

    Notes
    -----
    A trajectory holds arrays, so ``==`` and ``hash`` go by identity; compare two
    trajectories' arrays with :func:`numpy.allclose`.

    """

    time: FloatArray
    position: FloatArray
    velocity: FloatArray
    spring_force: FloatArray
    phase: npt.NDArray[np.int64]
    event_time: FloatArray
    event_kind: tuple[str, ...]
    event_force: FloatArray
    units: Mapping[str, str] = field(default_factory=dict)

    @property
    def physical(self) -> bool:
        """Whether the trajectory is in SI units."""
        return self.units.get("force") == "N"

    def __repr__(self) -> str:  # a summary at a glance, not the arrays' dump
        unit = unit_label("time", self.physical)
        span = f"t = {self.time[0]:.6g}..{self.time[-1]:.6g} {unit}" if self.time.size else "no samples"
        return (
            f"Trajectory({self.time.size} samples, {span}, {len(self.event_time)} events, "
            f"{'SI' if self.physical else 'dimensionless'})"
        )

    def to_xarray(self) -> Any:
        """Return the motion as an :class:`xarray.Dataset`, units in CF attributes.

        Samples on ``time``; the events on their own dimension ``event`` (their time, kind and
        spring force). Dimensionless values have units ``'1'`` and say of what in ``scale``.
        """
        import xarray as xr

        def attrs(kind: str, name: str) -> dict[str, str]:
            return {**unit_attrs(kind, self.physical), "long_name": name}

        return xr.Dataset(
            {
                "position": ("time", self.position, attrs("length", "block position from its start")),
                "velocity": ("time", self.velocity, attrs("velocity", "block velocity")),
                "spring_force": ("time", self.spring_force, attrs("force", "spring force k (v0 t - x)")),
                "phase": (
                    "time",
                    np.asarray(self.phase, dtype=np.int64),
                    {
                        "long_name": "phase",
                        "flag_values": list(PHASE_NAMES),
                        "flag_meanings": " ".join(PHASE_NAMES.values()),
                    },
                ),
                "event_kind": ("event", np.array([str(k) for k in self.event_kind], dtype=str)),
                "event_force": ("event", self.event_force, attrs("force", "spring force at the event")),
            },
            coords={
                "time": ("time", self.time, attrs("time", "time")),
                "event_time": ("event", self.event_time, attrs("time", "time of the event")),
            },
            attrs={"Conventions": "CF-1.8", "title": "stickslip trajectory"},
        )

    def columns(self) -> dict[str, Any]:
        """Return the columns with their units in brackets, as written to CSV."""
        t, x, v, f = (unit_label(kind, self.physical) for kind in ("time", "length", "velocity", "force"))
        return {
            f"time [{t}]": self.time,
            f"position [{x}]": self.position,
            f"velocity [{v}]": self.velocity,
            f"spring_force [{f}]": self.spring_force,
            "phase": np.array([PHASE_NAMES[int(p)] for p in self.phase]),
        }

    def to_csv(self, path: Any, *, out: Any = None, overwrite: bool = False) -> str:
        """Write the trajectory to a CSV file with units in the header (atomically); return its path.

        ``out`` stages it in an :class:`~stickslip.io.output.OutputFolder` (``path`` a name in it);
        an existing file stickslip did not write is kept unless ``overwrite``.
        """
        from ..io.csv import write_columns

        return write_columns(path, self.columns(), kind="trajectory", out=out, overwrite=overwrite)


def _failure_hint(status: Status, t_end: float, duration: Any, cycles: float | None) -> str:
    """Say why a run failed and what to change; the limits named are the engine's own."""
    asked = f"duration={duration!r}" if duration is not None else f"cycles={cycles!r}"
    if status == Status.TOO_MANY_PHASES:
        return (
            f"the motion has more than {MAX_PHASES:,} stick and slip phases before t = {t_end:.6g} "
            f"(sqrt(m/k)), the end of {asked}: simulate a shorter duration, or use `cycle` for the "
            "steady oscillation"
        )
    if status == Status.TOO_MANY_STEPS:
        return (
            f"one slip phase needed more than {defaults.MAX_STEPS:,} steps before t = {t_end:.6g} "
            f"(sqrt(m/k)), the end of {asked}: a motion that never sticks is one slip phase however "
            "long; simulate a shorter duration, or a larger rtol if the law is stiff"
        )
    return "try a larger rtol"


def _initial_state(initial: Any, scales: Any) -> Any:
    """Return ``initial`` in the model's units: a physical set-up's quantities are converted.

    A pair of quantities (``('50 mN', '0 m/s')``) is a pair like two numbers are.
    """
    if scales is None or not isinstance(initial, tuple | list) or len(initial) != 2:
        return initial
    if not any(isinstance(x, str | pint.Quantity) for x in initial):
        return initial
    signed = {"allow_zero": True, "allow_negative": True}
    force = parse_quantity(initial[0], "initial[0] (spring force)", "[force]", "50 mN", **signed)
    speed = parse_quantity(initial[1], "initial[1] (velocity)", "[length] / [time]", "0 m/s", **signed)
    return (scales.from_si("force", force), scales.from_si("velocity", speed))


def simulate(
    params: DimensionlessParameters | PhysicalParameters,
    *,
    duration: Any = None,
    cycles: float | None = None,
    n_points: int = 4000,
    initial: tuple[float, float] = (0.0, 0.0),
    rtol: float = defaults.RTOL,
    atol: float = defaults.ATOL,
) -> Trajectory:
    """Integrate the motion from a start and sample it on a uniform grid plus every event.

    Parameters
    ----------
    params : DimensionlessParameters or PhysicalParameters
        The set-up; physical input gives SI output.
    duration : float, str or pint.Quantity, optional
        Length of the simulation: a time with units for physical parameters, a
        number (units of ``sqrt(m/k)``) for dimensionless ones. Default: from rest
        to the end of ``cycles`` steady cycles.
    cycles : float, optional
        Number of steady cycles, instead of ``duration`` (not both). Default 3.
    n_points : int, optional
        Number of uniform samples (event times are added). Default 4000.
    initial : (float, float), optional
        Initial spring force and velocity, dimensionless (units of ``mu_s W`` and
        ``mu_s W / sqrt(k m)``), or for physical parameters quantities
        (``("50 mN", "0 m/s")``). Default ``(0, 0)``: at rest, spring relaxed.
    rtol, atol : float, optional
        Tolerances of the slip integration.

    Returns
    -------
    Trajectory

    """
    dp, scales = as_dimensionless(params)
    rtol, atol = validate_tolerances(rtol, atol)
    if isinstance(n_points, bool) or not isinstance(n_points, numbers.Integral):
        raise ArgumentTypeError(f"n_points={n_points!r}: expected an integer >= 2")
    if n_points < 2:
        raise ValueError(f"n_points={n_points!r}: expected an integer >= 2")
    check_memory(
        int(n_points) * BYTES_PER_SAMPLE,
        f"n_points={n_points}",
        "sample fewer points (events are always added) or simulate a shorter duration",
    )
    initial = _initial_state(initial, scales)
    pair = (
        f"initial={initial!r}: expected a pair (spring force, velocity): numbers in the model's "
        "units (mu_s W and mu_s W / sqrt(k m)), or, for physical parameters, quantities "
        "('50 mN', '0 m/s')"
    )
    s0, w0 = number_pair(initial, pair)
    if cycles is not None and duration is not None:  # cycles reached nothing
        raise ValueError(f"cycles={cycles!r} and duration={duration!r}: give one or the other")
    bound = 1e6
    if not (math.isfinite(s0) and math.isfinite(w0) and abs(s0) <= bound and abs(w0) <= bound):
        raise ValueError(
            f"initial={initial!r}: expected finite numbers of magnitude at most {bound:g} (units of the "
            "static friction force and of mu_s W / sqrt(k m))"
        )
    if duration is None:
        cycles = check_number(3.0 if cycles is None else cycles, "cycles", what="a positive number of cycles")
        res = cycle(dp, rtol=max(rtol, 1e-9), atol=atol, probe=False)
        period = res.period if math.isfinite(res.period) else 2.0 * math.pi
        # at rest between the thresholds the block sticks until s = 1; from any other start it
        # slips at once, and after its first stop breaks away within 2 / nu (s0 = -1e6 does not
        # stick for 1e6 / nu: such a bound would run out of phases)
        stuck = w0 == 0.0 and -1.0 <= s0 < 1.0
        t_end = ((1.0 - s0) if stuck else 2.0) / dp.nu + cycles * period
        if res.regime != Regime.STICK_SLIP:
            t_end = min(res.transient_time, defaults.MAX_SLIP_TIME) + cycles * period
    elif scales is not None:
        dq = parse_quantity(duration, "duration", "[time]", "10 s")
        t_end = scales.from_si("time", dq)
        end_s = float(dq.to("s").magnitude)  # the last sample's time as asked
    else:
        t_end = check_number(duration, "duration", what="a positive dimensionless duration")

    if t_end > MAX_TIME:  # the engine's own bound, named as the user's duration or cycles
        asked = f"duration={duration!r}" if duration is not None else f"cycles={cycles!r}"
        raise ValueError(
            f"{asked}: {t_end:.3g} in units of sqrt(m/k), expected at most {MAX_TIME:g} "
            "(time is a double: past that, a slip step is below its resolution)"
        )
    kernel, lp = law_arrays(dp.law)
    grid = np.linspace(0.0, t_end, n_points)
    # first pass: the event times, so that corners and extrema are sampled exactly
    _, _, ev, status = run_trajectory(kernel, lp, dp.nu, s0, w0, grid[-1:], rtol=rtol, atol=atol)
    t = np.unique(np.concatenate([grid, ev[:, 0][(ev[:, 0] >= 0) & (ev[:, 0] <= t_end)]]))
    y, mode, ev, status = run_trajectory(
        kernel, lp, dp.nu, s0, w0, t, rtol=rtol, atol=atol, event_capacity=max(16, ev.shape[0])
    )
    stopped = (Status.STEP_TOO_SMALL, Status.TOO_MANY_STEPS)
    if status != Status.OK:
        if status in stopped:
            # the trajectory keeps no state past its last sample: the same motion as one attractor
            # row, which records the velocity where it stopped, says whether a pole stopped it
            row = run_attractors(
                kernel, lp, [dp.nu], [s0], [w0], from_breakaway=False, rtol=rtol, atol=atol,
                max_slip_time=t_end, conv_tol=defaults.CONV_TOL,
            )  # fmt: skip
            speed = None if scales is None else (lambda w: scales.to_si("velocity", w))
            stop = Status.from_code(row.status[0])
            pole = pole_message(dp.law, float(row.w[0]), speed) if stop in stopped else None
            if pole is not None:
                raise ValueError(pole)
        raise RuntimeError(f"integration failed: {status} ({_failure_hint(status, t_end, duration, cycles)})")
    s = y[:, 0]
    w = y[:, 1]
    u = dp.nu * t - s
    kinds = tuple(EventKind.from_code(k) for k in ev[:, 1])
    if scales is None:
        return Trajectory(
            t, u - u[0], w, s, mode, ev[:, 0].copy(), kinds, ev[:, 2].copy(), dict(DIMENSIONLESS_UNITS)
        )
    si = scales.to_si
    times = si("time", t)
    if duration is not None:  # the end as asked (1 min ends at 60 s, not 60.00000000000001 s)
        times[-1] = end_s
    return Trajectory(
        times, si("length", u - u[0]), si("velocity", w), si("force", s), mode, si("time", ev[:, 0]), kinds,
        si("force", ev[:, 2]), dict(SI_UNITS),
    )  # fmt: skip
