"""Compile the CUDA backend's kernel for a GPU on a machine without one (PTX for sm_90, an H100).

Checks that the engine's source compiles for CUDA as it is (numba-cuda's typing and
NVVM) and that the PTX assembles and links for the target (nvJitLink, ptxas), law by
law, the forced oscillator's kernel with each (and the small kernel that gathers the
columns a caller keeps), where no GPU can
run it: the simulator of the test suite runs the engine as Python and cannot tell.
(A table of 1700 rows does not link: its constant memory; the backend refuses tables
over ``MAX_TABLE_ROWS``, 1600, in one line.) Needs numba-cuda with the CUDA toolkit's
NVVM (``pip install "stickslip[cuda]"``). numba-cuda asks the current device for its
compute capability when it compiles a device function, even for PTX alone; with no
device that question is answered here with the target's.

With ``--max-registers 168,128,96`` F1's kernel is linked again under each cap
(``-maxrregcount``, what ``cuda.jit(max_registers=...)`` asks): the registers it
then uses and the bytes it spills to local memory, the static side of
``bench_gpu.py``'s register-limit rows.

Run: python tools/cuda_ptx.py [--cc 9.0] [--max-registers 168,128,96]
"""

from __future__ import annotations

import argparse
import re
import time

import numba.cuda.dispatcher as cuda_dispatcher
import numpy as np
from numba import types
from numba.cuda import compile_ptx

from stickslip import Q_
from stickslip.core import _cuda_kernel
from stickslip.laws import CubicLaw, ExpressionLaw, TabulatedLaw, WeakeningLaw


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cc", default="9.0", help="compute capability of the target (default 9.0, H100)")
    ap.add_argument(
        "--max-registers",
        default="",
        help="caps to link F1's kernel under (e.g. 168,128,96)",
    )
    args = ap.parse_args()
    cc = tuple(int(v) for v in args.cc.split("."))
    caps = [int(v) for v in args.max_registers.split(",") if v.strip()]

    class _Target:
        compute_capability = cc

    cuda_dispatcher.get_current_device = lambda: _Target()  # type: ignore[attr-defined]
    # C-contiguous arrays, as a launch passes them
    f1, f2, i1 = types.float64[::1], types.float64[:, ::1], types.int64[::1]
    f, i, b = types.float64, types.int64, types.boolean
    sig = (i, f2, f1, f1, f1, b, f, f, f, f, i, f2, f1, f2, i1, f2, i1, i1)
    v = np.linspace(0.0, 0.05, 600)  # m/s
    kernels = {
        "F1/F2 (weakening)": WeakeningLaw(c=1.0).kernel,
        "cubic": CubicLaw(alpha=1.2, gamma=0.3).kernel,
        "expression 1/(1 + c*w) + 0.02*w": ExpressionLaw("1/(1 + c*w) + 0.02*w", c=1.0).kernel,
        "table (600 velocities)": TabulatedLaw(Q_(v, "m/s"), 0.46 / (1 + 160 * v)).spec.kernel(),
    }
    for rows in (1600, 1700):  # MAX_TABLE_ROWS, and beyond
        v = np.linspace(0.0, 0.05, rows)
        kernels[f"table ({rows} velocities)"] = TabulatedLaw(Q_(v, "m/s"), 0.46 / (1 + 160 * v)).spec.kernel()
    t0 = time.perf_counter()
    ptx, _ = compile_ptx(_cuda_kernel._gather, (f2, i1, f2), cc=cc)
    print(
        f"{'gather (the kept columns)':34s} PTX for sm_{cc[0]}{cc[1]}: {len(ptx.splitlines()):6d} lines, "
        f"compiled in {time.perf_counter() - t0:.1f} s; {_link(ptx, cc)}"
    )
    # the rows' order on the device: keys, histograms, offsets, scatter
    i2 = types.int64[:, ::1]
    sorts = {
        "_balance_keys": (f2, f1, i1, i1, f1, f1, i, i1),
        "_digit_histograms": (i1, i1, i, i2),
        "_digit_offsets": (i2, i1),
        "_digit_scatter": (i1, i1, i, i2, i1),
    }
    for fname, fsig in sorts.items():
        t0 = time.perf_counter()
        sptx, _ = compile_ptx(getattr(_cuda_kernel, fname), fsig, cc=cc)
        print(
            f"{'sort: ' + fname:34s} PTX for sm_{cc[0]}{cc[1]}: {len(sptx.splitlines()):6d} lines, "
            f"compiled in {time.perf_counter() - t0:.1f} s; {_link(sptx, cc)}"
        )
    for name, kernel in kernels.items():
        kern = _cuda_kernel.make(kernel.engine.attractor_ws)
        t0 = time.perf_counter()
        ptx, _ = compile_ptx(kern.py_func, sig, cc=cc)
        lines = ptx.splitlines()
        fma = sum("fma.rn.f64" in ln for ln in lines)
        div = sum("div.rn.f64" in ln for ln in lines)
        print(
            f"{name:34s} PTX for sm_{cc[0]}{cc[1]}: {len(lines):6d} lines, {fma} fma.rn.f64, "
            f"{div} div.rn.f64, compiled in {time.perf_counter() - t0:.1f} s; {_link(ptx, cc)}"
        )
        # the forced oscillator's kernel (stroboscopic sections and Lyapunov exponents)
        forced = _cuda_kernel.make_forced(kernel.forced_engine.strobe_one)
        f3 = types.float64[:, :, ::1]
        fsig = (i, f2, f2, f, f2, i, i, f, f, i, b, f3, f2, f2, f1, f2)
        t0 = time.perf_counter()
        fptx, _ = compile_ptx(forced.py_func, fsig, cc=cc)
        print(
            f"{'':34s} the forced kernel: {len(fptx.splitlines())} lines, compiled in "
            f"{time.perf_counter() - t0:.1f} s; {_link(fptx, cc)}"
        )
        if name.startswith("F1"):
            queue = _cuda_kernel.make(kernel.engine.attractor_ws, persistent=True)
            qptx, _ = compile_ptx(queue.py_func, sig, cc=cc)
            print(f"{'':34s} the persistent kernel (rows from a queue): {_link(qptx, cc)}")
            for cap in caps:
                print(f"{'':34s} linked with at most {cap} registers: {_link(ptx, cc, cap)}")


