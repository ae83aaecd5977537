"""Chain engine against the straightforward fixed-step loop (Carlson-Langer, 100 and 1000 blocks).

The fixed-step loop is what public Burridge-Knopoff codes do: explicit (symplectic
Euler) steps of dt = 0.005 for every block, a stuck block held until its force
exceeds the threshold, negative velocities clamped to zero; compiled with numba.
Both start from the same state (after a transient of the exact engine) and run
the same simulated time. Event-time errors: the exact engine against itself at
rtol 1e-12 (first 30 events); the fixed-step loop against the exact event times
(first 5 events, matched in order); both only up to the first event that takes
over half the chain, after which the chain's chaos, not the integration, sets
the difference (a start 1e-13 off gives event times 1e-2 off after it).

The issue's set has ``nu = 0.01``, a fast drive (Carlson and Langer's choice for
computing); a fault or a lab machine loads far slower. ``--nu`` adds rows for
1000 blocks at smaller ``nu`` (the simulated time scaled as ``6 / nu``, so that
each row sees about as many events): there the chain sticks as a whole between
events, which the exact engine jumps over and the fixed-step loop steps through.

``--floor`` adds the cost of the engine's own DOP853 step alone (its vector field and
its sums, with the error norm; no events, no dense output, no root finding) per
slipping block, for a cluster of 40 and one of 1000 slipping blocks: the least that any
scheme built on these steps pays per block and step, however it handles the events.

``--accuracy`` compares the two at equal accuracy instead of equal step size, on 100
and 1000 blocks at ``nu = 0.01``: the fixed-step loop at dt = 0.005 and below (to 5e-7
on 100 blocks, 5e-6 on 1000), and the exact engine at rtol 1e-6, 1e-8 and 1e-10, each
with its event-time error and its cost per simulated time unit; then, for each
tolerance of the exact engine, the cost of the loop at the largest step run whose
error is as small (measured), and at the step where its error, a power law in dt
fitted where the loop finds the same events, would be as small (extrapolated). Both
start at rest just after an event of over half the chain; the error is the largest
over the small events before the next large one (at most 30, matched in order),
against the exact engine at rtol 1e-12. How a large event ends is the chain's chaos,
not accuracy: on 1000 blocks its end moves by 100 time units between rtol 1e-10 and
1e-12.

Run: python benchmarks/bench_chain.py [--nu 0.001 0.0001] [--floor] [--accuracy]
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time

import numpy as np
from numba import njit

from stickslip.chains import ChainParameters
from stickslip.core.api import ChainState, chain_advance
from stickslip.core.laws import N_LAW_PARAMS
from stickslip.laws import CarlsonLangerLaw

ALPHA, SIGMA, NU, ELL = 2.5, 0.01, 0.01, 10.0
DT = 0.005


@njit(cache=True)
def fixed_step(x, v, t0, nu, ell2, alpha, sigma, dt, t_end, starts):  # type: ignore[no-untyped-def]
    """Fixed-step loop; returns the number of events and fills ``starts`` with their start times.

    The clock is ``t0 + i dt`` (the step count times dt): summing dt would drift by
    1e-5 over 30 time units at dt = 5e-7, more than the loop's own error there.
    """
    n = x.shape[0]
    e = np.empty(n)
    r = 1.0 - sigma
    t = t0
    i = 0
    events = 0
    moving_prev = False
    for j in range(n):
        if v[j] > 0.0:
            moving_prev = True
    while t < t_end:
        for j in range(n):
            xl = x[j - 1] if j > 0 else x[j]
            xr = x[j + 1] if j < n - 1 else x[j]
            e[j] = ell2 * (xl - 2.0 * x[j] + xr) + nu * t - x[j]
        moving = False
        for j in range(n):
            if v[j] == 0.0 and e[j] < 1.0:
                continue
            v[j] += (e[j] - r / (1.0 + 2.0 * alpha * v[j] / r)) * dt
            if v[j] < 0.0:
                v[j] = 0.0
            x[j] += v[j] * dt
            moving = True
        if moving and not moving_prev:
            if events < starts.shape[0]:
                starts[events] = t
            events += 1
        moving_prev = moving
        i += 1
        t = t0 + i * dt
    return events


def _dop853_steps(law: CarlsonLangerLaw):  # type: ignore[no-untyped-def]
    """Return ``steps(m, ell2, h, nsteps)``: DOP853 steps of ``m`` blocks slipping forward.

    Compiled from the functions of the law's own chain engine (the one ``chain`` runs):
    its vector field and its DOP853 sums. The blocks form a ring (no stuck neighbour to
    hold back its ends); the step is fixed (the error norm is computed, as in the
    engine, but does not act), no event is sought. The blocks slide steadily with the
    driver at ``v = nu = 0.05``, an unstable state on a weakening law: it is set again
    every 50 steps, before rounding errors have grown (``steps`` returns the summed
    error norms, which stay at rounding level).
    """
    eng = law.kernel.chain_engine
    pkg = sys.modules[eng.__package__]
    dop = importlib.import_module(f"{pkg.__name__}.dop853")
    C = importlib.import_module(f"{pkg.__name__}._dop853_tableau").C
    rhs, N_STAGES, N_STAGES_EXTENDED = eng._rhs, dop.N_STAGES, dop.N_STAGES_EXTENDED
    vec_stage, vec_advance, vec_error = dop.vec_stage, dop.vec_advance, dop.vec_error
    law_id = law.kernel.law_id
    lp = np.zeros(N_LAW_PARAMS)
    lp[: law.core_params().size] = law.core_params()
    P = tuple(float(q) for q in lp)
    nu = 0.05
    x0 = -float(law.value(nu))  # steady sliding: x = nu t - f(nu)

    @njit
    def steps(m, ell2, h, nsteps):  # type: ignore[no-untyped-def]
        nvar = 2 * m + 2
        y = np.zeros(nvar)
        y_new = np.zeros(nvar)
        ytmp = np.zeros(nvar)
        K = np.zeros((N_STAGES_EXTENDED, nvar))
        nbl = np.empty(m, np.int64)
        nbr = np.empty(m, np.int64)
        for k in range(m):
            nbl[k] = 2 * ((k - 1) % m)
            nbr[k] = 2 * ((k + 1) % m)
        dk = np.ones(m, np.int64)
        phk = np.ones(m)
        ctx = (law_id, P, nu, ell2, nbl, nbr, dk, phk, m, 0.0, 0, 0.0)
        t = 0.0
        acc = 0.0
        for i in range(nsteps):
            if i % 50 == 0:
                for k in range(m):
                    y[2 * k] = x0
                    y[2 * k + 1] = nu
                t = 0.0
                rhs(ctx, t, y, K[0])
            for s in range(1, N_STAGES):
                vec_stage(y, K, h, s, nvar, ytmp)
                rhs(ctx, t + C[s] * h, ytmp, K[s])
            vec_advance(y, K, h, nvar, y_new)
            rhs(ctx, t + h, y_new, K[N_STAGES])
            acc += vec_error(y, y_new, K, h, 2 * m, 1e-10, 1e-12)
            for c in range(nvar):
                y[c] = y_new[c]
                K[0, c] = K[N_STAGES, c]
            t += h
        return acc

    return steps


def floor(law: CarlsonLangerLaw) -> None:
    """Print the cost of one DOP853 step per slipping block, best of three."""
    steps = _dop853_steps(law)
    for m in (40, 1000):
        steps(m, ELL * ELL, 0.016, 10)
        n = int(4e6 // m)
        best = np.inf
        for _ in range(3):
            t0 = time.perf_counter()
            steps(m, ELL * ELL, 0.016, n)
            best = min(best, time.perf_counter() - t0)
        print(
            f"DOP853 step alone, {m:>4} slipping blocks: {best / n * 1e6:7.2f} us per step, "
            f"{best / (n * m) * 1e9:6.1f} ns per block and step"
        )


def _advance(p: ChainParameters, st: ChainState, **kw):  # type: ignore[no-untyped-def]
    """The engine's ``chain_advance`` on the chain ``p`` from ``st`` (advanced in place)."""
    return chain_advance(p.law.kernel, p.law.core_params(), p.nu, p.ell2, False, False, p.phi, st, **kw)


