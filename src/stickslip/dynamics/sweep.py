"""Parameter sweeps on the batched engine, returned as labelled ``xarray.Dataset``.

A sweep takes a base parameter set and a grid: one array of values per swept
parameter. Every combination is run (one dimension per swept parameter), in
parallel, in chunks, with a progress bar when the sweep takes more than a
moment. A point whose computation fails keeps its status and NaN values; the
other points are not affected.

What can be swept comes from the law's declaration (:mod:`stickslip.laws`):
physical sweeps vary the set-up (``v0``, ``mass``, ``stiffness``, ``load``,
``beta``, which sets the mass through ``m = (beta mu_s W)**2 / k``), the static
coefficient ``mu_s`` and the law's physical parameters (``a``, ``b`` of the
weakening law; a formula's own parameters); dimensionless sweeps vary ``nu`` and
the law's dimensionless parameters. Every point is validated with the law's own
validators, vectorised over the whole grid before anything runs.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pint
import xarray as xr

from .. import defaults
from ..bifurcation.attractors import polish_rows
from ..core.api import Kernel, run_attractors
from ..core.laws import N_LAW_PARAMS
from ..core.memory import check_memory
from ..core.results import AttractorRows, Regime
from ..io.output import OutputFolder, emit, netcdf_writer, package_version
from ..io.progress import progress_bar
from ..laws import PhysicalLaw
from ..laws.spec import STATIC, Parameter
from ..models.parameters import (
    DimensionlessParameters,
    PhysicalParameters,
    dimensionless_from_si,
    mass_for_beta,
)
from ..units import parse_quantity
from .cycle import DIMENSIONLESS_UNITS, validate_tolerances

__all__ = ["SETUP", "Axis", "axes", "check_sweep_size", "load_sweep", "save_sweep", "sweep", "sweepable"]

#: memory one point of a sweep takes in process (engine output, the grid, the dataset with
#: its labels), measured on 1e5-point sweeps and rounded up
BYTES_PER_POINT = 800.0


def check_sweep_size(n: int, what: str = "the sweep") -> None:
    """Refuse a sweep of ``n`` points that would not fit in memory, before anything is allocated.

    Raises
    ------
    MemoryRequestError
        A :class:`ValueError` with the estimate and what the machine has.

    """
    check_memory(
        n * BYTES_PER_POINT,
        f"{what} ({n:.3g} points)",
        "use a coarser grid or split the range into several sweeps",
    )


FloatArray = npt.NDArray[np.float64]

#: the set-up's parameters: name -> Parameter (SI unit, bounds, help)
SETUP = {
    "v0": Parameter("v0", "driving velocity", unit="m/s", example="5 um/s"),
    "mass": Parameter("mass", "mass of the moving part", unit="kg", example="1 kg"),
    "stiffness": Parameter("stiffness", "spring constant", unit="N/m", example="62 N/m"),
    "load": Parameter("load", "normal load", unit="N", example="196 mN"),
    "beta": Parameter("beta", "beta = sqrt(k m)/(mu_s W) (sets the mass)", unit="s/m", example="42 s/m"),
}
NU = Parameter("nu", "dimensionless driving velocity beta v0")


@dataclass(frozen=True)
class Axis:
    """What a sweep axis is: its parameter and whether it belongs to the set-up or the law."""

    parameter: Parameter
    kind: str  # "setup", "static", "law" (physical), "nu", "dimensionless"


def axes(params: DimensionlessParameters | PhysicalParameters) -> dict[str, Axis]:
    """Return every parameter a sweep of ``params`` can vary (aliases included), by name."""
    spec = params.law.spec
    if isinstance(params, PhysicalParameters):
        out = {k: Axis(p, "setup") for k, p in SETUP.items()}
        if spec.static_from is None:  # a formula's mu(0+) is not a parameter of its own
            out["mu_s"] = Axis(STATIC, "static")
            for alias in spec.static_aliases:
                out[alias] = Axis(STATIC, "static")
        out.update({p.name: Axis(p, "law") for p in spec.physical})
        return out
    return {"nu": Axis(NU, "nu"), **{p.name: Axis(p, "dimensionless") for p in spec.parameters}}


def sweepable(params: DimensionlessParameters | PhysicalParameters) -> list[str]:
    """Return the names of the parameters a sweep of ``params`` can vary."""
    return [k for k, a in axes(params).items() if a.parameter.name == k]


def _grid_values(p: Parameter, name: str, values: Any) -> tuple[FloatArray, FloatArray, str]:
    """Return (values in the user's unit, values in SI, unit string) for one swept parameter."""
    if isinstance(values, str):
        raise ValueError(f"{name}={values!r}: expected a sequence of values, not a single string")
    if isinstance(values, pint.Quantity):
        if np.ndim(values.magnitude) == 0:
            raise ValueError(
                f"{name}={values!r}: expected a sequence of values (an array "
                "quantity or a list), not a single value"
            )
        if p.unit and values.check(p.dimension):
            si = np.asarray(values.to(p.unit).magnitude, dtype=float).ravel()
            shown = np.asarray(values.magnitude, dtype=float).ravel()
            if si.size == 0:
                raise ValueError(f"{name}: the list of values is empty")
            p.check_array(si)
            return shown, si, f"{values.units:~}"
        items: list[Any] = [values[i] for i in range(len(values.magnitude))]
    else:
        try:
            items = list(values)
        except TypeError:
            raise ValueError(f"{name}={values!r}: expected a sequence of values") from None
    if not items:
        raise ValueError(f"{name}: the list of values is empty")
    if not p.unit:
        shown = np.array([_number(name, v) for v in items], dtype=float)
        p.check_array(shown)
        return shown, shown.copy(), ""
    example = p.example or f"1 {p.unit}"
    qs = [parse_quantity(v, name, p.dimension, example, allow_zero=True, allow_negative=True) for v in items]
    unit = qs[0].units
    shown = np.array([q.to(unit).magnitude for q in qs], dtype=float)
    si = np.array([q.to(p.unit).magnitude for q in qs], dtype=float)
    p.check_array(si)
    return shown, si, f"{unit:~}"


def _number(name: str, v: Any) -> float:
    if isinstance(v, pint.Quantity):
        if not v.dimensionless:
            raise ValueError(f"{name}={v!r}: expected a dimensionless number")
        v = v.to("").magnitude
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise ValueError(f"{name}={v!r}: expected a number") from None
    if not math.isfinite(x):
        raise ValueError(f"{name}={x!r}: expected a finite number")
    return x


def sweep(
    base: DimensionlessParameters | PhysicalParameters,
    grid: Mapping[str, Any],
    *,
    rtol: float = defaults.RTOL,
    atol: float = defaults.ATOL,
    max_slip_time: float = defaults.MAX_SLIP_TIME,
    conv_tol: float = defaults.CONV_TOL,
    progress: bool | None = None,
) -> xr.Dataset:
    """Compute the steady oscillation reached from rest at every point of a grid.

    Parameters
    ----------
    base : DimensionlessParameters or PhysicalParameters
        Values of the parameters that are not swept.
    grid : Mapping[str, sequence]
        Swept parameter to its values, e.g. ``{"v0": Q_(np.geomspace(5, 1000, 60), "um/s")}``
        or ``{"nu": np.geomspace(1e-4, 1e-1, 30), "c": [1, 3, 10]}``. Physical values
        may be quantities or strings; the dataset keeps the unit of the first value.
        :func:`sweepable` lists the names.
    rtol, atol, max_slip_time, conv_tol : float, optional
        As in :func:`stickslip.cycle`.
    progress : bool, optional
        Show a progress bar: None (default) shows one on a terminal for sweeps
        that take more than half a second; False never; True always.

    Returns
    -------
    xarray.Dataset
        One dimension per swept parameter (coordinates with ``units`` in their
        attributes); variables ``amplitude``, ``period``, ``stick_fraction``,
        ``stick_time``, ``slip_distance``, ``peak_velocity``, ``regime``,
        ``status``, ``multiplier`` (the nontrivial Floquet multiplier),
        ``steady_sliding_stable``, ``nu`` and the law's dimensionless parameters.
        Each point equals :func:`stickslip.cycle` with ``probe=False``: pure-slip
        and slip-reversal attractors are polished into their periodic orbits, and
        a point whose transient could not be polished is ``not-converged``.

    """
    rtol, atol = validate_tolerances(rtol, atol)
    if not isinstance(base, DimensionlessParameters | PhysicalParameters):
        raise ValueError(f"base={base!r}: expected DimensionlessParameters or PhysicalParameters")
    if not grid:
        raise ValueError("grid is empty: give at least one parameter to sweep")
    allowed = axes(base)
    for name in grid:
        if name not in allowed:
            raise ValueError(
                f"cannot sweep {name!r} for this set-up ({base.law.name} law, "
                f"{'physical' if isinstance(base, PhysicalParameters) else 'dimensionless'}): "
                f"expected one of {sweepable(base)}"
            )
    canonical = [allowed[n].parameter.name for n in grid]
    if len(set(canonical)) != len(canonical):
        raise ValueError(f"grid {list(grid)}: one parameter given twice (under two names)")
    coords: dict[str, tuple[FloatArray, str, str]] = {}
    si_axes: dict[str, FloatArray] = {}
    for name, values in grid.items():
        p = allowed[name].parameter
        shown, si, unit = _grid_values(dataclasses.replace(p, name=name), name, values)
        coords[p.name] = (shown, unit, p.help)
        si_axes[p.name] = si
    shape = tuple(len(v) for v in si_axes.values())
    check_sweep_size(int(np.prod(shape, dtype=np.float64)))
    mesh = dict(zip(si_axes, np.meshgrid(*si_axes.values(), indexing="ij"), strict=True))
    flat = {k: v.ravel() for k, v in mesh.items()}
    n = int(np.prod(shape))

    if isinstance(base, PhysicalParameters):
        nu, law_nd, scales = _physical_to_dimensionless(base, flat, n)
    else:
        nu, law_nd = _dimensionless_arrays(base, flat, n)
        scales = None
    spec = base.law.spec
    spec.validate(law_nd)
    lp = np.zeros((n, N_LAW_PARAMS))
    for j, p in enumerate(spec.parameters):
        lp[:, j] = law_nd[p.name]
    kernel = base.law.kernel if isinstance(base, DimensionlessParameters) else spec.kernel()
    out, mult = _run_chunks(kernel, lp, nu, rtol, atol, max_slip_time, conv_tol, progress)
    return _dataset(base, coords, shape, out, mult, nu, law_nd, scales, rtol, atol)


def _physical_to_dimensionless(
    base: PhysicalParameters, flat: dict[str, FloatArray], n: int
) -> tuple[FloatArray, dict[str, FloatArray], dict[str, FloatArray]]:
    def arr(name: str, default: float) -> FloatArray:
        return flat[name] if name in flat else np.full(n, default)

    law: PhysicalLaw = base.law
    spec = law.spec
    law_si = {key: arr(key, v) for key, v in law.si_parameters().items()}
    mu = spec.static_from(law_si) if spec.static_from is not None else arr("mu_s", law.mu_s)
    k = arr("stiffness", base.stiffness.to("N/m").magnitude)
    w = arr("load", base.load.to("N").magnitude)
    if "beta" in flat:
        if "mass" in flat:
            raise ValueError("sweep either 'beta' or 'mass', not both: beta sets the mass")
        m = mass_for_beta(flat["beta"], k, w, mu)
    else:
        m = arr("mass", base.mass.to("kg").magnitude)
    PhysicalLaw._validate(spec, mu, law_si)
    nu, nd, scales = dimensionless_from_si(
        spec, stiffness=k, mass=m, load=w, v0=arr("v0", base.v0.to("m/s").magnitude), mu_s=mu, law_si=law_si
    )
    return nu, nd, scales


def _dimensionless_arrays(
    base: DimensionlessParameters, flat: dict[str, FloatArray], n: int
) -> tuple[FloatArray, dict[str, FloatArray]]:
    nu = flat["nu"] if "nu" in flat else np.full(n, base.nu)
    nd = {k: flat[k] if k in flat else np.full(n, v) for k, v in base.law.params.items()}
    return nu, nd


def _run_chunks(
    kernel: Kernel,
    lp: FloatArray,
    nu: FloatArray,
    rtol: float,
    atol: float,
    max_slip_time: float,
    conv_tol: float,
    progress: bool | None,
) -> tuple[AttractorRows, FloatArray]:
    n = nu.shape[0]
    out = AttractorRows.empty(n)
    mult = np.empty(n)
    chunk = max(256, min(20_000, n // 50 + 1))
    bounds = [*range(0, n, chunk), n]
    pairs = list(itertools.pairwise(bounds))
    bar = progress_bar(n, unit="pt", desc="sweep", progress=progress)
    for lo, hi in pairs:
        rows = run_attractors(
            kernel,
            lp[lo:hi],
            nu[lo:hi],
            from_breakaway=True,
            rtol=rtol,
            atol=atol,
            max_slip_time=max_slip_time,
            conv_tol=conv_tol,
        )
        out[lo:hi], mult[lo:hi] = polish_rows((kernel, lp[lo:hi]), nu[lo:hi], rows)
        if bar is not None:
            bar.update(hi - lo)
    if bar is not None:
        bar.close()
    return out, mult


def _dataset(
    base: DimensionlessParameters | PhysicalParameters,
    coords: dict[str, tuple[FloatArray, str, str]],
    shape: tuple[int, ...],
    out: AttractorRows,
    mult: FloatArray,
    nu: FloatArray,
    law_nd: dict[str, FloatArray],
    scales: dict[str, FloatArray] | None,
    rtol: float,
    atol: float,
) -> xr.Dataset:
    dims = tuple(coords)
    bad = ~out.ok
    period = out.period
    stick = out.stick_time
    steady = out.regime == Regime.STEADY_SLIDING.code
    with np.errstate(invalid="ignore", divide="ignore"):
        stick_fraction = np.where(steady, 0.0, stick / period)
    slip_distance = np.where(steady, np.nan, nu * period)
    values = {
        "amplitude": (out.amplitude, "force", "range of the spring force over one steady cycle"),
        "period": (period, "time", "period of the steady oscillation"),
        "stick_time": (stick, "time", "duration of the stick phase per cycle"),
        "stick_fraction": (stick_fraction, "1", "fraction of the period at rest"),
        "slip_distance": (slip_distance, "length", "distance slipped per cycle"),
        "peak_velocity": (out.w_max, "velocity", "largest block velocity over the cycle"),
    }
    si = {"force": "N", "time": "s", "length": "m", "velocity": "m/s", "1": "1"}
    data: dict[str, Any] = {}
    for key, (v, kind, desc) in values.items():
        if scales is not None and kind != "1":
            v = v * scales[kind]
            unit = si[kind]
        else:
            unit = "1" if kind == "1" else DIMENSIONLESS_UNITS[kind]
        v = np.where(bad, np.nan, v)
        data[key] = (dims, v.reshape(shape), {"units": unit, "long_name": desc})
    # plain str arrays (numpy picks the width), so that NetCDF round-trips them exactly
    regimes = np.array([str(r) for r in out.regimes()])
    data["multiplier"] = (
        dims,
        np.where(bad, np.nan, mult).reshape(shape),
        {
            "units": "1",
            "long_name": "nontrivial Floquet multiplier of the attractor (0 stick-slip, NaN steady sliding)",
        },
    )
    data["regime"] = (
        dims,
        regimes.reshape(shape),
        {"long_name": "regime reached from rest", "values": "stick-slip, pure-slip, steady-sliding, unknown"},
    )
    data["status"] = (
        dims,
        np.array([str(st) for st in out.statuses()]).reshape(shape),
        {"long_name": "ok, or why the point failed"},
    )
    data["steady_sliding_stable"] = (
        dims,
        (out.dfnu > 0.0).reshape(shape),
        {"long_name": "steady sliding linearly stable, f'(nu) > 0"},
    )
    # the dimensionless form of every point (unless it is itself a swept coordinate)
    base_spec = base.law.spec
    names = {p.name for p in base_spec.parameters}
    if "nu" not in coords:
        data["nu"] = (dims, nu.reshape(shape), {"units": "1", "long_name": "nu = beta v0"})
    for key, v in law_nd.items():
        if key not in coords:
            data[key] = (
                dims,
                v.reshape(shape),
                {"units": "1", "long_name": base_spec.parameter(key).help if key in names else key},
            )
    coord_vars = {
        name: (name, vals, {"units": unit or "1", "long_name": desc})
        for name, (vals, unit, desc) in coords.items()
    }
    attrs = {
        "title": "stickslip parameter sweep: steady oscillation reached from rest",
        "law": base.law.name,
        "law_description": base.law.describe(),
        "kind": "physical" if isinstance(base, PhysicalParameters) else "dimensionless",
        "base_parameters": repr(base),
        "rtol": rtol,
        "atol": atol,
        "stickslip_version": package_version(),
        "Conventions": "CF-1.8",
    }
    return xr.Dataset(data, coords=coord_vars, attrs=attrs)


def save_sweep(
    ds: xr.Dataset,
    path: str | os.PathLike[str],
    *,
    kind: str = "sweep",
    out: OutputFolder | None = None,
    overwrite: bool = False,
) -> str:
    """Write a dataset to NetCDF (netCDF4 format), atomically; return the path.

    The file is marked as stickslip's output of ``kind`` (attribute ``stickslip_output``);
    an existing file that is not stickslip's output of that kind is kept unless
    ``overwrite``. ``out`` stages it with the other files of a run (``path`` a name in it).
    """
    return emit(os.fspath(path), kind, netcdf_writer(ds, kind), out=out, overwrite=overwrite)


def load_sweep(path: str | os.PathLike[str]) -> xr.Dataset:
    """Read a sweep written by :func:`save_sweep` (fully loaded, file closed).

    Raises
    ------
    ValueError
        If the file does not exist or is not a NetCDF file.

    """
    if not os.path.exists(path):
        raise ValueError(f"path={os.fspath(path)!r}: no such file")
    try:
        ds = xr.load_dataset(path, engine="netcdf4")
    except Exception as exc:  # netCDF4 raises OSError/RuntimeError/ValueError variously
        raise ValueError(f"path={os.fspath(path)!r} is not a readable NetCDF file ({exc})") from None
    for key in ("stickslip_output", "stickslip_generator"):  # the file's marks, not the data's
        ds.attrs.pop(key, None)
    return ds
