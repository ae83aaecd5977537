"""The examples in the docstrings run and print what they say (numpydoc ``Examples``)."""

import doctest
import importlib
from pathlib import Path

import pytest

import stickslip

ROOT = Path(stickslip.__file__).parent
MODULES = sorted(
    "stickslip." + ".".join(p.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
    for p in ROOT.rglob("*.py")
    if ">>>" in p.read_text(encoding="utf-8")
)


def test_the_examples_are_found() -> None:
    assert "stickslip.dynamics.cycle" in MODULES and "stickslip.bifurcation.regimes" in MODULES


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name: str) -> None:
    """Every docstring example runs and prints what it shows (a Regime's name, not its repr):
    an example no test runs drifts unnoticed."""
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0, f"{name}: '>>>' in the source, but no example found"
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples failed"
