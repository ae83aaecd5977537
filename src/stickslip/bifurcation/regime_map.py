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

import dataclasses
import math
import numbers
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import xarray as xr

from ..core.checks import NU_MAX, NU_MIN, nu_outside
from ..core.results import AttractorRows, Regime
from ..errors import ArgumentTypeError
from ..laws import DimensionlessLaw, require_dimensionless_law
from ..laws.spec import check_distinct
from ..scale.progress import ProgressLike, show_progress
from ..scale.store import Block, Layout, Variable
from .branches import RegimeDiagram, pure_slip_orbits_at
from .regimes import MAX_GRID, _grid, regimes

__all__ = ["REGIME_CODES", "RegimeMapJob", "criterion_table", "criterion_trial", "regime_map"]

#: integer codes of the ``regime`` variable (CF ``flag_values``): the codes of :class:`Regime`
REGIME_CODES = {
    r.value: r.code
    for r in (
        Regime.NONE,
        Regime.STICK_SLIP,
        Regime.PURE_SLIP,
        Regime.SLIP_REVERSAL,
        Regime.STEADY_SLIDING,
        Regime.BISTABLE,
        Regime.MULTISTABLE,
        Regime.UNKNOWN,
    )
}
#: what a simulation from rest reaches (``observed`` variable), in the same codes
_OBSERVED = (Regime.STICK_SLIP, Regime.PURE_SLIP, Regime.STEADY_SLIDING, Regime.SLIP_REVERSAL, Regime.UNKNOWN)
OBSERVED_CODES = {r.value: r.code for r in _OBSERVED}


def _with(law: DimensionlessLaw, name: str, value: float) -> DimensionlessLaw:
    allowed = law.spec.mappable
    if not isinstance(name, str):
        raise ArgumentTypeError(f"param={name!r} (type {type(name).__name__}): expected one of {allowed}")
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
    progress: ProgressLike = None,
    store: str | os.PathLike[str] | None = None,
    scheduler: Any = None,
    workers: int | None = None,
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
        Points of the ``nu`` grid (at least 5).
    progress : bool or callable, optional
        Progress bar (None: on a terminal, for long maps); a callable receives a
        :class:`~stickslip.scale.ProgressInfo` after each row.
    store : path, optional
        Write the map row by row to this Zarr store; run again after an
        interruption and only the missing rows are computed.
    scheduler, workers : optional
        Run the rows on a Dask cluster (address or ``distributed.Client``) or on a
        ``LocalCluster`` of ``workers`` processes (see :func:`stickslip.dynamics.sweep`).

    Returns
    -------
    xarray.Dataset
        Dimensions ``(param, nu)``; variables ``regime`` (codes in
        :data:`REGIME_CODES`, named in ``flag_meanings``), ``observed`` (what a
        simulation from rest reaches), ``amplitude`` (its spring-force range, units
        of static friction) and, per ``param`` value, the interval ends ``hopf``,
        ``fold``, ``grazing`` and ``stick_slip_onset``: the smallest ``nu`` of each
        kind in the row, NaN when absent (a row with two Hopf points keeps the
        lower; :func:`~.regimes.regimes` at that value lists them all).

    """
    law = require_dimensionless_law(law)
    sequence = f"values={values!r}: expected a 1-d sequence of finite numbers"
    if isinstance(values, str | bytes):
        raise ArgumentTypeError(sequence)
    try:
        vals = np.asarray(values, dtype=float)
    except (TypeError, ValueError):  # entries that are not numbers, or a ragged nesting
        raise ArgumentTypeError(sequence) from None
    if vals.ndim == 0:  # one value (or None) for a sequence
        raise ArgumentTypeError(sequence)
    if vals.ndim != 1 or vals.size < 1 or not np.all(np.isfinite(vals)):
        raise ValueError(sequence)
    for v in vals:  # the name, and every value before any row runs (not row by row, in the store)
        _with(law, param, float(v))
    check_distinct(param, vals, [f"{v:g}" for v in vals])
    for name, nu in (("nu_min", nu_min), ("nu_max", nu_max)):
        if isinstance(nu, bool) or not isinstance(nu, numbers.Real):
            raise ArgumentTypeError(f"{name}={nu!r} (type {type(nu).__name__}): expected a driving velocity")
    if not (0 < nu_min < nu_max) or not math.isfinite(nu_max):
        raise ValueError(f"nu_min={nu_min!r}, nu_max={nu_max!r}: expected 0 < nu_min < nu_max")
    if nu_outside([nu_min, nu_max]).any():  # before any row runs (not row by row, in the store)
        raise ValueError(
            f"nu_min={nu_min!r}, nu_max={nu_max!r}: expected driving velocities from {NU_MIN:g} to {NU_MAX:g}"
        )
    if isinstance(n_nu, bool) or not isinstance(n_nu, int | np.integer):
        raise ArgumentTypeError(f"n_nu={n_nu!r}: expected a whole number of nu points from 5 to {MAX_GRID}")
    if not 5 <= n_nu <= MAX_GRID:
        raise ValueError(f"n_nu={n_nu!r}: expected a whole number of nu points from 5 to {MAX_GRID}")
    job = RegimeMapJob(law, param, vals, float(nu_min), float(nu_max), int(n_nu))
    from ..scale import run_job

    show: ProgressLike = progress
    if progress is None:
        show = show_progress(None) and vals.size > 4
    return run_job(job, job.layout(), store=store, scheduler=scheduler, workers=workers, progress=show,
                   desc=f"regimes over {param}")  # fmt: skip


_ENDS = ("hopf", "fold", "grazing", "stick_slip_onset")


@dataclass(frozen=True)
class RegimeMapJob:
    """A regime map cut into rows (one value of the mapped parameter per block)."""

    law: DimensionlessLaw
    param: str
    values: npt.NDArray[np.float64]
    nu_min: float
    nu_max: float
    n_nu: int

    @property
    def nu(self) -> npt.NDArray[np.float64]:
        """The ``nu`` grid (the one :func:`~.regimes.regimes` uses)."""
        return _grid(self.nu_min, self.nu_max, self.n_nu)

    def task(self, block: Block) -> _RegimeRows:
        """Return the computation of one block of rows."""
        return _RegimeRows(dataclasses.replace(self, values=self.values[block.slices[0]]))

    def layout(self) -> Layout:
        """Return the store's layout: rows of ``(param, nu)``, one row per block."""
        dims = (self.param, "nu")
        variables = [
            Variable("regime", dims, "int8", _REGIME_ATTRS),
            Variable("observed", dims, "int8", _OBSERVED_ATTRS),
            Variable("amplitude", dims, "float64", _AMPLITUDE_ATTRS),
            *(
                Variable(
                    k, (self.param,), "float64", {"long_name": f"{k.replace('_', ' ')} (dimensionless nu)"}
                )
                for k in _ENDS
            ),
        ]
        return Layout(
            kind="regime-map",
            dims=dims,
            shape=(self.values.size, self.n_nu),
            chunks=(1, self.n_nu),
            coords=self._coords(),
            variables=tuple(variables),
            identity={
                "law": self.law.describe(),
                "param": self.param,
                "values": self.values,
                "nu": [self.nu_min, self.nu_max, self.n_nu],
            },
            attrs=self._attrs(),
            describe=(
                f"a regime map of the {self.law.name} law over {self.param} ({self.values.size} values "
                f"{self.values[0]:.4g}..{self.values[-1]:.4g}) and nu ({self.n_nu} values "
                f"{self.nu_min:.4g}..{self.nu_max:.4g})"
            ),
        )

    def _coords(self) -> dict[str, Any]:
        return {
            self.param: (
                (self.param,),
                self.values,
                {"long_name": f"{self.law.name} law parameter {self.param}", "units": "1"},
            ),
            "nu": (("nu",), self.nu, {"long_name": "dimensionless driving velocity beta*v0", "units": "1"}),
        }

    def _attrs(self) -> dict[str, Any]:
        return {"law": self.law.name, **{k: float(x) for k, x in self.law.params.items() if k != self.param}}

    def dataset(self, arrays: dict[str, Any]) -> xr.Dataset:
        """Return the map's Dataset from its arrays."""
        layout = self.layout()
        data = {v.name: (v.dims, arrays[v.name], dict(v.attrs)) for v in layout.variables}
        coords = {k: (d, vals, dict(a)) for k, (d, vals, a) in layout.coords.items()}
        return xr.Dataset(data, coords=coords, attrs=self._attrs())


