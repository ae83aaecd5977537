"""The forced oscillator's compiled engine against an independent SciPy reference.

The reference (``benchmarks/bench_forced.py``, :func:`reference_strobe`) is written from
the model alone: slip phases by ``solve_ivp`` (DOP853, rtol = atol = 1e-12) with a
terminal event where ``d w`` falls through 0, the stop rule ``|s + q cos(omega t)| <= 1``
(stick) or else a reversal, and stick in closed form with its breakaway found by
``brentq`` after a scan of a grid of 4000 points per period for the first crossing of
``|s + q cos(omega t)| = 1``. The engine runs at rtol 1e-12, atol 1e-14.

Measured over the 10 periods compared here (2 cores, x86_64): the sections agree to
1e-12 (Coulomb, weakening at omega = 0.8) and to 1.6e-10 and 3.8e-10 where the motion
is chaotic (weakening at omega = 1.3; the modulated drive, largest Lyapunov exponent
0.05-0.065 per unit time). There the difference is the reference's own error: the
reference at rtol 1e-13 moves by 2.6e-10 and 4.2e-10, while the engine at 1e-13 and the
reference at 1e-13 agree to 5e-12. ``TOL = 1e-8`` leaves a factor of 25 over the
largest measured difference; a misplaced event (an error of the order of a step times
the velocity, ~1e-3) or a wrong transition rule is many orders of magnitude larger. The
stop, breakaway and reversal counts must be equal.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from stickslip.core.forced_api import forced_poincare, forced_strobe
from stickslip.forced import ForcedSystem
from stickslip.laws import CoulombLaw, WeakeningLaw

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from bench_forced import coulomb_fplus, reference_strobe, weakening_fplus

#: largest difference of the stroboscopic states allowed (module docstring: 25 x the measured 3.8e-10)
TOL = 1e-8
#: stick time: the same events located by both, to the same tolerance
TOL_STICK_TIME = 1e-8
PERIODS = 10
ENGINE = {"rtol": 1e-12, "atol": 1e-14}


def weakening(omega: float, **kw: float) -> ForcedSystem:
    """Return the example system ``f_+ = 1/(1 + 3 w)``, ``q = 0.5``, ``nu0 = 0.3``, ``delta = 0.05``."""
    args = {"q": 0.5, "nu0": 0.3, "delta": 0.05, **kw}
    return ForcedSystem(WeakeningLaw(c=3.0), omega=omega, **args)


CASES = {
    # a period-2 orbit on the attractor, stuck once every two periods, with reversals
    "weakening-omega0.8": (weakening(0.8), weakening_fplus(3.0)),
    # chaotic (largest Lyapunov exponent 0.065 per unit time): sticks and reversals
    "weakening-omega1.3": (weakening(1.3), weakening_fplus(3.0)),
    # the drive's velocity modulated, no external force
    "modulated-drive": (weakening(1.0, q=0.0, nu1=0.2, phi=0.7), weakening_fplus(3.0)),
    # Coulomb friction, kinetic 0.7, Den Hartog's fixed spring end: a stick in every half period
    "coulomb": (
        ForcedSystem(CoulombLaw(kinetic=0.7), omega=0.6, q=2.0, nu0=0.0, delta=0.1),
        coulomb_fplus(0.7),
    ),
}


def compare(system: ForcedSystem, fplus, x0: tuple[float, float], periods: int = PERIODS) -> dict:
    """Run both from ``x0`` at phase 0; return the differences and both runs' event counts."""
    kernel, lp, fp = system.arrays()
    eng, _, stats = forced_strobe(kernel, lp, fp, x0, 0, periods, **ENGINE)
    eng, stats = eng[0], stats[0]
    ref, counts = reference_strobe(fplus, tuple(fp), x0, periods)
    return {
        "engine": eng,
        "reference": ref,
        "diff": float(np.max(np.abs(eng - ref))),
        "engine_counts": tuple(int(stats[i]) for i in (0, 1, 2)),
        "reference_counts": (counts.stops, counts.breakaways, counts.reversals),
        "stick_time": (float(stats[3]), counts.stick_time),
        "touches": (int(stats[11]), counts.touches),
    }


