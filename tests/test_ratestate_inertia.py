"""The Hopf curve of the inertial rate-and-state spring-slider (stickslip.ratestate.inertia).

References: the critical stiffness with inertia, Rice and Ruina, J. Appl. Mech. 50, 343 (1983);
Lyapunov coefficients, Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed. (2004), eq. (3.20).
The independent references here are the SI equations of motion (complex-step Jacobians), the
compiled rate-and-state core (RateStateParameters.critical_kw_at), sympy derivatives, normal
forms with known coefficients, Lienard centres, and direct integration.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from stickslip.errors import ArgumentTypeError
from stickslip.ratestate.inertia import (
    InertialSlider,
    bautin_points,
    critical_stiffness,
    criticality,
    first_lyapunov,
    first_lyapunov_coefficient,
    hopf_normal_form,
    hopf_residual,
    steady_eigenvalues,
)
from stickslip.units import ureg

Array = Any  # numpy arrays, real or complex
Forms = Callable[..., Any]

A, B, DC, SIGMA, MASS = 0.01, 0.015, 1e-5, 1e7, 100.0  # laboratory values; M in kg/m^2
LAB: dict[str, Any] = {"a": A, "b": B, "dc": DC, "sigma": SIGMA, "mass": MASS}
#: velocities (m/s) spanning inertia numbers m = M V^2/(sigma D_c) from 1e-12 to 1e4
VELOCITIES = (1e-5, 1e-3, 0.03, 0.1, 1.0, 100.0)


def velocity_of(mu: float, a: float = A, mass: float = MASS) -> float:
    """The load-point velocity at which ``m/a = mu``."""
    return math.sqrt(mu * a * SIGMA * DC / mass)


# ---------------------------------------------------------------- independent SI model
def si_field(
    law: str, k: float, vl: float, mass: float = MASS, a: float = A, b: float = B
) -> tuple[Callable[[Any], Any], Array]:
    """The SI slider in ``(ln v, ln theta, u)``, ``u = V t - delta`` (m), time in s (log friction)."""
    mu0, v0 = 0.6, 1e-6

    def f(X: Any) -> Any:
        lv, lth, u = X
        v, th = np.exp(lv), np.exp(lth)
        fric = mu0 + a * (lv - np.log(v0)) + b * np.log(v0 * th / DC)
        dth = 1.0 - v * th / DC if law == "aging" else -(v * th / DC) * np.log(v * th / DC)
        return np.array([(k * u - SIGMA * fric) / (mass * v), dth / th, vl - v])

    u_ss = SIGMA * (mu0 + (a - b) * math.log(vl / v0)) / k
    return f, np.array([math.log(vl), math.log(DC / vl), u_ss])


def complex_step_jacobian(f: Callable[[Any], Any], x0: Array) -> Array:
    """Exact to rounding for an analytic ``f``: ``J e_j = Im f(x0 + i h e_j) / h``."""
    n = x0.size
    J = np.empty((n, n))
    for j in range(n):
        h = 1e-30 * max(1.0, abs(x0[j]))
        e = np.zeros(n, dtype=complex)
        e[j] = 1j * h
        J[:, j] = f(x0 + e).imag / h
    return J


# ---------------------------------------------------------------- the Hopf set
@pytest.mark.parametrize("V", VELOCITIES)
def test_closed_form_is_the_root_of_the_residual(V: float) -> None:
    s = InertialSlider(**LAB)
    kc = s.critical_stiffness(V)
    root = brentq(lambda k: s.hopf_residual(V, k), 0.1 * kc, 10.0 * kc, xtol=1e-300, rtol=1e-14)
    assert root == pytest.approx(kc, rel=1e-10)
    assert s.hopf_residual(V, 1.001 * kc) > 0.0 > s.hopf_residual(V, 0.999 * kc)
    # the published form (Rice and Ruina 1983) with m = M V^2/(sigma D_c)
    assert kc == pytest.approx(SIGMA * (B - A) / DC * (1.0 + MASS * V**2 / (SIGMA * A * DC)), rel=1e-15)


@pytest.mark.parametrize("law", ["aging", "slip"])
@pytest.mark.parametrize("V", [1e-3, 0.1, 1.0])
def test_eigenvalues_are_those_of_the_si_equations(law: str, V: float) -> None:
    s = InertialSlider(**LAB, law=law)
    for k in (0.5 * s.critical_stiffness(V), 2.0 * s.critical_stiffness(V)):
        f, x0 = si_field(law, k, V)
        assert np.max(np.abs(f(x0))) < 1e-9 * V  # steady sliding
        J = complex_step_jacobian(f, x0.astype(complex))
        ref = np.sort_complex(np.linalg.eigvals(J))
        assert np.allclose(np.sort_complex(s.eigenvalues(V, k)), ref, rtol=1e-9, atol=0)
        # the residual is the Routh-Hurwitz determinant c2 c1 - c0 times m^2/(a (m + a)) (time D_c/V)
        c = np.poly(J * DC / V).real
        m = s.inertia_number(V)
        assert s.hopf_residual(V, k) == pytest.approx((c[1] * c[2] - c[3]) * m * m / (A * (m + A)), rel=1e-7)
        stable = bool(np.all(ref.real < 0.0))
        assert stable == (s.hopf_residual(V, k) > 0.0)


@pytest.mark.parametrize("mass", [1.0, 100.0, 1e4])
def test_eigenvalues_cross_the_imaginary_axis_at_the_closed_form(mass: float) -> None:
    s = InertialSlider(A, B, DC, SIGMA, mass)
    for V in (1e-3, 0.1, 3.0):
        kc = s.critical_stiffness(V)
        below, at, above = (s.eigenvalues(V, kc * (1.0 + d))[0] for d in (-1e-7, 0.0, 1e-7))
        assert below.real > 0.0 > above.real
        omega = V / DC * math.sqrt((B - A) / A)
        assert abs(at.imag) == pytest.approx(omega, rel=1e-9)
        assert abs(at.real) < 1e-9 * omega
        assert s.hopf_frequency(V) == pytest.approx(omega, rel=1e-15)


def test_massless_limit_is_the_quasi_static_critical_stiffness() -> None:
    k0 = SIGMA * (B - A) / DC
    for mass in (0.0, "0 kg/m^2"):
        s = InertialSlider(A, B, DC, SIGMA, mass)
        assert s.critical_stiffness(0.1) == k0
        assert s.eigenvalues(0.1, k0).size == 2
        assert s.first_lyapunov(0.1, k0) == 0.0
        assert s.criticality(0.1, k0) == "degenerate"
        assert s.bautin_points(1e-6, 1.0) == []
    assert critical_stiffness(1.0, a=A, b=B, dc=DC, sigma=SIGMA, mass=1e-30) == pytest.approx(k0, rel=1e-15)


def test_critical_stiffness_agrees_with_the_compiled_rate_state_model() -> None:
    """Per block (m in kg, W in N) is per unit area over 1 m^2; the core's friction is regularized."""
    from stickslip.ratestate import RateStateParameters

    p = RateStateParameters(
        a=A,
        b=B,
        dc="10 um",
        v_ref="1 um/s",
        mu0=0.6,
        stiffness_per_load="0.5 1/mm",
        load="1e7 N",
        mass="100 kg",
    )
    s = InertialSlider(**LAB)
    for V in (1e-3, 0.1, 1.0):
        kw = p.critical_kw_at(f"{V} m/s").to("1/m").magnitude
        assert kw * SIGMA == pytest.approx(s.critical_stiffness(V), rel=1e-10)


