"""The compiled engine against the independent plain-SciPy implementation."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from reference.one_block import reference_cycle

from stickslip import CoulombLaw, CubicLaw, DimensionlessParameters, WeakeningLaw, cycle
from stickslip.core.api import run_attractors

RTOL = 1e-10


def _agree(law_name: str, law_params: dict, law: object, nu: float) -> None:
    ref = reference_cycle(law_name, law_params, nu)
    r = cycle(
        DimensionlessParameters(nu=nu, law=law),
        rtol=1e-13,
        atol=1e-15,  # type: ignore[arg-type]
        probe=False,
    )
    assert r.regime == "stick-slip"
    assert r.amplitude == pytest.approx(ref.amplitude, rel=RTOL)
    # the stick time (1 - s_stop)/nu turns an absolute error of the stop force (about
    # 1e-13 at these tolerances) into 1e-13/nu of period: ill-conditioned when the
    # amplitude is tiny (c = 1, nu = 1e-5: 1 - s_stop = 1.2e-4), so that term is allowed
    assert r.period == pytest.approx(ref.period, rel=RTOL, abs=1e-13 / nu)
    assert r.peak_velocity == pytest.approx(ref.w_max, rel=RTOL)
    assert r.backward_slips == ref.n_backward


@given(
    nu=st.floats(1e-5, 0.5),
    c=st.floats(0.5, 50.0),
)
def test_f1_matches_scipy(nu: float, c: float) -> None:
    _agree("weakening", {"c": c}, WeakeningLaw(c=c), nu)


@given(
    nu=st.floats(1e-4, 0.3),
    c=st.floats(1.0, 20.0),
    ratio=st.floats(0.05, 0.6),
)
def test_f2_matches_scipy(nu: float, c: float, ratio: float) -> None:
    # keep p below the value at which nu would be past the Hopf point
    p = ratio * c / (1 + c * nu) ** 2
    _agree("weakening", {"c": c, "p": p}, WeakeningLaw(c=c, p=p), nu)


@given(
    nu=st.floats(1e-4, 0.2),
    alpha=st.floats(0.1, 1.0),
    gamma=st.floats(0.01, 0.3),
)
def test_cubic_matches_scipy(nu: float, alpha: float, gamma: float) -> None:
    _agree("cubic", {"alpha": alpha, "gamma": gamma}, CubicLaw(alpha=alpha, gamma=gamma), nu)


@given(nu=st.floats(1e-4, 1.0), fk=st.floats(0.01, 0.95))
def test_coulomb_matches_scipy(nu: float, fk: float) -> None:
    _agree("coulomb", {"kinetic": fk}, CoulombLaw(kinetic=fk), nu)


@pytest.mark.parametrize("nu", [1e-7, 1e-6])
def test_tiny_driving_velocity(nu: float) -> None:
    _agree("weakening", {"c": 3.8}, WeakeningLaw(c=3.8), nu)


@pytest.mark.parametrize("c", [100.0, 1000.0])
def test_steep_weakening(c: float) -> None:
    _agree("weakening", {"c": c}, WeakeningLaw(c=c), 1e-3)


def test_backward_slip_cycle_matches_scipy() -> None:
    """At nu = 1, c = 3.8 the block overshoots on its stop and slips backward once per cycle."""
    ref = reference_cycle("weakening", {"c": 3.8}, 1.0)
    assert ref.n_backward == 1
    _agree("weakening", {"c": 3.8}, WeakeningLaw(c=3.8), 1.0)


def test_batch_equals_single_calls() -> None:
    rng = np.random.default_rng(3)
    n = 64
    nu = 10 ** rng.uniform(-5, -1, n)
    c = rng.uniform(0.5, 50, n)
    lp = np.zeros((n, 3))
    lp[:, 0] = c
    batch = run_attractors(
        0, lp, nu, from_breakaway=True, rtol=1e-10, atol=1e-12, max_slip_time=1e4, conv_tol=1e-8
    )
    for i in range(0, n, 7):
        r = cycle(
            DimensionlessParameters(nu=nu[i], law=WeakeningLaw(c=c[i])), rtol=1e-10, atol=1e-12, probe=False
        )
        assert batch.amplitude[i] == r.amplitude
        assert batch.period[i] == r.period


def test_small_mass_f2_amplitude_falls_with_v0() -> None:
    """The reproduction report says F2 (b = 100 s/m) at m = 1 g is stick-slip with an amplitude
    that falls with v0: the independent SciPy reference says the same."""
    import stickslip as S

    amps = []
    for v in ("5 um/s", "1000 um/s"):
        p = S.PhysicalParameters(
            mass="1 g", stiffness="62 N/m", load="196 mN", v0=v, law=S.f2(0.46, "160 s/m", "100 s/m")
        )
        # the dimensionless form by hand (PHYSICS.md §1), not by the code under test
        force = 0.46 * 0.196
        beta = (62.0 * 1e-3) ** 0.5 / force
        v0 = float(v.split()[0]) * 1e-6
        ref = reference_cycle("weakening", {"c": 160.0 / beta, "p": 100.0 / beta}, beta * v0)
        assert S.cycle(p, probe=False).amplitude / force == pytest.approx(ref.amplitude, rel=1e-8)
        amps.append(ref.amplitude)
    assert amps[1] < amps[0]


def test_the_engines_own_convergence_test_near_a_hopf_point() -> None:
    """The attractor kernel stops when the amplitude has settled to conv_tol, the geometric
    tail of its changes included: near a Hopf point the cycle is weakly attracting (multiplier
    0.88 at nu = 0.98, 0.994 at 0.999) and a change below conv_tol still leaves up to 1/(1 - r)
    of it to come. Without shooting's polish, the raw kernel against plain SciPy shooting
    (without the tail: 7e-8 and 1.6e-6 off)."""
    from reference.one_block import cubic_orbit_reference

    alpha, gamma = 0.5, 0.5 / 3
    for nu in (0.98, 0.999):
        ref = cubic_orbit_reference(nu, alpha, gamma)
        rows = run_attractors(
            1, np.array([alpha, gamma, 0.0]), np.array([nu]), np.array([1.5]), np.array([nu]),
            from_breakaway=False, rtol=1e-12, atol=1e-14, max_slip_time=1e7, conv_tol=1e-8,
        )  # fmt: skip
        assert rows.status[0] == 0 and rows.regime[0] == 1  # ok, pure slip
        assert rows.amplitude[0] == pytest.approx(ref.amplitude, rel=3e-8), nu
