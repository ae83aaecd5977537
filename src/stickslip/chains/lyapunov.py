"""The event map of a chain and its largest Lyapunov exponent.

Between events every block sticks, so the state at the end of an event is the
blocks' positions relative to the driver, ``u_j = x_j - nu t``; the *event map*
takes ``u`` at the end of one event to ``u`` at the end of the next (the model
is invariant under a shift of time and of all positions by ``nu`` times it).
Its largest Lyapunov exponent (per event) is computed as Benettin et al. do for
flows: a companion orbit at distance ``eps``, renormalised after every event,
the logarithms of the stretchings averaged. A positive exponent is chaos; a
periodic orbit of the map has a negative one (or zero along a neutral direction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .. import defaults
from ..core.api import ChainState, chain_advance
from .model import ChainParameters

__all__ = ["EventMapUndefined", "LyapunovResult", "event_map", "lyapunov_exponent"]


class EventMapUndefined(RuntimeError):
    """The chain never sticks as a whole again from this state (no next event end)."""


FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class LyapunovResult:
    """The largest Lyapunov exponent of the event map.

    Attributes
    ----------
    exponent : float
        Per event (natural logarithm).
    error : float
        Standard error of the mean over blocks of ``events // 10`` events.
    events : int
        Events averaged (after the transient).
    u : array of float
        The last state of the map (positions relative to the driver).
    lateral_gap : float
        ``|u_0 - u_{N-1}|`` at the end: the outer blocks' distance (0 when they move in step).
    defined : bool
        False where the event map is not defined (the chain stopped sticking as a
        whole: see :class:`EventMapUndefined`); the exponent is then nan.

    """

    exponent: float
    error: float
    events: int
    u: FloatArray
    lateral_gap: float
    defined: bool = True


def event_map(
    params: ChainParameters,
    u: npt.ArrayLike,
    *,
    rtol: float = 1e-11,
    atol: float = 1e-13,
    max_steps: int = 200_000,
) -> FloatArray:
    """Return the stuck state after the next event from the stuck state ``u`` (positions minus ``nu t``).

    Raises
    ------
    EventMapUndefined
        When the event does not end within ``max_steps`` steps.

    """
    ua = np.array(u, dtype=np.float64)
    state = ChainState.at_rest(ua, 0.0)
    cat, _, _ = chain_advance(
        params.law.kernel, params.law.core_params(), params.nu, params.ell2,
        str(params.boundary) == "periodic", bool(params.backslip), params.phi, state,
        max_events=1, rtol=rtol, atol=atol, max_steps=max_steps,
    )  # fmt: skip
    if cat.shape[0] != 1:
        raise EventMapUndefined(
            f"event map: the event did not end within {max_steps} steps (time {state.t:.6g}): "
            "the blocks never all stick again (a sliding state of the chain)"
        )
    return state.x - params.nu * state.t


def lyapunov_exponent(
    params: ChainParameters,
    u0: npt.ArrayLike,
    *,
    events: int = 2000,
    transient: int = 200,
    eps: float = 1e-7,
    rtol: float = defaults.RTOL * 0.1,
    atol: float = defaults.ATOL * 0.1,
) -> LyapunovResult:
    """Return the largest Lyapunov exponent of the event map, per event, from the stuck state ``u0``."""
    u = np.array(u0, dtype=np.float64)
    try:
        return _lyapunov(params, u, events, transient, eps, rtol, atol)
    except EventMapUndefined:
        return LyapunovResult(math.nan, math.nan, 0, u, math.nan, defined=False)


def _lyapunov(
    params: ChainParameters, u: FloatArray, events: int, transient: int, eps: float, rtol: float, atol: float
) -> LyapunovResult:
    for _ in range(transient):
        u = event_map(params, u, rtol=rtol, atol=atol)
    rng = np.random.default_rng(12345)
    d = rng.standard_normal(u.size)
    d *= eps / np.linalg.norm(d)
    logs = np.empty(events)
    for i in range(events):
        un = event_map(params, u, rtol=rtol, atol=atol)
        wn = event_map(params, u + d, rtol=rtol, atol=atol)
        diff = wn - un
        dist = float(np.linalg.norm(diff))
        if dist == 0.0 or not math.isfinite(dist):
            diff = rng.standard_normal(u.size)
            dist_used = eps
            logs[i] = math.log(1e-16 / eps) if dist == 0.0 else math.nan
            d = diff * (eps / float(np.linalg.norm(diff)))
        else:
            logs[i] = math.log(dist / eps)
            dist_used = dist
            d = diff * (eps / dist_used)
        u = un
    good = logs[np.isfinite(logs)]
    nb = max(1, good.size // 10)
    blocks = [float(np.mean(good[k : k + nb])) for k in range(0, good.size - nb + 1, nb)]
    err = float(np.std(blocks, ddof=1) / math.sqrt(len(blocks))) if len(blocks) > 1 else math.nan
    return LyapunovResult(float(np.mean(good)), err, int(good.size), u, float(abs(u[0] - u[-1])))