# ---------------------------------------------------------------- the Lyapunov coefficient code
def polynomial_forms(components: list[Any], xs: list[Any], top: int = 5) -> tuple[Array, Forms]:
    """Jacobian and symmetric forms of a polynomial vector field (sympy expressions)."""
    n = len(xs)
    tensors = {o: np.zeros((n,) + (n,) * o) for o in range(1, top + 1)}
    for i, comp in enumerate(components):
        for monomial, coeff in sp.Poly(sp.expand(comp), *xs).terms():
            order = sum(monomial)
            if 1 <= order <= top:
                index = [v for v, e in enumerate(monomial) for _ in range(e)]
                value = float(coeff) * math.prod(math.factorial(e) for e in monomial)
                for perm in set(itertools.permutations(index)):
                    tensors[order][(i, *perm)] = value

    def form(*us: Any) -> Any:
        out = tensors[len(us)]
        for u in us:
            out = np.tensordot(out, u, axes=([1], [0]))
        return out

    return tensors[1], form


def taylor_forms(components: list[Any], xs: list[Any], top: int = 5) -> tuple[Array, Forms]:
    """Jacobian and symmetric forms of an analytic field from its Taylor polynomial at 0."""
    t = sp.Symbol("t")
    polys = [
        sp.series(c.subs({x: t * x for x in xs}, simultaneous=True), t, 0, top + 1).removeO()
        for c in components
    ]
    return polynomial_forms([p.subs(t, 1) for p in polys], xs, top)


