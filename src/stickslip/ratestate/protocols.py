"""Rate-and-state spring-slider: loading histories, laboratory protocols, stability.

:func:`simulate_rate_state` follows the slider through any piecewise-constant
history of the load-point velocity; :func:`velocity_steps` and
:func:`slide_hold_slide` build the two standard laboratory protocols on it.
The quasi-static model is the paper's appendix; with a mass the slider is
inertial (see :mod:`stickslip.core.ratestate`). The quasi-static slider is
integrated by the compiled DOP853 of :func:`stickslip.core.ratestate.integrate_qs`;
the inertial one, stiff (the velocity depends exponentially on friction), by the
compiled Radau IIA of :func:`stickslip.core.radau.integrate_in` with the analytic
Jacobian (SciPy's algorithm, step for step), both driven by
:mod:`~stickslip.ratestate.solvers`; :mod:`~stickslip.ratestate.series` makes the
dataset of a run. A case the solver cannot handle fails with a message after a
bounded number of steps or seconds, never hangs.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pint
import xarray as xr

from ..core import ratestate_api as core
from ..units import Q_, parse_quantity
from ..userwarnings import warn
from .model import MAX_DURATION, RateStateParameters, jacobian, steady_state
from .series import PEAK_FLOOR as PEAK_FLOOR
from .series import _above_steady as _above_steady
from .series import _dataset, _with_peaks
from .series import _record_velocity as _record_velocity
from .solvers import STOP_REASONS as STOP_REASONS
from .solvers import RateStateStopped, _dop853, _radau
from .solvers import _history_velocity as _history_velocity
from .solvers import _segments as _segments
from .solvers import _status_message as _status_message

__all__ = [
    "RateStateStopped",
    "Stability",
    "linear_stability",
    "simulate_rate_state",
    "slide_hold_slide",
    "velocity_steps",
]

FloatArray = npt.NDArray[np.float64]


def _history(history: Any) -> list[tuple[float, float]]:
    """Parse ``[(duration, velocity), ...]`` into SI pairs."""
    if isinstance(history, str) or not hasattr(history, "__iter__"):
        raise ValueError(f"history={history!r}: expected a sequence of (duration, velocity) pairs")
    out = []
    for i, item in enumerate(history):
        try:
            dur, vel = item
        except (TypeError, ValueError):
            raise ValueError(f"history[{i}]={item!r}: expected a (duration, velocity) pair") from None
        d = parse_quantity(dur, f"history[{i}] duration", "[time]", "10 s")
        v = parse_quantity(vel, f"history[{i}] velocity", "[length] / [time]", "1 um/s", allow_zero=True)
        seconds = float(d.to("s").magnitude)
        if not seconds <= MAX_DURATION:  # '1e308 s' would only run out of steps ('too stiff')
            raise ValueError(
                f"history[{i}] duration={seconds:.4g} s: expected at most 1e9 yr "
                f"({MAX_DURATION:.3g} s) a stage"
            )
        out.append((seconds, float(v.to("m/s").magnitude)))
    if not out:
        raise ValueError("history is empty: give at least one (duration, velocity) pair")
    return out


def _steady_state(params: RateStateParameters, v: float) -> FloatArray:
    """Steady sliding at load-point velocity ``v`` (m/s) in the core's variables."""
    P, S = params.core_arrays()
    return steady_state(params, v, P, S)


def sample_times(sample: Any, total: float) -> FloatArray:
    """Return the times (s) of ``sample``: a step (``"1 s"``: 0, 1, 2, ... to ``total``) or the times."""
    if isinstance(sample, str) or (isinstance(sample, pint.Quantity) and np.ndim(sample.magnitude) == 0):
        dt = float(parse_quantity(sample, "sample", "[time]", "1 s").to("s").magnitude)
        n = math.floor(total / dt * (1.0 + 1e-12)) + 1
        if n > 50_000_000:
            raise ValueError(
                f"sample={sample!r}: {n} samples over {total:g} s, more than 5e7; give a longer step"
            )
        return np.arange(n, dtype=np.float64) * dt
    if isinstance(sample, pint.Quantity):
        t = np.asarray(sample.to("s").magnitude, dtype=float)
    else:
        t = np.asarray(sample, dtype=float)
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0) or t[0] < 0:
        raise ValueError(f"sample={sample!r}: expected a step such as '1 s' or increasing times (s) from 0")
    if t[-1] > total * (1.0 + 1e-12):
        raise ValueError(f"sample: the last time {t[-1]:g} s is after the end of the history ({total:g} s)")
    return t


