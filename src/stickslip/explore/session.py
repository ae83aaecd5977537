"""What the explorer shows, computed from a set-up: no web server, no plotting.

The browser app (:mod:`stickslip.explore.app`) keeps one :class:`Setup` per
page, and on every change of a widget calls :func:`compute` and ships the
numbers of the returned :class:`View` to the page. Everything here is plain
stickslip: :func:`stickslip.cycle` for the steady oscillation (the same call as
``stickslip cycle``, so :func:`command` reproduces it), :func:`stickslip.simulate`
for the motion, :func:`stickslip.dynamics.sweep` for the amplitude-velocity
curve and the regime diagram, :func:`stickslip.data.classify` for the paper's
criterion, :func:`stickslip.bifurcation.diagram.two_parameter_diagram` for the
two-parameter diagram (:func:`two_parameter_view`, computed on demand).
"""

from __future__ import annotations

import csv
import functools
import io
import itertools
import math
import re
import shlex
import sys
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from ..data.criterion import classify
from ..dynamics import cycle, simulate
from ..dynamics.sweep import sweep
from ..laws import ExpressionLaw, registry
from ..laws.base import DimensionlessLaw
from ..models import DimensionlessParameters, PhysicalParameters, unit_label, zv_parameters
from ..models.parameters import beta_of
from ..units import Q_, check_number
from ..userwarnings import warn

__all__ = [
    "EXPR",
    "NU_RANGE",
    "Setup",
    "View",
    "check_nu",
    "command",
    "compute",
    "default_params",
    "law_names",
    "parse_params",
    "plane_key",
    "plane_window",
    "regime_diagram",
    "slider_range",
    "two_parameter_view",
    "view_csv",
]

FloatArray = npt.NDArray[np.float64]

#: the driving-velocity slider's range, log10 from -5 to 1
NU_RANGE = (1e-5, 10.0)
#: the law name of a user's formula
EXPR = "expr"
#: the driving velocities of the amplitude-velocity curve, a decade each side of nu
CURVE_POINTS = 25
#: the regime diagram's grid (driving velocity x the law's first parameter)
DIAGRAM_SHAPE = (36, 24)
#: the regimes in the order of their colour codes
REGIMES = ("stick-slip", "pure-slip", "slip-reversal", "steady-sliding", "unknown")
#: the two-parameter diagram's window: decades of nu each side of the current one (within
#: :data:`NU_RANGE`), and the factor each way of its parameter's value
PLANE_DECADES = 2
PLANE_FACTOR = 4.0
#: cells per axis of the two-parameter diagram's region raster
PLANE_RASTER = 120
#: the two-parameter diagram's curves: colour and words (Hopf black, fold blue, grazing red)
CURVE_COLORS = {"hopf": "#000000", "fold": "#2166ac", "grazing": "#b2182b"}
CURVE_WORDS = {
    "hopf": "Hopf (steady sliding)",
    "fold": "fold of pure-slip cycles",
    "grazing": "grazing (stick-slip born)",
}
#: the codimension-2 points' markers (Bokeh's names) and colours
POINT_MARKERS = {"bautin": "star", "fold-grazing": "diamond", "cusp": "triangle", "end": "circle"}
POINT_COLORS = {"bautin": "#fdb863", "fold-grazing": "#000000", "cusp": "#000000", "end": "#ffffff"}
#: the default physical scales (mass kg, stiffness N/m, load N, mu_s): the paper's zv set-up
_ZV = zv_parameters()
ZV_SCALES = (
    float(_ZV.mass.to("kg").magnitude),
    float(_ZV.stiffness.to("N/m").magnitude),
    float(_ZV.load.to("N").magnitude),
    float(_ZV.law.mu_s),
)
#: the formula offered first, and its parameters
DEFAULT_EXPRESSION = "1/(1 + c*w) + q*w"
DEFAULT_EXPRESSION_PARAMS = "c=3.8, q=0.5"


