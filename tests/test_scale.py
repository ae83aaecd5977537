"""Scale-out: the resumable store, the Dask backend, kills, corrupt chunks, full disks (issue 14).

Every result is compared bit for bit with the in-process run of the same job.
The cluster is a real ``distributed.LocalCluster`` of worker processes.
"""

from __future__ import annotations

import contextlib
import dataclasses
import errno
import hashlib
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import xarray as xr

import stickslip as ss
from stickslip.bifurcation.regime_map import regime_map
from stickslip.chains import ChainParameters, chain_ensemble
from stickslip.chains import ensemble as ensemble_module
from stickslip.chains.statistics import STATISTICS_VERSION
from stickslip.dynamics.sweep import load_sweep, sweep
from stickslip.laws import WeakeningLaw
from stickslip.scale import ProgressInfo, StoreError, chunk_shape

ROOT = Path(__file__).resolve().parents[1]


def _grid(n_v0: int = 24, n_k: int = 10) -> dict[str, Any]:
    return {
        "v0": ss.Q_(np.geomspace(5, 1000, n_v0), "um/s"),
        "stiffness": ss.Q_(np.linspace(30, 90, n_k), "N/m"),
    }


@pytest.fixture(scope="module")
def base() -> Any:
    return ss.zv_parameters()


@pytest.fixture(scope="module")
def reference(base: Any) -> xr.Dataset:
    return sweep(base, _grid(), progress=False)


def assert_same(a: xr.Dataset, b: xr.Dataset) -> None:
    """Bit for bit: every variable, coordinate and attribute."""
    b = b.copy()
    b.attrs.pop("run", None)
    xr.testing.assert_identical(a, b)
    for k in a.variables:
        x, y = a[k].values, b[k].values
        assert x.dtype == y.dtype, k
        if x.dtype.kind == "f":
            assert np.array_equal(x.view(np.int64), y.view(np.int64)), k  # NaN payloads included
        else:
            assert np.array_equal(x, y), k


def tree_digest(path: Path) -> str:
    h = hashlib.sha256()
    for p in sorted(path.rglob("*")):
        h.update(str(p.relative_to(path)).encode())
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


def run_of(ds: xr.Dataset) -> dict[str, Any]:
    out: dict[str, Any] = json.loads(ds.attrs["run"])
    return out


# ----------------------------------------------------------------------------- blocks and the store


@pytest.mark.fast
def test_chunk_shape_keeps_trailing_dimensions_whole() -> None:
    assert chunk_shape((24, 10), 50) == (5, 10)
    assert chunk_shape((10**7,), 32768) == (32768,)
    assert chunk_shape((5, 3, 10**6), 10**4) == (1, 1, 10**4)
    assert chunk_shape((4, 4), 10**6) == (4, 4)
    with pytest.raises(ValueError, match="at least one point"):
        chunk_shape((4,), 0)


def test_a_process_keeps_the_arrays_of_a_few_stores_open(base: Any, tmp_path: Path) -> None:
    """A notebook or a worker writing store after store kept every store's open arrays for
    the life of the process; now the few used last (the least recent goes), and a store
    whose handles went is opened again and still written right."""
    from stickslip.scale import store as store_module

    grid = _grid(4, 2)
    ref = sweep(base, grid, progress=False)
    keep = store_module._KEEP_ARRAYS
    paths = [tmp_path / f"s{i}.zarr" for i in range(keep + 3)]
    for path in paths:
        sweep(base, grid, progress=False, store=path, block_points=4)
        assert len(store_module._ARRAYS) <= keep
    assert not any(k[0] == os.fspath(paths[0]) for k in store_module._ARRAYS)
    shutil.rmtree(paths[0] / ".stickslip-done")  # its blocks again, through new handles
    again = sweep(base, grid, progress=False, store=paths[0], block_points=4)
    assert run_of(again)["computed"] == 2
    assert_same(ref, load_sweep(paths[0]))


def test_store_equals_in_process_bit_for_bit(base: Any, reference: xr.Dataset, tmp_path: Path) -> None:
    store = tmp_path / "s.zarr"
    ds = sweep(base, _grid(), progress=False, store=store, block_points=40)
    run = run_of(ds)
    assert run == run | {"blocks": 6, "reused": 0, "computed": 6, "points": 240, "backend": "in-process"}
    # the store read lazily: regime and status as CF flags
    assert ds["regime"].dtype == np.int8 and "flag_meanings" in ds["regime"].attrs
    assert_same(reference, load_sweep(store))
    # and by any Zarr reader
    raw = xr.open_zarr(store)
    assert np.array_equal(raw["amplitude"].values, reference["amplitude"].values, equal_nan=True)
    # a second run computes nothing
    again = sweep(base, _grid(), progress=False, store=store, block_points=40)
    assert run_of(again)["computed"] == 0 and run_of(again)["reused"] == 6


