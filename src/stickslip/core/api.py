"""Array-level entry points of the compiled engine (floats and arrays only).

These wrap the numba kernels of :mod:`stickslip.core.engine`: they fix dtypes
and memory layout and size the output buffers. They do not validate physics;
the model layer does that before calling them.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from . import engine, variational
from .laws import LAW_COULOMB, N_LAW_PARAMS

FloatArray = npt.NDArray[np.float64]

__all__ = ["run_attractors", "run_shooting", "run_trajectory"]


def run_attractors(
    law: npt.ArrayLike,
    lp: npt.ArrayLike,
    nu: npt.ArrayLike,
    s0: npt.ArrayLike | None = None,
    w0: npt.ArrayLike | None = None,
    *,
    from_breakaway: bool,
    rtol: float,
    atol: float,
    max_slip_time: float,
    conv_tol: float,
    diag: bool = False,
    max_steps: int = 2_000_000,
) -> FloatArray:
    """Run the attractor kernel for each row, in parallel; return an ``(n, NOUT)`` array.

    Parameters
    ----------
    law : array_like of int, shape (n,) or scalar
        Law ids (``LAW_*`` of :mod:`stickslip.core.laws`).
    lp : array_like, shape (n, N_LAW_PARAMS) or (N_LAW_PARAMS,)
        Law parameters.
    nu : array_like, shape (n,)
        Dimensionless driving velocities.
    s0, w0 : array_like, shape (n,), optional
        Initial spring force and velocity (ignored with ``from_breakaway``).
    from_breakaway : bool
        Start at breakaway ``(1, 0)`` and measure the first cycle.
    rtol, atol : float
        Tolerances of the slip integration.
    max_slip_time : float
        Bound on the slip time integrated per row (dimensionless).
    conv_tol : float
        Relative tolerance on the amplitude of converging oscillations.
    diag : bool, optional
        Also integrate the work of the drive and of friction.
    max_steps : int, optional
        Bound on the steps of one slip phase.

    """
    nu_a = np.array(np.atleast_1d(np.asarray(nu, dtype=np.float64)), order="C")
    if nu_a.ndim != 1 or not np.all(np.isfinite(nu_a) & (nu_a > 0)):
        raise ValueError("nu: expected a 1-d array of finite positive driving velocities")
    n = nu_a.shape[0]
    law_a = _broadcast("law", np.asarray(law, dtype=np.int64), (n,))
    if not np.all((law_a >= 0) & (law_a <= LAW_COULOMB)):
        raise ValueError(f"law={law!r}: expected law ids 0 (weakening), 1 (cubic) or 2 (coulomb)")
    lp_a = _broadcast("lp", np.asarray(lp, dtype=np.float64), (n, N_LAW_PARAMS))
    z = np.zeros(n)
    s0_a = z if s0 is None else _broadcast("s0", np.asarray(s0, dtype=np.float64), (n,))
    w0_a = z if w0 is None else _broadcast("w0", np.asarray(w0, dtype=np.float64), (n,))
    out = np.empty((n, engine.NOUT))
    engine.attractor_batch(
        law_a,
        lp_a,
        nu_a,
        s0_a,
        w0_a,
        bool(from_breakaway),
        float(rtol),
        float(atol),
        float(max_slip_time),
        float(conv_tol),
        bool(diag),
        int(max_steps),
        out,
    )
    return out


def _broadcast(name: str, a: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    try:
        # a writable copy: numba compiles read-only arrays (broadcast views) separately
        return np.array(np.broadcast_to(a, shape), order="C")
    except ValueError:
        raise ValueError(f"{name}: shape {a.shape} does not broadcast to {shape}") from None


def run_trajectory(
    law: int,
    lp: npt.ArrayLike,
    nu: float,
    s0: float,
    w0: float,
    t_eval: npt.ArrayLike,
    *,
    rtol: float,
    atol: float,
    max_steps: int = 2_000_000,
    event_capacity: int = 1024,
) -> tuple[FloatArray, npt.NDArray[np.int64], FloatArray, int]:
    """Integrate from ``(s0, w0)`` and sample at ``t_eval`` (sorted, starting at or after 0).

    Returns
    -------
    y : ndarray, shape (len(t_eval), 2)
        Spring force and velocity.
    mode : ndarray of int, shape (len(t_eval),)
        0 stick, +1 forward slip, -1 backward slip.
    events : ndarray, shape (m, 3)
        Rows ``(time, kind, spring force)``, kinds ``EV_*`` of the engine.
    status : int
        ``ST_*`` status code of the engine.

    """
    t = np.ascontiguousarray(np.asarray(t_eval, dtype=np.float64))
    if t.ndim != 1 or t.size == 0 or t[0] < 0 or np.any(np.diff(t) < 0) or not np.all(np.isfinite(t)):
        raise ValueError("t_eval: expected a non-empty, sorted 1-d array of finite times >= 0")
    lp_a = np.array(lp, dtype=np.float64, order="C")
    cap = max(16, int(event_capacity))
    while True:
        y = np.empty((t.shape[0], 2))
        mode = np.empty(t.shape[0], dtype=np.int64)
        ev = np.empty((cap, 3))
        evn = np.zeros(1, dtype=np.int64)
        status = engine.trajectory(
            int(law),
            lp_a,
            float(nu),
            float(s0),
            float(w0),
            t,
            float(rtol),
            float(atol),
            int(max_steps),
            y,
            mode,
            ev,
            evn,
        )
        if evn[0] <= cap:
            return y, mode, ev[: evn[0]].copy(), int(status)
        cap = int(evn[0])


def run_shooting(
    law: npt.ArrayLike,
    lp: npt.ArrayLike,
    nu: npt.ArrayLike,
    s0: npt.ArrayLike,
    period: npt.ArrayLike,
    *,
    tol: float,
    max_iter: int = 30,
    max_steps: int = 200_000,
) -> FloatArray:
    """Solve for pure-slip periodic orbits by Newton shooting from guesses, in parallel.

    Parameters
    ----------
    law, lp, nu : array_like
        As in :func:`run_attractors`.
    s0, period : array_like, shape (n,)
        Guesses: the spring-force maximum (where ``w`` crosses ``nu`` upward) and the period.
    tol : float
        Tolerance on the periodicity residual; the flow is integrated at ``tol / 100``.
    max_iter, max_steps : int, optional
        Newton iterations and integration steps allowed.

    Returns
    -------
    ndarray, shape (n, NSH)
        Layout ``SH_*`` of :mod:`stickslip.core.variational`.

    """
    nu_a = np.array(np.atleast_1d(np.asarray(nu, dtype=np.float64)), order="C")
    n = nu_a.shape[0]
    law_a = _broadcast("law", np.asarray(law, dtype=np.int64), (n,))
    lp_a = _broadcast("lp", np.asarray(lp, dtype=np.float64), (n, N_LAW_PARAMS))
    s0_a = _broadcast("s0", np.asarray(s0, dtype=np.float64), (n,))
    t_a = _broadcast("period", np.asarray(period, dtype=np.float64), (n,))
    out = np.empty((n, variational.NSH))
    variational.shoot_batch(law_a, lp_a, nu_a, s0_a, t_a, float(tol), int(max_iter), int(max_steps), out)
    return out
