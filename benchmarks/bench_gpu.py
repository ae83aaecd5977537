"""Exact stick-slip cycles per second on a CUDA GPU against the CPU engine, same work, same run.

Work: the steady stick-slip cycle of law F1 (the workload of ``bench_cycles.py``: ``nu``
log-uniform in [1e-5, 1e-1], ``c`` uniform in [0.5, 50], rtol 1e-9, atol 1e-12). The GPU
runs ``run_attractors(..., backend="cuda")``: the CPU engine's own per-row function
compiled by numba-cuda, one parameter set per thread, double precision. The CPU engine
runs a subset on this machine's cores; the two are compared on that subset (statuses
equal, amplitudes to 1e-8). The device is named. Where no GPU is usable, the script
says why and stops: the speed is then unmeasured (the numbers of docs/benchmarks.md
come from a run on a GPU, or say that there was none).

Where JAX and diffrax import, the same slip phases (from breakaway to the stop, F1, the
same parameter sets) also run through diffrax (``Dopri8``, a PID step-size controller at
the same tolerances, a terminal event at ``w = 0`` located by Newton's method, ``vmap``
over the sets, double precision) on JAX's default device: phases per second and the
spring force at the stop against the engine's.

The same F1 call then keeps only a sweep's 12 fields, and only status, regime and
amplitude (``fields=``: the rest stay on the GPU), end to end; then a sweep of
``--n-sweep`` points on the GPU, end to end (the host's share of a sweep included).

Then, on fewer sets (``--n-extra``), the GPU's cycles per second for F2, the cubic law, a
law typed as a formula and a measured table (600 rows), for F1 at other block sizes and
register limits, with the threads taking rows from a queue (``PERSISTENT``), with one,
two or three CUDA streams at launches of 2^18 rows, and for F1 with
each launch's rows sorted for the load balance (``SORT_ROWS``; alone and under a cap of
168 registers) and sorted beforehand (as a grid's rows come): each end to end
and its kernels alone (the launch options change the kernels; end to end, the host's
copies may hide it), and each F1 variant's rows against the default's.

Without a GPU, ``--host-only N`` times the host's part of a sweep of N points on the GPU
(its kernels and copies replaced by a copy of one row): what bounds a sweep end to end
once the kernels are fast; ``--copy-only N`` times the host's copy of N rows of results
out of a launch's buffer, in one thread and in several.

Run: python benchmarks/bench_gpu.py [--n 10000000] [--n-cpu 200000] [--n-diffrax 1000000] [--n-extra 2000000]
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from unittest import mock

import numpy as np
from bench_cycles import ATOL, RTOL, workload

from stickslip.core import cuda as core_cuda
from stickslip.core import kernel as core_kernel
from stickslip.core.api import run_attractors, threads
from stickslip.laws import WeakeningLaw
from stickslip.orbits.attractors import POLISH_FIELDS


def diffrax_phases(nu: np.ndarray, c: np.ndarray) -> tuple[float, float, np.ndarray, str] | None:
    """Slip phases from breakaway by diffrax: compile and run seconds, spring force at the stop, device.

    None where JAX or diffrax does not import.
    """
    try:
        import diffrax
        import jax
        import jax.numpy as jnp
        import optimistix as optx
    except ImportError:
        return None
    jax.config.update("jax_enable_x64", True)

    def field(t, y, args):  # type: ignore[no-untyped-def]
        nu_, c_ = args
        return jnp.stack([nu_ - y[1], y[0] - 1.0 / (1.0 + c_ * y[1])])

    def stopped(t, y, args, **kwargs):  # type: ignore[no-untyped-def]
        return jnp.where(t > 0.0, y[1], 1.0)  # w = 0 at breakaway: not the stop

    def phase(nu_, c_):  # type: ignore[no-untyped-def]
        sol = diffrax.diffeqsolve(
            diffrax.ODETerm(field), diffrax.Dopri8(), 0.0, 1e4, None, jnp.array([1.0, 0.0]), args=(nu_, c_),
            stepsize_controller=diffrax.PIDController(rtol=RTOL, atol=ATOL),
            event=diffrax.Event(stopped, optx.Newton(1e-12, 1e-14)), max_steps=100_000,
            saveat=diffrax.SaveAt(t1=True),
        )  # fmt: skip
        return sol.ys[0, 0]

    run = jax.jit(jax.vmap(phase))
    t0 = time.perf_counter()
    jax.block_until_ready(run(jnp.asarray(nu[:8]), jnp.asarray(c[:8])))
    t_compile = time.perf_counter() - t0
    t0 = time.perf_counter()
    s_stop = np.asarray(jax.block_until_ready(run(jnp.asarray(nu), jnp.asarray(c))))
    return t_compile, time.perf_counter() - t0, s_stop, str(jax.devices()[0])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000_000, help="parameter sets on the GPU")
    ap.add_argument("--n-cpu", type=int, default=200_000, help="parameter sets on the CPU (the first ones)")
    ap.add_argument("--n-diffrax", type=int, default=1_000_000, help="parameter sets for diffrax")
    ap.add_argument(
        "--n-extra", type=int, default=2_000_000, help="sets for other laws and launches (0: none)"
    )
    ap.add_argument(
        "--n-sweep", type=int, default=10_000_000, help="points of a sweep(..., backend='cuda') (0: none)"
    )
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--diffrax-only", action="store_true", help="diffrax against the CPU engine (no GPU)")
    ap.add_argument(
        "--copy-only",
        type=int,
        default=0,
        metavar="N",
        help="the host's copy of N rows of results out of a launch's buffer, one thread and several (no GPU)",
    )
    ap.add_argument(
        "--host-only",
        type=int,
        default=0,
        metavar="N",
        help="a sweep of N points with the GPU's work replaced by a copy of one row (no GPU)",
    )
    args = ap.parse_args()
    if args.diffrax_only:
        _diffrax_against_engine(args)
        return
    if args.host_only:
        _host_only_sweep(args.host_only)
        return
    if args.copy_only:
        _copy_out(args.copy_only)
        return
    ok, device = core_cuda.cuda_status()
    if not ok or core_cuda.simulator():
        print(f"no GPU to measure on: {device}; the GPU speed is unmeasured")
        sys.exit(0)
    _, nu, c = workload(args.n, args.seed)
    lp = c[:, None]
    kernel = WeakeningLaw(c=1.0).kernel
    kw = dict(from_breakaway=True, rtol=RTOL, atol=ATOL, max_slip_time=1e4, conv_tol=1e-8)

    t0 = time.perf_counter()
    run_attractors(kernel, lp[:1024], nu[:1024], backend="cuda", **kw)
    t_compile = time.perf_counter() - t0
    t0 = time.perf_counter()
    gpu = run_attractors(kernel, lp, nu, backend="cuda", **kw)
    t_cold = time.perf_counter() - t0  # the stream buffers made for launches of this size
    t0 = time.perf_counter()
    gpu = run_attractors(kernel, lp, nu, backend="cuda", **kw)
    t_gpu = time.perf_counter() - t0  # ... and reused
    times = dict(core_cuda.TIMES)

    m = min(args.n_cpu, args.n)
    run_attractors(kernel, lp[:8], nu[:8], **kw)  # compile or load from the cache
    t0 = time.perf_counter()
    cpu = run_attractors(kernel, lp[:m], nu[:m], **kw)
    t_cpu = time.perf_counter() - t0
    m1 = max(1, m // 10)
    with mock.patch.object(core_kernel, "threads", lambda: 1):
        t0 = time.perf_counter()
        run_attractors(kernel, lp[:m1], nu[:m1], **kw)
        t_one = time.perf_counter() - t0

    same_status = bool(np.array_equal(gpu.status[:m], cpu.status))
    okm = cpu.status == 0
    rel = np.abs(gpu.amplitude[:m][okm] - cpu.amplitude[okm]) / np.abs(cpu.amplitude[okm])
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; GPU: {device}")
    print(f"work: F1 steady stick-slip cycles, nu log-uniform [1e-5, 1e-1], c in [0.5, 50], rtol {RTOL:g}")
    print(
        f"GPU  : {args.n:10d} cycles in {t_gpu:8.3f} s = {args.n / t_gpu:14.0f} cycles/s"
        f"  (first call incl. compile {t_compile:.1f} s; the call before, making the stream "
        f"buffers, {t_cold:.3f} s)"
    )
    print(
        f"       of which the GPU with the copies {times['gpu']:.3f} s (the host sorting each launch's "
        f"rows {times['order']:.3f} s and copying results out of pinned memory {times['copy_out']:.3f} s "
        f"of it), waiting for another call {times['lock_wait']:.3f} s;"
    )
    print(
        f"       the GPU busy with kernels (CUDA events, their union over the streams) "
        f"{times['kernel']:.3f} s = "
        f"{_per_s(args.n, times['kernel']):14.0f} cycles/s; from the first launch's start to the last's "
        f"end {times['span']:.3f} s = {_per_s(args.n, times['span']):14.0f} cycles/s "
        f"({core_cuda.STREAMS} streams, launches of {core_cuda.MAX_BATCH} rows at most)"
    )
    _kept_fields(kernel, lp, nu, kw, gpu)
    if args.n_sweep:
        _gpu_sweep(args.n_sweep)
    print(f"CPU  : {m:10d} cycles in {t_cpu:8.3f} s = {m / t_cpu:14.0f} cycles/s ({threads()} threads)")
    print(f"       {m1:10d} cycles in {t_one:8.3f} s = {m1 / t_one:14.0f} cycles/s (one thread)")
    print(f"ratio: {(args.n / t_gpu) / (m / t_cpu):.1f} x the CPU engine")
    worst = float(rel.max()) if rel.size else float("nan")
    print(
        f"agreement on the {m} common sets: statuses equal {same_status}, amplitude largest relative "
        f"difference {worst:.3e} (median {float(np.median(rel)):.3e})"
    )
    if args.n_extra:
        _other_laws_and_launches(args.n_extra, nu, c, kw, gpu)
    k = min(args.n_diffrax, args.n)
    if k == 0:
        print("diffrax: not run (--n-diffrax 0)")
        return
    got = diffrax_phases(nu[:k], c[:k])
    if got is None:
        print("diffrax: JAX or diffrax does not import here; not compared")
        return
    t_dc, t_d, s_stop, jdev = got
    ref = gpu.s_stop[:k]
    drel = np.abs(s_stop - ref) / np.abs(ref)
    print(
        f"diffrax: {k:8d} slip phases in {t_d:8.3f} s = {k / t_d:14.0f} phases/s on {jdev} "
        f"(compile {t_dc:.1f} s); the GPU engine's cycles/s are {(args.n / t_gpu) / (k / t_d):.1f} x"
    )
    print(f"  spring force at the stop against the engine's: largest relative difference {drel.max():.3e}")


def _kept_fields(kernel: object, lp: np.ndarray, nu: np.ndarray, kw: dict, full: object) -> None:
    """End to end where only some fields cross back (``fields=``): a sweep's 12, a verdict's 3."""
    for label, fields in {
        "a sweep's 12 fields": POLISH_FIELDS,
        "status, regime, amplitude": ("status", "regime", "amplitude"),
    }.items():
        run_attractors(kernel, lp, nu, backend="cuda", fields=fields, **kw)  # its stream buffers made
        t0 = time.perf_counter()
        got = run_attractors(kernel, lp, nu, backend="cuda", fields=fields, **kw)
        dt = time.perf_counter() - t0
        same = all(np.array_equal(getattr(got, x), getattr(full, x), equal_nan=True) for x in fields)
        print(
            f"       keeping {label:26s}: {nu.size:10d} cycles in {dt:7.3f} s = {nu.size / dt:14.0f} "
            f"cycles/s{_kernels(nu.size)}; the host copying out {core_cuda.TIMES['copy_out']:.3f} s; "
            f"the same numbers as all 21 kept: {same}"
        )


def _other_laws_and_launches(n: int, nu: np.ndarray, c: np.ndarray, kw: dict, full: object) -> None:
    """Cycles per second of the other kinds of law, other block sizes, and without the sorting.

    Each F1 variant's rows are compared with the default kernel's (``full``, the same sets):
    statuses equal and the largest relative difference of the amplitudes, since a register
    cap or the row queue changes the compiled kernel, not only its speed.
    """
    from stickslip.laws import CubicLaw, ExpressionLaw, TabulatedLaw
    from stickslip.units import Q_

    n = min(n, nu.size)
    nu, c = nu[:n], c[:n]
    v = np.linspace(0.0, 50.0, 600)  # mm/s: the paper's F1 for zv, as a measured table
    table = TabulatedLaw(Q_(v, "mm/s"), 0.46 / (1.0 + 160e-3 * v)).nondimensionalize(Q_(160.0, "s/m"))
    laws = {
        "F2 (p = 0.5)": (WeakeningLaw(c=1.0, p=0.5).kernel, np.column_stack([c, np.full(n, 0.5)])),
        "cubic": (CubicLaw(alpha=1.2, gamma=0.3).kernel, np.tile([1.2, 0.3], (n, 1))),
        "expression 1/(1 + c*w)": (ExpressionLaw("1/(1 + c*w)", c=1.0).kernel, c[:, None]),
        "table (600 rows)": (table.kernel, np.tile(table.core_params(), (n, 1))),
    }
    for name, (kernel, lp) in laws.items():
        run_attractors(kernel, lp, nu, backend="cuda", **kw)  # compiled, its stream buffers made
        t0 = time.perf_counter()
        run_attractors(kernel, lp, nu, backend="cuda", **kw)
        dt = time.perf_counter() - t0
        print(f"  {name:26s}: {n:9d} cycles in {dt:7.3f} s = {n / dt:14.0f} cycles/s{_kernels(n)}")
    kernel, lp = WeakeningLaw(c=1.0).kernel, c[:, None]

    ref_status, ref_amp = full.status[:n], full.amplitude[:n]  # type: ignore[attr-defined]

    def f1(label: str, lp_: np.ndarray = lp, nu_: np.ndarray = nu, order: np.ndarray | None = None) -> None:
        run_attractors(kernel, lp_, nu_, backend="cuda", **kw)  # compiled if a knob changed, buffers made
        t0 = time.perf_counter()
        got = run_attractors(kernel, lp_, nu_, backend="cuda", **kw)
        dt = time.perf_counter() - t0
        st, amp = (ref_status, ref_amp) if order is None else (ref_status[order], ref_amp[order])
        ok = st == 0
        rel = np.abs(got.amplitude[ok] - amp[ok]) / np.abs(amp[ok])
        worst = float(rel.max()) if rel.size else 0.0
        print(
            f"  F1, {label:30s}: {n:9d} cycles in {dt:7.3f} s = {n / dt:12.0f} cycles/s{_kernels(n)}; "
            f"as the default: statuses {bool(np.array_equal(got.status, st))}, amplitudes {worst:.1e}"
        )

    streams, max_batch = core_cuda.STREAMS, core_cuda.MAX_BATCH
    core_cuda.MAX_BATCH = 1 << 18  # eight launches of 2e6 rows or more: the streams take turns
    for count in (1, 2, 3):  # one: no copy overlaps a kernel (the order of work before the streams)
        core_cuda.STREAMS = count
        f1(f"{count} stream{'s' if count > 1 else ''}, 2^18 a launch")
    core_cuda.STREAMS, core_cuda.MAX_BATCH = streams, max_batch
    default = core_cuda.THREADS_PER_BLOCK
    for threads_ in (64, 256):
        core_cuda.THREADS_PER_BLOCK = threads_
        f1(f"{threads_} threads a block")
    core_cuda.THREADS_PER_BLOCK = default
    default_options = core_cuda.JIT_OPTIONS
    for label, options in {
        "<= 168 registers": {"max_registers": 168},
        "<= 128 registers": {"max_registers": 128},
        "<= 96 registers": {"max_registers": 96},
        "L1 cache at its largest": {"shared_memory_carveout": "MaxL1"},
        "both": {"max_registers": 128, "shared_memory_carveout": "MaxL1"},
    }.items():
        core_cuda.JIT_OPTIONS = options
        f1(label)
    core_cuda.JIT_OPTIONS = default_options
    # the threads take rows from a queue, as many launched as stay resident (2 blocks a
    # multiprocessor at 201-203 registers, 4 under a cap of 128)
    per_sm = core_cuda.PERSISTENT_BLOCKS_PER_SM
    core_cuda.PERSISTENT = True
    f1("persistent (a row queue)")
    core_cuda.JIT_OPTIONS, core_cuda.PERSISTENT_BLOCKS_PER_SM = {"max_registers": 168}, 3
    f1("persistent, <= 168 regs")
    core_cuda.JIT_OPTIONS, core_cuda.PERSISTENT_BLOCKS_PER_SM = {"max_registers": 128}, 4
    f1("persistent, <= 128 regs")
    core_cuda.JIT_OPTIONS, core_cuda.PERSISTENT_BLOCKS_PER_SM = default_options, per_sm
    core_cuda.PERSISTENT = False
    sort = core_cuda.SORT_ROWS
    core_cuda.SORT_ROWS = True  # each launch's rows sorted by their keys, read through that order
    order = core_cuda.balance_order(lp, nu)
    f1("sorted per launch")
    core_cuda.JIT_OPTIONS = {"max_registers": 168}
    f1("sorted per launch, <= 168 regs")
    core_cuda.JIT_OPTIONS = default_options
    core_cuda.SORT_ROWS = False  # sorted beforehand, as a grid's rows come
    f1("sorted beforehand", lp[order], nu[order], order)
    core_cuda.SORT_ROWS = sort


def _per_s(n: int, seconds: float) -> float:
    """``n`` per second over ``seconds``: nan where no time was taken (no CUDA events)."""
    return n / seconds if seconds > 0 else float("nan")


def _kernels(n: int) -> str:
    """The last call's kernels alone (their busy time on the GPU): what the launch options change."""
    busy = core_cuda.TIMES.get("kernel", 0.0)
    return f"; kernels {busy:.3f} s = {n / busy:12.0f} cycles/s" if busy > 0 else ""


