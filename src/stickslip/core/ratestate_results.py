"""The rate-and-state integrators' results, decoded once: statuses, event kinds and named rows.

``integrate_qs`` of :mod:`~stickslip.core.ratestate` (the quasi-static and quasi-dynamic
slider, DOP853) and ``integrate_in`` of :mod:`~stickslip.core.radau` (the inertial slider,
Radau IIA) are read here, and only here.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from . import radau
from . import ratestate as rs
from .labelled import _Field, _field, _Labelled

__all__ = [
    "RadauEvent",
    "RadauEventRows",
    "RadauStatus",
    "RateStateEvent",
    "RateStateEventRows",
    "RateStateRecordRows",
    "RateStateSampleRows",
    "RateStateStatus",
    "radau_progress",
]

FloatArray = npt.NDArray[np.float64]


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
