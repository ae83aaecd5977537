"""Hopf bifurcation of the inertial rate-and-state spring-slider in the (V, k) plane.

The slider, per unit area of the interface (mass per area ``M`` in kg/m^2, stiffness per area
``k`` in Pa/m, normal stress ``sigma`` in Pa), driven at the load-point velocity ``V``:

    M dv/dt = k (V t - delta) - sigma [mu0 + a ln(v/v0) + b ln(v0 theta/D_c)],   d delta/dt = v
    aging:  theta' = 1 - v theta/D_c          slip:  theta' = -(v theta/D_c) ln(v theta/D_c)

In the variables ``x = ln(v/V)``, ``y = ln(theta V/D_c)``, ``z`` = (spring stress minus the
steady friction ``sigma mu_ss(V)``)/``sigma`` and the time ``T = t V/D_c``, with the inertia number
``m = M V^2/(sigma D_c)`` and the stiffness number ``kappa = k D_c/sigma``:

    x' = exp(-x) (z - a x - b y)/m,   z' = kappa (1 - exp(x))
    y' = exp(-y) - exp(x)  (aging),   y' = -exp(x) (x + y)  (slip)

``mu0`` and ``v0`` drop out: the Hopf set and the Lyapunov coefficients depend on ``a``, ``b``,
``m`` and ``kappa`` only (and their signs on ``b/a``, ``m/a`` and ``kappa/a``). Both laws have the
Jacobian ``[[-a/m, -b/m, 1/m], [-1, -1, 0], [-kappa, 0, 0]]`` at steady sliding, so one
characteristic polynomial serves both:

    m lambda^3 + (m + a) lambda^2 + (kappa + a - b) lambda + kappa = 0.

Routh-Hurwitz: stable iff ``(m + a)(kappa + a - b) > m kappa``, i.e. ``a kappa > (m + a)(b - a)``;
the Hopf set is ``kappa = (b - a)(1 + m/a)``, the critical stiffness of Rice and Ruina (J. Appl.
Mech. 50, 343, 1983), exact for this model, with the frequency ``(V/D_c) sqrt((b - a)/a)``
whatever the mass. Lyapunov coefficients follow Kuznetsov (Elements of Applied Bifurcation Theory,
3rd ed., 2004, eq. (3.20) and section 8.7): ``l1 = Re c1/omega``, ``l2 = Re c2/omega`` for the
normal form ``w' = i omega w + c1 w|w|^2 + c2 w|w|^4`` on the centre manifold ``X = 2 Re(w q) + ...``
with ``A q = i omega q``, ``<q, q> = 1``, ``<p, q> = 1``, in the nondimensional variables and time
above; ``l1 < 0``: supercritical. The multilinear forms are exact derivatives (closed form).

Without mass the Hopf point is a centre for both laws, so every Lyapunov coefficient vanishes:
the aging law's quasi-static flow is area-preserving at ``kappa = b - a`` (the divergence
``(b - a - kappa)(...)`` of PHYSICS.md section 5 vanishes; every orbit is then periodic, Ranjith
and Rice, J. Mech. Phys. Solids 47, 1207, 1999), and the slip law's is the Lienard equation
``a x'' + (a - b + kappa e^-x) x' + kappa (1 - e^-x) = 0`` in the slip-weighted time ``ds = e^x dT``,
whose damping is proportional to its restoring force at ``kappa = b - a``: it has a first integral.

With mass, with ``mu = m/a`` and ``beta = b/a``, the sign of ``l1`` on the Hopf set is that of
(sympy, exact, from formula (3.20) with ``q_x = 1`` and ``beta = 1 + omega^2``):

* slip law: ``-mu (mu + 1)(9 mu + 1)``: supercritical at every mass;
* aging law: ``-mu ((3 + 4 beta) mu^2 + 6 mu - 1)``: subcritical for small inertia, supercritical
  above the Bautin point ``mu* = (2 sqrt(3 + beta) - 3)/(3 + 4 beta)`` (``m* = 0.0013807`` for ``a = 0.01``,
  ``b = 0.015``). There ``l2 < 0`` for ``beta < 5.6338`` and ``l2 > 0`` above (measured): a
  codimension-three point at ``beta = 5.6338``, ``mu = 0.11265``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ..units import check_count, check_number, parse_quantity

__all__ = [
    "LAWS",
    "BautinPoint",
    "InertialSlider",
    "bautin_points",
    "critical_stiffness",
    "criticality",
    "first_lyapunov",
    "first_lyapunov_coefficient",
    "hopf_normal_form",
    "hopf_residual",
    "steady_eigenvalues",
]

LAWS = ("aging", "slip")
FloatArray = npt.NDArray[np.float64]
ComplexArray = npt.NDArray[np.complex128]
#: a symmetric n-linear form: ``form(u_1, ..., u_n)`` (n >= 2) of complex vectors
Forms = Callable[..., ComplexArray]
#: the largest ``|Re lambda| / omega`` of a pair accepted as the Hopf pair
HOPF_TOLERANCE = 1e-6
#: ``|l1|`` below this fraction of the largest term of Kuznetsov's sum is rounding: degenerate
DEGENERATE = 1e-12


def _si(value: Any, name: str, dimension: str, unit: str, example: str, *, allow_zero: bool = False) -> float:
    """Return ``value`` in ``unit``: a plain number is taken as SI, a quantity or string is parsed."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        sign = "non-negative" if allow_zero else "positive"
        what = f"a {sign} number in {unit} or a quantity like {example!r}"
        return check_number(value, name, allow_zero=allow_zero, what=what)
    if isinstance(value, np.floating | np.integer):
        return _si(float(value), name, dimension, unit, example, allow_zero=allow_zero)
    q = parse_quantity(value, name, dimension, example, allow_zero=allow_zero)
    return float(q.to(unit).magnitude)


