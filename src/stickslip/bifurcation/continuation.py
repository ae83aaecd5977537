"""Pseudo-arclength continuation of the pure-slip orbits born at a Hopf point.

Each point of a branch solves the periodic-orbit equations in ``x = (A, T, nu)``
(``A`` = spring-force maximum above ``f(nu)``, ``T`` = period) by Newton's method,
the residual and its Jacobian from one integration of the compiled variational
equations (:func:`~stickslip.core.api.run_flow`), backward in time wherever the
orbit is unstable. The steps are taken in coordinates scaled by the Hopf point's
size. A branch ends where its minimum velocity touches zero (grazing, located by a
secant), where it leaves the range, or where its period blows up; a fold of cycles
on the way is located by Brent on the ``nu`` component of the branch's tangent.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from ..core.api import run_flow
from ..laws import DimensionlessLaw, require_dimensionless_law
from ..orbits.stability import Hopf
from .branches import Branch, SpecialPoint

__all__ = ["continue_pure_slip"]


def _kink_ratio(f2_left: float, f2_right: float) -> float:
    """Return ``r = (nu - nu_H) / a`` of the small cycles born at a Hopf point on a kink of ``f'``.

    With ``f'(nu_H) = 0`` and ``f''`` equal to ``f2_left`` below ``nu_H`` and ``f2_right``
    above, the averaged amplitude equation of a cycle ``w = nu + a sin(theta)`` is homogeneous
    of degree 2 in ``(nu - nu_H, a)``; it vanishes where ``G(r)``, the first Fourier sine
    coefficient of ``f2(x) x**2`` with ``x = r + sin(theta)``, does: a root in ``(-1, 1)``
    (the cycle straddles the kink). The small-``r`` expansion ``r = -2 J / (3 pi f2)`` is 2.6
    times too large for a table with ``f''`` of 8747 and 1757 on its two sides.
    """
    from scipy.optimize import brentq

    theta = np.linspace(0.0, 2.0 * math.pi, 4097)[:-1]
    sin = np.sin(theta)

    def g(r: float) -> float:
        x = r + sin
        return float(np.mean(np.where(x > 0, f2_right, f2_left) * x * x * sin))

    lo, hi = g(-1.0), g(1.0)
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo * hi >= 0:
        return 0.0
    return float(brentq(g, -1.0, 1.0, xtol=1e-12))


class _Scaled:
    """A :class:`_Shooter` in scaled coordinates ``y = x / size``, for the continuation's steps.

    Unscaled, the arclength in ``x = (A, T, nu)`` lets the period dominate where ``nu`` is
    small: at a Hopf point at ``nu = 0.002`` (a table law) a step of ``0.02 nu`` moves ``T``
    by ``4e-5`` of its ``2 pi``, and 600 steps go nowhere. Scaled by ``(nu_H, 2 pi, nu_H)``
    (``nu_H`` at least 0.1), each component steps in proportion to its own size.
    """

    def __init__(self, sh: _Shooter, size: np.ndarray) -> None:
        self.sh, self.size = sh, size

    def residual(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        g, j = self.sh.residual(y * self.size)
        return g, j * self.size

    def measure(self, y: np.ndarray) -> dict[str, float]:
        return self.sh.measure(y * self.size)

    def evaluate(self, y: np.ndarray, *, measure: bool) -> tuple[np.ndarray, np.ndarray, dict[str, float]]:
        g, j, m = self.sh.evaluate(y * self.size, measure=measure)
        return g, j * self.size, m


class _Shooter:
    """Residual and Jacobian of the periodic-orbit equations in ``x = (A, T, nu)``.

    With ``reverse`` the period is integrated backward in time from the orbit's spring-force
    maximum: the same orbit, the same unknowns, but an unstable orbit contracts under the
    backward flow. Forward shooting of an orbit with multiplier ``m`` amplifies the
    integration's error by ``m`` (and a pchip table's 1e-10 to 1e-8 across its rows): it
    loses the unstable branch of a table's subcritical Hopf point at ``m = 3200``; backward
    shooting follows it through multipliers of ``exp(5000)`` to its grazing at the
    stick-slip onset. The continuation shoots backward wherever the last orbit was unstable.
    """

    def __init__(self, law: DimensionlessLaw, rtol: float) -> None:
        self.law = law
        self.kernel, self.lp = law.arrays()
        self.rtol = rtol
        self.reverse = False

    def f(self, nu: float, order: int = 0) -> float:
        return self.law.at(nu, order)

    def residual(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return ``G(x)`` and its 2 x 3 Jacobian."""
        g, j, _ = self.evaluate(x, measure=False)
        return g, j

    def measure(self, x: np.ndarray) -> dict[str, float]:
        """Return amplitude, minimum velocity and nontrivial multiplier of the orbit at ``x``."""
        return self.evaluate(x, measure=True)[2]

    def evaluate(self, x: np.ndarray, *, measure: bool) -> tuple[np.ndarray, np.ndarray, dict[str, float]]:
        """One integration: residual, Jacobian and (with ``measure``) the orbit's measurements."""
        a, period, nu = float(x[0]), float(x[1]), float(x[2])
        s0 = self.f(nu) + a
        if not (math.isfinite(s0) and math.isfinite(period) and period > 0 and 0 < nu < 1e12):
            raise RuntimeError(f"continuation left the domain (nu={nu!r}, period={period!r})")
        # inside Newton's loop: values of our own, checked just above
        fl = run_flow(
            self.kernel,
            self.lp,
            nu,
            s0,
            nu,
            period,
            rtol=self.rtol,
            measure=measure,
            checked=False,
            reverse=self.reverse,
        )
        y = fl.state
        g = np.array([y[0] - s0, y[1] - nu])
        phi = fl.monodromy
        d0 = np.array([self.f(nu, 1), 1.0])  # d(s0, w0)/d nu
        j = np.empty((2, 3))
        j[:, 0] = phi[:, 0] - np.array([1.0, 0.0])
        # d/dT of the end point: the vector field there, negative backward
        j[:, 1] = np.array([nu - y[1], y[0] - self.f(y[1])]) * (-1.0 if self.reverse else 1.0)
        j[:, 2] = phi @ d0 + fl.d_nu - d0
        meas = {}
        if measure:
            log_m = -fl.integral_dfdw
            meas = {
                "amplitude": s0 - fl.s_min,
                "min_velocity": fl.w_min,
                # beyond the floats (an orbit backward shooting still follows): infinite
                "multiplier": math.exp(log_m) if log_m < 709.0 else math.inf,
                "log_multiplier": log_m,
            }
        return g, j, meas


