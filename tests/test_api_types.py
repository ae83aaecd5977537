"""The API's rule for refused arguments: a wrong type raises TypeError, a wrong value ValueError.

The rule is stated in ``docs/api.md`` ("Errors") and in :mod:`stickslip.errors`: stickslip's own
type checks raise :class:`stickslip.ArgumentTypeError`, a TypeError that is also a ValueError
(so ``except ValueError`` keeps catching it), and every message names the argument. Each entry
point below is called once with an argument of the wrong type and once with an argument of the
right type and a wrong value; every call is refused before any computation starts.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import stickslip
from stickslip import (
    CoulombLaw,
    CubicLaw,
    DimensionlessParameters,
    ExpressionLaw,
    PhysicalParameters,
    PhysicalWeakeningLaw,
    TabulatedLaw,
    WeakeningLaw,
    cycle,
    laws,
    simulate,
    zv_parameters,
)
from stickslip.bifurcation.regime_map import regime_map
from stickslip.bifurcation.regimes import regimes
from stickslip.chains import ChainParameters, b_value, chain, chain_ensemble, connected_ruptures
from stickslip.chains.lyapunov import lyapunov_exponent
from stickslip.core.api import run_attractors
from stickslip.data.criterion import classify, classify_file
from stickslip.data.fitting import fit_record
from stickslip.data.records import analyze_records, measure_record, synthetic_record
from stickslip.dynamics.sweep import load_sweep, sweep
from stickslip.errors import ArgumentTypeError
from stickslip.io.formats import RecordOptions
from stickslip.io.records import Record
from stickslip.orbits.periodic import pure_slip_orbit
from stickslip.ratestate.model import RateStateParameters

D = DimensionlessParameters(nu=0.01, law=WeakeningLaw(c=3.0))
CHAIN = ChainParameters(blocks=3, law=WeakeningLaw(c=3.0), nu=0.01, ell=1.0)
RATE_STATE = {
    "a": 0.01,
    "b": 0.015,
    "dc": "10 um",
    "v_ref": "1 um/s",
    "mu0": 0.6,
    "stiffness_per_load": "1e3 1/m",
}
HALF = CubicLaw(alpha=0.5, gamma=1 / 6)
ATTRACTORS = {"from_breakaway": True, "rtol": 1e-10, "atol": 1e-12, "max_slip_time": 1e3, "conv_tol": 1e-6}


def _carlson_langer(**values: Any) -> Any:
    return laws.get("carlson-langer").dimensionless(**values)


def _physical(**changes: Any) -> PhysicalParameters:
    given = {
        "mass": "231 g",
        "stiffness": "62 N/m",
        "load": "196 mN",
        "v0": "5 um/s",
        "law": PhysicalWeakeningLaw(mu_s=0.46, a="160 s/m"),
    }
    return PhysicalParameters(**{**given, **changes})


def _record(**changes: Any) -> Record:
    return Record(**{"name": "r", "time": np.arange(4.0), "force": np.ones(4), **changes})


#: (call, the argument its message names, whether stickslip's own check refuses it: an
#: ArgumentTypeError; False: a plain TypeError, as documented)
WRONG_TYPES: list[Any] = [
    # friction laws, one per built-in law, dimensionless and physical
    pytest.param(lambda: WeakeningLaw(c="3"), "c", True, id="WeakeningLaw(c='3')"),
    pytest.param(lambda: CubicLaw(alpha=[0.5], gamma=0.17), "alpha", True, id="CubicLaw(alpha=[0.5])"),
    pytest.param(lambda: CoulombLaw(kinetic=None), "kinetic", True, id="CoulombLaw(kinetic=None)"),
    pytest.param(
        lambda: _carlson_langer(alpha="1", sigma=0.5), "alpha", True, id="carlson-langer(alpha='1')"
    ),
    pytest.param(lambda: PhysicalWeakeningLaw(mu_s=0.46, a=160), "a", True, id="PhysicalWeakeningLaw(a=160)"),
    pytest.param(
        lambda: PhysicalWeakeningLaw(mu_s="0.46", a="160 s/m"),
        "mu_s",
        True,
        id="PhysicalWeakeningLaw(mu_s='0.46')",
    ),
    pytest.param(lambda: ExpressionLaw("1/(1 + a*w)", a="3.8"), "a", True, id="ExpressionLaw(a='3.8')"),
    pytest.param(lambda: ExpressionLaw(123), "f", True, id="ExpressionLaw(123)"),
    pytest.param(
        lambda: ExpressionLaw(mu="0.46/(1 + a*v)", a=None), "a", True, id="ExpressionLaw(mu, a=None)"
    ),
    pytest.param(lambda: TabulatedLaw.from_csv(123), "path", False, id="TabulatedLaw.from_csv(123)"),
    # parameter sets
    pytest.param(
        lambda: DimensionlessParameters(nu="0.1", law=WeakeningLaw(c=3.0)), "nu", True, id="nu='0.1'"
    ),
    pytest.param(lambda: DimensionlessParameters(nu=0.1, law="weakening"), "law", True, id="law='weakening'"),
    pytest.param(lambda: _physical(v0=5), "v0", True, id="PhysicalParameters(v0=5)"),
    pytest.param(lambda: _physical(mass=None), "mass", True, id="PhysicalParameters(mass=None)"),
    pytest.param(
        lambda: _physical(law=WeakeningLaw(c=3.0)), "law", True, id="PhysicalParameters(law=dimensionless)"
    ),
    # the one-block model
    pytest.param(lambda: cycle("nu=0.1"), "params", True, id="cycle('nu=0.1')"),
    pytest.param(lambda: cycle(D, conv_tol="0.1"), "conv_tol", True, id="cycle(conv_tol='0.1')"),
    pytest.param(lambda: cycle(D, probe="no"), "probe", False, id="cycle(probe='no')"),
    pytest.param(lambda: simulate(D, n_points=10.5), "n_points", True, id="simulate(n_points=10.5)"),
    pytest.param(lambda: simulate(D, initial="59"), "initial", True, id="simulate(initial='59')"),
    pytest.param(lambda: simulate(D, initial=(0.0, "x")), "initial", True, id="simulate(initial=(0, 'x'))"),
    pytest.param(
        lambda: simulate(zv_parameters(), duration=3.0), "duration", True, id="simulate(duration=3.0)"
    ),
    # sweeps, regimes, orbits, the batched core
    pytest.param(lambda: sweep("x", {"nu": [0.1]}), "base", True, id="sweep(base='x')"),
    pytest.param(lambda: sweep(D, {"nu": "0.1"}), "nu", True, id="sweep({'nu': '0.1'})"),
    pytest.param(lambda: sweep(D, {"nu": 0.1}), "nu", True, id="sweep({'nu': 0.1})"),
    pytest.param(lambda: sweep(D, {"nu": [0.1, "x"]}), "nu", True, id="sweep({'nu': [0.1, 'x']})"),
    pytest.param(lambda: sweep(D, [("nu", [0.1])]), "grid", False, id="sweep(grid=list)"),
    pytest.param(
        lambda: sweep(D, {"nu": [0.1, 0.2]}, block_points="3"), "block_points", True, id="block_points"
    ),
    pytest.param(lambda: sweep(D, {"nu": [0.1, 0.2]}, backend=1), "backend", True, id="sweep(backend=1)"),
    pytest.param(lambda: load_sweep(3), "path", True, id="load_sweep(3)"),
    pytest.param(lambda: regimes(None, 0.5, 1.5), "law", False, id="regimes(None)"),
    pytest.param(lambda: regimes(HALF, "0.5", 1.5), "nu_min", True, id="regimes(nu_min='0.5')"),
    pytest.param(lambda: regimes(HALF, 0.5, 1.5, n_grid=10.0), "n_grid", True, id="regimes(n_grid=10.0)"),
    pytest.param(lambda: regimes(HALF, 0.5, 1.5, tol="1e-9"), "tol", True, id="regimes(tol='1e-9')"),
    pytest.param(
        lambda: regime_map(WeakeningLaw(c=3.0), "c", 3.0, 0.01, 0.1), "values", True, id="regime_map(3.0)"
    ),
    pytest.param(
        lambda: regime_map(WeakeningLaw(c=3.0), "c", [3.0], "0.01", 0.1),
        "nu_min",
        True,
        id="regime_map(nu_min)",
    ),
    pytest.param(lambda: pure_slip_orbit(D, tol="1e-10"), "tol", True, id="pure_slip_orbit(tol='1e-10')"),
    pytest.param(lambda: pure_slip_orbit(D, guess=1.0), "guess", True, id="pure_slip_orbit(guess=1.0)"),
    pytest.param(
        lambda: run_attractors(0, [3.0, 0.0], ["a"], **ATTRACTORS), "nu", False, id="run_attractors(nu)"
    ),
    # chains
    pytest.param(lambda: chain("x", 10), "params", True, id="chain(params='x')"),
    pytest.param(lambda: chain(CHAIN, 10.5), "events", True, id="chain(events=10.5)"),
    pytest.param(lambda: chain(CHAIN, 10, init=1), "init", True, id="chain(init=1)"),
    pytest.param(lambda: chain(CHAIN, 10, events_as=None), "events_as", True, id="chain(events_as=None)"),
    pytest.param(lambda: chain(CHAIN, 10, state="x"), "state", False, id="chain(state='x')"),
    pytest.param(
        lambda: ChainParameters(blocks="3", law=WeakeningLaw(c=3.0), nu=0.01, ell=1.0),
        "blocks",
        True,
        id="blocks",
    ),
    pytest.param(
        lambda: ChainParameters(blocks=3, law=WeakeningLaw(c=3.0), nu=0.01, ell=1.0, boundary=1),
        "boundary",
        True,
        id="boundary=1",
    ),
    pytest.param(
        lambda: chain_ensemble(CHAIN, 10, seeds="1,2"), "seeds", True, id="chain_ensemble(seeds='1,2')"
    ),
    pytest.param(lambda: b_value("abc"), "m", True, id="b_value('abc')"),
    pytest.param(lambda: b_value(np.arange(10.0), block=2.5), "block", True, id="b_value(block=2.5)"),
    pytest.param(lambda: connected_ruptures("x"), "slips", True, id="connected_ruptures('x')"),
    pytest.param(lambda: lyapunov_exponent(CHAIN, [0, 0, 0], eps="1e-7"), "eps", True, id="lyapunov(eps)"),
    # rate and state
    pytest.param(
        lambda: RateStateParameters(**{**RATE_STATE, "a": "0.01"}), "a", True, id="RateState(a='0.01')"
    ),
    pytest.param(
        lambda: RateStateParameters(**{**RATE_STATE, "dc": 1e-5}), "dc", True, id="RateState(dc=1e-5)"
    ),
    pytest.param(
        lambda: RateStateParameters(**{**RATE_STATE, "mu0": None}), "mu0", True, id="RateState(mu0=None)"
    ),
    # measured data
    pytest.param(lambda: classify("abc", [1, 2]), "velocity", True, id="classify('abc')"),
    pytest.param(lambda: classify(1.0, [1, 2]), "velocity", True, id="classify(1.0)"),
    pytest.param(
        lambda: classify([1, 2, 3, 4], [1, 2, 3, 4], confidence="0.95"), "confidence", True, id="conf"
    ),
    pytest.param(
        lambda: classify([1, 2, 3, 4], [1, 2, 3, 4], min_points=4.0), "min_points", True, id="min_points"
    ),
    pytest.param(lambda: classify_file(3), "path", True, id="classify_file(3)"),
    pytest.param(lambda: measure_record("x"), "record", True, id="measure_record('x')"),
    pytest.param(lambda: analyze_records("folder"), "records", False, id="analyze_records('folder')"),
    pytest.param(lambda: fit_record("x"), "record", False, id="fit_record('x')"),
    pytest.param(
        lambda: synthetic_record(zv_parameters(), duration="10 s", rate="100 Hz", drift=0.1),
        "drift",
        True,
        id="synthetic_record(drift=0.1)",
    ),
    pytest.param(
        lambda: synthetic_record("x", duration="10 s", rate="100 Hz"), "params", True, id="synthetic(x)"
    ),
    pytest.param(lambda: _record(name=3), "name", True, id="Record(name=3)"),
    pytest.param(lambda: _record(force="1,2,3,4"), "force", True, id="Record(force='1,2,3,4')"),
    pytest.param(lambda: RecordOptions(time=3), "time", True, id="RecordOptions(time=3)"),
]

#: calls with an argument of the right type and a wrong value
WRONG_VALUES: list[Any] = [
    pytest.param(lambda: WeakeningLaw(c=-1), id="WeakeningLaw(c=-1)"),
    pytest.param(lambda: CubicLaw(alpha=math.nan, gamma=0.17), id="CubicLaw(alpha=nan)"),
    pytest.param(lambda: CoulombLaw(kinetic=2.0), id="CoulombLaw(kinetic=2)"),
    pytest.param(lambda: _carlson_langer(alpha=1.0, sigma=1.5), id="carlson-langer(sigma=1.5)"),
    pytest.param(lambda: PhysicalWeakeningLaw(mu_s=0.46, a="160 kg"), id="PhysicalWeakeningLaw(a='160 kg')"),
    pytest.param(lambda: PhysicalWeakeningLaw(mu_s=0.46, a="fast"), id="PhysicalWeakeningLaw(a='fast')"),
    pytest.param(lambda: ExpressionLaw("1/(1 + a*w)", a=math.nan), id="ExpressionLaw(a=nan)"),
    pytest.param(lambda: ExpressionLaw("1/(1 + a*"), id="ExpressionLaw('1/(1 + a*')"),
    pytest.param(lambda: ExpressionLaw(mu="0.46/(1 + a*v)", a="160 kg"), id="ExpressionLaw(mu, a='160 kg')"),
    pytest.param(
        lambda: TabulatedLaw.from_csv("/nonexistent/table.csv"), id="TabulatedLaw.from_csv(missing)"
    ),
    pytest.param(lambda: DimensionlessParameters(nu=-0.1, law=WeakeningLaw(c=3.0)), id="nu=-0.1"),
    pytest.param(lambda: _physical(v0="10 N"), id="PhysicalParameters(v0='10 N')"),
    pytest.param(lambda: _physical(v0="fast"), id="PhysicalParameters(v0='fast')"),
    pytest.param(lambda: cycle(D, rtol=0.5), id="cycle(rtol=0.5)"),
    pytest.param(lambda: simulate(D, n_points=1), id="simulate(n_points=1)"),
    pytest.param(lambda: simulate(D, initial=(0.0, 0.0, 5.0)), id="simulate(initial=3 values)"),
    pytest.param(lambda: simulate(zv_parameters(), duration="3 m"), id="simulate(duration='3 m')"),
    pytest.param(lambda: sweep(D, {"nu": []}), id="sweep({'nu': []})"),
    pytest.param(lambda: sweep(D, {"speed": [0.1]}), id="sweep({'speed': ...})"),
    pytest.param(lambda: sweep(D, {"nu": [0.1, 0.2]}, backend="tpu"), id="sweep(backend='tpu')"),
    pytest.param(lambda: load_sweep("/nonexistent/sweep.nc"), id="load_sweep(missing)"),
    pytest.param(lambda: regimes(HALF, 1.5, 0.5), id="regimes(reversed)"),
    pytest.param(lambda: regimes(HALF, 0.5, 1.5, n_grid=2), id="regimes(n_grid=2)"),
    pytest.param(lambda: regime_map(WeakeningLaw(c=3.0), "q", [3.0], 0.01, 0.1), id="regime_map(param='q')"),
    pytest.param(lambda: pure_slip_orbit(D, tol=1.0), id="pure_slip_orbit(tol=1.0)"),
    pytest.param(lambda: pure_slip_orbit(D, guess=(1.0, 2.0, 3.0)), id="pure_slip_orbit(guess=3 values)"),
    pytest.param(lambda: run_attractors(0, [3.0, 0.0], [-1.0], **ATTRACTORS), id="run_attractors(nu=-1)"),
    pytest.param(lambda: chain(CHAIN, 0), id="chain(events=0)"),
    pytest.param(lambda: chain(CHAIN, 10, init="sorted"), id="chain(init='sorted')"),
    pytest.param(lambda: chain(CHAIN, 10, events_as="all"), id="chain(events_as='all')"),
    pytest.param(lambda: ChainParameters(blocks=0, law=WeakeningLaw(c=3.0), nu=0.01, ell=1.0), id="blocks=0"),
    pytest.param(lambda: b_value(np.arange(10.0), block="some"), id="b_value(block='some')"),
    pytest.param(lambda: connected_ruptures(np.ones(3)), id="connected_ruptures(1-d)"),
    pytest.param(lambda: lyapunov_exponent(CHAIN, [0, 0]), id="lyapunov(two positions)"),
    pytest.param(lambda: RateStateParameters(**{**RATE_STATE, "a": -0.01}), id="RateState(a=-0.01)"),
    pytest.param(lambda: RateStateParameters(**{**RATE_STATE, "dc": "10 kg"}), id="RateState(dc='10 kg')"),
    pytest.param(lambda: classify([1, 2, 3], [1, 2]), id="classify(lengths)"),
    pytest.param(lambda: classify([1, 2, 3, 4], [1, 2, 3, 4], confidence=2.0), id="classify(confidence=2)"),
    pytest.param(lambda: classify_file("/nonexistent/points.csv"), id="classify_file(missing)"),
    pytest.param(
        lambda: synthetic_record(zv_parameters(), duration="10 s", rate="100 Hz", drift="0.1 mN"),
        id="synthetic_record(drift='0.1 mN')",
    ),
    pytest.param(lambda: _record(force=np.ones(3)), id="Record(3 forces, 4 times)"),
    pytest.param(lambda: RecordOptions(time="  "), id="RecordOptions(time='  ')"),
]


@pytest.mark.parametrize(("call", "name", "own"), WRONG_TYPES)
def test_a_wrong_type_is_a_type_error_that_names_the_argument(
    call: Callable[[], Any], name: str, own: bool
) -> None:
    with pytest.raises(TypeError) as info:
        call()
    message = str(info.value)
    assert re.search(rf"(^|\W){re.escape(name)}\W", message), message
    # stickslip's own checks: also a ValueError, so `except ValueError` catches a bad argument
    assert isinstance(info.value, ArgumentTypeError) is own, type(info.value)
    assert isinstance(info.value, ValueError) is own


@pytest.mark.parametrize("call", WRONG_VALUES)
def test_a_wrong_value_is_a_value_error_not_a_type_error(call: Callable[[], Any]) -> None:
    with pytest.raises(ValueError) as info:
        call()
    assert not isinstance(info.value, TypeError), f"{type(info.value).__name__}: {info.value}"


def test_argument_type_error_is_a_type_error_and_a_value_error_exported_by_the_package() -> None:
    assert issubclass(ArgumentTypeError, TypeError) and issubclass(ArgumentTypeError, ValueError)
    assert stickslip.ArgumentTypeError is ArgumentTypeError
    assert "ArgumentTypeError" in stickslip.__all__
    with pytest.raises(ValueError, match=r"c='3': expected a positive number"):  # caught as before
        WeakeningLaw(c="3")


def test_a_quantity_as_text_is_the_right_type() -> None:
    """A str where a quantity may be given as text is accepted, and one that is no quantity is a value."""
    assert _physical(v0="5 um/s").v0.to("um/s").magnitude == pytest.approx(5.0)
    with pytest.raises(ValueError, match="is not a quantity") as info:
        _physical(v0="5 6 um/s")
    assert not isinstance(info.value, TypeError)
