"""Pure-slip orbits by shooting: against converged transients, Floquet multipliers, averaging."""

import numpy as np
import pytest
from reference.one_block import cubic_orbit_reference

from stickslip import CubicLaw, DimensionlessParameters, WeakeningLaw, simulate
from stickslip.orbits.periodic import pure_slip_orbit
from stickslip.orbits.stability import averaged_amplitude

LAW = CubicLaw(alpha=0.5, gamma=0.5 / 3)  # supercritical Hopf at nu = 1


@pytest.mark.parametrize("nu", [0.995, 0.97, 0.95])
def test_shooting_matches_the_scipy_reference(nu: float) -> None:
    """Compiled shooting against plain SciPy shooting (tests/reference/one_block.py), which shares no code."""
    o = pure_slip_orbit(DimensionlessParameters(nu=nu, law=LAW))
    ref = cubic_orbit_reference(nu, LAW.alpha, LAW.gamma)
    assert o.amplitude == pytest.approx(ref.amplitude, rel=1e-8)
    assert o.period == pytest.approx(ref.period, rel=1e-9)
    assert o.s0 == pytest.approx(ref.s0, rel=1e-9)
    assert o.min_velocity == pytest.approx(ref.w_min, rel=1e-7)
    assert abs(o.multipliers[1]) == pytest.approx(ref.multiplier, rel=1e-7)
    assert o.residual < 1e-10


@pytest.mark.parametrize("nu", [0.999, 0.97])
def test_floquet_multipliers(nu: float) -> None:
    o = pure_slip_orbit(DimensionlessParameters(nu=nu, law=LAW))
    assert abs(o.multipliers[0] - 1.0) < 1e-9  # autonomous: the trivial multiplier
    assert o.multipliers[1].imag == 0.0
    assert o.multipliers[1].real == pytest.approx(o.divergence_multiplier, rel=1e-9)
    assert o.stable and abs(o.multipliers[1]) < 1


def test_stability_confirmed_by_perturbed_simulation() -> None:
    """A push off the orbit decays by the nontrivial multiplier per period."""
    p = DimensionlessParameters(nu=0.97, law=LAW)
    o = pure_slip_orbit(p)
    eps = 1e-4
    n = 5
    traj = simulate(
        p, duration=(n + 0.5) * o.period, n_points=20 * n + 1, initial=(o.s0 + eps, p.nu), rtol=1e-12
    )
    # back on the section w = nu after n periods (phase drifts slightly): compare the deviation
    # of s at w = nu crossings with eps * multiplier**n
    maxima = [
        f
        for t, k, f in zip(traj.event_time, traj.event_kind, traj.event_force, strict=True)
        if k == "force-maximum"
    ]
    dev = maxima[n - 1] - o.s0
    assert dev == pytest.approx(eps * o.multipliers[1].real ** n, rel=0.05)


def test_weakly_nonlinear_limit_order() -> None:
    """Against first-order averaging the error shrinks like the distance to the Hopf point."""
    errs = []
    for d in (0.04, 0.02, 0.01):
        nu = 1.0 - d
        o = pure_slip_orbit(DimensionlessParameters(nu=nu, law=LAW))
        errs.append(abs(o.amplitude / (2 * averaged_amplitude(LAW, nu)) - 1))
    slope = np.polyfit(np.log([0.04, 0.02, 0.01]), np.log(errs), 1)[0]
    assert 0.8 < slope < 1.2, (slope, errs)


def test_grazing_orbit_is_refused() -> None:
    """At 0.85 nu_H there is no pure-slip orbit (the motion sticks): shooting must not invent one."""
    with pytest.raises(RuntimeError, match=r"grazes|did not converge|diverged"):
        pure_slip_orbit(DimensionlessParameters(nu=0.85, law=LAW))


