"""Every verdict right: attractors counted by their orbits, steady cycles exact near a Hopf point."""

import json
import math
import warnings

import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st
from reference.one_block import cubic_orbit_reference

from stickslip import CubicLaw, DimensionlessParameters, WeakeningLaw, cycle
from stickslip.bifurcation.regimes import confirm, regimes
from stickslip.cli import main
from stickslip.dynamics.sweep import sweep

# --------------------------------------------------------------------------- phantom attractors


@pytest.mark.parametrize(("alpha", "gamma"), [(0.03, 0.5), (0.04, 0.2), (0.05, 1.0)])
def test_one_pure_slip_interval_up_to_the_hopf_point(alpha: float, gamma: float) -> None:
    """One pure-slip orbit is counted once: an engine-found attractor matched to a linearly
    interpolated branch with a fixed tolerance can count it twice ('bistable', ['pure-slip',
    'pure-slip'])."""
    res = CliRunner().invoke(
        main,
        [
            *("regimes", "--law", "cubic", "--alpha", str(alpha), "--gamma", str(gamma)),
            *("--nu-min", "0.01", "--nu-max", "3", "--json", "--check"),
        ],
    )
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    regimes_found = [iv["regime"] for iv in d["intervals"]]
    assert regimes_found == ["stick-slip", "pure-slip", "steady-sliding"]
    assert "bistable" not in regimes_found
    (hopf,) = d["hopf"]
    assert hopf["nu"] == pytest.approx(math.sqrt(alpha / (3 * gamma)), rel=1e-12)
    assert d["intervals"][1]["nu_max"] == pytest.approx(hopf["nu"], rel=1e-12)
    assert d["intervals"][1]["attractors"] == ["pure-slip"]
    assert all(c["agree"] and c["found"] == c["expected"] for c in d["check"])


def _check_law(law, nu_min: float, nu_max: float) -> None:
    d = regimes(law, nu_min, nu_max, n_grid=61)
    checks = confirm(d)
    for c in checks:
        assert c.agree, (law, c)
        assert c.found == c.expected
    # the label says how many distinct attractors there are
    for iv in d.intervals:
        assert (iv.regime == "bistable") == (len(iv.attractors) == 2), iv
        assert (iv.regime == "multistable") == (len(iv.attractors) > 2), iv


@settings(max_examples=30)
@given(
    gamma=st.floats(0.02, 3.0),
    ratio=st.floats(0.02, 1.4),
)
def test_random_cubic_laws_confirmed_by_simulation(gamma: float, ratio: float) -> None:
    """Random cubic laws, including alpha**3 > 27 gamma / 4 where friction turns negative
    (slip reversal coexists with stick-slip there): every interval's distinct attractors are
    those that direct simulations from several starts reach."""
    alpha = ratio * (27.0 * gamma / 4.0) ** (1.0 / 3.0)  # ratio > 1: negative friction somewhere
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        law = CubicLaw(alpha=alpha, gamma=gamma)
    nu_h = math.sqrt(alpha / (3.0 * gamma))
    _check_law(law, nu_h / 10.0, 3.0 * nu_h)


@settings(max_examples=30)
@given(c=st.floats(0.3, 40.0), p_over_c=st.sampled_from([0.0]) | st.floats(0.005, 0.9))
def test_random_weakening_laws_confirmed_by_simulation(c: float, p_over_c: float) -> None:
    """Random weakening laws (F1 with p = 0, F2 with p > 0): subcritical Hopf points, bistability,
    slip reversal at large nu."""
    law = WeakeningLaw(c=c, p=p_over_c * c)
    if p_over_c == 0.0:
        _check_law(law, 0.01, 8.0)
    else:
        nu_h = (math.sqrt(1.0 / p_over_c) - 1.0) / c
        _check_law(law, nu_h / 10.0, 3.0 * nu_h)


def test_coexisting_slip_reversal_is_found_and_located() -> None:
    """With negative cubic friction a slip-reversal orbit coexists with stick-slip: the diagram
    finds it from a push, not only from rest, and locates where it stops coexisting."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        law = CubicLaw(alpha=0.8235369798017035, gamma=0.04601251002566534)
    d = regimes(law, 0.12, 2.5)
    first = d.intervals[0]
    assert first.regime == "bistable"
    assert first.attractors == ("stick-slip", "slip-reversal")
    assert all(c.agree for c in confirm(d))


# --------------------------------------------------------------------------- exact cycles near Hopf

CUBIC = CubicLaw(alpha=0.5, gamma=0.5 / 3)  # supercritical Hopf at nu = 1


def scipy_shooting(nu: float, alpha: float, gamma: float) -> tuple[float, float]:
    """The cubic law's pure-slip orbit by plain SciPy (reference/one_block.py): amplitude, period."""
    ref = cubic_orbit_reference(nu, alpha, gamma)
    return ref.amplitude, ref.period


