"""Periodic orbits with their Floquet multipliers: pure slip by Newton shooting, stick slip.

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

The stick-slip orbit through breakaway (:func:`stick_slip_orbit`) is the engine's; its
monodromy is the slip phase's, joined to the stick phase's by the saltation matrices
of the stop and of breakaway (:func:`saltation`).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..core.api import run_attractors, run_flow, run_shooting
from ..core.results import Regime, ShootingRows, ShootStatus
from ..errors import ArgumentTypeError
from ..laws import DimensionlessLaw
from ..models.parameters import DimensionlessParameters
from .return_map import check_guess
from .stability import averaged_amplitude

__all__ = [
    "PeriodicOrbit",
    "StickSlipOrbit",
    "orbit_from_shot",
    "pure_slip_orbit",
    "saltation",
    "stick_slip_orbit",
]


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
    ArgumentTypeError
        For ``params``, ``guess`` or ``tol`` of the wrong type.
    ValueError
        Without a guess where averaging gives none, or for ``tol`` or ``guess`` out of range.
    RuntimeError
        When Newton does not converge, or the orbit found reaches ``w <= 0``
        (it grazes: not pure slip).

    """
    if not isinstance(params, DimensionlessParameters):
        raise ArgumentTypeError(f"params={params!r}: expected DimensionlessParameters")
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
        raise ArgumentTypeError(f"tol={tol!r}: expected a tolerance between 1e-13 and 1e-3")
    if not 1e-13 <= tol <= 1e-3:
        raise ValueError(f"tol={tol!r}: expected a tolerance between 1e-13 and 1e-3")
    law, nu = params.law, params.nu
    f_nu = law.at(nu)
    if guess is None:
        a = averaged_amplitude(law, nu)
        if not math.isfinite(a):
            raise ValueError(
                f"no small-cycle guess at nu={nu!r} (averaging gives no cycle there): "
                "give guess=(s0, period), e.g. from stickslip.cycle"
            )
        guess = (f_nu + a, 2.0 * math.pi)
    s0, period = check_guess(guess)
    return _shot(law, nu, s0, period, tol, max_iter)


def _shot(
    law: DimensionlessLaw, nu: float, s0: float, period: float, tol: float, max_iter: int
) -> PeriodicOrbit:
    """Run the compiled shooting once and turn its output into a :class:`PeriodicOrbit`."""
    kernel, lp = law.arrays()
    sh = run_shooting(kernel, lp, [nu], [s0], [period], tol=tol, max_iter=max_iter)
    status = sh.statuses()[0]
    if status == ShootStatus.GRAZES:
        raise RuntimeError(f"{status.message} (w_min = {sh.w_min[0]:.3g})")
    if status != ShootStatus.OK:
        raise RuntimeError(
            f"{status.message} ({int(sh.iterations[0])} iterations, |G| = {sh.residual[0]:.3g})"
        )
    return orbit_from_shot(sh)


def orbit_from_shot(sh: ShootingRows) -> PeriodicOrbit:
    """Return the :class:`PeriodicOrbit` of a successful shooting (the first row of ``sh``)."""
    mult = np.linalg.eigvals(sh.monodromy[0])
    mult = mult[np.argsort(np.abs(np.abs(mult) - 1.0))]  # the trivial multiplier first
    return PeriodicOrbit(
        s0=float(sh.s0[0]),
        period=float(sh.period[0]),
        amplitude=float(sh.amplitude[0]),
        min_velocity=float(sh.w_min[0]),
        max_velocity=float(sh.w_max[0]),
        multipliers=(complex(mult[0]), complex(mult[1])),
        divergence_multiplier=float(sh.divergence_multiplier[0]),
        stable=bool(abs(mult[1]) < 1.0),
        iterations=int(sh.iterations[0]),
        residual=float(sh.residual[0]),
    )


