"""Benchmark: a two-parameter diagram against a grid of one-parameter runs at the same boundary resolution.

Work: the weakening law ``f(w) = 1/(1 + c w) + p w``, ``p = 0.5``, over ``nu`` in
[0.05, 2] (a logarithmic axis) and ``c`` in [2, 20] (a linear axis): its Hopf curve
``nu_H(c) = (sqrt(c/p) - 1)/c`` and its grazing curve (the stick-slip orbit's onset).

* The diagram: ``two_parameter_diagram(plane, raster=200)``, with and without the
  labelling of its regions (``label=False``). Its curves are continued by
  pseudo-arclength with steps of at most ``step`` (0.02 of the unit square), each point
  exact (Newton to 1e-10); between points a curve is the straight segment of the unit
  square, ``u = (log(nu/0.05)/log 40, (c - 2)/18)``. Its resolution is the largest
  distance, in the unit square, from the exact curves to its polylines: from the closed
  form ``nu_H(c)`` on 20001 values of ``c``, and from the grazing ``nu`` that
  ``regime_map`` locates (to 1e-9) on rows at the diagram's grazing points and midway
  (in ``c``) between them, where a chord strays furthest.
* Today's grid: ``regime_map(law, "c", values, 0.05, 2.0)`` (one ``regimes`` run of 201
  ``nu`` points per ``c`` value, in process), whose boundary between two rows is a
  staircase: its resolution is half the row spacing in the unit square,
  ``1/(2 (N - 1))`` for ``N`` rows. ``N`` is chosen so that it equals the diagram's
  resolution; ``--rows`` evenly spaced rows are timed and the time scaled linearly per
  row to ``N`` (the output says when that is an extrapolation). For
  reference, the rows needed if the rows' Hopf points were joined by straight segments
  instead (closed form, the same unit-square distance).

A small call of each comes first, so that compilation and the loading of the kernel
cache are not timed. The machine is shared: a diagram's time is the shortest of
``--repeat`` calls (with and without labelling alternated), the even rows' map the
shortest of ``--repeat-map``. Usage::

    python benchmarks/bench_diagram.py [--rows 41] [--repeat 5] [--repeat-map 2] [--raster 200] [--step 0.02]
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time

import numpy as np
import xarray as xr

from stickslip import WeakeningLaw, regime_map
from stickslip.bifurcation.diagram import Curve, Diagram, two_parameter_diagram
from stickslip.bifurcation.planes import Plane

P = 0.5
NU_RANGE = (0.05, 2.0)
C_RANGE = (2.0, 20.0)


def nu_hopf(c: np.ndarray) -> np.ndarray:
    """The Hopf velocity of the weakening law: ``f'(nu) = -c/(1 + c nu)^2 + p = 0``."""
    return (np.sqrt(c / P) - 1.0) / c


