"""The paper's criterion on trial: regime maps of F1, F2 and the cubic law, and the verdicts.

Each map runs :func:`stickslip.bifurcation.regime_map.regime_map` over one law
parameter and :func:`~stickslip.bifurcation.regime_map.criterion_trial` over ``nu``.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from ..bifurcation.regime_map import criterion_table, criterion_trial, regime_map
from ..errors import ArgumentTypeError
from ..laws import CubicLaw, DimensionlessLaw, WeakeningLaw
from ..models.parameters import zv_parameters
from ..plots.regimes import MARK_LABEL, MARK_NU_MAX, MARK_NU_MIN, MARK_VALUE

__all__ = ["TRIAL_MAPS", "TrialMap", "run_trials"]


@dataclass(frozen=True)
class TrialMap:
    """One map of the trial: a law, the parameter varied over ``values`` and the ``nu`` range."""

    key: str
    title: str
    law: DimensionlessLaw
    param: str
    values: tuple[float, ...]
    nu_min: float
    nu_max: float


TRIAL_MAPS = (
    TrialMap("f1_c", "F1 (p = 0), over c", WeakeningLaw(c=3.8), "c",
             tuple(np.geomspace(0.3, 30.0, 16)), 1e-3, 10.0),
    TrialMap("f2_p", "F2 (c = 3.8), over p", WeakeningLaw(c=3.8, p=0.5), "p",
             tuple(np.linspace(0.0, 2.5, 16)), 1e-3, 10.0),
    TrialMap("cubic_alpha", "Thomsen-Fidlin cubic law (gamma = 1/6), over alpha",
             CubicLaw(alpha=0.5, gamma=1 / 6), "alpha", tuple(np.linspace(0.1, 1.2, 16)), 0.01, 5.0),
)  # fmt: skip


def run_trials(
    *, quick: bool = False, progress: bool | None = False, keys: tuple[str, ...] | None = None
) -> dict[str, xr.Dataset]:
    """Compute the maps of :data:`TRIAL_MAPS` (those named in ``keys``; all by default) with the verdicts."""
    known = [m.key for m in TRIAL_MAPS]
    if keys is not None:
        if (
            isinstance(keys, str)
            or not isinstance(keys, Iterable)
            or not all(isinstance(k, str) for k in keys)
        ):
            raise ArgumentTypeError(f"keys={keys!r}: expected a tuple of trial names out of {known}")
        unknown = [k for k in keys if k not in known]
        if unknown:
            raise ValueError(f"keys: {unknown} are not trials: expected names out of {known}")
    out = {}
    for m in TRIAL_MAPS:
        if keys is not None and m.key not in keys:
            continue
        with warnings.catch_warnings():
            # the cubic map runs on past alpha**3 = 27 gamma / 4, where the friction turns
            # negative (said in the report): no warning per map row
            warnings.filterwarnings("ignore", message="cubic law.*turns negative", category=UserWarning)
            out[m.key] = _trial(m, quick, progress)
    return out


def _trial(m: TrialMap, quick: bool, progress: bool | None) -> xr.Dataset:
    values = m.values[::5] if quick else m.values
    ds = regime_map(m.law, m.param, values, m.nu_min, m.nu_max, n_nu=41 if quick else 161, progress=progress)
    tr = criterion_trial(ds)
    tr.attrs["title"] = m.title
    tr.attrs.update(_paper_point(m))
    return tr


def _paper_point(m: TrialMap) -> dict[str, Any]:
    """Where the paper's zv experiment lies on the map ``m`` (attributes the figures mark; none off it).

    The zv set-up at 5 to 1000 um/s (the range of its Figs. 2 and 3): ``c = a / beta`` for
    F1's map, ``p = b / beta`` with ``b = 100 s/m`` (its F2) on F2's, over ``nu = beta v0``.
    """
    key = {"f1_c": ("c", "0 s/m"), "f2_p": ("p", "100 s/m")}.get(m.key)
    if key is None:
        return {}
    name, b = key
    lo, hi = (zv_parameters(v, b=b).dimensionless() for v in ("5 um/s", "1000 um/s"))
    return {
        MARK_VALUE: float(getattr(lo.law, name)),
        MARK_NU_MIN: float(lo.nu),
        MARK_NU_MAX: float(hi.nu),
        MARK_LABEL: f"the paper's zv experiment, 5-1000 um/s (b = {b})",
    }


def trial_rows(trials: dict[str, xr.Dataset]) -> list[tuple[str, ...]]:
    """Rows ``(map, regime reached, judged, right, wrong)`` for the report."""
    rows: list[tuple[str, ...]] = []
    for tr in trials.values():
        for r in criterion_table(tr):
            if r["judged"]:
                rows.append(
                    (str(tr.attrs["title"]), r["regime"], str(r["judged"]), str(r["right"]), str(r["wrong"]))
                )
    return rows
