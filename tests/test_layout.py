"""The package as a user meets it: entry points, version, imports without side effects."""

from __future__ import annotations

import json
import subprocess
import sys
from importlib.metadata import version

import pytest
from reference import coulomb_cycle

import stickslip


def _python(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=300, check=False)


def test_python_dash_m_stickslip() -> None:
    res = _python(
        "-m", "stickslip", "cycle", "--law", "coulomb", "--kinetic", "0.5", "--nu", "0.05", "--json"
    )
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    exact = coulomb_cycle(0.05, 0.5)  # the closed-form Coulomb cycle (tests/reference.py)
    assert out["amplitude"] == pytest.approx(exact["amplitude"], rel=1e-9)
    help_res = _python("-m", "stickslip.cli", "regimes", "--help")
    assert help_res.returncode == 0 and "--nu-min" in help_res.stdout


def test_version_comes_from_the_package_metadata() -> None:
    assert stickslip.__version__ == version("stickslip")
    res = _python("-m", "stickslip", "--version")
    assert version("stickslip") in res.stdout


def test_importing_chooses_no_matplotlib_backend() -> None:
    code = (
        "import sys, stickslip, stickslip.plots.figures, stickslip.plots.regimes, stickslip.paper.figures\n"
        "print('matplotlib.pyplot' in sys.modules)"
    )
    res = _python("-c", code)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "False"
