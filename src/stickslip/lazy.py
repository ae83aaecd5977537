"""Lazy attributes of a package (PEP 562): a name loads its module on first use.

Used by :mod:`stickslip` and :mod:`stickslip.cli`, so that ``import stickslip`` and
``python -m stickslip.cli`` load nothing heavy before they can answer a Ctrl-C.
Imports nothing but :mod:`importlib`.
"""

from __future__ import annotations

import importlib
from collections.abc import Collection, Mapping
from typing import Any

__all__ = ["load_attribute"]


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
