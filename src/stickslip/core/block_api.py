"""Array-level entry points of the one-block engine (floats and arrays only).

These wrap the numba kernels of :mod:`stickslip.core.engine` and
:mod:`stickslip.core.variational`: they fix dtypes and memory layout, size the
output buffers, and check every argument as numbers (finite, in range, of the
right type: :mod:`stickslip.core.checks`) so that no NaN or absurd value reaches
the compiled loops. They do not validate physics; the model layer does that
before calling them. The chain engine's entry points are in
:mod:`stickslip.core.chain_api`; what both share (:class:`~stickslip.core.kernel.Kernel`,
the thread pool of row blocks) in :mod:`stickslip.core.kernel`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from . import checks, cuda, engine, variational
from .kernel import SERIAL_ROWS, Kernel, as_kernel, in_blocks, pole_is_an_error
from .laws import N_LAW_PARAMS
from .memory import check_memory
from .results import AttractorRows, FlowResult, ReturnMapRows, ShootingRows, Status

__all__ = [
    "BYTES_PER_ROW",
    "MAX_PHASES",
    "MAX_TIME",
    "Trajectories",
    "TrajectoryResult",
    "run_attractors",
    "run_flow",
    "run_return_maps",
    "run_shooting",
    "run_trajectory",
]

FloatArray = npt.NDArray[np.float64]

#: the most stick and slip phases one trajectory holds (the engine's bound)
MAX_PHASES = engine.MAX_PHASES


class TrajectoryResult(NamedTuple):
    """Output of :func:`run_trajectory`."""

    y: FloatArray
    mode: npt.NDArray[np.int64]
    events: FloatArray
    status: Status


#: memory of one row of run_attractors: the output (NOUT doubles), the checked copies of the
#: inputs (law id, law parameters, nu, s0, w0) and the validation's masks
BYTES_PER_ROW = 8.0 * (21 + 1 + 8 + 3) * 1.5


def run_attractors(
    law: Kernel | int,
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
    on_rows: Callable[[int], None] | None = None,
    backend: str = "cpu",
    fields: Sequence[str] | None = None,
) -> AttractorRows:
    """Run the attractor kernel for each row, in parallel.

    Parameters
    ----------
    law : Kernel or int
        The law's compiled kernel (or a built-in law's id).
    lp : array_like, shape (n, k) or (k,), k <= N_LAW_PARAMS
        Law parameters (missing trailing ones are 0).
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
    on_rows : callable, optional
        Called in this thread with the number of rows just finished, as blocks of
        rows finish (a progress bar's update).
    backend : {"cpu", "cuda", "auto"}, optional
        Where the rows run: this machine's cores (default), a CUDA GPU (the same
        kernel compiled by numba-cuda, :mod:`stickslip.core.cuda`), or the GPU
        where one is usable.
    fields : sequence of str, optional
        The fields of :class:`AttractorRows` to keep (default: all). The rows
        returned keep only these; on a GPU only these cross back to the host
        (a sweep keeps 12 of the 21: the copies of the results bound the GPU's
        speed, docs/gpu.md).

    Returns
    -------
    AttractorRows
        One row per parameter set, with named fields.

    Raises
    ------
    CudaUnavailableError
        For ``backend="cuda"`` where no CUDA device can run the kernel.

    """
    # first of all, from the input's size alone: the copies below and the output scale with it
    check_memory(np.size(nu) * BYTES_PER_ROW, f"{np.size(nu)} parameter sets")
    rtol, atol = checks.tolerances(rtol, atol)
    max_slip_time = checks.positive("max_slip_time", max_slip_time, upper=1e12)
    conv_tol = checks.positive("conv_tol", conv_tol, upper=0.1, what="a relative tolerance below 0.1")
    max_steps = checks.integer("max_steps", max_steps, lo=10, hi=10**9)
    kept = None if fields is None else AttractorRows.check_fields(fields)
    if kept is not None and len(kept) == engine.NOUT:
        kept = None  # every field: the full rows
    nu_a = np.array(np.atleast_1d(_nu(nu)), order="C")
    n = nu_a.shape[0]
    kernel = as_kernel(law)
    on_gpu = cuda.resolve_backend(backend) == "cuda"
    law_a, lp_a = _laws(kernel, lp, n, pad=not on_gpu)
    z = np.zeros(n)
    s0_a = z if s0 is None else _broadcast("s0", checks.finite_array("s0", s0), (n,))
    w0_a = z if w0 is None else _broadcast("w0", checks.finite_array("w0", w0), (n,))
    if on_gpu:
        columns = np.arange(engine.NOUT) if kept is None else np.array([_LAYOUT[x] for x in kept])
        out = np.empty((n, columns.size))
        cuda.run_attractors_cuda(
            kernel.engine.attractor_ws, law_a, lp_a, nu_a, s0_a, w0_a, bool(from_breakaway), rtol, atol,
            max_slip_time, conv_tol, bool(diag), max_steps, out, on_rows, columns,
        )  # fmt: skip
        return AttractorRows(out, kept)
    out = np.empty((n, engine.NOUT))
    if n <= SERIAL_ROWS:
        # a few rows (one command's cycle): the per-row kernel that attractor_rows calls,
        # straight from here, so that a command that never runs a batch does not compile
        # attractor_rows (1-2 s on a fresh install, most of it LLVM linking it again)
        one = kernel.engine.attractor_ws
        ws = _workspace(4 if diag else 2)
        for i in range(n):
            with pole_is_an_error():
                one(
                    law_a[i],
                    lp_a[i],
                    nu_a[i],
                    s0_a[i],
                    w0_a[i],
                    bool(from_breakaway),
                    rtol,
                    atol,
                    max_slip_time,
                    conv_tol,
                    max_steps,
                    out[i],
                    *ws,
                )
        if on_rows is not None:
            on_rows(n)
        return _keep(out, kept)
    rows = kernel.engine.attractor_rows

    def call(lo: int, hi: int) -> None:
        rows(
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

    in_blocks(call, n, on_rows)
    return _keep(out, kept)


#: the column of each field of AttractorRows in the engine's rows
_LAYOUT = AttractorRows.layout()


def _keep(out: np.ndarray, fields: tuple[str, ...] | None) -> AttractorRows:
    """Return the engine's rows ``out`` as AttractorRows keeping ``fields`` (None: all)."""
    if fields is None:
        return AttractorRows(out)
    return AttractorRows(out[:, [_LAYOUT[x] for x in fields]], fields)


