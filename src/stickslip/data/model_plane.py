"""The model's regimes beside the measured ones: each record's set-up computed, and the (V, k) plane.

A measured regime diagram (:func:`stickslip.data.records.analyze_records`, then
:func:`~stickslip.data.motion.measure_motion`) places each record at its driving
velocity and stiffness with the regime it shows. Given a friction law, the one-block
model says what that set-up does: :func:`model_regimes` computes the steady
oscillation reached from rest for each record (its driving velocity, stiffness,
mass and load: the stated values, else the measured ones) and over the (V, k) plane
around them, at the records' median mass and load.

A measured regime is compared with the model's where both name one:

- periodic or irregular stick-slip with the model's stick-slip;
- pure slip with the model's pure slip (or slip reversal);
- steady sliding with the model's steady sliding.

A mixed or undetermined record, or a set-up the model could not compute, is not
compared (None), and the count says so.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..dynamics.cycle import cycle
from ..dynamics.sweep import sweep
from ..io.errors import DataError
from ..laws import PhysicalLaw, PhysicalWeakeningLaw
from ..models.parameters import PhysicalParameters
from ..units import Q_

__all__ = ["MAP_POINTS", "MAP_SPAN", "ModelPlane", "model_regimes", "read_model_law", "records_diagram"]

#: grid of the (V, k) map: driving velocities x stiffnesses
MAP_POINTS = (48, 32)
#: the map spans the records' V and k, widened by this factor on each side
MAP_SPAN = 3.0

#: a measured regime and the model's regimes it agrees with
_SAME = {
    "periodic stick-slip": ("stick-slip",),
    "irregular stick-slip": ("stick-slip",),
    "pure slip": ("pure-slip", "slip-reversal"),
    "steady sliding": ("steady-sliding",),
}


@dataclass(frozen=True)
class ModelPlane:
    """The model's regimes at each record and over the (V, k) plane.

    Attributes
    ----------
    columns : dict[str, list]
        Per record of the table, in its order: ``model_regime`` (None where the
        set-up lacks a value or the record no driving velocity), ``model_stick_fraction``,
        ``model_period [s]``, ``model_agrees`` (True, False, or None where not compared).
    plane : xarray.Dataset or None
        The sweep over ``v0`` [um/s] and ``stiffness`` [N/m] at ``mass`` and ``load``
        (None where no record has a full set-up).
    mass, load : float
        The map's mass [kg] and load [N]: the records' medians.
    law : str
        The law, in words.
    agree, compared : int
        Records whose measured regime agrees with the model's, and records compared.

    """

    columns: dict[str, list[Any]]
    plane: Any
    mass: float
    load: float
    law: str
    agree: int
    compared: int

    def line(self) -> str:
        """Return one line: the law and how many records the model agrees with."""
        return (
            f"model ({self.law}): its regime agrees with {self.agree} of {self.compared} records whose "
            "regime both name (mixed and undetermined ones not compared)"
        )


def read_model_law(text: str) -> PhysicalWeakeningLaw:
    """Return the paper's law from ``text``: a fit's JSON file or ``'mu_s=0.4, a=300 s/m[, b=5 s/m]'``.

    A JSON file is the ``fit.json`` that ``stickslip fit`` writes for a waveform or
    features fit (its ``mu_s``, ``a`` and, where fitted, ``b``).

    Raises
    ------
    DataError
        One line naming the text and what was expected.

    """
    import json
    import os

    if os.path.isfile(text):
        try:
            with open(text, encoding="utf-8") as fh:
                d = json.load(fh)
            p = d["parameters"]
            values = {name: p[name]["value"] for name in ("mu_s", "a")}
            units = {name: p[name]["unit"] for name in ("a",)}
            b = p.get("b")
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise DataError(
                f"--model {text}: not a fit.json with parameters mu_s and a (from 'stickslip fit "
                f"--method waveform'): {type(exc).__name__}: {exc}"
            ) from None
        return _law(
            text,
            values["mu_s"],
            f"{values['a']} {units['a']}",
            f"{b['value']} {b['unit']}" if b else "0 s/m",
        )
    if text.lower().endswith(".json"):
        raise DataError(f"--model {text}: no such file (a fit.json from 'stickslip fit')")
    parts: dict[str, str] = {}
    for item in text.split(","):
        name, sep, value = item.partition("=")
        name = name.strip().replace("mu0", "mu_s")
        if not sep or name not in ("mu_s", "a", "b") or name in parts:
            raise DataError(
                f"--model {text!r}: expected a fit.json file or 'mu_s=NUMBER, a=RATE[, b=RATE]' "
                "(the paper's law, e.g. 'mu_s=0.4, a=300 s/m, b=5 s/m')"
            )
        parts[name] = value.strip()
    if "mu_s" not in parts or "a" not in parts:
        raise DataError(f"--model {text!r}: give mu_s and a (e.g. 'mu_s=0.4, a=300 s/m')")
    try:
        mu_s = float(parts["mu_s"])
    except ValueError:
        raise DataError(f"--model {text!r}: mu_s={parts['mu_s']!r} is not a number") from None
    return _law(text, mu_s, parts["a"], parts.get("b", "0 s/m"))


def _law(where: str, mu_s: Any, a: str, b: str) -> PhysicalWeakeningLaw:
    try:
        return PhysicalWeakeningLaw(mu_s=mu_s, a=a, b=b)
    except ValueError as exc:
        raise DataError(f"--model {where}: {exc}") from None


def _set_up(row: Mapping[str, Any], quantity: str) -> float:
    """Return a record's stated value of ``quantity`` (stiffness, mass), else its measured one."""
    unit = {"stiffness": "N/m", "mass": "kg"}[quantity]
    for col in (f"{quantity}_nominal [{unit}]", f"{quantity} [{unit}]"):
        value = float(row.get(col, math.nan))
        if math.isfinite(value) and value > 0:
            return value
    return math.nan


