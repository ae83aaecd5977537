"""Bad input to the Python entry points: clear errors, never a numba traceback."""

import math

import numpy as np
import pytest

from stickslip import DimensionlessParameters, WeakeningLaw, cycle, simulate, zv_parameters
from stickslip.core.api import run_attractors, run_trajectory

P = DimensionlessParameters(nu=0.01, law=WeakeningLaw(c=3.0))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"rtol": 0.0}, "rtol=0.0"),
        ({"rtol": 1e-20}, "rtol=1e-20"),
        ({"rtol": 0.5}, "rtol=0.5"),
        ({"rtol": math.nan}, "rtol=nan"),
        ({"atol": -1.0}, "atol=-1.0"),
        ({"max_slip_time": 0.0}, "max_slip_time=0.0"),
        ({"conv_tol": 2.0}, "conv_tol=2.0"),
    ],
)
def test_cycle_bad_options(kwargs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        cycle(P, **kwargs)


def test_cycle_bad_params() -> None:
    with pytest.raises(ValueError, match="params="):
        cycle("nu=0.1")  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"n_points": 1}, "n_points=1"),
        ({"n_points": 2.5}, "n_points=2.5"),
        ({"initial": (1.0,)}, "initial="),
        ({"initial": (math.nan, 0.0)}, "initial="),
        ({"duration": -1.0}, "duration=-1.0"),
        ({"duration": "10 s"}, "duration="),
        ({"cycles": 0}, "cycles=0"),
        ({"initial": (0.0, 0.0, 5.0)}, "initial=\\(0.0, 0.0, 5.0\\): expected a pair"),  # 5 was dropped
        ({"cycles": 5, "duration": 10.0}, "cycles=5 and duration=10.0: give one or the other"),  # ignored
    ],
)
def test_simulate_bad_options(kwargs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        simulate(P, **kwargs)


def test_simulate_physical_duration_needs_time_units() -> None:
    with pytest.raises(ValueError, match="duration='3 m' has dimension"):
        simulate(zv_parameters(), duration="3 m")
    with pytest.raises(ValueError, match=r"duration=3\.0 has no unit"):
        simulate(zv_parameters(), duration=3.0)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"nu": [0.1, -0.1]}, "nu"),
        ({"nu": [0.1, math.nan]}, "nu"),
        ({"lp": [[1.0, 0.0]] * 3}, "lp"),  # three rows of parameters for two velocities
        ({"lp": [1.0] * 9}, "lp"),  # more parameters than a law can have
        ({"law": 7}, "law"),
        ({"s0": [0.0, 0.0, 0.0]}, "s0"),
    ],
)
def test_core_api_checks_arrays(kwargs: dict, message: str) -> None:
    args = {"law": 0, "lp": [2.0, 0.0, 0.0], "nu": [0.1, 0.2], "s0": None, "w0": None}
    args.update(kwargs)
    with pytest.raises(ValueError, match=message):
        run_attractors(
            args["law"],
            args["lp"],
            args["nu"],
            args["s0"],
            args["w0"],
            from_breakaway=False,
            rtol=1e-9,
            atol=1e-12,
            max_slip_time=10.0,
            conv_tol=1e-8,
        )


def test_core_trajectory_checks_times() -> None:
    with pytest.raises(ValueError, match="t_eval"):
        run_trajectory(0, [2.0, 0.0, 0.0], 0.1, 0.0, 0.0, np.array([1.0, 0.5]), rtol=1e-9, atol=1e-12)
    with pytest.raises(ValueError, match="t_eval"):
        run_trajectory(0, [2.0, 0.0, 0.0], 0.1, 0.0, 0.0, np.array([]), rtol=1e-9, atol=1e-12)
