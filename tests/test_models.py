"""Friction laws (one conformance suite for all) and parameters with units."""

import math

import numpy as np
import pytest

from stickslip import (
    Q_,
    CoulombLaw,
    CubicLaw,
    DimensionlessParameters,
    PhysicalCoulombLaw,
    PhysicalCubicLaw,
    PhysicalParameters,
    PhysicalWeakeningLaw,
    WeakeningLaw,
    f1,
    f2,
    zv_parameters,
)
from stickslip.core.laws import N_LAW_PARAMS

LAWS = [
    WeakeningLaw(c=3.8),
    WeakeningLaw(c=3.8, p=2.38),
    CubicLaw(alpha=0.6, gamma=0.2),
    CoulombLaw(kinetic=0.4),
]
PHYSICAL_LAWS = [
    PhysicalWeakeningLaw(mu0=0.46, a="160 s/m", b="100 s/m"),
    PhysicalCubicLaw(mu_s=0.5, k1="0.8 s/m", k3="0.05 s**3/m**3"),
    PhysicalCoulombLaw(mu_s=0.5, mu_k=0.3),
]
W = np.linspace(1e-3, 3.0, 301)


@pytest.mark.parametrize("law", LAWS, ids=repr)
class TestLawConformance:
    def test_static_threshold_and_kinetic_limit(self, law) -> None:
        assert law.static_threshold == 1.0
        assert 0.0 < law.kinetic_limit <= 1.0

    def test_odd_extension(self, law) -> None:
        np.testing.assert_allclose(law.value(-W), -law.value(W), rtol=1e-15)
        assert law.value(0.0) == 0.0

    def test_matches_compiled_core(self, law) -> None:
        lp = tuple(np.pad(law.core_params(), (0, N_LAW_PARAMS - law.core_params().size)))
        k = law.kernel
        core = np.array([k.engine.f_plus(k.law_id, lp, w) for w in W])
        np.testing.assert_allclose(core, law.value(W), rtol=1e-14)
        dcore = np.array([k.engine.df_plus(k.law_id, lp, w) for w in W])
        np.testing.assert_allclose(dcore, law.derivative(W), rtol=1e-13, atol=1e-14)

    @pytest.mark.parametrize("order", [1, 2, 3])
    def test_derivatives_against_finite_differences(self, law, order: int) -> None:
        h = 1e-4
        w = W[10:-10]
        lower = law.value(w - h) if order == 1 else law.derivative(w - h, order - 1)
        upper = law.value(w + h) if order == 1 else law.derivative(w + h, order - 1)
        fd = (upper - lower) / (2 * h)
        np.testing.assert_allclose(law.derivative(w, order), fd, rtol=1e-6, atol=1e-6)
        # odd law: odd derivatives are even functions, even derivatives odd
        sign = (-1.0) ** (order + 1)
        np.testing.assert_allclose(law.derivative(-w, order), sign * law.derivative(w, order))

    def test_round_trip_through_physical(self, law) -> None:
        beta = Q_(42.0, "s/m")
        back = law.to_physical(beta, 0.46).nondimensionalize(beta)
        assert type(back) is type(law)
        for name, value in law.params.items():
            assert getattr(back, name) == pytest.approx(value, rel=1e-14)


CLOSED_FORMS = [  # the PHYSICAL_LAWS' coefficients, typed here
    lambda v: 0.46 * (1 / (1 + 160 * v) + 100 * v),
    lambda v: 0.5 - 0.8 * v + 0.05 * v**3,
    lambda v: 0.3 + 0 * v,
]


@pytest.mark.parametrize(("plaw", "closed"), list(zip(PHYSICAL_LAWS, CLOSED_FORMS, strict=True)))
def test_physical_law_matches_its_closed_form(plaw, closed) -> None:
    v = np.linspace(1e-4, 0.05, 50)
    np.testing.assert_allclose(plaw.coefficient(Q_(v, "m/s")), closed(v), rtol=1e-13)
    np.testing.assert_allclose(plaw.coefficient(Q_(-v, "m/s")), -closed(v), rtol=1e-13)
    # and through the dimensionless form: mu(v) = mu_s f(beta v)
    beta = Q_(87.0, "s/m")
    w = 87.0 * v
    np.testing.assert_allclose(plaw.mu_s * plaw.nondimensionalize(beta).value(w), closed(v), rtol=1e-13)


