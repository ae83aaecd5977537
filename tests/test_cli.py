"""The command line: outputs, and a clear error for every bad option."""

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from reference.one_block import coulomb_cycle, reference_cycle

import stickslip as ss
from stickslip.cli import main
from stickslip.cli.options import OnceCommand

PHYS = [
    "--v0",
    "20 um/s",
    "--mass",
    "231 g",
    "--stiffness",
    "62 N/m",
    "--load",
    "196 mN",
    "--mu0",
    "0.46",
    "--a",
    "160 s/m",
]


def run(*args: str):
    return CliRunner().invoke(main, list(args))


@pytest.mark.fast
def test_cycle_json_dimensionless() -> None:
    res = run("cycle", "--nu", "0.001", "--law", "weakening", "--c", "3.8", "--json")
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    assert d["regime"] == "stick-slip"
    # the SciPy reference (solve_ivp, rtol 1e-13) gives 1.2152321002; the engine's rtol is 1e-10
    assert d["amplitude"] == pytest.approx(
        reference_cycle("weakening", {"c": 3.8}, 0.001).amplitude, rel=1e-8
    )
    assert 0.99 < d["stick_fraction"] < 1.0
    assert d["units"]["force"].startswith("static friction force")
    assert d["units"]["time"] == "sqrt(m/k)"
    assert {k: d["parameters"][k] for k in ("nu", "law", "c", "p")} == {
        "nu": 0.001,
        "law": "weakening",
        "c": 3.8,
        "p": 0.0,
    }
    assert d["parameters"]["description"].startswith("weakening: f(w) = 1/(1 + c*w) + p*w")


def test_cycle_json_physical_matches_dimensionless() -> None:
    res = run("cycle", *PHYS, "--json")
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    assert d["units"] == {"force": "N", "time": "s", "length": "m", "velocity": "m/s", "energy": "J"}
    dim = d["parameters"]["dimensionless"]
    # by hand: beta = sqrt(k m)/(mu_s W), nu = beta v0, c = a / beta
    beta = (0.231 * 62) ** 0.5 / (0.46 * 0.196)
    assert dim["nu"] == pytest.approx(beta * 20e-6, rel=1e-12)
    assert dim["c"] == pytest.approx(160 / beta, rel=1e-12)
    res2 = run("cycle", "--nu", repr(beta * 20e-6), "--c", repr(160 / beta), "--json")
    d2 = json.loads(res2.output)
    force = 0.46 * 0.196
    time = (0.231 / 62) ** 0.5
    length = force / 62  # mu_s W / k (m)
    velocity = force / (62 * 0.231) ** 0.5  # mu_s W / sqrt(k m) (m/s)
    energy = force**2 / 62  # (mu_s W)^2 / k (J)
    for key, scale in (
        ("amplitude", force),
        ("max_force", force),
        ("min_force", force),
        ("period", time),
        ("stick_time", time),
        ("slip_distance", length),
        ("peak_velocity", velocity),
        ("drive_work", energy),
        ("friction_work", energy),
    ):
        assert d[key] == pytest.approx(d2[key] * scale, rel=1e-9), key


