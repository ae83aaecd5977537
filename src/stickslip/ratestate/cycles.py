"""Earthquake cycles on one spring-slider: quasi-dynamic (radiation damping) and inertial.

The fault of the SEAS BP1 benchmark (Erickson et al., Seismol. Res. Lett. 91, 874,
2020) at seismogenic depth, reduced to one degree of freedom: a patch of
rate-and-state friction loaded through a spring of stiffness ``k`` (Pa/m) by the
plate moving at ``V_pl``:

    tau = k (V_pl t - delta) + tau_0 = sigma f(V, theta) + eta V            (quasi-dynamic)
    M V' = k (V_pl t - delta) + tau_0 - sigma f(V, theta)                    (inertial)
    f = a asinh(V / (2 V_0) exp((f_0 + b ln(V_0 theta / D_c)) / a)),  theta' = 1 - V theta / D_c

with the radiation damping ``eta = G / (2 c_s)`` (shear modulus over twice the
shear-wave speed). Below the critical stiffness ``k_c = sigma (b - a) / D_c`` steady
sliding is unstable and the slider has earthquake cycles: decades of locking
with slip rates far below ``V_pl``, then seconds of slip at metres per second.

The quasi-dynamic slider is integrated by the compiled DOP853 of
:func:`stickslip.core.ratestate.integrate_qs` (the slip rate from the stress by a
safeguarded Newton iteration; steps from years down to milliseconds); the
inertial slider, stiff while locked, by SciPy's Radau with the compiled Jacobian.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt
import xarray as xr
from scipy.integrate import solve_ivp

from ..core import ratestate_api as core
from ..core.results import (
    RateStateEvent,
    RateStateEventRows,
    RateStateRecordRows,
    RateStateSampleRows,
    RateStateStatus,
)
from ..units import check_number, parse_quantity
from .model import MAX_DURATION, YEAR, check_dc

__all__ = ["BP1", "CycleRun", "SpringSliderFault", "earthquake_cycles", "recurrence_estimate"]

FloatArray = npt.NDArray[np.float64]
CHUNK = 1e7  # s: the integrations restart their clocks this often (the step stays resolved)
EVENT_CAPACITY = 200_000  # events one quasi-dynamic run locates


@dataclass(frozen=True)
class SpringSliderFault:
    """A rate-and-state fault patch on a spring (SEAS BP1's frictional parameters by default).

    Parameters
    ----------
    a, b : float
        Direct and evolution effects (dimensionless).
    dc : length
        Characteristic slip distance ``D_c``.
    normal_stress : pressure
        Effective normal stress ``sigma``.
    plate_rate : velocity
        Loading (plate) rate ``V_pl``.
    f0 : float
        Reference friction at ``V_0``.
    v0 : velocity
        Reference slip rate ``V_0``.
    eta : pressure * time / length, optional
        Radiation damping ``G / (2 c_s)``; ``None`` for none (the inertial slider).
    stiffness : pressure / length, optional
        Spring stiffness ``k``; default ``stiffness_ratio`` times the critical ``k_c``.
    stiffness_ratio : float, optional
        ``k / k_c`` when ``stiffness`` is not given (default 0.5).
    mass : mass / area, optional
        Mass per unit area of the inertial slider; default ``eta^2 / k`` (the mass whose
        natural time ``sqrt(M/k)`` equals the damping time ``eta/k``).

    """

    a: float = 0.010
    b: float = 0.015
    dc: Any = "8 mm"
    normal_stress: Any = "50 MPa"
    plate_rate: Any = "1e-9 m/s"
    f0: float = 0.6
    v0: Any = "1e-6 m/s"
    eta: Any = "4.62 MPa*s/m"
    stiffness: Any = None
    stiffness_ratio: float = 0.5
    mass: Any = None

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "a", check_number(self.a, "a", what="a positive direct effect a"))
        set_(self, "b", check_number(self.b, "b", what="a positive evolution effect b"))
        set_(self, "f0", check_number(self.f0, "f0", what="a positive reference friction f0"))
        set_(self, "dc", parse_quantity(self.dc, "dc", "[length]", "8 mm"))
        check_dc(self.dc, "dc")
        set_(
            self, "normal_stress", parse_quantity(self.normal_stress, "normal_stress", "[pressure]", "50 MPa")
        )
        set_(
            self, "plate_rate", parse_quantity(self.plate_rate, "plate_rate", "[length] / [time]", "1e-9 m/s")
        )
        set_(self, "v0", parse_quantity(self.v0, "v0", "[length] / [time]", "1e-6 m/s"))
        if self.eta is not None:
            set_(
                self, "eta", parse_quantity(self.eta, "eta", "[pressure] * [time] / [length]", "4.62 MPa*s/m")
            )
        if self.b <= self.a:
            raise ValueError(
                f"b={self.b} <= a={self.a}: velocity strengthening, steady sliding is stable and there "
                "are no earthquake cycles (need b > a)"
            )
        if self.stiffness is not None:
            set_(
                self,
                "stiffness",
                parse_quantity(self.stiffness, "stiffness", "[pressure] / [length]", "1e7 Pa/m"),
            )
        else:
            check_number(self.stiffness_ratio, "stiffness_ratio", what="a positive k / k_c")
        if self.mass is not None:
            set_(self, "mass", parse_quantity(self.mass, "mass", "[mass] / [length] ** 2", "1e6 kg/m^2"))
        if self.k >= self.k_c:
            raise ValueError(
                f"stiffness {self.k:.4g} Pa/m >= critical {self.k_c:.4g} Pa/m: steady sliding is stable; "
                "earthquake cycles need a stiffness below critical"
            )

    @property
    def sigma(self) -> float:
        """Normal stress (Pa)."""
        return float(self.normal_stress.to("Pa").magnitude)

    @property
    def k_c(self) -> float:
        """Critical stiffness ``sigma (b - a) / D_c`` (Pa/m)."""
        return self.sigma * (self.b - self.a) / float(self.dc.to("m").magnitude)

    @property
    def k(self) -> float:
        """Spring stiffness (Pa/m)."""
        if self.stiffness is not None:
            return float(self.stiffness.to("Pa/m").magnitude)
        return self.stiffness_ratio * self.k_c

    @property
    def eta_si(self) -> float:
        """Radiation damping (Pa s/m), 0 without."""
        return 0.0 if self.eta is None else float(self.eta.to("Pa*s/m").magnitude)

    @property
    def mass_si(self) -> float:
        """Mass per unit area (kg/m^2) of the inertial slider."""
        if self.mass is not None:
            return float(self.mass.to("kg/m**2").magnitude)
        eta = self.eta_si if self.eta_si > 0 else float(BP1.eta.to("Pa*s/m").magnitude)
        return eta**2 / self.k

    def core_arrays(self, inertial: bool = False) -> tuple[FloatArray, FloatArray]:
        """Return ``(P, S)`` for :mod:`stickslip.core.ratestate` (stresses per normal stress)."""
        P = np.array(
            [
                self.a,
                float(self.v0.to("m/s").magnitude),
                self.f0,
                self.k / self.sigma,
                self.sigma / self.mass_si if inertial else 0.0,
                self.eta_si / self.sigma,
                core.REGULARIZED,
            ]
        )
        S = np.array([[self.b, float(self.dc.to("m").magnitude), core.AGING, 0.0]])
        return P, S


BP1 = SpringSliderFault()


@dataclass(frozen=True)
class CycleRun:
    """Earthquake cycles of a spring-slider.

    Attributes
    ----------
    series : xarray.Dataset
        Over ``time`` (s), every accepted step: ``slip_rate`` (m/s), ``shear_stress`` (Pa),
        ``state`` (s), ``slip`` (m).
    catalog : xarray.Dataset
        Over ``event``: ``t_start``, ``t_end``, ``t_peak`` (s), ``peak_slip_rate`` (m/s),
        ``slip`` (m), ``duration`` (s), ``recurrence`` (s since the previous start), ``stress_drop`` (Pa),
        ``cumulative_slip`` (m, at the start).
    budget : dict
        Slip and energy budgets (J/m^2, m) and their relative closure errors.
    steps, rejected : int
        Accepted plus rejected steps, and rejected steps.
    seconds : float
        Wall time of the integration.
    model : str
        ``quasi-dynamic`` or ``inertial``.

    """

    series: xr.Dataset
    catalog: xr.Dataset
    budget: dict[str, float]
    steps: int
    rejected: int
    seconds: float
    model: str
    fault: SpringSliderFault = field(repr=False, default=BP1)

    def summary(self, spin_up: int = 2) -> dict[str, float]:
        """Return mean recurrence (yr), slip (m) and peak slip rate (m/s), after ``spin_up`` events."""
        cat = self.catalog.isel(event=slice(spin_up, None))
        rec = cat.recurrence.values
        if cat.sizes["event"] == 0:  # no event reached v_event (after the spin-up)
            keys = ("recurrence_yr", "recurrence_spread", "slip_m", "peak_slip_rate", "stress_drop_MPa")
            return {"events": 0, **dict.fromkeys(keys, math.nan)}
        return {
            "events": int(cat.sizes["event"]),
            "recurrence_yr": float(np.nanmean(rec)) / YEAR,
            "recurrence_spread": float(np.nanstd(rec) / np.nanmean(rec)) if rec.size > 1 else math.nan,
            "slip_m": float(np.mean(cat.slip.values)),
            "peak_slip_rate": float(np.mean(cat.peak_slip_rate.values)),
            "stress_drop_MPa": float(np.mean(cat.stress_drop.values)) / 1e6,
        }


def _initial(fault: SpringSliderFault, P: FloatArray, S: FloatArray, inertial: bool) -> FloatArray:
    """Slip rate V_pl with the state at half its steady value: the first event comes early."""
    vpl = float(fault.plate_rate.to("m/s").magnitude)
    theta = math.log(0.5 * P[core.P_VR] / vpl)
    y = np.array([0.0, vpl, theta])
    f = core.in_friction(vpl, y, S, 1, P)
    mu_s = f + P[core.P_ETA] * vpl
    return np.array([mu_s, vpl, theta]) if inertial else np.array([mu_s, theta])


def earthquake_cycles(
    fault: SpringSliderFault = BP1,
    duration: Any = "3000 yr",
    *,
    inertial: bool = False,
    v_event: Any = "1 mm/s",
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 20_000_000,
) -> CycleRun:
    """Run earthquake cycles of a spring-slider for ``duration``.

    Parameters
    ----------
    fault : SpringSliderFault
        The patch (SEAS BP1's frictional parameters by default).
    duration : time
        Simulated time, e.g. ``"3000 yr"``.
    inertial : bool, optional
        The inertial slider (mass, no radiation damping) instead of the quasi-dynamic one.
    v_event : velocity, optional
        An event is the time the slip rate spends above this (default 1 mm/s).
    rtol, atol : float, optional
        Tolerances on the stress per normal stress and the log-state.
    max_steps : int, optional
        Bound on the work.

    Returns
    -------
    CycleRun

    Raises
    ------
    RuntimeError
        The integration failed or exceeded ``max_steps`` (the message says where).

    """
    t_end = float(parse_quantity(duration, "duration", "[time]", "3000 yr").to("s").magnitude)
    if not t_end <= MAX_DURATION:  # 1e308 yr is infinite in seconds
        raise ValueError(f"duration={duration!r}: expected a simulated time of at most 1e9 yr")
    # checked here: a nan tolerance would make the compiled loop spin without end
    if isinstance(rtol, bool) or not (isinstance(rtol, float | int) and 1e-13 <= rtol <= 1e-3):
        raise ValueError(f"rtol={rtol!r}: expected a relative tolerance between 1e-13 and 1e-3")
    if isinstance(atol, bool) or not (isinstance(atol, float | int) and 0 < atol <= 1e-3):
        raise ValueError(f"atol={atol!r}: expected an absolute tolerance in (0, 1e-3]")
    if isinstance(max_steps, bool) or not isinstance(max_steps, int | np.integer) or max_steps < 1:
        raise ValueError(f"max_steps={max_steps!r}: expected a positive integer")
    ve = float(parse_quantity(v_event, "v_event", "[length] / [time]", "1 mm/s").to("m/s").magnitude)
    vpl = float(fault.plate_rate.to("m/s").magnitude)
    if not ve > 10.0 * vpl:  # else the interseismic creep itself crosses it: events without meaning
        raise ValueError(
            f"v_event={v_event!r}: an event starts where the slip rate passes v_event, which must be "
            f"well above the plate rate ({vpl:g} m/s; at least 10 times)"
        )
    P, S = fault.core_arrays(inertial)
    y0 = _initial(fault, P, S, inertial)
    started = time.perf_counter()
    if inertial:
        rec, ev, steps, rejected = _inertial(fault, P, S, y0, t_end, ve, rtol, atol, max_steps)
    else:
        rec, ev, steps, rejected = _quasi_dynamic(fault, P, S, y0, t_end, ve, rtol, atol, max_steps)
    seconds = time.perf_counter() - started
    series = _series(fault, P, rec, inertial)
    catalog = _catalog(fault, ev)
    return CycleRun(
        series, catalog, _budget(fault, P, rec, inertial), steps, rejected, seconds,
        "inertial" if inertial else "quasi-dynamic", fault,
    )  # fmt: skip


def _quasi_dynamic(
    fault: SpringSliderFault, P: FloatArray, S: FloatArray, y0: FloatArray, t_end: float, ve: float,
    rtol: float, atol: float, max_steps: int,
) -> tuple[RateStateRecordRows, RateStateEventRows, int, int]:  # fmt: skip
    """Run the compiled DOP853 in spans of :data:`CHUNK`, each on its own clock from 0.

    One clock over the whole run would lose the resolution of an event's millisecond
    steps after about 2.6e4 years (the spacing of doubles at 8e11 s is 1e-4 s); the state
    and the quadratures carry over from span to span, and times are offset back.
    """
    vpl = float(fault.plate_rate.to("m/s").magnitude)
    nvar = y0.size + core.N_QUAD
    cap = 400_000
    rec = RateStateRecordRows.empty(cap, 1, nvar)
    ev = RateStateEventRows.empty(EVENT_CAPACITY, 1, nvar)
    no_samples = RateStateSampleRows.empty(0, 1, nvar)

    def run(every: int) -> tuple[int, int, int, int, bool]:
        y = np.concatenate([y0, np.zeros(core.N_QUAD)])
        nrec, nev, steps, rejected = 0, 0, 0, 0
        for k in range(max(1, math.ceil(t_end / CHUNK))):
            offset = k * CHUNK
            span = min(CHUNK, t_end - offset)
            first = 0 if k == 0 else nrec - 1  # a span's first row is the last one's end
            code, t, _, k_ev, k_rec, k_steps, k_rej = core.integrate_qs(
                P, S, 1, np.array([span]), np.array([vpl]), y, 0.0, np.zeros(0), rtol, atol, math.inf,
                max_steps - steps, 0.0, ve, False, no_samples.raw, ev.raw[nev:], rec.raw[first:], every,
            )  # fmt: skip
            rec[first : first + k_rec].time += offset
            ev[nev : nev + k_ev].time += offset
            nrec, nev = first + k_rec, nev + k_ev
            steps, rejected = steps + k_steps, rejected + k_rej
            status = RateStateStatus.from_code(code)
            if status is not RateStateStatus.OK:
                _stopped(status, offset + t, steps, max_steps)
            _say_too_many_events(ev, nev, offset + span, t_end)
        return nrec, nev, steps, rejected, nrec >= cap

    nrec, nev, steps, rejected, full = run(1)
    if full:  # more steps than the record holds: run again keeping every k-th step
        nrec, nev, _, _, _ = run(steps // cap + 1)
    return rec[:nrec], ev[:nev], steps, rejected


def _say_too_many_events(ev: RateStateEventRows | FloatArray, nev: int, done: float, t_end: float) -> None:
    """Refuse a run that will locate more events than ``ev`` holds, from its first thousand or more.

    The rate is that of the later half of the events so far (past the first cycles'
    transient: from the first hundred, SEAS BP1's interval comes out 6 % short); the
    run is refused where it would end 5 % or more beyond the capacity, said within
    seconds (10^6 yr of BP1 would otherwise fill the capacity at 944 612 yr, after 110 s).
    """
    if nev < 1000:
        return
    rows = ev if isinstance(ev, RateStateEventRows) else RateStateEventRows(ev)
    capacity = len(rows)
    half = nev // 2
    rate = (nev - half) / (done - rows.time[half])
    expected = nev + rate * (t_end - done)
    if expected > 1.05 * capacity:
        raise RuntimeError(
            f"the quasi-dynamic integration would locate about {expected:.3g} events ({nev} in the "
            f"first {done / YEAR:.4g} yr, one every {1.0 / rate / YEAR:.3g} yr), more than one run "
            f"locates ({capacity}): give a duration of at most about "
            f"{(done + (capacity - nev) / rate) / YEAR:.3g} yr"
        )


def _stopped(status: RateStateStatus, t: float, steps: int, max_steps: int) -> None:
    """Raise the quasi-dynamic integrator's stop, in words."""
    why = status.message
    if status is RateStateStatus.MAX_STEPS:
        why = f"the bound of {max_steps} steps (max_steps): a larger one, or a shorter run"
    elif status is RateStateStatus.EVENTS_FULL:
        why = f"more events than one run locates ({EVENT_CAPACITY}): give a shorter duration"
    raise RuntimeError(
        f"the quasi-dynamic integration stopped at t = {t / YEAR:.6g} yr after {steps} steps: {why}"
    )


def _inertial(
    fault: SpringSliderFault, P: FloatArray, S: FloatArray, y0: FloatArray, t_end: float, ve: float,
    rtol: float, atol: float, max_steps: int,
) -> tuple[RateStateRecordRows, RateStateEventRows, int, int]:  # fmt: skip
    """Radau on ``(mu_s, u = ln(V/V_0), theta)`` and the quadratures (the slip rate stays positive).

    Its steps and events come back as the quasi-dynamic integrator's rows.
    """
    vpl = float(fault.plate_rate.to("m/s").magnitude)
    vr = float(P[core.P_VR])
    lnve = math.log(ve / vr)
    y3 = np.empty(3)
    f3 = np.empty(3)
    j3 = np.empty((3, 3))

    def state(z: FloatArray) -> FloatArray:
        y3[0] = z[0]
        y3[1] = vr * math.exp(z[1])
        y3[2] = z[2]
        return y3

    def fun(_t: float, z: FloatArray) -> FloatArray:
        y = state(z)
        core.in_rhs(y, P, S, 1, vpl, f3)
        v = y[1]
        eta = P[core.P_ETA]
        return np.array(
            [f3[0], f3[1] / v, f3[2], v, core.in_friction(v, y, S, 1, P) * v, eta * v * v, z[0] * vpl]
        )

    def jac(_t: float, z: FloatArray) -> FloatArray:
        y = state(z)
        core.in_rhs(y, P, S, 1, vpl, f3)
        core.in_jac(y, P, S, 1, j3)
        v = y[1]
        out = np.zeros((7, 7))
        out[:3, :3] = j3
        out[:, 1] *= 0.0
        out[0, 1] = j3[0, 1] * v
        out[2, 1] = j3[2, 1] * v
        out[1, 0] = j3[1, 0] / v
        out[1, 2] = j3[1, 2] / v
        out[1, 1] = j3[1, 1] - f3[1] / v
        out[3, 1] = v
        out[5, 1] = 2.0 * P[core.P_ETA] * v * v
        return out

    def up(_t: float, z: FloatArray) -> float:
        return float(z[1]) - lnve

    up.direction = 1  # type: ignore[attr-defined]

    def down(_t: float, z: FloatArray) -> float:
        return float(z[1]) - lnve

    down.direction = -1  # type: ignore[attr-defined]

    def peak(_t: float, z: FloatArray) -> float:
        if z[1] <= lnve:
            return 1.0
        y = state(z)
        return float(z[0]) - core.in_friction(y[1], y, S, 1, P) - P[core.P_ETA] * y[1]

    peak.direction = -1  # type: ignore[attr-defined]
    z = np.array([y0[0], math.log(y0[1] / vr), y0[2], 0.0, 0.0, 0.0, 0.0])
    atol_v = np.array([atol, atol, atol, 1e-9, atol, atol, atol])
    # the system is autonomous: restart the clock every CHUNK seconds, so that the steps through
    # an event are not limited by the spacing of doubles near a large t (1e-8 s at 3 years)
    kinds: list[int] = []
    found: list[tuple[float, FloatArray]] = []  # (time, z) of each event
    ts: list[FloatArray] = []
    zs: list[FloatArray] = []
    offset = 0.0
    nfev = 0
    while offset < t_end:
        span = min(CHUNK, t_end - offset)
        sol = solve_ivp(
            fun, (0.0, span), z, method="Radau", jac=jac, rtol=rtol, atol=atol_v, events=[up, down, peak]
        )
        nfev += int(sol.nfev)
        if sol.status == -1:
            raise RuntimeError(
                f"the inertial integration stopped at t = {(offset + sol.t[-1]) / YEAR:.6g} yr: {sol.message}"
            )
        for kind, k_ev in (
            (RateStateEvent.UP, 0),
            (RateStateEvent.DOWN, 1),
            (RateStateEvent.VELOCITY_PEAK, 2),
        ):
            for te, ze in zip(sol.t_events[k_ev], sol.y_events[k_ev], strict=True):
                kinds.append(kind.code)
                found.append((offset + te, ze))
        keep = slice(None) if not ts else slice(1, None)
        ts.append(offset + sol.t[keep])
        zs.append(sol.y[:, keep])
        z = sol.y[:, -1].copy()
        offset += span
        if nfev > max_steps:
            raise RuntimeError(
                f"the inertial integration stopped at t = {offset / YEAR:.6g} yr after {nfev} evaluations "
                f"(slip rate {vr * math.exp(z[1]):.3g} m/s)"
            )
    ze = np.array([z_e for _, z_e in found]).reshape(-1, z.size)
    ev = RateStateEventRows.stack(_qd_state(ze.T), 1, kind=kinds, time=[t_e for t_e, _ in found], u=ze[:, 1])
    ev = ev[np.argsort(ev.time, kind="stable")]
    zz = np.concatenate(zs, axis=1)
    t_all = np.concatenate(ts)
    rec = RateStateRecordRows.stack(_qd_state(zz), 1, time=t_all, u=zz[1])
    return rec, ev, int(t_all.size), 0


def _qd_state(z: FloatArray) -> FloatArray:
    """Return the states ``(mu_s, theta, quadratures)`` (a row each) of Radau's ``z`` (a column each)."""
    return np.column_stack([z[0], z[2], z[3:].T])


def _series(fault: SpringSliderFault, P: FloatArray, rec: RateStateRecordRows, inertial: bool) -> xr.Dataset:
    vr = float(P[core.P_VR])
    dc = float(fault.dc.to("m").magnitude)
    v = vr * np.exp(rec.u)
    return xr.Dataset(
        {
            "slip_rate": ("time", v, {"units": "m/s", "long_name": "slip rate"}),
            "shear_stress": (
                "time",
                rec.spring * fault.sigma,
                {"units": "Pa", "long_name": "spring (shear) stress"},
            ),
            "state": ("time", np.exp(rec.theta[:, 0]) * dc / vr, {"units": "s", "long_name": "state theta"}),
            "slip": ("time", rec.slip, {"units": "m", "long_name": "slip"}),
        },
        coords={"time": ("time", rec.time, {"units": "s", "long_name": "time"})},
        attrs={"model": "inertial" if inertial else "quasi-dynamic", "fault": repr(fault)},
    )


def _catalog(fault: SpringSliderFault, ev: RateStateEventRows) -> xr.Dataset:
    """Pair each upward crossing of the event velocity with the next downward one."""
    vr = float(fault.v0.to("m/s").magnitude)
    ups, downs, peaks = (
        ev.of_kind(kind) for kind in (RateStateEvent.UP, RateStateEvent.DOWN, RateStateEvent.VELOCITY_PEAK)
    )
    rows = []
    for i in range(len(ups)):
        t_up = ups.time[i]
        later = downs[downs.time > t_up]
        if len(later) == 0:
            break
        t_down = later.time[0]
        inside = peaks[(peaks.time >= t_up) & (peaks.time <= t_down)]
        if len(inside):
            k = int(np.argmax(inside.u))
            t_peak, v_peak = inside.time[k], vr * math.exp(inside.u[k])
        else:
            t_peak, v_peak = math.nan, math.nan
        drop = (ups.spring[i] - later.spring[0]) * fault.sigma
        rows.append((t_up, t_down, t_peak, v_peak, later.slip[0] - ups.slip[i], drop, ups.slip[i]))
    arr = np.array(rows) if rows else np.zeros((0, 7))
    rec = np.concatenate([[math.nan], np.diff(arr[:, 0])]) if len(arr) else np.zeros(0)
    columns = {
        "t_start": (arr[:, 0], "s", "slip rate rises above the event velocity"),
        "t_end": (arr[:, 1], "s", "slip rate falls below the event velocity"),
        "t_peak": (arr[:, 2], "s", "time of the peak slip rate"),
        "peak_slip_rate": (arr[:, 3], "m/s", "peak slip rate"),
        "slip": (arr[:, 4], "m", "slip during the event"),
        "duration": (arr[:, 1] - arr[:, 0], "s", "event duration"),
        "recurrence": (rec, "s", "time since the previous event started"),
        "stress_drop": (arr[:, 5], "Pa", "shear stress drop over the event"),
        "cumulative_slip": (arr[:, 6], "m", "slip since t = 0 at the start"),
    }
    return xr.Dataset(
        {
            name: ("event", values, {"units": units, "long_name": long_name})
            for name, (values, units, long_name) in columns.items()
        }
    )


def _budget(
    fault: SpringSliderFault, P: FloatArray, rec: RateStateRecordRows, inertial: bool
) -> dict[str, float]:
    """Slip and energy budgets from the quadratures (per unit area, J/m^2 and m)."""
    sigma = fault.sigma
    kw = float(P[core.P_KW])
    vpl = float(fault.plate_rate.to("m/s").magnitude)
    mu0, mu1 = rec.spring[0], rec.spring[-1]
    slip = rec.slip[-1]
    # the spring's stretch: mu_s / kw (m); slip = V_pl t - change of stretch
    slip_from_spring = vpl * (rec.time[-1] - rec.time[0]) - (mu1 - mu0) / kw
    w_fric, e_rad, w_load = rec.friction_work[-1] * sigma, rec.radiated[-1] * sigma, rec.load_work[-1] * sigma
    d_elastic = (mu1**2 - mu0**2) / (2 * kw) * sigma
    v0, v1 = (float(P[core.P_VR]) * math.exp(rec.u[i]) for i in (0, -1))
    d_kinetic = 0.5 * fault.mass_si * (v1**2 - v0**2) if inertial else 0.0
    return {
        "slip": slip,
        "slip_from_spring": slip_from_spring,
        "slip_error": abs(slip - slip_from_spring) / abs(slip_from_spring),
        "load_work": w_load,
        "friction_work": w_fric,
        "radiated": e_rad,
        "elastic_change": d_elastic,
        "kinetic_change": d_kinetic,
        "energy_error": abs(w_load - w_fric - e_rad - d_elastic - d_kinetic) / abs(w_load),
    }


def recurrence_estimate(fault: SpringSliderFault, peak_slip_rate: float) -> dict[str, float]:
    """Estimate stress drop (Pa), slip per event (m) and recurrence time (s) of a spring-slider.

    During an event the state is renewed (slip much larger than ``D_c``) and friction
    follows its steady state; the stress falls from about the steady-state stress at the
    plate rate to about the one at the peak slip rate ``V_max``, so the stress drop is
    ``sigma (b - a) ln(V_max / V_pl)``; the spring gives the slip ``stress drop / k``;
    if all the slip were seismic the plate would accumulate it in ``slip / V_pl``, a
    lower bound of the recurrence time (the measured time exceeds it by the share of
    slip that is aseismic: afterslip and nucleation). ``V_max`` in m/s.
    """
    vpl = float(fault.plate_rate.to("m/s").magnitude)
    drop = fault.sigma * (fault.b - fault.a) * math.log(peak_slip_rate / vpl)
    slip = drop / fault.k
    return {"stress_drop": drop, "slip": slip, "recurrence": slip / vpl}
