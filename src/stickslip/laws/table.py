"""A user's friction law from a measured table: friction coefficient against velocity.

``TabulatedLaw(v, mu)`` or ``TabulatedLaw.from_csv("mu_v.csv")``, with the header
convention of the records: ``velocity [um/s],friction coefficient [1]``, or a
friction force with a unit (``friction force [mN]``) and the normal ``load``.

* **Static coefficient.** The table starts at ``v = 0``: that row is the static
  coefficient ``mu_s``. A second row at ``v = 0`` gives ``mu(0+)``, the level
  just after breakaway (a drop at the onset of slip); without it friction is
  continuous at the onset, ``mu(0+) = mu_s``.
* **Interpolation** (``interpolation=``):

  - ``"pchip"`` (default): the monotone piecewise-cubic Hermite interpolant of
    Fritsch and Carlson (``scipy.interpolate.PchipInterpolator``). It passes
    through every row, its first derivative is continuous, and it never
    invents a wiggle between rows: where the data fall, it falls. That matters
    here: the sign of ``mu'(v)`` decides the stability of steady sliding, so a
    wiggle of an interpolant would be a spurious Hopf bifurcation. Its second
    derivative jumps at the rows, so the criticality of a Hopf point (which
    needs ``mu'''``) is that of the local cubic.
  - ``"cubic"``: the interpolating cubic spline (not-a-knot), twice continuously
    differentiable, for smooth, dense, noise-free tables.
  - ``"smoothing"``: a cubic smoothing spline with its smoothing chosen by
    generalised cross-validation (``scipy.interpolate.make_smoothing_spline``),
    twice continuously differentiable, for noisy measured tables: it does not
    pass through the rows.

* **Extrapolation.** Above the last row the coefficient continues along the
  tangent at the last row (value and slope continuous). A computation that
  reaches beyond the table says so (:meth:`TabulatedDimensionlessLaw.range_warning`):
  those results rest on the extrapolation. Below ``v = 0`` (the integrator's
  samples just before a stop) the first cubic piece continues as a polynomial.

Bad tables are refused with the row: unsorted or repeated velocities, negative
velocities or coefficients, coefficients outside ``1e-6..1e3`` (:data:`MU_RANGE`), too few
rows (at least 4 above ``v = 0``), no row at ``v = 0``.
"""

from __future__ import annotations

import functools
import hashlib
import math
import os
import re
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt
import pint

from ..io.errors import DataError
from ..io.tables import read_table
from ..units import Q_, check_number, format_speed, parse_quantity, ureg
from .base import DimensionlessLaw, PhysicalLaw
from .spec import LawSpec, Parameter

if TYPE_CHECKING:
    import sympy as sp

    # scipy.interpolate is imported where a table is fitted (0.4 s at import)
    from scipy.interpolate import PPoly

__all__ = ["INTERPOLATIONS", "TabulatedDimensionlessLaw", "TabulatedLaw"]

FloatArray = npt.NDArray[np.float64]
INTERPOLATIONS = ("pchip", "cubic", "smoothing")
#: weight of the first row (mu(0+)) in the smoothing spline's fit, against 1 for the others
SMOOTHING_PIN = 1e8
#: rows above v = 0 a table needs
MIN_ROWS = 4
#: the friction coefficients a table may hold: superlubric contacts reach about 1e-4 and clean
#: metals in vacuum tens; a value outside is a unit or column mistake, and a static coefficient of
#: 1e12 or 1e-300 makes beta = sqrt(k m)/(mu_s W) and nu = beta v0 leave the engine's range
MU_RANGE = (1e-6, 1e3)
#: the most rows a table may have: its pieces are compiled into the engine as one constant array,
#: 40 bytes a row, and numba makes an array above 1e6 bytes a dynamic global, which it cannot
#: cache (a warning from each of 15 functions) and compiles in 1.3 GB at 2e5 rows, 5.4 GB at 1e6
MAX_ROWS = 25_000


