"""ratestate-fit recovers a, b, Dc from noisy records made by an independent SciPy generator."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner
from reference.rsf_generator import generate, write_csv

from stickslip import Q_
from stickslip.cli import main
from stickslip.io.errors import DataError
from stickslip.io.lab import read_lab_record
from stickslip.ratestate.fitting import fit_rate_state

ONE = {"a": 0.008, "b": [0.012], "dc_um": [10.0], "k_per_um": 2e-3}
TWO = {"a": 0.012, "b": [0.0185, 0.0088], "dc_um": [5.0, 50.0]}
STEPS_ONE = [(1.0, 100.0), (10.0, 30.0), (1.0, 300.0), (10.0, 30.0)]
STEPS_TWO = [(1.0, 100.0), (10.0, 60.0), (1.0, 600.0), (10.0, 60.0)]


def _record(tmp_path, law: str, truth: dict, steps, k: float, *, trend: float = 0.0, seed: int = 1):
    t, v, mu = generate(
        a=truth["a"], b=truth["b"], dc_um=truth["dc_um"], law=law, k_per_um=k, steps=steps, dt=0.2,
        noise=1e-4, trend_per_um=trend, seed=seed,
    )  # fmt: skip
    path = tmp_path / f"{law}.csv"
    write_csv(
        path, t, v, mu, {"mu0": "0.6", "v_ref": "1 um/s", "stiffness_per_load": f"{k} 1/um", "law": law}
    )
    return path


def _truth_values(truth: dict, k: float | None = None) -> dict[str, float]:
    out = {"a": truth["a"], "b": truth["b"][0], "dc": truth["dc_um"][0] * 1e-6}
    if len(truth["b"]) > 1:
        out |= {"b_2": truth["b"][1], "dc_2": truth["dc_um"][1] * 1e-6}
    if k is not None:
        out["stiffness_per_load"] = k * 1e6
    return out


def _check(values: dict, errors: dict, truth: dict[str, float]) -> None:
    assert set(values) == set(truth)
    for name, true in truth.items():
        assert errors[name] > 0, name
        assert abs(values[name] - true) <= 3 * errors[name], (name, values[name], errors[name], true)
        assert abs(values[name] - true) <= 0.05 * true, (name, values[name], true)


@pytest.mark.parametrize("law", ["aging", "slip"])
def test_one_state_api(tmp_path, law: str) -> None:
    path = _record(tmp_path, law, ONE, STEPS_ONE, ONE["k_per_um"], trend=2e-5)
    fit = fit_rate_state(read_lab_record(path, need_friction=True))
    _check(fit.values, fit.errors, _truth_values(ONE))
    assert 0.8 < fit.reduced_chi2 < 1.2
    assert fit.trend == pytest.approx(20.0, rel=0.05)  # 2e-5 per um is 20 per m, detrended
    assert fit.noise == pytest.approx(1e-4, rel=0.1)
    assert not fit.warnings


@pytest.mark.parametrize(("law", "k"), [pytest.param("aging", 3e-3, marks=pytest.mark.slow), ("slip", 8e-3)])
def test_two_states_cli(tmp_path, law: str, k: float) -> None:
    path = _record(tmp_path, law, TWO, STEPS_TWO, k, seed=2)
    res = CliRunner().invoke(
        main, ["ratestate-fit", str(path), "--states", "2", "--json", "--out", str(tmp_path / "out")]
    )
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    values = {n: p["value"] for n, p in d["parameters"].items()}
    errors = {n: p["error"] for n, p in d["parameters"].items()}
    assert {p["unit"] for n, p in d["parameters"].items() if n.startswith("dc")} == {"m"}
    _check(values, errors, _truth_values(TWO))
    assert set(d["correlation"]) == set(values)
    assert 0.8 < d["reduced_chi2"] < 1.2
    assert not d["warnings"]
    assert (tmp_path / "out" / "ratestate_fit.png").stat().st_size > 10_000


def test_stiffness_fitted(tmp_path) -> None:
    path = _record(tmp_path, "aging", ONE, STEPS_ONE, ONE["k_per_um"], seed=3)
    # start from a wrong k/W: the fit finds the machine's stiffness
    fit = fit_rate_state(
        read_lab_record(path, need_friction=True), stiffness_per_load="3e-3 1/um", fit_stiffness=True
    )
    _check(fit.values, fit.errors, _truth_values(ONE, k=ONE["k_per_um"]))


@pytest.mark.slow
def test_two_close_state_variables_are_not_identifiable(tmp_path) -> None:
    truth = {"a": 0.012, "b": [0.0185, 0.0088], "dc_um": [5.0, 7.0]}
    path = _record(tmp_path, "aging", truth, STEPS_TWO, 8e-3, seed=4)
    fit = fit_rate_state(read_lab_record(path, need_friction=True), n_states=2)
    assert any("not separately identifiable" in w for w in fit.warnings)
    assert any("strongly correlated" in w for w in fit.warnings)
    # the one-state fit of the same record is well constrained
    one = fit_rate_state(read_lab_record(path, need_friction=True))
    assert one.reduced_chi2 < 3


def test_window_and_detrend(tmp_path) -> None:
    path = _record(tmp_path, "aging", ONE, STEPS_ONE, ONE["k_per_um"], trend=0.0, seed=5)
    rec = read_lab_record(path, need_friction=True)
    fit = fit_rate_state(rec, window=("50 s", "460 s"), detrend="none")
    _check(fit.values, fit.errors, _truth_values(ONE))
    assert fit.samples == np.count_nonzero((rec.time >= 50) & (rec.time <= 460))
    assert fit.time[0] >= 50 and fit.time[-1] <= 460


def test_bad_input(tmp_path) -> None:
    p = tmp_path / "nofriction.csv"
    p.write_text("time [s],load-point velocity [um/s]\n0,1\n1,1\n2,10\n")
    with pytest.raises(DataError, match="friction"):
        read_lab_record(p, need_friction=True)
    q = tmp_path / "nomu0.csv"
    q.write_text(
        "time [s],load-point velocity [um/s],friction [1]\n" + "".join(f"{i},1,0.6\n" for i in range(20))
    )
    with pytest.raises(DataError, match="mu0 is not given"):
        fit_rate_state(read_lab_record(q, need_friction=True), v_ref="1 um/s", stiffness_per_load="1 1/mm")
    r = tmp_path / "unit.csv"
    r.write_text("time [s],load-point velocity [N],friction [1]\n0,1,0.6\n1,1,0.6\n")
    res = CliRunner().invoke(main, ["ratestate-fit", str(r), "--mu0", "0.6"])
    assert res.exit_code != 0
    assert "expected [length] / [time]" in res.output
    assert "Traceback" not in res.output
    dup = tmp_path / "dup.csv"
    dup.write_text("time [s],load-point velocity [um/s],load-point velocity [um/s]\n0,1,1\n1,1,1\n")
    with pytest.raises(DataError, match="column 'load-point velocity' appears more than once"):
        read_lab_record(dup)
    # a friction column in percent is read as coefficients (60 % was 60)
    pct = tmp_path / "pct.csv"
    pct.write_text("time [s],load-point velocity [um/s],friction [%]\n0,1,60\n1,1,60.5\n2,1,61\n")
    np.testing.assert_allclose(read_lab_record(pct, need_friction=True).friction, [0.6, 0.605, 0.61])
    # the fit's own arguments, checked before it runs (an unknown key of initial did nothing,
    # a partial one was a KeyError, a bad value scipy's bounds error)
    rec = read_lab_record(_record(tmp_path, "aging", ONE, STEPS_ONE, ONE["k_per_um"]), need_friction=True)
    for kw, message in (
        ({"initial": {"dc": 1e-5, "typo": 1.0}}, "initial: 'typo' is not a fitted parameter"),
        ({"initial": {"stiffness_per_load": 2e3}}, "'stiffness_per_load' is not a fitted parameter"),
        ({"initial": {"a": -0.01}}, r"initial\['a'\]=-0.01 must be positive"),
        ({"initial": {"a": "x"}}, r"initial\['a'\]='x'"),
        ({"window": ("5 s",)}, "expected \\(start, end\\) times"),
        ({"mu0": "0.6 N"}, "mu0='0.6 N'"),
    ):
        with pytest.raises(ValueError, match=message):
            fit_rate_state(rec, **kw)
    # some starting values: the others from the steps; a window as a pint array
    fit = fit_rate_state(rec, initial={"dc": 2e-5}, window=Q_([0.0, 1e4], "s"))
    _check(fit.values, fit.errors, _truth_values(ONE))
    assert fit.samples == rec.time.size


def test_slide_hold_slide_record(tmp_path) -> None:
    """Holds of 10, 100 and 1000 s between slides at 1 um/s, no step: the healing constrains a, b, Dc."""
    steps = [(1.0, 100.0), (0.0, 10.0), (1.0, 100.0), (0.0, 100.0), (1.0, 100.0), (0.0, 1000.0), (1.0, 150.0)]
    path = _record(tmp_path, "aging", ONE, steps, ONE["k_per_um"], seed=7)
    fit = fit_rate_state(read_lab_record(path, need_friction=True))
    _check(fit.values, fit.errors, _truth_values(ONE))


@pytest.mark.parametrize(
    "steps",
    [
        ["--steps", "1 um/s,10 um/s,1 um/s", "--durations", "100 s,30 s,300 s"],
        # 20 Dc/v each: changes at 200, 266.67, 286.67 s, between samples 0.2 s apart
        ["--steps", "1 um/s,3 um/s,10 um/s,3 um/s"],
    ],
)
def test_round_trip_of_a_simulated_record(tmp_path, steps: list[str]) -> None:
    """stickslip ratestate writes ratestate.csv as a record; ratestate-fit reads it back to the parameters.

    With --sample the record has a row at each change of velocity: the record's velocity
    holds until the next row, so a change written at the next sample puts the fit of the
    noiseless record 0.4 % off, reduced chi2 7e14."""
    args = ["ratestate", "--a", "0.008", "--b", "0.012", "--dc", "10 um", "--v-ref", "1 um/s", "--mu0", "0.6"]
    args += ["--stiffness-per-load", "2e-3 1/um", *steps, "--sample", "0.2 s", "--out", str(tmp_path / "run")]
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, res.output
    record = tmp_path / "run" / "ratestate.csv"
    assert record.read_text().startswith("# stickslip rate-and-state record\n# mu0 = 0.6\n")
    rec = read_lab_record(record, need_friction=True)
    changes = rec.time[1:][np.diff(rec.velocity) != 0]
    want = [100.0, 130.0] if len(steps) == 4 else [200.0, 200.0 + 200.0 / 3, 200.0 + 200.0 / 3 + 20.0]
    np.testing.assert_allclose(changes, want, rtol=1e-14)
    res = CliRunner().invoke(
        main, ["ratestate-fit", str(record), "--detrend", "none", "--json", "--out", str(tmp_path / "fit")]
    )
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    p = d["parameters"]
    assert p["a"]["value"] == pytest.approx(0.008, rel=1e-6)
    assert p["b"]["value"] == pytest.approx(0.012, rel=1e-6)
    assert p["dc"]["value"] == pytest.approx(1e-5, rel=1e-6)
    # a noise-free record is weighted by a floor at the model's accuracy, and said to be; it is
    # not called a misfit (the parameters are exact; unfloored, the reduced chi-square is 7.9)
    if len(steps) == 4:  # (the other's noise estimate, 5e-6, is its own sharp turns)
        assert any(w.startswith("the record has no noise above the model's own") for w in d["warnings"])
    assert not any(w.startswith("reduced chi-squared") for w in d["warnings"]), d["warnings"]


def test_a_record_sampled_coarsely_says_its_errors_are_too_large(tmp_path) -> None:
    """The README's own record, sampled every second, fits to 1e-10, but the noise read off its
    second differences is its curvature (1.3e-5): the reduced chi-squared of 3.8e-14 and errors
    some 5e6 times too large are said to be so."""
    args = ["ratestate", "--a", "0.012", "--b", "0.0185", "--dc", "5 um", "--b", "0.0088", "--dc", "50 um"]
    args += ["--v-ref", "1 um/s", "--mu0", "0.6", "--stiffness-per-load", "3e-3 1/um"]
    args += ["--steps", "1 um/s,10 um/s", "--durations", "10 s,30 s", "--sample", "1 s"]
    res = CliRunner().invoke(main, [*args, "--out", str(tmp_path / "rs2")])
    assert res.exit_code == 0, res.output
    res = CliRunner().invoke(
        main, ["ratestate-fit", str(tmp_path / "rs2" / "ratestate.csv"), "--states", "2", "--detrend", "none",
               "--json"],
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    assert d["parameters"]["a"]["value"] == pytest.approx(0.012, rel=1e-8)
    assert d["reduced_chi2"] < 1e-10
    (low,) = [w for w in d["warnings"] if w.startswith("reduced chi-squared")]
    factor = float(low.split("by about ")[1].split(" times")[0])
    assert factor == pytest.approx(d["reduced_chi2"] ** -0.5, rel=0.01) and factor > 1e6
    assert "read off it (1.3e-05" in low


def test_a_damped_run_is_written_as_a_load_cell_would_measure_it(tmp_path) -> None:
    """A run with radiation damping is written as a load cell would measure it: the friction
    column is the spring force / W (not the rate-and-state part), a header line gives the
    damping, and ratestate-fit warns that it does not model it (it gives Dc 6 % off)."""
    import xarray as xr

    args = ["ratestate", "--a", "0.01", "--b", "0.015", "--dc", "10 um", "--v-ref", "1 um/s", "--mu0", "0.6"]
    args += ["--stiffness-per-load", "1e-2 1/um", "--steps", "1 um/s,10 um/s", "--durations", "10 s,40 s"]
    args += ["--sample", "0.25 s", "--out", str(tmp_path / "run")]
    res = CliRunner().invoke(main, [*args, "--radiation-damping", "1000 s/m"])
    assert res.exit_code == 0, res.output
    rec = read_lab_record(tmp_path / "run" / "ratestate.csv", need_friction=True)
    assert rec.metadata["radiation_damping"] == "1000.0 s/m"
    ds = xr.load_dataset(tmp_path / "run" / "ratestate.nc")
    np.testing.assert_allclose(rec.friction, ds.spring_friction.values, rtol=1e-15)
    # the steady state a load cell reads: mu0 + (a - b) ln 10 + eta v (eta in friction per m/s:
    # 1000 s/m x 10 um/s = 0.01)
    assert rec.friction[-1] == pytest.approx(0.6 + (0.01 - 0.015) * math.log(10.0) + 0.01, rel=1e-9)
    fit = CliRunner().invoke(main, ["ratestate-fit", str(tmp_path / "run" / "ratestate.csv"), "--json"])
    assert fit.exit_code == 0, fit.output
    warnings = json.loads(fit.stdout)["warnings"]
    assert warnings[0].startswith("the record was made with radiation_damping = 1000.0 s/m")
    # without damping: no such header line, no such warning
    res = CliRunner().invoke(main, [*args[:-1], str(tmp_path / "plain")])
    assert res.exit_code == 0, res.output
    assert "radiation_damping" not in (tmp_path / "plain" / "ratestate.csv").read_text()


@pytest.mark.slow
def test_records_that_cannot_be_fitted_are_refused_at_once(tmp_path) -> None:
    """A record of two rows, or of one velocity throughout, is refused (not a 'result' with NaN
    errors and exit status 0); a reversed window is named as such (not '0 samples'); a record in
    um/s under a header in m/s is refused at once, with options the command has."""
    head = "# mu0 = 0.6\n# v_ref = 1 um/s\n# stiffness_per_load = 2e-3 1/um\n"
    two = tmp_path / "two.csv"
    two.write_text(head + "time [s],load-point velocity [um/s],friction [1]\n0,1,0.6\n0.1,10,0.6\n")
    with pytest.raises(DataError, match="2 samples; a fit of a, b, Dc needs many more"):
        fit_rate_state(read_lab_record(two, need_friction=True))
    flat = tmp_path / "flat.csv"
    rows = "".join(f"{0.1 * i:.1f},1,{0.6 + 1e-4 * math.sin(i):.6f}\n" for i in range(200))
    flat.write_text(head + "time [s],load-point velocity [um/s],friction [1]\n" + rows)
    res = CliRunner().invoke(main, ["ratestate-fit", str(flat), "--out", str(tmp_path / "f")])
    assert res.exit_code != 0 and "load-point velocity never changes in the record" in res.output, res.output
    rec = read_lab_record(_record(tmp_path, "aging", ONE, STEPS_ONE, ONE["k_per_um"]), need_friction=True)
    with pytest.raises(ValueError, match="its end is not after its start"):
        fit_rate_state(rec, window=("400 s", "50 s"))
    with pytest.raises(DataError, match="never changes in the window"):
        fit_rate_state(rec, window=("0 s", "90 s"))
    # um/s read as m/s: said after one simulation, naming the units
    text = (tmp_path / "aging.csv").read_text().replace("velocity [um/s]", "velocity [m/s]")
    (tmp_path / "mps.csv").write_text(text)
    with pytest.raises(DataError, match=r"cannot be simulated at the starting values .* Check the units"):
        fit_rate_state(read_lab_record(tmp_path / "mps.csv", need_friction=True))


def test_a_record_that_starts_in_a_hold_names_where_sliding_begins(tmp_path) -> None:
    """The fit starts from steady sliding at the first sample's velocity: a record whose
    first samples hold is refused, naming when sliding begins, and the window from there
    recovers the parameters the record was made with."""
    path = _record(tmp_path, "aging", ONE, STEPS_ONE, ONE["k_per_um"])
    lines = path.read_text().splitlines()
    first = next(i for i, line in enumerate(lines) if line[:1].isdigit())
    t_slide = float(lines[first + 5].split(",")[0])
    for i in range(first, first + 5):
        cells = lines[i].split(",")
        cells[1] = "0"
        lines[i] = ",".join(cells)
    held = tmp_path / "held.csv"
    held.write_text("\n".join(lines) + "\n")
    rec = read_lab_record(held, need_friction=True)
    with pytest.raises(DataError, match=rf"held.csv starts in a hold .*sliding begins at t = {t_slide:g} s"):
        fit_rate_state(rec)
    fit = fit_rate_state(rec, window=(f"{t_slide} s", f"{rec.time[-1]} s"))
    _check(fit.values, fit.errors, _truth_values(ONE))


def test_an_inertial_record_is_fitted_with_the_mass_warning(tmp_path) -> None:
    """A record of a run with a mass is fitted (its velocity changes at the change, not a sample
    late, where the fit runs away), and the mass warning is seen: a 1 kg slider barely biases
    the fit, a, b and Dc come back within 0.1 %, with the warning that quotes a mass's example."""
    out = tmp_path / "run"
    args = ["ratestate", "--a", "0.005", "--b", "0.01", "--dc", "10 um", "--v-ref", "1 um/s", "--mu0", "0.6"]
    args += ["--stiffness", "1e4 N/m", "--load", "10 N", "--mass", "1 kg", "--steps", "1 um/s,10 um/s"]
    args += ["--durations", "10 s,30 s", "--sample", "0.1 s", "--out", str(out)]
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, res.output
    res = CliRunner().invoke(main, ["ratestate-fit", str(out / "ratestate.csv"), "--json", "--no-plot"])
    assert res.exit_code == 0, res.output
    fit = json.loads(res.stdout)
    for name, true in (("a", 0.005), ("b", 0.01), ("dc", 10e-6)):
        assert fit["parameters"][name]["value"] == pytest.approx(true, rel=1e-3), name
    (warning,) = [w for w in fit["warnings"] if "made with mass" in w]
    assert "1 kg on 1e4 N/m" in warning and "1000 s/m" not in warning


