"""Numerical evidence beside the appendix's theorem, and what inertia changes.

* Phase portraits of the derived dimensionless system (``stickslip.ratestate.dulac``)
  for ``kappa > B - A`` (orbits spiral into steady sliding), ``kappa < B - A``
  (they spiral out until the quasi-static slider runs away) and
  ``kappa = B - A`` (closed orbits: the flow preserves area). The return
  multiplier on the section ``alpha = alpha*`` measures which.
* The critical stiffness ``k_c = (B - A) W / D0``: growth rates of small
  perturbations in simulations of the physical model against linear theory,
  on both sides of ``k_c``.
* Inertia: with a mass the phase space is three-dimensional and Dulac's
  argument no longer applies. The critical stiffness moves with the mass
  (computed from the linearised inertial model), and below it the inertial
  slider settles on a bounded limit cycle where the quasi-static one runs away.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import xarray as xr
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..errors import ArgumentTypeError
from ..ratestate.dulac import lambdified_field
from ..ratestate.model import RateStateParameters, growth_rate
from ..ratestate.protocols import RateStateStopped, linear_stability, simulate_rate_state
from ..units import Q_

__all__ = ["APPENDIX_PARTS", "appendix_part", "compute_appendix", "merge_appendix"]

A, B, MU0 = 0.01, 0.015, 0.6
OMEGA = 1.0
KAPPAS = (0.006, 0.004, 0.005)  # above, below, at B - A = 0.005
DC, VR, LOAD = "10 um", "1 um/s", "10 N"


def _phase_portraits(n_orbits: int, t_end: float) -> xr.Dataset:
    field = lambdified_field()
    gamma = math.exp(-MU0 / A)
    phi_star = 1.0 / OMEGA
    deltas = np.linspace(0.02, 0.12, n_orbits)
    n_t = 1500
    alpha = np.full((len(KAPPAS), n_orbits, n_t), np.nan)
    phi = np.full_like(alpha, np.nan)
    multipliers = np.full((len(KAPPAS), n_orbits), np.nan)
    for i, kappa in enumerate(KAPPAS):
        a_star = -(A / kappa) * math.log(OMEGA ** (1 - B / A) / gamma)

        def f(_t: float, y: np.ndarray, kappa: float = kappa) -> list[float]:
            return field(float(y[0]), float(y[1]), OMEGA, gamma, kappa, A, B)

        def section(_t: float, y: np.ndarray, a_star: float = a_star) -> float:
            return y[0] - a_star

        section.direction = 1  # type: ignore[attr-defined]

        def runaway(_t: float, y: np.ndarray) -> float:
            return y[1] - 1e-3 * phi_star  # the state collapses as the slider runs away

        runaway.terminal = True  # type: ignore[attr-defined]
        for j, d in enumerate(deltas):
            t_eval = np.linspace(0.0, t_end, n_t)
            sol = solve_ivp(
                f,
                (0.0, t_end),
                [a_star, phi_star * (1 - d)],
                # not stiff here: DOP853 takes these orbits 15 times faster than Radau,
                # with the same return multipliers (to 7e-9) and portraits (to 1e-6)
                method="DOP853",
                rtol=1e-10,
                atol=1e-12,
                events=[section, runaway],
                t_eval=t_eval,
            )
            m = sol.t.size
            alpha[i, j, :m] = sol.y[0] - a_star
            phi[i, j, :m] = sol.y[1]
            crossings = np.reshape(sol.y_events[0], (-1, 2))[:, 1] - phi_star
            if crossings.size >= 2:
                multipliers[i, j] = crossings[1] / crossings[0]
    return xr.Dataset(
        {
            "portrait_alpha": (
                ("kappa", "orbit", "tau"),
                alpha,
                {"units": "1", "long_name": "alpha - alpha* = (x - v0 t)/D0 - alpha*"},
            ),
            "portrait_phi": (("kappa", "orbit", "tau"), phi, {"units": "1", "long_name": "phi = Phi/Phi0"}),
            "return_multiplier": (
                ("kappa", "orbit"),
                multipliers,
                {
                    "units": "1",
                    "long_name": "ratio of successive (phi - phi*) on the "
                    "section alpha = alpha*: < 1 spiral in, 1 closed, > 1 spiral out",
                },
            ),
        },
        coords={
            "kappa": ("kappa", np.array(KAPPAS), {"units": "1", "long_name": "kappa = k D0 / W"}),
            "orbit": ("orbit", deltas, {"units": "1", "long_name": "initial 1 - phi/phi*"}),
            "tau": ("tau", np.linspace(0.0, t_end, n_t), {"units": "1", "long_name": "tau = V_r t / D0"}),
        },
    )


def _params(kw: float, mass: str | None = None) -> RateStateParameters:
    return RateStateParameters(
        a=A, b=B, dc=DC, v_ref=VR, mu0=MU0, stiffness=Q_(kw * 10.0, "N/m"), load=LOAD, mass=mass
    )


def _growth_rate(ds: xr.Dataset, v0: float) -> float:
    """Exponential rate (1/s) of the envelope of the velocity deviation's peaks."""
    t = ds.time.values
    dv = np.abs(ds.slip_velocity.values - v0)
    peaks = [i for i in range(1, dv.size - 1) if dv[i] > dv[i - 1] and dv[i] >= dv[i + 1]]
    if len(peaks) < 4:
        return math.nan
    tp, vp = t[peaks], dv[peaks]
    return float(np.polyfit(tp, np.log(vp), 1)[0])


