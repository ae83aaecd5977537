"""A two-parameter diagram checked by brute force: the engine on a grid of the plane.

At the centre of each cell of an ``nx x ny`` grid, the exact engine runs from rest and
from two pushes off steady sliding (the one-parameter analysis' probes), each attractor it
settles on is polished into its orbit, and steady sliding is added where ``f' > 0``: the
set of attractors found there. It is compared with the set that names the diagram's region
at that point. Cells within one grid step of a curve are left out (the side of a curve a
cell centre is on is the curve's business, and transients crawl next to a Hopf point or a
fold); of the others, the share that agrees is the check's score, and each disagreement
is listed with the nearest curve and a reason.

The rows run on all cores or on a Dask cluster like any other job
(:func:`stickslip.scale.run_job`), into memory or into a Zarr store that an interrupted
check resumes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.results import Regime
from ..scale.progress import ProgressLike, show_progress
from ..scale.store import Block, Layout, Variable
from .diagram import Diagram
from .planes import Plane, check_positive_int

__all__ = ["DiagramCheck", "check_diagram"]

#: the kinds of attractor, each counted in two bits of a cell's code (at most 3 of a kind)
KINDS = (Regime.STICK_SLIP, Regime.SLIP_REVERSAL, Regime.PURE_SLIP, Regime.STEADY_SLIDING, Regime.UNKNOWN)


def encode(names: str) -> int:
    """Return the code of a set of attractors written ``a + b + ...`` (``-1`` for none given)."""
    parts = [p.strip() for p in names.split("+") if p.strip()]
    code = 0
    for k, kind in enumerate(KINDS):
        code += min(parts.count(str(kind)), 3) << (2 * k)
    return code


def decode(code: int) -> str:
    """Return the attractors of a code as ``a + b + ...``."""
    out = []
    for k, kind in enumerate(KINDS):
        out += [str(kind)] * ((int(code) >> (2 * k)) & 3)
    return " + ".join(out) if out else "none"


@dataclass(frozen=True)
class DiagramCheck:
    """The diagram against the engine on a grid.

    Attributes
    ----------
    x, y : ndarray
        Cell centres (axis units).
    expected, found : ndarray of int, shape (ny, nx)
        Codes of the attractor sets (:func:`decode`): the diagram's and the engine's.
    near : ndarray of bool
        Cells not scored: within one grid step of a curve, or in a region the diagram leaves
        undetermined (``expected`` is -2 there: it makes no claim).
    agree : float
        Share of the scored cells where both sets are the same.
    disagree : list of dict
        Each scored cell that differs: ``x``, ``y``, ``expected``, ``found``, ``nearest``
        (the kind of the nearest curve), ``steps`` (its distance in grid steps), ``why``.

    """

    x: np.ndarray
    y: np.ndarray
    expected: np.ndarray
    found: np.ndarray
    near: np.ndarray
    agree: float
    disagree: list[dict[str, Any]]

    @property
    def scored(self) -> int:
        """Cells compared (not next to a curve)."""
        return int((~self.near).sum())

    def report(self) -> str:
        """Return the check in words: the score and each disagreement."""
        open_cells = int((self.expected == -2).sum())
        lines = [
            f"brute-force check: {self.found.size} cells, {self.scored} scored "
            "(not within one grid step of a "
            f"curve); the engine's attractors agree with the diagram in {100 * self.agree:.2f} %"
        ]
        if open_cells:
            lines.append(
                f"  {open_cells} cells lie in regions the diagram leaves undetermined (a boundary it does "
                "not continue crosses them): not scored"
            )
        for d in self.disagree:
            lines.append(
                f"  ({d['x']:.6g}, {d['y']:.6g}): diagram {d['expected']}, engine {d['found']}; "
                "nearest curve "
                f"{d['nearest']} at {d['steps']:.2f} steps: {d['why']}"
            )
        return "\n".join(lines)

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready summary."""
        return {
            "cells": int(self.found.size),
            "scored": self.scored,
            "agree": self.agree,
            "disagree": self.disagree,
        }


