"""Array-level entry points of the forced oscillator's engine (:mod:`stickslip.core.forced`).

Floats and arrays in, floats and arrays out: a law's kernel and parameter vector
(``law.arrays()``), the forcing vector ``fp = (nu0, nu1, omega, phi, q, delta)``
(:data:`FORCING_FIELDS`) and states ``(s, w)`` in the dimensionless units of the
one-block model. Rows run in blocks on the thread pool of :func:`in_blocks`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from . import forced as _forced
from .kernel import Kernel, in_blocks, pole_is_an_error

__all__ = [
    "FORCED_STATUS",
    "FORCING_FIELDS",
    "STAT_FIELDS",
    "ForcedStats",
    "forced_poincare",
    "forced_strobe",
    "forced_trajectory",
]

FloatArray = npt.NDArray[np.float64]

#: the forcing vector's entries, in order
FORCING_FIELDS = ("nu0", "nu1", "omega", "phi", "q", "delta")
#: the statistics' entries, in order (``ST_*`` of the engine)
STAT_FIELDS = (
    "stops",
    "breakaways",
    "reversals",
    "stick_time",
    "steps",
    "status",
    "next_sample",
    "s_min",
    "s_max",
    "w_min",
    "w_max",
    "touches",
)
#: what each status means
FORCED_STATUS = {
    _forced.F_OK: "ok",
    _forced.F_MAX_STEPS: "ran out of integration steps",
    _forced.F_NONFINITE: "the motion left the finite numbers",
    _forced.F_MAX_EVENTS: "ran out of stick and slip phases",
}
#: slip steps and phases one call into the engine may take, per forcing period asked
STEPS_PER_PERIOD = 200_000


@dataclass(frozen=True)
class ForcedStats:
    """What happened over an interval: events, stick time, extremes, status.

    Attributes
    ----------
    stops, breakaways, reversals, touches : int
        Slip to stick, stick to slip, slip reversed without stick, ``w`` touching 0
        with the net force still pushing on.
    stick_time : float
        Time spent stuck (units of ``sqrt(m/k)``).
    steps : int
        Slip steps taken.
    s_min, s_max, w_min, w_max : float
        Extremes of the spring force and of the velocity (the spring force's exactly:
        at events and where ``s' = 0``; the velocity's at steps and events).
    status : str
        ``"ok"`` or what stopped the engine.

    """

    stops: int
    breakaways: int
    reversals: int
    touches: int
    stick_time: float
    steps: int
    s_min: float
    s_max: float
    w_min: float
    w_max: float
    status: str

    @classmethod
    def from_array(cls, a: FloatArray) -> ForcedStats:
        """Decode the engine's statistics vector."""
        return cls(
            stops=int(a[_forced.ST_STOPS]),
            breakaways=int(a[_forced.ST_BREAKS]),
            reversals=int(a[_forced.ST_REVERSALS]),
            touches=int(a[_forced.ST_TOUCHES]),
            stick_time=float(a[_forced.ST_STICK_TIME]),
            steps=int(a[_forced.ST_STEPS]),
            s_min=float(a[_forced.ST_S_MIN]),
            s_max=float(a[_forced.ST_S_MAX]),
            w_min=float(a[_forced.ST_W_MIN]),
            w_max=float(a[_forced.ST_W_MAX]),
            status=FORCED_STATUS.get(int(a[_forced.ST_STATUS]), "unknown"),
        )


def _fp(fp: npt.ArrayLike) -> FloatArray:
    a = np.ascontiguousarray(fp, dtype=np.float64)
    if a.shape[-1] != _forced.NFP:
        raise ValueError(f"fp: expected {_forced.NFP} entries {FORCING_FIELDS}, got shape {a.shape}")
    return a


def _budget(periods: float) -> int:
    return int(min(2**62, max(1.0, periods) * STEPS_PER_PERIOD))


