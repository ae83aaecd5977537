"""Benchmark: where the time of a stick-slip cycle goes, stage by stage, on one thread.

Work: the steady stick-slip cycles of ``bench_cycles.py`` (law F1, ``nu`` log-uniform in
[1e-5, 1e-1], ``c`` uniform in [0.5, 50], rtol 1e-9), all on one thread, timed as:

1. the engine (``attractor_rows`` of the law's compiled engine, called directly): the
   time per cycle and per DOP853 step (accepted and rejected), everything included;
2. a stripped slip phase: the engine's own step (``step_sw``) and its step-size
   controller, from breakaway to the stop, no events, no dense output;
3. the step alone, in a chain where each step starts from the last one's result;
4. the same step returning only the last stage (not the 13 stages of each component that
   the dense output needs);
5. lanes: four parameter sets side by side in one thread, the step inlined four times
   into one function, each lane with its own step size, controller and stop (as in 2);
   and (5b) the bound: a step of law F1 with no branch, four lanes interleaved stage by
   stage, in chains as in 3;
6. the dense output (``dense_sw``) of a step, as an event needs it;
7. SciPy's ``solve_ivp(method="DOP853")`` on the same cycles (``scipy_cycle`` of
   ``bench_cycles.py``): its time per step.

The machine's hardware counters are not available (a KVM guest: ``perf stat`` reports
cycles and instructions as not supported), so the account is in wall time per stage.
Usage::

    python benchmarks/bench_step.py [--n 20000] [--n-scipy 50] [--seed 0]
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import math
import os
import platform
import re
import sys
import time
from types import ModuleType

import numpy as np
from numba import njit

from stickslip.core import engine as core_engine
from stickslip.laws import WeakeningLaw

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_cycles import ATOL, RTOL, scipy_cycle, workload


def best_of(f, repeat: int = 3) -> float:  # type: ignore[no-untyped-def]
    """The shortest of ``repeat`` timed calls (the machine is shared and noisy)."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def variant_last_stage(mod: ModuleType):  # type: ignore[no-untyped-def]
    """``step_sw`` of ``mod`` compiled from its own source, returning only the last stage."""
    src = inspect.getsource(mod.step_sw.py_func)
    src = src[src.index("def step_sw") :]
    head, _, _ = src.rpartition("return err, s1, w1,")
    src = head + "return err, s1, w1, (ks12,), (kw12,)\n"
    ns = dict(vars(mod))
    exec(compile(src, "<step_sw, last stage only>", "exec"), ns)
    return njit(fastmath={"reassoc", "contract"})(ns["step_sw"])


def step_instructions(mod: ModuleType) -> tuple[int, dict[str, int]]:
    """Count the machine instructions of ``step_sw`` of ``mod`` (compiled afresh: cached code
    cannot be inspected), in total and by kind."""
    fresh = njit(fastmath={"reassoc", "contract"})(mod.step_sw.py_func)
    fresh(0, (3.8,) + (0.0,) * 7, 0.01, 1, 1.0, 0.0, 0.01, 0.0, 0.01, RTOL, ATOL)
    asm = fresh.inspect_asm(fresh.signatures[0])
    kinds: dict[str, int] = {}
    inside = False
    for line in asm.splitlines():
        label = re.match(r"^(\S+):\s*$", line)
        if label and not label.group(1).startswith("."):
            # the function itself, not its Python wrapper or its C entry point
            name = label.group(1)
            inside = "step_sw" in name and not name.startswith(("_ZN7cpython", "cfunc"))
            continue
        if inside and line.startswith("\t") and not line.strip().startswith("."):
            op = line.split()[0]
            kinds[op] = kinds.get(op, 0) + 1
    return sum(kinds.values()), kinds