@pytest.mark.fast
def test_paper_f1_f2_normalisation() -> None:
    """F2 = mu0 W [1/(1+av) + b v]; with beta = 42 s/m, b = 100 s/m gives p = 2.38 (PHYSICS.md)."""
    law = f2(0.46, "160 s/m", "100 s/m").nondimensionalize(Q_(42.0, "s/m"))
    assert law.p == pytest.approx(2.38, abs=0.005)
    assert law.c == pytest.approx(160 / 42)
    assert f1(0.46, "160 s/m").b.magnitude == 0.0


@pytest.mark.fast
def test_zv_parameters() -> None:
    p = zv_parameters("100 um/s")
    assert p.beta.to("s/m").magnitude == pytest.approx(42.0)
    assert p.mass.to("kg").magnitude == pytest.approx(0.2313, abs=1e-4)
    assert p.nu == pytest.approx(42.0 * 100e-6)
    d = p.dimensionless()
    assert d.law.c == pytest.approx(160 / 42)


@pytest.mark.fast
def test_dimensionless_round_trip() -> None:
    p = PhysicalParameters(
        mass="1 kg", stiffness="62 N/m", load="196 mN", v0="20 um/s", law=f2(0.46, "160 s/m", "100 s/m")
    )
    assert p.beta.to("s/m").magnitude == pytest.approx(math.sqrt(62) / (0.46 * 0.196))
    back = PhysicalParameters.from_dimensionless(
        p.dimensionless(), mass=p.mass, stiffness=p.stiffness, load=p.load, mu_s=0.46
    )
    assert back.v0.to("um/s").magnitude == pytest.approx(20.0)
    assert back.law.a.to("s/m").magnitude == pytest.approx(160.0)
    assert back.law.b.to("s/m").magnitude == pytest.approx(100.0)
    s = p.scales
    assert s.force.to("N").magnitude == pytest.approx(0.46 * 0.196)
    assert s.time.to("s").magnitude == pytest.approx(math.sqrt(1 / 62))
    assert (s.velocity * s.beta).to("").magnitude == pytest.approx(1.0)
    # by hand: length mu_s W / k, velocity mu_s W / sqrt(k m), energy (mu_s W)^2 / k
    assert s.length.to("m").magnitude == pytest.approx(0.46 * 0.196 / 62, rel=1e-12)
    assert s.velocity.to("m/s").magnitude == pytest.approx(0.46 * 0.196 / math.sqrt(62), rel=1e-12)
    assert s.energy.to("J").magnitude == pytest.approx((0.46 * 0.196) ** 2 / 62, rel=1e-12)


GOOD = {"mass": "1 kg", "stiffness": "62 N/m", "load": "196 mN", "v0": "5 um/s"}
EXPECTED_DIM = {
    "mass": "[mass]",
    "stiffness": "[mass] / [time] ** 2",
    "load": "[force]",
    "v0": "[length] / [time]",
}


@pytest.mark.fast
@pytest.mark.parametrize("arg", list(GOOD))
@pytest.mark.parametrize(
    ("bad", "message"),
    [
        ("3 parsec**3", "has dimension"),
        (5.0, "has no unit"),
        ("5", "has no unit"),
        ("1e-5", "has no unit"),  # a bare number, not pint's TypeError about a ParserHelper
        ("2.5e3", "has no unit"),  # a bare number in exponent form, not pint's unit 'e3'
        ("0 {u}", "must be positive"),
        ("-2 {u}", "must be positive"),
        ("nan {u}", "is NaN"),
        ("inf {u}", "is infinite"),
        ("7 furlongs_per_blorp", "not a quantity"),
        (None, "expected a quantity"),
    ],
)
def test_physical_parameters_bad_input(arg: str, bad, message: str) -> None:
    unit = GOOD[arg].split(" ", 1)[1]
    value = bad.format(u=unit) if isinstance(bad, str) else bad
    with pytest.raises(ValueError, match=message) as err:
        PhysicalParameters(**{**GOOD, arg: value}, law=f1(0.46, "160 s/m"))
    assert str(err.value).startswith(f"{arg}=")
    if message == "has dimension":
        assert EXPECTED_DIM[arg] in str(err.value)


