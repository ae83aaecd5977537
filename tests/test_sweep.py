"""Sweeps: equal to single cycle calls, labelled, round-trip to NetCDF, robust to failures."""

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from reference.one_block import cubic_orbit_reference

from stickslip import (
    Q_,
    CubicLaw,
    DimensionlessParameters,
    PhysicalParameters,
    WeakeningLaw,
    cycle,
    f2,
    zv_parameters,
)
from stickslip.dynamics.sweep import load_sweep, save_sweep, sweep


def test_physical_sweep_equals_single_calls() -> None:
    base = zv_parameters()
    grid = {
        "v0": Q_(np.geomspace(5, 1000, 4), "um/s"),
        "b": ["0 s/m", "100 s/m"],
        "load": ["100 mN", "196 mN", "0.3 N"],
    }
    ds = sweep(base, grid, progress=False)
    assert ds.amplitude.dims == ("v0", "b", "load")
    assert ds["v0"].attrs["units"] == "µm / s"
    assert ds["b"].attrs["units"] == "s / m"
    assert ds["load"].attrs["units"] == "mN"
    np.testing.assert_allclose(ds["load"].values, [100, 196, 300])
    assert ds.amplitude.attrs["units"] == "N"
    assert ds.period.attrs["units"] == "s"
    for i, j, k in itertools.product(range(4), range(2), range(3)):
        p = PhysicalParameters(
            mass=base.mass,
            stiffness=base.stiffness,
            load=Q_(ds["load"].values[k], "mN"),
            v0=Q_(ds["v0"].values[i], "um/s"),
            law=f2(0.46, "160 s/m", Q_(ds["b"].values[j], "s/m")),
        )
        r = cycle(p, probe=False)
        point = ds.isel(v0=i, b=j, load=k)
        assert float(point.amplitude) == r.amplitude
        assert float(point.period) == r.period
        assert float(point.stick_fraction) == r.stick_fraction
        assert str(point.regime.values) == r.regime
        assert str(point.status.values) == "ok"


def test_beta_sweep_sets_the_mass() -> None:
    ds = sweep(zv_parameters(), {"beta": ["42 s/m", "158 s/m"], "v0": ["100 um/s"]}, progress=False)
    for beta in (42.0, 158.0):
        p = zv_parameters("100 um/s", beta=Q_(beta, "s/m"))
        r = cycle(p, probe=False)
        got = float(ds.amplitude.sel(beta=beta, v0=100.0))
        assert got == pytest.approx(r.amplitude, rel=1e-12)
        assert float(ds.nu.sel(beta=beta, v0=100.0)) == pytest.approx(beta * 1e-4)


def test_dimensionless_sweep_equals_single_calls() -> None:
    base = DimensionlessParameters(nu=0.01, law=CubicLaw(alpha=0.5, gamma=0.5 / 3))
    ds = sweep(base, {"nu": [0.3, 0.97, 1.2], "gamma": [0.5 / 3]}, progress=False)
    assert list(ds.regime.values[:, 0]) == ["stick-slip", "pure-slip", "steady-sliding"]
    # CF conventions: units a UDUNITS string, the scale in its own attribute
    assert ds.amplitude.attrs["units"] == "1"
    assert ds.amplitude.attrs["scale"].startswith("static friction force")
    assert ds.period.attrs["units"] == "1" and ds.period.attrs["scale"] == "sqrt(m/k)"
    for i, nu in enumerate([0.3, 0.97, 1.2]):
        r = cycle(DimensionlessParameters(nu=nu, law=CubicLaw(alpha=0.5, gamma=0.5 / 3)), probe=False)
        np.testing.assert_equal(float(ds.amplitude[i, 0]), r.amplitude)
        assert bool(ds.steady_sliding_stable[i, 0]) == r.steady_sliding_stable


def test_a_sweep_at_loose_tolerances_equals_cycle_on_slip_reversal() -> None:
    """The slip-reversal orbit is measured again after polishing: at the sweep's tolerances.

    It once ran at the defaults, so a sweep at rtol=1e-4 gave 4.917371 (the default's
    amplitude) where cycle() gave 4.918455.
    """
    p = DimensionlessParameters(nu=1.0, law=CubicLaw(alpha=0.8235369798017035, gamma=0.04601251002566534))
    for rtol in (1e-4, 1e-10):
        r = cycle(p, rtol=rtol, probe=False)
        ds = sweep(p, {"nu": [1.0]}, rtol=rtol, progress=False)
        assert r.backward_slips > 0  # slip reversal: polished by the return map
        assert float(ds.amplitude[0]) == r.amplitude and float(ds.peak_velocity[0]) == r.peak_velocity
    assert cycle(p, rtol=1e-4, probe=False).amplitude - cycle(p, probe=False).amplitude > 1e-4


@pytest.mark.fast
def test_netcdf_round_trip(tmp_path: Path) -> None:
    ds = sweep(zv_parameters(), {"v0": Q_([5.0, 50.0, 500.0], "um/s")}, progress=False)
    path = tmp_path / "sub" / "sweep.nc"
    save_sweep(ds, path)
    back = load_sweep(path)
    xr.testing.assert_identical(back, ds)
    assert back.regime.dtype == ds.regime.dtype


