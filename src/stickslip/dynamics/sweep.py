"""Parameter sweeps on the batched engine, returned as labelled ``xarray.Dataset``.

A sweep takes a base parameter set and a grid: one array of values per swept
parameter. Every combination is run (one dimension per swept parameter), in
parallel, in chunks, with a progress bar when the sweep takes more than a
moment. A point whose computation fails keeps its status and NaN values; the
other points are not affected.

Physical sweeps can vary the set-up (``v0``, ``mass``, ``stiffness``, ``load``,
``beta``, which sets the mass through ``m = (beta mu_s W)**2 / k``) and the law's
physical parameters (``mu0``, ``a``, ``b``; ``mu_s``, ``k1``, ``k3``; ``mu_s``,
``mu_k``). Dimensionless sweeps vary ``nu`` and the law's dimensionless
parameters (``c``, ``p``; ``alpha``, ``gamma``; ``kinetic``).
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt
import pint
import xarray as xr

from .. import __version__, defaults
from ..bifurcation.attractors import polish_rows
from ..core.api import Kernel, builtin_kernel, run_attractors
from ..core.laws import N_LAW_PARAMS
from ..core.memory import check_memory
from ..core.results import AttractorRows, Regime
from ..io.output import OutputFolder, emit, netcdf_writer
from ..io.progress import progress_bar
from ..models.friction import CoulombLaw, CubicLaw, WeakeningLaw
from ..models.parameters import DimensionlessParameters, PhysicalParameters, dimensionless_from_si
from ..models.units import parse_quantity
from .cycle import DIMENSIONLESS_UNITS, validate_tolerances

__all__ = ["check_sweep_size", "load_sweep", "save_sweep", "sweep", "sweepable"]

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

# name: (dimension, SI unit, description); dimension "" = dimensionless number
SETUP = {
    "v0": ("[length] / [time]", "m/s", "driving velocity"),
    "mass": ("[mass]", "kg", "mass"),
    "stiffness": ("[mass] / [time] ** 2", "N/m", "spring constant"),
    "load": ("[force]", "N", "normal load"),
    "beta": ("[time] / [length]", "s/m", "beta = sqrt(k m)/(mu_s W)"),
}
PHYSICAL_LAW = {
    "weakening": {
        "mu0": ("", "", "static friction coefficient"),
        "a": ("[time] / [length]", "s/m", "weakening rate a"),
        "b": ("[time] / [length]", "s/m", "strengthening rate b"),
    },
    "cubic": {
        "mu_s": ("", "", "static friction coefficient"),
        "k1": ("[time] / [length]", "s/m", "linear coefficient k1"),
        "k3": ("[time] ** 3 / [length] ** 3", "s**3/m**3", "cubic coefficient k3"),
    },
    "coulomb": {
        "mu_s": ("", "", "static friction coefficient"),
        "mu_k": ("", "", "kinetic friction coefficient"),
    },
}
DIMENSIONLESS_LAW = {
    "weakening": {"c": "weakening rate c = a/beta", "p": "strengthening p = b/beta"},
    "cubic": {"alpha": "alpha = k1/(mu_s beta)", "gamma": "gamma = k3/(mu_s beta^3)"},
    "coulomb": {"kinetic": "kinetic/static friction ratio"},
}
ZERO_ALLOWED = {"b", "p"}


def sweepable(params: DimensionlessParameters | PhysicalParameters) -> list[str]:
    """Return the names of the parameters a sweep of ``params`` can vary."""
    if isinstance(params, PhysicalParameters):
        return [*SETUP, *PHYSICAL_LAW[params.law.name]]
    return ["nu", *DIMENSIONLESS_LAW[params.law.name]]


def _grid_values(name: str, values: Any, dimension: str) -> tuple[FloatArray, FloatArray, str]:
    """Return (values in the user's unit, values in SI, unit string) for one swept parameter."""
    if isinstance(values, str):
        raise ValueError(f"{name}={values!r}: expected a sequence of values, not a single string")
    if isinstance(values, pint.Quantity):
        if np.ndim(values.magnitude) == 0:
            raise ValueError(
                f"{name}={values!r}: expected a sequence of values (an array "
                "quantity or a list), not a single value"
            )
        items: list[Any] = [values[i] for i in range(len(values.magnitude))]
    else:
        try:
            items = list(values)
        except TypeError:
            raise ValueError(f"{name}={values!r}: expected a sequence of values") from None
    if not items:
        raise ValueError(f"{name}: the list of values is empty")
    if dimension == "":
        shown = np.array([_number(name, v) for v in items], dtype=float)
        return shown, shown.copy(), ""
    qs = [
        parse_quantity(
            v, name, dimension, "1 " + SETUP.get(name, ("", "s/m"))[1], allow_zero=name in ZERO_ALLOWED
        )
        for v in items
    ]
    unit = qs[0].units
    shown = np.array([q.to(unit).magnitude for q in qs], dtype=float)
    si_unit = SETUP[name][1] if name in SETUP else _law_si_unit(name)
    si = np.array([q.to(si_unit).magnitude for q in qs], dtype=float)
    return shown, si, f"{unit:~}"


def _law_si_unit(name: str) -> str:
    for table in PHYSICAL_LAW.values():
        if name in table:
            return table[name][1]
    raise KeyError(name)


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
    if x < 0 or (x == 0 and name not in ZERO_ALLOWED):
        raise ValueError(f"{name}={x!r} must be {'non-negative' if name in ZERO_ALLOWED else 'positive'}")
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
    allowed = sweepable(base)
    for name in grid:
        if name not in allowed:
            raise ValueError(
                f"cannot sweep {name!r} for this set-up ({base.law.name} law, "
                f"{'physical' if isinstance(base, PhysicalParameters) else 'dimensionless'}): "
                f"expected one of {allowed}"
            )
    physical = isinstance(base, PhysicalParameters)
    coords: dict[str, tuple[FloatArray, str, str]] = {}
    si_axes: dict[str, FloatArray] = {}
    for name, values in grid.items():
        if physical:
            dim = SETUP[name][0] if name in SETUP else PHYSICAL_LAW[base.law.name][name][0]
            desc = SETUP[name][2] if name in SETUP else PHYSICAL_LAW[base.law.name][name][2]
        else:
            dim, desc = (
                "",
                (
                    "dimensionless driving velocity"
                    if name == "nu"
                    else DIMENSIONLESS_LAW[base.law.name][name]
                ),
            )
        shown, si, unit = _grid_values(name, values, dim)
        coords[name] = (shown, unit, desc)
        si_axes[name] = si
    shape = tuple(len(v) for v in si_axes.values())
    check_sweep_size(int(np.prod(shape, dtype=np.float64)))
    mesh = dict(zip(si_axes, np.meshgrid(*si_axes.values(), indexing="ij"), strict=True))
    flat = {k: v.ravel() for k, v in mesh.items()}
    n = int(np.prod(shape))

    if physical:
        assert isinstance(base, PhysicalParameters)
        nu, law_nd, scales = _physical_to_dimensionless(base, flat, n)
    else:
        assert isinstance(base, DimensionlessParameters)
        nu, law_nd = _dimensionless_arrays(base, flat, n)
        scales = None
    law_name = base.law.name
    core_id = {"weakening": WeakeningLaw.core_id, "cubic": CubicLaw.core_id, "coulomb": CoulombLaw.core_id}[
        law_name
    ]
    _check_dimensionless_law(law_name, law_nd)
    lp = np.zeros((n, N_LAW_PARAMS))
    for j, key in enumerate(DIMENSIONLESS_LAW[law_name]):
        lp[:, j] = law_nd[key]

    out, mult = _run_chunks(builtin_kernel(core_id), lp, nu, rtol, atol, max_slip_time, conv_tol, progress)
    return _dataset(base, coords, shape, out, mult, nu, law_nd, scales, rtol, atol)


def _si(q: pint.Quantity, unit: str) -> float:
    return float(q.to(unit).magnitude)


def _physical_to_dimensionless(
    base: PhysicalParameters, flat: dict[str, FloatArray], n: int
) -> tuple[FloatArray, dict[str, FloatArray], dict[str, FloatArray]]:
    def arr(name: str, default: float) -> FloatArray:
        return flat[name] if name in flat else np.full(n, default)

    law = base.law
    mu_name = "mu0" if law.name == "weakening" else "mu_s"
    mu = arr(mu_name, law.static_coefficient)
    k = arr("stiffness", _si(base.stiffness, "N/m"))
    w = arr("load", _si(base.load, "N"))
    if "beta" in flat:
        if "mass" in flat:
            raise ValueError("sweep either 'beta' or 'mass', not both: beta sets the mass")
        m = (flat["beta"] * (mu * w)) ** 2 / k
    else:
        m = arr("mass", _si(base.mass, "kg"))
    law_si = {key: arr(key, v) for key, v in law.si_parameters().items()}
    if law.name == "coulomb" and np.any(law_si["mu_k"] >= mu):
        i = int(np.argmax(law_si["mu_k"] >= mu))
        raise ValueError(f"mu_k={float(law_si['mu_k'][i])!r} is not below mu_s={float(mu[i])!r} at point {i}")
    nu, nd, scales = dimensionless_from_si(
        law.name,
        stiffness=k,
        mass=m,
        load=w,
        v0=arr("v0", _si(base.v0, "m/s")),
        static_coefficient=mu,
        law_si=law_si,
    )
    return nu, nd, scales


def _dimensionless_arrays(
    base: DimensionlessParameters, flat: dict[str, FloatArray], n: int
) -> tuple[FloatArray, dict[str, FloatArray]]:
    nu = flat["nu"] if "nu" in flat else np.full(n, base.nu)
    nd = {}
    for key in DIMENSIONLESS_LAW[base.law.name]:
        nd[key] = flat[key] if key in flat else np.full(n, float(getattr(base.law, key)))
    return nu, nd


def _check_dimensionless_law(law_name: str, nd: dict[str, FloatArray]) -> None:
    if law_name == "coulomb" and np.any(nd["kinetic"] >= 1.0):
        i = int(np.argmax(nd["kinetic"] >= 1.0))
        raise ValueError(f"kinetic={float(nd['kinetic'][i])!r} at point {i}: expected a ratio below 1")


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
    dfnu = _steady_stable(base.law.name, nu, law_nd)
    data["steady_sliding_stable"] = (
        dims,
        dfnu.reshape(shape),
        {"long_name": "steady sliding linearly stable, f'(nu) > 0"},
    )
    # the dimensionless form of every point (unless it is itself a swept coordinate)
    if "nu" not in coords:
        data["nu"] = (dims, nu.reshape(shape), {"units": "1", "long_name": "nu = beta v0"})
    for key, v in law_nd.items():
        if key not in coords:
            data[key] = (
                dims,
                v.reshape(shape),
                {"units": "1", "long_name": DIMENSIONLESS_LAW[base.law.name][key]},
            )
    coord_vars = {
        name: (name, vals, {"units": unit or "1", "long_name": desc})
        for name, (vals, unit, desc) in coords.items()
    }
    attrs = {
        "title": "stickslip parameter sweep: steady oscillation reached from rest",
        "law": base.law.name,
        "kind": "physical" if isinstance(base, PhysicalParameters) else "dimensionless",
        "base_parameters": repr(base),
        "rtol": rtol,
        "atol": atol,
        "stickslip_version": __version__,
        "Conventions": "CF-1.8",
    }
    return xr.Dataset(data, coords=coord_vars, attrs=attrs)


def _steady_stable(law_name: str, nu: FloatArray, nd: dict[str, FloatArray]) -> npt.NDArray[np.bool_]:
    if law_name == "weakening":
        d = -nd["c"] / (1.0 + nd["c"] * nu) ** 2 + nd["p"]
    elif law_name == "cubic":
        d = -nd["alpha"] + 3.0 * nd["gamma"] * nu**2
    else:
        d = np.zeros_like(nu)
    return np.asarray(d > 0.0)


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
