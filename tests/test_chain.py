"""Chains of blocks: the exact event-driven engine against references, not against itself."""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from reference.chain import reference_chain

import stickslip as ss
from stickslip import Q_
from stickslip.chains import (
    BValue,
    ChainParameters,
    ChainResult,
    b_value,
    block_length,
    chain,
    chain_ensemble,
    completeness_magnitude,
    magnitude_frequency,
    open_catalog,
    recurrence_times,
    static_thresholds,
)
from stickslip.chains.lyapunov import event_map, lyapunov_exponent
from stickslip.chains.statistics import KS_CRITICAL_10, power_law_range, slope_change
from stickslip.io.errors import DataError
from stickslip.laws import CarlsonLangerLaw, CubicLaw, TabulatedLaw, WeakeningLaw

TIGHT = {"rtol": 1e-11, "atol": 1e-13}


def _one_block_period(law: ss.DimensionlessLaw, nu: float) -> float:
    r = ss.cycle(ss.DimensionlessParameters(nu, law), probe=False, **TIGHT)
    assert r.regime == "stick-slip"
    return float(r.period)


@pytest.mark.parametrize(
    ("law", "nu"),
    [
        pytest.param(WeakeningLaw(c=3.8), 0.5, id="F1"),
        pytest.param(WeakeningLaw(c=3.8, p=0.5), 0.2, id="F2"),
        # a third compiled chain engine (42 s of CI's 2 cores, cold): in the slow set
        pytest.param(CubicLaw(alpha=1.2, gamma=0.3), 0.1, id="cubic", marks=pytest.mark.slow),
    ],
)
def test_one_block_chain_is_the_one_block_model(law: ss.DimensionlessLaw, nu: float) -> None:
    period = _one_block_period(law, nu)
    r = chain(ChainParameters(1, law, nu, ell=3.0), 12, init="uniform", progress=False, **TIGHT)
    t0 = r.catalog["t_start"].values
    rec = np.diff(t0)[-5:]
    np.testing.assert_allclose(rec, period, rtol=1e-9, atol=0)
    np.testing.assert_allclose(r.catalog["moment"].values[-5:], nu * period, rtol=1e-9)
    assert r.summary()["largest_event_blocks"] == 1


@pytest.mark.parametrize("boundary", ["free"])
def test_identical_blocks_move_as_one(boundary: str) -> None:
    law = WeakeningLaw(c=3.8)
    nu = 0.5
    period = _one_block_period(law, nu)
    r = chain(
        ChainParameters(7, law, nu, ell=2.0, boundary=boundary), 8, init="uniform", progress=False, **TIGHT
    )
    assert (r.catalog["n_blocks"].values == 7).all()
    np.testing.assert_allclose(np.diff(r.catalog["t_start"].values)[-4:], period, rtol=1e-9, atol=0)
    np.testing.assert_allclose(r.catalog["moment"].values[-4:], 7 * nu * period, rtol=1e-9)


@pytest.mark.parametrize(
    ("law", "backslip"),
    [
        pytest.param(WeakeningLaw(c=3.8, p=0.2), True, id="weakening"),
        # 35 s of CI's two cores: in the slow set
        pytest.param(
            CarlsonLangerLaw(alpha=2.5, sigma=0.05), None, id="carlson-langer", marks=pytest.mark.slow
        ),
    ],
)
def test_energy_balance_per_event(law: ss.DimensionlessLaw, backslip: bool | None) -> None:
    p = ChainParameters(6, law, 0.05, ell=1.4, backslip=backslip)
    r = chain(p, 40, seed=3, amplitude=0.5, progress=False)
    c = r.catalog
    wd, wf, de = c["driver_work"].values, c["friction_work"].values, c["elastic_change"].values
    assert np.all(wf > 0.0)
    scale = np.maximum(np.abs(wd), 1.0)
    assert np.max(np.abs(wd - wf - de) / scale) < 1e-8


def _compare(
    n: int, law: WeakeningLaw, nu: float, ell: float, x0: np.ndarray, events: int, **kw: bool
) -> None:
    c, p = law.params["c"], law.params["p"]

    def f(w: float) -> float:
        return 1.0 / (1.0 + c * w) + p * w

    ref = reference_chain(f, x0, nu, ell * ell, events, periodic=kw.get("periodic", False))
    params = ChainParameters(n, law, nu, ell, boundary="periodic" if kw.get("periodic") else "free")
    state = ss.core.api.ChainState.at_rest(x0)
    r = chain(params, events, state=state, progress=False, **TIGHT)
    cat = r.catalog
    assert r.events == len(ref) == events
    np.testing.assert_allclose(cat["t_start"].values, [e["t_start"] for e in ref], rtol=0, atol=1e-7)
    np.testing.assert_allclose(cat["t_end"].values, [e["t_end"] for e in ref], rtol=0, atol=1e-7)
    np.testing.assert_allclose(cat["moment"].values, [e["moment"] for e in ref], rtol=0, atol=1e-7)
    np.testing.assert_array_equal(cat["n_blocks"].values, [e["n_blocks"] for e in ref])
    # the epicentre is defined where one block breaks first (synchronised blocks break together)
    single = cat["n_blocks"].values == 1
    assert single.sum() >= 4
    np.testing.assert_array_equal(
        cat["epicentre"].values[single], np.array([e["epicentre"] for e in ref])[single]
    )
    slips = cat["slip"].values[:events]
    np.testing.assert_allclose(slips, np.array([e["slips"] for e in ref]), rtol=0, atol=1e-7)


def test_two_blocks_against_the_scipy_reference() -> None:
    _compare(2, WeakeningLaw(c=3.8), 0.01, 1.0, np.array([0.0, 0.3]), 50)


def test_three_blocks_against_the_scipy_reference() -> None:
    _compare(3, WeakeningLaw(c=0.1), 0.01, 1.0, np.array([0.0, 0.3, 0.1]), 50)


def test_three_periodic_blocks_against_the_scipy_reference() -> None:
    _compare(3, WeakeningLaw(c=0.1), 0.01, 1.0, np.array([0.0, 0.3, 0.1]), 30, periodic=True)


def test_a_chain_that_never_sticks_again_stops_with_a_status() -> None:
    """Three blocks that end up sliding (no event ends): the run stops, says why, keeps its events."""
    p = ChainParameters(3, WeakeningLaw(c=1.0, p=0.3), 0.05, 0.8)
    r = chain(
        p,
        50,
        state=ss.core.api.ChainState.at_rest(np.array([0.1, 0.45, -0.2])),
        progress=False,
        max_event_duration=2000.0,
    )
    assert r.status == "sliding" and 0 < r.events < 50


@pytest.mark.parametrize("longest", [100.0, 1000.0])
def test_a_sliding_chain_is_told_when_its_event_passes_max_event_duration(longest: float) -> None:
    """Three blocks at c = 0.3 slide for ever from t = 127.6: the engine pauses at the step that
    passes max_event_duration, so the run says so just after it (decided between two engine
    calls of 2e6 units of work, it would say so only at t = 29 182 with a bound of 100)."""
    p = ChainParameters(3, WeakeningLaw(c=0.3), 0.01, 1.0)
    start = ss.core.api.ChainState.at_rest(np.array([0.0, 0.3, 0.1]))
    r = chain(p, 50, state=start, progress=False, max_event_duration=longest)
    assert r.status == "sliding" and r.events == 12
    last = float(r.catalog.t_start.values[-1])  # 122.72; the sliding event starts at 127.6
    assert last + longest < r.simulated_time < last + longest + 6.0


def test_krakow_three_blocks_lateral_synchrony_and_chaos() -> None:
    """Szkutnik, Kawecka-Magiera, Kułakowski (arXiv nlin/0310030): periodic with the outer blocks in
    step below a critical weakening, chaotic above (largest Lyapunov exponent of the event map)."""
    u0 = [0.0, 0.3, 0.1]
    weak = lyapunov_exponent(
        ChainParameters(3, WeakeningLaw(c=0.1), 0.01, 1.0), u0, events=150, transient=150
    )
    strong = lyapunov_exponent(
        ChainParameters(3, WeakeningLaw(c=2.0), 0.01, 1.0), u0, events=150, transient=150
    )
    assert weak.exponent < -3 * weak.error and weak.exponent < 0.0
    assert weak.lateral_gap < 1e-9
    assert strong.exponent > 3 * strong.error and strong.exponent > 0.1


def test_event_map_is_shift_invariant() -> None:
    p = ChainParameters(3, WeakeningLaw(c=1.0), 0.05, 1.0)
    u = np.array([0.0, 0.3, 0.1])
    a = event_map(p, u)
    # all positions shifted back: the same event, sooner (shifted forward by 0.25, the middle
    # block's force, -0.8, would pass its backward threshold -1 and slip back at once)
    b = event_map(p, u - 0.25)
    np.testing.assert_allclose(a, b, atol=1e-9)


