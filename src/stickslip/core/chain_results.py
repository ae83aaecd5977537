"""The chain engine's results, decoded once: its statuses, catalogue rows and scalar state.

The chain engine (:mod:`~stickslip.core.chain`) writes catalogue rows (``C_*`` columns)
and a scalar state (``S_*`` entries of ``ChainState.sc``); they are read here, and only
here, as :class:`EventRows` and :class:`ChainScalars`; its statuses are :class:`ChainStatus`.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from . import chain
from .labelled import _field, _Labelled, _Rows

__all__ = ["ChainScalars", "ChainStatus", "EventRows"]

FloatArray = npt.NDArray[np.float64]


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


# ---------------------------------------------------------------- chains
# The chain engine (core.chain): its catalogue rows (C_* columns) and its scalar state
# (S_* entries of ChainState.sc) are read here, and only here; its statuses are ChainStatus.


class EventRows(_Rows):
    """Catalogue rows of the chain engine (:func:`~stickslip.core.chain.chain_run`): one event a row.

    Dimensionless (the catalogue of a physical chain scales them); ``epicentre``,
    ``n_blocks``, ``first_block`` and ``last_block`` are whole numbers held as floats.
    """

    _width = chain.NCAT
    t_start = _field(chain.C_T0, "Start of the event: a block breaks away while all stick.")
    t_end = _field(chain.C_T1, "End of the event: all blocks stick again.")
    epicentre = _field(chain.C_EPI, "The block that broke away first (0-based).")
    n_blocks = _field(chain.C_NB, "Number of blocks that slipped.")
    moment = _field(chain.C_MOMENT, "Sum of the blocks' slips during the event.")
    peak_velocity = _field(chain.C_PEAK, "Largest block speed during the event.")
    driver_work = _field(chain.C_WD, "Work of the driver on the loading springs.")
    friction_work = _field(chain.C_WF, "Energy dissipated by friction.")
    elastic_change = _field(chain.C_DE, "Change of the springs' elastic energy.")
    first_block = _field(chain.C_LO, "Lowest index of a block that slipped.")
    last_block = _field(chain.C_HI, "Highest index of a block that slipped.")


class ChainScalars(_Rows):
    """The scalar state of a chain (``ChainState.sc``, a row of :attr:`SIZE` values; a view: writable).

    ``ChainScalars(state.sc)`` reads and writes the state's own array.
    """

    #: the number of scalars of a chain's state
    SIZE = chain.NSC
    _width = chain.NSC
    t = _field(chain.S_T, "Time of the state.")
    step = _field(chain.S_H, "The step size to try next (0: not yet chosen).")
    in_event = _field(chain.S_IN_EVENT, "1 while an event is in progress, else 0.")
    event_start = _field(chain.S_EV_T0, "Start of the event in progress.")
    epicentre = _field(chain.S_EV_EPI, "The event's first block.")
    peak_velocity = _field(chain.S_EV_PEAK, "Largest block speed of the event so far.")
    driver_work = _field(chain.S_EV_WD, "Work of the driver in the event so far.")
    friction_work = _field(chain.S_EV_WF, "Energy dissipated by friction in the event so far.")
    elastic_energy = _field(chain.S_EV_E0, "Elastic energy at the start of the event.")
    n_steps = _field(chain.S_NSTEP, "Integration steps taken.")
    n_rejected = _field(chain.S_NREJ, "Integration steps rejected.")
    n_blocks = _field(chain.S_EV_N, "Blocks that slipped in the event so far.")
    first_block = _field(chain.S_EV_LO, "Lowest index of a block that slipped in the event so far.")
    last_block = _field(chain.S_EV_HI, "Highest index of a block that slipped in the event so far.")
    stalled = _field(chain.S_STALL, "Events in a row without progress in time (counted over calls).")
    work = _field(chain.S_NWORK, "Work done: WORK_STEP plus the slipping blocks, per step.")

    def event_longer_than(self, duration: float) -> bool:
        """Whether an event is in progress (first row) and has lasted longer than ``duration``.

        The chain engine's mark of a chain that slides for ever (:class:`ChainStatus` ``SLIDING``).
        """
        return bool(self.in_event[0]) and bool(float(self.t[0]) - self.event_start[0] > duration)
