"""Lazy attributes of a package (PEP 562): a name loads its module on first use.

Used by :mod:`stickslip` and :mod:`stickslip.cli`, so that ``import stickslip`` and
``python -m stickslip.cli`` load nothing heavy before they can answer a Ctrl-C.
Imports nothing but :mod:`importlib`.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Collection, Mapping
from typing import Any

__all__ = ["exports", "load_attribute"]


def load_attribute(package: str, name: str, homes: Mapping[str, str], modules: Collection[str]) -> Any:
    """Return ``package.name``, importing what holds it.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    name : str
        The attribute asked for.
    homes : mapping
        Exported name to the submodule (relative to ``package``) that defines it.
    modules : collection of str
        Submodules returned themselves.

    Raises
    ------
    AttributeError
        ``name`` is neither exported nor a submodule, as Python says it.

    """
    if name in homes:
        return getattr(importlib.import_module(f".{homes[name]}", package), name)
    if name in modules:
        return importlib.import_module(f".{name}", package)
    raise AttributeError(f"module {package!r} has no attribute {name!r}")


def exports(package: str, homes: Mapping[str, str]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """Return a package's ``__getattr__`` and ``__dir__`` that load its exported names on first use.

    ``homes`` maps each exported name to the submodule that defines it. A name loaded
    once is kept in the package's namespace, so later uses cost a dictionary lookup.
    """
    import sys

    def __getattr__(name: str) -> Any:
        value = load_attribute(package, name, homes, ())
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted({*vars(sys.modules[package]), *homes})

    return __getattr__, __dir__
