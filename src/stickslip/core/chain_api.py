"""Array-level entry points of the chain engine: its state between calls, and one call's advance.

:class:`ChainState` holds every array of a chain's state (updated in place by the
compiled loop of :mod:`stickslip.core.chain`, or a law's own copy of it);
:func:`chain_advance` runs that loop for a budget of events, steps or work and
returns the events' catalogue rows. The one-block engine's entry points are in
:mod:`stickslip.core.block_api`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from . import chain
from .kernel import Kernel, pole_is_an_error
from .laws import N_LAW_PARAMS

__all__ = ["ChainState", "chain_advance", "check_state", "stuck_forces"]

FloatArray = npt.NDArray[np.float64]


@dataclass
class ChainState:
    """The whole state of a chain between two calls of the chain engine (arrays updated in place).

    Attributes
    ----------
    x, v : array of float
        Positions and velocities of the blocks.
    mode : array of int
        0 stuck, +1 slipping forward, -1 slipping backward.
    sc : array of float
        Time, step size, the event in progress and counters (``chain.S_*``).
    ev_x0, ev_flag, ev_list : arrays
        Work arrays of the event in progress.

    """

    x: FloatArray
    v: FloatArray
    mode: npt.NDArray[np.int64]
    sc: FloatArray
    ev_x0: FloatArray
    ev_flag: npt.NDArray[np.int8]
    ev_list: npt.NDArray[np.int64]

    @classmethod
    def at_rest(cls, x: npt.ArrayLike, t: float = 0.0) -> ChainState:
        """Return the state of blocks at rest at positions ``x`` at time ``t``."""
        xa = np.array(x, dtype=np.float64)
        n = xa.shape[0]
        sc = np.zeros(chain.NSC)
        sc[chain.S_T] = t
        return cls(
            xa, np.zeros(n), np.zeros(n, dtype=np.int64), sc, np.zeros(n), np.zeros(n, dtype=np.int8),
            np.zeros(n, dtype=np.int64),
        )  # fmt: skip

    @property
    def t(self) -> float:
        """Time of the state."""
        return float(self.sc[chain.S_T])

    @property
    def in_event(self) -> bool:
        """Whether an event is in progress."""
        return bool(self.sc[chain.S_IN_EVENT])

    def copy(self) -> ChainState:
        """Return an independent copy."""
        return ChainState(
            self.x.copy(), self.v.copy(), self.mode.copy(), self.sc.copy(), self.ev_x0.copy(),
            self.ev_flag.copy(), self.ev_list.copy(),
        )  # fmt: skip


def check_state(state: ChainState) -> None:
    """Refuse a chain state with a position or velocity that is not finite, naming the block.

    (A NaN breakaway time would walk the engine's tree of breakaway times off its leaves:
    a compiled loop that does not end and that Ctrl-C cannot stop.)
    """
    for name, values in (("position", state.x), ("velocity", state.v)):
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            j = int(bad[0])
            raise ValueError(
                f"state: block {j + 1}'s {name} is {float(values[j])!r}; expected finite positions "
                "and velocities"
            )


def stuck_forces(state: ChainState, nu: float, ell2: float, periodic: bool) -> FloatArray:
    """Return the elastic force on each block of ``state`` at its time, every position taken as it is."""
    x = state.x
    return np.array([chain.stuck_force(x, j, state.t, nu, ell2, periodic) for j in range(x.shape[0])])


def chain_advance(
    kernel: Kernel,
    lp: npt.ArrayLike,
    nu: float,
    ell2: float,
    periodic: bool,
    backward: bool,
    phi: npt.ArrayLike,
    state: ChainState,
    *,
    max_events: int,
    t_max: float = np.inf,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_steps: int = 2_000_000,
    max_work: float = np.inf,
    max_event_duration: float = np.inf,
    slip_rows: int = 0,
) -> tuple[FloatArray, FloatArray, int]:
    """Advance a chain (``state``, updated in place) by up to ``max_events`` complete events.

    Returns ``(catalogue rows (events x chain.NCAT), slips (first slip_rows events x N), status)``
    with a ``chain.CH_*`` status; ``CH_PAUSED`` means the budget of this call ran out
    (``max_steps`` steps, or ``max_work`` units of work: ``chain.WORK_STEP`` plus the
    slipping blocks per step): call again to go on (the state is exact, not an
    approximation; where a call pauses changes the events' works in their last bits only).
    It also pauses at the step where the event in progress passes ``max_event_duration``
    (time units): the caller's sign that the chain slides for ever, to be told at once
    (a call of ``max_work`` units could run on for tens of thousands of time units).
    """
    n = state.x.shape[0]
    check_state(state)
    if state.sc.shape != (chain.NSC,):
        raise ValueError(
            f"state: {state.sc.shape[0]} scalars, expected {chain.NSC} (a state of another version of "
            "stickslip's chain engine)"
        )
    lpa = np.zeros(N_LAW_PARAMS)
    lp_in = np.asarray(lp, dtype=np.float64).ravel()
    lpa[: lp_in.size] = lp_in
    phia = np.ascontiguousarray(phi, dtype=np.float64)
    cat = np.zeros((max(int(max_events), 0), kernel.chain_engine.NCAT))
    slips = np.zeros((min(int(slip_rows), max(int(max_events), 0)), n))
    with pole_is_an_error():
        written, status = kernel.chain_engine.chain_run(
            kernel.law_id, lpa, float(nu), float(ell2), bool(periodic), bool(backward), phia,
            state.x, state.v, state.mode, state.sc, state.ev_x0, state.ev_flag, state.ev_list,
            int(max_events), float(t_max), float(rtol), float(atol), int(max_steps), float(max_work),
            float(max_event_duration), cat, slips,
        )  # fmt: skip
    return cat[:written], slips[: min(written, slips.shape[0])], int(status)