def exact(p: ChainParameters, state: ChainState, t_span: float, rtol: float = 1e-10, atol: float = 1e-12):  # type: ignore[no-untyped-def]
    st = state.copy()
    t_end = st.t + t_span
    rows = []
    while st.t < t_end:
        cat, _, code = _advance(
            p, st, max_events=10**6, t_max=t_end, rtol=rtol, atol=atol, max_steps=5_000_000
        )
        rows.append(cat)
        if code not in (0, 2):
            break
    return np.concatenate(rows), st


def _start(law: CarlsonLangerLaw, n: int, nu: float, transient: int) -> tuple[ChainParameters, ChainState]:
    """The chain after ``transient`` events from a random start (seed 1), both loops compiled."""
    p = ChainParameters(n, law, nu, ELL)
    st = ChainState.at_rest(np.random.default_rng(1).uniform(0.0, 0.01, n))
    _advance(p, st, max_events=transient, max_steps=10**9)
    exact(p, st, 1.0)  # compile
    fixed_step(st.x.copy(), st.v.copy(), st.t, nu, p.ell2, ALPHA, SIGMA, DT, st.t + 1.0, np.zeros(1))
    return p, st


def _fixed_error(p: ChainParameters, start: ChainState, dt: float, span: float, ref: np.ndarray, k: int):  # type: ignore[no-untyped-def]
    """Time the fixed-step loop over ``span``; its largest error on the first ``k`` starts; its events."""
    starts = np.zeros(max(k, 1))
    t0 = time.perf_counter()
    nf = fixed_step(start.x.copy(), start.v.copy(), start.t, p.nu, p.ell2, ALPHA, SIGMA, dt, start.t + span,
                    starts)  # fmt: skip
    tf = time.perf_counter() - t0
    if nf < k:  # events merged: no match for the last ones
        return tf, float("inf"), int(nf)
    return tf, float(np.max(np.abs(starts[:k] - ref[:k, 0]))) if k else float("nan"), int(nf)


