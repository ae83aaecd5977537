"""The appendix of the paper: the Rice–Ruina model's autonomous form and Dulac's criterion.

Everything is derived here with sympy from the physical equations

    (k/W)(v0 t - x) = mu0 + B ln(Phi/Phi0) + A ln(x'/V_r),   Phi' = 1 - x' Phi/D0,

by the substitutions ``alpha = (x - v0 t)/D0``, ``phi = Phi/Phi0``, ``Phi0 = D0/V_r``,
``tau = V_r t/D0``, ``omega = v0/V_r``, ``gamma = exp(-mu0/A)``, ``kappa = k D0/W``:
nothing below is typed in from the paper except the expression it is checked
against (:func:`paper_divergence`).

Dulac's criterion (Bendixson–Dulac) with ``g = 1``: if the divergence of a
planar vector field keeps one sign on a simply connected region and vanishes
on no open set, the region holds no periodic orbit. Here the divergence is
``(B - A - kappa) (gamma/A) phi^(-B/A) exp(-kappa alpha/A)``: of the sign of
``B - A - kappa`` everywhere on ``phi > 0``, so periodic orbits are excluded
unless ``kappa = B - A`` (the critical stiffness, where it vanishes identically).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import sympy as sp

__all__ = ["DulacDerivation", "derive", "excluded", "paper_divergence", "symbols"]


@functools.cache
def symbols() -> dict[str, sp.Symbol]:
    """Return the sympy symbols used (named as in the paper's appendix)."""
    names = "t k W v0 mu0 A B V_r D0 x Phi xdot alpha phi omega gamma kappa"
    syms = sp.symbols(names, positive=True)
    return dict(zip(names.split(), syms, strict=True))


@dataclass(frozen=True)
class DulacDerivation:
    """The derived autonomous system and its divergence.

    Attributes
    ----------
    velocity : sympy.Expr
        The slip velocity ``x'`` solved from the friction law (physical variables).
    alpha_dot, phi_dot : sympy.Expr
        ``d alpha/d tau`` and ``d phi/d tau``.
    divergence : sympy.Expr
        ``d(alpha_dot)/d alpha + d(phi_dot)/d phi``, simplified.
    sign_factor : sympy.Expr
        The factor whose sign decides: ``B - A - kappa``.
    positive_factor : sympy.Expr
        The rest, positive on ``phi > 0``: ``(gamma/A) phi^(-B/A) exp(-kappa alpha/A)``.

    """

    velocity: sp.Expr
    alpha_dot: sp.Expr
    phi_dot: sp.Expr
    divergence: sp.Expr
    sign_factor: sp.Expr
    positive_factor: sp.Expr


@functools.cache
def derive() -> DulacDerivation:
    """Derive the appendix's dimensionless system and its divergence from the physical equations."""
    s = symbols()
    t, k, w, v0, mu0, a, b, vr, d0 = (s[n] for n in "t k W v0 mu0 A B V_r D0".split())
    x, phi_state, xdot = s["x"], s["Phi"], s["xdot"]
    alpha, phi, omega, gamma, kappa = (s[n] for n in "alpha phi omega gamma kappa".split())
    phi0 = d0 / vr
    # quasi-static force balance with the rate-and-state friction law; solve it for x'
    balance = sp.Eq(k / w * (v0 * t - x), mu0 + b * sp.log(phi_state / phi0) + a * sp.log(xdot / vr))
    (velocity,) = sp.solve(balance, xdot)
    aging = 1 - xdot * phi_state / d0  # dPhi/dt
    # change of variables: x = D0 alpha + v0 t, Phi = Phi0 phi; parameters omega, kappa, gamma
    to_dimless = {x: d0 * alpha + v0 * t, phi_state: phi0 * phi}
    params = {v0: omega * vr, k: kappa * w / d0, mu0: -a * sp.log(gamma)}
    v_dl = velocity.subs(to_dimless).subs(params)
    v_dl = sp.simplify(sp.powsimp(sp.expand_log(sp.simplify(v_dl), force=True), force=True))
    # d alpha/d tau = (D0/V_r) d/dt[(x - v0 t)/D0] = (x' - v0)/V_r
    alpha_dot = sp.simplify((v_dl - omega * vr) / vr)
    # d phi/d tau = (D0/V_r)(1/Phi0) dPhi/dt = dPhi/dt
    phi_dot = sp.simplify(aging.subs(xdot, v_dl).subs(to_dimless).subs(params))
    div = sp.simplify(sp.diff(alpha_dot, alpha) + sp.diff(phi_dot, phi))
    sign_factor = b - a - kappa
    positive = sp.simplify(div / sign_factor)
    return DulacDerivation(velocity, alpha_dot, phi_dot, div, sign_factor, positive)


def paper_divergence() -> sp.Expr:
    """Return the divergence as printed in the paper's appendix (for comparison only)."""
    s = symbols()
    a, b, kappa, gamma, alpha, phi = (s[n] for n in "A B kappa gamma alpha phi".split())
    return (b - a - kappa) * gamma / a * phi ** (-b / a) * sp.exp(-kappa / a * alpha)


def excluded(a: float, b: float, kappa: float, *, rel: float = 1e-12) -> bool:
    """Return whether Dulac's criterion excludes periodic orbits for these values.

    ``a`` and ``b`` are the direct and evolution effects (the paper's ``A`` and ``B``).
    True unless ``b - a - kappa`` vanishes (to ``rel`` relative to the largest of
    ``a``, ``b``, ``kappa``).

    Raises
    ------
    ValueError
        For a non-positive ``a`` or ``kappa``, a negative ``b``, or a non-finite value.

    """
    from ..units import check_number

    a = check_number(a, "a", what="a positive direct effect a")
    b = check_number(b, "b", allow_zero=True, what="a non-negative evolution effect b")
    kappa = check_number(kappa, "kappa", what="a positive stiffness kappa = k Dc / W")
    return abs(b - a - kappa) > rel * max(a, b, kappa)


def sign_verdict(a: float, b: float, kappa: float) -> str:
    """Describe, in one sentence, what the criterion says for these values."""
    if not excluded(a, b, kappa):
        return (
            "b - a - kappa = 0: the divergence vanishes identically (the flow preserves "
            "area), Dulac's criterion says nothing, and closed orbits do exist (a centre)"
        )
    side = "negative" if b - a - kappa < 0 else "positive"
    return (
        f"b - a - kappa = {b - a - kappa:.6g} < 0"
        if side == "negative"
        else f"b - a - kappa = {b - a - kappa:.6g} > 0"
    ) + (f": the divergence is {side} on all of phi > 0, so no periodic orbit exists")


def lambdified() -> tuple[Any, Any]:
    """Return numpy functions ``alpha_dot(alpha, phi, omega, gamma, kappa, A, B)`` and ``phi_dot``."""
    s = symbols()
    d = derive()
    args = [s[n] for n in "alpha phi omega gamma kappa A B".split()]
    return sp.lambdify(args, d.alpha_dot, "numpy"), sp.lambdify(args, d.phi_dot, "numpy")


def lambdified_field() -> Any:
    """Return ``field(alpha, phi, omega, gamma, kappa, A, B) -> [alpha_dot, phi_dot]`` for an ODE solver.

    Printed by sympy from :func:`derive` with ``math`` functions: a scalar call
    costs a fraction of the numpy functions of :func:`lambdified`.
    """
    s = symbols()
    d = derive()
    args = [s[n] for n in "alpha phi omega gamma kappa A B".split()]
    return sp.lambdify(args, [d.alpha_dot, d.phi_dot], "math")