def law_names() -> list[str]:
    """Return the laws the explorer offers: every registered law, then ``expr``."""
    return [*registry.names(), EXPR]


def default_params(law: str) -> dict[str, float]:
    """Return the parameters a law is shown with first: its spec's example, or the formula's."""
    if law == EXPR:
        return parse_params(DEFAULT_EXPRESSION_PARAMS)
    return dict(registry.get(law).spec.example)


@dataclass(frozen=True)
class Setup:
    """One set-up of the explorer.

    Parameters
    ----------
    law : str
        A registered law's name or ``"expr"``.
    params : Mapping[str, float]
        The law's dimensionless parameters.
    nu : float
        Dimensionless driving velocity ``beta v0``.
    expression : str
        The formula ``f(w)`` of an ``expr`` law (dimensionless, ``f(0+) = 1``).
    physical : bool
        Show (and export) the set-up in SI units with the scales below. A
        formula law (``expr``) is dimensionless and stays so (``View.units``
        says which units are shown; the page says so too).
    mass, stiffness, load, mu_s : float
        The physical scales: kg, N/m, N, and the static friction coefficient.

    """

    law: str = "weakening"
    params: Mapping[str, float] = field(default_factory=lambda: {"c": 3.8, "p": 0.0})
    nu: float = 1.0  # F1's curve (0.1 to 10) holds its change from stick-slip to slip reversal (4.5)
    expression: str = DEFAULT_EXPRESSION
    physical: bool = False
    mass: float = ZV_SCALES[0]
    stiffness: float = ZV_SCALES[1]
    load: float = ZV_SCALES[2]
    mu_s: float = ZV_SCALES[3]

    def __post_init__(self) -> None:
        for name in ("mass", "stiffness", "load", "mu_s"):  # a bad scale was blamed on beta
            check_number(getattr(self, name), name, what=f"a positive {name} scale")

    def dimensionless_law(self) -> DimensionlessLaw:
        """Return the friction law (dimensionless)."""
        if self.law == EXPR:
            return ExpressionLaw(self.expression, **dict(self.params))
        law = registry.get(self.law)
        names = [p.name for p in law.spec.parameters]
        unknown = [k for k in self.params if k not in names]
        if unknown:  # a TypeError from the law's constructor
            raise ValueError(f"params: {unknown} are not parameters of the {self.law} law (it has {names})")
        return law.dimensionless(**dict(self.params))

    @property
    def beta(self) -> float:
        """``beta = sqrt(k m)/(mu_s W)`` of the physical scales (s/m)."""
        return float(beta_of(self.stiffness, self.mass, self.load, self.mu_s))

    def parameters(self) -> DimensionlessParameters | PhysicalParameters:
        """Return the set-up as stickslip parameters: physical ones in physical mode."""
        law = self.dimensionless_law()
        dp = DimensionlessParameters(nu=self.nu, law=law)
        if not self.physical or self.law == EXPR:
            return dp
        beta = self.beta
        return PhysicalParameters(
            mass=Q_(self.mass, "kg"),
            stiffness=Q_(self.stiffness, "N/m"),
            load=Q_(self.load, "N"),
            v0=Q_(self.nu / beta, "m/s"),
            law=law.to_physical(Q_(beta, "s/m"), self.mu_s),
        )

    def with_(self, **changes: Any) -> Setup:
        """Return a copy with some fields changed."""
        return replace(self, **changes)

    def rescaled(self, mass: float, stiffness: float, load: float, mu_s: float) -> Setup:
        """Return the set-up under other physical scales, the same machine and law in SI units.

        In physical units a new mass (stiffness, load, ``mu_s``) changes the set-up, not
        the driving velocity ``v0`` in m/s or the law's physical parameters (``a``, ``b``
        in s/m; ``mu_k``; ...): those are held, and ``nu = beta v0`` and the law's
        dimensionless parameters follow, so that a new mass changes neither ``v0`` nor
        the law. Where the law cannot be held
        (``mu_k`` above a new ``mu_s``), its dimensionless parameters are kept and a
        warning says so. A formula (dimensionless) and the dimensionless view keep their
        values.

        Raises
        ------
        ValueError
            For a scale that is not a positive number, or a ``v0`` whose ``nu`` under the
            new scales falls outside the driving-velocity slider's range, :data:`NU_RANGE`.

        """
        new = self.with_(mass=mass, stiffness=stiffness, load=load, mu_s=mu_s)
        same = (mass, stiffness, load, mu_s) == (self.mass, self.stiffness, self.load, self.mu_s)
        if same or not self.physical or self.law == EXPR:
            return new
        v0 = self.nu / self.beta
        nu = v0 * new.beta
        if not (NU_RANGE[0] <= nu <= NU_RANGE[1]):
            raise ValueError(
                f"v0 = {v0:.6g} m/s is nu = beta v0 = {nu:.4g} with these scales "
                f"(beta = {new.beta:.6g} s/m), outside the driving-velocity slider's range, 1e-5 to 10: "
                f"{'lower' if nu > NU_RANGE[1] else 'raise'} v0 or change the scales back"
            )
        law = self.dimensionless_law().to_physical(Q_(self.beta, "s/m"), self.mu_s)
        try:
            if mu_s != self.mu_s:
                law = law.replace(mu_s=mu_s)
            params = law.nondimensionalize(Q_(new.beta, "s/m")).params
        except ValueError as e:
            warn(
                f"the {self.law} law's physical parameters ({law.describe()}) cannot be held with these "
                f"scales ({e}): its dimensionless parameters are kept",
                UserWarning,
            )
            params = dict(self.params)
        return new.with_(nu=nu, params=params)


