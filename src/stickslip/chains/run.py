"""Simulate a chain: events streamed to a NetCDF catalogue, statistics on the way out."""

from __future__ import annotations

import contextlib
import json
import math
import os
import signal
import tempfile
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt
import xarray as xr

from .. import defaults
from ..core.api import ChainState, chain_advance, check_state
from ..core.chain_api import stuck_forces
from ..core.memory import check_memory
from ..core.results import ChainScalars, ChainStatus, EventRows
from ..dynamics.cycle import validate_tolerances
from ..errors import ArgumentTypeError
from ..io.errors import DataError
from ..io.output import check_target
from ..models.scales import unit_label
from ..scale.progress import progress_bar
from ..units import check_count, check_seed, parse_quantity
from ..userwarnings import warn
from .catalog import COLUMNS, KIND, RUPTURE_COLUMNS, CatalogWriter, open_catalog, read_state
from .model import Boundary, ChainParameters, Init, initial_positions, sliding_after
from .statistics import BValue, b_value, check_fit_range, connected_ruptures, ruptures_in_pieces

__all__ = ["ChainResult", "chain"]

#: work per call of the compiled engine, in units of ``chain.WORK_STEP`` plus the slipping
#: blocks per step: 190-290 ns a unit measured from 3 to 1000 blocks (2 cores, AMD EPYC),
#: so 0.4-0.6 s a call there. Progress, Ctrl-C and SIGTERM are answered between calls. A
#: fixed budget, not one from the clock: one command gives one catalogue, bit for bit (where
#: a call pauses moves the events' works in their last bits)
WORK_PER_CALL = 2e6
#: events per call
EVENTS_PER_CHUNK = 20_000
#: a chain warns when more than this share of its events (of at least PIECES_CHECKED checked)
#: are slips in separate places (:func:`~.statistics.ruptures_in_pieces`)
PIECES_SHARE = 0.1
PIECES_CHECKED = 20
#: what an event of the statistics is: ``whole``, the chain's event (from all stuck to all stuck), or
#: ``connected``, each connected run of slipping blocks in it (Carlson and Langer's event)
EVENTS_AS = ("whole", "connected")
#: with ``events_as="connected"`` every event's slips leave the engine (to be split into ruptures):
#: a call takes at most this many slip values, 4e6 doubles or 32 MB (4000 events of 1000 blocks)
SLIP_VALUES_PER_CALL = 4_000_000
#: a catalogue on disk takes the calls' rows and the state after them at most this often (s):
#: a write and its flush to disk took about 23 ms, 4 % of a run that wrote after every call
FLUSH_SECONDS = 5.0


