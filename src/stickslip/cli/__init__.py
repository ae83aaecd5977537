"""Command line: a thin layer over the public API, one module per command family.

:mod:`~.dynamics` (``cycle``, ``simulate``, ``sweep``), :mod:`~.bifurcation`
(``regimes``), :mod:`~.data` (``examples``, ``analyze``, ``fit``, ``classify``),
:mod:`~.ratestate` (``ratestate``, ``ratestate-fit``, ``earthquake-cycles``, ``dulac``),
:mod:`~.chain` (``chain``), :mod:`~.paper` (``reproduce``) and :mod:`~.explore`
(``explore``, the browser app);
the options of a parameter set are built from the law registry (:mod:`~.options`);
:mod:`~.commands` holds the click group. Each command is a module-level click
command of its family's module (``from stickslip.cli.dynamics import cycle``), to
import and invoke alone (``click.testing.CliRunner().invoke(cycle, [...])``); each
family's ``register(main)`` adds its commands to the group.

The package loads its command families on first use of a name (PEP 562), so that
``python -m stickslip.cli`` reaches :func:`stickslip.__main__.main`, which turns a
Ctrl-C during the seconds of imports into one line, before anything heavy loads.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..lazy import load_attribute

if TYPE_CHECKING:
    from .commands import main
    from .options import build_parameters, describe_parameters

__all__ = ["build_parameters", "describe_parameters", "main"]

_HOME = {"main": "commands", "build_parameters": "options", "describe_parameters": "options"}
_MODULES = ("bifurcation", "chain", "commands", "data", "dynamics", "errors", "explore", "options", "paper",
            "ratestate")  # fmt: skip


def __getattr__(name: str) -> Any:
    """Load a public name or a module of the command line on first use."""
    value = load_attribute(__name__, name, _HOME, _MODULES)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__) | set(_MODULES))
