"""A user's own friction law: a formula (``--law expr``) or a measured table (``--law table``).

A formula equal to a built-in law gives the built-in law's results to 1e-9, through the
generated and compiled engine; a dense table of the paper's F1 gives them to 1e-3.
"""

from __future__ import annotations

import json
import math
import pickle
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from reference.one_block import coulomb_cycle
from sympy import sstr as sympy_str

import stickslip as ss
from stickslip.cli import main
from stickslip.dynamics.sweep import sweep
from stickslip.io.errors import DataError
from stickslip.laws import ExpressionLaw, PhysicalExpressionLaw, TabulatedLaw

NUMBERS = (
    "amplitude",
    "period",
    "stick_fraction",
    "stick_time",
    "slip_distance",
    "peak_velocity",
    "max_force",
    "min_force",
    "drive_work",
    "friction_work",
    "transient_time",
    "multiplier",
)


def run(*args: str) -> object:
    return CliRunner().invoke(main, list(args))


def _same_numbers(a: dict, b: dict, rel: float) -> None:
    for k in NUMBERS:
        x, y = a[k], b[k]
        if x is None or y is None:
            assert x is None and y is None, k
        else:
            assert x == pytest.approx(y, rel=rel, abs=1e-12), k
    assert a["regime"] == b["regime"] and a["status"] == b["status"] == "ok"


# --------------------------------------------------------------------------- formulas: the commands


@pytest.mark.slow
def test_expression_equals_the_builtin_law_on_the_command_line() -> None:
    expr = run("cycle", "--law", "expr", "--f", "1/(1 + 3.8*w) + 0.5*w", "--nu", "0.3", "--json")
    builtin = run("cycle", "--law", "weakening", "--c", "3.8", "--p", "0.5", "--nu", "0.3", "--json")
    assert expr.exit_code == 0, expr.output
    assert builtin.exit_code == 0, builtin.output
    a, b = json.loads(expr.output), json.loads(builtin.output)
    _same_numbers(a, b, 1e-9)
    assert a["parameters"]["law"] == "expr"


@pytest.mark.slow
def test_expression_gives_the_same_regimes() -> None:
    args = ("--nu-min", "0.05", "--nu-max", "2", "--n", "41", "--json")
    expr = run("regimes", "--law", "expr", "--f", "1/(1 + 3.8*w) + 0.5*w", *args)
    builtin = run("regimes", "--law", "weakening", "--c", "3.8", "--p", "0.5", *args)
    assert expr.exit_code == 0, expr.output
    a, b = json.loads(expr.output), json.loads(builtin.output)
    assert len(a["hopf"]) == len(b["hopf"]) == 1
    assert a["hopf"][0]["nu"] == pytest.approx(b["hopf"][0]["nu"], rel=1e-9)
    # the closed form: f'(nu) = -c/(1 + c nu)^2 + p = 0
    assert a["hopf"][0]["nu"] == pytest.approx((math.sqrt(3.8 / 0.5) - 1) / 3.8, rel=1e-9)
    assert a["hopf"][0]["criticality"] == b["hopf"][0]["criticality"]
    assert [iv["regime"] for iv in a["intervals"]] == [iv["regime"] for iv in b["intervals"]]
    for x, y in zip(a["intervals"], b["intervals"], strict=True):
        assert x["nu_min"] == pytest.approx(y["nu_min"], rel=1e-9)
        assert x["nu_max"] == pytest.approx(y["nu_max"], rel=1e-9)


@pytest.mark.slow
def test_physical_expression_reproduces_the_zv_setup() -> None:
    expr = run("cycle", "--law", "expr", "--mu", "0.46/(1 + 160*v)", "--preset", "zv", "--json")
    builtin = run(
        "cycle", "--law", "weakening", "--mu0", "0.46", "--a", "160 s/m", "--preset", "zv", "--json"
    )
    assert expr.exit_code == 0, expr.output
    _same_numbers(json.loads(expr.output), json.loads(builtin.output), 1e-9)


@pytest.mark.slow
def test_dense_table_of_f1_reproduces_the_zv_setup(tmp_path: Path) -> None:
    v = np.linspace(0.0, 50.0, 600)  # mm/s: beyond the peak velocity of the zv cycle (14 mm/s)
    path = tmp_path / "mu_v.csv"
    path.write_text(
        "velocity [mm/s],friction coefficient [1]\n"
        + "".join(f"{float(x)!r},{0.46 / (1 + 160 * float(x) * 1e-3)!r}\n" for x in v)
    )
    table = run("cycle", "--law", "table", "--table", str(path), "--preset", "zv", "--json")
    builtin = run(
        "cycle", "--law", "weakening", "--mu0", "0.46", "--a", "160 s/m", "--preset", "zv", "--json"
    )
    assert table.exit_code == 0, table.output
    _same_numbers(json.loads(table.output), json.loads(builtin.output), 1e-3)


# --------------------------------------------------------------------------- formulas from Python