def _positive(value: float, name: str) -> float:
    """Return ``float(value)``, or a ValueError naming it unless it is finite and positive."""
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise ValueError(f"{name}={value!r}: expected a finite positive number (SI units)")
    return v


# ---------------------------------------------------------------- normal form of a Hopf point
def _hopf_pair(A: FloatArray) -> tuple[float, ComplexArray, ComplexArray]:
    """Return ``(omega, q, pbar)``: ``A q = i omega q``, ``|q| = 1``, ``pbar A = i omega pbar``.

    ``pbar`` is the row ``p^H`` of Kuznetsov's ``<p, v> = p^H v``, with ``pbar q = 1``.
    """
    ev, vecs = np.linalg.eig(A)
    i = int(np.argmax(ev.imag))
    lam = ev[i]
    if not lam.imag > 0.0:
        raise ValueError(f"eigenvalues {np.round(ev, 6)}: no complex pair, not a Hopf point")
    if abs(lam.real) > HOPF_TOLERANCE * lam.imag:
        raise ValueError(
            f"eigenvalue {lam:.6g}: Re lambda / omega = {lam.real / lam.imag:.3g}, not a Hopf point "
            f"(|Re lambda / omega| <= {HOPF_TOLERANCE:g} expected)"
        )
    q = vecs[:, i] / np.linalg.norm(vecs[:, i])
    evt, left = np.linalg.eig(A.T)
    j = int(np.argmin(np.abs(evt - lam)))
    pbar = left[:, j] / (left[:, j] @ q)  # a row with pbar A = lambda pbar, pbar q = 1
    return float(lam.imag), q.astype(complex), pbar.astype(complex)


def first_lyapunov_coefficient(A: FloatArray, forms: Forms) -> tuple[float, float]:
    """Return ``(l1, scale)`` of a Hopf point by Kuznetsov's formula (3.20).

    ``l1 = Re[<p, C(q,q,qbar)> - 2 <p, B(q, A^-1 B(q,qbar))> + <p, B(qbar, (2 i omega - A)^-1 B(q,q))>]
    / (2 omega)`` with ``<q, q> = 1`` and ``<p, q> = 1``; ``scale`` is the largest of the three terms
    over ``2 omega``, the size against which ``l1`` is rounding.

    Parameters
    ----------
    A : ndarray
        The Jacobian at the equilibrium (n x n, real), with eigenvalues ``+-i omega``.
    forms : callable
        ``forms(u, v)`` = ``B(u, v)`` and ``forms(u, v, w)`` = ``C(u, v, w)``, the symmetric forms of
        the second and third derivatives at the equilibrium.

    """
    omega, q, pbar = _hopf_pair(A)
    n = A.shape[0]
    qb = q.conj()
    terms = (
        pbar @ forms(q, q, qb),
        -2.0 * (pbar @ forms(q, np.linalg.solve(A, forms(q, qb)))),
        pbar @ forms(qb, np.linalg.solve(2j * omega * np.eye(n) - A, forms(q, q))),
    )
    return float(sum(terms).real / (2.0 * omega)), float(max(abs(t) for t in terms)) / (2.0 * omega)