@dataclass(frozen=True)
class View:
    """Everything the page draws for one set-up (in the units of :attr:`units`).

    Attributes
    ----------
    setup : Setup
    regime : str
        The steady regime reached from rest (``stickslip cycle``'s ``regime``).
    amplitude, period, stick_fraction : float
        Of the steady cycle (force, time, 1).
    time, spring_force, velocity : ndarray
        The motion from rest through three steady cycles.
    stuck : ndarray of bool
        Samples where the block is at rest.
    curve_v, curve_amplitude : ndarray
        The amplitude-velocity curve about the current driving velocity.
    curve_regime : tuple of str
        The regime at each point of the curve.
    verdict, verdict_reason : str
        The paper's criterion applied to the curve about the current velocity.
    v0 : float
        The current driving velocity (velocity unit).
    units : Mapping[str, str]
        ``force``, ``time``, ``velocity``.
    command : str
        The equivalent ``stickslip cycle`` command.

    """

    setup: Setup
    regime: str
    amplitude: float
    period: float
    stick_fraction: float
    time: FloatArray
    spring_force: FloatArray
    velocity: FloatArray
    stuck: npt.NDArray[np.bool_]
    curve_v: FloatArray
    curve_amplitude: FloatArray
    curve_regime: tuple[str, ...]
    verdict: str
    verdict_reason: str
    v0: float
    units: Mapping[str, str]
    command: str


def parse_params(text: str) -> dict[str, float]:
    """Read ``"c=3.8, q=0.5"`` into a dict (the parameters of a formula).

    Raises
    ------
    ValueError
        Naming the entry that is not ``name=number``.

    """
    if not isinstance(text, str):
        raise ValueError(f"parameters={text!r}: expected text such as 'c=3.8, q=0.5'")
    out: dict[str, float] = {}
    for part in re.split(r"[,;\s]+", re.sub(r"\s*=\s*", "=", text.strip())):
        if not part:
            continue
        name, sep, value = part.partition("=")
        try:
            if not sep or not name.isidentifier():
                raise ValueError
            number = float(value)
        except ValueError:
            raise ValueError(f"parameters: {part!r} is not name=number, e.g. 'c=3.8'") from None
        if name in out:  # 'c=1, c=2' kept the last, unsaid
            raise ValueError(f"parameters: {name!r} is given twice")
        out[name] = number
    return out


