"""The forced oscillator's motion: trajectories, stroboscopic sections, Lyapunov exponents.

Every function takes a :class:`~.system.ForcedSystem` (dimensionless) or a
:class:`~.system.PhysicalForcedSystem` and returns results in the system's units:
dimensionless for the first, SI for the second (its ``physical`` flag says which).
The stroboscopic section is taken at the times ``t0 + k T`` (``T = 2 pi / omega``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..core.forced_api import ForcedStats, forced_poincare, forced_strobe, forced_trajectory
from ..core.memory import check_memory
from ..errors import ArgumentTypeError
from ..models import Scales
from ..units import check_number
from .system import ForcedSystem, as_forced

__all__ = [
    "ForcedTrajectory",
    "Lyapunov",
    "Section",
    "check_start",
    "lyapunov",
    "lyapunov_two_trajectories",
    "poincare_section",
    "trajectory",
]

#: the engine's tolerances for sections, diagrams and exponents (relative, absolute)
RTOL = 1e-10
ATOL = 1e-12
#: the largest number of periods one call runs
MAX_PERIODS = 10_000_000
#: the longest motion one row simulates, in units of sqrt(m/k): 1.6e6 natural periods, some
#: 1e8 slip steps (minutes on one core); a slower forcing or more periods is refused up front
MAX_DURATION = 1e7
#: bytes of one trajectory sample (time, s, w, mode and the arrays made from them)
SAMPLE_BYTES = 64
#: the most samples one trajectory holds (640 MB, a plot's worth many times over)
MAX_SAMPLES = 10_000_000


def check_duration(system: ForcedSystem, periods: float, what: str) -> None:
    """Refuse, in one line, a run of ``periods`` forcing periods longer than :data:`MAX_DURATION`."""
    span = periods * system.period
    if span > MAX_DURATION:
        raise ValueError(
            f"{what}: {periods:g} periods of 2 pi/omega = {system.period:.4g} (omega = {system.omega:g}) "
            f"are {span:.3g} units of sqrt(m/k), more than {MAX_DURATION:g} (about "
            f"{MAX_DURATION / 2 / math.pi:.2g} natural periods); ask fewer periods or a faster forcing"
        )


def check_start(start: Any) -> tuple[float, float]:
    """Return ``start`` as ``(s0, w0)``: two finite numbers."""
    try:
        s0, w0 = (float(v) for v in start)
    except (TypeError, ValueError):
        raise ArgumentTypeError(
            f"start={start!r}: expected (s0, w0), the spring force and the velocity at the first section"
        ) from None
    if not (math.isfinite(s0) and math.isfinite(w0) and abs(s0) < 1e12 and abs(w0) < 1e12):
        raise ValueError(f"start={start!r}: expected finite numbers of magnitude below 1e12")
    return s0, w0


def _periods(value: Any, name: str, *, zero: bool = False) -> int:
    v = check_number(
        value, name, allow_zero=zero, upper=MAX_PERIODS, upper_inclusive=True, what="a number of periods"
    )
    if v != int(v):
        raise ValueError(f"{name}={value!r}: expected a whole number of forcing periods")
    return int(v)


#: forcing periods per call into the engine while a transient runs: Ctrl-C is seen between calls
CHUNK_PERIODS = 1000


def run_periods(system: ForcedSystem, x: Any, periods: int, t0: float = 0.0) -> tuple[np.ndarray, float]:
    """Return the state after ``periods`` forcing periods from ``x`` at ``t0``, and the time then.

    The periods run in calls of at most :data:`CHUNK_PERIODS`, so that Ctrl-C stops a long
    transient between two of them.
    """
    kernel, lp, fp = system.arrays()
    state = np.asarray(x, dtype=float)
    done = 0
    while done < periods:
        k = min(CHUNK_PERIODS, periods - done)
        state, _, _, stats = forced_poincare(
            kernel, lp, fp, t0 + done * system.period, state, k, rtol=RTOL, atol=ATOL
        )
        if stats.status != "ok":
            raise RuntimeError(f"the motion of {system.describe()}: the engine {stats.status}")
        done += k
    return state, t0 + periods * system.period


def _si(scales: Scales | None, kind: str, x: Any) -> Any:
    return x if scales is None else scales.to_si(kind, x)


@dataclass(frozen=True)
class ForcedTrajectory:
    """A sampled motion of the forced oscillator.

    Attributes
    ----------
    t : ndarray
        Times (s or units of ``sqrt(m/k)``).
    s, w : ndarray
        Spring force (N or ``mu_s W``) and block velocity (m/s or ``mu_s W / sqrt(k m)``).
    mode : ndarray of int
        0 stuck, +1 / -1 slipping forward / backward.
    stats : ForcedStats
        Events over the run (dimensionless).
    physical : bool

    """

    t: np.ndarray
    s: np.ndarray
    w: np.ndarray
    mode: np.ndarray
    stats: ForcedStats
    physical: bool
    system: ForcedSystem = field(repr=False)

    def to_dataset(self) -> Any:
        """Return an xarray Dataset with CF attributes and units."""
        import xarray as xr

        from ..models.scales import unit_attrs

        p = self.physical
        return xr.Dataset(
            {
                "spring_force": ("time", self.s, {"long_name": "spring force", **unit_attrs("force", p)}),
                "velocity": ("time", self.w, {"long_name": "block velocity", **unit_attrs("velocity", p)}),
                "mode": (
                    "time",
                    self.mode.astype(np.int8),
                    {
                        "long_name": "stick or slip",
                        "flag_values": np.array([-1, 0, 1], dtype=np.int8),
                        "flag_meanings": "slip_backward stick slip_forward",
                    },
                ),
            },
            coords={"time": ("time", self.t, {"long_name": "time", **unit_attrs("time", p)})},
            attrs={"system": self.system.describe(), "stops": self.stats.stops, "Conventions": "CF-1.10"},
        )


def trajectory(
    system: Any,
    periods: float = 10.0,
    *,
    samples_per_period: int = 200,
    start: Any = (0.0, 0.0),
    transient: int = 0,
    t0: float = 0.0,
) -> ForcedTrajectory:
    """Return the motion over ``periods`` forcing periods after ``transient`` ones.

    Parameters
    ----------
    system : ForcedSystem or PhysicalForcedSystem
        The oscillator: dimensionless, or physical (results in SI).
    periods : float
        Forcing periods sampled.
    samples_per_period : int
        Samples per period (events are not sampled: they are exact in the engine).
    start : (float, float)
        ``(s0, w0)`` at ``t0`` (dimensionless); at rest by default.
    transient : int
        Periods run before the samples.
    t0 : float
        Start time (dimensionless).

    """
    dp, scales = as_forced(system)
    s0, w0 = check_start(start)
    periods = check_number(
        periods, "periods", upper=MAX_PERIODS, upper_inclusive=True, what="a number of periods"
    )
    n = int(
        check_number(
            samples_per_period, "samples_per_period", upper=1e5, what="samples per period (1 to 1e5)"
        )
    )
    transient = _periods(transient, "transient", zero=True)
    check_duration(dp, transient + periods, f"transient={transient}, periods={periods:g}")
    n_samples = max(2, round(periods * n) + 1)
    if n_samples > MAX_SAMPLES:
        raise ValueError(
            f"periods={periods:g}, samples_per_period={n}: {n_samples:.3g} samples, more than "
            f"{MAX_SAMPLES:.0e}; ask fewer periods or fewer samples per period (a section or a diagram "
            "samples once a period)"
        )
    check_memory(n_samples * SAMPLE_BYTES, f"{n_samples} samples ({periods:g} periods x {n})", "ask fewer")
    kernel, lp, fp = dp.arrays()
    if transient:
        (s0, w0), t0 = run_periods(dp, (s0, w0), transient, t0)
    ts = t0 + np.linspace(0.0, periods * dp.period, n_samples)
    samples, stats = forced_trajectory(kernel, lp, fp, (t0, s0, w0), ts, rtol=RTOL, atol=ATOL)
    if stats.status != "ok":
        raise RuntimeError(f"forced trajectory of {dp.describe()}: the engine {stats.status}")
    return ForcedTrajectory(
        t=_si(scales, "time", ts),
        s=_si(scales, "force", samples[:, 0]),
        w=_si(scales, "velocity", samples[:, 1]),
        mode=samples[:, 2].astype(np.int64),
        stats=stats,
        physical=scales is not None,
        system=dp,
    )


@dataclass(frozen=True)
class Section:
    """Stroboscopic samples: the state at ``t0 + k T`` after the transient.

    Attributes
    ----------
    s, w : ndarray
        Spring force and velocity at each section (the system's units).
    stops_per_period : float
        Stick phases per forcing period over the recorded periods.
    stick_fraction : float
        Fraction of the recorded time spent stuck.
    status : str

    """

    s: np.ndarray
    w: np.ndarray
    stops_per_period: float
    stick_fraction: float
    status: str
    physical: bool


def poincare_section(
    system: Any, periods: int = 1000, *, transient: int = 500, start: Any = (0.0, 0.0), t0: float = 0.0
) -> Section:
    """Return ``periods`` stroboscopic samples after ``transient`` periods from ``start``."""
    dp, scales = as_forced(system)
    s0, w0 = check_start(start)
    n = _periods(periods, "periods")
    nt = _periods(transient, "transient", zero=True)
    check_duration(dp, nt + n, f"transient={nt}, periods={n}")
    check_memory(n * 2 * 8 * 2, f"{n} sections", "ask fewer periods")
    kernel, lp, fp = dp.arrays()
    out, _, stats = forced_strobe(kernel, lp, fp, (s0, w0), nt, n, t0=t0, rtol=RTOL, atol=ATOL)
    st = ForcedStats.from_array(stats[0])
    return Section(
        s=_si(scales, "force", out[0, :, 0]),
        w=_si(scales, "velocity", out[0, :, 1]),
        stops_per_period=st.stops / n,
        stick_fraction=st.stick_time / (n * dp.period),
        status=st.status,
        physical=scales is not None,
    )


@dataclass(frozen=True)
class Lyapunov:
    """Lyapunov exponents of the forced motion (per unit time: 1/s, or per ``sqrt(m/k)``).

    Attributes
    ----------
    exponents : ndarray
        ``(lambda_1, lambda_2)``, largest first; ``lambda_2 = -inf`` where stick phases
        collapse the tangent plane onto a line (stick forgets the velocity). The
        third exponent of the flow, along time, is 0.
    periods : int
        Periods averaged over.
    running : ndarray
        ``lambda_1`` over the first 1/8, 1/4, 1/2 and all of the periods: its convergence.
    stops_per_period : float

    """

    exponents: np.ndarray
    periods: int
    running: np.ndarray
    stops_per_period: float
    physical: bool

    @property
    def largest(self) -> float:
        """The largest exponent."""
        return float(self.exponents[0])

    @property
    def chaotic(self) -> bool:
        """Whether the largest exponent is positive beyond its convergence spread."""
        spread = float(np.ptp(self.running[-2:]))
        return self.largest > max(2.0 * spread, 1e-3 * abs(self.largest))


def lyapunov(
    system: Any, periods: int = 2000, *, transient: int = 500, start: Any = (0.0, 0.0), t0: float = 0.0
) -> Lyapunov:
    """Return the Lyapunov exponents of the motion from ``start`` (with the saltation matrices).

    The Jacobian of each forcing period comes from the variational equations and the
    saltation matrix of every stop, breakaway and reversal; an orthonormal frame
    carried through them and re-orthonormalised each period (Benettin, Galgani,
    Giorgilli and Strelcyn 1980) gives the exponents.
    """
    dp, scales = as_forced(system)
    s0, w0 = check_start(start)
    n = _periods(periods, "periods")
    nt = _periods(transient, "transient", zero=True)
    check_duration(dp, nt + n, f"transient={nt}, periods={n}")
    kernel, lp, fp = dp.arrays()
    # the run in pieces of 1/8, 1/8, 1/4 and 1/2 of the periods, each from where the last ended
    parts = [max(1, n // 8), max(1, n // 8), max(1, n // 4)]
    parts.append(max(1, n - sum(parts)))
    sums = np.zeros(2)
    done = 0
    running = []
    stops = 0
    x = np.array([s0, w0])
    skip = nt
    time_t0 = t0
    for p in parts:
        out, lyap, stats = forced_strobe(
            kernel, lp, fp, x, skip, p, t0=time_t0, lyapunov=True, rtol=RTOL, atol=ATOL
        )
        st = ForcedStats.from_array(stats[0])
        if st.status != "ok":
            raise RuntimeError(f"Lyapunov exponents of {dp.describe()}: the engine {st.status}")
        sums += lyap[0] * p
        done += p
        stops += st.stops
        running.append(sums[0] / done)
        x = out[0, -1]
        time_t0 += (skip + p) * dp.period
        skip = 0
    ex = sums / done
    rate = 1.0 if scales is None else 1.0 / float(scales.time.to("s").magnitude)
    return Lyapunov(
        exponents=ex * rate,
        periods=done,
        running=np.array(running) * rate,
        stops_per_period=stops / done,
        physical=scales is not None,
    )


def lyapunov_two_trajectories(
    system: Any,
    periods: int = 2000,
    *,
    transient: int = 500,
    start: Any = (0.0, 0.0),
    separation: float = 1e-8,
    t0: float = 0.0,
) -> float:
    """Return the largest Lyapunov exponent from the divergence of two nearby trajectories.

    The reference for :func:`lyapunov`: no variational equations, no saltation
    matrices. A second trajectory starts ``separation`` away; after each forcing
    period the distance is measured and the second state is pulled back to
    ``separation`` along the same direction (Benettin et al. 1976). The exponent is the
    mean log growth per unit time (1/s for a physical system).
    """
    dp, scales = as_forced(system)
    s0, w0 = check_start(start)
    n = _periods(periods, "periods")
    nt = _periods(transient, "transient", zero=True)
    d0 = check_number(separation, "separation", upper=1e-2, what="a small separation (at most 1e-2)")
    check_duration(dp, nt + n, f"transient={nt}, periods={n}")
    kernel, lp, fp = dp.arrays()
    x = np.array([s0, w0])
    t = t0
    if nt:
        x, t = run_periods(dp, x, nt, t)
    y = x + np.array([d0, 0.0])
    total = 0.0
    for _ in range(n):
        x, _, _, _ = forced_poincare(kernel, lp, fp, t, x, 1, rtol=RTOL, atol=ATOL)
        y, _, _, _ = forced_poincare(kernel, lp, fp, t, y, 1, rtol=RTOL, atol=ATOL)
        t += dp.period
        d = float(np.linalg.norm(y - x))
        if d == 0.0:  # both stuck in the same stick phase: the separation is gone
            total += math.log(1e-300 / d0)
            y = x + np.array([d0, 0.0])
            continue
        total += math.log(d / d0)
        y = x + (y - x) * (d0 / d)
    rate = 1.0 if scales is None else 1.0 / float(scales.time.to("s").magnitude)
    return total / (n * dp.period) * rate
