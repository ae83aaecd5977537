"""The attractor kernel on a CUDA GPU (numbers only).

No second engine: the CUDA kernel calls the CPU engine's own per-row function,
:func:`stickslip.core.engine.attractor_ws` of the law's compiled package, which
numba-cuda compiles again as a device function from the same Python source
(with the law's functions, the DOP853 step, its dense output and the event
location under it). One GPU thread integrates one parameter set, with its own
work arrays (the per-row workspace of the CPU engine, one slice per thread);
the kernel allocates nothing.

Threads of a warp run in lockstep and wait for the slowest, and the cost of a
cycle grows with the steepness of the law: the rows can be sorted by their law
parameters and ``nu`` before they go to the GPU (:data:`SORT_ROWS`; off, since on
an H100 it cost the host more than it saved the GPU), the results put back in the
caller's order. The rows go in launches on :data:`STREAMS` CUDA streams in turn,
their inputs and results copied through pinned host buffers, so that the copies
and the host's work overlap the kernels.

numba-cuda is optional (``pip install "stickslip[cuda]"``) and imported only
here, when a CUDA backend is asked for. With ``NUMBA_ENABLE_CUDASIM=1`` and
``NUMBA_DISABLE_JIT=1`` the same kernel runs in numba's CUDA simulator (the engine
as Python, thread after thread: small batches only), which is how the test suite
checks it without a GPU; ``tools/cuda_ptx.py`` compiles it for a GPU without one.
"""

from __future__ import annotations

import contextlib
import importlib.util
import itertools
import math
import os
import sys
import threading
import time
import warnings
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

from ..errors import ArgumentTypeError
from . import engine

#: the backends of the attractor kernel
BACKENDS = ("cpu", "cuda", "auto")
#: threads per block of the kernel
THREADS_PER_BLOCK = 128
#: rows per launch in the simulator (it runs every thread in Python)
SIMULATOR_BATCH = 256
#: sort each launch's rows for the load balance (:func:`balance_order`): a 16-bit key's radix
#: sort on the host, through which the kernel reads its rows and writes their results. Off: on
#: an H200 it made random F1 rows' kernels 2.1 times as fast (1.26e8 cycles/s) but cost the
#: host more (0.28 s for 10^7 rows), end to end 1.01 s against 0.75 s; a grid's rows come in
#: order already (1.37e8 cycles/s unsorted). docs/gpu.md
SORT_ROWS = False
#: seconds of the last GPU run: ordering the rows (each launch's key and its sort), the GPU's
#: work with the copies, the kernels alone (CUDA events; 0 in the simulator), in all
TIMES: dict[str, float] = {}
#: options of the kernel's ``cuda.jit`` on a GPU (``max_registers``, ``shared_memory_carveout``)
JIT_OPTIONS: dict[str, Any] = {}
#: the threads take rows from a queue (an atomic counter) until none is left, launched as many
#: as stay resident, instead of one row a thread: a variant to measure (``bench_gpu.py``), off
PERSISTENT = False
#: blocks a multiprocessor keeps resident with the persistent kernel (2 of 128 threads at its
#: 201 registers a thread on an H100; more under a register cap)
PERSISTENT_BLOCKS_PER_SM = 2
#: rows per launch at most on a GPU (a launch also sizes itself to the free memory): 2^20 rows
#: are some 30 waves of an H100's resident threads, and 170 MB of results a launch
MAX_BATCH = 1 << 20
#: launches in flight at once, each on its own CUDA stream with its own buffers: while the GPU
#: runs one, the host copies the results of the one before out of its pinned buffer
STREAMS = 2
#: rows of a launch's results from which the host copies them out of pinned memory in
#: several threads (:func:`copy_rows`; numpy's copies let go of the GIL)
COPY_THREADS_ROWS = 1 << 16
#: threads of that copy at most
COPY_THREADS = 8


class CudaUnavailableError(RuntimeError):
    """A CUDA backend was asked for where none can run (no numba-cuda, no device or driver)."""


def simulator() -> bool:
    """Return whether numba's CUDA simulator is switched on (``NUMBA_ENABLE_CUDASIM=1``)."""
    return os.environ.get("NUMBA_ENABLE_CUDASIM", "0") not in ("", "0")