def test_expression_with_parameters_equals_the_builtin_law() -> None:
    law = ExpressionLaw("1/(1 + c*w) + p*w", c=3.8, p=0.5)
    assert law.params == {"c": 3.8, "p": 0.5}
    for nu in (0.01, 0.3):
        a = ss.cycle(ss.DimensionlessParameters(nu=nu, law=law))
        b = ss.cycle(ss.DimensionlessParameters(nu=nu, law=ss.WeakeningLaw(c=3.8, p=0.5)))
        assert a.amplitude == pytest.approx(b.amplitude, rel=1e-9)
        assert a.period == pytest.approx(b.period, rel=1e-9)
    # the parameters are values, not code: a sweep over c runs one compiled engine
    grid = {"nu": [0.01, 0.02], "c": [2.0, 3.8]}
    ds = sweep(ss.DimensionlessParameters(nu=0.01, law=law), grid, progress=False)
    ref = sweep(ss.DimensionlessParameters(nu=0.01, law=ss.WeakeningLaw(c=3.8, p=0.5)), grid, progress=False)
    np.testing.assert_allclose(ds.amplitude.values, ref.amplitude.values, rtol=1e-9)


@pytest.mark.slow
def test_constant_expression_with_a_static_level_is_coulomb_friction() -> None:
    """``f = 0.5`` with ``static=1``: a drop at the onset, the closed-form Coulomb cycle."""
    law = ExpressionLaw("0.5", static=1)
    assert law.kinetic_limit == 0.5
    r = ss.cycle(ss.DimensionlessParameters(nu=0.05, law=law), probe=False)
    exact = coulomb_cycle(0.05, 0.5)
    assert r.amplitude == pytest.approx(exact["amplitude"], rel=1e-9)
    assert r.period == pytest.approx(exact["period"], rel=1e-9)


def test_static_threshold_in_other_units_rescales_the_formula() -> None:
    """``f = 2/(1 + c w)`` with static 2: in units of the static friction, ``1/(1 + 2 c w)``."""
    law = ExpressionLaw("2/(1 + c*w)", static=2, c=1.5)
    w = np.linspace(0, 3, 7)
    np.testing.assert_allclose(law.forward(w), 1 / (1 + 3.0 * w), rtol=1e-14)


@pytest.mark.fast
@pytest.mark.parametrize(
    ("text", "params", "message"),
    [
        ("__import__('os').system('touch PWNED')", {}, "not an allowed function"),
        ("w.__class__", {}, "is not allowed in a formula"),
        ("(lambda: 1)()", {}, "not an allowed function"),
        ("[1, 2][0] + w", {}, "is not allowed in a formula"),
        ("'abc'", {}, "is not a number"),
        ("exp(w, 2)", {}, "takes exactly one argument"),
        ("foo(w)", {}, "foo(...) is not an allowed function"),
        ("1/(1 + w", {}, "is not a formula"),
        ("", {}, "empty"),
        ("1/(1 + c*w)", {}, "give the value of c"),
        ("1/(1 + w)", {"c": 1.0}, "has no parameter 'c'"),
        ("0.5/(1 + w)", {}, "f(0+) = 0.5"),
        ("2/(1 + w)", {"static": 1}, "exceeds the static"),
        # a pole on a probe velocity itself is named as a pole (numpy 2.4's geomspace hits 1 and 1e-5)
        ("1/(1 - w)", {}, "has a pole at w = 1, where 1 - w is zero"),
        ("1 + 0.01*sqrt(w - 2)", {}, "is not finite at w = 0"),
        ("1/(1 + c*w)", {"c": math.nan}, "finite number"),
        ("1/(1 + _c*w)", {}, "leading underscore"),
    ],
)
def test_bad_formulas_get_one_line(
    text: str, params: dict, message: str, tmp_path: Path, monkeypatch
) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=None) as err:
        ExpressionLaw(text, **params)
    assert message in str(err.value)
    assert "\n" not in str(err.value)
    assert not (tmp_path / "PWNED").exists()


def test_physical_formula_units_are_checked() -> None:
    with pytest.raises(ValueError, match="not dimensionally consistent"):
        PhysicalExpressionLaw("0.46/(1 + a*v)", a="160 m/s")  # (m/s)**2 or m/s added to 1
    with pytest.raises(ValueError, match="not dimensionally consistent"):
        PhysicalExpressionLaw("m0*v", m0="1 N")  # a force is not a friction coefficient
    # numbers are SI: v in m/s, a in s/m
    bare = PhysicalExpressionLaw("0.46/(1 + a*v)", a=160.0)
    assert float(bare.coefficient(ss.Q_(1.0, "mm/s"))) == pytest.approx(0.46 / 1.16, rel=1e-14)
    ok = PhysicalExpressionLaw("m0/(1 + a*v)", m0=0.46, a="160 s/m")
    assert ok.mu_s == pytest.approx(0.46)
    np.testing.assert_allclose(ok.coefficient(ss.Q_([0.0, 1e-3], "m/s")), [0.0, 0.46 / 1.16], rtol=1e-14)
    drop = PhysicalExpressionLaw("0.3", static=0.5)
    assert drop.mu_s == 0.5 and drop.nondimensionalize("42 s/m").kinetic_limit == pytest.approx(0.6)
    with pytest.raises(ValueError, match="exceeds static"):
        PhysicalExpressionLaw("0.6", static=0.5)


