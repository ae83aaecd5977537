"""What the compiled kernels return, decoded once: named fields, and statuses as enums.

The kernels write their results into rows of floats (layouts ``O_*`` of
:mod:`~stickslip.core.engine` and ``SH_*`` of :mod:`~stickslip.core.variational`);
this module is the one place that reads those layouts. Everything above it uses
:class:`AttractorRows` and :class:`ShootingRows` (a field per quantity, a view of
the rows, so that writing a field writes the row) and the enums below. The
rate-and-state integrators' rows and codes (:mod:`~stickslip.core.ratestate`,
:mod:`~stickslip.core.radau`) are read in the section at the end.

The enums are string enums: a member equals its label (``Status.OK == "ok"``), so
results, JSON and NetCDF carry the labels, while each member also carries its
integer code (the kernels' and the NetCDF flag values) and its message for users,
in the manner of diffrax's ``RESULTS``.
"""

from __future__ import annotations

import enum
from typing import Any

import numpy as np
import numpy.typing as npt

from . import chain, engine, radau
from . import ratestate as rs
from . import variational as va

__all__ = [
    "AttractorRows",
    "ChainStatus",
    "EventKind",
    "FlowResult",
    "RadauEvent",
    "RadauEventRows",
    "RadauStatus",
    "RateStateEvent",
    "RateStateEventRows",
    "RateStateRecordRows",
    "RateStateSampleRows",
    "RateStateStatus",
    "Regime",
    "ReturnMapRows",
    "ReturnMapStatus",
    "ShootStatus",
    "ShootingRows",
    "Status",
    "radau_progress",
    "reversal",
]

FloatArray = npt.NDArray[np.float64]


class _Labelled(enum.StrEnum):
    """A string enum whose members carry an integer code and a message."""

    code: int
    message: str

    def __new__(cls, label: str, code: int, message: str) -> _Labelled:
        obj = str.__new__(cls, label)
        obj._value_ = label
        obj.code = code
        obj.message = message
        return obj

    @classmethod
    def from_code(cls, code: Any) -> Any:
        """Return the member with integer code ``code``."""
        c = int(code)
        for m in cls:
            if m.code == c:
                return m
        raise ValueError(f"{cls.__name__}: no member with code {c}")

    @classmethod
    def from_label(cls, label: str) -> Any:
        """Return the member labelled ``label`` (ValueError when there is none)."""
        for m in cls:
            if m.value == label:
                return m
        raise ValueError(f"{cls.__name__}: no member {label!r}")

    @classmethod
    def codes(cls) -> dict[str, int]:
        """Return ``{label: code}`` of every member (for NetCDF ``flag_values``)."""
        return {m.value: m.code for m in cls}


class Status(_Labelled):
    """How a computation ended."""

    OK = "ok", engine.ST_OK, "finished"
    NOT_CONVERGED = (
        "not-converged",
        engine.ST_NOT_CONVERGED,
        "the oscillation could not be pinned down to the promised 1e-8: the transient did not "
        "settle and could not be solved as a periodic orbit to that accuracy (the orbit's "
        "multiplier tends to 1 within about 1e-5 of a Hopf point, and where the friction's slope "
        "f'(nu) is nearly zero, as for a slip-reversal orbit at a large nu)",
    )
    STEP_TOO_SMALL = (
        "step-size-too-small",
        engine.ST_STEP_TOO_SMALL,
        "the integration step fell below the resolution of the time: the friction law is "
        "singular or not finite where the motion went, or the motion ran away where friction "
        "falls to zero or below",
    )
    TOO_MANY_STEPS = (
        "too-many-steps",
        engine.ST_TOO_MANY_STEPS,
        "the slip phase needs more steps than allowed: the law is very stiff at these parameters",
    )
    TOO_MANY_PHASES = (
        "too-many-phases",
        engine.ST_TOO_MANY_PHASES,
        "more stick and slip phases than allowed before the motion settled",
    )