_REGIME_ATTRS = {
    "long_name": "set of attractors",
    "flag_values": list(REGIME_CODES.values()),
    "flag_meanings": " ".join(REGIME_CODES),
}
_OBSERVED_ATTRS = {
    "long_name": "attractor reached from rest",
    "flag_values": list(OBSERVED_CODES.values()),
    "flag_meanings": " ".join(OBSERVED_CODES),
}
_AMPLITUDE_ATTRS = {
    "long_name": "spring-force range of the attractor reached from rest",
    "units": "1",  # CF: UDUNITS; what it is in units of is the scale
    "scale": "static friction force mu_s W",
}


@dataclass(frozen=True)
class _RegimeRows:
    """Rows of a regime map: what one task computes (the job restricted to its rows)."""

    job: RegimeMapJob

    def __call__(self) -> dict[str, Any]:
        job = self.job
        k = job.values.size
        regime = np.empty((k, job.n_nu), dtype=np.int8)
        observed = np.empty((k, job.n_nu), dtype=np.int8)
        amplitude = np.empty((k, job.n_nu))
        ends = {key: np.full(k, math.nan) for key in _ENDS}
        for i, v in enumerate(job.values):
            d = regimes(_with(job.law, job.param, float(v)), job.nu_min, job.nu_max, n_grid=job.n_nu)
            regime[i], observed[i], amplitude[i] = _rows(d)
            for p in d.points:
                key = p.kind.replace("-", "_")
                if key in ends and math.isnan(ends[key][i]):
                    ends[key][i] = p.nu
        return {"regime": regime, "observed": observed, "amplitude": amplitude, **ends}


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