def _spec(parameters: Any, name: str, law: str) -> Any:
    """Return the parameter ``name`` of a law's spec, or a ValueError naming the law's parameters."""
    for p in parameters:
        if p.name == name:
            return p
    raise ValueError(f"{name!r} is not a parameter of the {law} law (it has {[p.name for p in parameters]})")


def check_nu(nu: float) -> None:
    """Refuse a driving velocity outside the slider's range (the slider showed it outside its ends).

    Parameters
    ----------
    nu : float
        The driving velocity (dimensionless).

    Raises
    ------
    ValueError
        Naming ``nu`` and the range, :data:`NU_RANGE`.

    """
    if not (NU_RANGE[0] <= nu <= NU_RANGE[1]):
        raise ValueError(f"nu={nu!r}: expected a driving velocity from 1e-5 to 10 (the slider's range)")


def slider_range(law: str, name: str, value: float) -> tuple[float, float, float]:
    """Return ``(start, end, step)`` of a slider for a law parameter, inside its bounds.

    A registered law's bounds come from its spec (an excluded bound is kept one
    step away, or closer where ``value`` lies closer: the slider holds the value
    given, unmoved); an unbounded end is four times the value (at
    least 1).
    """
    if not math.isfinite(value):  # before the formula's branch too (a nan slider)
        raise ValueError(f"{name}={value!r}: expected a finite value")
    top = max(min(4.0 * abs(value), sys.float_info.max), 1.0)  # 4 * 1e308 was inf
    if law == EXPR:
        return (-top if value < 0 else 0.0), top, top / 400.0
    p = _spec(registry.get(law).spec.parameters, name, law)
    lo = p.lower if math.isfinite(p.lower) else -top
    hi = p.upper if math.isfinite(p.upper) else top
    step = hi / 400.0 - lo / 400.0  # (hi - lo) / 400 overflowed to inf near the largest float
    start = lo if p.lower_inclusive else (min(lo + step, value) if value > lo else lo + step)
    end = hi if p.upper_inclusive else (max(hi - step, value) if value < hi else hi - step)
    return start, end, step


def _units(setup: Setup) -> dict[str, str]:
    physical = setup.physical and setup.law != EXPR  # a formula f(w) is dimensionless
    return {kind: unit_label(kind, physical) for kind in ("force", "time", "velocity")}


def _scale(setup: Setup) -> tuple[float, float, float]:
    """Force, time and velocity units of the display in terms of the dimensionless ones."""
    if not (setup.physical and setup.law != EXPR):
        return 1.0, 1.0, 1.0
    force = setup.mu_s * setup.load
    return force, math.sqrt(setup.mass / setup.stiffness), 1.0 / setup.beta


@functools.lru_cache(maxsize=64)
def _curve(law: DimensionlessLaw, nu: float) -> tuple[FloatArray, FloatArray, tuple[str, ...]]:
    nus = np.geomspace(nu / 10.0, nu * 10.0, CURVE_POINTS)
    ds = sweep(DimensionlessParameters(nu=nu, law=law), {"nu": nus}, progress=False)
    return nus, np.asarray(ds["amplitude"].values, float), tuple(str(r) for r in ds["regime"].values)


