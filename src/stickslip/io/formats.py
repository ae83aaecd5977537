"""Reading the files laboratories write: MATLAB, HDF5, NumPy, Excel, TDMS and free-form text.

Each reader returns the file's one-dimensional numeric variables by name, the units
the file states for them (an HDF5 or TDMS attribute ``units``/``unit_string``, a
spreadsheet or text header cell ``name [unit]``) and its metadata (HDF5 root
attributes, TDMS file properties, ``# key = value`` lines); :func:`pick_record`
then takes the time and force among them, by the caller's names or by a documented
guess, and makes a :class:`~stickslip.io.records.Record`.

The readers are the formats' own libraries: :func:`scipy.io.loadmat` for MATLAB v5
files, h5py for MATLAB v7.3 and plain HDF5, NumPy for ``.npy``/``.npz``, openpyxl
for ``.xlsx``, nptdms for National Instruments TDMS. h5py, openpyxl and nptdms come
with the ``lab`` extra (``pip install 'stickslip[lab]'``); a file that needs one
that is missing gets a one-line error naming it.
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ..errors import ArgumentTypeError
from ..units import ureg
from .errors import DataError

__all__ = [
    "BINARY_SUFFIXES",
    "RecordOptions",
    "apply_name_pattern",
    "pick_record",
    "read_arrays",
    "read_sidecar",
]

FloatArray = npt.NDArray[np.float64]
#: a file's 1-D variable: float64 numbers, or the text it holds where it holds text (named in errors)
Column = npt.NDArray[Any]

#: the file name endings read by :func:`read_arrays` (the text formats have their own reader)
BINARY_SUFFIXES = (".mat", ".h5", ".hdf5", ".hdf", ".npy", ".npz", ".xlsx", ".xlsm", ".tdms")
#: names taken for the time when none is given (compared in lower case)
TIME_GUESSES = ("time", "t", "times", "time_s", "temps", "timestamp")
#: names taken for a force (N, or the file's unit)
FORCE_GUESSES = (
    "force",
    "spring_force",
    "friction_force",
    "f",
    "fx",
    "ft",
    "ff",
    "friction force",
    "lateral force",
)
#: names taken for a force normalised by the normal load (a friction coefficient, F/W)
NORMALISED_GUESSES = (
    "fnorm",
    "f_norm",
    "mu",
    "friction",
    "friction_coefficient",
    "friction coefficient",
    "cof",
)
#: a variable this long or longer is a record's column; shorter ones are metadata
MIN_SAMPLES = 3
#: the unit a name pattern's field has when it names none ('k{stiffness}Nm_v{v0}')
PATTERN_UNITS = {"stiffness": "N/m", "v0": "um/s", "mass": "g", "load": "N"}
#: the dimension and an example of each metadata quantity
QUANTITIES = {
    "v0": ("[length] / [time]", "42 um/s"),
    "load": ("[force]", "0.301 N"),
    "stiffness": ("[force] / [length]", "168 N/m"),
    "mass": ("[mass]", "30.7 g"),
}


@dataclass(frozen=True)
class RecordOptions:
    """How to take a record from a file whose variables are not named as stickslip's.

    Attributes
    ----------
    time, force : str or None
        The variables (or columns) holding the time and the force; None guesses
        (:data:`TIME_GUESSES`, :data:`FORCE_GUESSES`, :data:`NORMALISED_GUESSES`).
    normalised : bool or None
        The force is divided by the normal load (a friction coefficient, F/W), so it is
        multiplied by the load; None: when its name says so (``Fnorm``, ``mu``).
    time_unit, force_unit : str or None
        Units of the time and force when the file does not state them (default ``s`` and ``N``).
    name_pattern : str or None
        Metadata from the file name, e.g. ``k{stiffness}Nm_v{v0}`` or
        ``k{stiffness:N/m}_v{v0:mm/s}`` (:func:`apply_name_pattern`).

    """

    time: str | None = None
    force: str | None = None
    normalised: bool | None = None
    time_unit: str | None = None
    force_unit: str | None = None
    name_pattern: str | None = None

    def __post_init__(self) -> None:
        for key in ("time", "force", "time_unit", "force_unit", "name_pattern"):
            value = getattr(self, key)
            if value is not None and not isinstance(value, str):
                raise ArgumentTypeError(f"{key}={value!r}: expected a non-empty name")
            if value is not None and not value.strip():
                raise ValueError(f"{key}={value!r}: expected a non-empty name")
        if self.normalised is not None and not isinstance(self.normalised, bool):
            raise ArgumentTypeError(f"normalised={self.normalised!r}: expected True, False or None")


def _need(module: str, path: str) -> Any:
    """Import an optional reader, or say in one line which extra brings it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        package = {"nptdms": "npTDMS"}.get(module, module)
        raise DataError(
            f"{path}: reading this file needs {package}, which is not installed "
            f"(pip install 'stickslip[lab]' or pip install {package})"
        ) from None