@dataclass(frozen=True)
class ChainResult:
    """The outcome of :func:`chain`.

    Attributes
    ----------
    params : ChainParameters
        The set-up.
    catalog : xarray.Dataset
        The events (``t_start``, ``t_end``, ``epicentre``, ``n_blocks``,
        ``moment``, ``magnitude``, ``peak_velocity``, ...), lazily read from
        ``path`` when there is one.
    path : str or None
        The NetCDF catalogue, when written to disk.
    status : ChainStatus
        How the run ended.
    simulated_time : float
        Time reached (units of the catalogue: s for physical input).
    state : ChainState
        The final state (continue with ``chain(..., state=result.state)``).
    b : BValue
        Gutenberg-Richter fit of the magnitudes (see :func:`~.statistics.b_value`): of the
        events, or with ``events_as="connected"`` of their connected ruptures.
    units : dict
        Units of time, length, velocity and energy in the catalogue.
    events_as : {"whole", "connected"}
        What the statistics count as an event (see :func:`chain`).

    """

    params: ChainParameters
    catalog: xr.Dataset = field(repr=False)
    path: str | None
    status: ChainStatus
    simulated_time: float
    state: ChainState = field(repr=False)
    b: BValue
    units: dict[str, str] = field(default_factory=dict)
    events_as: str = "whole"

    @property
    def events(self) -> int:
        """Number of events in the catalogue."""
        return int(self.catalog.sizes["event"])

    @property
    def ruptures(self) -> int | None:
        """Number of connected ruptures in the catalogue (None where they were not kept)."""
        return int(self.catalog.sizes["rupture"]) if "rupture_moment" in self.catalog else None

    def magnitudes(self) -> npt.NDArray[np.float64]:
        """Return the magnitudes the statistics use, in time order: the events', or their ruptures'."""
        name = "rupture_magnitude" if self.events_as == "connected" else "magnitude"
        return np.asarray(self.catalog[name].values, dtype=float)

    def in_pieces(self) -> tuple[int, int]:
        """Return (events whose slips are separate pieces of the chain, events checked).

        See :func:`~.statistics.ruptures_in_pieces`: an event ends only when every block
        sticks, so on a long chain slips far apart are one event.
        """
        c = self.catalog
        slips = c["slip"].values if "slip" in c else None
        return ruptures_in_pieces(
            c["n_blocks"].values,
            c["first_block"].values,
            c["last_block"].values,
            slips,
            periodic=self.params.boundary == Boundary.PERIODIC,
        )

    def summary(self) -> dict[str, Any]:
        """Return the numbers of ``stickslip chain --json``."""
        t0 = self.catalog["t_start"].values
        moment = self.catalog["moment"].values
        nb = self.catalog["n_blocks"].values
        pieces, checked = self.in_pieces()
        connected = self.events_as == "connected"
        rupture_moment = self.catalog["rupture_moment"].values if connected else None
        return {
            "blocks": self.params.blocks,
            "events": self.events,
            # what the statistics (the b-value) count as an event, and how many of those there are
            "events_as": self.events_as,
            "ruptures": self.ruptures if connected else None,
            "simulated_time": self.simulated_time,
            "mean_recurrence": float(np.mean(np.diff(t0))) if t0.size > 1 else math.nan,
            "mean_moment": float(np.mean(moment)) if moment.size else math.nan,
            "largest_event_blocks": int(np.max(nb)) if nb.size else 0,
            # events whose slips are not one connected stretch (of those that could be checked)
            "events_in_pieces": pieces,
            "events_checked_for_pieces": checked,
            # with backward slip a moment (the blocks' slips, signed) can be <= 0: no magnitude
            "events_without_magnitude": int(np.count_nonzero(~(moment > 0))),
            "ruptures_without_magnitude": (
                int(np.count_nonzero(~(rupture_moment > 0))) if rupture_moment is not None else None
            ),
            "b_value": self.b.b,
            "b_value_err": self.b.error,
            "b_value_block": self.b.block,
            "completeness_magnitude": self.b.mc,
            "b_value_m_max": self.b.m_max if math.isfinite(self.b.m_max) else None,
            "b_value_range": self.b.method,
            "b_value_power_law": self.b.power_law,
            "b_value_lower": self.b.b_lower,
            "b_value_upper": self.b.b_upper,
            "b_value_split": self.b.m_split,
            "b_value_slope_p": self.b.slope_p,
            "b_value_upper_events": self.b.n_upper,
            "b_value_ks_p": self.b.ks_p,
            "b_value_span": self.b.span,
            "b_value_verdict": self.b.verdict,
            "status": str(self.status),
            "units": dict(self.units),
        }


def _units(params: ChainParameters) -> tuple[dict[str, str], dict[str, float], npt.NDArray[np.float64]]:
    """Units of the catalogue, the factor of each unit, and the factor of each column of the engine's rows."""
    names = ("time", "length", "velocity", "energy")
    factor = np.ones(len(EventRows.layout()))
    if params.scales is None:
        return dict.fromkeys(names, "1"), dict.fromkeys(names, 1.0), factor
    conv = {kind: params.scales.factor(kind) for kind in names}
    for _, (col, _, unit, _) in COLUMNS.items():
        if unit in conv:
            factor[col] = conv[unit]
    return {kind: unit_label(kind, physical=True) for kind in names}, conv, factor