def hopf_normal_form(A: FloatArray, forms: Forms) -> tuple[float, complex, complex]:
    """Return ``(omega, c1, c2)`` of ``w' = i omega w + c1 w|w|^2 + c2 w|w|^4`` at a Hopf point.

    The centre manifold ``X = sum h_jk w^j wbar^k`` (``h_10 = q``, ``<q, q> = 1``) is solved order by
    order to fifth order from the invariance equation ``DX w' = A X + sum_n F_n(X, ..., X)/n!``; the
    resonant terms ``w^(k+1) wbar^k`` go to the normal form and their ``h`` is kept orthogonal to
    ``p``; no other term stays. ``l1 = Re c1 / omega`` and, where ``Re c1 = 0``,
    ``l2 = Re c2 / omega`` (Kuznetsov 2004, section 8.7: ``c1 = G21/2``, ``c2 = G32/12``).

    Parameters
    ----------
    A : ndarray
        The Jacobian at the equilibrium, with eigenvalues ``+-i omega``.
    forms : callable
        ``forms(u_1, ..., u_n)`` for ``n = 2 .. 5``: the symmetric forms of the n-th derivatives.

    """
    omega, q, pbar = _hopf_pair(A)
    n = A.shape[0]
    h: dict[tuple[int, int], ComplexArray] = {(1, 0): q, (0, 1): q.conj()}  # coefficients of w^j wbar^k
    g: dict[tuple[int, int], complex] = {}  # resonant normal-form coefficients
    bordered = np.zeros((n + 1, n + 1), dtype=complex)
    bordered[:n, :n] = 1j * omega * np.eye(n) - A
    bordered[:n, n] = q
    bordered[n, :n] = pbar
    for order in range(2, 6):
        for j in range(order, -1, -1):
            k = order - j
            if j < k:  # the conjugate of (k, j)
                h[(j, k)] = h[(k, j)].conj()
                continue
            if order == 5 and j - k != 1:
                continue  # only the resonant coefficient is needed at fifth order
            rhs = _composed(h, forms, j, k)
            for (jj, kk), hv in h.items():  # minus DX (w' - i omega w), the lower orders of both
                if jj + kk < 2:
                    continue
                for (gj, gk), gv in g.items():
                    if jj and (jj + gj - 1, kk + gk) == (j, k):
                        rhs = rhs - jj * gv * hv
                    if kk and (jj + gk, kk + gj - 1) == (j, k):
                        rhs = rhs - kk * np.conj(gv) * hv
            if j - k == 1:
                g[(j, k)] = complex(pbar @ rhs)
                if order == 5:
                    return omega, g[(2, 1)], g[(3, 2)]
                sol = np.linalg.solve(bordered, np.concatenate([rhs - g[(j, k)] * q, [0.0]]))
                h[(j, k)] = sol[:n]
            else:
                h[(j, k)] = np.linalg.solve(1j * omega * (j - k) * np.eye(n) - A, rhs).astype(complex)
    raise AssertionError("unreachable: order 5 returns at (3, 2)")


def _splits(j: int, k: int, keys: list[tuple[int, int]]) -> list[list[tuple[int, int]]]:
    """Ordered lists of ``keys`` (orders >= 1) that add up to ``(j, k)``."""
    if j == 0 and k == 0:
        return [[]]
    out: list[list[tuple[int, int]]] = []
    for key in keys:
        if key[0] <= j and key[1] <= k:
            out.extend([key, *rest] for rest in _splits(j - key[0], k - key[1], keys))
    return out


