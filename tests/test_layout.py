"""The package as a user meets it: entry points, version, imports without side effects."""

from __future__ import annotations

import json
import subprocess
import sys
from importlib.metadata import version

import pytest
from reference.one_block import coulomb_cycle

import stickslip


def _python(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=300, check=False)


def test_python_dash_m_stickslip() -> None:
    res = _python(
        "-m", "stickslip", "cycle", "--law", "coulomb", "--kinetic", "0.5", "--nu", "0.05", "--json"
    )
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    exact = coulomb_cycle(0.05, 0.5)  # the closed-form Coulomb cycle (tests/reference/one_block.py)
    assert out["amplitude"] == pytest.approx(exact["amplitude"], rel=1e-9)
    help_res = _python("-m", "stickslip.cli", "regimes", "--help")
    assert help_res.returncode == 0 and "--nu-min" in help_res.stdout


def test_version_comes_from_the_package_metadata() -> None:
    assert stickslip.__version__ == version("stickslip")
    res = _python("-m", "stickslip", "--version")
    assert version("stickslip") in res.stdout


def _printed(code: str) -> list[str]:
    """The lines ``code`` prints in a fresh interpreter (which must succeed)."""
    res = _python("-c", code)
    assert res.returncode == 0, res.stderr
    return res.stdout.splitlines()


def test_import_stickslip_is_lazy_and_every_public_name_loads() -> None:
    """``import stickslip`` loads no numba (so the command line can answer Ctrl-C while it
    starts); each name of ``__all__`` and each subpackage then loads on first use."""
    code = (
        "import sys, stickslip\n"
        "print('numba' in sys.modules, 'pint' in sys.modules)\n"
        "print(all(getattr(stickslip, n) is not None for n in stickslip.__all__))\n"
        "print(stickslip.cycle is stickslip.dynamics.cycle, stickslip.core.__name__)\n"
        "from stickslip import *\n"
        "print(Q_('1 mN').to('N').magnitude, 'zv_parameters' in dir(stickslip))\n"
        "try:\n    stickslip.nope\nexcept AttributeError as e:\n    print(e)\n"
    )
    assert _printed(code) == [
        "False False",
        "True",
        "True stickslip.core",
        "0.001 True",
        "module 'stickslip' has no attribute 'nope'",
    ]


def test_import_stickslip_cli_is_lazy_and_its_names_load() -> None:
    """``import stickslip.cli`` (what ``python -m stickslip.cli`` does before its
    ``__main__`` runs) loads no numba; ``main`` and the option builders load on first use."""
    code = (
        "import sys, stickslip.cli as c\n"
        "print('numba' in sys.modules, 'click' in sys.modules)\n"
        "print(c.main.name, c.build_parameters.__module__, c.chain.__name__, 'options' in dir(c))\n"
        "try:\n    c.nope\nexcept AttributeError as e:\n    print(e)\n"
    )
    assert _printed(code) == [
        "False False",
        "main stickslip.cli.options stickslip.cli.chain True",
        "module 'stickslip.cli' has no attribute 'nope'",
    ]


@pytest.mark.slow
def test_importing_chooses_no_matplotlib_backend() -> None:
    code = (
        "import sys, stickslip, stickslip.plots.figures, stickslip.plots.regimes, stickslip.paper.figures\n"
        "print('matplotlib.pyplot' in sys.modules)"
    )
    res = _python("-c", code)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "False"


def test_moved_modules_warn_at_their_old_paths_and_are_the_new_ones() -> None:
    """A module that moved keeps its old path for one release, with a DeprecationWarning naming both."""
    import importlib
    import sys
    import warnings

    moved = {
        "stickslip.bifurcation.orbits": "stickslip.orbits.periodic",
        "stickslip.bifurcation.stability": "stickslip.orbits.stability",
        "stickslip.dynamics.return_map": "stickslip.orbits.return_map",
        "stickslip.dynamics.attractors": "stickslip.orbits.attractors",
    }
    for old, new in moved.items():
        sys.modules.pop(old, None)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            shim = importlib.import_module(old)
        said = [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]
        assert said and f"{old} is now {new}" in said[0], (old, said)
        target = importlib.import_module(new)
        for name in target.__all__:
            assert getattr(shim, name) is getattr(target, name), (old, name)
