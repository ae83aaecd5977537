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
"""

from __future__ import annotations

import contextlib
import dataclasses
import errno
import functools
import hashlib
import itertools
import json
import math
import os
import shutil
import threading
import uuid
import warnings
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from ..io.errors import DataError
from ..io.output import temporary_file, temporary_folder
from ..userwarnings import warn

__all__ = [
    "Block",
    "ChunkStore",
    "Layout",
    "StoreError",
    "Variable",
    "chunk_shape",
    "computed_points",
    "damaged_coordinates",
    "is_store",
    "store_kind",
]

#: attribute of the group that marks a stickslip store (and holds the job's identity)
MARK = "stickslip_store"
#: folder (inside the store) of the markers of finished blocks
DONE = ".stickslip-done"
#: names of files that a new store's path may not take (a store is a folder)
_FILE_SUFFIXES = (".nc", ".nc4", ".netcdf", ".h5", ".hdf5", ".csv", ".json", ".txt", ".png", ".svg")


class StoreError(DataError):
    """A store cannot be used: another job's, unreadable, or the disk refuses writes (one line).

    A :class:`~stickslip.io.errors.DataError` (so a :class:`ValueError`): the command
    line prints it as one ``Error:`` line.
    """


@dataclass(frozen=True)
class Variable:
    """One array of a job's result.

    Attributes
    ----------
    name : str
        Variable name.
    dims : tuple of str
        Its dimensions: the job's dimensions, or a leading subset of them whose
        trailing dimensions are never split into blocks.
    dtype : str
        numpy dtype (``float64``, ``int8``, ``bool``, ``int64``).
    attrs : mapping
        Attributes (``units``, ``long_name``, CF ``flag_values``/``flag_meanings``).

    """

    name: str
    dims: tuple[str, ...]
    dtype: str
    attrs: Mapping[str, Any] = field(default_factory=dict)

    @property
    def fill(self) -> Any:
        """Value of a chunk never written: NaN for floats, the type's least integer, False.

        (Integers were -1 before 2026-11-24: a real code, ``unknown`` regime or ``sliding``
        chain, in a store read before it was finished.)
        """
        kind = np.dtype(self.dtype).kind
        if kind == "f":
            return math.nan
        return False if kind == "b" else int(np.iinfo(np.dtype(self.dtype)).min)


@dataclass(frozen=True)
class Block:
    """One block of a job: its number, its region in the grid and its size in points."""

    index: int
    slices: tuple[slice, ...]

    @property
    def points(self) -> int:
        """Grid points in the block."""
        return int(np.prod([s.stop - s.start for s in self.slices], dtype=np.int64))


@dataclass(frozen=True)
class Layout:
    """The shape of a job's result and how it is cut into blocks.

    Attributes
    ----------
    kind : str
        ``sweep``, ``regime-map``, ``chain-ensemble``.
    dims, shape : tuple
        The grid.
    chunks : tuple of int
        Block (and chunk) shape.
    coords : mapping
        Coordinate name to ``(dims, values, attrs)``.
    variables : tuple of Variable
        The result's arrays.
    identity : mapping
        What defines the values (JSON-able): compared with an existing store's.
    attrs : mapping
        Other attributes of the result.
    describe : str
        One line naming the job, for messages.

    """

    kind: str
    dims: tuple[str, ...]
    shape: tuple[int, ...]
    chunks: tuple[int, ...]
    coords: Mapping[str, tuple[tuple[str, ...], npt.NDArray[Any], Mapping[str, Any]]]
    variables: tuple[Variable, ...]
    identity: Mapping[str, Any]
    attrs: Mapping[str, Any]
    describe: str

    def __post_init__(self) -> None:
        if len(self.chunks) != len(self.shape) or any(c < 1 for c in self.chunks):
            raise ValueError(f"chunks={self.chunks}: expected one positive size per dimension {self.dims}")
        for v in self.variables:
            k = len(v.dims)
            if v.dims != self.dims[:k] or any(
                c < s for c, s in zip(self.chunks[k:], self.shape[k:], strict=True)
            ):
                raise ValueError(f"variable {v.name} {v.dims}: blocks would split it")

    @property
    def n_blocks(self) -> int:
        """Number of blocks."""
        return int(np.prod(self.grid_of_blocks, dtype=np.int64))

    @property
    def grid_of_blocks(self) -> tuple[int, ...]:
        """Blocks along each dimension."""
        return tuple(-(-s // c) for s, c in zip(self.shape, self.chunks, strict=True))

    @property
    def points(self) -> int:
        """Grid points in all."""
        return int(np.prod(self.shape, dtype=np.int64))

    def blocks(self) -> Iterator[Block]:
        """Yield every block in row-major order."""
        ranges = [range(n) for n in self.grid_of_blocks]
        for i, idx in enumerate(itertools.product(*ranges)):
            yield Block(
                i,
                tuple(
                    slice(j * c, min((j + 1) * c, s))
                    for j, c, s in zip(idx, self.chunks, self.shape, strict=True)
                ),
            )

    def region(self, name: str, block: Block) -> tuple[slice, ...]:
        """Return the region of variable ``name`` that ``block`` writes."""
        v = self.variable(name)
        return block.slices[: len(v.dims)]

    def variable(self, name: str) -> Variable:
        """Return the variable called ``name``."""
        for v in self.variables:
            if v.name == name:
                return v
        raise KeyError(name)

    @functools.cached_property
    def identity_digest(self) -> str:
        """A digest of the identity (arrays by their bytes): equal for the same job only."""
        text = json.dumps({"kind": self.kind, **self.identity}, sort_keys=True, default=_hashable)
        return hashlib.sha256(text.encode()).hexdigest()

    def light(self) -> Layout:
        """Return the same layout without its coordinates (what a worker needs to write a block)."""
        out = dataclasses.replace(self, coords={}, identity={})
        out.__dict__["identity_digest"] = self.identity_digest
        return out


def _hashable(x: Any) -> Any:
    if isinstance(x, np.ndarray):
        a = np.ascontiguousarray(x)
        return f"array {a.dtype} {a.shape} " + hashlib.blake2b(a.tobytes(), digest_size=16).hexdigest()
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"{type(x).__name__} is not JSON-able")


def _jsonable(x: Any) -> Any:
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"{type(x).__name__} is not JSON-able")


def chunk_shape(shape: tuple[int, ...], target: int) -> tuple[int, ...]:
    """Return a block shape of about ``target`` points: whole trailing dimensions, the rest split.

    From the last dimension backward, whole dimensions are kept while the block
    stays within ``target`` points; the next dimension is cut to fit; the
    leading ones have blocks of one. A block is then one contiguous run of the
    grid's C order (or a few), so it maps to one region without gaps.
    """
    if target < 1:
        raise ValueError(f"chunk size {target!r}: expected at least one point")
    out = [1] * len(shape)
    size = 1
    for d in range(len(shape) - 1, -1, -1):
        if size * shape[d] <= target:
            out[d] = shape[d]
            size *= shape[d]
        else:
            out[d] = max(1, target // size)
            break
    return tuple(out)


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

    (A store made before 2026-11-24 records none: nothing is returned for it.)
    """
    parts = _mark(os.fspath(path)).get("identity_parts")
    if not isinstance(parts, Mapping):
        return []
    out = []
    for name, values in coords.items():
        want = parts.get(f"shown.{name}")
        if want is not None and json.dumps(np.asarray(values), default=_hashable) != want:
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


