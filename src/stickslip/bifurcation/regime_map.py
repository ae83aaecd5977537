"""Two-parameter regime maps and the paper's criterion on trial.

:func:`regime_map` runs :func:`~.regimes.regimes` for each value of one law
parameter and stores, on a common ``nu`` grid, the set of attractors and what a
simulation from rest reaches (the stick-slip orbit where it exists, otherwise
the stable pure-slip orbit, otherwise steady sliding), with its amplitude from
the periodic orbit solved at that ``nu`` (exact near the Hopf point, where
transients crawl).

:func:`criterion_trial` then applies the paper's criterion to those amplitudes,
as an experimenter would: the sign of ``d(amplitude)/d(nu)`` read as
stick-slip (rising) or pure slip (falling), and compares it with the regime
actually reached.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from ..core.results import AttractorRows, Regime
from ..io.progress import show_progress
from ..laws import DimensionlessLaw, require_dimensionless_law
from .regimes import RegimeDiagram, pure_slip_orbits_at, regimes

__all__ = ["REGIME_CODES", "criterion_table", "criterion_trial", "regime_map"]

#: integer codes of the ``regime`` variable (CF ``flag_values``): the codes of :class:`Regime`
REGIME_CODES = {
    r.value: r.code
    for r in (
        Regime.NONE,
        Regime.STICK_SLIP,
        Regime.PURE_SLIP,
        Regime.STEADY_SLIDING,
        Regime.BISTABLE,
        Regime.UNKNOWN,
    )
}
#: what a simulation from rest reaches (``observed`` variable), in the same codes
_OBSERVED = (Regime.STICK_SLIP, Regime.PURE_SLIP, Regime.STEADY_SLIDING, Regime.SLIP_REVERSAL, Regime.UNKNOWN)
OBSERVED_CODES = {r.value: r.code for r in _OBSERVED}


def _with(law: DimensionlessLaw, name: str, value: float) -> DimensionlessLaw:
    allowed = law.spec.mappable
    if name not in allowed:
        raise ValueError(f"param={name!r}: a regime map of the {law.name} law runs over one of {allowed}")
    return law.replace(**{name: float(value)})


def regime_map(
    law: DimensionlessLaw,
    param: str,
    values: Sequence[float] | np.ndarray,
    nu_min: float,
    nu_max: float,
    *,
    n_nu: int = 201,
    progress: bool | None = None,
) -> xr.Dataset:
    """Compute the regimes over the plane (``param``, ``nu``).

    Parameters
    ----------
    law : DimensionlessLaw
        The law; its other parameters are held fixed.
    param : str
        One of its parameters (``law.spec.mappable``): ``c`` or ``p`` (weakening),
        ``alpha`` or ``gamma`` (cubic), a formula's own.
    values : sequence of float
        Values of ``param``.
    nu_min, nu_max : float
        Range of ``nu`` (a logarithmic grid when it spans more than a factor 20).
    n_nu : int, optional
        Points of the ``nu`` grid.
    progress : bool, optional
        Progress bar (None: on a terminal, for long maps).

    Returns
    -------
    xarray.Dataset
        Dimensions ``(param, nu)``; variables ``regime`` (codes in
        :data:`REGIME_CODES`, named in ``flag_meanings``), ``observed`` (what a
        simulation from rest reaches), ``amplitude`` (its spring-force range, units
        of static friction) and, per ``param`` value, the interval ends ``hopf``,
        ``fold``, ``grazing`` and ``stick_slip_onset`` (NaN when absent).

    """
    law = require_dimensionless_law(law)
    vals = np.asarray(values, dtype=float)
    if vals.ndim != 1 or vals.size < 1 or not np.all(np.isfinite(vals)):
        raise ValueError(f"values={values!r}: expected a 1-d sequence of finite numbers")
    _with(law, param, float(vals[0]))  # checks the name
    from tqdm.auto import tqdm

    show = show_progress(progress) if progress is not None else (show_progress(None) and vals.size > 4)
    regime = np.empty((vals.size, n_nu), dtype=np.int8)
    observed = np.empty((vals.size, n_nu), dtype=np.int8)
    amplitude = np.empty((vals.size, n_nu))
    ends = {k: np.full(vals.size, math.nan) for k in ("hopf", "fold", "grazing", "stick_slip_onset")}
    grid = None
    for i, v in enumerate(tqdm(vals, desc=f"regimes over {param}", disable=not show)):
        d = regimes(_with(law, param, float(v)), nu_min, nu_max, n_grid=n_nu)
        steady = d.branches[0]
        grid = steady.nu
        regime[i], observed[i], amplitude[i] = _rows(d)
        for p in d.points:
            key = p.kind.replace("-", "_")
            if key in ends and math.isnan(ends[key][i]):
                ends[key][i] = p.nu
    assert grid is not None
    ds = xr.Dataset(
        {
            "regime": (
                (param, "nu"),
                regime,
                {
                    "long_name": "set of attractors",
                    "flag_values": list(REGIME_CODES.values()),
                    "flag_meanings": " ".join(REGIME_CODES),
                },
            ),
            "observed": (
                (param, "nu"),
                observed,
                {
                    "long_name": "attractor reached from rest",
                    "flag_values": list(OBSERVED_CODES.values()),
                    "flag_meanings": " ".join(OBSERVED_CODES),
                },
            ),
            "amplitude": (
                (param, "nu"),
                amplitude,
                {"long_name": "spring-force range of the attractor reached from rest", "units": "mu_s W"},
            ),
            **{
                k: ((param,), a, {"long_name": f"{k.replace('_', ' ')} (dimensionless nu)"})
                for k, a in ends.items()
            },
        },
        coords={
            param: (param, vals, {"long_name": f"{law.name} law parameter {param}"}),
            "nu": ("nu", grid, {"long_name": "dimensionless driving velocity beta*v0"}),
        },
        attrs={"law": law.name, **{k: float(x) for k, x in law.params.items() if k != param}},
    )
    return ds


def _rows(d: RegimeDiagram) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    grid = d.branches[0].nu
    rows: AttractorRows = d.rest  # the engine from rest on this grid, run once (and polished) by regimes()
    regime = np.empty(grid.size, dtype=np.int8)
    observed = np.empty(grid.size, dtype=np.int8)
    amplitude = np.full(grid.size, math.nan)
    stick_slip = rows.is_regime(Regime.STICK_SLIP)
    oscillating = rows.is_regime(Regime.PURE_SLIP)
    steady = rows.is_regime(Regime.STEADY_SLIDING)
    for j, nu in enumerate(grid):
        regime[j] = REGIME_CODES[d.regime_at(float(nu)).regime]
        if stick_slip[j]:
            observed[j], amplitude[j] = Regime.STICK_SLIP.code, rows.amplitude[j]
        elif oscillating[j]:
            # polished into its periodic orbit: exact even where the transient crawls
            kind = Regime.SLIP_REVERSAL if rows.n_backward[j] > 0 else Regime.PURE_SLIP
            observed[j], amplitude[j] = kind.code, rows.amplitude[j]
        else:
            # steady sliding reached, or a transient not pinned down: a stable pure-slip
            # orbit of the continued branches, solved at this nu, if there is one
            ps = pure_slip_orbits_at(d, float(nu), stable_only=True)
            if ps:
                observed[j], amplitude[j] = Regime.PURE_SLIP.code, min(o.amplitude for o in ps)
            elif steady[j]:
                observed[j], amplitude[j] = Regime.STEADY_SLIDING.code, 0.0
            else:
                observed[j] = Regime.UNKNOWN.code
    return regime, observed, amplitude


def criterion_trial(ds: xr.Dataset) -> xr.Dataset:
    """Apply the paper's criterion along ``nu`` and compare with the regime reached.

    At each grid point where an oscillation is reached from rest and its two
    neighbours reach the same kind of oscillation, the slope of
    ``log(amplitude)`` against ``log(nu)`` (centred difference) is read as
    *stick-slip* when positive and *pure slip* when negative.

    Returns
    -------
    xarray.Dataset
        ``ds`` with ``slope`` (d log A / d log nu), ``verdict`` (0 stick-slip,
        1 pure slip, -1 no verdict) and ``right`` (1 right, 0 wrong, -1 not
        judged: steady sliding, or a regime change next to the point).

    """
    obs = ds.observed.values
    amp = ds.amplitude.values
    lnu = np.log(ds.nu.values)
    slope = np.full(amp.shape, math.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        la = np.log(amp)
        slope[:, 1:-1] = (la[:, 2:] - la[:, :-2]) / (lnu[2:] - lnu[:-2])
    same = np.zeros(amp.shape, dtype=bool)
    same[:, 1:-1] = (obs[:, 2:] == obs[:, 1:-1]) & (obs[:, :-2] == obs[:, 1:-1])
    osc = obs != Regime.STEADY_SLIDING.code
    osc &= obs != Regime.UNKNOWN.code
    judged = same & osc & np.isfinite(slope)
    # verdicts in the regime codes: stick-slip (amplitude rising) or pure slip (falling)
    verdict = np.where(
        judged, np.where(slope > 0, Regime.STICK_SLIP.code, Regime.PURE_SLIP.code), Regime.NONE.code
    ).astype(np.int8)
    truth = np.where(obs == Regime.SLIP_REVERSAL.code, Regime.PURE_SLIP.code, obs)  # it never sticks
    right = np.where(judged, (verdict == truth).astype(np.int8), -1).astype(np.int8)
    out = ds.copy()
    dims = ds.amplitude.dims
    out["slope"] = (dims, slope, {"long_name": "d log(amplitude) / d log(nu)"})
    out["verdict"] = (
        dims,
        verdict,
        {
            "long_name": "criterion verdict",
            "flag_values": [Regime.NONE.code, Regime.STICK_SLIP.code, Regime.PURE_SLIP.code],
            "flag_meanings": "none stick-slip pure-slip",
        },
    )
    out["right"] = (
        dims,
        right,
        {
            "long_name": "criterion agrees with the regime",
            "flag_values": [-1, 0, 1],
            "flag_meanings": "not-judged wrong right",
        },
    )
    return out


def criterion_table(trial: xr.Dataset) -> list[dict[str, Any]]:
    """Summarise a :func:`criterion_trial`: counts of right and wrong verdicts per regime reached.

    For ``slip-reversal`` (never sticks, velocity changes sign) *right* means the
    criterion said "no stick" (amplitude falling).
    """
    rows = []
    for regime in (Regime.STICK_SLIP, Regime.PURE_SLIP, Regime.SLIP_REVERSAL):
        sel = (trial.observed.values == regime.code) & (trial.right.values >= 0)
        n = int(sel.sum())
        n_right = int((trial.right.values[sel] == 1).sum())
        rows.append(
            {
                "regime": regime.value,
                "judged": n,
                "right": n_right,
                "wrong": n - n_right,
                "fraction_right": (n_right / n) if n else math.nan,
            }
        )
    return rows