def _column(value: Any, name: str, where: str) -> Column | None:
    """Return ``value`` as a 1-D float array when it is a record's column (None for metadata).

    A 1-D variable of text (strings, bytes, objects) is returned as it is, so that a
    record asking for it is told that it holds text, not that it is missing.
    """
    arr = np.asarray(value)
    if arr.dtype.kind not in "biufSUO" or arr.size < MIN_SAMPLES:
        return None
    arr = np.squeeze(arr)
    if arr.ndim != 1:
        return None
    return np.asarray(arr, dtype=float) if arr.dtype.kind in "biuf" else arr


def _mat_v5(path: str, where: str) -> tuple[dict[str, Column], dict[str, str], dict[str, str]]:
    from scipy.io import loadmat

    try:
        data = loadmat(path, squeeze_me=False)
    except Exception as exc:  # scipy raises ValueError, TypeError or OSError for a damaged file
        raise DataError(f"{where}: not a readable MATLAB file ({_short(exc)})") from None
    arrays: dict[str, Column] = {}
    meta: dict[str, str] = {}
    for key, value in data.items():
        if key.startswith("__"):
            continue
        col = _column(value, key, where)
        if col is not None:
            arrays[key] = col
        elif isinstance(value, np.ndarray) and value.dtype.kind in "US" and value.size == 1:
            meta[key] = str(value.item())
        elif isinstance(value, np.ndarray) and value.dtype.kind in "biuf" and value.size == 1:
            meta[key] = repr(float(value.item()))
    return arrays, {}, meta


def _attr_text(value: Any) -> str:
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    if isinstance(value, np.ndarray):
        if value.size == 1:
            return _attr_text(value.item())
        if value.dtype.kind in "biuf" and value.ndim == 2 and value.shape[0] == 1:  # MATLAB's char array
            return "".join(chr(int(c)) for c in value.ravel())
        return str(value.tolist())
    return str(value)


def _hdf5(path: str, where: str) -> tuple[dict[str, Column], dict[str, str], dict[str, str]]:
    h5py = _need("h5py", where)
    arrays: dict[str, Column] = {}
    units: dict[str, str] = {}
    meta: dict[str, str] = {}
    try:
        with h5py.File(path, "r") as f:
            meta.update(
                {str(k): _attr_text(v) for k, v in f.attrs.items() if not str(k).startswith("MATLAB")}
            )

            def visit(name: str, obj: Any) -> None:
                if not isinstance(obj, h5py.Dataset) or name.startswith("#refs#"):
                    return
                if obj.dtype.kind not in "biufSO":
                    return
                if obj.attrs.get("MATLAB_class") == b"char":
                    meta[name.rsplit("/", 1)[-1]] = _attr_text(obj[()])
                    return
                col = _column(obj[()], name, where)
                if col is None:
                    if obj.size == 1:
                        meta[name.rsplit("/", 1)[-1]] = repr(float(np.asarray(obj[()]).ravel()[0]))
                    return
                arrays[name] = col
                for key in ("units", "unit", "Units", "unit_string"):
                    if key in obj.attrs:
                        units[name] = _attr_text(obj.attrs[key])
                        break

            f.visititems(visit)
    except DataError:
        raise
    except Exception as exc:  # h5py raises OSError for a truncated or foreign file
        raise DataError(f"{where}: not a readable HDF5 file ({_short(exc)})") from None
    return arrays, units, meta