def simulate_rate_state(
    params: RateStateParameters,
    history: Sequence[tuple[Any, Any]],
    *,
    initial: str | tuple[float, Any] = "steady",
    n_points: int = 400,
    sample: Any = None,
    at_changes: bool = False,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: int = 2_000_000,
    max_seconds: float = 60.0,
) -> xr.Dataset:
    """Follow the slider through a history of load-point velocities.

    Parameters
    ----------
    params : RateStateParameters
        The slider (quasi-static, or inertial when it has a mass).
    history : sequence of (duration, velocity)
        Load-point velocity held for each duration, e.g.
        ``[("100 s", "1 um/s"), ("10 s", "10 um/s")]``; a velocity of 0 is a hold.
    initial : "steady" or (friction, state)
        Start in steady sliding at the first velocity (default), or from a
        spring friction value and a state ``Phi`` (a time, e.g. ``(0.6, "10 s")``;
        a sequence of times with several state variables).
    n_points : int, optional
        Samples per segment of the history (without ``sample``).
    sample : time or sequence of times, optional
        Output at exactly these times from the integrator's dense output:
        ``"1 s"`` gives 0, 1, 2, ... s to the end; or the times themselves (s).
    at_changes : bool, optional
        With ``sample``, output also at each change of the load-point velocity and at
        the end of the history: a record whose velocity holds until the next row
        (``ratestate.csv``) then changes it at its true time, not at the next sample.
    rtol, atol : float, optional
        Relative and absolute tolerances (on the spring friction and the log-states;
        with inertia the velocity's is ``atol`` times the fastest load-point velocity);
        ``rtol`` defaults to 3e-13 for the quasi-static slider (velocities to about 1e-9
        relative: the velocity is exponential in friction / A) and 1e-10 with inertia,
        ``atol`` to 1e-15 for the quasi-static slider and with inertia to 1e-12 on the
        friction and 1e-10 on the log-states.
    max_steps, max_seconds : optional
        Bounds on the work: beyond them the integration stops with an error.

    Returns
    -------
    xarray.Dataset
        Over ``time`` (s): ``friction``, ``slip_velocity`` (m/s), ``state`` (Phi of the
        first state variable, s; ``state_2``, ... for the others), ``slider_displacement``
        and ``load_point_displacement`` (m, from the start), ``load_point_velocity``
        (m/s), ``spring_friction`` (spring force / W); the spring-force maxima located on
        the dense output (``spring_peak_*``) and, with inertia, the velocity maxima.

    Raises
    ------
    ValueError
        Malformed history, samples or initial state.
    RuntimeError
        The solver failed or exceeded its bounds (the message says which).

    Notes
    -----
    The quasi-static slider is integrated by the compiled DOP853 of
    :func:`stickslip.core.ratestate.integrate_qs` (error control on the spring
    friction and the log-states, events located on the 7th-order dense output,
    each change of the load-point velocity a step boundary); the inertial slider,
    stiff at low velocity, by Radau IIA of order 5 (SciPy's algorithm, compiled:
    :func:`stickslip.core.radau.integrate_in`) with the analytic Jacobian.

    """
    if not isinstance(params, RateStateParameters):
        raise ValueError(f"params={params!r}: expected RateStateParameters")
    hist = _history(history)
    if isinstance(n_points, bool) or not isinstance(n_points, int) or n_points < 2:
        raise ValueError(f"n_points={n_points!r}: expected an integer >= 2")
    if rtol is None:
        rtol = 1e-10 if params.inertial else 3e-13
    if not (isinstance(rtol, float | int) and 1e-13 <= rtol <= 1e-3):
        raise ValueError(f"rtol={rtol!r}: expected a relative tolerance between 1e-13 and 1e-3")
    if atol is not None and not (isinstance(atol, float | int) and 0 < atol <= 1e-3):
        raise ValueError(f"atol={atol!r}: expected an absolute tolerance in (0, 1e-3]")
    if isinstance(max_steps, bool) or not isinstance(max_steps, int | np.integer) or max_steps < 1:
        raise ValueError(f"max_steps={max_steps!r}: expected a positive integer")
    if not isinstance(at_changes, bool | np.bool_):
        raise ValueError(f"at_changes={at_changes!r}: expected True or False")
    if isinstance(max_seconds, bool) or not (isinstance(max_seconds, float | int) and max_seconds > 0):
        raise ValueError(f"max_seconds={max_seconds!r}: expected a positive number of seconds")
    P, S = params.core_arrays()
    n = params.n_states
    vr = float(P[core.P_VR])
    if isinstance(initial, str):
        if initial != "steady":
            raise ValueError(f"initial={initial!r}: expected 'steady' or (friction, state)")
        if hist[0][1] <= 0:
            raise ValueError(
                "initial='steady' needs a positive first velocity (there is no steady "
                "sliding at zero velocity); start the history with a slide (on the command line: "
                "a first step or a --history row at a positive velocity), or give initial=(friction, "
                "state) in Python"
            )
        y = _steady_state(params, hist[0][1])
    else:
        try:
            mu_i, phi_i = initial
        except (TypeError, ValueError):
            raise ValueError(f"initial={initial!r}: expected 'steady' or (friction, state)") from None
        phis = list(phi_i) if isinstance(phi_i, list | tuple) else [phi_i] * n
        if len(phis) != n:
            raise ValueError(f"initial state: {len(phis)} value(s) for {n} state variables")
        theta = np.array(
            [
                math.log(
                    float(parse_quantity(ph, "initial state", "[time]", "10 s").to("s").magnitude)
                    * vr
                    / params.state_scale(i)
                )
                for i, ph in enumerate(phis)
            ]
        )
        mu_v = float(mu_i)
        if not math.isfinite(mu_v):
            raise ValueError(f"initial friction {mu_i!r}: expected a finite number")
        if params.inertial:
            v_i = core.qs_velocity(mu_v, np.concatenate([[mu_v], theta]), S, n, _log_form(P))
            y = np.concatenate([[mu_v, v_i], theta])
        else:
            y = np.concatenate([[mu_v], theta])
    total = float(sum(d for d, _ in hist))
    bounds = np.concatenate([[0.0], np.cumsum([d for d, _ in hist])])
    if sample is None:
        t_s = np.unique(
            np.concatenate([np.linspace(bounds[k], bounds[k + 1], n_points) for k in range(len(hist))])
        )
    else:
        t_s = sample_times(sample, total)
        if at_changes:  # a sample within rounding of a change is the change
            j = np.clip(np.searchsorted(bounds, t_s), 1, bounds.size - 1)  # the changes around each
            gap = np.minimum(t_s - bounds[j - 1], bounds[j] - t_s)
            t_s = np.unique(np.concatenate([t_s[np.abs(gap) > 1e-12 * max(total, 1.0)], bounds]))
    if params.inertial:
        t_out, y_out, vlp, peaks = _radau(params, hist, y, t_s, rtol, atol, max_steps, max_seconds)
        u_out = None
    else:
        t_out, y_out, u_out, vlp, peaks = _dop853(
            params, hist, y, t_s, rtol, 1e-15 if atol is None else atol, max_steps, max_seconds
        )
    ds = _dataset(params, t_out, y_out, u_out, vlp, hist)
    return _with_peaks(ds, params, peaks)