class Regime(_Labelled):
    """The one vocabulary of regimes and attractors, with one integer code each.

    The engine writes the first three codes and ``unknown``, with a count of backward
    slips: a ``pure-slip`` row with backward slips is ``slip-reversal`` (its velocity
    changes sign without sticking) wherever a regime is shown or stored
    (:func:`reversal`). The others name what the analyses above it find: two
    coexisting attractors, no attractor of a kind.
    """

    STICK_SLIP = "stick-slip", engine.RG_STICK_SLIP, "the block sticks once per cycle"
    PURE_SLIP = (
        "pure-slip",
        engine.RG_PURE_SLIP,
        "an oscillation that never sticks and never slips backward (w > 0 throughout)",
    )
    STEADY_SLIDING = "steady-sliding", engine.RG_STEADY, "sliding at the driving velocity"
    SLIP_REVERSAL = "slip-reversal", 3, "an oscillation that never sticks but slips backward"
    BISTABLE = "bistable", 4, "two attractors coexist"
    MULTISTABLE = "multistable", 6, "three or more attractors coexist"
    NONE = "none", 5, "no attractor of this kind"
    UNKNOWN = "unknown", engine.RG_UNKNOWN, "the computation did not finish"


def reversal(codes: Any, n_backward: Any) -> Any:
    """Return the regime codes with ``pure-slip`` made ``slip-reversal`` where there are backward slips.

    ``codes`` and ``n_backward`` are the engine's arrays (or scalars) of one shape; a
    NaN count is no backward slip.
    """
    codes = np.asarray(codes)
    back = np.nan_to_num(np.asarray(n_backward, dtype=float), nan=0.0) > 0
    out = np.where((codes == Regime.PURE_SLIP.code) & back, Regime.SLIP_REVERSAL.code, codes)
    return out.astype(codes.dtype)


class ShootStatus(_Labelled):
    """How Newton shooting for a pure-slip orbit ended."""

    OK = "ok", va.SHOOT_OK, "converged"
    NO_CONVERGENCE = (
        "no-convergence",
        va.SHOOT_NO_CONVERGENCE,
        "shooting did not converge in the iterations allowed",
    )
    DIVERGED = "diverged", va.SHOOT_DIVERGED, "shooting diverged; try a better guess"
    FLOW_FAILED = (
        "flow-failed",
        va.SHOOT_FLOW_FAILED,
        "the slip flow failed during shooting (step budget or a non-finite state)",
    )
    GRAZES = (
        "grazes",
        va.SHOOT_GRAZES,
        "the orbit found reaches w <= 0: it grazes, so it is not a pure-slip orbit (the motion sticks)",
    )
    TRIVIAL = (
        "trivial",
        va.SHOOT_TRIVIAL,
        "shooting fell onto steady sliding (zero amplitude): no oscillation near the guess",
    )


class EventKind(_Labelled):
    """Events of a trajectory (rows ``(time, code, spring force)`` of its event log)."""

    STOP = "stop", engine.EV_STOP, "the block stops"
    BREAKAWAY = "breakaway", engine.EV_FORWARD, "the block starts to slip forward"
    BACKWARD_SLIP = "backward-slip", engine.EV_BACKWARD, "the block starts to slip backward"
    FORCE_MAXIMUM = "force-maximum", engine.EV_SMAX, "a maximum of the spring force (w crosses nu upward)"
    FORCE_MINIMUM = "force-minimum", engine.EV_SMIN, "a minimum of the spring force (w crosses nu downward)"
    STICK = "stick", engine.EV_STICK, "the block stays at rest after a stop"


#: the fields of each kind of rows, by name, with their columns (:meth:`_Rows.layout`)
_LAYOUTS: dict[type, dict[str, int]] = {}


