"""Reading laboratory rate-and-state records and load-point histories.

A record is a CSV or TSV file whose header cells give units in brackets:
``time [s]``, then ``load-point velocity [um/s]`` or ``load-point displacement [um]``,
and (for a record to fit) ``friction [1]``. Lines starting with ``#`` before the
header carry metadata as ``# key = value``, e.g. ``# mu0 = 0.6``,
``# v_ref = 1 um/s``, ``# stiffness_per_load = 0.001 1/um``, ``# law = aging``.

A load-point velocity column is read as a piecewise-constant history (each
row's velocity holds until the next row, as a servo's set point does); a
displacement column as piecewise linear (the velocity of each interval is its
displacement over its duration).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from ..core.noise import noise_level
from ..units import Q_, ureg
from ..userwarnings import warn
from . import text
from .errors import DataError
from .tables import MAX_BYTES, check_file, parse_header

__all__ = ["LabRecord", "read_lab_record"]

FloatArray = npt.NDArray[np.float64]

VELOCITY = ("load-point velocity", "load_point_velocity", "loadpoint velocity", "velocity")
DISPLACEMENT = (
    "load-point displacement",
    "load_point_displacement",
    "loadpoint displacement",
    "displacement",
)
FRICTION = ("friction", "mu", "friction coefficient")


@dataclass(frozen=True)
class LabRecord:
    """A laboratory record in SI units.

    Attributes
    ----------
    name : str
        File name.
    time : ndarray
        Sample times (s), strictly increasing.
    velocity : ndarray
        Load-point velocity of each interval ``[time[i], time[i+1])`` (m/s), one per sample
        (the last repeats the one before it when read from displacements).
    displacement : ndarray
        Load-point displacement at each sample (m), from the first.
    friction : ndarray or None
        Measured friction (dimensionless), when the file has it.
    metadata : dict
        Every ``# key = value`` header line.

    """

    name: str
    time: FloatArray
    velocity: FloatArray
    displacement: FloatArray
    friction: FloatArray | None = None
    metadata: dict[str, str] = field(default_factory=dict)

    def history(self) -> list[tuple[Any, Any]]:
        """Return the load-point history as ``(duration, velocity)`` quantities, equal neighbours merged."""
        dt = np.diff(self.time)
        v = self.velocity[:-1]
        out: list[tuple[float, float]] = []  # SI
        for d, vi in zip(dt, v, strict=True):
            if out and out[-1][1] == vi:
                out[-1] = (out[-1][0] + float(d), out[-1][1])
            else:
                out.append((float(d), float(vi)))
        return [(Q_(d, "s"), Q_(v, "m/s")) for d, v in out]


def _column(names: list[str], choices: tuple[str, ...]) -> str | None:
    return next((c for c in choices if c in names), None)


def _si(values: FloatArray, unit: Any, name: str, dimension: str, example: str, where: str) -> FloatArray:
    if unit is None:
        raise DataError(f"{where}: column {name!r} has no unit; write e.g. '{name} [{example}]'")
    q = ureg.Quantity(1.0, unit)
    if not q.check(dimension):
        raise DataError(
            f"{where}: column {name!r} has unit [{unit:~}], expected {dimension} (e.g. [{example}])"
        )
    return values * float(q.to_base_units().magnitude)


def read_lab_record(path: str | os.PathLike[str], *, need_friction: bool = False) -> LabRecord:
    """Read a velocity-step or slide-hold-slide record (or a load-point history).

    Parameters
    ----------
    path : str or path-like
        The CSV/TSV file.
    need_friction : bool, optional
        Require a ``friction`` column (for a fit).

    Raises
    ------
    DataError
        Missing or malformed file, missing column, wrong unit, a value that is not a
        number, time not strictly increasing, a negative velocity; the message names
        the file, the column and the row.

    """
    p = check_file(path, MAX_BYTES)
    layout = text.inspect(p)
    parsed = [parse_header(c, p) for c in layout.header]
    names = [n for n, _ in parsed]
    units = dict(parsed)
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:  # pandas failed on it: "malformed rows"
        raise DataError(f"{p}: column {dup[0]!r} appears more than once")
    if "time" not in names:
        raise DataError(
            f"{p}: missing column 'time' (found {names}); expected 'time [s]', "
            "'load-point velocity [um/s]' (or 'load-point displacement [um]') and 'friction [1]'"
        )
    vcol = _column(names, VELOCITY)
    xcol = _column(names, DISPLACEMENT)
    fcol = _column(names, FRICTION)
    if vcol is None and xcol is None:
        raise DataError(
            f"{p}: missing a load-point column (found {names}); expected 'load-point velocity [um/s]' "
            "or 'load-point displacement [um]'"
        )
    if need_friction and fcol is None:
        raise DataError(f"{p}: missing column 'friction' (found {names}); expected 'friction [1]'")
    wanted = [c for c in ("time", vcol, xcol, fcol) if c is not None]
    frame = text.read_frame(layout, names, numeric=wanted)
    if len(frame) < 2:
        raise DataError(f"{p}: {len(frame)} data row(s); a record needs at least two")
    if frame[wanted].isna().any().any():
        text.diagnose(layout, names, numeric=wanted, nan_is_error=True)
        raise DataError(f"{p}: missing values")  # pragma: no cover - diagnose raises first
    t = _si(frame["time"].to_numpy(float), units["time"], "time", "[time]", "s", p)
    dt = np.diff(t)
    if np.any(dt <= 0):
        i = int(np.argmax(dt <= 0))
        a, b = text.data_lines(layout, [i, i + 1])
        raise DataError(
            f"{p}: time is not strictly increasing at lines {a}-{b} "
            f"({float(t[i])!r} s then {float(t[i + 1])!r} s)"
        )
    if vcol is not None:
        v = _si(frame[vcol].to_numpy(float), units[vcol], vcol, "[length] / [time]", "um/s", p)
        x = np.concatenate([[0.0], np.cumsum(v[:-1] * dt)])
        if xcol is not None:  # both given: the velocity is used, and the displacement said if it differs
            xd = _si(frame[xcol].to_numpy(float), units[xcol], xcol, "[length]", "um", p)
            off = np.abs((xd - xd[0]) - x)
            i = int(np.argmax(off))
            # beyond 1 % of the travel and ten times the displacement's own noise (a measured
            # displacement is noisy: a hold's 0.02 um, a slide-hold-slide's 0.5 um warned once)
            floor = 10.0 * noise_level(xd) if xd.size >= 8 else 0.0
            if off[i] > max(0.01 * max(float(np.ptp(x)), float(np.ptp(xd))), floor):
                (line,) = text.data_lines(layout, [i])
                warn(
                    f"{p}: the load-point displacement disagrees with the velocity column by "
                    f"{off[i] * 1e6:.3g} um at line {line} (the velocity, held until the next row, is "
                    f"used): give one of the two columns"
                )
    else:
        assert xcol is not None
        x = _si(frame[xcol].to_numpy(float), units[xcol], xcol, "[length]", "um", p)
        x = x - x[0]
        vi = np.diff(x) / dt
        v = np.concatenate([vi, vi[-1:]])
    if np.any(v < 0):
        i = int(np.argmax(v < 0))
        (line,) = text.data_lines(layout, [i + 1 if vcol is None else i])  # from displacements: the later
        raise DataError(
            f"{p}: the load-point velocity is negative at line {line} ({v[i]:.3g} m/s); "
            "the model drives the slider forward (holds have velocity 0)"
        )
    mu = None
    if fcol is not None:
        f = frame[fcol].to_numpy(float)
        if units[fcol] is not None and not ureg.Quantity(1.0, units[fcol]).check(""):
            raise DataError(
                f"{p}: column {fcol!r} has unit [{units[fcol]:~}], expected a dimensionless friction [1]"
            )
        # in the unit given: 60 % is 0.6 (it was taken as 60)
        mu = f if units[fcol] is None else f * float(ureg.Quantity(1.0, units[fcol]).to("").magnitude)
    return LabRecord(os.path.basename(p), t, v, x, mu, dict(layout.meta))


def format_lab_record(
    time: FloatArray,
    velocity: FloatArray,
    friction: FloatArray,
    extra: dict[str, FloatArray] | None = None,
    metadata: dict[str, str] | None = None,
) -> str:
    """Return a record as :func:`read_lab_record` reads it: ``# key = value`` lines, then the columns.

    ``time`` in s, the load-point ``velocity`` in m/s (written in um/s, held until the
    next row), ``friction``; ``extra`` columns are written as given (their header
    names the unit).
    """
    cols = {
        "time [s]": np.asarray(time, dtype=float),
        "load-point velocity [um/s]": np.asarray(velocity, dtype=float) * 1e6,
        "friction [1]": np.asarray(friction, dtype=float),
        **(extra or {}),
    }
    # the first line marks the file as stickslip's (so that a rerun may replace it)
    lines = text.header_lines("rate-and-state record", metadata or {}, cols)
    data = np.column_stack(list(cols.values()))
    lines += [",".join(repr(float(x)) for x in row) for row in data]
    return "\n".join(lines) + "\n"