def _link(ptx: str, cc: tuple[int, ...], max_registers: int = 0) -> str:
    """Assemble and link the PTX for the target with nvJitLink (ptxas): what a launch would do.

    Returns what ptxas reports: the registers a thread uses and, where it spills
    registers to local memory (under a cap), the bytes of spill stores and loads.
    """
    try:
        from cuda.bindings import nvjitlink
    except ImportError:
        return "not linked (no nvJitLink here)"
    options = [f"-arch=sm_{cc[0]}{cc[1]}", "-verbose"]
    if max_registers:
        options.append(f"-maxrregcount={max_registers}")
    handle = nvjitlink.create(len(options), options)
    data = ptx.encode()
    try:
        nvjitlink.add_data(handle, nvjitlink.InputType.PTX, data, len(data), "kernel")
        nvjitlink.complete(handle)
    except Exception:
        size = nvjitlink.get_error_log_size(handle)
        log = bytearray(size)
        nvjitlink.get_error_log(handle, log)
        lines = [ln.strip() for ln in log.decode(errors="replace").splitlines() if ln.strip()]
        errors = [ln for ln in lines if "error" in ln.lower()] or lines or ["(no log)"]
        return "does NOT link: " + errors[-1]
    size = nvjitlink.get_info_log_size(handle)
    log = bytearray(size)
    nvjitlink.get_info_log(handle, log)
    text = log.decode(errors="replace")
    used = re.findall(r"Used (\d+) registers", text)
    spills = [
        (int(a), int(b)) for a, b in re.findall(r"(\d+) bytes spill stores, (\d+) bytes spill loads", text)
    ]
    stores, loads = max((a for a, _ in spills), default=0), max((b for _, b in spills), default=0)
    spilled = (
        f", {stores} bytes spill stores, {loads} bytes spill loads" if stores or loads else ", no spills"
    )
    return f"links, {max(map(int, used))} registers a thread{spilled}" if used else "links"


if __name__ == "__main__":
    main()