@pytest.mark.parametrize("fraction", [0.98, 0.995, 0.999])
def test_cycle_near_a_supercritical_hopf_point_is_the_periodic_orbit(fraction: float) -> None:
    """Near the Hopf point the cycle is polished by shooting, within 1e-8: the transient, which
    the Floquet multiplier (0.994 at 0.999 nu_H) still carries, stops 6e-7 off the orbit."""
    nu = fraction * 1.0
    amp, period = scipy_shooting(nu, CUBIC.alpha, CUBIC.gamma)
    r = cycle(DimensionlessParameters(nu=nu, law=CUBIC))
    assert r.regime == "pure-slip" and r.status == "ok"
    assert r.amplitude == pytest.approx(amp, rel=1e-8)
    assert r.period == pytest.approx(period, rel=1e-8)
    # the nontrivial Floquet multiplier: near 1 - 2 pi * 2 |f'(nu)| / 2 ... strictly inside (0, 1)
    assert 0.0 < r.multiplier < 1.0
    assert r.attractors[0].multiplier == r.multiplier
    # against Liouville's exp(-integral of f'(w) dt) over SciPy's orbit
    ref = cubic_orbit_reference(nu, CUBIC.alpha, CUBIC.gamma)
    assert r.multiplier == pytest.approx(ref.multiplier, rel=1e-9)
    # the work integrals are measured on the polished orbit: the energy balance closes
    assert r.drive_work == pytest.approx(r.friction_work, rel=1e-9)
    # the same in a sweep
    ds = sweep(DimensionlessParameters(nu=nu, law=CUBIC), {"nu": [nu]}, progress=False)
    assert float(ds.amplitude[0]) == pytest.approx(amp, rel=1e-8)
    assert float(ds.period[0]) == pytest.approx(period, rel=1e-8)
    assert float(ds.multiplier[0]) == pytest.approx(r.multiplier, rel=1e-9)


def test_multiplier_follows_the_linear_rate_near_the_hopf_point() -> None:
    """Close to a Hopf point the orbit's multiplier is exp(-2 pi |f'(nu)|) to leading order
    (averaging: da/dt = -(f'/2) a - ..., twice the linear rate on the cycle)."""
    nu = 0.999
    fprime = -CUBIC.alpha + 3 * CUBIC.gamma * nu**2
    r = cycle(DimensionlessParameters(nu=nu, law=CUBIC))
    assert r.multiplier == pytest.approx(math.exp(-2 * math.pi * abs(fprime)), rel=2e-3)


def test_too_close_to_the_hopf_point_is_not_converged_not_wrong() -> None:
    """At 1e-6 from the Hopf point the orbit's multiplier is 1 - 6e-6: the transient has not
    settled and the orbit cannot be solved to 1e-8 either. The status says so (exit code 1)."""
    r = cycle(DimensionlessParameters(nu=1.0 - 1e-6, law=CUBIC))
    assert r.status == "not-converged"
    assert math.isnan(r.multiplier)
    assert r.attractors == ()
    res = CliRunner().invoke(
        main, ["cycle", "--law", "cubic", "--alpha", "0.5", "--gamma", str(0.5 / 3), "--nu", "0.999999"]
    )
    assert res.exit_code == 1
    assert "not-converged" in res.output
    ok = CliRunner().invoke(
        main,
        ["cycle", "--law", "cubic", "--alpha", "0.5", "--gamma", str(0.5 / 3), "--nu", "0.999", "--json"],
    )
    assert ok.exit_code == 0, ok.output
    d = json.loads(ok.output)
    assert d["status"] == "ok"
    assert 0.99 < d["multiplier"] < 1.0