X, Y, Z = sp.symbols("x y z")


def test_l1_of_the_lienard_oscillator() -> None:
    """x'' + (mu + x^2) x' + x = 0 at mu = 0: r' = -r^3/8 by averaging, l1 = 2(-1/8)/1 for <q, q> = 1."""
    J, form = polynomial_forms([Y, -X - X**2 * Y], [X, Y])
    l1, _ = first_lyapunov_coefficient(J, form)
    assert l1 == pytest.approx(-0.25, rel=1e-13)
    omega, c1, _ = hopf_normal_form(J, form)
    assert (omega, c1.real / omega) == pytest.approx((1.0, -0.25), rel=1e-13)
    # x'' + x^4 x' + x = 0: r' = -r^5/16, so l2 = 4 (-1/16) = -1/4, and l1 = 0
    J, form = polynomial_forms([Y, -X - X**4 * Y], [X, Y])
    omega, c1, c2 = hopf_normal_form(J, form)
    assert abs(c1) < 1e-15
    assert c2.real / omega == pytest.approx(-0.25, rel=1e-13)


def normal_form_field(omega: float, c1: complex, c2: complex) -> list[Any]:
    """``z' = i omega z + c1 z|z|^2 + c2 z|z|^4`` in ``(x, y)``, ``z = x + i y``: then ``w = z/sqrt(2)``."""
    r2 = X**2 + Y**2
    return [
        -omega * Y + (c1.real * X - c1.imag * Y) * r2 + (c2.real * X - c2.imag * Y) * r2**2,
        omega * X + (c1.imag * X + c1.real * Y) * r2 + (c2.imag * X + c2.real * Y) * r2**2,
    ]


