"""A resumable on-disk store for long jobs: a Zarr group written chunk by chunk.

A long job (a sweep, a regime map, an ensemble of chains) is cut into *blocks*:
hyper-rectangles of its grid that are exactly the chunks of the store's arrays,
so that two blocks never touch the same chunk file and no lock is needed, from
threads, processes or machines. A block is written in two steps: its data (every
variable's region, each chunk file written atomically by Zarr), then a marker
holding a digest of what was written. On a second run only the blocks without a
valid marker are computed; a marker whose digest no longer matches the data (a
truncated, corrupt or deleted chunk file) is dropped and its block recomputed;
an array's ``zarr.json`` that is lost, not JSON or not the job's is written
again from the copy in the store's consolidated metadata.

The store's attributes hold the job's *identity* (the grid, the fixed
parameters, the tolerances): opening a store for another job is a one-line
:class:`StoreError`, never an overwrite. The store is a plain Zarr (format 3)
group with consolidated metadata: ``xarray.open_zarr(path)`` reads it.

This module opens, checks and writes stores; the job's layout and identity are in
:mod:`stickslip.scale.layout`, the repairs of a reopened store's metadata and
coordinates in :mod:`stickslip.scale.repair`, and :class:`StoreError` in
:mod:`stickslip.scale.errors` (their public names importable from here too).
"""

from __future__ import annotations

import dataclasses
import errno
import hashlib
import json
import os
import shutil
import threading
import uuid
import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from ..io.output import temporary_file, temporary_folder
from .errors import StoreError as StoreError
from .errors import disk_error, why
from .layout import Block as Block
from .layout import Layout as Layout
from .layout import Variable as Variable
from .layout import chunk_shape as chunk_shape
from .layout import differences, hashable, identity_parts, jsonable
from .repair import repair_coordinates, repair_metadata

__all__ = ["ChunkStore", "computed_points", "damaged_coordinates", "is_store", "store_kind"]

#: attribute of the group that marks a stickslip store (and holds the job's identity)
MARK = "stickslip_store"
#: folder (inside the store) of the markers of finished blocks
DONE = ".stickslip-done"
#: names of files that a new store's path may not take (a store is a folder)
_FILE_SUFFIXES = (".nc", ".nc4", ".netcdf", ".h5", ".hdf5", ".csv", ".json", ".txt", ".png", ".svg")


def is_store(path: str | os.PathLike[str]) -> bool:
    """Return whether ``path`` is a stickslip store (a Zarr group marked as one)."""
    meta = os.path.join(os.fspath(path), "zarr.json")
    try:
        with open(meta, encoding="utf-8") as f:
            return MARK in json.load(f).get("attributes", {})
    except (OSError, ValueError):
        return False


def store_kind(path: str | os.PathLike[str]) -> str:
    """Return the kind of job a store holds (``sweep``, ``regime-map``, ``chain-ensemble``)."""
    return str(_mark(os.fspath(path)).get("kind", "?"))