@functools.lru_cache(maxsize=16)
def regime_diagram(
    law: DimensionlessLaw, param: str, nu: float, value: float
) -> tuple[FloatArray, FloatArray, npt.NDArray[np.int64]]:
    """Return the regime diagram over driving velocity and the law's parameter ``param``.

    The grid spans two decades each side of ``nu`` and ``param`` from near 0 to
    three times ``value`` (within the parameter's bounds, an excluded one kept a 24th
    inside unless ``value`` lies closer; a negative value, which a formula's parameter
    may have, from three times it to near 0; a value of 0 from -1 to 1); the other
    parameters are those of ``law``. The range always holds ``value``.

    Returns
    -------
    nu, param_values, codes : ndarray
        ``codes`` of shape ``(len(param_values), len(nu))``, indices into :data:`REGIMES`.

    Raises
    ------
    ValueError
        For a ``nu`` that is not positive and finite, a ``value`` that is not finite,
        or a ``param`` the law does not have.

    """
    if not (math.isfinite(nu) and nu > 0.0):  # nan was blamed on the law's parameter
        raise ValueError(f"nu={nu!r}: expected a positive finite driving velocity")
    if not math.isfinite(value):
        raise ValueError(f"{param}={value!r}: expected a finite value")
    nus = np.geomspace(nu / 100.0, nu * 100.0, DIAGRAM_SHAPE[0])
    n = DIAGRAM_SHAPE[1]
    spec = _spec(law.spec.parameters, param, law.name)
    # an excluded bound is kept 1/n of the scale inside (or closer, where the value lies closer)
    scale = max(abs(value), 1.0 / n)
    upper, lower = math.inf, -math.inf
    if math.isfinite(spec.upper):
        inner = spec.upper if spec.upper_inclusive else spec.upper - max(abs(spec.upper), scale) / n
        upper = max(inner, value)
    if math.isfinite(spec.lower):
        inner = spec.lower if spec.lower_inclusive else spec.lower + max(abs(spec.lower), scale) / n
        lower = min(inner, value)
    three = math.copysign(min(3.0 * abs(value), sys.float_info.max), value)  # 3 x 1e308 was inf
    if value == 0.0:  # both signs (1/n .. 1 left the value out)
        lo, hi = max(-1.0, lower), min(1.0, upper)
    elif value > 0.0:  # from near 0 (or an included lower bound: p = 0 is F1) to three times it
        hi = min(three, upper)
        lo = spec.lower if math.isfinite(spec.lower) and spec.lower_inclusive else max(hi / n, lower)
    else:  # the mirror image: from three times the value up to near 0
        lo = max(three, lower)
        hi = spec.upper if math.isfinite(spec.upper) and spec.upper_inclusive else min(lo / n, upper)
    values = np.linspace(lo, hi, n)
    ds = sweep(DimensionlessParameters(nu=nu, law=law), {param: values, "nu": nus}, progress=False)
    labels = np.asarray(ds["regime"].transpose(param, "nu").values).astype(str)
    codes = np.full(labels.shape, REGIMES.index("unknown"), dtype=np.int64)
    for i, r in enumerate(REGIMES):
        codes[labels == r] = i
    return nus, values, codes


def plane_key(setup: Setup, param: str) -> tuple[Any, ...]:
    """Return what a two-parameter diagram of ``param`` depends on: the law and its other parameters.

    The driving velocity and ``param``'s own value are the diagram's axes: moving them moves
    the set-up's point across the same diagram.
    """
    others = tuple(sorted((k, float(v)) for k, v in setup.params.items() if k != param))
    return (setup.law, setup.expression if setup.law == EXPR else "", param, others)


