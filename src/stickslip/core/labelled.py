"""The two kinds of decoded result: enums whose members carry a code and a message, and named rows.

:class:`_Labelled` is a string enum: a member equals its label (``Status.OK == "ok"``),
and carries its integer code (the kernels' and the NetCDF flag values) and its message
for users, in the manner of diffrax's ``RESULTS``. :class:`_Rows` is a kernel's output
rows with a named field per column (:func:`_field`), views that write the rows.
The results of each engine are declared with these in :mod:`.results`,
:mod:`.chain_results` and :mod:`.ratestate_results`.
"""

from __future__ import annotations

import enum
from typing import Any

import numpy as np
import numpy.typing as npt


class _Labelled(enum.StrEnum):
    """A string enum whose members carry an integer code and a message."""

    code: int
    message: str

    def __new__(cls, label: str, code: int, message: str) -> _Labelled:
        obj = str.__new__(cls, label)
        obj._value_ = label
        obj.code = code
        obj.message = message
        return obj

    @classmethod
    def from_code(cls, code: Any) -> Any:
        """Return the member with integer code ``code``."""
        c = int(code)
        for m in cls:
            if m.code == c:
                return m
        raise ValueError(f"{cls.__name__}: no member with code {c}")

    @classmethod
    def from_label(cls, label: str) -> Any:
        """Return the member labelled ``label`` (ValueError when there is none)."""
        for m in cls:
            if m.value == label:
                return m
        raise ValueError(f"{cls.__name__}: no member {label!r}")

    @classmethod
    def codes(cls) -> dict[str, int]:
        """Return ``{label: code}`` of every member (for NetCDF ``flag_values``)."""
        return {m.value: m.code for m in cls}


#: the fields of each kind of rows, by name, with their columns (:meth:`_Rows.layout`)
_LAYOUTS: dict[type, dict[str, int]] = {}


class _Rows:
    """Rows of a kernel's output with a named field per column (views: writable).

    ``fields``: the names of the fields these rows keep, in the layout's order, where
    they keep only some (``raw`` then has a column for each, in that order); None
    where they keep every column of the layout. Reading or writing a field they do
    not keep raises an AttributeError that says so (``hasattr`` is then False).
    """

    _width: int = 0

    def __init__(self, raw: npt.ArrayLike, fields: tuple[str, ...] | str | None = None) -> None:
        if isinstance(fields, str):
            fields = (fields,)
        if fields is not None:
            fields = tuple(fields)
            if fields != type(self).check_fields(fields):
                raise ValueError(
                    f"{type(self).__name__}: fields {fields} not each once in the layout's order"
                )
            if len(fields) == len(type(self).layout()):
                fields = None  # every field, in the layout's order: the full rows
        a = np.asarray(raw, dtype=np.float64)
        if a.ndim == 1:
            a = a[None, :]
        width = self._width if fields is None else len(fields)
        if a.ndim != 2 or a.shape[1] != width:
            raise ValueError(f"{type(self).__name__}: expected rows of {width} values, got {a.shape}")
        self.raw = a
        self.fields = fields
        self._where: dict[int, int] | None = None
        if fields is not None:
            layout = _LAYOUTS.get(type(self)) or type(self).layout()
            self._where = {layout[name]: j for j, name in enumerate(fields)}

    @classmethod
    def layout(cls) -> dict[str, int]:
        """Return every field's name and its column in the kernel's rows, in the columns' order."""
        if cls not in _LAYOUTS:
            found = {
                name: f.column
                for k in reversed(cls.__mro__)
                for name, f in vars(k).items()
                if isinstance(f, _Field)
            }
            _LAYOUTS[cls] = dict(sorted(found.items(), key=lambda item: item[1]))
        return dict(_LAYOUTS[cls])

    @classmethod
    def check_fields(cls, fields: Any) -> tuple[str, ...]:
        """Return ``fields`` (names of this kind's fields) once each, in the layout's order.

        Raises
        ------
        ValueError
            For a name that is not a field, or no name at all.

        """
        names = [fields] if isinstance(fields, str) else list(fields)
        layout = cls.layout()
        unknown = [x for x in names if x not in layout]
        if unknown or not names:
            raise ValueError(
                f"fields={unknown[0] if unknown else names!r}: expected names of {cls.__name__}'s "
                f"fields ({', '.join(layout)})"
            )
        return tuple(x for x in layout if x in names)

    def keeps(self, name: str) -> bool:
        """Whether these rows keep the field ``name``."""
        return name in type(self).layout() and (self.fields is None or name in self.fields)

    def _column(self, f: _Field) -> int:
        if self._where is None:
            return f.column
        j = self._where.get(f.column)
        if j is None:
            kept = ", ".join(self.fields or ())
            raise AttributeError(f"{type(self).__name__}.{f.name}: not kept by these rows (they keep {kept})")
        return j

    def __len__(self) -> int:
        return int(self.raw.shape[0])

    def __getitem__(self, index: Any) -> Any:
        """Return the rows selected by ``index`` (an integer keeps a row of its own)."""
        sub = self.raw[index]
        return type(self)(sub if sub.ndim == 2 else sub[None, :], self.fields)

    def copy(self) -> Any:
        """Return a copy that shares nothing with these rows."""
        return type(self)(self.raw.copy(), self.fields)

    def __setitem__(self, index: Any, other: _Rows) -> None:
        if other.fields != self.fields:
            raise ValueError(
                f"{type(self).__name__}: rows of other fields ({other.fields}) put into rows of {self.fields}"
            )
        self.raw[index] = other.raw

    @classmethod
    def concat(cls, parts: Any) -> Any:
        """Return the rows of ``parts`` (rows of this kind, keeping the same fields) one after the other."""
        parts = list(parts)
        kept = {p.fields for p in parts}
        if len(kept) > 1:
            raise ValueError(f"{cls.__name__}.concat: rows of different fields ({sorted(map(str, kept))})")
        return cls(np.vstack([p.raw for p in parts]), kept.pop() if kept else None)


class _Field:
    """A named column of a kernel's rows (a view of it: writing it writes the rows)."""

    def __init__(self, column: int, doc: str) -> None:
        self.column = column
        self.__doc__ = doc
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, obj: _Rows | None, owner: type | None = None) -> Any:
        if obj is None:
            return self
        return obj.raw[:, obj._column(self)]

    def __set__(self, obj: _Rows, value: Any) -> None:
        obj.raw[:, obj._column(self)] = value


def _field(column: int, doc: str) -> Any:
    return _Field(column, doc)