def _disk_error(exc: BaseException) -> OSError | None:
    """Return the OSError behind ``exc`` (zarr may wrap it), or None."""
    seen: BaseException | None = exc
    while seen is not None:
        if isinstance(seen, OSError):
            return seen
        if isinstance(seen, BaseExceptionGroup):
            for sub in seen.exceptions:
                found = _disk_error(sub)
                if found is not None:
                    return found
        seen = seen.__cause__ or seen.__context__
    return None


def _why(err: OSError) -> str:
    if err.errno in (errno.ENOSPC, errno.EDQUOT):
        return "the disk is full"
    if err.errno in (errno.EACCES, errno.EPERM):
        return "permission denied"
    if err.errno == errno.EROFS:
        return "the file system is read-only"
    return err.strerror or str(err)


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
            err = _disk_error(exc)
            if err is not None and err.errno in (errno.EEXIST, errno.ENOTEMPTY) and os.path.exists(p):
                # another run of the same command made it first: use that one
                return cls._reopen(p, layout)
            if err is None:
                raise
            raise StoreError(f"store={os.fspath(path)!r}: cannot create it: {_why(err)}") from None
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
                f"store={p!r} holds another job: {_differences(mark, layout)}; "
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
        _repair_metadata(p, layout)
        _repair_coordinates(p, layout)
        try:
            os.makedirs(os.path.join(p, DONE), exist_ok=True)  # its markers' folder, if it was lost
        except OSError as exc:
            if exc.errno not in (errno.EROFS, errno.EACCES, errno.EPERM):
                raise StoreError(f"store={p!r}: cannot use it: {_why(exc)}") from None
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
                    k: _jsonable(v) if isinstance(v, np.generic | np.ndarray) else v
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
                    "identity_parts": _parts(layout),
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
            err = _disk_error(exc)
            if err is None:
                raise
            raise StoreError(
                f"store={self.path!r}: cannot write block {block.index} of {self.layout.n_blocks}: "
                f"{_why(err)}; the blocks written before are intact: fix that and run the same "
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

    Opening an array reads its metadata from the disk through zarr's event loop: as
    long as writing the block itself, when it was done for every block. ``key`` (the
    job's identity, its chunks and the store's id) tells a store deleted and made
    again at the same path from the one opened before: the handles of the old one
    wrote chunks of the old shape into the new one, silently.
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


def _parts(layout: Layout) -> dict[str, str]:
    """Return the identity key by key, in words (arrays by their digest): to say how jobs differ."""
    out: dict[str, str] = {}

    def walk(prefix: str, value: Any) -> None:
        if isinstance(value, Mapping):
            for k, v in value.items():
                walk(f"{prefix}.{k}" if prefix else str(k), v)
        else:
            out[prefix] = json.dumps(value, sort_keys=True, default=_hashable, ensure_ascii=False)

    walk("", {"kind": layout.kind, **layout.identity})
    return out


def _differences(mark: Mapping[str, Any], layout: Layout) -> str:
    """Say how the job of a store's ``mark`` differs from ``layout``'s, key by key where it can."""
    theirs = mark.get("identity_parts")
    ours = _parts(layout)
    both = f"{mark.get('describe', '?')}; this one is {layout.describe}"
    if not isinstance(theirs, Mapping) or theirs.get("kind") != ours["kind"]:
        return both  # a store made before 2026-11-24, or another kind of job: the two named
    said = []
    for key in sorted(theirs.keys() | ours.keys()):
        a, b = theirs.get(key), ours.get(key)
        if a == b:
            continue
        if a is None:
            said.append(f"{key} {_short(str(b))} here, none there")
        elif b is None:
            said.append(f"{key} {_short(str(a))} there, none here")
        elif str(a).startswith('"array ') and str(b).startswith('"array '):
            grid = f"grid.{key[6:]}"
            if key.startswith("shown.") and theirs.get(grid) != ours.get(grid):
                continue  # the same axis in the user's units: said once, as grid.*
            na, nb = _size(str(a)), _size(str(b))
            said.append(f"other values of {key}" + (f" ({na} there, {nb} here)" if na != nb else ""))
        else:
            x, y = _excerpts(str(a), str(b))
            said.append(f"{key} {x} there, {y} here")
    if not said:  # same parts, another digest (a change in how the identity is written)
        return f"{mark.get('describe', '?')}, made by another version of stickslip"
    return f"{mark.get('describe', '?')}, with {'; '.join(said)}"


def _size(text: str) -> str:
    """``'"array float64 (20,) 5f0c..."'`` (an array in :func:`_parts`) as ``'20 values'``."""
    dims = [int(k) for k in text.split(" (", 1)[1].split(")", 1)[0].split(",") if k.strip()]
    return f"{dims[0]} values" if len(dims) == 1 else f"shape {tuple(dims)}"


def _excerpts(a: str, b: str, width: int = 100) -> tuple[str, str]:
    """Return ``a`` and ``b`` cut to ``width`` around where they first differ."""
    if max(len(a), len(b)) <= width:
        return a, b
    first = next((i for i, (x, y) in enumerate(zip(a, b, strict=False)) if x != y), min(len(a), len(b)))
    start = max(0, first - width // 3)

    def cut(t: str) -> str:
        part = t[start : start + width]
        return ("..." if start else "") + part + ("..." if start + width < len(t) else "")

    return cut(a), cut(b)


def _short(text: str, width: int = 100) -> str:
    return text if len(text) <= width else text[: width - 3] + "..."


def _repair_coordinates(p: str, layout: Layout) -> None:
    """Write a store's coordinates again where they no longer read back as the job's.

    The identity (checked) fixes them; a deleted or corrupt chunk of a coordinate
    read as zeros or raised inside numcodecs, and the loaded result had a wrong grid.

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
            err = _disk_error(exc)
            raise StoreError(
                f"store={p!r}: its coordinate {name!r} no longer reads as the grid, and it cannot "
                f"be written again ({_why(err) if err is not None else exc})"
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
        return None, f"cannot be read ({_why(exc)})"


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


def _repair_metadata(p: str, layout: Layout) -> None:
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
        group = json.load(f)  # read by _mark just before: it parses
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
                    f"{where} {problem or differs}, and it cannot be written again ({_why(exc)}): "
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
                f"{what}, and it cannot be written again ({_why(exc)}): delete the store and run the "
                "command again"
            ) from None
        warn(f"{what}: written again from the array's own zarr.json")