class _Rows:
    """Rows of a kernel's output with a named field per column (views: writable).

    ``fields``: the names of the fields these rows keep, in the layout's order, where
    they keep only some (``raw`` then has a column for each, in that order); None
    where they keep every column of the layout. Reading or writing a field they do
    not keep raises an AttributeError that says so (``hasattr`` is then False).
    """

    _width: int = 0

    def __init__(self, raw: npt.ArrayLike, fields: tuple[str, ...] | str | None = None) -> None:
        if isinstance(fields, str):
            fields = (fields,)
        if fields is not None:
            fields = tuple(fields)
            if fields != type(self).check_fields(fields):
                raise ValueError(
                    f"{type(self).__name__}: fields {fields} not each once in the layout's order"
                )
            if len(fields) == len(type(self).layout()):
                fields = None  # every field, in the layout's order: the full rows
        a = np.asarray(raw, dtype=np.float64)
        if a.ndim == 1:
            a = a[None, :]
        width = self._width if fields is None else len(fields)
        if a.ndim != 2 or a.shape[1] != width:
            raise ValueError(f"{type(self).__name__}: expected rows of {width} values, got {a.shape}")
        self.raw = a
        self.fields = fields
        self._where: dict[int, int] | None = None
        if fields is not None:
            layout = _LAYOUTS.get(type(self)) or type(self).layout()
            self._where = {layout[name]: j for j, name in enumerate(fields)}

    @classmethod
    def layout(cls) -> dict[str, int]:
        """Return every field's name and its column in the kernel's rows, in the columns' order."""
        if cls not in _LAYOUTS:
            found = {
                name: f.column
                for k in reversed(cls.__mro__)
                for name, f in vars(k).items()
                if isinstance(f, _Field)
            }
            _LAYOUTS[cls] = dict(sorted(found.items(), key=lambda item: item[1]))
        return dict(_LAYOUTS[cls])

    @classmethod
    def check_fields(cls, fields: Any) -> tuple[str, ...]:
        """Return ``fields`` (names of this kind's fields) once each, in the layout's order.

        Raises
        ------
        ValueError
            For a name that is not a field, or no name at all.

        """
        names = [fields] if isinstance(fields, str) else list(fields)
        layout = cls.layout()
        unknown = [x for x in names if x not in layout]
        if unknown or not names:
            raise ValueError(
                f"fields={unknown[0] if unknown else names!r}: expected names of {cls.__name__}'s "
                f"fields ({', '.join(layout)})"
            )
        return tuple(x for x in layout if x in names)

    def keeps(self, name: str) -> bool:
        """Whether these rows keep the field ``name``."""
        return name in type(self).layout() and (self.fields is None or name in self.fields)

    def _column(self, f: _Field) -> int:
        if self._where is None:
            return f.column
        j = self._where.get(f.column)
        if j is None:
            kept = ", ".join(self.fields or ())
            raise AttributeError(f"{type(self).__name__}.{f.name}: not kept by these rows (they keep {kept})")
        return j

    def __len__(self) -> int:
        return int(self.raw.shape[0])

    def __getitem__(self, index: Any) -> Any:
        """Return the rows selected by ``index`` (an integer keeps a row of its own)."""
        sub = self.raw[index]
        return type(self)(sub if sub.ndim == 2 else sub[None, :], self.fields)

    def copy(self) -> Any:
        """Return a copy that shares nothing with these rows."""
        return type(self)(self.raw.copy(), self.fields)

    def __setitem__(self, index: Any, other: _Rows) -> None:
        if other.fields != self.fields:
            raise ValueError(
                f"{type(self).__name__}: rows of other fields ({other.fields}) put into rows of {self.fields}"
            )
        self.raw[index] = other.raw

    @classmethod
    def concat(cls, parts: Any) -> Any:
        """Return the rows of ``parts`` (rows of this kind, keeping the same fields) one after the other."""
        parts = list(parts)
        kept = {p.fields for p in parts}
        if len(kept) > 1:
            raise ValueError(f"{cls.__name__}.concat: rows of different fields ({sorted(map(str, kept))})")
        return cls(np.vstack([p.raw for p in parts]), kept.pop() if kept else None)


class _Field:
    """A named column of a kernel's rows (a view of it: writing it writes the rows)."""

    def __init__(self, column: int, doc: str) -> None:
        self.column = column
        self.__doc__ = doc
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, obj: _Rows | None, owner: type | None = None) -> Any:
        if obj is None:
            return self
        return obj.raw[:, obj._column(self)]

    def __set__(self, obj: _Rows, value: Any) -> None:
        obj.raw[:, obj._column(self)] = value


def _field(column: int, doc: str) -> Any:
    return _Field(column, doc)


