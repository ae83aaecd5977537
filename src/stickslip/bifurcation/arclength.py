"""Pseudo-arclength continuation of a curve ``F(x) = 0``, ``F: R^(n+1) -> R^n``, with events.

:func:`trace` follows the solution curve of ``n`` equations in ``n + 1`` unknowns from a
solution ``x0``: a predictor along the tangent (the null vector of the Jacobian), a Newton
corrector on the hyperplane normal to it, and a step that grows after an easy correction
and halves after a hard or failed one. Because the curve is parametrised by its
arclength, turning points (where one coordinate goes back) are passed like any other
point: no coordinate is singled out.

Test functions ``phi(x)`` are watched along the way; where one changes sign between two
accepted points the zero is located on the curve (the secant, then bisection, on the
position along the step, each trial point corrected back onto the curve) to ``1e-12`` of
the step: a codimension-2 point of a bifurcation curve. A test marked ``stop`` ends the
curve there (the curve itself ends: a fold of cycles whose orbit touches zero velocity).
The curve also ends where it leaves its box (the crossing is located on the edge), where
it closes on itself, where the Newton corrector fails at the smallest step, or after
``max_points``.

The unknowns should be scaled so that a unit step is of the same size in each of them
(the caller's coordinates: logarithms of physical parameters, amplitudes over their
scale); the Jacobian, when not given, is taken by forward differences of relative step
``1e-7``, which leaves Newton's convergence linear at a rate of about ``1e-6`` per
iteration (the root itself is exact: it is set by the residual alone).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Event", "TracedCurve", "fd_jacobian", "newton", "trace"]

Residual = Callable[[np.ndarray], np.ndarray]
Jacobian = Callable[[np.ndarray], np.ndarray]

#: relative step of the forward-difference Jacobian
FD_STEP = 1e-7


def fd_jacobian(fun: Residual, x: np.ndarray, f0: np.ndarray | None = None) -> np.ndarray:
    """Return the forward-difference Jacobian of ``fun`` at ``x`` (``f0 = fun(x)`` when known)."""
    f0 = fun(x) if f0 is None else f0
    jac = np.empty((f0.size, x.size))
    for i in range(x.size):
        h = FD_STEP * max(1.0, abs(float(x[i])))
        xh = x.copy()
        xh[i] += h
        jac[:, i] = (fun(xh) - f0) / h
    return jac


def newton(
    fun: Residual,
    x: np.ndarray,
    *,
    jac: Jacobian | None = None,
    tol: float = 1e-10,
    max_iter: int = 12,
) -> tuple[np.ndarray, int] | None:
    """Solve the square system ``fun(x) = 0`` by Newton's method; None when it fails.

    Converged when ``|fun(x)| <= tol`` and the last correction is below ``1e3 tol`` (or
    the residual has stopped falling within ``1e2 tol``: the evaluation's own noise).
    """
    last = math.inf
    for it in range(1, max_iter + 1):
        try:
            g = fun(x)
            if not np.all(np.isfinite(g)):
                return None
            gn = float(np.max(np.abs(g)))
            j = jac(x) if jac is not None else fd_jacobian(fun, x, g)
            dx = np.linalg.solve(j, -g)
        except (RuntimeError, ValueError, ArithmeticError, np.linalg.LinAlgError):
            return None
        dn = float(np.max(np.abs(dx)))
        if gn <= tol and dn <= 1e3 * tol:
            return x, it
        if gn <= 1e2 * tol and gn >= 0.5 * last:
            return x, it
        x = x + dx
        last = gn
        if not np.all(np.isfinite(x)):
            return None
    try:
        g = fun(x)
    except (RuntimeError, ValueError, ArithmeticError):
        return None
    return (x, max_iter) if float(np.max(np.abs(g))) <= tol else None


@dataclass(frozen=True)
class Event:
    """A zero of a test function on the curve (a codimension-2 point), or an end of the curve.

    Attributes
    ----------
    name : str
        The test function's name, or the end: ``edge``, ``closed``.
    index : int
        Position in the curve's points (the event is inserted there).
    x : ndarray
        The point.
    values : dict
        Every test function at the point.

    """

    name: str
    index: int
    x: np.ndarray
    values: dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class TracedCurve:
    """A continued curve: its points in order, the test functions along it, its events and end.

    Attributes
    ----------
    x : ndarray, shape (n_points, n + 1)
    tests : dict of ndarray
        Each test function at each point.
    events : list of Event
    end : tuple of str
        Why each end stopped (first: the backward end, second: the forward end):
        ``edge``, ``closed``, a stopping test's name, ``failed`` or ``points``.

    """

    x: np.ndarray
    tests: dict[str, np.ndarray]
    events: list[Event]
    end: tuple[str, str]


@dataclass
class _Walk:
    xs: list[np.ndarray]
    vals: list[dict[str, float]]
    events: list[Event]
    end: str = "points"


def _tested(test: Callable[[np.ndarray], float], x: np.ndarray) -> float:
    """Return ``test(x)``, NaN where it cannot be evaluated (a NaN watches for no sign change)."""
    try:
        return float(test(x))
    except (RuntimeError, ValueError, ArithmeticError):
        return math.nan


def _tangent(j: np.ndarray) -> np.ndarray:
    """Return the unit null vector of the ``n x (n + 1)`` Jacobian (its last right singular vector)."""
    _, _, vt = np.linalg.svd(j)
    t = vt[-1]
    return np.asarray(t / np.linalg.norm(t))


def trace(
    fun: Residual,
    x0: np.ndarray,
    direction: np.ndarray | None = None,
    *,
    jac: Jacobian | None = None,
    tests: Mapping[str, Callable[[np.ndarray], float]] | None = None,
    stops: Sequence[str] = (),
    inside: Callable[[np.ndarray], float] | None = None,
    h0: float = 0.01,
    h_max: float = 0.05,
    h_min: float = 1e-7,
    max_points: int = 400,
    tol: float = 1e-10,
    both: bool = True,
) -> TracedCurve:
    """Follow the curve ``fun(x) = 0`` through ``x0`` (a solution) both ways, or along ``direction``.

    Parameters
    ----------
    fun : callable
        ``x -> F(x)``, ``n`` values from ``n + 1`` unknowns.
    x0 : ndarray
        A point on the curve (solved to ``tol``; it is corrected once more here).
    direction : ndarray, optional
        The way to go first; the tangent's sign is chosen along it. With ``both`` the
        other way is traced too and the two halves joined.
    jac : callable, optional
        ``x -> dF/dx``; forward differences when not given.
    tests : mapping of name to callable, optional
        Test functions watched along the curve; their sign changes are located as events.
    stops : sequence of str
        The tests whose zero ends the curve.
    inside : callable, optional
        ``x -> d``: positive inside the box, negative outside (smooth in ``x``); the curve
        ends on ``d = 0``.
    h0, h_max, h_min : float
        First, largest and smallest arclength step.
    max_points : int
        Points per direction.
    tol : float
        Newton tolerance on ``|F|``.
    both : bool
        Trace both ways from ``x0``.

    Returns
    -------
    TracedCurve

    """
    tests = dict(tests or {})

    def jacobian(x: np.ndarray) -> np.ndarray:
        return jac(x) if jac is not None else fd_jacobian(fun, x)

    def values(x: np.ndarray) -> dict[str, float]:
        return {k: _tested(t, x) for k, t in tests.items()}

    t0 = _tangent(jacobian(x0))
    if direction is not None and float(np.dot(t0, direction)) < 0:
        t0 = -t0
    walks = [_walk(fun, jacobian, x0, t0, values, stops, inside, h0, h_max, h_min, max_points, tol)]
    if both:
        walks.insert(
            0, _walk(fun, jacobian, x0, -t0, values, stops, inside, h0, h_max, h_min, max_points, tol)
        )
    if len(walks) == 1:
        xs, vals, events, ends = walks[0].xs, walks[0].vals, walks[0].events, ("start", walks[0].end)
    else:
        back, fwd = walks
        if fwd.end == "closed":  # the forward half came round: the backward half is the same loop
            xs, vals, events, ends = fwd.xs, fwd.vals, fwd.events, ("closed", "closed")
        else:
            nb = len(back.xs)
            xs = back.xs[::-1] + fwd.xs[1:]
            vals = back.vals[::-1] + fwd.vals[1:]
            events = [Event(e.name, nb - 1 - e.index, e.x, e.values) for e in back.events][::-1] + [
                Event(e.name, nb - 1 + e.index, e.x, e.values) for e in fwd.events
            ]
            ends = (back.end, fwd.end)
    names = list(tests)
    return TracedCurve(
        x=np.array(xs),
        tests={k: np.array([v[k] for v in vals]) for k in names},
        events=events,
        end=ends,
    )


def _walk(
    fun: Residual,
    jacobian: Jacobian,
    x0: np.ndarray,
    t: np.ndarray,
    values: Callable[[np.ndarray], dict[str, float]],
    stops: Sequence[str],
    inside: Callable[[np.ndarray], float] | None,
    h0: float,
    h_max: float,
    h_min: float,
    max_points: int,
    tol: float,
) -> _Walk:
    """Trace one way from ``x0`` along ``t``."""
    walk = _Walk([x0], [values(x0)], [])
    h = h0
    x = x0
    travelled = 0.0

    def correct(xp: np.ndarray, tt: np.ndarray) -> tuple[np.ndarray, int] | None:
        def aug(z: np.ndarray) -> np.ndarray:
            return np.concatenate([fun(z), [float(np.dot(tt, z - xp))]])

        def aug_j(z: np.ndarray) -> np.ndarray:
            return np.vstack([jacobian(z), tt])

        return newton(aug, xp, jac=aug_j, tol=tol, max_iter=8)

    while len(walk.xs) < max_points:
        xp = x + h * t
        res = correct(xp, t)
        if res is None:
            h *= 0.5
            if h < h_min:
                walk.end = "failed"
                break
            continue
        xn, its = res
        try:
            tn = _tangent(jacobian(xn))
        except (RuntimeError, ValueError, ArithmeticError, np.linalg.LinAlgError):
            h *= 0.5
            if h < h_min:
                walk.end = "failed"
                break
            continue
        # a corrector that lands far from its prediction, or turns the tangent by more than
        # 25 degrees, may have jumped to another part of the curve: the step is taken again
        if float(np.linalg.norm(xn - xp)) > h or abs(float(np.dot(tn, t))) < 0.9:
            h *= 0.5
            if h < h_min:
                walk.end = "failed"
                break
            continue
        if float(np.dot(tn, t)) < 0:
            tn = -tn
        if inside is not None and inside(xn) < 0:
            xe = _locate(inside, x, t, h, correct)
            if xe is not None and not np.array_equal(xe, x):
                walk.xs.append(xe)
                walk.vals.append(values(xe))
            walk.end = "edge"
            break
        vn = values(xn)
        stop = None
        for name, v_old in walk.vals[-1].items():
            v_new = vn[name]
            if math.isfinite(v_old) and math.isfinite(v_new) and v_old * v_new < 0:
                xe = _locate(functools.partial(_named, values, name), x, t, h, correct)
                if xe is None:
                    continue
                walk.events.append(Event(name, len(walk.xs), xe, values(xe)))
                if name in stops and stop is None:
                    stop = (name, xe)
        if stop is not None:
            walk.xs.append(stop[1])
            walk.vals.append(values(stop[1]))
            walk.end = stop[0]
            break
        travelled += float(np.linalg.norm(xn - x))
        walk.xs.append(xn)
        walk.vals.append(vn)
        # closed: the step passed next to the start (within a tenth of its length), after going round
        seg = xn - x
        along = float(np.dot(x0 - x, seg)) / max(float(np.dot(seg, seg)), 1e-300)
        if travelled > 4 * h and 0.0 <= along <= 1.0:
            if float(np.linalg.norm(x + along * seg - x0)) < 0.1 * float(np.linalg.norm(seg)):
                walk.xs[-1] = x0
                walk.vals[-1] = walk.vals[0]
                walk.end = "closed"
                break
        x, t = xn, tn
        h = min(h_max, h * (1.5 if its <= 3 else (1.0 if its <= 5 else 0.5)))
    return walk


def _named(values: Callable[[np.ndarray], dict[str, float]], name: str, z: np.ndarray) -> float:
    return values(z)[name]


def _locate(
    phi: Callable[[np.ndarray], float],
    x: np.ndarray,
    t: np.ndarray,
    h: float,
    correct: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, int] | None],
) -> np.ndarray | None:
    """Zero of ``phi`` on the curve between ``x`` (``sigma = 0``) and the step ``sigma = h`` along ``t``.

    Each trial ``sigma`` is corrected onto the curve on the hyperplane through
    ``x + sigma t`` normal to ``t``; the secant (Illinois) with bisection as a safeguard
    brackets the zero to ``1e-12`` of the step.
    """
    lo, hi = 0.0, h
    f_lo = phi(x)
    if f_lo == 0.0:
        return x
    r = correct(x + hi * t, t)
    if r is None:
        return None
    z_hi = r[0]
    f_hi = phi(z_hi)
    if not (math.isfinite(f_lo) and math.isfinite(f_hi)) or f_lo * f_hi > 0:
        return None
    best = z_hi
    side = 0
    for _ in range(80):
        if hi - lo <= 1e-12 * h or f_hi == 0.0:
            break
        sig = hi - f_hi * (hi - lo) / (f_hi - f_lo) if f_hi != f_lo else 0.5 * (lo + hi)
        if not lo < sig < hi:
            sig = 0.5 * (lo + hi)
        r = correct(x + sig * t, t)
        if r is None:
            sig = 0.5 * (lo + hi)
            r = correct(x + sig * t, t)
            if r is None:
                return best
        z = r[0]
        fz = phi(z)
        best = z
        if fz == 0.0:
            break
        if fz * f_lo < 0:
            hi, f_hi = sig, fz
            if side == -1:
                f_lo *= 0.5
            side = -1
        else:
            lo, f_lo = sig, fz
            if side == 1:
                f_hi *= 0.5
            side = 1
    return best