def test_formula_laws_pickle_and_compare_by_value() -> None:
    a = ExpressionLaw("1/(1 + c*w) + p*w", c=3.8, p=0.5)
    assert pickle.loads(pickle.dumps(a)) == a
    assert a.replace(c=2.0) == ExpressionLaw("1/(1 + c*w) + p*w", c=2.0, p=0.5)
    b = PhysicalExpressionLaw("0.46/(1 + a*v)", a="160 s/m")
    assert pickle.loads(pickle.dumps(b)) == b
    assert "ExpressionLaw" in repr(a) and "mu=" in repr(b)


def test_formula_command_line_errors() -> None:
    cases = [
        (["--law", "expr", "--nu", "0.1"], "needs one formula"),
        (["--law", "expr", "--f", "1", "--mu", "1", "--nu", "0.1"], "needs one formula"),
        (["--law", "expr", "--f", "1/(1+c*w)", "--param", "c", "--nu", "0.1"], "expected NAME=VALUE"),
        (["--law", "expr", "--f", "1/(1+w)", "--v0", "1 um/s"], "takes --nu and --param only"),
        (["--law", "weakening", "--c", "3", "--nu", "0.1", "--f", "1"], "--f belongs to --law expr"),
        (["--law", "expr", "--mu", "0.4", "--nu", "0.1"], "--nu: a physical formula"),
        (["--law", "table", "--nu", "0.1"], "needs --table"),
    ]
    for args, message in cases:
        res = run("cycle", *args)
        assert res.exit_code == 2, (args, res.output)
        assert message in res.output, (args, res.output)


# --------------------------------------------------------------------------- tables


def _table(tmp_path: Path, rows: str, header: str = "velocity [um/s],friction coefficient [1]") -> Path:
    p = tmp_path / "t.csv"
    p.write_text(header + "\n" + rows)
    return p


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        ("0,0.5\n1,0.49\n3,0.48\n2,0.47\n4,0.46\n", "line 5: velocity 2e-06 m/s is not above"),
        ("0,0.5\n1,0.49\n1,0.48\n3,0.47\n4,0.46\n", "line 4"),
        ("0,0.5\n1,-0.49\n2,0.48\n3,0.47\n4,0.46\n", "line 3: friction coefficient -0.49"),
        ("1,0.5\n2,0.49\n3,0.48\n4,0.47\n5,0.46\n", "no row at v = 0"),
        ("0,0.5\n1,0.49\n2,0.48\n", "2 rows above v = 0: at least 4"),
        ("0,0.5\n0,0.45\n0,0.4\n1,0.4\n2,0.4\n3,0.4\n4,0.4\n", "3 rows at v = 0"),
        ("0,0.5\n0,0.6\n1,0.5\n2,0.5\n3,0.5\n4,0.5\n", "exceeds the static coefficient"),
    ],
)
def test_bad_tables_name_the_row(rows: str, message: str, tmp_path: Path) -> None:
    with pytest.raises(DataError) as err:
        TabulatedLaw.from_csv(_table(tmp_path, rows))
    assert message in str(err.value)
    assert str(tmp_path) in str(err.value)


def test_table_conventions(tmp_path: Path) -> None:
    # a friction force needs the load; a second row at v = 0 is the level just after breakaway
    rows = "0,98\n0,88.2\n10,88\n20,87\n40,86\n80,85\n"
    with pytest.raises(DataError, match="give the normal load"):
        TabulatedLaw.from_csv(_table(tmp_path, rows, "velocity [um/s],friction force [mN]"))
    law = TabulatedLaw.from_csv(_table(tmp_path, rows, "velocity [um/s],friction force [mN]"), load="196 mN")
    assert law.mu_s == pytest.approx(0.5)
    nd = law.nondimensionalize("42 s/m")
    assert nd.kinetic_limit == pytest.approx(0.9)  # 88.2 / 98
    # PCHIP passes through the rows; the tangent continues above the last
    v = ss.Q_([10.0, 20.0, 80.0, 100.0], "um/s")
    np.testing.assert_allclose(law.coefficient(v)[:3], [88 / 196, 87 / 196, 85 / 196], rtol=1e-12)
    slope = law.derivative(ss.Q_(80.0, "um/s")).to("s/m").magnitude
    assert slope < 0
    assert float(law.coefficient(v)[3]) == pytest.approx(85 / 196 + slope * 20e-6, rel=1e-12)
    # coefficients as pint quantities: dimensionless ones converted, forces refused
    vq = ss.Q_([0.0, 10.0, 20.0, 40.0, 80.0], "um/s")
    pct = TabulatedLaw(vq, ss.Q_([50.0, 45.0, 44.0, 43.0, 42.0], "percent"))
    assert pct.mu_s == pytest.approx(0.5)
    with pytest.raises(ValueError, match="friction in newton: expected coefficients"):
        TabulatedLaw(vq, ss.Q_([0.5, 0.45, 0.44, 0.43, 0.42], "N"))
    assert nd.range_warning(42.0 * 90e-6) is not None and "beyond the table" in nd.range_warning(42.0 * 90e-6)
    assert nd.range_warning(42.0 * 50e-6) is None
    assert pickle.loads(pickle.dumps(law)) == law
    with pytest.raises(DataError, match="velocity unit"):
        TabulatedLaw.from_csv(
            _table(tmp_path, "0,0.5\n1,0.4\n2,0.4\n3,0.4\n4,0.4\n", "velocity [mm],friction coefficient [1]")
        )
    with pytest.raises(ValueError, match="interpolation='linear'"):
        TabulatedLaw(ss.Q_([0, 1, 2, 3, 4], "um/s"), [0.5, 0.4, 0.4, 0.4, 0.4], interpolation="linear")