class AttractorRows(_Rows):
    """Output of :func:`~stickslip.core.api.run_attractors`: one row per parameter set.

    Every field is an array over the rows (dimensionless units; NaN where it does
    not apply). ``status`` and ``regime`` hold the integer codes of
    :class:`Status` and :class:`Regime`; :meth:`statuses` and :meth:`regimes`
    return the members. Rows of ``run_attractors(..., fields=...)`` keep only the
    fields asked for (:attr:`fields`; on a GPU only those cross back to the host).
    """

    _width = engine.NOUT
    status = _field(engine.O_STATUS, "Status code (Status.code).")
    regime = _field(engine.O_REGIME, "Regime code (Regime.code): stick-slip, pure-slip or steady sliding.")
    amplitude = _field(engine.O_AMPLITUDE, "Full range of the spring force over the measured cycle.")
    period = _field(engine.O_PERIOD, "Period of the measured cycle.")
    stick_time = _field(engine.O_STICK_TIME, "Time at rest per cycle.")
    s_max = _field(engine.O_SMAX, "Largest spring force over the cycle.")
    s_min = _field(engine.O_SMIN, "Smallest spring force over the cycle.")
    w_max = _field(engine.O_WMAX, "Largest velocity over the cycle.")
    w_min = _field(engine.O_WMIN, "Smallest velocity over the cycle.")
    s_stop = _field(engine.O_SSTOP, "Spring force at the stop of a stick-slip cycle.")
    n_backward = _field(engine.O_NBACKWARD, "Backward slip phases per cycle.")
    drive_work = _field(engine.O_DRIVE_WORK, "Work of the drive over the cycle (with diag).")
    friction_work = _field(engine.O_FRICTION_WORK, "Work of friction over the cycle (with diag).")
    transient = _field(engine.O_TRANSIENT, "Time from the start to the measured cycle.")
    s = _field(engine.O_S, "Spring force at the end of the run.")
    w = _field(engine.O_W, "Velocity at the end of the run.")
    t = _field(engine.O_T, "Time at the end of the run.")
    n_steps = _field(engine.O_NSTEP, "Accepted integration steps.")
    n_rejected = _field(engine.O_NREJECT, "Rejected integration steps.")
    dfnu = _field(engine.O_DFNU, "f'(nu): steady sliding is linearly stable where it is positive.")
    fnu = _field(engine.O_FNU, "f(nu): the spring force of steady sliding.")

    @property
    def ok(self) -> npt.NDArray[np.bool_]:
        """Rows whose computation finished."""
        return np.asarray(self.status == Status.OK.code)

    def is_regime(self, regime: Regime) -> npt.NDArray[np.bool_]:
        """Rows that finished in ``regime``."""
        return np.asarray(self.ok & (self.regime == regime.code))

    def statuses(self) -> list[Status]:
        """Return the status of every row."""
        return [Status.from_code(c) for c in self.status]

    def regimes(self) -> list[Regime]:
        """Return the regime of every row (``unknown`` where the computation did not finish)."""
        return [
            Regime.from_code(r) if s == Status.OK.code else Regime.UNKNOWN
            for r, s in zip(self.regime, self.status, strict=True)
        ]

    @classmethod
    def empty(cls, n: int, fields: tuple[str, ...] | str | None = None) -> AttractorRows:
        """Return ``n`` rows of NaN (keeping only ``fields``, where given)."""
        kept = None if fields is None else cls.check_fields(fields)
        width = engine.NOUT if kept is None or len(kept) == engine.NOUT else len(kept)
        return cls(np.full((n, width), np.nan), kept)


class ReturnMapStatus(_Labelled):
    """How the search for a fixed point of the return map on ``w = nu`` ended."""

    OK = "ok", engine.RM_OK, "converged"
    FAILED = "integration-failed", engine.RM_FAILED, "the integration failed"
    STICKS = "sticks", engine.RM_STICKS, "the motion sticks (not a non-sticking orbit)"
    NO_MAXIMUM = "no-maximum", engine.RM_NO_MAXIMUM, "no spring-force maximum within the time integrated"
    STALLED = "stalled", engine.RM_STALLED, "the secant iteration stalled"
    NOT_CONVERGED = "not-converged", engine.RM_NOT_CONVERGED, "no fixed point within the iterations allowed"
    LEFT = "left-the-states", engine.RM_LEFT, "the secant iteration left the states the engine takes"