def test_normal_form_coefficients_and_their_invariance() -> None:
    omega, c1, c2 = 1.5, 0.7j, -0.3 + 0.4j
    field = normal_form_field(omega, c1, c2)
    J, form = polynomial_forms(field, [X, Y])
    w, g21, g32 = hopf_normal_form(J, form)  # <q, q> = 1: z = sqrt(2) w, so c1 -> 2 c1, c2 -> 4 c2
    assert (w, g21, g32) == pytest.approx((omega, 2 * c1, 4 * c2), abs=1e-14)
    # a near-identity change X = h(Y) (two shears) keeps Re c1 and, where Re c1 = 0, Re c2
    x, y = sp.Poly(X, X, Y), sp.Poly(Y, X, Y)
    r = sp.Rational  # a Poly times a Rational stays a Poly
    phi, dphi = (lambda s: s**2 * r(1, 2) - s**3 * r(1, 3)), (lambda s: s - s**2)
    psi, dpsi = (lambda s: s**4 * r(1, 5) - s**2 * r(1, 3)), (lambda s: s**3 * r(4, 5) - s * r(2, 3))
    y1 = _truncate(x - psi(y))
    y2 = _truncate(y - phi(y1))  # h(y) = (y1 + psi(y2 + phi(y1)), y2 + phi(y1)), inverted exactly
    r2 = _truncate(y1**2 + y2**2)
    g1 = _truncate(-omega * y2 + (c1.real * y1 - c1.imag * y2) * r2 + (c2.real * y1 - c2.imag * y2) * r2**2)
    g2 = _truncate(omega * y1 + (c1.imag * y1 + c1.real * y2) * r2 + (c2.imag * y1 + c2.real * y2) * r2**2)
    du, dp = _truncate(dphi(y1)), _truncate(dpsi(_truncate(y2 + phi(y1))))
    f = [_truncate((1 + dp * du) * g1 + dp * g2), _truncate(du * g1 + g2)]
    J, form = polynomial_forms([e.as_expr() for e in f], [X, Y])
    w, g21, g32 = hopf_normal_form(J, form)
    assert w == pytest.approx(omega, rel=1e-14)
    assert g21 == pytest.approx(1.4j, abs=1e-13)
    assert g32.real == pytest.approx(-1.2, rel=1e-12)
    e1 = np.array([1.0, 0.0])
    assert np.max(np.abs(form(e1, e1))) > 0.5  # the change did act: quadratic terms
    assert first_lyapunov_coefficient(J, form)[0] == pytest.approx(0.0, abs=1e-13)


def _truncate(poly: Any, degree: int = 5) -> Any:
    """The terms of a sympy Poly up to ``degree``."""
    terms = {mon: c for mon, c in poly.as_dict().items() if sum(mon) <= degree}
    return sp.Poly.from_dict(terms or {(0, 0): 0}, *poly.gens)


@pytest.mark.parametrize("law", ["aging", "slip"])
def test_quasi_static_hopf_point_is_a_centre(law: str) -> None:
    """Without mass every Lyapunov coefficient vanishes (first integrals; module docstring)."""
    kap = B - A
    x = (Z - B * Y) / A  # quasi-static: the spring carries friction, z = a x + b y
    dy = sp.exp(-Y) - sp.exp(x) if law == "aging" else -sp.exp(x) * (x + Y)
    J, form = taylor_forms([dy, kap * (1 - sp.exp(x))], [Y, Z])
    omega, c1, c2 = hopf_normal_form(J, form)
    assert omega == pytest.approx(math.sqrt((B - A) / A), rel=1e-12)
    assert abs(c1.imag) > 1e-3  # the forms are not trivial
    assert abs(c1.real) < 1e-12 * abs(c1) and abs(c2.real) < 1e-10 * abs(c2)
    # and so is the slip law's Lienard form a x'' + (a - b + kappa e^-x) x' + kappa (1 - e^-x) = 0
    J, form = taylor_forms([Y, (-(A - B + kap * sp.exp(-X)) * Y - kap * (1 - sp.exp(-X))) / A], [X, Y])
    omega, c1, c2 = hopf_normal_form(J, form)
    assert abs(c1.real) < 1e-12 * abs(c1) and abs(c2.real) < 1e-10 * abs(c2)


@pytest.mark.parametrize("law", ["aging", "slip"])
def test_slider_forms_are_the_derivatives_of_its_vector_field(law: str) -> None:
    s = InertialSlider(**LAB, law=law)
    V = 0.05
    k = s.critical_stiffness(V)
    m, kap = s.inertia_number(V), s.stiffness_number(k)
    dy = sp.exp(-Y) - sp.exp(X) if law == "aging" else -sp.exp(X) * (X + Y)
    field = [sp.exp(-X) * (Z - A * X - B * Y) / m, dy, kap * (1 - sp.exp(X))]
    J, form = taylor_forms(field, [X, Y, Z])
    assert np.allclose(s.jacobian(V, k), J, rtol=1e-13, atol=0)
    f = s.vector_field(V, k)
    h = 1e-7
    fd = np.array([(f(0.0, h * e) - f(0.0, -h * e)) / (2 * h) for e in np.eye(3)]).T
    assert np.allclose(fd, J, rtol=1e-6, atol=1e-6)
    rng = np.random.default_rng(56)
    ours = s.forms(V, k)
    for n in range(2, 6):
        us = [rng.normal(size=3) + 1j * rng.normal(size=3) for _ in range(n)]
        assert np.allclose(ours(*us), form(*us), rtol=1e-12, atol=1e-12 * np.max(np.abs(form(*us))))