def test_a_record_of_a_law_the_fit_lacks_says_so(tmp_path) -> None:
    """A Nagata (or formula, or two-law) run's record names its law in a '# law' line, and
    ratestate-fit refuses a law it lacks, naming the header line (fitted with the aging law it
    gives a = 0.00161 for 0.005); --law still fits one on purpose."""
    out = tmp_path / "run"
    args = ["ratestate", "--a", "0.005", "--b", "0.01", "--dc", "10 um", "--v-ref", "1 um/s", "--mu0", "0.6"]
    args += ["--law", "nagata", "--nagata-c", "2", "--stiffness-per-load", "1e-3 1/um"]
    args += ["--steps", "1 um/s,10 um/s,1 um/s", "--durations", "20 s,20 s,100 s", "--out", str(out)]
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, res.output
    text = (out / "ratestate.csv").read_text()
    assert "# law = nagata\n" in text and "# nagata_c = 2.0\n" in text
    res = CliRunner().invoke(main, ["ratestate-fit", str(out / "ratestate.csv"), "--no-plot"])
    assert res.exit_code == 2 and "law='nagata' (the record's '# law' line" in res.output
    res = CliRunner().invoke(
        main, ["ratestate-fit", str(out / "ratestate.csv"), "--no-plot", "--law", "aging"]
    )
    assert res.exit_code == 0, res.output


