"""Regression tests: each docstring names the failure it guards against."""

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import stickslip as S
from stickslip.cli import main
from stickslip.data.criterion import classify


def test_coulomb_is_not_reported_multistable() -> None:
    """The neutral orbits around Coulomb steady sliding (f' = 0) are not a pure-slip attractor."""
    r = S.cycle(S.DimensionlessParameters(nu=0.01, law=S.CoulombLaw(kinetic=0.3)))
    assert not r.multistable
    assert [a.regime for a in r.attractors] == ["stick-slip"]


def test_unconverged_probe_is_not_an_attractor() -> None:
    """A probe that has not converged does not make the result 'multistable'."""
    r = S.cycle(S.DimensionlessParameters(nu=0.1, law=S.WeakeningLaw(c=1e-6)))
    assert all(a.status == "ok" for a in r.attractors)
    assert r.multistable == (len(r.attractors) > 1)


def test_backward_slips_counted_in_pure_slip() -> None:
    """backward_slips counts the backward phases of a motion that never sticks (slip reversal)."""
    r = S.cycle(S.DimensionlessParameters(nu=42.0, law=S.WeakeningLaw(c=3.8)))
    assert r.regime == "slip-reversal"
    assert r.min_velocity < 0
    assert r.backward_slips == 1


def test_fixed_beta_holds_at_every_sweep_point(tmp_path: Path) -> None:
    """With --beta fixed and --load swept, the mass follows each load (not that of the first)."""
    out = tmp_path / "s.nc"
    res = CliRunner().invoke(
        main,
        [
            "sweep",
            "--preset",
            "zv",
            "--beta",
            "42 s/m",
            "--load",
            "100 mN..400 mN",
            "--num",
            "3",
            "--out",
            str(out),
            "--no-plot",
            "--quiet",
        ],
    )
    assert res.exit_code == 0, res.output
    from stickslip.dynamics.sweep import load_sweep

    ds = load_sweep(out)
    np.testing.assert_allclose(ds.c.values.ravel(), 160 / 42)


def test_unwritable_output_is_a_one_line_error() -> None:
    """An output path that cannot be created is one line, not a NotADirectoryError traceback."""
    res = CliRunner().invoke(main, ["simulate", "--nu", "0.1", "--c", "3", "--out", "/dev/null/x"])
    assert res.exit_code == 1
    assert "cannot write" in res.output
    assert "Traceback" not in res.output


def test_numpy_integers_are_integers() -> None:
    """np.int64 is an integer wherever an integer is expected."""
    assert classify([1, 2, 3, 4, 5], [1, 2, 3, 4, 5], min_points=np.int64(4)).verdict == "stick-slip"
    p = S.DimensionlessParameters(nu=0.1, law=S.WeakeningLaw(c=2.0))
    assert S.simulate(p, n_points=np.int64(50)).time.size >= 50


def test_backward_slip_that_ends_inside_its_first_step() -> None:
    """A stop just past the static threshold (s slightly below -1) starts a backward slip so
    weak that it ends inside its first step: that stop is located, or the slip runs on into
    the continued law until the step size collapses (step-size-too-small for c = 3.8,
    p = 0.05 and 1.005 < nu < 1.04)."""
    from reference.one_block import reference_cycle

    for nu in (1.006, 1.02):
        r = S.cycle(S.DimensionlessParameters(nu=nu, law=S.WeakeningLaw(c=3.8, p=0.05)), probe=False)
        assert r.status == "ok" and r.regime == "stick-slip" and r.backward_slips == 1
        assert -1e-4 < r.min_velocity < 0
        ref = reference_cycle("weakening", {"c": 3.8, "p": 0.05}, nu)
        assert r.amplitude == pytest.approx(ref.amplitude, rel=1e-8)
        assert r.period == pytest.approx(ref.period, rel=1e-8)
