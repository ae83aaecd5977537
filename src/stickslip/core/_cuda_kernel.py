"""The CUDA kernel of :mod:`stickslip.core.cuda` (imported only when a CUDA backend runs).

A module of its own, importing ``numba.cuda`` at its top: numba's CUDA simulator
swaps the name ``cuda`` in the kernel's module for its own while the kernel runs.
"""

from __future__ import annotations

import math
from typing import Any

from numba import cuda, float64, int64

from . import engine, forced
from .laws import N_LAW_PARAMS


def make(one: Any, width: int = 2, options: dict[str, Any] | None = None, persistent: bool = False) -> Any:
    """Return the CUDA kernel running the per-row function ``one`` (a law's ``engine.attractor_ws``).

    Thread ``i`` runs row ``r = order[i]`` (``r = i`` where ``order`` is empty:
    the launch's rows sorted for the load balance, read and written in place):
    the law's id ``law`` (one for all rows), the law's parameters ``lp_a[r]``
    (only the columns the law has: the rest are zeros), ``nu_a[r]`` and the start
    ``s0_a[r]``, ``w0_a[r]`` (or ``[0]`` where they are of length 1: a start at
    breakaway ignores them), its results into ``out[r]``. What goes to the GPU is
    so kept to what differs between rows. Its work arrays (the stages
    ``K`` to the event count ``evn``, ``width`` = 2 state variables, 4 with the
    variational ones) and a copy of its law parameters are the thread's own
    local arrays, which NVVM keeps in registers (ptxas for sm_90: no local
    memory, no spills); they were slices of global arrays, one per thread,
    before (on an H100, 2 x 10^6 rows in 0.545 s against 0.477 s now, the host's
    copies included). The empty sample and event buffers are shared (an
    attractor records nothing). ``options`` go to ``cuda.jit``
    (``max_registers``, ``shared_memory_carveout``).

    ``persistent``: the threads take rows from a queue (``next_row[0]``, an atomic
    counter set to 0 before the launch) until none is left, instead of one row each;
    launched as many as stay resident, a thread whose row ends early takes the next,
    so that a warp's threads wait less for its slowest (a variant to measure:
    ``bench_gpu.py``). The last argument, ``next_row``, is ignored otherwise.
    """
    ns, nt = engine.N_STAGES_EXTENDED, engine.NTRK
    npar = N_LAW_PARAMS

    def rows(  # type: ignore[no-untyped-def]
        law, lp_a, nu_a, s0_a, w0_a, from_breakaway, rtol, atol, t_max, conv_tol, max_steps, out,
        t_eval, out_y, out_mode, evbuf, order, next_row,
    ):  # fmt: skip
        k = cuda.local.array((ns, width), float64)
        f = cuda.local.array((7, width), float64)
        y_new = cuda.local.array(width, float64)
        ytmp = cuda.local.array(width, float64)
        y = cuda.local.array(width, float64)
        trk = cuda.local.array(nt, float64)
        evn = cuda.local.array(1, int64)
        lp = cuda.local.array(npar, float64)
        # a thread's own row, or the queue's next (``persistent``, a constant when compiled)
        i = cuda.atomic.add(next_row, 0, 1) if persistent else cuda.grid(1)
        while i < nu_a.shape[0]:
            r = order[i] if order.shape[0] > 0 else i  # the row, through the launch's sort
            for j in range(npar):
                lp[j] = lp_a[r, j] if j < lp_a.shape[1] else 0.0
            evn[0] = 0
            r0 = r if s0_a.shape[0] > 1 else 0
            one(
                law, lp, nu_a[r], s0_a[r0], w0_a[r0], from_breakaway, rtol, atol, t_max, conv_tol,
                max_steps, out[r], k, f, y_new, ytmp, y, trk, t_eval, out_y, out_mode, evbuf, evn,
            )  # fmt: skip
            i = cuda.atomic.add(next_row, 0, 1) if persistent else nu_a.shape[0]

    return cuda.jit(rows, **(options or {}))


def make_forced(one: Any, options: dict[str, Any] | None = None) -> Any:
    """Return the CUDA kernel running the forced engine's per-row function ``one`` (``forced.strobe_one``).

    Thread ``i`` runs row ``i``: its law parameters ``lp_a[i]`` (or ``lp_a[0]`` for
    all rows where ``lp_a`` has one row), its forcing ``fp_a[i]`` and its start
    ``x0_a[i]`` (or ``x0_a[0]``); its sections into ``out[i]``, its Lyapunov
    exponents into ``lyap[i]``, its statistics into ``stats[i]``. The work arrays
    are the thread's own local arrays; ``ts`` and ``samples`` are empty.
    """
    # sizes as closure constants: numba-cuda's local arrays need literal shapes
    npar = N_LAW_PARAMS
    nwork = forced.N_STAGES_EXTENDED + 10
    width = forced.NVAR_TRACK
    nstate = forced.NSTATE
    nfp = forced.NFP

    def rows(  # type: ignore[no-untyped-def]
        law, lp_a, fp_a, t0, x0_a, n_transient, n_record, rtol, atol, max_steps, track, out, lyap, stats,
        ts, samples,
    ):  # fmt: skip
        work = cuda.local.array((nwork, width), float64)
        st = cuda.local.array(nstate, float64)
        phi = cuda.local.array(4, float64)
        qm = cuda.local.array(4, float64)
        m = cuda.local.array(4, float64)
        lp = cuda.local.array(npar, float64)
        fp = cuda.local.array(nfp, float64)
        i = cuda.grid(1)
        if i < fp_a.shape[0]:
            rl = i if lp_a.shape[0] > 1 else 0
            rx = i if x0_a.shape[0] > 1 else 0
            for j in range(npar):
                lp[j] = lp_a[rl, j]
            for j in range(nfp):
                fp[j] = fp_a[i, j]
            s0 = x0_a[rx, 0]
            w0 = x0_a[rx, 1]
            one(
                law, lp, fp, t0, s0, w0, n_transient, n_record, rtol, atol, max_steps, track, out[i], lyap[i],
                stats[i], work, st, phi, qm, m, ts, samples,
            )  # fmt: skip

    return cuda.jit(rows, **(options or {}))