@pytest.mark.parametrize(
    "args",
    [
        ["--law", "cubic", "--nu", "0.05", "--alpha", "0.5", "--gamma", "0.1"],
        ["--law", "coulomb", "--nu", "0.05", "--kinetic", "0.3"],
        [
            "--law",
            "cubic",
            "--v0",
            "1 mm/s",
            "--mass",
            "1 kg",
            "--stiffness",
            "100 N/m",
            "--load",
            "1 N",
            "--mu-s",
            "0.5",
            "--k1",
            "2 s/m",
            "--k3",
            "10 s**3/m**3",
        ],
        [
            "--law",
            "coulomb",
            "--v0",
            "1 mm/s",
            "--mass",
            "1 kg",
            "--stiffness",
            "100 N/m",
            "--load",
            "1 N",
            "--mu-s",
            "0.5",
            "--mu-k",
            "0.3",
        ],
        ["--preset", "zv", "--v0", "50 um/s", "--b", "100 s/m"],
    ],
)
def test_cycle_every_law(args: list[str]) -> None:
    res = run("cycle", *args, "--json")
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    # every case is stick-slip; the cubic and zv ones against plain SciPy (tests/reference/one_block.py),
    # the physical ones in units of mu_s W and sqrt(m/k) worked out by hand
    assert d["regime"] == "stick-slip"
    cases = {
        "cubic": ({"alpha": 0.5, "gamma": 0.1}, 0.05, 1.0, 1.0),
        # mu_s W = 0.5 N, beta = 20 s/m: alpha = k1/(mu_s beta), gamma = k3/(mu_s beta^3)
        "cubic-physical": ({"alpha": 2 / (0.5 * 20), "gamma": 10 / (0.5 * 20**3)}, 20 * 1e-3, 0.5, 0.1),
    }
    if "--preset" in args:  # zv: beta = 42 s/m, c = a/beta, p = b/beta, mu0 W = 0.46 x 0.196 N
        m = (42 * 0.46 * 0.196) ** 2 / 62  # beta = sqrt(k m)/(mu0 W) = 42 s/m with k = 62 N/m
        ref = reference_cycle("weakening", {"c": 160 / 42, "p": 100 / 42}, 42 * 50e-6)
        assert d["amplitude"] == pytest.approx(ref.amplitude * 0.46 * 0.196, rel=1e-8)
        assert d["period"] == pytest.approx(ref.period * math.sqrt(m / 62), rel=1e-8)
    elif "cubic" in args:
        law_params, nu, force, time = cases["cubic" if "--nu" in args else "cubic-physical"]
        ref = reference_cycle("cubic", law_params, nu)
        assert d["amplitude"] == pytest.approx(ref.amplitude * force, rel=1e-8)
        assert d["period"] == pytest.approx(ref.period * time, rel=1e-8)
    elif "coulomb" in args and "--nu" in args:  # the closed form (tests/reference/one_block.py)
        exact = coulomb_cycle(0.05, 0.3)
        assert d["amplitude"] == pytest.approx(exact["amplitude"], rel=1e-9)
        assert d["period"] == pytest.approx(exact["period"], rel=1e-9)
    elif "coulomb" in args:  # mu_s W = 0.5 N, beta = sqrt(100 * 1)/0.5 = 20 s/m, sqrt(m/k) = 0.1 s
        exact = coulomb_cycle(20.0 * 1e-3, 0.3 / 0.5)
        assert d["amplitude"] == pytest.approx(exact["amplitude"] * 0.5, rel=1e-9)
        assert d["period"] == pytest.approx(exact["period"] * 0.1, rel=1e-9)
    assert {"regime", "amplitude", "period", "stick_fraction", "units"} <= set(d)


def test_cycle_text_output() -> None:
    res = run("cycle", "--nu", "0.01", "--c", "2")
    assert res.exit_code == 0
    assert "regime          stick-slip" in res.output


