"""Repairs of a reopened store's metadata and coordinates, from what the store itself holds.

A job's store is reopened on every run after the first. Its arrays' ``zarr.json``
files and the store's consolidated copy of them are checked against the job's
layout and against each other, the one that fits written again from the other
(:func:`repair_metadata`); its coordinates, fixed by the job's identity, are read
back and written again where they no longer read as the grid
(:func:`repair_coordinates`). The blocks' data are checked by their digests
elsewhere (:meth:`stickslip.scale.store.ChunkStore.finished`).
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..io.output import temporary_file
from ..userwarnings import warn
from .errors import StoreError, disk_error, why
from .layout import Layout

__all__ = ["repair_coordinates", "repair_metadata"]


def repair_coordinates(p: str, layout: Layout) -> None:
    """Write a store's coordinates again where they no longer read back as the job's.

    The identity (checked) fixes them; a deleted or corrupt chunk of a coordinate
    reads as zeros or raises inside numcodecs, and the loaded result would have a wrong grid.

    Raises
    ------
    StoreError
        A coordinate's metadata is lost, or one is wrong and the store cannot be written.

    """
    if not layout.coords:
        return
    import zarr

    bad = []
    for name, (_, values, _) in layout.coords.items():
        want = np.asarray(values)
        try:
            arr: Any = zarr.open_array(store=p, path=name, mode="r")
        except Exception:
            raise StoreError(
                f"store={p!r}: its coordinate {name!r} cannot be opened (its zarr.json is lost or "
                "damaged): delete the store and run the command again"
            ) from None
        try:
            got = np.asarray(arr[...])
            ok = got.shape == want.shape and np.array_equal(got, want, equal_nan=want.dtype.kind == "f")
        except Exception:  # a chunk that cannot be decoded
            ok = False
        if not ok:
            bad.append((name, want))
    for name, want in bad:
        try:
            out: Any = zarr.open_array(store=p, path=name, mode="r+")
            out[...] = want
        except Exception as exc:
            err = disk_error(exc)
            raise StoreError(
                f"store={p!r}: its coordinate {name!r} no longer reads as the grid, and it cannot "
                f"be written again ({why(err) if err is not None else exc})"
            ) from None


def _expected_metadata(layout: Layout) -> dict[str, dict[str, Any]]:
    """Return, per array of a job's store, what its ``zarr.json`` must say: shape, chunks, type, dims."""
    out: dict[str, dict[str, Any]] = {}
    for name, (dims, values, _) in layout.coords.items():
        vals = np.asarray(values)
        out[name] = {
            "shape": list(vals.shape),
            "chunks": list(vals.shape) if vals.size else None,  # zarr makes an empty one's chunks
            "data_type": _zarr_type(vals.dtype),
            "dims": [dims] if isinstance(dims, str) else list(dims),
        }
    for v in layout.variables:
        k = len(v.dims)
        out[v.name] = {
            "shape": list(layout.shape[:k]),
            "chunks": list(layout.chunks[:k]),
            "data_type": _zarr_type(np.dtype(v.dtype)),
            "dims": list(v.dims),
        }
    return out


def _zarr_type(dtype: np.dtype[Any]) -> str | None:
    """Return Zarr 3's name of a numeric or boolean ``dtype`` (numpy's name), None for another type."""
    return dtype.name if dtype.kind in "biuf" else None


def _metadata_problem(meta: Any, want: Mapping[str, Any]) -> str | None:
    """Say how an array's parsed ``zarr.json`` differs from ``want`` (:func:`_expected_metadata`), or None."""
    if not isinstance(meta, dict) or meta.get("node_type") != "array" or meta.get("zarr_format") != 3:
        return "is not a Zarr 3 array's metadata"
    try:
        chunks = meta["chunk_grid"]["configuration"]["chunk_shape"]
    except (KeyError, TypeError):
        return "has no chunk grid"
    said = [
        f"{key} {got}, not {expected}"
        for key, got, expected in (
            ("shape", meta.get("shape"), want["shape"]),
            ("chunks", chunks, want["chunks"]),
            ("data_type", meta.get("data_type"), want["data_type"]),
            ("dimension_names", meta.get("dimension_names"), want["dims"]),
        )
        if expected is not None and got != expected
    ]
    return "has " + ", ".join(said) if said else None