@pytest.mark.slow
def test_percent_tables_erf_and_complex_formulas(tmp_path: Path) -> None:
    """A table in '[%]' is read as hundredths (as plain numbers, friction would be 100 times too
    high); erf, a documented function, evaluates on arrays (math.erf takes scalars only); a
    formula with a complex value is refused when the law is made, not deep in the engine."""
    rows = "0,50\n1,46\n10,40\n30,37\n100,35\n"
    pct = TabulatedLaw.from_csv(_table(tmp_path, rows, "velocity [um/s],friction coefficient [%]"))
    p = tmp_path / "one"
    p.mkdir()
    one = TabulatedLaw.from_csv(_table(p, "0,0.50\n1,0.46\n10,0.40\n30,0.37\n100,0.35\n"))
    assert pct.mu_s == pytest.approx(0.5) and pct.mu_s == pytest.approx(one.mu_s)
    law = ExpressionLaw("1 + 0.5*w - 0.1*erf(w)")
    w = np.array([0.1, 1.0, 3.0])
    expected = [1 + 0.5 * x - 0.1 * math.erf(x) for x in w]
    np.testing.assert_allclose(np.ravel(law.spec.evaluate(w, [])), expected, rtol=1e-14)
    res = CliRunner().invoke(main, ["cycle", "--law", "expr", "--f", "1/(1+3*w) + 0.2*erf(w)", "--nu", "0.1"])
    assert res.exit_code == 0 and "stick-slip" in res.output, res.output
    for formula in ("1 + sqrt(-1)*w", "(-1)**0.5*w + 1"):
        with pytest.raises(ValueError, match="the formula is not a real number"):
            ExpressionLaw(formula)


def test_a_pole_between_the_checked_velocities_is_an_error_not_a_traceback() -> None:
    """A pole at w = 0.7, between the velocities the law is checked at, is found when the law is
    made, with where it is (not a ZeroDivisionError from the compiled engine in `regimes`)."""
    f = "1/(1+3.8*w) + 0.001/(w-0.7) + 0.001/0.7"
    res = CliRunner().invoke(main, ["regimes", "--law", "expr", "--f", f, "--nu-min", "0.1", "--nu-max", "2"])
    assert res.exit_code == 2, res.output
    assert "has a pole at w = 0.7, where w - 0.7 is zero" in res.output
    assert "Traceback" not in res.output


@pytest.mark.parametrize(
    ("formula", "at", "zero"),
    [
        ("1/(w - 0.5) + 3", 0.5, "w - 0.5"),  # a pole, not a compile failure
        ("0.9/(1+w) + 0.001/(w**2 - w + 0.25)", 0.5, "w**2 - w + 0.25"),  # a double root: no sign change
        ("0.9/(1+w) + 1e-6/((w - 0.5)*(w - 0.51))", 0.5, "w - 0.5"),  # two poles between grid points
        ("0.9/(1+w) + 1e-6/(w - 1e-5)**2", 1e-5, "w - 1.0e-5"),
        ("0.9/(1+w) + 1e-3/(1 + cos(w))", math.pi, "cos(w) + 1"),  # a touch of a function
        ("0.9 + 0.001*tan(w)", math.pi / 2, "cos(w)"),
        ("0.5 + 0.001/abs(w - 0.3)", 0.3, "Abs(w - 0.3)"),  # a V, no sign change
        ("0.9/(1+w) + 1e-6/(w - 73.1)**2", 73.1, "w - 73.1"),
        # a double root next to w = 100 (its minimum's neighbour lies past the grid's end)
        ("0.9/(1+w) + 1e-3/(w**2 - 198*w + 9801)", 99.0, "w**2 - 198*w + 9801"),
        ("0.5 + 1e-3/abs(w - 99.5)", 99.5, "Abs(w - 99.5)"),
        # 1/tan jumps through infinity at pi/2 - 0.1, where 1/tan is 0: its pole is at pi - 0.1
        ("0.9 + 0.001/tan(w + 0.1)", math.pi - 0.1, "tan(w + 0.1)"),
    ],
)
def test_a_pole_anywhere_the_block_can_reach_is_found_when_the_law_is_made(
    formula: str, at: float, zero: str
) -> None:
    """Each denominator (tan's cos, log's argument) is searched for a zero on a grid of 6.5 %
    steps, its sign changes and the minima of its magnitude refined: a check at 46 velocities
    accepts a pole between two of them, and a run then fails or goes wrong far from the cause."""
    with pytest.raises(ValueError, match=r"has a pole at w = ([0-9.e+-]+), where (.*) is zero") as err:
        ExpressionLaw(formula, static=1)
    found = re.search(r"has a pole at w = ([0-9.e+-]+), where (.*) is zero", str(err.value))
    assert found is not None
    assert float(found.group(1)) == pytest.approx(at, rel=1e-5), str(err.value)
    assert found.group(2) == zero and str(err.value).startswith(f"f(w) = {formula} has")