def _setup(
    params: ChainParameters,
    init: str,
    seed: int | None,
    amplitude: float,
    rtol: float,
    atol: float,
    events_as: str = "whole",
) -> str:
    # atol is part of the set-up: a catalogue resumed at another atol would mix two tolerances
    # (a catalogue whose set-up lacks atol resumes with a warning). A catalogue of connected
    # ruptures says so (one of whole events, the default: nothing), so that a run is resumed with
    # the ruptures of every event or of none
    extra = {"events_as": events_as} if events_as != "whole" else {}
    return json.dumps(
        {
            **extra,
            "atol": atol,
            "blocks": params.blocks,
            "law": params.law.name,
            "law_params": params.law.params,
            "nu": params.nu,
            "ell": params.ell,
            "boundary": str(params.boundary),
            "backslip": params.backslip,
            "thresholds": None if params.thresholds is None else [float(p) for p in params.thresholds],
            "init": init,
            "seed": seed,
            "amplitude": amplitude,
            "rtol": rtol,
        },
        sort_keys=True,
    )


def _check_same_setup(path: str, saved: str, setup: str) -> None:
    """Refuse to resume the catalogue ``path`` unless it was made with ``setup``; say what differs."""
    if saved == setup:
        return
    try:
        old, new = json.loads(saved), json.loads(setup)
    except ValueError:
        old = None
    if not isinstance(old, dict):  # a damaged set-up attribute: unreadable, not a list of differences
        raise DataError(
            f"{path}: its set-up record is unreadable ({saved[:60]!r}): not a stickslip chain "
            "catalogue, or a damaged one; start again without resume, or remove the file"
        )
    differ = sorted(str(k) for k in old.keys() | new.keys() if old.get(k) != new.get(k))
    if differ == ["atol"] and "atol" not in old:
        # a set-up without atol: at the default, or, a member of an ensemble, at the store's own
        # tolerances (its identity holds them)
        warn(
            f"{path}: written before its atol was recorded; resumed assuming atol={new['atol']!r}",
        )
        return
    if "init" in differ and "state" in (old.get("init"), new.get("init")):
        how = (
            "from a given state (state=)" if old.get("init") == "state" else f"with init={old.get('init')!r}"
        )
        raise DataError(f"{path}: the run was started {how}; resume it the same way")
    raise DataError(
        f"{path}: made with another set-up ({'; '.join(_difference(k, old, new) for k in differ)}); "
        "resume needs the same set-up"
    )


def _difference(key: str, old: dict[str, Any], new: dict[str, Any]) -> str:
    """One differing setting, with both values: 'ell 10 in the file, 11 now' (not the name alone)."""
    was, now = old.get(key), new.get(key)
    if isinstance(was, dict) and isinstance(now, dict):  # the law's parameters: the ones that differ
        return "; ".join(
            _difference(k, was, now) for k in sorted(was.keys() | now.keys()) if was.get(k) != now.get(k)
        )

    def shown(x: Any) -> str:
        return "not set" if x is None else (f"{x:g}" if isinstance(x, float) else str(x))

    return f"{key} {shown(was)} in the file, {shown(now)} now"


def check_events(events: Any, transient: Any) -> tuple[int, int]:
    """Return ``events`` (>= 1) and ``transient`` (>= 0) as ints, or a ValueError naming the one at fault."""
    return (
        check_count(events, "events", what="a whole number of events"),
        check_count(transient, "transient", minimum=0, what="a whole number of events"),
    )


def _duration(name: str, value: Any, params: ChainParameters) -> float:
    """Return a time in units of ``sqrt(m/k_p)``: from a number, or (a physical chain) a time with units."""
    if isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool):
        if params.scales is not None and math.isfinite(value):
            # the catalogue is in seconds: a bare 50 read as 50 sqrt(m/k_p) could come out as 10 s
            unit = params.scales.factor("time")
            raise ArgumentTypeError(
                f"{name}={value!r}: a physical chain takes a time with units, e.g. '{value:g} s' (a "
                f"number would be in units of sqrt(m/k_p) = {unit:.4g} s, its output is in s)"
            )
        return float(value)
    if params.scales is None:
        raise ArgumentTypeError(
            f"{name}={value!r}: a dimensionless chain takes a number (units of sqrt(m/k_p))"
        )
    q = parse_quantity(value, name, "[time]", "10 s")
    return float(params.scales.from_si("time", q))