def _sweep_grid(n: int) -> tuple[object, dict[str, np.ndarray]]:
    """F1 over ``nu`` (log) x ``c``, about ``n`` points: the sweep of --n-sweep and --host-only."""
    from stickslip import DimensionlessParameters

    base = DimensionlessParameters(0.01, WeakeningLaw(c=3.8))
    return base, {"nu": np.geomspace(1e-4, 0.05, max(1, n // 1000)), "c": np.linspace(2.0, 10.0, 1000)}


def _timed_sweep(n: int) -> tuple[int, float]:
    """Run ``sweep(..., backend="cuda")`` over :func:`_sweep_grid` after a warm-up: (points, seconds)."""
    from stickslip.dynamics.sweep import sweep

    base, grid = _sweep_grid(n)
    sweep(base, {"nu": [0.01, 0.02], "c": [3.8]}, backend="cuda", progress=False)  # imports, compiles
    t0 = time.perf_counter()
    ds = sweep(base, grid, backend="cuda", progress=False)
    return ds.sizes["nu"] * ds.sizes["c"], time.perf_counter() - t0


def _gpu_sweep(n: int) -> None:
    """A sweep on the GPU end to end (the host's share included): what a user runs."""
    m, dt = _timed_sweep(n)
    kernels = core_cuda.TIMES.get("kernel", 0.0)
    print(
        f"sweep(..., backend='cuda'), end to end: {m} points in {dt:.3f} s = {m / dt:.3g} points/s "
        f"(the last launch call's kernels {kernels:.3f} s; nu log [1e-4, 0.05] x c [2, 10], F1)"
    )


def _host_only_sweep(n: int) -> None:
    """A sweep's work on the host with a GPU: everything but the kernels and the copies.

    ``run_attractors_cuda`` is replaced by a copy of one real stick-slip row into every
    row (the rows the GPU would bring back), so that the host's part of
    ``sweep(..., backend="cuda")`` is timed on a machine without a GPU: checking the
    grid, making the rows, the polish, the result's variables and its labels.
    """
    from stickslip.dynamics import sweep as sweep_module

    kernel = WeakeningLaw(c=1.0).kernel
    kw = dict(from_breakaway=True, rtol=RTOL, atol=ATOL, max_slip_time=1e4, conv_tol=1e-8)
    row = run_attractors(kernel, [[3.8]], [0.01], **kw).raw[0]

    def rows_as_the_gpu_would(*args: object, **kwargs: object) -> None:
        out, on_rows = args[13], args[14] if len(args) > 14 else None
        cols = args[15] if len(args) > 15 else None
        out[:] = row if cols is None else row[cols]  # type: ignore[index]
        if callable(on_rows):
            on_rows(len(out))  # type: ignore[arg-type]

    core_cuda.run_attractors_cuda = rows_as_the_gpu_would  # type: ignore[assignment]
    core_cuda.resolve_backend = lambda backend: "cuda" if backend == "cuda" else "cpu"  # type: ignore[assignment]
    sweep_module.resolve_backend = core_cuda.resolve_backend  # type: ignore[attr-defined]
    m, dt = _timed_sweep(n)
    machine = platform.processor() or platform.machine()
    print(f"machine: {machine}, {os.cpu_count()} cores; no GPU: its work stubbed")
    print(f"sweep(..., backend='cuda'), the host's part: {m} points in {dt:.3f} s = {m / dt:.3g} points/s")


def _copy_out(n: int) -> None:
    """The host's copy of ``n`` rows of 21 results out of a launch's buffer (2^20 rows) into fresh memory.

    What takes most of a GPU call end to end (docs/gpu.md): one thread, as before
    2026-11-28, against :func:`stickslip.core.cuda.copy_rows` (several), each into a
    fresh array, four times, the two in turn first (the first touch of fresh pages is
    most of it).
    """
    rows = 1 << 20
    buf = np.random.default_rng(0).random((rows, 21))

    def copy(one: bool) -> float:
        out = np.empty((n, 21))
        t0 = time.perf_counter()
        for lo in range(0, n, rows):
            hi = min(n, lo + rows)
            if one:
                out[lo:hi] = buf[: hi - lo]
            else:
                core_cuda.copy_rows(out[lo:hi], buf[: hi - lo])
        dt = time.perf_counter() - t0
        assert np.array_equal(out[-1], buf[(n - 1) % rows])
        return dt

    threads = min(core_cuda.COPY_THREADS, os.cpu_count() or 1)
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores")
    for k in range(4):  # in turn which goes first: a process's first touch of memory costs the most
        if k % 2:
            t1, tk = copy(True), copy(False)
        else:
            tk, t1 = copy(False), copy(True)
        print(
            f"copying {n} rows of 21 numbers out of a buffer of {rows} rows: one thread {t1:.3f} s, "
            f"{threads} threads {tk:.3f} s ({t1 / tk:.2f} x; {'one thread' if k % 2 else 'threads'} first)"
        )


def _diffrax_against_engine(args: argparse.Namespace) -> None:
    """diffrax's slip phases against the CPU engine's on this machine: the comparison's code, checked."""
    k = args.n_diffrax
    _, nu, c = workload(k, args.seed)
    got = diffrax_phases(nu, c)
    if got is None:
        print("diffrax: JAX or diffrax does not import here")
        return
    t_dc, t_d, s_stop, jdev = got
    kernel = WeakeningLaw(c=1.0).kernel
    kw = dict(from_breakaway=True, rtol=RTOL, atol=ATOL, max_slip_time=1e4, conv_tol=1e-8)
    run_attractors(kernel, c[:8, None], nu[:8], **kw)
    t0 = time.perf_counter()
    cpu = run_attractors(kernel, c[:, None], nu, **kw)
    t_cpu = time.perf_counter() - t0
    drel = np.abs(s_stop - cpu.s_stop) / np.abs(cpu.s_stop)
    print(
        f"diffrax: {k} slip phases in {t_d:.3f} s = {k / t_d:.0f} phases/s on {jdev} (compile {t_dc:.1f} s)"
    )
    print(f"engine : {k} cycles in {t_cpu:.3f} s = {k / t_cpu:.0f} cycles/s on {os.cpu_count()} CPU cores")
    worst, median = drel.max(), np.median(drel)
    print(f"spring force at the stop: largest relative difference {worst:.3e} (median {median:.3e})")


if __name__ == "__main__":
    main()