def _composed(h: dict[tuple[int, int], ComplexArray], forms: Forms, j: int, k: int) -> ComplexArray:
    """Coefficient of ``w^j wbar^k`` in ``sum_n F_n(X, ..., X)/n!`` for the lower orders of ``X``."""
    known = [key for key in h if key[0] + key[1] < j + k]
    total = np.zeros_like(h[(1, 0)])
    for keys in _splits(j, k, known):
        if len(keys) >= 2:
            total = total + forms(*(h[key] for key in keys)) / math.factorial(len(keys))
    return total


# ---------------------------------------------------------------- the slider
@dataclass(frozen=True)
class InertialSlider:
    """The inertial rate-and-state spring-slider per unit area (aging or slip law, log friction).

    Methods take the load-point velocity ``V`` (m/s) and the stiffness ``k`` (Pa/m) as plain floats
    and return plain floats: fast scalar functions of ``(V, k)`` for continuation.

    Parameters
    ----------
    a, b : float
        Direct and evolution effects (dimensionless; ``a > 0``, ``b >= 0``).
    dc : float or length
        Characteristic slip ``D_c`` (a number is metres), e.g. ``"10 um"``.
    sigma : float or pressure
        Normal stress (a number is Pa), e.g. ``"10 MPa"``.
    mass : float or mass/area
        Mass per unit area ``M`` (a number is kg/m^2; 0 is the quasi-static slider), e.g. ``"100 kg/m^2"``.
    law : str
        ``"aging"`` or ``"slip"``.
    mu0 : float
        Friction at ``v0`` (does not enter the Hopf set).
    v0 : float or velocity
        Reference velocity (a number is m/s; does not enter the Hopf set).

    """

    a: float
    b: float
    dc: Any
    sigma: Any
    mass: Any
    law: str = "aging"
    mu0: float = 0.6
    v0: Any = 1e-6

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "a", check_number(self.a, "a", what="a positive direct effect a"))
        set_(self, "b", check_number(self.b, "b", allow_zero=True, what="a non-negative evolution effect b"))
        dc = _si(self.dc, "dc", "[length]", "m", "10 um")
        if not 1e-12 <= dc <= 1e3:
            raise ValueError(f"dc={self.dc!r}: expected a slip distance between 1 pm and 1 km")
        set_(self, "dc", dc)
        set_(self, "sigma", _si(self.sigma, "sigma", "[pressure]", "Pa", "10 MPa"))
        set_(
            self,
            "mass",
            _si(self.mass, "mass", "[mass] / [length] ** 2", "kg/m**2", "100 kg/m^2", allow_zero=True),
        )
        if self.law not in LAWS:
            raise ValueError(f"law={self.law!r}: expected 'aging' or 'slip'")
        set_(self, "mu0", check_number(self.mu0, "mu0", what="a positive reference friction mu0"))
        set_(self, "v0", _si(self.v0, "v0", "[length] / [time]", "m/s", "1 um/s"))

    # ------------------------------------------------------------ scales
    def inertia_number(self, V: float) -> float:
        """``m = M V^2 / (sigma D_c)``: the slider's inertia at load-point velocity ``V`` (m/s)."""
        V = _positive(V, "V")
        return self.mass * V * V / (self.sigma * self.dc)

    def stiffness_number(self, k: float) -> float:
        """``kappa = k D_c / sigma`` for the stiffness ``k`` (Pa/m)."""
        return float(k) * self.dc / self.sigma

    def steady_state(self, V: float) -> tuple[float, float]:
        """Return ``(mu_ss, theta_ss)``: friction ``mu0 + (a - b) ln(V/v0)`` and state ``D_c/V`` (s)."""
        V = _positive(V, "V")
        return self.mu0 + (self.a - self.b) * math.log(V / self.v0), self.dc / V

    # ------------------------------------------------------------ Hopf set
    def critical_stiffness(self, V: float) -> float:
        """Hopf stiffness (Pa/m): ``k_c = sigma (b - a)/D_c (1 + M V^2/(sigma a D_c))``, exact.

        Steady sliding at ``V`` is stable for ``k > k_c`` and unstable for ``0 < k < k_c``; for
        ``b <= a`` the value is not positive and every positive stiffness is stable.
        """
        return self.sigma * (self.b - self.a) / self.dc * (1.0 + self.inertia_number(V) / self.a)

    def hopf_frequency(self, V: float) -> float:
        """Angular frequency (rad/s) at the Hopf point: ``(V/D_c) sqrt((b - a)/a)``, whatever the mass."""
        V = _positive(V, "V")
        if self.b <= self.a:
            raise ValueError(f"b={self.b} <= a={self.a}: no Hopf point at positive stiffness (need b > a)")
        return V / self.dc * math.sqrt((self.b - self.a) / self.a)

    def hopf_residual(self, V: float, k: float) -> float:
        """Return ``kappa/(m + a) - (b - a)/a``: zero on the Hopf set, positive where sliding is stable.

        The Routh-Hurwitz determinant ``c2 c1 - c0`` of ``lambda^3 + c2 lambda^2 + c1 lambda + c0``
        times ``m^2/(a (m + a)) > 0``: linear in ``k``, polynomial in ``V``, of order ``(b - a)/a``
        (``(b - a)/a (k/k_c - 1)`` for ``b > a``). Stability needs ``k > 0`` as well.
        """
        m = self.inertia_number(V)
        return self.stiffness_number(k) / (m + self.a) - (self.b - self.a) / self.a

    def jacobian(self, V: float, k: float) -> FloatArray:
        """Nondimensional Jacobian at steady sliding, in ``(x, y, z)`` and time ``D_c/V`` (needs a mass)."""
        m = self.inertia_number(V)
        if m == 0.0:
            raise ValueError("mass=0: the quasi-static slider has two variables, no inertial Jacobian")
        kap = self.stiffness_number(k)
        a, b = self.a, self.b
        return np.array([[-a / m, -b / m, 1.0 / m], [-1.0, -1.0, 0.0], [-kap, 0.0, 0.0]])

    def eigenvalues(self, V: float, k: float) -> ComplexArray:
        """Eigenvalues (1/s) of steady sliding at ``(V, k)``, largest real part first.

        The roots of ``m lambda^3 + (m + a) lambda^2 + (kappa + a - b) lambda + kappa`` times ``V/D_c``;
        two roots without mass (``a lambda^2 + (kappa + a - b) lambda + kappa``).
        """
        m = self.inertia_number(V)
        kap = self.stiffness_number(k)
        coeffs = (
            [m, m + self.a, kap + self.a - self.b, kap] if m > 0.0 else [self.a, kap + self.a - self.b, kap]
        )
        roots = np.roots(coeffs) * (float(V) / self.dc)
        return roots[np.argsort(-roots.real, kind="stable")].astype(complex)

    # ------------------------------------------------------------ nonlinear terms
    def forms(self, V: float, k: float) -> Forms:
        """Return the symmetric n-linear forms (``n >= 2``) of the nondimensional field at steady sliding.

        Exact: ``d^n/dx^n`` of ``exp(-x)(z - a x - b y)/m`` is ``(-1)^n exp(-x)(z - a x - b y + n a)/m``,
        and likewise for the exponentials of the other components.
        """
        m = self.inertia_number(V)
        kap = self.stiffness_number(k)
        a, b, aging = self.a, self.b, self.law == "aging"

        def form(*us: ComplexArray) -> ComplexArray:
            n = len(us)
            xs = [u[0] for u in us]
            px = np.prod(xs)
            sy = sum(us[j][1] * np.prod(xs[:j] + xs[j + 1 :]) for j in range(n))
            sz = sum(us[j][2] * np.prod(xs[:j] + xs[j + 1 :]) for j in range(n))
            f1 = (-1) ** n * (n * a * px + b * sy - sz) / m
            f2 = (-1) ** n * np.prod([u[1] for u in us]) - px if aging else -n * px - sy
            return np.array([f1, f2, -kap * px], dtype=complex)

        return form

    def vector_field(self, V: float, k: float) -> Callable[[float, FloatArray], FloatArray]:
        """Return ``f(T, (x, y, z))``, the nondimensional slider (time ``D_c/V``), for ``solve_ivp``."""
        m = self.inertia_number(V)
        kap = self.stiffness_number(k)
        a, b, aging = self.a, self.b, self.law == "aging"

        def f(_t: float, X: FloatArray) -> FloatArray:
            x, y, z = X
            ex = math.exp(x)
            dy = math.exp(-y) - ex if aging else -ex * (x + y)
            return np.array([(z - a * x - b * y) / (m * ex), dy, kap * (1.0 - ex)])

        return f

    # ------------------------------------------------------------ criticality
    def _lyapunov(self, V: float, k: float) -> tuple[float, float]:
        if self.inertia_number(V) == 0.0:
            return 0.0, 0.0  # the quasi-static Hopf point is a centre (module docstring)
        return first_lyapunov_coefficient(self.jacobian(V, k), self.forms(V, k))

    def first_lyapunov(self, V: float, k: float) -> float:
        """First Lyapunov coefficient at the Hopf point ``(V, k)``: < 0 supercritical, > 0 subcritical.

        Kuznetsov's formula (3.20) in the nondimensional variables (module docstring), with exact
        forms; 0 without mass. A ValueError unless ``k`` is on the Hopf set (``|Re lambda| <= 1e-6
        omega``; ``k = critical_stiffness(V)``).
        """
        return self._lyapunov(V, k)[0]

    def second_lyapunov(self, V: float, k: float) -> float:
        """``Re c2 / omega`` of the fifth-order normal form at ``(V, k)`` (meaningful where ``l1 = 0``)."""
        if self.inertia_number(V) == 0.0:
            return 0.0
        omega, _c1, c2 = hopf_normal_form(self.jacobian(V, k), self.forms(V, k))
        return c2.real / omega

    def criticality(self, V: float, k: float) -> str:
        """Return ``"supercritical"`` (l1 < 0), ``"subcritical"`` (l1 > 0) or ``"degenerate"`` (rounding)."""
        l1, scale = self._lyapunov(V, k)
        if abs(l1) <= DEGENERATE * scale or l1 == 0.0:
            return "degenerate"
        return "supercritical" if l1 < 0.0 else "subcritical"

    def bautin_points(self, v_min: float, v_max: float, *, samples: int = 200) -> list[BautinPoint]:
        """Return the Bautin points (``l1 = 0``) on the Hopf curve ``k = k_c(V)`` for ``v_min <= V <= v_max``.

        ``l1`` is sampled at ``samples`` velocities spaced evenly in ``ln V``; each sign change
        between neighbours whose ``l1`` is above rounding (``l1 ~ m`` as ``m -> 0``) is refined by
        Brent's method to ``1e-12`` relative in ``V``. Empty without mass (``l1 = 0`` identically:
        no isolated point) or without a sign change. The sign of ``l1`` depends on ``m/a`` and
        ``b/a`` only, so the points sit at one inertia number ``m*``: ``V* = sqrt(m* sigma D_c/M)``.
        """
        from scipy.optimize import brentq  # scipy loads on the first search only

        lo, hi = _positive(v_min, "v_min"), _positive(v_max, "v_max")
        if not lo < hi:
            raise ValueError(f"v_min={v_min!r}, v_max={v_max!r}: expected v_min < v_max")
        if self.b <= self.a:
            raise ValueError(f"b={self.b} <= a={self.a}: no Hopf curve at positive stiffness (need b > a)")
        n = check_count(samples, "samples", minimum=2, what="a number of velocities")
        if self.mass == 0.0:
            return []

        def l1(v: float) -> float:
            return self.first_lyapunov(v, self.critical_stiffness(v))

        def sign(v: float) -> float:  # 0 where l1 is rounding (small inertia: l1 ~ m)
            value, scale = self._lyapunov(v, self.critical_stiffness(v))
            return 0.0 if abs(value) <= DEGENERATE * scale else math.copysign(1.0, value)

        vs = [float(v) for v in np.geomspace(lo, hi, n)]
        signs = [sign(v) for v in vs]
        out = []
        for v1, v2, s1, s2 in zip(vs[:-1], vs[1:], signs[:-1], signs[1:], strict=True):
            if s1 * s2 < 0.0:
                v = float(brentq(l1, v1, v2, xtol=1e-300, rtol=1e-12))
                k = self.critical_stiffness(v)
                out.append(BautinPoint(v, k, self.inertia_number(v), self.second_lyapunov(v, k)))
        return out