def _critical_check(ratios: tuple[float, ...], n_points: int) -> xr.Dataset:
    kc = (B - A) / Q_(DC).to("m").magnitude  # critical k/W (1/m)
    v0: float = float(Q_(VR).to("m/s").magnitude)
    sim, lin = [], []
    for r in ratios:
        p = _params(r * kc)
        st = linear_stability(p, VR)
        period = 2 * math.pi / st.angular_frequency
        mu_ss = float(p.steady_state_friction(VR))
        phi_ss = Q_(DC).to("m").magnitude / v0
        ds = simulate_rate_state(
            p, [(Q_(6 * period, "s"), VR)], initial=(mu_ss + 1e-6, Q_(phi_ss, "s")), n_points=n_points
        )
        sim.append(_growth_rate(ds, v0))
        lin.append(st.growth_rate)
    return xr.Dataset(
        {
            "growth_simulated": (
                "stiffness_ratio",
                np.array(sim),
                {"units": "1/s", "long_name": "growth rate of a small perturbation, simulated"},
            ),
            "growth_linear": (
                "stiffness_ratio",
                np.array(lin),
                {"units": "1/s", "long_name": "growth rate from the linearisation"},
            ),
        },
        coords={
            "stiffness_ratio": ("stiffness_ratio", np.array(ratios), {"units": "1", "long_name": "k / k_c"})
        },
    )


def _inertial_growth(kw: float, mass_kg: float, v0: float) -> float:
    return growth_rate(_params(kw, f"{mass_kg} kg"), kw, v0)


def _inertia(n_mass: int, n_points: int) -> xr.Dataset:
    kc = (B - A) / Q_(DC).to("m").magnitude
    w, a_ = 10.0, A
    dc: float = float(Q_(DC).to("m").magnitude)
    v0 = 1e-3  # m/s: inertia matters at high driving velocity
    eps = np.geomspace(1e-4, 10.0, n_mass)  # m v0**2 / (W A D0)
    masses = eps * w * a_ * dc / v0**2
    kc_m = []
    for m in masses:
        lo, hi = 0.2 * kc, 50.0 * kc
        g_lo, g_hi = _inertial_growth(lo, m, v0), _inertial_growth(hi, m, v0)
        kc_m.append(
            brentq(lambda k, m=m: _inertial_growth(k, m, v0), lo, hi, xtol=1e-9 * kc)
            if g_lo > 0 > g_hi
            else math.nan
        )
    # below k_c: the quasi-static slider runs away, the inertial one stays on a limit cycle
    m_demo = float(masses[np.searchsorted(eps, 1e-2)])
    p_in = _params(0.8 * kc, f"{m_demo} kg")
    ds = simulate_rate_state(p_in, **_demo_run(p_in, n_points))
    # the slip-velocity maxima, located as events on the solver's dense output (not samples)
    vp = ds.velocity_peak.values
    tp = ds.velocity_peak_time.values
    big = vp > 10 * v0  # the slip events, not the small wiggles of the stick phase
    vp, tp = vp[big], tp[big]
    peaks = list(range(vp.size))
    cycle_peak = float(vp[-1]) if vp.size else math.nan
    cycle_period = float(np.mean(np.diff(tp[-4:]))) if vp.size >= 4 else math.nan
    peak_change = float(abs(vp[-1] - vp[-2]) / vp[-1]) if vp.size >= 2 else math.nan
    return xr.Dataset(
        {
            "inertia_kc_ratio": (
                "inertia_eps",
                np.array(kc_m) / kc,
                {"units": "1", "long_name": "critical stiffness with inertia / (B - A) W / D0"},
            ),
            "inertia_mass": ("inertia_eps", masses, {"units": "kg", "long_name": "mass"}),
            "cycle_velocity": (
                "cycle_time",
                ds.slip_velocity.values,
                {"units": "m/s", "long_name": "slip velocity, inertial model, k = 0.8 k_c"},
            ),
            "cycle_friction": ("cycle_time", ds.friction.values, {"units": "1", "long_name": "friction"}),
        },
        coords={
            "inertia_eps": ("inertia_eps", eps, {"units": "1", "long_name": "m v0^2 / (W A D0)"}),
            "cycle_time": ("cycle_time", ds.time.values, {"units": "s", "long_name": "time"}),
        },
        attrs={
            "inertia_v0": v0,
            "inertia_demo_mass": m_demo,
            "quasi_static_runaway": "",  # the part "runaway" (the quasi-static integrator)
            "cycle_peak_velocity": cycle_peak,
            "cycle_period": cycle_period,
            "cycle_last_peak_change": peak_change,
            "cycle_n_peaks": len(peaks),
        },
    )