def _log_form(P: FloatArray) -> FloatArray:
    out = P.copy()
    out[core.P_FORM] = core.LOG
    out[core.P_ETA] = 0.0
    return out


def step_history(
    velocities: Sequence[Any],
    *,
    durations: Sequence[Any] | None = None,
    displacements: Sequence[Any] | None = None,
    displacement: Any = None,
    default_displacement: Any = None,
) -> list[tuple[Any, Any]]:
    """Build ``(duration, velocity)`` pairs of a velocity-step test.

    Each velocity is held for its duration (``durations``), for its load-point
    displacement (``displacements``), or for one displacement for all
    (``displacement``, else ``default_displacement``). A velocity of 0 (a hold)
    needs a duration.
    """
    if isinstance(velocities, str) or len(velocities) < 1:
        raise ValueError(f"velocities={velocities!r}: expected a sequence of velocities")
    if durations is not None and displacements is not None:
        raise ValueError("give durations or displacements for the steps, not both")
    if displacement is not None and (durations is not None or displacements is not None):
        raise ValueError(
            f"displacement={displacement!r}: one displacement for every step, or durations/displacements "
            "for each, not both"
        )
    for name, seq in (("durations", durations), ("displacements", displacements)):
        if seq is not None and (isinstance(seq, str) or len(seq) != len(velocities)):
            raise ValueError(f"{name}={seq!r}: expected one per velocity ({len(velocities)} velocities)")
    hist: list[tuple[Any, Any]] = []
    for i, v in enumerate(velocities):
        vq = parse_quantity(
            v, f"velocities[{i}]", "[length] / [time]", "1 um/s", allow_zero=durations is not None
        )
        if durations is not None:
            hist.append((parse_quantity(durations[i], f"durations[{i}]", "[time]", "10 s"), vq))
            continue
        if displacements is not None:
            d = parse_quantity(displacements[i], f"displacements[{i}]", "[length]", "100 um")
        elif displacement is not None:
            d = parse_quantity(displacement, "displacement", "[length]", "100 um")
        else:
            d = default_displacement
        hist.append(((d / vq).to("s"), vq))
    return hist