def test_three_attractors_are_multistable_not_bistable() -> None:
    """An interval with three attractors (a table law's steady sliding, pure-slip orbit and
    stick-slip) is 'multistable', not 'bistable' (two): each count has its own name, and the
    regime maps code it (6) and colour it."""
    from stickslip.bifurcation.regime_map import REGIME_CODES
    from stickslip.bifurcation.regimes import interval_regime
    from stickslip.core.results import Regime
    from stickslip.plots.regimes import REGIME_COLORS

    ss, ps, st, rev = Regime.STICK_SLIP, Regime.PURE_SLIP, Regime.STEADY_SLIDING, Regime.SLIP_REVERSAL
    assert interval_regime([ss, ps, st]) == Regime.MULTISTABLE
    assert interval_regime([ss, rev, ps, st]) == Regime.MULTISTABLE
    assert interval_regime([ss, st]) == Regime.BISTABLE
    assert interval_regime([rev]) == Regime.SLIP_REVERSAL
    assert interval_regime([st]) == Regime.STEADY_SLIDING
    assert interval_regime([]) == Regime.NONE
    assert interval_regime([ss, Regime.UNKNOWN, st]) == Regime.UNKNOWN
    assert REGIME_CODES["multistable"] == 6 and "multistable" in REGIME_COLORS
    assert REGIME_CODES["slip-reversal"] == 3 and "slip-reversal" in REGIME_COLORS
    assert len(set(REGIME_CODES.values())) == len(REGIME_CODES)


@pytest.mark.slow
def test_the_bifurcation_legend_names_each_kind_once() -> None:
    """A law with two Hopf points has two pure-slip branches: the legend names 'pure-slip' once,
    not once a branch."""
    import matplotlib

    matplotlib.use("Agg")
    from stickslip.bifurcation.regimes import regimes
    from stickslip.laws import ExpressionLaw
    from stickslip.plots.regimes import plot_bifurcation

    d = regimes(ExpressionLaw("1/(1+3.8*w)+2*w*exp(-w/2)+0.05*w"), 1.5, 12.0)
    assert sum(b.kind == "pure-slip" for b in d.branches) >= 2
    fig = plot_bifurcation(d)
    ax = fig.axes[0]
    assert ax.get_legend() is None and len(fig.legends) == 1  # under the axes, not beside them
    legend = fig.legends[0]
    labels = [t.get_text() for t in legend.get_texts()]
    assert len(labels) == len(set(labels)), labels
    assert "pure-slip" in labels and "regime: pure-slip" in labels
    # a branch's entry is solid and the styles are said once: an entry in the style of its
    # first piece would show steady sliding dashed where it is stable
    styles = dict(zip(labels, (h.get_linestyle() for h in legend.legend_handles), strict=True))
    assert styles["steady-sliding"] == "-" and styles["pure-slip"] == "-"
    assert styles["stable"] == "-" and styles["unstable"] == "--"
    assert {ln.get_linestyle() for ln in ax.lines} >= {"-", "--"}  # the lines themselves unchanged
    # two bistable intervals with different attractors: told apart (one 0.07 % of the axis wide)
    assert "regime: bistable (stick-slip + pure-slip)" in labels
    assert "regime: bistable (stick-slip + steady-sliding)" in labels
    # a physical set-up's driving velocity on the top axis
    top = plot_bifurcation(d, beta=42.0).axes[0].child_axes
    assert len(top) == 1 and top[0].get_xlabel() == "driving velocity $v_0$ [mm/s]"


@pytest.mark.slow
def test_a_stable_orbit_that_a_tables_noise_keeps_from_1e10_is_still_an_attractor() -> None:
    """The weakening law sampled as a 41-row pchip table: its small stable pure-slip orbits
    (multiplier 0.97 to 0.998) cannot be shot to 1e-10 (the flow is good to 1e-10 to 1e-8
    across the rows, and 1 / (1 - multiplier) multiplies that). Shot again at the noise floor,
    they are kept as attractors: `cycle` finds two attractors at nu = 0.674 and one ulp either
    side, and `regimes` finds them below the Hopf point (with `--check`). Their multipliers
    agree with plain SciPy shooting (0.971187 at nu = 0.674)."""
    import numpy as np
    from reference.one_block import pure_slip_orbit_reference

    from stickslip import TabulatedLaw
    from stickslip.units import Q_

    v = np.r_[0.0, np.geomspace(10.0, 2e5, 40)]
    w = 42.0 * v * 1e-6
    table = TabulatedLaw(Q_(v, "um/s"), 0.46 * (1.0 / (1.0 + 3.8 * w) + 0.5 * w))
    law = table.nondimensionalize("60 s/m")
    for nu in (0.674, float(np.nextafter(0.674, 0.0)), float(np.nextafter(0.674, 1.0))):
        r = cycle(DimensionlessParameters(nu, law))
        assert [a.regime.value for a in r.attractors] == ["stick-slip", "pure-slip"], nu
        orbit = r.attractors[1]
        guess = (float(law.at(nu)) + 0.5 * orbit.amplitude, orbit.period)  # (s at w = nu, T)
        ref = pure_slip_orbit_reference(lambda x: float(law.at(x)), lambda x: float(law.at(x, 1)), nu, guess)
        assert orbit.multiplier == pytest.approx(ref.multiplier, abs=1e-5)
        assert orbit.multiplier == pytest.approx(0.971187, abs=1e-5)
        assert orbit.amplitude == pytest.approx(ref.amplitude, rel=1e-6)
    # at beta 30 the small orbit lives between the fold and the Hopf point (on a row)
    law = table.nondimensionalize("30 s/m")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the Hopf point on a row
        d = regimes(law, 0.1, 1.5, n_grid=101)
    (h,) = d.hopf
    below = d.regime_at(h.nu * (1.0 - 1e-4))
    assert below.regime.value == "bistable" and below.nu_max == h.nu
    assert {a.value for a in below.attractors} == {"stick-slip", "pure-slip"}
    assert all(c.agree for c in confirm(d))