def _newton(
    fun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    x: np.ndarray,
    tol: float,
    max_iter: int = 12,
) -> tuple[np.ndarray, int] | None:
    """Newton's method on a square system; None when it fails.

    Where the residual stagnates above ``tol`` (the integration's own noise: across
    a pchip table's rows, where ``f''`` jumps, the flow is good to 1e-10 to 1e-8
    however small its tolerance), Newton stops at the noise floor: once the residual is
    within ``1e3 tol`` and the correction no longer shrinks (more than half the last one)
    or is below ``tol``, the iterate is taken, with its count. Wandering in the noise for
    the remaining iterations would have the continuation read the count as a hard step
    and shorten the next one (a table's unstable branch would take steps of 1e-7). Failing
    that, the best iterate within ``1e3 tol`` that Newton moved by less than ``1e4 tol``
    is taken, with the count of the iteration that first came that close.
    """
    best: tuple[float, np.ndarray, int] | None = None
    dn_last = math.inf
    for it in range(1, max_iter + 1):
        try:
            g, j = fun(x)
        except RuntimeError:
            return None
        if not np.all(np.isfinite(g)):
            return None
        try:
            dx = np.linalg.solve(j, -g)
        except np.linalg.LinAlgError:
            return None
        gn, dn = float(np.linalg.norm(g)), float(np.linalg.norm(dx))
        if gn < 1e3 * tol and dn < 1e4 * tol and (best is None or gn < best[0]):
            best = (gn, x.copy(), it if best is None else best[2])
        if gn < 1e3 * tol and (dn < tol or (dn < 1e4 * tol and dn > 0.5 * dn_last)):
            return (x + dx if gn < tol or dn < tol else x), it
        x = x + dx
        dn_last = dn
        if gn < tol and dn < 1e3 * tol:
            return x, it
        if not np.all(np.isfinite(x)) or x[1] <= 0:
            return None
    if best is not None:
        return best[1], best[2]
    return None


def _null_vector(j: np.ndarray) -> np.ndarray:
    t = np.cross(j[0], j[1])
    return t / np.linalg.norm(t)


