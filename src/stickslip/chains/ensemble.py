"""Ensembles of chains: many seeds of one set-up, each member's statistics, on Dask and in a store.

One member is one :func:`~.run.chain` run: its seed sets the initial positions
and, with ``threshold_spread``, the static thresholds. The ensemble's result is a
Dataset over ``seed`` of each member's numbers (events, recurrence, moment,
b-value, status). With a store, each member's catalogue is streamed to
``STORE/catalogs/seed-S.nc`` and the member's numbers written to the store when
it finishes; a killed run resumes, members half done continuing their catalogue
from its saved state.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import xarray as xr

from .. import defaults
from ..core.results import ChainStatus
from ..dynamics.cycle import validate_tolerances
from ..errors import ArgumentTypeError
from ..scale.progress import ProgressLike
from ..scale.store import Block, Layout, Variable
from ..units import check_count, check_number
from ..userwarnings import warn
from .catalog import read_state
from .model import ChainParameters, Init, static_thresholds
from .run import chain, check_events, check_events_as
from .statistics import STATISTICS_VERSION, check_fit_range

__all__ = ["EnsembleJob", "chain_ensemble"]

#: the largest seed of a member (the store's seed coordinate is int64)
_SEED_MAX = 2**63 - 1
#: members of one ensemble at most (a block of its store each)
MAX_MEMBERS = 1_000_000

#: each member's numbers: name -> (dtype, long name); "status" as ChainStatus codes
_FIELDS: dict[str, tuple[str, str]] = {
    "events": ("int64", "events recorded"),
    "simulated_time": ("float64", "time reached"),
    "mean_recurrence": ("float64", "mean time between event starts"),
    "mean_moment": ("float64", "mean moment (sum of the blocks' slips) per event"),
    "largest_event_blocks": ("int64", "blocks that slipped in the largest event"),
    "b_value": ("float64", "Gutenberg-Richter b-value (Aki-Utsu maximum likelihood)"),
    "b_value_err": ("float64", "b-value standard error (block bootstrap)"),
    "completeness_magnitude": ("float64", "lower magnitude of the b-value fit (its power-law range)"),
    "b_value_m_max": ("float64", "upper magnitude of the b-value fit (nan: none)"),
    "status": ("int8", "how the run ended"),
}


def chain_ensemble(
    params: ChainParameters,
    events: int,
    seeds: Sequence[int],
    *,
    threshold_spread: float = 0.0,
    init: str = "random",
    amplitude: float = 0.01,
    transient: int = 0,
    rtol: float = defaults.RTOL,
    atol: float = defaults.ATOL,
    mc: float | str | None = "auto",
    m_max: float | None = None,
    store: str | os.PathLike[str] | None = None,
    scheduler: Any = None,
    workers: int | None = None,
    progress: ProgressLike = None,
    events_as: str = "whole",
) -> xr.Dataset:
    """Run one chain per seed; return each member's statistics over a ``seed`` dimension.

    Parameters
    ----------
    params : ChainParameters
        The set-up shared by every member (its thresholds are replaced by each
        seed's when ``threshold_spread`` > 0).
    events : int
        Events recorded per member.
    seeds : sequence of int
        One member per seed (initial positions and thresholds).
    threshold_spread : float
        Heterogeneous thresholds ``1 + s U(-1, 1)`` drawn with each member's seed.
    init, amplitude, transient, rtol, atol
        As in :func:`~.run.chain`.
    mc, m_max : optional
        The range of every member's b-value fit, as in :func:`~.run.chain`
        (default: each member's own power-law range). A range fixed for all
        compares the members over the same magnitudes; each member's own
        range adds the choice of the range to the spread of b.
    store : path, optional
        Zarr store of the members' numbers, with each member's catalogue in
        ``catalogs/``; resumable.
    scheduler, workers : optional
        Run the members on a Dask cluster or a ``LocalCluster`` (see
        :func:`stickslip.dynamics.sweep`).
    progress : bool or callable, optional
        Progress over members.
    events_as : {"whole", "connected"}
        What an event of each member's statistics is, as in :func:`~.run.chain`.

    Returns
    -------
    xarray.Dataset
        Variables ``events``, ``simulated_time``, ``mean_recurrence``,
        ``mean_moment``, ``largest_event_blocks``, ``b_value``, ``b_value_err``,
        ``completeness_magnitude``, ``status`` (codes, named in ``flag_meanings``),
        over ``seed``.

    """
    if not isinstance(params, ChainParameters):
        raise ArgumentTypeError(f"params={params!r}: expected ChainParameters")
    if isinstance(seeds, str) or not isinstance(seeds, Sequence | np.ndarray | range):
        raise ArgumentTypeError(f"seeds={seeds!r}: expected a sequence of whole numbers")
    # whole numbers, checked: seeds=[1.7, 2.2] would run the members of seeds 1 and 2
    if len(seeds) > MAX_MEMBERS:  # range(10**12), checked seed by seed, would take minutes
        raise ValueError(f"seeds: {len(seeds)} members; expected at most {MAX_MEMBERS} in one ensemble")
    what = "a whole-number seed"
    checked = [check_count(s, f"seeds[{i}]", minimum=0, what=what) for i, s in enumerate(seeds)]
    too_big = next((i for i, s in enumerate(checked) if s > _SEED_MAX), None)
    if too_big is not None:  # the store's coordinate is int64
        raise ValueError(f"seeds[{too_big}]={checked[too_big]!r}: expected a whole-number seed <= 2**63 - 1")
    seed_arr = np.array(checked, dtype=np.int64)
    # before the store is made: events=2.7 would run 2 events, and events=0 fail in a member
    events, transient = check_events(events, transient)
    rtol, atol = validate_tolerances(rtol, atol)
    if not isinstance(init, str):
        raise ArgumentTypeError(f"init={init!r}: expected 'uniform' or 'random'")
    try:
        init = str(Init(init))
    except ValueError:
        raise ValueError(f"init={init!r}: expected 'uniform' or 'random'") from None
    if init == Init.RANDOM:  # as chain(): uniform positions take no amplitude (it stays in the identity)
        amplitude = check_number(amplitude, "amplitude", what="a positive displacement amplitude")
    else:
        try:
            amplitude = float(amplitude)
        except (TypeError, ValueError):
            raise ArgumentTypeError(f"amplitude={amplitude!r}: expected a number") from None
    if seed_arr.size == 0 or np.unique(seed_arr).size != seed_arr.size:
        raise ValueError(f"seeds={seeds!r}: expected at least one seed, each once")
    static_thresholds(params.blocks, threshold_spread, 0)  # checks the spread
    mc, m_max = check_fit_range(mc, m_max)
    check_events_as(events_as)
    catalogs = None if store is None else os.path.join(os.path.abspath(os.fspath(store)), "catalogs")
    job = EnsembleJob(params, int(events), seed_arr, float(threshold_spread), str(init), float(amplitude),
                      int(transient), float(rtol), float(atol), catalogs, mc, m_max, events_as)  # fmt: skip
    from ..scale import run_job

    return run_job(job, job.layout(), store=store, scheduler=scheduler, workers=workers, progress=progress,
                   desc="ensemble")  # fmt: skip


@dataclass(frozen=True)
class EnsembleJob:
    """An ensemble cut into members (one per block)."""

    params: ChainParameters
    events: int
    seeds: npt.NDArray[np.int64]
    threshold_spread: float
    init: str
    amplitude: float
    transient: int
    rtol: float
    atol: float
    catalogs: str | None
    mc: float | str | None = "auto"
    m_max: float | None = None
    events_as: str = "whole"

    def task(self, block: Block) -> _Member:
        """Return the computation of one member."""
        return _Member(self, int(self.seeds[block.slices[0]][0]))

    def layout(self) -> Layout:
        """Return the store's layout: one block per seed."""
        variables = [
            Variable(k, ("seed",), dtype, {"long_name": desc, **self._units(k)})
            for k, (dtype, desc) in _FIELDS.items()
        ]
        status = variables[-1]
        variables[-1] = dataclasses.replace(
            status,
            attrs={
                **status.attrs,
                "flag_values": [m.code for m in ChainStatus],
                "flag_meanings": " ".join(m.value for m in ChainStatus),
            },
        )
        p = self.params
        return Layout(
            kind="chain-ensemble",
            dims=("seed",),
            shape=(self.seeds.size,),
            chunks=(1,),
            coords={"seed": (("seed",), self.seeds, {"long_name": "seed of the member"})},
            variables=tuple(variables),
            identity={
                "params": repr(p),
                "thresholds": p.thresholds if p.thresholds is not None else "uniform",
                "seeds": self.seeds,
                "run": [self.events, self.threshold_spread, self.init, self.amplitude, self.transient],
                # seeded thresholds are drawn from a stream of their own (stream 2), apart from the
                # initial positions' draws: stores of another stream are another job
                **({"threshold_stream": 2} if self.threshold_spread > 0 else {}),
                "tolerances": [self.rtol, self.atol],
                # a store of members' b-values from other statistics is another job: resuming
                # it would mix the two (STATISTICS_VERSION says how the range and error of b are made)
                "statistics": STATISTICS_VERSION,
                "fit": [self.mc, self.m_max],
                # members of connected ruptures are another job (whole events, the default: unsaid)
                **({"events_as": self.events_as} if self.events_as != "whole" else {}),
            },
            attrs=self._attrs(),
            describe=(
                f"an ensemble of {self.seeds.size} chains of {p.blocks} blocks ({p.law.name} law, "
                f"nu={p.nu:g}, ell={p.ell:g}), {self.events} events each, "
                f"b-values by the statistics of version {STATISTICS_VERSION}"
            ),
        )

    def _units(self, name: str) -> dict[str, str]:
        time = "s" if self.params.scales is not None else "sqrt(m/k_p)"
        length = "m" if self.params.scales is not None else "F_s/k_p"
        return {"simulated_time": {"units": time}, "mean_recurrence": {"units": time},
                "mean_moment": {"units": length}}.get(name, {})  # fmt: skip

    def _attrs(self) -> dict[str, Any]:
        p = self.params
        return {
            "title": "stickslip chain ensemble: one chain per seed",
            "law": p.law.name,
            "blocks": p.blocks,
            "nu": p.nu,
            "ell": p.ell,
            "boundary": str(p.boundary),
            "events_per_member": self.events,
            "threshold_spread": self.threshold_spread,
            "b_value_fit": self._fit(),
            "events_as": self.events_as,
        }

    def _fit(self) -> str:
        """Return the range of the members' b-value fits, in words (an attribute of the dataset)."""
        of = " of connected ruptures" if self.events_as == "connected" else ""
        if self.mc == "auto":
            top = "" if self.m_max is None else f" below {self.m_max:g}"
            return f"each member's power-law range{top}{of}"
        low = "maximum curvature" if self.mc is None else f"{self.mc:g}"
        return f"from {low}" + ("" if self.m_max is None else f" to {self.m_max:g}") + of

    def dataset(self, arrays: dict[str, Any]) -> xr.Dataset:
        """Return the ensemble's Dataset from its arrays."""
        layout = self.layout()
        data = {v.name: (v.dims, arrays[v.name], dict(v.attrs)) for v in layout.variables}
        return xr.Dataset(data, coords={"seed": ("seed", self.seeds, {"long_name": "seed of the member"})},
                          attrs=self._attrs())  # fmt: skip


@dataclass(frozen=True)
class _Member:
    """One member of an ensemble: what one task runs."""

    job: EnsembleJob
    seed: int

    def __call__(self) -> dict[str, Any]:
        job = self.job
        p = job.params
        phi = static_thresholds(p.blocks, job.threshold_spread, self.seed)
        if phi is not None:
            p = dataclasses.replace(p, thresholds=phi)
        out = None
        with contextlib.ExitStack() as held:
            if job.catalogs is not None:
                os.makedirs(job.catalogs, exist_ok=True)
                out = os.path.join(job.catalogs, f"seed-{self.seed}.nc")
                # two runs of one ensemble (sharing its store) take a member in turn: the second
                # finds the catalogue complete, and never takes the first's open file for a broken one
                held.enter_context(_member_lock(out))
                _drop_if_unreadable(out)
            return self._run(p, out)

    def _run(self, p: ChainParameters, out: str | None) -> dict[str, Any]:
        job = self.job
        res = chain(
            p, job.events, init=job.init, seed=self.seed, amplitude=job.amplitude, transient=job.transient,
            out=out, resume=out is not None, rtol=job.rtol, atol=job.atol, mc=job.mc, m_max=job.m_max,
            progress=False, events_as=job.events_as,
        )  # fmt: skip
        s = res.summary()
        res.catalog.close()
        row: dict[str, Any] = {}
        for k, (dtype, _) in _FIELDS.items():
            v = ChainStatus.from_label(s[k]).code if k == "status" else s[k]
            if dtype == "float64" and v is None:
                v = math.nan
            row[k] = np.array([v], dtype=dtype)
        return row


def _drop_if_unreadable(path: str) -> None:
    """Remove a member's catalogue that cannot be continued, so that the member starts again.

    The store's own file (its identity, checked, says it is this job's): a catalogue
    truncated by a full disk or a copy, or one holding events without the state after
    them, made the member fail on every run ("NetCDF: HDF error") and the store could
    never finish. A member is deterministic: run again, it gives the same numbers.
    """
    if not os.path.exists(path):
        return
    try:
        read_state(path)
    except PermissionError:
        raise  # not broken: not ours to read (said as a file error)
    except (OSError, RuntimeError, KeyError, IndexError, ValueError) as exc:
        warn(f"{path}: cannot be continued ({exc}); its member starts again")
        os.remove(path)


@contextlib.contextmanager
def _member_lock(catalog: str) -> Iterator[None]:
    """Hold a lock on ``.CATALOG.lock`` beside it (waiting for another run's), where the OS has locks."""
    try:
        import fcntl
    except ImportError:  # not POSIX: no lock (one run at a time per store)
        yield
        return
    folder, name = os.path.split(catalog)
    with open(os.path.join(folder, f".{name}.lock"), "a") as f:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f.fileno(), fcntl.LOCK_UN)
