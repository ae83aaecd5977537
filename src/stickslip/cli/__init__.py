"""Command line: a thin layer over the public API, one module per command family.

:mod:`~.dynamics` (``cycle``, ``simulate``, ``sweep``), :mod:`~.bifurcation`
(``regimes``), :mod:`~.data` (``analyze``, ``fit``, ``classify``),
:mod:`~.ratestate` (``ratestate``, ``dulac``), :mod:`~.chain` (``chain``) and
:mod:`~.paper` (``reproduce``) and :mod:`~.explore` (``explore``, the browser app);
the options of a parameter set are built from the law registry (:mod:`~.options`).
"""

from __future__ import annotations

import warnings
from typing import Any

import click

from . import bifurcation, chain, data, dynamics, explore, paper, ratestate
from .options import build_parameters, describe_parameters

__all__ = ["build_parameters", "describe_parameters", "main"]


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="stickslip")
def main() -> None:
    """Friction oscillators: the one-block spring-slider, exact and fast."""
    warnings.showwarning = _one_line_warning


def _one_line_warning(message: Any, category: Any, filename: str, lineno: int, *args: Any, **kw: Any) -> None:
    """Print a warning as one ``warning:`` line on standard error (no file, no source line)."""
    click.echo(f"warning: {message}", err=True)


for _family in (dynamics, paper, ratestate, data, bifurcation, chain, explore):
    _family.register(main)
