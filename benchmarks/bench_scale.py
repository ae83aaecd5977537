"""Scale-out overheads: one sweep in process, on a LocalCluster, and streamed to a store.

The same 10^6-point sweep (weakening law, dimensionless, ``nu`` x ``c``) is run

1. in process (the default: numba's threads, no Dask);
2. in process, streamed block by block to a Zarr store;
3. on a ``LocalCluster`` of 2 worker processes (1 numba thread each), results
   sent back; the cluster's start-up is timed apart;
4. on that cluster, each worker writing its blocks to a store;
5. on a ``LocalCluster`` of 1 process with numba's threads on every core;

and the overhead of each against (1) is printed, with the results checked
equal bit for bit. SciPy's ``solve_ivp`` on a sample of the grid's stick-slip
points gives the straightforward anchor. ``--big`` adds a 10^7-point sweep to a
store in a child process and reports its peak resident memory (and that of the
in-memory sweep it replaces, as estimated by ``check_sweep_size``).

Run::

    python benchmarks/bench_scale.py [--points 1000000] [--big] [--n-scipy 100]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

from stickslip.dynamics.sweep import BYTES_PER_POINT, load_sweep, sweep
from stickslip.laws import WeakeningLaw
from stickslip.models import DimensionlessParameters

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_cycles import scipy_cycle

BASE = DimensionlessParameters(0.01, WeakeningLaw(c=3.8, p=0.0))


def grid(points: int) -> dict[str, np.ndarray]:
    n_c = 1000 if points >= 10**6 else max(2, int(np.sqrt(points)))
    n_nu = points // n_c
    return {"nu": np.geomspace(1e-3, 0.3, n_nu), "c": np.linspace(2.0, 10.0, n_c)}


def timed(label: str, fn, ref_seconds: float | None = None):  # type: ignore[no-untyped-def]
    t0 = time.perf_counter()
    out = fn()
    dt = time.perf_counter() - t0
    extra = "" if ref_seconds is None else f"  overhead {100 * (dt / ref_seconds - 1):+6.1f} %"
    print(f"{label:44s} {dt:8.2f} s{extra}", flush=True)
    return out, dt


def same(a, b) -> bool:  # type: ignore[no-untyped-def]
    for k in a.data_vars:
        x, y = a[k].values, b[k].values
        if x.dtype.kind == "f":
            if not np.array_equal(x.view(np.int64), y.view(np.int64)):
                return False
        elif not np.array_equal(x, y):
            return False
    return True


def big_child(points: int, store: str) -> None:
    """Run in a child process: a sweep to a store; print its peak memory."""
    import resource

    t0 = time.perf_counter()
    ds = sweep(BASE, grid(points), progress=False, store=store)
    dt = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    print(json.dumps({"seconds": dt, "peak_bytes": peak, "run": json.loads(ds.attrs["run"])}))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", type=int, default=10**6)
    ap.add_argument("--big", action="store_true", help="also a 10^7-point sweep to a store (peak memory)")
    ap.add_argument("--big-points", type=int, default=10**7)
    ap.add_argument("--n-scipy", type=int, default=100)
    ap.add_argument("--child", nargs=2, metavar=("POINTS", "STORE"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        big_child(int(args.child[0]), args.child[1])
        return
    from distributed import Client

    from stickslip.scale.backend import local_cluster

    g = grid(args.points)
    n = g["nu"].size * g["c"].size
    machine = platform.processor() or platform.machine()
    print(f"machine: {machine}, {os.cpu_count()} cores; python {sys.version.split()[0]}")
    print(f"sweep: weakening law, {g['nu'].size} nu x {g['c'].size} c = {n} points")
    sweep(BASE, {"nu": g["nu"][:50], "c": g["c"][:4]}, progress=False)  # compile / load the kernels
    tmp = tempfile.mkdtemp(prefix="bench-scale-")
    try:
        ref, t_ref = timed("1. in process (default)", lambda: sweep(BASE, g, progress=False))
        rate = n / t_ref
        print(f"   {rate:,.0f} points/s")
        _, t_store = timed(
            "2. in process, to a store",
            lambda: sweep(BASE, g, progress=False, store=os.path.join(tmp, "a.zarr")),
            t_ref,
        )
        eq_store = same(ref, load_sweep(os.path.join(tmp, "a.zarr")))
        # what a terminal shows by default: a progress bar, here a callable that counts its updates
        updates: list[int] = []
        barred, _ = timed(
            "2b. in process, with a progress bar (callable)",
            lambda: sweep(BASE, g, progress=lambda info: updates.append(info.points)),
            t_ref,
        )
        print(f"   {len(updates)} progress updates; equal to (1): {same(ref, barred)}")
        t0 = time.perf_counter()
        cluster = local_cluster(2, numba_threads=1)
        client = Client(cluster)
        t_start = time.perf_counter() - t0
        print(f"   LocalCluster of 2 processes started in {t_start:.2f} s")
        # the workers load their kernels once (from numba's cache), as on a real cluster's first task
        sweep(BASE, {"nu": g["nu"][:50], "c": g["c"][:4]}, progress=False, scheduler=client, block_points=100)
        dask_ds, t_dask = timed(
            "3. LocalCluster (2 processes), results back",
            lambda: sweep(BASE, g, progress=False, scheduler=client),
            t_ref,
        )
        timed(
            "4. LocalCluster (2 processes), to a store",
            lambda: sweep(BASE, g, progress=False, scheduler=client, store=os.path.join(tmp, "b.zarr")),
            t_ref,
        )
        eq_dask = same(ref, dask_ds)
        eq_dask_store = same(ref, load_sweep(os.path.join(tmp, "b.zarr")))
        client.close()
        cluster.close()
        print(f"   with the cluster's start-up, (3) costs {100 * ((t_dask + t_start) / t_ref - 1):+.1f} %")
        # one worker process with numba's threads on every core: the scheduler's and the client's
        # own CPU time then no longer stalls one of two single-threaded workers
        cluster = local_cluster(1, numba_threads=os.cpu_count() or 1)
        client = Client(cluster)
        sweep(BASE, {"nu": g["nu"][:50], "c": g["c"][:4]}, progress=False, scheduler=client, block_points=100)
        one_ds, _ = timed(
            f"5. LocalCluster (1 process, {os.cpu_count()} threads)",
            lambda: sweep(BASE, g, progress=False, scheduler=client),
            t_ref,
        )
        eq_dask = eq_dask and same(ref, one_ds)
        client.close()
        cluster.close()
        print(f"bit for bit equal to (1): store {eq_store}, cluster {eq_dask}, cluster+store {eq_dask_store}")
        # the straightforward SciPy way on a sample of stick-slip points
        rng = np.random.default_rng(0)
        flat_nu, flat_c = (a.ravel() for a in np.meshgrid(g["nu"], g["c"], indexing="ij"))
        ok = (ref["regime"].values.ravel() == "stick-slip") & (flat_nu < 0.05)
        idx = rng.choice(np.flatnonzero(ok), size=min(args.n_scipy, int(ok.sum())), replace=False)
        t0 = time.perf_counter()
        amp = np.array([scipy_cycle(flat_nu[i], flat_c[i]) for i in idx])
        t_scipy = (time.perf_counter() - t0) / idx.size
        rel = np.max(np.abs(amp - ref["amplitude"].values.ravel()[idx]) / amp)
        print(
            f"SciPy solve_ivp, one stick-slip cycle per point: {1 / t_scipy:,.0f} points/s "
            f"({idx.size} points; largest relative amplitude difference {rel:.1e})"
        )
        print(
            f"ratios to SciPy: in process {rate * t_scipy:,.0f} x, "
            f"to a store {n / t_store * t_scipy:,.0f} x, LocalCluster {n / t_dask * t_scipy:,.0f} x"
        )
        if args.big:
            store = os.path.join(tmp, "big.zarr")
            res = subprocess.run(
                [sys.executable, os.path.abspath(__file__), "--child", str(args.big_points), store],
                capture_output=True,
                text=True,
                check=True,
            )
            r = json.loads(res.stdout.strip().splitlines()[-1])
            size = sum(os.path.getsize(os.path.join(d, f)) for d, _, files in os.walk(store) for f in files)
            print(
                f"{args.big_points:.0e}-point sweep to a store: {r['seconds']:.1f} s "
                f"({args.big_points / r['seconds']:,.0f} points/s), peak resident memory "
                f"{r['peak_bytes'] / 2**20:,.0f} MiB (in memory it would need about "
                f"{args.big_points * BYTES_PER_POINT / 2**30:,.1f} GiB); store {size / 2**20:,.0f} MiB "
                f"in {r['run']['blocks']} blocks"
            )
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