@pytest.mark.slow
def test_default_run_imports_no_distributed() -> None:
    code = (
        "import sys, numpy as np, stickslip as ss\n"
        "from stickslip.dynamics.sweep import sweep\n"
        "sweep(ss.zv_parameters(), {'v0': ss.Q_(np.geomspace(5, 1000, 4), 'um/s')}, progress=False)\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('distributed', 'zarr')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_a_store_without_a_polish_key_is_another_job(
    base: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A store whose identity has no "polish" key is another job: at other tolerances than the
    defaults, continuing it would mix two polishings."""
    import stickslip.dynamics.sweep as sw

    store = tmp_path / "old.zarr"
    with monkeypatch.context() as m:  # the identity such a store has: no "polish" key
        m.setattr(sw.defaults, "RTOL", 1e-8)
        sweep(base, _grid(), progress=False, store=store, rtol=1e-8, block_points=80)
    with pytest.raises(StoreError, match="holds another job"):
        sweep(base, _grid(), progress=False, store=store, rtol=1e-8)
    # at the defaults nothing changed: such stores still resume
    same = tmp_path / "default.zarr"
    sweep(base, _grid(), progress=False, store=same, block_points=80)
    sweep(base, _grid(), progress=False, store=same)


@pytest.mark.slow
def test_another_grid_is_a_one_line_error_and_the_store_is_untouched(base: Any, tmp_path: Path) -> None:
    store = tmp_path / "s.zarr"
    sweep(base, _grid(), progress=False, store=store, block_points=80)
    before = tree_digest(store)
    with pytest.raises(StoreError) as err:
        sweep(base, _grid(n_v0=25), progress=False, store=store)
    msg = str(err.value)
    assert "\n" not in msg and "holds another job" in msg and "25 values" in msg
    # other fixed parameters, other tolerances: refused as well
    with pytest.raises(StoreError, match="holds another job"):
        sweep(ss.zv_parameters(b="10 s/m"), _grid(), progress=False, store=store)
    with pytest.raises(StoreError, match="holds another job"):
        sweep(base, _grid(), progress=False, store=store, rtol=1e-8)
    assert tree_digest(store) == before
    # from the command line: one Error line, exit status 2 or 1, store untouched
    cmd = _sweep_cmd(store, n_v0=25, n_k=10)
    res = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path)
    assert res.returncode != 0
    errors = [ln for ln in res.stderr.splitlines() if ln.strip()]
    assert len(errors) == 1 and errors[0].startswith("Error:") and "holds another job" in errors[0], (
        res.stderr
    )
    assert tree_digest(store) == before


def test_a_path_that_is_not_a_store_is_never_overwritten(base: Any, tmp_path: Path) -> None:
    folder = tmp_path / "data.zarr"
    folder.mkdir()
    (folder / "precious.txt").write_text("keep me")
    with pytest.raises(StoreError, match="not a stickslip store"):
        sweep(base, _grid(), progress=False, store=folder)
    assert (folder / "precious.txt").read_text() == "keep me"
    with pytest.raises(StoreError, match="does not exist"):
        sweep(base, _grid(), progress=False, store=tmp_path / "missing" / "s.zarr")


def test_corrupt_truncated_and_missing_chunks_are_recomputed(
    base: Any, reference: xr.Dataset, tmp_path: Path
) -> None:
    store = tmp_path / "s.zarr"
    sweep(base, _grid(), progress=False, store=store, block_points=40)
    # block 1: amplitude's chunk truncated; block 3: period's chunk garbled; block 4: stick_time's deleted
    amp = store / "amplitude" / "c" / "1" / "0"
    amp.write_bytes(amp.read_bytes()[: amp.stat().st_size // 2])
    per = store / "period" / "c" / "3" / "0"
    data = bytearray(per.read_bytes())
    data[len(data) // 2] ^= 0xFF
    per.write_bytes(bytes(data))
    (store / "stick_time" / "c" / "4" / "0").unlink()
    ds = sweep(base, _grid(), progress=False, store=store)
    assert run_of(ds)["reused"] == 3 and run_of(ds)["computed"] == 3
    assert_same(reference, load_sweep(store))


# ----------------------------------------------------------------------------- stores made, shared, refused


def test_a_store_made_again_at_the_same_path_is_another_store(
    base: Any, reference: xr.Dataset, tmp_path: Path
) -> None:
    """A store deleted and made again at the same path with other blocks is a new store: arrays
    kept open per path and job would give it chunks of the old shape, silently (then a reshape
    error deep in zarr on loading), in a notebook or on a long-lived cluster."""
    store = tmp_path / "s.zarr"
    sweep(base, _grid(), progress=False, store=store, block_points=20)
    shutil.rmtree(store)
    ds = sweep(base, _grid(), progress=False, store=store, block_points=60)
    assert run_of(ds)["computed"] == 4
    assert_same(reference, load_sweep(store))


def test_two_runs_making_one_store_at_once_share_it(
    base: Any, reference: xr.Dataset, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two runs of one command started together share the store: the one whose rename comes
    second does not remove the store the first has just made."""
    from stickslip.scale.store import ChunkStore

    made = ChunkStore._create

    def beaten(p: str, layout: Any) -> str:
        made(p, layout)  # the other run gets there first
        return made(p, layout)  # this one's rename then fails: the folder exists

    monkeypatch.setattr(ChunkStore, "_create", staticmethod(beaten))
    store = tmp_path / "s.zarr"
    ds = sweep(base, _grid(), progress=False, store=store, block_points=40)
    assert run_of(ds)["computed"] == 6
    assert_same(reference, load_sweep(store))
    assert [n for n in os.listdir(tmp_path) if n.startswith(".creating-")] == []


def test_lost_coordinates_and_markers_folder_are_made_again(
    base: Any, reference: xr.Dataset, tmp_path: Path
) -> None:
    """A coordinate's deleted chunk is made again (read as zeros, load_sweep would give v0 = 0 at
    every point), as is a truncated one (an error from inside numcodecs) and a deleted
    markers' folder (not 'No such file or directory' on every run)."""
    store = tmp_path / "s.zarr"
    sweep(base, _grid(), progress=False, store=store, block_points=40)
    (store / "v0" / "c" / "0").unlink()
    stiff = store / "stiffness" / "c" / "0"
    stiff.write_bytes(stiff.read_bytes()[:5])
    shutil.rmtree(store / ".stickslip-done")
    ds = sweep(base, _grid(), progress=False, store=store)
    assert run_of(ds)["computed"] == 6
    assert_same(reference, load_sweep(store))


def test_an_unfinished_store_is_said_and_read_only_when_asked(
    base: Any, reference: xr.Dataset, tmp_path: Path
) -> None:
    """load_sweep of an interrupted sweep's store says so, and reads it only when asked, the
    unfilled points marked as such (not KeyError: -1 from inside the labels, nor -1, the code
    of the 'unknown' regime)."""
    from stickslip.scale import computed_points

    store = tmp_path / "s.zarr"
    sweep(base, _grid(), progress=False, store=store, block_points=40)  # blocks of 4 v0 rows
    (store / ".stickslip-done" / "000000002").unlink()
    shutil.rmtree(store / "regime" / "c" / "2")
    with pytest.raises(StoreError, match=r"unfinished \(200 of 240 points computed\).*partial=True"):
        load_sweep(store)
    raw = xr.open_zarr(store, chunks=None)
    assert set(np.unique(raw["regime"].values[8:12])) == {-128}  # the fill: no code of any regime
    part = load_sweep(store, partial=True)
    mask = np.ones((24, 10), dtype=bool)
    mask[8:12] = False
    assert np.array_equal(computed_points(store), mask) and np.array_equal(part["computed"].values, mask)
    assert (part["regime"].values[8:12] == "not computed").all()
    assert (part["status"].values[8:12] == "not computed").all()
    assert np.isnan(part["amplitude"].values[8:12]).all()
    assert np.array_equal(part["amplitude"].values[mask], reference["amplitude"].values[mask], equal_nan=True)
    assert np.array_equal(part["regime"].values[mask], reference["regime"].values[mask])
    assert part.attrs["partial"].startswith("200 of 240 points computed")
    # finished: the sweep as before, no mask
    sweep(base, _grid(), progress=False, store=store)
    assert_same(reference, load_sweep(store))
    # another job's store
    law = WeakeningLaw(c=3.8, p=0.3)
    regime_map(law, "p", [0.1, 0.3], 0.05, 2.0, n_nu=11, progress=False, store=tmp_path / "m.zarr")
    with pytest.raises(StoreError, match="a store of a regime map, not of a sweep"):
        load_sweep(tmp_path / "m.zarr")


def test_another_job_is_told_by_what_differs(base: Any, tmp_path: Path) -> None:
    store = tmp_path / "s.zarr"
    sweep(base, _grid(), progress=False, store=store, block_points=80)
    with pytest.raises(StoreError) as err:
        sweep(base, _grid(), progress=False, store=store, rtol=1e-9)
    msg = str(err.value)
    assert "tolerances [1e-10, " in msg and "there, [1e-09, " in msg and " here" in msg, msg
    with pytest.raises(StoreError) as err:
        sweep(base, _grid(n_v0=25), progress=False, store=store)
    assert "other values of grid.v0 (24 values there, 25 values here)" in str(err.value)
    with pytest.raises(StoreError) as err:
        sweep(ss.zv_parameters(b="10 s/m"), _grid(), progress=False, store=store)
    assert "base " in str(err.value) and " there, " in str(err.value)
    # a mark edited by hand: said, not an AttributeError
    meta = store / "zarr.json"
    doc = json.loads(meta.read_text())
    doc["attributes"]["stickslip_store"] = "edited"
    meta.write_text(json.dumps(doc))
    with pytest.raises(StoreError, match=r"its mark .* is damaged"):
        sweep(base, _grid(), progress=False, store=store)
    # a file's name, and a file where the folder should be
    with pytest.raises(StoreError, match=r"a store is a Zarr folder, not a \.nc file"):
        sweep(base, _grid(), progress=False, store=tmp_path / "x.nc")
    assert not (tmp_path / "x.nc").exists()
    (tmp_path / "afile").write_text("")
    with pytest.raises(StoreError, match="afile is a file, not a folder"):
        sweep(base, _grid(), progress=False, store=tmp_path / "afile" / "s.zarr")


def test_the_gpu_backend_is_part_of_a_sweeps_identity(base: Any) -> None:
    """The GPU's cycles agree with the CPU's to 1e-9, not bit for bit: a store is one or the other."""
    import dataclasses

    from stickslip.dynamics.sweep import SweepPlan

    vals = np.array([5.0, 10.0])
    plan = SweepPlan(
        base, {"v0": (vals, "um/s", "driving velocity")}, {"v0": vals * 1e-6}, 1e-10, 1e-12, 1e5, 1e-8
    )
    cpu = plan.layout((2,))
    gpu = dataclasses.replace(plan, backend="cuda").layout((2,))
    assert "backend" not in cpu.identity and gpu.identity["backend"] == "cuda"
    assert cpu.identity_digest != gpu.identity_digest


def test_progress_from_python(base: Any, tmp_path: Path) -> None:
    seen: list[ProgressInfo] = []
    sweep(base, _grid(), progress=seen.append, store=tmp_path / "s.zarr", block_points=40)
    assert len(seen) == 6
    assert [p.blocks for p in seen] == list(range(1, 7))
    assert seen[-1].points == seen[-1].total_points == 240 and seen[-1].fraction == 1.0
    assert all(p.rate > 0 for p in seen) and seen[-1].eta == 0.0
    assert np.isfinite(seen[0].eta)
    # in process, without a store, too
    seen.clear()
    sweep(base, _grid(), progress=seen.append)
    assert seen and seen[-1].points == 240


# ----------------------------------------------------------------------------- full and read-only disks


@contextlib.contextmanager
def tmpfs(path: Path, size: str, *extra: str) -> Any:
    path.mkdir(parents=True, exist_ok=True)
    opts = ",".join([f"size={size}", *extra])
    res = subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", str(path)], capture_output=True)
    if res.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here (needs root): {res.stderr.decode().strip()}")
    try:
        yield path
    finally:
        subprocess.run(["umount", "-l", str(path)], capture_output=True)


def test_full_disk_is_a_clear_error_and_earlier_blocks_stay(
    base: Any, reference: xr.Dataset, tmp_path: Path
) -> None:
    # measure what the finished store takes on a tmpfs, then give it a third of that
    with tmpfs(tmp_path / "big", "64m") as big:
        sweep(base, _grid(), progress=False, store=big / "s.zarr", block_points=10)
        used = os.statvfs(big).f_bsize * (os.statvfs(big).f_blocks - os.statvfs(big).f_bfree)
    with tmpfs(tmp_path / "small", f"{used // 3}") as small:
        store = small / "s.zarr"
        with pytest.raises(StoreError) as err:
            sweep(base, _grid(), progress=False, store=store, block_points=10)
        msg = str(err.value)
        assert "the disk is full" in msg and "intact" in msg and "\n" not in msg
        done = [int(n) for n in os.listdir(store / ".stickslip-done") if n.isdigit()]
        assert 0 < len(done) < 24
        # the blocks written before the disk filled are right
        partial = xr.open_zarr(store, chunks=None)
        rows = sorted(done)
        for b in rows:
            sl = slice(b, b + 1)  # blocks of 10 points: one v0 row each
            assert np.array_equal(
                partial["amplitude"].values[sl], reference["amplitude"].values[sl], equal_nan=True
            )
        # room again: the same command completes and only the missing blocks run
        subprocess.run(["mount", "-o", "remount,size=64m", str(small)], check=True)
        ds = sweep(base, _grid(), progress=False, store=store, block_points=10)
        assert run_of(ds)["reused"] == len(done) and run_of(ds)["computed"] == 24 - len(done)
        assert_same(reference, load_sweep(store))


def test_read_only_disk_is_a_clear_error(base: Any, tmp_path: Path) -> None:
    with tmpfs(tmp_path / "ro", "4m", "ro") as ro:
        with pytest.raises(StoreError, match=r"cannot create it: the file system is read-only"):
            sweep(base, _grid(), progress=False, store=ro / "s.zarr")


def test_a_refused_marker_write_keeps_the_earlier_blocks(
    base: Any, reference: xr.Dataset, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Without root (no tmpfs): the disk refuses the fourth block's marker."""
    import stickslip.scale.store as st

    calls = {"n": 0}
    real = os.replace

    def failing(src: Any, dst: Any) -> None:
        if st.DONE in str(dst):
            calls["n"] += 1
            if calls["n"] == 4:
                raise OSError(errno.ENOSPC, "No space left on device")
        real(src, dst)

    monkeypatch.setattr(st.os, "replace", failing)
    store = tmp_path / "s.zarr"
    with pytest.raises(
        StoreError, match=r"block 3 of 6: the disk is full; the blocks written before are intact"
    ):
        sweep(base, _grid(), progress=False, store=store, block_points=40)
    monkeypatch.setattr(st.os, "replace", real)
    assert sorted(os.listdir(store / st.DONE)) == ["000000000", "000000001", "000000002"]
    ds = sweep(base, _grid(), progress=False, store=store)
    assert run_of(ds)["computed"] == 3
    assert_same(reference, load_sweep(store))


# ----------------------------------------------------------------------------- killing the client


def _sweep_cmd(store: Path, n_v0: int, n_k: int, block_points: int = 40) -> list[str]:
    return [
        sys.executable, "-m", "stickslip", "sweep", "--preset", "zv",
        "--v0", "5 um/s..1000 um/s", "--num", str(n_v0), "--log",
        "--stiffness", ",".join(f"{k:.6g} N/m" for k in np.linspace(30, 90, n_k)),
        "--store", str(store), "--block-points", str(block_points), "--quiet",
    ]  # fmt: skip


@pytest.mark.slow
def test_sigkill_of_the_client_then_the_same_command_completes(base: Any, tmp_path: Path) -> None:
    n_v0, n_k = 120, 60  # 7200 points in 120 blocks of one v0 row
    store = tmp_path / "s.zarr"
    cmd = _sweep_cmd(store, n_v0, n_k, block_points=60)
    proc = subprocess.Popen(cmd, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    done_dir = store / ".stickslip-done"
    deadline = time.monotonic() + 240
    killed_at = 0
    while time.monotonic() < deadline and proc.poll() is None:
        if done_dir.is_dir():
            # finished markers only: a marker being written has a temporary name
            killed_at = len([n for n in os.listdir(done_dir) if n.isdigit()])
            if killed_at >= 5:
                proc.send_signal(signal.SIGKILL)
                break
        time.sleep(0.002)
    proc.wait(timeout=60)
    assert proc.returncode == -signal.SIGKILL, "the sweep ended before it could be killed"
    before = len([n for n in os.listdir(done_dir) if n.isdigit()])
    assert 5 <= before < 120
    res = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr
    m = re.search(r"store: (\d+) blocks, (\d+) already there, (\d+) computed", res.stderr)
    assert m, res.stderr
    blocks, reused, computed = (int(x) for x in m.groups())
    assert blocks == 120 and reused == before and computed == 120 - before
    grid = {
        "v0": ss.Q_(np.geomspace(5, 1000, n_v0), "um/s"),
        "stiffness": [f"{k:.6g} N/m" for k in np.linspace(30, 90, n_k)],
    }
    # the command's base set-up is the grid's first point: all else is the same
    ref, got = sweep(base, grid, progress=False), load_sweep(store)
    assert ref.attrs.pop("base_parameters") != got.attrs.pop("base_parameters")
    assert_same(ref, got)


# ----------------------------------------------------------------------------- a LocalCluster


@pytest.fixture(scope="module")
def client() -> Any:
    import logging

    from distributed import Client

    from stickslip.scale.backend import local_cluster

    cluster = local_cluster(2, numba_threads=1, log_level=logging.CRITICAL)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def _signatures() -> int:
    from stickslip.laws import WeakeningLaw

    return len(WeakeningLaw(c=3.8).kernel.engine.attractor_rows.signatures)


def test_cluster_equals_in_process_and_compiles_once_per_worker(
    base: Any, reference: xr.Dataset, client: Any
) -> None:
    ds = sweep(base, _grid(), progress=False, scheduler=client, block_points=20)  # 12 tasks
    assert_same(reference, ds)
    # one compiled specialisation of the engine per worker process, however many tasks it ran
    assert set(client.run(_signatures).values()) == {1}


@pytest.mark.slow
def test_sigkill_of_a_worker_mid_sweep(base: Any, reference: xr.Dataset, client: Any, tmp_path: Path) -> None:
    pids = client.run(os.getpid)
    victim = sorted(pids.values())[0]
    killed: list[int] = []

    def kill_after_first(info: ProgressInfo) -> None:
        if not killed:
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

    store = tmp_path / "s.zarr"
    ds = sweep(base, _grid(), progress=kill_after_first, scheduler=client, store=store, block_points=10)
    assert killed and victim not in client.run(os.getpid).values()
    assert run_of(ds)["computed"] == 24
    assert_same(reference, load_sweep(store))
    # and without a store: the results come back over the network
    victim = sorted(client.run(os.getpid).values())[-1]
    killed.clear()
    assert_same(reference, sweep(base, _grid(), progress=kill_after_first, scheduler=client, block_points=10))
    assert killed


@pytest.mark.slow
def test_workers_option_starts_a_local_cluster(base: Any, tmp_path: Path) -> None:
    out = tmp_path / "s.nc"
    res = subprocess.run(
        [*_sweep_cmd(tmp_path / "s.zarr", 24, 10, 40), "--workers", "2", "--out", str(out), "--no-plot"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=600,
    )
    assert res.returncode == 0, res.stderr
    assert "local-cluster (2 workers)" in res.stderr
    grid = {
        "v0": ss.Q_(np.geomspace(5, 1000, 24), "um/s"),
        "stiffness": [f"{k:.6g} N/m" for k in np.linspace(30, 90, 10)],
    }
    ref = sweep(base, grid, progress=False)
    got = load_sweep(out)
    for key in ("stickslip_version", "base_parameters"):  # the command's base: the grid's first point
        ref.attrs.pop(key)
        got.attrs.pop(key)
    assert_same(ref, got)


# ------------------------------------------------------------------- regime maps and chain ensembles


@pytest.mark.slow
def test_regime_map_through_the_store_and_the_cluster(client: Any, tmp_path: Path) -> None:
    law = WeakeningLaw(c=3.8, p=0.3)
    args = (law, "p", [0.1, 0.3, 0.6], 0.05, 2.0)
    ref = regime_map(*args, n_nu=41, progress=False)
    store = tmp_path / "m.zarr"
    got = regime_map(*args, n_nu=41, progress=False, store=store, scheduler=client)
    assert run_of(got)["blocks"] == 3 and run_of(got)["computed"] == 3
    assert_same(ref, got)
    os.remove(store / ".stickslip-done" / "000000001")
    again = regime_map(*args, n_nu=41, progress=False, store=store)
    assert run_of(again)["reused"] == 2 and run_of(again)["computed"] == 1
    assert_same(ref, again)
    with pytest.raises(StoreError, match="holds another job"):
        regime_map(law, "p", [0.1, 0.3], 0.05, 2.0, n_nu=41, progress=False, store=store)


def test_forced_bifurcation_diagram_through_the_store_and_the_cluster(client: Any, tmp_path: Path) -> None:
    """A forced oscillator's bifurcation diagram (3 blocks of omega) on the cluster into a store,
    resumed after one block's record is lost, equals the in-process one bit for bit."""
    from stickslip.forced import ForcedSystem
    from stickslip.forced.diagram import bifurcation_diagram

    system = ForcedSystem(WeakeningLaw(c=3.0), omega=1.0, q=0.5, nu0=0.3, delta=0.05)
    omegas = np.linspace(0.6, 2.4, 150)
    kw: dict[str, Any] = dict(transient=20, record=8, lyapunov=True, progress=False)
    ref = bifurcation_diagram(system, omegas, **kw)
    store = tmp_path / "f.zarr"
    got = bifurcation_diagram(system, omegas, **kw, store=store, scheduler=client)
    assert run_of(got)["blocks"] == 3 and run_of(got)["computed"] == 3
    for name in ("s", "w", "lyapunov", "stops_per_period", "status"):
        assert np.array_equal(ref[name].values, got[name].values, equal_nan=True), name
    os.remove(store / ".stickslip-done" / "000000001")
    again = bifurcation_diagram(system, omegas, **kw, store=store)
    assert run_of(again)["reused"] == 2 and run_of(again)["computed"] == 1
    assert np.array_equal(ref["s"].values, again["s"].values)
    with pytest.raises(StoreError, match="holds another job"):
        bifurcation_diagram(system, omegas[:-1], **kw, store=store)


def test_chain_ensemble_through_the_store_and_the_cluster(
    client: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    params = ChainParameters(6, WeakeningLaw(c=3.0, p=0.0), 0.01, 2.0)
    kw: dict[str, Any] = dict(threshold_spread=0.1, progress=False)
    ref = chain_ensemble(params, 60, [1, 2, 3], **kw)
    assert (ref["events"].values == 60).all() and (ref["status"].values == 0).all()
    assert len(set(ref["mean_moment"].values.tolist())) == 3  # the seeds differ
    store = tmp_path / "e.zarr"
    got = chain_ensemble(params, 60, [1, 2, 3], store=store, scheduler=client, **kw)
    assert_same(ref, got)
    catalogs = sorted(n for n in os.listdir(store / "catalogs") if not n.startswith("."))
    assert catalogs == ["seed-1.nc", "seed-2.nc", "seed-3.nc"]
    os.remove(store / ".stickslip-done" / "000000002")
    again = chain_ensemble(params, 60, [1, 2, 3], store=store, **kw)
    assert run_of(again)["computed"] == 1
    assert_same(ref, again)
    # members' b-values of other statistics are another job: resuming would mix the two
    monkeypatch.setattr(ensemble_module, "STATISTICS_VERSION", STATISTICS_VERSION + 1)
    v = STATISTICS_VERSION
    old = f"holds another job: .*statistics of version {v}, with statistics {v} there, {v + 1} here;"
    with pytest.raises(StoreError, match=old):
        chain_ensemble(params, 60, [1, 2, 3], store=store, **kw)


def _cli(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "stickslip", *args], capture_output=True, text=True, cwd=cwd, timeout=600
    )


@pytest.mark.slow
def test_cli_regime_map_and_chain_ensemble_resume_from_their_stores(tmp_path: Path) -> None:
    law = ["--law", "weakening", "--c", "3.8", "--p", "0.3"]
    rm = [*law, "--nu-min", "0.05", "--nu-max", "2", "--n", "31", "--map", "p=0.1..0.6", "--map-n", "3"]
    first = _cli("regimes", *rm, "--json", "--store", "m.zarr", cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    assert "store: 3 blocks, 0 already there, 3 computed" in first.stderr
    again = _cli("regimes", *rm, "--json", "--store", "m.zarr", cwd=tmp_path)
    assert "store: 3 blocks, 3 already there, 0 computed" in again.stderr
    assert json.loads(first.stdout)["criterion"] == json.loads(again.stdout)["criterion"]
    ch = ["--law", "weakening", "--c", "3", "--p", "0", "--nu", "0.01", "--ell", "2", "--blocks", "6"]
    ens = [*ch, "--events", "40", "--threshold-spread", "0.1", "--seeds", "1..3", "--json", "--quiet"]
    res = _cli("chain", *ens, "--store", "e.zarr", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["members"] == 3 and out["events"] == 120
    errs = [m["b_value_err"] for m in out["per_member"] if m["b_value_err"] is not None]
    assert out["b_value_err_mean"] == (pytest.approx(float(np.mean(errs))) if errs else None)
    assert [m["seed"] for m in out["per_member"]] == [1, 2, 3]
    # one member's catalogue matches a single run of that seed
    single = _cli(
        "chain", *ch, "--events", "40", "--threshold-spread", "0.1", "--seed", "2", "--json", cwd=tmp_path
    )
    assert json.loads(single.stdout)["mean_moment"] == out["per_member"][1]["mean_moment"]
    res2 = _cli("chain", *ens, "--store", "e.zarr", cwd=tmp_path)
    assert "3 already there, 0 computed" in res2.stderr and json.loads(res2.stdout) == out
    bad = _cli("chain", *ch, "--events", "40", "--store", "e.zarr", cwd=tmp_path)
    assert bad.returncode != 0 and "--seeds" in bad.stderr


def test_a_bad_scheduler_address_is_refused_before_anything_is_made(base: Any, tmp_path: Path) -> None:
    """A bad scheduler address is refused by name before anything is made: 'nonsense' (not only
    "missing port number in address"), and a port outside 1..65535 (which would wait 30 s in
    silence, after making the store)."""
    from click.testing import CliRunner

    from stickslip.cli import main
    from stickslip.scale.backend import check_scheduler

    for address, why in (
        ("nonsense", "missing port number"),
        ("localhost:99999", "port 99999 is not a port"),
    ):
        with pytest.raises(ValueError, match=f"scheduler='{address}': .*{why}"):
            sweep(base, _grid(), progress=False, store=tmp_path / "s.zarr", scheduler=address)
        assert not (tmp_path / "s.zarr").exists()
        res = CliRunner().invoke(
            main, ["sweep", "--preset", "zv", "--v0", "5 um/s..10 um/s", "--scheduler", address, "--quiet"]
        )
        assert res.exit_code == 2 and "Invalid value for '--scheduler'" in res.output and why in res.output
    check_scheduler("tcp://10.0.0.1:8786")
    check_scheduler("[::1]:8786")
    check_scheduler(None)


def test_an_unreachable_scheduler_makes_no_store(
    base: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A well-formed address where no scheduler answers is reached first, before any store is
    made: the job fails and leaves nothing behind (no empty store)."""
    from stickslip.scale import backend

    monkeypatch.setattr(backend, "CONNECT_TIMEOUT", "2s")
    with socket.socket() as sock:  # a port nobody listens on
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    with pytest.raises(ValueError, match=f"scheduler='{address}': cannot reach a Dask scheduler there"):
        sweep(base, _grid(), progress=False, store=tmp_path / "s.zarr", scheduler=address)
    assert not (tmp_path / "s.zarr").exists()


def test_stores_of_other_jobs_copies_and_lost_chunks_are_said(
    base: Any, reference: xr.Dataset, tmp_path: Path
) -> None:
    """Another job's store of another shape is not called damaged;
    a store copied without its hidden markers still loads; a lost chunk of a finished store
    is said, not a KeyError; a lost coordinate is said by load_sweep too; a long value's
    difference is shown where it is."""
    law = WeakeningLaw(c=3.8, p=0.3)
    regime_map(law, "p", [0.1, 0.3], 0.05, 2.0, n_nu=11, progress=False, store=tmp_path / "m.zarr")
    with pytest.raises(StoreError, match=r"holds another job: a regime map .*; this one is a sweep"):
        sweep(base, {"v0": ss.Q_([5.0, 10.0], "um/s")}, progress=False, store=tmp_path / "m.zarr")
    store = tmp_path / "s.zarr"
    sweep(base, _grid(), progress=False, store=store, block_points=40)
    copy = tmp_path / "copy.zarr"
    shutil.copytree(store, copy, ignore=shutil.ignore_patterns(".stickslip-done"))
    assert_same(reference, load_sweep(copy))
    part = load_sweep(copy, partial=True)
    assert part["computed"].values.all() and part.attrs["partial"] == "240 of 240 points computed"
    shutil.rmtree(copy / "regime" / "c" / "1")
    with pytest.raises(StoreError, match=r"unfinished \(200 of 240"):
        load_sweep(copy)
    (store / "v0" / "c" / "0").unlink()
    with pytest.raises(StoreError, match="its coordinates v0 are damaged: run its command again"):
        load_sweep(store)
    sweep(base, _grid(), progress=False, store=store)  # which writes them again
    assert_same(reference, load_sweep(store))
    with pytest.raises(StoreError) as err:
        sweep(dataclasses.replace(base, load=ss.Q_(200, "mN")), _grid(), progress=False, store=store)
    assert "load=<Quantity(" in str(err.value) and "200" in str(err.value), str(err.value)


@pytest.mark.slow
def test_an_ensemble_member_is_taken_by_one_run_at_a_time(tmp_path: Path) -> None:
    """Two runs of one ensemble share its store: a member's lock makes the second wait, so that
    it never takes the first's open catalogue (HDF5-locked: unreadable) for a broken one."""
    from stickslip.chains.ensemble import _member_lock

    catalog = str(tmp_path / "seed-1.nc")
    code = (
        "import sys, time\n"
        "from stickslip.chains.ensemble import _member_lock\n"
        "print('ready', flush=True)\n"
        "t = time.monotonic()\n"
        f"with _member_lock({catalog!r}):\n"
        "    print(round(time.monotonic() - t, 1))\n"
    )
    with _member_lock(catalog):
        other = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
        assert other.stdout is not None
        assert other.stdout.readline().strip() == "ready"  # imported: now it asks for the lock
        time.sleep(1.5)
        assert other.poll() is None  # still waiting
    out, _ = other.communicate(timeout=60)
    assert float(out) >= 1.0


def test_a_cluster_without_workers_is_said_not_waited_on(base: Any, tmp_path: Path, monkeypatch: Any) -> None:
    """A job on a scheduler without workers (or whose workers have all died) stops after
    NO_WORKERS_TIMEOUT seconds with one message that says what to do, rather than waiting
    without a word; the store stays resumable (nothing in it is damaged)."""
    import logging

    from distributed import LocalCluster

    from stickslip.scale import backend

    monkeypatch.setattr(backend, "NO_WORKERS_TIMEOUT", 3.0)
    with LocalCluster(
        n_workers=0, processes=False, dashboard_address=None, silence_logs=logging.CRITICAL
    ) as cl:
        t0 = time.monotonic()
        with pytest.raises(RuntimeError, match=r"has had no workers for 3 s: start some"):
            sweep(
                base, _grid(4, 2), progress=False, store=tmp_path / "s.zarr", scheduler=cl.scheduler_address
            )
        assert time.monotonic() - t0 < 30.0
    finished = sweep(base, _grid(4, 2), progress=False, store=tmp_path / "s.zarr")
    assert_same(sweep(base, _grid(4, 2), progress=False), load_sweep(tmp_path / "s.zarr"))
    assert finished.sizes == {"v0": 4, "stiffness": 2}


@pytest.mark.slow
def test_a_scheduler_lost_mid_sweep_is_one_error_line(tmp_path: Path) -> None:
    """SIGKILL of the scheduler mid-sweep gives one Error: line that says what was kept and how
    to go on, not 81 lines of traceback (FutureCancelledError, scheduler-connection-lost); the
    store is resumable."""
    import signal
    import subprocess
    import sys

    dask = str(Path(sys.executable).parent / "dask")
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    sched = subprocess.Popen(
        [dask, "scheduler", "--port", "0", "--no-dashboard", "--scheduler-file", str(tmp_path / "s.json")],
        **quiet,
    )
    worker = None
    try:
        for _ in range(600):
            if (tmp_path / "s.json").exists() and (tmp_path / "s.json").read_text().strip():
                break
            time.sleep(0.1)
        address = json.loads((tmp_path / "s.json").read_text())["address"]
        worker = subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--no-dashboard"], **quiet)
        args = ["sweep", "--nu", "0.001..3", "--c", "1..10", "--p", "0.02", "--num", "300", "--block-points"]
        args += ["3000", "--store", "k.zarr", "--scheduler", address, "--quiet", "--no-plot"]
        proc = subprocess.Popen(
            [sys.executable, "-m", "stickslip", *args],
            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        done = tmp_path / "k.zarr" / ".stickslip-done"
        for _ in range(1800):
            if done.exists() and any(done.iterdir()):
                break
            time.sleep(0.1)
        sched.send_signal(signal.SIGKILL)
        _, err = proc.communicate(timeout=300)
    finally:
        for p in (sched, worker):
            if p is not None:
                p.kill()
                p.wait()
    assert proc.returncode == 1 and "Traceback" not in err, err[-2000:]
    errors = [ln for ln in err.splitlines() if ln.startswith("Error:")]
    assert len(errors) == 1 and "was lost mid-job" in errors[0], err[-2000:]
    assert "the blocks finished are kept in the store" in errors[0]
    kept = len(list(done.iterdir()))
    assert 1 <= kept < 30  # 30 blocks of 3000 points