def _gather(src, cols, dst):  # type: ignore[no-untyped-def]
    """Copy columns ``cols`` of the rows ``src`` into ``dst`` (rows x len(cols)), one row a thread."""
    i = cuda.grid(1)
    if i < dst.shape[0]:
        for j in range(cols.shape[0]):
            dst[i, j] = src[i, cols[j]]


_GATHER: list[Any] = []


def gather() -> Any:
    """Return the CUDA kernel that keeps some columns of the results (compiled at its first launch).

    What crosses back to the host is then only what the caller keeps (a sweep:
    12 of the 21 numbers a row); it reads and writes the GPU's own memory, a few
    microseconds a launch of 2^20 rows.
    """
    if not _GATHER:
        _GATHER.append(cuda.jit(_gather))
    return _GATHER[0]


# ---------------------------------------------------------------- the rows' order, on the device
# A stable sort of the rows by their 16-bit balance keys (``stickslip.core.cuda.balance_key``)
# on the GPU: the keys from the rows' own parameters, then two passes of a counting sort of
# 8 bits each (least significant first), each pass a histogram per segment of rows, a scan of
# the histograms in digit-major order, and a scatter that walks each segment in order, so
# that rows of equal keys keep their order: numpy's ``argsort(kind="stable")``.

#: rows a thread counts and scatters in one pass of the sort
SORT_SEGMENT = 256
#: values of one digit (8 bits)
RADIX = 256


def _balance_keys(lp, nu, cols, logs, los, scales, bits, key):  # type: ignore[no-untyped-def]
    """Set ``key[i]`` to row ``i``'s balance key (the host's ``balance_key``, operation for operation)."""
    i = cuda.grid(1)
    if i < nu.shape[0]:
        k = 0
        for b in range(cols.shape[0]):
            j = cols[b]
            x = nu[i] if j < 0 else lp[i, j]
            if logs[b]:
                x = math.log(x)
            k = ((k << bits) | int((x - los[b]) * scales[b])) & 0xFFFF
        key[i] = k


def _digit_histograms(key, order_in, shift, hist):  # type: ignore[no-untyped-def]
    """Count the digits ``(key >> shift) & 255`` of segment ``g``'s rows into ``hist[:, g]``."""
    g = cuda.grid(1)
    if g < hist.shape[1]:
        for d in range(RADIX):
            hist[d, g] = 0
        lo = g * SORT_SEGMENT
        hi = min(lo + SORT_SEGMENT, key.shape[0])
        for p in range(lo, hi):
            r = order_in[p] if order_in.shape[0] > 0 else p
            d = (key[r] >> shift) & (RADIX - 1)
            hist[d, g] += 1


def _digit_offsets(hist, totals):  # type: ignore[no-untyped-def]
    """Turn the counts into the first position of each (digit, segment): one block of ``RADIX`` threads."""
    d = cuda.threadIdx.x
    n = hist.shape[1]
    acc = 0
    for g in range(n):
        acc += hist[d, g]
    totals[d] = acc
    cuda.syncthreads()
    if d == 0:
        run = 0
        for e in range(RADIX):
            v = totals[e]
            totals[e] = run
            run += v
    cuda.syncthreads()
    run = totals[d]
    for g in range(n):
        v = hist[d, g]
        hist[d, g] = run
        run += v


def _digit_scatter(key, order_in, shift, hist, order_out):  # type: ignore[no-untyped-def]
    """Write segment ``g``'s rows, in their order, to the positions of their digits."""
    g = cuda.grid(1)
    if g < hist.shape[1]:
        lo = g * SORT_SEGMENT
        hi = min(lo + SORT_SEGMENT, key.shape[0])
        for p in range(lo, hi):
            r = order_in[p] if order_in.shape[0] > 0 else p
            d = (key[r] >> shift) & (RADIX - 1)
            pos = hist[d, g]
            hist[d, g] = pos + 1
            order_out[pos] = r


_SORT: list[Any] = []


def sort_kernels() -> tuple[Any, Any, Any, Any]:
    """Return the four kernels of the device sort (compiled at their first launch)."""
    if not _SORT:
        _SORT.extend(cuda.jit(f) for f in (_balance_keys, _digit_histograms, _digit_offsets, _digit_scatter))
    return _SORT[0], _SORT[1], _SORT[2], _SORT[3]