def test_simulate_writes_csv_and_figures(tmp_path: Path) -> None:
    res = run("simulate", "--out", str(tmp_path), "--points", "400")
    assert res.exit_code == 0, res.output
    with open(tmp_path / "trajectory.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["time [s]", "position [m]", "velocity [m/s]", "spring_force [N]", "phase"]
    assert len(rows) > 400
    assert {r[4] for r in rows[1:]} == {"stick", "slip"}
    for name in ("spring_force.png", "spring_force.svg"):
        assert (tmp_path / name).stat().st_size > 5000


def test_simulate_out_must_be_a_folder(tmp_path: Path) -> None:
    f = tmp_path / "a_file"
    f.write_text("x")
    res = run("simulate", "--nu", "0.1", "--c", "3", "--out", str(f))
    assert res.exit_code == 2
    assert "is a file" in res.output


def test_simulate_dimensionless_duration(tmp_path: Path) -> None:
    res = run("simulate", "--nu", "0.1", "--c", "3", "--duration", "50", "--out", str(tmp_path), "--no-plot")
    assert res.exit_code == 0, res.output
    header = (tmp_path / "trajectory.csv").read_text().splitlines()[0]
    assert header.startswith("time [sqrt(m/k)]")
    # the count of stick phases is the CSV's, the stick from the start included (it said one less)
    with (tmp_path / "trajectory.csv").open() as f:
        phases = [row["phase"] for row in csv.DictReader(line for line in f if not line.startswith("#"))]
    runs = [k for i, k in enumerate(phases) if i == 0 or k != phases[i - 1]]
    assert f"{runs.count('stick')} stick phases simulated" in res.output and runs[0] == "stick"


BAD = [
    (["cycle"], "no parameters"),
    (["cycle", "--nu", "0.01"], "needs --c"),
    (["cycle", "--nu", "-0.01", "--c", "3"], "nu=-0.01 must be positive"),
    (["cycle", "--nu", "nan", "--c", "3"], "nu=nan is NaN"),
    (["cycle", "--nu", "inf", "--c", "3"], "nu=inf is infinite"),
    (["cycle", "--nu", "0.01", "--c", "0"], "c=0.0 must be positive"),
    (["cycle", "--nu", "0.01", "--c", "3", "--p", "-1"], "p=-1.0 must be non-negative"),
    (
        ["cycle", "--nu", "0.01", "--alpha", "1"],
        "--alpha belongs to --law carlson-langer/cubic, not --law weakening",
    ),
    (["cycle", "--law", "cubic", "--nu", "0.01", "--alpha", "1"], "needs --gamma"),
    (
        ["cycle", "--law", "cubic", "--nu", "0.01", "--alpha", "1", "--gamma", "0"],
        "gamma=0.0 must be positive",
    ),
    (["cycle", "--law", "coulomb", "--nu", "0.01", "--kinetic", "1.2"], "kinetic=1.2"),
    (["cycle", "--nu", "0.01", "--c", "3", "--v0", "1 um/s"], "give one kind only"),
    (["cycle", *PHYS[:-2]], "needs --a"),
    (["cycle", *PHYS[2:]], "needs --v0"),
    (["cycle", *PHYS[:1], "5 m", *PHYS[2:]], "v0='5 m' has dimension"),
    (["cycle", *PHYS[:3], "231", *PHYS[4:]], "mass='231' has no unit"),
    (["cycle", *PHYS[:5], "-62 N/m", *PHYS[6:]], "stiffness='-62 N/m' must be positive"),
    (["cycle", *PHYS[:7], "196 mN/m", *PHYS[8:]], "load='196 mN/m' has dimension"),
    (["cycle", *PHYS[:9], "0", *PHYS[10:]], "mu0=0.0 must be positive"),
    (["cycle", *PHYS[:11], "160 m/s"], "a='160 m/s' has dimension"),
    (["cycle", *PHYS, "--b", "-3 s/m"], "b='-3 s/m' must be non-negative"),
    (["cycle", *PHYS, "--k1", "1 s/m"], "--k1 belongs to --law cubic"),
    (
        ["cycle", "--law", "cubic", *PHYS[:8], "--mu-s", "0.5", "--k1", "1 s/m", "--k3", "1 s/m"],
        "k3='1 s/m' has dimension",
    ),
    (["cycle", "--law", "coulomb", *PHYS[:8], "--mu-s", "0.5", "--mu-k", "0.7"], "mu_k=0.7"),
    (["cycle", "--v0", "12 bananas", *PHYS[2:]], "not a quantity"),
    (["cycle", "--nu", "0.01", "--c", "3", "--rtol", "0"], "rtol=0.0"),
    (["cycle", "--nu", "0.01", "--c", "3", "--rtol", "0.5"], "rtol=0.5"),
    (["cycle", "--nu", "0.01", "--c", "3", "--atol", "-1"], "atol=-1.0"),
    (["cycle", "--nu", "abc", "--c", "3"], "'abc' is not a valid float"),
    (["cycle", "--preset", "bri"], "'bri' is not 'zv'"),
    (
        ["cycle", "--law", "cubic", *PHYS[:8], "--mu-s", "-0.5", "--k1", "1 s/m", "--k3", "1 s**3/m**3"],
        "mu_s=-0.5 must be positive",
    ),
    (
        ["cycle", "--law", "cubic", *PHYS[:8], "--mu-s", "0.5", "--k1", "1 kg", "--k3", "1 s**3/m**3"],
        "k1='1 kg' has dimension",
    ),
    (
        ["cycle", "--law", "coulomb", "--nu", "0.01", "--kinetic", "0.3", "--c", "2"],
        "--c belongs to --law weakening",
    ),
    (["cycle", "--law", "dieterich", "--nu", "0.1"], "'dieterich' is not one of"),
    (
        ["simulate", "--nu", "0.1", "--c", "3", "--duration", "10 s", "--no-plot"],
        "expected a number for dimensionless input",
    ),
    (["simulate", "--preset", "zv", "--duration", "10 m", "--no-plot"], "duration='10 m' has dimension"),
    (["simulate", "--preset", "zv", "--duration", "-3 s", "--no-plot"], "must be positive"),
    (["simulate", "--nu", "0.1", "--c", "3", "--points", "1", "--no-plot"], "n_points=1"),
    (["simulate", "--nu", "0.1", "--c", "3", "--cycles", "0", "--no-plot"], "cycles=0.0"),
    # a duration beyond the engine's bound is named by the option, as given (not as t_eval[0])
    (
        ["simulate", "--nu", "0.3", "--c", "3.8", "--duration", "1e300", "--no-plot"],
        "duration=1e+300: 1e+300 in",
    ),
    (["simulate", "--preset", "zv", "--duration", "1e30 s", "--no-plot"], "duration='1e30 s': 1.64e+31 in"),
    # physical options alone are not the zv set-up that no options give: say how to take it
    (["simulate", "--v0", "20 um/s", "--no-plot"], "needs --mu-s (or add --preset zv: the paper's set-up"),
    # options that reach nothing in that combination are refused, not dropped without a word
    (["simulate", "--nu", "0.1", "--c", "3", "--duration", "50", "--cycles", "3"], "--duration or --cycles"),
    (["cycle", "--law", "expr", "--mu", "0.46/(1+160*v)", "--preset", "zv", "--mu-s", "0.9"], "is --static"),
    (["cycle", "--law", "expr", "--mu", "0.46/(1+160*v)", "--preset", "zv", "--a", "1 s/m"], "--a: not opt"),
    (["regimes", "--c", "3.8", "--nu-min", "0.05", "--nu-max", "2", "--rtol", "1e-8"], "own tolerances"),
    (["regimes", "--c", "3.8", "--nu-min", "0.05", "--nu-max", "2", "--map-n", "5"], "--map-n goes with"),
    (["cycle", "--law", "expr", "--f", "1/(1+3*w)", "--nu", "0.1", "--interpolation", "cubic"], "law table"),
    (
        [
            "chain",
            "--law",
            "weakening",
            "--blocks",
            "5",
            "--events",
            "3",
            "--nu",
            "0.1",
            "--c",
            "3",
            "--seeds",
            "1,2",
            "--resume",
        ],
        "an ensemble resumes from its --store",
    ),
]


@pytest.mark.fast
@pytest.mark.parametrize(("args", "message"), BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_input_gives_a_clear_error(args: list[str], message: str, tmp_path: Path) -> None:
    if args[0] == "simulate":
        args = [*args, "--out", str(tmp_path)]
    res = run(*args)
    assert res.exit_code == 2, res.output
    assert message in res.output
    assert res.output.count("\n") == 1 and res.output.startswith("Error: "), res.output  # one line
    assert "Traceback" not in res.output
    assert res.exception is None or isinstance(res.exception, SystemExit)


def test_failed_computation_is_reported_without_traceback(monkeypatch: pytest.MonkeyPatch) -> None:
    import stickslip.dynamics.trajectory as tr

    def boom(*args, **kwargs):
        raise RuntimeError("integration failed: step-size-too-small (try a larger rtol)")

    monkeypatch.setattr(tr, "simulate", boom)
    res = run("simulate", "--nu", "0.1", "--c", "3", "--no-plot")
    assert res.exit_code == 1
    assert "integration failed" in res.output
    assert "Traceback" not in res.output


def test_sweep_command(tmp_path: Path) -> None:
    out = tmp_path / "zv.nc"
    res = run(
        "sweep",
        "--preset",
        "zv",
        "--v0",
        "5 um/s..1000 um/s",
        "--num",
        "6",
        "--log",
        "--b",
        "0 s/m,100 s/m",
        "--out",
        str(out),
        "--quiet",
    )
    assert res.exit_code == 0, res.output
    from stickslip.dynamics.sweep import load_sweep

    ds = load_sweep(out)
    assert dict(ds.sizes) == {"v0": 6, "b": 2}
    np.testing.assert_allclose(ds["v0"].values, np.geomspace(5, 1000, 6))
    assert (tmp_path / "zv.png").stat().st_size > 5000
    assert (tmp_path / "zv.svg").stat().st_size > 5000


def test_sweep_command_dimensionless_and_beta(tmp_path: Path) -> None:
    res = run(
        "sweep",
        "--nu",
        "0.001..0.1",
        "--num",
        "3",
        "--c",
        "1,3.8",
        "--out",
        str(tmp_path / "d.nc"),
        "--no-plot",
    )
    assert res.exit_code == 0, res.output
    from stickslip.dynamics.sweep import load_sweep

    ds = load_sweep(tmp_path / "d.nc")
    ref = reference_cycle("weakening", {"c": 3.8}, 0.001)
    assert float(ds.amplitude.sel(nu=0.001, c=3.8)) == pytest.approx(ref.amplitude, rel=1e-8)
    res = run(
        "sweep",
        "--preset",
        "zv",
        "--a",
        "250 s/m",
        "--beta",
        "42 s/m,158 s/m,418 s/m",
        "--v0",
        "5..1000 um/s",
        "--num",
        "4",
        "--log",
        "--out",
        str(tmp_path / "b.nc"),
        "--no-plot",
    )
    assert res.exit_code == 0, res.output
    ds = load_sweep(tmp_path / "b.nc")
    # beta fixes the mass at every point: the dimensionless form is c = a/beta, nu = beta v0 (by hand)
    for beta in (42.0, 418.0):
        ref = reference_cycle("weakening", {"c": 250.0 / beta}, beta * 5e-6)
        amp = float(ds.amplitude.sel(beta=beta, v0=5.0))
        assert amp == pytest.approx(ref.amplitude * 0.46 * 0.196, rel=1e-8)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--preset", "zv"], "nothing to sweep"),
        (["--preset", "zv", "--v0", "5 um/s..1000 m"], "has dimension"),
        (["--preset", "zv", "--v0", "5 um/s..1000 um/s..3"], "expected a range"),
        (["--preset", "zv", "--v0", "0..1000 um/s", "--log"], "must be positive"),
        (["--nu", "-1..1", "--c", "3", "--log"], "positive ends"),
        (["--preset", "zv", "--v0", "5..1000 um/s", "--num", "1"], "at least 2 points"),
        (["--nu", "0.1..x", "--c", "3"], "nu='x': expected a number"),
        (["--preset", "zv", "--mass", "1 kg", "--beta", "42 s/m,60 s/m"], "not both"),
    ],
)
def test_sweep_bad_input(args: list[str], message: str, tmp_path: Path) -> None:
    res = run("sweep", *args, "--out", str(tmp_path / "x.nc"), "--no-plot")
    assert res.exit_code == 2, res.output
    assert message in res.output
    assert "Traceback" not in res.output