class _TableSpec(LawSpec):
    """The spec of one table: the kernel and the derivatives come from its piecewise cubic."""

    pp: PPoly

    def evaluate(self, w: npt.ArrayLike, values: Any, order: int = 0) -> FloatArray:
        beta = np.asarray(values[0], dtype=float)
        mu_s = np.asarray(values[1], dtype=float)
        w = np.asarray(w, dtype=float)
        v = w / beta
        return np.asarray(_mu(self.pp, v, order) / (mu_s * beta**order), dtype=float)

    def evaluate_scalar(self, w: float, values: Any, order: int = 0) -> float:
        return float(self.evaluate(np.array([w]), values, order)[0])

    @functools.cached_property
    def continuation(self) -> sp.Expr:  # the first cubic piece, not a Taylor polynomial
        import sympy as sp

        return sp.Integer(0)

    def kernel_source(self) -> str:
        from .compiler import piecewise_module_source

        return piecewise_module_source(self.pp.x, self.pp.c, self.name, self.f)

    def kernel(self) -> Any:
        from .compiler import compile_kernel

        return compile_kernel(self.kernel_source(), f"table {self.f}")


def _mu(pp: PPoly, v: npt.ArrayLike, order: int = 0) -> FloatArray:
    """Return the interpolant's ``order``-th derivative (the tangent continues above the last row)."""
    v = np.asarray(v, dtype=float)
    end = pp.x[-1]
    inside = pp(np.minimum(v, end), order) if order else pp(np.minimum(v, end))
    if order == 0:
        slope = pp(end, 1)
        return np.where(v > end, pp(end) + slope * (v - end), inside)
    if order == 1:
        return np.where(v > end, pp(end, 1), inside)
    return np.where(v > end, 0.0, inside)


#: the largest velocity of a friction table (m/s): 10 km/s, beyond any sliding experiment
MAX_TABLE_VELOCITY = 1e4


def _pp(v: FloatArray, mu: FloatArray, interpolation: str) -> PPoly:
    """Return the interpolant as a piecewise cubic in ``v`` (m/s), pieces of positive length only.

    The fit runs on ``v / v_max`` (the smoothing spline's choice of smoothing depends
    on the scale of the abscissa) and is mapped back.
    """
    from scipy.interpolate import CubicSpline, PchipInterpolator, PPoly, make_smoothing_spline

    scale = float(v[-1])
    x = v / scale
    if interpolation == "pchip":
        pp: PPoly = PchipInterpolator(x, mu, extrapolate=True)
    elif interpolation == "cubic":
        pp = CubicSpline(x, mu, bc_type="not-a-knot", extrapolate=True)
    else:
        # the first row is mu(0+) (the static coefficient, or the level after breakaway): the
        # spline passes through it, weighted 1e8 and then shifted by what is left (1e-10 or
        # less), so friction just after breakaway is neither above the static level (the block
        # moved backward at breakaway, unsaid: a 0.22 % rise from noise) nor an unasked drop
        weights = np.ones_like(x)
        weights[0] = SMOOTHING_PIN
        pp = PPoly.from_spline(make_smoothing_spline(x, mu, w=weights))
        pp.c[-1, :] += float(mu[0]) - float(pp(0.0))
    keep = np.flatnonzero(np.diff(pp.x) > 0)
    coefs = pp.c[:, keep] / scale ** np.arange(3, -1, -1)[:, None]  # d/dv = d/dx / scale
    breaks = np.append(pp.x[keep], pp.x[keep[-1] + 1]) * scale
    return PPoly(coefs, breaks, extrapolate=True)


