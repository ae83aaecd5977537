"""Invariants: energy balance, periodicity by simulation, convergence order."""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from stickslip import CubicLaw, DimensionlessParameters, WeakeningLaw, cycle, simulate
from stickslip.core._dop853_unrolled import step2
from stickslip.core.dop853 import rhs
from stickslip.core.laws import N_LAW_PARAMS


def _coulomb_params(fk: float) -> np.ndarray:
    """The Coulomb law's parameter vector: the kernels read all N_LAW_PARAMS (8) entries."""
    lp = np.zeros(N_LAW_PARAMS)
    lp[0] = fk
    return lp


@given(nu=st.floats(1e-5, 1.0), c=st.floats(0.5, 100.0), p=st.floats(0.0, 0.5))
def test_energy_balance_stick_slip(nu: float, c: float, p: float) -> None:
    """Over a steady cycle the drive's work equals the work of friction."""
    r = cycle(DimensionlessParameters(nu=nu, law=WeakeningLaw(c=c, p=p)), probe=False)
    assume(r.regime == "stick-slip")
    assert r.drive_work > 0
    assert r.drive_work == pytest.approx(r.friction_work, rel=1e-8)


@given(nu=st.floats(1e-3, 0.3), alpha=st.floats(0.2, 1.0), gamma=st.floats(0.02, 0.3))
def test_energy_balance_cubic(nu: float, alpha: float, gamma: float) -> None:
    r = cycle(DimensionlessParameters(nu=nu, law=CubicLaw(alpha=alpha, gamma=gamma)), probe=False)
    assume(r.regime in ("stick-slip", "pure-slip") and r.status == "ok")
    assert r.drive_work == pytest.approx(r.friction_work, rel=1e-7, abs=1e-12)


def test_energy_balance_pure_slip() -> None:
    """A pure-slip cycle (cubic law just below its supercritical Hopf point)."""
    alpha, gamma = 0.5, 0.5 / 3  # Hopf at nu = 1; averaging: velocity amplitude 0.28 at 0.97
    r = cycle(DimensionlessParameters(nu=0.97, law=CubicLaw(alpha=alpha, gamma=gamma)))
    pure = [a for a in r.attractors if a.regime == "pure-slip"]
    assert pure, r
    r2 = cycle(DimensionlessParameters(nu=0.97, law=CubicLaw(alpha=alpha, gamma=gamma)), probe=False)
    assert r2.regime == "pure-slip"  # from rest as well
    assert r2.drive_work > 0
    assert r2.drive_work == pytest.approx(r2.friction_work, rel=1e-6)


@pytest.mark.fast
@pytest.mark.parametrize(("nu", "c"), [(1e-3, 3.8), (0.05, 10.0), (1.0, 3.8)])
def test_simulated_cycles_repeat_the_computed_cycle(nu: float, c: float) -> None:
    """One slip integration from breakaway gives the cycle: simulation agrees cycle by cycle."""
    p = DimensionlessParameters(nu=nu, law=WeakeningLaw(c=c))
    r = cycle(p, probe=False)
    traj = simulate(p, cycles=4, n_points=20001)
    breaks = np.array(
        [
            t
            for t, k in zip(traj.event_time, traj.event_kind, strict=True)
            if k == "breakaway" and np.isclose(traj.spring_force[np.searchsorted(traj.time, t)], 1.0)
        ]
    )
    periods = np.diff(breaks)
    assert len(periods) >= 3
    np.testing.assert_allclose(periods, r.period, rtol=1e-9)
    # amplitude over the last full cycle, from the force extrema events
    last = (traj.event_time >= breaks[-2]) & (traj.event_time <= breaks[-1])
    forces = traj.event_force[last]
    assert forces.max() - forces.min() == pytest.approx(r.amplitude, rel=1e-9)


def _slip_fixed_step(h: float, t_end: float, nu: float, fk: float) -> np.ndarray:
    law, lp = 2, _coulomb_params(fk)
    y = np.array([1.0, 0.0])
    K = np.empty((16, 2))
    y_new = np.empty(2)
    n = round(t_end / h)
    for _ in range(n):
        rhs(law, lp, nu, 1, y, K[0])
        step2(law, lp, nu, 1, y, h, K, y_new, 1.0, 1.0)
        y = y_new.copy()
    return y


@pytest.mark.fast
def test_dop853_convergence_order_is_eight() -> None:
    """Fixed-step error on the harmonic slip phase falls as h**8."""
    nu, fk, t_end = 0.1, 0.3, 4.0
    exact_w = nu - nu * math.cos(t_end) + (1 - fk) * math.sin(t_end)
    hs = np.array([1.0, 0.8, 0.5, 0.4])  # larger steps reach round-off
    errs = np.array([abs(_slip_fixed_step(h, t_end, nu, fk)[1] - exact_w) for h in hs])
    slope = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert 7.5 < slope < 8.8, (slope, errs)


def test_error_proportional_to_tolerance() -> None:
    """The adaptive engine's global error scales with rtol (slope about 1 in log-log)."""
    nu = 0.05
    # a law with curvature, against a very tight solution, to avoid the exactly-harmonic case
    law = WeakeningLaw(c=5.0)
    ref = cycle(DimensionlessParameters(nu=nu, law=law), rtol=1e-14, atol=1e-16, probe=False)
    rtols = np.array([1e-5, 1e-6, 1e-7, 1e-8])
    errs = np.array(
        [
            abs(
                cycle(DimensionlessParameters(nu=nu, law=law), rtol=r, atol=1e-16, probe=False).period
                - ref.period
            )
            for r in rtols
        ]
    )
    slope = np.polyfit(np.log(rtols), np.log(errs), 1)[0]
    assert 0.6 < slope < 1.4, (slope, errs)
    assert np.all(errs < 100 * rtols * ref.period)


def test_the_unrolled_step_the_engine_runs_has_order_eight() -> None:
    """The order test above drives the array step; the engine runs ``step_sw``, the same step
    written out stage by stage (generated): its fixed-step error falls as h**8 too."""
    from stickslip.core._dop853_unrolled import step_sw
    from stickslip.core.laws import params, slip_accel

    nu, fk, t_end = 0.1, 0.3, 4.0
    law, lp = 2, params(_coulomb_params(fk))
    exact_w = nu - nu * math.cos(t_end) + (1 - fk) * math.sin(t_end)
    errs = []
    hs = np.array([1.0, 0.8, 0.5, 0.4])
    for h in hs:
        s, w = 1.0, 0.0
        for _ in range(round(t_end / h)):
            _, s, w, _, _ = step_sw(law, lp, nu, 1, s, w, nu - w, slip_accel(law, lp, 1, s, w), h, 1.0, 1.0)
        errs.append(abs(w - exact_w))
    slope = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert 7.5 < slope < 8.8, (slope, errs)


def test_the_generated_step_is_what_its_generator_writes(tmp_path) -> None:
    """``_dop853_unrolled.py`` is generated from the tableau: a hand edit (a mistyped weight)
    would pass the order test yet no longer be the tableau's step."""
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    out = tmp_path / "unrolled.py"
    subprocess.run([sys.executable, str(root / "tools" / "gen_dop853_unrolled.py"), str(out)], check=True)
    committed = root / "src" / "stickslip" / "core" / "_dop853_unrolled.py"
    assert out.read_text() == committed.read_text(), "run python tools/gen_dop853_unrolled.py"