def cuda_status() -> tuple[bool, str]:
    """Return ``(usable, description)``: the device's name, or in one line why there is none."""
    if importlib.util.find_spec("numba_cuda") is None:  # numba's old built-in target does not count
        return False, 'numba-cuda is not installed: install it with pip install "stickslip[cuda]"'
    try:
        from numba import cuda
    except Exception as exc:  # an import that fails for any reason: not usable, said in one line
        return False, (
            f"numba-cuda is not installed or does not import ({type(exc).__name__}: {exc}); "
            'install it with: pip install "stickslip[cuda]"'
        )
    if simulator():
        if os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0"):
            # the simulator hands its own arrays to the engine, which compiled code cannot take
            return False, (
                "numba's CUDA simulator runs the kernel as Python: set NUMBA_DISABLE_JIT=1 "
                "with NUMBA_ENABLE_CUDASIM=1"
            )
        return True, "numba's CUDA simulator (NUMBA_ENABLE_CUDASIM=1, NUMBA_DISABLE_JIT=1)"
    try:
        if not cuda.is_available():
            return False, "no CUDA device or driver found (numba.cuda.is_available() is False)"
        dev = cuda.get_current_device()
        name = dev.name.decode() if isinstance(dev.name, bytes) else str(dev.name)
        cc = ".".join(str(v) for v in dev.compute_capability)
        from numba.cuda.cudadrv import nvvm

        if not nvvm.is_available():
            return False, (
                f"a GPU ({name}) but not the CUDA toolkit's compiler (NVVM): "
                'pip install "stickslip[cuda]" brings it'
            )
    except Exception as exc:
        return False, f"no CUDA device usable ({type(exc).__name__}: {_first_line(exc)})"
    return True, f"{name} (compute capability {cc})"


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def resolve_backend(backend: str) -> str:
    """Return ``"cpu"`` or ``"cuda"`` for ``backend`` (``"auto"``: the GPU where one is usable).

    Raises
    ------
    ArgumentTypeError
        For a backend that is not a str.
    ValueError
        For a backend that is not one of :data:`BACKENDS`.
    CudaUnavailableError
        For ``"cuda"`` where no CUDA device can run the kernel (said in one line).

    """
    if not isinstance(backend, str):
        raise ArgumentTypeError(f"backend={backend!r}: expected one of {', '.join(map(repr, BACKENDS))}")
    if backend not in BACKENDS:
        raise ValueError(f"backend={backend!r}: expected one of {', '.join(map(repr, BACKENDS))}")
    if backend == "cpu":
        return "cpu"
    ok, why = cuda_status()
    if backend == "auto":
        return "cuda" if ok else "cpu"
    if not ok:
        raise CudaUnavailableError(f"backend='cuda': {why}")
    return "cuda"


_KERNELS: dict[tuple[int, int, str, bool], Any] = {}


def _load_registries_without_row_stack() -> None:
    """Load numba-cuda's typing registries where NumPy has no ``row_stack`` (NumPy 2.5 and later).

    numba-cuda 0.30 (the newest release, 2026-11) registers an overload for
    ``np.row_stack`` while it loads its typing registries, at the first kernel's
    compilation, and NumPy 2.5 removed that alias of ``np.vstack``: every kernel
    then fails to compile (AttributeError). The registries are loaded once here
    with the alias put back for that moment, and removed again.
    """
    if hasattr(np, "row_stack") or simulator():
        return
    from numba.cuda.descriptor import cuda_target

    alias = "row_stack"
    setattr(np, alias, np.vstack)
    try:
        cuda_target.typing_context.refresh()
    finally:
        delattr(np, alias)


def attractor_kernel(one: Any, width: int = 2, persistent: bool | None = None) -> Any:
    """Return the CUDA kernel running the per-row function ``one`` (a law's ``engine.attractor_ws``).

    ``width`` is the state's size: 2, or 4 with the variational equations;
    ``persistent`` (default :data:`PERSISTENT`): the threads take rows from a queue.
    """
    persistent = PERSISTENT if persistent is None else persistent
    options = {} if simulator() else dict(JIT_OPTIONS)
    key = (id(one), width, repr(sorted(options.items())), persistent)
    if key not in _KERNELS:
        from . import _cuda_kernel

        _load_registries_without_row_stack()
        kern = _cuda_kernel.make(one, width, options, persistent=persistent)
        _KERNELS[key] = (one, kern)  # the function kept alive with it: ids stay unique
    return _KERNELS[key][1]


def balance_bins(lp: np.ndarray, nu: np.ndarray) -> tuple[tuple[int, bool, float, float], ...] | None:
    """Return how :func:`balance_key` bins the rows: for each column that varies, its range.

    The columns are the law parameters that vary and ``nu`` (index -1), in that order
    of precedence, each binned in equal steps of its logarithm where it is positive and
    spans more than a decade (else of itself): ``(column, log, lo, hi)``. None where
    :data:`SORT_ROWS` is off or nothing varies. Taken over all the rows once, so that
    every launch's rows are binned alike.
    """
    if not SORT_ROWS or nu.size == 0:
        return None
    bins = []
    for j in [*range(lp.shape[1]), -1]:
        x = nu if j < 0 else lp[:, j]
        lo, hi = float(x.min()), float(x.max())
        if lo == hi:
            continue
        log = lo > 0 and hi > 10 * lo
        bins.append((j, log, math.log(lo), math.log(hi)) if log else (j, log, lo, hi))
    return tuple(bins) or None


