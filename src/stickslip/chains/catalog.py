"""Event catalogues on disk: NetCDF written event by event, and read back with xarray.

A catalogue is a NetCDF file with an unlimited ``event`` dimension; rows are
appended as the chain produces them, so a catalogue of millions of events never
sits in memory. With the rows (every few seconds, and when the run stops) the file
also takes the chain's exact state after them (``state_*`` variables) and is
flushed: a run that is killed can be continued from its last write
(:func:`stickslip.chains.chain` with ``resume=True``), and gives the same catalogue
as an uninterrupted run.

A catalogue of a run with ``events_as="connected"`` also holds its events' connected
ruptures (:func:`~.statistics.connected_ruptures`), on a ``rupture`` dimension of their own
(:data:`RUPTURE_COLUMNS`), appended with the events they belong to.

The state records how many events precede it (``events_saved``, ``slip_saved``
for the per-block slips and ``ruptures_saved`` for the ruptures). HDF5 may write
appended rows before the state that follows them (its caches, a full disk, a kill
during the flush): such rows are not part of
the catalogue; a resumed run writes over them (the same events, computed again), and
:func:`open_catalog` leaves them out.
"""

from __future__ import annotations

import os
from typing import Any

import netCDF4
import numpy as np
import numpy.typing as npt
import xarray as xr

from ..core.api import ChainState
from ..core.results import ChainScalars, EventRows
from ..io.errors import DataError
from ..io.output import generator

__all__ = ["COLUMNS", "RUPTURE_COLUMNS", "CatalogWriter", "open_catalog", "read_state"]

KIND = "chain-catalog"

_DESCRIBED: dict[str, tuple[str, str, str]] = {
    "t_start": ("f8", "time", "start of the event: a block breaks away while all stick"),
    "t_end": ("f8", "time", "end of the event: all blocks stick again"),
    "epicentre": ("i4", "1", "the block that broke away first (0-based)"),
    "n_blocks": ("i4", "1", "number of blocks that slipped"),
    "moment": ("f8", "length", "sum of the blocks' slips during the event"),
    "peak_velocity": ("f8", "velocity", "largest block speed during the event"),
    "first_block": ("i4", "1", "lowest index of a block that slipped"),
    "last_block": ("i4", "1", "highest index of a block that slipped"),
    "driver_work": ("f8", "energy", "work of the driver on the loading springs"),
    "friction_work": ("f8", "energy", "energy dissipated by friction"),
    "elastic_change": ("f8", "energy", "change of the springs' elastic energy"),
}
#: the catalogue's variables, each a field of the engine's rows (:class:`~stickslip.core.results.EventRows`):
#: (its column in the rows, dtype, units, description)
COLUMNS: dict[str, tuple[int, str, str, str]] = {
    name: (EventRows.layout()[name], *described) for name, described in _DESCRIBED.items()
}
#: the ruptures' variables (``events_as="connected"``): (dtype, units, description)
RUPTURE_COLUMNS: dict[str, tuple[str, str, str]] = {
    "rupture_event": ("i8", "1", "the event (0-based row of the catalogue) the rupture belongs to"),
    "rupture_first_block": ("i4", "1", "first block of the connected run of slipping blocks (0-based)"),
    "rupture_last_block": ("i4", "1", "its last block (below the first: across the ends of a ring)"),
    "rupture_n_blocks": ("i4", "1", "number of blocks that slipped in the rupture"),
    "rupture_moment": ("f8", "length", "sum of the rupture's blocks' slips"),
}
_STATE = ("x", "v", "mode", "sc", "ev_x0", "ev_flag", "ev_list")


