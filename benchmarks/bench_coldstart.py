"""Cold start: the first command on a fresh install, compilation included, and what each kernel costs.

Each command runs in a new process with an empty numba cache (``NUMBA_CACHE_DIR``
and ``STICKSLIP_CACHE_DIR`` pointing to a new temporary folder), as on a fresh
install; then once more with the cache it left (the warm start). The compile
time of every kernel is taken from numba's own compile events: inclusive of the
kernels it calls and compiles first, and its own part (the rest).

Run: ``python benchmarks/bench_coldstart.py [--reproduce] [--warm-only]``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
from numba.core import event as ev
rec = ev.RecordingListener()
ev.register("numba:compile", rec)
from stickslip.cli import main
from click.testing import CliRunner
t_import = time.perf_counter() - t0
res = CliRunner().invoke(main, json.loads(sys.argv[1]))
stack, kernels, own = [], {}, {}
for ts, e in rec.buffer:  # compiles nest: a kernel compiles the kernels it calls first
    if e.is_start:
        stack.append([ts, 0.0])
        continue
    t0, inner = stack.pop()
    f = e.data["dispatcher"].py_func
    name = f.__module__ + "." + f.__qualname__
    kernels[name] = kernels.get(name, 0.0) + ts - t0
    own[name] = own.get(name, 0.0) + ts - t0 - inner
    if stack:
        stack[-1][1] += ts - t0
print(json.dumps({"exit": res.exit_code, "import": t_import, "kernels": kernels, "own": own,
                  "output": res.output[-300:]}))
"""

COMMANDS = {
    "cycle": ["cycle", "--nu", "0.001", "--law", "weakening", "--c", "3.8", "--json"],
}


def run(args: list[str], cache: str) -> tuple[float, dict]:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, STICKSLIP_CACHE_DIR=os.path.join(cache, "kernels"))
    started = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", CHILD, json.dumps(args)], env=env, capture_output=True, text=True, check=True
    )
    wall = time.perf_counter() - started
    return wall, json.loads(out.stdout.strip().splitlines()[-1])


def warm_start(repeat: int = 5) -> None:
    """Time the installed command as a user runs it, caches warm: the median of ``repeat`` runs.

    The reference is what any SciPy script pays before its first step: the interpreter
    and ``from scipy.integrate import solve_ivp``.
    """

    def median(cmd: list[str]) -> float:
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            subprocess.run(cmd, capture_output=True, check=True)
            times.append(time.perf_counter() - t0)
        return sorted(times)[len(times) // 2]

    cycle = [sys.executable, "-m", "stickslip", "cycle", "--law", "weakening", "--nu", "0.1", "--c", "3.8"]
    median(cycle)  # the caches of this checkout, warm
    scipy = median([sys.executable, "-c", "from scipy.integrate import solve_ivp"])
    rows = {
        "stickslip cycle --law weakening --nu 0.1 --c 3.8": median(cycle),
        "stickslip --help": median([sys.executable, "-m", "stickslip", "--help"]),
        "python -c 'import stickslip'": median([sys.executable, "-c", "import stickslip"]),
    }
    print(f"warm start, median of {repeat} runs (reference: python + import of solve_ivp, {scipy:.2f} s)")
    for name, t in rows.items():
        print(f"  {t:5.2f} s  ({t / scipy:4.1f} x the reference)  {name}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--reproduce", action="store_true", help="also time `stickslip reproduce --quick`")
    parser.add_argument("--top", type=int, default=8)
    parser.add_argument("--warm-only", action="store_true", help="only the installed command's warm start")
    a = parser.parse_args()
    warm_start()
    if a.warm_only:
        return
    cmds = dict(COMMANDS)
    if a.reproduce:
        cmds["reproduce"] = ["reproduce", "--out", tempfile.mkdtemp(prefix="stickslip-repro-")]
    for args in cmds.values():
        with tempfile.TemporaryDirectory(prefix="stickslip-numba-") as cache:
            cold, info = run(args, cache)
            warm, _ = run(args, cache)
        assert info["exit"] == 0, info["output"]
        ks = sorted(info["kernels"].items(), key=lambda kv: -kv[1])
        print(f"stickslip {' '.join(args)}")
        print(
            f"  cold (empty numba cache): {cold:6.2f} s   warm: {warm:5.2f} s   "
            f"import: {info['import']:.2f} s"
        )
        print(
            f"  kernels compiled: {len(ks)}, {sum(info['own'].values()):.2f} s in all; the largest "
            "(inclusive of the kernels they call and compile first, and their own part):"
        )
        for k, t in ks[: a.top]:
            print(f"    {t:6.2f} s  own {info['own'][k]:5.2f} s  {k}")


if __name__ == "__main__":
    main()