def test_twins_breaking_away_a_moment_apart_do_not_stall_the_engine() -> None:
    """Blocks 0 and 2 of three, at their threshold 4e-16 apart (a companion orbit of the Krakow
    chain, c = 0.05, rtol 1e-11): block 0's first step is cut to 6.7e-14 by block 2's
    breakaway, and its speed, pushed forward but within the rounding of its increments, can
    come out -7e-30 (a stop at once, a breakaway again at the same time, 10000 times over,
    until 'stopped making progress'). The event is that of the twins started exactly
    together, to the last digits."""
    p = ChainParameters(3, WeakeningLaw(c=0.05), 0.01, 1.0)
    u = np.array([-0.9939844744254636, -0.9939844607191958, -0.9939844744254632])
    got = event_map(p, u, rtol=1e-11, atol=1e-13)
    twins = event_map(p, np.array([u[0], u[1], u[0]]), rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(got, twins, rtol=0.0, atol=1e-13)
    assert abs(got[0] - got[2]) < 1e-13 and np.all(got > u)  # the event moved every block on


@pytest.mark.fast
def test_b_value_of_a_gutenberg_richter_sample() -> None:
    rng = np.random.default_rng(1)
    b_true = 1.0
    m = 2.0 + rng.exponential(1.0 / (b_true * math.log(10)), 20000)
    fit = b_value(m, mc=2.0, n_boot=100)
    assert abs(fit.b - b_true) < 3 * fit.error
    assert fit.error == pytest.approx(fit.shi_bolt, rel=0.3)
    # a sample truncated at 3: the untruncated estimate is biased, the truncated one is not
    mt = m[m <= 3.0]
    assert abs(b_value(mt, mc=2.0, m_max=3.0, n_boot=50).b - b_true) < 0.05


def test_b_value_and_its_errors_at_b_other_than_one() -> None:
    """At b = 1 a b-power in an error formula is invisible: b = 1.5 against Aki's estimate
    log10(e)/(mean - Mc) and Shi and Bolt's error ln(10) b^2 sigma/sqrt(n) (their 2.30), computed here; the
    truncated estimate against the root of the truncated exponential's mean, by Brent."""
    from scipy.optimize import brentq

    rng = np.random.default_rng(3)
    b_true, n = 1.5, 20000
    m = 2.0 + rng.exponential(1.0 / (b_true * math.log(10)), n)
    fit = b_value(m, mc=2.0, n_boot=200)
    aki = math.log10(math.e) / (m.mean() - 2.0)
    assert fit.b == pytest.approx(aki, rel=1e-12)
    assert fit.shi_bolt == pytest.approx(math.log(10) * aki**2 * m.std(ddof=1) / math.sqrt(n), rel=1e-12)
    assert abs(fit.b - b_true) < 3 * fit.shi_bolt
    assert fit.error == pytest.approx(fit.shi_bolt, rel=0.2)  # the bootstrap agrees with the formula
    mt = m[m <= 2.5]
    width, mean = 0.5, mt.mean() - 2.0

    def excess(beta: float) -> float:  # the truncated exponential's mean above Mc, minus the data's
        return 1.0 / beta - width / math.expm1(beta * width) - mean

    beta = brentq(excess, 1e-6, 100.0, xtol=1e-15)
    truncated = b_value(mt, mc=2.0, m_max=2.5, n_boot=0)
    assert truncated.b == pytest.approx(beta / math.log(10), rel=1e-10)
    assert math.isnan(truncated.shi_bolt)  # the formula is for the untruncated exponential
    assert b_value(mt, mc=2.0, n_boot=0).b > 1.2


def test_block_length_of_known_series() -> None:
    """Politis-White: independent values need no blocks; an AR(1) series with phi = 0.5 has the
    optimal length (2 G^2 / D)^(1/3) n^(1/3) = (8/3)^(1/3) n^(1/3) of the circular block bootstrap."""
    rng = np.random.default_rng(2)
    n = 20000
    assert block_length(rng.exponential(1.0, n)) <= 3
    e = rng.normal(size=n)
    y = np.empty(n)
    y[0] = e[0]
    for i in range(1, n):
        y[i] = 0.5 * y[i - 1] + e[i]
    assert block_length(y) == pytest.approx((8.0 / 3.0) ** (1 / 3) * n ** (1 / 3), rel=0.3)
    assert block_length(np.ones(100)) == 1 and block_length([1.0, 2.0]) == 1


@pytest.mark.slow
def test_block_bootstrap_error_meets_the_spread_of_correlated_catalogues() -> None:
    """Events that come in runs (each magnitude five times, as if an event set up the next four):
    over 60 such catalogues the b-values spread about sqrt(5) times what the event-by-event
    bootstrap says; the block bootstrap's error meets the spread."""
    rng = np.random.default_rng(3)
    bs, plain, blocked, lengths = [], [], [], []
    for i in range(60):
        m = 1.0 + np.repeat(rng.exponential(1.0 / math.log(10), 600), 5)
        f = b_value(m, mc=1.0, n_boot=100, block="auto", seed=i)
        bs.append(f.b)
        blocked.append(f.error)
        lengths.append(f.block)
        plain.append(b_value(m, mc=1.0, n_boot=100, seed=i).error)
    spread = float(np.std(bs, ddof=1))
    assert float(np.mean(plain)) < 0.6 * spread  # iid resampling understates it
    assert float(np.mean(blocked)) == pytest.approx(spread, rel=0.3)
    assert min(lengths) >= 5
    # a block as long as the catalogue would resample rotations of it, all with its mean (error 0):
    # a given block is held to min(3 sqrt(n), n / 3)
    whole = b_value(m, mc=1.0, n_boot=100, block=10**6)
    assert whole.block == math.ceil(3 * math.sqrt(whole.n)) and whole.error > 0.3 * spread
    with pytest.raises(ValueError, match="block"):
        b_value(m, mc=1.0, block=0)
    with pytest.raises(ValueError, match="block"):
        b_value(m, mc=1.0, block="best")


def test_expected_cumulative_of_a_truncated_fit_meets_the_catalogue() -> None:
    rng = np.random.default_rng(4)
    m = _spike_plateau_power_law_bump(rng, 40000)
    fit = b_value(m, mc=-2.0, m_max=0.5, n_boot=0)
    above = int(np.sum(m > 0.5))
    ends = fit.expected_cumulative([-2.0, 0.5], above)
    # at the range's ends: every event from mc up, and those above m_max only
    assert ends[0] == pytest.approx(np.sum(m >= -2.0), rel=1e-12)
    assert ends[1] == pytest.approx(above, rel=1e-12)
    # inside: the catalogue's own N(>= M) within its Poisson noise (the sample is b = 1 there)
    for mm in (-1.5, -1.0, -0.5, 0.0):
        n_obs = np.sum(m >= mm)
        assert abs(fit.expected_cumulative(mm, above) - n_obs) < 4 * math.sqrt(n_obs - above)
    # without an upper end: the Gutenberg-Richter line 10**(a - b M) itself
    free = b_value(m[m <= 0.5], mc=-2.0, n_boot=0)
    np.testing.assert_allclose(
        free.expected_cumulative([-1.0, 0.0]), 10.0 ** (free.a - free.b * np.array([-1.0, 0.0]))
    )


def test_completeness_by_maximum_curvature() -> None:
    rng = np.random.default_rng(2)
    m = 1.0 + rng.exponential(1.0 / math.log(10), 50000)
    # detection falls off below 1: keep a fraction
    small = rng.uniform(0.0, 1.0, 20000)
    m = np.concatenate([m, small[rng.uniform(size=small.size) < small]])
    assert completeness_magnitude(m) == pytest.approx(1.0, abs=0.11)


def _spike_plateau_power_law_bump(rng: np.random.Generator, n: int) -> npt.NDArray[np.float64]:
    """A chain-like catalogue: one-block spike, flat plateau, b = 1 from M = -2 to 0.5, a bump at 3.3."""
    spike = np.full(n // 10, -3.9)
    plateau = rng.uniform(-3.5, -2.0, n // 2)
    gr = -2.0 + rng.exponential(1.0 / math.log(10), n // 4)
    bump = rng.normal(3.3, 0.3, n // 8)
    return np.concatenate([spike, plateau, gr[gr < 0.5], bump])


def test_power_law_range_between_the_spike_and_the_bump() -> None:
    rng = np.random.default_rng(3)
    m = _spike_plateau_power_law_bump(rng, 40000)
    auto = b_value(m, mc="auto", n_boot=50)
    assert auto.method == "power-law range" and auto.power_law
    assert -2.15 <= auto.mc <= -1.85 and 0.4 <= auto.m_max <= 3.0
    assert abs(auto.b - 1.0) < max(3 * auto.error, 0.03)
    # the textbook default, from the fullest bin up, is a wrong verdict here, and says so
    maxc = b_value(m, n_boot=0)
    assert maxc.b < 0.4 and not maxc.power_law
    # a plain Gutenberg-Richter sample: its completeness and no upper end (a range that is a
    # power law fails a 10 % test once in ten: the scan may start a bin or two higher)
    g = 2.0 + rng.exponential(1.0 / math.log(10), 20000)
    thin = rng.uniform(0.0, 2.0, 20000)
    g = np.concatenate([g, thin[rng.uniform(size=thin.size) < thin / 2.0]])
    fit = b_value(g, mc="auto", n_boot=50)
    assert 1.99 <= fit.mc <= 2.31 and fit.m_max == math.inf and fit.power_law
    assert abs(fit.b - 1.0) < 3 * fit.error
    # with the upper end given, only the lower one is scanned
    assert b_value(m, mc="auto", m_max=0.5, n_boot=0).m_max == 0.5
    # two spikes are no power law over any range a magnitude unit wide: the best, marked so
    spikes = np.repeat([0.0, 1.5], 500)
    assert not b_value(spikes, mc="auto", n_boot=0).power_law
    with pytest.raises(ValueError, match="mc='best'"):
        b_value(m, mc="best")


def _truncated_gr(rng: np.random.Generator, n: int, b: float, lo: float, hi: float) -> np.ndarray:
    beta = b * math.log(10.0)
    return lo - np.log1p(rng.uniform(size=n) * math.expm1(-beta * (hi - lo))) / beta


def test_slope_change_holds_its_level_and_sees_a_knee() -> None:
    """One slope against two: 1 % of true power laws rejected, down to a few events in a half."""
    rng = np.random.default_rng(7)
    for n, hi in ((40, 3.0), (400, 2.0)):  # about 1 and 40 events above the cut
        p = np.array([slope_change(_truncated_gr(rng, n, 1.0, 0.0, hi), 0.0, hi)[3] for _ in range(1500)])
        assert np.isfinite(p).all()
        # 1500 draws: the rate's own spread is 0.26 % at 1 %, 0.56 % at 5 %
        assert 0.002 <= np.mean(p < 0.01) <= 0.025 and 0.025 <= np.mean(p < 0.05) <= 0.08
    # b = 1 from M = -2, flattening to b = 0.4 above 0 (1 % of the events): KS alone takes a
    # range whose halves differ (here [-2.0, 2.4]: b 1.02 below M = 0.2, 0.42 above, p 2e-8);
    # the default range passes both tests (here [-1.9, 1.4], b 1.013)
    rng = np.random.default_rng(0)
    x = -2.0 + rng.exponential(1.0 / math.log(10), 10000)
    tail = x > 0.0
    x[tail] = rng.exponential(1.0 / (0.4 * math.log(10)), int(tail.sum()))
    x = x[x < 3.0]
    lo, hi, ks = power_law_range(x, slope_level=0.0)
    ks_only = b_value(x, mc=lo, m_max=None if math.isinf(hi) else hi, n_boot=0)
    assert ks <= KS_CRITICAL_10 and hi > 2.0 and not ks_only.power_law
    assert ks_only.slope_p < 1e-3 and ks_only.b_upper < 0.7 < 0.95 < ks_only.b_lower
    assert "the slope changes across the range" in ks_only.verdict
    auto = b_value(x, mc="auto", n_boot=0)
    assert auto.power_law and auto.verdict == "" and auto.m_max < 2.5 and abs(auto.b - 1.0) < 0.03
    # its change of slope is sought at every cut (the largest ratio of two slopes to one; without a
    # bootstrap, its p bounded by Bonferroni's, the cuts tried times chi-square's p)
    assert auto.slope_p >= 0.1 and auto.m_split < auto.m_max and auto.n_upper >= 10
    # events of a half all at its lower end: no slope to compare, no overflow on a steep sample
    assert math.isnan(slope_change([0.0, 0.3, 0.5, 0.5, 0.5], 0.0, 1.0)[3])
    assert slope_change([0.0, 0.1, 0.2, 1.0 + 1e-5, 1.0 + 2e-5], 0.0, 2.0)[3] < 0.01
    steep = b_value([1e-4, 2e-4, 3e-4], mc=0.0, m_max=2.0, n_boot=0, bin_width=1e-5)
    assert steep.b == pytest.approx(math.log10(math.e) / 2e-4, rel=1e-6)
    with pytest.raises(ValueError, match="slope_level"):
        power_law_range(x, slope_level=1.0)
    # the verdict of a fit without a b-value, and of an empty half
    assert "no b-value" in b_value(np.full(5, 1.0), mc=0.0, n_boot=0).verdict
    flat = b_value(np.random.default_rng(1).uniform(0.0, 1.5, 300), mc=0.0, m_max=4.0, n_boot=0)
    assert flat.m_split == 1.4 and flat.slope_p < 0.01 and "Kolmogorov" in flat.verdict
    empty_top = BValue(1.0, 0.1, 0.1, 0.0, 4.0, 300, 2.5, 0.5, b_lower=1.0, m_split=2.0, slope_p=1e-3)
    assert empty_top.verdict.endswith("b = 1 below M = 2.00, none (no events) above (p = 0.001)")


@pytest.mark.slow
def test_catalogue_streams_to_netcdf_and_resumes(tmp_path: Path) -> None:
    p = ChainParameters(20, CarlsonLangerLaw(alpha=2.5, sigma=0.01), 0.01, 3.0)
    whole = chain(p, 120, out=tmp_path / "whole.nc", progress=False)
    part = chain(p, 50, out=tmp_path / "part.nc", progress=False)
    assert part.events == 50
    part.catalog.close()  # an open file cannot be appended to (HDF5 locks it)
    more = chain(p, 120, out=tmp_path / "part.nc", resume=True, progress=False)
    a = open_catalog(tmp_path / "whole.nc")
    b = open_catalog(tmp_path / "part.nc")
    assert more.events == 120 == a.sizes["event"] == b.sizes["event"]
    for name in ("t_start", "t_end", "epicentre", "n_blocks", "moment", "peak_velocity"):
        np.testing.assert_array_equal(a[name].values, b[name].values)
    np.testing.assert_allclose(a["driver_work"].values, b["driver_work"].values, rtol=1e-12)
    assert whole.summary() == more.summary()
    # another set-up: a clear error, the file untouched
    a.close()
    b.close()
    more.catalog.close()
    other = ChainParameters(20, CarlsonLangerLaw(alpha=2.0, sigma=0.01), 0.01, 3.0)
    # the values too (it said '(law_params differ)', naming neither alpha nor its values)
    with pytest.raises(ValueError, match=r"another set-up \(alpha 2.5 in the file, 2 now\)"):
        chain(other, 130, out=tmp_path / "part.nc", resume=True, progress=False)
    with pytest.raises(
        ValueError, match=r"another set-up \(ell 3 in the file, 4 now; nu 0.01 in the file, 0.02"
    ):
        chain(
            ChainParameters(20, p.law, 0.02, 4.0), 130, out=tmp_path / "part.nc", resume=True, progress=False
        )
    reopened = open_catalog(tmp_path / "part.nc")
    assert reopened.sizes["event"] == 120 and reopened.attrs["complete"] == 1
    reopened.close()
    # a resumed run that stops early must not keep the earlier run's mark of completion
    import netCDF4

    from stickslip.chains.catalog import CatalogWriter

    with netCDF4.Dataset(tmp_path / "part.nc") as ds:
        setup = ds.getncattr("setup")
    CatalogWriter(str(tmp_path / "part.nc"), 20, {"setup": setup}, {}, resume=True).close(complete=False)
    with netCDF4.Dataset(tmp_path / "part.nc") as ds:
        assert ds.getncattr("complete") == 0


@pytest.mark.slow
def test_a_run_stopped_before_its_first_save_begins_again(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A run stopped in the seconds between creating its catalogue and first saving the state
    (a transient, FLUSH_SECONDS) leaves a catalogue that says it holds no state, and resuming
    starts the run from the beginning: netCDF's fill values read as a state would run from
    x = 9.97e36 and store the member as 'not-finite' for good (a kill -9 there leaves an
    unreadable 48-byte file, treated alike)."""
    import netCDF4

    import stickslip.chains.run as run_module
    from stickslip.chains.catalog import CatalogWriter, read_state

    p = ChainParameters(20, CarlsonLangerLaw(alpha=2.5, sigma=0.01), 0.01, 3.0)
    whole = chain(p, 60, transient=10, out=tmp_path / "whole.nc", progress=False)
    created = CatalogWriter.__init__

    def stopped(self: Any, *args: Any, **kw: Any) -> None:
        created(self, *args, **kw)
        self.ds.close()  # as the end of the process would (HDF5 locks an open file)
        raise KeyboardInterrupt

    monkeypatch.setattr(CatalogWriter, "__init__", stopped)
    with pytest.raises(KeyboardInterrupt):
        chain(p, 60, transient=10, out=tmp_path / "part.nc", progress=False)
    monkeypatch.undo()
    assert read_state(str(tmp_path / "part.nc"))[:2] == (None, 0)
    again = chain(p, 60, transient=10, out=tmp_path / "part.nc", resume=True, progress=False)
    assert str(again.status) == "ok" and again.summary() == whole.summary()
    again.catalog.close()
    whole.catalog.close()
    # a Ctrl-C in the middle: the rows so far and the state after them, and not marked complete
    calls = [0]
    advance = run_module.chain_advance

    def interrupted(*args: Any, **kw: Any) -> Any:
        calls[0] += 1
        if calls[0] == 4:
            raise KeyboardInterrupt
        return advance(*args, **kw)

    monkeypatch.setattr(run_module, "EVENTS_PER_CHUNK", 10)
    monkeypatch.setattr(run_module, "FLUSH_SECONDS", 0.0)
    monkeypatch.setattr(run_module, "chain_advance", interrupted)
    with pytest.raises(KeyboardInterrupt):
        chain(p, 60, transient=10, out=tmp_path / "cut.nc", progress=False)
    monkeypatch.undo()
    with netCDF4.Dataset(tmp_path / "cut.nc") as ds:
        assert ds.getncattr("complete") == 0 and 0 < len(ds.dimensions["event"]) < 60
    again = chain(p, 60, transient=10, out=tmp_path / "cut.nc", resume=True, progress=False)
    assert again.summary() == whole.summary()
    again.catalog.close()
    # events without a state after them (HDF5 wrote the first rows, not the first state):
    # computed again from the beginning, not continued from fill values
    with netCDF4.Dataset(tmp_path / "cut.nc", "a") as ds:
        ds.setncattr("state_saved", 0)
    assert read_state(str(tmp_path / "cut.nc"))[:2] == (None, 0)
    again = chain(p, 60, transient=10, out=tmp_path / "cut.nc", resume=True, progress=False)
    assert again.summary() == whole.summary()
    again.catalog.close()


@pytest.mark.parametrize("events", [pytest.param(60, marks=pytest.mark.slow), 40])
def test_rows_written_without_the_state_after_them_are_computed_again(tmp_path: Path, events: int) -> None:
    """HDF5 may write appended rows before the state after them (a kill or a full disk during a
    flush): a catalogue of 45 rows with the state after 30. The state names the rows it
    follows, so a resumed run writes over the others (the same events) instead of continuing
    after the 45th row with events 30..44 twice, and open_catalog leaves out rows no state
    follows."""
    import netCDF4

    from stickslip.chains.catalog import COLUMNS, CatalogWriter, read_state
    from stickslip.core import chain as ce

    p = ChainParameters(12, CarlsonLangerLaw(alpha=2.5, sigma=0.01), 0.01, 3.0)
    whole = chain(p, 60, out=tmp_path / "whole.nc", record_slip=40, progress=False)
    ref = whole.catalog.load()
    whole.catalog.close()
    path = tmp_path / "cut.nc"
    part = chain(p, 30, out=path, record_slip=40, progress=False)
    part.catalog.close()
    with netCDF4.Dataset(path) as ds:
        setup = ds.getncattr("setup")
    # the next flush's rows (and slips) reach the file; the process dies before the state
    w = CatalogWriter(str(path), 12, {"setup": setup}, {}, resume=True)
    rows = np.zeros((15, ce.NCAT))
    for name, (col, _, _, _) in COLUMNS.items():
        rows[:, col] = ref[name].values[30:45]
    w.append(rows, ref["slip"].values[30:40])
    w.ds.sync()
    w.ds.close()
    state, done, attrs = read_state(str(path))
    assert state is not None and done == 30 and attrs["slip_recorded"] == 30
    cut = open_catalog(path)
    assert cut.sizes["event"] == 30  # the 15 rows no state follows are not events yet
    cut.close()
    more = chain(p, events, out=path, record_slip=40, resume=True, progress=False)
    got = more.catalog.load()
    more.catalog.close()
    assert got.sizes["event"] == events and got.attrs["complete"] == 1
    assert got.attrs["slip_recorded"] == min(events, 40)
    for name in COLUMNS:  # the energies are sums carried across the resume: equal to rounding
        exact = name not in ("driver_work", "friction_work", "elastic_change")
        np.testing.assert_allclose(
            got[name].values, ref[name].values[:events], rtol=0 if exact else 1e-12, atol=0, err_msg=name
        )
    k = min(events, 40)
    np.testing.assert_array_equal(got["slip"].values[:k], ref["slip"].values[:k])
    assert more.summary() == chain(p, events, record_slip=40, progress=False).summary()


def test_an_ensemble_member_with_a_broken_catalogue_starts_again(tmp_path: Path) -> None:
    """A member's catalogue truncated (or left unreadable by a kill -9) is warned about and its
    member starts again: failing it with 'NetCDF: HDF error' on every run, the store could
    never finish."""
    p = ChainParameters(6, WeakeningLaw(c=3.0, p=0.0), 0.01, 2.0)
    ref = chain_ensemble(p, 40, [1, 2], progress=False)
    store = tmp_path / "e.zarr"
    chain_ensemble(p, 40, [1, 2], store=store, progress=False)
    (store / ".stickslip-done" / "000000001").unlink()
    broken = store / "catalogs" / "seed-2.nc"
    broken.write_bytes(broken.read_bytes()[:600])
    with pytest.warns(UserWarning, match="seed-2.nc: cannot be continued .*its member starts again"):
        again = chain_ensemble(p, 40, [1, 2], store=store, progress=False)
    for name in ("events", "mean_moment", "b_value", "status"):
        np.testing.assert_array_equal(again[name].values, ref[name].values)


@pytest.mark.slow
def test_events_do_not_depend_on_where_a_call_pauses() -> None:
    """A call that pauses after every step gives the events of one call, bit for bit.

    The forces of the stuck blocks next to slipping ones at the start of each
    step once came from the positions of the last pause: event times then moved
    with the pauses (by 1e-8 on a 1000-block chain), not only by rounding.
    """
    from stickslip.core import chain as core_chain
    from stickslip.core.api import ChainState, chain_advance

    law = CarlsonLangerLaw(alpha=2.5, sigma=0.01)
    p = ChainParameters(60, law, 0.01, 10.0)
    args = (law.kernel, law.core_params(), p.nu, p.ell2, False, False, p.phi)
    start = ChainState.at_rest(np.random.default_rng(3).uniform(0.0, 0.01, 60))
    chain_advance(*args, start, max_events=300, max_steps=10**8)
    one = start.copy()
    whole, _, _ = chain_advance(*args, one, max_events=40, max_steps=10**8)

    def in_calls(state: ChainState, **budget: float) -> tuple[npt.NDArray[np.float64], int]:
        rows, calls, done = [], 0, 0
        while done < 40:
            cat, _, status = chain_advance(*args, state, max_events=40 - done, **budget)  # type: ignore[arg-type]
            rows.append(cat)
            calls += 1
            done += cat.shape[0]
            assert status in (core_chain.CH_EVENTS, core_chain.CH_PAUSED)
        return np.concatenate(rows), calls

    works = [core_chain.C_WD, core_chain.C_WF]  # summed in other pieces: rounding
    same = [c for c in range(core_chain.NCAT) if c not in works]
    paused, worked = start.copy(), start.copy()
    # a budget of one step, and a budget of work: they pause alike, and change nothing
    for state, budget, least in ((paused, {"max_steps": 1}, 1000), (worked, {"max_work": 100.0}, 100)):
        got, calls = in_calls(state, **budget)
        assert calls > least and whole.shape == got.shape == (40, core_chain.NCAT)
        np.testing.assert_array_equal(whole[:, same], got[:, same])
        np.testing.assert_allclose(whole[:, works], got[:, works], rtol=1e-11, atol=1e-12)
        np.testing.assert_array_equal(one.x, state.x)
    assert worked.sc[core_chain.S_NWORK] == one.sc[core_chain.S_NWORK] > 0


def test_carlson_langer_blocks_never_slip_backward() -> None:
    law = CarlsonLangerLaw(alpha=2.5, sigma=0.01)
    assert ChainParameters(5, law, 0.01, 3.0).backslip is False
    assert ChainParameters(5, WeakeningLaw(c=1.0), 0.01, 3.0).backslip is True
    r = chain(ChainParameters(50, law, 0.01, 3.0), 300, progress=False)
    assert np.all(r.catalog["slip"].values >= 0.0)


def test_heterogeneous_thresholds_are_seeded() -> None:
    a = static_thresholds(10, 0.1, seed=4)
    b = static_thresholds(10, 0.1, seed=4)
    assert a is not None and b is not None
    np.testing.assert_array_equal(a, b)
    assert np.all(np.abs(a - 1.0) <= 0.1)
    r = chain(ChainParameters(10, WeakeningLaw(c=2.0), 0.05, 1.0, thresholds=a), 30, progress=False)
    assert r.status == "ok" and r.events == 30


@pytest.mark.fast
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"blocks": 0}, "blocks=0"),
        ({"blocks": 2.5}, "blocks=2.5"),
        ({"ell": -1.0}, "ell"),
        ({"nu": 0.0}, "nu"),
        ({"boundary": "open"}, "boundary='open'"),
        ({"thresholds": np.ones(3)}, "thresholds: expected 4 values"),
        ({"thresholds": -np.ones(4)}, "thresholds: expected positive"),
        ({"backslip": "no"}, "backslip='no'"),  # was stored, and counted as true
    ],
)
def test_bad_parameters_are_named(kwargs: dict[str, object], message: str) -> None:
    base: dict[str, object] = {"blocks": 4, "law": WeakeningLaw(c=1.0), "nu": 0.1, "ell": 1.0}
    base.update(kwargs)
    with pytest.raises(ValueError, match=message):
        ChainParameters(**base)  # type: ignore[arg-type]


def test_bad_run_arguments_are_named(tmp_path: Path) -> None:
    p = ChainParameters(3, WeakeningLaw(c=1.0), 0.1, 1.0)
    with pytest.raises(ValueError, match="events=0"):
        chain(p, 0)
    with pytest.raises(ValueError, match="init='sideways'"):
        chain(p, 5, init="sideways")
    with pytest.raises(ValueError, match="does not exist"):
        chain(p, 5, out=tmp_path / "no" / "such.nc")
    with pytest.raises(ValueError, match=r"events=2\.5"):
        chain(p, 2.5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="seed=-1"):
        chain(p, 5, seed=-1)
    with pytest.raises(ValueError, match="t_max='2 s': a dimensionless chain takes a number"):
        chain(p, 5, t_max="2 s")  # type: ignore[arg-type]
    # resume: without out it did nothing; beside state= it blamed the set-up
    with pytest.raises(ValueError, match="resume=True needs out"):
        chain(p, 5, resume=True)
    first = chain(p, 5, out=tmp_path / "a.nc", progress=False)
    first.catalog.close()
    with pytest.raises(DataError, match="started with init='random'; resume it the same way"):
        chain(p, 8, out=tmp_path / "a.nc", resume=True, state=first.state)
    # another atol is another set-up (it was resumed, mixing two tolerances)
    with pytest.raises(DataError, match=r"another set-up \(atol 1e-\d+ in the file, 1e-06 now\)"):
        chain(p, 8, out=tmp_path / "a.nc", resume=True, atol=1e-6, progress=False)
    again = chain(p, 8, out=tmp_path / "a.nc", resume=True, progress=False)
    assert again.events == 8
    again.catalog.close()
    # a run started from a given state resumes with it
    from_state = chain(p, 5, state=first.state, out=tmp_path / "s.nc", progress=False)
    from_state.catalog.close()
    with pytest.raises(DataError, match=r"started from a given state \(state=\)"):
        chain(p, 8, out=tmp_path / "s.nc", resume=True, progress=False)
    resumed = chain(p, 8, state=first.state, out=tmp_path / "s.nc", resume=True, progress=False)
    assert resumed.events == 8
    resumed.catalog.close()
    # a catalogue written before the set-up kept atol resumes, with a warning, and takes it
    import netCDF4

    old = chain(p, 5, out=tmp_path / "old.nc", progress=False)
    old.catalog.close()
    with netCDF4.Dataset(tmp_path / "old.nc", "a") as nc:
        setup = json.loads(nc.getncattr("setup"))
        del setup["atol"]
        nc.setncattr("setup", json.dumps(setup, sort_keys=True))
    with pytest.warns(UserWarning, match="written before its atol was recorded"):
        later = chain(p, 8, out=tmp_path / "old.nc", resume=True, progress=False)
    later.catalog.close()
    with netCDF4.Dataset(tmp_path / "old.nc") as nc:
        assert json.loads(nc.getncattr("setup"))["atol"] == ss.defaults.ATOL
    # the ensemble checks the same before its store is made (events=2.7 ran 2, seeds 1.7 ran 1)
    for kw, message in (
        ({"events": 2.7}, "events=2.7"),
        ({"events": 0}, "events=0"),
        ({"transient": 1.9}, "transient=1.9"),
        ({"seeds": [1.7, 2.0]}, r"seeds\[0\]=1.7"),
        ({"seeds": [-1]}, r"seeds\[0\]=-1"),
        ({"amplitude": "x"}, "amplitude='x'"),
        ({"init": "sideways"}, "init='sideways'"),
        ({"rtol": float("nan")}, "rtol=nan"),
    ):
        args: dict[str, Any] = {"events": 3, "seeds": [1, 2]} | kw
        with pytest.raises(ValueError, match=message):
            chain_ensemble(p, store=tmp_path / "e.zarr", progress=False, **args)
        assert not (tmp_path / "e.zarr").exists()
    # uniform positions take no amplitude, as in chain()
    same = chain_ensemble(p, 3, [1], init="uniform", amplitude=0.0, progress=False)
    assert int(same["events"][0]) == 3
    # b_value's own arguments
    m = np.random.default_rng(0).exponential(0.43, 200)
    for kw, message in (
        ({"n_boot": -5}, "n_boot=-5"),
        ({"n_boot": 2.5}, "n_boot=2.5"),
        ({"n_boot": 1}, "n_boot=1: expected 0"),
        ({"seed": -1}, "seed=-1"),
        ({"bin_width": 0.0}, "bin_width=0.0"),
        ({"bin_width": float("nan")}, "bin_width=nan"),
    ):
        with pytest.raises(ValueError, match=message):
            b_value(m, mc=0.0, **kw)
    with pytest.raises(ValueError, match=r"bin_width=-0\.1"):
        magnitude_frequency(m, -0.1)
    with pytest.raises(ValueError, match=r"t_start\[2\]: the event starts are not in increasing order"):
        recurrence_times([0.0, 2.0, 1.0])


def test_physical_chain_has_units() -> None:
    phys = ss.PhysicalParameters(
        law=ss.f1(0.46, "160 s/m"), mass="1 kg", stiffness="62 N/m", load="196 mN", v0="5 mm/s"
    )
    p = ChainParameters.from_physical(phys, blocks=3, coupling="62 N/m")
    assert p.ell == pytest.approx(1.0)
    assert p.nu == pytest.approx(phys.nu)
    r = chain(p, 10, progress=False)
    assert r.catalog["t_start"].attrs["units"] == "s"
    assert r.catalog["moment"].attrs["units"] == "m"
    d = chain(ChainParameters(3, p.law, p.nu, p.ell), 10, progress=False)
    t_unit = phys.scales.time.to("s").magnitude
    np.testing.assert_allclose(r.catalog["t_start"].values, d.catalog["t_start"].values * t_unit, rtol=1e-12)
    with pytest.raises(ValueError, match="coupling"):
        ChainParameters.from_physical(phys, blocks=3, coupling="3 m")
    # a physical chain's times have units (a bare number, in units of sqrt(m/k_p), is 5 times
    # smaller in seconds here: refused), the dimensionless chain's are numbers
    half = r.simulated_time / t_unit / 2  # units of sqrt(m/k_p): stops before the 10th event
    by_number = chain(ChainParameters(3, p.law, p.nu, p.ell), 10, t_max=half, progress=False)
    by_units = chain(p, 10, t_max=f"{half * t_unit!r} s", progress=False)
    assert by_number.events < 10 and by_units.events == by_number.events
    assert by_units.simulated_time == pytest.approx(by_number.simulated_time * t_unit, rel=1e-12)
    with pytest.raises(
        ValueError, match=r"t_max=50.0: a physical chain takes a time with units, e.g. '50 s'"
    ):
        chain(p, 10, t_max=50.0, progress=False)
    with pytest.raises(ValueError, match="max_event_duration='3 m'"):
        chain(p, 10, max_event_duration="3 m", progress=False)


def test_command_line_json(tmp_path: Path) -> None:
    from click.testing import CliRunner

    from stickslip.cli import main

    res = CliRunner().invoke(
        main,
        [
            "chain",
            "--blocks",
            "8",
            "--events",
            "60",
            "--law",
            "carlson-langer",
            "--alpha",
            "2.5",
            "--sigma",
            "0.01",
            "--nu",
            "0.01",
            "--ell",
            "3",
            "--seed",
            "2",
            "--json",
            "--out",
            str(tmp_path),
        ],
    )
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    for key in (
        "blocks",
        "events",
        "simulated_time",
        "mean_recurrence",
        "mean_moment",
        "largest_event_blocks",
        "b_value",
        "b_value_err",
        "b_value_block",
        "status",
    ):
        assert key in out
    assert out["blocks"] == 8 and out["events"] == 60 and out["status"] == "ok"
    assert out["b_value_range"] == "power-law range"
    # the command's fit is b_value's default range of the catalogue's magnitudes, in time order;
    # 60 events of 8 blocks hold no power law over a decade of moment: no b-value, and why
    fit = b_value(open_catalog(tmp_path / "catalog.nc")["magnitude"].values, mc="auto", block="auto")
    assert out["b_value"] is None and math.isnan(fit.b) and not out["b_value_power_law"]
    assert out["b_value_verdict"] == fit.verdict and fit.verdict.startswith("not a power law")
    assert out["completeness_magnitude"] == fit.mc and out["b_value_ks_p"] == pytest.approx(fit.ks_p)
    assert out["events_as"] == "whole" and out["ruptures"] is None
    cat = open_catalog(tmp_path / "catalog.nc")
    assert cat.sizes["event"] == 60
    assert float(np.mean(np.diff(cat["t_start"].values))) == pytest.approx(out["mean_recurrence"])
    assert json.loads((tmp_path / "summary.json").read_text())["events"] == 60
    for fig in ("magnitude_frequency.png", "space_time.png", "recurrence.png"):
        assert (tmp_path / fig).stat().st_size > 1000


def test_command_line_bad_input() -> None:
    from click.testing import CliRunner

    from stickslip.cli import main

    res = CliRunner().invoke(
        main, ["chain", "--law", "weakening", "--blocks", "0", "--events", "5", "--c", "1", "--nu", "0.1"]
    )
    assert res.exit_code == 2 and "blocks" in res.output
    res = CliRunner().invoke(
        main,
        [
            "chain",
            "--law",
            "weakening",
            "--blocks",
            "3",
            "--events",
            "5",
            "--c",
            "1",
            "--nu",
            "0.1",
            "--boundary",
            "open",
        ],
    )
    assert res.exit_code == 2 and "boundary" in res.output
    res = CliRunner().invoke(
        main,
        [
            "chain",
            "--law",
            "weakening",
            "--blocks",
            "3",
            "--events",
            "5",
            "--c",
            "1",
            "--nu",
            "0.1",
            "--mc",
            "x",
        ],
    )
    assert res.exit_code == 2 and "--mc='x'" in res.output


def test_space_time_figure_of_a_large_catalogue_stays_small(tmp_path: Path) -> None:
    """Clouds of points are images inside the SVG: 3000 events on 1000 blocks once made 63 MB."""
    import xarray as xr

    from stickslip.plots.chains import RASTER, plot_recurrence, plot_space_time
    from stickslip.plots.figures import save_figure

    rng = np.random.default_rng(5)
    events, blocks = 6000, 20
    slip = np.where(rng.uniform(size=(events, blocks)) < 0.3, rng.uniform(0.01, 1.0, (events, blocks)), 0.0)
    slip[:, 0] = 0.5  # every event slips somewhere
    assert np.count_nonzero(slip) > 4 * RASTER and events > RASTER
    moment = slip.sum(axis=1)
    cat = xr.Dataset(
        {
            "t_start": ("event", np.cumsum(rng.uniform(1.0, 2.0, events))),
            "magnitude": ("event", np.log10(moment)),
            "moment": ("event", moment),
            "first_block": ("event", np.zeros(events, dtype=np.int64)),
            "last_block": ("event", np.full(events, blocks - 1)),
            "n_blocks": ("event", np.full(events, blocks)),  # contiguous ruptures: drawn as segments
            "slip": (("event", "block"), slip),
        },
        attrs={"blocks": blocks, "slip_recorded": events},
    )
    from matplotlib.collections import LineCollection, PathCollection

    fig = plot_space_time(cat)
    assert [c.get_rasterized() for c in fig.axes[0].collections if isinstance(c, PathCollection)] == [True]
    save_figure(fig, tmp_path / "st")
    # drawn one mark at a time, the slips' squares made 3.6 MB of SVG (measured with 24 000)
    assert (tmp_path / "st.svg").stat().st_size < 1_000_000
    segments = plot_space_time(cat.assign_attrs(slip_recorded=0), max_events=events)  # segments
    assert [c.get_rasterized() for c in segments.axes[0].collections if isinstance(c, LineCollection)] == [
        True
    ]
    # the small events drawn last, on top of the large ones (they hid them at nu = 0.01)
    for f in (fig, segments):
        drawn = next(c for c in f.axes[0].collections if isinstance(c, (PathCollection, LineCollection)))
        shown = np.asarray(drawn.get_array())
        assert shown.size > RASTER and np.all(np.diff(shown) <= 0.0)
    rec = plot_recurrence(cat)
    assert [ln.get_rasterized() for ln in rec.axes[1].lines] == [True]  # the moments against time
    small = plot_recurrence(cat.isel(event=slice(0, 100)))  # a few marks stay vector
    assert [ln.get_rasterized() for ln in small.axes[1].lines] == [False]


def test_a_force_that_touches_the_threshold_and_turns_back_does_not_stall_the_chain() -> None:
    """Three stiffly coupled blocks (ell = 1000): at t = 14.078 the middle one, at rest with its force
    2e-12 above its threshold and falling (the outer blocks swing against each other), slips for
    about 2e-5 inside a step of 4e-4. That slip was taken for none: the block stopped at once and
    slipped on at once, again and again, without the time advancing (the command hung)."""
    from stickslip.chains.model import initial_positions
    from stickslip.core.api import ChainState, chain_advance
    from stickslip.core.chain import CH_STALLED

    p = ChainParameters(3, WeakeningLaw(c=3.0), 0.01, 1000.0)
    st = ChainState.at_rest(initial_positions(3, "random", 0))
    args = (p.law.kernel, p.law.core_params(), p.nu, p.ell2, False, True, p.phi)
    cat, _, code = chain_advance(*args, st, max_events=200, max_steps=400_000)
    assert code != CH_STALLED
    assert st.t > 20.0 and cat.shape[0] == 200  # the first event ends at t = 19.43
    assert np.all(np.diff(cat[:, 0]) >= 0.0)


def test_the_stall_guard_counts_over_calls() -> None:
    """Steps without progress in time are counted over calls, not per call: a run in short calls
    (a second of work each) must still end a stall instead of pausing in it forever."""
    from stickslip.core import chain as core_chain
    from stickslip.core.api import ChainState, chain_advance

    p = ChainParameters(3, WeakeningLaw(c=3.0), 0.01, 10.0)
    st = ChainState.at_rest(np.array([0.0, 0.003, 0.001]))
    args = (p.law.kernel, p.law.core_params(), p.nu, p.ell2, False, True, p.phi)
    chain_advance(*args, st, max_events=3)
    st.sc[core_chain.S_STALL] = core_chain.STALL_STEPS - 5  # as if 9995 steps had made no progress
    with_progress = st.copy()
    _, _, code = chain_advance(*args, with_progress, max_events=3, max_steps=3)
    # kept over the pause (started again at 0 by each call, a stall that spans calls of fewer
    # than STALL_STEPS steps would never be caught)
    assert code == core_chain.CH_PAUSED and with_progress.sc[core_chain.S_STALL] == core_chain.STALL_STEPS - 5
    # the counter is read at the start of a call: past the guard, the call ends at once
    st.sc[core_chain.S_STALL] = core_chain.STALL_STEPS + 1
    _, _, code = chain_advance(*args, st, max_events=3, max_steps=3)
    assert code == core_chain.CH_STALLED


def test_a_state_of_another_engine_version_is_refused() -> None:
    from stickslip.core import chain as core_chain
    from stickslip.core.api import ChainState, chain_advance

    p = ChainParameters(3, WeakeningLaw(c=3.0), 0.01, 10.0)
    st = ChainState.at_rest(np.zeros(3))
    old = ChainState(st.x, st.v, st.mode, st.sc[:14].copy(), st.ev_x0, st.ev_flag, st.ev_list)
    args = (p.law.kernel, p.law.core_params(), p.nu, p.ell2, False, True, p.phi)
    with pytest.raises(ValueError, match=f"14 scalars, expected {core_chain.NSC}"):
        chain_advance(*args, old, max_events=1)


def test_b_value_of_identical_events_is_undefined() -> None:
    """One block (or identical blocks) repeats one event: no spread, no power law, no b-value."""
    m = np.full(50, -0.3) + np.random.default_rng(6).normal(0.0, 1e-12, 50)
    fit = b_value(m, n_boot=20)
    assert math.isnan(fit.b) and math.isnan(fit.error) and fit.n > 0
    assert math.isnan(b_value(m, mc="auto", n_boot=0).b)
    # a spread over more than a bin is fitted
    assert math.isfinite(b_value(np.linspace(0.0, 1.0, 50), mc=0.0, n_boot=0).b)


def test_command_line_text_report_without_a_b_value_and_bad_fit_ranges() -> None:
    from click.testing import CliRunner

    from stickslip.cli import main

    base = [
        "chain",
        "--law",
        "weakening",
        "--blocks",
        "3",
        "--events",
        "5",
        "--c",
        "3",
        "--ell",
        "1",
        "--quiet",
    ]
    # a sliding chain: no event, no b-value; the text report says so (it raised a TypeError)
    res = CliRunner().invoke(main, [*base, "--nu", "10"])
    assert res.exit_code == 1 and isinstance(res.exception, SystemExit)  # not a TypeError
    assert "b-value              undefined" in res.output and "Traceback" not in res.output
    for bad, word in ((["--mc", "nan"], "--mc"), (["--mc", "0", "--m-max", "-1"], "--m-max"),
                      (["--m-max", "inf"], "--m-max")):  # fmt: skip
        res = CliRunner().invoke(main, [*base, "--nu", "0.01", *bad])
        assert res.exit_code == 2 and word in res.output, res.output


def test_command_line_reports_the_change_of_slope_in_the_fitted_range() -> None:
    from click.testing import CliRunner

    from stickslip.cli import main

    args = ["chain", "--law", "carlson-langer", "--alpha", "2.5", "--sigma", "0.01", "--nu", "0.01"]
    args += ["--ell", "10", "--blocks", "30", "--events", "600", "--seed", "1", "--quiet"]
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, res.output
    line = next(x for x in res.output.splitlines() if x.startswith("slope change"))
    js = CliRunner().invoke(main, [*args, "--json"])
    s = json.loads(js.stdout)  # a warning goes to stderr
    assert f"below M = {s['b_value_split']:.2f}" in line and f"p = {s['b_value_slope_p']:.2g}" in line
    assert f"b = {s['b_value_lower']:.4g} below" in line and f"{s['b_value_upper']:.4g} above" in line


def test_command_line_refuses_negative_seeds_in_one_line() -> None:
    from click.testing import CliRunner

    from stickslip.cli import main

    base = [
        "chain",
        "--law",
        "weakening",
        "--blocks",
        "3",
        "--events",
        "5",
        "--c",
        "3",
        "--nu",
        "0.01",
        "--quiet",
    ]
    for bad, word in (
        (["--seed", "-1"], "--seed"),
        (["--seeds", "-2..0"], "--seeds"),
        (["--seeds", "3,-1"], "--seeds"),
    ):
        res = CliRunner().invoke(main, [*base, *bad])
        assert res.exit_code == 2 and word in res.output and "Traceback" not in res.output, res.output


def test_command_line_resume_never_replaces_a_finished_run(tmp_path: Path) -> None:
    from click.testing import CliRunner

    from stickslip.cli import main

    base = [
        "chain",
        "--law",
        "weakening",
        "--blocks",
        "3",
        "--events",
        "5",
        "--c",
        "3",
        "--ell",
        "1",
        "--quiet",
        "--no-plot",
    ]
    out = ["--out", str(tmp_path / "run")]
    first = CliRunner().invoke(main, [*base, "--nu", "0.01", *out, "--resume"])
    assert first.exit_code == 0 and "starting a new one" in first.output
    before = (tmp_path / "run" / "catalog.nc").read_bytes()
    # another set-up with --resume: once it silently replaced the finished catalogue
    res = CliRunner().invoke(main, [*base, "--nu", "0.02", *out, "--resume"])
    assert res.exit_code == 2 and "complete" in res.output
    assert (tmp_path / "run" / "catalog.nc").read_bytes() == before


def test_command_line_warns_where_seed_or_amplitude_cannot_matter() -> None:
    from click.testing import CliRunner

    from stickslip.cli import main

    base = [
        "chain",
        "--law",
        "weakening",
        "--blocks",
        "3",
        "--events",
        "3",
        "--c",
        "3",
        "--nu",
        "0.1",
        "--quiet",
        "--json",
    ]
    runs = {
        "seed": CliRunner().invoke(main, [*base, "--init", "uniform", "--seed", "4"]),
        "amplitude": CliRunner().invoke(main, [*base, "--init", "uniform", "--amplitude", "0.1"]),
        "seeds thresholds": CliRunner().invoke(
            main, [*base, "--init", "uniform", "--seed", "4", "--threshold-spread", "0.1"]
        ),
        "random": CliRunner().invoke(main, [*base, "--seed", "4"]),
    }
    for res in runs.values():
        assert res.exit_code == 0, res.output
    assert "warning: --seed does nothing with --init uniform" in runs["seed"].output
    assert "warning: --amplitude does nothing with --init uniform" in runs["amplitude"].output
    # the seed draws the thresholds; with random positions it draws those: no warning
    assert "warning" not in runs["seeds thresholds"].output
    assert "warning" not in runs["random"].output
    ensemble = [
        "chain",
        "--law",
        "weakening",
        "--blocks",
        "3",
        "--events",
        "3",
        "--c",
        "3",
        "--nu",
        "0.1",
        "--quiet",
        "--json",
    ]
    same = CliRunner().invoke(main, [*ensemble, "--seeds", "1..2", "--init", "uniform"])
    seed = CliRunner().invoke(main, [*ensemble, "--seeds", "1..2", "--seed", "7"])
    assert same.exit_code == 0 and seed.exit_code == 0, same.output + seed.output
    assert "members of --seeds are identical" in same.output
    assert "--seed is not used with --seeds" in seed.output
    noplot = CliRunner().invoke(main, [*ensemble, "--seeds", "1..2", "--no-plot"])
    assert noplot.exit_code == 0 and "--no-plot does nothing with --seeds" in noplot.output
    # a usage error comes alone, before any warning
    misuse = CliRunner().invoke(main, [*base, "--init", "uniform", "--seed", "4", "--workers", "2"])
    assert misuse.exit_code == 2 and "go with --seeds" in misuse.output
    assert "warning" not in misuse.output


def test_an_ensemble_fits_every_member_over_the_range_given() -> None:
    """--mc and --m-max reach every member of --seeds (they were dropped without a word)."""
    from click.testing import CliRunner

    from stickslip.cli import main

    p = ChainParameters(30, CarlsonLangerLaw(alpha=2.5, sigma=0.01), 0.01, 10.0)
    own = chain_ensemble(p, 300, [1, 2], transient=50, progress=False)
    fixed = chain_ensemble(p, 300, [1, 2], transient=50, mc=-2.0, m_max=0.0, progress=False)
    assert (fixed["completeness_magnitude"].values == -2.0).all() and (
        fixed["b_value_m_max"].values == 0.0
    ).all()
    assert (
        fixed.attrs["b_value_fit"] == "from -2 to 0"
        and own.attrs["b_value_fit"] == "each member's power-law range"
    )
    for s in (1, 2):  # each member's b is its own chain's over that range
        one = chain(p, 300, transient=50, seed=s, mc=-2.0, m_max=0.0, progress=False)
        assert fixed["b_value"].sel(seed=s).item() == one.b.b
        one.catalog.close()
    np.testing.assert_array_equal(own["mean_moment"].values, fixed["mean_moment"].values)
    base = ["chain", "--law", "carlson-langer", "--alpha", "2.5", "--sigma", "0.01", "--nu", "0.01"]
    base += ["--ell", "10", "--blocks", "30", "--events", "300", "--transient", "50", "--seeds", "1..2"]
    res = CliRunner().invoke(main, [*base, "--mc", "-2", "--m-max", "0", "--quiet", "--json"])
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["b_value_fit"] == "from -2 to 0"
    assert [m["completeness_magnitude"] for m in out["per_member"]] == [-2.0, -2.0]
    assert out["b_value_mean"] == pytest.approx(float(np.mean(fixed["b_value"].values)), rel=1e-12)
    bad = CliRunner().invoke(main, [*base, "--mc", "0", "--m-max", "-1", "--quiet"])
    assert bad.exit_code == 2 and "--m-max" in bad.output
    for kw, word in (
        ({"mc": "best"}, "mc="),
        ({"mc": math.nan}, "mc="),
        ({"mc": 0.0, "m_max": -1.0}, "m_max="),
    ):
        with pytest.raises(ValueError, match=word):
            chain_ensemble(p, 10, [1], progress=False, **kw)  # type: ignore[arg-type]
        with pytest.raises(ValueError, match=word):
            chain(p, 10, progress=False, **kw)  # type: ignore[arg-type]


def test_the_command_line_gives_sigterm_back_when_it_ends() -> None:
    import signal

    from click.testing import CliRunner

    from stickslip.cli import main

    before = signal.getsignal(signal.SIGTERM)
    res = CliRunner().invoke(
        main, ["chain", "--law", "weakening", "--blocks", "2", "--events", "2", "--c", "3", "--nu", "0.1"]
    )
    assert res.exit_code == 0, res.output
    # a program (or a test run) that calls main keeps its own SIGTERM afterwards
    assert signal.getsignal(signal.SIGTERM) is before


def test_a_stiff_random_start_is_warned_about() -> None:
    # ell = 3000 and displacements of 0.01: coupling forces 7e4 times the threshold, a first
    # event that rings for 40 s of computing (ell = 1e5: days) with nothing on the screen
    law = WeakeningLaw(3.0)
    with pytest.warns(UserWarning, match=r"times the static threshold \(ell = 3000\)"):
        chain(ChainParameters(10, law, 0.01, ell=3000.0), 1, progress=False, t_max=1e-3)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        chain(ChainParameters(10, law, 0.01, ell=3000.0), 1, progress=False, t_max=1e-3, amplitude=1e-7)
        chain(ChainParameters(10, law, 0.01, ell=10.0), 1, progress=False, t_max=1e-3)


def test_the_progress_bar_shows_the_simulated_time(capsys: pytest.CaptureFixture[str]) -> None:
    r = chain(ChainParameters(4, WeakeningLaw(3.0), 0.05, ell=2.0), 3, progress=True, transient=2)
    err = capsys.readouterr().err
    assert "transient 2/2, t = " in err, err  # events that the bar does not count
    # the time after the last call of the engine: a run with few events still shows it advances
    assert f"t = {r.simulated_time:.4g}" in err, err
    assert "event" in err


@pytest.mark.slow
def test_sigterm_leaves_a_resumable_chain_and_no_staging_folder(tmp_path: Path) -> None:
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "run"
    cmd = [sys.executable, "-m", "stickslip.cli", "chain", "--blocks", "60", "--events", "10000000",
           "--c", "3", "--nu", "0.01", "--ell", "3", "--quiet", "--no-plot", "--out", str(out),
           "--law", "weakening"]  # fmt: skip
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    partial = out / ".catalog.partial.nc"
    deadline = time.monotonic() + 120
    while not partial.exists() and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.2)
    time.sleep(2.0)  # some events recorded
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    # before: killed at once (-15), the staging folder left behind, the catalogue not closed
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert "stopped by SIGTERM" in err
    assert not [n for n in os.listdir(out) if n.startswith(".stickslip-staging-")]
    assert not (out / "catalog.nc").exists()
    from stickslip.chains.catalog import read_state

    _, done, _ = read_state(str(partial))
    res = subprocess.run([*cmd[:7], str(done + 5), *cmd[8:], "--resume", "--json"],
                         capture_output=True, text=True, timeout=300)  # fmt: skip
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout)["events"] == done + 5


class _Stop(Exception):
    pass


def _raise_stop(signum: int, frame: object) -> None:
    raise _Stop


def _stopped_by_sigterm(p: ChainParameters, path: Path) -> None:
    """Run 300 events into ``path`` until a SIGTERM (sent by a patched function) stops the run."""
    import signal

    before = signal.signal(signal.SIGTERM, _raise_stop)
    try:
        with pytest.raises(_Stop):
            chain(p, 300, out=path, progress=False)
    finally:
        signal.signal(signal.SIGTERM, before)


def _resumes_to(p: ChainParameters, path: Path, whole: ChainResult) -> None:
    """The stopped run, resumed, has the 300 events of the run never stopped, each once."""
    resumed = chain(p, 300, out=path, resume=True, progress=False)
    t0 = resumed.catalog["t_start"].values
    assert t0.size == 300 and np.all(np.diff(t0) > 0.0)
    np.testing.assert_allclose(t0, whole.catalog["t_start"].values, rtol=1e-12, atol=1e-9)


def test_a_signal_while_a_chunk_is_written_waits_for_rows_and_state(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A SIGTERM between a chunk's rows and its state waits for both: a catalogue whose rows ran
    ahead of its state would simulate those events again when resumed (320 duplicated rows in
    one such run)."""
    import os
    import signal

    from stickslip.chains import catalog
    from stickslip.chains import run as chain_run_module

    p = ChainParameters(20, CarlsonLangerLaw(alpha=2.5, sigma=0.01), 0.01, 3.0)
    whole = chain(p, 300, progress=False)
    monkeypatch.setattr(chain_run_module, "WORK_PER_CALL", 3e4)  # many chunks
    monkeypatch.setattr(chain_run_module, "FLUSH_SECONDS", 0.0)  # each written at once
    appends = {"n": 0}
    append = catalog.CatalogWriter.append

    def signalled_append(self: catalog.CatalogWriter, rows: object, slips: object) -> None:
        appends["n"] += 1
        append(self, rows, slips)  # type: ignore[arg-type]
        if appends["n"] == 3:
            os.kill(os.getpid(), signal.SIGTERM)  # the rows written, not yet the state

    monkeypatch.setattr(catalog.CatalogWriter, "append", signalled_append)
    path = tmp_path / "cat.nc"
    _stopped_by_sigterm(p, path)
    assert appends["n"] == 3
    monkeypatch.setattr(catalog.CatalogWriter, "append", append)
    _resumes_to(p, path, whole)


def test_rows_held_in_memory_are_written_with_their_state_when_a_run_is_stopped(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Rows are written every FLUSH_SECONDS, not after every call: a run stopped between two
    writes writes the rows it holds with the state after them. Stopped inside a call, that
    call's rows are lost and the state before it is kept, so the resumed run has every event
    once."""
    import os
    import signal

    from stickslip.chains import run as chain_run_module

    p = ChainParameters(20, CarlsonLangerLaw(alpha=2.5, sigma=0.01), 0.01, 3.0)
    whole = chain(p, 300, progress=False)
    monkeypatch.setattr(chain_run_module, "WORK_PER_CALL", 3e4)
    monkeypatch.setattr(chain_run_module, "FLUSH_SECONDS", 1e9)  # nothing written before the end
    calls = {"n": 0}
    advance = chain_run_module.chain_advance

    def signalled_advance(*args: object, **kw: object) -> object:
        calls["n"] += 1
        out = advance(*args, **kw)  # type: ignore[arg-type]
        if calls["n"] == 6:
            os.kill(os.getpid(), signal.SIGTERM)  # this call done, its rows not yet taken
        return out

    monkeypatch.setattr(chain_run_module, "chain_advance", signalled_advance)
    path = tmp_path / "cat.nc"
    _stopped_by_sigterm(p, path)
    monkeypatch.setattr(chain_run_module, "chain_advance", advance)
    from stickslip.chains.catalog import read_state

    _, written, _ = read_state(str(path))
    assert 0 < written < 300  # the five calls' rows, written when the run stopped
    _resumes_to(p, path, whole)


def test_one_command_gives_one_catalogue_bit_for_bit(monkeypatch: pytest.MonkeyPatch) -> None:
    """The calls' budget is fixed work, not wall-clock time: where calls pause moves the events'
    works in their last bits, so a budget from the clock made two runs of one command differ."""
    from stickslip.chains import run as chain_run_module

    monkeypatch.setattr(chain_run_module, "WORK_PER_CALL", 2e4)
    p = ChainParameters(20, CarlsonLangerLaw(alpha=2.5, sigma=0.01), 0.01, 3.0)
    a, b = (chain(p, 200, progress=False).catalog for _ in range(2))
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values)


def test_a_catalogue_on_disk_holds_the_slips_recorded_and_no_fill_values(tmp_path: Path) -> None:
    """The slip dimension is made for record_slip rows (2000), but the catalogue on disk has the
    recorded rows only, as the one in memory does, and a raw NetCDF reader sees NaN beyond
    them, not netCDF's default fill 9.97e36 (which slip.max() would return)."""
    import netCDF4

    p = ChainParameters(4, WeakeningLaw(c=10.0), 0.002, 2.0)
    disk = chain(p, 30, out=tmp_path / "c.nc", seed=3, progress=False)
    mem = chain(p, 30, seed=3, progress=False)
    assert disk.catalog.sizes["recorded_event"] == mem.catalog.sizes["recorded_event"] == 30
    np.testing.assert_array_equal(disk.catalog["slip"].values, mem.catalog["slip"].values)
    # every event's slips add up to its moment (no backward slip here)
    np.testing.assert_allclose(disk.catalog["slip"].sum("block"), disk.catalog["moment"], rtol=1e-12)
    disk.catalog.close()
    with netCDF4.Dataset(tmp_path / "c.nc") as raw:
        assert np.isnan(np.ma.filled(raw["slip"][30:], np.nan)).all()


def test_a_state_that_is_not_finite_is_refused() -> None:
    """A NaN position is refused by name: in the compiled engine the breakaway-time tree walks
    past its leaves without end, where Ctrl-C cannot stop it."""
    p = ChainParameters(3, WeakeningLaw(c=1.0), 0.05, 1.0)
    bad = ss.core.api.ChainState.at_rest([0.0, math.nan, 0.0])
    with pytest.raises(ValueError, match=r"state: block 2's position is nan; expected finite"):
        chain(p, 5, state=bad, progress=False)
    with pytest.raises(ValueError, match=r"block 2's position is nan"):
        event_map(p, [0.0, math.nan, 0.1])
    with pytest.raises(ValueError, match=r"block 1's position is inf"):
        lyapunov_exponent(p, [math.inf, 0.0, 0.1], events=10, transient=0)


def test_the_event_map_refuses_what_is_not_a_state_and_a_constant_map_is_superstable() -> None:
    """The event map refuses 2 positions for 3 blocks (taken, they make a 2-block map with an
    exponent 0.517), names a refused tolerance as such (not 'a sliding state of the chain'),
    and refuses eps = 0. One block's map is constant (every cycle starts from the same
    breakaway): the companion orbit lands within rounding, and the exponent is -inf, not
    log(rounding/eps) (-13.4 to -27.2 with eps)."""
    p = ChainParameters(3, WeakeningLaw(c=1.0), 0.05, 1.0)
    with pytest.raises(ValueError, match=r"u: 2 positions, shape \(2,\); expected one per block, 3"):
        event_map(p, [0.0, 0.3])
    with pytest.raises(ValueError, match=r"rtol=-1 must be positive: expected a relative tolerance"):
        event_map(p, [0.0, 0.3, 0.1], rtol=-1)
    # an event longer than max_steps goes on over several calls of the engine (it was called
    # 'a sliding state' after one call): one step per call gives the same map
    np.testing.assert_allclose(
        event_map(p, [0.0, 0.3, 0.1], max_steps=1), event_map(p, [0.0, 0.3, 0.1]), atol=1e-13
    )
    with pytest.raises(ValueError, match="max_steps=0"):
        event_map(p, [0.0, 0.3, 0.1], max_steps=0)
    for kwargs, message in (
        ({"eps": 0.0}, "eps=0.0: expected the companion orbit's distance"),
        ({"events": -1}, "events=-1: expected a whole number >= 2"),
        ({"transient": 1.5}, "transient=1.5"),
    ):
        with pytest.raises(ValueError, match=message):
            lyapunov_exponent(p, [0.0, 0.3, 0.1], **kwargs)
    one = ChainParameters(1, WeakeningLaw(c=2.0), 0.01, 1.0)
    for eps in (1e-9, 1e-5, 1e-3):
        r = lyapunov_exponent(one, [0.05], events=40, transient=2, eps=eps)
        assert r.defined and r.exponent == -math.inf and r.unresolved == 40
    # a chaotic three-block chain: every stretch resolved (Benettin's method by hand agrees)
    r = lyapunov_exponent(ChainParameters(3, WeakeningLaw(c=2.0), 0.05, 1.0), [0.0, 0.3, 0.1], events=200)
    assert r.unresolved == 0 and r.exponent > 3 * r.error > 0


def test_thresholds_and_initial_positions_are_independent() -> None:
    """Thresholds and initial positions come from independent streams: both drawn from
    default_rng(seed), the strongest block would always start furthest ahead (correlation 1)."""
    from stickslip.chains.model import initial_positions

    phi = static_thresholds(2000, 0.3, seed=7)
    x = initial_positions(2000, "random", seed=7)
    assert phi is not None
    assert abs(np.corrcoef(phi, x)[0, 1]) < 4 / math.sqrt(2000)  # 4 sigma of no correlation
    np.testing.assert_array_equal(phi, static_thresholds(2000, 0.3, seed=7))  # still seeded


def test_chain_messages_name_the_option_and_its_bound(tmp_path: Path) -> None:
    """Each bad chain input is refused in words that name the option, its value and its bound."""
    from click.testing import CliRunner

    from stickslip.cli import main

    law = WeakeningLaw(c=1.0)
    with pytest.raises(
        ValueError, match=r"ell=10000000.0: expected a coupling ell = sqrt\(k_c/k_p\) below 1e\+06"
    ):
        ChainParameters(3, law, 0.05, 1e7)  # the bound in words, not 'ell >= 0 < 1000000.0'
    phys = ss.zv_parameters("100 um/s")
    with pytest.raises(ValueError, match=r"coupling='1e30 N/m': k_c/k_p = 1.613e\+28"):
        ChainParameters.from_physical(phys, blocks=3, coupling="1e30 N/m")  # as given, not ell=1.3e14
    assert ChainParameters.from_physical(phys, blocks=3, coupling="0 N/m").ell == 0.0  # as ell=0 is
    with pytest.raises(ValueError, match="record_slip=-1: expected a whole number >= 0"):
        chain(ChainParameters(3, law, 0.05, 1.0), 5, record_slip=-1, out=tmp_path / "r.nc")  # OverflowError
    with pytest.raises(ValueError, match=r"record_slip=1\.5"):
        chain(ChainParameters(3, law, 0.05, 1.0), 5, record_slip=1.5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="blocks=-1"):
        static_thresholds(-1, 0.1, seed=1)
    with pytest.raises(ValueError, match=r"m: magnitudes of shape \(2, 3\)"):
        b_value(np.zeros((2, 3)), mc=0.0)
    cli = [
        "chain",
        "--law",
        "weakening",
        "--nu",
        "0.002",
        "--c",
        "10",
        "--ell",
        "2",
        "--blocks",
        "4",
        "--events",
        "30",
    ]
    res = CliRunner().invoke(main, [*cli, "--out", str(tmp_path / "d"), "--no-plot"])
    assert res.exit_code == 0, res.output
    assert f"wrote {tmp_path / 'd'}/catalog.nc, summary.json\n" in res.output  # no 'and figures'
    res = CliRunner().invoke(main, [*cli, "--threshold-spread", "1.5"])
    assert (
        res.exit_code == 2
        and "Invalid value for --threshold-spread: 1.5: expected a threshold spread" in res.output
    )
    physical = ["chain", "--law", "weakening", "--preset", "zv", "--v0", "100 um/s"]
    res = CliRunner().invoke(main, [*physical, "--ell", "2", "--events", "5", "--blocks", "3"])
    assert res.exit_code == 2 and "--ell is for dimensionless input" in res.output


def test_events_with_backward_moment_are_counted() -> None:
    """With backward slip an event's moment (signed) can be <= 0: no magnitude, so it is not in
    the b-value; the summary and the text output say how many (such events are common: one in
    each of four set-ups tried)."""
    from click.testing import CliRunner

    from stickslip.cli import main

    p = ChainParameters(3, WeakeningLaw(c=10.0), 0.01, 3.0)
    assert p.backslip
    r = chain(p, 20, state=ss.core.api.ChainState.at_rest([0.0, 0.4, 0.1]), progress=False)
    moment = r.catalog["moment"].values
    assert moment[0] == pytest.approx(-0.278, abs=1e-3)  # event 0 slips back
    assert r.summary()["events_without_magnitude"] == int(np.sum(moment <= 0)) > 0
    assert r.b.n <= int(np.sum(moment > 0))
    cli = [
        "chain",
        "--law",
        "weakening",
        "--nu",
        "0.01",
        "--c",
        "10",
        "--ell",
        "3",
        "--blocks",
        "3",
        "--events",
        "40",
    ]
    res = CliRunner().invoke(main, [*cli, "--amplitude", "0.5"])  # random starts half a unit apart
    assert res.exit_code == 0, res.output
    assert "no magnitude         1 events (a net backward or zero moment" in res.output
    res = CliRunner().invoke(
        main, ["chain", "--law", "weakening", "--nu", "0.02", "--c", "1", "--ell", "1", "--blocks", "3"]
    )
    assert res.exit_code == 0 and "no magnitude" not in res.output


def test_a_block_that_starts_beyond_its_backward_threshold_slips_back_at_once() -> None:
    """Random initial positions with ell = 10 put the middle block's force at -1.463, beyond its
    backward threshold -1: it slips back at t = 0 (left stuck until a neighbour breaks away at
    24.4, it would write a spurious event and put every later event 28.4 early, status ok). The
    values come from an independent SciPy reference (event-driven, exact stick, DOP853 at rtol
    1e-12), not reference/chain.py, which starts from rest below the thresholds only."""
    r = chain(
        ChainParameters(3, WeakeningLaw(c=3.0), 0.01, 10.0),
        4,
        seed=12,
        progress=False,
        rtol=1e-12,
        atol=1e-14,
    )
    cat = r.catalog
    assert int(cat["epicentre"].values[0]) == 1 and cat["t_start"].values[0] == 0.0
    np.testing.assert_allclose(cat["t_end"].values[0], 0.222379719308814, rtol=0, atol=1e-9)
    np.testing.assert_allclose(cat["moment"].values[0], -0.0054120736432995776, rtol=0, atol=1e-12)
    ref_start = [78.56680098556922, 79.27792675260615, 79.98905251964388]
    ref_end = [79.0742739253632, 79.78539969239932, 80.49652545943796]
    np.testing.assert_allclose(cat["t_start"].values[1:], ref_start, rtol=0, atol=1e-9)
    np.testing.assert_allclose(cat["t_end"].values[1:], ref_end, rtol=0, atol=1e-9)
    np.testing.assert_allclose(cat["moment"].values[1:], 7.0408491785836e-05, rtol=1e-9)


@pytest.mark.slow
def test_a_tables_chain_that_fails_where_its_friction_reaches_zero_says_why() -> None:
    """A table whose extrapolation falls to zero friction (at 0.5 m/s, along the tangent at its
    last row) ends not-finite after a few events, and the chain names the cause, as `cycle`
    does."""
    law = TabulatedLaw(Q_([0.0, 0.1, 0.2, 0.3, 0.4], "m/s"), [0.5, 0.4, 0.3, 0.2, 0.1])
    p = ChainParameters(5, law.nondimensionalize(Q_(1.0, "s/m")), 0.01, 3.0)
    with pytest.warns(
        UserWarning, match=r"chain: the table ends at v = 400 mm/s with friction still falling"
    ):
        r = chain(p, 20, seed=1, progress=False)
    assert r.status == "not-finite"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an ordinary run says nothing
        chain(ChainParameters(3, WeakeningLaw(c=3.0), 0.01, 1.0), 5, progress=False)


@pytest.mark.parametrize(
    ("boundary", "t_end", "moment"),
    [
        (
            "periodic",
            [0.154359080091171, 30.62506782174332, 30.775308401210758],
            [1.0361736197822e-3, 8.342064379e-7],
        ),
        (
            "free",
            [0.17316193241598457, 50.75170402961361, 50.90194460908023],
            [1.1879246938473545e-4, 8.342064379e-7],
        ),
    ],
)
def test_every_block_that_starts_beyond_its_backward_threshold_slips_back(
    boundary: str, t_end: list[float], moment: list[float]
) -> None:
    """Ten blocks at ell = 30 (seed 5) start with forces -1.334, -1.371, -1.749 and -5.156 beyond
    their backward thresholds beside forward ones: every one of them slips back, block 1
    (-1.334, between stuck neighbours) too. The first event ends at 0.154359 with moment
    1.036e-3 (with block 1 left stuck: 0.154692 and 1.445e-3, every later one off, status ok).
    The values come from an independent SciPy reference (event-driven, exact stick, every block
    integrated, DOP853 at rtol 1e-13); its rtol 1e-12 agrees to 1e-13."""
    p = ChainParameters(10, WeakeningLaw(c=3.0), 0.01, 30.0, boundary=boundary)
    r = chain(p, 3, seed=5, amplitude=0.005, rtol=1e-13, atol=1e-15, progress=False)
    cat = r.catalog
    assert r.status == "ok"
    np.testing.assert_allclose(cat["t_end"].values, t_end, rtol=0, atol=1e-9)
    np.testing.assert_allclose(cat["moment"].values[0], moment[0], rtol=1e-9)
    np.testing.assert_allclose(cat["moment"].values[1:], moment[1], rtol=1e-9)
    # at t = 0 every block beyond a threshold slips, and only those
    first = chain(p, 1, seed=5, amplitude=0.005, t_max=1e-9, progress=False)
    np.testing.assert_array_equal(first.state.mode, [0, -1, 0, 0, 1, -1, -1, 1, 1, -1])


def test_events_in_pieces_are_counted_and_warned() -> None:
    """An event runs until every block sticks, so on a long chain slips far apart are one event,
    and their moments add: such events are counted and warned. Counted exactly on
    known rows, free and periodic (whose extent cannot tell a stretch across the ends), and on
    Carlson and Langer's 100 blocks, where many are, a warning."""
    from stickslip.chains.statistics import ruptures_in_pieces

    # blocks 2-4 (one stretch), 1 and 5 (two pieces), 0-2 and 7 (two) on eight blocks
    assert ruptures_in_pieces([3, 2, 4], [2, 1, 0], [4, 5, 7]) == (2, 3)
    slips = np.array(
        [
            [1.0, 0, 0, 0, 0, 0, 0, 2.0],  # across the ends: one stretch on a ring, two on a line
            [1.0, 0, 0, 3.0, 0, 0, 0, 0],  # two pieces on both
            [np.nan] * 8,  # not recorded: not checked
        ]
    )
    assert ruptures_in_pieces([2, 2, 3], [0, 0, 0], [7, 3, 7], slips, periodic=True) == (1, 2)
    assert ruptures_in_pieces([2, 2], [0, 0], [7, 3]) == (2, 2)
    p = ChainParameters(100, CarlsonLangerLaw(alpha=2.5, sigma=0.01), 0.01, 10.0)
    with pytest.warns(UserWarning, match=r"of 300 events slipped in separate pieces of the chain"):
        r = chain(p, 300, transient=100, seed=1, progress=False)
    s = r.summary()
    assert s["events_checked_for_pieces"] == 300 and 30 < s["events_in_pieces"] < 300
    c = r.catalog
    span = c["last_block"].values - c["first_block"].values + 1
    assert s["events_in_pieces"] == int(np.count_nonzero(c["n_blocks"].values < span))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # three blocks moving as one: no pieces, no warning
        one = chain(ChainParameters(3, WeakeningLaw(c=3.0), 0.1, 1.0), 30, init="uniform", progress=False)
    assert one.in_pieces() == (0, 30)


def test_a_damaged_or_foreign_catalogue_is_refused_in_one_line(tmp_path: Path) -> None:
    """Resuming a foreign NetCDF, a truncated one or one with an unreadable set-up is refused in
    one line naming the file and what is wrong (not 'IndexError: state_x not found in /',
    'NetCDF: HDF error' or 'another set-up ( differ)'); open_catalog of a file without 'moment'
    names the file (not xarray's bare KeyError)."""
    import netCDF4
    import xarray as xr

    p = ChainParameters(3, WeakeningLaw(c=3.0), 0.1, 1.0)
    xr.Dataset({"x": ("t", np.arange(3.0))}).to_netcdf(tmp_path / "foreign.nc")
    with pytest.raises(DataError, match=r"foreign.nc: cannot be resumed: not a stickslip chain catalogue"):
        chain(p, 5, out=tmp_path / "foreign.nc", resume=True, progress=False)
    first = chain(p, 5, out=tmp_path / "a.nc", progress=False)
    first.catalog.close()
    data = (tmp_path / "a.nc").read_bytes()
    (tmp_path / "cut.nc").write_bytes(data[: len(data) // 2])
    with pytest.raises(DataError, match=r"cut.nc: cannot be resumed: .*damaged"):
        chain(p, 8, out=tmp_path / "cut.nc", resume=True, progress=False)
    with netCDF4.Dataset(tmp_path / "a.nc", "a") as ds:
        ds.setncattr("setup", "{not json")
    with pytest.raises(DataError, match=r"a.nc: its set-up record is unreadable"):
        chain(p, 8, out=tmp_path / "a.nc", resume=True, progress=False)
    with netCDF4.Dataset(tmp_path / "a.nc", "a") as ds:
        ds.renameVariable("moment", "m0")
    with pytest.raises(DataError, match=r"a.nc: a chain catalogue without its 'moment' variable"):
        open_catalog(tmp_path / "a.nc")
