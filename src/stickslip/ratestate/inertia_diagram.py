"""The inertial rate-and-state slider's (V, k) diagram: its Hopf curve continued, its Bautin points.

:func:`inertial_diagram` continues the Hopf set of steady sliding of an
:class:`~stickslip.ratestate.inertia.InertialSlider` (the Routh-Hurwitz residual
:meth:`~stickslip.ratestate.inertia.InertialSlider.hopf_residual`) in the plane of the
load-point velocity ``V`` and the stiffness ``k`` by the pseudo-arclength continuation of
the one-block diagrams (:func:`~stickslip.bifurcation.arclength.trace`), in the unit square of
logarithmic axes, watching the first Lyapunov coefficient along it: where it changes sign
(a Bautin point) the second decides whether the subcritical cycles fold back into a stable
one. Its regions are where steady sliding is stable (``k > k_c``) and where it is not; the
oscillations beyond are not continued here (a periodic orbit of the three-variable slider
needs shooting in three dimensions), so that region is named as undetermined.

The curve is compared in the tests with the closed form ``k_c(V)`` of Rice and Ruina (1983)
with the inertial term (exact for this model).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..bifurcation.arclength import newton, trace
from ..bifurcation.diagram import Curve, Diagram, SpecialPoint2
from ..bifurcation.planes import Axes, Axis, check_positive_int
from .inertia import InertialSlider

__all__ = ["inertial_diagram"]

#: the regions' names
STABLE = "steady-sliding"
UNSTABLE = "undetermined: steady sliding unstable (its oscillations are not continued)"


def _range(value: Any, name: str) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}={value!r}: expected (lo, hi), two positive numbers") from None
    if not (0 < lo < hi and math.isfinite(hi)):
        raise ValueError(f"{name}={value!r}: expected 0 < lo < hi")
    return lo, hi


def _on_line(
    residual: Callable[[np.ndarray], np.ndarray], at: np.ndarray, free: int, z: np.ndarray
) -> np.ndarray:
    u = at.copy()
    u[free] = z[0]
    return residual(u)


def _bautin_words(m: float, l2: float) -> str:
    side = "< 0: a stable large cycle beside the unstable small one" if l2 < 0 else "> 0"
    where = f"the inertia number M V^2/(sigma D_c) = {m:.6g}"
    return f"Bautin (generalized Hopf): l1 changes sign at {where}; l2 {side}"


def inertial_diagram(
    slider: InertialSlider,
    velocity: tuple[float, float],
    stiffness: tuple[float, float],
    *,
    step: float = 0.02,
    raster: int = 120,
    seed_lines: int = 5,
) -> Diagram:
    """Continue the Hopf curve of the inertial slider over ``V`` (m/s) and ``k`` (Pa/m).

    Parameters
    ----------
    slider : InertialSlider
        The slider (its law, ``a``, ``b``, ``D_c``, ``sigma`` and mass per area).
    velocity, stiffness : (lo, hi)
        The plane: load-point velocity (m/s, shown in um/s) and stiffness per area (Pa/m),
        both on logarithmic axes.
    step : float, optional
        Largest continuation step (fraction of the plane).
    raster : int, optional
        Cells per axis of the regions' raster.
    seed_lines : int, optional
        Lines of constant ``k`` on which the curve is seeded.

    Returns
    -------
    Diagram
        With Hopf curves (``data``: ``l1`` along them, ``nu`` set to the inertia number
        ``M V^2/(sigma D_c)``), Bautin points (``value``: the second Lyapunov coefficient), and the
        regions of stable and unstable steady sliding.

    """
    if not isinstance(slider, InertialSlider):
        from ..errors import ArgumentTypeError

        raise ArgumentTypeError(f"slider={slider!r}: expected an InertialSlider")
    v_lo, v_hi = _range(velocity, "velocity")
    k_lo, k_hi = _range(stiffness, "stiffness")
    raster = check_positive_int(raster, "raster", 10, 2000)
    seed_lines = check_positive_int(seed_lines, "seed_lines", 1, 200)
    ax = Axis("V", v_lo * 1e6, v_hi * 1e6, True, "um/s", 1e-6)
    ay = Axis("k", k_lo, k_hi, True, "Pa/m", 1.0)
    words = (
        f"inertial rate-and-state slider ({slider.law} law; a = {slider.a:g}, b = {slider.b:g}, "
        f"D_c = {slider.dc:g} m, sigma = {slider.sigma:g} Pa, M = {slider.mass:g} kg/m^2) over (V, k)"
    )
    axes = Axes(ax, ay, words)
    b_a = (slider.b - slider.a) / slider.a

    def vk(u: np.ndarray) -> tuple[float, float]:
        return ax.to_unit(float(u[0])) * 1e-6, ay.to_unit(float(u[1]))

    def residual(u: np.ndarray) -> np.ndarray:
        v, k = vk(u)
        return np.array([slider.hopf_residual(v, k) / max(b_a, 1e-300)])

    def l1(u: np.ndarray) -> float:
        v, k = vk(u)
        return slider.first_lyapunov(v, k)

    def box(u: np.ndarray) -> float:
        return float(min(u[0], 1.0 - u[0], u[1], 1.0 - u[1]))

    curves: list[Curve] = []
    points: list[SpecialPoint2] = []
    grid = np.linspace(0.0, 1.0, 200)
    lines = np.linspace(0.0, 1.0, seed_lines) if seed_lines > 1 else np.array([0.5])
    seeds = []
    for c in lines:  # sign changes along lines of constant k and of constant V
        for along_x in (True, False):
            pts = [np.array([g, c]) if along_x else np.array([c, g]) for g in grid]
            vals = np.array([float(residual(p)[0]) for p in pts])
            for i in np.flatnonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) < 0):
                free = 0 if along_x else 1
                res = newton(
                    functools.partial(_on_line, residual, pts[i], free),
                    np.array([0.5 * (grid[i] + grid[i + 1])]),
                    tol=1e-14,
                )
                if res is not None:
                    seed = pts[i].copy()
                    seed[free] = float(res[0][0])
                    seeds.append(seed)
    for seed in seeds:
        if any(np.min(np.linalg.norm(c.u - seed, axis=1)) < 2 * step for c in curves):
            continue
        tests = {"bautin": l1} if slider.mass > 0 else {}
        tc = trace(residual, seed, tests=tests, inside=box, h0=step / 4, h_max=step, tol=1e-13)
        xs, ys = axes.values(tc.x)
        v_si = np.asarray(xs) * 1e-6
        curves.append(
            Curve(
                "hopf",
                np.asarray(xs),
                np.asarray(ys),
                tc.x,
                {
                    "nu": np.array([slider.inertia_number(float(v)) for v in v_si]),
                    "l1": tc.tests.get("bautin", np.zeros(len(tc.x))),
                    # the figure draws a Hopf curve dashed where f3 < 0 (subcritical): here l1 > 0
                    "f3": -tc.tests.get("bautin", np.zeros(len(tc.x))),
                },
                tc.end,
            )
        )
        for e in tc.events:
            v, k = vk(e.x)
            x, y = axes.values(e.x)
            l2 = slider.second_lyapunov(v, k)
            points.append(
                SpecialPoint2(
                    "bautin",
                    float(x),
                    float(y),
                    slider.inertia_number(v),
                    "second Lyapunov coefficient l2",
                    l2,
                    _bautin_words(slider.inertia_number(v), l2),
                )
            )
    rx = np.linspace(0.5 / raster, 1 - 0.5 / raster, raster)
    region = np.array(
        [[0 if float(residual(np.array([ux, uy]))[0]) > 0 else 1 for ux in rx] for uy in rx], dtype=np.int64
    )
    xs, ys = axes.values(np.stack([rx, rx], axis=-1))
    notes = [
        "where steady sliding is unstable the slider oscillates (stick-slip or a limit cycle); those "
        "oscillations are not continued for the three-variable slider: the region is named undetermined"
    ]
    return Diagram(
        axes,
        curves,
        points,
        region,
        [STABLE, UNSTABLE],
        ["steady-sliding", "unknown"],
        np.asarray(xs),
        np.asarray(ys),
        notes,
    )