def continue_pure_slip(
    law: DimensionlessLaw,
    hopf: Hopf,
    nu_min: float,
    nu_max: float,
    *,
    tol: float = 1e-10,
    max_points: int = 600,
    ds_max: float | None = None,
) -> tuple[Branch, list[SpecialPoint]]:
    """Follow the pure-slip orbits born at ``hopf`` until they graze or leave ``[nu_min, nu_max]``.

    Parameters
    ----------
    law : DimensionlessLaw
        The friction law.
    hopf : Hopf
        Where the branch is born (from :func:`~stickslip.orbits.stability.hopf_points`).
    nu_min, nu_max : float
        Range in which to follow the branch.
    tol : float, optional
        Newton tolerance on the periodicity residual; the flow is integrated at ``tol / 100``.
    max_points : int, optional
        Budget of continuation points.
    ds_max : float, optional
        Largest arclength step in ``(A, T, nu)``; default ``0.02 * max(nu_H, 0.1)``.

    Returns
    -------
    branch : Branch
    points : list of SpecialPoint
        Folds and the grazing point found on the way.

    """
    law = require_dimensionless_law(law)
    shooter = _Shooter(law, tol * 1e-2)
    nu_h = hopf.nu
    f2, f3 = shooter.f(nu_h, 2), shooter.f(nu_h, 3)
    scale = max(nu_h, 0.1)
    ds_max = 0.02 * scale if ds_max is None else ds_max
    # First two points at fixed small A (natural continuation in A): nu from averaging,
    # a^2 = -8 f'(nu)/f'''(nu) ~ -8 f''(nu_H)(nu - nu_H)/f'''(nu_H).
    # At a Hopf point on a kink of f' (a row of a pchip table, where f' = 0 and f'' jumps) the
    # small cycle grows linearly: nu - nu_H = r a (see _kink_ratio); its first amplitudes are
    # kept within a hundredth of nu_H of it (the cubic guess fails there: no first orbit, no
    # branch)
    amplitudes = (0.01 * scale, 0.02 * scale)
    if hopf.kink:
        per_a = _kink_ratio(shooter.f(nu_h * (1 - 1e-9), 2), shooter.f(nu_h * (1 + 1e-9), 2))
        a_small = min(0.01 * scale, 0.01 * nu_h / max(abs(per_a), 1e-3))
        amplitudes = (a_small, 2.0 * a_small)
    xs: list[np.ndarray] = []
    for a in amplitudes:
        if hopf.kink:
            nu0 = nu_h + per_a * a
        else:
            nu0 = nu_h - a * a * f3 / (8.0 * f2) if f2 != 0 else nu_h
        x0 = np.array([a, 2.0 * math.pi, nu0])

        def fixed_a(x: np.ndarray, a: float = a) -> tuple[np.ndarray, np.ndarray]:
            g, j = shooter.residual(x)
            return np.concatenate([g, [x[0] - a]]), np.vstack([j, [1.0, 0.0, 0.0]])

        res = _newton(fixed_a, x0, tol)
        if res is None:
            return _empty_branch("failed"), []
        xs.append(res[0])
    # from here on in scaled coordinates (see _Scaled): steps, tangents and arclength
    size = np.array([scale, 2.0 * math.pi, scale])
    sh = _Scaled(shooter, size)
    xs = [x / size for x in xs]
    ds_max /= scale
    pts: list[np.ndarray] = list(xs)
    meas = [sh.measure(xs[0])]
    _, j_last, m_last = sh.evaluate(xs[1], measure=True)
    meas.append(m_last)
    shooter.reverse = m_last["multiplier"] > 1.0  # unstable: shoot backward (see _Shooter)
    tangent = _null_vector(j_last)
    if np.dot(tangent, xs[1] - xs[0]) < 0:
        tangent = -tangent
    ds = min(ds_max, float(np.linalg.norm(xs[1] - xs[0])))
    special: list[SpecialPoint] = []
    end = "points"

    def corrector(xp: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, int] | None:
        def aug(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            g, j = sh.residual(x)
            return np.concatenate([g, [float(np.dot(t, x - xp))]]), np.vstack([j, t])

        return _newton(aug, xp, tol)

    while len(pts) < max_points:
        x = pts[-1]
        res = corrector(x + ds * tangent, tangent)
        if res is None or res[0][0] <= 0 or res[0][1] > 100.0:  # T > 200 pi
            if res is not None and res[0][1] > 100.0:
                end = "period"
                break
            if res is not None and res[0][0] <= 0:
                end = "hopf"
                break
            ds *= 0.5
            if ds < 1e-9:
                end = "failed"
                break
            continue
        xn, its = res
        _, j_n, m = sh.evaluate(xn, measure=True)
        # the corrector's hyperplane can cut the branch again far away (near grazing, on the
        # unstable part it came along): a step that lands farther than its own length from the
        # prediction, or turns the tangent by more than 25 degrees, is taken again, shorter
        if np.linalg.norm(xn - (x + ds * tangent)) > ds or abs(np.dot(_null_vector(j_n), tangent)) < 0.9:
            ds *= 0.5
            if ds < 1e-9:
                end = "failed"
                break
            continue
        if not (nu_min <= xn[2] * scale <= nu_max):
            # land exactly on the end of the range
            target = (nu_max if xn[2] * scale > nu_max else nu_min) / scale

            def on_bound(z: np.ndarray, target: float = target) -> tuple[np.ndarray, np.ndarray]:
                g, j = sh.residual(z)
                return np.concatenate([g, [z[2] - target]]), np.vstack([j, [0.0, 0.0, 1.0]])

            rb = _newton(on_bound, xn, tol)
            if rb is not None and m["min_velocity"] > 0:
                pts.append(rb[0])
                meas.append(sh.measure(rb[0]))
            end = "range"
            if m["min_velocity"] > 0:
                break
        if m["min_velocity"] <= 0:
            xg = _grazing(sh, x, tangent, ds, corrector, tol)
            if xg is not None:
                pts.append(xg)
                mg = sh.measure(xg)
                meas.append(mg)
                nu_g = float(xg[2]) * scale
                special.append(SpecialPoint("grazing", nu_g, mg["amplitude"], "min velocity 0"))
            end = "grazing"
            break
        if end == "range":
            break
        t_new = _null_vector(j_n)
        if np.dot(t_new, tangent) < 0:
            t_new = -t_new
        pts.append(xn)
        meas.append(m)
        shooter.reverse = m["multiplier"] > 1.0
        if t_new[2] * tangent[2] < 0:  # nu turned back: a fold of cycles between the last points
            fold = _refine_fold(sh, pts[-3:], tol)
            if fold is None:  # the quadratic through the three points (to the step's resolution)
                special.append(_fold([p * size for p in pts[-3:]], meas[-3:]))
            else:  # on the branch too: the orbits between its last points and the fold exist
                xf, mf, k = fold
                pts.insert(len(pts) - 3 + k, xf)
                meas.insert(len(meas) - 3 + k, mf)
                special.append(
                    SpecialPoint(
                        "fold",
                        float(xf[2]) * scale,
                        mf["amplitude"],
                        f"fold of cycles (saddle-node); multiplier {mf['multiplier']:.6f}",
                    )
                )
        tangent = t_new
        ds = min(ds_max, ds * (1.5 if its <= 3 else (1.0 if its <= 5 else 0.5)))
    xa = np.array(pts) * size
    amp = np.array([m["amplitude"] for m in meas])
    mult = np.array([m["multiplier"] for m in meas])
    branch = Branch(
        kind="pure-slip",
        nu=xa[:, 2],
        amplitude=amp,
        period=xa[:, 1],
        min_velocity=np.array([m["min_velocity"] for m in meas]),
        max_force=np.array([shooter.f(float(x[2])) + float(x[0]) for x in xa]),
        multiplier=mult,
        stable=mult < 1.0,
        end=end,
        log_multiplier=np.array([m["log_multiplier"] for m in meas]),
    )
    return branch, special


def _grazing(
    sh: _Shooter | _Scaled,
    x: np.ndarray,
    tangent: np.ndarray,
    ds: float,
    corrector: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, int] | None],
    tol: float,
) -> np.ndarray | None:
    """Locate the orbit with minimum velocity 0 between ``x`` and ``x + ds * tangent`` (secant)."""
    lo, hi = 0.0, ds
    w_lo = sh.measure(x)["min_velocity"]
    res = corrector(x + hi * tangent, tangent)
    if res is None:
        return None
    w_hi = sh.measure(res[0])["min_velocity"]
    best, w_best = res[0], w_hi  # the orbit of the smallest minimum velocity found
    near = 1e-10 * max(1.0, float(x[2]))
    for _ in range(60):
        sig = hi - w_hi * (hi - lo) / (w_hi - w_lo) if w_hi != w_lo else 0.5 * (lo + hi)
        if not (min(lo, hi) < sig < max(lo, hi)):
            sig = 0.5 * (lo + hi)
        r = corrector(x + sig * tangent, tangent)
        if r is None:  # the best so far, where it grazes to 1e-10 (found before the refinement below)
            return best if abs(w_best) < near else None
        wv = sh.measure(r[0])["min_velocity"]
        if abs(wv) <= abs(w_best):
            best, w_best = r[0], wv
        if wv == 0.0:
            return best
        if wv > 0:
            lo, w_lo = sig, wv
        else:
            hi, w_hi = sig, wv
        # done where the minimum velocity is zero to 1e-10 and the secant's next move in nu is
        # below 1e-9 of nu: at a grazing (a tangency) the minimum velocity changes slowly with nu,
        # and 1e-10 of velocity alone can leave nu 2.3e-6 off the stick-slip onset; the
        # corrector's own precision leaves a few 1e-9 (2.7e-10 from the onset at nu = 0.0505)
        if abs(wv) < near:
            moves = abs(wv) * abs(hi - lo) / abs(w_hi - w_lo) * abs(float(tangent[2]))
            if moves <= 1e-9 * abs(float(x[2])):
                return best
    return best


