"""What the compiled kernels return, decoded once: named fields, and statuses as enums.

The kernels write their results into rows of floats (layouts ``O_*`` of
:mod:`~stickslip.core.engine` and ``SH_*`` of :mod:`~stickslip.core.variational`);
this module is the one place that reads those layouts, and with
:mod:`.chain_results` (the chain engine's ``C_*`` rows and ``S_*`` state) and
:mod:`.ratestate_results` (the rate-and-state integrators' rows and codes) it is
the one face of every engine's results: everything above the core imports them
from here. :class:`AttractorRows` and :class:`ShootingRows` have a field per
quantity, views of the rows, so that writing a field writes the row.

The enums are string enums (:mod:`.labelled`): a member equals its label
(``Status.OK == "ok"``), so results, JSON and NetCDF carry the labels, while each
member also carries its integer code (the kernels' and the NetCDF flag values) and
its message for users, in the manner of diffrax's ``RESULTS``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from . import engine
from . import variational as va
from .chain_results import ChainScalars, ChainStatus, EventRows
from .labelled import _field, _Labelled, _Rows
from .ratestate_results import (
    RadauEvent,
    RadauEventRows,
    RadauStatus,
    RateStateEvent,
    RateStateEventRows,
    RateStateRecordRows,
    RateStateSampleRows,
    RateStateStatus,
    radau_progress,
)

__all__ = [
    "AttractorRows",
    "ChainScalars",
    "ChainStatus",
    "EventKind",
    "EventRows",
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