def _workspace(n: int) -> tuple[np.ndarray, ...]:
    """Allocate the work arrays of one integration, as :func:`stickslip.core.engine.new_workspace` does."""
    return (
        np.empty((engine.N_STAGES_EXTENDED, n)),
        np.empty((7, n)),
        np.empty(n),
        np.empty(n),
        np.empty(n),
        np.empty(engine.NTRK),
        np.empty(0),
        np.empty((0, 2)),
        np.empty(0, dtype=np.int64),
        np.empty((0, 3)),
        np.zeros(1, dtype=np.int64),
    )


def _nu(nu: npt.ArrayLike) -> FloatArray:
    a = checks.finite_array("nu", nu, bound=checks.NU_MAX, positive=True)
    if a.ndim > 1:
        raise ValueError(f"nu: expected a 1-d array of driving velocities, got shape {a.shape}")
    if a.size and float(a.min()) < checks.NU_MIN:
        raise ValueError(
            f"nu: {float(a.min())!r} is below {checks.NU_MIN:g}, the smallest driving velocity resolved "
            "in double precision"
        )
    return a


def _laws(
    kernel: Kernel, lp: npt.ArrayLike, n: int, pad: bool = True
) -> tuple[npt.NDArray[np.int64], FloatArray]:
    """Return the law ids and the parameters, ``(n, N_LAW_PARAMS)`` (``pad``) or ``(n, max(k, 1))``.

    The CPU kernels take all :data:`N_LAW_PARAMS` columns, the trailing unused ones
    zeros; the GPU's takes the ``k`` given (fewer bytes to copy, fewer to make).
    """
    law_a = np.full(n, kernel.law_id, dtype=np.int64)
    lp_c = checks.finite_array("lp", lp, bound=1e15)
    k = lp_c.shape[-1] if lp_c.ndim else 0
    if lp_c.ndim == 0 or lp_c.ndim > 2 or k > N_LAW_PARAMS:
        raise ValueError(
            f"lp: shape {lp_c.shape}: expected law parameters of shape (n, k) or (k,), k <= {N_LAW_PARAMS}"
        )
    width = N_LAW_PARAMS if pad else max(k, 1)
    if k < width:  # the trailing parameters of a law with fewer are unused: zeros
        lp_c = np.concatenate([lp_c, np.zeros((*lp_c.shape[:-1], width - k))], axis=-1)
    if lp_c.shape == (n, width) and lp_c.flags.c_contiguous and lp_c.flags.writeable:
        return law_a, lp_c  # already what the kernels take: no copy
    lp_a = _broadcast("lp", lp_c, (n, width))
    return law_a, lp_a