class CatalogWriter:
    """Append events to a NetCDF catalogue and keep the chain's state in it.

    Parameters
    ----------
    path : str
        The file, created (or, with ``resume``, opened to continue).
    blocks : int
        Number of blocks.
    attrs : mapping
        Global attributes: the set-up (compared on resume).
    units : mapping
        Unit of ``time``, ``length``, ``velocity`` and ``energy`` (``"1"`` when dimensionless).
    slip_rows : int
        How many events' per-block slips to keep (``slip(recorded_event, block)``, for the
        space-time diagram).
    ruptures : bool
        Keep the events' connected ruptures too (``rupture_*`` variables on a ``rupture``
        dimension; a resumed catalogue keeps them where it has them).

    """

    def __init__(
        self,
        path: str,
        blocks: int,
        attrs: dict[str, Any],
        units: dict[str, str],
        slip_rows: int = 0,
        *,
        resume: bool = False,
        ruptures: bool = False,
    ) -> None:
        self.path = path
        if resume:
            try:
                self.ds = netCDF4.Dataset(path, "a")
            except OSError as exc:
                raise OSError(
                    f"{path}: cannot open the catalogue to continue it ({exc}); is it open elsewhere?"
                ) from None
            setup = self.ds.getncattr("setup")
            if setup != attrs["setup"]:
                self.ds.close()
                raise DataError(
                    f"{path}: this catalogue was made with another set-up; resuming needs the same "
                    "command (or write to a new file)"
                )
            # complete again only when this run finishes (close(True))
            self.ds.setncattr("complete", 0)
            # continue after the rows the saved state follows: rows written after it (flushed
            # by HDF5 before the state was) are computed again and written over
            self._next = _saved_count(self.ds, "events_saved", len(self.ds.dimensions["event"]))
            self._slips = _saved_count(self.ds, "slip_saved", int(self.ds.getncattr("slip_recorded")))
            self.ruptures = "rupture" in self.ds.dimensions
            self._ruptures = (
                _saved_count(self.ds, "ruptures_saved", len(self.ds.dimensions["rupture"]))
                if self.ruptures
                else 0
            )
            return
        self._next = 0
        self._slips = 0
        self._ruptures = 0
        self.ruptures = bool(ruptures)
        ds = netCDF4.Dataset(path, "w", format="NETCDF4")
        self.ds = ds
        ds.createDimension("event", None)
        ds.createDimension("block", blocks)
        ds.createDimension("recorded_event", slip_rows)
        ds.createDimension("scalar", ChainScalars.SIZE)
        for name, (_, dtype, unit, desc) in COLUMNS.items():
            var = ds.createVariable(name, dtype, ("event",), zlib=True, complevel=1, chunksizes=(65536,))
            var.units = units.get(unit, unit)
            var.long_name = desc
        # rows not (yet) recorded read as NaN in any NetCDF reader, not the default fill 9.97e36
        slip_dims = ("recorded_event", "block")
        ds.createVariable("slip", "f8", slip_dims, zlib=True, complevel=1, fill_value=np.nan)
        ds["slip"].units = units["length"]
        ds["slip"].long_name = "slip of each block in the first recorded events"
        if self.ruptures:
            ds.createDimension("rupture", None)
            for name, (dtype, unit, desc) in RUPTURE_COLUMNS.items():
                var = ds.createVariable(
                    name, dtype, ("rupture",), zlib=True, complevel=1, chunksizes=(65536,)
                )
                var.units = units.get(unit, unit)
                var.long_name = desc
        for name in _STATE:
            dims = ("scalar",) if name == "sc" else ("block",)
            dtype = {"mode": "i8", "ev_flag": "i1", "ev_list": "i8"}.get(name, "f8")
            ds.createVariable(f"state_{name}", dtype, dims)
        ds.setncatts({k: v for k, v in attrs.items()})
        ds.setncattr("stickslip_output", KIND)
        ds.setncattr("stickslip_generator", generator(KIND))
        ds.setncattr("complete", 0)
        ds.setncattr("slip_recorded", 0)
        # no state yet: a run killed before its first save (its transient, its first seconds)
        # starts again on resuming; synced now, so that the file is a readable NetCDF from the start
        ds.setncattr("state_saved", 0)
        ds.setncattr("events_saved", 0)
        ds.setncattr("slip_saved", 0)
        if self.ruptures:
            ds.setncattr("ruptures_saved", 0)
        ds.sync()

    @property
    def n_events(self) -> int:
        """Events written so far by this writer (a resumed one: from the saved state on)."""
        return self._next

    @property
    def slip_recorded(self) -> int:
        """Events whose per-block slips are stored."""
        return self._slips

    @property
    def n_ruptures(self) -> int:
        """Ruptures written so far (0 in a catalogue without them)."""
        return self._ruptures

    def append(
        self,
        rows: npt.NDArray[np.float64],
        slips: npt.NDArray[np.float64],
        ruptures: dict[str, npt.NDArray[Any]] | None = None,
    ) -> None:
        """Append the engine's rows (:class:`~stickslip.core.results.EventRows`), first slips, ruptures.

        ``ruptures``: the :data:`RUPTURE_COLUMNS` of the rows' ruptures (their events numbered
        in the whole catalogue); required where the catalogue keeps ruptures.
        """
        if self.ruptures and ruptures is None:
            raise ValueError(
                f"{self.path}: a catalogue of connected ruptures needs the ruptures of its events"
            )
        if self.ruptures and ruptures is not None:
            r = self._ruptures
            m = ruptures["rupture_moment"].shape[0]
            if m:
                for name, (dtype, _, _) in RUPTURE_COLUMNS.items():
                    self.ds[name][r : r + m] = ruptures[name].astype(dtype)
            self._ruptures = r + m
        k = self._next
        m = rows.shape[0]
        if m:
            for name, (col, dtype, _, _) in COLUMNS.items():
                data = rows[:, col]
                self.ds[name][k : k + m] = data.astype(np.int32) if dtype == "i4" else data
        self._next = k + m
        r = self._slips
        take = min(slips.shape[0], len(self.ds.dimensions["recorded_event"]) - r)
        if take > 0:
            self.ds["slip"][r : r + take, :] = slips[:take]
            self._slips = r + take

    def save_state(self, state: ChainState, extra: dict[str, Any] | None = None) -> None:
        """Store the chain's state (exact) and the counts of rows before it; flush the file to disk."""
        for name in _STATE:
            self.ds[f"state_{name}"][:] = getattr(state, name)
        for k, v in (extra or {}).items():
            self.ds.setncattr(k, v)
        self._mark_saved()
        self.ds.setncattr("state_saved", 1)
        self.ds.sync()

    def _mark_saved(self) -> None:
        if self.ruptures:
            self.ds.setncattr("ruptures_saved", self._ruptures)
        self.ds.setncattr("events_saved", self._next)
        self.ds.setncattr("slip_saved", self._slips)
        self.ds.setncattr("slip_recorded", self._slips)

    def close(self, complete: bool) -> None:
        """Mark the catalogue complete (or not) and close it.

        Complete means every row is written, and the state after them where one is kept.
        """
        if complete:
            self._mark_saved()
            self.ds.setncattr("complete", 1)
        self.ds.close()