def test_poles_of_a_slope_of_a_physical_law_and_of_one_sweep_point() -> None:
    """The slope's poles (the engine evaluates f' too), a physical law's pole in m/s, and the
    one point of a swept parameter that puts a pole in reach; laws near a pole but finite,
    and singular only at w = 0 itself (sqrt(w)), are taken."""
    with pytest.raises(ValueError, match=r"^the slope of f\(w\) = .* has a pole at w = 0.5, where Abs"):
        ExpressionLaw("0.9/(1+w) + 0.01*sqrt(abs(w - 0.5))", static=1)
    with pytest.raises(
        ValueError, match=r"^mu\(v\) = .* has a pole at v = 0.02 m/s, where -v/v0 \+ 1 is zero"
    ):
        ExpressionLaw(mu="0.4/(1 + a*v) + 0.001/(1 - v/v0)", a="160 s/m", v0="2 cm/s")
    for ok in (
        "0.9/(1+w) + 1e-3/((w - 0.5)**2 + 1e-8)",  # steep but finite
        "0.9/(1+w) + 0.01/(1 + 1e16*(w - 0.5)**2)",  # at most 0.01: a bump, not a pole beside its neighbours
        "0.9/(1+w) + 1e-3/(w - 105)",  # beyond w = 100
        "0.9/(1+w) + 0.01*sqrt(w)",
        "0.9/(1+w) + 0.01*abs(w - 0.5)",
        "0.9/(1+w) + 1e-3*log(w + 1)",
        "0.9/(1+w) + 1e-3/(w + 2)",
    ):
        ExpressionLaw(ok, static=1)
    law = ExpressionLaw("0.9/(1+w) + 1e-3/(2.5 + cos(c*w))", static=1, c=3.8)
    law.spec.validate({"c": np.linspace(1.0, 5.0, 2000)})  # bounded away from zero at every point
    law = ExpressionLaw("0.99/(1 + c*w) + 1e-3/(w + p)", static=1, c=3.8, p=2.0)
    p = np.linspace(2.0, -0.3, 1000)
    with pytest.raises(ValueError, match=r"has a pole at w = 0.000700701 at point 869, where p \+ w is zero"):
        law.spec.validate({"c": np.full(p.size, 3.8), "p": p})
    assert p[869] < 0 <= p[868]


@pytest.mark.slow
def test_a_formula_that_runs_into_the_compile_check_pole_still_compiles() -> None:
    """The compile check calls the law at w = 0.5 with every parameter 0.5: 1e-3/(c - w) divides
    by zero there and was 'numba cannot compile its formula (division by zero)'. A pole beyond
    the checked range that a motion reaches is the engine's ValueError, not a traceback."""
    law = ExpressionLaw("0.9/(1+w) + 1e-3/(c - w) + 5e-4", static=1, c=-2.0)
    res = ss.cycle(ss.DimensionlessParameters(law=law, nu=0.3))
    assert res.regime.name == "STICK_SLIP"
    far = ExpressionLaw("0.9/(1+w) + 1e-3/(200 - w)", static=1)
    for call in (
        lambda: ss.cycle(ss.DimensionlessParameters(law=far, nu=200.0)),
        lambda: ss.simulate(ss.DimensionlessParameters(law=far, nu=1.0), duration=5.0, initial=(0.0, 200.0)),
    ):
        with pytest.raises(
            ValueError, match="the friction law divides by zero at a velocity the motion reached"
        ):
            call()


def _f2_table(rows: int) -> ss.laws.DimensionlessLaw:
    """The paper's F2 tabulated at ``rows`` log-spaced velocities (pchip), with beta = 1 s/m."""
    f2 = ss.WeakeningLaw(c=3.8, p=0.5)
    w = np.concatenate([[0.0], np.geomspace(1e-3, 10.0, rows)])
    mu = np.asarray(f2.forward(w), dtype=float)
    mu[0] = 1.0
    return TabulatedLaw(ss.Q_(w, "m/s"), mu).nondimensionalize("1 s/m")


