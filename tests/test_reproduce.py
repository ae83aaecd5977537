"""stickslip reproduce --quick, end to end: data, figures drawn from the data, report."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from stickslip.cli import main
from stickslip.paper.compute import measured_trends
from stickslip.paper.figures import FIGURES, make_figures
from stickslip.paper.trial import TRIAL_MAPS

# one worker runs this module (`.ci/run`: --dist loadgroup), so that its fixture's
# reproduce --quick (20 s) runs once, not once per worker
pytestmark = pytest.mark.xdist_group("reproduce_quick")


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("repro")
    res = CliRunner().invoke(main, ["reproduce", "--out", str(out), "--quick"])
    assert res.exit_code == 0, res.output
    assert "done in" in res.output
    return out


def test_every_file_is_written_and_not_empty(quick_run: Path) -> None:
    assert (quick_run / "reproduce.nc").stat().st_size > 10_000
    for name in FIGURES:
        for ext in ("png", "svg"):
            assert (quick_run / f"{name}.{ext}").stat().st_size > 5_000, name
    md = (quick_run / "report.md").read_text()
    html = (quick_run / "report.html").read_text()
    for name in FIGURES:
        assert f"{name}.png" in md
    from stickslip.paper.trial import TRIAL_MAPS

    assert html.count("data:image/png;base64,") == len(FIGURES) + 2 * len(TRIAL_MAPS)
    assert "<img" in html and 'src="fig' not in html  # self-contained


def test_a_quick_report_says_it_is_quick(quick_run: Path) -> None:
    """A quick report says that it is quick: its 8 velocities put a crossing at 548 um/s where
    bisection gives 578, and a reader must not take it for the full one."""
    md = (quick_run / "report.md").read_text()
    assert "A quick run (--quick): the curves are computed on a reduced grid (8 driving velocities" in md
    assert xr.load_dataset(quick_run / "reproduce.nc").attrs["quick"] == 1


def test_criterion_trial_in_the_report(quick_run: Path) -> None:
    from stickslip.paper.trial import TRIAL_MAPS

    md = (quick_run / "report.md").read_text()
    assert "## The criterion on trial" in md
    for m in TRIAL_MAPS:
        tr = xr.load_dataset(quick_run / f"criterion_{m.key}.nc")
        assert set(tr.right.dims) == {m.param, "nu"}
        judged = int((tr.right.values >= 0).sum())
        assert judged > 0
        assert m.title in md


def test_figures_are_drawn_from_the_netcdf_data(quick_run: Path) -> None:
    ds = xr.load_dataset(quick_run / "reproduce.nc")
    figs = make_figures(ds)
    line = figs["fig2_amplitude_v0"].axes[0].lines[0]
    np.testing.assert_array_equal(line.get_xdata(), ds["fig2_v0"].values)
    np.testing.assert_array_equal(line.get_ydata(), ds["fig2_amplitude"].values[0] * 1e3)
    line = figs["fig3_amplitude_v0"].axes[0].lines[2]
    np.testing.assert_array_equal(line.get_ydata(), ds["fig3_amplitude_au"].values[2])
    line = figs["fig1_spring_force"].axes[0].lines[0]
    np.testing.assert_array_equal(line.get_ydata(), ds["fig1_spring_force"].values * 1e3)
    line = figs["load_dependence"].axes[1].lines[1]
    np.testing.assert_array_equal(line.get_ydata(), ds["load_period"].values[1])
    import matplotlib.pyplot as plt

    plt.close("all")


def test_dataset_has_units_and_every_curve(quick_run: Path) -> None:
    ds = xr.load_dataset(quick_run / "reproduce.nc")
    for var, unit in [
        ("fig2_amplitude", "N"),
        ("fig2_period", "s"),
        ("fig1_spring_force", "N"),
        ("fig1_time", "s"),
        ("load_W", "mN"),
        ("fig3_beta", "s / m"),
        ("mass_mass", "g"),
        ("fig3_amplitude_au", "1"),
    ]:
        assert ds[var].attrs["units"] == unit, var
    assert list(ds["fig3_beta"].values) == [42.0, 158.0, 418.0]
    assert list(ds["fig2_b"].values) == [0.0, 100.0]
    assert ds["fig2_v0"].values[0] == pytest.approx(5.0)
    assert ds["fig2_v0"].values[-1] == pytest.approx(1000.0)
    assert set(np.unique(ds["fig2_status"].values)) == {"ok"}


def test_report_states_claims_and_beta_inconsistency(quick_run: Path) -> None:
    md = (quick_run / "report.md").read_text()
    # the set-up's cross-reference names the beta claim's number (it said 11, the mu0 W claim)
    n = next(line.split("|")[1].strip() for line in md.splitlines() if "| Parameters: beta" in line)
    assert f"(claim {n})." in md
    assert "beta = 87.3 s/m" in md
    assert "0.231 kg" in md
    assert "slope" in md
    assert "pure-slip" in md and "stick-slip" in md
    # the measured trends are quoted, with the slope they imply, never as invented points
    assert "two orders of magnitude" in md
    t = measured_trends()
    assert t["zv"]["slope"] == pytest.approx(np.log10(0.5) / 2)
    assert t["bri"]["slope"] == pytest.approx(np.log10(2.0))
    assert f"{t['zv']['slope']:+.3f}" in md


def test_config_and_load_claim_wording() -> None:
    """One point per curve ran and flipped five claims; claim 6 said 'both increase' whatever the sign."""
    from stickslip.paper.compute import PaperConfig
    from stickslip.paper.report import _directions

    for bad in ({"n_v0": 1}, {"n_load": 2.5}, {"n_time": 0}):
        with pytest.raises(ValueError, match=f"{next(iter(bad))}="):
            PaperConfig(**bad)
    assert _directions([0.5, 0.4], [0.1, 0.2]) == (
        "the amplitude increases with the load, the period increases with the load"
    )
    assert _directions([-0.98, -0.7], [0.1, -0.2]) == (
        "the amplitude decreases with the load, the period goes either way with the load"
    )


@pytest.mark.fast
def test_reproduce_bad_out(tmp_path: Path) -> None:
    f = tmp_path / "file"
    f.write_text("x")
    res = CliRunner().invoke(main, ["reproduce", "--out", str(f), "--quick"])
    assert res.exit_code == 2
    assert "Traceback" not in res.output
    # an empty --out named no folder here; a sweep wrote results/sweep.nc, a store the cwd
    for args in (["reproduce", "--quick"], ["sweep", "--nu", "0.1", "--c", "3"]):
        res = CliRunner().invoke(main, [*args, "--out", ""])
        assert res.exit_code == 2 and "'' is empty: expected the path of a" in res.output, res.output
    res = CliRunner().invoke(main, ["sweep", "--nu", "0.1", "--c", "3", "--store", ""])
    assert res.exit_code == 2 and "Invalid value for '--store'" in res.output


def test_every_path_a_command_writes_refuses_an_empty_one() -> None:
    """Every path option of every command is an input (a click.Path) or an output (an OutPath,
    which refuses ''): a new command's --out cannot slip back to the plain type."""
    import click

    from stickslip.cli.options import OutPath

    inputs = {"record_file", "history", "source", "file"}
    seen = []

    def walk(cmd: click.Command, path: tuple[str, ...] = ()) -> None:
        if isinstance(cmd, click.Group):
            for name, sub in cmd.commands.items():
                walk(sub, (*path, name))
            return
        for p in cmd.params:
            if isinstance(p.type, click.Path) and p.name not in inputs:
                assert isinstance(p.type, OutPath), (path, p.name)
                seen.append((path, p.name))

    walk(main)
    assert len(seen) >= 13  # --out of 10 commands, --store of 3
    with pytest.raises(click.BadParameter, match="'  ' is empty: expected the path of a directory"):
        OutPath(file_okay=False).convert("  ", None, None)


