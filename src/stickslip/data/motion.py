r"""The slider's motion from a measured force: slip events, stick phases, regime, stiffness and mass.

A spring of stiffness :math:`k` pulled at :math:`V` holds the slider at
:math:`x = V t - F/k`, so the force alone gives the position, and its velocity is
:math:`v = V - \dot F / k`. The method, for records with drift, beats, impulsive
spikes and an ADC's steps:

1. **Noise and spikes.** The force's noise :math:`\sigma` comes from its second
   differences (:func:`~stickslip.core.noise.noise_level`, robust to the drops and to
   quantization). A sample more than :data:`SPIKE_SIGMAS` deviations from the running
   median of :data:`SPIKE_WINDOW` samples is a spike and takes the median's value: a
   median follows a step (a slip's drop) and removes a spike up to three samples wide.
2. **Stiffness from the stick slopes.** During a stick :math:`\dot F = k V`. Each stick
   (below) of at least :data:`MIN_STICK_SAMPLES` samples gives a slope from the middle
   half of its samples (its ends are where a slip stops and starts); the stiffness is
   the duration-weighted median of the sticks' slopes over :math:`V`, its uncertainty
   the weighted spread over the square root of their number. As the sticks depend on
   the stiffness, the two are found by iteration from the stated stiffness (or from
   the force's mean rise rate), :data:`STIFFNESS_ITERATIONS` times.
3. **Position by total variation.** :math:`x = V t - F/k` is denoised by exact 1-D
   total variation (:func:`~stickslip.core.tv.tv_denoise`) with weight
   :math:`\lambda = c\,\sigma / k` with :math:`c` = :data:`TV_WEIGHT`: a stick is a flat stretch of
   :math:`x`, which TV keeps exactly flat while the running sum of its noise stays
   within :math:`\lambda` (ten deviations: a hundred samples of white noise), and a
   slip a rise, which it keeps (TV leaves a monotone stretch as it is).
4. **Velocity and stick.** :math:`v` is the central difference of the denoised position
   over :math:`2h` samples (:data:`VELOCITY_HALF_WINDOW` :math:`= h`); a sample is
   stuck where :math:`|v|` is below the velocity of one noise deviation of position
   over that window, :math:`\sigma / (2 h k \Delta t)` (a floor of :math:`10^{-3} V`
   for noise-free records). At 2 kHz with the records of Colas et al. (2019) this is
   about 240 um/s; their authors use 40 um/s on a velocity denoised differently.
5. **Events.** A slip event is a run of moving samples between sticks (gaps shorter
   than :math:`h` samples closed): its time, force before and after (denoised), drop,
   duration, slip distance and peak velocity, and the recurrence time to the next
   one. Events whose drop is below ``min_drop`` (default :data:`MIN_DROP_SIGMAS`
   :math:`\sigma`) are not counted; the smallest drop counted is reported.
6. **Cycles and period.** A cycle starts where :math:`v` rises through
   :math:`V + v_\mathrm{stick}` after it was below :math:`V/2`: once per slip in
   stick-slip (a slip whose velocity dips and rises again is one slip), once per
   oscillation in pure slip. The period is the
   median cycle; a cycle sticks where it holds a stick of :math:`h` samples or more.
7. **Regime.** Steady sliding where fewer than three cycles stand above the noise;
   stick-slip where at least :data:`STICK_CYCLES` of the cycles stick (periodic
   where the recurrence's coefficient of variation is below :data:`PERIODIC_CV`,
   irregular above); pure slip (inertial) where at most :data:`PURE_SLIP_CYCLES`
   do; mixed (intermittent) between.
8. **Mass.** From the inertial oscillation where the slider rarely stops,
   :math:`m = k (T / 2\pi)^2`; from the slips where it sticks: a slip under
   slowly varying friction is a stretch of harmonic motion, so each slip's force is
   fitted by :math:`c + A\cos\omega t + B\sin\omega t` and :math:`m = k/\omega^2` with
   the median :math:`\omega`. A slip shorter than :data:`MIN_SLIP_SAMPLES` samples does
   not resolve it, and the record says so.

Source of the method's checks: J. Colas, N. Pustelnik, C. Oliver, P. Abry, J.-C.
Géminard, V. Vidal, *Nonlinear denoising for solid friction dynamics
characterization*, Phys. Rev. E 100, 032803 (2019).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.ndimage import median_filter
from scipy.optimize import minimize_scalar

from ..core.memory import check_memory
from ..core.noise import noise_level
from ..core.tv import tv_denoise
from ..io.errors import DataError
from ..io.records import Record
from .cleaning import exclude_outliers

__all__ = [
    "OBSERVED_OF",
    "EventTable",
    "Motion",
    "MotionSummary",
    "measure_motion",
    "motion_columns",
    "records_events",
]

FloatArray = npt.NDArray[np.float64]

#: a sample this many noise deviations from the running median is a spike
SPIKE_SIGMAS = 8.0
#: the running median's width (samples): removes spikes up to three samples wide
SPIKE_WINDOW = 7
#: the TV weight in noise deviations of the position
TV_WEIGHT = 10.0
#: half the window of the velocity's central difference (samples)
VELOCITY_HALF_WINDOW = 5
#: the shortest stick whose slope counts for the stiffness (samples)
MIN_STICK_SAMPLES = 40
#: iterations of sticks and stiffness
STIFFNESS_ITERATIONS = 4
#: the smallest drop counted as an event, in noise deviations of the force
MIN_DROP_SIGMAS = 5.0
#: share of cycles that stick for stick-slip
STICK_CYCLES = 0.9
#: most share of cycles that stick for pure slip
PURE_SLIP_CYCLES = 0.1
#: the recurrence's coefficient of variation below which stick-slip is periodic
PERIODIC_CV = 0.25
#: the fewest samples of a slip that resolve the mass
MIN_SLIP_SAMPLES = 12
#: the fewest cycles for a period, a regime or an inertial mass
MIN_CYCLES = 3
#: working memory per sample (the force, its median, position, TV output, velocity, masks)
BYTES_PER_SAMPLE = 96.0


@dataclass(frozen=True)
class EventTable:
    """The slip events of a record (SI units), one entry per event."""

    time: FloatArray
    end_time: FloatArray
    force_before: FloatArray
    force_after: FloatArray
    drop: FloatArray
    duration: FloatArray
    recurrence: FloatArray  # to the next event; NaN for the last
    slip_distance: FloatArray
    peak_velocity: FloatArray

    def __len__(self) -> int:
        return int(self.time.size)

    def as_frame(self, record: str | None = None) -> Any:
        """Return the events as a pandas DataFrame, units in the column names (first, ``record``'s name)."""
        import pandas as pd

        return pd.DataFrame(
            ({"record": [record] * len(self)} if record is not None else {})
            | {
                "time [s]": self.time,
                "end_time [s]": self.end_time,
                "force_before [N]": self.force_before,
                "force_after [N]": self.force_after,
                "drop [N]": self.drop,
                "duration [s]": self.duration,
                "recurrence [s]": self.recurrence,
                "slip_distance [m]": self.slip_distance,
                "peak_velocity [m/s]": self.peak_velocity,
            }
        )


@dataclass(frozen=True)
class Motion:
    """The slider's motion from the force (SI units): despiked and denoised force, position, velocity."""

    time: FloatArray
    force: FloatArray
    force_denoised: FloatArray
    position: FloatArray
    velocity: FloatArray
    stuck: npt.NDArray[np.bool_]


@dataclass(frozen=True)
class MotionSummary:
    """What a record's motion shows: events, period, stick, regime, stiffness and mass (SI units).

    ``regime`` is one of ``periodic stick-slip``, ``irregular stick-slip``,
    ``pure slip``, ``mixed``, ``steady sliding`` or ``undetermined``;
    ``regime_reason`` gives the numbers that decided it. ``amplitude`` is the median
    over cycles of the denoised force's range (the paper's amplitude); ``period`` the
    median cycle; ``recurrence`` the median time between counted events.
    """

    name: str
    n_events: int
    min_drop: float
    recurrence: float
    recurrence_q1: float
    recurrence_q3: float
    recurrence_cv: float
    drop: float
    drop_q1: float
    drop_q3: float
    drop_cv: float
    duration: float
    n_cycles: int
    amplitude: float
    amplitude_spread: float
    force_before: float
    force_after: float
    period: float
    cycles_sticking: float
    stick_fraction: float
    peak_slip_velocity: float
    slip_distance: float
    regime: str
    regime_reason: str
    stiffness: float
    stiffness_error: float
    stiffness_source: str
    stiffness_nominal: float
    mass: float
    mass_error: float
    mass_source: str
    mass_nominal: float
    inertial_period_nominal: float
    v0: float
    noise: float
    spikes: int
    tv_weight: float
    stick_velocity: float
    notes: tuple[str, ...] = field(default=())

    def as_dict(self) -> dict[str, Any]:
        """Return a dictionary (for tables and JSON)."""
        d = asdict(self)
        d["notes"] = "; ".join(self.notes)
        return d


def _runs(mask: npt.NDArray[np.bool_]) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.intp]]:
    """Return the starts and (exclusive) ends of the runs of True in ``mask``."""
    edges = np.flatnonzero(np.diff(np.r_[0, mask.astype(np.int8), 0]))
    return edges[::2], edges[1::2]


