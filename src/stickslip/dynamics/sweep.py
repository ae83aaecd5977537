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
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pint
import xarray as xr

from .. import defaults
from ..core.api import Kernel, run_attractors
from ..core.checks import NU_MAX, NU_MIN, finite, nu_outside
from ..core.cuda import release_buffers, release_idle_buffers, resolve_backend
from ..core.laws import N_LAW_PARAMS
from ..core.memory import check_memory
from ..core.results import AttractorRows, Regime, Status, reversal
from ..errors import ArgumentTypeError
from ..io.netcdf import flag_attrs, labels, load_dataset, save_dataset
from ..io.output import package_version
from ..laws.spec import STATIC, Parameter, check_distinct
from ..models.parameters import DimensionlessParameters, PhysicalParameters
from ..models.scales import unit_attrs
from ..orbits.attractors import POLISH_FIELDS, polish_rows
from ..scale.progress import Progress, ProgressLike
from ..scale.store import Block, Layout, Variable
from ..units import parse_quantity
from .cycle import validate_tolerances

__all__ = [
    "SETUP",
    "Axis",
    "SweepPlan",
    "axes",
    "check_sweep_size",
    "load_sweep",
    "save_sweep",
    "sweep",
    "sweepable",
]

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
        raise ArgumentTypeError(f"{name}={values!r}: expected a sequence of values, not a single string")
    if isinstance(values, pint.Quantity):
        if np.ndim(values.magnitude) == 0:
            raise ArgumentTypeError(
                f"{name}={values!r}: expected a sequence of values (an array "
                "quantity or a list), not a single value"
            )
        if p.unit and values.check(p.dimension):
            si = np.asarray(values.to(p.unit).magnitude, dtype=float).ravel()
            shown = np.asarray(values.magnitude, dtype=float).ravel()
            if si.size == 0:
                raise ValueError(f"{name}: the list of values is empty")
            as_given = [f"{m:g} {values.units:~P}" for m in shown]
            p.check_array(si, shown=as_given)
            check_distinct(name, si, as_given)
            return shown, si, f"{values.units:~}"
        items: list[Any] = [values[i] for i in range(len(values.magnitude))]
    else:
        size = len(values) if hasattr(values, "__len__") else None
        if size is not None:  # range(10**12) refused before its list fills the memory
            check_memory(64.0 * size, f"{name}: {size} values", "a coarser grid, or blocks of it")
        try:
            items = list(values)
        except TypeError:
            raise ArgumentTypeError(f"{name}={values!r}: expected a sequence of values") from None
    if not items:
        raise ValueError(f"{name}: the list of values is empty")
    if not p.unit:
        shown = np.array([_number(name, v) for v in items], dtype=float)
        p.check_array(shown)
        check_distinct(name, shown, [f"{x:g}" for x in shown])
        return shown, shown.copy(), ""
    example = p.example or f"1 {p.unit}"
    qs = [parse_quantity(v, name, p.dimension, example, allow_zero=True, allow_negative=True) for v in items]
    unit = qs[0].units
    shown = np.array([q.to(unit).magnitude for q in qs], dtype=float)
    si = np.array([q.to(p.unit).magnitude for q in qs], dtype=float)
    as_given = [
        v if isinstance(v, str) else f"{q.magnitude:g} {q.units:~P}" for v, q in zip(items, qs, strict=True)
    ]
    p.check_array(si, shown=as_given)  # named as given ('-5 um/s'), not in SI
    check_distinct(name, si, as_given)
    return shown, si, f"{unit:~}"


def _number(name: str, v: Any) -> float:
    if isinstance(v, pint.Quantity):
        if not v.dimensionless:
            raise ValueError(f"{name}={v!r}: expected a dimensionless number")
        v = v.to("").magnitude
    return finite(name, v, text=True)