def model_regimes(
    table: Any,
    law: PhysicalLaw,
    *,
    points: tuple[int, int] = MAP_POINTS,
    span: float = MAP_SPAN,
) -> ModelPlane:
    """Compute the model's regime for each record's set-up and over the (V, k) plane around them.

    Parameters
    ----------
    table : pandas.DataFrame
        From :func:`stickslip.data.records.analyze_records` (with the motion's columns:
        ``regime``, ``stiffness [N/m]``, ``mass [kg]`` and their stated values).
    law : PhysicalLaw
        The friction law, e.g. ``PhysicalWeakeningLaw(mu_s=0.4, a="300 s/m")``.
    points : (int, int), optional
        The map's driving velocities and stiffnesses.
    span : float, optional
        The map reaches this factor beyond the records' V and k on each side.

    Returns
    -------
    ModelPlane

    """
    rows = [dict(zip(table.columns, r, strict=True)) for r in table.itertuples(index=False)]
    cols: dict[str, list[Any]] = {
        "model_regime": [],
        "model_stick_fraction": [],
        "model_period [s]": [],
        "model_agrees": [],
    }
    set_ups = []
    for row in rows:
        v0, load = float(row.get("v0 [m/s]", math.nan)), float(row.get("load [N]", math.nan))
        k, m = _set_up(row, "stiffness"), _set_up(row, "mass")
        if not all(math.isfinite(x) and x > 0 for x in (v0, load, k, m)):
            for values in cols.values():
                values.append(None)
            continue
        set_ups.append((v0, k, m, load))
        res = cycle(
            PhysicalParameters(
                mass=Q_(m, "kg"), stiffness=Q_(k, "N/m"), load=Q_(load, "N"), v0=Q_(v0, "m/s"), law=law
            )
        )
        regime = str(res.regime)
        measured = row.get("regime")
        same = _SAME.get(measured) if isinstance(measured, str) else None
        cols["model_regime"].append(regime)
        cols["model_stick_fraction"].append(float(res.stick_fraction))
        cols["model_period [s]"].append(float(res.period))
        cols["model_agrees"].append(None if same is None or res.status != "ok" else regime in same)
    compared = [a for a in cols["model_agrees"] if a is not None]
    words = law.describe()
    if not set_ups:
        return ModelPlane(cols, None, math.nan, math.nan, words, 0, 0)
    v0s, ks, ms, loads = (np.array(x) for x in zip(*set_ups, strict=True))
    mass, load = float(np.median(ms)), float(np.median(loads))
    v_axis = np.geomspace(v0s.min() / span, v0s.max() * span, points[0]) * 1e6
    k_axis = np.geomspace(ks.min() / span, ks.max() * span, points[1])
    base = PhysicalParameters(
        mass=Q_(mass, "kg"),
        stiffness=Q_(float(np.median(ks)), "N/m"),
        load=Q_(load, "N"),
        v0=Q_(float(np.median(v0s)), "m/s"),
        law=law,
    )
    plane = sweep(base, {"v0": Q_(v_axis, "um/s"), "stiffness": Q_(k_axis, "N/m")}, progress=None)
    return ModelPlane(cols, plane, mass, load, words, sum(compared), len(compared))


def records_diagram(
    table: Any, law: PhysicalLaw, *, span: float = MAP_SPAN, **diagram_options: Any
) -> tuple[Any, list[tuple[float, float, str]]]:
    """Return the model's two-parameter (V, k) diagram around the records, and their measured points.

    The plane spans the records' driving velocities and stiffnesses (stated, else
    measured), widened by ``span`` on each side, at the records' median mass and load;
    its curves and regions are those of
    :func:`~stickslip.bifurcation.diagram.two_parameter_diagram` (``diagram_options``
    passed on). Each record with a full set-up is a point ``(v0 [um/s], k [N/m],
    measured regime)``, periodic or irregular stick-slip both named ``stick-slip``.

    Raises
    ------
    DataError
        When no record has a driving velocity, stiffness, mass and load.

    """
    from ..bifurcation.diagram import two_parameter_diagram
    from ..bifurcation.planes import Plane

    rows = [dict(zip(table.columns, r, strict=True)) for r in table.itertuples(index=False)]
    pts, set_ups = [], []
    for row in rows:
        v0, load = float(row.get("v0 [m/s]", math.nan)), float(row.get("load [N]", math.nan))
        k, m = _set_up(row, "stiffness"), _set_up(row, "mass")
        if not all(math.isfinite(x) and x > 0 for x in (v0, load, k, m)):
            continue
        set_ups.append((v0, k, m, load))
        regime = row.get("regime")
        name = "stick-slip" if isinstance(regime, str) and regime.endswith("stick-slip") else str(regime)
        pts.append((v0 * 1e6, k, name))
    if not set_ups:
        raise DataError("no record has a driving velocity, a stiffness, a mass and a load: no (V, k) plane")
    v0s, ks, ms, loads = (np.array(x) for x in zip(*set_ups, strict=True))
    base = PhysicalParameters(
        mass=Q_(float(np.median(ms)), "kg"),
        stiffness=Q_(float(np.median(ks)), "N/m"),
        load=Q_(float(np.median(loads)), "N"),
        v0=Q_(float(np.median(v0s)), "m/s"),
        law=law,
    )
    plane = Plane.physical(
        base,
        ("v0", (v0s.min() * 1e6 / span, v0s.max() * 1e6 * span)),
        ("stiffness", (ks.min() / span, ks.max() * span)),
    )
    return two_parameter_diagram(plane, **diagram_options), pts
