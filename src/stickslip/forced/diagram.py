"""Brute-force bifurcation diagrams of the forced oscillator: stroboscopic samples against a parameter.

For each value of the parameter (the forcing frequency by default) the engine runs
``transient`` periods from the start and records the state at the next
``record`` sections, with the largest Lyapunov exponent over them when asked.
The job is cut into blocks of parameter values and runs as every long job does
(:mod:`stickslip.scale`): on all cores by default, on ``workers`` local processes
or a Dask cluster (``scheduler``), streamed block by block into a resumable Zarr
store (``store``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.forced_api import STAT_FIELDS, forced_strobe
from ..core.memory import check_memory
from ..errors import ArgumentTypeError
from ..models.scales import unit_attrs
from ..scale import Block, Layout, ProgressLike, Variable
from ..scale.progress import show_progress
from ..units import check_number
from .motion import RTOL, check_duration, check_start
from .response import CURVE_PARAMETERS
from .system import ForcedSystem, as_forced

__all__ = ["BifurcationJob", "bifurcation_diagram"]

#: parameter values per block of the job
BLOCK_ROWS = 64


@dataclass(frozen=True)
class BifurcationJob:
    """A bifurcation diagram cut into blocks of parameter values."""

    system: ForcedSystem
    parameter: str
    values: np.ndarray
    transient: int
    record: int
    start: tuple[float, float]
    lyapunov: bool
    rtol: float
    backend: str = "cpu"

    def rows(self, sl: slice) -> tuple[np.ndarray, np.ndarray]:
        """Return the law and forcing vectors of the rows ``sl``."""
        vals = self.values[sl]
        _, lp, fp = self.system.arrays()
        fps = np.tile(fp, (vals.size, 1))
        lps = np.tile(lp, (vals.size, 1))
        if self.parameter in CURVE_PARAMETERS:
            fps[:, ("nu0", "nu1", "omega", "phi", "q", "delta").index(self.parameter)] = vals
        else:
            for i, v in enumerate(vals):
                lps[i] = self.system.law.replace(**{self.parameter: float(v)}).arrays()[1]
        return lps, fps

    def task(self, block: Block) -> Any:
        """Return the computation of one block."""
        return _Rows(self, block.slices[0])

    def layout(self) -> Layout:
        """Return the store's layout: ``(value, sample)``."""
        n = self.values.size
        ex = "" if self.lyapunov else " (not computed)"
        return Layout(
            kind="forced-bifurcation",
            dims=("value", "sample"),
            shape=(n, self.record),
            chunks=(min(BLOCK_ROWS, n), self.record),
            coords={
                "value": (("value",), self.values, {"long_name": self.parameter, "units": "1"}),
                "sample": (("sample",), np.arange(self.record), {"long_name": "section after the transient"}),
            },
            variables=(
                Variable(
                    "s",
                    ("value", "sample"),
                    "float64",
                    {"long_name": "spring force at the section", **unit_attrs("force", False)},
                ),
                Variable(
                    "w",
                    ("value", "sample"),
                    "float64",
                    {"long_name": "velocity at the section", **unit_attrs("velocity", False)},
                ),
                Variable(
                    "stops_per_period",
                    ("value",),
                    "float64",
                    {"long_name": "stick phases per forcing period", "units": "1"},
                ),
                Variable(
                    "stick_fraction",
                    ("value",),
                    "float64",
                    {"long_name": "fraction of the time stuck", "units": "1"},
                ),
                Variable(
                    "lyapunov",
                    ("value",),
                    "float64",
                    {"long_name": "largest Lyapunov exponent" + ex, "units": "1", "scale": "per sqrt(m/k)"},
                ),
                Variable(
                    "status",
                    ("value",),
                    "int8",
                    {
                        "long_name": "engine status",
                        "flag_values": [0, 1, 2, 3],
                        "flag_meanings": "ok max_steps nonfinite max_events",
                    },
                ),
            ),
            identity={
                "system": self.system.describe(),
                "parameter": self.parameter,
                "values": [float(self.values[0]), float(self.values[-1]), int(n)],
                "transient": self.transient,
                "record": self.record,
                "start": list(self.start),
                "lyapunov": self.lyapunov,
                "rtol": self.rtol,
            },
            attrs={
                "system": self.system.describe(),
                "transient_periods": self.transient,
                "Conventions": "CF-1.10",
            },
            describe=f"a bifurcation diagram of {n} values of {self.parameter} x {self.record} sections",
        )

    def dataset(self, arrays: dict[str, Any]) -> Any:
        """Return the diagram's Dataset."""
        import xarray as xr

        layout = self.layout()
        coords = {k: (d, v, dict(a)) for k, (d, v, a) in layout.coords.items()}
        data = {v.name: (v.dims, arrays[v.name], dict(v.attrs)) for v in layout.variables}
        return xr.Dataset(data, coords=coords, attrs=dict(layout.attrs))