def plane_window(setup: Setup, param: str) -> tuple[tuple[float, float], tuple[float, float]]:
    """Return the ranges of ``nu`` and of ``param`` of the two-parameter diagram about ``setup``.

    ``nu`` spans :data:`PLANE_DECADES` decades each side of the set-up's (within
    :data:`NU_RANGE`); ``param`` from its value divided by :data:`PLANE_FACTOR` to its
    value times it (mirrored for a negative value; -1 to 1 for a value of 0), held inside
    the parameter's bounds: an included bound is kept, an excluded one is approached to a
    quarter of its distance from the value. The range always holds the value.

    Raises
    ------
    ValueError
        For a ``param`` the law does not have, or a value that is not finite.

    """
    check_nu(setup.nu)
    law = setup.dimensionless_law()
    spec = _spec(law.spec.parameters, param, setup.law)
    value = float(setup.params[param])
    if not math.isfinite(value):
        raise ValueError(f"{param}={value!r}: expected a finite value")
    span = 10.0**PLANE_DECADES
    nus = (max(setup.nu / span, NU_RANGE[0]), min(setup.nu * span, NU_RANGE[1]))
    if value == 0.0:
        lo, hi = -1.0, 1.0
    else:
        far = math.copysign(min(abs(value) * PLANE_FACTOR, sys.float_info.max), value)
        lo, hi = sorted((value / PLANE_FACTOR, far))
    if math.isfinite(spec.lower):
        lo = max(lo, spec.lower if spec.lower_inclusive else spec.lower + (value - spec.lower) / 4.0)
    if math.isfinite(spec.upper):
        hi = min(hi, spec.upper if spec.upper_inclusive else spec.upper - (spec.upper - value) / 4.0)
    if not lo < hi:
        raise ValueError(f"{param}={value!r}: no range about it inside the bounds of the {setup.law} law")
    return nus, (lo, hi)