class ReturnMapRows(_Rows):
    """Output of :func:`~stickslip.core.api.run_return_maps`: a non-sticking orbit per row."""

    _width = engine.NRM
    status = _field(engine.RM_STATUS, "ReturnMapStatus code.")
    s0 = _field(engine.RM_S0, "Spring-force maximum of the orbit (where w crosses nu upward).")
    period = _field(engine.RM_PERIOD, "Return time.")
    multiplier = _field(engine.RM_MULT, "Derivative of the return map at the fixed point.")
    residual = _field(engine.RM_RESIDUAL, "The residual ``|P(s0) - s0|``.")
    at = _field(engine.RM_AT, "Where an integration failed: the spring force it started from.")
    detail = _field(
        engine.RM_DETAIL,
        "What a failure was: the integration's status code, the time integrated, or ``|P(s) - s|``.",
    )

    def message(self, i: int) -> str:
        """Return why row ``i`` has no orbit (or that it converged), in one line."""
        st = ReturnMapStatus.from_code(self.status[i])
        at, detail = float(self.at[i]), float(self.detail[i])
        if st == ReturnMapStatus.FAILED:
            why = Status.from_code(detail).message
            return f"return map from s = {at:.6g}: the integration failed ({why})"
        if st == ReturnMapStatus.STICKS:
            return f"return map from s = {at:.6g}: the motion sticks (not a non-sticking orbit)"
        if st == ReturnMapStatus.NO_MAXIMUM:
            return f"return map from s = {at:.6g}: no spring-force maximum within tau = {detail:.3g}"
        if st == ReturnMapStatus.LEFT:
            return f"return map: the secant iteration left the states the engine takes (s = {at:.6g})"
        if st == ReturnMapStatus.NOT_CONVERGED:
            return f"return map: no fixed point within the iterations allowed (|P(s) - s| = {detail:.3g})"
        return f"return map: {st.message}"


class ShootingRows(_Rows):
    """Output of :func:`~stickslip.core.api.run_shooting`: one pure-slip orbit per row."""

    _width = va.NSH
    status = _field(va.SH_STATUS, "ShootStatus code.")
    s0 = _field(va.SH_S0, "Spring force where the orbit crosses w = nu upward (its maximum).")
    period = _field(va.SH_PERIOD, "Period of the orbit.")
    amplitude = _field(va.SH_AMPLITUDE, "Full range of the spring force on the orbit.")
    w_min = _field(va.SH_W_MIN, "Smallest velocity on the orbit.")
    w_max = _field(va.SH_W_MAX, "Largest velocity on the orbit.")
    divergence_multiplier = _field(va.SH_DIV_MULT, "exp(-integral of f'(w)): the nontrivial multiplier.")
    iterations = _field(va.SH_ITER, "Newton iterations.")
    residual = _field(va.SH_RESIDUAL, "Periodicity residual |G|.")
    err_s0 = _field(va.SH_ERR_S0, "Estimated error of s0.")
    err_period = _field(va.SH_ERR_PERIOD, "Estimated error of the period.")

    @property
    def monodromy(self) -> FloatArray:
        """Monodromy matrices, shape (n, 2, 2)."""
        if self.fields is not None:
            raise AttributeError("ShootingRows.monodromy: not kept by rows that keep some fields only")
        return self.raw[:, va.SH_PHI : va.SH_PHI + 4].reshape(-1, 2, 2)

    def statuses(self) -> list[ShootStatus]:
        """Return the status of every row."""
        return [ShootStatus.from_code(c) for c in self.status]