@dataclass(frozen=True)
class _Rows:
    job: BifurcationJob
    rows: slice

    def __call__(self) -> dict[str, Any]:
        job = self.job
        lps, fps = job.rows(self.rows)
        kernel = job.system.law.arrays()[0]
        out, lyap, stats = forced_strobe(
            kernel,
            lps,
            fps,
            job.start,
            job.transient,
            job.record,
            lyapunov=job.lyapunov,
            rtol=job.rtol,
            atol=job.rtol * 1e-2,
            backend=job.backend,
        )
        period = 2.0 * math.pi / fps[:, 2]
        return {
            "s": out[:, :, 0],
            "w": out[:, :, 1],
            "stops_per_period": stats[:, STAT_FIELDS.index("stops")] / job.record,
            "stick_fraction": stats[:, STAT_FIELDS.index("stick_time")] / (job.record * period),
            "lyapunov": lyap[:, 0],
            "status": stats[:, STAT_FIELDS.index("status")].astype(np.int8),
        }


def bifurcation_diagram(
    system: Any,
    values: Any,
    *,
    parameter: str = "omega",
    transient: int = 500,
    record: int = 200,
    start: Any = (0.0, 0.0),
    lyapunov: bool = False,
    rtol: float = RTOL,
    backend: str = "cpu",
    progress: ProgressLike = None,
    store: Any = None,
    scheduler: Any = None,
    workers: int | None = None,
) -> Any:
    """Return the stroboscopic bifurcation diagram of ``system`` against ``parameter``.

    Parameters
    ----------
    system : ForcedSystem or PhysicalForcedSystem
        The oscillator: dimensionless, or physical (results in SI).
    values : array_like
        The parameter's values (dimensionless).
    parameter : str
        ``omega`` (default), ``q``, ``nu0``, ``nu1``, ``delta``, ``phi`` or a law parameter.
    transient, record : int
        Periods run before the samples, and sections recorded.
    start : (float, float)
        ``(s, w)`` at the first section, the same for every value.
    lyapunov : bool
        Compute the Lyapunov exponents over the recorded periods (about three
        times the cost of the samples alone).
    rtol : float
        The engine's relative tolerance (absolute: ``rtol / 100``).
    backend : str
        ``"cpu"`` (numba's threads), ``"cuda"`` (a GPU thread per value) or ``"auto"``.
    progress, store, scheduler, workers : optional
        As for :func:`stickslip.regime_map`: a progress bar, a Zarr store to resume, a
        Dask cluster or ``workers`` local processes.

    Returns
    -------
    xarray.Dataset
        ``s`` and ``w`` (value x sample), ``stops_per_period``, ``stick_fraction``,
        ``lyapunov`` and ``status`` per value, with CF attributes.

    """
    dp, _ = as_forced(system)
    if not isinstance(parameter, str) or parameter not in CURVE_PARAMETERS + tuple(dp.law.params):
        raise ValueError(
            f"parameter={parameter!r}: expected one of {', '.join(CURVE_PARAMETERS + tuple(dp.law.params))}"
        )
    try:
        vals = np.asarray(values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"values={values!r}: expected numbers") from None
    if vals.size == 0 or not np.all(np.isfinite(vals)):
        raise ValueError(
            f"values: expected finite numbers, got {vals.size} values with NaN or inf"
            if vals.size
            else "values: empty"
        )
    if parameter == "omega" and np.any(vals <= 0):
        raise ValueError(f"values: omega must be positive, got {vals.min():g}")
    nt = int(check_number(transient, "transient", allow_zero=True, upper=1e7, what="a number of periods"))
    nr = int(
        check_number(
            record, "record", upper=1e6, upper_inclusive=True, what="a number of sections (1 to 1e6)"
        )
    )
    s0, w0 = check_start(start)
    rt = check_number(rtol, "rtol", upper=1e-3, what="a relative tolerance in (0, 1e-3]")
    from ..core.cuda import resolve_backend

    for w in (float(np.min(vals)), float(np.max(vals))) if parameter == "omega" else (dp.omega,):
        check_duration(dp.with_(omega=w), nt + nr, f"transient={nt}, record={nr} at omega={w:g}")
    check_memory(
        vals.size * nr * 2 * 8 * 2, f"{vals.size} values x {nr} sections", "ask fewer, or give store="
    )
    job = BifurcationJob(dp, parameter, vals, nt, nr, (s0, w0), bool(lyapunov), rt, resolve_backend(backend))
    from ..scale import run_job

    show: ProgressLike = progress
    if progress is None:
        show = show_progress(None) and vals.size > BLOCK_ROWS
    return run_job(
        job,
        job.layout(),
        store=store,
        scheduler=scheduler,
        workers=workers,
        progress=show,
        desc="bifurcation diagram",
    )