@dataclass(frozen=True)
class BautinPoint:
    """A Bautin (generalised Hopf) point: ``l1 = 0`` on the Hopf curve.

    Attributes
    ----------
    velocity : float
        Load-point velocity ``V`` (m/s).
    stiffness : float
        Hopf stiffness ``k_c(V)`` (Pa/m).
    inertia_number : float
        ``M V^2/(sigma D_c)``.
    l2 : float
        Second Lyapunov coefficient (nondimensional, as ``l1``). ``l2 < 0``: near the point, on the
        subcritical side, a stable larger cycle surrounds the unstable small one, the two born in
        a fold of cycles; ``l2 > 0``: on the supercritical side, an unstable larger cycle surrounds
        the stable small one.

    """

    velocity: float
    stiffness: float
    inertia_number: float
    l2: float


# ---------------------------------------------------------------- keyword functions
def _slider(a: Any, b: Any, dc: Any, sigma: Any, mass: Any, law: str = "aging") -> InertialSlider:
    return InertialSlider(a=a, b=b, dc=dc, sigma=sigma, mass=mass, law=law)


def critical_stiffness(V: float, *, a: float, b: float, dc: Any, sigma: Any, mass: Any) -> float:
    """Return the Hopf stiffness (Pa/m) ``sigma (b - a)/D_c [1 + M V^2/(sigma a D_c)]`` (exact).

    Per unit area: ``dc`` (m), ``sigma`` (Pa), ``mass`` (kg/m^2), numbers or quantities; ``V`` in m/s.
    See :class:`InertialSlider`.
    """
    return _slider(a, b, dc, sigma, mass).critical_stiffness(V)


