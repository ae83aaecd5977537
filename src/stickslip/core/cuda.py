"""The attractor kernel on a CUDA GPU (numbers only).

No second engine: the CUDA kernel calls the CPU engine's own per-row function,
:func:`stickslip.core.engine.attractor_ws` of the law's compiled package, which
numba-cuda compiles again as a device function from the same Python source
(with the law's functions, the DOP853 step, its dense output and the event
location under it). One GPU thread integrates one parameter set, with its own
work arrays (the per-row workspace of the CPU engine, one slice per thread);
the kernel allocates nothing.

Threads of a warp run in lockstep and wait for the slowest, and the cost of a
cycle grows with the steepness of the law: the rows are sorted by their law
parameters and ``nu`` before they go to the GPU (neighbouring threads then
integrate similar cycles), and the results are put back in the caller's order.

numba-cuda is optional (``pip install "stickslip[cuda]"``) and imported only
here, when a CUDA backend is asked for. With ``NUMBA_ENABLE_CUDASIM=1`` and
``NUMBA_DISABLE_JIT=1`` the same kernel runs in numba's CUDA simulator (the engine
as Python, thread after thread: small batches only), which is how the test suite
checks it without a GPU; ``tools/cuda_ptx.py`` compiles it for a GPU without one.
"""

from __future__ import annotations

import importlib.util
import os
import sys
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

from . import engine
from .laws import N_LAW_PARAMS