def test_bad_input() -> None:
    with pytest.raises(ValueError, match="no small-cycle guess"):
        pure_slip_orbit(DimensionlessParameters(nu=0.5, law=WeakeningLaw(c=3.8)))
    with pytest.raises(ValueError, match="tol="):
        pure_slip_orbit(DimensionlessParameters(nu=0.97, law=LAW), tol=1.0)
    with pytest.raises(ValueError, match="params="):
        pure_slip_orbit("nu=0.97")  # type: ignore[arg-type]
    for bad in ((1.1,), (1.1, -6.3), ("x", 6.3)):  # (1.1,) was an IndexError
        with pytest.raises(ValueError, match="guess="):
            pure_slip_orbit(DimensionlessParameters(nu=0.97, law=LAW), guess=bad)  # type: ignore[arg-type]
    guessed = pure_slip_orbit(DimensionlessParameters(nu=0.97, law=LAW), guess=(1.1, 6.3))
    assert guessed.period == pytest.approx(cubic_orbit_reference(0.97, LAW.alpha, LAW.gamma).period, rel=1e-9)


def test_trajectories_checked_once_give_run_trajectorys_events() -> None:
    """A return map's runs (law, nu and tolerances checked once, buffers reused) are run_trajectory's."""
    from stickslip.core.api import Trajectories, run_trajectory
    from stickslip.core.memory import UNCHECKED_BYTES, check_memory

    law = WeakeningLaw(c=3.8)
    kernel, lp = law.kernel, np.array(list(law.params.values()))
    runs = Trajectories(kernel, lp, 0.5, rtol=1e-10, atol=1e-12)
    for s0, t_end in ((1.3, 5.0), (0.2, 400.0)):  # a few events; more than the first buffer's 64
        ev, status = runs.events(s0, 0.5, t_end)
        want = run_trajectory(kernel, lp, 0.5, s0, 0.5, [t_end], rtol=1e-10, atol=1e-12)
        np.testing.assert_array_equal(ev, want.events)
        assert status == want.status == "ok"
    assert len(ev) > 64
    with pytest.raises(ValueError, match=r"t_end=nan: expected a time between 0 and 1e\+15"):
        runs.events(1.0, 0.5, float("nan"))
    with pytest.raises(ValueError, match="s0"):
        runs.events(float("inf"), 0.5, 1.0)
    with pytest.raises(ValueError, match="rtol"):
        Trajectories(kernel, lp, 0.5, rtol=0.0, atol=1e-12)
    check_memory(UNCHECKED_BYTES - 1, "a small request")  # not read: small requests pass unchecked
    with pytest.raises(ValueError, match="needs about"):
        check_memory(1e18, "an exabyte")


def test_compiled_return_maps_equal_the_python_secant_bit_for_bit() -> None:
    """Slip-reversal orbits of F1: compiled, many at once (a sweep's polish from 16 rows on), against
    the secant in Python around the engine's trajectories (a cycle's, which compiles nothing more)."""
    from stickslip.core.api import run_attractors, run_return_maps
    from stickslip.core.results import ReturnMapStatus
    from stickslip.orbits.return_map import return_map_orbit_core

    kernel = WeakeningLaw(c=1.0).kernel
    rng = np.random.default_rng(3)
    c, nu = rng.uniform(2.0, 10.0, 400), 10 ** rng.uniform(0.0, 1.3, 400)
    att = run_attractors(kernel, c[:, None], nu, from_breakaway=True, rtol=1e-9, atol=1e-12,
                         max_slip_time=1e4, conv_tol=1e-8)  # fmt: skip
    rev = np.flatnonzero((att.regime == 1) & (att.n_backward > 0))[:12]
    assert rev.size == 12
    got = run_return_maps(kernel, c[rev, None], nu[rev], att.s_max[rev], att.period[rev])
    for j, i in enumerate(rev):
        want = return_map_orbit_core(kernel, np.array([c[i]]), float(nu[i]), (att.s_max[i], att.period[i]))
        assert (got.s0[j], got.period[j], got.multiplier[j], got.residual[j]) == (
            want.s0, want.period, want.multiplier, want.residual,
        )  # fmt: skip
        assert got.status[j] == ReturnMapStatus.OK.code and abs(want.multiplier) < 1.0


