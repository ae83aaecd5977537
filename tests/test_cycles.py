"""Earthquake cycles of the SEAS BP1 spring-slider: budgets, recurrence, integration through events."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner
from scipy.integrate import solve_ivp

from stickslip.cli import main
from stickslip.ratestate.cycles import BP1, YEAR, SpringSliderFault, earthquake_cycles, recurrence_estimate


@pytest.fixture(scope="module")
def run():
    return earthquake_cycles(BP1, "3000 yr")


def test_budgets_closed(run) -> None:
    b = run.budget
    # slip integrated from the slip rate against the plate's displacement minus the spring's stretch
    assert b["slip_error"] < 1e-10
    # load work = friction work + radiated energy + change of elastic energy
    assert b["energy_error"] < 1e-8
    assert b["radiated"] > 0 and b["friction_work"] > 0


def test_slip_rate_spans_ten_decades_and_steps_years_to_milliseconds(run) -> None:
    v = run.series.slip_rate.values
    assert v.max() / v.min() > 1e10
    assert v.max() > 0.1 and v.min() < 1e-12
    dt = np.diff(run.series.time.values)
    assert dt.max() > 0.3 * YEAR
    assert dt.min() < 1e-2
    assert np.all(np.isfinite(run.series.shear_stress.values))


def test_periodic_cycles_and_the_estimate(run) -> None:
    s = run.summary()
    assert s["events"] > 150
    assert s["recurrence_spread"] < 1e-6  # a limit cycle: every event alike
    est = recurrence_estimate(BP1, s["peak_slip_rate"])
    # the stress drop and the slip of the spring-slider estimate, to 10 %
    assert s["slip_m"] == pytest.approx(est["slip"], rel=0.1)
    assert s["stress_drop_MPa"] * 1e6 == pytest.approx(est["stress_drop"], rel=0.1)
    # the recurrence is at least the all-seismic bound, and the difference is the aseismic slip
    t_rec = s["recurrence_yr"] * YEAR
    assert est["recurrence"] <= t_rec <= 1.5 * est["recurrence"]
    vpl = BP1.plate_rate.to("m/s").magnitude
    seismic_share = s["slip_m"] / (vpl * t_rec)
    assert 0.6 < seismic_share < 1.0
    # the slip budget per cycle: the plate's displacement in one recurrence
    cat = run.catalog.isel(event=slice(2, None))
    per_cycle = np.diff(cat.cumulative_slip.values)
    np.testing.assert_allclose(per_cycle, vpl * cat.recurrence.values[1:], rtol=1e-6)


def _scipy_reference(years: float) -> np.ndarray:
    """Event start times by SciPy's Radau on (slip, state), from the equations (not our code)."""
    from reference import bp1 as ref

    def event(t: float, y: np.ndarray) -> float:
        return math.log(ref.slip_rate(t, y) / 1e-3)

    event.direction = 1  # type: ignore[attr-defined]
    sol = solve_ivp(
        ref.rhs, (0.0, years * YEAR), [0.0, ref.THETA0], method="Radau", rtol=1e-10, atol=[1e-12, 1e-8],
        events=event,
    )  # fmt: skip
    assert sol.status == 0
    return sol.t_events[0]


def test_event_times_against_scipy(run) -> None:
    t_ref = _scipy_reference(35.0)
    t_ours = run.catalog.t_start.values[: t_ref.size]
    assert t_ref.size >= 2
    np.testing.assert_allclose(t_ours, t_ref, rtol=1e-6)


def test_inertial_beside_it() -> None:
    inert = earthquake_cycles(BP1, "120 yr", inertial=True)
    s = inert.summary(spin_up=1)
    assert s["events"] >= 4
    assert inert.budget["slip_error"] < 1e-8
    assert inert.budget["energy_error"] < 1e-6
    qd = earthquake_cycles(BP1, "120 yr").summary(spin_up=1)
    # same friction, same loading: recurrences within 30 % of each other
    assert s["recurrence_yr"] == pytest.approx(qd["recurrence_yr"], rel=0.3)


