"""rsfmodel's published velocity-step tests reproduced to 2e-8, from the API and the command line.

The expected values are quoted from rsfmodel's own test suite (see ``reference/rsfmodel.py``):
one and two state variables, the aging (Dieterich), slip (Ruina), Perrin-Rice-Zheng and
Nagata laws. rsfmodel's units are um, s and 1/um; ours are SI, converted here by hand.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from reference.rsfmodel import CASES

from stickslip.cli import main
from stickslip.ratestate.model import RateStateParameters
from stickslip.ratestate.protocols import velocity_steps

TOL = 2e-8
# rsfmodel's one-state aging case on the command line (the load-point options follow)
AGING_ONE_CLI = (
    "ratestate",
    "--a",
    "0.005",
    "--b",
    "0.01",
    "--dc",
    "10 um",
    "--v-ref",
    "1 um/s",
    "--mu0",
    "0.6",
)


def _params(case: dict) -> RateStateParameters:
    n = len(case["b"])
    return RateStateParameters(
        a=case["a"],
        b=case["b"] if n > 1 else case["b"][0],
        dc=[f"{d} um" for d in case["dc_um"]] if n > 1 else f"{case['dc_um'][0]} um",
        v_ref="1 um/s",
        mu0=0.6,
        stiffness_per_load=f"{case['k_per_um']} 1/um",
        state_law=case["law"] if n > 1 else case["law"][0],
        nagata_c=case["c"],
    )


def _check(ds: xr.Dataset, case: dict) -> None:
    np.testing.assert_array_equal(ds.time.values, np.arange(41.0))
    np.testing.assert_allclose(ds.friction.values, case["friction"], rtol=0, atol=TOL)
    np.testing.assert_allclose(ds.slip_velocity.values * 1e6, case["slider_velocity_um_s"], rtol=0, atol=TOL)
    np.testing.assert_allclose(
        ds.load_point_displacement.values * 1e6, case["loadpoint_displacement_um"], rtol=0, atol=TOL
    )
    for i, truth in enumerate(case["states_s"]):
        name = "state" if i == 0 else f"state_{i + 1}"
        np.testing.assert_allclose(ds[name].values, truth, rtol=0, atol=TOL, err_msg=name)
    # the step is not a smoothed one: the friction jumps only through the spring
    assert ds.friction.values[10] == pytest.approx(0.6, abs=1e-12)


@pytest.mark.fast
@pytest.mark.parametrize("name", sorted(CASES))
def test_api(name: str) -> None:
    case = CASES[name]
    ds = velocity_steps(_params(case), ["1 um/s", "10 um/s"], durations=["10 s", "30 s"], sample="1 s")
    _check(ds, case)


@pytest.mark.parametrize("name", sorted(CASES))
def test_cli(name: str, tmp_path) -> None:
    case = CASES[name]
    args = ["ratestate", "--a", str(case["a"]), "--v-ref", "1 um/s", "--mu0", "0.6"]
    for b, dc in zip(case["b"], case["dc_um"], strict=True):
        args += ["--b", str(b), "--dc", f"{dc} um"]
    for law in case["law"]:
        args += ["--law", law]
    if case["c"]:
        args += ["--nagata-c", str(case["c"])]
    args += [
        "--stiffness-per-load", f"{case['k_per_um']} 1/um",
        "--steps", "1 um/s,10 um/s", "--durations", "10 s,30 s", "--sample", "1 s",
        "--out", str(tmp_path),
    ]  # fmt: skip
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, res.output
    _check(xr.load_dataset(tmp_path / "ratestate.nc"), case)


def test_cases_cover_the_laws() -> None:
    laws = {(law, len(c["b"])) for c in CASES.values() for law in c["law"]}
    assert {
        ("aging", 1),
        ("aging", 2),
        ("slip", 1),
        ("slip", 2),
        ("prz", 1),
        ("prz", 2),
        ("nagata", 1),
    } <= laws


def test_history_file_equals_steps(tmp_path) -> None:
    """A load-point history read from a CSV (velocities, or displacements) gives the same run."""
    case = CASES["TestDeiterichOneStateVar"]
    t = np.arange(41.0)
    v = np.where(t < 10, 1.0, 10.0)
    (tmp_path / "v.csv").write_text(
        "time [s],load-point velocity [um/s]\n" + "".join(f"{a},{b}\n" for a, b in zip(t, v, strict=True))
    )
    x = np.concatenate([[0.0], np.cumsum(v[:-1])])
    (tmp_path / "x.csv").write_text(
        "time [s],load-point displacement [mm]\n"
        + "".join(f"{a},{b / 1000}\n" for a, b in zip(t, x, strict=True))
    )
    for f in ("v.csv", "x.csv"):
        out = tmp_path / f"out-{f}"
        args = list(AGING_ONE_CLI)
        args += ["--stiffness-per-load", "1e-3 1/um", "--history", str(tmp_path / f), "--sample", "1 s"]
        res = CliRunner().invoke(main, [*args, "--out", str(out)])
        assert res.exit_code == 0, res.output
        _check(xr.load_dataset(out / "ratestate.nc"), case)


@pytest.mark.parametrize(
    ("name", "formula"),
    [
        ("TestDeiterichOneStateVar", "1 - v*phi/dc"),
        ("TestRuinaOneStateVar", "-(v*phi/dc)*log(v*phi/dc)"),
        ("TestDeiterichTwoStateVar", "1 - v*phi/dc"),
    ],
)
def test_user_law_from_a_formula(name: str, formula: str, tmp_path) -> None:
    """The aging and slip laws typed as formulas for dPhi/dt reproduce rsfmodel's values too."""
    case = CASES[name]
    p = _params(case)
    user = RateStateParameters(
        a=p.a,
        b=p.b,
        dc=p.dc,
        v_ref=p.v_ref,
        mu0=p.mu0,
        stiffness_per_load=p.stiffness_per_load,
        state_law=formula,
    )
    _check(velocity_steps(user, ["1 um/s", "10 um/s"], durations=["10 s", "30 s"], sample="1 s"), case)
    if name == "TestDeiterichOneStateVar":
        assert float(user.critical_kw.to("1/m").magnitude) == pytest.approx(500.0, rel=1e-6)
        args = list(AGING_ONE_CLI)
        args += ["--stiffness-per-load", "1e-3 1/um", "--law", formula, "--steps", "1 um/s,10 um/s"]
        args += ["--durations", "10 s,30 s", "--sample", "1 s", "--out", str(tmp_path)]
        res = CliRunner().invoke(main, args)
        assert res.exit_code == 0, res.output
        _check(xr.load_dataset(tmp_path / "ratestate.nc"), case)


@pytest.mark.parametrize(
    ("law", "message"),
    [
        ("agng", "unknown name 'agng'"),
        ("1 - v/dc", "must depend on phi"),
        ("1 + v*phi/dc", "no stable steady state"),
        # Python's math raises OverflowError / ValueError in the search: caught, said in words
        ("exp(phi) - v*phi/dc", "no stable steady state"),
        ("log(1 - phi) - v*phi/dc", "no stable steady state"),
        ("__import__('os')", "not a formula|not allowed|allowed"),
    ],
)
def test_bad_user_law(law: str, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        p = RateStateParameters(
            a=0.01, b=0.015, dc="10 um", v_ref="1 um/s", mu0=0.6, stiffness_per_load="1 1/mm", state_law=law
        )
        velocity_steps(p, ["1 um/s", "10 um/s"], durations=["1 s", "1 s"])