# ---------------------------------------------------------------- criticality of the slider
@pytest.mark.parametrize("law", ["aging", "slip"])
def test_kuznetsov_formula_equals_the_normal_form(law: str) -> None:
    s = InertialSlider(**LAB, law=law)
    for mu in (1e-3, 0.1, 1.0, 30.0):
        V = velocity_of(mu)
        k = s.critical_stiffness(V)
        omega, c1, _ = hopf_normal_form(s.jacobian(V, k), s.forms(V, k))
        assert s.first_lyapunov(V, k) == pytest.approx(c1.real / omega, rel=1e-10)
        assert first_lyapunov(V, k, law=law, **LAB) == s.first_lyapunov(V, k)


@pytest.mark.parametrize("beta", [1.05, 1.5, 2.0, 3.0, 10.0])
def test_sign_of_l1_along_the_hopf_curve(beta: float) -> None:
    """Sympy, exact in b/a = 1 + W^2 with mu = m/a (module docstring):
    slip: Re G ~ -mu (mu + 1)(9 mu + 1) < 0;  aging: Re G ~ -mu ((3 + 4 b/a) mu^2 + 6 mu - 1)."""
    b = A * beta
    for law in ("aging", "slip"):
        s = InertialSlider(A, b, DC, SIGMA, MASS, law)
        for mu in np.geomspace(1e-6, 1e3, 37):
            V = velocity_of(mu)
            expected = -1.0 if law == "slip" else -np.sign((3 + 4 * beta) * mu**2 + 6 * mu - 1)
            assert np.sign(s.first_lyapunov(V, s.critical_stiffness(V))) == expected
            assert s.criticality(V, s.critical_stiffness(V)) == (
                "supercritical" if expected < 0 else "subcritical"
            )


@pytest.mark.parametrize("mass", [1.0, 100.0, 1e4, 1e6])
def test_bautin_points_at_the_closed_form(mass: float) -> None:
    """The aging law's Bautin point: m*/a = (2 sqrt(3 + b/a) - 3)/(3 + 4 b/a); none for the slip law."""
    beta = B / A
    mu_star = (2.0 * math.sqrt(3.0 + beta) - 3.0) / (3.0 + 4.0 * beta)
    v_star = velocity_of(mu_star, mass=mass)
    lab: dict[str, Any] = {**LAB, "mass": mass}
    points = bautin_points((1e-6, 10.0), law="aging", **lab)
    assert len(points) == 1
    p = points[0]
    assert p.velocity == pytest.approx(v_star, rel=1e-8)
    assert p.stiffness == pytest.approx(critical_stiffness(v_star, **lab), rel=1e-8)
    assert p.inertia_number == pytest.approx(mu_star * A, rel=1e-8)
    assert p.l2 < 0.0  # a stable large cycle beside the unstable small one on the subcritical side
    assert bautin_points((1e-6, 10.0), law="slip", **lab) == []
    assert (
        criticality(0.5 * v_star, critical_stiffness(0.5 * v_star, **lab), law="aging", **lab)
        == "subcritical"
    )


def test_second_lyapunov_coefficient_changes_sign_near_b_over_a_5_63() -> None:
    """A measured codimension-three point: l2 = 0 at the aging Bautin point for b/a = 5.6338."""
    signs = []
    for beta in (5.5, 5.8):
        points = InertialSlider(A, A * beta, DC, SIGMA, MASS).bautin_points(0.01, 1.0)
        assert len(points) == 1
        signs.append(np.sign(points[0].l2))
    assert signs == [-1.0, 1.0]