def check_events_as(events_as: Any) -> None:
    """Check what an event of the statistics is: ``"whole"`` or ``"connected"``.

    Raises
    ------
    ArgumentTypeError
        For a value that is not a str.
    ValueError
        For another str.

    """
    expected = (
        f"events_as={events_as!r}: expected 'whole' (an event from all blocks stuck to all stuck) or "
        "'connected' (each connected run of slipping blocks in it)"
    )
    if not isinstance(events_as, str):
        raise ArgumentTypeError(expected)
    if events_as not in EVENTS_AS:
        raise ValueError(expected)


def chain(
    params: ChainParameters,
    events: int,
    *,
    init: Init | str = Init.RANDOM,
    seed: int | None = 0,
    amplitude: float = 0.01,
    state: ChainState | None = None,
    transient: int = 0,
    out: str | os.PathLike[str] | None = None,
    resume: bool = False,
    overwrite: bool = False,
    record_slip: int = 2000,
    t_max: float = math.inf,
    rtol: float = defaults.RTOL,
    atol: float = defaults.ATOL,
    mc: float | str | None = "auto",
    m_max: float | None = None,
    max_event_duration: float | None = None,
    progress: bool | None = None,
    events_as: str = "whole",
) -> ChainResult:
    """Simulate a chain of blocks event by event, exactly (stick in closed form for every block).

    Parameters
    ----------
    params : ChainParameters
        The chain.
    events : int
        Events to record (an event: from a breakaway while all blocks stick to
        the moment all stick again).
    init : {"random", "uniform"}
        Blocks at rest at seeded random positions in ``[0, amplitude)`` (units
        of ``F_s/k_p``), or all at the same position.
    seed : int, optional
        Seed of the initial positions.
    amplitude : float
        Range of the random initial positions (units of ``F_s/k_p``).
    state : ChainState, optional
        Start from this state instead (e.g. ``result.state`` of an earlier run).
    transient : int
        Events simulated first and not recorded.
    out : path, optional
        Stream the catalogue to this NetCDF file (nothing held in memory);
        default: in memory.
    resume : bool
        Continue the catalogue ``out`` of an interrupted run of the same set-up
        (tolerances included, and ``state`` where it was started from one), from
        the state saved in it; where ``out`` does not exist, start it.
    overwrite : bool
        Replace ``out`` where it exists and is not a chain catalogue stickslip wrote
        (default: refuse, with a :class:`~stickslip.io.errors.ForeignFileError`).
    record_slip : int
        Keep each block's slip for this many first events (space-time diagram).
    t_max : float or time
        Stop at this time if the events are not complete: a number (units of
        ``sqrt(m/k_p)``) for a dimensionless chain, a time with units (e.g. ``"2 s"``)
        for a physical one.
    rtol, atol : float
        Tolerances of the slip integration.
    mc : float or "auto", optional
        Lower magnitude of the b-value fit. Default ``"auto"``: both ends of the
        range that is a power law (:func:`~.statistics.power_law_range`: the lower
        end by the least Kolmogorov-Smirnov distance, as Clauset, Shalizi and
        Newman choose it; the widest range that passes KS by parametric bootstrap
        and one slope against two at 10 %, its events spread over a magnitude unit
        at least; a chain's catalogue has a spike of one-block events below it and
        a bump of chain-wide ruptures above it). Where no range passes, ``b`` is nan:
        not a power law over a decade of moment (``result.b.verdict`` says why). The
        range depends on the catalogue's size where the slope drifts: fix it to
        compare catalogues. None: the completeness magnitude by maximum curvature,
        no upper end unless ``m_max``.
    m_max : float, optional
        Upper magnitude of the b-value fit.
    max_event_duration : float or time, optional
        An event longer than this (units of ``sqrt(m/k_p)``, or a time with units
        for a physical chain) ends the run with
        status ``sliding``: the blocks never all stick again. Default
        ``1000 / nu + 1000``, a thousand loading times.
    progress : bool, optional
        Progress bar on events (default: on a terminal).
    events_as : {"whole", "connected"}
        What an event of the statistics (b-value, magnitude-frequency) is. ``"whole"``
        (default): the catalogue's event, from all blocks stuck to all stuck again; on a
        long chain slips in separate places, unrelated ruptures, fall into one such event
        and their moments add. ``"connected"``: each connected run of neighbouring blocks
        that slipped in an event is an event of its own, with its own moment and block
        count (Carlson and Langer's definition; :func:`~.statistics.connected_ruptures`);
        the catalogue then keeps them (``rupture_*`` variables, ``rupture_magnitude``),
        and every event's slips pass through memory, a call at most
        :data:`SLIP_VALUES_PER_CALL` values. The events themselves are the same.

    Returns
    -------
    ChainResult

    Raises
    ------
    TypeError
        For an argument of the wrong type, named (:class:`~stickslip.ArgumentTypeError`).
    ValueError
        For an argument of the right type with a wrong value, named.

    """
    if not isinstance(params, ChainParameters):
        raise ArgumentTypeError(f"params={params!r}: expected ChainParameters")
    if out is not None and not isinstance(out, str | os.PathLike):
        raise ArgumentTypeError(f"out={out!r} (type {type(out).__name__}): expected a file's path")
    events, transient = check_events(events, transient)
    seed = check_seed(seed)
    rtol, atol = validate_tolerances(rtol, atol)
    record_slip = check_count(record_slip, "record_slip", minimum=0)
    if resume and out is None:
        raise ValueError("resume=True needs out (the catalogue of the interrupted run to continue)")
    if out is None:  # the catalogue in memory: its rows, and their copy into the result's Dataset
        check_memory(
            3.0 * 8 * len(COLUMNS) * events,
            f"events={events} held in memory",
            "stream them to a file (out=, --out)",
        )
    t_max = _duration("t_max", t_max, params)
    if not (t_max > 0):
        raise ValueError(f"t_max={t_max!r}: expected a positive time")
    mc, m_max = check_fit_range(mc, m_max)  # before the run, not after it
    check_events_as(events_as)
    connected = events_as == "connected"
    if not isinstance(init, str):
        raise ArgumentTypeError(f"init={init!r}: expected 'uniform' or 'random'")
    try:
        init_s = str(Init(init)) if state is None else "state"
    except ValueError:
        raise ValueError(f"init={init!r}: expected 'uniform' or 'random'") from None
    n = params.blocks
    kernel = params.law.kernel
    lp = params.law.core_params()
    units, scale, factor = _units(params)
    setup = _setup(params, init_s, seed, amplitude, rtol, atol, events_as)
    attrs = {"setup": setup, "blocks": n, "law": params.law.name, "nu": params.nu, "ell": params.ell}
    longest = (
        sliding_after(params)
        if max_event_duration is None
        else _duration("max_event_duration", max_event_duration, params)
    )
    if not longest > 0:
        raise ValueError(f"max_event_duration={max_event_duration!r}: expected a positive duration")
    path = None if out is None else os.fspath(out)
    done = 0
    st: ChainState | None = None
    if path is not None and resume and os.path.exists(path):
        st, done, fattrs = read_state(path)
        saved = str(fattrs.get("setup"))
        _check_same_setup(path, saved, setup)
        # st None: stopped before its first save (in the transient, or its first seconds): begin again
    if st is not None and path is not None:
        resumed = CatalogWriter(path, n, {**attrs, "setup": saved}, units, resume=True)
        resumed.ds.setncattr("setup", setup)  # an older set-up (no atol) takes the full one
        writer: CatalogWriter | None = resumed
        transient = 0
        state = st
    else:
        if state is None:
            state = ChainState.at_rest(initial_positions(n, init, seed, amplitude))
            _warn_stiff_start(params, state)
        elif not isinstance(state, ChainState):
            raise TypeError(f"state={state!r}: expected a ChainState (a result's .state)")
        else:
            state = state.copy()
        if state.x.shape != (n,):
            raise ValueError(f"state: expected {n} blocks, got {state.x.shape[0]}")
        check_state(state)  # before the catalogue is made
        if path is None:
            writer = None
        else:
            folder = os.path.dirname(os.path.abspath(path))
            if not os.path.isdir(folder):
                raise ValueError(f"out={path!r}: the folder {folder} does not exist")
            check_target(path, KIND, overwrite=bool(overwrite))  # never over a file that is not ours
            writer = CatalogWriter(path, n, attrs, units, slip_rows=record_slip, ruptures=connected)
    phi = params.phi
    args = (
        kernel,
        lp,
        params.nu,
        params.ell2,
        str(params.boundary) == "periodic",
        bool(params.backslip),
        phi,
    )
    rows_mem: list[npt.NDArray[np.float64]] = []
    slips_mem: list[npt.NDArray[np.float64]] = []
    ruptures_mem: list[dict[str, npt.NDArray[Any]]] = []
    periodic = params.boundary == Boundary.PERIODIC
    per_call = max(1, min(EVENTS_PER_CHUNK, SLIP_VALUES_PER_CALL // n)) if connected else EVENTS_PER_CHUNK
    n_slips = writer.slip_recorded if writer is not None else 0
    pending = None if writer is None else _Pending(writer)
    status = ChainStatus.OK
    ended = False
    bar = progress_bar(events, unit="event", desc="chain", progress=progress)
    advance = _Advance(args, state, t_max, rtol, atol, bar, scale["time"], units["time"], longest)
    if bar is not None and done:
        bar.update(done)
    try:
        # the transient: events not recorded
        left = int(transient)
        while left > 0:
            cat, _, code = advance(min(left, EVENTS_PER_CHUNK), 0)
            left -= cat.shape[0]
            advance.show(f"transient {transient - left}/{transient}, ")
            if ChainStatus.from_code(code) not in (ChainStatus.OK, ChainStatus.PAUSED):
                status = ChainStatus.from_code(code)
                break
            if ChainScalars(state.sc).event_longer_than(longest):
                status = ChainStatus.SLIDING
                break
        while status is ChainStatus.OK and done < events:
            want_slips = max(0, record_slip - n_slips)
            chunk = min(events - done, per_call)
            cat, slips, code = advance(chunk, chunk if connected else want_slips)
            cat = cat * factor
            slips = slips * scale["length"]
            rup = _ruptures(slips, done, periodic) if connected else None
            slips = slips[:want_slips]
            if pending is not None:
                pending.add(cat, slips, state, rup)
            else:
                rows_mem.append(cat)
                if slips.shape[0]:
                    slips_mem.append(slips)
                if rup is not None:
                    ruptures_mem.append(rup)
            n_slips += slips.shape[0]
            done += cat.shape[0]
            if bar is not None:
                bar.update(cat.shape[0])
            advance.show()
            if ChainStatus.from_code(code) not in (ChainStatus.OK, ChainStatus.PAUSED):
                status = ChainStatus.from_code(code)
            elif ChainScalars(state.sc).event_longer_than(longest):
                status = ChainStatus.SLIDING
        ended = True  # not stopped by an exception (a Ctrl-C): the catalogue may be complete
    finally:
        if bar is not None:
            bar.close()
        if pending is not None:
            flushed = False
            try:
                pending.flush()
                flushed = True
            finally:  # complete only if every row and the state after them are written
                pending.writer.close(complete=ended and flushed and status is ChainStatus.OK)
    t_end = state.t * scale["time"]
    if writer is not None and path is not None:
        ds = open_catalog(path)
    else:
        ds = _in_memory(rows_mem, slips_mem, n, attrs, units, ruptures_mem if connected else None)
    mags = ds["rupture_magnitude" if connected else "magnitude"].values
    fit = b_value(mags, mc=mc, m_max=m_max, block="auto")  # in time order: blocks of events
    # the law's own word where the motion failed or went beyond its range (a measured table
    # whose extrapolation reaches zero friction), as `cycle` gives it: a table's chain can end
    # not-finite after 2 events, and the status alone does not say why
    failed = status in (ChainStatus.NONFINITE, ChainStatus.STEP_TOO_SMALL)
    peaks = np.append(ds["peak_velocity"].values / scale["velocity"], np.abs(state.v))
    note = params.law.motion_warning(peaks, failed)
    if note:
        warn(f"chain: {note}", UserWarning)
    result = ChainResult(params, ds, path, status, float(t_end), state, fit, units, events_as)
    pieces, checked = result.in_pieces()
    if not connected and checked >= PIECES_CHECKED and pieces > PIECES_SHARE * checked:
        warn(
            f"chain: {pieces} of {checked} events slipped in separate pieces of the chain (blocks "
            "that never slipped between blocks that did), one event because the chain was never all "
            "stuck between them: where the pieces are unrelated ruptures their moments add, and the "
            "magnitudes and the b-value are not those of single ruptures (Carlson and Langer count "
            "connected clusters); events_in_pieces in the summary; events_as='connected' "
            "(stickslip chain --events-as connected) counts each piece as an event of its own"
        )
    return result


def _ruptures(slips: npt.NDArray[np.float64], before: int, periodic: bool) -> dict[str, npt.NDArray[Any]]:
    """Return the connected ruptures of a call's events (all slips kept), numbered after ``before`` events."""
    r = connected_ruptures(slips, periodic=periodic)
    return {
        "rupture_event": r.event + before,
        "rupture_first_block": r.first_block,
        "rupture_last_block": r.last_block,
        "rupture_n_blocks": r.n_blocks,
        "rupture_moment": r.moment,
    }


def _joined(parts: list[dict[str, npt.NDArray[Any]]]) -> dict[str, npt.NDArray[Any]]:
    """Return the ruptures of several calls as one set of columns."""
    return {
        name: np.concatenate([p[name] for p in parts]) if parts else np.zeros(0, dtype=dtype)
        for name, (dtype, _, _) in RUPTURE_COLUMNS.items()
    }


#: coupling force over static threshold at the start above which :func:`chain` warns
STIFF_START = 1e4


def _warn_stiff_start(params: ChainParameters, state: ChainState) -> None:
    """Warn where the initial displacements load the coupling springs far past the thresholds.

    The first event then rings at the coupling's frequency ``ell`` for a long time
    (measured on 10 blocks, ``c = 3``, amplitude 0.01: ``ell = 1000``, 2 s;
    ``ell = 3000``, 40 s; ``ell = 10^4``, minutes), with no event to show for it.
    """
    x, periodic = state.x, str(params.boundary) == "periodic"
    if x.shape[0] < 2:
        return
    force = stuck_forces(state, params.nu, params.ell2, periodic)
    load = float(np.max(np.abs(force) / params.phi))
    if load > STIFF_START:
        warn(
            f"the initial displacements load the coupling springs to {load:.3g} times the static "
            f"threshold (ell = {params.ell:g}): the first event will ring for a long time; give a "
            f"smaller amplitude (about 1/ell**2 = {1 / params.ell2:.2g}) or init='uniform'",
        )


@contextlib.contextmanager
def _signals_deferred() -> Iterator[None]:
    """Hold Ctrl-C and SIGTERM over a block; deliver them, to the handlers of before, on leaving.

    A signal between a chunk's rows and its state (or inside either) would close a
    catalogue whose rows run ahead of its state: resumed, it would simulate those events
    again (duplicated rows). Only in the main thread, where Python runs its handlers.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []
    before: dict[int, Any] = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        handler = signal.getsignal(sig)
        if handler is not None:  # None: a handler not set from Python, left alone
            before[sig] = handler
            signal.signal(sig, lambda signum, frame: held.append(signum))
    try:
        yield
    finally:
        for number, handler in before.items():
            signal.signal(number, handler)
        for number in dict.fromkeys(held):
            signal.raise_signal(number)


class _Pending:
    """The rows of the calls not yet written, and the state after the last of them.

    Written together (signals held) at most every :data:`FLUSH_SECONDS`, and when the
    run ends, however it ends: the file always holds rows and a state that agree, so a
    killed run resumes without a duplicated or a missing event (``kill -9`` loses at
    most the last few seconds). Each call's rows and the copy of the state after it are
    taken together too: a Ctrl-C between a call and this copy loses that call's rows
    and keeps the state before it.
    """

    def __init__(self, writer: CatalogWriter) -> None:
        self.writer = writer
        self.rows: list[npt.NDArray[np.float64]] = []
        self.slips: list[npt.NDArray[np.float64]] = []
        self.ruptures: list[dict[str, npt.NDArray[Any]]] = []
        self.state: ChainState | None = None
        self.last = time.monotonic()

    def add(
        self,
        rows: npt.NDArray[np.float64],
        slips: npt.NDArray[np.float64],
        state: ChainState,
        ruptures: dict[str, npt.NDArray[Any]] | None = None,
    ) -> None:
        with _signals_deferred():
            self.rows.append(rows)
            self.slips.append(slips)
            if ruptures is not None:
                self.ruptures.append(ruptures)
            self.state = state.copy()
        if time.monotonic() - self.last >= FLUSH_SECONDS:
            self.flush()

    def flush(self) -> None:
        """Write the rows and the state after them (nothing if no call since the last flush)."""
        if self.state is None:
            return
        with _signals_deferred():  # rows and state together, or neither
            rows, slips = np.concatenate(self.rows), np.concatenate(self.slips)
            if self.writer.ruptures:
                self.writer.append(rows, slips, _joined(self.ruptures))
            else:
                self.writer.append(rows, slips)
            self.writer.save_state(self.state)
            self.rows.clear()
            self.slips.clear()
            self.ruptures.clear()
            self.state = None
        self.last = time.monotonic()


class _Advance:
    """Calls of the compiled engine, each :data:`WORK_PER_CALL` units of work.

    A step of ``m`` slipping blocks counts ``chain.WORK_STEP + m`` (a budget in steps
    lasts seconds in a rupture of thousands of blocks, microseconds on three). The
    progress bar shows the simulated time after each call (and the transient's events,
    which it does not count), so that a run with few events (a stiff chain, a long
    event, the transient) still shows that it advances.
    """

    def __init__(
        self,
        args: tuple[Any, Any, float, float, bool, bool, Any],
        state: ChainState,
        t_max: float,
        rtol: float,
        atol: float,
        bar: Any,
        time_factor: float,
        time_unit: str,
        longest: float,
    ) -> None:
        self.args, self.state, self.t_max, self.rtol, self.atol = args, state, t_max, rtol, atol
        self.bar, self.time_factor, self.time_unit = bar, time_factor, time_unit
        self.longest = longest

    def __call__(
        self, max_events: int, slip_rows: int
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], int]:
        return chain_advance(
            *self.args, self.state, max_events=max_events, t_max=self.t_max, rtol=self.rtol,
            atol=self.atol, max_work=WORK_PER_CALL, max_event_duration=self.longest, slip_rows=slip_rows,
        )  # fmt: skip

    def show(self, note: str = "") -> None:
        """Show the simulated time (after ``note``) on the progress bar, if there is one."""
        if self.bar is not None:
            t = self.state.t * self.time_factor
            unit = "" if self.time_unit == "1" else f" {self.time_unit}"
            self.bar.set_postfix_str(f"{note}t = {t:.4g}{unit}", refresh=True)


def _in_memory(
    rows: list[npt.NDArray[np.float64]],
    slips: list[npt.NDArray[np.float64]],
    n: int,
    attrs: dict[str, Any],
    units: dict[str, str],
    ruptures: list[dict[str, npt.NDArray[Any]]] | None = None,
) -> xr.Dataset:
    """Return the catalogue as a Dataset, through the same NetCDF writer (one code path for both)."""
    fd, tmp = tempfile.mkstemp(suffix=".nc")
    os.close(fd)
    try:
        allrows = np.concatenate(rows) if rows else np.zeros((0, len(EventRows.layout())))
        allslips = np.concatenate(slips) if slips else np.zeros((0, n))
        w = CatalogWriter(tmp, n, attrs, units, slip_rows=allslips.shape[0], ruptures=ruptures is not None)
        if ruptures is None:
            w.append(allrows, allslips)
        else:
            w.append(allrows, allslips, _joined(ruptures))
        w.close(complete=True)
        ds = open_catalog(tmp).load()
        ds.close()
    finally:
        os.remove(tmp)
    return ds