def velocity_steps(
    params: RateStateParameters,
    velocities: Sequence[Any],
    *,
    displacement: Any = None,
    durations: Sequence[Any] | None = None,
    displacements: Sequence[Any] | None = None,
    n_points: int = 400,
    sample: Any = None,
    at_changes: bool = False,
    rtol: float | None = None,
    atol: float | None = None,
) -> xr.Dataset:
    """Run a velocity-step test: each load-point velocity held for a duration or a displacement.

    Parameters
    ----------
    params : RateStateParameters
        The slider.
    velocities : sequence of velocities
        E.g. ``["1 um/s", "10 um/s", "1 um/s"]``; starts in steady sliding at the first.
    displacement : length, optional
        Load-point displacement of every step; default ``20 D_c`` (the largest ``D_c``).
    durations : sequence of times, optional
        Duration of each step instead, e.g. ``["10 s", "30 s"]``.
    displacements : sequence of lengths, optional
        Load-point displacement of each step instead.
    n_points, sample, at_changes, rtol, atol : optional
        As in :func:`simulate_rate_state`.

    Examples
    --------
    rsfmodel's one-state velocity step (``k = 1e-3 /um``, a step to 10 um/s at 10 s),
    sampled every second:

    >>> p = RateStateParameters(a=0.005, b=0.01, dc="10 um", v_ref="1 um/s", mu0=0.6,
    ...                         stiffness_per_load="1e-3 1/um")
    >>> ds = velocity_steps(p, ["1 um/s", "10 um/s"], durations=["10 s", "30 s"], sample="1 s")
    >>> round(float(ds.friction.sel(time=11.0)), 8)
    0.60720485

    """
    hist = step_history(
        velocities,
        durations=durations,
        displacements=displacements,
        displacement=displacement,
        default_displacement=params.dc_max * 20,
    )
    return simulate_rate_state(
        params, hist, n_points=n_points, sample=sample, at_changes=at_changes, rtol=rtol, atol=atol
    )


#: a slide before a hold counts as unsettled when its end is this far from steady sliding,
#: relative to the healing measured from it
UNSETTLED = 0.01


