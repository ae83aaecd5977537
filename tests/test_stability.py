"""Hopf points and criticality, cross-checked against the orbits the engine finds."""

import math

import pytest

from stickslip import CoulombLaw, CubicLaw, DimensionlessParameters, WeakeningLaw, cycle
from stickslip.orbits.stability import averaged_amplitude, hopf_points, steady_sliding_eigenvalues

# every test here is quick: all in the fast tier (pytest -m fast)
pytestmark = pytest.mark.fast


def test_cubic_law_hopf_is_supercritical() -> None:
    law = CubicLaw(alpha=0.5, gamma=0.5 / 3)
    (h,) = hopf_points(law)
    assert h.nu == pytest.approx(math.sqrt(0.5 / (3 * 0.5 / 3)), rel=1e-12)
    assert h.criticality == "supercritical"
    assert h.l1 == pytest.approx(-6 * (0.5 / 3) / 16)
    assert h.stable_side == "above"
    # cross-check: a small stable pure-slip cycle just below, with the averaging amplitude
    for frac in (0.999, 0.99):
        r = cycle(DimensionlessParameters(nu=frac * h.nu, law=law))
        assert r.regime == "pure-slip"
        nu = frac * h.nu
        # Thomsen-Fidlin averaging: a^2 = 4 (alpha - 3 gamma nu^2) / (3 gamma)
        a = math.sqrt(4 * (0.5 - 0.5 * nu**2) / 0.5)
        assert averaged_amplitude(law, nu) == pytest.approx(a, rel=1e-12)
        assert r.amplitude == pytest.approx(2 * a, rel=0.02 if frac < 0.995 else 0.005)
    assert cycle(DimensionlessParameters(nu=1.01 * h.nu, law=law)).regime == "steady-sliding"


def test_f2_hopf_is_subcritical_with_bistability() -> None:
    c, p = 3.8, 0.5
    law = WeakeningLaw(c=c, p=p)
    (h,) = hopf_points(law)
    assert h.nu == pytest.approx((math.sqrt(c / p) - 1) / c, rel=1e-12)
    assert h.criticality == "subcritical"
    assert h.l1 > 0
    # cross-check: no small stable cycle; past the Hopf point stick-slip coexists with sliding
    assert math.isnan(averaged_amplitude(law, 0.99 * h.nu))
    r = cycle(DimensionlessParameters(nu=1.05 * h.nu, law=law))
    assert r.multistable
    assert {a.regime for a in r.attractors} == {"stick-slip", "steady-sliding"}


@pytest.mark.parametrize("law", [WeakeningLaw(c=3.8), CoulombLaw(kinetic=0.3)])
def test_no_hopf_point(law) -> None:
    assert hopf_points(law) == []


def test_eigenvalues() -> None:
    law = WeakeningLaw(c=3.8, p=0.5)
    lam = steady_sliding_eigenvalues(law, 0.3)
    g = -3.8 / (1 + 3.8 * 0.3) ** 2 + 0.5  # f'(0.3) by hand
    assert g == pytest.approx(-0.3297667918595513, rel=1e-15)
    assert sum(lam).real == pytest.approx(-g)
    assert (lam[0] * lam[1]).real == pytest.approx(1.0)
    assert max(x.real for x in lam) > 0  # f'(0.3) < 0: unstable


def test_bad_range() -> None:
    with pytest.raises(ValueError, match="nu_max"):
        hopf_points(WeakeningLaw(c=1.0), 1.0, 0.5)
    with pytest.raises(ValueError, match="nu_min"):
        hopf_points(WeakeningLaw(c=1.0), -1.0, 0.5)