@pytest.mark.slow
def test_a_noisy_velocity_column_or_a_displacement_column_fits_the_truth(tmp_path) -> None:
    """Steps are changes of velocity beyond the noise: with a logged velocity of 1e-4 relative
    noise, np.diff(v) != 0 makes every row a 'step', the starting values absurd (Dc = 1e-9 m),
    and the fit ends at a = b = 0.032, Dc = 3e-10 m with tiny error bars; the same history as a
    displacement column (velocities differing in their last bits) fits too."""
    from stickslip.ratestate.fitting import velocity_steps

    t, v, mu = generate(
        a=0.008, b=[0.012], dc_um=[10.0], law="aging", k_per_um=2e-3, steps=STEPS_ONE, dt=0.2,
        noise=1e-4, seed=3,
    )  # fmt: skip
    header = {"mu0": "0.6", "v_ref": "1 um/s", "stiffness_per_load": "0.002 1/um", "law": "aging"}
    noisy = v * (1.0 + np.random.default_rng(7).normal(0.0, 1e-4, v.size))
    assert velocity_steps(noisy).size == velocity_steps(v).size == 3  # three steps, not every row
    path = tmp_path / "noisy.csv"
    write_csv(path, t, noisy, mu, header)
    fit = fit_rate_state(read_lab_record(path, need_friction=True))
    _check(fit.values, fit.errors, _truth_values(ONE))
    x = np.concatenate([[0.0], np.cumsum(v[:-1] * np.diff(t))])  # um: the same history, as a lab logs it
    lines = [f"# {k} = {val}" for k, val in header.items()] + [
        "time [s],load-point displacement [um],friction [1]"
    ]
    lines += [f"{a:.6f},{b:.9f},{c:.9f}" for a, b, c in zip(t, x, mu, strict=True)]
    (tmp_path / "disp.csv").write_text("\n".join(lines) + "\n")
    fit = fit_rate_state(read_lab_record(tmp_path / "disp.csv", need_friction=True))
    _check(fit.values, fit.errors, _truth_values(ONE))


def test_a_fit_that_cannot_finish_says_what_to_check_within_its_bound(tmp_path) -> None:
    """The fit has a wall-time bound that names the units to check: with a velocity header
    mislabelled [mm/s] (1000 times too fast) it runs past 400 s otherwise."""
    import time

    path = _record(tmp_path, "aging", ONE, STEPS_ONE, ONE["k_per_um"])
    text = path.read_text().replace("load-point velocity [um/s]", "load-point velocity [mm/s]")
    path.write_text(text)
    start = time.monotonic()
    with pytest.raises(
        DataError, match=r"did not finish in max_seconds=2 s\. Check the units of the columns"
    ):
        fit_rate_state(read_lab_record(path, need_friction=True), max_seconds=2.0)
    assert time.monotonic() - start < 30.0  # one model run is cut to the bound too (at least 1 s)
    with pytest.raises(ValueError, match="max_seconds=-1"):
        fit_rate_state(read_lab_record(path, need_friction=True), max_seconds=-1.0)