def test_sweep_warns_where_num_and_log_space_no_range(tmp_path: Path) -> None:
    """--num and --log space ranges 'A..B' only: over lists they did nothing, without a word."""
    lists = run("sweep", "--nu", "0.1,0.2", "--c", "3", "--num", "5", "--log", "--out", f"{tmp_path}/a.nc")
    assert lists.exit_code == 0, lists.output
    assert "warning: --num and --log space ranges" in lists.output
    ranged = run("sweep", "--nu", "0.1..0.2", "--c", "3", "--num", "2", "--out", str(tmp_path / "b.nc"))
    assert ranged.exit_code == 0 and "warning" not in ranged.output, ranged.output


def test_file_flags_warn_where_no_file_is_written(tmp_path: Path) -> None:
    """--overwrite and --no-plot act on --out's files: without --out they reached nothing, unsaid."""
    store = run(
        "sweep", "--nu", "0.1,0.2", "--c", "3", "--store", f"{tmp_path}/s.zarr", "--no-plot", "--overwrite"
    )
    assert store.exit_code == 0, store.output
    assert "warning: --no-plot and --overwrite do nothing with --store alone" in store.output
    written = run("sweep", "--nu", "0.1,0.2", "--c", "3", "--store", f"{tmp_path}/t.zarr",
                  "--out", f"{tmp_path}/t.nc", "--no-plot", "--overwrite")  # fmt: skip
    assert written.exit_code == 0 and "warning" not in written.output, written.output
    chain = [
        "chain",
        "--law",
        "weakening",
        "--blocks",
        "3",
        "--events",
        "3",
        "--c",
        "3",
        "--nu",
        "0.1",
        "--quiet",
        "--json",
    ]
    one = run(*chain, "--no-plot")
    assert one.exit_code == 0 and "warning: --no-plot does nothing without --out" in one.output, one.output
    ensemble = run(*chain, "--seeds", "1..2", "--overwrite")
    assert ensemble.exit_code == 0 and "warning: --overwrite does nothing without --out" in ensemble.output
    regimes = run("regimes", "--c", "3", "--nu-min", "0.2", "--nu-max", "0.4", "--overwrite")
    assert regimes.exit_code == 0 and "warning: --overwrite does nothing without --out" in regimes.output
    quiet = run("regimes", "--c", "3", "--nu-min", "0.2", "--nu-max", "0.4")
    assert quiet.exit_code == 0 and "warning" not in quiet.output, quiet.output