@pytest.mark.slow
def test_a_hopf_point_on_a_pchip_row_gets_the_type_of_its_kink() -> None:
    """pchip puts the minimum of a tabulated F2 on a row, where mu'' jumps: the Hopf point's type
    comes from the kink, not the one-sided mu''' (which depends on which side Brent lands, and
    can contradict the branch: a 'subcritical' point starting a stable branch).

    At a kink of f'' first-order averaging gives a' = -(a/2) f'(nu) - (J/(3 pi)) a^2 with J the
    jump: J > 0 is supercritical. Checked against the branch's stability, and the amplitude of
    the small cycle against plain SciPy shooting (tests/reference/one_block.py) and the averaged
    equation solved with the kink at its place."""
    from reference.one_block import pure_slip_orbit_reference
    from scipy.optimize import brentq

    from stickslip.bifurcation.regimes import regimes
    from stickslip.orbits.stability import hopf_points

    for rows, kind in ((256, "supercritical"), (512, "subcritical")):
        law = _f2_table(rows)
        (h,) = hopf_points(law, 0.01, 10.0)
        assert h.criticality == kind and math.isnan(h.l1)
        assert (h.kink > 0) == (kind == "supercritical")
        assert np.min(np.abs(law.breakpoints() - h.nu)) < 1e-12  # on a row
        with pytest.warns(UserWarning, match="lies on a row of the table: pchip"):
            d = regimes(law, 0.4, 0.55)
        (b,) = [b for b in d.branches if b.kind == "pure-slip"]
        assert bool(b.stable[0]) == (kind == "supercritical")
        assert d.hopf[0].kink == pytest.approx(h.kink) and "lies on a row" in d.notes[0]
        assert json.loads(d.to_json())["warnings"] == list(d.notes)
    # the branch reaches grazing (it stopped 'failed' after 36 points: across the rows, where f''
    # jumps, the flow is good to 1e-10..1e-8 only, and Newton waited for 1e-10)
    law = _f2_table(256)
    with pytest.warns(UserWarning, match="lies on a row"):
        d = regimes(law, 0.4, 0.7)
    (b,) = [b for b in d.branches if b.kind == "pure-slip"]
    (graze,) = [p for p in d.points if p.kind == "grazing"]
    (onset,) = [p for p in d.points if p.kind == "stick-slip-onset"]
    assert b.end == "grazing" and graze.nu == pytest.approx(onset.nu, abs=1e-7)
    (h,) = hopf_points(law, 0.01, 10.0)
    left, right = law.at(h.nu * (1 - 1e-12), 2), law.at(h.nu * (1 + 1e-12), 2)
    delta = 1e-4
    nu = h.nu - delta  # the stable small cycle lives on the unstable side (below)
    th = np.linspace(0.0, 2 * np.pi, 20001)[:-1]

    def averaged(a: float) -> float:
        x = a * np.cos(th)
        return float(np.mean(np.where(x < delta, left, right) * (x - delta) * np.sin(th) ** 2))

    a = brentq(averaged, 1.01 * delta, 1.0)
    ref = pure_slip_orbit_reference(
        lambda w: float(law.at(w)), lambda w: float(law.at(w, 1)), nu, (law.at(nu) + a, 2 * np.pi)
    )
    assert ref.amplitude == pytest.approx(2 * a, rel=0.01)
    assert ref.multiplier < 1.0


@pytest.mark.slow
def test_two_hopf_points_3e_4_apart_are_found() -> None:
    """A weakening band 3.1e-4 wide at w = 1 (f'(1) = -2.5) falls between two points of a
    4000-point grid over the range: the grid that brackets the Hopf points has 20000 points per
    decade. The roots are exact, 1 +- 1e-4 acosh(sqrt(6)), and the band is not steady sliding."""
    from stickslip.bifurcation.regimes import regimes
    from stickslip.orbits.stability import hopf_points

    law = ExpressionLaw("0.9 + 0.5*w - 0.0003*tanh((w-1)/0.0001)", static=1)
    hs = hopf_points(law, 1e-6, 1e3)
    off = 1e-4 * math.acosh(math.sqrt(6.0))
    assert [h.nu for h in hs] == pytest.approx([1 - off, 1 + off], abs=1e-12)
    d = regimes(law, 0.99, 1.01)
    assert d.regime_at(1.0).regime != "steady-sliding"
    assert d.regime_at(0.995).regime == d.regime_at(1.005).regime == "steady-sliding"


@pytest.mark.slow
def test_a_dip_of_f_prime_narrower_than_the_grid_gives_its_two_hopf_points() -> None:
    """A band ten times narrower than the grid's spacing (1.15e-4 at w = 1) has no grid point
    where f' < 0, but f'' changes sign across it: the minimum of f' is located and the two
    roots either side of it are exact (1 +- 1e-5 acosh(sqrt(6))); the same for a narrow
    strengthening bump on a weakening law, against Brent on f' written out by hand."""
    from scipy.optimize import brentq

    from stickslip.bifurcation.regimes import regimes
    from stickslip.orbits.stability import hopf_points

    law = ExpressionLaw("0.9 + 0.5*w - 0.00003*tanh((w-1)/0.00001)", static=1)
    off = 1e-5 * math.acosh(math.sqrt(6.0))
    assert [h.nu for h in hopf_points(law, 1e-6, 1e3)] == pytest.approx([1 - off, 1 + off], abs=1e-12)
    d = regimes(law, 0.9999, 1.0001)
    assert d.regime_at(1.0).regime != "steady-sliding"
    assert d.regime_at(0.99993).regime == d.regime_at(1.00007).regime == "steady-sliding"

    bump = ExpressionLaw("1/(1+w) + 0.00003*tanh((w-1)/0.00001)", static=1)

    def fp(w: float) -> float:
        return -1.0 / (1.0 + w) ** 2 + 3.0 / math.cosh((w - 1.0) / 1e-5) ** 2

    ref = [brentq(fp, 1.0 - 1e-4, 1.0, xtol=1e-15), brentq(fp, 1.0, 1.0 + 1e-4, xtol=1e-15)]
    hs = hopf_points(bump, 1e-3, 1e2)
    assert [h.nu for h in hs] == pytest.approx(ref, abs=1e-12)
    assert [h.stable_side for h in hs] == ["above", "below"]  # steady sliding stable inside the bump


