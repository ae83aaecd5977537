"""Array-level entry points of the compiled engines (floats and arrays only), in one namespace.

The entry points live with their engine: the one-block engine's in
:mod:`stickslip.core.block_api` (:func:`run_attractors`, :func:`run_trajectory`,
:func:`run_shooting`, :func:`run_return_maps`, :func:`run_flow`), the chain
engine's in :mod:`stickslip.core.chain_api` (:class:`ChainState`,
:func:`chain_advance`), and what both share in :mod:`stickslip.core.kernel`
(:class:`Kernel`, the thread pool of row blocks). This module re-exports them.
"""

from __future__ import annotations

from .block_api import (
    BYTES_PER_ROW,
    MAX_PHASES,
    MAX_TIME,
    FloatArray,
    Trajectories,
    TrajectoryResult,
    run_attractors,
    run_flow,
    run_return_maps,
    run_shooting,
    run_trajectory,
)
from .chain_api import ChainState, chain_advance, check_state
from .kernel import (
    BATCH,
    SERIAL_ROWS,
    Kernel,
    as_kernel,
    builtin_kernel,
    in_blocks,
    pole_is_an_error,
    threads,
)

__all__ = [
    "BATCH",
    "BYTES_PER_ROW",
    "MAX_PHASES",
    "MAX_TIME",
    "SERIAL_ROWS",
    "ChainState",
    "FloatArray",
    "Kernel",
    "Trajectories",
    "TrajectoryResult",
    "as_kernel",
    "builtin_kernel",
    "chain_advance",
    "check_state",
    "in_blocks",
    "pole_is_an_error",
    "run_attractors",
    "run_flow",
    "run_return_maps",
    "run_shooting",
    "run_trajectory",
    "threads",
]