def test_a_return_map_that_sticks_says_so() -> None:
    from stickslip.core.api import run_return_maps
    from stickslip.orbits.return_map import return_map_orbit

    law = WeakeningLaw(c=3.8)  # the Python secant and the compiled one say the same
    said = r"return map from s = 1: the motion sticks \(not a non-sticking orbit\)"
    with pytest.raises(RuntimeError, match=said):
        return_map_orbit(law, 0.01, (1.0, 10.0))  # stick-slip at nu = 0.01
    got = run_return_maps(law.kernel, [3.8], [0.01, 0.01], [1.0, 1.0], [10.0, 10.0], max_iter=3)
    assert got.message(1).startswith("return map from s = 1: the motion sticks")
    with pytest.raises(ValueError, match="period"):
        run_return_maps(law.kernel, [3.8], [0.5], [1.0], [-1.0])


def test_a_sweeps_polish_is_the_same_with_its_return_maps_compiled_or_in_python(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from stickslip.core.api import run_attractors
    from stickslip.orbits import attractors

    kernel = WeakeningLaw(c=1.0).kernel
    c, nu = np.linspace(2.0, 10.0, 40), np.geomspace(1.0, 20.0, 40)
    rows = run_attractors(kernel, c[:, None], nu, from_breakaway=True, rtol=1e-9, atol=1e-12,
                          max_slip_time=1e4, conv_tol=1e-8, fields=attractors.POLISH_FIELDS)  # fmt: skip
    assert ((rows.regime == 1) & (rows.n_backward > 0)).sum() >= 16
    monkeypatch.setattr(attractors, "COMPILED_RETURN_MAPS", 16)
    compiled, m_compiled = attractors.polish_rows((kernel, c[:, None]), nu, rows)
    monkeypatch.setattr(attractors, "COMPILED_RETURN_MAPS", 10**9)
    python, m_python = attractors.polish_rows((kernel, c[:, None]), nu, rows)
    np.testing.assert_array_equal(compiled.raw, python.raw)
    np.testing.assert_array_equal(m_compiled, m_python)
    assert np.isfinite(m_python).all()


@pytest.mark.slow
def test_return_maps_refuse_what_the_python_secant_refuses() -> None:
    """The flow's tolerances (tol / 100) and an iterate beyond the states: the same on both paths."""
    from stickslip.core.api import run_return_maps
    from stickslip.core.results import ReturnMapStatus
    from stickslip.orbits.return_map import return_map_orbit_core

    kernel = WeakeningLaw(c=1.0).kernel
    with pytest.raises(ValueError, match=r"rtol=1e-15: expected a relative tolerance between 1e-14"):
        run_return_maps(kernel, [5.9], [4.3], [3.0], [2.0], tol=1e-13)
    with pytest.raises(ValueError, match=r"rtol=1e-15: expected a relative tolerance between 1e-14"):
        return_map_orbit_core(kernel, np.array([5.9]), 4.3, (3.0, 2.0), tol=1e-13)
    # an iterate beyond the states (the guesses are checked: the compiled secant, called directly)
    from stickslip.core import engine
    from stickslip.core.results import ReturnMapRows

    out = np.empty((1, engine.NRM))
    kernel.engine.return_map_orbit(kernel.law_id, np.array([5.9, 0, 0, 0, 0, 0, 0, 0]), 4.3, 2e13, 2.0, 1e-10,
                                   40, out[0])  # fmt: skip
    got = ReturnMapRows(out)
    assert got.status[0] == ReturnMapStatus.LEFT.code
    assert got.message(0) == "return map: the secant iteration left the states the engine takes (s = 2e+13)"
    with pytest.raises(ValueError, match=r"s0\[0\]=20000000000000.0: expected a finite value"):
        run_return_maps(kernel, [5.9], [4.3], [2e13], [2.0])
    with pytest.raises(RuntimeError, match=r"left the states the engine takes \(s = 2e\+13\)"):
        return_map_orbit_core(kernel, np.array([5.9]), 4.3, (2e13, 2.0))