def _saved_count(ds: netCDF4.Dataset, name: str, written: int) -> int:
    """Return the count ``name`` stored with the state (older catalogues: ``written``)."""
    if name not in ds.ncattrs():
        return written
    return min(int(ds.getncattr(name)), written)


def read_state(path: str) -> tuple[ChainState | None, int, dict[str, Any]]:
    """Return the state stored in a catalogue, its number of events and its attributes.

    The state is None where the run was stopped before it saved one (no event
    recorded then): a resumed run starts from the beginning.
    """
    try:
        with netCDF4.Dataset(path, "r") as ds:
            if ds.__dict__.get("stickslip_output") != KIND:
                raise DataError(f"no stickslip_output = {KIND!r}")
            raw = [ds[f"state_{n}"][:] for n in _STATE]
            n = _saved_count(ds, "events_saved", len(ds.dimensions["event"]))
            attrs = {k: ds.getncattr(k) for k in ds.ncattrs()}
    except PermissionError:
        raise  # not damaged: not ours to read (said as a file error)
    except (OSError, RuntimeError, KeyError, IndexError, ValueError, DataError) as exc:
        # a foreign NetCDF ends in 'IndexError: state_x not found in /', a truncated one in
        # 'NetCDF: HDF error': both said as a catalogue that cannot be resumed
        raise DataError(
            f"{path}: cannot be resumed: not a stickslip chain catalogue, or a damaged one ({exc}); "
            "run without resume to start again (with --overwrite), or remove the file"
        ) from None
    # a catalogue without "state_saved" whose state was never written reads as netCDF fill values.
    # Rows without a state (written by HDF5 before the first state was): computed again
    if not attrs.get("state_saved", 1) or any(np.ma.is_masked(a) for a in raw):
        return None, 0, attrs
    arrays = [np.asarray(a) for a in raw]
    if arrays[3].shape != (ChainScalars.SIZE,):
        raise DataError(
            f"{path}: its state was stored by another version of stickslip's chain engine "
            f"({arrays[3].shape[0]} scalars, expected {ChainScalars.SIZE}): it cannot be resumed; start the "
            "run again"
        )
    state = ChainState(
        arrays[0].astype(np.float64), arrays[1].astype(np.float64), arrays[2].astype(np.int64),
        arrays[3].astype(np.float64), arrays[4].astype(np.float64), arrays[5].astype(np.int8),
        arrays[6].astype(np.int64),
    )  # fmt: skip
    return state, n, attrs