@pytest.mark.parametrize(
    ("make", "arg"),
    [
        (lambda v: WeakeningLaw(c=v), "c"),
        (lambda v: CubicLaw(alpha=v, gamma=0.1), "alpha"),
        (lambda v: CubicLaw(alpha=0.5, gamma=v), "gamma"),
        (lambda v: CoulombLaw(kinetic=v), "kinetic"),
        (lambda v: DimensionlessParameters(nu=v, law=WeakeningLaw(c=1.0)), "nu"),
        (lambda v: PhysicalWeakeningLaw(mu0=v, a="1 s/m"), "mu0"),
        (lambda v: PhysicalCoulombLaw(mu_s=v, mu_k=0.1), "mu_s"),
    ],
)
@pytest.mark.parametrize("value", [0.0, -1.0, math.nan, math.inf, "abc"])
def test_dimensionless_bad_input(make, arg: str, value) -> None:
    with pytest.raises(ValueError, match=f"^{arg}="):
        make(value)


def test_other_bad_input() -> None:
    with pytest.raises(ValueError, match=r"kinetic=1\.5"):
        CoulombLaw(kinetic=1.5)
    with pytest.raises(ValueError, match=r"mu_k=0\.6"):
        PhysicalCoulombLaw(mu_s=0.5, mu_k=0.6)
    with pytest.raises(ValueError, match="p=-1"):
        WeakeningLaw(c=1.0, p=-1.0)
    with pytest.raises(ValueError, match=r"a='160 m/s' has dimension"):
        PhysicalWeakeningLaw(mu0=0.4, a="160 m/s")
    with pytest.raises(ValueError, match=r"k3='1 s/m' has dimension"):
        PhysicalCubicLaw(mu_s=0.4, k1="1 s/m", k3="1 s/m")
    with pytest.raises(ValueError, match="law="):
        DimensionlessParameters(nu=0.1, law=f1(0.4, "1 s/m"))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="law="):
        PhysicalParameters(**GOOD, law=WeakeningLaw(c=1.0))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="order="):
        WeakeningLaw(c=1.0).derivative(1.0, order=0)
    with pytest.raises(ValueError, match="v="):
        f1(0.4, "1 s/m").coefficient(3.0)


@pytest.mark.parametrize("plaw", PHYSICAL_LAWS, ids=repr)
@pytest.mark.parametrize("order", [1, 2])
def test_physical_derivatives(plaw, order: int) -> None:
    v = np.linspace(2e-4, 0.05, 40)
    h = 1e-7
    if order == 1:
        fd = (plaw.value(Q_(v + h, "m/s")) - plaw.value(Q_(v - h, "m/s"))) / (2 * h)
    else:
        fd = (plaw.derivative(Q_(v + h, "m/s")).magnitude - plaw.derivative(Q_(v - h, "m/s")).magnitude) / (
            2 * h
        )
    d = plaw.derivative(Q_(v, "m/s"), order)
    assert d.check(f"[time]**{order} / [length]**{order}")
    np.testing.assert_allclose(d.to(f"(s/m)**{order}").magnitude, fd, rtol=2e-5, atol=1e-6)
    assert plaw.static_threshold == plaw.mu_s


def test_more_bad_input() -> None:
    with pytest.raises(ValueError, match="v0='fast'"):
        zv_parameters("fast")
    with pytest.raises(ValueError, match="b='1 m'"):
        zv_parameters(b="1 m")
    d = DimensionlessParameters(nu=0.01, law=WeakeningLaw(c=2.0))
    with pytest.raises(ValueError, match=r"mu_s=-0\.5"):
        PhysicalParameters.from_dimensionless(d, mass="1 kg", stiffness="1 N/m", load="1 N", mu_s=-0.5)
    with pytest.raises(ValueError, match="mass='1 N'"):
        PhysicalParameters.from_dimensionless(d, mass="1 N", stiffness="1 N/m", load="1 N", mu_s=0.5)
    from stickslip import cycle

    r = cycle(d)
    with pytest.raises(ValueError, match="physical parameters"):
        r.quantity("amplitude")
    rp = cycle(zv_parameters("50 um/s"))
    assert rp.quantity("amplitude").check("[force]")
    assert rp.quantity("period").check("[time]")
    with pytest.raises(ValueError, match="name='volume'"):
        rp.quantity("volume")


@pytest.mark.fast
@pytest.mark.parametrize("text", ["5,5 um/s", "196,5 mN", "[5, 6] um/s", "5 6 um/s", ""])
def test_decimal_commas_and_lists_are_errors(text: str) -> None:
    """Decimal commas and lists are errors: pint alone reads '5,5 um/s' as 55 um/s and '5 6 um/s'
    as 30 um/s."""
    with pytest.raises(ValueError, match="is not a quantity"):
        zv_parameters(
            text if "N" not in text else "5 um/s", b="0 s/m"
        ) if "N" not in text else PhysicalParameters(**{**GOOD, "load": text}, law=f1(0.46, "160 s/m"))
