"""The CUDA backend: the CPU engine compiled for a GPU, checked in numba's CUDA simulator.

The simulator runs the kernel thread after thread, with the engine as Python
(``NUMBA_ENABLE_CUDASIM=1``, ``NUMBA_DISABLE_JIT=1``: set at numba's import, hence
the subprocesses); its results are compared with the compiled CPU engine's in
this process. Tests that need a real GPU skip where there is none.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import xarray as xr

from stickslip import DimensionlessParameters
from stickslip.core import cuda as core_cuda
from stickslip.core import engine
from stickslip.core.api import run_attractors
from stickslip.dynamics.sweep import sweep
from stickslip.laws import CubicLaw, ExpressionLaw, WeakeningLaw

needs_numba_cuda = pytest.mark.skipif(
    importlib.util.find_spec("numba_cuda") is None,
    reason='numba-cuda is not installed (pip install "stickslip[test]" brings it)',
)
SIM = {**os.environ, "NUMBA_ENABLE_CUDASIM": "1", "NUMBA_DISABLE_JIT": "1"}
NO_SIM = {k: v for k, v in os.environ.items() if k not in ("NUMBA_ENABLE_CUDASIM", "NUMBA_DISABLE_JIT")}

# a grid per law, reaching stick-slip with pure slip (F1), steady sliding (F2, cubic)
GRIDS = {
    "F1": ["--law", "weakening", "--c", "3.8", "--nu", "0.001..20"],
    "F2": ["--law", "weakening", "--c", "3.8", "--p", "0.5", "--nu", "0.01..5"],
    "cubic": ["--law", "cubic", "--alpha", "1.2", "--gamma", "0.3", "--nu", "0.01..3"],
    "expression": ["--law", "expr", "--f", "1/(1 + c*w) + 0.02*w", "--param", "c=3.8", "--nu", "0.001..20"],
    "table": ["--law", "table", "--table", "mu_v.csv", "--preset", "zv", "--v0", "5 um/s..20 mm/s"],
}


_SLOW_SIMULATED = {(law, "simulator") for law in ("table", "expression", "F2", "cubic")}


def _stickslip(args: list[str], env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "stickslip", *args], env=env, cwd=cwd, capture_output=True, text=True,
        timeout=600,
    )  # fmt: skip


# the laws on a real GPU; in CI's simulator F1 (the simulator runs the kernel in Python:
# 13-26 s of CI's two cores a law), the others in the slow set
_SWEEP_CASES = [
    pytest.param(law, target, marks=pytest.mark.slow if (law, target) in _SLOW_SIMULATED else ())
    for law in GRIDS
    for target in ("simulator", "gpu")
]


@needs_numba_cuda
@pytest.mark.parametrize(("law", "target"), _SWEEP_CASES)
def test_sweep_on_cuda_equals_the_cpu_sweep(law: str, target: str, tmp_path: Path) -> None:
    """In the simulator to 1e-9 (CI); on a real GPU, where there is one, to 1e-8 (fused multiply-adds)."""
    if target == "gpu":
        ok, why = core_cuda.cuda_status()
        if not ok or core_cuda.simulator():
            pytest.skip(f"no CUDA device here: {why}")
    env, rtol = (SIM, 1e-9) if target == "simulator" else (NO_SIM, 1e-8)
    common = [*GRIDS[law], "--log", "--num", "7", "--no-plot", "--quiet"]
    v = np.linspace(0.0, 50.0, 600)  # mm/s, a measured law's table: the paper's F1 for zv
    (tmp_path / "mu_v.csv").write_text(
        "velocity [mm/s],friction coefficient [1]\n"
        + "".join(f"{float(x)!r},{0.46 / (1 + 160 * float(x) * 1e-3)!r}\n" for x in v)
    )
    cpu = _stickslip(["sweep", *common, "--out", "cpu.nc"], NO_SIM, tmp_path)
    assert cpu.returncode == 0, cpu.stderr
    gpu = _stickslip(["sweep", *common, "--out", "cuda.nc", "--backend", "cuda"], env, tmp_path)
    assert gpu.returncode == 0, gpu.stderr
    a = xr.open_dataset(tmp_path / "cpu.nc")
    b = xr.open_dataset(tmp_path / "cuda.nc")
    assert set(a.data_vars) == set(b.data_vars) and len(a.data_vars) >= 10
    for name in a.data_vars:
        x, y = a[name].values, b[name].values
        if x.dtype.kind == "f":
            # the time at rest is the period less the slip time: to 1e-9 of the period
            floor = {"stick_time": rtol * float(np.nanmax(a.period.values)), "stick_fraction": rtol}
            tol = {"rtol": rtol, "atol": floor.get(name, 0.0)}
            np.testing.assert_allclose(y, x, **tol, equal_nan=True, err_msg=name)
        else:
            np.testing.assert_array_equal(y, x, err_msg=name)
    assert len(set(np.asarray(a.regime.values).tolist())) == (1 if law == "table" else 2)
    a.close()
    b.close()


# numba's simulator runs every copy and launch at once, whatever the stream. A GPU does not:
# a copy or a launch on a stream runs later, in the stream's order, and the host sees its
# work only once it has waited for the stream. These streams keep their copies and
# launches until they are waited for, so a result read, or a buffer reused, before its
# stream has finished reads stale numbers here too.
_DEFERRED_STREAMS = """
from numba import cuda
from numba.cuda.simulator import kernel as sim_kernel
from numba.cuda.simulator.cudadrv import devicearray as sim_array