def test_a_single_valued_option_given_twice_is_refused() -> None:
    """``--c 3 --c 4`` (and ``--json --no-json``-style pairs) is refused by name by every command
    of the group: click keeps the last without a word, a set-up the user did not ask for.
    Repeatable options and plain flags stay."""
    from stickslip.cli.commands import main as group

    cases = {
        "--c": ("cycle", "--nu", "0.01", "--c", "3", "--c", "4"),  # a law's option (LawCommand)
        "--nu": ("cycle", "--nu", "0.01", "--nu", "0.02"),
        "--a": ("dulac", "--a", "0.01", "--a", "0.02", "--b", "0.015", "--kappa", "1"),  # plain command
        "--v-ref": ("ratestate", "--a", "0.01", "--b", "0.015", "--dc", "1e-5", "--v-ref", "1e-6",
                    "--v-ref", "2e-6"),
    }  # fmt: skip
    for name, args in cases.items():
        res = run(*args)
        assert res.exit_code == 2, (args, res.output)
        assert f"option {name} is given more than once" in res.output, res.output
    for name, command in group.commands.items():  # not only the commands above
        assert isinstance(command, OnceCommand), name
    # options that take several values, and a flag given twice, are not refused
    res = run("ratestate", "--a", "0.01", "--b", "0.01", "--b", "0.005", "--dc", "1e-5", "--dc", "1e-4",
              "--v-ref", "1 um/s", "--help")  # fmt: skip
    assert res.exit_code == 0, res.output
    res = run("cycle", "--nu", "0.01", "--c", "3", "--json", "--json")
    assert res.exit_code == 0 and json.loads(res.output)["parameters"]["c"] == 3.0, res.output