def test_bad_fault() -> None:
    with pytest.raises(ValueError, match="velocity strengthening"):
        SpringSliderFault(a=0.02, b=0.015)
    with pytest.raises(ValueError, match="below critical"):
        SpringSliderFault(stiffness_ratio=1.5)
    with pytest.raises(ValueError, match="normal_stress"):
        SpringSliderFault(normal_stress="50 m")
    # checked before the compiled loop: a nan rtol made it spin without end
    for bad in ({"rtol": float("nan")}, {"rtol": -1.0}, {"atol": 0.0}, {"max_steps": 0}):
        with pytest.raises(ValueError, match=f"{next(iter(bad))}="):
            earthquake_cycles(BP1, "1 yr", **bad)


def test_cli(tmp_path) -> None:
    res = CliRunner().invoke(
        main, ["earthquake-cycles", "--duration", "200 yr", "--out", str(tmp_path), "--json"]
    )
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)["quasi-dynamic"]
    assert d["recurrence_yr"] == pytest.approx(14.17, rel=1e-3)
    assert d["budget"]["energy_error"] < 1e-8
    assert (tmp_path / "cycles.png").stat().st_size > 20_000
    assert (tmp_path / "catalog_quasi-dynamic.csv").read_text().count("\n") > 10
    # the catalogue's columns carry their units; the values are SI, as in
    # cycles.nc (the JSON gives years and MPa)
    import pandas as pd

    cat = pd.read_csv(tmp_path / "catalog_quasi-dynamic.csv")
    assert {"t_start [s]", "slip [m]", "stress_drop [Pa]", "recurrence [s]"} <= set(cat.columns)
    recurrence_yr = cat["recurrence [s]"].iloc[2:].mean() / (365.25 * 86400)
    assert recurrence_yr == pytest.approx(d["recurrence_yr"], rel=1e-3)
    # the range's top is the events' located peak, not only the samples' (the samples' top
    # lies below it: 0.83259 against 0.83291 here)
    assert d["slip_rate_range_m_s"][1] == pytest.approx(cat["peak_slip_rate [m/s]"].max(), rel=1e-12)
    assert d["slip_rate_range_m_s"][1] >= d["peak_slip_rate"]


def test_json_has_null_not_nan(tmp_path) -> None:
    """cycles.json and --json write null, never bare NaN (one event: no recurrence spread; an
    inertial run without events): JSON parsers other than Python's refuse NaN."""

    def strict(text: str) -> dict:
        return json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in JSON"))

    res = CliRunner().invoke(
        main, ["earthquake-cycles", "--duration", "20 yr", "--out", str(tmp_path), "--json"]
    )
    assert res.exit_code == 0, res.output
    printed = strict(res.output)
    assert printed["quasi-dynamic"]["recurrence_spread"] is None  # one event after the spin-up, or none
    strict((tmp_path / "cycles.json").read_text())


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--stiffness", "1.5e7 Pa/m", "--stiffness-ratio", "0.7"], "--stiffness or --stiffness-ratio"),
        (["--mass", "1e9 kg/m^2"], "give --inertial with it"),
    ],
)
def test_cli_refuses_options_that_would_reach_nothing(args: list[str], message: str, tmp_path) -> None:
    """Once ignored without a word: the ratio beside a stiffness, a mass without the inertial slider."""
    res = CliRunner().invoke(
        main, ["earthquake-cycles", "--duration", "10 yr", *args, "--out", str(tmp_path)]
    )
    assert res.exit_code == 2 and message in res.output, res.output


