"""CSV files whose header names each column with its unit in brackets."""

from __future__ import annotations

import csv
import os
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import ArgumentTypeError
from .output import OutputFolder, emit

__all__ = ["write_columns"]

#: rows formatted at a time
CHUNK = 100_000


def _column(header: str, values: Any) -> np.ndarray:
    """Return a column's values; a pint quantity in the unit its header names (numpy stripped it)."""
    import pint

    if isinstance(values, pint.Quantity):
        m = re.search(r"\[([^]]*)\]\s*$", header)
        if m is None:
            raise ValueError(
                f"column {header!r}: values with units need a unit in the header, e.g. 'force [N]'"
            )
        try:
            values = values.to(m.group(1)).magnitude
        except (pint.DimensionalityError, pint.UndefinedUnitError, AttributeError, ValueError):
            raise ValueError(
                f"column {header!r}: values in {values.units} do not convert to {m.group(1)}"
            ) from None
    out = np.asarray(values)
    if out.ndim == 0:  # one value for a column
        raise ArgumentTypeError(f"column {header!r}={values!r}: expected a 1-d sequence of values")
    if out.ndim != 1:
        raise ValueError(f"column {header!r}: expected a 1-d sequence of values, got shape {out.shape}")
    return out


def write_columns(
    path: str | os.PathLike[str],
    columns: Mapping[str, Any],
    *,
    kind: str = "trajectory",
    out: OutputFolder | None = None,
    overwrite: bool = False,
) -> str:
    """Write equal-length columns to ``path`` as CSV (atomically); floats to full precision.

    Parameters
    ----------
    path : str or path-like
        Output file (a name inside ``out`` when given); parent folders are created.
    columns : Mapping[str, array_like]
        Header (for instance ``"time [s]"``) to values (pint quantities are
        written in the unit of their header).
    kind : str, optional
        What the file is, for :func:`~stickslip.io.output.check_target`.
    out : OutputFolder, optional
        Stage the file with the other files of a run.
    overwrite : bool, optional
        Replace an existing file that stickslip did not write.

    Returns
    -------
    str
        The path written.

    Raises
    ------
    ValueError
        If the columns differ in length, or the path names a foreign file.

    """
    arrays = {k: _column(k, v) for k, v in columns.items()}
    lengths = {len(v) for v in arrays.values()}
    if len(lengths) > 1:
        raise ValueError(f"columns have different lengths: { {k: len(v) for k, v in arrays.items()} }")
    n = next(iter(lengths), 0)

    def write(p: str) -> None:
        with open(p, "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(list(arrays))
            # in chunks: the text of a long series is never in memory all at once
            for lo in range(0, n, CHUNK):
                cols = [
                    [repr(float(x)) for x in v[lo : lo + CHUNK]]
                    if v.dtype.kind == "f"
                    else [str(x) for x in v[lo : lo + CHUNK]]
                    for v in arrays.values()
                ]
                writer.writerows(zip(*cols, strict=True))

    return emit(os.fspath(path), kind, write, out=out, overwrite=overwrite)