def two_parameter_view(
    setup: Setup, param: str | None = None, *, raster: int = PLANE_RASTER
) -> dict[str, Any]:
    """Return the two-parameter diagram of ``nu`` and ``param`` about ``setup``, as the page's data.

    The window is :func:`plane_window`'s; the diagram is
    :func:`~stickslip.bifurcation.diagram.two_parameter_diagram` of the dimensionless law.

    Parameters
    ----------
    setup : Setup
        The set-up: its law and parameters, and its ``nu``, the centre of the window.
    param : str, optional
        The vertical axis: a parameter of the law (default its last, as the page's).
    raster : int, optional
        Cells per axis of the region raster.

    Returns
    -------
    dict
        ``regions`` (quads: ``left``, ``right``, ``bottom``, ``top``, ``color``, ``regime``,
        ``attractors``; a run of equal cells of a raster row is one quad, a cell on a curve
        takes its nearest region's colour), ``curves`` (lines: ``xs``, ``ys``, ``kind``,
        ``label``, ``color``, ``dash``; a Hopf curve is cut where its criticality changes,
        dashed where subcritical), ``points`` (``x``, ``y``, ``kind``, ``text``, ``marker``,
        ``color``), ``current`` (the set-up's point), ``x_range``, ``y_range``, ``x_log``,
        ``y_log``, ``x_label``, ``y_label``, ``title``, ``notes`` (the diagram's notes and the
        computation's warnings) and ``key`` (:func:`plane_key`).

    Raises
    ------
    ValueError
        For a ``param`` the law does not have or a plane cannot run over, or a set-up that
        cannot be computed (the message names the value).

    """
    from ..bifurcation.diagram import two_parameter_diagram
    from ..bifurcation.planes import Plane

    names = list(setup.params)
    if param is None:
        if not names:
            raise ValueError(f"law={setup.law!r}: it has no parameter to put on the vertical axis")
        param = names[-1]
    if param not in setup.params:
        raise ValueError(
            f"two-parameter diagram: {param!r} is not a parameter of the {setup.law} law: expected one of "
            f"{', '.join(names) or '(none)'}"
        )
    nus, values = plane_window(setup, param)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        plane = Plane.dimensionless(setup.dimensionless_law(), ("nu", nus), (param, values))
        d = two_parameter_diagram(plane, raster=raster)
    said = [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    return {
        "regions": _region_quads(d),
        "curves": _curve_lines(d),
        "points": _special_points(d),
        "current": {"x": [float(setup.nu)], "y": [float(setup.params[param])]},
        "x_range": (plane.x.lo, plane.x.hi),
        "y_range": (plane.y.lo, plane.y.hi),
        "x_log": plane.x.log,
        "y_log": plane.y.log,
        "x_label": "nu (dimensionless driving velocity)",
        "y_label": param,
        "title": plane.describe,
        "notes": list(dict.fromkeys([*d.notes, *said])),
        "key": plane_key(setup, param),
    }


def _region_quads(d: Any) -> dict[str, list[Any]]:
    """Return the regions of a diagram as quads: one per run of equal cells along a raster row."""
    from scipy import ndimage

    from ..plots.regimes import REGIME_COLORS

    region = np.asarray(d.region)
    ny, nx = region.shape
    ex = [d.plane.x.to_unit(k / nx) for k in range(nx + 1)]
    ey = [d.plane.y.to_unit(k / ny) for k in range(ny + 1)]
    out: dict[str, list[Any]] = {
        k: [] for k in ("left", "right", "bottom", "top", "color", "regime", "attractors")
    }
    if not (region >= 0).any():
        return out
    # a cell on a curve (-1) takes its nearest region: the curve is drawn over it
    idx = ndimage.distance_transform_edt(region < 0, return_distances=False, return_indices=True)
    region = region[tuple(idx)]
    for i in range(ny):
        row = region[i]
        starts = np.flatnonzero(np.r_[True, row[1:] != row[:-1]])
        for a, b in zip(starts, [*starts[1:], nx], strict=True):
            r = int(row[a])
            regime = str(d.region_regime[r])
            out["left"].append(ex[a])
            out["right"].append(ex[b])
            out["bottom"].append(ey[i])
            out["top"].append(ey[i + 1])
            out["color"].append(REGIME_COLORS.get(regime, "#ffffff"))
            out["regime"].append(regime)
            out["attractors"].append(str(d.region_names[r]))
    return out


def _curve_lines(d: Any) -> dict[str, list[Any]]:
    """Return the curves of a diagram as lines, a Hopf curve cut where its criticality changes."""
    out: dict[str, list[Any]] = {k: [] for k in ("xs", "ys", "kind", "label", "color", "dash")}

    def add(kind: str, x: np.ndarray, y: np.ndarray, label: str, dash: str) -> None:
        out["xs"].append(np.asarray(x, float).tolist())
        out["ys"].append(np.asarray(y, float).tolist())
        out["kind"].append(kind)
        out["label"].append(label)
        out["color"].append(CURVE_COLORS.get(kind, "#666666"))
        out["dash"].append(dash)

    for c in d.curves:
        words = CURVE_WORDS.get(c.kind, c.kind)
        if c.kind != "hopf" or "f3" not in c.data or len(c.x) < 2:
            add(c.kind, c.x, c.y, words, "solid")
            continue
        # l1 = -f'''/16: subcritical (dashed) where f''' < 0; each piece overlaps the next by a point
        sub = np.asarray(c.data["f3"]) < 0
        cuts = [0, *(np.flatnonzero(sub[1:] != sub[:-1]) + 1).tolist(), len(sub)]
        for a, b in itertools.pairwise(cuts):
            end = min(b + 1, len(sub))
            if sub[a]:
                add("hopf", c.x[a:end], c.y[a:end], f"{words}, subcritical", "dashed")
            else:
                add("hopf", c.x[a:end], c.y[a:end], f"{words}, supercritical", "solid")
    return out


def _special_points(d: Any) -> dict[str, list[Any]]:
    """Return the codimension-2 points of a diagram, each with its words for the hover."""
    out: dict[str, list[Any]] = {k: [] for k in ("x", "y", "kind", "text", "marker", "color")}
    for p in d.points:
        out["x"].append(float(p.x))
        out["y"].append(float(p.y))
        out["kind"].append(p.kind)
        out["text"].append(
            f"{p.kind} at nu = {p.nu:.5g}, {d.plane.y.name} = {p.y:.5g}: {p.detail} "
            f"({p.coefficient} = {p.value:.4g})"
        )
        out["marker"].append(POINT_MARKERS.get(p.kind, "circle"))
        out["color"].append(POINT_COLORS.get(p.kind, "#000000"))
    return out


def compute(setup: Setup) -> View:
    """Compute what the page shows for ``setup``.

    Raises
    ------
    ValueError
        For a non-physical set-up (the message names the parameter).

    """
    params = setup.parameters()
    law = setup.dimensionless_law()
    res = cycle(params)
    traj = simulate(params, cycles=3, n_points=1500)
    fs, _, vs = _scale(setup)
    nus, amps, regimes = _curve(law, float(setup.nu))
    ok = np.isfinite(amps) & (amps > 0)
    near = ok & (nus >= setup.nu / 2.2) & (nus <= setup.nu * 2.2)
    if near.sum() >= 4:
        crit = classify(nus[near], amps[near])
        verdict, reason = crit.verdict, crit.reason
    else:
        verdict, reason = "inconclusive", "fewer than 4 oscillating points near this velocity"
    return View(
        setup=setup,
        regime=res.regime,
        amplitude=float(res.amplitude),
        period=float(res.period),
        stick_fraction=float(res.stick_fraction),
        time=np.asarray(traj.time, float),
        spring_force=np.asarray(traj.spring_force, float),
        velocity=np.asarray(traj.velocity, float),
        stuck=np.asarray(traj.phase) == 0,
        curve_v=nus * vs,
        curve_amplitude=np.where(ok, amps, np.nan) * fs,
        curve_regime=regimes,
        verdict=verdict,
        verdict_reason=reason,
        v0=float(setup.nu) * vs,
        units=_units(setup),
        command=command(setup),
    )


def prepare(setup: Setup) -> None:
    """Compile the engine of ``setup``'s law and write numba's caches: what its first view costs.

    Run in a worker process by a served page (:class:`~.app.Explorer`): the server's own
    process then loads the compiled engine from the cache in a second, and a formula that
    compiles for half a minute never holds the other pages up.

    Raises
    ------
    ValueError
        For a set-up that cannot be computed (the message names the value).

    """
    compute(setup)


def _num(x: float) -> str:
    return repr(float(x))


def command(setup: Setup) -> str:
    """Return the ``stickslip cycle`` command that computes the set-up's steady oscillation."""
    args = ["stickslip", "cycle"]
    if setup.law == EXPR:
        args += ["--law", EXPR, "--f", setup.expression]
        for k, v in setup.params.items():
            args += ["--param", f"{k}={_num(v)}"]
        args += ["--nu", _num(setup.nu)]
        return shlex.join(args)
    args += ["--law", setup.law]
    params = setup.parameters()
    if isinstance(params, PhysicalParameters):
        args += [
            "--v0", f"{_num(params.v0.to('m/s').magnitude)} m/s",
            "--mass", f"{_num(setup.mass)} kg",
            "--stiffness", f"{_num(setup.stiffness)} N/m",
            "--load", f"{_num(setup.load)} N",
            "--mu-s", _num(setup.mu_s),
        ]  # fmt: skip
        for p, q in zip(params.law.spec.physical, params.law.params.values(), strict=True):
            value = q.to(p.unit).magnitude if p.unit else q
            args += [f"--{p.name.replace('_', '-')}", f"{_num(value)} {p.unit}".strip()]
    else:
        args += ["--nu", _num(setup.nu)]
        for k, v in setup.params.items():
            args += [f"--{k.replace('_', '-')}", _num(v)]
    return shlex.join(args)


def view_csv(view: View) -> str:
    """Return the shown motion as CSV text: a ``# command`` line, a header with units, the samples."""
    u = view.units
    buf = io.StringIO()
    buf.write(f"# {view.command}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(
        [f"time [{u['time']}]", f"spring_force [{u['force']}]", f"velocity [{u['velocity']}]", "stuck"]
    )
    for row in zip(view.time, view.spring_force, view.velocity, view.stuck, strict=True):
        w.writerow([repr(float(row[0])), repr(float(row[1])), repr(float(row[2])), int(row[3])])
    return buf.getvalue()