def test_a_foreign_trial_figure_is_refused_before_the_work(tmp_path: Path) -> None:
    """regimes_<trial>.png is checked with every other target, before the work: checked when
    written, a foreign file would stop a quick run after some 20 s (a full one after hours)."""
    import time

    (tmp_path / f"regimes_{TRIAL_MAPS[0].key}.png").write_text("a colleague's figure")
    t0 = time.perf_counter()
    res = CliRunner().invoke(main, ["reproduce", "--quick", "--serial", "--out", str(tmp_path)])
    assert res.exit_code != 0 and f"regimes_{TRIAL_MAPS[0].key}.png" in res.output, res.output
    assert time.perf_counter() - t0 < 10.0  # refused before any map is computed
    assert (tmp_path / f"regimes_{TRIAL_MAPS[0].key}.png").read_text() == "a colleague's figure"


@pytest.mark.fast
def test_paper_api_refuses_what_it_dropped() -> None:
    """Unknown trial keys are refused (not a run of nothing); a dict config is refused at once,
    not deep inside; the appendix's resolution following n_v0 < 20 is said; claim 10's verdict
    is computed, not fixed text."""
    from stickslip.paper.compute import PaperConfig, compute_paper
    from stickslip.paper.report import _against_measured
    from stickslip.paper.trial import run_trials

    with pytest.raises(ValueError, match=r"\['f1-c'\] are not trials"):
        run_trials(quick=True, keys=("f1-c",))
    with pytest.raises(ValueError, match="keys='f1_c'"):
        run_trials(quick=True, keys="f1_c")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"config=.*expected a PaperConfig"):
        compute_paper({"n_v0": 8})  # type: ignore[arg-type]
    assert PaperConfig.quick().quick_appendix and not PaperConfig(n_v0=8).quick_appendix
    with pytest.raises(ValueError, match="quick_appendix='yes'"):
        PaperConfig(quick_appendix="yes")  # type: ignore[arg-type]
    bri = float(np.log10(2.0))
    assert _against_measured(-0.095, bri) == "contradicted"
    assert _against_measured(0.505, bri) == "partly supported (right direction, steeper)"
    assert _against_measured(0.1, bri) == "partly supported (right direction, shallower)"
    assert _against_measured(0.3, bri) == "supported"


