"""CSV files whose header names each column with its unit in brackets."""

from __future__ import annotations

import csv
import os
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["write_columns"]


def write_columns(path: str | os.PathLike[str], columns: Mapping[str, Any]) -> None:
    """Write equal-length columns to ``path`` as CSV; floats to full precision.

    Parameters
    ----------
    path : str or path-like
        Output file; parent folders are created.
    columns : Mapping[str, array_like]
        Header (for instance ``"time [s]"``) to values.

    Raises
    ------
    ValueError
        If the columns differ in length.

    """
    arrays = {k: np.asarray(v) for k, v in columns.items()}
    lengths = {len(v) for v in arrays.values()}
    if len(lengths) > 1:
        raise ValueError(f"columns have different lengths: { {k: len(v) for k, v in arrays.items()} }")
    folder = os.path.dirname(os.fspath(path))
    if folder:
        os.makedirs(folder, exist_ok=True)
    cols = [
        [repr(float(x)) for x in v] if v.dtype.kind == "f" else [str(x) for x in v] for v in arrays.values()
    ]
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(list(arrays))
        writer.writerows(zip(*cols, strict=True))
