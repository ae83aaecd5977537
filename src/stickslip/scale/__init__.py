"""Scale-out: long jobs cut into blocks, run in process or on Dask, streamed to a resumable store.

The default of every job stays in process (numba's threads, no cluster, no Dask
imported). ``store=`` streams the result to a Zarr store block by block and makes
the job resumable; ``scheduler=``/``workers=`` run the blocks on a Dask
distributed cluster. See ``docs/scale.md``.

Modules: :mod:`.backend` (running the blocks), :mod:`.progress`, :mod:`.store`
(the store on disk), :mod:`.layout` (a job's grid, blocks and identity),
:mod:`.repair` (a reopened store's metadata made whole), :mod:`.errors`.
"""

from __future__ import annotations

from .backend import RunReport, local_threads, run_blocks, run_job
from .errors import StoreError
from .layout import Block, Layout, Variable, chunk_shape
from .progress import Progress, ProgressInfo, ProgressLike
from .store import ChunkStore, computed_points, damaged_coordinates, is_store, store_kind

__all__ = [
    "Block",
    "ChunkStore",
    "Layout",
    "Progress",
    "ProgressInfo",
    "ProgressLike",
    "RunReport",
    "StoreError",
    "Variable",
    "chunk_shape",
    "computed_points",
    "damaged_coordinates",
    "is_store",
    "local_threads",
    "run_blocks",
    "run_job",
    "store_kind",
]

#: points per block of a sweep by default: a task of a fraction of a second on one core,
#: long enough that Dask's per-task cost (about a millisecond) and the block's write stay
#: under a few per cent (benchmarks/bench_scale.py)
SWEEP_BLOCK_POINTS = 32_768