def test_appendix_evidence(quick_run: Path) -> None:
    ds = xr.load_dataset(quick_run / "reproduce.nc")
    mult = ds["return_multiplier"]
    above = mult.sel(kappa=0.006).values
    below = mult.sel(kappa=0.004).values
    at = mult.sel(kappa=0.005).values
    assert np.all(above[np.isfinite(above)] < 0.9)  # spirals into steady sliding
    assert np.all(below[np.isfinite(below)] > 1.1)  # spirals out
    np.testing.assert_allclose(at, 1.0, atol=1e-6)  # closed orbits at kappa = B - A
    np.testing.assert_allclose(ds["growth_simulated"], ds["growth_linear"], rtol=0.01)
    # the report's words, with its numbers; not the command line's advice (give the slider a mass)
    runaway = ds.attrs["appendix_quasi_static_runaway"]
    assert runaway.startswith("runs away: its slip velocity passes 1e+03 m/s at t = ")
    assert "Give" not in runaway
    md = (quick_run / "report.md").read_text()
    assert "simplifies to 0: True" in md


def test_no_report_cell_is_cut(quick_run: Path) -> None:
    """No report cell is cut mid-word (as by a message sliced to 160 characters)."""
    import html

    from stickslip.paper.report import claims

    ds = xr.load_dataset(quick_run / "reproduce.nc")
    md = (quick_run / "report.md").read_text()
    page = (quick_run / "report.html").read_text()
    for c in claims(ds):
        for text in (c.paper, c.model, c.verdict):
            assert text.replace("|", "/") in md, (c.number, text[-40:])
            assert html.escape(text) in page, (c.number, text[-40:])
        assert c.model.rstrip()[-1] in ".)", (c.number, c.model[-60:])


def test_claims_judge_every_law_and_the_fig3_order(quick_run: Path) -> None:
    from stickslip.paper.report import claims

    by_text = claims(xr.load_dataset(quick_run / "reproduce.nc"))
    mass = next(c for c in by_text if "very small mass" in c.paper)
    assert "F1:" in mass.model and "F2 (b = 100 s/m):" in mass.model
    # F2 at small masses: the stick-slip amplitude falls with v0 (checked against the SciPy
    # reference in test_small_mass_f2_amplitude_falls_with_v0); F1's still rises
    assert "F2 (b = 100 s/m): an exception in sign" in mass.model
    assert "no exception in sign" in mass.model
    order = next(c for c in by_text if "curves are ordered" in c.paper)
    assert "cross at" in order.model and order.verdict.startswith("partly")
    assert any("three distinct possibilities" in c.paper for c in by_text)
    assert any("friction force" in c.paper for c in by_text)
    assert [c.number for c in by_text] == list(range(1, len(by_text) + 1))