def hopf_residual(V: float, k: float, *, a: float, b: float, dc: Any, sigma: Any, mass: Any) -> float:
    """``kappa/(m + a) - (b - a)/a``: zero on the Hopf set, positive where steady sliding is stable."""
    return _slider(a, b, dc, sigma, mass).hopf_residual(V, k)


def steady_eigenvalues(
    V: float, k: float, *, a: float, b: float, dc: Any, sigma: Any, mass: Any
) -> ComplexArray:
    """Eigenvalues (1/s) of steady sliding at ``(V, k)``, largest real part first."""
    return _slider(a, b, dc, sigma, mass).eigenvalues(V, k)


def first_lyapunov(
    V: float, k: float, *, law: str, a: float, b: float, dc: Any, sigma: Any, mass: Any
) -> float:
    """Return the first Lyapunov coefficient at the Hopf point ``(V, k)`` (< 0: supercritical).

    See :meth:`InertialSlider.first_lyapunov`.
    """
    return _slider(a, b, dc, sigma, mass, law).first_lyapunov(V, k)


def criticality(V: float, k: float, *, law: str, a: float, b: float, dc: Any, sigma: Any, mass: Any) -> str:
    """``"supercritical"``, ``"subcritical"`` or ``"degenerate"`` at the Hopf point ``(V, k)``."""
    return _slider(a, b, dc, sigma, mass, law).criticality(V, k)


def bautin_points(
    V_range: Sequence[float],
    *,
    law: str,
    a: float,
    b: float,
    dc: Any,
    sigma: Any,
    mass: Any,
    samples: int = 200,
) -> list[BautinPoint]:
    """Return the Bautin points on the Hopf curve for ``V_range = (v_min, v_max)`` (m/s).

    See :meth:`InertialSlider.bautin_points`.
    """
    if isinstance(V_range, str) or len(V_range) != 2:
        raise ValueError(f"V_range={V_range!r}: expected (v_min, v_max) in m/s")
    return _slider(a, b, dc, sigma, mass, law).bautin_points(V_range[0], V_range[1], samples=samples)