def slide_hold_slide(
    params: RateStateParameters,
    v_slide: Any,
    holds: Sequence[Any],
    *,
    displacement: Any = None,
    n_points: int = 400,
    sample: Any = None,
    at_changes: bool = False,
    rtol: float | None = None,
    atol: float | None = None,
) -> xr.Dataset:
    """Run a slide-hold-slide test: slide, then for each hold time hold and slide again.

    Returns the time series and, over a ``hold`` dimension, ``hold_time`` (s) and
    ``peak_friction_change`` (the peak of the spring force / W on reloading minus its
    value at the end of the slide before the hold: the healing; quasi-statically, without
    damping, the friction's). That value is steady sliding's once the slide has settled; a
    warning says when it is more than :data:`UNSETTLED` of the healing away (near the
    critical stiffness the slider rings for many ``Dc``: lengthen the slides).
    ``n_points``, ``sample``, ``at_changes``, ``rtol`` and ``atol`` are those of
    :func:`simulate_rate_state`.
    """
    v = parse_quantity(v_slide, "v_slide", "[length] / [time]", "1 um/s")
    d = (
        params.dc_max * 20
        if displacement is None
        else parse_quantity(displacement, "displacement", "[length]", "100 um")
    )
    slide = ((d / v).to("s"), v)
    hist: list[tuple[Any, Any]] = [slide]
    hold_s = []
    for i, h in enumerate(holds):
        hq = parse_quantity(h, f"holds[{i}]", "[time]", "10 s")
        hold_s.append(float(hq.to("s").magnitude))
        hist += [(hq, Q_(0.0, "m/s")), slide]
    if not hold_s:
        raise ValueError("holds is empty: give at least one hold time")
    ds = simulate_rate_state(
        params, hist, n_points=n_points, sample=sample, at_changes=at_changes, rtol=rtol, atol=atol
    )
    t = ds.time.values
    bounds = np.concatenate([[0.0], np.cumsum([_history([h])[0][0] for h in hist])])
    # the spring force on both sides (what a machine measures): the peak is the spring
    # force's; the rate-and-state friction before the hold differs from it by eta v with
    # radiation damping, which would enter the healing in whole (+0.01 of 0.015 at 1000 s/m,
    # 10 um/s), and with a mass where the slide has not settled
    spring = ds.spring_friction.values
    t_peak = ds.spring_peak_time.values
    mu_peak = ds.spring_peak_friction.values
    peaks = []
    eta = 0.0 if params.radiation_damping is None else float(params.radiation_damping.to("s/m").magnitude)
    v_si = float(v.to("m/s").magnitude)
    steady = float(params.steady_state_friction(v)) + eta * v_si  # the spring's, with damping's eta v
    for j in range(len(hold_s)):
        # steady sliding just before the hold: the segment's last sample, at its very end
        before = spring[np.searchsorted(t, bounds[2 * j + 1], side="right") - 1]
        lo, hi = bounds[2 * j + 2], bounds[2 * j + 3]
        sel = (t_peak > lo) & (t_peak <= hi)
        if not sel.any():
            # no healing to measure (b = 0, a hold of nanoseconds): said, and the run kept with
            # its other holds (one such hold must not cost the whole output)
            warn(
                f"hold {j} ({hold_s[j]:g} s): no spring-force peak on reloading within the slide (no "
                "healing to measure: b = 0, or a hold too short to age the contact); its peak "
                "friction change is NaN",
                UserWarning,
            )
            peaks.append(math.nan)
            continue
        peaks.append(float(mu_peak[np.flatnonzero(sel)[0]] - before))
        off = before - steady
        if abs(off) > UNSETTLED * abs(peaks[-1]):  # k near k_c rings for many Dc
            warn(
                f"hold {j} ({hold_s[j]:g} s): the slide before it has not settled: the spring force / W "
                f"is {before:.6g} at its end, {off:+.2g} from steady sliding's {steady:.6g}, so the "
                f"healing {peaks[-1]:.4g} is measured from an unsettled level; lengthen the slides "
                f"(displacement=, --displacement; now {float(d.to('m').magnitude):.3g} m)",
                UserWarning,
            )
    ds["hold_time"] = ("hold", np.array(hold_s), {"units": "s", "long_name": "hold time"})
    ds["peak_friction_change"] = (
        "hold",
        np.array(peaks),
        {"units": "1", "long_name": "peak spring force / W after the hold minus its steady value before it"},
    )
    return ds


@dataclass(frozen=True)
class Stability:
    """Linear stability of steady sliding (quasi-static or inertial model).

    Attributes
    ----------
    eigenvalues : tuple of complex
        Eigenvalues of the linearised system (1/s).
    growth_rate : float
        Largest real part (1/s): positive means unstable.
    angular_frequency : float
        Imaginary part of the leading pair (rad/s), 0 if real.
    kw_critical : float
        Critical ``k/W`` (1/m) at this velocity: ``(B - A)/D0`` for one state
        variable without damping or mass; with them, where the growth rate at this
        velocity crosses zero (:meth:`RateStateParameters.critical_kw_at`). 0: stable
        at any stiffness.

    """

    eigenvalues: tuple[complex, ...]
    growth_rate: float
    angular_frequency: float
    kw_critical: float


def linear_stability(params: RateStateParameters, v0: Any) -> Stability:
    """Linearise the model about steady sliding at ``v0`` (with a mass: the inertial model).

    Raises
    ------
    ValueError
        For a non-positive ``v0``.

    """
    v = parse_quantity(v0, "v0", "[length] / [time]", "1 um/s")
    ev = np.linalg.eigvals(jacobian(params, float(v.to("m/s").magnitude)))
    lead = ev[np.argmax(ev.real)]
    return Stability(
        tuple(complex(e) for e in ev),
        float(lead.real),
        float(abs(lead.imag)),
        float(params.critical_kw_at(v).to("1/m").magnitude),
    )
