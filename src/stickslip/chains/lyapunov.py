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
import numbers
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .. import defaults
from ..core.api import ChainState, chain_advance
from ..core.results import ChainScalars, ChainStatus
from ..dynamics.cycle import validate_tolerances
from ..errors import ArgumentTypeError
from ..units import check_count
from .model import ChainParameters, sliding_after

__all__ = ["EventMapUndefined", "LyapunovResult", "event_map", "lyapunov_exponent"]


#: steps per call of the engine in the event map (an event goes on over as many calls as it needs)
MAX_STEPS = 200_000

#: a companion orbit closer than this times the size of the state (and 1) is not resolved
RESOLVED = 1e-12


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
    unresolved : int
        Events after which the companion orbit was closer than rounding resolves
        (left out of the average; when they are most of the events, the exponent is
        ``-inf``: the map is superstable).

    """

    exponent: float
    error: float
    events: int
    u: FloatArray
    lateral_gap: float
    defined: bool = True
    unresolved: int = 0


def _positions(name: str, u: object, params: object) -> FloatArray:
    """Return the blocks' positions ``u`` as a float array of one per block of the chain ``params``."""
    if not isinstance(params, ChainParameters):
        raise ArgumentTypeError(f"params={params!r}: expected ChainParameters")
    if isinstance(u, str | bytes):
        raise ArgumentTypeError(f"{name}={u!r}: expected one position per block")
    try:
        ua = np.array(u, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name}: expected one position per block, got {type(u).__name__}") from None
    if ua.shape != (params.blocks,):
        raise ValueError(
            f"{name}: {ua.size} positions, shape {ua.shape}; expected one per block, {params.blocks}"
        )
    return ua


def event_map(
    params: ChainParameters,
    u: npt.ArrayLike,
    *,
    rtol: float = 1e-11,
    atol: float = 1e-13,
    max_steps: int = MAX_STEPS,
    max_event_duration: float | None = None,
) -> FloatArray:
    """Return the stuck state after the next event from the stuck state ``u`` (positions minus ``nu t``).

    Parameters
    ----------
    params : ChainParameters
        The chain (dimensionless).
    u : array_like, shape (blocks,)
        Positions of the blocks at rest, relative to the driver.
    rtol, atol : float
        Tolerances of the engine.
    max_steps : int
        Steps per call of the engine (the event goes on over as many calls as it needs).
    max_event_duration : float, optional
        An event longer than this (time units) is a sliding state of the chain, as in
        :func:`~stickslip.chains.chain`; default ``1000/nu + 1000``.

    Raises
    ------
    EventMapUndefined
        When the event lasts longer than ``max_event_duration``: the blocks never all stick again.
    RuntimeError
        When the engine fails (a step below the resolution of the time, a motion that is
        not finite), with the reason: no verdict on the chain.

    """
    rtol, atol = validate_tolerances(rtol, atol)
    steps = check_count(max_steps, "max_steps")  # 0 would pause before any step, for ever
    ua = _positions("u", u, params)
    if max_event_duration is not None and (
        isinstance(max_event_duration, bool) or not isinstance(max_event_duration, numbers.Real)
    ):
        raise ArgumentTypeError(f"max_event_duration={max_event_duration!r}: expected a positive duration")
    longest = sliding_after(params) if max_event_duration is None else float(max_event_duration)
    if not longest > 0:
        raise ValueError(f"max_event_duration={max_event_duration!r}: expected a positive duration")
    return _next_event_end(params, ua, rtol, atol, steps, longest)