def _after_big_event(p: ChainParameters, state: ChainState) -> ChainState:
    """The chain at rest just after its next event over half the chain (the events after it are small)."""
    st = state.copy()
    while True:
        cat, _, _ = _advance(p, st, max_events=1, max_steps=10**9)
        if cat.shape[0] and cat[-1, 3] > p.blocks / 2:
            return st


def accuracy(law: CarlsonLangerLaw) -> None:
    """Print both loops' event-time errors and costs, and the loop's cost at the engine's accuracy."""
    for n, transient, span, smallest in ((100, 3000, 3000.0, DT / 10000), (1000, 300, 600.0, DT / 1000)):
        p, start = _start(law, n, NU, transient)
        start = _after_big_event(p, start)
        ref, _ = exact(p, start, span, rtol=1e-12, atol=1e-14)
        k = _before_divergence(ref, n, 31) - 1  # the small events before the next large one
        assert k >= 1, "the event after a large one is large too: no small events to compare"
        short = float(ref[k - 1, 1] - start.t) + 1.0  # to the end of the k-th event
        print(
            f"Equal accuracy: {n} blocks, nu = {NU}, from the end of a large event, the next {k} (small) "
            f"events ({short:.1f} time units); cost in ms per simulated time unit over these "
            f"(the exact engine's also over {span:g}, large events in), largest event-time error"
        )
        fixed = []
        dt = DT
        while dt >= smallest * 0.99:
            tf, err, nf = _fixed_error(p, start, dt, short, ref, k)
            fixed.append((dt, tf / short * 1e3, err))
            missed = f" ({nf} events found: merged)" if nf < k else ""
            print(f"fixed step dt = {dt:<7g} {tf / short * 1e3:10.4f} ms  error {err:.1e}{missed}")
            dt /= 10
        dts, costs, errs = (np.array(c) for c in zip(*fixed, strict=True))
        # the steps at which the loop finds the same events (its error well below their spacing)
        same = errs < 1e-2
        if same.sum() >= 2:
            order, lead = np.polyfit(np.log(dts[same]), np.log(errs[same]), 1)
            print(f"the loop's error goes as dt^{order:.2f} where it finds the same events")
        else:
            print("the loop finds the same events at fewer than two steps: no fit, no extrapolation")
        for rtol in (1e-6, 1e-8, 1e-10):
            t0 = time.perf_counter()
            exact(p, start, short, rtol=rtol, atol=rtol * 1e-2)
            cost = (time.perf_counter() - t0) / short * 1e3
            t0 = time.perf_counter()
            rows, _ = exact(p, start, span, rtol=rtol, atol=rtol * 1e-2)  # every event ends in it
            cost_span = (time.perf_counter() - t0) / span * 1e3
            err = float(np.max(np.abs(rows[:k, 0] - ref[:k, 0]))) if rows.shape[0] >= k else float("inf")
            good = np.flatnonzero(errs <= err)
            i = good[0] if good.size else -1  # the largest step at least as accurate, or the smallest
            ratio = f"{costs[i] / cost:.3g} x the exact engine ({costs[i] / cost_span:.3g} x over {span:g})"
            if good.size:  # measured
                verdict = f"the loop as accurate at dt = {dts[i]:g}: {ratio}"
            else:
                verdict = f"the loop is less accurate even at dt = {dts[i]:g}, at {ratio}"
            if same.sum() >= 2:  # an optimistic bound for the loop: rounding ignored
                dt_eq = float(np.exp((np.log(max(err, 1e-16)) - lead) / order))
                verdict += f"; at dt = {dt_eq:.1e} by the fit: {costs[-1] * dts[-1] / dt_eq / cost:.3g} x"
            print(f"exact rtol = {rtol:<7g} {cost:10.4f} ms ({cost_span:.4f})  error {err:.1e}  -> {verdict}")


