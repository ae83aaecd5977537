"""An independent event-driven reference for chains of blocks: SciPy's solve_ivp with events.

Written from the model's equations only (docs/chain.md), sharing no code with
stickslip: every block is integrated (stuck ones with zero velocity and
acceleration), and each change of a block's state is a terminal event of
``solve_ivp`` (DOP853, tight tolerances).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.integrate import solve_ivp


def reference_chain(
    f: Callable[[float], float],
    x0: np.ndarray,
    nu: float,
    ell2: float,
    n_events: int,
    *,
    periodic: bool = False,
    backward: bool = True,
    rtol: float = 1e-12,
    atol: float = 1e-14,
) -> list[dict[str, float]]:
    """Return the first ``n_events`` events (t_start, t_end, epicentre, n_blocks, moment, slips)."""
    n = len(x0)
    x = np.array(x0, dtype=float)
    v = np.zeros(n)
    mode = np.zeros(n, dtype=int)
    t = 0.0

    def neighbours(j: int) -> tuple[int, int]:
        left = j - 1 if j > 0 else (n - 1 if periodic else j)
        right = j + 1 if j < n - 1 else (0 if periodic else j)
        return left, right

    def force(xs: np.ndarray, tt: float, j: int) -> float:
        a, b = neighbours(j)
        return ell2 * (xs[a] - 2.0 * xs[j] + xs[b]) + nu * tt - xs[j]

    def friction(d: int, w: float) -> float:
        return d * f(d * w)

    events: list[dict[str, float]] = []
    current: dict[str, float] | None = None
    start_x: dict[int, float] = {}

    def start_slip(j: int, d: int) -> None:
        nonlocal current
        if current is None:
            current = {"t_start": t, "epicentre": j}
            start_x.clear()
        mode[j] = d
        v[j] = 0.0
        start_x.setdefault(j, x[j])

    def check_breaks() -> None:
        for j in range(n):
            if mode[j] == 0:
                e = force(x, t, j)
                if e >= 1.0 - 1e-12:
                    start_slip(j, 1)
                elif backward and e <= -1.0 + 1e-12:
                    start_slip(j, -1)

    for _ in range(100 * n_events * max(n, 1)):
        if len(events) >= n_events:
            break
        m = mode.copy()

        def rhs(tt: float, y: np.ndarray, m: np.ndarray = m) -> np.ndarray:
            xs, vs = y[:n], y[n:]
            out = np.zeros(2 * n)
            for j in range(n):
                if m[j] != 0:
                    out[j] = vs[j]
                    out[n + j] = force(xs, tt, j) - friction(m[j], vs[j])
            return out

        funcs = []
        for j in range(n):
            if m[j] != 0:

                def stop(tt: float, y: np.ndarray, j: int = j, d: int = int(m[j])) -> float:
                    return d * y[n + j]

                stop.terminal = True  # type: ignore[attr-defined]
                stop.direction = -1  # type: ignore[attr-defined]
                funcs.append(stop)
            else:

                def brk(tt: float, y: np.ndarray, j: int = j) -> float:
                    return force(y[:n], tt, j) - 1.0

                brk.terminal = True  # type: ignore[attr-defined]
                brk.direction = 1  # type: ignore[attr-defined]
                funcs.append(brk)
                if backward:

                    def brk_back(tt: float, y: np.ndarray, j: int = j) -> float:
                        return -1.0 - force(y[:n], tt, j)

                    brk_back.terminal = True  # type: ignore[attr-defined]
                    brk_back.direction = 1  # type: ignore[attr-defined]
                    funcs.append(brk_back)
        # all stuck: jump close to the next breakaway (exact, the forces grow at rate nu)
        if not mode.any():
            t_next = min((1.0 - force(x, t, j)) / nu for j in range(n)) + t
            t = max(t, t_next - 1e-3)
        sol = solve_ivp(
            rhs, (t, t + 1e4), np.concatenate([x, v]), method="DOP853", rtol=rtol, atol=atol, events=funcs
        )
        if sol.status != 1:
            raise RuntimeError("reference: no event")
        hit = min(te[0] for te in sol.t_events if len(te))
        y = sol.sol(hit) if sol.sol is not None else None
        for te, ye in zip(sol.t_events, sol.y_events, strict=True):
            if len(te) and te[0] == hit:
                y = ye[0]
        assert y is not None
        t = hit
        x = np.array(y[:n])
        v = np.array(y[n:])
        v[mode == 0] = 0.0
        for j in range(n):
            if mode[j] != 0 and mode[j] * v[j] <= 1e-9:
                v[j] = 0.0
                e = force(x, t, j)
                if backward and e < -1.0:
                    mode[j] = -1
                elif e >= 1.0:
                    mode[j] = 1
                else:
                    mode[j] = 0
        check_breaks()
        if current is not None and not mode.any():
            slips = {j: x[j] - x0j for j, x0j in start_x.items()}
            current.update(
                t_end=t,
                n_blocks=len(slips),
                moment=sum(slips.values()),
                slips=np.array([slips.get(j, 0.0) for j in range(n)]),
            )
            events.append(current)
            current = None
        if current is None and not mode.any():
            continue
    return events
