"""NetCDF and CSV files of datasets: writing them marked as stickslip's, reading them back.

A dataset of results (a sweep, a regime map, a chain's catalogue) is written with
:func:`save_dataset`: NetCDF (netCDF4) marked with the ``stickslip_output``
attribute, or for a ``.csv`` path a table with one row per point, units in the
column names. Enumerations (regime, status) go to NetCDF as integer codes with CF
``flag_values``/``flag_meanings`` (:func:`flag_attrs`) and come back as labels
(:func:`labels`). :func:`load_dataset` reads a NetCDF file back, fully loaded.

A failure of the netCDF library (``NetCDF: HDF error``) is reported with the
system's cause (a full disk, a quota, a read-only folder), found by a probe write.
"""

from __future__ import annotations

import errno
import os
from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt

from ..errors import ArgumentTypeError
from . import output
from .output import OutputFolder, _remove, emit, generator

__all__ = ["flag_attrs", "labels", "load_dataset", "netcdf_writer", "save_dataset"]


def save_dataset(
    ds: Any,
    path: str | os.PathLike[str],
    *,
    kind: str = "sweep",
    out: OutputFolder | None = None,
    overwrite: bool = False,
) -> str:
    """Write a dataset to NetCDF (netCDF4 format), or a ``.csv`` path as a table; return the path.

    The file is marked as stickslip's output of ``kind`` (attribute ``stickslip_output``);
    an existing file that is not stickslip's output of that kind is kept unless
    ``overwrite``. ``out`` stages it with the other files of a run (``path`` a name in it).
    A ``.csv`` path gets one row per point, its coordinates first, units in the column
    names (``amplitude [N]``), regimes and statuses by name: a file named ``.csv`` is a
    table, never NetCDF.
    """
    p = os.fspath(path)
    if p.lower().endswith(".csv"):
        from .tables import frame_with_units  # pandas and pint, loaded only for a table

        table = frame_with_units(ds)

        def write(target: str) -> None:
            with open(target, "w", encoding="utf-8") as fh:
                fh.write(f"# stickslip {kind} table\n")  # pandas: read_csv(path, comment="#")
                table.to_csv(fh, index=False)

        return emit(p, kind, write, out=out, overwrite=overwrite)
    return emit(p, kind, netcdf_writer(ds, kind), out=out, overwrite=overwrite)


def load_dataset(path: str | os.PathLike[str]) -> Any:
    """Read a NetCDF file, fully loaded, without stickslip's marks of the file (not of the data).

    Raises
    ------
    ArgumentTypeError
        If ``path`` is not a str or a path.
    ValueError
        If the file does not exist or is not a readable NetCDF file.

    """
    import xarray as xr

    if not isinstance(path, str | os.PathLike):  # os.path.exists(3) asks about file descriptor 3
        raise ArgumentTypeError(f"path={path!r} (type {type(path).__name__}): expected a file's path")
    if not os.path.exists(path):
        raise ValueError(f"path={os.fspath(path)!r}: no such file")
    try:
        ds = xr.load_dataset(path, engine="netcdf4")
    except Exception as exc:  # netCDF4 raises OSError/RuntimeError/ValueError variously
        raise ValueError(f"path={os.fspath(path)!r} is not a readable NetCDF file ({exc})") from None
    for key in ("stickslip_output", "stickslip_generator"):
        ds.attrs.pop(key, None)
    return ds


def flag_attrs(enum: Any) -> dict[str, Any]:
    """Return CF ``flag_values`` and ``flag_meanings`` of an enumeration whose members carry a ``code``."""
    return {"flag_values": [m.code for m in enum], "flag_meanings": " ".join(m.value for m in enum)}


def labels(codes: npt.NDArray[Any], enum: Any) -> npt.NDArray[np.str_]:
    """Integer codes to their labels (plain str arrays: numpy picks the width, NetCDF round-trips)."""
    codes = np.asarray(codes)
    names = {m.code: str(m) for m in enum}
    lo = min(names)
    flat = codes.ravel().astype(np.int64) - lo
    counts = np.bincount(flat, minlength=max(names) - lo + 1) if flat.size and flat.min() >= 0 else None
    present = [] if counts is None else [int(c) + lo for c in np.flatnonzero(counts)]
    if flat.size and (counts is None or any(c not in names for c in present)):
        unknown = sorted({int(c) for c in codes.ravel()} - set(names))
        raise ValueError(f"{enum.__name__}: no member with code {unknown[0]}")
    # one lookup for all points, as wide as the labels present (numpy's choice for the same
    # list); a Python loop over the points takes 0.5 s a million points
    width = max((len(names[c]) for c in present), default=1)
    table = np.array([names.get(c, "") for c in range(lo, max(names) + 1)], dtype=f"<U{width}")
    return table[flat].reshape(codes.shape)


def netcdf_writer(ds: Any, kind: str) -> Callable[[str], None]:
    """Return a writer of ``ds`` as NetCDF (netCDF4), marked as stickslip's output of ``kind``."""

    def write(path: str) -> None:
        marked = ds.copy(deep=False)
        marked.attrs = {**ds.attrs, "stickslip_output": kind, "stickslip_generator": generator(kind)}
        try:
            marked.to_netcdf(path, engine="netcdf4")
        except (RuntimeError, OSError) as exc:
            said = _netcdf_library_error(exc)
            if said is None:
                raise
            raise _netcdf_cause(said, path) from None

    return write


def _netcdf_library_error(exc: BaseException) -> str | None:
    """Return the netCDF library's own text of ``exc`` (``NetCDF: HDF error``), or None for another error.

    netCDF4 raises its library's failures as RuntimeError (``NetCDF: ...``) or, on
    creating a file, as OSError with the library's negative error code; neither says
    which system call failed (a full disk reads ``NetCDF: HDF error``).
    """
    if isinstance(exc, OSError) and isinstance(exc.errno, int) and exc.errno < 0:
        return str(exc.strerror or exc)
    text = str(exc)
    if isinstance(exc, RuntimeError) and text.startswith(("NetCDF:", "HDF")):
        return text
    return None


#: bytes written to the folder to find why the netCDF library could not write: more than the
#: few kilobytes a failed HDF5 write can leave free, little enough to be instant
_PROBE_BYTES = 1 << 16


def _netcdf_cause(said: str, path: str) -> OSError:
    """Return an OSError naming ``path`` and the cause of the netCDF library's failure ``said``.

    The cause is found by writing :data:`_PROBE_BYTES` (then removed) beside the partial file,
    which still holds its space: a full disk, a quota, a read-only or refused folder gives
    the system's error; a probe that succeeds leaves the library's text alone.
    """
    folder = os.path.dirname(path) or "."
    probe = None
    try:
        fd, probe = output.temporary_file(folder, ".stickslip-space-")
        with os.fdopen(fd, "wb") as fh:
            fh.write(bytes(_PROBE_BYTES))
            fh.flush()
            os.fsync(fh.fileno())
    except OSError as err:
        why = err.strerror or str(err)
        return OSError(err.errno, f"{why}; the NetCDF library said '{said}'", path)
    finally:
        if probe is not None:
            _remove(probe)
    return OSError(errno.EIO, f"the NetCDF library failed: '{said}'", path)
