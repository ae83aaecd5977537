"""Bad input to the Python entry points: clear errors, never a numba traceback."""

import math
from dataclasses import replace

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


@pytest.mark.fast
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


@pytest.mark.fast
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


def test_python_api_units_probe_and_start_are_checked() -> None:
    """A formula with erf checks its parameters' units (160 kg is not 160 s/m: the check reads
    through SciPy's erf); a physical formula's law shows its own units, not those of an earlier
    law of the same formula; probe='no' is refused, not taken as true; a physical start may be
    given as quantities; v in a dimensionless formula is refused with the word that its
    velocity is w."""
    from stickslip import Q_, ExpressionLaw

    for wrong in ("160 kg", "160 m/s"):
        with pytest.raises(ValueError, match="is not dimensionally consistent with v in m/s"):
            ExpressionLaw(mu="0.46 - 0.2*erf(a*v)", a=wrong)
    right = ExpressionLaw(mu="0.46 - 0.2*erf(a*v)", a="160 s/m")
    assert right.params["a"] == Q_(160.0, "s/m")
    plain = ExpressionLaw(mu="0.46/(1 + a*v)", a=160)  # SI, as the docstring says
    held = ExpressionLaw(mu="0.46/(1 + a*v)", a="160 s/mm")
    assert plain.params["a"] == 160.0 and held.params["a"] == Q_(160000.0, "s/m")
    assert plain.si_parameters() == {"a": 160.0} and held.si_parameters() == {"a": 160000.0}
    with pytest.raises(ValueError, match=r"the dimensionless formula's velocity is w .* give mu="):
        ExpressionLaw("1/(1 + 3.8*v)")
    with pytest.raises(TypeError, match=r"probe='no': expected True or False"):
        cycle(DimensionlessParameters(nu=0.1, law=WeakeningLaw(c=3.8)), probe="no")
    zv = zv_parameters()
    traj = simulate(zv, initial=("50 mN", "0 m/s"), duration="5 s", n_points=20)
    assert traj.spring_force[0] == pytest.approx(0.05, rel=1e-12) and traj.velocity[0] == 0.0
    same = simulate(zv, initial=(0.05 / zv.scales.force.to("N").magnitude, 0.0), duration="5 s", n_points=20)
    np.testing.assert_allclose(traj.spring_force, same.spring_force, rtol=1e-12)
    with pytest.raises(ValueError, match=r"initial\[0\] \(spring force\)='50 kg' has dimension \[mass\]"):
        simulate(zv, initial=("50 kg", "0 m/s"), duration="5 s")


def test_law_classes_show_their_parameters_and_a_sweep_grid_is_a_mapping() -> None:
    """Every law class has its parameters in its signature (not (*args, **kwargs)), for help(),
    inspect.signature and a notebook's completion; sweep(d, [('nu', [...])]) is refused at once
    as not a mapping (not 'unhashable type: list' from inside the sweep)."""
    import inspect

    from stickslip import CubicLaw, PhysicalWeakeningLaw
    from stickslip.dynamics.sweep import sweep

    assert str(inspect.signature(WeakeningLaw)) == "(c, p=0.0)"
    assert str(inspect.signature(CubicLaw)) == "(alpha, gamma)"
    assert str(inspect.signature(PhysicalWeakeningLaw)) == "(mu_s, a, b=0.0)"
    assert inspect.signature(WeakeningLaw).bind(3.8).arguments == {"c": 3.8}
    with pytest.raises(TypeError, match=r"grid=\[\('nu', \[0.1, 0.2\]\)\]: expected a mapping of names"):
        sweep(DimensionlessParameters(nu=0.1, law=WeakeningLaw(c=3.8)), [("nu", [0.1, 0.2])])  # type: ignore[arg-type]


def test_a_trajectory_reads_at_a_glance_and_goes_to_xarray_with_its_units() -> None:
    """A Trajectory's repr is one line (samples, span, events, units), not its arrays, and it
    goes to xarray with its units, as a sweep's results do."""
    traj = simulate(zv_parameters(), duration="30 s", n_points=200)
    assert (
        repr(traj) == f"Trajectory({traj.time.size} samples, t = 0..30 s, {traj.event_time.size} events, SI)"
    )
    ds = traj.to_xarray()
    assert ds["spring_force"].attrs["units"] == "N" and ds["time"].attrs["units"] == "s"
    np.testing.assert_array_equal(ds["spring_force"].values, traj.spring_force)
    np.testing.assert_array_equal(ds["event_time"].values, traj.event_time)
    assert list(ds["event_kind"].values) == [str(k) for k in traj.event_kind]
    assert ds["phase"].attrs["flag_meanings"] == "stick slip backward-slip"
    dim = simulate(DimensionlessParameters(nu=0.1, law=WeakeningLaw(c=3.8)), n_points=50).to_xarray()
    assert dim["spring_force"].attrs == {
        "units": "1",
        "long_name": "spring force k (v0 t - x)",
        "scale": "static friction force mu_s W",
    }