def _numpy(path: str, where: str) -> tuple[dict[str, Column], dict[str, str], dict[str, str]]:
    try:
        data = np.load(path, allow_pickle=False)
    except Exception as exc:  # a pickled array, a truncated file: ValueError, EOFError, OSError
        raise DataError(f"{where}: not a readable NumPy file ({_short(exc)})") from None
    arrays: dict[str, Column] = {}
    meta: dict[str, str] = {}
    if isinstance(data, np.ndarray):
        if data.ndim == 2 and data.shape[1] in (2, 3, 4) and data.shape[0] > data.shape[1]:
            names = ("time", "force", "displacement", "velocity")[: data.shape[1]]
            return {n: np.asarray(data[:, i], float) for i, n in enumerate(names)}, {}, {}
        raise DataError(
            f"{where}: a .npy record is a 2-D array of columns time, force (n x 2), got shape {data.shape}; "
            "save named arrays with numpy.savez instead"
        )
    with data:
        try:
            items = {k: data[k] for k in data.files}
        except Exception as exc:
            raise DataError(f"{where}: not a readable .npz file ({_short(exc)})") from None
    for key, value in items.items():
        col = _column(value, key, where)
        if col is not None:
            arrays[key] = col
        elif value.dtype.kind in "US" and value.size == 1:
            meta[key] = str(value.item())
        elif value.dtype.kind in "biuf" and value.size == 1:
            meta[key] = repr(float(value.item()))
    return arrays, {}, meta


def _xlsx(path: str, where: str) -> tuple[dict[str, Column], dict[str, str], dict[str, str]]:
    openpyxl = _need("openpyxl", where)
    from .tables import split_header

    try:
        book = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as exc:  # zipfile.BadZipFile, KeyError, InvalidFileException
        raise DataError(f"{where}: not a readable Excel workbook ({_short(exc)})") from None
    try:
        sheet = book.worksheets[0]
        rows = list(sheet.iter_rows(values_only=True))
        sheet_name = sheet.title
    finally:
        book.close()
    meta: dict[str, str] = {}
    header_at = None
    for i, row in enumerate(rows):
        cells = [c for c in row if c is not None and str(c).strip()]
        if not cells:
            continue
        first = str(cells[0]).strip()
        if first.startswith("#"):
            text = " ".join(str(c) for c in cells).lstrip("#").strip()
            if "=" in text:
                key, _, text_value = text.partition("=")
                meta[key.strip().lower().replace(" ", "_")] = text_value.strip()
            continue
        header_at = i
        break
    if header_at is None:
        raise DataError(f"{where}: sheet {sheet_name!r} has no header row")
    header = rows[header_at]
    arrays: dict[str, Column] = {}
    units: dict[str, str] = {}
    for j, cell in enumerate(header):
        if cell is None or not str(cell).strip():
            continue
        name, unit = split_header(str(cell), where)
        values: list[float] = []
        for r, row in enumerate(rows[header_at + 1 :], start=header_at + 2):
            value: Any = row[j] if j < len(row) else None
            if value is None or (isinstance(value, str) and not value.strip()):
                break
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise DataError(
                    f"{where}: sheet {sheet_name!r}, row {r}, column {str(cell).strip()!r}: "
                    f"{value!r} is not a number"
                )
            values.append(float(value))
        if len(values) >= MIN_SAMPLES:
            arrays[name] = np.asarray(values, dtype=np.float64)
            if unit:
                units[name] = unit
    return arrays, units, meta