def test_v_event_and_stops_are_said_in_words(tmp_path) -> None:
    """v_event must lie well above the plate rate (below it the creep itself counts as events,
    with a 3.9 MPa 'stress drop'); a 1 m/s plate, a v_event above every peak and a Dc too small
    are each said in words, not as a status number or NaN summaries among numpy warnings."""
    with pytest.raises(ValueError, match=r"v_event='1e-12 m/s': .* well above the plate rate"):
        earthquake_cycles(BP1, "10 yr", v_event="1e-12 m/s")
    with pytest.raises(ValueError, match=r"plate rate \(1 m/s"):
        earthquake_cycles(SpringSliderFault(plate_rate="1 m/s"), "10 yr")
    args = ["earthquake-cycles", "--v-event", "10 m/s", "--duration", "100 yr", "--out", str(tmp_path / "o")]
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, res.output
    said = "no event after the spin-up reached v_event = 10 m/s (the slip rate peaked at 0.833 m/s)"
    assert said in res.output, res.output
    assert "nan" not in res.output and "warning" not in res.output, res.output
    from stickslip.plots.figures import plot_earthquake_cycles

    fig = plot_earthquake_cycles([earthquake_cycles(BP1, "100 yr", v_event="10 m/s")])
    assert [t.get_text() for t in fig.axes[2].texts] == ["no event to show: fewer than 3 reached v_event"]
    with pytest.raises(RuntimeError, match="the step size fell below the precision of the clock") as info:
        earthquake_cycles(SpringSliderFault(dc="1e-12 m"), "10 yr")
    assert "status" not in str(info.value)


@pytest.mark.slow
def test_a_run_longer_than_one_clock_holds(run) -> None:
    """The integration restarts its clock every CHUNK seconds: on one clock an event's
    millisecond steps fall below the precision of t after about 26627 years. 30000 years give
    the same cycle as 3000."""
    long = earthquake_cycles(BP1, "30000 yr")
    a, b = long.summary(), run.summary()
    assert a["events"] > 9 * b["events"]
    for key, rel in (("recurrence_yr", 1e-6), ("slip_m", 1e-6), ("peak_slip_rate", 1e-5)):
        assert a[key] == pytest.approx(b[key], rel=rel), key  # the peak: on the dense output, rtol 1e-8
    assert long.budget["slip_error"] < 1e-10 and long.budget["energy_error"] < 1e-8
    t = long.series.time.values  # the spans' clocks offset back: one increasing time
    assert np.all(np.diff(t) > 0) and t[-1] > 29999 * YEAR
    assert np.all(np.diff(long.catalog.t_start.values) > 0)


def test_the_estimate_sits_in_the_stress_panel_above_its_curve() -> None:
    """The spring-slider estimate sits inside the stress panel, in headroom above the curve:
    as a title between the panels it reads as the slip-rate panel's caption, and at the
    panel's foot it hides three of the four stress drops."""
    import matplotlib

    matplotlib.use("Agg")
    from stickslip.plots.figures import plot_earthquake_cycles

    run = earthquake_cycles(BP1, "40 yr")
    est = recurrence_estimate(BP1, run.summary()["peak_slip_rate"])
    ax = plot_earthquake_cycles([run], est).axes[1]
    assert ax.get_title() == ""
    (text,) = [t for t in ax.texts if t.get_text().startswith("spring-slider estimate: stress drop")]
    assert text.get_position()[1] > 0.9
    y = np.concatenate([ln.get_ydata() for ln in ax.get_lines()])
    lo, hi = ax.get_ylim()
    assert (hi - float(np.max(y))) / (hi - lo) > 0.15  # the text's headroom


def test_a_run_with_more_events_than_it_locates_is_refused_from_its_first_thousand() -> None:
    """The rate of the later half of the events so far sets the refusal (5 % beyond the capacity)."""
    from stickslip.ratestate.cycles import _say_too_many_events

    ev = np.zeros((200_000, 4))
    ev[:1000, 1] = np.arange(1000) * 5.0 * YEAR  # an event every 5 yr, after a transient below
    ev[:10, 1] = np.arange(10) * 0.1 * YEAR
    done = 5000.0 * YEAR
    _say_too_many_events(ev, 999, done, 1e7 * YEAR)  # too few events yet to say
    _say_too_many_events(ev, 1000, done, 1.0e6 * YEAR)  # 2e5 expected: it runs
    said = r"about 2.2e\+05 events \(1000 in the first 5000 yr, one every 5 yr\).*at most about 1e\+06 yr"
    with pytest.raises(RuntimeError, match=said):
        _say_too_many_events(ev, 1000, done, 1.1e6 * YEAR)