def _law_row(kernel: Kernel, lp: npt.ArrayLike) -> FloatArray:
    """Return one parameter set, checked and padded as :func:`_laws` does, as the one-row kernels take it."""
    _, lp_2d = _laws(kernel, lp, 1)
    return np.array(lp_2d[0], order="C")


def _full_law_row(lp: npt.ArrayLike) -> FloatArray:
    """Return ``lp`` as a float array after checking its shape only: all :data:`N_LAW_PARAMS` parameters.

    The compiled kernels read :data:`N_LAW_PARAMS` entries, unchecked: a shorter
    array (unpadded) would be read past its end. One shape check a call, not one a step.
    """
    a = np.asarray(lp, dtype=np.float64)
    if a.ndim != 1 or a.shape[0] < N_LAW_PARAMS:
        got = f"length {a.shape[0]}" if a.ndim == 1 else f"shape {a.shape}"
        raise ValueError(
            f"lp: {got}, expected length {N_LAW_PARAMS}: with checked=False the kernel reads all "
            f"{N_LAW_PARAMS} law parameters as given (pad with zeros, or leave checked=True)"
        )
    return a


def _broadcast(name: str, a: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    try:
        # a writable copy: numba compiles read-only arrays (broadcast views) separately
        return np.array(np.broadcast_to(a, shape), order="C")
    except ValueError:
        raise ValueError(f"{name}: shape {a.shape} does not broadcast to {shape}") from None


#: the latest sample time of a trajectory (units of sqrt(m/k)): past it, a slip step is below
#: the resolution of a double
MAX_TIME = 1e15


class Trajectories:
    """Trajectories of one law, its parameters and ``nu``, checked once: the runs of a return map.

    :func:`run_trajectory` checks each of its arguments, which takes a few times
    longer than a short run itself; a return map's secant iterations run thousands of
    them from the same law and ``nu``. These are checked here once, and each call
    checks only its start and end time, reusing one set of buffers.

    Parameters
    ----------
    law, lp, nu, rtol, atol, max_steps
        As in :func:`run_trajectory` (one row of law parameters).

    """

    def __init__(
        self,
        law: Kernel | int,
        lp: npt.ArrayLike,
        nu: float,
        *,
        rtol: float,
        atol: float,
        max_steps: int = 2_000_000,
    ) -> None:
        self.kernel = as_kernel(law)
        self.law_id = int(self.kernel.law_id)
        self.lp = _law_row(self.kernel, lp)
        self.nu = float(_nu(nu))
        self.rtol, self.atol = checks.tolerances(rtol, atol)
        self.max_steps = checks.integer("max_steps", max_steps, lo=10, hi=10**9)
        self._t = np.empty(1)
        self._y = np.empty((1, 2))
        self._mode = np.empty(1, dtype=np.int64)
        self._ev = np.empty((64, 3))
        self._evn = np.zeros(1, dtype=np.int64)

    def events(self, s0: float, w0: float, t_end: float) -> tuple[FloatArray, Status]:
        """Integrate from ``(s0, w0)`` to ``t_end``; return the events ``(time, kind, s)`` and the status.

        The same events and status as ``run_trajectory(..., [t_end])`` with the
        arguments given to the constructor.
        """
        s0 = checks.state("s0", s0)
        w0 = checks.state("w0", w0)
        if not 0.0 <= t_end <= MAX_TIME:  # NaN too
            raise ValueError(f"t_end={t_end!r}: expected a time between 0 and {MAX_TIME:g}")
        self._t[0] = t_end
        while True:
            self._evn[0] = 0
            with pole_is_an_error():
                status = self.kernel.engine.trajectory(
                    self.law_id, self.lp, self.nu, float(s0), float(w0), self._t, self.rtol, self.atol,
                    self.max_steps, self._y, self._mode, self._ev, self._evn,
                )  # fmt: skip
            if self._evn[0] <= self._ev.shape[0]:
                return self._ev[: self._evn[0]].copy(), Status.from_code(status)
            self._ev = np.empty((int(self._evn[0]), 3))


def run_trajectory(
    law: Kernel | int,
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
) -> TrajectoryResult:
    """Integrate from ``(s0, w0)`` and sample at ``t_eval`` (sorted, starting at or after 0).

    Returns
    -------
    TrajectoryResult
        A named tuple of:
    y : ndarray, shape (len(t_eval), 2)
        Spring force and velocity.
    mode : ndarray of int, shape (len(t_eval),)
        0 stick, +1 forward slip, -1 backward slip.
    events : ndarray, shape (m, 3)
        Rows ``(time, kind, spring force)``, kinds ``EV_*`` of the engine.
    status : Status
        How the integration ended.

    """
    t = np.ascontiguousarray(checks.finite_array("t_eval", t_eval, bound=MAX_TIME))
    if t.ndim != 1 or t.size == 0 or t[0] < 0 or np.any(np.diff(t) < 0):
        raise ValueError("t_eval: expected a non-empty, sorted 1-d array of finite times >= 0")
    kernel = as_kernel(law)
    lp_a = _law_row(kernel, lp)
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
        with pole_is_an_error():
            status = kernel.engine.trajectory(
                int(kernel.law_id),
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
            return TrajectoryResult(y, mode, ev[: evn[0]].copy(), Status.from_code(status))
        cap = int(evn[0])


def run_shooting(
    law: Kernel | int,
    lp: npt.ArrayLike,
    nu: npt.ArrayLike,
    s0: npt.ArrayLike,
    period: npt.ArrayLike,
    *,
    tol: float,
    max_iter: int = 30,
    max_steps: int = 200_000,
) -> ShootingRows:
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
    ShootingRows
        One orbit (or the reason there is none) per row.

    """
    guesses = _orbit_guesses(law, lp, nu, s0, period, tol, max_iter)
    max_steps = checks.integer("max_steps", max_steps, lo=10, hi=10**9)
    rows = guesses.kernel.variational.shoot_rows
    return ShootingRows(_orbit_rows(rows, guesses, variational.NSH, int(max_steps)))


class _Guesses(NamedTuple):
    """The checked rows of a search for periodic orbits from guesses (:func:`_orbit_guesses`)."""

    kernel: Kernel
    law: npt.NDArray[np.int64]
    lp: FloatArray
    nu: FloatArray
    s0: FloatArray
    period: FloatArray
    tol: float
    max_iter: int


def _orbit_guesses(
    law: Kernel | int,
    lp: npt.ArrayLike,
    nu: npt.ArrayLike,
    s0: npt.ArrayLike,
    period: npt.ArrayLike,
    tol: float,
    max_iter: int,
) -> _Guesses:
    """Check the rows of a search for periodic orbits from guesses (shooting, return maps)."""
    nu_a = np.array(np.atleast_1d(_nu(nu)), order="C")
    n = nu_a.shape[0]
    kernel = as_kernel(law)
    law_a, lp_a = _laws(kernel, lp, n)
    s0_a = _broadcast("s0", checks.finite_array("s0", s0), (n,))
    t_a = _broadcast("period", checks.finite_array("period", period, bound=1e12, positive=True), (n,))
    tol = checks.positive("tol", tol, upper=1e-3, what="a tolerance of at most 1e-3")
    if tol < 1e-14:
        raise ValueError(f"tol={tol!r}: expected a tolerance of at least 1e-14")
    max_iter = checks.integer("max_iter", max_iter, lo=1, hi=1000)
    return _Guesses(kernel, law_a, lp_a, nu_a, s0_a, t_a, tol, max_iter)


def _orbit_rows(rows: Callable[..., None], g: _Guesses, width: int, *options: int) -> FloatArray:
    """Run the row kernel ``rows`` of an orbit search over the rows ``g``, in blocks on the threads.

    ``rows(law, lp, nu, s0, period, tol, max_iter, *options, out)`` fills ``out``,
    ``width`` values a row (the shooting's and the return maps' kernels); return ``out``.
    """
    n = g.nu.shape[0]
    out = np.empty((n, width))

    def call(lo: int, hi: int) -> None:
        rows(
            g.law[lo:hi], g.lp[lo:hi], g.nu[lo:hi], g.s0[lo:hi], g.period[lo:hi], float(g.tol),
            int(g.max_iter), *options, out[lo:hi],
        )  # fmt: skip

    in_blocks(call, n)
    return out


def run_return_maps(
    law: Kernel | int,
    lp: npt.ArrayLike,
    nu: npt.ArrayLike,
    s0: npt.ArrayLike,
    period: npt.ArrayLike,
    *,
    tol: float = 1e-10,
    max_iter: int = 40,
) -> ReturnMapRows:
    """Find non-sticking periodic orbits as fixed points of the return map on ``w = nu``, in parallel.

    The return map takes the spring force at one upward crossing of ``w = nu`` to
    the next, by the exact non-smooth engine (stops, backward slips and velocity
    reversals on the way): what covers slip reversal, which shooting in the slip
    phase cannot. Each row runs compiled from its guess to its orbit (secant
    iterations, then the map's derivative), the rows side by side on the threads.

    Parameters
    ----------
    law, lp, nu : array_like
        As in :func:`run_attractors`.
    s0, period : array_like, shape (n,)
        Guesses: the spring-force maximum and the period (dimensionless).
    tol : float, optional
        Tolerance on ``|P(s) - s|`` relative to ``max(1, |s0|)``; the flow runs at
        ``tol / 100``.
    max_iter : int, optional
        Secant iterations allowed.

    Returns
    -------
    ReturnMapRows
        One orbit (or why there is none) per row.

    """
    guesses = _orbit_guesses(law, lp, nu, s0, period, tol, max_iter)
    n, tol = guesses.nu.shape[0], guesses.tol
    checks.tolerances(tol * 1e-2, tol * 1e-4)  # the flow's, as the Python secant checks them
    check_memory(n * 8.0 * (engine.NRM + 12), f"{n} return maps")
    return ReturnMapRows(_orbit_rows(guesses.kernel.engine.return_map_rows, guesses, engine.NRM))


def run_flow(
    law: Kernel | int,
    lp: npt.ArrayLike,
    nu: float,
    s0: float,
    w0: float,
    period: float,
    *,
    rtol: float,
    measure: bool = False,
    max_steps: int = 200_000,
    checked: bool = True,
    reverse: bool = False,
) -> FlowResult:
    """Integrate the forward slip flow and its variational equations over ``[0, period]``.

    Parameters
    ----------
    law, lp, nu
        As in :func:`run_attractors` (one parameter set).
    s0, w0 : float
        Start.
    period : float
        Time to integrate (> 0).
    rtol : float
        Relative tolerance (the absolute one is ``rtol / 100``).
    measure : bool, optional
        Record the spring force where ``w`` crosses ``nu`` downward and the extremes of ``w``.
    max_steps : int, optional
        Step budget.
    checked : bool, optional
        Check every argument (default). An inner loop that calls this hundreds of
        times with values it made itself (Newton iterations) may skip the checks;
        ``lp`` must then be a float array of length ``N_LAW_PARAMS`` (its shape is
        still checked: a shorter one is a ValueError).
    reverse : bool, optional
        Integrate backward in time, over ``[-period, 0]`` (the slip still forward: ``w > 0``).
        An unstable orbit is a stable one of the backward flow: shooting it so is as
        well-conditioned as shooting a stable orbit forward. The result's monodromy and
        ``d_nu`` are then those of the backward flow; its ``integral_dfdw`` is still the
        integral of ``f'(w)`` over the orbit's forward time, and ``s_min`` the spring force
        where ``w`` crosses ``nu`` downward in forward time.

    Raises
    ------
    RuntimeError
        When the integration fails (step budget, non-finite state).

    """
    kernel = as_kernel(law)
    if checked:
        lp_a = _law_row(kernel, lp)
        nu = float(_nu(nu))
        s0 = checks.state("s0", s0)
        w0 = checks.state("w0", w0)
        period = checks.positive("period", period, upper=1e12)
        rtol, _ = checks.tolerances(rtol, rtol * 1e-2)
        max_steps = checks.integer("max_steps", max_steps, lo=10, hi=10**9)
    else:
        lp_a = _full_law_row(lp)
    va = kernel.variational
    y = np.zeros(va.NVAR)
    y[0], y[1], y[2], y[5] = s0, w0, 1.0, 1.0
    kv = np.empty((12, 7))
    extras = np.zeros(va.NX)
    direction = -1.0 if reverse else 1.0
    va.flow_variational(
        kernel.law_id, lp_a, nu, y, period, rtol, rtol * 1e-2, max_steps, measure, direction, kv, extras
    )
    if extras[va.X_STATUS] != va.VS_OK:
        why = (
            "the step budget ran out"
            if extras[va.X_STATUS] == va.VS_MAX_STEPS
            else "the state became non-finite"
        )
        raise RuntimeError(f"slip flow from (s, w) = ({s0:.6g}, {w0:.6g}) over tau = {period:.6g}: {why}")
    if reverse:
        y[8] = -y[8]  # the integral over the forward-time interval
    return FlowResult(y, extras)