def _read_metadata(path: str) -> tuple[Any, str | None]:
    """Return an array's ``zarr.json`` parsed (None where it cannot be) and what kept it from parsing."""
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f), None
    except FileNotFoundError:
        return None, "is missing"
    except (UnicodeDecodeError, ValueError):
        return None, "is not valid JSON (truncated or damaged)"
    except OSError as exc:
        return None, f"cannot be read ({why(exc)})"


def _write_json(path: str, obj: Any) -> None:
    """Write ``obj`` to ``path`` as Zarr does (indented JSON), through a temporary file renamed into place."""
    folder = os.path.dirname(path)
    os.makedirs(folder, exist_ok=True)
    fd, tmp = temporary_file(folder, ".zarr.json.")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            json.dump(obj, f, indent=2)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise


def repair_metadata(p: str, layout: Layout) -> None:
    """Make every array's ``zarr.json`` in a job's store agree with the job and the consolidated copy.

    The store's own ``zarr.json`` holds a copy of every array's metadata (consolidated,
    what ``xarray.open_zarr`` reads); the array's file is what a plain Zarr reader and the
    writing of blocks read. Where one of the two is lost, not JSON, or not the job's
    (shape, chunks, data type, dimensions), it is written again from the other, which is
    exact; where neither is the job's, the store cannot be repaired. A repair is said in
    one warning per file; the chunks are then checked by their digests as always.

    Raises
    ------
    StoreError
        An array's metadata cannot be restored from the store, or cannot be written.

    """
    group_path = os.path.join(p, "zarr.json")
    with open(group_path, encoding="utf-8") as f:
        group = json.load(f)  # the store's mark was read from it just before: it parses
    consolidated = group.get("consolidated_metadata")
    copies = consolidated.get("metadata") if isinstance(consolidated, dict) else None
    if not isinstance(copies, dict):
        copies = None
    stale = []  # the arrays whose copy in the store's zarr.json is the damaged one
    for name, want in _expected_metadata(layout).items():
        file = os.path.join(p, name, "zarr.json")
        own, problem = _read_metadata(file)
        if problem is None:
            problem = _metadata_problem(own, want)
        copy = copies.get(name) if copies is not None else None
        copy_problem = _metadata_problem(copy, want)
        if problem is None and (copies is None or copy == own):
            continue  # the array's file is the job's (and so is the copy, where there is one)
        where = f"store={p!r}: {name}/zarr.json"
        differs = "differs from its copy in the store's zarr.json"
        if copy_problem is None:  # the copy wins where the two differ
            try:
                _write_json(file, copy)
            except OSError as exc:
                raise StoreError(
                    f"{where} {problem or differs}, and it cannot be written again ({why(exc)}): "
                    "delete the store and run the command again"
                ) from None
            warn(f"{where} {problem or differs}: written again from the copy in the store's zarr.json")
        elif problem is None and copies is not None:  # the copy is the damaged one
            copies[name] = own
            stale.append(name)
        else:
            raise StoreError(
                f"{where} {problem}, and the store's zarr.json has no copy of it that fits the job: "
                "delete the store and run the command again"
            )
    if stale:
        what = f"store={p!r}: the copy in zarr.json of {', '.join(stale)}'s metadata does not fit the job"
        try:
            _write_json(group_path, group)
        except OSError as exc:
            raise StoreError(
                f"{what}, and it cannot be written again ({why(exc)}): delete the store and run the "
                "command again"
            ) from None
        warn(f"{what}: written again from the array's own zarr.json")