def forced_trajectory(
    kernel: Kernel,
    lp: FloatArray,
    fp: npt.ArrayLike,
    start: tuple[float, float, float],
    ts: npt.ArrayLike,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> tuple[FloatArray, ForcedStats]:
    """Sample the motion from ``start = (tau0, s0, w0)`` at the times ``ts`` (ascending).

    Returns ``samples`` (``len(ts)`` x 3: ``s``, ``w``, mode 0 stick / +-1 slip)
    and the statistics of the run.
    """
    f = _fp(fp)
    t = np.ascontiguousarray(ts, dtype=np.float64)
    samples = np.full((t.size, 3), np.nan)
    stats = np.zeros(_forced.NST)
    t0, s0, w0 = (float(v) for v in start)
    periods = (float(t[-1]) - t0) * f[2] / (2 * np.pi) if t.size else 1.0
    with pole_is_an_error():
        kernel.forced_engine.trajectory(
            kernel.law_id, lp, f, t0, s0, w0, t, rtol, atol, _budget(periods), samples, stats
        )
    return samples, ForcedStats.from_array(stats)


def forced_poincare(
    kernel: Kernel,
    lp: FloatArray,
    fp: npt.ArrayLike,
    t0: float,
    x: npt.ArrayLike,
    periods: int = 1,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> tuple[FloatArray, FloatArray, int, ForcedStats]:
    """Apply the stroboscopic map ``periods`` times to ``x = (s, w)`` at phase ``t0``.

    Returns the image ``(s, w)``, its Jacobian (2 x 2, with the saltation matrices
    of every transition), the mode after it (0 stuck, +-1 slipping) and the
    statistics of the periods.
    """
    f = _fp(fp)
    out = np.zeros(3)
    phi = np.zeros(4)
    stats = np.zeros(_forced.NST)
    xa = np.ascontiguousarray(x, dtype=np.float64)
    with pole_is_an_error():
        kernel.forced_engine.poincare(
            kernel.law_id, lp, f, float(t0), xa, int(periods), rtol, atol, _budget(periods), out, phi, stats
        )
    return out[:2].copy(), phi.reshape(2, 2), int(out[2]), ForcedStats.from_array(stats)


def _row_arrays(lp: npt.ArrayLike, fp: npt.ArrayLike, x0: npt.ArrayLike) -> tuple[FloatArray, ...]:
    f = np.atleast_2d(_fp(fp))
    n = f.shape[0]
    lpa = np.ascontiguousarray(np.broadcast_to(np.atleast_2d(np.asarray(lp, dtype=np.float64)), (n, 8)))
    xa = np.ascontiguousarray(np.broadcast_to(np.atleast_2d(np.asarray(x0, dtype=np.float64)), (n, 2)))
    return lpa, f, xa


def forced_strobe(
    kernel: Kernel,
    lp: npt.ArrayLike,
    fp: npt.ArrayLike,
    x0: npt.ArrayLike,
    n_transient: int,
    n_record: int,
    *,
    t0: float = 0.0,
    lyapunov: bool = False,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    done: Callable[[int], None] | None = None,
    backend: str = "cpu",
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Return every row's stroboscopic samples, Lyapunov exponents and statistics.

    ``lp`` (8 or rows x 8), ``fp`` (6 or rows x 6) and ``x0`` (2 or rows x 2) are
    broadcast against each other's rows. The samples are ``(rows, n_record, 2)``;
    the exponents ``(rows, 2)`` over the recorded periods (per unit dimensionless
    time; NaN without ``lyapunov``, ``lambda_2 = -inf`` where stick collapsed the
    tangent frame); the statistics (rows x ``len(STAT_FIELDS)``) cover the recorded
    periods. ``backend`` ``"cuda"`` runs a GPU thread a row (:mod:`stickslip.core.cuda`),
    ``"auto"`` where a GPU is usable, ``"cpu"`` the threads of :func:`in_blocks`.
    """
    from .cuda import resolve_backend, run_forced_strobe_cuda

    lpa, f, xa = _row_arrays(lp, fp, x0)
    n = f.shape[0]
    out = np.full((n, int(n_record), 2), np.nan)
    lyap = np.full((n, 2), np.nan)
    stats = np.zeros((n, _forced.NST))
    budget = _budget(1)
    if resolve_backend(backend) == "cuda":
        with pole_is_an_error():
            run_forced_strobe_cuda(
                kernel.forced_engine.strobe_one, kernel.law_id, lpa, f, xa, float(t0), int(n_transient),
                int(n_record), rtol, atol, budget, bool(lyapunov), out, lyap, stats, done,
            )  # fmt: skip
        return out, lyap, stats
    fn = kernel.forced_engine.strobe_rows

    def call(lo: int, hi: int) -> None:
        fn(
            kernel.law_id,
            lpa[lo:hi],
            f[lo:hi],
            float(t0),
            xa[lo:hi],
            int(n_transient),
            int(n_record),
            rtol,
            atol,
            budget,
            bool(lyapunov),
            out[lo:hi],
            lyap[lo:hi],
            stats[lo:hi],
        )

    in_blocks(call, n, done)
    return out, lyap, stats