def _tdms(path: str, where: str) -> tuple[dict[str, Column], dict[str, str], dict[str, str]]:
    nptdms = _need("nptdms", where)
    try:
        f = nptdms.TdmsFile.read(path)
    except Exception as exc:  # nptdms raises ValueError or struct errors for a damaged file
        raise DataError(f"{where}: not a readable TDMS file ({_short(exc)})") from None
    arrays: dict[str, Column] = {}
    units: dict[str, str] = {}
    meta = {str(k): str(v) for k, v in f.properties.items()}
    for group in f.groups():
        for channel in group.channels():
            try:
                col = _column(channel[:], channel.name, where)
            except Exception as exc:
                raise DataError(
                    f"{where}: channel {group.name}/{channel.name} cannot be read ({_short(exc)})"
                ) from None
            if col is None:
                continue
            arrays[channel.name] = col
            unit = channel.properties.get("unit_string")
            if unit:
                units[channel.name] = str(unit)
            if "wf_increment" in channel.properties and "time" not in {n.lower() for n in arrays}:
                # a waveform channel: its samples' times from its start and increment
                dt = float(channel.properties["wf_increment"])
                t0 = float(channel.properties.get("wf_start_offset", 0.0))
                arrays.setdefault("__waveform_time__", t0 + dt * np.arange(col.size, dtype=np.float64))
    return arrays, units, meta