def test_a_physical_set_ups_slip_time_bound_may_be_a_time() -> None:
    """cycle(zv, max_slip_time='10 s') takes a time for physical parameters, as simulate's
    duration does, besides a number in the model's units; a wrong dimension is named."""
    zv = zv_parameters()
    scale = zv.scales.time.to("s").magnitude
    given = cycle(zv, max_slip_time="100 s", probe=False)
    same = cycle(zv, max_slip_time=100.0 / scale, probe=False)
    assert given.amplitude == same.amplitude and given.period == same.period
    with pytest.raises(ValueError, match=r"max_slip_time='10 kg' has dimension \[mass\], expected \[time\]"):
        cycle(zv, max_slip_time="10 kg")


def test_results_can_be_keys_and_trajectories_compare_by_identity() -> None:
    """A CycleResult is hashable (its units dict included), so results can be set members or cache
    keys; a Trajectory's == is identity (comparing arrays would raise for two equal runs)."""
    params = DimensionlessParameters(nu=0.5, law=WeakeningLaw(c=3.8))
    first, second = cycle(params, probe=False), cycle(params, probe=False)
    assert first == second and hash(first) == hash(second) and len({first, second}) == 1
    assert first != replace(first, units={"force": "N"})
    traj = simulate(params, duration=20.0)
    again = simulate(params, duration=20.0)
    assert traj == traj and traj != again and len({traj, again}) == 2
    np.testing.assert_allclose(traj.spring_force, again.spring_force)


@pytest.mark.fast
@pytest.mark.parametrize(
    ("value", "positive", "message"),
    [
        ([1.0, math.nan], False, r"x\[1\]=nan: expected a finite value of magnitude at most 1e\+13"),
        ([[0.0, 1.0], [math.inf, 2.0]], False, r"x\[1, 0\]=inf: expected a finite value"),
        ([-1e14, 0.0], False, r"x\[0\]=-100000000000000.0: expected a finite value"),
        ([1e14], False, r"x\[0\]=100000000000000.0: expected a finite value"),
        ([0.5, 0.0], True, r"x\[1\]=0.0: expected a positive finite value"),
        ([0.5, -3.0], True, r"x\[1\]=-3.0: expected a positive finite value"),
    ],
)
def test_arrays_are_checked_entry_by_entry(value: list, positive: bool, message: str) -> None:
    """The two-reduction fast path of finite_array lets nothing through that the entry-wise check refuses."""
    from stickslip.core.checks import finite_array

    with pytest.raises(ValueError, match=message):
        finite_array("x", value, positive=positive)


@pytest.mark.fast
def test_good_arrays_pass_the_check_unchanged() -> None:
    from stickslip.core.checks import finite_array

    a = np.array([-1e13, 0.0, 1e13])
    np.testing.assert_array_equal(finite_array("x", a), a)
    assert finite_array("x", []).size == 0
    assert finite_array("x", [1e-300], positive=True)[0] == 1e-300


def test_a_table_law_from_a_number_is_a_type_error_naming_the_path() -> None:
    from stickslip import TabulatedLaw

    with pytest.raises(TypeError, match=r"path=123: expected the path of a CSV file"):
        TabulatedLaw.from_csv(123)


@pytest.mark.parametrize(("text", "which"), [("0.1,,0.2", "value 2 of 3"), ("0.1,0.2,", "value 3 of 3")])
def test_an_empty_element_of_a_list_is_named(text: str, which: str, tmp_path) -> None:
    from click.testing import CliRunner

    from stickslip.cli import main

    res = CliRunner().invoke(main, ["sweep", "--nu", text, "--c", "3.8", "--out", str(tmp_path / "s.nc")])
    assert res.exit_code == 2
    assert f"nu={text!r}: {which} is empty: expected values separated by single commas" in res.output
    assert not (tmp_path / "s.nc").exists()
