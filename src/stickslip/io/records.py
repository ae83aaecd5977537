"""Reading measured force-time records.

A record is a CSV or TSV file with a header row whose cells give units in
brackets: ``time [s]`` and ``force [mN]`` (also accepted: ``spring_force``,
``friction_force``), optionally ``displacement [um]`` and/or ``velocity [um/s]``.
Lines starting with ``#`` before the header may carry metadata as
``# key = value``, e.g. ``# v0 = 10 um/s`` and ``# load = 196 mN``.

A folder of records has one file per record and either an index file
(``index.csv`` with columns ``file``, ``v0 [unit]`` and optionally ``load [unit]``)
or the metadata in each file's header lines. One long table with a ``record``
column (and ``v0``/``load`` columns) holds several records at once.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import partial
from typing import Any

import numpy as np
import numpy.typing as npt
import pandas as pd
import pint

from ..errors import ArgumentTypeError
from ..units import parse_quantity, ureg
from ..userwarnings import warn
from . import text
from .errors import DataError
from .formats import (
    BINARY_SUFFIXES,
    QUANTITIES,
    RecordOptions,
    apply_name_pattern,
    pick_record,
    read_arrays,
    read_sidecar,
)
from .tables import check_file, header_name, parse_header, split_header

__all__ = ["Record", "UnreadableRecord", "format_record", "read_record", "read_records", "write_record"]

FORCE_NAMES = ("force", "spring_force", "friction_force")
MAX_BYTES = 20_000_000_000  # beyond the memory check, a plain bound

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Record:
    """One measured record in SI units.

    Attributes
    ----------
    name : str
        File name or record label.
    time : ndarray
        Sample times (s), strictly increasing.
    force : ndarray
        Spring (friction) force (N).
    displacement, velocity : ndarray or None
        Slider displacement (m) and velocity (m/s) when recorded.
    v0, load : pint.Quantity or None
        Driving velocity and normal load, from the index or the header lines.
    metadata : dict
        Every ``# key = value`` header line.
    stiffness, mass : pint.Quantity or None
        The spring's stiffness and the slider's mass as the set-up states them
        (nominal values: :func:`stickslip.data.motion.measure_motion` measures the
        effective ones).

    """

    name: str
    time: FloatArray
    force: FloatArray
    displacement: FloatArray | None = None
    velocity: FloatArray | None = None
    v0: pint.Quantity | None = None
    load: pint.Quantity | None = None
    metadata: Mapping[str, str] = field(default_factory=dict)
    stiffness: pint.Quantity | None = None
    mass: pint.Quantity | None = None

    def __post_init__(self) -> None:
        # arrays as the readers make them: a 2-D force broadcast into an n x n array (and ran out
        # of memory), lists failed on .size, NaN and repeated times went on silently
        if not isinstance(self.name, str):
            raise ArgumentTypeError(f"name={self.name!r}: expected a str")
        n = None
        for key, unit in (("time", "s"), ("force", "N"), ("displacement", "m"), ("velocity", "m/s")):
            value = getattr(self, key)
            if value is None and key in ("displacement", "velocity"):
                continue
            if isinstance(value, str | bytes):
                raise ArgumentTypeError(
                    f"{self.name}: {key}: expected numbers ({unit}), got {type(value).__name__}"
                )
            try:
                arr = np.asarray(value, dtype=float)
            except (TypeError, ValueError):
                raise ArgumentTypeError(
                    f"{self.name}: {key}: expected numbers ({unit}), got {type(value).__name__}"
                ) from None
            if arr.ndim != 1:
                raise ValueError(
                    f"{self.name}: {key}: expected a 1-D array of samples ({unit}), got shape {arr.shape}"
                )
            if n is None:
                n = arr.size
            elif arr.size != n:
                raise ValueError(f"{self.name}: {key} has {arr.size} samples, time has {n}")
            bad = ~np.isfinite(arr)
            if bad.any():
                i = int(np.argmax(bad))
                shown = float(arr[i])
                raise ValueError(f"{self.name}: {key}[{i}]={shown!r}: expected finite values ({unit})")
            object.__setattr__(self, key, arr)
        problem = _clock_problem(self.time, "time", _samples)
        if problem:
            raise ValueError(f"{self.name}: {problem}")
        # v0=1e-5 (no unit) failed later with an AttributeError on .to
        for key, dim, example in (
            ("v0", "[length] / [time]", "10 um/s"),
            ("load", "[force]", "196 mN"),
            ("stiffness", "[force] / [length]", "168 N/m"),
            ("mass", "[mass]", "30.7 g"),
        ):
            value = getattr(self, key)
            if value is not None:
                object.__setattr__(self, key, parse_quantity(value, key, dim, example))


def _si(
    values: FloatArray, unit: pint.Unit | None, name: str, dimension: str, si: str, where: str
) -> FloatArray:
    if unit is None:
        raise DataError(f"{where}: column {name!r} has no unit; write e.g. '{name} [{si}]'")
    q = ureg.Quantity(1.0, unit)
    if not q.check(dimension):
        raise DataError(f"{where}: column {name!r} has unit [{unit:~}], expected {dimension} (e.g. [{si}])")
    return values * float(q.to(si).magnitude)


#: the shortest median sample interval of a record (s): a molecular-dynamics trace samples in
#: femtoseconds (1e-15 s) and is measured as any record; 1e-302 s ended in 'SVD did not converge'
MIN_SAMPLE_INTERVAL = 1e-200


def _clock_problem(t: FloatArray, name: str, at: Callable[[int, int], str]) -> str | None:
    """Return what is wrong with a record's sample times ``t`` (s), or None.

    The times must increase strictly (``at(i, j)`` names samples ``i`` and ``j`` where
    they do not: sample numbers, or a file's lines), and the median interval must be at
    least :data:`MIN_SAMPLE_INTERVAL` (1e-302 s ended in 'SVD did not converge').
    """
    step = np.diff(t)
    if np.any(step <= 0):
        i = int(np.argmax(step <= 0))
        return (
            f"{name} is not strictly increasing at {at(i, i + 1)} "
            f"({float(t[i])!r} s then {float(t[i + 1])!r} s)"
        )
    if step.size and float(np.median(step)) < MIN_SAMPLE_INTERVAL:
        return (
            f"the median sample interval is {float(np.median(step)):.3g} s, below {MIN_SAMPLE_INTERVAL:g} s: "
            "is the time column in the unit its header says?"
        )
    return None


def _samples(i: int, j: int) -> str:
    return f"samples {i} and {j}"


def _lines(df: pd.DataFrame, first: int, last: int | None = None) -> str:
    """Name the file lines of ``df``'s rows ``first`` to ``last`` (positions).

    ``line 7``; ``lines 7-9``; in a long table whose records' rows interleave,
    ``lines 8 and 10`` or ``lines 8 to 14 (among other records' rows)``.
    """
    last = first if last is None else last
    layout = df.attrs.get("layout")
    if layout is None:  # pragma: no cover - every frame here comes from _read
        return f"rows {first + 1}-{last + 1}"
    a, b = text.data_lines(layout, [int(df.index[first]), int(df.index[last])])
    if a == b:
        return f"line {a}"
    if int(df.index[last]) - int(df.index[first]) == last - first:  # no other record's row between
        return f"lines {a}-{b}"
    return f"lines {a} and {b}" if last == first + 1 else f"lines {a} to {b} (among other records' rows)"


def _written(df: pd.DataFrame, col: str) -> str:
    """Return column ``col``'s header cell as the file writes it (``col`` itself when unknown)."""
    return str(df.attrs.get("header", {}).get(col, col))


def _check_numeric(df: pd.DataFrame, col: str, where: str) -> FloatArray:
    """Return a float column, refusing missing or NaN values with a summary of where they are."""
    v = df[col].to_numpy(dtype=float)
    col = _written(df, col)
    nan = np.isnan(v)
    if nan.any():
        starts = np.flatnonzero(nan & ~np.concatenate([[False], nan[:-1]]))
        ends = np.flatnonzero(nan & ~np.concatenate([nan[1:], [False]]))
        longest = int(np.argmax(ends - starts))
        raise DataError(
            f"{where}: column {col!r} has {int(nan.sum())} missing/NaN values in {starts.size} "
            f"run(s), the longest {int(ends[longest] - starts[longest] + 1)} samples at "
            f"{_lines(df, int(starts[longest]), int(ends[longest]))}; fill or cut them before analysis"
        )
    return v


#: columns read as numbers (when present) and as text
NUMERIC = ("time", *FORCE_NAMES, "displacement", "velocity", "v0", "load", "stiffness", "mass")
TEXT = ("record", "file")
#: other names of an index's columns (an index has no sample velocity: 'velocity' is v0 there)
INDEX_ALIASES = {
    "driving velocity": "v0",
    "driving_velocity": "v0",
    "drive velocity": "v0",
    "velocity": "v0",
    "v_0": "v0",
    "normal load": "load",
    "normal_load": "load",
    "normal force": "load",
    "normal_force": "load",
    "k": "stiffness",
    "spring stiffness": "stiffness",
    "m": "mass",
}


#: other names of the metadata lines giving v0 and load (keys as read: lower case, '_')
META_ALIASES = {text.meta_key(k): v for k, v in INDEX_ALIASES.items()} | {
    "driving_speed": "v0",
    "sliding_velocity": "v0",
    "sliding_speed": "v0",
    "speed": "v0",
    "fn": "load",
    "f_n": "load",
    "k": "stiffness",
    "spring_stiffness": "stiffness",
    "spring_constant": "stiffness",
    "m": "mass",
    "slider_mass": "mass",
}


def _from_meta(meta: Mapping[str, str], key: str, where: str) -> str | None:
    """Return the metadata's value for ``v0`` or ``load``, under its name or another one.

    Two lines that give it different values (``# v0 = 10 um/s`` and ``# speed = 20 um/s``)
    are an error naming both; an empty value (``# Load:``, a section title) gives none.
    """
    found = [(k, v) for k, v in meta.items() if (k == key or META_ALIASES.get(k) == key) and v.strip()]
    found.sort(key=lambda kv: kv[0] != key)  # its own name first
    if len(found) > 1:
        # pint's parse errors are many (a value that is not a quantity, units that differ): then
        # the texts must agree
        try:
            q: list[pint.Quantity] = [ureg.Quantity(v) for _, v in found]
            agree = all(np.isclose(float((x / q[0]).to("").magnitude), 1.0, rtol=1e-12, atol=0) for x in q)
        except Exception:
            agree = len({v for _, v in found}) == 1
        if not agree:
            shown = " and ".join(f"'# {k} = {v}'" for k, v in found)
            raise DataError(f"{where}: header lines {shown} both give {key} and disagree")
    return found[0][1] if found else None


#: instruments' names of a record's columns (a tribometer's Fx is the friction force)
RECORD_ALIASES = {
    "t": "time",
    "fx": "friction_force",
    "ff": "friction_force",
    "friction force": "friction_force",
    "lateral force": "friction_force",
    "tangential force": "friction_force",
    "spring force": "spring_force",
}


def _header_hint(cells: Sequence[str], where: str) -> str:
    """Return the hint of a header naming no known column: a title line, or the names to use."""
    if not all(split_header(c, where)[1] for c in cells if c.strip()):  # not all 'name [unit]'
        return " (a title line? put '# ' before it)"
    names = sorted({*NUMERIC, *RECORD_ALIASES})
    return f" (columns are named {', '.join(names)}: rename yours, keeping the units)"


class NotARecord(DataError):
    """A file whose header names no column a record has (a README in a folder of records)."""


def _read(
    path: str, where: str, aliases: Mapping[str, str] | None = None
) -> tuple[pd.DataFrame, dict[str, pint.Unit | None], dict[str, str]]:
    """Read a record file (or a long table, or an index) into a frame of its known columns.

    A column stickslip does not read may have any unit (``raw [LSB]``); ``aliases``
    renames columns (an index's ``driving velocity`` is its ``v0``).
    """
    layout = text.inspect(path, where)
    aliases = aliases or {}
    parsed = []
    for cell in layout.header:
        raw = header_name(cell, where)
        name = aliases.get(raw, raw)
        unit: pint.Unit | None = None  # a column that is not read: its unit does not matter
        if name in NUMERIC + TEXT:
            unit = parse_header(cell, where)[1]
        parsed.append((name, unit))
    names = [n for n, _ in parsed]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise DataError(f"{where}: column {sorted(dup)[0]!r} appears more than once")
    numeric = [n for n in names if n in NUMERIC]
    textual = [n for n in names if n in TEXT]
    if not numeric and not textual:  # pandas failed inside with an IndexError
        raise NotARecord(
            f"{where}: line {layout.header_line} is taken for the header, and names no known column "
            f"({layout.header!r}); expected 'time [s]' and 'force [N]'{_header_hint(layout.header, where)}"
        )
    frame = text.read_frame(layout, names, numeric=numeric, text=textual, where=where)
    if len(frame) == 0:
        raise DataError(f"{where}: the file has a header but no data rows")
    frame.attrs["layout"] = layout  # for messages naming a file line (groupby keeps attrs and labels)
    # and the header's cells as written, for messages naming a column the user knows ('Fx [mN]',
    # not the 'friction_force' it is read as)
    frame.attrs["header"] = {n: cell.strip() for (n, _), cell in zip(parsed, layout.header, strict=True)}
    return frame, dict(parsed), dict(layout.meta)


def _record_from_frame(
    df: pd.DataFrame,
    units: Mapping[str, pint.Unit | None],
    meta: Mapping[str, str],
    name: str,
    where: str,
    v0: Any = None,
    load: Any = None,
    stiffness: Any = None,
    mass: Any = None,
) -> Record:
    if "time" not in df.columns:
        raise DataError(
            f"{where}: missing column 'time' (found {list(df.columns)}); expected 'time [s]' and 'force [N]'"
        )
    forces = [c for c in FORCE_NAMES if c in df.columns]
    if not forces:
        raise DataError(
            f"{where}: missing a force column ('force', 'spring_force' or "
            f"'friction_force'; found {list(df.columns)})"
        )
    force_col = forces[0]
    if len(forces) > 1:
        warn(
            f"{where}: columns {', '.join(map(repr, forces))}: the force analysed is {force_col!r}",
        )
    if len(df) < 3:
        raise DataError(f"{where}: only {len(df)} samples; a record needs many cycles")
    t = _si(_check_numeric(df, "time", where), units["time"], _written(df, "time"), "[time]", "s", where)
    f = _si(
        _check_numeric(df, force_col, where), units[force_col], _written(df, force_col), "[force]", "N", where
    )
    problem = _clock_problem(t, "time", lambda i, j: _lines(df, i, j))
    if problem:
        raise DataError(f"{where}: {problem}")

    def optional(col: str, dimension: str, si: str) -> FloatArray | None:
        if col not in df.columns:
            return None
        return _si(_check_numeric(df, col, where), units[col], _written(df, col), dimension, si, where)

    x = optional("displacement", "[length]", "m")
    v = optional("velocity", "[length] / [time]", "m/s")
    for key, given in (("v0", v0), ("load", load)):
        if isinstance(given, float) and np.isnan(given):  # it dropped the header's value, unsaid
            raise DataError(f"{where}: {key}=nan: expected a quantity, or None for the header's")
    # an empty header value ('# Load:', a section title) gives none, as a missing line does
    v0q = _quantity(
        v0 if v0 is not None else _from_meta(meta, "v0", where), "v0", "[length] / [time]", "10 um/s", where
    )
    loadq = _quantity(
        load if load is not None else _from_meta(meta, "load", where), "load", "[force]", "196 mN", where
    )
    kq = _quantity(
        stiffness if stiffness is not None else _from_meta(meta, "stiffness", where),
        "stiffness",
        "[force] / [length]",
        "168 N/m",
        where,
    )
    mq = _quantity(
        mass if mass is not None else _from_meta(meta, "mass", where), "mass", "[mass]", "30.7 g", where
    )
    meta = dict(meta)
    for key, given, used in (
        ("v0", v0, v0q),
        ("load", load, loadq),
        ("stiffness", stiffness, kq),
        ("mass", mass, mq),
    ):
        if given is not None and used is not None:  # the metadata say what the record's quantities are
            meta[key] = f"{used.magnitude!r} {used.units}"
    return Record(name, t, f, x, v, v0q, loadq, meta, kq, mq)


def _quantity(value: Any, name: str, dimension: str, example: str, where: str) -> pint.Quantity | None:
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return None
    try:
        return parse_quantity(value, name, dimension, example)
    except ValueError as exc:
        raise DataError(f"{where}: {exc}") from None


def read_record(
    path: str | os.PathLike[str],
    *,
    v0: Any = None,
    load: Any = None,
    stiffness: Any = None,
    mass: Any = None,
    options: RecordOptions | None = None,
) -> Record:
    """Read one force-time record: a text table, or a file a laboratory's software writes.

    Parameters
    ----------
    path : str or path-like
        The file: CSV/TSV/text (units in the header), MATLAB ``.mat`` (v5 or v7.3),
        HDF5, ``.npy``/``.npz``, Excel ``.xlsx`` or TDMS (:mod:`stickslip.io.formats`).
    v0, load, stiffness, mass : quantity or str, optional
        Driving velocity, normal load, spring stiffness and slider mass; they override
        a sidecar ``NAME.json``, the file name (``options.name_pattern``) and the file's
        own metadata, in that order. ``load="weight"`` is the slider's weight, mass times
        standard gravity (a slider pressed by its own weight).
    options : RecordOptions, optional
        Which variables hold the time and the force, whether the force is normalised by
        the load (F/W, multiplied by the load here), their units, a name pattern.

    Raises
    ------
    ValueError
        For a missing, empty or huge file, a missing column, an unknown unit, a
        cell that is not a number, a run of NaN, or time that does not increase.

    """
    p = check_file(path, MAX_BYTES)
    opts = options if options is not None else RecordOptions()
    if not isinstance(opts, RecordOptions):
        raise TypeError(f"options: expected RecordOptions, got {type(opts).__name__}")
    side = read_sidecar(p)
    named = apply_name_pattern(opts.name_pattern, p) if opts.name_pattern else {}
    if side and any(k in side for k in ("time", "force", "normalised")):
        opts = RecordOptions(
            time=opts.time or side.get("time"),
            force=opts.force or side.get("force"),
            normalised=opts.normalised
            if opts.normalised is not None
            else (
                {"true": True, "false": False}.get(side["normalised"].lower())
                if "normalised" in side
                else None
            ),
            time_unit=opts.time_unit,
            force_unit=opts.force_unit,
            name_pattern=opts.name_pattern,
        )
    given = {"v0": v0, "load": load, "stiffness": stiffness, "mass": mass}
    for key in given:
        if given[key] is None:
            given[key] = side.get(key, named.get(key))
    binary = p.lower().endswith(BINARY_SUFFIXES)
    if not binary and opts == RecordOptions(name_pattern=opts.name_pattern):
        df, units, meta = _read(p, p, RECORD_ALIASES)
        mass_q = given["mass"] if given["mass"] is not None else _from_meta(meta, "mass", p)
        given["load"] = _weight(given["load"], mass_q, p)
        return _record_from_frame(df, units, meta, os.path.basename(p), p, **given)
    arrays, file_units, meta = read_arrays(p)
    t, f, normalised, notes = pick_record(arrays, file_units, meta, opts, p)
    meta = {text.meta_key(str(k)): str(v) for k, v in meta.items()}
    values = {
        key: given[key] if given[key] is not None else _from_meta(meta, key, p)
        for key in ("v0", "load", "stiffness", "mass")
    }
    values["load"] = _weight(values["load"], values["mass"], p)
    q = {key: _quantity(values[key], key, dim, example, p) for key, (dim, example) in QUANTITIES.items()}
    if normalised:
        if q["load"] is None:
            raise DataError(
                f"{p}: the force {notes['force_variable']!r} is normalised by the load (F/W): give the load "
                "(--load '0.3 N', or --load weight with --mass, or in a sidecar NAME.json)"
            )
        f = f * float(q["load"].to("N").magnitude)
    problem = _clock_problem(t, f"time {notes['time_variable']!r}", _samples)
    if problem:
        raise DataError(f"{p}: {problem}")
    meta = dict(meta) | notes
    for key, used in q.items():
        if used is not None:
            meta[key] = f"{used.magnitude!r} {used.units}"
    return Record(os.path.basename(p), t, f, None, None, q["v0"], q["load"], meta, q["stiffness"], q["mass"])


#: standard gravity (m/s^2), for a load given as the slider's weight
STANDARD_GRAVITY = 9.80665


def _weight(load: Any, mass: Any, where: str) -> Any:
    """Return ``load``, or the slider's weight where it is ``"weight"`` (mass times standard gravity)."""
    if not (isinstance(load, str) and load.strip().lower() in ("weight", "mg", "m g")):
        return load
    if mass is None:
        raise DataError(f"{where}: load='weight' is the slider's weight: give the mass too (--mass '30.7 g')")
    m = _quantity(mass, "mass", "[mass]", "30.7 g", where)
    assert m is not None
    return (m * ureg.Quantity(STANDARD_GRAVITY, "m/s^2")).to("N")


class UnreadableRecord(UserWarning):
    """A record of several that could not be read, left out (``read_records(on_error="warn")``).

    Attributes
    ----------
    name : str
        The record: its file's name in a folder, its name in a long table.
    reason : str
        Why, as :func:`read_record` would have raised it.

    """

    def __init__(self, name: str, reason: str) -> None:
        super().__init__(f"{name}: not read: {reason}")
        self.name = name
        self.reason = reason


def read_records(
    path: str | os.PathLike[str],
    *,
    on_error: str = "raise",
    options: RecordOptions | None = None,
    **setup: Any,
) -> list[Record]:
    """Read several records: a folder (with ``index.csv`` or header lines) or one long table.

    A long table has a ``record`` column naming the record of each row, and may
    have ``v0 [unit]`` and ``load [unit]`` columns (constant within a record).

    Parameters
    ----------
    path : str or path-like
        The folder or the table.
    on_error : {"raise", "warn"}
        What a record that cannot be read (a run of NaN, a cell that is not a number,
        time that does not increase) does: raise, or, with ``"warn"``, leave the
        others to be read and issue an :class:`UnreadableRecord` warning naming it and
        why (as ``pandas.read_csv``'s ``on_bad_lines``). Problems of the folder or the
        table as a whole (no records, an index naming a missing file) raise either way,
        as does a source of which no record can be read.
    options : RecordOptions, optional
        How each file's time and force are taken (:func:`read_record`).
    **setup
        ``v0``, ``load``, ``stiffness``, ``mass`` for every record (as :func:`read_record`'s).

    Raises
    ------
    ValueError
        For a folder without records, index entries naming missing files, and
        every error of :func:`read_record`.

    """
    if not isinstance(on_error, str):
        raise ArgumentTypeError(f"on_error={on_error!r}: expected 'raise' or 'warn'")
    if on_error not in ("raise", "warn"):
        raise ValueError(f"on_error={on_error!r}: expected 'raise' or 'warn'")
    unknown = set(setup) - set(QUANTITIES)
    if unknown:
        raise TypeError(f"read_records: unexpected argument {sorted(unknown)[0]!r}")
    setup = {k: v for k, v in setup.items() if v is not None}
    p = os.fspath(path)
    unread: list[str] = []

    def attempt(name: str, read: Callable[[], Record]) -> Record | None:
        try:
            return read()
        except NotARecord:
            raise
        except DataError as exc:
            if on_error == "raise":
                raise
            unread.append(str(exc))
            warn(UnreadableRecord(name, str(exc)))
            return None

    def read_all(out: list[Record | None], what: str) -> list[Record]:
        got = [r for r in out if r is not None]
        if not got and unread:
            raise DataError(f"{p}: none of its {len(out)} {what} could be read: {unread[0]}")
        return got

    if os.path.isdir(p):
        index = os.path.join(p, "index.csv")
        files = sorted(
            f for f in os.listdir(p) if f.lower().endswith((".csv", ".tsv", ".txt", *BINARY_SUFFIXES))
        )
        if os.path.isfile(index):
            df, units, _ = _read(index, index, INDEX_ALIASES)
            if "file" not in df.columns:
                raise DataError(f"{index}: missing column 'file'")
            out = []
            named = set()
            listed: set[str] = set()  # real paths: day1/run.csv and day2/run.csv are two records
            for i, (_, row) in enumerate(df.iterrows()):
                f = os.path.join(p, str(row["file"]).strip())
                if not os.path.isfile(f):
                    raise DataError(f"{index}: names {row['file']!r}, which is not in {p}")
                if os.path.realpath(f) in listed:  # read twice, and counted twice in the criterion
                    raise DataError(
                        f"{index}: {_lines(df, i)} names {row['file']!r} again: list each record once"
                    )
                listed.add(os.path.realpath(f))
                named.add(os.path.basename(f))
                here = f"{index}: {_lines(df, i)} ({str(row['file']).strip()})"
                v0 = _quantity(
                    _with_unit(row.get("v0"), units.get("v0")), "v0", "[length] / [time]", "10 um/s", here
                )
                load = _quantity(
                    _with_unit(row.get("load"), units.get("load")), "load", "[force]", "196 mN", here
                )
                row_setup = {
                    key: _quantity(_with_unit(row.get(key), units.get(key)), key, dim, example, here)
                    for key, dim, example in (
                        ("stiffness", "[force] / [length]", "168 N/m"),
                        ("mass", "[mass]", "30.7 g"),
                    )
                }
                given = {k: v for k, v in ({"v0": v0, "load": load} | row_setup).items() if v is not None}
                out.append(
                    attempt(
                        os.path.basename(f),
                        partial(read_record, f, options=options, **(setup | given)),
                    )
                )
            left = [f for f in files if f not in named and f != "index.csv"]
            if left:
                shown = ", ".join(left[:5]) + (f" and {len(left) - 5} more" if len(left) > 5 else "")
                warn(
                    f"{index}: {len(left)} file(s) in the folder are not in the index and were not "
                    f"read: {shown}",
                    UserWarning,
                )
            return read_all(out, "indexed records")
        if not files:
            raise DataError(
                f"{p}: no .csv, .tsv or .txt records in the folder (nor {', '.join(BINARY_SUFFIXES)})"
            )
        if options is not None and options.name_pattern:
            matching = []
            for f in files:
                try:
                    apply_name_pattern(options.name_pattern, f)
                except DataError:
                    continue
                matching.append(f)
            if not matching:
                raise DataError(f"{p}: no file name matches the name pattern {options.name_pattern!r}")
            files = matching
        out = []
        why: list[str] = []
        for f in files:
            try:
                out.append(attempt(f, partial(read_record, os.path.join(p, f), options=options, **setup)))
            except NotARecord as exc:  # a README.txt, notes: not a record, said and left out
                why.append(str(exc))
                warn(f"not a record, skipped: {exc}", UserWarning)
        if not out:
            # with the first file's reason (a folder of exports with a title line): the user sees
            # what to change
            raise DataError(
                f"{p}: none of its {len(files)} .csv, .tsv or .txt files is a record (the first: {why[0]})"
            )
        return read_all(out, "records")
    if not os.path.isfile(p):
        raise DataError(f"{p}: no such file or folder")
    check_file(p, MAX_BYTES)
    if p.lower().endswith(BINARY_SUFFIXES) or (options is not None and options != RecordOptions()) or setup:
        return [read_record(p, options=options, **setup)]
    df, units, meta = _read(p, p, RECORD_ALIASES)
    if "record" not in df.columns:
        return [_record_from_frame(df, units, meta, os.path.basename(p), p)]
    names = df["record"]
    blank = names.isna() | (names.astype(str).str.strip() == "")
    if blank.any():  # groupby skipped such rows without a word
        i = int(np.flatnonzero(blank.to_numpy())[0])
        raise DataError(f"{p}: {_lines(df, i)} has no record name (column 'record' is empty)")
    out = []
    for name, part in df.groupby("record", sort=False):
        out.append(attempt(str(name), partial(_table_record, part, units, meta, str(name), p)))
    return read_all(out, "records")


def _table_record(
    part: pd.DataFrame, units: Mapping[str, pint.Unit | None], meta: Mapping[str, str], name: str, path: str
) -> Record:
    """Return record ``name`` of a long table: its rows ``part``, its v0 and load from its columns."""
    where = f"{path} (record {name!r})"
    v0 = _constant(part, "v0", units, where)
    load = _constant(part, "load", units, where)
    return _record_from_frame(part, units, meta, name, where, v0, load)


def _with_unit(value: Any, unit: pint.Unit | None) -> Any:
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return None
    if unit is None:
        return str(value)
    return f"{float(value)!r} {unit}"  # a text: a message shows it as written, not a Quantity's repr


def _constant(df: pd.DataFrame, col: str, units: Mapping[str, pint.Unit | None], where: str) -> Any:
    if col not in df.columns:
        return None
    vals = pd.to_numeric(df[col], errors="coerce").to_numpy(dtype=float)
    if np.any(np.isnan(vals)) or np.ptp(vals) != 0:
        raise DataError(f"{where}: column {col!r} must hold one number per record")
    return _with_unit(float(vals[0]), units.get(col))


def format_record(record: Record, *, force_unit: str = "mN") -> str:
    """Return ``record`` as the CSV text :func:`read_record` reads.

    A first line marking the file as stickslip's, the metadata as ``# key = value``
    lines (``v0`` and ``load`` with their units), then ``time [s]``, ``force
    [force_unit]`` and, when recorded, ``displacement [um]`` and ``velocity
    [um/s]``, every number written in full (``repr``).

    Raises
    ------
    ValueError
        For a ``force_unit`` that is not a unit of force.

    """
    if not isinstance(force_unit, str):
        raise ArgumentTypeError(f"force_unit={force_unit!r}: expected a unit of force, e.g. 'mN' or 'N'")
    try:
        to_unit = float(ureg.Quantity(1.0, "N").to(force_unit).magnitude)
    except Exception:  # pint's parser raises what it meets (a TokenError for 'mN]')
        raise ValueError(f"force_unit={force_unit!r}: expected a unit of force, e.g. 'mN' or 'N'") from None
    if not isinstance(record, Record):  # write_record(path, record) failed on 'str'.metadata
        raise TypeError(f"record: expected a stickslip Record, got {type(record).__name__}")
    meta = {k: v for k, v in record.metadata.items() if text.meta_key(str(k)) not in ("v0", "load")}
    if record.v0 is not None:
        meta["v0"] = f"{float(record.v0.to('um/s').magnitude)!r} um/s"
    if record.load is not None:
        meta["load"] = f"{float(record.load.to('mN').magnitude)!r} mN"
    cols = {"time [s]": np.asarray(record.time, float), f"force [{force_unit}]": record.force * to_unit}
    if record.displacement is not None:
        cols["displacement [um]"] = np.asarray(record.displacement, float) * 1e6
    if record.velocity is not None:
        cols["velocity [um/s]"] = np.asarray(record.velocity, float) * 1e6
    lines = text.header_lines("force-time record", meta, cols)
    data = np.column_stack(list(cols.values()))
    lines += [",".join(repr(float(x)) for x in row) for row in data]
    return "\n".join(lines) + "\n"


def write_record(
    record: Record,
    path: str | os.PathLike[str],
    *,
    force_unit: str = "mN",
    out: Any = None,
    overwrite: bool = False,
) -> str:
    """Write ``record`` as a CSV file that :func:`read_record` reads back; return its path.

    The file is written atomically; an existing file that stickslip did not write
    is kept unless ``overwrite``. With ``out`` (an
    :class:`~stickslip.io.output.OutputFolder`) ``path`` is a name inside it.
    """
    from .output import emit

    text_ = format_record(record, force_unit=force_unit)

    def write(p: str) -> None:
        with open(p, "w", encoding="utf-8") as f:
            f.write(text_)

    return emit(os.fspath(path), "record", write, out=out, overwrite=overwrite)