def test_tiny_inertia_is_rounding_not_a_bautin_point() -> None:
    """l1 ~ m as m -> 0: below rounding it is degenerate, and sign noise there is no Bautin point."""
    s = InertialSlider(A, B, DC, SIGMA, 1.0)
    assert s.criticality(1e-9, s.critical_stiffness(1e-9)) == "degenerate"
    assert len(s.bautin_points(1e-10, 1.0)) == 1


def hopf_case(law: str, mu: float, eps: float) -> tuple[InertialSlider, float, float, complex, Array, float]:
    """Slider, nondimensional stiffness and the eigen-direction ``q`` at ``k = (1 + eps) k_c``."""
    s = InertialSlider(**LAB, law=law)
    V = velocity_of(mu)
    kc = s.critical_stiffness(V)
    omega = math.sqrt((B - A) / A)
    lam = s.eigenvalues(V, (1.0 + eps) * kc)[0] * DC / V  # nondimensional
    q = np.array([1.0, -1.0 / (1.0 + 1j * omega), -s.stiffness_number(kc) / (1j * omega)])
    q /= np.linalg.norm(q)
    # normal form: rho' = Re(lambda) rho + l1 omega rho^3; x = ln(v/V) ~ 2 rho |q_x| cos(omega t)
    rho = math.sqrt(abs(lam.real / (s.first_lyapunov(V, kc) * omega)))
    return s, V, (1.0 + eps) * kc, lam, q, rho


def simulate_si(
    law: str, V: float, k: float, x0: Array, duration: float, stop_above: float = math.inf
) -> tuple[float, float, bool]:
    """Integrate the SI equations from ``(x, y, z)`` = (ln(v/V), ln(theta V/D_c), (stress - steady)/sigma)."""
    f, ss = si_field(law, k, V)
    start = ss + np.array([x0[0], x0[1], SIGMA * x0[2] / k])

    def big(_t: float, X: Array) -> float:
        return float(abs(X[0] - ss[0]) - stop_above)

    big.terminal = True  # type: ignore[attr-defined]
    t_end = duration * DC / V
    period = 2 * math.pi / math.sqrt((B - A) / A) * DC / V
    sol = solve_ivp(
        lambda _t, X: f(X),
        (0.0, t_end),
        start,
        method="DOP853",
        rtol=1e-9,
        atol=1e-12,
        first_step=1e-3 * DC / V,
        max_step=period / 20,
        dense_output=True,
        events=big,
    )
    assert sol.status in (0, 1)
    T = sol.t[-1]
    first = np.max(np.abs(sol.sol(np.linspace(0.0, period, 200))[0] - ss[0]))
    last = np.max(np.abs(sol.sol(np.linspace(T - period, T, 200))[0] - ss[0]))
    return float(first), float(last), bool(sol.status == 1)


@pytest.mark.parametrize("law", ["aging", "slip"])
def test_supercritical_cycle_by_direct_simulation(law: str) -> None:
    """m = a (well above the aging law's Bautin point): a small stable cycle on the unstable side, of
    the amplitude l1 predicts; decay on the stable side."""
    s, V, k, lam, q, rho = hopf_case(law, 1.0, -1e-2)
    assert s.criticality(V, s.critical_stiffness(V)) == "supercritical"
    predicted = 2 * rho * abs(q[0])
    duration = 6.0 / lam.real
    _, last, _ = simulate_si(law, V, k, 0.3 * 2 * rho * q.real, duration)
    assert last == pytest.approx(predicted, rel=0.1)
    s, V, k, lam, q, rho = hopf_case(law, 1.0, +1e-2)
    first, last, _ = simulate_si(law, V, k, 2 * rho * q.real, 0.5 / abs(lam.real))
    assert last < 0.8 * first