class DeferredStream:
    def __init__(self):
        self.queue = []
    def synchronize(self):
        while self.queue:
            self.queue.pop(0)()

def deferred(copy):
    def on_stream(self, ary=None, stream=0):
        if isinstance(stream, DeferredStream):
            stream.queue.append(lambda: copy(self, ary))
            return ary
        return copy(self, ary)
    return on_stream

sim_array.FakeCUDAArray.copy_to_host = deferred(sim_array.FakeCUDAArray.copy_to_host)
sim_array.FakeCUDAArray.copy_to_device = deferred(sim_array.FakeCUDAArray.copy_to_device)
run_now = sim_kernel.FakeCUDAKernel.__call__

def configure(self, config):
    stream = config[2] if len(config) > 2 else 0
    def launch(*args):
        def run():
            self.grid_dim, self.block_dim = sim_kernel.normalize_kernel_dimensions(*config[:2])
            run_now(self, *args)
        if isinstance(stream, DeferredStream):
            stream.queue.append(run)
        else:
            run()
    return launch

sim_kernel.FakeCUDAKernel.__getitem__ = configure
cuda.stream = DeferredStream
"""

_ROWS = """
import json, sys
import numpy as np
if sys.argv[5] == "deferred":
    exec(DEFERRED)
from stickslip.core import cuda
from stickslip.core.api import run_attractors
# three launches of four blocks for 40 rows: every index path (one launch with ``one-launch``)
cuda.SIMULATOR_BATCH = 64 if "one-launch" in sys.argv[7:] else 16
cuda.THREADS_PER_BLOCK = 4
# the threads take rows from a queue: two blocks of four (the simulator's one multiprocessor)
cuda.PERSISTENT = "persistent" in sys.argv[7:]
# each launch's rows sorted by their keys, read and written through that order on the GPU
cuda.SORT_ROWS = "unsorted" not in sys.argv[7:]
sorted_launches = []
key = cuda.balance_key
cuda.balance_key = lambda *a: sorted_launches.append(1) or key(*a)
on_device = cuda.sort_on_device  # the launch's rows sorted on the GPU (DEVICE_SORT)
cuda.sort_on_device = lambda *a: sorted_launches.append(1) or on_device(*a)
from stickslip.laws import WeakeningLaw
rng = np.random.default_rng(7)
n = 40
nu = 10 ** rng.uniform(-4, 1.3, n)
c = rng.uniform(0.5, 30.0, n)
start = sys.argv[4] == "start"  # from a start of each row's own, not breakaway
s0, w0 = rng.uniform(-0.5, 0.9, n), rng.uniform(0.0, 2.0, n)
out = run_attractors(WeakeningLaw(c=1.0).kernel, c[:, None], nu, s0=s0 if start else None,
                     w0=w0 if start else None, from_breakaway=not start, rtol=1e-10, atol=1e-12,
                     max_slip_time=float(sys.argv[1]), conv_tol=1e-8, max_steps=int(sys.argv[2]),
                     backend=sys.argv[3],
                     fields=sys.argv[6].split(",") if len(sys.argv) > 6 and sys.argv[6] != "all" else None)
print(json.dumps({"raw": out.raw.tolist(), "fields": out.fields, "sorted": len(sorted_launches)}))
""".replace("DEFERRED", repr(_DEFERRED_STREAMS))


def _cycle_columns() -> list[int]:
    """The engine's output columns that describe the measured cycle (see the comment below)."""
    ended = [engine.O_TRANSIENT, engine.O_S, engine.O_W, engine.O_T, engine.O_NSTEP, engine.O_NREJECT]
    return [k for k in range(engine.NOUT) if k not in ended]