def interleaved_step(lanes: int):  # type: ignore[no-untyped-def]
    """A DOP853 step of ``lanes`` parameter sets of law F1 written stage by stage, the
    lanes interleaved within each stage, with no branch: ``s - 1/(1 + c w)`` without the
    engine's continuation for ``w < 0``, the division without numba's zero check.

    Not the engine's step (that one keeps the continuation past a stop): an upper bound of
    what lanes in lockstep could give if the step had no branch. Returns a compiled
    function of ``lanes`` tuples ``(c, nu, s, w, ks0, kw0, h)`` that returns ``lanes``
    tuples ``(err, s1, w1, ks12, kw12)``.
    """
    from stickslip.core import _dop853_tableau as T

    ns = T.N_STAGES

    def comb(coefs, pre, lane):  # type: ignore[no-untyped-def]
        terms = [f"{float(a)!r} * {pre}{j}_{lane}" for j, a in enumerate(coefs) if a != 0.0]
        return " + ".join(terms) if terms else "0.0"

    args = ", ".join(f"c_{k}, nu_{k}, s_{k}, w_{k}, ks0_{k}, kw0_{k}, h_{k}" for k in range(lanes))
    lines = [f"def step_lanes({args}, rtol, atol):"]
    for st in range(1, ns + 1):
        co = T.A[st, :st] if st < ns else T.B
        for k in range(lanes):
            lines.append(f"    ss_{k} = s_{k} + h_{k} * ({comb(co, 'ks', k)})")
            lines.append(f"    ww_{k} = w_{k} + h_{k} * ({comb(co, 'kw', k)})")
        for k in range(lanes):
            lines.append(f"    ks{st}_{k} = nu_{k} - ww_{k}")
            lines.append(f"    kw{st}_{k} = ss_{k} - 1.0 / (1.0 + c_{k} * ww_{k})")
    res = []
    for k in range(lanes):
        lines += [
            f"    sc_s = atol + rtol * max(abs(s_{k}), abs(ss_{k}))",
            f"    sc_w = atol + rtol * max(abs(w_{k}), abs(ww_{k}))",
            f"    e5s = ({comb(T.E5[:ns], 'ks', k)}) / sc_s",
            f"    e5w = ({comb(T.E5[:ns], 'kw', k)}) / sc_w",
            f"    e3s = ({comb(T.E3[:ns], 'ks', k)}) / sc_s",
            f"    e3w = ({comb(T.E3[:ns], 'kw', k)}) / sc_w",
            "    err5 = e5s * e5s + e5w * e5w",
            "    den = (err5 + 0.01 * (e3s * e3s + e3w * e3w)) * 2.0",
            f"    err_{k} = abs(h_{k}) * err5 / math.sqrt(den if den > 0.0 else 1.0)",
        ]
        res.append(f"(err_{k}, ss_{k}, ww_{k}, ks{ns}_{k}, kw{ns}_{k})")
    lines.append("    return (" + ", ".join(res) + ",)")
    env = {"math": math}
    exec(compile("\n".join(lines), f"<step of {lanes} lanes>", "exec"), env)
    return njit(fastmath={"reassoc", "contract"}, error_model="numpy")(env["step_lanes"])


def interleaved_chain(lanes: int):  # type: ignore[no-untyped-def]
    """A compiled chain of interleaved steps (as stage 3, ``lanes`` chains side by side)."""
    step = interleaved_step(lanes)
    lines = ["def chain(n, c, nu, h):"]
    for k in range(lanes):
        lines.append(f"    s_{k}, w_{k}, ks_{k}, kw_{k}, c_{k} = 1.0, 0.0, nu, 0.0, c * (1.0 + 0.01 * {k})")
    lines += ["    tot = 0.0", f"    for i in range(n // {lanes}):"]
    lines.append(
        "        r = step("
        + ", ".join(f"c_{k}, nu, s_{k}, w_{k}, ks_{k}, kw_{k}, h" for k in range(lanes))
        + ", RTOL, ATOL)"
    )
    for k in range(lanes):
        lines += [
            f"        tot += r[{k}][0]",
            f"        if (i & 31) == 0 or r[{k}][2] <= 0.0:",
            f"            s_{k}, w_{k}, ks_{k}, kw_{k} = 1.0, 0.0, nu, 0.0",
            "        else:",
            f"            s_{k}, w_{k}, ks_{k}, kw_{k} = r[{k}][1], r[{k}][2], r[{k}][3], r[{k}][4]",
        ]
    lines.append("    return tot")
    env = {"step": step, "RTOL": RTOL, "ATOL": ATOL}
    exec(compile("\n".join(lines), f"<chain of {lanes} lanes>", "exec"), env)
    return njit(env["chain"])