def check(r: dict) -> None:
    assert r["engine_counts"] == r["reference_counts"], r
    assert r["touches"] == (0, 0), r
    assert np.all(np.isfinite(r["engine"])), r
    assert r["diff"] <= TOL, r
    assert abs(r["stick_time"][0] - r["stick_time"][1]) <= TOL_STICK_TIME, r


@pytest.mark.parametrize(
    "name",
    [
        pytest.param(n, marks=pytest.mark.slow) if n == "coulomb" else n for n in CASES
    ],  # coulomb: on the attractor too
)
def test_sections_and_events_from_rest(name: str) -> None:
    system, fplus = CASES[name]
    r = compare(system, fplus, (0.0, 0.0))
    check(r)
    stops, breakaways, reversals = r["reference_counts"]
    # every case exercises stick, breakaway and reversal
    assert stops >= 4 and breakaways >= 4 and reversals >= 3, r


@pytest.mark.parametrize("name", ["weakening-omega0.8", "weakening-omega1.3", "coulomb"])
def test_sections_on_the_attractor(name: str) -> None:
    # from the section after 200 periods, as a bifurcation diagram records them
    system, fplus = CASES[name]
    kernel, lp, fp = system.arrays()
    x, _, _, _ = forced_poincare(kernel, lp, fp, 0.0, (0.0, 0.0), 200, **ENGINE)
    r = compare(system, fplus, (float(x[0]), float(x[1])))
    check(r)
    assert r["reference_counts"][0] >= PERIODS // 2, r


def test_period_two_orbit_sticks_every_other_period() -> None:
    # omega = 0.8: on the attractor the sections alternate between two points; one of the two
    # periods has a stick phase (0.218 of the time unit), the other only reversals
    system, fplus = CASES["weakening-omega0.8"]
    kernel, lp, fp = system.arrays()
    x, _, _, _ = forced_poincare(kernel, lp, fp, 0.0, (0.0, 0.0), 200, **ENGINE)
    ref, counts = reference_strobe(fplus, tuple(fp), (float(x[0]), float(x[1])), 4)
    assert np.max(np.abs(ref[2:] - ref[:2])) < 1e-8
    assert np.max(np.abs(ref[1] - ref[0])) > 0.1
    assert counts.stops == 2 and counts.breakaways == 2


def test_poincare_matches_strobe() -> None:
    # the map applied 10 times and the 10th section of the strobe are one computation
    system, _ = CASES["modulated-drive"]
    kernel, lp, fp = system.arrays()
    x, _, _, stats = forced_poincare(kernel, lp, fp, 0.0, (0.0, 0.0), PERIODS, **ENGINE)
    eng, _, st = forced_strobe(kernel, lp, fp, (0.0, 0.0), 0, PERIODS, **ENGINE)
    assert np.array_equal(x, eng[0, -1])
    assert (stats.stops, stats.breakaways, stats.reversals) == tuple(int(v) for v in st[0, :3])


@pytest.mark.slow
def test_radau_reference_agrees() -> None:
    # an implicit method for the reference's slip phases: the same sections and events
    system, fplus = CASES["coulomb"]
    kernel, lp, fp = system.arrays()
    eng, _, stats = forced_strobe(kernel, lp, fp, (0.0, 0.0), 0, PERIODS, **ENGINE)
    ref, counts = reference_strobe(fplus, tuple(fp), (0.0, 0.0), PERIODS, method="Radau")
    assert np.max(np.abs(eng[0] - ref)) <= TOL
    assert (counts.stops, counts.breakaways, counts.reversals) == tuple(int(v) for v in stats[0, :3])
