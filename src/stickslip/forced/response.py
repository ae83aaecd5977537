"""Periodic responses of the forced oscillator: shooting, Floquet multipliers, response curves.

A period-``n`` response is a fixed point of the ``n``-th iterate of the
stroboscopic map ``P`` (the state ``(s, w)`` at ``t0 + k T``). Newton's method
solves ``P^n(x) = x`` with the exact Jacobian of ``P^n``: the variational
equations along each slip phase multiplied by the saltation matrix of every stop,
breakaway and reversal (:mod:`stickslip.core.forced`). Its eigenvalues are the
response's Floquet multipliers; a stick phase makes one of them 0 (stick forgets
the velocity).

:func:`response_curve` continues a response against the forcing frequency, its
amplitude or any other parameter by pseudo-arclength
(:func:`stickslip.bifurcation.arclength.trace`), through folds, and reports the
bifurcations on it:

- ``fold``: a multiplier passes +1 where the curve turns back (a saddle-node);
- ``branch``: a multiplier passes +1 where the curve goes on (a pitchfork: the
  symmetry breaking of a symmetric response, where an asymmetric pair branches);
- ``period-doubling``: a multiplier passes -1;
- ``torus``: a complex pair leaves the unit circle (Neimark-Sacker);
- ``stick-change``: the number of stick phases (or reversals) per period changes,
  the non-smooth bifurcations of friction oscillators (grazing, where a slip
  phase touches zero velocity and a stick phase is born; sliding, where a stick
  phase ends at its border): located to ``1e-9`` of the parameter by bisection.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..bifurcation.arclength import trace
from ..core.forced_api import ForcedStats, forced_poincare
from ..errors import ArgumentTypeError
from ..units import check_number
from .motion import ATOL, RTOL, check_start, run_periods
from .system import ForcedSystem, as_forced

__all__ = ["ForcedOrbit", "ResponseBifurcation", "ResponseCurve", "periodic_response", "response_curve"]

#: parameters a response curve can follow (besides a law parameter)
CURVE_PARAMETERS = ("omega", "q", "nu0", "nu1", "delta", "phi")


@dataclass(frozen=True)
class ForcedOrbit:
    """A periodic response: a fixed point of the ``period``-th iterate of the stroboscopic map.

    Attributes
    ----------
    x : ndarray
        ``(s, w)`` at the section ``t0`` (dimensionless).
    period : int
        Forcing periods per response period.
    monodromy : ndarray
        Jacobian of ``P^period`` at ``x`` (2 x 2), with the saltation matrices.
    multipliers : ndarray
        Its eigenvalues (complex), largest modulus first.
    stable : bool
        All multipliers inside the unit circle.
    stops, reversals : int
        Stick phases and reversals without stick per response period.
    stick_fraction : float
    s_range, w_range : tuple of float
        The extremes of the spring force (exact: at events and where ``s' = 0``) and
        of the velocity over the response.
    residual : float
        ``|P^n(x) - x|``.
    converged : bool

    """

    x: np.ndarray
    period: int
    monodromy: np.ndarray
    multipliers: np.ndarray
    stable: bool
    stops: int
    reversals: int
    stick_fraction: float
    s_range: tuple[float, float]
    w_range: tuple[float, float]
    residual: float
    converged: bool
    system: ForcedSystem = field(repr=False)

    @property
    def amplitude(self) -> float:
        """Half the range of the spring force: the response amplitude (units of ``mu_s W``)."""
        return 0.5 * (self.s_range[1] - self.s_range[0])


def _evaluate(
    dp: ForcedSystem, x: np.ndarray, n: int, t0: float
) -> tuple[np.ndarray, np.ndarray, ForcedStats]:
    kernel, lp, fp = dp.arrays()
    y, jac, _, stats = forced_poincare(kernel, lp, fp, t0, x, n, rtol=RTOL * 1e-2, atol=ATOL * 1e-2)
    if stats.status != "ok":
        raise RuntimeError(f"stroboscopic map of {dp.describe()}: the engine {stats.status}")
    return y, jac, stats


def _orbit(dp: ForcedSystem, x: np.ndarray, n: int, t0: float, converged: bool) -> ForcedOrbit:
    y, jac, stats = _evaluate(dp, x, n, t0)
    mult = np.linalg.eigvals(jac)
    mult = mult[np.argsort(-np.abs(mult))]
    return ForcedOrbit(
        x=x.copy(),
        period=n,
        monodromy=jac,
        multipliers=mult,
        stable=bool(np.all(np.abs(mult) < 1.0)),
        stops=stats.stops,
        reversals=stats.reversals,
        stick_fraction=stats.stick_time / (n * dp.period),
        s_range=(stats.s_min, stats.s_max),
        w_range=(stats.w_min, stats.w_max),
        residual=float(np.linalg.norm(y - x)),
        converged=converged,
        system=dp,
    )


def _newton(
    dp: ForcedSystem, x: np.ndarray, n: int, t0: float, tol: float, max_iter: int = 40
) -> tuple[np.ndarray, float, bool]:
    res = math.inf
    for _ in range(max_iter):
        y, jac, _ = _evaluate(dp, x, n, t0)
        g = y - x
        res = float(np.linalg.norm(g))
        if res <= tol * max(1.0, float(np.linalg.norm(x))):
            return x, res, True
        a = jac - np.eye(2)
        try:
            dx = np.linalg.solve(a, -g)
        except np.linalg.LinAlgError:
            return x, res, False
        # a step longer than the state's own size is halved until the residual falls
        lam = 1.0
        for _ in range(20):
            trial = x + lam * dx
            try:
                yt, _, _ = _evaluate(dp, trial, n, t0)
            except RuntimeError:
                lam *= 0.5
                continue
            if np.linalg.norm(yt - trial) < res or lam < 1e-3:
                break
            lam *= 0.5
        x = x + lam * dx
    return x, res, False


def periodic_response(
    system: Any,
    period: int = 1,
    *,
    start: Any = None,
    transient: int = 300,
    t0: float = 0.0,
    tol: float = 1e-11,
) -> ForcedOrbit:
    """Find a period-``period`` response by Newton shooting on the stroboscopic map.

    Parameters
    ----------
    system : ForcedSystem or PhysicalForcedSystem
        The oscillator: dimensionless, or physical (results in SI).
    period : int
        Forcing periods per response period (1 to 64).
    start : (float, float), optional
        A guess ``(s, w)`` at the section; without one, the state after ``transient``
        periods from rest.
    transient : int
        Periods run from the guess (or from rest) before Newton starts.
    t0 : float
        The section's phase (dimensionless time).
    tol : float
        Newton's tolerance on ``|P^n(x) - x|`` relative to ``max(1, |x|)``.

    Returns
    -------
    ForcedOrbit
        ``converged`` is False where Newton did not converge (the motion may be
        quasi-periodic or chaotic there, or of another period).

    """
    dp, _ = as_forced(system)
    n = int(
        check_number(
            period, "period", upper=64, upper_inclusive=True, what="a whole number of periods (1 to 64)"
        )
    )
    x = np.array(check_start((0.0, 0.0) if start is None else start))
    nt = int(check_number(transient, "transient", allow_zero=True, upper=1e7, what="a number of periods"))
    if nt:
        x, _ = run_periods(dp, x, nt, t0)
    x, _, ok = _newton(dp, x, n, t0, tol)
    return _orbit(dp, x, n, t0, ok)


@dataclass(frozen=True)
class ResponseBifurcation:
    """A bifurcation on a response curve.

    Attributes
    ----------
    kind : str
        ``fold``, ``branch``, ``period-doubling``, ``torus`` or ``stick-change``.
    value : float
        The parameter there.
    x : ndarray
        ``(s, w)`` at the section.
    multipliers : ndarray
    detail : str
        What changes (``stops 0 -> 1``) or the multiplier that crosses.

    """

    kind: str
    value: float
    x: np.ndarray
    multipliers: np.ndarray
    detail: str = ""


@dataclass(frozen=True)
class ResponseCurve:
    """A continued periodic response.

    Attributes
    ----------
    parameter : str
    values : ndarray
        The parameter along the curve.
    x : ndarray
        ``(s, w)`` at the section along the curve (n x 2).
    amplitude : ndarray
        Half the spring force's range over the response.
    multipliers : ndarray
        (n x 2, complex), largest modulus first.
    stable : ndarray of bool
    stops, reversals : ndarray of int
        Per response period.
    bifurcations : list of ResponseBifurcation
    period : int
    ends : tuple of str
        Why each end of the curve stopped (``edge``, ``points``, ``failed``).

    """

    parameter: str
    values: np.ndarray
    x: np.ndarray
    amplitude: np.ndarray
    multipliers: np.ndarray
    stable: np.ndarray
    stops: np.ndarray
    reversals: np.ndarray
    bifurcations: list[ResponseBifurcation]
    period: int
    ends: tuple[str, str]
    system: ForcedSystem = field(repr=False)

    def to_dataset(self) -> Any:
        """Return the curve as an xarray Dataset (dimensionless units, CF attributes)."""
        import xarray as xr

        from ..models.scales import unit_attrs

        b = self.bifurcations
        return xr.Dataset(
            {
                "s": (
                    "point",
                    self.x[:, 0],
                    {"long_name": "spring force at the section", **unit_attrs("force", False)},
                ),
                "w": (
                    "point",
                    self.x[:, 1],
                    {"long_name": "velocity at the section", **unit_attrs("velocity", False)},
                ),
                "amplitude": (
                    "point",
                    self.amplitude,
                    {"long_name": "half the spring force's range", **unit_attrs("force", False)},
                ),
                "multiplier_modulus": (
                    ("point", "k"),
                    np.abs(self.multipliers),
                    {"long_name": "Floquet multipliers' moduli", "units": "1"},
                ),
                "multiplier_real": (("point", "k"), self.multipliers.real, {"units": "1"}),
                "multiplier_imag": (("point", "k"), self.multipliers.imag, {"units": "1"}),
                "stable": (
                    "point",
                    self.stable.astype(np.int8),
                    {"flag_values": np.array([0, 1], dtype=np.int8), "flag_meanings": "unstable stable"},
                ),
                "stops": (
                    "point",
                    self.stops,
                    {"long_name": "stick phases per response period", "units": "1"},
                ),
                "reversals": (
                    "point",
                    self.reversals,
                    {"long_name": "reversals without stick per response period", "units": "1"},
                ),
                "bifurcation_value": (
                    "bifurcation",
                    np.array([v.value for v in b], dtype=float),
                    {"long_name": self.parameter, "units": "1"},
                ),
                "bifurcation_kind": ("bifurcation", np.array([v.kind for v in b], dtype=object)),
            },
            coords={"parameter": ("point", self.values, {"long_name": self.parameter, "units": "1"})},
            attrs={"system": self.system.describe(), "period": self.period, "Conventions": "CF-1.10"},
        )


def response_curve(
    system: Any,
    parameter: str = "omega",
    bounds: tuple[float, float] = (0.5, 2.0),
    *,
    period: int = 1,
    start: Any = None,
    transient: int = 300,
    t0: float = 0.0,
    max_points: int = 400,
    h_max: float = 0.1,
) -> ResponseCurve:
    """Continue a periodic response against ``parameter`` over ``bounds``, both ways from where it starts.

    Parameters
    ----------
    system : ForcedSystem or PhysicalForcedSystem
        The start: the response is found at this system's value of ``parameter``.
    parameter : str
        ``omega``, ``q``, ``nu0``, ``nu1``, ``delta``, ``phi`` or a law parameter.
    bounds : (float, float)
        The parameter's range; the curve ends where it leaves it.
    period : int
        Forcing periods per response period.
    start, transient, t0 :
        As for :func:`periodic_response` (the first point).
    max_points : int
        Points per direction.
    h_max : float
        Largest arclength step (in the parameter over its range, and the state).

    """
    dp, _ = as_forced(system)
    if not isinstance(parameter, str) or parameter not in CURVE_PARAMETERS + tuple(dp.law.params):
        raise ValueError(
            f"parameter={parameter!r}: expected one of {', '.join(CURVE_PARAMETERS + tuple(dp.law.params))}"
        )
    try:
        lo, hi = (float(v) for v in bounds)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"bounds={bounds!r}: expected (low, high)") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"bounds={bounds!r}: expected two finite numbers, low < high")
    p0 = float(getattr(dp, parameter)) if parameter in CURVE_PARAMETERS else float(dp.law.params[parameter])
    if not lo <= p0 <= hi:
        raise ValueError(f"bounds={bounds!r}: the system's {parameter} = {p0:g} lies outside")
    first = periodic_response(dp, period, start=start, transient=transient, t0=t0)
    if not first.converged:
        raise RuntimeError(
            f"no period-{period} response found at {dp.describe()} (residual {first.residual:.2g}): "
            "start from a parameter where the motion is periodic, or give another period"
        )
    n = first.period
    width = hi - lo
    cache: dict[bytes, tuple[np.ndarray, np.ndarray, ForcedStats]] = {}

    def at(z: np.ndarray) -> ForcedSystem:
        return dp.with_(**{parameter: lo + z[2] * width})

    def ev(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, ForcedStats]:
        key = z.tobytes()
        if key not in cache:
            if len(cache) > 64:
                cache.clear()
            cache[key] = _evaluate(at(z), z[:2], n, t0)
        return cache[key]

    def fun(z: np.ndarray) -> np.ndarray:
        y, _, _ = ev(z)
        return y - z[:2]

    def jac(z: np.ndarray) -> np.ndarray:
        y, j, _ = ev(z)
        eps = 1e-7 * max(1.0, abs(z[2]))
        zp = z.copy()
        zp[2] += eps
        yp, _, _ = ev(zp)
        out = np.empty((2, 3))
        out[:, :2] = j - np.eye(2)
        out[:, 2] = (yp - y) / eps
        return out

    def fold_test(z: np.ndarray) -> float:
        return float(np.linalg.det(ev(z)[1] - np.eye(2)))

    def flip_test(z: np.ndarray) -> float:
        return float(np.linalg.det(ev(z)[1] + np.eye(2)))

    def inside(z: np.ndarray) -> float:
        return float(min(z[2], 1.0 - z[2]))

    z0 = np.array([first.x[0], first.x[1], (p0 - lo) / width])
    traced = trace(
        fun,
        z0,
        np.array([0.0, 0.0, 1.0]),
        jac=jac,
        tests={"fold": fold_test, "flip": flip_test},
        inside=inside,
        h0=min(0.01, h_max),
        h_max=h_max,
        max_points=max_points,
        tol=1e-10,
    )
    zs = traced.x
    rows = [_orbit(at(z), z[:2], n, t0, True) for z in zs]
    values = lo + zs[:, 2] * width
    bif: list[ResponseBifurcation] = []
    for e in traced.events:
        if e.name not in ("fold", "flip"):
            continue
        o = _orbit(at(e.x), e.x[:2], n, t0, True)
        val = lo + float(e.x[2]) * width
        if e.name == "flip":
            bif.append(
                ResponseBifurcation(
                    "period-doubling", val, e.x[:2].copy(), o.multipliers, "a multiplier passes -1"
                )
            )
            continue
        # a turning point: the parameter runs one way on the segment before the event and the
        # other way on the segment after it (segments that do not end on the event itself)
        i = e.index
        before = zs[max(i - 1, 1), 2] - zs[max(i - 2, 0), 2]
        after = zs[min(i + 2, len(zs) - 1), 2] - zs[min(i + 1, len(zs) - 2), 2]
        turns = before * after < 0.0
        kind = "fold" if turns else "branch"
        bif.append(ResponseBifurcation(kind, val, e.x[:2].copy(), o.multipliers, "a multiplier passes +1"))
    keys = [(r.stops, r.reversals) for r in rows]
    last_change = -1
    for i in range(len(rows) - 1):
        a, b = rows[i], rows[i + 1]
        if keys[i] != keys[i + 1]:
            if last_change >= 0 and i > 0 and keys[i - 1] != keys[i] and keys[i + 1] == keys[i - 1]:
                # one point whose orbit counts an event more (or fewer) than its neighbours on both
                # sides: a stop that falls on the section itself, counted in both periods or in
                # neither; the orbit is the same on both sides, and nothing bifurcates there
                del bif[last_change]
                last_change = -1
            else:
                bif.append(_stick_change(dp, parameter, values[i], values[i + 1], a, b, n, t0))
                last_change = len(bif) - 1
        ca = abs(a.multipliers[0].imag) > 0.0 and abs(a.multipliers[0]) < 1.0
        cb = abs(b.multipliers[0].imag) > 0.0 and abs(b.multipliers[0]) < 1.0
        if a.multipliers[0].imag != 0.0 and b.multipliers[0].imag != 0.0 and ca != cb:
            mid = 0.5 * (values[i] + values[i + 1])
            bif.append(
                ResponseBifurcation(
                    "torus", mid, rows[i].x, rows[i].multipliers, "a complex pair crosses the unit circle"
                )
            )
    bif.sort(key=lambda b: b.value)
    mult = np.array([r.multipliers for r in rows])
    return ResponseCurve(
        parameter=parameter,
        values=values,
        x=zs[:, :2].copy(),
        amplitude=np.array([r.amplitude for r in rows]),
        multipliers=mult,
        stable=np.array([r.stable for r in rows]),
        stops=np.array([r.stops for r in rows]),
        reversals=np.array([r.reversals for r in rows]),
        bifurcations=bif,
        period=n,
        ends=traced.end,
        system=dp,
    )


def _stick_change(
    dp: ForcedSystem, parameter: str, va: float, vb: float, a: ForcedOrbit, b: ForcedOrbit, n: int, t0: float
) -> ResponseBifurcation:
    """Locate where the stops (or reversals) per period change between two points, by bisection."""
    key_a = (a.stops, a.reversals)
    xa, xb = a.x, b.x
    lo, hi = va, vb
    for _ in range(40):
        if abs(hi - lo) <= 1e-9 * max(1.0, abs(lo)):
            break
        mid = 0.5 * (lo + hi)
        guess = 0.5 * (xa + xb)
        sysm = dp.with_(**{parameter: mid})
        x, _, ok = _newton(sysm, guess, n, t0, 1e-11)
        if not ok:
            break
        _, _, st = _evaluate(sysm, x, n, t0)
        if (st.stops, st.reversals) == key_a:
            lo, xa = mid, x
        else:
            hi, xb = mid, x
    o = _orbit(dp.with_(**{parameter: 0.5 * (lo + hi)}), 0.5 * (xa + xb), n, t0, True)
    detail = f"stops {a.stops} -> {b.stops}, reversals {a.reversals} -> {b.reversals} per period"
    return ResponseBifurcation("stick-change", 0.5 * (lo + hi), o.x, o.multipliers, detail)
