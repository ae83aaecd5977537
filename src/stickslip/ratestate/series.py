"""The record of a simulated history as a dataset: time series and the located maxima.

:func:`~stickslip.ratestate.protocols.simulate_rate_state` turns what the integrators of
:mod:`~stickslip.ratestate.solvers` return into an :class:`xarray.Dataset`: the
friction, slip velocity, states, displacements and load-point velocity over ``time``,
and the spring-force maxima (with inertia also the slip-velocity maxima) located on
the dense output, without the ones that are rounding on steady sliding.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt
import xarray as xr

from ..core import ratestate_api as core
from ..units import Q_
from .model import RateStateParameters

__all__ = ["PEAK_FLOOR"]

FloatArray = npt.NDArray[np.float64]


def _record_velocity(ds: xr.Dataset, t: float) -> float:
    """Return the load-point velocity of the record ``ds`` at ``t`` (held from each row to the next)."""
    t_s = ds.time.values
    return float(ds.load_point_velocity.values[max(0, int(np.searchsorted(t_s, t, side="right")) - 1)])


#: a spring-force maximum less than this above steady sliding's spring force is rounding, not a peak
PEAK_FLOOR = 1e-9

Located = list[tuple[float, FloatArray]]  # maxima located on the dense output: (time, state)


def _real(ds: xr.Dataset, located: Located, real: Callable[[float, FloatArray], bool]) -> Located:
    """Return the maxima ``(t, y)`` for which ``real(v_lp, y)``, ``v_lp`` the record's at ``t``."""
    return [(t, y) for t, y in located if real(_record_velocity(ds, t), y)]


def _above_steady(ds: xr.Dataset, params: RateStateParameters, spring: Located) -> Located:
    """Drop spring-force 'maxima' within ``PEAK_FLOOR`` of steady sliding at the load-point velocity.

    On steady sliding the slip velocity wiggles about the load point's at rounding level, and
    each upward crossing is located as a maximum (3e-14 above steady sliding after a velocity
    step has settled).
    """
    if not spring:
        return spring
    eta = 0.0 if params.radiation_damping is None else float(params.radiation_damping.to("s/m").magnitude)

    def steady(v_lp: float) -> float:
        return float(params.steady_state_friction(Q_(v_lp, "m/s"))) + eta * v_lp

    return _real(ds, spring, lambda v_lp, y: not v_lp > 0 or float(y[0]) - steady(v_lp) > PEAK_FLOOR)


def _add_maxima(ds: xr.Dataset, dim: str, variables: dict[str, tuple[list[Any], str, str]]) -> None:
    """Add ``{name: (values, units, long name)}`` over ``dim``, the dimension of some maxima."""
    for name, (values, units, long_name) in variables.items():
        ds[name] = (dim, np.array(values), {"units": units, "long_name": long_name})


def _with_peaks(ds: xr.Dataset, params: RateStateParameters, peaks: dict[str, Located]) -> xr.Dataset:
    """Add the located extrema: spring-force peaks and, with inertia, slip-velocity peaks."""
    P, S = params.core_arrays()
    n = params.n_states
    sp = _above_steady(ds, params, peaks["spring"])
    v_at = [float(y[1]) if params.inertial else core.qs_velocity(y[0], y, S, n, P) for _, y in sp]
    _add_maxima(
        ds,
        "spring_peak",
        {
            "spring_peak_time": (
                [t for t, _ in sp],
                "s",
                "time of a spring-force maximum (event on the dense output)",
            ),
            "spring_peak_friction": (
                [float(y[0]) for _, y in sp],
                "1",
                "spring force / W at its maximum (the friction, quasi-statically)",
            ),
            "spring_peak_velocity": (
                v_at,
                "m/s",
                "slip velocity at the spring-force maximum (= load-point velocity)",
            ),
        },
    )
    if params.inertial:
        # a 'maximum' of the slip velocity within 1e-8 of the load point's, on steady sliding, is
        # rounding (a start settled at 1e-4 m/s has such maxima at v = 1.0000000000e-4)
        vp = _real(ds, peaks["velocity"], lambda v_lp, y: not abs(float(y[1]) - v_lp) <= 1e-8 * v_lp)
        _add_maxima(
            ds,
            "velocity_peak",
            {
                "velocity_peak_time": (
                    [t for t, _ in vp],
                    "s",
                    "time of a slip-velocity maximum (event on the dense output)",
                ),
                "velocity_peak": ([float(y[1]) for _, y in vp], "m/s", "slip velocity at its maximum"),
                "velocity_peak_friction": (
                    [core.in_friction(float(y[1]), y, S, n, P) for _, y in vp],
                    "1",
                    "friction at the slip-velocity maximum",
                ),
            },
        )
    return ds


def _dataset(
    params: RateStateParameters,
    t: FloatArray,
    y: FloatArray,
    u: FloatArray | None,
    vlp: FloatArray,
    hist: list[tuple[float, float]],
) -> xr.Dataset:
    """Return the time series at ``t`` of the states ``y`` (a column each; ``u``: ``ln(v/V_r)``)."""
    P, S = params.core_arrays()
    n = params.n_states
    vr, kw, eta = float(P[core.P_VR]), float(P[core.P_KW]), float(P[core.P_ETA])
    # load-point displacement: integral of the piecewise-constant velocity
    bounds = np.concatenate([[0.0], np.cumsum([d for d, _ in hist])])
    disp = np.concatenate([[0.0], np.cumsum([d * v for d, v in hist])])
    seg = np.clip(np.searchsorted(bounds, t, side="right") - 1, 0, len(hist) - 1)
    x_lp = disp[seg] + (t - bounds[seg]) * np.array([v for _, v in hist])[seg]
    if params.inertial:
        spring, v, theta = y[0], y[1], y[2:]
        mu = np.array([core.in_friction(y[1, i], y[:, i], S, n, P) for i in range(t.size)])
    else:
        spring, theta = y[0], y[1:]
        assert u is not None
        v = vr * np.exp(u)
        mu = spring - eta * v
    x = x_lp - spring / kw
    data: dict[str, Any] = {
        "friction": ("time", mu, {"units": "1", "long_name": "friction coefficient"}),
        "slip_velocity": ("time", v, {"units": "m/s", "long_name": "slider velocity"}),
        "slider_displacement": ("time", x - x[0], {"units": "m", "long_name": "slider displacement"}),
        "load_point_displacement": ("time", x_lp, {"units": "m", "long_name": "load-point displacement"}),
        "load_point_velocity": ("time", vlp, {"units": "m/s", "long_name": "load-point velocity"}),
        "spring_friction": ("time", spring, {"units": "1", "long_name": "spring force / W"}),
    }
    for i in range(n):
        name = "state" if i == 0 else f"state_{i + 1}"
        data[name] = (
            "time",
            np.exp(theta[i]) * params.state_scale(i) / vr,
            {
                "units": "s",
                "long_name": f"state Phi{'' if n == 1 else f'_{i + 1}'} ({params.laws[i]} law)",
            },
        )
    return xr.Dataset(
        data,
        coords={"time": ("time", t, {"units": "s", "long_name": "time"})},
        attrs={
            "model": "inertial" if params.inertial else ("quasi-dynamic" if eta > 0 else "quasi-static"),
            "state_law": ",".join(params.laws),
            "state_variables": n,
            "parameters": repr(params),
        },
    )
