"""The defining systems of the one-block model's bifurcation curves in a plane, and their tracing.

Unknowns are scaled to order one: a plane point ``u`` in the unit square (:mod:`~.planes`),
a pure-slip orbit by ``A`` (its spring-force maximum above ``f(nu)``, where it crosses
``w = nu`` upward) and ``tau = T / (2 pi)``. Each residual is one integration of the
compiled slip flow with its variational equations (:func:`~stickslip.core.api.run_flow`);
an unstable orbit is shot backward in time (as the one-parameter continuation does).

``hopf``  ``f'(nu) = 0`` in ``u``: steady sliding changes stability. Test ``bautin``:
    ``f'''(nu)``, whose sign is the criticality (the first Lyapunov coefficient of the
    Liénard form is ``l1 = -f'''/16``); where it vanishes the quintic coefficient
    ``-f^(5)/384`` of the averaged amplitude equation decides the Bautin point's type.
``branch``  the pure-slip orbits along a line of the plane (``G(A, tau, u1) = 0``, ``u2``
    fixed), from a Hopf point; tests ``fold`` (the log of the nontrivial Floquet
    multiplier, ``-integral of f'(w)``: zero at a fold of cycles of a planar flow) and
    ``graze`` (the minimum velocity).
``fold``  ``G(A, tau, u) = 0`` and ``ln m = 0``: the fold-of-cycles curve. Test ``graze``:
    where the fold orbit touches ``w = 0`` the curve ends (a fold-grazing point). Test
    ``cusp``: ``P''(A)``, the curvature of the first-return map ``P`` on ``w = nu`` at the
    fold's fixed point (:meth:`OneBlockSystems.section_map`). On the fold curve
    ``P(A) = A`` and ``P'(A) = 1``; its tangent ``(dA, du)`` obeys ``P_u du = 0`` and
    ``P''(A) dA + P'_u du = 0``, so the curve stops moving in the plane (``du = 0``, a cusp
    where three cycles meet) exactly where ``P''(A) = 0``.
``grazing``  from breakaway ``(s, w) = (1, 0)`` the slip returns to ``w = 0`` tangentially:
    ``s(T) = f(0+)`` and ``w(T) = 0`` in ``(tau, u)``. Where ``f(0+) = 1`` this is a
    periodic orbit through breakaway: a pure-slip orbit touching zero velocity, where the
    stick-slip orbit is born or dies. Test ``fold-grazing``: the orbit's ``ln m`` (a stable
    grazing orbit turns into the stick-slip orbit continuously; an unstable one collides
    with it).
``reversal``  the slip from breakaway stops at ``s1 < -1``, slips backward and stops again
    exactly at ``s = 1``: no stick is left in the cycle, and beyond it the block oscillates
    forward and backward without sticking (slip reversal). In ``(tau1, tau2, u)``:
    ``w(T1) = 0`` forward from ``(1, 0)``; backward from ``(s1, 0)``, ``w(T2) = 0`` and
    ``s(T2) = 1``. A backward slip is the forward flow of ``(-s, -w)`` at ``-nu`` (friction is
    odd), so both phases are one compiled flow.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..core.api import run_flow
from .planes import LawPoint, Plane

__all__ = ["OneBlockSystems"]

Residual = Callable[[np.ndarray], np.ndarray]
Test = Callable[[np.ndarray], float]


class OneBlockSystems:
    """Residuals and test functions of the one-block model's curves in ``plane``.

    Parameters
    ----------
    plane : Plane
    rtol : float
        Relative tolerance of the flow (Newton's tolerance is 100 times larger).

    """

    def __init__(self, plane: Plane, rtol: float = 1e-12) -> None:
        self.plane = plane
        self.kernel = plane.spec.kernel()
        self.rtol = rtol
        self.reverse = False
        self._cache: dict[tuple[str, bytes], dict[str, float]] = {}

    # ----------------------------------------------------------------------------- Hopf

    def point(self, u: np.ndarray) -> LawPoint:
        """Return the model at plane point ``u``."""
        return self.plane.at(u)

    def hopf(self, u: np.ndarray) -> np.ndarray:
        """``f'(nu)`` at ``u`` (one equation in two unknowns)."""
        p = self.point(u)
        if not p.nu > 0:
            raise ValueError(f"nu={p.nu!r} at u={u!r}: the plane left positive driving velocities")
        return np.array([p.f(p.nu, 1)])

    def hopf_tests(self) -> dict[str, Test]:
        """Test functions along the Hopf curve: ``bautin`` (``f'''``)."""

        def f3(u: np.ndarray) -> float:
            p = self.point(u)
            return p.f(p.nu, 3)

        return {"bautin": f3}

    # ----------------------------------------------------------------------------- orbits

    def _orbit(self, a: float, tau: float, u: np.ndarray) -> dict[str, float]:
        """One shot of the pure-slip orbit ``(A, tau)`` at ``u``: residual and measurements."""
        key = ("orbit", np.array([a, tau, *u, float(self.reverse)]).tobytes())
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        p = self.point(u)
        nu = p.nu
        s0 = p.f(nu) + a
        period = 2.0 * math.pi * tau
        if not (nu > 0 and period > 0 and math.isfinite(s0) and period < 1e6):
            raise RuntimeError(f"the orbit left the domain (nu={nu!r}, period={period!r})")
        fl = run_flow(
            self.kernel,
            p.lp(),
            nu,
            s0,
            nu,
            period,
            rtol=self.rtol,
            measure=True,
            checked=False,
            reverse=self.reverse,
        )
        out = {
            "gs": fl.s - s0,
            "gw": fl.w - nu,
            "log_multiplier": -float(fl.state[8]),
            "w_min": fl.w_min,
            "amplitude": s0 - fl.s_min,
            "nu": nu,
        }
        if len(self._cache) > 4096:
            self._cache.clear()
        self._cache[key] = out
        return out

    def branch(self, u2: float) -> Residual:
        """Residual of the pure-slip orbits on the line ``u[1] = u2``, in ``z = (A, tau, u1)``."""

        def g(z: np.ndarray) -> np.ndarray:
            o = self._orbit(float(z[0]), float(z[1]), np.array([z[2], u2]))
            return np.array([o["gs"], o["gw"]])

        return g

    def branch_tests(self, u2: float) -> dict[str, Test]:
        """``fold`` (``ln m``) and ``graze`` (minimum velocity) along a branch on ``u[1] = u2``."""

        def measure(z: np.ndarray, name: str) -> float:
            o = self._orbit(float(z[0]), float(z[1]), np.array([z[2], u2]))
            self.reverse = o["log_multiplier"] > 0.0
            return o[name]

        return {
            "fold": lambda z: measure(z, "log_multiplier"),
            "graze": lambda z: measure(z, "w_min"),
        }

    def fold(self, z: np.ndarray) -> np.ndarray:
        """Residual of the fold of cycles in ``z = (A, tau, u1, u2)``: ``G = 0``, ``ln m = 0``."""
        o = self._orbit(float(z[0]), float(z[1]), np.asarray(z[2:4]))
        return np.array([o["gs"], o["gw"], o["log_multiplier"]])

    def fold_tests(self) -> dict[str, Test]:
        """``graze`` (minimum velocity of the fold orbit) and ``cusp`` (``P''(A)``) along a fold curve."""
        return {
            "graze": lambda z: self._orbit(float(z[0]), float(z[1]), np.asarray(z[2:4]))["w_min"],
            "cusp": lambda z: self.map_curvature(float(z[0]), float(z[1]), np.asarray(z[2:4])),
        }

    def section_map(self, a: float, tau: float, u: np.ndarray) -> tuple[float, float]:
        """Return ``P(A)`` and ``P'(A)``: the slip from ``(f(nu) + A, nu)`` back to ``w = nu``.

        The section is ``w = nu`` crossed upward, ``A = s - f(nu)`` on it; the return is
        looked for near ``T = 2 pi tau`` (Newton on ``w(T) = nu``, ``w' = s - f(w)``; ``s`` is
        stationary there, ``s' = nu - w = 0``, so ``P`` is insensitive to the time's last
        error). For a planar flow ``P'(A) = exp(integral of div) (F(x0).n)/(F(x1).n)``; the
        divergence is ``-f'(w)`` and ``F.n = w' = A`` at the start, ``P(A)`` at the return.
        """
        p = self.point(u)
        nu = p.nu
        fn = p.f(nu)
        lp = p.lp()
        t = 2.0 * math.pi * tau
        for _ in range(12):
            if not (0 < t < 1e6):
                raise RuntimeError(f"the return to w = nu left the domain (T={t!r})")
            fl = run_flow(self.kernel, lp, nu, fn + a, nu, t, rtol=self.rtol, checked=False)
            dt = -(fl.w - nu) / (fl.s - p.f(fl.w))
            t += dt
            if abs(dt) <= 1e-14 * t:
                break
        pa = fl.s - fn
        return pa, math.exp(-fl.integral_dfdw) * a / pa

    def map_curvature(self, a: float, tau: float, u: np.ndarray) -> float:
        """Return ``P''(A)`` by central differences of :meth:`section_map`'s ``P'`` (step ``1e-4 A``)."""
        h = 1e-4 * a
        return (self.section_map(a + h, tau, u)[1] - self.section_map(a - h, tau, u)[1]) / (2.0 * h)

    # ----------------------------------------------------------------------------- grazing

    def _touch(self, tau: float, u: np.ndarray) -> dict[str, float]:
        """Return the slip from breakaway over ``2 pi tau``: where it ends and what it measured."""
        key = ("touch", np.array([tau, *u, float(self.reverse)]).tobytes())
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        p = self.point(u)
        period = 2.0 * math.pi * tau
        if not (p.nu > 0 and 0 < period < 1e6):
            raise RuntimeError(f"the orbit left the domain (nu={p.nu!r}, period={period!r})")
        f0 = p.f(0.0)
        if self.reverse:  # back from the end state: the same orbit, shot backward from (f0, 0)
            fl = run_flow(
                self.kernel,
                p.lp(),
                p.nu,
                f0,
                0.0,
                period,
                rtol=self.rtol,
                measure=True,
                checked=False,
                reverse=True,
            )
            gs, gw = fl.s - 1.0, fl.w
        else:
            fl = run_flow(
                self.kernel, p.lp(), p.nu, 1.0, 0.0, period, rtol=self.rtol, measure=True, checked=False
            )
            gs, gw = fl.s - f0, fl.w
        out = {
            "gs": gs,
            "gw": gw,
            "log_multiplier": -float(fl.state[8]),
            "w_max": fl.w_max,
            "nu": p.nu,
        }
        if len(self._cache) > 4096:
            self._cache.clear()
        self._cache[key] = out
        return out

    def grazing(self, z: np.ndarray) -> np.ndarray:
        """Residual of the tangency of the slip from breakaway with ``w = 0``, ``z = (tau, u1, u2)``."""
        o = self._touch(float(z[0]), np.asarray(z[1:3]))
        return np.array([o["gs"], o["gw"]])

    def reversal(self, z: np.ndarray) -> np.ndarray:
        """Residual of the cycle with no stick left, ``z = (tau1, tau2, u1, u2)``."""
        p = self.point(np.asarray(z[2:4]))
        t1, t2 = 2.0 * math.pi * float(z[0]), 2.0 * math.pi * float(z[1])
        if not (p.nu > 0 and 0 < t1 < 1e6 and 0 < t2 < 1e6):
            raise RuntimeError(f"the cycle left the domain (nu={p.nu!r}, T1={t1!r}, T2={t2!r})")
        lp = p.lp()
        fwd = run_flow(self.kernel, lp, p.nu, 1.0, 0.0, t1, rtol=self.rtol, checked=False)
        back = run_flow(self.kernel, lp, -p.nu, -fwd.s, 0.0, t2, rtol=self.rtol, checked=False)
        return np.array([fwd.w, back.w, back.s + 1.0])

    def first_stop(self, u: np.ndarray, s0: float, backward: bool = False) -> tuple[float, float] | None:
        """Return ``(T, s)`` where the slip from ``(s0, 0)`` first stops (backward: in ``(-s, -w)``).

        Stepped in pieces of 0.05 (each from where the last ended) and bisected in the piece
        where ``w`` reaches 0, to 1e-12; None without a stop before ``T = 200``. A flow that
        fails past the stop (a law with a pole at negative velocity) counts as stopped there.
        """
        p = self.point(u)
        nu = -p.nu if backward else p.nu
        lp = p.lp()
        dt = 0.05

        def flow(s: float, w: float, t: float) -> tuple[float, float]:
            try:
                fl = run_flow(self.kernel, lp, nu, s, w, t, rtol=self.rtol, checked=False)
                return fl.s, fl.w
            except RuntimeError:
                return math.nan, -1.0

        t, s, w = 0.0, s0, 0.0
        while t < 200.0:
            s1, w1 = flow(s, w, dt)
            if not w1 > 0.0:
                lo, hi = 0.0, dt
                while hi - lo > 1e-12 * max(t, 1.0):
                    mid = 0.5 * (lo + hi)
                    if flow(s, w, mid)[1] > 0.0:
                        lo = mid
                    else:
                        hi = mid
                return t + lo, flow(s, w, lo)[0] if lo > 0 else s
            t, s, w = t + dt, s1, w1
        return None

    def grazing_tests(self) -> dict[str, Test]:
        """``fold-grazing`` (``ln m`` of the grazing orbit) along a grazing curve."""

        def logm(z: np.ndarray) -> float:
            o = self._touch(float(z[0]), np.asarray(z[1:3]))
            self.reverse = o["log_multiplier"] > 1.0
            return o["log_multiplier"]

        return {"fold-grazing": logm}