def _distance(diagram: Diagram, u: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """Distance (unit square) from each point ``u`` (shape (n, 2)) to the nearest curve, and its kind."""
    best = np.full(len(u), np.inf)
    kind = ["-"] * len(u)
    for c in diagram.curves:
        if len(c.u) < 2:
            continue
        a, b = c.u[:-1], c.u[1:]
        d = b - a
        dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        for i, p in enumerate(u):
            t = np.clip(np.einsum("ij,ij->i", p - a, d) / dd, 0.0, 1.0)
            m = float(np.min(np.linalg.norm(a + t[:, None] * d - p, axis=1)))
            if m < best[i]:
                best[i], kind[i] = m, c.kind
    return best, kind


@dataclass(frozen=True)
class CheckJob:
    """The brute-force grid cut into rows (one row of constant ``y`` per block)."""

    plane: Plane
    nx: int
    ny: int

    @property
    def u(self) -> tuple[np.ndarray, np.ndarray]:
        """Cell centres in the unit square, along x and along y."""
        return (np.arange(self.nx) + 0.5) / self.nx, (np.arange(self.ny) + 0.5) / self.ny

    def task(self, block: Block) -> Any:
        """Return the computation of one block of rows."""
        return _Rows(self, block.slices[0])

    def layout(self) -> Layout:
        """Return the store's layout: rows of ``(y, x)``."""
        ux, uy = self.u
        xs, ys = self.plane.values(np.stack([ux, ux], axis=-1))
        _, ys = self.plane.values(np.stack([uy, uy], axis=-1))
        return Layout(
            kind="diagram-check",
            dims=("y", "x"),
            shape=(self.ny, self.nx),
            chunks=(1, self.nx),
            coords={
                "x": (("x",), np.asarray(xs), {"long_name": self.plane.x.name, "units": self.plane.x.unit}),
                "y": (("y",), np.asarray(ys), {"long_name": self.plane.y.name, "units": self.plane.y.unit}),
            },
            variables=(Variable("found", ("y", "x"), "int64", {"long_name": "attractors the engine finds"}),),
            identity={
                "plane": self.plane.describe,
                "x": [self.plane.x.lo, self.plane.x.hi],
                "y": [self.plane.y.lo, self.plane.y.hi],
                "grid": [self.nx, self.ny],
            },
            attrs={},
            describe=f"a brute-force check of {self.plane.describe} on {self.nx} x {self.ny} cells",
        )

    def dataset(self, arrays: dict[str, Any]) -> Any:
        """Return the grid's Dataset."""
        import xarray as xr

        layout = self.layout()
        coords = {k: (d, v, dict(a)) for k, (d, v, a) in layout.coords.items()}
        return xr.Dataset({"found": (("y", "x"), arrays["found"])}, coords=coords)


@dataclass(frozen=True)
class _Rows:
    job: CheckJob
    rows: slice

    def __call__(self) -> dict[str, Any]:
        from .probes import _attractor_sets

        job = self.job
        ux, uy = job.u
        sel = uy[self.rows]
        out = np.empty((sel.size, job.nx), dtype=np.int64)
        for i, v in enumerate(sel):
            groups: dict[tuple[float, ...], list[tuple[int, float]]] = {}
            laws = {}
            for j, w in enumerate(ux):
                p = job.plane.at((w, v))
                groups.setdefault(p.values, []).append((j, p.nu))
                if p.values not in laws:
                    laws[p.values] = job.plane.law_at((w, v))[1]
            for vals, cells in groups.items():
                nus = np.array([c[1] for c in cells])
                sets = _attractor_sets(laws[vals], nus, [])
                for (j, _), s in zip(cells, sets, strict=True):
                    out[i, j] = encode(" + ".join(str(a) for a in s))
        return {"found": out}


def check_diagram(
    diagram: Diagram,
    grid: tuple[int, int] = (40, 40),
    *,
    progress: ProgressLike = None,
    store: Any = None,
    scheduler: Any = None,
    workers: int | None = None,
) -> DiagramCheck:
    """Check ``diagram`` by direct simulation on a grid of the plane.

    Parameters
    ----------
    diagram : Diagram
        From :func:`~.diagram.two_parameter_diagram` (with its regions labelled).
    grid : (int, int)
        Cells along x and along y.
    progress, store, scheduler, workers : optional
        As for :func:`stickslip.regime_map`: a progress bar, a Zarr store to resume, a Dask
        cluster or ``workers`` local processes.

    Returns
    -------
    DiagramCheck

    """
    from ..errors import ArgumentTypeError

    if not isinstance(diagram, Diagram):
        raise ArgumentTypeError(f"diagram={diagram!r}: expected a Diagram (two_parameter_diagram)")
    if not isinstance(diagram.plane, Plane):
        raise ValueError(
            f"diagram of {diagram.plane.describe}: the brute-force check runs the one-block engine; "
            "this diagram's model is not the one-block model"
        )
    try:
        nx, ny = grid
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"grid={grid!r}: expected (nx, ny), two integers from 2 to 2000") from None
    nx = check_positive_int(nx, "grid[0]", 2, 2000)
    ny = check_positive_int(ny, "grid[1]", 2, 2000)
    job = CheckJob(diagram.plane, nx, ny)
    from ..scale import run_job

    show: ProgressLike = progress
    if progress is None:
        show = show_progress(None) and ny > 4
    ds = run_job(
        job,
        job.layout(),
        store=store,
        scheduler=scheduler,
        workers=workers,
        progress=show,
        desc="brute-force check",
    )
    found = np.asarray(ds["found"].values, dtype=np.int64)
    ux, uy = job.u
    uu = np.stack(np.meshgrid(ux, uy), axis=-1).reshape(-1, 2)
    dist, nearest = _distance(diagram, uu)
    step = max(1.0 / nx, 1.0 / ny)
    near = (dist < step).reshape(ny, nx)
    n = diagram.region.shape[0]
    ri = np.clip((uu[:, 1] * n).astype(int), 0, n - 1)
    rj = np.clip((uu[:, 0] * n).astype(int), 0, n - 1)
    reg = diagram.region[ri, rj]
    # -1: on a curve's wall; -2: a region the diagram leaves undetermined (it makes no claim there)
    expected = np.array(
        [
            (-2 if diagram.region_names[r].startswith("undetermined") else encode(diagram.region_names[r]))
            if r >= 0
            else -1
            for r in reg
        ],
        dtype=np.int64,
    ).reshape(ny, nx)
    near |= expected < 0
    xs, ys = np.asarray(ds["x"].values), np.asarray(ds["y"].values)
    disagree = []
    bad = (~near) & (expected != found)
    for i, j in np.argwhere(bad):
        k = i * nx + j
        f = decode(found[i, j])
        why = (
            "the engine could not follow the motion from one of its starts"
            if "unknown" in f
            else "the region's set differs: a curve between this cell and the region's labelled point is "
            "missing or misplaced, or an attractor of small basin was missed by the three starts"
        )
        disagree.append(
            {
                "x": float(xs[j]),
                "y": float(ys[i]),
                "expected": decode(expected[i, j]),
                "found": f,
                "nearest": nearest[k],
                "steps": float(dist[k] / step),
                "why": why,
            }
        )
    scored = int((~near).sum())
    agree = 1.0 - len(disagree) / scored if scored else math.nan
    return DiagramCheck(xs, ys, expected, found, near, agree, disagree)