class FlowResult:
    """Final state of :func:`~stickslip.core.api.run_flow` and what it measured on the way.

    Attributes
    ----------
    state : ndarray, shape (9,)
        ``(s, w)``, the monodromy ``Phi`` (row-major), ``d(s, w)/d nu`` and the
        integral of ``f'(w)`` (layout of :mod:`~stickslip.core.variational`).
    s_min, w_min, w_max : float
        Spring force where ``w`` crosses ``nu`` downward, and the extremes of ``w``
        (NaN unless measured).
    steps : int
        Integration steps.

    """

    def __init__(self, state: FloatArray, extras: FloatArray) -> None:
        self.state = state
        self.s_min = float(extras[va.X_S_MIN])
        self.w_min = float(extras[va.X_W_MIN])
        self.w_max = float(extras[va.X_W_MAX])
        self.steps = int(extras[va.X_STEPS])

    @property
    def s(self) -> float:
        """Spring force at the end."""
        return float(self.state[0])

    @property
    def w(self) -> float:
        """Velocity at the end."""
        return float(self.state[1])

    @property
    def monodromy(self) -> FloatArray:
        """``d(s, w)/d(s0, w0)`` at the end, 2 x 2."""
        return self.state[2:6].reshape(2, 2)

    @property
    def d_nu(self) -> FloatArray:
        """``d(s, w)/d nu`` at the end (at fixed start)."""
        return self.state[6:8]

    @property
    def integral_dfdw(self) -> float:
        """Integral of ``f'(w)`` over the flow."""
        return float(self.state[8])


class ChainStatus(_Labelled):
    """How a chain simulation ended."""

    OK = "ok", chain.CH_EVENTS, "finished: every requested event simulated"
    TIME_LIMIT = (
        "time-limit",
        chain.CH_T_MAX,
        "the time limit came before the requested number of events (in a pure-slip or steady-sliding "
        "regime an event never ends)",
    )
    PAUSED = "paused", chain.CH_PAUSED, "stopped between two calls of the engine (internal)"
    SLIDING = (
        "sliding",
        -1,
        "an event lasted longer than max_event_duration: the blocks never all stick again "
        "(a sliding state of the chain: pure slip or steady sliding of some blocks)",
    )
    STEP_TOO_SMALL = (
        "step-size-too-small",
        chain.CH_STEP_TOO_SMALL,
        "the integration step fell below the resolution of the time: the friction law is singular "
        "or not finite where the motion went",
    )
    STALLED = (
        "stalled",
        chain.CH_STALLED,
        "the engine stopped making progress in time (events at one instant again and again): a "
        "state it cannot resolve; please report it with the command",
    )
    NONFINITE = (
        "not-finite",
        chain.CH_NONFINITE,
        "the motion left the range of floating-point numbers (a law that drives the blocks?)",
    )


# ---------------------------------------------------------------- rate and state
# The compiled rate-and-state integrators: integrate_qs of core.ratestate (the quasi-static
# and quasi-dynamic slider, DOP853) and integrate_in of core.radau (the inertial slider,
# Radau IIA). Their statuses, event kinds and rows are read here, and only here.


class RateStateStatus(_Labelled):
    """How :func:`~stickslip.core.ratestate.integrate_qs` stopped; the label says it in a word."""

    OK = "ok", rs.RS_OK, "reached the end of the history"
    RUNAWAY = "runaway", rs.RS_RUNAWAY, "the slip rate ran away"
    MAX_STEPS = "max-steps", rs.RS_MAX_STEPS, "this call's bound on the steps reached (call again to go on)"
    STEP_TOO_SMALL = (
        "step-too-small",
        rs.RS_STEP_TOO_SMALL,
        "the step size fell below the precision of the clock: a Dc too small to resolve, or a slip "
        "rate that changes faster than the model holds",
    )
    NONFINITE = "not-finite", rs.RS_NONFINITE, "the slip rate overflowed (faster than the model holds)"
    EVENTS_FULL = "events-full", rs.RS_EVENTS_FULL, "the events buffer is full (empty it and call again)"


class RateStateEvent(_Labelled):
    """Events that :func:`~stickslip.core.ratestate.integrate_qs` locates on its dense output."""

    SPRING_PEAK = "spring-peak", rs.EV_SPRING_PEAK, "a maximum of the spring force (v crosses v_lp upward)"
    UP = "up", rs.EV_UP, "the slip velocity rises through the event velocity"
    DOWN = "down", rs.EV_DOWN, "the slip velocity falls through the event velocity"
    VELOCITY_PEAK = (
        "velocity-peak",
        rs.EV_VELOCITY_PEAK,
        "a maximum of the slip velocity above the event velocity",
    )
    RUNAWAY = "runaway", rs.EV_RUNAWAY, "the slip velocity passes the cap"