@needs_numba_cuda
@pytest.mark.parametrize(
    ("max_slip_time", "max_steps", "start", "streams"),
    [
        pytest.param(1e4, 2_000_000, "breakaway", "at-once", marks=pytest.mark.slow),
        (100.0, 40, "breakaway", "at-once"),
        pytest.param(1e4, 2_000_000, "start", "at-once", marks=pytest.mark.slow),
        (1e4, 2_000_000, "start", "deferred"),
    ],
)
def test_rows_and_statuses_equal_the_cpu_engine(
    max_slip_time: float, max_steps: int, start: str, streams: str
) -> None:
    """Random rows in three launches, with failures in the second set.

    The third starts each row at its own ``(s0, w0)``, which then go to the GPU row by row;
    the fourth does so on streams that run their copies and launches only when waited for,
    as a GPU's run behind the host (:data:`_DEFERRED_STREAMS`).
    """
    run = subprocess.run(
        [sys.executable, "-c", _ROWS, str(max_slip_time), str(max_steps), "cuda", start, streams],
        env=SIM, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["sorted"] == 3  # three launches, each sorted
    gpu = np.array(got["raw"], dtype=float)
    rng = np.random.default_rng(7)
    nu = 10 ** rng.uniform(-4, 1.3, 40)
    c = rng.uniform(0.5, 30.0, 40)
    s0, w0 = rng.uniform(-0.5, 0.9, 40), rng.uniform(0.0, 2.0, 40)
    own = start == "start"
    cpu = run_attractors(
        WeakeningLaw(c=1.0).kernel, c[:, None], nu, s0=s0 if own else None, w0=w0 if own else None,
        from_breakaway=not own, rtol=1e-10, atol=1e-12, max_slip_time=max_slip_time, conv_tol=1e-8,
        max_steps=max_steps,
    )  # fmt: skip
    if own:  # the rows start where they are: the time to reach the attractor says whether they did
        k = engine.O_TRANSIENT
        np.testing.assert_allclose(gpu[:, k], cpu.raw[:, k], rtol=1e-7, equal_nan=True)  # 1.4e-9 seen
        assert not np.allclose(cpu.raw[:, engine.O_T], run_attractors(
            WeakeningLaw(c=1.0).kernel, c[:, None], nu, from_breakaway=True, rtol=1e-10, atol=1e-12,
            max_slip_time=max_slip_time, conv_tol=1e-8, max_steps=max_steps,
        ).raw[:, engine.O_T], equal_nan=True)  # fmt: skip
    np.testing.assert_array_equal(gpu[:, 0], cpu.status)
    np.testing.assert_array_equal(gpu[:, 1], cpu.regime)
    # the measured cycle and the works, where the run finished; not the state and time where
    # it ended nor its step counts: the engine as Python (in the simulator) differs from the
    # compiled one in the last bits, as a GPU's fused multiply-adds would, and where that flips
    # a step's acceptance the run ends elsewhere on the same attractor (or, failing at a step
    # budget, after the same number of other steps)
    cycle = _cycle_columns()
    ok = cpu.status == 0
    got, want = gpu[ok][:, cycle], cpu.raw[ok][:, cycle]
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-300, equal_nan=True)
    codes = set(cpu.status.tolist())
    regimes = set(cpu.regime.tolist())
    if max_steps > 40:
        assert codes == {0} and regimes == {0, 1}  # stick-slip and pure slip, all ok
    else:
        assert len(codes) == 3 and len(regimes) == 3  # two ways to fail beside ok


def _cpu_rows_from_breakaway() -> Any:
    """The CPU engine's rows for :data:`_ROWS`' 40 random rows, from breakaway."""
    rng = np.random.default_rng(7)
    nu = 10 ** rng.uniform(-4, 1.3, 40)
    c = rng.uniform(0.5, 30.0, 40)
    return run_attractors(
        WeakeningLaw(c=1.0).kernel, c[:, None], nu, from_breakaway=True, rtol=1e-10, atol=1e-12,
        max_slip_time=1e4, conv_tol=1e-8,
    )  # fmt: skip