def to_unit(plane: Plane, nu: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Points ``(nu, c)`` in the plane's unit square, shape (n, 2)."""
    return np.stack([plane.x.from_value(nu), plane.y.from_value(c)], axis=-1)


def distance(points: np.ndarray, curves: list[np.ndarray]) -> np.ndarray:
    """Distance from each point (n, 2) to the nearest segment of the polylines (unit square)."""
    best = np.full(len(points), np.inf)
    for q in curves:
        a, d = q[:-1], np.diff(q, axis=0)
        dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        for s in range(0, len(points), 2000):
            p = points[s : s + 2000, None, :]
            t = np.clip(np.einsum("mij,ij->mi", p - a, d) / dd, 0.0, 1.0)
            dist = np.linalg.norm(a + t[..., None] * d - p, axis=-1).min(axis=1)
            best[s : s + 2000] = np.minimum(best[s : s + 2000], dist)
    return best


def nu_on(plane: Plane, curves: list[Curve], c: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """``nu`` of the polylines at each ``c`` (straight in the unit square), the crossing nearest ``ref``."""
    out = np.full(c.size, math.nan)
    uc = plane.y.from_value(c)
    for cv in curves:
        u = cv.u
        for k in range(len(u) - 1):
            (x0, y0), (x1, y1) = u[k], u[k + 1]
            if y1 == y0:
                continue
            t = (uc - y0) / (y1 - y0)
            ok = (t >= 0) & (t <= 1)
            val = np.array([plane.x.to_unit(float(x0 + s * (x1 - x0))) for s in t[ok]])
            idx = np.flatnonzero(ok)
            better = np.isnan(out[idx]) | (np.abs(val - ref[idx]) < np.abs(out[idx] - ref[idx]))
            out[idx[better]] = val[better]
    return out


def timed_diagrams(plane: Plane, repeat: int, raster: int, step: float) -> tuple[float, float, Diagram]:
    """The shortest of ``repeat`` diagrams without and with labelling, alternated; the last labelled one."""
    best = {False: math.inf, True: math.inf}
    d = None
    for _ in range(repeat):
        for label in (False, True):
            t0 = time.perf_counter()
            d = two_parameter_diagram(plane, raster=raster, step=step, label=label)
            best[label] = min(best[label], time.perf_counter() - t0)
    assert d is not None
    return best[False], best[True], d


def timed_map(law: WeakeningLaw, values: np.ndarray, repeat: int) -> tuple[float, xr.Dataset]:
    """The shortest of ``repeat`` regime maps over ``c = values``."""
    best, ds = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        ds = regime_map(law, "c", values, *NU_RANGE, progress=False)
        best = min(best, time.perf_counter() - t0)
    assert ds is not None
    return best, ds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rows", type=int, default=41, help="evenly spaced rows of regime_map timed")
    parser.add_argument("--repeat", type=int, default=5, help="diagram calls timed (the shortest kept)")
    parser.add_argument("--repeat-map", type=int, default=2, help="even-row maps timed (the shortest kept)")
    parser.add_argument("--raster", type=int, default=200)
    parser.add_argument("--step", type=float, default=0.02)
    a = parser.parse_args()
    law = WeakeningLaw(c=5.0, p=P)
    plane = Plane.dimensionless(law, ("nu", NU_RANGE), ("c", C_RANGE))
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores")
    print(
        f"work: weakening law p = {P}, nu in {list(NU_RANGE)} (log axis), c in {list(C_RANGE)} (linear); "
        f"diagram raster {a.raster}, step {a.step}; regime_map n_nu = 201"
    )

    t0 = time.perf_counter()
    small = Plane.dimensionless(law, ("nu", (0.2, 1.0)), ("c", (4.0, 6.0)))
    two_parameter_diagram(small, seed_lines=2, raster=20)
    regime_map(law, "c", [4.0, 6.0], 0.2, 1.0, n_nu=21, progress=False)
    print(
        f"warm-up, not timed below (a small diagram and a 2-row map; compilation, cache loading): "
        f"{time.perf_counter() - t0:.2f} s"
    )

    t_nolab, t_lab, d = timed_diagrams(plane, a.repeat, a.raster, a.step)
    hopf, graz = d.curves_of("hopf"), d.curves_of("grazing")
    n_pts = {k: sum(len(c.u) for c in v) for k, v in (("hopf", hopf), ("grazing", graz))}
    print(
        f"diagram, regions labelled : {t_lab:8.3f} s  (shortest of {a.repeat}; "
        f"{len(d.region_names)} regions: {'; '.join(d.region_names)})"
    )
    print(
        f"diagram, label=False      : {t_nolab:8.3f} s  (shortest of {a.repeat}; {len(hopf)} Hopf curve of "
        f"{n_pts['hopf']} points, {len(graz)} grazing curve of {n_pts['grazing']} points)"
    )

    # the diagram's Hopf curve against the closed form: at its points, and between them
    c_dense = np.linspace(*C_RANGE, 20001)
    u_dense = to_unit(plane, nu_hopf(c_dense), c_dense)
    d_hopf = distance(u_dense, [c.u for c in hopf])
    node_err = max(float(np.max(np.abs(c.x - nu_hopf(c.y)))) for c in hopf)
    dnu_hopf = np.abs(nu_on(plane, hopf, c_dense, nu_hopf(c_dense)) - nu_hopf(c_dense))

    # the grazing curve against regime_map's rows at its points and midway (in c) between them
    gc = np.unique(np.concatenate([c.y for c in graz]))
    rows = np.sort(np.concatenate([gc, 0.5 * (gc[:-1] + gc[1:])]))
    t_rows, ds = timed_map(law, rows, 1)
    g_rm = ds.grazing.values
    dnu_g = np.abs(nu_on(plane, graz, rows, g_rm) - g_rm)
    d_graz = distance(to_unit(plane, g_rm, rows), [c.u for c in graz])
    at_pt = np.isin(rows, gc)
    onset_gap = float(np.nanmax(np.abs(g_rm - ds.stick_slip_onset.values)))

    res = max(float(d_hopf.max()), float(d_graz.max()))
    n_stair = 1 + math.ceil(1.0 / (2.0 * res))

    def joined(n: int) -> float:
        """Distance from the Hopf curve to its exact points on ``n`` even rows joined by segments."""
        cr = np.linspace(*C_RANGE, n)
        return float(distance(u_dense, [to_unit(plane, nu_hopf(cr), cr)]).max())

    n_lin = 2
    while joined(n_lin) > res:
        n_lin += 1

    # today's grid of one-parameter runs, timed on --rows evenly spaced rows
    values = np.linspace(*C_RANGE, a.rows)
    t_even, ds_even = timed_map(law, values, a.repeat_map)
    per_row = t_even / a.rows
    hopf_rm = float(np.max(np.abs(ds_even.hopf.values - nu_hopf(values))))
    t_stair, t_line = per_row * n_stair, per_row * n_lin

    print(
        f"regime_map, {a.rows} even rows: {t_even:8.3f} s = {per_row * 1e3:.1f} ms per row "
        f"(shortest of {a.repeat_map}; its Hopf nu against the closed form: max {hopf_rm:.1e})"
    )
    print(
        f"regime_map, {rows.size} rows at and between the diagram's grazing points: {t_rows:.3f} s "
        f"= {t_rows / rows.size * 1e3:.1f} ms per row"
    )
    print("agreement (distance in the unit square u = (log(nu/0.05)/log 40, (c - 2)/18)):")
    print(f"  Hopf, diagram points vs closed form            : max |dnu| {node_err:.1e}")
    print(
        f"  Hopf, diagram polyline vs closed form          : max |dnu| at equal c {np.nanmax(dnu_hopf):.1e}, "
        f"max distance {d_hopf.max():.2e} (20001 values of c)"
    )
    print(
        f"  grazing, diagram points vs regime_map          : max |dnu| {dnu_g[at_pt].max():.1e} "
        f"({at_pt.sum()} rows; regime_map's grazing vs its stick-slip onset: max {onset_gap:.1e})"
    )
    print(
        f"  grazing, diagram polyline midway vs regime_map : max |dnu| {dnu_g[~at_pt].max():.1e}, "
        f"max distance {d_graz[~at_pt].max():.2e} ({(~at_pt).sum()} rows)"
    )
    print(
        f"diagram resolution (the largest distance above): {res:.2e} of the unit square "
        f"(= {res * 18:.2e} in c)"
    )
    print(f"regime_map rows for a staircase of that resolution (half the spacing, 1/(2(N-1))): N = {n_stair}")
    extra = "" if n_stair <= a.rows else f" (extrapolated linearly from the {a.rows} rows timed)"
    print(f"regime_map, {n_stair} rows: {t_stair:8.1f} s{extra}")
    print(
        f"ratio regime_map / diagram: {t_stair / t_lab:,.0f} x (labelled), "
        f"{t_stair / t_nolab:,.0f} x (label=False)"
    )
    print(
        f"for reference, rows joined by straight segments instead (Hopf, closed form): N = {n_lin} rows "
        f"for the same resolution, {t_line:.2f} s, {t_line / t_lab:.1f} x the labelled diagram"
    )


if __name__ == "__main__":
    main()