def test_a_simulation_that_runs_out_of_phases_or_steps_says_which_and_what_to_change(tmp_path: Path) -> None:
    """A run that exhausts its phases or steps names the limit and --duration (not only
    'too-many-phases' or 'try a larger rtol'): a pure-slip run is one slip phase however long,
    which no rtol fixes. The default duration of a start beyond the backward threshold covers
    its stick of -s0/nu (1e6/nu from s0 = -1e6)."""
    res = run(
        "simulate", "--nu", "0.3", "--c", "3.8", "--duration", "1e7", "--no-plot", "--out", str(tmp_path)
    )
    assert res.exit_code == 1 and "Traceback" not in res.output
    assert (
        "more than 100,000 stick and slip phases before t = 1e+07 (sqrt(m/k)), the end of duration="
        in res.output
    )
    args = ["--law", "cubic", "--alpha", "0.5", "--gamma", "1", "--nu", "0.39", "--duration", "1e9"]
    res = run("simulate", *args, "--no-plot", "--out", str(tmp_path))
    assert res.exit_code == 1 and "Traceback" not in res.output
    assert "one slip phase needed more than 2,000,000 steps" in res.output and "duration=" in res.output
    assert "never sticks" in res.output
    dp = ss.DimensionlessParameters(nu=0.3, law=ss.WeakeningLaw(c=3.8, p=0.0))
    period = ss.cycle(dp).period
    traj = ss.simulate(dp, initial=(-1e6, 0.0))  # ran out of phases
    assert traj.time[-1] == pytest.approx(2.0 / 0.3 + 3.0 * period, rel=1e-6)
    traj = ss.simulate(dp, initial=(-0.5, 0.0))  # stuck until s = 1: 1.5 / nu, then three cycles
    assert traj.time[-1] == pytest.approx(1.5 / 0.3 + 3.0 * period, rel=1e-6)
    traj = ss.simulate(ss.zv_parameters(), duration="1 min", n_points=50)
    assert traj.time[-1] == 60.0  # it ended at 60.00000000000001 s
    # a start at rest beyond a threshold breaks away at t = 0 and says so, as after a stop
    for start, kind in (((2.0, 0.0), "breakaway"), ((-1.5, 0.0), "backward-slip"), ((1.0, 0.0), "breakaway")):
        traj = ss.simulate(dp, initial=start, duration=10.0)
        assert traj.event_time[0] == 0.0 and traj.event_kind[0] == kind and traj.event_force[0] == start[0]
    assert ss.simulate(dp, duration=10.0).event_time[0] == pytest.approx(1.0 / 0.3, rel=1e-15)
