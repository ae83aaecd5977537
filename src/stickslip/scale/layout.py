"""The shape of a job's result and what defines it: grid, blocks, variables, identity.

A :class:`Layout` is a job's grid (dimensions, coordinates), its cut into
:class:`Block` s (the chunks of the store's arrays, :func:`chunk_shape`), the
:class:`Variable` s of its result and its *identity*: what defines the values,
compared by digest with the identity a store records. :func:`differences` says how
two identities differ, key by key, for the error that refuses another job's store.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import itertools
import json
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = [
    "Block",
    "Layout",
    "Variable",
    "chunk_shape",
    "differences",
    "hashable",
    "identity_parts",
    "jsonable",
]


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

        (Not -1 for integers: that is a real code, the ``unknown`` regime or a ``sliding``
        chain, which a store read before it is finished would show for points never computed.)
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
        text = json.dumps({"kind": self.kind, **self.identity}, sort_keys=True, default=hashable)
        return hashlib.sha256(text.encode()).hexdigest()

    def light(self) -> Layout:
        """Return the same layout without its coordinates (what a worker needs to write a block)."""
        out = dataclasses.replace(self, coords={}, identity={})
        out.__dict__["identity_digest"] = self.identity_digest
        return out


def hashable(x: Any) -> Any:
    """JSON ``default`` of an identity: an array as its type, shape and digest, a numpy scalar as a number."""
    if isinstance(x, np.ndarray):
        a = np.ascontiguousarray(x)
        return f"array {a.dtype} {a.shape} " + hashlib.blake2b(a.tobytes(), digest_size=16).hexdigest()
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"{type(x).__name__} is not JSON-able")


def jsonable(x: Any) -> Any:
    """JSON ``default`` of an attribute: an array as a list, a numpy scalar as a number."""
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


def identity_parts(layout: Layout) -> dict[str, str]:
    """Return the identity key by key, in words (arrays by their digest): to say how jobs differ."""
    out: dict[str, str] = {}

    def walk(prefix: str, value: Any) -> None:
        if isinstance(value, Mapping):
            for k, v in value.items():
                walk(f"{prefix}.{k}" if prefix else str(k), v)
        else:
            out[prefix] = json.dumps(value, sort_keys=True, default=hashable, ensure_ascii=False)

    walk("", {"kind": layout.kind, **layout.identity})
    return out


def differences(mark: Mapping[str, Any], layout: Layout) -> str:
    """Say how the job of a store's ``mark`` differs from ``layout``'s, key by key where it can."""
    theirs = mark.get("identity_parts")
    ours = identity_parts(layout)
    both = f"{mark.get('describe', '?')}; this one is {layout.describe}"
    if not isinstance(theirs, Mapping) or theirs.get("kind") != ours["kind"]:
        return both  # a mark without identity parts, or another kind of job: the two named
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
    """``'"array float64 (20,) 5f0c..."'`` (an array in :func:`identity_parts`) as ``'20 values'``."""
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