def _next_event_end(
    params: ChainParameters, ua: FloatArray, rtol: float, atol: float, steps: int, longest: float
) -> FloatArray:
    """:func:`event_map` on checked arguments (the Lyapunov loop calls it twice an event)."""
    state = ChainState.at_rest(ua, 0.0)
    while True:
        cat, _, code = chain_advance(
            params.law.kernel, params.law.core_params(), params.nu, params.ell2,
            str(params.boundary) == "periodic", bool(params.backslip), params.phi, state,
            max_events=1, rtol=rtol, atol=atol, max_steps=steps, max_event_duration=longest,
        )  # fmt: skip
        if cat.shape[0] == 1:
            return state.x - params.nu * state.t
        status = ChainStatus.from_code(code)
        if status is not ChainStatus.PAUSED:
            raise RuntimeError(f"event map: {status.message}")
        if ChainScalars(state.sc).event_longer_than(longest):
            raise EventMapUndefined(
                f"event map: the event lasted longer than {longest:.6g} (time {state.t:.6g}): "
                "the blocks never all stick again (a sliding state of the chain)"
            )


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
    """Return the largest Lyapunov exponent of the event map, per event, from the stuck state ``u0``.

    A companion orbit at distance ``eps`` is followed and renormalised after every event.
    Where the map contracts it below what the arithmetic resolves (a distance under
    :data:`RESOLVED` times the size of the state: a constant map, as for one block whose
    every cycle starts from the same breakaway), that event's stretch is not a number;
    when most events are so, the exponent is ``-inf`` (the map is superstable), else those
    events are left out and counted in ``unresolved``. Where an event never ends (the
    chain slides) the result has ``defined`` false.

    Raises
    ------
    ValueError
        For positions that are not one per block, or not finite, and bad ``events``,
        ``transient``, ``eps`` or tolerances.
    RuntimeError
        When the engine fails (see :func:`event_map`).

    """
    u = _positions("u0", u0, params)
    ev = check_count(events, "events", minimum=2)
    tr = check_count(transient, "transient", minimum=0)
    if isinstance(eps, bool) or not isinstance(eps, int | float):
        raise ArgumentTypeError(
            f"eps={eps!r}: expected the companion orbit's distance, 0 < eps < 1 (e.g. 1e-7)"
        )
    if not (math.isfinite(eps) and 0 < eps < 1):
        raise ValueError(f"eps={eps!r}: expected the companion orbit's distance, 0 < eps < 1 (e.g. 1e-7)")
    rtol, atol = validate_tolerances(rtol, atol)
    try:
        return _lyapunov(params, u, ev, tr, float(eps), rtol, atol)
    except EventMapUndefined:
        return LyapunovResult(math.nan, math.nan, 0, u, math.nan, defined=False)


def _lyapunov(
    params: ChainParameters, u: FloatArray, events: int, transient: int, eps: float, rtol: float, atol: float
) -> LyapunovResult:
    longest = sliding_after(params)

    def step(x: FloatArray) -> FloatArray:
        return _next_event_end(params, x, rtol, atol, MAX_STEPS, longest)

    for _ in range(transient):
        u = step(u)
    rng = np.random.default_rng(12345)
    d = rng.standard_normal(u.size)
    d *= eps / np.linalg.norm(d)
    logs = np.full(events, math.nan)
    for i in range(events):
        un = step(u)
        wn = step(u + d)
        diff = wn - un
        dist = float(np.linalg.norm(diff))
        if dist > RESOLVED * max(1.0, float(np.max(np.abs(un)))):
            logs[i] = math.log(dist / eps)
        else:  # contracted below rounding: no stretch to measure; a fresh direction
            diff = rng.standard_normal(u.size)
            dist = float(np.linalg.norm(diff))
        d = diff * (eps / dist)
        u = un
    good = logs[np.isfinite(logs)]
    unresolved = events - int(good.size)
    gap = float(abs(u[0] - u[-1]))
    if good.size < max(2, events // 2):  # most stretches below rounding: a superstable map
        return LyapunovResult(-math.inf, math.nan, events, u, gap, unresolved=unresolved)
    nb = max(1, good.size // 10)
    blocks = [float(np.mean(good[k : k + nb])) for k in range(0, good.size - nb + 1, nb)]
    err = float(np.std(blocks, ddof=1) / math.sqrt(len(blocks))) if len(blocks) > 1 else math.nan
    return LyapunovResult(float(np.mean(good)), err, int(good.size), u, gap, unresolved=unresolved)
