"""Reading CSV tables whose header gives units in brackets, e.g. ``velocity [um/s]``."""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt
import pint

from ..errors import ArgumentTypeError
from ..units import ureg
from . import text
from .errors import DataError

__all__ = [
    "Column",
    "check_file",
    "frame_with_units",
    "parse_header",
    "read_table",
    "split_header",
    "unit_of",
]

_HEADER = re.compile(r"^\s*([^\[\]]*?)\s*(?:\[([^\[\]]*)\])?\s*$")
MAX_BYTES = 20_000_000_000  # beyond the memory check, a plain bound


@dataclass(frozen=True)
class Column:
    """One column of a table: name, values and unit (None when the header gives none).

    ``layout`` is the file's (when read from one): :meth:`place` then names a value's
    line in the file.
    """

    name: str
    values: npt.NDArray[np.float64]
    unit: pint.Unit | None
    layout: text.TextLayout | None = field(default=None, repr=False, compare=False)

    def place(self, i: int) -> str:
        """Where value ``i`` (0-based) is: ``line N`` of the file, or ``row N`` (1-based) of an array."""
        if self.layout is None:
            return f"row {int(i) + 1}"
        return f"line {text.data_lines(self.layout, [int(i)])[0]}"


_PARENS = re.compile(r"^\s*([^()\[\]]*?)\s*\(([^()\[\]]+)\)\s*$")


def unit_of(variable: Any) -> str:
    """Return what a variable is measured in: its ``scale``, else its ``units``.

    A dimensionless value's ``scale`` ("static friction force mu_s W") says more than its
    CF ``units`` ("1").
    """
    return str(variable.attrs.get("scale") or variable.attrs.get("units", ""))


def frame_with_units(ds: Any) -> Any:
    """Return a dataset as a table: one row per point, its coordinates first, units in the names.

    ``amplitude [N]`` where the variable has units (:func:`unit_of`), as stickslip's records
    write their headers; labels (regimes, statuses) as they are. For a CSV file a reader can
    take without the NetCDF's attributes.
    """
    table = ds.to_dataframe().reset_index()
    units = {n: unit_of(ds[n]) for n in table.columns if n in ds.variables}
    table.columns = [f"{n} [{units[n]}]" if units.get(n) else str(n) for n in table.columns]
    return table


def split_header(cell: str, path: str) -> tuple[str, str | None]:
    """Return a header cell's name and unit text.

    ``name [unit]``, or ``name (unit)`` where the parentheses hold a unit pint knows
    (instruments write ``Time (s)``, ``Fx (mN)``).
    """
    m = _HEADER.match(cell)
    if not m or not m.group(1):
        raise DataError(f"{path}: header cell {cell!r} is not of the form 'name [unit]'")
    if m.group(2) is None:
        p = _PARENS.match(cell)
        if p and p.group(1) and _is_unit(p.group(2)):
            return p.group(1).strip().lower(), p.group(2)
    return m.group(1).strip().lower(), m.group(2)


def _is_unit(text: str) -> bool:
    try:
        ureg.Unit(text.strip())
    except Exception:
        return False
    return True


def header_name(cell: str, path: str) -> str:
    """Return the name of a header cell, ``"velocity"`` for ``"Velocity [um/s]"``; raise if malformed."""
    return split_header(cell, path)[0]


def parse_header(cell: str, path: str) -> tuple[str, pint.Unit | None]:
    """Split ``"velocity [um/s]"`` (or ``"Velocity (um/s)"``) into ``("velocity", unit)``."""
    name, unit_text = split_header(cell, path)
    if unit_text is None or unit_text.strip() == "":
        return name, None
    text = unit_text.strip()
    if text.lower() in ("a.u.", "au", "arb", "arbitrary", "arb. units", "1", "-"):
        return name, ureg.dimensionless
    try:
        unit = ureg.Unit(text)
    except Exception:
        raise DataError(
            f"{path}: column {name!r} has unknown unit [{text}] (pint does not know it; "
            "write e.g. [um/s], [mN], [a.u.])"
        ) from None
    return name, unit


def check_file(path: str | os.PathLike[str], max_bytes: int) -> str:
    """Return the path as a string after checking that it is a non-empty file below ``max_bytes``.

    Raises
    ------
    DataError
        Naming the file: missing, empty, or too large (with the limit).

    """
    p = text.check_file(path)
    size = os.path.getsize(p)
    if size > max_bytes:
        raise DataError(
            f"{p}: {size / 1e6:.0f} MB is larger than the {max_bytes / 1e6:.0f} MB limit; split it"
        )
    return p


def read_table(
    path: str | os.PathLike[str],
    required: Sequence[str],
    optional: Sequence[str] = (),
) -> dict[str, Column]:
    """Read the named numeric columns of a CSV (or TSV) file with units in the header.

    Parameters
    ----------
    path : str or path-like
        The file. Lines starting with ``#`` are comments.
    required : sequence of str
        Column names that must be present (case-insensitive, without the unit).
    optional : sequence of str
        Column names read when present.

    Returns
    -------
    dict of Column
        By lower-case name.

    Raises
    ------
    DataError
        Missing file, empty file, huge file, not UTF-8 text, missing column,
        duplicate column, unknown unit, ragged rows, or a cell that is not a number
        (or NaN); the message names the file, the column and the line.

    """
    for arg, value in (("required", required), ("optional", optional)):
        if isinstance(value, str):  # "velocity" was read as the columns 'v', 'e', ...
            raise ArgumentTypeError(f"{arg}={value!r}: expected a sequence of column names, e.g. [{value!r}]")
    required = [r.strip().lower() for r in required]  # case-insensitive, as the header's names
    optional = [o.strip().lower() for o in optional]
    p = check_file(path, MAX_BYTES)
    layout = text.inspect(p)
    header = [parse_header(c, p) for c in layout.header]
    names = [h[0] for h in header]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise DataError(f"{p}: column {sorted(dup)[0]!r} appears more than once")
    missing = [r for r in required if r not in names]
    if missing:
        raise DataError(
            f"{p}: missing column {missing[0]!r} (found {names}); expected a header such as "
            + ", ".join(f"{r} [unit]" for r in required)
        )
    wanted = [*required, *[o for o in optional if o in names]]
    frame = text.read_frame(layout, names, numeric=wanted)
    if len(frame) == 0:
        raise DataError(f"{p}: the file has a header but no data rows")
    if frame[wanted].isna().any().any():
        # an empty cell, a short row or a NaN: name the first
        text.diagnose(layout, names, numeric=wanted, nan_is_error=True)
        raise DataError(f"{p}: missing values")  # pragma: no cover - diagnose raises first
    return {
        name: Column(name, frame[name].to_numpy(dtype=np.float64), header[names.index(name)][1], layout)
        for name in wanted
    }