def _demo_run(params: RateStateParameters, n_points: int) -> dict[str, Any]:
    """Return the run of the demonstration slider ``params`` below ``k_c``: 1 mm/s from near steady state.

    The same for the inertial slider (part "inertia") and the quasi-static one (part "runaway").
    """
    dc = float(Q_(DC).to("m").magnitude)
    v0 = 1e-3  # m/s: inertia matters at high driving velocity
    mu_ss = float(params.steady_state_friction(Q_(v0, "m/s")))
    duration = Q_(3.0 if n_points > 3000 else 1.5, "s")
    return {
        "history": [(duration, Q_(v0, "m/s"))],
        "initial": (mu_ss + 1e-3, Q_(dc / v0, "s")),
        "n_points": n_points,
        "rtol": 1e-9,
    }


def _runaway(n_points: int) -> xr.Dataset:
    """Run the inertia part's demonstration slider without its mass: quasi-static, it runs away.

    A part of its own: it needs the quasi-static integrator, which the critical-stiffness
    part compiles (the same process, in ``reproduce``), not the inertial one.
    """
    kc = (B - A) / Q_(DC).to("m").magnitude
    p_qs = _params(0.8 * kc)
    try:
        simulate_rate_state(p_qs, **_demo_run(p_qs, n_points))
        runaway = "does not run away within the simulated time"
    except RateStateStopped as exc:  # said in the report's words, not the command line's advice
        runaway = (
            f"runs away: its slip velocity passes {exc.velocity:.3g} m/s at t = {exc.time:.3g} s and "
            "still rises (an instability without bound)"
            if exc.reason == "runaway"
            else f"stops at t = {exc.time:.3g} s ({exc.reason})"
        )
    return xr.Dataset(attrs={"quasi_static_runaway": runaway})


#: the appendix's parts, computed apart (``reproduce(parallel=True)`` shares them out) and merged;
#: the second process takes its parts in this order: "critical" compiles the quasi-static
#: integrator that "runaway" then finds compiled (the results do not depend on the order)
APPENDIX_PARTS = ("portraits", "critical", "runaway", "inertia")


def appendix_part(name: str, quick: bool = False) -> xr.Dataset:
    """Compute one part of the appendix (one of :data:`APPENDIX_PARTS`)."""
    if not isinstance(name, str):
        raise ArgumentTypeError(
            f"name={name!r} (type {type(name).__name__}): expected one of {APPENDIX_PARTS}"
        )
    if name == "portraits":
        return _phase_portraits(3 if quick else 5, 60.0 if quick else 120.0)
    if name == "critical":
        return _critical_check((0.9, 0.97, 1.03, 1.1) if not quick else (0.9, 1.1), 800 if quick else 3000)
    if name == "inertia":
        return _inertia(6 if quick else 24, 2000 if quick else 6000)
    if name == "runaway":
        return _runaway(2000 if quick else 6000)
    raise ValueError(f"name={name!r}: expected one of {APPENDIX_PARTS}")


def merge_appendix(parts: dict[str, xr.Dataset]) -> xr.Dataset:
    """Return the appendix from its parts (every name of :data:`APPENDIX_PARTS`)."""
    portraits, critical, runaway, inertia = (parts[name] for name in APPENDIX_PARTS)
    ds = xr.merge([portraits, critical, inertia], combine_attrs="override")
    ds.attrs = {
        "appendix_A": A,
        "appendix_B": B,
        "appendix_mu0": MU0,
        "appendix_omega": OMEGA,
        "appendix_D0": DC,
        "appendix_V_r": VR,
        "appendix_load": LOAD,
        **{f"appendix_{k}": v for k, v in {**inertia.attrs, **runaway.attrs}.items()},
    }
    return ds


def compute_appendix(quick: bool = False) -> xr.Dataset:
    """Compute the appendix's evidence: phase portraits, critical stiffness, inertia."""
    return merge_appendix({name: appendix_part(name, quick) for name in APPENDIX_PARTS})