def _before_divergence(ref: np.ndarray, n: int, most: int) -> int:
    """Events to compare: at most ``most``, up to and including the first that takes over half the chain.

    The chain is chaotic: the event after a rupture of the whole chain starts
    about 1e-2 later when one block starts 1e-13 off (measured), so event times
    after it say nothing about the accuracy of the integration.
    """
    big = np.flatnonzero(ref[:most, 3] > n / 2)
    return int(min(most, ref.shape[0], big[0] + 1 if big.size else most))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--nu", type=float, nargs="*", default=[], help="more rows: 1000 blocks at these driving velocities"
    )
    parser.add_argument("--floor", action="store_true", help="also the cost of the DOP853 step alone")
    parser.add_argument(
        "--accuracy", action="store_true", help="also both loops at equal event-time accuracy"
    )
    a = parser.parse_args()
    law = CarlsonLangerLaw(alpha=ALPHA, sigma=SIGMA)
    if a.floor:
        floor(law)
    if a.accuracy:
        accuracy(law)
    print(f"Carlson-Langer chain: alpha={ALPHA}, sigma={SIGMA}, ell={ELL}; fixed step dt={DT}")
    print(
        f"{'nu':>7} {'blocks':>6} {'sim. time':>9} {'exact s':>8} {'events':>7} {'ev/s':>8} {'time/s':>8} "
        f"{'fixed s':>8} {'events':>7} {'time/s':>8} {'ratio':>6} {'err exact':>9} {'err fixed':>9}"
    )
    rows_ = [(NU, 100, 3000, 3000.0), (NU, 1000, 300, 600.0)]
    rows_ += [(nu, 1000, 300, 6.0 / nu) for nu in a.nu]
    for nu, n, transient, span in rows_:
        p, start = _start(law, n, nu, transient)
        t0 = time.perf_counter()
        rows, _ = exact(p, start, span)
        te = time.perf_counter() - t0
        ref, _ = exact(p, start, span, rtol=1e-12, atol=1e-14)
        k = _before_divergence(ref, n, 30)
        k = min(k, rows.shape[0])
        err_exact = float(np.max(np.abs(rows[:k, 0] - ref[:k, 0]))) if k else float("nan")
        tf, err_fixed, nf = _fixed_error(p, start, DT, span, ref, _before_divergence(ref, n, 5))
        print(
            f"{nu:>7.0e} {n:>6} {span:>9.0f} {te:>8.3f} {rows.shape[0]:>7} {rows.shape[0] / te:>8.1f} "
            f"{span / te:>8.1f} "
            f"{tf:>8.3f} {nf:>7} {span / tf:>8.1f} {tf / te:>6.2f} {err_exact:>9.1e} {err_fixed:>9.1e}"
        )
    print(
        "ratio = fixed-step wall time / exact wall time at equal simulated time "
        "(> 1: the exact engine is faster)"
    )


if __name__ == "__main__":
    main()