def open_catalog(path: str | os.PathLike[str]) -> xr.Dataset:
    """Open a catalogue with xarray (lazily: a variable is read when used), with ``magnitude`` added.

    Raises
    ------
    DataError
        When the file is not a stickslip chain catalogue.

    """
    p = os.fspath(path)
    try:
        ds = xr.open_dataset(p, engine="netcdf4")
    except (OSError, ValueError) as exc:
        raise DataError(f"{p}: cannot read a NetCDF catalogue ({exc})") from None
    if ds.attrs.get("stickslip_output") != KIND:
        ds.close()
        raise DataError(f"{p}: not a stickslip chain catalogue (no stickslip_output = {KIND!r})")
    opened = ds
    ds = ds.drop_vars([f"state_{n}" for n in _STATE])
    saved = ds.attrs.get("events_saved")
    if saved is not None and int(saved) < ds.sizes["event"]:
        # rows written after the last saved state (a run stopped during a flush): not yet events
        ds = ds.isel(event=slice(0, int(saved)))
    # the slips of the events recorded so far: the dimension is made for record_slip rows
    # (2000 by default), and the rows beyond them were never written
    recorded = int(ds.attrs.get("slip_saved", ds.attrs.get("slip_recorded", 0)))
    ds = ds.isel(recorded_event=slice(0, min(recorded, ds.sizes["recorded_event"])))
    if "rupture" in ds.dims:  # ruptures written after the last saved state: not yet in the catalogue
        kept = int(ds.attrs.get("ruptures_saved", ds.sizes["rupture"]))
        ds = ds.isel(rupture=slice(0, min(kept, ds.sizes["rupture"])))
    ds.set_close(opened.close)  # closing the result closes the file
    if "moment" not in ds:
        ds.close()
        raise DataError(f"{p}: a chain catalogue without its 'moment' variable: damaged, or not stickslip's")
    ds["magnitude"] = np.log10(ds["moment"].where(ds["moment"] > 0))
    unit = str(ds["moment"].attrs.get("units", "1"))
    per = "its dimensionless unit" if unit in ("1", "") else f"1 {unit}"  # a physical chain's is in m
    ds["magnitude"].attrs = {"units": "1", "long_name": f"log10 of the moment / ({per})"}
    if "rupture_moment" in ds:
        ds["rupture_magnitude"] = np.log10(ds["rupture_moment"].where(ds["rupture_moment"] > 0))
        ds["rupture_magnitude"].attrs = {
            "units": "1",
            "long_name": f"log10 of the rupture's moment / ({per})",
        }
    return ds
