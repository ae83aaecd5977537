"""A two-parameter diagram as an xarray Dataset (NetCDF, CF attributes) and back to its parts.

Layout of :func:`diagram_dataset`:

- ``region(y, x)``: the region of each raster cell (``-1`` on a curve), with
  ``region_attractors(region_index)`` and ``region_regime(region_index)`` naming each;
- the curves, all in one dimension ``curve_point``: ``curve_x``, ``curve_y`` (axis units),
  ``curve_nu`` and ``curve_id``; per ``curve``: ``curve_kind`` and ``curve_ends``;
- the codimension-2 points along ``special``: ``special_kind``, ``special_x``,
  ``special_y``, ``special_nu``, ``special_value`` and ``special_coefficient``;
- attributes: the plane (``plane``), the axes' names, units and scales, and the notes.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["diagram_dataset"]


def diagram_dataset(diagram: Any) -> Any:
    """Return ``diagram`` (a :class:`~.diagram.Diagram`) as an :class:`xarray.Dataset`."""
    import xarray as xr

    pl = diagram.plane
    ax, ay = pl.x, pl.y
    cx = np.concatenate([c.x for c in diagram.curves]) if diagram.curves else np.empty(0)
    cy = np.concatenate([c.y for c in diagram.curves]) if diagram.curves else np.empty(0)
    cnu = np.concatenate([c.data["nu"] for c in diagram.curves]) if diagram.curves else np.empty(0)
    cid: Any = (
        np.concatenate([np.full(len(c.x), i) for i, c in enumerate(diagram.curves)]) if diagram.curves else []
    )
    pts = diagram.points

    def attrs(a: Any, what: str) -> dict[str, Any]:
        return {
            "long_name": f"{a.name} ({what})",
            "units": a.unit,
            "axis_scale": "log" if a.log else "linear",
        }

    ds = xr.Dataset(
        {
            "region": (
                ("y", "x"),
                diagram.region.astype(np.int32),
                {
                    "long_name": "region of the plane (index into region_attractors; -1 on a curve)",
                    "_FillValue": -2,
                },
            ),
            "region_attractors": (
                ("region_index",),
                np.array(diagram.region_names, dtype=str),
                {"long_name": "attractors of the region, joined by +"},
            ),
            "region_regime": (
                ("region_index",),
                np.array(diagram.region_regime, dtype=str),
                {"long_name": "regime of the region"},
            ),
            "curve_x": (("curve_point",), cx, attrs(ax, "along the curves")),
            "curve_y": (("curve_point",), cy, attrs(ay, "along the curves")),
            "curve_nu": (
                ("curve_point",),
                cnu,
                {"long_name": "dimensionless driving velocity beta*v0", "units": "1"},
            ),
            "curve_id": (
                ("curve_point",),
                np.asarray(cid, dtype=np.int32),
                {"long_name": "index into curve"},
            ),
            "curve_kind": (
                ("curve",),
                np.array([c.kind for c in diagram.curves], dtype=str),
                {"long_name": "hopf, fold (of cycles) or grazing"},
            ),
            "curve_ends": (
                ("curve",),
                np.array([" ".join(c.ends) for c in diagram.curves], dtype=str),
                {"long_name": "why each end of the curve stopped"},
            ),
            "special_kind": (
                ("special",),
                np.array([p.kind for p in pts], dtype=str),
                {"long_name": "codimension-2 point: bautin, fold-grazing, cusp, end"},
            ),
            "special_x": (
                ("special",),
                np.array([p.x for p in pts], dtype=float),
                attrs(ax, "special points"),
            ),
            "special_y": (
                ("special",),
                np.array([p.y for p in pts], dtype=float),
                attrs(ay, "special points"),
            ),
            "special_nu": (
                ("special",),
                np.array([p.nu for p in pts], dtype=float),
                {"long_name": "dimensionless driving velocity beta*v0", "units": "1"},
            ),
            "special_value": (
                ("special",),
                np.array([p.value for p in pts], dtype=float),
                {"long_name": "the coefficient that decides the point's type"},
            ),
            "special_coefficient": (
                ("special",),
                np.array([p.coefficient for p in pts], dtype=str),
                {"long_name": "what special_value is"},
            ),
        },
        coords={
            "x": (("x",), diagram.raster_x, {"long_name": ax.name, "units": ax.unit}),
            "y": (("y",), diagram.raster_y, {"long_name": ay.name, "units": ay.unit}),
        },
        attrs={
            "title": f"two-parameter bifurcation diagram: {pl.describe}",
            "plane": pl.describe,
            "x_name": ax.name,
            "y_name": ay.name,
            "x_scale": "log" if ax.log else "linear",
            "y_scale": "log" if ay.log else "linear",
            "x_range": [ax.lo, ax.hi],
            "y_range": [ay.lo, ay.hi],
            "notes": "\n".join(diagram.notes),
            "Conventions": "CF-1.8",
        },
    )
    return ds