@needs_numba_cuda
@pytest.mark.parametrize("streams", ["at-once", pytest.param("deferred", marks=pytest.mark.slow)])
def test_only_the_fields_kept_cross_back_from_the_gpu(streams: str) -> None:
    """``fields=``: a kernel on the GPU gathers the kept columns side by side, on the launch's
    stream, before they are copied back; they equal the CPU engine's columns (three launches).
    On deferred streams a gather or a copy out of order would read zeros or stale rows."""
    fields = ["status", "regime", "amplitude", "s_stop", "fnu"]
    run = subprocess.run(
        [sys.executable, "-c", _ROWS, "1e4", "2000000", "cuda", "breakaway", streams, ",".join(fields)],
        env=SIM, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["fields"] == fields  # the layout's order
    gpu = np.array(got["raw"], dtype=float)
    assert gpu.shape == (40, len(fields))
    cpu = _cpu_rows_from_breakaway()
    want = np.column_stack([getattr(cpu, x) for x in fields])
    np.testing.assert_array_equal(gpu[:, :2], want[:, :2])
    np.testing.assert_allclose(gpu[:, 2:], want[:, 2:], rtol=1e-9)
    assert set(cpu.regime.tolist()) == {0, 1}


@needs_numba_cuda
@pytest.mark.parametrize(
    ("variant", "sorted_launches"), [pytest.param("persistent", 3, marks=pytest.mark.slow), ("unsorted", 0)]
)
def test_in_the_simulator_the_kernels_variants_give_the_cpu_engines_rows(
    variant: str, sorted_launches: int
) -> None:
    """On deferred streams, the rows equal the CPU engine's as the default kernel's do.

    ``persistent``: eight threads a launch take its 16 rows from a queue (an atomic counter),
    each launch's rows sorted. ``unsorted`` (SORT_ROWS = False, the default): the kernel runs
    the launch's rows in their order (the other simulator tests of random rows sort them:
    SORT_ROWS = True in :data:`_ROWS`).
    """
    run = subprocess.run(
        [sys.executable, "-c", _ROWS, "1e4", "2000000", "cuda", "breakaway", "deferred", "all", variant],
        env=SIM, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["sorted"] == sorted_launches  # the launches whose rows were sorted on the GPU
    gpu = np.array(got["raw"], dtype=float)
    cpu = _cpu_rows_from_breakaway()
    np.testing.assert_array_equal(gpu[:, 0], cpu.status)
    np.testing.assert_array_equal(gpu[:, 1], cpu.regime)
    cycle = _cycle_columns()
    np.testing.assert_allclose(gpu[:, cycle], cpu.raw[:, cycle], rtol=1e-9, atol=1e-300, equal_nan=True)


_PERMUTED = """
import json
import numpy as np
from stickslip.core import cuda, engine
from stickslip.laws import WeakeningLaw
one = WeakeningLaw(c=1.0).kernel.engine.attractor_ws
c = np.array([[1.0], [3.0], [6.0]])
nu = np.array([0.01, 0.5, 2.0])
got = {}
for name, cols in {"reversed": list(range(engine.NOUT))[::-1], "twice": [2, 0, 2]}.items():
    out = np.empty((3, len(cols)))
    cuda.run_attractors_cuda(one, np.zeros(3, np.int64), c, nu, np.zeros(1), np.zeros(1), True, 1e-10, 1e-12,
                             1e4, 1e-8, False, 2_000_000, out, None, np.array(cols))
    got[name] = out.tolist()
print(json.dumps(got))
"""


@needs_numba_cuda
def test_columns_in_any_order_come_back_in_that_order() -> None:
    """The GPU path takes the engine's columns in the caller's order (all 21 reversed, one twice)."""
    run = subprocess.run(
        [sys.executable, "-c", _PERMUTED], env=SIM, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    cpu = run_attractors(
        WeakeningLaw(c=1.0).kernel, np.array([[1.0], [3.0], [6.0]]), np.array([0.01, 0.5, 2.0]),
        from_breakaway=True, rtol=1e-10, atol=1e-12, max_slip_time=1e4, conv_tol=1e-8,
    ).raw  # fmt: skip
    cycle = _cycle_columns()
    rev = np.array(got["reversed"])[:, ::-1]
    np.testing.assert_allclose(rev[:, cycle], cpu[:, cycle], rtol=1e-9, equal_nan=True)
    np.testing.assert_allclose(np.array(got["twice"]), cpu[:, [2, 0, 2]], rtol=1e-9)


_STOPPED = """
import json
import numpy as np
exec(DEFERRED)
from stickslip.core import cuda
from stickslip.core.api import run_attractors
from stickslip.laws import WeakeningLaw
cuda.SIMULATOR_BATCH = 4
cuda.THREADS_PER_BLOCK = 2
law = WeakeningLaw(c=1.0).kernel
kw = dict(from_breakaway=True, rtol=1e-10, atol=1e-12, max_slip_time=1e4, conv_tol=1e-8, backend="cuda")
c = np.linspace(1.0, 6.0, 12)[:, None]

def stop(rows):
    raise KeyboardInterrupt  # Ctrl-C in the progress bar, after the first launch's results

try:
    run_attractors(law, c, np.full(12, 0.002), on_rows=stop, **kw)
except KeyboardInterrupt:
    pass
counted = []
out = run_attractors(law, c, np.full(12, 0.02), on_rows=counted.append, **kw)
kept = len(cuda._SLOTS)
cuda.release_buffers()
again = run_attractors(law, c[:5], np.full(5, 0.02), **kw)  # new buffers, for 4 rows a launch
print(json.dumps({"amplitude": out.amplitude.tolist(), "counted": counted, "kept": kept,
                  "again": again.amplitude.tolist()}))
""".replace("DEFERRED", repr(_DEFERRED_STREAMS))


@needs_numba_cuda
def test_a_gpu_call_stopped_half_way_leaves_nothing_to_the_next() -> None:
    """The launches a stopped call left on its streams are not taken for the next call's results;
    a call's buffers are kept, and can be released."""
    run = subprocess.run(
        [sys.executable, "-c", _STOPPED], env=SIM, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["counted"] == [4, 4, 4]  # in launch order
    c = np.linspace(1.0, 6.0, 12)[:, None]
    kw = {"from_breakaway": True, "rtol": 1e-10, "atol": 1e-12, "max_slip_time": 1e4, "conv_tol": 1e-8}
    want = run_attractors(WeakeningLaw(c=1.0).kernel, c, np.full(12, 0.02), **kw).amplitude
    stopped = run_attractors(WeakeningLaw(c=1.0).kernel, c, np.full(12, 0.002), **kw).amplitude
    assert np.abs(stopped / want - 1).min() > 1e-3  # the stopped call's numbers would show
    np.testing.assert_allclose(got["amplitude"], want, rtol=1e-9)
    # the buffers are kept for the next call (one set per stream), released on demand, and made
    # again by the next call
    assert got["kept"] == core_cuda.STREAMS
    np.testing.assert_allclose(got["again"], want[:5], rtol=1e-9)


def test_backends_are_named_and_checked() -> None:
    p = DimensionlessParameters(0.01, WeakeningLaw(c=3.8))
    with pytest.raises(ValueError, match="backend='gpu': expected one of 'cpu', 'cuda', 'auto'"):
        sweep(p, {"nu": [0.01, 0.02]}, backend="gpu")
    assert core_cuda.resolve_backend("cpu") == "cpu"
    ok, why = core_cuda.cuda_status()
    assert core_cuda.resolve_backend("auto") == ("cuda" if ok else "cpu")
    if ok:
        pytest.skip(f"a CUDA device is usable here ({why}): no error to check")
    assert "\n" not in why and why
    with pytest.raises(core_cuda.CudaUnavailableError, match="backend='cuda': "):
        sweep(p, {"nu": [0.01, 0.02]}, backend="cuda")


def test_command_line_without_a_gpu_says_why_in_one_line(tmp_path: Path) -> None:
    ok, why = core_cuda.cuda_status()
    if ok:
        pytest.skip(f"a CUDA device is usable here ({why})")
    run = _stickslip(
        ["sweep", *GRIDS["F1"], "--num", "3", "--backend", "cuda", "--out", "x.nc"], NO_SIM, tmp_path
    )
    assert run.returncode == 1
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: backend='cuda': "), run.stderr
    assert not (tmp_path / "x.nc").exists()


def test_rows_are_balanced_by_law_parameters_then_nu(monkeypatch: pytest.MonkeyPatch) -> None:
    lp = np.array([[3.0, 0.0], [1.0, 0.0], [3.0, 0.0], [1.0, 1.0]])
    nu = np.array([0.2, 0.5, 0.1, 0.1])
    assert core_cuda.balance_order(lp, nu) is None  # off by default (docs/gpu.md: measured)
    monkeypatch.setattr(core_cuda, "SORT_ROWS", True)
    order = core_cuda.balance_order(lp, nu)
    assert order is not None and order.tolist() == [1, 3, 2, 0]
    assert core_cuda.balance_order(np.ones((3, 2)), np.full(3, 0.1)) is None  # nothing varies
    # a million rows of F1 (c and nu span two and four decades: both binned by their logs):
    # sorted by c to a bin's width, and within a bin of c by nu to a bin's width
    rng = np.random.default_rng(3)
    c, nu = rng.uniform(0.5, 50.0, 1_000_000), 10 ** rng.uniform(-5, -1, 1_000_000)
    order = core_cuda.balance_order(np.column_stack([c, np.zeros_like(c)]), nu)
    assert order is not None and np.array_equal(np.sort(order), np.arange(c.size))
    logc, lognu = np.log(c[order]), np.log(nu[order])
    width_c, width_nu = np.ptp(logc) / 255, np.ptp(lognu) / 255
    assert np.all(np.diff(logc) > -width_c * 1.0001)
    bins = ((logc - logc.min()) * (255 / np.ptp(logc))).astype(np.uint16)  # the code's own binning
    assert np.all(np.diff(bins) >= 0)
    same = bins[1:] == bins[:-1]
    assert np.all(np.diff(lognu)[same] > -width_nu * 1.0001)
    bins_nu = ((lognu - lognu.min()) * (255 / np.ptp(lognu))).astype(np.uint16)
    assert np.all(np.diff(bins_nu.astype(int))[same] >= 0)
    # a launch's rows are keyed on the bins of all the rows: the keys of a slice are the
    # slice of the keys (a launch's own ranges would bin its rows differently)
    lp = np.column_stack([c, np.zeros_like(c)])
    bins_all = core_cuda.balance_bins(lp, nu)
    assert bins_all is not None and [b[:2] for b in bins_all] == [(0, True), (-1, True)]
    keys = core_cuda.balance_key(bins_all, lp, nu)
    part = slice(1000, 5000)
    assert np.array_equal(core_cuda.balance_key(bins_all, lp[part], nu[part]), keys[part])
    assert not np.array_equal(
        core_cuda.balance_key(core_cuda.balance_bins(lp[part], nu[part]), lp[part], nu[part]), keys[part]
    )  # type: ignore[arg-type]


@pytest.mark.parametrize(("launch", "start"), [(1 << 20, "breakaway"), (3000, "breakaway"), (3000, "own")])
def test_on_a_real_gpu_the_cycles_equal_the_cpu_engine(
    launch: int, start: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """In one launch, and in seven on the two streams in turn (the pipeline on a real GPU); the
    third with each row's own start (copied launch by launch) and the works (``diag``)."""
    ok, why = core_cuda.cuda_status()
    if not ok or core_cuda.simulator():
        pytest.skip(f"no CUDA device here: {why}")
    monkeypatch.setattr(core_cuda, "MAX_BATCH", launch)
    rng = np.random.default_rng(1)
    n = 20_000
    nu = 10 ** rng.uniform(-5, -1, n)
    c = rng.uniform(0.5, 50.0, n)
    own = start == "own"
    s0, w0 = (rng.uniform(-0.5, 0.9, n), rng.uniform(0.0, 0.5, n)) if own else (None, None)
    laws = [
        (WeakeningLaw(c=1.0), c[:, None]),
        (CubicLaw(alpha=1.2, gamma=0.3), np.tile([1.2, 0.3], (n, 1))),
        (ExpressionLaw("1/(1 + c*w)", c=1.0), c[:, None]),
    ]
    for law, lp in laws:
        kw = dict(from_breakaway=not own, rtol=1e-9, atol=1e-12, max_slip_time=1e4, conv_tol=1e-8, diag=own)
        cpu = run_attractors(law.kernel, lp, nu, s0, w0, **kw)
        counted: list[int] = []
        gpu = run_attractors(law.kernel, lp, nu, s0, w0, backend="cuda", on_rows=counted.append, **kw)
        assert counted == [min(launch, n - lo) for lo in range(0, n, launch)]
        assert core_cuda.TIMES["span"] >= core_cuda.TIMES["kernel"] > 0.0
        np.testing.assert_array_equal(gpu.status, cpu.status)
        np.testing.assert_array_equal(gpu.regime, cpu.regime)
        cols = _cycle_columns()  # a GPU fuses multiply-adds: the last bits differ
        ok_rows = cpu.status == 0
        got, want = gpu.raw[ok_rows][:, cols], cpu.raw[ok_rows][:, cols]
        np.testing.assert_allclose(got, want, rtol=1e-8, atol=1e-300, equal_nan=True)
    core_cuda.release_buffers()


_STORE = """
import json, sys
import numpy as np
from stickslip import DimensionlessParameters
from stickslip.dynamics.sweep import load_sweep, sweep
from stickslip.laws import WeakeningLaw
p = DimensionlessParameters(0.01, WeakeningLaw(c=3.8))
sweep(p, {"nu": np.geomspace(1e-3, 20, 5), "c": [2.0, 3.8]}, store=sys.argv[1], backend="cuda",
      block_points=3, progress=False)
ds = load_sweep(sys.argv[1])
print(json.dumps({k: ds[k].values.tolist() for k in ("amplitude", "period", "regime")}))
"""


@needs_numba_cuda
def test_a_sweep_on_cuda_streams_to_a_store(tmp_path: Path) -> None:
    store = tmp_path / "map.zarr"
    run = subprocess.run(
        [sys.executable, "-c", _STORE, str(store)], env=SIM, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    p = DimensionlessParameters(0.01, WeakeningLaw(c=3.8))
    want = sweep(p, {"nu": np.geomspace(1e-3, 20, 5), "c": [2.0, 3.8]}, progress=False)
    np.testing.assert_allclose(got["amplitude"], want.amplitude.values, rtol=1e-9)
    np.testing.assert_allclose(got["period"], want.period.values, rtol=1e-9)
    regimes = [[str(v) for v in row] for row in want.regime.values]
    assert [[str(v) for v in row] for row in got["regime"]] == regimes


_CLUSTER = """
import json
import time
import numpy as np
from distributed import Client, LocalCluster
from stickslip import DimensionlessParameters
from stickslip.core import cuda
from stickslip.dynamics.sweep import sweep
from stickslip.laws import WeakeningLaw


def slots():
    return len(cuda._SLOTS)


def one_call():
    from stickslip.core.api import run_attractors
    run_attractors(1, [3.8], [0.01], from_breakaway=True, rtol=1e-9, atol=1e-12, max_slip_time=1e4,
                   conv_tol=1e-8, backend="cuda")
    return len(cuda._SLOTS)


with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
    with Client(cluster) as client:
        kept = client.submit(one_call, pure=False).result()  # a worker keeps its buffers between calls
        p = DimensionlessParameters(0.01, WeakeningLaw(c=3.8))
        ds = sweep(p, {"nu": np.geomspace(1e-3, 20, 4)}, backend="cuda", scheduler=client, progress=False)
        for _ in range(100):  # the clean-up is sent, not waited for
            after = list(client.run(slots).values())
            if after == [0]:
                break
            time.sleep(0.1)
        print(json.dumps({"kept": kept, "after": after, "amplitude": ds.amplitude.values.tolist()}))
"""


@pytest.mark.slow
@needs_numba_cuda
def test_a_sweep_on_a_cluster_frees_its_workers_gpu_buffers() -> None:
    """A worker of a user's cluster keeps the buffers between a sweep's blocks, not after the sweep."""
    run = subprocess.run(
        [sys.executable, "-c", _CLUSTER], env=SIM, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout.strip().splitlines()[-1])
    assert got["kept"] == core_cuda.STREAMS  # made on the worker, and kept after its call
    assert got["after"] == [0]  # ... until the sweep on its cluster ended
    p = DimensionlessParameters(0.01, WeakeningLaw(c=3.8))
    want = sweep(p, {"nu": np.geomspace(1e-3, 20, 4)}, progress=False)
    np.testing.assert_allclose(got["amplitude"], want.amplitude.values, rtol=1e-9)


def test_cleaning_up_skips_buffers_in_use() -> None:
    """The workers' clean-up does not wait for a GPU call running there (their event loop must not)."""
    with core_cuda._LOCK:
        assert core_cuda.release_idle_buffers() is False
    assert core_cuda.release_idle_buffers() is True


@pytest.mark.slow
@needs_numba_cuda
def test_a_table_too_long_for_the_gpu_is_refused_in_one_line(tmp_path: Path) -> None:
    v = np.linspace(0.0, 50.0, core_cuda.MAX_TABLE_ROWS + 100)  # mm/s
    (tmp_path / "mu_v.csv").write_text(
        "velocity [mm/s],friction coefficient [1]\n"
        + "".join(f"{float(x)!r},{0.46 / (1 + 160 * float(x) * 1e-3)!r}\n" for x in v)
    )
    args = [*GRIDS["table"], "--num", "3", "--backend", "cuda", "--out", "x.nc", "--no-plot"]
    run = _stickslip(["sweep", *args], SIM, tmp_path)
    assert run.returncode == 2, run.stderr
    assert f"a table of {v.size} rows: the GPU kernel holds at most" in run.stderr
    assert "Traceback" not in run.stderr


def test_a_table_is_held_once_so_1600_rows_fit_on_the_gpu() -> None:
    """One array of 40 bytes a piece, read by one function (ptxas: 1600 rows link, 1700 do not).

    Five arrays read by two functions held 88 bytes a row in a GPU's constant memory and
    stopped at 700 rows (``tools/cuda_ptx.py`` links the kernel for an H100 to check it).
    """
    import sys

    from stickslip import Q_
    from stickslip.laws import TabulatedLaw

    for rows, fits in ((core_cuda.MAX_TABLE_ROWS, True), (core_cuda.MAX_TABLE_ROWS + 1, False)):
        v = np.linspace(0.0, 0.05, rows)  # m/s
        kernel = TabulatedLaw(Q_(v, "m/s"), 0.46 / (1 + 160 * v)).spec.kernel()
        laws = sys.modules[kernel.engine.__name__.rsplit(".", 1)[0] + ".laws"]
        assert laws._TABLE.shape == (5 * (rows - 1),)  # the breaks and coefficients, interleaved
        assert [k for k in vars(laws) if k.startswith("_") and isinstance(getattr(laws, k), np.ndarray)] == [
            "_TABLE"
        ]
        if fits:
            core_cuda.check_kernel(kernel.engine.attractor_ws)
        else:
            with pytest.raises(
                ValueError, match=f"a table of {rows} rows: the GPU kernel holds at most 1600"
            ):
                core_cuda.check_kernel(kernel.engine.attractor_ws)
    assert core_cuda.MAX_TABLE_ROWS == 1600


def test_the_gpu_path_needs_no_host_memory_beyond_the_cpu_paths(monkeypatch: pytest.MonkeyPatch) -> None:
    """The rows are sorted on the GPU, launch by launch: no sorted copies of the rows or the results
    on the host. Memory just enough for the CPU path's rows lets the GPU path run too."""
    from stickslip.core import api, memory

    n = 1_000_000
    avail = int(n * api.BYTES_PER_ROW / memory.FRACTION) + 1
    monkeypatch.setattr(memory, "available_memory", lambda: avail)
    monkeypatch.setattr(core_cuda, "resolve_backend", lambda backend: "cuda")
    reached: list[int] = []
    monkeypatch.setattr(core_cuda, "run_attractors_cuda", lambda *a, **k: reached.append(a[3].size))
    law = WeakeningLaw(c=1.0).kernel
    kw = {"from_breakaway": True, "rtol": 1e-10, "atol": 1e-12, "max_slip_time": 1e4, "conv_tol": 1e-8}
    run_attractors(law, np.full((n, 1), 3.0), np.full(n, 0.5), backend="cuda", **kw)
    assert reached == [n]
    monkeypatch.setattr(memory, "available_memory", lambda: avail // 2)
    with pytest.raises(memory.MemoryRequestError, match="1000000 parameter sets needs about"):
        run_attractors(law, np.full((n, 1), 3.0), np.full(n, 0.5), backend="cuda", **kw)
    assert reached == [n]


_ROW_STACK = """
import numpy as np
if hasattr(np, "row_stack"):
    del np.row_stack  # as NumPy 2.5 has it
from numba.cuda.descriptor import cuda_target
from stickslip.core import cuda
try:
    cuda_target.typing_context.refresh()  # what the first kernel's compilation does
except AttributeError as exc:
    print("without the guard:", exc)
cuda._load_registries_without_row_stack()
cuda_target.typing_context.refresh()
print("with the guard: loaded; np.row_stack", hasattr(np, "row_stack"))
"""


@needs_numba_cuda
def test_numba_cuda_compiles_where_numpy_has_no_row_stack() -> None:
    """numba-cuda 0.30.4 failed every kernel on the GPU machine's NumPy 2.5.2 (seen on an H100)."""
    run = subprocess.run(
        [sys.executable, "-c", _ROW_STACK], env=NO_SIM, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr
    assert "without the guard: module 'numpy' has no attribute 'row_stack'" in run.stdout
    assert "with the guard: loaded; np.row_stack False" in run.stdout


def test_the_hosts_copy_out_of_a_launch_runs_in_threads_and_equals_one_copy(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """From COPY_THREADS_ROWS rows the results are copied out of pinned memory in slices, one a
    thread: the same rows as one copy, every row written; below it, one copy in the caller's thread."""
    import threading
    import time

    rng = np.random.default_rng(5)
    src = rng.random(((1 << 16) + 7, 5))
    names: set[str] = set()
    assign = core_cuda._assign

    def spy(dst: np.ndarray, part: np.ndarray) -> None:
        names.add(threading.current_thread().name)
        time.sleep(0.05)  # each slice holds its thread a while: the others go to other threads
        assign(dst, part)

    monkeypatch.setattr(core_cuda, "_assign", spy)
    monkeypatch.setattr(core_cuda.os, "cpu_count", lambda: 3)
    dst = np.full_like(src, np.nan)
    core_cuda.copy_rows(dst, src)
    assert np.array_equal(dst, src)
    assert len(names) >= 2 and all(x.startswith("stickslip-copy") for x in names)
    names.clear()
    small = np.full_like(src[:100], np.nan)
    core_cuda.copy_rows(small, src[:100])
    assert np.array_equal(small, src[:100]) and not names  # one copy, no thread


# ------------------------------------------------------------------------ the forced oscillator

_FORCED = """
import json, sys
import numpy as np
from stickslip.core.forced_api import forced_strobe
from stickslip.forced import ForcedSystem
from stickslip.laws import CoulombLaw, WeakeningLaw
law = {"weakening": WeakeningLaw(c=3.0), "coulomb": CoulombLaw(kinetic=0.7)}[sys.argv[1]]
system = ForcedSystem(law, omega=1.0, q=0.5, nu0=0.3, delta=0.05)
kernel, lp, fp = system.arrays()
fps = np.tile(fp, (5, 1))
fps[:, 2] = [0.8, 1.3, 1.55, 1.83, 2.3]
out, lyap, stats = forced_strobe(kernel, lp, fps, (0.0, 0.0), 3, 4, lyapunov=True, rtol=1e-10, atol=1e-12,
                                 backend=sys.argv[2])
print(json.dumps({"out": out.tolist(), "lyap": np.nan_to_num(lyap, neginf=-1e300).tolist(),
                  "stats": stats.tolist()}))
"""


@needs_numba_cuda
@pytest.mark.parametrize("law", ["weakening", pytest.param("coulomb", marks=pytest.mark.slow)])
def test_the_forced_diagrams_gpu_kernel_gives_the_cpu_rows(law: str) -> None:
    """The forced engine's per-row function compiled as the GPU kernel's (run in the simulator;
    on a real GPU where there is one): the sections, Lyapunov exponents and event counts of five
    forcing frequencies (stick, reversals, period doubling, chaos) equal the CPU's; in the
    simulator bit for bit (the same arithmetic), on a GPU to 1e-9 (its fused multiply-adds)."""
    ok, _ = core_cuda.cuda_status()
    targets = [("simulator", SIM)] + ([("gpu", NO_SIM)] if ok else [])
    # the CPU's rows in this process (its engine compiled once for the suite), as the script prints them
    printed: list[str] = []
    namespace = {"print": printed.append, "__name__": "cpu"}
    argv = sys.argv
    try:
        sys.argv = ["-c", law, "cpu"]
        exec(compile(_FORCED, "<forced>", "exec"), namespace)
    finally:
        sys.argv = argv
    cpu = json.loads(printed[0])
    for target, env in targets:
        run = subprocess.run(
            [sys.executable, "-c", _FORCED, law, "cuda"], env=env, capture_output=True, text=True, timeout=600
        )
        assert run.returncode == 0, run.stderr
        gpu = json.loads(run.stdout)
        for key in ("out", "lyap", "stats"):
            a, b = np.array(gpu[key], dtype=float), np.array(cpu[key], dtype=float)
            if target == "simulator":
                np.testing.assert_array_equal(a, b, err_msg=key)
            else:
                np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12, err_msg=key)


def test_a_forced_diagram_without_a_gpu_says_why_in_one_line(tmp_path: Path) -> None:
    ok, why = core_cuda.cuda_status()
    if ok:
        pytest.skip(f"a CUDA device is usable here ({why})")
    args = "forced --c 3 --nu 0.3 --q 0.5 --omega 1.5 --mode diagram --values 3 --backend cuda --out d"
    run = _stickslip(args.split(), NO_SIM, tmp_path)
    assert run.returncode == 1
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: backend='cuda': "), run.stderr
    assert not (tmp_path / "d").exists()


_DEVICE_SORT = """
import json
import numpy as np
from stickslip.core import cuda
cuda.SORT_ROWS = True
rng = np.random.default_rng(11)
n = 700  # three segments of the sort, the last one short
lp = np.column_stack([rng.choice([0.5, 2.0, 30.0], n), rng.uniform(0.0, 1.0, n), np.zeros(n)])
nu = 10 ** rng.uniform(-4, 1, n)
nu[::7] = nu[0]  # equal keys: their order must stay the callers'
bins = cuda.balance_bins(lp, nu)
print(json.dumps({"device": cuda.device_balance_order(lp, nu, bins).tolist(),
                  "host": cuda.balance_order(lp, nu, bins).tolist()}))
"""


@needs_numba_cuda
def test_the_device_sort_gives_the_hosts_order() -> None:
    """The GPU's counting sort of the balance keys (keys computed on the GPU, two stable passes of
    8 bits) orders 700 rows (three columns binned, equal keys among them) as the host's stable
    argsort does, in the simulator; on a real GPU where there is one."""
    ok, _ = core_cuda.cuda_status()
    for env in [SIM] + ([NO_SIM] if ok else []):
        run = subprocess.run(
            [sys.executable, "-c", _DEVICE_SORT], env=env, capture_output=True, text=True, timeout=600
        )
        assert run.returncode == 0, run.stderr
        got = json.loads(run.stdout)
        assert got["device"] == got["host"]
        assert sorted(got["host"]) == list(range(700)) and got["host"] != list(range(700))


@needs_numba_cuda
@pytest.mark.parametrize("order", ["sorted", pytest.param("unsorted", marks=pytest.mark.slow)])
def test_a_map_in_several_launches_equals_it_in_one_bit_for_bit(order: str) -> None:
    """40 rows in three launches of 16 (each sorted on the device, or not) give the results of one
    launch of all 40, bit for bit: the rows of a launch do not depend on which launch they are in."""
    runs = []
    args = ["1e4", "2000000", "cuda", "breakaway", "at-once", "all", order]
    for extra in ([], ["one-launch"]):
        run = subprocess.run(
            [sys.executable, "-c", _ROWS, *args, *extra],
            env=SIM, capture_output=True, text=True, timeout=600,
        )  # fmt: skip
        assert run.returncode == 0, run.stderr
        runs.append(json.loads(run.stdout))
    many, one = runs
    assert many["sorted"] == (3 if order == "sorted" else 0) and one["sorted"] == (
        1 if order == "sorted" else 0
    )
    assert np.array_equal(np.array(many["raw"]), np.array(one["raw"]), equal_nan=True)