def test_subcritical_aging_by_direct_simulation() -> None:
    """m/a = 0.06 (below the Bautin point): on the stable side, k = 1.001 k_c, the unstable cycle of
    amplitude rho separates decay (start at rho/2) from growth (start at 2 rho)."""
    s, V, k, lam, q, rho = hopf_case("aging", 0.06, 1e-3)
    assert s.criticality(V, s.critical_stiffness(V)) == "subcritical"
    duration = 0.3 / abs(lam.real)
    first, last, _ = simulate_si("aging", V, k, 0.5 * 2 * rho * q.real, duration)
    assert last < 0.95 * first
    first, last, escaped = simulate_si("aging", V, k, 2.0 * 2 * rho * q.real, duration, stop_above=1.0)
    assert escaped or last > 1.2 * first


# ---------------------------------------------------------------- input
def test_quantities_and_plain_si_floats_agree() -> None:
    q = InertialSlider(0.01, 0.015, "10 um", "10 MPa", "100 kg/m^2", "slip", 0.6, "1 um/s")
    plain = InertialSlider(0.01, 0.015, 1e-5, 1e7, 100.0, "slip", 0.6, 1e-6)
    assert dataclasses.astuple(q) == pytest.approx(dataclasses.astuple(plain), rel=1e-15)
    assert InertialSlider(A, B, ureg.Quantity(10.0, "um"), "100 bar", "0.1 t/m^2").mass == pytest.approx(MASS)
    assert hopf_residual(0.1, 2e9, **LAB) == InertialSlider(**LAB).hopf_residual(0.1, 2e9)
    assert steady_eigenvalues(0.1, 2e9, **LAB) == pytest.approx(InertialSlider(**LAB).eigenvalues(0.1, 2e9))
    assert InertialSlider(**LAB).steady_state(1e-6) == (0.6, DC / 1e-6)


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"law": "ageing"}, ValueError, "law='ageing'"),
        ({"a": -0.01}, ValueError, "a=-0.01"),
        ({"a": "0.01"}, ArgumentTypeError, "a='0.01'"),
        ({"b": math.nan}, ValueError, "b=nan"),
        ({"dc": "10 kg"}, ValueError, "dc="),
        ({"dc": 1e9}, ValueError, "dc=1000000000.0"),
        ({"sigma": "ten MPa"}, ValueError, "sigma="),
        ({"sigma": -1.0}, ValueError, "sigma=-1.0"),
        ({"mass": "100 kg"}, ValueError, "mass="),
        ({"mass": None}, ArgumentTypeError, "mass=None"),
    ],
)
def test_bad_parameters_are_one_line_errors(
    kwargs: dict[str, Any], error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match=message.replace("(", r"\(")) as info:
        InertialSlider(**{**LAB, **kwargs})
    assert "\n" not in str(info.value)


def test_bad_arguments_are_one_line_errors() -> None:
    s = InertialSlider(**LAB)
    with pytest.raises(ValueError, match=r"V=0\.0"):
        s.critical_stiffness(0.0)
    with pytest.raises(ValueError, match=r"V=-1"):
        s.hopf_residual(-1, 1e9)
    with pytest.raises(ValueError, match="not a Hopf point"):
        s.first_lyapunov(0.1, 1.01 * s.critical_stiffness(0.1))
    with pytest.raises(ValueError, match=r"b=0\.01 <= a=0\.01"):
        InertialSlider(**{**LAB, "b": 0.01}).hopf_frequency(0.1)
    with pytest.raises(ValueError, match=r"v_min=1\.0, v_max=0\.1"):
        s.bautin_points(1.0, 0.1)
    with pytest.raises(ValueError, match="V_range="):
        bautin_points((1.0,), law="aging", **LAB)
    with pytest.raises(ArgumentTypeError, match=r"samples=2\.5"):
        s.bautin_points(0.1, 1.0, samples=2.5)  # type: ignore[arg-type]
