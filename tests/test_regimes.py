"""Regimes found without assuming them, confirmed by direct simulation."""

import math

import numpy as np
import pytest

from stickslip import CubicLaw, DimensionlessParameters, WeakeningLaw, cycle, simulate

# cubic law with its (supercritical) Hopf point at nu = 1
CUBIC = CubicLaw(alpha=0.5, gamma=0.5 / 3)


def averaging_force_range(nu: float) -> float:
    """First-order averaging: x = w - nu = a cos t with a**2 = -4 f'(nu) / f'''(nu) * 2."""
    fprime = -CUBIC.alpha + 3 * CUBIC.gamma * nu**2
    a = math.sqrt(-4 * fprime / (3 * CUBIC.gamma))
    return 2 * a  # s oscillates with the same amplitude as w at unit frequency


@pytest.mark.parametrize("nu", [0.99, 0.999])
def test_pure_slip_near_supercritical_hopf(nu: float) -> None:
    r = cycle(DimensionlessParameters(nu=nu, law=CUBIC))
    assert r.regime == "pure-slip"
    assert r.status == "ok"
    assert r.stick_fraction == 0.0
    assert r.min_velocity > 0.0
    # weakly nonlinear limit: the averaging amplitude, error shrinking towards the Hopf point
    assert r.amplitude == pytest.approx(averaging_force_range(nu), rel=0.05 if nu < 0.995 else 0.01)
    assert r.drive_work == pytest.approx(r.friction_work, rel=1e-6)


def test_pure_slip_confirmed_by_simulation() -> None:
    nu = 0.97
    p = DimensionlessParameters(nu=nu, law=CUBIC)
    r = cycle(p)
    assert r.regime == "pure-slip"
    traj = simulate(p, duration=r.transient_time + 5 * r.period, n_points=20001)
    late = traj.time > r.transient_time
    assert np.all(traj.phase[late] == 1)
    assert np.ptp(traj.spring_force[late]) == pytest.approx(r.amplitude, rel=1e-4)
    assert traj.velocity[late].min() == pytest.approx(r.min_velocity, rel=1e-3)


def test_criterion_holds_for_the_cubic_law() -> None:
    """Amplitude rises with nu in stick-slip and falls with nu in pure slip (Thomsen-Fidlin)."""
    stick = [cycle(DimensionlessParameters(nu=nu, law=CUBIC)) for nu in (0.3, 0.5, 0.7)]
    pure = [cycle(DimensionlessParameters(nu=nu, law=CUBIC)) for nu in (0.95, 0.97, 0.99)]
    assert [r.regime for r in stick] == ["stick-slip"] * 3
    assert [r.regime for r in pure] == ["pure-slip"] * 3
    assert np.all(np.diff([r.amplitude for r in stick]) > 0)
    assert np.all(np.diff([r.amplitude for r in pure]) < 0)


def test_bistability_subcritical_f2() -> None:
    """F2 has f''' < 0: past its Hopf point steady sliding is stable, yet stick-slip survives."""
    c, p = 3.8, 0.5
    nu_hopf = (math.sqrt(c / p) - 1) / c
    nu = 0.5
    assert nu > nu_hopf
    params = DimensionlessParameters(nu=nu, law=WeakeningLaw(c=c, p=p))
    r = cycle(params)
    assert r.regime == "stick-slip"
    assert r.steady_sliding_stable
    assert r.multistable
    assert {a.regime for a in r.attractors} == {"stick-slip", "steady-sliding"}
    # both attractors by direct simulation: from rest it sticks for ever ...
    traj = simulate(params, cycles=6, n_points=4001)
    late = traj.time > traj.time[-1] / 2
    assert (traj.phase[late] == 0).any()
    # ... and a small push off steady sliding dies away
    f_nu = 1 / (1 + c * nu) + p * nu
    traj = simulate(params, duration=400.0, n_points=401, initial=(f_nu + 1e-3, nu))
    assert np.all(traj.phase == 1)
    # near the Hopf point the decay rate f'(nu)/2 is small: by t = 400 the 1e-3 push is < 1e-6
    assert abs(traj.spring_force[-1] - f_nu) < 1e-6
    assert abs(traj.velocity[-1] - nu) < 1e-6


def test_unstable_steady_sliding_is_left() -> None:
    """Below the Hopf point of F2 a push off steady sliding grows into stick-slip."""
    params = DimensionlessParameters(nu=0.3, law=WeakeningLaw(c=3.8, p=0.5))
    r = cycle(params)
    assert not r.steady_sliding_stable
    assert [a.regime for a in r.attractors] == ["stick-slip"]


def test_driving_velocities_below_resolution_and_map_ranges_are_refused(tmp_path) -> None:
    """Driving velocities below NU_MIN = 1e-15 are refused: at nu = 1e-20 the amplitude comes
    out 3e-4 off with status ok, and a subnormal nu stalls the compiled loop beyond SIGTERM's
    reach. regimes over nu < 1e-7 works (its Hopf window stays in range); --map refuses a
    reversed range, one value and --map-n 1, each named by its option."""
    from click.testing import CliRunner

    from stickslip.bifurcation.regimes import regimes
    from stickslip.cli import main

    law = WeakeningLaw(c=3.81, p=0.0)
    for nu in (1e-20, 5e-324):
        with pytest.raises(ValueError, match="expected a driving velocity of at least 1e-15"):
            DimensionlessParameters(nu=nu, law=law)
    # 1e-15 is resolved: the amplitude of the small-nu limit, 1.20879911609 (independent SciPy)
    amplitude = cycle(DimensionlessParameters(nu=1e-15, law=law)).amplitude
    assert amplitude == pytest.approx(1.20879911609, rel=1e-9)
    with pytest.raises(ValueError, match="nu_min=1e-310: expected a driving velocity of at least 1e-15"):
        regimes(WeakeningLaw(c=3.8, p=0.5), 1e-310, 1.0)
    low = regimes(WeakeningLaw(c=3.8, p=0.5), 1e-9, 1e-7)
    assert [iv.regime for iv in low.intervals] == ["stick-slip"]
    base = ["regimes", "--c", "3.8", "--p", "0.5", "--nu-min", "0.1", "--nu-max", "1"]
    for extra, said in (
        (["--map", "p=1.5..0.05"], "expected A < B"),
        (["--map", "p=0.1"], "expected a range NAME=A..B"),
        (["--map", "p=0.1..0.1"], "expected A < B"),
        (["--map", "p=0.1..1", "--map-n", "1"], "--map-n=1: a map needs at least 2 values"),
    ):
        res = CliRunner().invoke(main, [*base, *extra, "--out", str(tmp_path)])
        assert res.exit_code == 2 and said in res.output, (extra, res.output)


def test_a_law_parameter_beyond_the_kernels_range_is_named() -> None:
    """A law parameter beyond the kernels' 1e15 is refused by its own name (c), not the core's (lp[0])."""
    with pytest.raises(ValueError, match=r"c=1e\+300 is beyond 1e\+15 in magnitude"):
        WeakeningLaw(c=1e300, p=0.5)
    assert WeakeningLaw(c=1e12, p=0.0).params["c"] == 1e12