@pytest.mark.slow
def test_an_orbit_kept_at_a_tables_noise_floor_says_how_well_it_is_known() -> None:
    """An orbit shot again at the noise floor (the test above) is known to a few 1e-8..1e-5 only,
    not to every digit: `cycle` warns, with the estimate, and the SciPy reference's amplitude
    lies within three times it. An orbit pinned to 1e-8 (nu = 0.674, multiplier 0.97) says
    nothing."""
    import re

    import numpy as np
    from reference.one_block import pure_slip_orbit_reference

    from stickslip import TabulatedLaw
    from stickslip.orbits.attractors import NoisyOrbitWarning
    from stickslip.units import Q_

    v = np.r_[0.0, np.geomspace(10.0, 2e5, 40)]
    w = 42.0 * v * 1e-6
    law = TabulatedLaw(Q_(v, "um/s"), 0.46 * (1.0 / (1.0 + 3.8 * w) + 0.5 * w)).nondimensionalize("60 s/m")
    for nu, noisy in ((0.674, False), (0.73, True), (0.732, True)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            r = cycle(DimensionlessParameters(nu, law))
        said = [str(c.message) for c in caught if issubclass(c.category, NoisyOrbitWarning)]
        assert bool(said) == noisy, (nu, said)
        orbit = r.attractors[1]
        assert orbit.regime.value == "pure-slip" and orbit.status.value == "ok"
        if not noisy:
            continue
        (message,) = said
        pattern = r"known to about ([0-9.e+-]+) of its amplitude and period only, not to 1e-08"
        found = re.search(pattern, message)
        assert found is not None, message
        guess = (float(law.at(nu)) + 0.5 * orbit.amplitude, orbit.period)
        ref = pure_slip_orbit_reference(lambda x: float(law.at(x)), lambda x: float(law.at(x, 1)), nu, guess)
        error = abs(orbit.amplitude / ref.amplitude - 1.0)
        assert 1e-8 < float(found.group(1)) and error <= 3.0 * float(found.group(1)), (nu, error, message)


def test_f1_at_large_nu_is_slip_reversal_never_pure_slip_anywhere() -> None:
    """F1 (p = 0) never slides steadily (f' < 0 everywhere); its oscillation that never sticks,
    at large nu, slips backward: slip reversal, not the paper's pure slip, in the engine's
    result, a sweep, a regime map (interval and observed), the map's flags, and the explorer."""
    import numpy as np

    from stickslip.bifurcation.regime_map import regime_map
    from stickslip.core.results import Regime
    from stickslip.dynamics.sweep import sweep
    from stickslip.explore.session import REGIMES, regime_diagram

    law = WeakeningLaw(c=3.8, p=0.0)
    res = cycle(DimensionlessParameters(nu=6.0, law=law), probe=False)
    assert str(res.regime) == "slip-reversal" and res.backward_slips > 0 and res.stick_fraction == 0
    ds = sweep(DimensionlessParameters(nu=1.0, law=law), {"nu": np.geomspace(0.1, 10.0, 12)}, progress=False)
    labels = ds.regime.values.astype(str)
    assert "pure-slip" not in labels and "slip-reversal" in labels
    assert np.all(
        (labels == "slip-reversal") == (ds.backward_slips.values > 0) & (ds.stick_fraction.values == 0)
    )
    m = regime_map(law, "c", [1.0, 3.8], 0.5, 10.0, n_nu=9, progress=False)
    for var in ("regime", "observed"):
        codes = m[var].values
        assert not np.any(codes == Regime.PURE_SLIP.code), var
        assert np.any(codes == Regime.SLIP_REVERSAL.code), var
    assert "slip-reversal" in m.regime.attrs["flag_meanings"].split()
    _, _, codes = regime_diagram(law, "c", 1.0, 3.8)
    shown = {REGIMES[c] for c in codes.ravel()}
    assert "pure-slip" not in shown and "slip-reversal" in shown