#: the backends of the attractor kernel
BACKENDS = ("cpu", "cuda", "auto")
#: threads per block of the kernel
THREADS_PER_BLOCK = 128
#: rows per launch in the simulator (it runs every thread in Python)
SIMULATOR_BATCH = 256
#: rows per launch at most on a GPU (a launch also sizes itself to the free memory)
MAX_BATCH = 1 << 22
#: host memory of one row beyond the CPU path's (:data:`stickslip.core.api.BYTES_PER_ROW`): the
#: rows' order, their sorted copies (law id, law parameters, nu, s0, w0) and the sorted result
HOST_BYTES_PER_ROW = 8 * (1 + 1 + N_LAW_PARAMS + 3 + engine.NOUT)


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
    ValueError
        For a backend that is not one of :data:`BACKENDS`.
    CudaUnavailableError
        For ``"cuda"`` where no CUDA device can run the kernel (said in one line).

    """
    if not isinstance(backend, str) or backend not in BACKENDS:
        raise ValueError(f"backend={backend!r}: expected one of {', '.join(map(repr, BACKENDS))}")
    if backend == "cpu":
        return "cpu"
    ok, why = cuda_status()
    if backend == "auto":
        return "cuda" if ok else "cpu"
    if not ok:
        raise CudaUnavailableError(f"backend='cuda': {why}")
    return "cuda"


_KERNELS: dict[int, Any] = {}


def attractor_kernel(one: Any) -> Any:
    """Return the CUDA kernel running the per-row function ``one`` (a law's ``engine.attractor_ws``)."""
    key = id(one)
    if key not in _KERNELS:
        from . import _cuda_kernel

        _KERNELS[key] = (one, _cuda_kernel.make(one))  # the function kept alive with it: ids stay unique
    return _KERNELS[key][1]


def balance_order(lp: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """Return the order of the rows for the GPU: sorted by law parameters, then ``nu``.

    A warp's 32 threads wait for the slowest; the number of steps of a cycle
    follows the law's parameters (the width of its boundary layers) and ``nu``,
    so neighbouring threads get similar rows.
    """
    keys = [nu] + [lp[:, j] for j in range(lp.shape[1] - 1, -1, -1)]
    return np.lexsort(keys)


def _batch_rows(n: int, width: int) -> int:
    """Rows per launch: what a quarter of the free device memory holds (bounded)."""
    if simulator():
        return SIMULATOR_BATCH
    from numba import cuda

    free, _total = cuda.current_context().get_memory_info()
    per_row = 8 * ((engine.N_STAGES_EXTENDED + 7 + 3) * width + engine.NTRK + engine.NOUT + 13 + 1)
    return int(max(THREADS_PER_BLOCK, min(MAX_BATCH, free // 4 // per_row, n)))


#: rows of a measured table a GPU kernel holds: the table goes to the GPU's constant
#: memory (64 KB a module), one copy per function that reads it (measured: 88 bytes a
#: row beside 2.5 KB; a 1000-row table fails to link for sm_90)
MAX_TABLE_ROWS = 700


def check_kernel(one: Any) -> None:
    """Refuse, in one line, a law whose engine cannot build for a GPU (a table too long).

    Raises
    ------
    ValueError
        For a tabulated law of more than :data:`MAX_TABLE_ROWS` rows.

    """
    package = sys.modules.get(getattr(one, "__module__", "").rsplit(".", 1)[0] + ".laws")
    breaks = getattr(package, "_X", None)
    if breaks is not None and len(breaks) > MAX_TABLE_ROWS:
        raise ValueError(
            f"a table of {len(breaks)} rows: the GPU kernel holds at most {MAX_TABLE_ROWS} "
            "(its constant memory); thin the table, or use backend='cpu'"
        )


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
) -> None:
    """Fill ``out`` (rows x ``engine.NOUT``) as the CPU engine's ``attractor_ws`` row by row, on the GPU.

    The arguments are those of the CPU kernels, already validated (see
    :func:`stickslip.core.api.run_attractors`).
    """
    from numba import cuda
    from numba.core.errors import NumbaPerformanceWarning

    check_kernel(one)
    kern = attractor_kernel(one)
    n = nu_a.shape[0]
    width = 4 if diag else 2
    order = balance_order(lp_a, nu_a)
    law_s, lp_s, nu_s = law_a[order], np.ascontiguousarray(lp_a[order]), nu_a[order]
    s0_s, w0_s = s0_a[order], w0_a[order]
    res = np.empty_like(out)
    batch = _batch_rows(n, width)
    empty = (np.empty(0), np.empty((0, 2)), np.empty(0, dtype=np.int64), np.empty((0, 3)))
    shared = tuple(cuda.to_device(a) for a in empty)
    for lo in range(0, n, batch):
        hi = min(n, lo + batch)
        b = hi - lo
        work = (
            cuda.device_array((b, engine.N_STAGES_EXTENDED, width)),
            cuda.device_array((b, 7, width)),
            cuda.device_array((b, width)),
            cuda.device_array((b, width)),
            cuda.device_array((b, width)),
            cuda.device_array((b, engine.NTRK)),
        )
        evn = cuda.to_device(np.zeros((b, 1), dtype=np.int64))
        d_out = cuda.device_array((b, engine.NOUT))
        blocks = -(-b // THREADS_PER_BLOCK)
        try:
            with warnings.catch_warnings():
                # a small grid under-uses the GPU: known (a small sweep, a store's last block)
                warnings.simplefilter("ignore", NumbaPerformanceWarning)
                kern[blocks, THREADS_PER_BLOCK](
                    cuda.to_device(law_s[lo:hi]), cuda.to_device(lp_s[lo:hi]), cuda.to_device(nu_s[lo:hi]),
                    cuda.to_device(s0_s[lo:hi]), cuda.to_device(w0_s[lo:hi]), bool(from_breakaway),
                    float(rtol), float(atol), float(t_max), float(conv_tol), int(max_steps), d_out,
                    *work, *shared, evn,
                )  # fmt: skip
            d_out.copy_to_host(res[lo:hi])  # into the result: no temporary of the batch's size
        except (ValueError, CudaUnavailableError):
            raise
        except Exception as exc:  # the toolkit, the driver, the GPU's memory: one line, not numba's trace
            raise CudaUnavailableError(
                f"backend='cuda': the GPU kernel failed ({type(exc).__name__}: {_first_line(exc)})"
            ) from exc
        if on_rows is not None:
            on_rows(b)
    out[order] = res