def test_a_sweep_to_a_csv_path_is_a_table(tmp_path: Path) -> None:
    """`sweep --out x.csv` writes a table, not a NetCDF file under a .csv name: one row per
    point, units in the column names, regimes by name, every number as in the NetCDF file; a
    rerun replaces it as stickslip's own."""
    import pandas as pd
    from click.testing import CliRunner

    from stickslip.cli import main

    ds = sweep(zv_parameters(), {"v0": Q_([5.0, 50.0], "um/s"), "mass": Q_([0.1, 0.5], "kg")}, progress=False)
    path = save_sweep(ds, tmp_path / "s.csv")
    assert open(path, "rb").read(24).startswith(b"# stickslip sweep table")
    table = pd.read_csv(path, comment="#")
    assert len(table) == 4
    assert "amplitude [N]" in table.columns and "period [s]" in table.columns
    assert f"v0 [{ds.v0.attrs['units']}]" in table.columns and "mass [kg]" in table.columns
    flat = ds.to_dataframe().reset_index()
    np.testing.assert_array_equal(table["amplitude [N]"].to_numpy(), flat["amplitude"].to_numpy())
    np.testing.assert_array_equal(table["period [s]"].to_numpy(), flat["period"].to_numpy())
    assert table["regime"].tolist() == flat["regime"].astype(str).tolist()
    save_sweep(ds, tmp_path / "s.csv")  # its own file: replaced without asking
    args = ["sweep", "--law", "coulomb", "--nu", "0.1,0.2", "--kinetic", "0.5", "--no-plot"]
    res = CliRunner().invoke(main, [*args, "--out", str(tmp_path / "c.csv")])
    assert res.exit_code == 0, res.output
    assert pd.read_csv(tmp_path / "c.csv", comment="#")["regime"].tolist() == ["stick-slip"] * 2


def test_failed_point_leaves_the_others_intact() -> None:
    """A slip budget shorter than one oscillation near the Hopf point: that point fails, not the others."""
    base = DimensionlessParameters(nu=0.5, law=CubicLaw(alpha=0.5, gamma=0.5 / 3))
    nus = [0.3, 0.99999, 0.5]
    ds = sweep(base, {"nu": nus}, max_slip_time=6.0, progress=False)  # stick-slip slips last ~5
    assert list(ds.status.values) == ["ok", "not-converged", "ok"]
    assert ds.regime.values[1] == "unknown"
    assert np.isnan(ds.amplitude.values[1])
    assert np.isnan(ds.multiplier.values[1])
    for i in (0, 2):
        r = cycle(DimensionlessParameters(nu=nus[i], law=base.law), probe=False, max_slip_time=6.0)
        assert float(ds.amplitude[i]) == r.amplitude


def test_unfinished_transients_next_to_a_hopf_point_are_resolved() -> None:
    """Before a supercritical Hopf point an unfinished transient is polished into its orbit; just
    past it, where no orbit exists and steady sliding is stable, it is decaying onto steady sliding."""
    base = DimensionlessParameters(nu=0.5, law=CubicLaw(alpha=0.5, gamma=0.5 / 3))
    ds = sweep(base, {"nu": [0.99999, 1.00001]}, max_slip_time=300.0, progress=False)
    assert list(ds.status.values) == ["ok", "ok"]
    assert list(ds.regime.values) == ["pure-slip", "steady-sliding"]
    ref = cubic_orbit_reference(0.99999, 0.5, 0.5 / 3)  # plain SciPy shooting (tests/reference/one_block.py)
    assert float(ds.amplitude[0]) == pytest.approx(ref.amplitude, rel=1e-8)
    assert float(ds.multiplier[0]) == pytest.approx(ref.multiplier, rel=1e-6)
    # near the Hopf point the multiplier is exp(2 pi f'(nu)) to first order, f' = -alpha + 3 gamma nu^2
    first_order = math.exp(2 * math.pi * (-0.5 + 0.5 * 0.99999**2))
    assert float(ds.multiplier[0]) == pytest.approx(first_order, rel=1e-4)
    assert float(ds.amplitude[1]) == 0.0


def test_progress_bar(capsys: pytest.CaptureFixture[str]) -> None:
    base = DimensionlessParameters(nu=0.01, law=WeakeningLaw(c=2.0))
    sweep(base, {"nu": np.geomspace(1e-4, 0.1, 600)}, progress=True)
    err = capsys.readouterr().err
    assert "sweep:" in err
    assert "/600" in err
    sweep(base, {"nu": np.geomspace(1e-4, 0.1, 600)}, progress=None)  # not a terminal: silent
    sweep(base, {"nu": np.geomspace(1e-4, 0.1, 600)}, progress=False)
    assert capsys.readouterr().err == ""


