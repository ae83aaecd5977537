"""Branches, bifurcations and regimes: continuation, saltation, averaging, the criterion on trial."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from reference.one_block import (
    forward_branch,
    pure_slip_orbit_reference,
    reference_cycle,
    unstable_orbit_reference,
)
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from stickslip import CoulombLaw, CubicLaw, DimensionlessParameters, WeakeningLaw, cycle
from stickslip.bifurcation.averaging import averaging_table, thomsen_fidlin
from stickslip.bifurcation.regime_map import criterion_table, criterion_trial, regime_map
from stickslip.bifurcation.regimes import _fold, _orbits_at, confirm, pure_slip_orbits_at, regimes
from stickslip.cli import main
from stickslip.core.api import run_flow
from stickslip.laws import law_arrays
from stickslip.laws.expression import ExpressionLaw
from stickslip.orbits.periodic import pure_slip_orbit, saltation, stick_slip_orbit

CUBIC = CubicLaw(alpha=0.5, gamma=0.5 / 3)  # supercritical Hopf at nu = 1
F2 = WeakeningLaw(c=3.8, p=0.5)  # subcritical Hopf at nu = 0.4623


@pytest.fixture(scope="module")
def cubic_diagram():
    return regimes(CUBIC, 0.5, 1.5)


@pytest.fixture(scope="module")
def f2_diagram():
    return regimes(F2, 0.1, 1.5)


@pytest.mark.parametrize(("law", "nu", "s0"), [(CUBIC, 0.97, 1.3), (F2, 0.55, 0.8), (F2, 0.3, 0.75)])
def test_compiled_variational_flow_matches_scipy(law, nu: float, s0: float) -> None:
    """Phi, d/dnu and the divergence integral against an independent solve_ivp integration."""
    period = 3.0

    cubic = ("cubic", {"alpha": 0.5, "gamma": 0.5 / 3})
    name, params = cubic if law is CUBIC else ("weakening", {"c": 3.8, "p": 0.5})
    slope = {  # f'(w), typed here
        "cubic": lambda w: -params["alpha"] + 3 * params["gamma"] * w * w,
        "weakening": lambda w: -params["c"] / (1 + params["c"] * w) ** 2 + params["p"],
    }[name]

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        s, w = y[0], y[1]
        f = forward_branch(name, params, w)  # tests/reference/one_block.py: its own copy of the laws
        df = slope(w)
        p = y[2:6].reshape(2, 2)
        j = np.array([[0.0, -1.0], [1.0, -df]])
        dz = j @ y[6:8] + np.array([1.0, 0.0])
        return [nu - w, s - f, *(j @ p).ravel(), *dz, df]

    y0 = [s0, nu, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    sol = solve_ivp(rhs, (0, period), y0, method="DOP853", rtol=1e-13, atol=1e-15)
    ref = sol.y[:, -1]
    kernel, lp = law_arrays(law)
    y = run_flow(kernel, lp, nu, s0, nu, period, rtol=1e-12).state
    assert sol.y[1].min() > 0  # the comparison stays in forward slip
    np.testing.assert_allclose(y, ref, rtol=1e-9, atol=1e-11)


def test_cubic_regimes(cubic_diagram) -> None:
    d = cubic_diagram
    assert [iv.regime for iv in d.intervals] == ["stick-slip", "pure-slip", "steady-sliding"]
    (h,) = d.hopf
    assert h.nu == pytest.approx(1.0, abs=1e-12) and h.criticality == "supercritical"
    assert d.intervals[1].nu_max == pytest.approx(1.0, abs=1e-12)
    graze = [p.nu for p in d.points if p.kind == "grazing"]
    onset = [p.nu for p in d.points if p.kind == "stick-slip-onset"]
    # two independent computations of one point: the continued orbit touching w = 0
    # (shooting) and the slip from breakaway ceasing to stop (the non-smooth engine)
    assert graze[0] == pytest.approx(onset[0], rel=1e-8)
    ps = next(b for b in d.branches if b.kind == "pure-slip")
    assert ps.end == "grazing" and ps.stable.all() and np.all(ps.multiplier < 1)
    assert ps.min_velocity[-1] == pytest.approx(0.0, abs=1e-9)


def test_subcritical_weakening_regimes(f2_diagram) -> None:
    d = f2_diagram
    assert [iv.regime for iv in d.intervals] == ["stick-slip", "bistable", "steady-sliding"]
    (h,) = d.hopf
    assert h.criticality == "subcritical"
    # f'(nu_H) = 0: -c/(1 + c nu)^2 + p = 0
    assert h.nu == pytest.approx((math.sqrt(3.8 / 0.5) - 1) / 3.8, rel=1e-12)
    bi = d.intervals[1]
    assert bi.attractors == ("stick-slip", "steady-sliding")
    assert bi.nu_min == pytest.approx(h.nu, rel=1e-12)
    ps = next(b for b in d.branches if b.kind == "pure-slip")
    assert not ps.stable.any() and np.all(ps.multiplier > 1)  # the unstable cycle of a subcritical Hopf
    # the unstable cycle grows with nu until it grazes: that ends the bistable interval. Independently,
    # the plain-SciPy reference: the slip from breakaway stops (stick-slip) just below that end and
    # never stops (it spirals onto steady sliding) just above
    assert np.all(np.diff(ps.nu) > 0)
    end = bi.nu_max
    assert reference_cycle("weakening", {"c": 3.8, "p": 0.5}, end * (1 - 1e-5)).amplitude > 0
    with pytest.raises(RuntimeError, match="did not stop"):
        reference_cycle("weakening", {"c": 3.8, "p": 0.5}, end * (1 + 1e-5), t_phase=2e3)


@pytest.mark.parametrize("which", ["cubic", "f2"])
def test_intervals_confirmed_by_simulation(which: str, cubic_diagram, f2_diagram) -> None:
    d = cubic_diagram if which == "cubic" else f2_diagram
    checks = confirm(d)
    assert len(checks) == len(d.intervals)
    for c in checks:
        assert c.agree, c
    if which == "f2":  # both attractors reached in the bistable interval
        assert checks[1].found == ("steady-sliding", "stick-slip")
    else:  # the stable pure-slip cycle reached from other starts is the continued one
        assert checks[1].pure_slip_amplitude_error < 1e-6


def test_unstable_orbit_separates_the_basins(f2_diagram) -> None:
    """Inside the unstable cycle motion decays to steady sliding; outside it sticks."""
    from stickslip import simulate

    nu = 0.55
    (o,) = pure_slip_orbits_at(f2_diagram, nu)
    assert o.multipliers[1].real > 1 and not o.stable
    assert abs(o.multipliers[0] - 1) < 1e-8
    p = DimensionlessParameters(nu=nu, law=F2)
    f_nu = float(F2.forward(np.array([nu]))[0])
    inner = simulate(p, duration=300, n_points=3001, initial=(f_nu + 0.97 * (o.s0 - f_nu), nu))
    outer = simulate(p, duration=300, n_points=3001, initial=(f_nu + 1.03 * (o.s0 - f_nu), nu))
    assert np.ptp(inner.spring_force[-500:]) < 1e-3
    assert np.any(outer.velocity == 0.0)  # it sticks


@pytest.mark.parametrize(
    ("law", "nu"), [(WeakeningLaw(c=3.8), 0.1), (F2, 0.3), (CUBIC, 0.8), (CoulombLaw(kinetic=0.5), 0.3)]
)
def test_stick_slip_multipliers(law, nu: float) -> None:
    """Saltation at the stop kills the velocity direction: multipliers 1 (trivial) and 0."""
    o = stick_slip_orbit(DimensionlessParameters(nu=nu, law=law))
    assert abs(o.multipliers[0] - 1) < 1e-8
    assert abs(o.multipliers[1]) < 1e-12


def test_saltation_matrix() -> None:
    # Coulomb breakaway: the stick field (nu, 0) jumps to (nu, 1 - k) across s = 1
    nu, k = 0.3, 0.5
    s = saltation(np.array([nu, 0.0]), np.array([nu, 1 - k]), np.array([1.0, 0.0]))
    np.testing.assert_allclose(s, [[1, 0], [(1 - k) / nu, 1]])
    # it maps the field before onto the field after
    np.testing.assert_allclose(s @ [nu, 0.0], [nu, 1 - k])
    with pytest.raises(ValueError, match="tangentially"):
        saltation(np.array([0.0, 1.0]), np.array([1.0, 1.0]), np.array([1.0, 0.0]))


def test_no_stick_slip_orbit_is_reported() -> None:
    with pytest.raises(RuntimeError, match="does not stop"):
        stick_slip_orbit(DimensionlessParameters(nu=1.2, law=CUBIC))


def test_fold_location() -> None:
    """A fold of cycles between three continuation points is the vertex of nu(arclength)."""
    pts = [np.array([a, 6.28, 1.0 - (a - 0.5) ** 2]) for a in (0.4, 0.52, 0.6)]
    f = _fold(pts, [{"amplitude": 2 * p[0]} for p in pts])
    assert f.kind == "fold"
    assert f.nu == pytest.approx(1.0, abs=1e-4)
    assert f.amplitude == pytest.approx(1.0, abs=1e-2)


def test_a_fold_of_cycles_is_located_to_1e_9() -> None:
    """A fold of cycles is located to 1e-9, not as the vertex of a quadratic through three
    continuation points (5.7e-4 short on this N-shaped law: 2.2786964 for 2.2792696), so that
    `regime_at(2.279)` finds the stable pure-slip orbit that exists there.

    Reference: plain SciPy shooting of the stable and the unstable orbit at two velocities below
    the fold; near a saddle-node the squared gap between their amplitudes is linear in the
    distance to the fold, which gives the fold independently."""
    law = ExpressionLaw("1/(1+3.8*w)+2*w*exp(-w/2)")
    d = regimes(law, 1.5, 3.0)
    (fold,) = [p for p in d.points if p.kind == "fold"]
    assert "multiplier 1.0000" in fold.detail
    gaps = []
    nus = (fold.nu - 4e-5, fold.nu - 1e-5)
    for nu in nus:
        orbits = []
        for amp, s0, period in _orbits_at(d.branches, nu, stable_only=False):
            if amp > 4.0:  # the two orbits about to meet (the small one near the Hopf point aside)
                orbits.append(
                    pure_slip_orbit_reference(
                        lambda w: float(law.at(w)), lambda w: float(law.at(w, 1)), nu, (s0, period)
                    )
                )
        amps = sorted({round(o.amplitude, 9) for o in orbits})
        assert len(amps) == 2, (nu, amps)
        mults = sorted(o.multiplier for o in orbits)
        assert mults[0] < 1.0 < mults[1]  # one stable, one unstable
        gaps.append((amps[1] - amps[0]) ** 2)
    nu_ref = nus[1] + gaps[1] * (nus[1] - nus[0]) / (gaps[0] - gaps[1])
    assert fold.nu == pytest.approx(nu_ref, abs=2e-8)
    assert d.regime_at(2.279).regime == "bistable"  # stick-slip and the stable pure-slip orbit
    assert d.regime_at(fold.nu + 1e-6).regime == "stick-slip"


@pytest.mark.slow
def test_continuation_does_not_jump_to_another_part_of_its_branch() -> None:
    """On this law's branch from its subcritical Hopf point, near grazing (minimum velocity
    0.025), a corrector step must not land on the unstable part of the same branch (9.6 away in
    amplitude for a step of at most 0.2) and retrace it to the Hopf point (the branch ending
    `hopf`, no grazing point, the unstable part drawn twice): the branch ends where the
    stick-slip onset (located independently, by bisection on the engine) says it grazes."""
    law = ExpressionLaw("1/(1+3.8*w)+2*w*exp(-w/2)+0.05*w")
    d = regimes(law, 9.0, 16.0)
    (h,) = d.hopf
    assert h.criticality == "subcritical" and h.nu == pytest.approx(10.3264898, abs=1e-7)
    (b,) = [b for b in d.branches if b.kind == "pure-slip" and abs(b.nu[0] - h.nu) < 0.01]
    assert b.end == "grazing"
    assert np.all(np.abs(np.diff(b.amplitude)) < 1.0)  # no jump along the branch
    (graze,) = [p for p in d.points if p.kind == "grazing"]
    (onset,) = [p for p in d.points if p.kind == "stick-slip-onset"]
    assert graze.nu == pytest.approx(onset.nu, abs=1e-7)
    (fold,) = [p for p in d.points if p.kind == "fold"]
    assert fold.nu == pytest.approx(15.2324919, abs=1e-6)
    assert [iv.regime for iv in d.intervals] == ["stick-slip", "bistable", "bistable", "steady-sliding"]


def test_thomsen_fidlin_formulas() -> None:
    tf = thomsen_fidlin(CUBIC)
    assert tf.nu_hopf == pytest.approx(1.0)
    assert tf.nu_border == pytest.approx(math.sqrt(0.8))
    assert tf.amplitude(tf.nu_border) == pytest.approx(2 * tf.nu_border)  # a = nu at the border
    assert math.isnan(tf.amplitude(1.1))
    with pytest.raises(ValueError, match="cubic"):
        thomsen_fidlin(F2)  # type: ignore[arg-type]


def test_averaging_error_shrinks_with_the_nonlinearity() -> None:
    """First-order averaging is exact for the Hopf point and second-order accurate
    (error ~ eps^2, as for the van der Pol amplitude) for the pure-slip amplitude and border."""
    rows = averaging_table((0.5, 0.25, 0.125))
    for r in rows:
        assert r.nu_hopf == pytest.approx(1.0, rel=1e-12)  # sqrt(alpha/(3 gamma)) = 1 for every eps
    for attr in ("border_error", "amplitude_error"):
        errs = np.array([getattr(r, attr) for r in rows])
        order = np.polyfit(np.log([0.5, 0.25, 0.125]), np.log(errs), 1)[0]
        assert 1.8 < order < 2.2, (attr, errs)


def test_regime_map_and_criterion(tmp_path: Path) -> None:
    ds = regime_map(CUBIC, "gamma", [0.1, 0.5 / 3, 0.3], 0.3, 2.0, n_nu=61, progress=False)
    # the Hopf line is f'(nu) = 0: nu = sqrt(alpha / (3 gamma))
    np.testing.assert_allclose(ds.hopf.values, np.sqrt(0.5 / (3 * ds.gamma.values)), rtol=1e-10)
    assert set(np.unique(ds.regime.values)) <= {0, 1, 2}
    trial = criterion_trial(ds)
    table = criterion_table(trial)
    assert [r["regime"] for r in table] == ["stick-slip", "pure-slip", "slip-reversal"]
    assert all(r["judged"] > 0 for r in table[:2])
    # for this law the criterion holds wherever it is judged
    assert all(r["wrong"] == 0 for r in table)
    # and it is judged from real slopes: positive on stick-slip, negative on pure slip
    sl = trial.slope.values
    assert np.all(sl[(trial.observed.values == 0) & (trial.right.values == 1)] > 0)
    assert np.all(sl[(trial.observed.values == 1) & (trial.right.values == 1)] < 0)
    trial.to_netcdf(tmp_path / "m.nc")
    back = xr.load_dataset(tmp_path / "m.nc")
    np.testing.assert_array_equal(back.regime.values, ds.regime.values)
    # the coordinates have units, as CF asks; the figure names the onset in words, as the
    # bifurcation figure does
    assert back.nu.attrs["units"] == "1" and back.gamma.attrs["units"] == "1"
    assert (
        back.amplitude.attrs["units"] == "1"
        and back.amplitude.attrs["scale"] == "static friction force mu_s W"
    )
    from stickslip.plots.regimes import plot_regime_map

    labels = plot_regime_map(ds).axes[0].get_legend_handles_labels()[1]
    assert "onset of stick-slip" in labels and "Hopf point" in labels
    assert not any(w in labels for w in ("stick-slip-onset", "stick slip onset", "hopf"))


def test_a_log_sweep_figure_leaves_steady_sliding_out() -> None:
    """On log axes steady sliding's amplitude 0 is left out of the plot (drawn, its lines run off
    the bottom of the figure); the data keep those points."""
    from stickslip.dynamics.sweep import sweep
    from stickslip.plots.figures import plot_sweep

    ds = sweep(DimensionlessParameters(nu=0.1, law=WeakeningLaw(c=3.8, p=0.5)), {"nu": [0.1, 0.3, 2.0]})
    assert float(ds.amplitude.values[-1]) == 0.0  # steady sliding at nu = 2
    line = plot_sweep(ds, log=True).axes[0].get_lines()[0]
    y = np.asarray(line.get_ydata(), dtype=float)
    assert np.isnan(y[-1]) and np.all(y[:2] > 0)


def test_regimes_bad_input() -> None:
    with pytest.raises(ValueError, match="nu_max"):
        regimes(CUBIC, 1.0, 0.5)
    with pytest.raises(ValueError, match="nu_min"):
        regimes(CUBIC, -1.0, 0.5)
    with pytest.raises(ValueError, match="n_grid"):
        regimes(CUBIC, 0.5, 1.0, n_grid=2)
    with pytest.raises(ValueError, match="param='c'"):
        regime_map(CUBIC, "c", [1.0], 0.5, 1.0)
    with pytest.raises(ValueError, match="regime map of the coulomb law"):
        regime_map(CoulombLaw(kinetic=0.5), "kinetic", [0.5], 0.5, 1.0)
    # the shooting tolerance: nan or negative once lost the pure-slip branch without a word
    for tol in (float("nan"), -1.0, 0.0, 1.0):
        with pytest.raises(ValueError, match="tol="):
            regimes(CUBIC, 0.5, 1.0, tol=tol)
    assert len(regimes(CUBIC, 0.5, 1.5, n_grid=np.int64(11)).intervals) == 3
    # every value and the nu grid are checked before the first row (the map's n_nu, not n_grid)
    with pytest.raises(ValueError, match="n_nu=4"):
        regime_map(CUBIC, "alpha", [0.5], 0.5, 1.0, n_nu=4)
    with pytest.raises(ValueError, match=r"alpha: 0.5 is given twice \(points 0 and 2\)"):  # one row twice
        regime_map(CUBIC, "alpha", [0.5, 0.6, 0.5], 0.5, 1.0)
    with pytest.raises(ValueError, match="gamma"):
        regime_map(CUBIC, "gamma", [1 / 6, -1.0], 0.5, 1.0, progress=False)


def run(*args: str):
    return CliRunner().invoke(main, list(args))


def test_cli_regimes_json(tmp_path: Path) -> None:
    res = run(
        "regimes",
        "--c",
        "3.8",
        "--p",
        "0.5",
        "--nu-min",
        "0.1",
        "--nu-max",
        "1.5",
        "--json",
        "--check",
        "--out",
        str(tmp_path),
    )
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    assert d["hopf"][0]["criticality"] == "subcritical"
    assert d["hopf"][0]["nu"] == pytest.approx(0.46231835537, rel=1e-9)
    assert [iv["regime"] for iv in d["intervals"]] == ["stick-slip", "bistable", "steady-sliding"]
    assert all(set(iv) >= {"regime", "nu_min", "nu_max"} for iv in d["intervals"])
    assert {b["kind"] for b in d["branches"]} == {"steady-sliding", "pure-slip", "stick-slip"}
    assert all(c["agree"] for c in d["check"])
    assert (tmp_path / "bifurcation.png").stat().st_size > 10_000
    assert json.loads((tmp_path / "regimes.json").read_text())["intervals"] == d["intervals"]


def test_cli_regimes_physical_and_map(tmp_path: Path) -> None:
    res = run(
        "regimes",
        "--preset",
        "zv",
        "--b",
        "100 s/m",
        "--nu-min",
        "0.01",
        "--nu-max",
        "1",
        "--map",
        "p=1..3",
        "--map-n",
        "3",
        "--n",
        "41",
        "--out",
        str(tmp_path),
    )
    assert res.exit_code == 0, res.output
    assert "Hopf point" in res.output and "m/s" in res.output
    d = json.loads((tmp_path / "regimes.json").read_text())
    assert d["beta_s_per_m"] == pytest.approx(42.0)
    iv = d["intervals"][0]
    assert iv["v0_max_m_per_s"] == pytest.approx(iv["nu_max"] / 42.0)
    # the text in a unit that suits the range (0.24 to 23.8 mm/s; it printed m/s), Hopf point too
    hopf_mm_s = d["hopf"][0]["nu"] / 42.0 * 1e3
    assert f"(v0 = {hopf_mm_s:.6g} mm/s)" in res.output
    first = next(ln for ln in res.output.splitlines() if ln.startswith(iv["regime"] + " "))
    assert f"v0 {iv['nu_min'] / 42.0 * 1e3:.4g} .. {iv['nu_max'] / 42.0 * 1e3:.4g} mm/s" in first
    assert [r["regime"] for r in d["criterion"]] == ["stick-slip", "pure-slip", "slip-reversal"]
    for name in ("regime_map.nc", "regime_map.png", "criterion_map.png"):
        assert (tmp_path / name).exists()
    # the map of a physical set-up says which: beta stored, v0 on its figures
    from stickslip.plots.regimes import plot_criterion_map, plot_regime_map

    m = xr.load_dataset(tmp_path / "regime_map.nc")
    assert m.attrs["beta_s_per_m"] == pytest.approx(42.0)
    for fig in (plot_regime_map(m), plot_criterion_map(m)):
        (top,) = fig.axes[0].child_axes
        assert top.get_xlabel() == "driving velocity $v_0$ [mm/s]"
        assert "beta_s_per_m" not in fig.axes[0].get_title()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--c", "3.8", "--nu", "0.5"], "--nu-min and --nu-max"),
        (["--c", "3.8", "--nu-min", "2", "--nu-max", "1"], "nu_max"),
        (["--c", "3.8", "--nu-min", "0", "--nu-max", "1"], "nu_min"),
        (["--c", "3.8", "--map", "p"], "NAME=A..B"),
        (["--c", "3.8", "--map", "alpha=1..2"], "param='alpha'"),
        (["--c", "3.8", "--map", "p=a..b"], "p="),
        (["--law", "cubic", "--alpha", "0.5"], "--gamma"),
    ],
)
def test_cli_regimes_bad_input(args: list[str], message: str) -> None:
    res = run("regimes", *args)
    assert res.exit_code == 2 or res.exit_code == 1, res.output
    assert message in res.output
    assert "Traceback" not in res.output


def test_pure_slip_orbit_from_branch_guess_matches_direct(cubic_diagram) -> None:
    (o,) = pure_slip_orbits_at(cubic_diagram, 0.97)
    direct = pure_slip_orbit(DimensionlessParameters(nu=0.97, law=CUBIC))
    assert o.amplitude == pytest.approx(direct.amplitude, rel=1e-8)


@pytest.mark.parametrize(
    ("c", "nu", "exact"),
    [(38.547360389217516, 5.568813990945273, 0.6014472250591165), (50.0, 10.0, 0.8556683749985649)],
)
def test_the_slip_reversal_multiplier_is_the_variational_one(c: float, nu: float, exact: float) -> None:
    """A slip-reversal orbit's multiplier is the variational one, within 1e-8: one central
    difference of the return map at h = 1e-5 is off by 3.4e-7 and 1.9e-7 here, whatever the
    tolerance. The exact values come from an independent reference (SciPy DOP853 at rtol
    1e-13, the variational equations with the saltation matrices at the crossings of w = 0:
    det of the monodromy; two reversals a period), extrapolated."""
    r = cycle(DimensionlessParameters(nu=nu, law=WeakeningLaw(c=c)), probe=False)
    assert r.regime.value == "slip-reversal" and r.backward_slips > 0
    assert r.multiplier == pytest.approx(exact, abs=1e-8)
    assert abs(r.multiplier - exact) < 0.1 * 1.9e-7  # tenfold below the finite difference's error


def test_slip_reversal_is_an_attractor_of_its_own() -> None:
    """F1 at large nu: the block never sticks but its velocity changes sign every cycle."""
    d = regimes(WeakeningLaw(c=3.8), 1.0, 9.0, n_grid=41)
    assert [iv.regime for iv in d.intervals] == ["stick-slip", "slip-reversal"]
    assert d.intervals[1].attractors == ("slip-reversal",)
    # independently, the plain-SciPy reference sticks just below the boundary and reverses
    # without ever sticking just above it
    end = d.intervals[0].nu_max
    assert reference_cycle("weakening", {"c": 3.8}, end * (1 - 1e-5)).stick_time > 0
    with pytest.raises(RuntimeError, match="no stick"):
        reference_cycle("weakening", {"c": 3.8}, end * (1 + 1e-5), t_phase=2e3)
    assert all(c.agree for c in confirm(d))


def test_cubic_law_warns_where_friction_turns_negative() -> None:
    import warnings

    with pytest.warns(UserWarning, match="turns negative"):
        CubicLaw(alpha=1.2, gamma=1 / 6)  # alpha**3 = 1.73 > 27 gamma / 4 = 1.125
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        CubicLaw(alpha=1.0, gamma=1 / 6)  # 1.0 < 1.125: positive everywhere
        CubicLaw(alpha=0.5, gamma=1 / 6)


@pytest.mark.slow
def test_a_hopf_point_on_a_table_row_starts_its_branch() -> None:
    """A subcritical Hopf point on a pchip row (f'' jumps by J there) starts its pure-slip
    branch: near a kink the small cycle grows linearly, f'(nu) = -2 J a / (3 pi) (the cubic
    averaging formula's guess fails Newton there), and the branch is followed in scaled
    coordinates (in (A, T, nu) the period takes every step). Forward shooting loses it at
    multiplier 3200; shot backward in time where unstable, it is followed to its grazing at
    the stick-slip onset. Its orbits agree with plain SciPy shooting
    (forward where that can converge, a backward return map beyond)."""
    from stickslip import PhysicalParameters, TabulatedLaw
    from stickslip.units import Q_

    v = [0, 1, 3, 10, 30, 100, 300, 1000, 3000, 10000]
    mu = [0.50, 0.49, 0.47, 0.44, 0.41, 0.39, 0.385, 0.39, 0.40, 0.42]
    table = TabulatedLaw(Q_(v, "um/s"), mu)
    law = PhysicalParameters(mass="100 g", stiffness="500 N/m", load="2 N", v0="1 mm/s", law=table)
    law = law.dimensionless().law
    d = regimes(law, 0.0005, 0.2)
    (h,) = d.hopf
    assert h.kink < 0 and h.criticality == "subcritical"
    assert h.nu == pytest.approx(300e-6 * math.sqrt(0.1 * 500) / (0.5 * 2.0), rel=1e-12)
    (b,) = [b for b in d.branches if b.kind == "pure-slip"]
    assert b.nu.size > 50 and not b.stable.any() and np.all(b.nu > h.nu)
    # linear growth from the kink: for w = nu + a sin(theta), the averaged equation's root r =
    # (nu - nu_H) / a of the sine coefficient of f''(x) x^2, x = r + sin(theta) (f'(nu_H) = 0 on
    # a pchip extremum); the spring force's peak-to-trough amplitude is 2 a
    f2_left, f2_right = law.at(h.nu * (1 - 1e-9), 2), law.at(h.nu * (1 + 1e-9), 2)
    theta = np.linspace(0.0, 2.0 * math.pi, 200001)[:-1]

    def sine_coefficient(r: float) -> float:
        x = r + np.sin(theta)
        return float(np.mean(np.where(x > 0, f2_right, f2_left) * x * x * np.sin(theta)))

    r = brentq(sine_coefficient, -1.0, 1.0)  # 0.327 (the small-r formula -2 J / (3 pi f'') says 0.84)
    assert (b.nu[0] - h.nu) / (0.5 * b.amplitude[0]) == pytest.approx(r, rel=0.02)
    k = int(np.argmin(np.abs(b.multiplier - 10.0)))  # an orbit SciPy can still shoot
    ref = pure_slip_orbit_reference(
        lambda w: float(law.at(w)),
        lambda w: float(law.at(w, 1)),
        float(b.nu[k]),
        (b.max_force[k], b.period[k]),
    )
    assert ref.amplitude == pytest.approx(b.amplitude[k], rel=1e-7)
    assert ref.period == pytest.approx(b.period[k], rel=1e-8)
    assert ref.multiplier == pytest.approx(b.multiplier[k], rel=1e-5)
    # followed to its end (it was lost at multiplier 3200, where forward shooting multiplied the
    # flow's error by as much): shot backward in time, the unstable orbit grazes where stick-slip
    # ends, the basin boundary of the whole bistable interval
    assert not any("were followed to nu" in n for n in d.notes)
    assert [iv.regime for iv in d.intervals] == ["stick-slip", "bistable", "steady-sliding"]
    assert b.end == "grazing"
    (onset,) = [p for p in d.points if p.kind == "stick-slip-onset"]
    (grazing,) = [p for p in d.points if p.kind == "grazing"]
    # one point computed two ways, each to 1e-9 of nu (the grazing's secant stopped at a minimum
    # velocity of 1e-10 alone, 1.2e-7 from the onset, which is a tangency's slope away: seen with
    # numpy 2.4.6 and scipy 1.17.1); the interval ends at the first of the two
    assert abs(grazing.nu - onset.nu) < 1e-8
    assert d.intervals[1].nu_max == min(onset.nu, grazing.nu)
    assert grazing.amplitude == pytest.approx(onset.amplitude, rel=1e-6)
    assert b.log_multiplier is not None and b.log_multiplier.max() > 5000.0
    assert np.all(np.isinf(b.multiplier[b.log_multiplier > 710.0]))
    # orbits far too unstable for SciPy's forward shooting, against SciPy's backward return map:
    # one of multiplier exp(46), one of exp(5858) (stiff backward: LSODA)
    for log_m, nu, method in ((46.0, None, "DOP853"), (None, 0.003, "LSODA")):
        k = int(np.argmin(np.abs(b.log_multiplier - log_m) if nu is None else np.abs(b.nu - nu)))
        ref, ref_log_m = unstable_orbit_reference(
            lambda w: float(law.at(w)),
            lambda w: float(law.at(w, 1)),
            float(b.nu[k]),
            float(b.max_force[k]) + 1e-3,  # a start off the orbit
            method=method,
        )
        assert ref.amplitude == pytest.approx(b.amplitude[k], rel=1e-7)
        assert ref.period == pytest.approx(b.period[k], rel=1e-7)
        assert ref.w_min == pytest.approx(b.min_velocity[k], rel=1e-7)
        assert ref_log_m == pytest.approx(b.log_multiplier[k], rel=1e-7)


def test_a_map_cell_on_a_supercritical_hopf_point_is_steady_sliding() -> None:
    """A map cell exactly on the cubic law's supercritical Hopf point (nu = 1, alpha = 0.5, on a
    linear grid) is steady sliding, not pure slip without an orbit (its amplitude is 0 there);
    just below it, the small cycle."""
    d = regimes(CUBIC, 0.5, 1.5)
    (h,) = d.hopf
    assert h.criticality == "supercritical" and h.nu == pytest.approx(1.0, abs=1e-12)
    assert d.regime_at(h.nu).regime == "steady-sliding"
    assert d.regime_at(h.nu * (1 - 1e-9)).regime == "pure-slip"
    ds = regime_map(CUBIC, "alpha", [0.5], 0.5, 1.5, n_nu=11, progress=False)
    at_hopf = int(np.argmin(np.abs(ds.nu.values - 1.0)))
    assert ds.nu.values[at_hopf] == pytest.approx(1.0, abs=1e-12)
    assert int(ds.regime.values[0, at_hopf]) == 2  # steady-sliding's code


def test_the_mapped_parameter_need_not_be_given_twice(tmp_path: Path) -> None:
    """`regimes --law cubic --map alpha=0.3..0.7` needs no --alpha: the diagram is drawn at the
    map's first value, and the output says so.
    The map is the same as with --alpha given."""
    args = ["regimes", "--law", "cubic", "--gamma", "0.1666", "--nu-min", "0.5", "--nu-max", "1.5"]
    args += ["--n", "21", "--map", "alpha=0.3..0.7", "--map-n", "3", "--json"]
    res = run(*args)
    assert res.exit_code == 0, res.output
    assert "the diagram is at alpha = 0.3, the map's first value" in res.output
    given = run(*args, "--alpha", "0.3")
    assert given.exit_code == 0, given.output
    assert json.loads(res.stdout) == json.loads(given.stdout)  # the note is on stderr