@dataclass(frozen=True)
class StickSlipOrbit:
    """The stick-slip orbit through breakaway and its monodromy (dimensionless units).

    Attributes
    ----------
    nu : float
        Driving velocity.
    period, slip_time, stick_time : float
        Period and its slip and stick parts (units of ``sqrt(m/k)``).
    stop_force : float
        Spring force at the stop.
    monodromy : ndarray, shape (2, 2)
        ``S_break Phi_stick S_stop Phi_slip``: the linearised return map of a
        perturbation of the breakaway state, with the saltation matrices of the
        stop (slip to stick) and of breakaway (stick to slip).
    multipliers : tuple of complex
        Its eigenvalues, the trivial one (1) first; the other is 0: the stick
        phase forgets the velocity, so the orbit is superstable.

    """

    nu: float
    period: float
    slip_time: float
    stick_time: float
    stop_force: float
    monodromy: np.ndarray
    multipliers: tuple[complex, complex]


def saltation(f_before: np.ndarray, f_after: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Return the saltation matrix ``I + (F+ - F-) n^T / (n . F-)`` of a switch.

    ``f_before`` and ``f_after`` are the vector fields on either side at the
    switching point, ``normal`` the gradient of the switching function.
    """
    denom = float(normal @ f_before)
    if denom == 0.0:
        raise ValueError("the switching surface is reached tangentially (grazing): no saltation matrix")
    return np.eye(2) + np.outer(f_after - f_before, normal) / denom


def stick_slip_orbit(params: DimensionlessParameters, *, tol: float = 1e-10) -> StickSlipOrbit:
    """Compute the stick-slip orbit through breakaway and its Floquet multipliers.

    The slip phase from ``(s, w) = (1, 0)`` is integrated with its variational
    equations up to the stop found by the engine; the stick phase
    ``s' = nu, w = 0`` has the identity as its Jacobian. At the stop the flow
    switches from slip ``(nu, s - f(0))`` to stick ``(nu, 0)`` across ``w = 0``;
    at breakaway from stick to slip ``(nu, 1 - f(0+))`` across ``s = 1``.

    Raises
    ------
    RuntimeError
        When the slip from breakaway does not stop (no stick-slip orbit at this
        ``nu``) or the cycle contains backward slip (not covered).

    """
    if not isinstance(params, DimensionlessParameters):
        raise ArgumentTypeError(f"params={params!r}: expected DimensionlessParameters")

    kernel, lp = params.law.arrays()
    nu = params.nu
    o = run_attractors(
        kernel,
        lp,
        [nu],
        from_breakaway=True,
        rtol=tol * 1e-2,
        atol=tol * 1e-4,
        max_slip_time=1e5,
        conv_tol=1e-8,
    )
    if not o.is_regime(Regime.STICK_SLIP)[0]:
        raise RuntimeError(f"no stick-slip orbit at nu={nu!r}: the slip from breakaway does not stop")
    if o.n_backward[0] > 0:
        raise RuntimeError(
            f"the stick-slip cycle at nu={nu!r} has backward slip: its monodromy is not covered"
        )
    period = float(o.period[0])
    stick = float(o.stick_time[0])
    slip = period - stick
    fl = run_flow(kernel, lp, nu, 1.0, 0.0, slip, rtol=tol * 1e-2)
    s_stop = fl.s
    f0 = params.law.at(0.0)
    phi_slip = fl.monodromy
    s_stop_m = saltation(np.array([nu, s_stop - f0]), np.array([nu, 0.0]), np.array([0.0, 1.0]))
    s_break = saltation(np.array([nu, 0.0]), np.array([nu, 1.0 - f0]), np.array([1.0, 0.0]))
    mono = s_break @ np.eye(2) @ s_stop_m @ phi_slip
    mult = np.linalg.eigvals(mono)
    mult = mult[np.argsort(np.abs(mult - 1.0))]
    return StickSlipOrbit(
        nu=nu,
        period=period,
        slip_time=slip,
        stick_time=stick,
        stop_force=s_stop,
        monodromy=mono,
        multipliers=(complex(mult[0]), complex(mult[1])),
    )