@pytest.mark.fast
@pytest.mark.parametrize(
    ("grid", "message"),
    [
        ({}, "grid is empty"),
        ({"c": [1.0]}, "cannot sweep 'c'"),
        ({"v0": []}, "empty"),
        ({"v0": "5 um/s"}, "not a single string"),
        ({"v0": ["5 m"]}, "v0='5 m' has dimension"),
        ({"v0": ["-5 um/s"]}, "must be positive"),
        ({"mu0": [0.4, -1]}, r"mu0=-1\.0 must be positive"),
        ({"b": ["-1 s/m"]}, "must be non-negative"),
        ({"beta": ["42 s/m"], "mass": ["1 kg"]}, "either 'beta' or 'mass'"),
        # a bad point is named as given, not in SI (it said v0=<Quantity(-0.005, 'meter / second')>)
        ({"v0": ["10 um/s", "-5 mm/s"]}, r"v0='-5 mm/s' must be positive \(point 1\)"),
        ({"v0": Q_([5.0, -1.0], "um/s")}, r"v0='-1 µm/s' must be positive \(point 1\)"),
        # a value given twice made a coordinate that .sel could not pick out
        ({"v0": ["5 um/s", "6 um/s", "5 um/s"]}, r"v0: 5 um/s is given twice \(points 0 and 2\)"),
        (
            {"v0": ["5 um/s", "0.005 mm/s"]},
            r"5 um/s \(point 0\) and 0.005 mm/s \(point 1\) are the same value",
        ),
        ({"mu0": [0.4, 0.5, 0.4]}, r"mu0: 0.4 is given twice \(points 0 and 2\): expected distinct values"),
    ],
)
def test_bad_grids(grid: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        sweep(zv_parameters(), grid, progress=False)


def test_block_points_is_checked_in_process_too() -> None:
    with pytest.raises(ValueError, match="block_points=-3"):
        sweep(zv_parameters(), {"v0": ["5 um/s"]}, progress=False, block_points=-3)


def test_bad_dimensionless_grid() -> None:
    base = DimensionlessParameters(nu=0.01, law=WeakeningLaw(c=2.0))
    with pytest.raises(ValueError, match="nu=nan"):
        sweep(base, {"nu": [0.1, float("nan")]})
    with pytest.raises(ValueError, match="cannot sweep 'v0'"):
        sweep(base, {"v0": ["1 um/s"]})


def test_load_sweep_errors(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="no such file"):
        load_sweep(tmp_path / "missing.nc")
    bad = tmp_path / "bad.nc"
    bad.write_text("not netcdf")
    with pytest.raises(ValueError, match="not a readable NetCDF"):
        load_sweep(bad)


def test_a_block_of_a_job_runs_in_few_engine_calls(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    # A block of a job (store or cluster) has no progress bar of its own: its rows go to the
    # engine in calls of up to 20 000, not in ~50 calls for a bar's updates (each call starts
    # its threads and waits on the slowest: that made a store or a cluster 20-50 % slower).
    import stickslip.dynamics.sweep as sweep_module

    calls: list[int] = []
    real = sweep_module.run_attractors

    def counting(*args, **kwargs):  # type: ignore[no-untyped-def]
        calls.append(len(np.atleast_1d(args[2])))
        return real(*args, **kwargs)

    monkeypatch.setattr(sweep_module, "run_attractors", counting)
    base = DimensionlessParameters(0.01, WeakeningLaw(c=3.8))
    grid = {"nu": np.geomspace(1e-3, 0.3, 60), "c": np.linspace(2.0, 10.0, 50)}
    sweep(base, grid, progress=False, store=tmp_path / "s.zarr", block_points=3000)
    assert calls == [3000]  # one block, one call
    calls.clear()
    # with a bar of its own: the same one call, the bar moved as the engine's blocks finish
    seen: list[int] = []
    sweep(base, grid, progress=lambda info: seen.append(info.points))
    assert calls == [3000]
    assert len(seen) > 10 and seen == sorted(seen) and seen[-1] == 3000


def test_slip_reversal_is_told_apart_in_a_sweep() -> None:
    """A slip-reversal oscillation (the velocity changes sign without sticking) is its own regime
    in a sweep and in `cycle`, with the engine's count of backward slips beside it."""
    from click.testing import CliRunner

    from stickslip.cli import main

    base = DimensionlessParameters(nu=1.0, law=WeakeningLaw(c=3.8, p=0.0))
    nus = [0.5, 4.516952255, 7.181011546]
    ds = sweep(base, {"nu": nus}, progress=False)
    for nu, back, regime in zip(nus, ds.backward_slips.values, ds.regime.values, strict=True):
        single = cycle(DimensionlessParameters(nu=nu, law=WeakeningLaw(c=3.8, p=0.0)), probe=False)
        assert back == single.backward_slips and regime == str(single.regime)
    assert ds.backward_slips.values.tolist() == [0, 1, 1]
    assert ds.regime.values.tolist() == ["stick-slip", "slip-reversal", "slip-reversal"]
    assert ds.backward_slips.attrs["units"] == "1"
    res = CliRunner().invoke(main, ["cycle", "--c", "3.8", "--p", "0", "--nu", "4.516952255"])
    assert "regime          slip-reversal  (it slips backward without sticking" in res.output
    res = CliRunner().invoke(main, ["cycle", "--c", "3.8", "--p", "0.5", "--nu", "0.5"])
    assert "slip-reversal" not in res.output and "slips backward" not in res.output