def _text(path: str, where: str) -> tuple[dict[str, Column], dict[str, str], dict[str, str]]:
    """Read a text table of any delimiter, ``#`` lines before the header (``# key = value`` kept)."""
    import pandas as pd

    from .tables import split_header

    meta: dict[str, str] = {}
    with open(path, encoding="utf-8", errors="replace") as fh:
        skip = 0
        for line in fh:
            if not line.startswith("#"):
                break
            skip += 1
            body = line[1:].strip()
            if "=" in body:
                key, _, value = body.partition("=")
                meta[key.strip().lower().replace(" ", "_")] = value.strip()
    try:
        frame = pd.read_csv(path, sep=None, engine="python", skiprows=skip, comment="#")
    except Exception as exc:
        raise DataError(f"{where}: not a readable text table ({_short(exc)})") from None
    arrays: dict[str, Column] = {}
    units: dict[str, str] = {}
    for cell in frame.columns:
        name, unit = split_header(str(cell), where)
        values = pd.to_numeric(frame[cell], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(np.isnan(values))
        if bad.size and bad.size < values.size:
            i = int(bad[0])
            raise DataError(
                f"{where}: column {str(cell).strip()!r}, data row {i + 1}: "
                f"{frame[cell].iloc[i]!r} is not a number"
            )
        if bad.size == values.size:
            continue
        arrays[name] = values
        if unit:
            units[name] = unit
    return arrays, units, meta


def _short(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    return text[:160]


def read_arrays(path: str) -> tuple[dict[str, Column], dict[str, str], dict[str, str]]:
    """Return a file's 1-D numeric variables, the units it states for them, and its metadata.

    Parameters
    ----------
    path : str
        A ``.mat`` (v5 through SciPy, v7.3 through h5py), ``.h5``/``.hdf5``, ``.npy``/``.npz``,
        ``.xlsx`` (the first sheet: ``# key = value`` rows, then a header row of
        ``name [unit]`` cells, then numbers) or ``.tdms`` file; any other name is read as
        a text table (any delimiter).

    Raises
    ------
    DataError
        A file that cannot be read, in one line naming it and what was wrong.

    """
    where = path
    lower = path.lower()
    if lower.endswith(".mat"):
        with open(path, "rb") as fh:
            head = fh.read(128)
        if len(head) < 128:
            raise DataError(f"{where}: not a readable MATLAB file ({len(head)} bytes: truncated)")
        if b"MATLAB 7.3" in head or head[:8] == b"\x89HDF\r\n\x1a\n" or _is_hdf5(path):
            return _hdf5(path, where)
        return _mat_v5(path, where)
    if lower.endswith((".h5", ".hdf5", ".hdf")):
        return _hdf5(path, where)
    if lower.endswith((".npy", ".npz")):
        return _numpy(path, where)
    if lower.endswith((".xlsx", ".xlsm")):
        return _xlsx(path, where)
    if lower.endswith(".tdms"):
        return _tdms(path, where)
    return _text(path, where)


def _is_hdf5(path: str) -> bool:
    """Whether the file has HDF5's signature at 0 or at a user block of 512 bytes (MATLAB v7.3's)."""
    with open(path, "rb") as fh:
        for offset in (0, 512, 1024):
            fh.seek(offset)
            if fh.read(8) == b"\x89HDF\r\n\x1a\n":
                return True
    return False


def _find(
    arrays: Mapping[str, Column], name: str | None, guesses: tuple[str, ...], *, numeric: bool = True
) -> str | None:
    """Return the variable named ``name`` (case-insensitive, a path's last part too), or the first guess.

    A guess is a numeric variable (``numeric``) or a text one (not ``numeric``).
    """
    by_lower: dict[str, str] = {}
    for key in arrays:
        by_lower.setdefault(key.lower(), key)
        by_lower.setdefault(key.rsplit("/", 1)[-1].lower(), key)
    if name is not None:
        return by_lower.get(name.lower())
    for guess in guesses:
        if guess in by_lower and (arrays[by_lower[guess]].dtype.kind == "f") == numeric:
            return by_lower[guess]
    return None


def _text_note(arrays: Mapping[str, Column], guesses: tuple[str, ...]) -> str:
    """Return '; NAME holds text ('a', ...), not numbers' for a text variable among the guesses, or ''."""
    name = _find(arrays, None, guesses, numeric=False)
    return "" if name is None else f"; {name!r} holds text ({_first_text(arrays[name])}), not numbers"


def _first_text(arr: Column) -> str:
    first = arr[0].decode("utf-8", "replace") if isinstance(arr[0], bytes) else str(arr[0])
    return f"{first!r}, ..."


def _scale(unit: str | None, default: str, si: str, dimension: str, what: str, where: str) -> float:
    text = (unit or default).strip()
    try:
        q = ureg.Quantity(1.0, text)
    except Exception:
        raise DataError(f"{where}: {what}'s unit {text!r} is not a unit (expected e.g. {si!r})") from None
    if not q.check(dimension):
        raise DataError(f"{where}: {what}'s unit {text!r} is not a {dimension} (expected e.g. {si!r})")
    return float(q.to(si).magnitude)


def apply_name_pattern(pattern: str, name: str) -> dict[str, str]:
    """Return the metadata a file name carries by ``pattern`` (quantities as text with units).

    ``{key}`` or ``{key:unit}`` fields match numbers (``168``, ``4.3e3``, ``0p5`` for 0.5);
    the rest of the pattern matches literally, anywhere in the name (the extension is
    ignored). A field without a unit takes :data:`PATTERN_UNITS`' (stiffness in N/m, v0
    in um/s, mass in g, load in N).

    Raises
    ------
    DataError
        When the name does not match, naming both.

    """
    fields: list[tuple[str, str]] = []
    regex = ""
    pos = 0
    for m in re.finditer(r"\{([A-Za-z_][A-Za-z_0-9]*)(?::([^{}]+))?\}", pattern):
        regex += re.escape(pattern[pos : m.start()])
        key = m.group(1)
        if key not in QUANTITIES:
            raise DataError(
                f"name pattern {pattern!r}: field {{{key}}}: expected one of {', '.join(QUANTITIES)}"
            )
        unit = m.group(2) or PATTERN_UNITS[key]
        fields.append((key, unit))
        regex += r"([-+]?\d+(?:[.p]\d*)?(?:[eE][-+]?\d+)?)"
        pos = m.end()
    regex += re.escape(pattern[pos:])
    if not fields:
        raise DataError(f"name pattern {pattern!r}: no field such as {{stiffness}} or {{v0:um/s}}")
    stem = os.path.splitext(os.path.basename(name))[0]
    found = re.search(regex, stem)
    if found is None:
        raise DataError(f"{name}: the file name does not match the name pattern {pattern!r}")
    return {key: f"{found.group(i + 1).replace('p', '.')} {unit}" for i, (key, unit) in enumerate(fields)}


def read_sidecar(path: str) -> dict[str, str]:
    """Return the metadata of a record's sidecar file, ``NAME.json`` beside ``NAME.ext`` ({} if none).

    A JSON object of quantities as text (``{"stiffness": "168 N/m", "v0": "42 um/s",
    "mass": "30.7 g"}``) and, optionally, ``time``, ``force``, ``normalised``.
    """
    side = os.path.splitext(path)[0] + ".json"
    if not os.path.isfile(side) or side == path:
        return {}
    try:
        with open(side, encoding="utf-8") as fh:
            data = json.load(fh)
    except (OSError, ValueError) as exc:
        raise DataError(f"{side}: not a readable JSON sidecar ({_short(exc)})") from None
    if not isinstance(data, dict):
        raise DataError(f"{side}: expected a JSON object of metadata, got {type(data).__name__}")
    return {
        str(k).lower(): str(v) if not isinstance(v, bool) else ("true" if v else "false")
        for k, v in data.items()
    }


def pick_record(
    arrays: Mapping[str, Column],
    units: Mapping[str, str],
    meta: Mapping[str, str],
    options: RecordOptions,
    where: str,
) -> tuple[FloatArray, FloatArray, bool, dict[str, str]]:
    """Take the time (s) and force (N, or F/W when normalised) among a file's variables.

    Returns
    -------
    time, force : ndarray
        In seconds, and in newtons (or as the normalised force, when ``normalised``).
    normalised : bool
        The force is F/W: the caller multiplies it by the load.
    notes : dict
        The variables chosen (``time_variable``, ``force_variable``) for the record's metadata.

    Raises
    ------
    DataError
        A variable that is not there, named with the variables the file has.

    """
    have = ", ".join(sorted(k for k in arrays if not k.startswith("__"))) or "none"
    tname = _find(arrays, options.time, TIME_GUESSES)
    if tname is None and options.time is None and "__waveform_time__" in arrays:
        tname = "__waveform_time__"
    if tname is None:
        asked = f"no variable {options.time!r}" if options.time else "no time variable (t, time)"
        note = "" if options.time else _text_note(arrays, TIME_GUESSES)
        raise DataError(f"{where}: {asked}{note}; it has {have} (choose with --time NAME)")
    normalised = options.normalised
    fname = _find(arrays, options.force, ())
    if options.force is not None and fname is None:
        raise DataError(f"{where}: no variable {options.force!r}; it has {have} (choose with --force NAME)")
    if fname is None:
        fname = _find(arrays, None, FORCE_GUESSES)
        if fname is not None and normalised is None:
            normalised = False
    if fname is None:
        fname = _find(arrays, None, NORMALISED_GUESSES)
        if fname is not None and normalised is None:
            normalised = True
    if fname is None:
        note = _text_note(arrays, FORCE_GUESSES + NORMALISED_GUESSES)
        raise DataError(
            f"{where}: no force variable (force, F, Fnorm, mu){note}; it has {have} "
            "(choose with --force NAME)"
        )
    for kind, name in (("time", tname), ("force", fname)):
        if arrays[name].dtype.kind != "f":
            raise DataError(
                f"{where}: the {kind} variable {name!r} holds text ({_first_text(arrays[name])}), not numbers"
            )
    if normalised is None:
        normalised = fname.rsplit("/", 1)[-1].lower() in NORMALISED_GUESSES
    t = arrays[tname]
    f = arrays[fname]
    if t.size != f.size:
        raise DataError(f"{where}: time {tname!r} has {t.size} samples, force {fname!r} has {f.size}")
    for name, arr in ((tname, t), (fname, f)):
        bad = ~np.isfinite(arr)
        if bad.any():
            i = int(np.argmax(bad))
            raise DataError(
                f"{where}: {name}[{i}] = {arr[i]!r}: expected finite numbers ({int(bad.sum())} are not)"
            )
    t = t * _scale(options.time_unit or units.get(tname), "s", "s", "[time]", f"time {tname!r}", where)
    if normalised:
        unit = options.force_unit or units.get(fname)
        if unit and unit.strip() not in ("1", "", "-"):
            scale = _scale(unit, "1", "", "[]", f"normalised force {fname!r}", where)
            f = f * scale
    else:
        f = f * _scale(options.force_unit or units.get(fname), "N", "N", "[force]", f"force {fname!r}", where)
    notes = {"time_variable": tname.rsplit("/", 1)[-1], "force_variable": fname.rsplit("/", 1)[-1]}
    if normalised:
        notes["force_is"] = "normalised by the load (F/W)"
    return np.asarray(t, float), np.asarray(f, float), bool(normalised), notes