@pytest.mark.slow
def test_a_table_that_ends_falling_names_its_zero_crossing(tmp_path: Path) -> None:
    """A table ending while friction still falls extrapolates to zero friction (here at v =
    2.231 mm/s): `cycle` and `regimes` name the table's end and where its tangent reaches zero
    (not only 'the friction law is singular or not finite', nor unknown intervals without a
    word), and `regimes` warns when motions go beyond the last row."""
    f2 = ss.WeakeningLaw(c=3.8, p=0.5)
    w = np.concatenate([[0.0], np.geomspace(1e-3, 0.3, 40)])
    mu = 0.46 * np.asarray(f2.forward(w), dtype=float)
    mu[0] = 0.46
    path = tmp_path / "fall.csv"
    path.write_text(
        "velocity [mm/s],friction coefficient [1]\n"
        + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(w, mu, strict=True))
    )
    law = TabulatedLaw.from_csv(path).nondimensionalize("1000 s/m")
    from scipy.interpolate import PchipInterpolator

    slope = float(PchipInterpolator(w, mu)(0.3, 1))  # per mm/s: SciPy's pchip on the rows
    zero = 0.3 - mu[-1] / slope  # mm/s
    assert law.zero_velocity() * 1e3 == pytest.approx(zero, rel=1e-12)
    # said with the law too, not only when a motion fails there
    assert f"the last row's tangent reaches zero friction at {zero:.4g} mm/s" in law.describe()
    setup = ["--law", "table", "--table", str(path), "--beta", "1000 s/m", "--stiffness", "62 N/m"]
    setup += ["--load", "196 mN"]
    res = CliRunner().invoke(main, ["cycle", *setup, "--v0", "1.5 mm/s"])
    assert res.exit_code == 1
    assert "the table ends at v = 300 um/s with friction still falling" in res.output
    assert f"reaches zero at v = {zero:.4g} mm/s" in res.output
    res = CliRunner().invoke(main, ["regimes", *setup, "--nu-min", "0.01", "--nu-max", "3", "--n", "21"])
    assert res.exit_code == 0 and "unknown" in res.output
    assert "extend the table to faster rows" in res.output
    res = CliRunner().invoke(main, ["regimes", *setup, "--nu-min", "0.01", "--nu-max", "0.5", "--n", "21"])
    assert res.exit_code == 0 and "beyond the table's last row (300 um/s)" in res.output


def test_user_law_input_is_refused_or_warned_in_words() -> None:
    """A repeated --param is refused (not the last value kept silently); sin(w)/w is refused as
    0/0 with its finite limit named; a table's bad mu names the argument; a constant law equal
    to the static threshold is warned about, its diagram neutrally stable."""
    runner = CliRunner()
    law = ["--law", "expr", "--f", "1/(1+c*w)"]
    res = runner.invoke(main, ["cycle", *law, "--param", "c=1", "--param", "c=2"])
    assert res.exit_code == 2 and "c is already given (c=1); give each parameter once" in res.output
    with pytest.raises(ValueError, match=r"is 0/0 at w = 0 \(its limit there is 1\)"):
        ExpressionLaw("sin(w)/w")
    with pytest.raises(ValueError, match="is not finite at w = 0: friction must be finite"):
        ExpressionLaw("1/w + 1")
    v = ss.Q_([0, 1, 2, 3, 4], "um/s")
    with pytest.raises(ValueError, match=r"mu=\['a'.*expected friction coefficients"):
        TabulatedLaw(v, ["a", "b", "c", "d", "e"])
    with pytest.raises(ValueError, match=r"mu has shape \(5, 2\): expected one coefficient per velocity"):
        TabulatedLaw(v, np.full((5, 2), 0.4))
    with pytest.raises(ValueError, match="mu has 4 friction values for 5 velocities in v"):
        TabulatedLaw(v, [0.5, 0.4, 0.4, 0.4])
    from stickslip.bifurcation.regimes import regimes

    with pytest.warns(UserWarning, match="friction is constant and equal to the static threshold"):
        d = regimes(ExpressionLaw("1 + 0*w"), 0.1, 2.0, n_grid=11)
    assert "neutrally stable" in d.notes[0]


@pytest.mark.slow
def test_a_flat_stretch_of_a_table_is_named(tmp_path: Path) -> None:
    """Equal rows make pchip flat (f' = 0 on a whole interval), where steady sliding's stability
    changes: regimes names the stretch, its ends bisected to the rows (0.6 and 1.5 mm/s here),
    rather than showing it only as an attractor boundary."""
    from stickslip.bifurcation.regimes import regimes

    rows = "0,0.5\n0.1,0.45\n0.3,0.40\n0.6,0.38\n1,0.38\n1.5,0.38\n2,0.39\n4,0.42\n8,0.5\n"
    path = tmp_path / "flat.csv"
    path.write_text("velocity [mm/s],friction coefficient [1]\n" + rows)
    law = TabulatedLaw.from_csv(path).nondimensionalize("1000 s/m")
    with pytest.warns(UserWarning, match=r"f'\(nu\) = 0 from nu = 0.6 to 1.5 \(a flat stretch of the law\)"):
        d = regimes(law, 0.05, 6.0, n_grid=41)
    assert d.regime_at(1.0).regime == "stick-slip" and d.regime_at(1.8).regime == "bistable"


