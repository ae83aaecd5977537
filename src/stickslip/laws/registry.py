"""The registry of friction laws: every name ``--law`` accepts, and its classes.

A law module declares a :class:`~.spec.LawSpec` and calls :func:`register`;
that is all it takes for the law to work in every command, sweep, regime map,
JSON file and the docs table. A law registered at run time (a test's, a
plug-in's) works the same way: the command line builds its options from the
registry when it parses.
"""

from __future__ import annotations

import inspect
from typing import Any

from ..errors import ArgumentTypeError
from .base import DimensionlessLaw, PhysicalLaw
from .spec import LawSpec, Parameter

__all__ = [
    "RESERVED",
    "LawEntry",
    "dimensionless_class",
    "get",
    "names",
    "physical_class",
    "register",
    "unregister",
]

#: names no law parameter may take: set-up options, and attributes of the law classes
RESERVED = frozenset(
    {
        "nu", "v0", "mass", "stiffness", "load", "beta", "mu_s", "law", "preset", "rtol", "atol",
        "f", "mu", "static", "table", "param", "w", "v",
        *(n for n in dir(DimensionlessLaw) if not n.startswith("_")),
        *(n for n in dir(PhysicalLaw) if not n.startswith("_")),
    }
)  # fmt: skip


class LawEntry:
    """A registered law: its spec and its dimensionless and physical classes."""

    def __init__(
        self, spec: LawSpec, dimensionless: type[DimensionlessLaw], physical: type[PhysicalLaw]
    ) -> None:
        self.spec = spec
        self.dimensionless_class = dimensionless
        self.physical_class = physical

    def dimensionless(self, *args: Any, **kwargs: Any) -> DimensionlessLaw:
        """Return the law in dimensionless form with these parameters."""
        return self.dimensionless_class(*args, **kwargs)

    def physical(self, *args: Any, **kwargs: Any) -> PhysicalLaw:
        """Return the law in physical form (``mu_s`` first) with these parameters."""
        return self.physical_class(*args, **kwargs)


_LAWS: dict[str, LawEntry] = {}
#: increases with every change of the registry (the command line rebuilds its options)
version = 0


def register(
    spec: LawSpec,
    dimensionless: type[DimensionlessLaw] | None = None,
    physical: type[PhysicalLaw] | None = None,
) -> LawEntry:
    """Register a law under ``spec.name``; return its entry.

    Classes not given are made (``<Name>Law`` and ``Physical<Name>Law``).

    Raises
    ------
    ValueError
        For a name already taken by another law, or a parameter name that would
        clash with an option or attribute.

    """
    global version
    if spec.name in _LAWS and _LAWS[spec.name].spec is not spec:
        raise ValueError(f"a law named {spec.name!r} is already registered")
    if (
        not spec.name.replace("-", "_").isidentifier()
        or spec.name.startswith("-")
        or spec.name in ("expr", "table")
    ):
        raise ValueError(
            f"law name {spec.name!r}: expected an identifier (hyphens allowed) other than 'expr' and 'table'"
        )
    for p in (*spec.parameters, *spec.physical):
        if p.name in RESERVED:
            raise ValueError(f"law {spec.name!r}: the parameter name {p.name!r} is reserved")
    title = "".join(part.capitalize() for part in spec.name.replace("-", "_").split("_"))
    if dimensionless is None:
        dimensionless = type(f"{title}Law", (DimensionlessLaw,), {"__slots__": (), "_spec": spec})
    if physical is None:
        physical = type(f"Physical{title}Law", (PhysicalLaw,), {"__slots__": (), "_spec": spec})
    # help(), inspect.signature and a notebook's completion show the law's parameters, not
    # (*args, **kwargs)
    dimensionless.__signature__ = _signature(spec.parameters)  # type: ignore[attr-defined]
    physical.__signature__ = _signature(  # type: ignore[attr-defined]
        (Parameter("mu_s", "static friction coefficient"), *spec.physical)
    )
    entry = LawEntry(spec, dimensionless, physical)
    _LAWS[spec.name] = entry
    version += 1
    return entry


def _signature(params: tuple[Parameter, ...]) -> inspect.Signature:
    """Return a law class's call signature: its parameters, a default where they have one."""
    return inspect.Signature(
        [
            inspect.Parameter(
                p.name,
                inspect.Parameter.POSITIONAL_OR_KEYWORD,
                default=inspect.Parameter.empty if p.default is None else p.default,
            )
            for p in params
        ]
    )


def unregister(name: str) -> None:
    """Remove a law (tests)."""
    global version
    _LAWS.pop(name, None)
    version += 1


def get(name: str) -> LawEntry:
    """Return the registered law ``name``.

    Raises
    ------
    ArgumentTypeError
        For a name that is not a str.
    ValueError
        For an unknown name, naming the laws there are.

    """
    if not isinstance(name, str):
        raise ArgumentTypeError(
            f"law={name!r} (type {type(name).__name__}): expected one of {', '.join(names())}"
        )
    try:
        return _LAWS[name]
    except KeyError:
        raise ValueError(f"law={name!r}: expected one of {', '.join(names())}") from None


def names() -> list[str]:
    """Return the registered laws' names, in order of registration."""
    return list(_LAWS)


def entries() -> list[LawEntry]:
    """Return the registered laws."""
    return list(_LAWS.values())


def dimensionless_class(spec: LawSpec) -> type[DimensionlessLaw]:
    """Return the dimensionless class of a spec (the base class for unregistered specs)."""
    e = _LAWS.get(spec.name)
    if e is not None and e.spec is spec:
        return e.dimensionless_class
    return type(f"{spec.name}Law", (DimensionlessLaw,), {"__slots__": (), "_spec": spec})


def physical_class(spec: LawSpec) -> type[PhysicalLaw]:
    """Return the physical class of a spec."""
    e = _LAWS.get(spec.name)
    if e is not None and e.spec is spec:
        return e.physical_class
    return type(f"Physical{spec.name}Law", (PhysicalLaw,), {"__slots__": (), "_spec": spec})


def rebuild_dimensionless(name: str, params: dict[str, float]) -> DimensionlessLaw:
    """Unpickle a registered dimensionless law."""
    return get(name).dimensionless(**params)


def rebuild_physical(name: str, mu_s: float, si: dict[str, float]) -> PhysicalLaw:
    """Unpickle a registered physical law."""
    e = get(name)
    return e.physical_class._from_values(e.spec, mu_s, si)