class RadauStatus(_Labelled):
    """How a call of :func:`~stickslip.core.radau.integrate_in` ended."""

    DONE = "done", radau.RD_DONE, "reached the end of the segment"
    MAX_STEPS = (
        "max-steps",
        radau.RD_MAX_STEPS,
        "this call's bound on the steps reached (call again to go on)",
    )
    EVENTS_FULL = "events-full", radau.RD_EVENTS_FULL, "the events buffer is full (empty it and call again)"
    STEP_TOO_SMALL = (
        "step-too-small",
        radau.RD_STEP_TOO_SMALL,
        "the required step size is less than spacing between numbers",
    )


class RadauEvent(_Labelled):
    """Events that :func:`~stickslip.core.radau.integrate_in` locates on its dense output."""

    SPRING_PEAK = "spring-peak", radau.EV_SPRING_PEAK, "a maximum of the spring force (v crosses v_lp upward)"
    VELOCITY_PEAK = (
        "velocity-peak",
        radau.EV_VELOCITY_PEAK,
        "a maximum of the slip velocity (mu_s - f - eta v crosses zero downward)",
    )


def radau_progress(ws: radau.Workspace) -> tuple[float, int]:
    """Return the time (s) reached and the steps taken by the Radau integrator of workspace ``ws``."""
    return float(ws.st[radau.ST_T]), int(ws.st[radau.ST_STEPS])


class _StateRows:
    """Rows of a rate-and-state integrator: named columns and the state ``y`` (views: writable).

    ``y`` has ``nvar`` values: for :func:`~stickslip.core.ratestate.integrate_qs`
    ``(mu_s, theta_1..n)`` and its :data:`~stickslip.core.ratestate.N_QUAD` quadratures per
    normal stress, for :func:`~stickslip.core.radau.integrate_in` ``(mu_s, v, theta_1..n)``.
    ``n_states`` (``n``) splits ``y`` into its parts; None where only the named columns are read.
    """

    _y: int = 0  # the column where y starts
    _others: int = 0  # the columns besides y
    _named: tuple[str, ...] = ()  # their names

    def __init__(self, raw: npt.ArrayLike, n_states: int | None = None) -> None:
        a = np.asarray(raw, dtype=np.float64)
        if a.ndim != 2 or a.shape[1] < self._others + (0 if n_states is None else 1 + n_states):
            named = ", ".join(self._named)
            raise ValueError(f"{type(self).__name__}: expected rows of {named} and the state, got {a.shape}")
        self.raw = a
        self.n_states = n_states

    @classmethod
    def empty(cls, rows: int, n_states: int, nvar: int, fill: float = 0.0) -> Any:
        """Return ``rows`` rows (of ``fill``) for a state of ``nvar`` values, for the integrator to write."""
        return cls(np.full((rows, cls._others + nvar), fill), n_states)

    @classmethod
    def stack(cls, y: npt.ArrayLike, n_states: int | None = None, **columns: npt.ArrayLike) -> Any:
        """Return the rows of the states ``y`` (one a row) with the named columns (an array each)."""
        if set(columns) != set(cls._named):
            raise ValueError(f"{cls.__name__}.stack: expected the columns {', '.join(cls._named)}")
        ys = np.asarray(y, dtype=np.float64)
        out = cls(np.empty((ys.shape[0], cls._others + ys.shape[1])), n_states)
        out.y[:] = ys
        for name, values in columns.items():
            setattr(out, name, values)
        return out

    def _column(self, f: _Field) -> int:
        return f.column

    def __len__(self) -> int:
        return int(self.raw.shape[0])

    def __getitem__(self, index: Any) -> Any:
        """Return the rows selected by ``index`` (an integer keeps a row of its own)."""
        sub = self.raw[index]
        return type(self)(sub if sub.ndim == 2 else sub[None, :], self.n_states)

    @property
    def nvar(self) -> int:
        """Number of values of the state ``y``."""
        return int(self.raw.shape[1]) - self._others

    @property
    def y(self) -> FloatArray:
        """The state, one row each."""
        return self.raw[:, self._y : self._y + self.nvar]

    @property
    def spring(self) -> FloatArray:
        """``mu_s``: the spring's stress per normal stress (spring force / W)."""
        return self.raw[:, self._y]


