"""Non-sticking orbits as fixed points of the return map on ``w = nu``: the engine's, exact.

A pure-slip or slip-reversal orbit never sticks; its spring-force maximum (where
``w`` crosses ``nu`` upward) returns to itself after one period. The return map
``P`` is computed by the exact non-smooth engine (backward slip and its velocity
reversals handled) and ``P(s) = s`` is solved by secant iterations. The polish of
attractors (:mod:`~.attractors`) solves slip-reversal orbits with it, for the basic
operations (:mod:`stickslip.dynamics`) and the regimes (:mod:`stickslip.bifurcation`)
alike; :func:`check_guess` checks the ``(s0, period)`` guesses of shooting too
(:mod:`~.periodic`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.api import Kernel, Trajectories
from ..core.checks import MAX_STATE, number_pair
from ..core.results import EventKind, Status
from ..laws import DimensionlessLaw

__all__ = ["ReturnMapOrbit", "check_guess", "next_force_maximum", "return_map_orbit", "return_map_orbit_core"]


def check_guess(guess: Any) -> tuple[float, float]:
    """Return ``(s0, period)`` as floats: a finite spring force and a positive period."""
    s0, period = number_pair(guess, f"guess={guess!r}: expected a pair (s0, period) of numbers")
    if not (math.isfinite(s0) and math.isfinite(period) and period > 0):
        raise ValueError(f"guess={guess!r}: expected a finite s0 and a positive period")
    return s0, period


def next_force_maximum(
    kernel: Kernel,
    lp: np.ndarray,
    nu: float,
    s0: float,
    t_guess: float,
    *,
    rtol: float,
    atol: float,
    runs: Trajectories | None = None,
) -> tuple[float, float]:
    """Return ``(s, t)`` at the next spring-force maximum after leaving ``(s0, w = nu)`` (exact engine).

    This is the Poincaré return map on the section ``w = nu`` (crossed upward, where
    ``s`` is largest); the non-smooth engine handles stops and slip reversals on the way.
    ``runs``: the law, ``lp``, ``nu`` and tolerances checked once, for many calls.
    """
    if runs is None:
        runs = Trajectories(kernel, lp, nu, rtol=rtol, atol=atol)
    t_end = 2.5 * t_guess
    for _ in range(8):
        ev, status = runs.events(s0, nu, t_end)
        if status != Status.OK:
            raise RuntimeError(f"return map from s = {s0:.6g}: the integration failed ({status.message})")
        if np.any(ev[:, 1] == EventKind.STICK.code):
            raise RuntimeError(f"return map from s = {s0:.6g}: the motion sticks (not a non-sticking orbit)")
        hit = ev[(ev[:, 1] == EventKind.FORCE_MAXIMUM.code) & (ev[:, 0] > 0.0)]
        if hit.size:
            return float(hit[0, 2]), float(hit[0, 0])
        t_end *= 2.0
    raise RuntimeError(f"return map from s = {s0:.6g}: no spring-force maximum within tau = {t_end:.3g}")


@dataclass(frozen=True)
class ReturnMapOrbit:
    """A non-sticking orbit found as a fixed point of the return map on ``w = nu`` (dimensionless).

    Attributes
    ----------
    s0 : float
        Spring-force maximum (where ``w`` crosses ``nu`` upward).
    period : float
        Return time.
    multiplier : float
        Derivative of the return map at the fixed point: the nontrivial Floquet
        multiplier (central difference).
    residual : float
        ``|P(s0) - s0|``.

    """

    s0: float
    period: float
    multiplier: float
    residual: float


def return_map_orbit(
    law: DimensionlessLaw,
    nu: float,
    guess: tuple[float, float],
    *,
    tol: float = 1e-10,
    max_iter: int = 40,
) -> ReturnMapOrbit:
    """Find a non-sticking periodic orbit (pure slip or slip reversal) as a fixed point of the return map.

    The return map ``P`` takes the spring force at one upward crossing of ``w = nu``
    to the next, computed by the exact non-smooth engine (so backward slip and
    its velocity reversals are handled). Secant iterations solve ``P(s) = s``.

    Raises
    ------
    RuntimeError
        When the iteration does not converge or the motion sticks.

    """
    kernel, lp = law.arrays()
    return return_map_orbit_core(kernel, lp, nu, check_guess(guess), tol=tol, max_iter=max_iter)


def return_map_orbit_core(
    kernel: Kernel,
    lp: np.ndarray,
    nu: float,
    guess: tuple[float, float],
    *,
    tol: float = 1e-10,
    max_iter: int = 40,
) -> ReturnMapOrbit:
    """:func:`return_map_orbit` for a law given by its compiled kernel and parameter vector.

    In Python, around the compiled engine's trajectories: a few orbits need no
    compilation of their own (a cycle's). Many at once run compiled, bit for bit the
    same (:func:`~stickslip.core.api.run_return_maps`, as a sweep's slip-reversal rows do).
    """
    rtol, atol = tol * 1e-2, tol * 1e-4
    runs = Trajectories(kernel, lp, nu, rtol=rtol, atol=atol)

    def g(s: float) -> tuple[float, float]:
        if not abs(s) <= MAX_STATE:  # as the compiled secant says it
            raise RuntimeError(
                f"return map: the secant iteration left the states the engine takes (s = {s:.6g})"
            )
        s1, t1 = next_force_maximum(kernel, lp, nu, s, guess[1], rtol=rtol, atol=atol, runs=runs)
        return s1 - s, t1

    scale = max(1.0, abs(guess[0]))
    x0 = float(guess[0])
    x1 = x0 + 1e-6 * scale
    g0, _ = g(x0)
    g1, t1 = g(x1)
    for _ in range(max_iter):
        if abs(g1) < tol * scale:
            break
        if g1 == g0:
            raise RuntimeError("return map: the secant iteration stalled")
        x0, x1, g0 = x1, x1 - g1 * (x1 - x0) / (g1 - g0), g1
        g1, t1 = g(x1)
    else:
        raise RuntimeError(
            f"return map: no fixed point within {max_iter} iterations (|P(s) - s| = {abs(g1):.3g})"
        )
    # the derivative of the map by central differences at h and h/2, extrapolated (Richardson):
    # the map is strongly curved near sticking, and the difference at h = 1e-5 alone is off by
    # 1e-7 to 3e-7 (0.60144688 where the variational equations with saltation say
    # 0.60144723); extrapolated, 7.5e-12 and 6.9e-9 from them at two orbits (a
    # third level, h/4, is no better: the map's integration noise then dominates)
    h = 1e-5 * scale

    def central(step: float) -> float:
        return (g(x1 + step)[0] - g(x1 - step)[0]) / (2.0 * step)

    mult = 1.0 + (4.0 * central(0.5 * h) - central(h)) / 3.0
    return ReturnMapOrbit(s0=x1, period=t1, multiplier=mult, residual=abs(g1))