def balance_key(
    bins: tuple[tuple[int, bool, float, float], ...], lp: np.ndarray, nu: np.ndarray
) -> np.ndarray:
    """Return the rows' 16-bit sort keys: the columns of ``bins`` (:func:`balance_bins`), each in its bits.

    A warp's 32 threads wait for the slowest; the number of steps of a cycle
    follows the law's parameters (the width of its boundary layers) and ``nu``,
    so rows of neighbouring keys take similar times.
    """
    bits = max(1, 16 // len(bins))
    key = np.zeros(nu.size, dtype=np.uint16)
    for j, log, lo, hi in bins[: 16 // bits]:
        x = nu if j < 0 else lp[:, j]
        if log:
            x = np.log(x)
        step = ((x - lo) * (((1 << bits) - 1) / (hi - lo))).astype(np.uint16)
        key = (key << np.uint16(bits)) | step
    return key


def balance_order(
    lp: np.ndarray, nu: np.ndarray, bins: tuple[tuple[int, bool, float, float], ...] | None = None
) -> np.ndarray | None:
    """Return the order of the rows for the GPU (None: the caller's): by law parameters, then ``nu``.

    A stable radix sort of :func:`balance_key` (a few nanoseconds a row; sorting the
    values themselves took 0.5 s a million rows), on ``bins`` (default: these rows'
    own, :func:`balance_bins`). The GPU path sorts each launch's rows so, on the bins
    of all the rows, and the kernel reads the rows and writes their results through
    that order: the rows and the results stay in the caller's order on the host. None
    where :data:`SORT_ROWS` is off or nothing varies.
    """
    bins = balance_bins(lp, nu) if bins is None else bins
    return None if bins is None else np.argsort(balance_key(bins, lp, nu), kind="stable")


#: sort each launch's rows on the GPU (:func:`sort_on_device`: the keys, then a counting
#: sort) rather than on the host (:func:`balance_order`) where :data:`SORT_ROWS` is on: the
#: same order, without the host's sort (0.28 s for 10^7 rows on the H200) and the order's copy
DEVICE_SORT = True


def _sort_arguments(bins: tuple[tuple[int, bool, float, float], ...]) -> tuple[np.ndarray, ...]:
    """Return the key kernel's per-column arrays and bits: what :func:`balance_key` computes with."""
    bits = max(1, 16 // len(bins))
    use = bins[: 16 // bits]
    cols = np.array([j for j, _, _, _ in use], dtype=np.int64)
    logs = np.array([1 if log else 0 for _, log, _, _ in use], dtype=np.int64)
    los = np.array([lo for _, _, lo, _ in use], dtype=np.float64)
    # the host's ``(x - lo) * (((1 << bits) - 1) / (hi - lo))``: the same factor, the same product
    scales = np.array([((1 << bits) - 1) / (hi - lo) for _, _, lo, hi in use], dtype=np.float64)
    return cols, logs, los, scales, np.array(bits)


def sort_on_device(
    bins: tuple[tuple[int, bool, float, float], ...], d_lp: Any, d_nu: Any, d_order: Any, stream: Any = 0
) -> None:
    """Write into ``d_order`` (on the GPU) the rows of ``d_lp``, ``d_nu`` in :func:`balance_order`'s order.

    The keys are computed on the GPU from the rows (as :func:`balance_key`), then sorted
    by two stable counting passes of 8 bits (histogram per segment of rows, scan, scatter:
    ``_cuda_kernel.sort_kernels``), all on ``stream``: no row and no order crosses to the
    host.
    """
    from numba import cuda

    from . import _cuda_kernel

    keys_k, hist_k, offsets_k, scatter_k = _cuda_kernel.sort_kernels()
    cols, logs, los, scales, bits = _sort_arguments(bins)
    n = d_nu.shape[0]
    segments = -(-n // _cuda_kernel.SORT_SEGMENT)
    d_key = cuda.device_array(n, dtype=np.int64, stream=stream)
    d_tmp = cuda.device_array(n, dtype=np.int64, stream=stream)
    d_hist = cuda.device_array((_cuda_kernel.RADIX, segments), dtype=np.int64, stream=stream)
    d_tot = cuda.device_array(_cuda_kernel.RADIX, dtype=np.int64, stream=stream)
    d_none = cuda.device_array(0, dtype=np.int64, stream=stream)
    d_cols, d_logs, d_los, d_scales = (cuda.to_device(a, stream=stream) for a in (cols, logs, los, scales))
    rows_blocks = -(-n // THREADS_PER_BLOCK)
    seg_blocks = -(-segments // THREADS_PER_BLOCK)
    keys_k[rows_blocks, THREADS_PER_BLOCK, stream](
        d_lp, d_nu, d_cols, d_logs, d_los, d_scales, int(bits), d_key
    )
    for shift, d_in, d_out in ((0, d_none, d_tmp), (8, d_tmp, d_order)):
        hist_k[seg_blocks, THREADS_PER_BLOCK, stream](d_key, d_in, shift, d_hist)
        offsets_k[1, _cuda_kernel.RADIX, stream](d_hist, d_tot)
        scatter_k[seg_blocks, THREADS_PER_BLOCK, stream](d_key, d_in, shift, d_hist, d_out)


def device_balance_order(
    lp: np.ndarray, nu: np.ndarray, bins: tuple[tuple[int, bool, float, float], ...] | None = None
) -> np.ndarray | None:
    """Return :func:`sort_on_device`'s order of the rows, copied to the host (None where nothing is sorted).

    What the GPU path computes for each launch, for a comparison with :func:`balance_order`.
    """
    from numba import cuda
    from numba.core.errors import NumbaPerformanceWarning

    bins = balance_bins(lp, nu) if bins is None else bins
    if bins is None:
        return None
    d_order = cuda.device_array(nu.shape[0], dtype=np.int64)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NumbaPerformanceWarning)
        sort_on_device(
            bins, cuda.to_device(np.ascontiguousarray(lp)), cuda.to_device(np.ascontiguousarray(nu)), d_order
        )
    return np.asarray(d_order.copy_to_host())


_COPY_POOL: list[ThreadPoolExecutor] = []
_COPY_LOCK = threading.Lock()


def _assign(dst: np.ndarray, src: np.ndarray) -> None:
    dst[...] = src


def copy_rows(dst: np.ndarray, src: np.ndarray) -> None:
    """Copy the rows ``src`` into ``dst``, in several threads from :data:`COPY_THREADS_ROWS` rows.

    The host's share of a GPU call end to end is mostly this copy of each launch's
    results out of pinned memory into the caller's array, whose fresh pages are touched
    for the first time (on an H200's host, 0.60 s of 0.75 s for 10^7 rows of 21
    numbers). Its threads take a slice of the rows each; one thread below the threshold
    or on one core.
    """
    n = dst.shape[0]
    threads = min(COPY_THREADS, os.cpu_count() or 1)
    if n < COPY_THREADS_ROWS or threads < 2:
        dst[...] = src
        return
    with _COPY_LOCK:
        if not _COPY_POOL:
            _COPY_POOL.append(ThreadPoolExecutor(threads, thread_name_prefix="stickslip-copy"))
    edges = np.linspace(0, n, threads + 1).astype(np.int64)
    parts = [_COPY_POOL[0].submit(_assign, dst[a:b], src[a:b]) for a, b in itertools.pairwise(edges) if b > a]
    for part in parts:
        part.result()


def _batch_rows(n: int, per_row: int) -> int:
    """Rows per launch: what a quarter of the free device memory holds over the streams (bounded).

    ``per_row`` is the bytes of one row on the device (its inputs and its result).
    """
    if simulator():
        return SIMULATOR_BATCH
    from numba import cuda

    free, _total = cuda.current_context().get_memory_info()
    return int(max(THREADS_PER_BLOCK, min(MAX_BATCH, free // 4 // (STREAMS * per_row), n)))


#: rows of a measured table a GPU kernel holds: the table goes to the GPU's constant
#: memory (64 KB a module), 40 bytes a row in one array (``tools/cuda_ptx.py``: 1600 rows
#: link for sm_90, 1700 do not; 700 when each function held its own copies, 88 bytes a row)
MAX_TABLE_ROWS = 1600
#: the same for the forced oscillator's kernel, which reads the table in more places
#: (``tools/cuda_ptx.py``: 1500 rows link for sm_90, 1600 do not)
FORCED_MAX_TABLE_ROWS = 1500


def check_kernel(one: Any, max_rows: int = MAX_TABLE_ROWS) -> None:
    """Refuse, in one line, a law whose engine cannot build for a GPU (a table too long).

    Raises
    ------
    ValueError
        For a tabulated law of more than ``max_rows`` rows (:data:`MAX_TABLE_ROWS` for the
        attractor kernel, :data:`FORCED_MAX_TABLE_ROWS` for the forced oscillator's).

    """
    package = sys.modules.get(getattr(one, "__module__", "").rsplit(".", 1)[0] + ".laws")
    table = getattr(package, "_TABLE", None)  # five numbers a piece, the table's rows its pieces' ends
    rows = 0 if table is None else table.size // 5 + 1
    if rows > max_rows:
        raise ValueError(
            f"a table of {rows} rows: the GPU kernel holds at most {max_rows} "
            "(its constant memory); thin the table, or use backend='cpu'"
        )


class _Slot:
    """One stream's buffers: the rows' inputs and results on the device, and their pinned host copies.

    Page-locked (pinned) host memory is what the GPU's copy engines read and write
    while the host and the GPU go on with other work; a copy from or to ordinary
    (pageable) memory goes through a staging buffer of the driver and holds the host
    (on the H100, 1.7 GB of results came back at 2.9 GB/s so). The buffers are kept
    for the process's next call that fits them (a sweep's blocks), in the CUDA context
    they were made in, until :func:`release_buffers`.
    """

    def __init__(self, rows: int, k: int, own_start: bool, columns: tuple[int, ...]) -> None:
        from numba import cuda

        self.context = _context()
        self.rows, self.k, self.own_start, self.columns = rows, k, own_start, columns
        self.stream = cuda.stream()
        m = rows if own_start else 1
        self.d_lp = cuda.device_array((rows, k))
        self.d_nu = cuda.device_array(rows)
        self.d_s0 = cuda.device_array(m)
        self.d_w0 = cuda.device_array(m)
        self.d_out = cuda.device_array((rows, engine.NOUT))
        # the columns the caller keeps, gathered on the GPU: only they cross back
        self.gathered = columns != tuple(range(engine.NOUT))
        self.d_cols = cuda.to_device(np.array(columns, dtype=np.int64)) if self.gathered else None
        self.d_kept = cuda.device_array((rows, len(columns))) if self.gathered else self.d_out
        self.h_lp = cuda.pinned_array((rows, k))
        self.h_nu = cuda.pinned_array(rows)
        self.h_s0 = cuda.pinned_array(m)
        self.h_w0 = cuda.pinned_array(m)
        self.h_out = cuda.pinned_array((rows, len(columns)))
        self.d_order = cuda.device_array(rows, dtype=np.int64)  # a launch's rows in their keys' order
        self.h_order = cuda.pinned_array(rows, dtype=np.int64)
        self.d_next = cuda.device_array(1, dtype=np.int64)  # the persistent kernel's queue
        self.h_zero = cuda.pinned_array(1, dtype=np.int64)
        self.h_zero[0] = 0
        self.pending: tuple[int, int] | None = None  # the rows whose results this slot's stream brings back
        self.events: tuple[Any, Any] | None = None  # the kernel's start and end (CUDA events)


#: the slots of the last call, reused by a later call that fits them
_SLOTS: list[_Slot] = []
#: held by a call while it uses the slots (threads of a Dask worker share the process's GPU)
_LOCK = threading.Lock()


def release_buffers() -> None:
    """Free the GPU backend's buffers: on the GPU and in pinned host memory (some 400 MB each).

    A call with ``backend="cuda"`` keeps them for the next (a sweep's blocks reuse them);
    a sweep frees them when it ends, in its own process and on the workers of the
    cluster it ran on (:func:`release_idle_buffers`). Safe to call at any time, without
    a GPU too.
    """
    with _LOCK:
        _drop_slots()


def release_idle_buffers() -> bool:
    """Free the buffers as :func:`release_buffers` does, unless a call is using them now.

    What a Dask worker runs once a sweep is done (its event loop must not wait for a
    GPU call of another job). Returns whether they were freed (or there were none).
    """
    if not _LOCK.acquire(blocking=False):
        return False
    try:
        _drop_slots()
    finally:
        _LOCK.release()
    return True


def _drop_slots() -> None:
    """Let the slots go (each stream waited for first, where the GPU still answers), and free them now.

    numba-cuda frees device and pinned memory lazily, once ten frees are pending: the
    pending ones are carried out here, so that the memory is back when this returns.
    """
    global _SLOTS
    if not _SLOTS:
        return
    ctx = _SLOTS[0].context  # the slots are made together, in one context
    pushed = False
    if ctx is not None:  # current in this thread (a Dask worker's event loop has none of its own)
        try:
            ctx.push()
            pushed = True
        except Exception:  # a context that failed or was reset: its memory went with it
            pass
    try:
        for x in _SLOTS:
            try:
                x.stream.synchronize()
            except Exception:  # a context that failed or was reset: its memory went with it
                pass
        _SLOTS = []
        if ctx is not None:
            try:
                ctx.deallocations.clear()
            except Exception:  # a context that failed or was reset
                pass
    finally:
        if pushed:
            with contextlib.suppress(Exception):
                ctx.pop()


def _multiprocessors() -> int:
    """Return the GPU's multiprocessors (1 in the simulator, which has none)."""
    from numba import cuda

    return int(getattr(cuda.get_current_device(), "MULTIPROCESSOR_COUNT", 1))


def _context() -> Any:
    """Return the current CUDA context (None in the simulator, which has none to reset)."""
    if simulator():
        return None
    from numba import cuda

    return cuda.current_context()


def _slots(rows: int, k: int, own_start: bool, columns: tuple[int, ...]) -> list[_Slot]:
    """Return :data:`STREAMS` slots for launches of at most ``rows`` rows (the last call's, if they fit)."""
    global _SLOTS
    current = _context()
    if not (
        len(_SLOTS) == STREAMS
        and all(
            x.rows >= rows and x.k == k and x.own_start == own_start and x.columns == columns for x in _SLOTS
        )
        # a context reset since (numba.cuda.close(), a device reset) freed their memory
        and all(x.context is current for x in _SLOTS)
    ):
        _drop_slots()  # the old buffers go before the new ones are made
        _SLOTS = [_Slot(rows, k, own_start, columns) for _ in range(STREAMS)]
    for x in _SLOTS:  # a call stopped half-way (Ctrl-C in a progress bar) left launches behind
        x.stream.synchronize()
        x.pending = None
    return _SLOTS


def _busy(intervals: list[tuple[float, float]]) -> float:
    """Return the length of the union of ``intervals`` (the kernels of several streams overlap)."""
    total, end = 0.0, -math.inf
    for a, b in sorted(intervals):
        if b > end:
            total += b - max(a, end)
            end = b
    return total


def run_attractors_cuda(
    one: Any,
    law_a: np.ndarray,
    lp_a: np.ndarray,
    nu_a: np.ndarray,
    s0_a: np.ndarray,
    w0_a: np.ndarray,
    from_breakaway: bool,
    rtol: float,
    atol: float,
    t_max: float,
    conv_tol: float,
    diag: bool,
    max_steps: int,
    out: np.ndarray,
    on_rows: Callable[[int], None] | None = None,
    columns: np.ndarray | None = None,
) -> None:
    """Fill ``out`` as the CPU engine's ``attractor_ws`` row by row, on the GPU.

    ``out`` has a row for each parameter set and a column for each of the engine's
    columns ``columns`` (default: all ``engine.NOUT``, in order): the rest stay on the
    GPU, and what crosses back is only these (docs/gpu.md).

    The arguments are those of the CPU kernels, already validated (see
    :func:`stickslip.core.api.run_attractors`); one law for all rows, its
    parameters ``lp_a`` of shape ``(n, k)``, ``1 <= k <= N_LAW_PARAMS`` of
    :mod:`stickslip.core.laws` (the kernel takes the missing ones as zeros), and no
    start where the rows start at breakaway. The rows and results keep the
    caller's order on the host; with :data:`SORT_ROWS` each launch's kernel runs its
    rows in the order of their keys (:func:`balance_order`), read and written in place.
    The bytes that cross to the GPU and back bound the speed
    (docs/gpu.md): the rows go in launches of at most :data:`MAX_BATCH`, on
    :data:`STREAMS` CUDA streams in turn, each launch's inputs and results
    copied through pinned host buffers while the other streams' launches run;
    the host copies a launch's results into ``out`` (and calls ``on_rows``) once
    its stream has finished it.
    """
    from numba import cuda
    from numba.core.errors import NumbaPerformanceWarning

    from . import _cuda_kernel

    check_kernel(one)
    cols = tuple(range(engine.NOUT)) if columns is None else tuple(int(j) for j in columns)
    if out.shape[1:] != (len(cols),) or not cols or not all(0 <= j < engine.NOUT for j in cols):
        raise ValueError(f"out of shape {out.shape} for the engine's columns {cols}")
    n = nu_a.shape[0]
    if n == 0:
        return
    law = np.int64(law_a[0])
    if not np.all(law_a == law):
        raise ValueError("the GPU kernel runs one law for all rows; law_a has several")
    if from_breakaway:  # the start is ignored
        s0_a, w0_a = np.zeros(1), np.zeros(1)
    width = 4 if diag else 2
    persistent = PERSISTENT
    kern = attractor_kernel(one, width, persistent)
    t0 = time.perf_counter()
    bins = balance_bins(lp_a, nu_a)  # each launch's rows sorted by their keys on these bins
    one_start = s0_a.shape[0] == 1
    t_order = time.perf_counter() - t0
    k = lp_a.shape[1]
    timed = not simulator()
    with _LOCK:  # one call at a time in a process: they share the GPU, the slots and TIMES
        t_locked = time.perf_counter()
        TIMES.update(order=t_order, kernel=0.0, copy_out=0.0, span=0.0, lock_wait=t_locked - t0 - t_order)
        first: Any = None  # the first launch's start: the launches' times are taken from it
        busy: list[tuple[float, float]] = []  # each launch's kernel, from its start to its end
        in_callback = False
        try:
            per_row = 8 * (k + 1 + (0 if one_start else 2) + engine.NOUT + len(cols) + 1)
            batch = _batch_rows(n, per_row)
            slots = _slots(min(batch, n), k, not one_start, cols)
            gather = _cuda_kernel.gather()
            resident = _multiprocessors() * PERSISTENT_BLOCKS_PER_SM
            shared = tuple(
                cuda.to_device(a)
                for a in (np.empty(0), np.empty((0, 2)), np.empty(0, dtype=np.int64), np.empty((0, 3)))
            )
            unsorted = cuda.to_device(np.empty(0, dtype=np.int64))  # the rows in the launch's order
            if one_start:  # one start for every row: copied once to each slot, on its stream
                for x in slots:
                    x.h_s0[:] = s0_a[:1]
                    x.h_w0[:] = w0_a[:1]
                    x.d_s0.copy_to_device(x.h_s0, stream=x.stream)
                    x.d_w0.copy_to_device(x.h_w0, stream=x.stream)

            def finish(x: _Slot) -> None:
                """Wait for the slot's launch and copy its results into ``out``."""
                nonlocal in_callback
                x.stream.synchronize()
                if x.pending is None:
                    return
                lo, hi = x.pending
                x.pending = None
                if x.events is not None:
                    # from the first launch's start: a launch's own start event fires when its
                    # stream reaches it, while another stream's kernel may still fill the GPU
                    ev0, ev1 = x.events
                    busy.append(
                        (cuda.event_elapsed_time(first, ev0) / 1e3, cuda.event_elapsed_time(first, ev1) / 1e3)
                    )
                tc = time.perf_counter()
                copy_rows(out[lo:hi], x.h_out[: hi - lo])
                TIMES["copy_out"] += time.perf_counter() - tc
                if on_rows is not None:
                    in_callback = True  # the caller's own exception (Ctrl-C in its bar) is its own
                    on_rows(hi - lo)
                    in_callback = False

            for j, lo in enumerate(range(0, n, batch)):
                x = slots[j % STREAMS]
                finish(x)  # the launch before on this stream: its buffers are free again
                hi = min(n, lo + batch)
                b = hi - lo
                st = x.stream
                x.h_lp[:b] = lp_a[lo:hi]
                x.h_nu[:b] = nu_a[lo:hi]
                x.d_lp[:b].copy_to_device(x.h_lp[:b], stream=st)
                x.d_nu[:b].copy_to_device(x.h_nu[:b], stream=st)
                d_order = unsorted
                if bins is not None:  # the launch's rows in the order of their keys, on the GPU
                    ts = time.perf_counter()
                    d_order = x.d_order[:b]
                    if DEVICE_SORT:  # keys and sort on the GPU, on this launch's stream
                        sort_on_device(bins, x.d_lp[:b], x.d_nu[:b], d_order, st)
                    else:
                        x.h_order[:b] = balance_order(lp_a[lo:hi], nu_a[lo:hi], bins)
                        d_order.copy_to_device(x.h_order[:b], stream=st)
                    TIMES["order"] += time.perf_counter() - ts
                if not one_start:
                    x.h_s0[:b] = s0_a[lo:hi]
                    x.h_w0[:b] = w0_a[lo:hi]
                    x.d_s0[:b].copy_to_device(x.h_s0[:b], stream=st)
                    x.d_w0[:b].copy_to_device(x.h_w0[:b], stream=st)
                d_s0, d_w0 = (x.d_s0, x.d_w0) if one_start else (x.d_s0[:b], x.d_w0[:b])
                d_out = x.d_out[:b]
                blocks = -(-b // THREADS_PER_BLOCK)
                if persistent:  # as many threads as stay resident, taking rows from the queue
                    x.d_next.copy_to_device(x.h_zero, stream=st)
                    blocks = min(blocks, resident)
                args = (
                    law, x.d_lp[:b], x.d_nu[:b], d_s0, d_w0, bool(from_breakaway), float(rtol), float(atol),
                    float(t_max), float(conv_tol), int(max_steps), d_out, *shared, d_order, x.d_next,
                )  # fmt: skip
                x.events = (cuda.event(), cuda.event()) if timed else None
                if x.events is not None:
                    x.events[0].record(stream=st)
                    if first is None:
                        first = x.events[0]
                with warnings.catch_warnings():
                    # a small grid under-uses the GPU: known (a small sweep, a store's last block)
                    warnings.simplefilter("ignore", NumbaPerformanceWarning)
                    kern[blocks, THREADS_PER_BLOCK, st](*args)
                    if x.gathered:  # the kept columns, side by side: only they cross back
                        whole = -(-b // THREADS_PER_BLOCK)
                        gather[whole, THREADS_PER_BLOCK, st](d_out, x.d_cols, x.d_kept[:b])
                if x.events is not None:
                    x.events[1].record(stream=st)
                x.d_kept[:b].copy_to_host(x.h_out[:b], stream=st)
                x.pending = (lo, hi)
            for j in range(STREAMS):  # the last launches, in the order they were made
                finish(slots[(-(-n // batch) + j) % STREAMS])
        except (ValueError, CudaUnavailableError):
            raise
        except Exception as exc:  # the toolkit, the driver, the GPU's memory: one line, not numba's trace
            if in_callback:
                raise
            _drop_slots()
            raise CudaUnavailableError(
                f"backend='cuda': the GPU kernel failed ({type(exc).__name__}: {_first_line(exc)})"
            ) from exc
        finally:
            slots = x = None  # type: ignore[assignment]  # no reference to the buffers in a traceback
        # the GPU busy with kernels (their union over the streams) and from the first start to the last end
        TIMES["kernel"] = _busy(busy)
        TIMES["span"] = max((b for _, b in busy), default=0.0)
        TIMES["gpu"] = time.perf_counter() - t_locked
    TIMES["total"] = time.perf_counter() - t0


_FORCED_KERNELS: dict[tuple[int, str], Any] = {}


def forced_kernel(one: Any) -> Any:
    """Return the CUDA kernel running the forced engine's per-row function ``one`` (``strobe_one``)."""
    options = {} if simulator() else dict(JIT_OPTIONS)
    key = (id(one), repr(sorted(options.items())))
    if key not in _FORCED_KERNELS:
        from . import _cuda_kernel

        _load_registries_without_row_stack()
        _FORCED_KERNELS[key] = (one, _cuda_kernel.make_forced(one, options))
    return _FORCED_KERNELS[key][1]


def run_forced_strobe_cuda(
    one: Any,
    law: int,
    lp: np.ndarray,
    fp: np.ndarray,
    x0: np.ndarray,
    t0: float,
    n_transient: int,
    n_record: int,
    rtol: float,
    atol: float,
    max_steps: int,
    track: bool,
    out: np.ndarray,
    lyap: np.ndarray,
    stats: np.ndarray,
    on_rows: Callable[[int], None] | None = None,
) -> None:
    """Fill ``out``, ``lyap`` and ``stats`` as the CPU's ``strobe_rows``, one GPU thread a row.

    ``lp`` and ``x0`` have one row for all or one a row; ``fp`` one a row. The rows go
    in launches that use at most a quarter of the free device memory for their
    sections (one stream, ordinary copies: the forced diagrams' results are their
    sections, ``8 n_record`` bytes a row per state variable, which dwarf the inputs).
    """
    from numba import cuda
    from numba.core.errors import NumbaPerformanceWarning

    check_kernel(one, FORCED_MAX_TABLE_ROWS)
    kern = forced_kernel(one)
    n = fp.shape[0]
    per_row = 8 * (2 * n_record + 2 + stats.shape[1] + fp.shape[1] + lp.shape[1] + 2)
    batch = _batch_rows(n, per_row)
    ts = np.zeros(0)
    samples = np.zeros((0, 3))
    with warnings.catch_warnings():
        # a small launch (the simulator's, a short diagram) leaves the GPU mostly idle: not an error
        warnings.simplefilter("ignore", NumbaPerformanceWarning)
        d_ts = cuda.to_device(ts)
        d_samples = cuda.to_device(samples)
        for lo in range(0, n, batch):
            hi = min(n, lo + batch)
            lp_b = lp if lp.shape[0] == 1 else lp[lo:hi]
            x0_b = x0 if x0.shape[0] == 1 else x0[lo:hi]
            d_out = cuda.device_array((hi - lo, n_record, 2))
            d_lyap = cuda.device_array((hi - lo, 2))
            d_stats = cuda.device_array((hi - lo, stats.shape[1]))
            blocks = -(-(hi - lo) // THREADS_PER_BLOCK)
            d_lp, d_fp, d_x0 = (cuda.to_device(np.ascontiguousarray(a)) for a in (lp_b, fp[lo:hi], x0_b))
            kern[blocks, THREADS_PER_BLOCK](
                law, d_lp, d_fp, float(t0), d_x0, int(n_transient), int(n_record), float(rtol), float(atol),
                int(max_steps), bool(track), d_out, d_lyap, d_stats, d_ts, d_samples,
            )  # fmt: skip
            out[lo:hi] = d_out.copy_to_host()
            lyap[lo:hi] = d_lyap.copy_to_host()
            stats[lo:hi] = d_stats.copy_to_host()
            if on_rows is not None:
                on_rows(hi - lo)
