"""The criterion on model data, on noisy and short data, and on malformed files."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from stickslip import Q_, CubicLaw, DimensionlessParameters, zv_parameters
from stickslip.cli import main
from stickslip.data.criterion import classify, classify_file
from stickslip.dynamics.sweep import sweep


def write_csv(path: Path, header: str, rows: list) -> Path:
    path.write_text(header + "\n" + "\n".join(",".join(str(x) for x in r) for r in rows) + "\n")
    return path


def f1_data() -> tuple[np.ndarray, np.ndarray]:
    """Stick-slip: the paper's zv set-up with F1, 5 to 1000 um/s (amplitude in mN)."""
    v = np.geomspace(5, 1000, 12)
    ds = sweep(zv_parameters(), {"v0": Q_(v, "um/s")}, progress=False)
    assert set(ds.regime.values) == {"stick-slip"}
    return v, ds.amplitude.values * 1e3


def cubic_pure_slip_data() -> tuple[np.ndarray, np.ndarray]:
    """Pure slip: cubic law between its grazing border (~0.92) and its Hopf point (1)."""
    nu = np.linspace(0.95, 0.995, 8)
    ds = sweep(
        DimensionlessParameters(nu=0.97, law=CubicLaw(alpha=0.5, gamma=0.5 / 3)), {"nu": nu}, progress=False
    )
    assert set(ds.regime.values) == {"pure-slip"}
    beta = 100.0  # s/m: velocity v0 = nu / beta
    return nu / beta * 1e6, ds.amplitude.values


@pytest.mark.fast
def test_stick_slip_model_data(tmp_path: Path) -> None:
    v, a = f1_data()
    path = write_csv(tmp_path / "f1.csv", "velocity [um/s],amplitude [mN]", list(zip(v, a, strict=True)))
    r = classify_file(path)
    assert r.verdict == "stick-slip"
    assert r.slope > 0
    assert r.slope_ci[0] > 0
    assert r.n_points == 12


def test_pure_slip_model_data(tmp_path: Path) -> None:
    v, a = cubic_pure_slip_data()
    path = write_csv(tmp_path / "cubic.csv", "velocity [um/s],amplitude [a.u.]", list(zip(v, a, strict=True)))
    r = classify_file(path)
    assert r.verdict == "pure-slip"
    assert r.slope_ci[1] < 0


def test_units_do_not_change_the_slope(tmp_path: Path) -> None:
    v, a = f1_data()
    p1 = write_csv(tmp_path / "a.csv", "velocity [um/s],amplitude [mN]", list(zip(v, a, strict=True)))
    p2 = write_csv(
        tmp_path / "b.csv", "Velocity [mm/s],Amplitude [N]", list(zip(v / 1e3, a / 1e3, strict=True))
    )
    assert classify_file(p1).slope == pytest.approx(classify_file(p2).slope, rel=1e-12)


@pytest.mark.fast
def test_noisy_data() -> None:
    """Noise well below the trend keeps the verdict; noise as large as the trend gives inconclusive."""
    v, a = f1_data()
    rng = np.random.default_rng(7)
    small = a * (1 + 0.002 * rng.standard_normal(a.size))
    assert classify(v, small).verdict == "stick-slip"
    large = a * (1 + 0.1 * rng.standard_normal(a.size))
    r = classify(v, large)
    assert r.verdict == "inconclusive"
    assert "consistent with zero" in r.reason


def test_errors_weight_the_fit(tmp_path: Path) -> None:
    v = np.array([5.0, 10, 20, 50, 100, 200])
    a = 2.0 * v**0.3
    a[-1] *= 3.0  # an outlier ...
    err = np.full(v.size, 0.01 * a.min())
    err[-1] = 100.0  # ... with a huge error bar
    r = classify(v, a, err)
    assert r.slope == pytest.approx(0.3, rel=1e-3)
    # errors given in another unit are converted to the amplitude's unit
    path = write_csv(
        tmp_path / "e.csv",
        "velocity [um/s],amplitude [mN],amplitude_err [N]",
        list(zip(v, a, err / 1e3, strict=True)),
    )
    assert classify_file(path).slope == pytest.approx(r.slope, rel=1e-9)
    # the same with pint quantities: numpy stripped their units, and 10 mN counted as 10 N
    q = classify(Q_(v, "um/s"), Q_(a, "mN"), Q_(err / 1e3, "N"))
    assert q.slope == pytest.approx(r.slope, rel=1e-9)
    # (a common scale of the errors leaves the slope alone: the interval shows the unit)
    assert q.slope_ci == pytest.approx(r.slope_ci, rel=1e-9)
    with pytest.raises(ValueError, match="amplitude_err: units meter / second do not convert"):
        classify(v, Q_(a, "mN"), Q_(err, "m/s"))
    with pytest.raises(ValueError, match="give both with units, or neither"):
        classify(v, a, Q_(err, "N"))
    with pytest.raises(ValueError, match="velocity: units newton: expected a velocity"):
        classify(Q_(v, "N"), a)