def _velocity(x: FloatArray, dt: float, h: int) -> FloatArray:
    """Return the central difference of ``x`` over ``2 h`` samples (one-sided h at the ends)."""
    n = x.size
    h = max(1, min(h, (n - 1) // 2))
    v = np.empty(n)
    v[h : n - h] = (x[2 * h :] - x[: n - 2 * h]) / (2 * h * dt)
    v[:h] = v[h]
    v[n - h :] = v[n - h - 1]
    return v


def _weighted_median(values: FloatArray, weights: FloatArray) -> float:
    order = np.argsort(values)
    cum = np.cumsum(weights[order])
    return float(values[order][np.searchsorted(cum, 0.5 * cum[-1])])


def _stick_slopes(
    t: FloatArray, f: FloatArray, stuck: npt.NDArray[np.bool_]
) -> tuple[FloatArray, FloatArray]:
    """Return the slope of ``f`` over the middle half of each long stick, and its number of samples.

    Long: :data:`MIN_STICK_SAMPLES` or more.
    """
    starts, ends = _runs(stuck)
    keep = ends - starts >= MIN_STICK_SAMPLES
    starts, ends = starts[keep], ends[keep]
    if not starts.size:
        return np.empty(0), np.empty(0)
    quarter = (ends - starts) // 4
    a, b = starts + quarter, ends - quarter
    # least-squares slopes of all the middle halves at once, from cumulative sums
    tc = t - t[0]
    cs = [np.r_[0.0, np.cumsum(y)] for y in (tc, f, tc * tc, tc * f)]
    n = (b - a).astype(float)
    st, sf, stt, stf = (c[b] - c[a] for c in cs)
    den = stt - st * st / n
    ok = den > 0
    return ((stf - st * sf / n)[ok] / den[ok]), n[ok]


def _harmonic_rss(omega: float, tau: FloatArray, f: FloatArray) -> float:
    basis = np.column_stack([np.ones_like(tau), np.cos(omega * tau), np.sin(omega * tau)])
    coef, *_ = np.linalg.lstsq(basis, f, rcond=None)
    r = f - basis @ coef
    return float(r @ r)


def _slip_frequency(tau: FloatArray, f: FloatArray) -> float:
    """Return the angular frequency of the harmonic stretch that best fits one slip's force (NaN if none)."""
    dur = float(tau[-1])
    if not dur > 0:
        return math.nan
    lo, hi = 0.3 * math.pi / dur, 3.0 * math.pi / dur
    res = minimize_scalar(
        _harmonic_rss, bounds=(lo, hi), args=(tau, f), method="bounded", options={"xatol": 1e-4 * lo}
    )
    w = float(res.x)
    return w if lo * 1.01 < w < hi * 0.99 else math.nan


def _median(x: FloatArray) -> float:
    """Return the median of ``x``, NaN for none."""
    return float(np.median(x)) if x.size else math.nan


def _quartiles(x: FloatArray) -> tuple[float, float, float, float]:
    x = x[np.isfinite(x)]
    if x.size == 0:
        return (math.nan,) * 4
    q1, q2, q3 = (float(v) for v in np.percentile(x, [25, 50, 75]))
    cv = float(np.std(x) / np.mean(x)) if x.size >= 2 and np.mean(x) > 0 else math.nan
    return q2, q1, q3, cv


def _si(q: Any, unit: str) -> float:
    return float(q.to(unit).magnitude) if q is not None else math.nan


def measure_motion(
    record: Record,
    *,
    stiffness: Any = None,
    min_drop: Any = None,
    stick_velocity: Any = None,
) -> tuple[EventTable, Motion, MotionSummary]:
    """Measure a force record's slip events, the slider's motion, its regime, stiffness and mass.

    Parameters
    ----------
    record : Record
        A force-time record with its driving velocity (``record.v0``); its stiffness
        and mass (``record.stiffness``, ``record.mass``) are the nominal values, set
        beside the measured ones.
    stiffness : quantity or str, optional
        Use this stiffness instead of measuring it from the stick slopes.
    min_drop : quantity or str, optional
        The smallest force drop counted as an event (default :data:`MIN_DROP_SIGMAS`
        times the force's noise).
    stick_velocity : quantity or str, optional
        The speed below which the slider is stuck (default: one noise deviation of
        position over the velocity's window; the module's docstring).

    Returns
    -------
    EventTable, Motion, MotionSummary

    Raises
    ------
    DataError
        Without a driving velocity, with too few samples, or where neither a stated
        stiffness nor the stick slopes give one.

    """
    from ..units import parse_quantity

    if not isinstance(record, Record):
        raise TypeError(f"record: expected a stickslip Record, got {type(record).__name__}")
    name = record.name
    if record.v0 is None:
        raise DataError(
            f"{name}: the slider's motion follows from the force only with the driving velocity "
            "(--v0, '# v0 = ...', index.csv or the name pattern)"
        )
    V = _si(record.v0, "m/s")
    t = record.time
    n = t.size
    if n < 50:
        raise DataError(f"{name}: {n} samples are too few to find slip events (at least 50)")
    check_memory(n * BYTES_PER_SAMPLE, f"{name} ({n} samples)", "cut the record into parts")
    dt = float(np.median(np.diff(t)))
    notes: list[str] = []
    # a sensor's glitch (1e308, a dropped bit) first, as every measurement of a record does
    raw, _ = exclude_outliers(record.force)
    sigma = noise_level(raw)
    if not sigma > 0:
        sigma = 1e-12 * max(float(np.ptp(raw)), 1e-300)
    med = median_filter(raw, size=SPIKE_WINDOW, mode="nearest")
    spike = np.abs(raw - med) > SPIKE_SIGMAS * sigma
    f = np.where(spike, med, raw)
    n_spikes = int(np.count_nonzero(spike & ~np.r_[False, spike[:-1]]))
    h = VELOCITY_HALF_WINDOW
    k_nominal = _si(record.stiffness, "N/m")
    k_given = (
        _si(parse_quantity(stiffness, "stiffness", "[force] / [length]", "168 N/m"), "N/m")
        if stiffness is not None
        else math.nan
    )
    v_given = (
        _si(parse_quantity(stick_velocity, "stick_velocity", "[length] / [time]", "40 um/s"), "m/s")
        if stick_velocity is not None
        else math.nan
    )

    def motion_for(k: float) -> tuple[FloatArray, FloatArray, float]:
        xt = tv_denoise(V * t - f / k, TV_WEIGHT * sigma / k)
        v = _velocity(xt, dt, h)
        vth = v_given if math.isfinite(v_given) else max(sigma / k / (2 * h * dt), 1e-3 * V)
        return xt, v, vth

    k_err = math.nan
    if math.isfinite(k_given):
        k, source = k_given, "given"
    else:
        k = k_nominal
        if not math.isfinite(k):  # the force's mean rise rate over a third of the time: a start
            ft = tv_denoise(f, TV_WEIGHT * sigma)
            k = max(float(np.sum(np.clip(np.diff(ft), 0, None))) / (3.0 * (t[-1] - t[0]) * V) * 3.0, 1e-300)
        source = "stick slopes"
        measured = False
        for it in range(STIFFNESS_ITERATIONS):
            _, v, vth = motion_for(k)
            # at first a stick is a slow or backward position (a stiffness far off makes the
            # sticks drift back); at the end, a still one
            stuck = v < vth if it < STIFFNESS_ITERATIONS // 2 else np.abs(v) < vth
            slopes, weights = _stick_slopes(t, f, stuck)
            if slopes.size < 2:
                break
            k_new = _weighted_median(slopes, weights) / V
            if not k_new > 0:
                break
            k = k_new
            measured = True
            spread = _weighted_median(np.abs(slopes / V - k), weights) * 1.4826
            k_err = spread / math.sqrt(slopes.size)
        if not measured:
            if not math.isfinite(k_nominal):
                raise DataError(
                    f"{name}: no stick of {MIN_STICK_SAMPLES} samples or more to measure the stiffness from; "
                    "give it (--stiffness, '# stiffness = ...')"
                )
            k, source = k_nominal, "stated (no stick long enough to measure it)"
            notes.append(f"no stick of {MIN_STICK_SAMPLES} samples or more: the stated stiffness is used")
    xt, v, vth = motion_for(k)
    stuck = np.abs(v) < vth
    ftv = k * (V * t - xt)
    # events: runs of motion between sticks, gaps shorter than h samples closed
    moving = ~stuck
    s0, s1 = _runs(stuck)
    for a, b in zip(s0, s1, strict=True):
        if b - a < h and a > 0 and b < n:
            moving[a:b] = True
    m0, m1 = _runs(moving)
    drop_floor = (
        _si(parse_quantity(min_drop, "min_drop", "[force]", "1 mN"), "N")
        if min_drop is not None
        else MIN_DROP_SIGMAS * sigma
    )
    before = ftv[np.maximum(m0 - 1, 0)]
    after = ftv[np.minimum(m1, n - 1)]
    drops = before - after
    # events that start or end with the record are cut short: not counted
    keep = (drops >= drop_floor) & (m0 > 0) & (m1 < n)
    m0, m1, before, after, drops = m0[keep], m1[keep], before[keep], after[keep], drops[keep]
    peak = np.array([float(np.max(v[a:b])) for a, b in zip(m0, m1, strict=True)])
    ev_t = t[m0]
    recurrence = np.r_[np.diff(ev_t), math.nan] if ev_t.size else np.empty(0)
    events = EventTable(
        time=ev_t,
        end_time=t[np.minimum(m1, n - 1)],
        force_before=before,
        force_after=after,
        drop=drops,
        duration=t[np.minimum(m1, n - 1)] - ev_t,
        recurrence=recurrence,
        slip_distance=xt[np.minimum(m1, n - 1)] - xt[np.maximum(m0 - 1, 0)],
        peak_velocity=peak if peak.size else np.empty(0),
    )
    # cycles: v rises through V + vth after it was below V/2 (a slip's own dips stay above)
    hi, lo = V + vth, 0.5 * V
    above = v > hi
    below = v < lo
    ups = []
    armed = False
    below_idx = np.flatnonzero(below)
    above_idx = np.flatnonzero(above)
    i = 0
    while True:  # alternate: the next sample below, then the next above it
        j = np.searchsorted(below_idx, i)
        if j >= below_idx.size:
            break
        i = int(below_idx[j])
        armed = True
        j = np.searchsorted(above_idx, i)
        if j >= above_idx.size:
            break
        i = int(above_idx[j])
        if armed:
            ups.append(i)
    ups_arr = np.asarray(ups, dtype=np.intp)
    cycles = np.diff(t[ups_arr]) if ups_arr.size >= 2 else np.empty(0)
    sticking = []
    for a, b in itertools.pairwise(ups_arr):
        r0, r1 = _runs(stuck[a:b])
        sticking.append(bool(np.any(r1 - r0 >= h)))
    share = float(np.mean(sticking)) if sticking else math.nan
    swings = [float(np.ptp(ftv[a:b])) for a, b in itertools.pairwise(ups_arr)]
    amplitude = float(np.median(swings)) if swings else math.nan
    amplitude_spread = (
        1.4826 * float(np.median(np.abs(np.asarray(swings) - amplitude))) if len(swings) >= 2 else math.nan
    )
    period = float(np.median(cycles)) if cycles.size >= MIN_CYCLES else math.nan
    rec_med, rec_q1, rec_q3, rec_cv = _quartiles(events.recurrence)
    drop_med, drop_q1, drop_q3, drop_cv = _quartiles(events.drop)
    stick_fraction = float(np.mean(stuck))
    # regime
    if cycles.size < MIN_CYCLES:
        swing = float(np.percentile(ftv, 99) - np.percentile(ftv, 1))
        if len(events) < MIN_CYCLES and swing < 2 * MIN_DROP_SIGMAS * sigma:
            regime = "steady sliding"
            reason = (
                f"no oscillation above the noise: the denoised force spans {swing:.3g} N, "
                f"{swing / sigma:.1f} noise deviations, and {cycles.size} cycles"
            )
        else:
            regime = "undetermined"
            reason = (
                f"{cycles.size} complete cycles and {len(events)} events: too few to tell (record longer)"
            )
    elif share >= STICK_CYCLES:
        periodic = math.isfinite(rec_cv) and rec_cv < PERIODIC_CV
        regime = "periodic stick-slip" if periodic else "irregular stick-slip"
        reason = (
            f"{100 * share:.0f}% of {cycles.size} cycles stick (>= {100 * STICK_CYCLES:.0f}%); "
            "the recurrence "
            f"varies by {rec_cv:.2f} (coefficient of variation, {'below' if periodic else 'at or above'} "
            f"{PERIODIC_CV:g})"
        )
    elif share <= PURE_SLIP_CYCLES:
        regime = "pure slip"
        reason = (
            f"{100 * share:.0f}% of {cycles.size} cycles stick (<= {100 * PURE_SLIP_CYCLES:.0f}%): "
            "the slider oscillates without stopping"
        )
    else:
        regime = "mixed"
        reason = (
            f"{100 * share:.0f}% of {cycles.size} cycles stick: the slider stops in some cycles and "
            "oscillates through others (intermittent)"
        )
    # mass
    mass, mass_err, mass_source = math.nan, math.nan, ""
    if regime in ("pure slip", "mixed") and math.isfinite(period):
        omega = 2 * math.pi / period
        mass = k / omega**2
        q1, q3 = np.percentile(cycles, [25, 75])
        rel = float((q3 - q1) / 1.349 / period / math.sqrt(cycles.size))
        mass_err = mass * math.sqrt((2 * rel) ** 2 + ((k_err / k) if math.isfinite(k_err) else 0.0) ** 2)
        mass_source = (
            f"inertial oscillation (period {period:.4g} s over {cycles.size} cycles): m = k (T / 2 pi)^2"
        )
    elif len(events):
        samples = (m1 - m0).astype(int)
        long_enough = samples >= MIN_SLIP_SAMPLES
        if np.count_nonzero(long_enough) >= MIN_CYCLES:
            omegas = []
            for a, b in zip(m0[long_enough], m1[long_enough], strict=True):
                a0, b0 = max(a - 1, 0), min(b + 1, n)
                w = _slip_frequency(t[a0:b0] - t[a0], f[a0:b0])
                if math.isfinite(w):
                    omegas.append(w)
            if len(omegas) >= MIN_CYCLES:
                om = np.asarray(omegas)
                w_med = float(np.median(om))
                mass = k / w_med**2
                rel = 1.4826 * float(np.median(np.abs(om - w_med))) / w_med / math.sqrt(om.size)
                mass_err = mass * math.sqrt(
                    (2 * rel) ** 2 + ((k_err / k) if math.isfinite(k_err) else 0.0) ** 2
                )
                mass_source = (
                    f"slip dynamics: harmonic fits of {om.size} slips "
                    f"(median {int(np.median(samples))} samples "
                    "each): m = k / omega^2"
                )
        if not mass_source:
            mass_source = (
                f"not resolved: each slip lasts {int(np.median(samples))} samples (median; "
                f"{MIN_SLIP_SAMPLES} or more resolve the slip's oscillation): "
                "sample faster to measure the mass"
            )
    else:
        mass_source = "not resolved: no slip event and no inertial oscillation"
    m_nominal = _si(record.mass, "kg")
    if (
        math.isfinite(k_nominal)
        and math.isfinite(k)
        and abs(k / k_nominal - 1) > 0.15
        and source == "stick slopes"
    ):
        notes.append(
            f"the stick slopes give an effective stiffness of {k:.4g} N/m, {100 * (k / k_nominal - 1):+.0f}% "
            f"from the stated {k_nominal:.4g} N/m (contact compliance, the drive's calibration)"
        )
    if n_spikes:
        notes.append(
            f"{n_spikes} impulsive spike(s) replaced by the running median of {SPIKE_WINDOW} samples"
        )
    summary = MotionSummary(
        name=name,
        n_events=len(events),
        min_drop=float(drop_floor),
        recurrence=rec_med,
        recurrence_q1=rec_q1,
        recurrence_q3=rec_q3,
        recurrence_cv=rec_cv,
        drop=drop_med,
        drop_q1=drop_q1,
        drop_q3=drop_q3,
        drop_cv=drop_cv,
        duration=_median(events.duration),
        n_cycles=int(cycles.size),
        amplitude=amplitude,
        amplitude_spread=amplitude_spread,
        force_before=_median(events.force_before),
        force_after=_median(events.force_after),
        period=period,
        cycles_sticking=share,
        stick_fraction=stick_fraction,
        peak_slip_velocity=_median(events.peak_velocity),
        slip_distance=_median(events.slip_distance),
        regime=regime,
        regime_reason=reason,
        stiffness=float(k),
        stiffness_error=float(k_err),
        stiffness_source=source,
        stiffness_nominal=k_nominal,
        mass=float(mass),
        mass_error=float(mass_err),
        mass_source=mass_source,
        mass_nominal=m_nominal,
        inertial_period_nominal=2 * math.pi * math.sqrt(m_nominal / k_nominal)
        if math.isfinite(m_nominal) and math.isfinite(k_nominal)
        else math.nan,
        v0=V,
        noise=float(sigma),
        spikes=n_spikes,
        tv_weight=float(TV_WEIGHT * sigma / k),
        stick_velocity=float(vth),
        notes=tuple(notes),
    )
    motion = Motion(t, f, ftv, xt, v, stuck)
    return events, motion, summary


#: the coarse regime of each of :class:`MotionSummary`'s (the words the criterion's table uses)
OBSERVED_OF = {
    "periodic stick-slip": "stick-slip",
    "irregular stick-slip": "stick-slip",
    "pure slip": "pure-slip",
    "mixed": "mixed",
    "steady sliding": "steady",
    "undetermined": "unknown",
}


def motion_columns(summary: MotionSummary) -> dict[str, Any]:
    """Return a record's motion as the summary table's columns (SI units in the names)."""
    d = summary.as_dict()
    return {
        "regime": d["regime"],
        "regime_reason": d["regime_reason"],
        "n_events": d["n_events"],
        "min_drop [N]": d["min_drop"],
        "recurrence [s]": d["recurrence"],
        "recurrence_q1 [s]": d["recurrence_q1"],
        "recurrence_q3 [s]": d["recurrence_q3"],
        "recurrence_cv": d["recurrence_cv"],
        "drop [N]": d["drop"],
        "drop_q1 [N]": d["drop_q1"],
        "drop_q3 [N]": d["drop_q3"],
        "drop_cv": d["drop_cv"],
        "slip_duration [s]": d["duration"],
        "cycles_sticking": d["cycles_sticking"],
        "peak_slip_velocity [m/s]": d["peak_slip_velocity"],
        "slip_distance [m]": d["slip_distance"],
        "stiffness [N/m]": d["stiffness"],
        "stiffness_error [N/m]": d["stiffness_error"],
        "stiffness_nominal [N/m]": d["stiffness_nominal"],
        "mass [kg]": d["mass"],
        "mass_error [kg]": d["mass_error"],
        "mass_nominal [kg]": d["mass_nominal"],
        "mass_source": d["mass_source"],
        "inertial_period_nominal [s]": d["inertial_period_nominal"],
        "motion_period": d["period"],
        "motion_amplitude": d["amplitude"],
        "motion_amplitude_spread": d["amplitude_spread"],
        "motion_force_before": d["force_before"],
        "motion_force_after": d["force_after"],
        "n_motion_cycles": d["n_cycles"],
        "stick_fraction": d["stick_fraction"],
        "stick_velocity [m/s]": d["stick_velocity"],
        "noise [N]": d["noise"],
        "spikes": d["spikes"],
    }


def records_events(records: Any) -> Any:
    """Return the slip events of every record whose motion can be measured, one table (None if none).

    A ``record`` column names each event's record; the other columns are
    :meth:`EventTable.as_frame`'s.
    """
    import pandas as pd

    frames = []
    for rec in records:
        if rec.v0 is None or rec.velocity is not None or rec.displacement is not None:
            continue
        try:
            events, _, _ = measure_motion(rec)
        except DataError:
            continue
        frames.append(events.as_frame(rec.name))
    return pd.concat(frames, ignore_index=True) if frames else None
