"""Exact answers: the Coulomb cycle in closed form, the harmonic slip, steady sliding."""

import math

import numpy as np
import pytest
from reference.one_block import coulomb_cycle

from stickslip import (
    CoulombLaw,
    CubicLaw,
    DimensionlessParameters,
    WeakeningLaw,
    cycle,
    simulate,
)


@pytest.mark.fast
@pytest.mark.parametrize("nu", [1e-6, 1e-3, 0.05, 0.5, 2.0])
@pytest.mark.parametrize("fk", [0.05, 0.3, 0.8])
def test_coulomb_cycle_closed_form(nu: float, fk: float) -> None:
    exact = coulomb_cycle(nu, fk)
    r = cycle(DimensionlessParameters(nu=nu, law=CoulombLaw(kinetic=fk)), rtol=1e-12)
    assert r.regime == "stick-slip"
    assert r.status == "ok"
    assert r.amplitude == pytest.approx(exact["amplitude"], rel=1e-11, abs=1e-11)
    assert r.period == pytest.approx(exact["period"], rel=1e-11)
    assert r.stick_time == pytest.approx(exact["stick_time"], rel=1e-11, abs=1e-10)
    assert r.min_force == pytest.approx(exact["min_force"], abs=1e-11)
    assert r.max_force == pytest.approx(exact["max_force"], abs=1e-11)
    assert r.peak_velocity == pytest.approx(exact["w_max"], rel=1e-11)
    assert r.stick_fraction == pytest.approx(exact["stick_time"] / exact["period"], abs=1e-10)
    assert r.slip_distance == pytest.approx(nu * exact["period"], rel=1e-11)
    assert r.friction_work == pytest.approx(exact["friction_work"], rel=1e-9)
    assert r.backward_slips == 0


@pytest.mark.fast
def test_coulomb_slip_is_a_shifted_harmonic_oscillator() -> None:
    """During slip, s - fk and w - nu rotate rigidly: w = nu - nu cos t + (1 - fk) sin t."""
    nu, fk = 0.2, 0.4
    exact = coulomb_cycle(nu, fk)
    p = DimensionlessParameters(nu=nu, law=CoulombLaw(kinetic=fk))
    t_break = 1.0 / nu  # from rest the spring loads from 0 to 1 at rate nu
    traj = simulate(p, duration=t_break + exact["slip_time"] + 1.0, n_points=3001, rtol=1e-12)
    slip = traj.phase == 1
    tau = traj.time[slip] - t_break
    w_exact = nu - nu * np.cos(tau) + (1 - fk) * np.sin(tau)
    s_exact = fk + nu * np.sin(tau) + (1 - fk) * np.cos(tau)
    assert slip.sum() > 1000
    np.testing.assert_allclose(traj.velocity[slip], w_exact, atol=1e-11)
    np.testing.assert_allclose(traj.spring_force[slip], s_exact, atol=1e-11)
    # stick phases: s grows linearly at rate nu, the block does not move
    stick = traj.phase == 0
    assert np.all(traj.velocity[stick] == 0.0)
    first = stick & (traj.time < t_break)
    np.testing.assert_allclose(traj.spring_force[first], nu * traj.time[first], rtol=1e-14)
    # the stop is an event at the closed-form time and force
    stops = [t for t, k in zip(traj.event_time, traj.event_kind, strict=True) if k == "stop"]
    assert stops[0] == pytest.approx(t_break + exact["slip_time"], rel=1e-12)


@pytest.mark.fast
def test_position_is_the_integral_of_the_velocity() -> None:
    """The position, integrated from the velocity samples (Simpson on a fine grid), not by its definition."""
    from scipy.integrate import cumulative_simpson

    nu = 0.01
    traj = simulate(DimensionlessParameters(nu=nu, law=WeakeningLaw(c=3.0)), n_points=200_001)
    moved = cumulative_simpson(traj.velocity, x=traj.time, initial=0.0)
    np.testing.assert_allclose(traj.position, moved, atol=2e-6)
    # and it does not move while it sticks
    stuck = traj.phase == 0
    assert np.ptp(traj.position[stuck & (traj.time < traj.event_time[0])]) == 0.0


@pytest.mark.fast
@pytest.mark.parametrize(
    ("law", "nu", "f_nu"),
    [
        (WeakeningLaw(c=1.0, p=2.0), 0.3, 1 / 1.3 + 2 * 0.3),  # f' > 0 everywhere: no weakening at all
        (CubicLaw(alpha=0.5, gamma=0.5), 1.5, 1 - 0.5 * 1.5 + 0.5 * 1.5**3),  # above the Hopf point
    ],
)
def test_steady_sliding(law: object, nu: float, f_nu: float) -> None:
    p = DimensionlessParameters(nu=nu, law=law)  # type: ignore[arg-type]
    r = cycle(p)
    assert r.regime == "steady-sliding"
    assert r.steady_sliding_stable
    assert r.amplitude == 0.0
    assert r.max_force == pytest.approx(f_nu, abs=1e-12)
    traj = simulate(p, duration=200.0, n_points=200, initial=(1.0, 0.0))
    assert traj.spring_force[-1] == pytest.approx(f_nu, abs=1e-7)
    assert traj.velocity[-1] == pytest.approx(nu, abs=1e-7)


@pytest.mark.fast
def test_steady_sliding_is_a_fixed_point() -> None:
    """Started exactly on steady sliding, the block stays there."""
    nu, c, pp = 0.7, 2.0, 0.5
    p = DimensionlessParameters(nu=nu, law=WeakeningLaw(c=c, p=pp))
    f_nu = 1.0 / (1.0 + c * nu) + pp * nu
    traj = simulate(p, duration=50.0, n_points=101, initial=(f_nu, nu))
    np.testing.assert_allclose(traj.velocity, nu, rtol=1e-13)
    np.testing.assert_allclose(traj.spring_force, f_nu, rtol=1e-13)


@pytest.mark.fast
def test_coulomb_amplitude_formula_limits() -> None:
    """Closed form sanity: at small nu the amplitude is 2(1 - fk) (the classic result)."""
    r = cycle(DimensionlessParameters(nu=1e-7, law=CoulombLaw(kinetic=0.25)))
    assert r.amplitude == pytest.approx(2 * (1 - 0.25), rel=1e-9)
    assert math.isclose(r.stick_fraction, 1.0, rel_tol=1e-5)


def test_serial_rows_equal_the_parallel_batch() -> None:
    """A few rows run in the calling thread (no parallel kernel to compile); bit for bit the batch's."""
    from stickslip.core.api import SERIAL_ROWS, run_attractors

    nu = np.geomspace(1e-4, 0.5, SERIAL_ROWS + 5)
    lp = np.array([3.8, 0.0, 0.0])  # the weakening law (law 0) with c = 3.8

    def run(n: int):
        return run_attractors(
            0, lp, nu[:n], from_breakaway=True, rtol=1e-9, atol=1e-12, max_slip_time=1e4, conv_tol=1e-8
        )

    few = run(SERIAL_ROWS)
    np.testing.assert_array_equal(few.raw, run(nu.size).raw[:SERIAL_ROWS])
    assert np.all(few.status == 0)