@pytest.mark.fast
def test_too_few_points() -> None:
    r = classify([5.0, 50.0, 500.0], [1.0, 1.5, 2.0])
    assert r.verdict == "inconclusive"
    assert "too few points" in r.reason
    r = classify([5.0, 5.0], [1.0, 1.5])
    assert r.verdict == "inconclusive"


@pytest.mark.fast
def test_non_monotonic() -> None:
    v = np.geomspace(1, 1000, 15)
    a = np.exp(-((np.log(v) - np.log(30)) ** 2) / 4)
    r = classify(v, a)
    assert r.verdict == "inconclusive"
    assert "non-monotonic" in r.reason


@pytest.mark.fast
@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("", "is empty"),
        ("# only a comment\n", "no header"),
        ("velocity [um/s],amplitude [mN]\n", "no data rows"),
        ("speed [um/s],amplitude [mN]\n1,2\n", "missing column 'velocity'"),
        ("velocity [um/s],force [mN]\n1,2\n", "missing column 'amplitude'"),
        ("velocity [um/s],amplitude [mN]\n1,abc\n", "line 2, column 'amplitude': 'abc' is not a number"),
        ("velocity [um/s],amplitude [mN]\n1,2\n3\n", "line 3 has 1 cells"),
        ("velocity [furlongs/fortnight_x],amplitude [mN]\n1,2\n", "unknown unit"),
        ("velocity [mN],amplitude [mN]\n1,2\n", "expected a velocity"),
        ("velocity [um/s],amplitude [m/s]\n1,2\n", "a velocity"),
        ("velocity [um/s],amplitude [mN],amplitude_err [s]\n1,2,0.1\n", "inconsistent units"),
        ("velocity [um/s],amplitude [mN],amplitude_err\n1,2,0.1\n", "for both amplitude and"),
        ("velocity [um/s],amplitude [mN]\n-1,2\n2,3\n", "velocity -1.0 is not positive"),
        ("velocity [um/s],amplitude [mN]\n1,0\n2,3\n", "amplitude 0.0 is not positive"),
        ("velocity [um/s],amplitude [mN]\n1,nan\n", "is NaN"),
        ("velocity [um/s],velocity [um/s],amplitude [mN]\n1,1,2\n", "more than once"),
        ("velocity [um/s,amplitude [mN]\n1,2\n", "not of the form"),
    ],
)
def test_malformed_files(tmp_path: Path, content: str, message: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        classify_file(path)
    res = CliRunner().invoke(main, ["classify", str(path)])
    assert res.exit_code == 2
    assert "Traceback" not in res.output


def test_missing_file(tmp_path: Path) -> None:
    res = CliRunner().invoke(main, ["classify", str(tmp_path / "nope.csv")])
    assert res.exit_code == 2
    assert "no such file" in res.output


def test_line_numbers_semicolons_and_trailing_commas(tmp_path: Path) -> None:
    path = tmp_path / "c.csv"
    path.write_text("# comment\n\n# another\nvelocity [um/s];amplitude [mN];\n5;1;\n50;x;\n")
    with pytest.raises(ValueError, match="line 6, column 'amplitude'"):
        classify_file(path)
    path.write_text("velocity [um/s],amplitude [mN],,\n5,1.0,,\n50,1.4,,\n500,2.1,,\n5000,2.9,,\n")
    assert classify_file(path).verdict == "stick-slip"


def test_tsv_and_comments(tmp_path: Path) -> None:
    path = tmp_path / "d.tsv"
    path.write_text(
        "# measured 2026\nvelocity [um/s]\tamplitude [mN]\n5\t1.0\n50\t1.4\n500\t2.1\n5000\t2.9\n"
    )
    assert classify_file(path).verdict == "stick-slip"


@pytest.mark.fast
def test_classify_cli_json(tmp_path: Path) -> None:
    v, a = f1_data()
    path = write_csv(tmp_path / "f1.csv", "velocity [um/s],amplitude [mN]", list(zip(v, a, strict=True)))
    res = CliRunner().invoke(main, ["classify", str(path), "--json"])
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    assert d["verdict"] == "stick-slip"
    assert {"slope", "slope_ci", "n_points", "reason", "confidence"} <= set(d)
    res = CliRunner().invoke(main, ["classify", str(path)])
    assert "verdict   stick-slip" in res.output


@pytest.mark.fast
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"velocity": [1, 2], "amplitude": [1]}, "equal lengths"),
        ({"velocity": [1, 2], "amplitude": [1, 2], "confidence": 1.5}, "confidence=1.5"),
        ({"velocity": [1, 2], "amplitude": [1, 2], "min_points": 1}, "min_points=1"),
        ({"velocity": [1, 2], "amplitude": [1, 2], "amplitude_err": [1, -1]}, r"amplitude_err\[1\]"),
        ({"velocity": [[1, 2]], "amplitude": [[1, 2]]}, "1-d"),
        ({"velocity": [1, np.inf], "amplitude": [1, 2]}, "finite"),
    ],
)
def test_classify_bad_arguments(kwargs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        classify(**kwargs)


@pytest.mark.fast
def test_the_slope_and_its_interval_against_scipy() -> None:
    """The slope's interval is Student's t at n - 2 degrees of freedom times the standard
    error: against scipy.stats.linregress without errors, and against numpy's weighted
    polyfit with them (the covariance scaled by the reduced chi-square where it exceeds 1)."""
    from scipy import stats

    rng = np.random.default_rng(5)
    v = np.geomspace(2.0, 300.0, 6)
    a = 3.0 * v**0.3 * np.exp(rng.normal(0.0, 0.2, v.size))
    r = classify(v, a, confidence=0.9)
    ref = stats.linregress(np.log(v), np.log(a))
    t = stats.t.ppf(0.95, v.size - 2)
    assert r.slope == pytest.approx(ref.slope, rel=1e-12)
    assert r.slope_ci == pytest.approx((ref.slope - t * ref.stderr, ref.slope + t * ref.stderr), rel=1e-10)
    for scale in (0.05, 1.0):  # errors too small for the scatter (chi2 scales them) and large ones
        err = scale * a * rng.uniform(0.5, 1.5, v.size)
        r = classify(v, a, amplitude_err=err)
        sigma = err / a
        coef, cov = np.polyfit(np.log(v), np.log(a), 1, w=1.0 / sigma, cov="unscaled")
        chi2 = float(np.sum(((np.log(a) - np.polyval(coef, np.log(v))) / sigma) ** 2))
        se = math.sqrt(cov[0, 0] * max(1.0, chi2 / (v.size - 2)))
        t95 = stats.t.ppf(0.975, v.size - 2)
        assert r.slope == pytest.approx(coef[0], rel=1e-10)
        assert r.slope_ci == pytest.approx((coef[0] - t95 * se, coef[0] + t95 * se), rel=1e-10)


@pytest.mark.fast
def test_errors_that_differ_by_1e9_keep_a_rising_trend_rising() -> None:
    """Noise-free records give amplitude errors of 1e-16 next to 1e-5: the weighted fit is
    solved from the scaled design's SVD, since the normal matrix squares that spread and pinv
    truncates it (the upper half's slope comes out -0.0136 instead of +0.0349, and a monotonic
    rise reads 'inconclusive (non-monotonic ...)'). Measured-like numbers, and the exact
    weighted slope in closed form."""
    v = np.array([50, 100, 200, 500, 1000, 2000, 5000]) * 1e-6
    a = np.array([1.002489, 1.005890, 1.012011, 1.027669, 1.050437, 1.090061, 1.187516])
    spread = np.array([1.975e-15, 1.317e-15, 6.584e-16, 9.876e-16, 1.639e-05, 5.097e-05, 6.509e-04])
    err = spread / np.sqrt([11, 11, 11, 11, 10, 9, 8])
    r = classify(v, a, amplitude_err=err)
    assert r.verdict == "stick-slip", r.reason
    x, y, w = np.log(v), np.log(a), (a / err) ** 2
    xb, yb = np.sum(w * x) / w.sum(), np.sum(w * y) / w.sum()
    assert r.slope == pytest.approx(np.sum(w * (x - xb) * (y - yb)) / np.sum(w * (x - xb) ** 2), rel=1e-9)
