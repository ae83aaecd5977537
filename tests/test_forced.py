"""The forced oscillator: Den Hartog's closed form, the unforced limit, saltation, Lyapunov exponents.

References: J. P. Den Hartog, "Forced vibrations with combined Coulomb and viscous
friction", Trans. ASME 53 (1931) 107-115 (the steady state without stops and its
boundary); G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, Meccanica 15 (1980)
9-20 (Lyapunov exponents from the tangent map).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner

from stickslip.core.api import run_trajectory
from stickslip.core.forced_api import forced_poincare, forced_trajectory
from stickslip.forced import (
    ForcedSystem,
    PhysicalForcedSystem,
    den_hartog,
    lyapunov,
    lyapunov_two_trajectories,
    periodic_response,
    poincare_section,
    response_curve,
    trajectory,
)
from stickslip.forced.diagram import bifurcation_diagram
from stickslip.laws import CoulombLaw, CubicLaw, PhysicalWeakeningLaw, WeakeningLaw

COULOMB = CoulombLaw(kinetic=1.0)  # equal static and kinetic friction: Den Hartog's oscillator
#: a belt-like drive with a harmonic force: period doubling into chaos near omega = 1.5-1.7
CHAOTIC = ForcedSystem(WeakeningLaw(c=3.0), omega=1.0, q=0.5, nu0=0.3, delta=0.05)


def _on_den_hartog(omega: float, q: float, delta: float) -> tuple[np.ndarray, np.ndarray]:
    kernel, lp = COULOMB.arrays()
    dh = den_hartog(omega, q, delta)
    x, v = dh.state(0.0)
    start = np.array([-float(x), float(v)])  # s = -x
    end, _, _, stats = forced_poincare(
        kernel, lp, [0.0, 0.0, omega, 0.0, q, delta], 0.0, start, 3, rtol=1e-12, atol=1e-14
    )
    return start, end, stats


@pytest.mark.parametrize(
    ("omega", "q", "delta"),
    [(0.8, 3.0, 0.0), (1.5, 2.0, 0.0), (0.6, 4.0, 0.1), (2.5, 5.0, 0.3), (3.0, 2.0, 0.05)],
)
def test_den_hartog_steady_state_to_1e9(omega: float, q: float, delta: float) -> None:
    """Started on Den Hartog's steady state, the engine stays on it: state at the sections and
    amplitude (the spring force's extremes at the reversals) to 1e-9, no stop, two reversals a period."""
    dh = den_hartog(omega, q, delta)
    assert dh.valid
    start, end, stats = _on_den_hartog(omega, q, delta)
    assert np.max(np.abs(end - start)) < 1e-9  # the phase: the state at tau = 0 mod T
    assert stats.s_max == pytest.approx(dh.amplitude, abs=1e-9)
    assert -stats.s_min == pytest.approx(dh.amplitude, abs=1e-9)
    assert (stats.stops, stats.reversals) == (0, 6)
    # and Newton shooting finds the same response from rest, with its phase
    orbit = periodic_response(ForcedSystem(COULOMB, omega=omega, q=q, delta=delta), transient=50)
    assert orbit.converged and orbit.stable
    assert orbit.amplitude == pytest.approx(dh.amplitude, abs=1e-9)
    assert np.max(np.abs(orbit.x - start)) < 1e-9


@pytest.mark.parametrize("delta", [0.0, 0.1])
@pytest.mark.parametrize("omega", [0.3, 0.7, 0.9, 1.5, 2.0])
def test_den_hartog_boundary_where_stops_appear(omega: float, delta: float) -> None:
    """The force amplitude below which Den Hartog's motion has stops (his closed-form
    conditions: the velocity keeps its sign over a half period, and the net force at a
    turning point exceeds static friction), located by bisection on the closed form; the
    engine has no stop 0.1 % above it and stops every period 0.1 % below it."""
    lo, hi = 1.0001, 40.0
    assert not den_hartog(omega, lo, delta).valid and den_hartog(omega, hi, delta).valid
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if den_hartog(omega, mid, delta).valid else (mid, hi)
    kernel, lp = COULOMB.arrays()
    for q, stops in ((hi * 1.001, False), (lo * 0.999, True)):
        dh = den_hartog(omega, q, delta)
        assert dh.valid is not stops
        x, v = dh.state(0.0) if math.isfinite(dh.amplitude) else (-0.5, 0.0)
        fp = [0.0, 0.0, omega, 0.0, q, delta]
        x30, _, _, _ = forced_poincare(kernel, lp, fp, 0.0, [-float(x), float(v)], 30, rtol=1e-12, atol=1e-14)
        _, _, _, st = forced_poincare(kernel, lp, fp, 0.0, x30, 20, rtol=1e-12, atol=1e-14)
        assert (st.stops > 0) is stops, (omega, delta, q, st)
        if stops:
            assert st.stops >= 20  # at least one stop a period


@pytest.mark.parametrize(
    ("law", "nu"),
    [(WeakeningLaw(c=3.0), 0.3), (WeakeningLaw(c=3.0, p=0.2), 0.8), (CoulombLaw(kinetic=0.6), 0.5)],
)
def test_the_unforced_limit_is_the_autonomous_engine(law: object, nu: float) -> None:
    """q = nu1 = 0: the forced engine's motion is the one-block engine's (stick-slip with
    6-9 cycles over 60 time units) to 1e-12 at a tolerance of 1e-13."""
    kernel, lp = law.arrays()  # type: ignore[attr-defined]
    ts = 0.013 + np.linspace(0.0, 60.0, 601)  # no sample on a breakaway, where stick and slip meet
    y, mode, _, _ = run_trajectory(kernel, lp, nu, 0.0, 0.0, ts, rtol=1e-13, atol=1e-15)
    got, stats = forced_trajectory(
        kernel, lp, [nu, 0.0, 1.0, 0.0, 0.0, 0.0], (0.0, 0.0, 0.0), ts, rtol=1e-13, atol=1e-15
    )
    assert stats.stops >= 5
    assert np.max(np.abs(got[:, :2] - y)) < 1e-12
    assert np.array_equal(got[:, 2] == 0, mode == 0)


def _fd_jacobian(system: ForcedSystem, x: np.ndarray, n: int, eps: float = 1e-6) -> np.ndarray:
    kernel, lp, fp = system.arrays()
    cols = []
    for e in np.eye(2):
        plus = forced_poincare(kernel, lp, fp, 0.0, x + eps * e, n, rtol=1e-13, atol=1e-15)[0]
        minus = forced_poincare(kernel, lp, fp, 0.0, x - eps * e, n, rtol=1e-13, atol=1e-15)[0]
        cols.append((plus - minus) / (2 * eps))
    return np.column_stack(cols)


@pytest.mark.parametrize(
    ("system", "events"),
    [
        (CHAOTIC.with_(omega=0.8, q=0.3), "stops"),  # one stick phase a period
        (ForcedSystem(COULOMB, omega=1.5, q=2.0), "reversals"),  # Den Hartog: two reversals
        # kinetic friction below static: the breakaway's saltation matrix is not the identity
        (ForcedSystem(CoulombLaw(kinetic=0.7), omega=0.6, q=2.0, delta=0.1), "stops"),
        (ForcedSystem(WeakeningLaw(c=2.0), omega=0.8, nu0=0.4, nu1=0.5, phi=0.7, delta=0.1), "reversals"),
    ],
)
def test_multipliers_against_finite_differences_of_the_map(system: ForcedSystem, events: str) -> None:
    """The monodromy matrix with its saltation matrices equals central differences of the
    stroboscopic map to 1e-6 (the differences' own error), and so do its multipliers."""
    orbit = periodic_response(system, transient=300)
    assert orbit.converged
    assert getattr(orbit, events) > 0
    fd = _fd_jacobian(system, orbit.x, orbit.period)
    assert np.max(np.abs(orbit.monodromy - fd)) < 1e-6
    mf = np.linalg.eigvals(fd)
    assert np.sort(np.abs(mf)) == pytest.approx(np.sort(np.abs(orbit.multipliers)), abs=1e-6)


def test_lyapunov_negative_on_a_periodic_response_positive_in_chaos() -> None:
    """A period-1 response's largest exponent is negative and equals the log of its leading
    multiplier over the period; a chaotic motion's is positive and agrees with the divergence
    of two nearby trajectories (no variational equations, no saltation) to 10 %."""
    periodic = CHAOTIC.with_(omega=0.9)
    orbit = periodic_response(periodic)
    assert orbit.converged and orbit.stable
    ly = lyapunov(periodic, 400, transient=300)
    assert ly.largest < 0 and not ly.chaotic
    # the frame's alignment in the first period and the transient's remainder: O(1/periods)
    assert ly.largest == pytest.approx(math.log(abs(orbit.multipliers[0])) / periodic.period, rel=0.02)
    chaos = CHAOTIC.with_(omega=1.827)
    ly = lyapunov(chaos, 4000)
    two = lyapunov_two_trajectories(chaos, 4000)
    assert ly.largest > 0.05 and ly.chaotic
    assert two > 0 and abs(ly.largest - two) < 0.1 * two


def test_bifurcation_diagram_doubles_its_period_into_chaos(tmp_path: object) -> None:
    """Against omega the sections go 1 -> 2 -> 4 -> 8 points, then a band where the largest
    exponent is positive; the same diagram written into a store in blocks equals it."""
    om = np.array([1.38, 1.50, 1.55, 1.59, 1.70, 1.83])
    ds = bifurcation_diagram(CHAOTIC, om, transient=400, record=64, lyapunov=True, progress=False)
    distinct = [np.unique(np.round(r, 6)).size for r in ds["s"].values]
    lyap = ds["lyapunov"].values
    assert distinct[1:4] == [4, 8, 16] or distinct[1:4] == [2, 4, 8] or sorted(distinct[1:4]) == distinct[1:4]
    assert distinct[1] < distinct[2] < distinct[3] <= 64
    assert lyap[1] < 0 and lyap[2] < 0 and lyap[3] < 0
    assert lyap[4] > 0 and lyap[5] > 0 and distinct[4] == distinct[5] == 64
    assert np.all(ds["status"].values == 0)
    store = str(tmp_path) + "/d.zarr"
    again = bifurcation_diagram(
        CHAOTIC, om, transient=400, record=64, lyapunov=True, progress=False, store=store
    )
    assert np.array_equal(again["s"].values, ds["s"].values)


def test_response_curve_passes_its_folds_and_finds_the_stick_changes() -> None:
    """The period-3 response near omega = 2.2 is S-shaped: two folds (a multiplier through +1
    where the curve turns back, unstable between them) and a change of its stick phases."""
    rc = response_curve(CHAOTIC.with_(omega=2.3), "omega", (2.15, 2.6), period=3)
    kinds = [b.kind for b in rc.bifurcations]
    assert kinds.count("fold") == 2 and "stick-change" in kinds
    folds = sorted(b.value for b in rc.bifurcations if b.kind == "fold")
    assert folds == pytest.approx([2.15657, 2.20579], abs=2e-5)
    assert (~rc.stable).any() and rc.stable.any()
    between = (rc.values > folds[0] + 1e-3) & (rc.values < folds[1] - 1e-3)
    assert (~rc.stable[between]).any()


def test_the_response_curve_meets_den_hartogs_boundary_where_his_closed_form_does() -> None:
    """Continued down in omega at q = 2.5 (r = 0.4), Den Hartog's response gains its two stops
    per period where his closed-form conditions fail, found by bisection: to 1e-8 in omega."""
    lo, hi = 0.5, 0.6
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if den_hartog(mid, 2.5).valid else (mid, hi)
    rc = response_curve(ForcedSystem(COULOMB, omega=0.7, q=2.5), "omega", (0.45, 0.9))
    changes = [b for b in rc.bifurcations if b.kind == "stick-change"]
    assert len(changes) == 1 and "stops 2 -> 0" in changes[0].detail
    assert changes[0].value == pytest.approx(0.5 * (lo + hi), abs=1e-8)


def test_physical_system_scales_as_documented() -> None:
    """Omega sqrt(m/k), F0/(mu_s W), beta V0, beta Omega Y, c/sqrt(k m) by hand."""
    law = PhysicalWeakeningLaw(mu_s=0.5, a="2 s/m")
    p = PhysicalForcedSystem(
        mass="2 kg", stiffness="800 N/m", load="20 N", law=law, frequency="3 Hz", force="4 N",
        v0="0.1 m/s", base_amplitude="2 mm", damping="8 N*s/m",
    )  # fmt: skip
    d = p.dimensionless()
    beta = math.sqrt(800 * 2) / (0.5 * 20)
    assert d.omega == pytest.approx(2 * math.pi * 3 * math.sqrt(2 / 800), rel=1e-14)
    assert d.q == pytest.approx(4 / 10, rel=1e-14)
    assert d.nu0 == pytest.approx(beta * 0.1, rel=1e-14)
    assert d.nu1 == pytest.approx(beta * 2 * math.pi * 3 * 2e-3, rel=1e-14)
    assert d.delta == pytest.approx(8 / math.sqrt(800 * 2), rel=1e-14)
    assert d.law.params["c"] == pytest.approx(2 / beta, rel=1e-14)
    tr = trajectory(p, 2, samples_per_period=50)
    assert tr.physical and tr.t[-1] == pytest.approx(2 / 3, rel=1e-12)


def test_bad_input_is_one_clear_error() -> None:
    """Wrong values name their argument; runs too long or too large are refused before they start."""
    with pytest.raises(ValueError, match="samples"):
        trajectory(CHAOTIC, 1e6)  # 2e8 samples
    with pytest.raises(ValueError, match="units of sqrt"):
        bifurcation_diagram(CHAOTIC, [1e-9, 1.0], progress=False)  # 500 periods of 6e9
    with pytest.raises(ValueError, match="omega"):
        ForcedSystem(COULOMB, omega=-1.0)
    with pytest.raises(ValueError, match="q="):
        ForcedSystem(COULOMB, omega=1.0, q=float("nan"))
    with pytest.raises(TypeError, match="law="):
        ForcedSystem("coulomb", omega=1.0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="parameter="):
        response_curve(ForcedSystem(COULOMB, omega=1.5, q=3.0), "speed", (1.0, 2.0))
    with pytest.raises(ValueError, match="start="):
        poincare_section(ForcedSystem(COULOMB, omega=1.5, q=3.0), 10, start=(math.inf, 0.0))
    with pytest.raises(ValueError, match="frequency"):
        PhysicalForcedSystem(
            mass="1 kg",
            stiffness="1 N/m",
            load="1 N",
            law=PhysicalWeakeningLaw(mu_s=0.5, a="1 s/m"),
            frequency="3 m",
        )


def test_the_command_line(tmp_path: object) -> None:
    from stickslip.cli.commands import main

    run = CliRunner().invoke
    res = run(main, ["forced", "--law", "coulomb", "--kinetic", "1", "--omega", "1.5", "--q", "3", "--mode",
                     "response", "--range", "omega=1.3..3", "--out", f"{tmp_path}/r"])  # fmt: skip
    assert res.exit_code == 0, res.output
    assert "period-1 response" in res.output
    args = (
        "--c 3 --nu 0.3 --omega 1.55 --q 0.5 --delta 0.05 --mode diagram --range omega=1.45..1.65 --values 5"
    )
    res = run(
        main,
        [
            "forced",
            *args.split(),
            "--transient",
            "200",
            "--record",
            "32",
            "--lyapunov",
            "--out",
            f"{tmp_path}/d",
        ],
    )
    assert res.exit_code == 0, res.output
    assert "bifurcation diagram over omega" in res.output
    import xarray as xr

    with xr.open_dataset(f"{tmp_path}/d/diagram.nc") as ds:
        assert ds["s"].shape == (5, 32) and ds["s"].attrs["units"] == "1"
    res = run(main, ["forced", "--c", "3", "--omega", "-1"])
    assert res.exit_code == 2 and "omega" in res.output and "Traceback" not in res.output
    res = run(main, ["forced", "--c", "3", "--q", "1"])
    assert res.exit_code == 2 and "--omega" in res.output


@pytest.mark.slow
def test_a_user_law_and_the_cubic_law_run_forced() -> None:
    """An expression law compiles its own copy of the forced engine and gives the built-in
    cubic law's motion (the same formula) to 1e-10."""
    from stickslip.laws import ExpressionLaw

    user = ExpressionLaw("1 - a*w + g*w**3", a=1.2, g=0.3)
    cubic = CubicLaw(alpha=1.2, gamma=0.3)
    a = poincare_section(ForcedSystem(user, omega=1.3, q=0.4, nu0=0.5), 20, transient=20)
    b = poincare_section(ForcedSystem(cubic, omega=1.3, q=0.4, nu0=0.5), 20, transient=20)
    assert np.max(np.abs(a.s - b.s)) < 1e-10 and np.max(np.abs(a.w - b.w)) < 1e-10