def drivers(mod: ModuleType, accel):  # type: ignore[no-untyped-def]
    """The compiled drivers of stages 2 to 6 for the step kernels of ``mod``."""
    step = mod.step_sw
    step_last = variant_last_stage(mod)
    step_inl = njit(inline="always", fastmath={"reassoc", "contract"})(mod.step_sw.py_func)
    dense = mod.dense_sw

    def chain_of(stepper):  # type: ignore[no-untyped-def]
        @njit
        def chain(n, c, nu, h):  # type: ignore[no-untyped-def]
            P = (c, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            s, w, ks0, kw0 = 1.0, 0.0, nu, accel(0, P, 1, 1.0, 0.0)
            tot = 0.0
            for i in range(n):
                err, s1, w1, ks, kw = stepper(0, P, nu, 1, s, w, ks0, kw0, h, RTOL, ATOL)
                tot += err
                if (i & 31) == 0 or w1 <= 0.0:
                    s, w, ks0, kw0 = 1.0, 0.0, nu, accel(0, P, 1, 1.0, 0.0)
                else:
                    s, w, ks0, kw0 = s1, w1, ks[-1], kw[-1]  # the derivative at the new state
            return tot

        return chain

    chain = chain_of(step)
    chain_last = chain_of(step_last)

    @njit
    def controller(err, h, rejected):  # type: ignore[no-untyped-def]
        if not (err <= 1.0):
            return h * max(0.333, 0.9 / math.sqrt(math.sqrt(math.sqrt(err)))), False
        f = 3.0 if err == 0.0 else min(3.0, 0.9 / math.sqrt(math.sqrt(math.sqrt(err))))
        if rejected:
            f = min(1.0, f)
        return h * f, True

    @njit
    def phases(c, nu, h0):  # type: ignore[no-untyped-def]
        steps = 0
        for r in range(c.shape[0]):
            P = (c[r], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            s, w, ks0, kw0, h, rej = 1.0, 0.0, nu[r], accel(0, P, 1, 1.0, 0.0), h0[r], False
            while True:
                err, s1, w1, ks, kw = step(0, P, nu[r], 1, s, w, ks0, kw0, h, RTOL, ATOL)
                steps += 1
                h_new, ok = controller(err, h, rej)
                rej = not ok
                h = h_new
                if ok:
                    if w1 <= 0.0:
                        break
                    s, w, ks0, kw0 = s1, w1, ks[12], kw[12]
        return steps

    @njit(inline="always")
    def one_lane(C, NU, S, W, KS0, KW0, H, k):  # type: ignore[no-untyped-def]
        P = (C[k], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        return step_inl(0, P, NU[k], 1, S[k], W[k], KS0[k], KW0[k], H[k], RTOL, ATOL)

    @njit(inline="always")
    def load_row(lane, r, c, nu, h0, ROW, C, NU, H, S, W, KS0, KW0, REJ):  # type: ignore[no-untyped-def]
        ROW[lane] = r
        C[lane] = c[r]
        NU[lane] = nu[r]
        H[lane] = h0[r]
        S[lane] = 1.0
        W[lane] = 0.0
        REJ[lane] = False
        KS0[lane] = nu[r]
        KW0[lane] = accel(0, (c[r], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0), 1, 1.0, 0.0)

    @njit
    def lanes(c, nu, h0):  # type: ignore[no-untyped-def]
        L = 4
        n = c.shape[0]
        S = np.ones(L)
        W = np.zeros(L)
        KS0 = np.empty(L)
        KW0 = np.empty(L)
        H = np.empty(L)
        REJ = np.zeros(L, dtype=np.bool_)
        ROW = np.full(L, -1)
        E = np.empty(L)
        S1 = np.empty(L)
        W1 = np.empty(L)
        K1 = np.empty(L)
        Q1 = np.empty(L)
        C = np.ones(L)
        NU = np.full(L, 0.1)
        KS0[:] = 0.1  # an idle lane steps a harmless system
        KW0[:] = 0.0
        H[:] = 1e-3
        nxt = 0
        live = 0
        for lane in range(L):
            if nxt < n:
                load_row(lane, nxt, c, nu, h0, ROW, C, NU, H, S, W, KS0, KW0, REJ)
                live += 1
                nxt += 1
        steps = 0
        while live > 0:
            e0, a0, b0, k0, q0 = one_lane(C, NU, S, W, KS0, KW0, H, 0)
            e1, a1, b1, k1, q1 = one_lane(C, NU, S, W, KS0, KW0, H, 1)
            e2, a2, b2, k2, q2 = one_lane(C, NU, S, W, KS0, KW0, H, 2)
            e3, a3, b3, k3, q3 = one_lane(C, NU, S, W, KS0, KW0, H, 3)
            E[0], S1[0], W1[0], K1[0], Q1[0] = e0, a0, b0, k0[12], q0[12]
            E[1], S1[1], W1[1], K1[1], Q1[1] = e1, a1, b1, k1[12], q1[12]
            E[2], S1[2], W1[2], K1[2], Q1[2] = e2, a2, b2, k2[12], q2[12]
            E[3], S1[3], W1[3], K1[3], Q1[3] = e3, a3, b3, k3[12], q3[12]
            for lane in range(L):
                if ROW[lane] < 0:
                    continue
                steps += 1
                h_new, ok = controller(E[lane], H[lane], REJ[lane])
                REJ[lane] = not ok
                H[lane] = h_new
                if not ok:
                    continue
                if W1[lane] > 0.0:
                    S[lane], W[lane], KS0[lane], KW0[lane] = S1[lane], W1[lane], K1[lane], Q1[lane]
                    continue
                # the lane's row is done: the next one
                if nxt < n:
                    load_row(lane, nxt, c, nu, h0, ROW, C, NU, H, S, W, KS0, KW0, REJ)
                    nxt += 1
                else:
                    ROW[lane] = -1
                    live -= 1
        return steps

    @njit
    def dense_calls(n, c, nu, h):  # type: ignore[no-untyped-def]
        P = (c, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        kw0 = accel(0, P, 1, 1.0, 0.0)
        _err, s1, w1, ks, kw = step(0, P, nu, 1, 1.0, 0.0, nu, kw0, h, RTOL, ATOL)
        tot = 0.0
        for i in range(n):
            cs, _cw, _a, _b = dense(0, P, nu, 1, 1.0, 0.0 * i, s1, w1, h, ks, kw)
            tot += cs[3]
        return tot

    return chain, chain_last, phases, lanes, dense_calls


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=20_000, help="parameter sets (cycles)")
    ap.add_argument("--n-scipy", type=int, default=50, help="parameter sets for SciPy")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()

    rng, nu, c = workload(args.n, args.seed)
    kernel = WeakeningLaw(c=1.0).kernel
    eng = kernel.engine
    unrolled = importlib.import_module(eng.__name__.rpartition(".")[0] + "._dop853_unrolled")
    laws_mod = importlib.import_module(eng.__name__.rpartition(".")[0] + ".laws")
    accel = laws_mod.slip_accel

    # 1. the engine, on this thread
    law = np.full(args.n, kernel.law_id, dtype=np.int64)
    lp = np.zeros((args.n, 8))
    lp[:, 0] = c
    out = np.empty((args.n, core_engine.NOUT))
    zeros = np.zeros(args.n)

    def engine() -> None:
        eng.attractor_rows(law, lp, nu, zeros, zeros, True, RTOL, ATOL, 1e4, 1e-8, False, 1_000_000, out)

    engine()
    ok = out[:, core_engine.O_STATUS] == core_engine.ST_OK
    stick = out[:, core_engine.O_REGIME] == core_engine.RG_STICK_SLIP
    assert np.all(ok & stick), "every row a steady stick-slip cycle"
    t_engine = best_of(engine)
    n_acc = out[:, core_engine.O_NSTEP].sum()
    n_rej = out[:, core_engine.O_NREJECT].sum()
    n_steps = n_acc + n_rej

    chain, chain_last, phases, lanes, dense_calls = drivers(unrolled, accel)
    # first step sizes: the engine's own initial guess is not reproduced here; a first step
    # of 1e-3 lets the controller find its way (the counts are printed)
    h0 = np.full(args.n, 1e-3)
    n_chain = 2_000_000
    for f in (chain, chain_last, dense_calls):
        f(64, 3.8, 0.01, 0.01)
    phases(c[:4], nu[:4], h0[:4])
    lanes(c[:8], nu[:8], h0[:8])
    t_chain = best_of(lambda: chain(n_chain, 3.8, 0.01, 0.01))
    t_last = best_of(lambda: chain_last(n_chain, 3.8, 0.01, 0.01))
    t_dense = best_of(lambda: dense_calls(n_chain // 4, 3.8, 0.01, 0.01))
    n_ph = phases(c, nu, h0)
    t_ph = best_of(lambda: phases(c, nu, h0))
    n_ln = lanes(c, nu, h0)
    t_ln = best_of(lambda: lanes(c, nu, h0))

    # 7. SciPy on a subset: its time per step (solve_ivp's DOP853 makes 12 evaluations a step)
    idx = rng.choice(args.n, size=min(args.n_scipy, args.n), replace=False)
    t0 = time.perf_counter()
    for i in idx:
        scipy_cycle(nu[i], c[i])
    t_scipy = time.perf_counter() - t0
    sub = out[idx]
    # about the same steps as the engine takes
    scipy_steps = (sub[:, core_engine.O_NSTEP] + sub[:, core_engine.O_NREJECT]).sum()

    t_inter = {}
    for k in (1, 4):
        f = interleaved_chain(k)
        f(64, 3.8, 0.01, 0.01)
        t_inter[k] = best_of(lambda f=f: f(n_chain, 3.8, 0.01, 0.01))
    n_ins, kinds = step_instructions(unrolled)
    fp = sum(v for k, v in kinds.items() if re.match(r"v(f?n?m(add|sub)\d*|add|sub|mul|div)sd$", k))
    fma = sum(v for k, v in kinds.items() if k.startswith("vf"))
    moves = kinds.get("vmovsd", 0) + kinds.get("vmovapd", 0) + kinds.get("vmovaps", 0)

    ns = 1e9
    per_step = t_engine / n_steps * ns
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; all on one thread; "
        f"the shortest of 3 runs each"
    )
    print(
        f"work: {args.n} F1 stick-slip cycles, nu log-uniform [1e-5, 1e-1], c uniform [0.5, 50], "
        f"rtol {RTOL:g}"
    )
    print(
        f"1. engine, everything       : {t_engine / args.n * 1e6:8.2f} us per cycle, "
        f"{per_step:6.1f} ns per step "
        f"({n_acc / args.n:.1f} accepted + {n_rej / args.n:.1f} rejected steps per cycle)"
    )
    print(
        f"2. step + controller only   : {t_ph / n_ph * ns:6.1f} ns per step "
        f"({n_ph / args.n:.1f} steps per cycle, no events)  {t_ph / n_ph * ns / per_step:5.0%} of 1"
    )
    print(
        f"3. the step alone           : {t_chain / n_chain * ns:6.1f} ns per step  "
        f"{t_chain / n_chain * ns / per_step:5.0%} of 1"
    )
    print(
        f"   its machine code: {n_ins} instructions, {fp} of them floating-point arithmetic "
        f"({fma} fused multiply-adds, {kinds.get('vdivsd', 0)} divisions), {moves} moves of doubles"
    )
    print(
        f"4. step, last stage only    : {t_last / n_chain * ns:6.1f} ns per step  "
        f"(returning the 26 stage values costs {(t_chain - t_last) / n_chain * ns:.1f} ns)"
    )
    print(
        f"5. four lanes (as 2)        : {t_ln / n_ln * ns:6.1f} ns per step and lane "
        f"({n_ln / args.n:.1f} steps per cycle); {t_ph / n_ph / (t_ln / n_ln):.2f} x the speed of 2"
    )
    print(
        f"5b. no branch, interleaved : {t_inter[1] / n_chain * ns:6.1f} ns per step in one chain (as 3), "
        f"{t_inter[4] / n_chain * ns:6.1f} ns per step and lane in four chains side by side "
        "(F1 only, not the engine's step: an upper bound for lanes)"
    )
    print(f"6. dense output of a step   : {t_dense / (n_chain // 4) * ns:6.1f} ns per call")
    print(
        f"7. scipy solve_ivp DOP853   : {t_scipy / len(idx) * 1e6:8.1f} us per cycle, about "
        f"{t_scipy / scipy_steps * ns / 1000:.1f} us per step; "
        f"{t_scipy / len(idx) / (t_engine / args.n):.0f} x the engine's time per cycle (one thread)"
    )


if __name__ == "__main__":
    main()