class _QuasiStaticRows(_StateRows):
    """Rows of :func:`~stickslip.core.ratestate.integrate_qs`: ``y`` split into its parts."""

    def _n(self) -> int:
        if self.n_states is None:
            raise AttributeError(f"{type(self).__name__}: n_states not given, the state cannot be split")
        return self.n_states

    @property
    def slider(self) -> FloatArray:
        """``(mu_s, theta_1..n)``: the quasi-static slider's state without the quadratures."""
        return self.y[:, : 1 + self._n()]

    @property
    def theta(self) -> FloatArray:
        """The log-states ``theta_1..n`` of the quasi-static slider, one column each."""
        return self.y[:, 1 : 1 + self._n()]

    def _quadrature(self, k: int) -> FloatArray:
        n = self._n()
        if self.nvar < 1 + n + rs.N_QUAD:
            raise AttributeError(f"{type(self).__name__}: these rows hold no quadratures")
        return self.raw[:, self._y + 1 + n + k]

    @property
    def slip(self) -> FloatArray:
        """Slip (m) since the start of the integration."""
        return self._quadrature(0)

    @property
    def friction_work(self) -> FloatArray:
        """Work of friction ``int (mu_s - eta v) v dt`` (m, per normal stress)."""
        return self._quadrature(1)

    @property
    def radiated(self) -> FloatArray:
        """Energy radiated by the damping ``int eta v^2 dt`` (m, per normal stress)."""
        return self._quadrature(2)

    @property
    def load_work(self) -> FloatArray:
        """Work of the load point ``int mu_s v_lp dt`` (m, per normal stress)."""
        return self._quadrature(3)


class RateStateSampleRows(_QuasiStaticRows):
    """Samples that :func:`~stickslip.core.ratestate.integrate_qs` writes: rows ``(y..., u)``."""

    _others = 1
    _named = ("u",)

    @property
    def u(self) -> FloatArray:
        """``ln(v/V_r)``: the log of the slip velocity."""
        return self.raw[:, -1]

    @u.setter
    def u(self, value: Any) -> None:
        self.raw[:, -1] = value


class RateStateRecordRows(_QuasiStaticRows):
    """Accepted steps that :func:`~stickslip.core.ratestate.integrate_qs` records: ``(t, u, y...)``."""

    _y = rs.RECC_Y
    _others = 2
    _named = ("time", "u")
    time = _field(rs.RECC_T, "Time (s).")
    u = _field(rs.RECC_U, "``ln(v/V_r)``: the log of the slip velocity.")


class RateStateEventRows(_QuasiStaticRows):
    """Events that :func:`~stickslip.core.ratestate.integrate_qs` locates: ``(kind, t, u, y...)``."""

    _y = rs.EVC_Y
    _others = 3
    _named = ("kind", "time", "u")
    kind = _field(rs.EVC_KIND, "RateStateEvent code.")
    time = _field(rs.EVC_T, "Time (s).")
    u = _field(rs.EVC_U, "``ln(v/V_r)``: the log of the slip velocity.")

    def kinds(self) -> list[RateStateEvent]:
        """Return the kind of every row."""
        return [RateStateEvent.from_code(c) for c in self.kind]

    def of_kind(self, kind: RateStateEvent) -> RateStateEventRows:
        """Return the rows of events of ``kind``."""
        return self[self.kind == kind.code]


class RadauEventRows(_StateRows):
    """Events that :func:`~stickslip.core.radau.integrate_in` locates: ``(kind, t, y...)``."""

    _y = 2
    _others = 2
    _named = ("kind", "time")
    kind = _field(0, "RadauEvent code.")
    time = _field(1, "Time (s).")

    def kinds(self) -> list[RadauEvent]:
        """Return the kind of every row."""
        return [RadauEvent.from_code(c) for c in self.kind]
