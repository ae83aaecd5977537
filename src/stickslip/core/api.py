"""Array-level entry points of the compiled engine (floats and arrays only).

These wrap the numba kernels of :mod:`stickslip.core.engine`: they fix dtypes
and memory layout, size the output buffers, and check every argument as numbers
(finite, in range, of the right type: :mod:`stickslip.core.checks`) so that no
NaN or absurd value reaches the compiled loops. They do not validate physics; the
model layer does that before calling them.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from . import checks, engine, variational
from .laws import LAW_COULOMB, N_LAW_PARAMS
from .memory import check_memory

FloatArray = npt.NDArray[np.float64]

#: rows per call into the compiled batch kernel (Ctrl-C is seen between calls)
BATCH = 4096
#: memory of one row of run_attractors: the output (NOUT doubles), the checked copies of the
#: inputs (law id, law parameters, nu, s0, w0) and the validation's masks
BYTES_PER_ROW = 8.0 * (20 + 1 + 3 + 3) * 1.5

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
    # first of all, from the input's size alone: the copies below and the output scale with it
    check_memory(np.size(nu) * BYTES_PER_ROW, f"{np.size(nu)} parameter sets")
    rtol, atol = checks.tolerances(rtol, atol)
    max_slip_time = checks.positive("max_slip_time", max_slip_time, upper=1e12)
    conv_tol = checks.positive("conv_tol", conv_tol, upper=0.1, what="a relative tolerance below 0.1")
    max_steps = checks.integer("max_steps", max_steps, lo=10, hi=10**9)
    nu_a = np.array(np.atleast_1d(_nu(nu)), order="C")
    n = nu_a.shape[0]
    law_a, lp_a = _laws(law, lp, n)
    z = np.zeros(n)
    s0_a = z if s0 is None else _broadcast("s0", checks.finite_array("s0", s0), (n,))
    w0_a = z if w0 is None else _broadcast("w0", checks.finite_array("w0", w0), (n,))
    out = np.empty((n, engine.NOUT))
    # in chunks: Ctrl-C is seen between two calls into the compiled code, never inside one
    for lo in range(0, n, BATCH):
        hi = min(n, lo + BATCH)
        engine.attractor_batch(
            law_a[lo:hi],
            lp_a[lo:hi],
            nu_a[lo:hi],
            s0_a[lo:hi],
            w0_a[lo:hi],
            bool(from_breakaway),
            rtol,
            atol,
            max_slip_time,
            conv_tol,
            bool(diag),
            max_steps,
            out[lo:hi],
        )
    return out


def _nu(nu: npt.ArrayLike) -> FloatArray:
    a = checks.finite_array("nu", nu, bound=1e12, positive=True)
    if a.ndim > 1:
        raise ValueError(f"nu: expected a 1-d array of driving velocities, got shape {a.shape}")
    return a


def _laws(law: npt.ArrayLike, lp: npt.ArrayLike, n: int) -> tuple[npt.NDArray[np.int64], FloatArray]:
    try:
        law_i = np.asarray(law, dtype=np.int64)
    except (TypeError, ValueError):
        raise TypeError(f"law={law!r}: expected law ids 0 (weakening), 1 (cubic) or 2 (coulomb)") from None
    law_a = _broadcast("law", law_i, (n,))
    if not np.all((law_a >= 0) & (law_a <= LAW_COULOMB)):
        raise ValueError(f"law={law!r}: expected law ids 0 (weakening), 1 (cubic) or 2 (coulomb)")
    lp_a = _broadcast("lp", checks.finite_array("lp", lp, bound=1e15), (n, N_LAW_PARAMS))
    return law_a, lp_a


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
    t = np.ascontiguousarray(checks.finite_array("t_eval", t_eval, bound=1e15))
    if t.ndim != 1 or t.size == 0 or t[0] < 0 or np.any(np.diff(t) < 0):
        raise ValueError("t_eval: expected a non-empty, sorted 1-d array of finite times >= 0")
    law_a, lp_2d = _laws(law, lp, 1)
    lp_a = np.array(lp_2d[0], order="C")
    nu = float(_nu(nu))
    s0 = checks.state("s0", s0)
    w0 = checks.state("w0", w0)
    rtol, atol = checks.tolerances(rtol, atol)
    max_steps = checks.integer("max_steps", max_steps, lo=10, hi=10**9)
    check_memory(t.size * 40.0, f"{t.size} samples")
    cap = max(16, int(event_capacity))
    while True:
        y = np.empty((t.shape[0], 2))
        mode = np.empty(t.shape[0], dtype=np.int64)
        ev = np.empty((cap, 3))
        evn = np.zeros(1, dtype=np.int64)
        status = engine.trajectory(
            int(law_a[0]),
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
    nu_a = np.array(np.atleast_1d(_nu(nu)), order="C")
    n = nu_a.shape[0]
    law_a, lp_a = _laws(law, lp, n)
    s0_a = _broadcast("s0", checks.finite_array("s0", s0), (n,))
    t_a = _broadcast("period", checks.finite_array("period", period, bound=1e12, positive=True), (n,))
    tol = checks.positive("tol", tol, upper=1e-3, what="a tolerance of at most 1e-3")
    if tol < 1e-14:
        raise ValueError(f"tol={tol!r}: expected a tolerance of at least 1e-14")
    max_iter = checks.integer("max_iter", max_iter, lo=1, hi=1000)
    max_steps = checks.integer("max_steps", max_steps, lo=10, hi=10**9)
    out = np.empty((n, variational.NSH))
    variational.shoot_batch(law_a, lp_a, nu_a, s0_a, t_a, float(tol), int(max_iter), int(max_steps), out)
    return out
