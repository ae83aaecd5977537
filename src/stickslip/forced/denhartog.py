r"""Den Hartog's exact steady state of the harmonically forced oscillator with Coulomb friction.

J. P. Den Hartog, "Forced vibrations with combined Coulomb and viscous friction",
Trans. ASME 53 (1931) APM-53-9, 107-115. In the units of the forced model
(:mod:`stickslip.core.forced`: forces of the friction force, times of
``sqrt(m/k)``, no drive) the block obeys

.. math:: x'' + \delta x' + x = q \cos(\omega \tau) - \operatorname{sgn}(x')

and Den Hartog's motion without stops is symmetric: ``x(tau + T/2) = -x(tau)``,
each half period a slip in one direction from one turning point ``-X`` (velocity
0) to the next, ``+X``. Over a half period the equation is linear, so its solution
is a homogeneous part plus the particular one; the four conditions at the two
turning points are linear in ``(A, B, X, q cos theta, q sin theta)`` (``A, B`` the
homogeneous amplitudes, ``theta`` the forcing's phase at the turning point ``-X``),
and with ``cos**2 + sin**2 = 1`` they leave a quadratic. Its root with ``X > 0``
is the steady state; it holds (the motion has no stop) where the velocity keeps
its sign over the half period and the net force at the turning point exceeds the
static friction, which is Den Hartog's boundary.

The spring force of the forced model is ``s = -x`` and its velocity ``w = x'``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["DenHartog", "den_hartog"]


@dataclass(frozen=True)
class DenHartog:
    """The steady state without stops (Den Hartog 1931).

    Attributes
    ----------
    amplitude : float
        ``X``, the largest displacement (units of the friction force over ``k``);
        NaN where no such motion exists.
    theta : float
        The phase ``omega tau`` of the force ``q cos(omega tau)`` at the turning point
        ``x = -X`` (rad, in ``[0, 2 pi)``).
    valid : bool
        The motion has no stop: the velocity keeps its sign between turning points
        and the net force at a turning point exceeds the static friction.
    reverses : bool
        The net force at the turning point exceeds the static friction.
    monotone : bool
        The velocity keeps its sign over each half period.

    """

    omega: float
    q: float
    delta: float
    amplitude: float
    theta: float
    coefficients: tuple[float, float]
    valid: bool
    reverses: bool
    monotone: bool

    def state(self, tau: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """Return the displacement ``x`` and velocity ``x'`` of the steady state at times ``tau``."""
        t = np.asarray(tau, dtype=float)
        half = math.pi / self.omega
        t0 = self.theta / self.omega
        sigma = np.mod(t - t0, 2.0 * half)
        second = sigma >= half
        sigma = np.where(second, sigma - half, sigma)
        x, v = _half(self, sigma)
        return np.where(second, -x, x), np.where(second, -v, v)


def _basis(omega: float, delta: float, sigma: np.ndarray) -> tuple[np.ndarray, ...]:
    """Return the homogeneous and particular basis functions and their derivatives at ``sigma``."""
    wd = math.sqrt(1.0 - 0.25 * delta * delta)
    e = np.exp(-0.5 * delta * sigma)
    c, s = np.cos(wd * sigma), np.sin(wd * sigma)
    h1, h2 = e * c, e * s
    dh1 = e * (-0.5 * delta * c - wd * s)
    dh2 = e * (-0.5 * delta * s + wd * c)
    den = (1.0 - omega**2) ** 2 + (delta * omega) ** 2
    al, be = (1.0 - omega**2) / den, delta * omega / den
    co, si = np.cos(omega * sigma), np.sin(omega * sigma)
    pc = al * co + be * si  # coefficient of q cos(theta) in x_p
    ps = be * co - al * si  # ... of q sin(theta)
    dpc = omega * (-al * si + be * co)
    dps = omega * (-be * si - al * co)
    return h1, h2, dh1, dh2, pc, ps, dpc, dps


def _half(dh: DenHartog, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    h1, h2, dh1, dh2, pc, ps, dpc, dps = _basis(dh.omega, dh.delta, sigma)
    a, b = dh.coefficients
    qc, qs = dh.q * math.cos(dh.theta), dh.q * math.sin(dh.theta)
    return a * h1 + b * h2 + qc * pc + qs * ps - 1.0, a * dh1 + b * dh2 + qc * dpc + qs * dps


def den_hartog(omega: float, q: float, delta: float = 0.0, *, samples: int = 4001) -> DenHartog:
    """Return Den Hartog's steady state at forcing frequency ``omega`` and amplitude ``q``.

    Parameters
    ----------
    omega : float
        Forcing frequency over the natural frequency ``sqrt(k/m)`` (> 0, not 1 without damping).
    q : float
        Force amplitude over the friction force (> 0).
    delta : float
        Viscous damping ``c / sqrt(k m)`` (0 <= delta < 2).
    samples : int
        Points of the half period on which the velocity's sign is checked (its zeros
        between them are found from the sign of the velocity's samples and their
        local minima).

    """
    if not (omega > 0.0 and q > 0.0 and 0.0 <= delta < 2.0):
        raise ValueError(
            f"omega={omega!r}, q={q!r}, delta={delta!r}: expected omega > 0, q > 0, 0 <= delta < 2"
        )
    half = math.pi / omega
    ends = np.array([0.0, half])
    h1, h2, dh1, dh2, pc, ps, dpc, dps = _basis(omega, delta, ends)
    # unknowns (A, B, X, C = q cos theta, S = q sin theta)
    m = np.array(
        [
            [h1[0], h2[0], 1.0, pc[0], ps[0]],  # x(0) = -X
            [dh1[0], dh2[0], 0.0, dpc[0], dps[0]],  # x'(0) = 0
            [h1[1], h2[1], -1.0, pc[1], ps[1]],  # x(T/2) = X
            [dh1[1], dh2[1], 0.0, dpc[1], dps[1]],  # x'(T/2) = 0
        ]
    )
    rhs = np.array([1.0, 0.0, 1.0, 0.0])
    z0 = np.linalg.lstsq(m, rhs, rcond=None)[0]
    null = np.linalg.svd(m)[2][-1]
    # (C, S) = (z0 + t null)[3:5] on the circle of radius q: a quadratic in t
    c0, n0 = z0[3:5], null[3:5]
    qa, qb, qc = n0 @ n0, 2.0 * c0 @ n0, c0 @ c0 - q * q
    disc = qb * qb - 4.0 * qa * qc
    nan = DenHartog(omega, q, delta, math.nan, math.nan, (math.nan, math.nan), False, False, False)
    if disc < 0.0:
        return nan
    best = None
    for t in ((-qb + math.sqrt(disc)) / (2 * qa), (-qb - math.sqrt(disc)) / (2 * qa)):
        z = z0 + t * null
        if z[2] > 0.0 and (best is None or z[2] > best[2]):
            best = z
    if best is None:
        return nan
    theta = math.atan2(best[4], best[3]) % (2.0 * math.pi)
    dh = DenHartog(
        omega, q, delta, float(best[2]), theta, (float(best[0]), float(best[1])), False, False, False
    )
    sigma = np.linspace(0.0, half, samples)[1:-1]
    _, v = _half(dh, sigma)
    monotone = bool(np.all(v > 0.0))
    # the net force on the block at the turning point x = +X (time T/2), against the static friction 1
    net = -dh.amplitude + q * math.cos(theta + math.pi)
    reverses = net < -1.0
    return DenHartog(
        omega, q, delta, dh.amplitude, theta, dh.coefficients, monotone and reverses, reverses, monotone
    )