@pytest.mark.slow
def test_a_smoothing_table_passes_through_its_first_row() -> None:
    """A smoothing spline need not pass through the v = 0 row: on a noisy table it puts friction
    just after breakaway 0.02 % (0.22 % on a noisier one) above the static level, where the
    block moves backward at breakaway, status ok; below it, an unasked drop at the onset. The
    first row is pinned (weight 1e8, then the remaining 1e-10 shifted out), and an interpolant
    above the static level is refused."""
    from scipy.interpolate import make_smoothing_spline

    w = np.linspace(0.0, 3.0, 31)
    rng = np.random.default_rng(1)
    mu = 1.0 - 0.1 * w + 0.02 * w**2 + np.concatenate([[0.0], 3e-3 * rng.standard_normal(30)])
    assert make_smoothing_spline(w / 3.0, mu)(0.0) > 1.0 + 1e-4  # the case: unpinned, above mu_s
    law = TabulatedLaw(ss.Q_(w, "m/s"), mu, interpolation="smoothing").nondimensionalize("1 s/m")
    assert law.at(0.0) == pytest.approx(1.0, abs=1e-15)
    # SciPy's smoothing spline with the first row weighted 1e8, shifted by what it leaves
    weights = np.ones_like(w)
    weights[0] = 1e8
    ref = make_smoothing_spline(w / 3.0, mu, w=weights)
    shift = 1.0 - float(ref(0.0))
    assert abs(shift) < 1e-9
    for x in (0.05, 0.7, 1.9, 2.5, 2.95):
        assert law.at(x) == pytest.approx(float(ref(x / 3.0)) + shift, rel=1e-12)
    res = ss.cycle(ss.DimensionlessParameters(nu=1.0, law=law))
    assert str(res.regime) == "stick-slip" and res.backward_slips == 0 and res.min_velocity >= 0.0


@pytest.mark.slow
def test_a_continuation_that_sympy_cannot_take_stops_where_it_can() -> None:
    """A term that switches on at w = 50 as a power 1.5 has a second derivative 0/0 at w = 0 for
    sympy: its limit stayed unevaluated (a Limit) and the code printer failed with a traceback.
    The continuation below w = 0 now stops at the last derivative sympy gives; below w = 50 the
    law is 0.9/(1+w), and the cycle is that law's."""
    law = ExpressionLaw("0.9/(1+w) + 0.01*(w - 50 + abs(w - 50))**1.5", static=1)
    assert sympy_str(law.spec.continuation) == "0.9 - 0.9*w"
    got = ss.cycle(ss.DimensionlessParameters(law=law, nu=0.3))
    plain = ss.cycle(ss.DimensionlessParameters(law=ExpressionLaw("0.9/(1+w)", static=1), nu=0.3))
    assert got.regime.name == "STICK_SLIP" and got.status.name == "OK"
    assert got.amplitude == pytest.approx(plain.amplitude, rel=1e-9)
    assert got.period == pytest.approx(plain.period, rel=1e-9)


def test_a_negative_dip_between_probe_points_is_warned_with_its_minimum() -> None:
    """docs/laws.md promises a warning where a formula's friction turns negative: also for
    1 - 2.9 w + 2 w**2 (negative on 0.565 < w < 0.885 only, between 45 probe points), and for
    1 - 2 w + w**3 as for the built-in cubic law. The minimum is exact: 1 - 2.9**2/8 at
    w = 2.9/4; mu's own for the physical form, said in m/s. The warning names the user's line,
    not expression.py."""
    with pytest.warns(UserWarning, match=r"turns negative \(minimum -0.0513 at w = 0.725\)") as got:
        ExpressionLaw("1 - 2.9*w + 2*w**2")
    assert got[0].filename == __file__
    with pytest.warns(UserWarning, match=r"minimum -0.0887 at w = 0.816"):  # 1 - 2 (2/3)^(3/2) / ... exact
        ExpressionLaw("1 - 2*w + w**3")
    with pytest.warns(
        UserWarning,
        match=r"mu\(v\) = 0.5 - 2.9\*v \+ 2\*v\*\*2 turns negative \(minimum -0.551 at v = 0.725 m/s\)",
    ):
        PhysicalExpressionLaw("0.5 - 2.9*v + 2*v**2")
    with pytest.warns(UserWarning, match=r"at 4 of 8 points, the first shown: a=1.9"):
        ExpressionLaw("1 - a*w + w**3", a=1.5).spec.check({"a": np.linspace(1.5, 2.2, 8)})
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # positive everywhere (minimum 0.0705): no warning
        ExpressionLaw("1 - 1.8*w + w**3")
        ExpressionLaw("1 - a*w + w**3", a=1.5).spec.check({"a": np.linspace(1.0, 1.85, 8)})


def test_e_and_pi_are_constants_and_a_parameter_of_that_name_is_refused() -> None:
    """'e' and 'pi' in a formula are the constants, and the error for a parameter named 'e'
    (--param e=75) says so, not only that the formula has no parameter 'e'."""
    law = ExpressionLaw("1/(1 + 3.8*w) + 0.1*e*w")
    assert float(law.forward(1.0)) == pytest.approx(1 / 4.8 + 0.1 * math.e, rel=1e-14)
    assert float(ExpressionLaw("1/(1 + pi*w)").forward(1.0)) == pytest.approx(1 / (1 + math.pi), rel=1e-14)
    with pytest.raises(ValueError, match=r"'e' in a formula is the constant e = 2.71828, not a parameter"):
        ExpressionLaw("1/(1 + 3.8*w) + 0.1*e*w", e=2.0)
    with pytest.raises(ValueError, match=r"allowed: .*the constants pi and e"):
        ExpressionLaw("1/(1 + w.real)")