@pytest.mark.slow
def test_serial_run_gives_the_same_data(quick_run: Path, tmp_path: Path) -> None:
    """The CLI shares the work out to a second process (the cubic law's trial, two of the
    appendix's parts, half the figures); in one process the data are the same, bit for bit."""
    from stickslip.paper import reproduce

    reproduce(tmp_path / "serial", quick=True, parallel=False)
    for name in ["reproduce.nc", *(f"criterion_{m.key}.nc" for m in TRIAL_MAPS)]:
        one, two = xr.load_dataset(tmp_path / "serial" / name), xr.load_dataset(quick_run / name)
        xr.testing.assert_identical(one, two)
    assert len(one.data_vars) > 5
    # and the figures, whichever process drew them (the trials' figures included), byte for byte
    pngs = sorted(p.name for p in quick_run.glob("*.png"))
    assert len(pngs) == len(FIGURES) + 2 * len(TRIAL_MAPS)
    for name in pngs:
        assert (tmp_path / "serial" / name).read_bytes() == (quick_run / name).read_bytes(), name
    assert (tmp_path / "serial" / "report.md").read_text() == (quick_run / "report.md").read_text()


def test_the_trial_maps_mark_the_papers_experiment() -> None:
    """The regime maps show where the paper's experiment lies. F1's map marks c = a / beta = 160/42
    over nu = beta v0 for 5-1000 um/s; F2's marks p = b / beta = 100/42; the cubic law's, which
    the paper does not use, marks nothing."""
    from stickslip.paper.trial import TRIAL_MAPS, _paper_point, run_trials
    from stickslip.plots.regimes import MARK_LABEL, plot_regime_map

    marks = {m.key: _paper_point(m) for m in TRIAL_MAPS}
    assert marks["cubic_alpha"] == {}
    assert marks["f1_c"]["mark_value"] == pytest.approx(160 / 42, rel=1e-12)
    assert marks["f2_p"]["mark_value"] == pytest.approx(100 / 42, rel=1e-12)
    for m in ("f1_c", "f2_p"):
        assert (marks[m]["mark_nu_min"], marks[m]["mark_nu_max"]) == pytest.approx((42 * 5e-6, 42 * 1e-3))
    (trial,) = run_trials(quick=True, keys=("f1_c",)).values()
    fig = plot_regime_map(trial)
    (line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label() == trial.attrs[MARK_LABEL]]
    np.testing.assert_allclose(line.get_xdata(), [1e-3, 0.042])  # clipped to the map's nu >= 1e-3
    np.testing.assert_allclose(line.get_ydata(), [160 / 42, 160 / 42])
    assert "mark" not in fig.axes[0].get_title()


def test_f1_maps_show_slip_reversal_not_pure_slip(quick_run: Path) -> None:
    """F1 (p = 0) has no pure slip: its non-sticking oscillation slips backward. The trial maps'
    regimes (drawn in regimes_f1_c.png and the p = 0 row of regimes_f2_p.png) and the regime
    reached say slip-reversal, and their flags name it."""
    from stickslip.core.results import Regime

    f1 = xr.load_dataset(quick_run / "criterion_f1_c.nc")
    f2 = xr.load_dataset(quick_run / "criterion_f2_p.nc").sel(p=0.0)
    for ds in (f1, f2):
        for var in ("regime", "observed"):
            codes = ds[var].values
            assert not np.any(codes == Regime.PURE_SLIP.code), var
            assert np.any(codes == Regime.SLIP_REVERSAL.code), var
        meanings = ds.regime.attrs["flag_meanings"].split()
        assert meanings[list(ds.regime.attrs["flag_values"]).index(3)] == "slip-reversal"


def test_the_report_opens_with_verdicts_in_a_fixed_vocabulary(quick_run: Path) -> None:
    from stickslip.paper.report import GRADES, claims

    cl = claims(xr.load_dataset(quick_run / "reproduce.nc"))
    assert all(c.grade in GRADES for c in cl)
    md = (quick_run / "report.md").read_text()
    verdicts = md.index("## Verdicts")
    assert verdicts < md.index("## Set-up and choices") < md.index("## Claims")
    counts = md[verdicts:].split("\n\n")[1]
    assert counts.startswith(f"Of the paper's {len(cl)} claims, the model agrees with ")
    assert "zv and bri are the paper's own keys for its two experiments" in md
    with pytest.raises(ValueError, match="of none of the report's forms"):
        from stickslip.paper.report import grade

        grade("fine")
