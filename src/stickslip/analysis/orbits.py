"""Pure-slip periodic orbits by Newton shooting, with Floquet multipliers.

A pure-slip orbit never stops, so in the slip region the flow is smooth:

    s' = nu - w,   w' = s - f(w)                         (w > 0)

The orbit is found as a zero of ``G(s0, T) = phi_T(s0, nu) - (s0, nu)``: the
state after a time ``T`` from ``(s0, w = nu)`` must return to itself (the phase
is fixed by starting on ``w = nu``, where ``s`` is at its maximum). Newton's
method uses the exact Jacobian ``[Phi(T) e_s - e_s, F(phi_T)]`` from the
variational equations ``Phi' = J Phi``, ``J = [[0, -1], [1, -f'(w)]]``
integrated alongside the flow. The Floquet multipliers are the eigenvalues of
the monodromy matrix ``Phi(T)``: one equals 1 (the orbit is autonomous); for a
planar flow the other equals ``exp(-integral of f'(w) over the period)``,
integrated here as an independent check. An orbit that would touch ``w = 0``
is not pure slip (it grazes and becomes stick-slip): that is reported.

This solves where transients crawl: near a Hopf point the approach to the
cycle is as slow as the distance to the bifurcation, but Newton converges
quadratically from a nearby guess (the averaging amplitude).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core import variational as va
from ..models.parameters import DimensionlessParameters
from .stability import averaged_amplitude

__all__ = ["PeriodicOrbit", "pure_slip_orbit"]


@dataclass(frozen=True)
class PeriodicOrbit:
    """A pure-slip periodic orbit (dimensionless units).

    Attributes
    ----------
    s0 : float
        Spring force where the orbit crosses ``w = nu`` upward (its maximum).
    period : float
        Period (units of ``sqrt(m/k)``).
    amplitude : float
        ``max s - min s`` over the orbit.
    min_velocity, max_velocity : float
        Extremes of ``w`` (``min_velocity > 0`` for pure slip).
    multipliers : tuple of complex
        Floquet multipliers (eigenvalues of the monodromy matrix).
    divergence_multiplier : float
        ``exp(-integral of f'(w) dt)``: equals the nontrivial multiplier.
    stable : bool
        Both nontrivial multipliers inside the unit circle.
    iterations : int
        Newton iterations.
    residual : float
        Final ``|G|``.

    """

    s0: float
    period: float
    amplitude: float
    min_velocity: float
    max_velocity: float
    multipliers: tuple[complex, complex]
    divergence_multiplier: float
    stable: bool
    iterations: int
    residual: float


def _law_arrays(params: DimensionlessParameters) -> tuple[int, np.ndarray]:
    return int(params.law.core_id), np.ascontiguousarray(params.law.core_params(), dtype=np.float64)  # type: ignore[attr-defined]


def flow(
    law_id: int,
    lp: np.ndarray,
    nu: float,
    s0: float,
    w0: float,
    period: float,
    rtol: float,
    measure: bool = False,
    max_steps: int = 200_000,
) -> tuple[np.ndarray, np.ndarray]:
    """Integrate the slip flow and its variational equations over ``[0, period]``.

    Returns the final state (see :mod:`stickslip.core.variational` for the
    layout) and the measurements ``extras``.

    Raises
    ------
    RuntimeError
        When the integration fails (step budget, non-finite state).

    """
    y = np.zeros(va.NVAR)
    y[0], y[1], y[2], y[5] = s0, w0, 1.0, 1.0
    kv = np.empty((12, 7))
    extras = np.zeros(va.NX)
    va.flow_variational(law_id, lp, nu, y, period, rtol, rtol * 1e-2, max_steps, measure, kv, extras)
    if extras[va.X_STATUS] != va.VS_OK:
        why = (
            "the step budget ran out"
            if extras[va.X_STATUS] == va.VS_MAX_STEPS
            else "the state became non-finite"
        )
        raise RuntimeError(f"slip flow from (s, w) = ({s0:.6g}, {w0:.6g}) over tau = {period:.6g}: {why}")
    return y, extras


def pure_slip_orbit(
    params: DimensionlessParameters,
    *,
    guess: tuple[float, float] | None = None,
    tol: float = 1e-10,
    max_iter: int = 30,
) -> PeriodicOrbit:
    """Find the pure-slip periodic orbit at ``params`` by Newton shooting.

    Parameters
    ----------
    params : DimensionlessParameters
        Driving velocity and law.
    guess : (s0, period), optional
        Starting point; default from first-order averaging near a Hopf point
        (``s0 = f(nu) + a``, period ``2 pi``).
    tol : float, optional
        Tolerance on ``|G|``; the flow is integrated at ``tol / 100``.
    max_iter : int, optional
        Newton iterations allowed.

    Raises
    ------
    ValueError
        Without a guess where averaging gives none, or for an invalid ``tol``.
    RuntimeError
        When Newton does not converge, or the orbit found reaches ``w <= 0``
        (it grazes: not pure slip).

    """
    if not isinstance(params, DimensionlessParameters):
        raise ValueError(f"params={params!r}: expected DimensionlessParameters")
    if not (isinstance(tol, float) and 1e-13 <= tol <= 1e-3):
        raise ValueError(f"tol={tol!r}: expected a tolerance between 1e-13 and 1e-3")
    law, nu = params.law, params.nu
    f_nu = float(law.forward(np.array([nu]))[0])  # type: ignore[attr-defined]
    if guess is None:
        a = averaged_amplitude(law, nu)
        if not math.isfinite(a):
            raise ValueError(
                f"no small-cycle guess at nu={nu!r} (averaging gives no cycle there): "
                "give guess=(s0, period), e.g. from stickslip.cycle"
            )
        guess = (f_nu + a, 2.0 * math.pi)
    s0, period = float(guess[0]), float(guess[1])
    rtol = tol * 1e-2
    residual = math.inf
    law_id, lp = _law_arrays(params)
    for it in range(1, max_iter + 1):
        y, _ = flow(law_id, lp, nu, s0, nu, period, rtol)
        g = np.array([y[0] - s0, y[1] - nu])
        residual = float(np.linalg.norm(g))
        if residual < tol:
            break
        phi = y[2:6].reshape(2, 2)
        fT = np.array([nu - y[1], y[0] - float(law.forward(np.array([y[1]]))[0])])  # type: ignore[attr-defined]
        jac = np.column_stack([phi[:, 0] - np.array([1.0, 0.0]), fT])
        ds0, dT = np.linalg.solve(jac, -g)
        s0, period = s0 + ds0, period + dT
        if not (math.isfinite(s0) and math.isfinite(period) and period > 0):
            raise RuntimeError(f"shooting diverged at iteration {it} (period {period!r}); try a better guess")
    else:
        raise RuntimeError(f"shooting did not converge in {max_iter} iterations (|G| = {residual:.3g})")
    y, extras = flow(law_id, lp, nu, s0, nu, period, rtol, measure=True)
    if extras[va.X_W_MIN] <= 0:
        raise RuntimeError(
            f"the orbit found reaches w = {extras[va.X_W_MIN]:.3g} <= 0: it grazes, "
            "so it is not a pure-slip orbit (the motion sticks)"
        )
    phi = y[2:6].reshape(2, 2)
    mult = np.linalg.eigvals(phi)
    order = np.argsort(np.abs(np.abs(mult) - 1.0))  # the trivial multiplier first
    mult = mult[order]
    div_mult = math.exp(-float(y[8]))
    return PeriodicOrbit(
        s0=s0,
        period=period,
        amplitude=float(s0 - extras[va.X_S_MIN]),
        min_velocity=float(extras[va.X_W_MIN]),
        max_velocity=float(extras[va.X_W_MAX]),
        multipliers=(complex(mult[0]), complex(mult[1])),
        divergence_multiplier=div_mult,
        stable=bool(abs(mult[1]) < 1.0),
        iterations=it,
        residual=residual,
    )