def computed_points(path: str | os.PathLike[str]) -> npt.NDArray[np.bool_]:
    """Return which grid points of a store its finished blocks hold (True), from their markers.

    A store whose job was interrupted holds some blocks only: the other points read as
    the arrays' fill values (NaN, the integer type's least value, False). The markers
    are taken as they are (:meth:`ChunkStore.finished` checks them against the data).

    Raises
    ------
    StoreError
        ``path`` is not a stickslip store, or its mark is damaged.

    """
    p = os.fspath(path)
    mark = _mark(p)
    try:
        shape = tuple(int(n) for n in mark["shape"])
        chunks = tuple(int(c) for c in mark["chunks"])
        if len(chunks) != len(shape) or any(c < 1 for c in chunks):
            raise ValueError(chunks)
    except (TypeError, KeyError, ValueError):
        raise StoreError(f"store={p!r}: its mark ({MARK!r} in zarr.json) is damaged") from None
    grid = tuple(-(-n // c) for n, c in zip(shape, chunks, strict=True))
    try:
        names = os.listdir(os.path.join(p, DONE))
    except FileNotFoundError:
        names = []
    done = np.zeros(grid, dtype=bool)
    for name in names:
        if name.isdigit() and int(name) < done.size:
            done.flat[int(name)] = True
    # each block's flag spread over its points (the last block of a dimension may be cut short)
    out = done
    for axis, c in enumerate(chunks):
        out = np.repeat(out, c, axis=axis)
    return out[tuple(slice(0, n) for n in shape)]


def damaged_coordinates(path: str | os.PathLike[str], coords: Mapping[str, npt.NDArray[Any]]) -> list[str]:
    """Return the names of the coordinates read from a store that are not the grid its mark records.

    (A mark without ``identity_parts``, from a stickslip that did not record them, gives
    nothing to compare: nothing is returned for it.)
    """
    parts = _mark(os.fspath(path)).get("identity_parts")
    if not isinstance(parts, Mapping):
        return []
    out = []
    for name, values in coords.items():
        want = parts.get(f"shown.{name}")
        if want is not None and json.dumps(np.asarray(values), default=hashable) != want:
            out.append(name)
    return out


def _mark(p: str) -> dict[str, Any]:
    if not is_store(p):
        raise StoreError(f"store={p!r}: not a stickslip store")
    with open(os.path.join(p, "zarr.json"), encoding="utf-8") as f:
        mark = json.load(f)["attributes"][MARK]
    if not isinstance(mark, dict):
        raise StoreError(f"store={p!r}: its mark ({MARK!r} in zarr.json) is damaged")
    return mark


def _digest(arrays: Mapping[str, npt.NDArray[Any]], names: list[str]) -> str:
    h = hashlib.blake2b(digest_size=16)
    for name in names:
        a = np.ascontiguousarray(arrays[name])
        h.update(name.encode())
        h.update(str(a.dtype).encode())
        h.update(str(a.shape).encode())
        h.update(a.tobytes())
    return h.hexdigest()


class ChunkStore:
    """A job's store on disk: create or reopen, find the finished blocks, write a block.

    Use :meth:`open` (the client, once) and :meth:`write_block` (any process,
    for one block). A store is only ever written block by block, each block's
    region being whole chunks of every array.
    """

    def __init__(self, path: str, layout: Layout, store_id: str = "") -> None:
        self.path = path
        self.layout = layout
        #: made when the store was created: a store deleted and made again is another one
        self.store_id = store_id

    def __reduce__(self) -> tuple[Any, ...]:
        # sent to every worker with each block: without the coordinates
        return (ChunkStore, (self.path, self.layout.light(), self.store_id))

    # ------------------------------------------------------------------ opening

    @classmethod
    def open(cls, path: str | os.PathLike[str], layout: Layout) -> ChunkStore:
        """Open the store of ``layout`` at ``path``, creating it if there is none.

        An existing store must hold the same job (same :attr:`Layout.identity`);
        its block shape is kept (a second run may use other workers or another
        chunk size: the store's blocks win).

        Raises
        ------
        StoreError
            ``path`` exists and is not a stickslip store, or holds another job,
            or cannot be created.

        """
        p = os.path.abspath(os.fspath(path))
        if os.path.exists(p):
            return cls._reopen(p, layout)
        parent = os.path.dirname(p)
        if not os.path.isdir(parent):
            what = "is a file, not a folder" if os.path.exists(parent) else "does not exist"
            raise StoreError(f"store={os.fspath(path)!r}: the folder {parent} {what}")
        if os.path.splitext(p)[1].lower() in _FILE_SUFFIXES:
            raise StoreError(
                f"store={os.fspath(path)!r}: a store is a Zarr folder, not a {os.path.splitext(p)[1]} file: "
                "name it PATH.zarr (a sweep's NetCDF file is --out / save_sweep)"
            )
        try:
            store_id = cls._create(p, layout)
        except Exception as exc:
            # (_create removes its own temporary folder; p is not ours to remove)
            err = disk_error(exc)
            if err is not None and err.errno in (errno.EEXIST, errno.ENOTEMPTY) and os.path.exists(p):
                # another run of the same command made it first: use that one
                return cls._reopen(p, layout)
            if err is None:
                raise
            raise StoreError(f"store={os.fspath(path)!r}: cannot create it: {why(err)}") from None
        return cls(p, layout, store_id)

    @classmethod
    def _reopen(cls, p: str, layout: Layout) -> ChunkStore:
        if os.path.isfile(p):
            raise StoreError(
                f"store={p!r} is a file, not a store: refusing to overwrite it (give a new path)"
            )
        if not is_store(p):
            raise StoreError(
                f"store={p!r} exists and is not a stickslip store: refusing to overwrite it (give a new path)"
            )
        mark = _mark(p)
        theirs = mark.get("identity")
        if theirs != layout.identity_digest:  # first: another job's store is not "damaged"
            raise StoreError(
                f"store={p!r} holds another job: {differences(mark, layout)}; "
                "give another --store path, or delete that one"
            )
        try:
            chunks = tuple(int(c) for c in mark["chunks"])
            if len(chunks) != len(layout.dims) or any(c < 1 for c in chunks):
                raise ValueError(chunks)
        except (TypeError, KeyError, ValueError):
            raise StoreError(
                f"store={p!r}: its mark ({MARK!r} in zarr.json) is damaged: "
                "delete the store and run the command again"
            ) from None
        if chunks != layout.chunks:
            layout = dataclasses.replace(layout, chunks=chunks)
        repair_metadata(p, layout)
        repair_coordinates(p, layout)
        try:
            os.makedirs(os.path.join(p, DONE), exist_ok=True)  # its markers' folder, if it was lost
        except OSError as exc:
            if exc.errno not in (errno.EROFS, errno.EACCES, errno.EPERM):
                raise StoreError(f"store={p!r}: cannot use it: {why(exc)}") from None
            # read-only: a finished store still reads; writing a block says why not
        return cls(p, layout, str(mark.get("store_id", "")))

    @staticmethod
    def _create(p: str, layout: Layout) -> str:
        import zarr

        # built in a temporary folder beside it, then renamed: a store is there whole or not at all
        tmp = temporary_folder(os.path.dirname(p) or ".", ".creating-")
        store_id = uuid.uuid4().hex
        try:
            attrs = {
                **{
                    k: jsonable(v) if isinstance(v, np.generic | np.ndarray) else v
                    for k, v in layout.attrs.items()
                },
                MARK: {
                    "kind": layout.kind,
                    "identity": layout.identity_digest,
                    "describe": layout.describe,
                    "chunks": list(layout.chunks),
                    "shape": list(layout.shape),
                    "dims": list(layout.dims),
                    "store_id": store_id,
                    "identity_parts": identity_parts(layout),
                },
            }
            g = zarr.open_group(tmp, mode="w", zarr_format=3, attributes=attrs)
            for name, (dims, values, vattrs) in layout.coords.items():
                vals = np.asarray(values)
                g.create_array(
                    name, data=vals, chunks=vals.shape, dimension_names=dims, attributes=dict(vattrs)
                )
            for v in layout.variables:
                k = len(v.dims)
                g.create_array(
                    v.name,
                    shape=layout.shape[:k],
                    chunks=layout.chunks[:k],
                    dtype=v.dtype,
                    fill_value=v.fill,
                    dimension_names=v.dims,
                    attributes=dict(v.attrs),
                )
            with warnings.catch_warnings():  # "not part of the format 3 spec": xarray reads it
                warnings.simplefilter("ignore")
                zarr.consolidate_metadata(tmp)
            os.makedirs(os.path.join(tmp, DONE))
            os.rename(tmp, p)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        return store_id

    # ------------------------------------------------------------------ finished blocks

    def _marker(self, index: int) -> str:
        return os.path.join(self.path, DONE, f"{index:09d}")

    def marked(self) -> set[int]:
        """Return the blocks with a marker (finished, not yet verified)."""
        folder = os.path.join(self.path, DONE)
        try:
            names = os.listdir(folder)
        except FileNotFoundError:
            return set()
        return {int(n) for n in names if n.isdigit()}

    def finished(self, *, verify: bool = True) -> set[int]:
        """Return the blocks already written, checked against their digests.

        A block whose data cannot be read back, or whose digest differs (a
        truncated, corrupt or missing chunk file), loses its marker and is not
        returned, so that it is computed again.
        """
        marked = self.marked()
        if not verify or not marked:
            return marked
        import zarr

        g = zarr.open_group(self.path, mode="r")
        names = [v.name for v in self.layout.variables]
        arrays: dict[str, Any] = {n: g[n] for n in names}
        good = set()
        for block in self.layout.blocks():
            if block.index not in marked:
                continue
            try:
                with open(self._marker(block.index), encoding="ascii") as f:
                    want = f.read().strip()
                data = {n: np.asarray(arrays[n][self.layout.region(n, block)]) for n in names}
                ok = _digest(data, names) == want
            except Exception:  # an unreadable chunk: compute the block again
                ok = False
            if ok:
                good.add(block.index)
            else:
                try:
                    os.remove(self._marker(block.index))
                except OSError:
                    pass
        return good

    # ------------------------------------------------------------------ writing

    def write_block(self, block: Block, arrays: Mapping[str, npt.NDArray[Any]]) -> str:
        """Write one block's arrays to their regions, then its marker; return the digest.

        Raises
        ------
        StoreError
            The disk refused the write (full, read-only, no permission); the
            blocks written before are intact, and this one has no marker.

        """
        names = [v.name for v in self.layout.variables]
        try:
            handles = _arrays(
                self.path, (self.layout.identity_digest, self.layout.chunks, self.store_id), names
            )
            for v in self.layout.variables:
                a = np.asarray(arrays[v.name], dtype=v.dtype)
                handles[v.name][self.layout.region(v.name, block)] = a
            typed = {n: np.asarray(arrays[n], dtype=self.layout.variable(n).dtype) for n in names}
            digest = _digest(typed, names)
            marker = self._marker(block.index)
            os.makedirs(os.path.dirname(marker), exist_ok=True)  # deleted while the job ran
            fd, tmp = temporary_file(os.path.dirname(marker), ".tmp-")
            try:
                with os.fdopen(fd, "w", encoding="ascii") as f:
                    f.write(digest)
                os.replace(tmp, marker)
            except BaseException:
                if os.path.exists(tmp):
                    os.remove(tmp)
                raise
        except Exception as exc:
            err = disk_error(exc)
            if err is None:
                raise
            raise StoreError(
                f"store={self.path!r}: cannot write block {block.index} of {self.layout.n_blocks}: "
                f"{why(err)}; the blocks written before are intact: fix that and run the same "
                "command again"
            ) from None
        return digest

    # ------------------------------------------------------------------ reading

    def open_dataset(self) -> Any:
        """Return the store as a lazily read ``xarray.Dataset``."""
        import xarray as xr

        ds = xr.open_zarr(self.path, consolidated=True, chunks=None)
        ds.attrs.pop(MARK, None)
        return ds


_ARRAYS: dict[tuple[str, Any], dict[str, Any]] = {}
#: stores whose arrays a process keeps open (a notebook or a worker that writes many stores)
_KEEP_ARRAYS = 8
_ARRAYS_LOCK = threading.Lock()


def _arrays(path: str, key: Any, names: list[str]) -> dict[str, Any]:
    """Return the store's arrays opened for writing, once per process and store.

    Opening an array reads its metadata from the disk through zarr's event loop, which
    takes as long as writing a block itself: once per store, not once per block. ``key``
    (the job's identity, its chunks and the store's id) tells a store deleted and made
    again at the same path from the one opened before, whose handles would write chunks
    of the old shape into the new one, silently.
    """
    with _ARRAYS_LOCK:  # a threaded Dask worker writes blocks side by side
        got = _ARRAYS.pop((path, key), None)  # put back last: the most recent
        if got is None:
            import zarr

            g = zarr.open_group(path, mode="r+", use_consolidated=False)
            got = {n: g[n] for n in names}
            while len(_ARRAYS) >= _KEEP_ARRAYS:  # the store used least recently goes
                del _ARRAYS[next(iter(_ARRAYS))]
        _ARRAYS[(path, key)] = got
        return got