class TabulatedLaw(PhysicalLaw):
    """A physical friction law from a table of the friction coefficient against velocity.

    Parameters
    ----------
    v : pint.Quantity (array) or sequence of str
        Velocities, sorted, starting at 0 (e.g. ``Q_([0, 1, 10, 100], "um/s")``); a
        second 0 gives the level just after breakaway.
    mu : array_like
        Friction coefficients (numbers) at those velocities.
    static : float, optional
        Static coefficient, instead of the first row's.
    interpolation : {"pchip", "cubic", "smoothing"}, optional
        See the module's notes. Default ``"pchip"``.
    name : str, optional
        A name for messages (the file's).

    Raises
    ------
    ValueError
        For a bad table, naming the row.

    """

    __slots__ = ("_pp", "interpolation", "source", "table_mu", "table_v")
    table_v: FloatArray
    table_mu: FloatArray
    interpolation: str
    source: str
    _pp: PPoly

    def __init__(
        self,
        v: Any,
        mu: npt.ArrayLike,
        *,
        static: float | None = None,
        interpolation: str = "pchip",
        name: str = "table",
    ) -> None:
        if interpolation not in INTERPOLATIONS:
            raise ValueError(f"interpolation={interpolation!r}: expected one of {', '.join(INTERPOLATIONS)}")
        v_si = _velocities(v, name)
        if isinstance(mu, pint.Quantity):  # a coefficient: N was taken as one, 50 percent as 50
            if not mu.dimensionless:
                raise ValueError(f"{name}: friction in {mu.units}: expected coefficients (dimensionless)")
            mu = mu.to("").magnitude
        try:
            mu_a = np.asarray(mu, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{name}: mu={mu!r}: expected friction coefficients (numbers)") from None
        if mu_a.ndim != 1:
            raise ValueError(
                f"{name}: mu has shape {mu_a.shape}: expected one coefficient per velocity (1-D)"
            )
        if mu_a.size != v_si.size:
            raise ValueError(f"{name}: mu has {mu_a.size} friction values for {v_si.size} velocities in v")
        if v_si.size > MAX_ROWS:
            step = -(-v_si.size // (MAX_ROWS - 3))  # with the first two rows and the last: MAX_ROWS
            raise ValueError(
                f"{name}: {v_si.size} rows, more than {MAX_ROWS}: a table is compiled into the engine as "
                "a constant, 40 bytes a row, which numba caches up to 1 MB only; thin it (one row in "
                f"{step}, with the first two and the last)"
            )
        bad = np.flatnonzero(~np.isfinite(mu_a) | (mu_a <= 0))
        if bad.size:
            i = int(bad[0])
            raise ValueError(
                f"{name}: row {i + 1}: friction coefficient {float(mu_a[i])!r} is not a positive number"
            )
        absurd = np.flatnonzero((mu_a < MU_RANGE[0]) | (mu_a > MU_RANGE[1]))
        if absurd.size:  # said here: beta and nu made from it leave their range far from the table
            i = int(absurd[0])
            raise ValueError(
                f"{name}: row {i + 1}: friction coefficient {float(mu_a[i]):.6g} is outside "
                f"{MU_RANGE[0]:g}..{MU_RANGE[1]:g}, beyond any pair of surfaces: is the column a coefficient "
                "in the unit its header says (a friction force is 'friction force [mN]' with --load)?"
            )
        if v_si.size == 0 or v_si[0] != 0.0:
            at_zero = np.flatnonzero(v_si == 0.0)
            if at_zero.size:  # there is one, further down: say that the order is the fault
                raise ValueError(
                    f"{name}: the row at v = 0 is row {int(at_zero[0]) + 1}, not the first: sort the "
                    "table by velocity (the first row is the static coefficient, v = 0)"
                )
            raise ValueError(
                f"{name}: the table has no row at v = 0: its first row must be the static coefficient (v = 0)"
            )
        if float(np.max(v_si)) > MAX_TABLE_VELOCITY:  # 1e300 m/s ended in scipy's 'dydx ... finite'
            i = int(np.argmax(v_si))
            raise ValueError(
                f"{name}: row {i + 1}: velocity {float(v_si[i]):.3g} m/s is above "
                f"{MAX_TABLE_VELOCITY:g} m/s: is the velocity column in the unit its header says?"
            )
        zero = int(np.sum(v_si == 0.0))
        if zero > 2:
            raise ValueError(
                f"{name}: {zero} rows at v = 0: at most two (static, then the level just after breakaway)"
            )
        steps = np.diff(v_si[zero - 1 :])
        if np.any(steps <= 0):
            i = int(np.flatnonzero(steps <= 0)[0]) + zero
            raise ValueError(
                f"{name}: row {i + 1}: velocity {v_si[i]:.6g} m/s is not above the row before "
                f"({v_si[i - 1]:.6g} m/s): sort the table by velocity, without repeats"
            )
        if v_si.size - zero < MIN_ROWS:
            raise ValueError(
                f"{name}: {v_si.size - zero} rows above v = 0: at least {MIN_ROWS} are needed to interpolate"
            )
        mu_s = (
            float(mu_a[0])
            if static is None
            else check_number(static, "static", what="a positive static coefficient")
        )
        if not MU_RANGE[0] <= mu_s <= MU_RANGE[1]:  # a static coefficient given apart from the rows
            raise ValueError(
                f"{name}: static={static!r}: a static coefficient outside {MU_RANGE[0]:g}..{MU_RANGE[1]:g}, "
                "beyond any pair of surfaces"
            )
        kin_v = v_si[zero - 1 :]
        kin_mu = mu_a[zero - 1 :]
        if kin_mu[0] > mu_s * (1.0 + 1e-12):
            raise ValueError(f"{name}: mu(0+) = {kin_mu[0]:.6g} exceeds the static coefficient {mu_s:.6g}")
        pp = _pp(kin_v, kin_mu, interpolation)
        if float(pp(0.0)) > mu_s * (1.0 + 1e-12):  # the interpolant's, not only the row's
            raise ValueError(
                f"{name}: the {interpolation} interpolant gives mu(0+) = {float(pp(0.0)):.9g}, above the "
                f"static coefficient {mu_s:.9g}: the block would move backward at breakaway"
            )
        digest = hashlib.sha256(np.ascontiguousarray(np.vstack([pp.x[:-1], pp.c])).tobytes()).hexdigest()[:12]
        spec = _TableSpec(
            name="table",
            title=f"friction coefficient tabulated at {kin_v.size} velocities ({interpolation})",
            f=f"{name} [{interpolation}, {digest}]",
            parameters=(
                Parameter("beta", "beta = sqrt(k m)/(mu_s W) in s/m"),
                Parameter("mu_s", "static coefficient"),
            ),
            to_dimensionless={"beta": "beta", "mu_s": "mu_s"},
            physical=(),
            expression=_table_symbol(),
            source=name,
        )
        object.__setattr__(spec, "pp", pp)
        object.__setattr__(self, "spec", spec)
        object.__setattr__(self, "mu_s", mu_s)
        object.__setattr__(self, "_values", ())
        object.__setattr__(self, "table_v", v_si)
        object.__setattr__(self, "table_mu", mu_a)
        object.__setattr__(self, "interpolation", interpolation)
        object.__setattr__(self, "source", name)
        object.__setattr__(self, "_pp", pp)
        fmin = float(np.min(_mu(pp, np.linspace(0.0, kin_v[-1], 4 * kin_v.size + 1))))
        if fmin <= 0.0:
            raise ValueError(
                f"{name}: the {interpolation} interpolant turns negative ({fmin:.3g}) between rows"
            )

    @classmethod
    def from_csv(
        cls,
        path: str | os.PathLike[str],
        *,
        load: Any = None,
        static: float | None = None,
        interpolation: str = "pchip",
    ) -> TabulatedLaw:
        """Read a table of ``velocity [unit]`` and ``friction coefficient [1]`` (or a friction force).

        The header follows the records': ``velocity [um/s],friction coefficient [1]``, or
        ``friction force [mN]`` with the normal ``load``.

        Raises
        ------
        DataError
            For a file that cannot be read or a table that cannot be used (naming the file and row).
        TypeError
            For a ``path`` that is not a path (a number, None).

        """
        if not isinstance(path, str | os.PathLike):  # 123 gave Python's own TypeError from open()
            raise TypeError(f"path={path!r}: expected the path of a CSV file (str or os.PathLike)")
        cols = read_table(path, ["velocity"], ["friction coefficient", "friction force", "mu", "friction"])
        p = os.fspath(path)
        vel = cols["velocity"]
        if vel.unit is None or not (1.0 * vel.unit).check("[length] / [time]"):
            found = "no unit" if vel.unit is None else f"the unit [{vel.unit:~}]"
            raise DataError(
                f"{p}: column 'velocity' has {found}: it needs a velocity unit in its header, "
                "e.g. 'velocity [um/s]'"
            )
        force_col = next((cols[k] for k in ("friction force", "friction") if k in cols), None)
        coef_col = next((cols[k] for k in ("friction coefficient", "mu") if k in cols), None)
        if coef_col is not None and (coef_col.unit is None or (1.0 * coef_col.unit).dimensionless):
            # a dimensionless unit is a scale all the same: '[%]' is hundredths (it was read as is)
            unit = coef_col.unit
            mu = coef_col.values if unit is None else Q_(coef_col.values, unit).to("").magnitude
        elif force_col is not None and force_col.unit is not None and (1.0 * force_col.unit).check("[force]"):
            if load is None:
                raise DataError(
                    f"{p}: the table gives a friction force: give the normal load (--load) to divide by"
                )
            w = parse_quantity(load, "load", "[force]", "196 mN")
            mu = (Q_(force_col.values, force_col.unit) / w).to("").magnitude
        else:
            raise DataError(
                f"{p}: expected a column 'friction coefficient [1]', or 'friction force [mN]' with a load"
            )
        try:
            return cls(Q_(vel.values, vel.unit), mu, static=static, interpolation=interpolation, name=p)
        except ValueError as exc:  # a row of the table is a line of the file
            msg = re.sub(r"^(.*?): row (\d+): ", lambda m: f"{m[1]}: {vel.place(int(m[2]) - 1)}: ", str(exc))
            raise DataError(msg) from None

    # ------------------------------------------------------------------ value semantics

    def _key(self) -> tuple[Any, ...]:
        return ("table", self.spec.f, self.mu_s)

    def __repr__(self) -> str:
        rows = self.table_v.size
        return f"TabulatedLaw({self.source!r}, {rows} rows, mu_s={self.mu_s!r}, {self.interpolation})"

    def __reduce__(self) -> tuple[Any, ...]:
        return _rebuild, (self.table_v, self.table_mu, self.mu_s, self.interpolation, self.source)

    def replace(self, **changes: Any) -> TabulatedLaw:
        """Return a copy with another static coefficient (``mu_s=``); a table has no other parameter."""
        extra = set(changes) - {"mu_s", "static"}
        if extra:
            raise ValueError(f"a tabulated law has no parameter {sorted(extra)[0]!r}")
        mu_s = changes.get("mu_s", changes.get("static", self.mu_s))
        return TabulatedLaw(
            Q_(self.table_v, "m/s"),
            self.table_mu,
            static=mu_s,
            interpolation=self.interpolation,
            name=self.source,
        )

    def nondimensionalize(self, beta: Any) -> DimensionlessLaw:
        """Return ``f(w) = mu(w / beta) / mu_s`` (``beta`` and ``mu_s`` its parameters)."""
        b = float(parse_quantity(beta, "beta", "[time] / [length]", "42 s/m").to("s/m").magnitude)
        law = object.__new__(TabulatedDimensionlessLaw)
        law._set(self.spec, (), {"beta": b, "mu_s": self.mu_s})
        object.__setattr__(law, "table", self)
        return law

    def coefficient(self, v: Any) -> FloatArray:
        """Return ``mu(v)`` (0 at ``v = 0``, odd in ``v``)."""
        from .base import _velocity

        x = _velocity(v)
        return np.where(x == 0, 0.0, np.sign(x) * _mu(self._pp, np.abs(x)))

    def zero_velocity(self) -> float:
        """Return where the extrapolation falls to zero friction (m/s); inf when it does not fall."""
        pp = self._pp
        end = float(pp.x[-1])
        slope = float(pp(end, 1))
        return end + float(pp(end)) / -slope if slope < 0 else math.inf

    def describe(self) -> str:
        """One line: the table, its interpolation, ``mu_s``, and where its extrapolation reaches zero."""
        zero = self.zero_velocity()  # told with the law, not only when a motion fails there
        end = float(self.table_v[-1])
        where = format_speed(zero) if zero <= 1e3 * end else "more than 1000 times that speed"
        falls = f"; beyond it the last row's tangent reaches zero friction at {where}"
        return (
            f"table: {self.source}, {self.table_v.size} rows up to {format_speed(self.table_v[-1])}, "
            f"{self.interpolation}; mu_s = {self.mu_s:.6g}{falls if math.isfinite(zero) else ''}"
        )


def _rebuild(v: FloatArray, mu: FloatArray, mu_s: float, interpolation: str, name: str) -> TabulatedLaw:
    return TabulatedLaw(Q_(v, "m/s"), mu, static=mu_s, interpolation=interpolation, name=name)


class TabulatedDimensionlessLaw(DimensionlessLaw):
    """The dimensionless form of a :class:`TabulatedLaw`: ``f(w) = mu(w / beta) / mu_s``."""

    __slots__ = ("table",)
    table: TabulatedLaw

    def __repr__(self) -> str:
        return f"TabulatedDimensionlessLaw({self.table!r}, beta={self.beta!r})"

    def __reduce__(self) -> tuple[Any, ...]:
        return _rebuild_nd, (self.table, self.beta)

    def replace(self, **changes: float) -> DimensionlessLaw:
        """Return a copy with another ``beta`` or ``mu_s``."""
        table = self.table.replace(mu_s=changes["mu_s"]) if "mu_s" in changes else self.table
        return table.nondimensionalize(Q_(changes.get("beta", self.beta), "s/m"))

    def zero_velocity(self) -> float:
        """Return where the extrapolation falls to zero friction (m/s); inf when it does not fall."""
        return self.table.zero_velocity()

    def range_warning(self, w_max: float) -> str | None:
        """Say so when a motion reaches beyond the table's last row, or failed where it falls to zero.

        ``w_max`` NaN means the motion could not be followed: where the table ends
        with friction still falling, the likeliest cause is named.
        """
        v = w_max / self.beta
        end = float(self.table.table_v[-1])
        zero = self.zero_velocity()
        if math.isnan(v):
            if not math.isfinite(zero):
                return None
            return (
                f"the table ends at v = {format_speed(end)} with friction still falling: along the tangent "
                f"at its last row friction reaches zero at v = {format_speed(zero)} "
                f"(beta v = {zero * self.beta:.4g}), where a motion cannot be followed; "
                "extend the table to faster rows"
            )
        if v > end:
            falls = f"; it falls to zero at v = {format_speed(zero)}" if math.isfinite(zero) else ""
            return (
                f"the motion reaches v = {format_speed(v)}, beyond the table's last row "
                f"({format_speed(end)}): "
                f"friction there is the tangent at the last row (extrapolated){falls}"
            )
        return None

    def breakpoints(self) -> FloatArray:
        """Return the rows above ``v = 0`` as dimensionless velocities ``w = beta v``."""
        x = np.asarray(self.table._pp.x, dtype=float)
        return x[x > 0] * self.beta

    def hopf_note(self, nu: float, criticality: str) -> str | None:
        """Warn that a Hopf point on a ``pchip`` row sits there because of the interpolant."""
        if self.table.interpolation != "pchip":
            return None
        return (
            f"the Hopf point at nu = {nu:.6g} (v0 = {format_speed(nu / self.beta)}) lies on a row of the "
            "table: pchip puts an extremum (minimum or maximum) of the friction coefficient on the row "
            "nearest to it, so the point is only as good as the rows' spacing, and its type ("
            f"{criticality}, from the jump of mu'' at the row) belongs to the interpolant, not "
            "necessarily to the friction; for a smooth, dense table use interpolation='cubic' "
            "(--interpolation cubic)"
        )

    def to_physical(self, beta: Any, mu_s: float) -> PhysicalLaw:
        """Return the table (physical laws of a table do not depend on ``beta``)."""
        return self.table.replace(mu_s=mu_s) if mu_s != self.table.mu_s else self.table

    def describe(self) -> str:
        """One line: the table and ``beta``."""
        return f"{self.table.describe()}; beta = {self.beta:.6g} s/m"


def _rebuild_nd(table: TabulatedLaw, beta: float) -> DimensionlessLaw:
    return table.nondimensionalize(Q_(beta, "s/m"))


def _velocities(v: Any, name: str) -> FloatArray:
    if isinstance(v, pint.Quantity):
        q = v
    elif isinstance(v, list | tuple) and v and all(isinstance(x, str) for x in v):
        q = Q_(
            np.array(
                [
                    parse_quantity(x, "v", "[length] / [time]", "5 um/s", allow_zero=True).to("m/s").magnitude
                    for x in v
                ]
            ),
            "m/s",
        )
    else:
        raise ValueError(
            f"{name}: v: expected velocities with units, e.g. Q_([0, 1, 10, 100], 'um/s'), "
            f"not {type(v).__name__}"
        )
    if not q.check("[length] / [time]"):
        raise ValueError(f"{name}: v has dimension {q.dimensionality}, expected a velocity")
    arr = np.atleast_1d(np.asarray(q.to("m/s").magnitude, dtype=float))
    bad = np.flatnonzero(~np.isfinite(arr) | (arr < 0))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"{name}: row {i + 1}: velocity {float(arr[i])!r} m/s is not a non-negative number")
    return arr


_ = ureg  # the package's registry (quantities above are made in it)


def _table_symbol() -> sp.Expr:
    """``table(w)``: the formula a table law stands for (sympy, loaded on a table's first use)."""
    import sympy as sp

    from .spec import W

    return sp.Function("table")(W)