def sweep(
    base: DimensionlessParameters | PhysicalParameters,
    grid: Mapping[str, Any],
    *,
    rtol: float = defaults.RTOL,
    atol: float = defaults.ATOL,
    max_slip_time: float = defaults.MAX_SLIP_TIME,
    conv_tol: float = defaults.CONV_TOL,
    progress: ProgressLike = None,
    store: str | os.PathLike[str] | None = None,
    scheduler: Any = None,
    workers: int | None = None,
    block_points: int | None = None,
    backend: str = "cpu",
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
    progress : bool or callable, optional
        Show a progress bar: None (default) shows one on a terminal for sweeps
        that take more than half a second; False never; True always. A callable
        is called after each block with a :class:`~stickslip.scale.ProgressInfo`
        (points done, points per second, seconds left).
    store : path, optional
        Stream the result block by block to this Zarr store and make the sweep
        resumable: run the same sweep again after an interruption and only the
        missing blocks are computed. A store made for another grid or other fixed
        parameters is refused (:class:`~stickslip.scale.StoreError`). The sweep
        then returns the store, lazily read, with ``regime`` and ``status`` as CF
        flag variables (integer codes) and the run's report (blocks reused and
        computed) as JSON in its ``run`` attribute; :func:`load_sweep` reads it
        in the form returned without a store.
    scheduler : str or distributed.Client, optional
        Run the blocks on this Dask distributed cluster (its scheduler's address).
    workers : int, optional
        Run the blocks on a ``LocalCluster`` of this many processes, started for
        the sweep. With neither ``scheduler`` nor ``workers`` the sweep runs in
        this process and Dask is not imported.
    block_points : int, optional
        Points per block (one task, one chunk of the store); default
        :data:`~stickslip.scale.SWEEP_BLOCK_POINTS` (:data:`GPU_BLOCK_POINTS` on a GPU,
        whose launches want many rows), whole trailing dimensions first
        (:func:`~stickslip.scale.chunk_shape`). An existing store keeps its own.
    backend : {"cpu", "cuda", "auto"}, optional
        Where the cycles are integrated: this machine's cores (default), a CUDA GPU
        (``pip install "stickslip[cuda]"``; the same engine compiled for the GPU,
        equal to the CPU's within 1e-9), or the GPU where one is usable. The
        polishing of pure-slip orbits runs on the CPU either way.

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
    backend = resolve_backend(backend)  # an unknown backend, or no GPU for "cuda": said before any work
    if not isinstance(base, DimensionlessParameters | PhysicalParameters):
        raise ArgumentTypeError(f"base={base!r}: expected DimensionlessParameters or PhysicalParameters")
    if not isinstance(grid, Mapping):  # a list of pairs is named here, not left to 'unhashable type'
        raise TypeError(f"grid={grid!r}: expected a mapping of names to values, e.g. {{'nu': [0.01, 0.1]}}")
    if not grid:
        raise ValueError("grid is empty: give at least one parameter to sweep")
    allowed = axes(base)
    for name in grid:
        if not isinstance(name, str):
            raise ArgumentTypeError(f"grid: the key {name!r} (type {type(name).__name__}): expected a str")
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
    plan = SweepPlan(base, coords, si_axes, rtol, atol, max_slip_time, conv_tol, backend)
    # checked in every mode, though it is used only with a store or a cluster
    if block_points is not None:
        if isinstance(block_points, bool) or not isinstance(block_points, int | np.integer):
            raise ArgumentTypeError(f"block_points={block_points!r}: expected a whole number of points >= 1")
        if block_points < 1:
            raise ValueError(f"block_points={block_points!r}: expected a whole number of points >= 1")
    try:
        return _run(plan, si_axes, store, scheduler, workers, block_points, progress)
    finally:
        if backend == "cuda":  # the GPU's buffers kept between the sweep's calls (in this process)
            release_buffers()


def _run(
    plan: SweepPlan,
    si_axes: dict[str, np.ndarray],
    store: str | os.PathLike[str] | None,
    scheduler: Any,
    workers: int | None,
    block_points: int | None,
    progress: ProgressLike,
) -> xr.Dataset:
    """Run a checked sweep: in memory, or block by block to a store or a cluster."""
    backend = plan.backend
    if store is None and scheduler is None and workers is None:
        # in process, the grid in memory (no Dask imported)
        check_sweep_size(plan.points)
        arrays = plan.compute(si_axes, progress=progress)
        return plan.dataset(arrays)
    from ..scale import SWEEP_BLOCK_POINTS, chunk_shape, run_job

    default_block = SWEEP_BLOCK_POINTS if backend == "cpu" else GPU_BLOCK_POINTS
    layout = plan.layout(chunk_shape(plan.shape, block_points or default_block))
    if store is None:
        check_sweep_size(plan.points)
    # every point validated before anything runs, block by block (bounded memory)
    for block in layout.blocks():
        plan.inputs(plan.sub_axes(block))
    return run_job(plan, layout, store=store, scheduler=scheduler, workers=workers, progress=progress,
                   desc="sweep", load=False)  # fmt: skip


#: points per block of a sweep on a GPU (a store's chunk, one launch): many launch waves of
#: the 30 000-odd threads an H100 keeps resident with this kernel (199 registers a thread)
GPU_BLOCK_POINTS = 1 << 20


@dataclass(frozen=True)
class SweepPlan:
    """A validated sweep: the base set-up, the grid, the tolerances; computes any block of it.

    Picklable and small (a block carries only its own coordinates), so that Dask
    workers compute blocks from it.
    """

    base: DimensionlessParameters | PhysicalParameters
    coords: dict[str, tuple[FloatArray, str, str]]
    si_axes: dict[str, FloatArray]
    rtol: float
    atol: float
    max_slip_time: float
    conv_tol: float
    backend: str = "cpu"

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the grid."""
        return tuple(len(v) for v in self.si_axes.values())

    @property
    def points(self) -> int:
        """Points of the grid."""
        return int(np.prod(self.shape, dtype=np.int64))

    def sub_axes(self, block: Block) -> dict[str, FloatArray]:
        """Return the SI values of each axis within ``block``."""
        return {k: v[s] for (k, v), s in zip(self.si_axes.items(), block.slices, strict=True)}

    def worker_cleanup(self) -> Callable[[], bool] | None:
        """Return what a cluster's workers run once the sweep is done: free their GPU buffers.

        A worker keeps the CUDA backend's buffers between the sweep's blocks (some
        400 MB on the GPU and as much pinned host memory); a worker still running
        another job's GPU call keeps them (it is not waited for).
        """
        return release_idle_buffers if self.backend == "cuda" else None

    def task(self, block: Block) -> _SweepTask:
        """Return the computation of one block (what a worker runs)."""
        light = dataclasses.replace(self, coords={}, si_axes={k: v[:0] for k, v in self.si_axes.items()})
        return _SweepTask(light, self.sub_axes(block))

    def inputs(
        self, axes: dict[str, FloatArray]
    ) -> tuple[FloatArray, dict[str, FloatArray], dict[str, FloatArray] | None, FloatArray]:
        """Return (nu, law's dimensionless parameters, scales, core parameters) on the mesh of ``axes``.

        Raises
        ------
        ValueError
            For a point where the law or the set-up is not valid (named).

        """
        mesh = np.meshgrid(*axes.values(), indexing="ij")
        flat = {k: v.ravel() for k, v in zip(axes, mesh, strict=True)}
        n = int(np.prod([len(v) for v in axes.values()], dtype=np.int64))
        base = self.base
        if isinstance(base, PhysicalParameters):
            nu, law_nd, scales = base.dimensionless_at(flat, n)
            bad = nu_outside(nu)
            if bad.any():  # 'nu[0]=5.3e+149', a number never typed: name the point's settings
                i = int(np.argmax(bad))
                point = ", ".join(f"{k}={float(flat[k][i]):.4g} {_unit_of(base, k)}".rstrip() for k in flat)
                raise ValueError(
                    f"at the grid point {point} (SI), nu = beta v0 = {float(nu[i]):.4g}: expected "
                    f"{NU_MIN:g} to {NU_MAX:g}; check the swept values' units and magnitudes"
                )
        else:
            nu, law_nd = base.law_arrays_at(flat, n)
            scales = None
        spec = base.law.spec
        spec.validate(law_nd)
        lp = np.zeros((n, N_LAW_PARAMS))
        for j, p in enumerate(spec.parameters):
            lp[:, j] = law_nd[p.name]
        return nu, law_nd, scales, lp

    def compute(self, axes: dict[str, FloatArray], progress: ProgressLike = False) -> dict[str, FloatArray]:
        """Run the engine on the mesh of ``axes``; return the result's arrays (shape of the mesh)."""
        nu, law_nd, scales, lp = self.inputs(axes)
        base = self.base
        kernel = base.law.kernel if isinstance(base, DimensionlessParameters) else base.law.spec.kernel()
        out, mult = _run_chunks(
            kernel, lp, nu, self.rtol, self.atol, self.max_slip_time, self.conv_tol, progress, self.backend
        )
        shape = tuple(len(v) for v in axes.values())
        return _variables(out, mult, nu, law_nd, scales, shape, self.coords_names)

    @property
    def coords_names(self) -> tuple[str, ...]:
        """The swept parameters."""
        return tuple(self.si_axes)

    def variables(self) -> list[Variable]:
        """Return the result's arrays as stored: names, dtypes, attributes (labels as CF flag codes)."""
        dims = self.coords_names
        out = []
        for key, (_, kind, desc) in _VALUES.items():
            out.append(Variable(key, dims, "float64", {**self._unit_attrs(kind), "long_name": desc}))
        out.append(Variable("multiplier", dims, "float64", _MULTIPLIER_ATTRS))
        out.append(Variable("regime", dims, "int8", {**_REGIME_ATTRS, **flag_attrs(Regime)}))
        out.append(Variable("status", dims, "int8", {**_STATUS_ATTRS, **flag_attrs(Status)}))
        out.append(Variable("steady_sliding_stable", dims, "bool", _STABLE_ATTRS))
        for key, attrs in self._extra_attrs().items():
            out.append(Variable(key, dims, "float64", attrs))
        return out

    def _unit_attrs(self, kind: str) -> dict[str, str]:
        """Return a value's CF ``units`` (and ``scale``, for a dimensionless sweep)."""
        return unit_attrs(kind, isinstance(self.base, PhysicalParameters))

    def _extra_attrs(self) -> dict[str, dict[str, str]]:
        """``nu`` and the law's dimensionless parameters, unless swept."""
        spec = self.base.law.spec
        names = {p.name for p in spec.parameters}
        out = {}
        if "nu" not in self.si_axes:
            out["nu"] = {"units": "1", "long_name": "nu = beta v0"}
        for key in (p.name for p in spec.parameters):
            if key not in self.si_axes:
                out[key] = {"units": "1", "long_name": spec.parameter(key).help if key in names else key}
        return out

    def layout(self, chunks: tuple[int, ...]) -> Layout:
        """Return the store's layout of this sweep with blocks of shape ``chunks``."""
        coords = {
            name: ((name,), vals, {"units": unit or "1", "long_name": desc})
            for name, (vals, unit, desc) in self.coords.items()
        }
        identity = {
            "grid": {k: v for k, v in self.si_axes.items()},
            "units": {k: u for k, (_, u, _) in self.coords.items()},
            "shown": {k: v for k, (v, _, _) in self.coords.items()},
            "base": repr(self.base),
            "law": self.base.law.describe(),
            "tolerances": [self.rtol, self.atol, self.max_slip_time, self.conv_tol],
        }
        if self.backend != "cpu":
            # the GPU's cycles agree with the CPU's to 1e-9, not bit for bit: a store is one or the other
            identity["backend"] = self.backend
        if (self.rtol, self.atol) != (defaults.RTOL, defaults.ATOL):
            # slip-reversal orbits are polished at the sweep's own tolerances: a store begun by a
            # version that polished them at the defaults is another job (its rows would mix the two)
            identity["polish"] = "at the sweep's tolerances"
        grid = ", ".join(
            f"{k} ({len(v)} values {v[0]:.4g}..{v[-1]:.4g}{' ' + u if u else ''})"
            for k, (v, u, _) in self.coords.items()
        )
        return Layout(
            kind="sweep",
            dims=self.coords_names,
            shape=self.shape,
            chunks=chunks,
            coords=coords,
            variables=tuple(self.variables()),
            identity=identity,
            attrs=self.attrs(),
            describe=f"a sweep of the {self.base.law.name} law over {grid}",
        )

    def attrs(self) -> dict[str, Any]:
        """Attributes of the result."""
        base = self.base
        return {
            "title": "stickslip parameter sweep: steady oscillation reached from rest",
            "law": base.law.name,
            "law_description": base.law.describe(),
            "kind": "physical" if isinstance(base, PhysicalParameters) else "dimensionless",
            "base_parameters": repr(base),
            "rtol": self.rtol,
            "atol": self.atol,
            "stickslip_version": package_version(),
            "Conventions": "CF-1.8",
        }

    def dataset(self, arrays: Mapping[str, npt.NDArray[Any]]) -> xr.Dataset:
        """Return the sweep's Dataset from its arrays (regime and status codes named)."""
        return _assemble(self, arrays)


@dataclass(frozen=True)
class _SweepTask:
    """One block of a sweep: the plan (without its grid) and the block's axes."""

    plan: SweepPlan
    axes: dict[str, FloatArray]

    def __call__(self) -> dict[str, FloatArray]:
        return self.plan.compute(self.axes)


def _unit_of(base: PhysicalParameters, name: str) -> str:
    """Return the SI unit of a swept parameter of a physical set-up ('' where dimensionless)."""
    allowed = axes(base)
    return allowed[name].parameter.unit if name in allowed else ""


def _run_chunks(
    kernel: Kernel,
    lp: FloatArray,
    nu: FloatArray,
    rtol: float,
    atol: float,
    max_slip_time: float,
    conv_tol: float,
    progress: ProgressLike,
    backend: str = "cpu",
) -> tuple[AttractorRows, FloatArray]:
    n = nu.shape[0]
    # the rows keep what the result and the polish read (12 of the engine's 21 numbers a
    # row): on a GPU only these cross back to the host, whose copies bound its speed
    parts: list[AttractorRows] = []
    mult = np.empty(n)
    # calls as large as the bound on one call's work, with a progress bar or without one (a
    # block of a job: the job's bar counts blocks): each call into run_attractors starts its
    # threads and ends waiting on the slowest of them. The bar moves as the engine's blocks
    # of rows finish inside a call, and counts a block at the end of each call.
    chunk = 20_000 if backend == "cpu" else 1 << 22  # a GPU launch wants many rows
    bounds = [*range(0, n, chunk), n]
    pairs = list(itertools.pairwise(bounds))
    bar = Progress(n, len(pairs), progress, desc="sweep") if progress is not False else None
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
            on_rows=None if bar is None else bar.advance,
            backend=backend,
            fields=POLISH_FIELDS,
        )
        # the slip-reversal orbits are measured again on the polished orbit: at the sweep's
        # tolerances, as cycle() does (they once ran at the defaults); the rows are this
        # call's own, polished where they are
        polished, mult[lo:hi] = polish_rows(
            (kernel, lp[lo:hi]), nu[lo:hi], rows, rtol=rtol, atol=atol, inplace=True
        )
        parts.append(polished)
        if bar is not None:
            bar.update(0)
    if bar is not None:
        bar.close()
    if not parts:
        return AttractorRows.empty(0, POLISH_FIELDS), mult
    return (parts[0] if len(parts) == 1 else AttractorRows.concat(parts)), mult


_VALUES = {
    "amplitude": ("amplitude", "force", "range of the spring force over one steady cycle"),
    "period": ("period", "time", "period of the steady oscillation"),
    "stick_time": ("stick_time", "time", "duration of the stick phase per cycle"),
    "stick_fraction": ("stick_fraction", "1", "fraction of the period at rest"),
    "slip_distance": ("slip_distance", "length", "distance slipped per cycle"),
    "peak_velocity": ("w_max", "velocity", "largest block velocity over the cycle"),
    "backward_slips": (
        "n_backward",
        "1",
        "backward slip phases per cycle (above 0 without a stick: slip-reversal, the velocity "
        "changes sign without sticking)",
    ),
}
_MULTIPLIER_ATTRS = {
    "units": "1",
    "long_name": "nontrivial Floquet multiplier of the attractor (0 stick-slip, NaN steady sliding)",
}
_REGIME_ATTRS = {
    "long_name": "regime reached from rest",
    "values": "stick-slip, pure-slip (never sticks, never slips backward), slip-reversal (never sticks, "
    "its velocity changes sign: backward_slips > 0), steady-sliding, unknown",
}
_STATUS_ATTRS = {"long_name": "ok, or why the point failed"}
_STABLE_ATTRS = {"long_name": "steady sliding linearly stable, f'(nu) > 0"}


def _variables(
    out: AttractorRows,
    mult: FloatArray,
    nu: FloatArray,
    law_nd: dict[str, FloatArray],
    scales: dict[str, FloatArray] | None,
    shape: tuple[int, ...],
    swept: tuple[str, ...],
) -> dict[str, Any]:
    """Return the result's arrays on a block of the grid (regime and status as integer codes)."""
    bad = ~out.ok
    period = out.period
    stick = out.stick_time
    steady = out.regime == Regime.STEADY_SLIDING.code
    with np.errstate(invalid="ignore", divide="ignore"):
        stick_fraction = np.where(steady, 0.0, stick / period)
    raw = {
        "amplitude": out.amplitude,
        "period": period,
        "stick_time": stick,
        "stick_fraction": stick_fraction,
        "slip_distance": np.where(steady, np.nan, nu * period),
        "w_max": out.w_max,
        "n_backward": np.asarray(out.n_backward, dtype=float),
    }
    data: dict[str, Any] = {}
    for key, (field_, kind, _) in _VALUES.items():
        v = raw[field_]
        if scales is not None and kind != "1":
            v = v * scales[kind]
        data[key] = np.where(bad, np.nan, v).reshape(shape)
    data["multiplier"] = np.where(bad, np.nan, mult).reshape(shape)
    regime = reversal(out.regime, out.n_backward)
    data["regime"] = np.where(bad, Regime.UNKNOWN.code, regime).astype(np.int8).reshape(shape)
    data["status"] = np.asarray(out.status).astype(np.int8).reshape(shape)
    data["steady_sliding_stable"] = (out.dfnu > 0.0).reshape(shape)
    if "nu" not in swept:
        data["nu"] = nu.reshape(shape)
    for key, v in law_nd.items():
        if key not in swept:
            data[key] = v.reshape(shape)
    return data


def _assemble(plan: SweepPlan, arrays: Mapping[str, Any]) -> xr.Dataset:
    dims = plan.coords_names
    data: dict[str, Any] = {}
    for v in plan.variables():
        a = arrays[v.name]
        attrs = {k: x for k, x in v.attrs.items() if k not in ("flag_values", "flag_meanings")}
        if v.name == "regime":
            a = labels(a, Regime)
        elif v.name == "status":
            a = labels(a, Status)
        data[v.name] = (dims, np.asarray(a), attrs)
    coord_vars = {
        name: (name, vals, {"units": unit or "1", "long_name": desc})
        for name, (vals, unit, desc) in plan.coords.items()
    }
    return xr.Dataset(data, coords=coord_vars, attrs=plan.attrs())


#: write a sweep's dataset: NetCDF, or a table for a ``.csv`` path (:func:`stickslip.io.netcdf.save_dataset`)
save_sweep = save_dataset


def load_sweep(path: str | os.PathLike[str], *, partial: bool = False) -> xr.Dataset:
    """Read a sweep written by :func:`save_sweep`, or a sweep's store, fully loaded.

    A store (``sweep(..., store=path)``) is returned as the sweep without a store
    returns it: ``regime`` and ``status`` as labels, the same attributes.

    Parameters
    ----------
    path : path
        A NetCDF file or a store.
    partial : bool, optional
        Read a store whose sweep was interrupted: the points not computed yet are
        NaN, their ``regime`` and ``status`` ``"not computed"``, a boolean
        ``computed`` variable says which are which, and the ``partial``
        attribute how many there are. (Without it such a store is an error:
        run the sweep's command again to finish it.)

    Raises
    ------
    ArgumentTypeError
        If ``path`` is not a str or a path.
    ValueError
        If the file does not exist or is not a NetCDF file, or the store holds
        another kind of job, or an unfinished sweep (without ``partial``).

    """
    if not isinstance(path, str | os.PathLike):  # os.path.exists(3) asks about file descriptor 3
        raise ArgumentTypeError(f"path={path!r} (type {type(path).__name__}): expected a file's path")
    from ..scale import is_store

    if os.path.exists(path) and is_store(path):
        return _load_store(path, partial)
    return load_dataset(path)


#: the label of a point a partly finished store does not hold yet (``load_sweep(partial=True)``)
NOT_COMPUTED = "not computed"


def _load_store(path: str | os.PathLike[str], partial: bool = False) -> xr.Dataset:
    import xarray as xr_
    import zarr

    from ..scale import StoreError, computed_points, damaged_coordinates, store_kind

    p = os.fspath(path)
    kind = store_kind(p)
    if kind != "sweep":
        raise StoreError(
            f"path={p!r}: a store of a {kind.replace('-', ' ')}, not of a sweep: read it with "
            "xarray.open_zarr(path), or run its command again (it reuses every finished block)"
        )
    ds = xr_.open_zarr(p, consolidated=True, chunks=None).load()
    ds.attrs.pop("stickslip_store", None)
    again = "run its command again, which computes the lost blocks again"
    lost = damaged_coordinates(p, {k: ds[k].values for k in ds.coords})
    if lost:
        raise StoreError(f"path={p!r}: its coordinates {', '.join(lost)} are damaged: {again}")
    codes = {name: ds[name].values for name in ("regime", "status")}
    fill = zarr.open_array(store=p, path="regime", mode="r").fill_value
    if int(fill) in {m.code for m in Regime}:  # a fill that is a regime's code (-1, unknown) hides
        done = computed_points(p)  # which points are there: the blocks' markers say it
    else:  # the fill is no regime's code: the data say which points are there
        done = codes["regime"] != fill
    n_done, n = int(done.sum()), done.size
    if n_done < n and not partial:
        raise StoreError(
            f"path={p!r}: the sweep in this store is unfinished ({n_done} of {n} points computed): "
            "run its command again to finish it, or read the points so far with "
            "load_sweep(path, partial=True)"
        )
    for name, enum in (("regime", Regime), ("status", Status)):
        valid = [m.code for m in enum]
        if not np.isin(codes[name][done], valid).all():
            raise StoreError(f"path={p!r}: {name} holds values that are no code (a damaged store): {again}")
        attrs = {k: x for k, x in ds[name].attrs.items() if k not in ("flag_values", "flag_meanings")}
        words = labels(np.where(done, codes[name], valid[0]), enum)
        if n_done < n:
            words = np.where(done, words, NOT_COMPUTED)
        ds[name] = (ds[name].dims, words, attrs)
    if partial:
        dims = ds["regime"].dims
        for name, var in ds.data_vars.items():
            if var.dtype.kind == "f" and var.dims == dims:
                ds[name] = var.where(done)
        ds["computed"] = (dims, done, {"long_name": "whether the point is computed yet (a partial store)"})
        ds.attrs["partial"] = f"{n_done} of {n} points computed" + (
            "" if n_done == n else ": the sweep was interrupted"
        )
    return ds