def _refine_fold(
    sh: _Shooter | _Scaled, pts: Sequence[np.ndarray], tol: float
) -> tuple[np.ndarray, dict[str, float], int] | None:
    """Locate the fold of cycles between the first and last of three branch points, to ``1e-9``.

    The branch is parametrised by ``sigma``, the position along the chord from
    ``pts[0]`` to ``pts[2]`` (transverse to ``nu`` near a fold); at each ``sigma``
    the orbit is solved by Newton, and the fold is the root of the ``nu``
    component of the branch's tangent (Brent). Returns the fold's ``(A, T, nu)``,
    its measurements and where it goes among the three points (1: after the
    first, 2: after the second); None when a solve fails (the caller falls back
    to the quadratic through the points).
    """
    p = np.array(pts)
    chord = p[2] - p[0]
    length = float(np.linalg.norm(chord))
    if not length > 0:
        return None
    d = chord / length
    sig = p @ d - float(p[0] @ d)
    if not (0.0 < sig[1] < sig[2]):
        return None
    guess = [np.polyfit(sig, p[:, i], 2) for i in range(3)]

    def solve(s: float) -> tuple[np.ndarray, np.ndarray] | None:
        x0 = np.array([np.polyval(c, s) for c in guess])
        xp = p[0] + s * d

        def aug(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            g, j = sh.residual(x)
            return np.concatenate([g, [float(np.dot(d, x - xp))]]), np.vstack([j, d])

        res = _newton(aug, x0, tol)
        if res is None:
            return None
        _, j = sh.residual(res[0])
        t = _null_vector(j)
        return res[0], (t if np.dot(t, d) > 0 else -t)

    def tnu(s: float) -> float:
        r = solve(s)
        if r is None:
            raise RuntimeError("no orbit")
        return float(r[1][2])

    from scipy import optimize

    try:
        t0, t1, t2 = tnu(0.0), tnu(float(sig[1])), tnu(float(sig[2]))
        if t0 * t1 <= 0:
            lo, hi = 0.0, float(sig[1])
        elif t1 * t2 <= 0:
            lo, hi = float(sig[1]), float(sig[2])
        else:
            return None
        s_f = optimize.brentq(tnu, lo, hi, xtol=1e-12 * length, rtol=1e-14)
    except (RuntimeError, ValueError):
        return None
    r = solve(s_f)
    if r is None:
        return None
    return r[0], sh.measure(r[0]), 1 if s_f < sig[1] else 2


def _fold(pts: Sequence[np.ndarray], meas: Sequence[dict[str, float]]) -> SpecialPoint:
    """Extremum of nu through three points, by a quadratic in the arclength."""
    p = np.array(pts)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    c = np.polyfit(s, p[:, 2], 2)
    s_star = -c[1] / (2 * c[0]) if c[0] != 0 else s[1]
    nu_f = float(np.polyval(c, s_star))
    amp = np.array([m["amplitude"] for m in meas])
    a_f = float(np.polyval(np.polyfit(s, amp, 2), s_star))
    return SpecialPoint("fold", nu_f, a_f, "fold of cycles (saddle-node)")


def _empty_branch(end: str) -> Branch:
    e = np.empty(0)
    return Branch("pure-slip", e, e, e, e, e, e, np.empty(0, dtype=bool), end, e)
