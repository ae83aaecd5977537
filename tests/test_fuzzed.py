"""Fuzzed bad input: each gives a clear error, at once.

A range typed with three dots is refused (read as two dots it would sweep another range);
a constant power beyond double precision (``2**2**26``) is refused before it is computed; a
repeated header line or index entry is refused; ``chain(out=)`` never replaces a user's
file; huge requests are refused before they run, not after hours or in a traceback.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from stickslip import DimensionlessParameters
from stickslip.bifurcation.regime_map import regime_map
from stickslip.chains import ChainParameters, chain, chain_ensemble
from stickslip.cli import main
from stickslip.core.memory import MemoryRequestError
from stickslip.dynamics.sweep import sweep
from stickslip.io.errors import DataError
from stickslip.io.output import ForeignFileError
from stickslip.io.records import read_record, read_records
from stickslip.laws import ExpressionLaw, WeakeningLaw
from stickslip.laws.formula import FormulaError

CHAIN = "chain --blocks 10 --law carlson-langer --alpha 2.5 --sigma 0.01 --nu 0.01".split()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["sweep", "--nu", "5...6", "--c", "3.8", "--num", "3", "--out", "OUT"],
            "expected a range 'A..B' (two dots)",
        ),
        (["sweep", "--preset", "zv", "--v0", "5 um/s...1 mm/s", "--num", "3"], "(two dots)"),
        (["regimes", "--map", "c=0.01...5", "--nu-min", "0.1", "--nu-max", "1"], "(two dots)"),
        (["regimes", "--c", "3.8", "--nu-min", "0.1", "--nu-max", "1e308"], "at most 1e+12"),
        (
            ["regimes", "--c", "3.8", "--nu-min", "0.1", "--nu-max", "1", "--n", "100000000"],
            "from 5 to 100000",
        ),
        (["cycle", "--law", "expr", "--f", "10**10**10", "--nu", "0.3"], "beyond double precision"),
        (["cycle", "--law", "expr", "--f", "-" * 1990 + "w", "--nu", "0.3"], "nested too deeply"),
        (["cycle", "--law", "expr", "--f", "1/(1+w)", "--static", "1e308", "--nu", "0.3"], "static=1e+308"),
        (["earthquake-cycles", "--duration", "1e308 yr", "--out", "OUT"], "at most 1e9 yr"),
        ([*CHAIN, "--ell", "10", "--events", "10", "--seeds", "0..100000000000"], "at most 1000000 in one"),
        ([*CHAIN, "--ell", "10", "--events", "100000000000"], "held in memory"),
    ],
)
def test_bad_command_lines_are_one_line_errors_at_once(tmp_path: Path, args: list[str], message: str) -> None:
    t0 = time.perf_counter()
    res = CliRunner().invoke(main, [a.replace("OUT", str(tmp_path / "o")) for a in args])
    assert res.exit_code in (1, 2), res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), repr(res.exception)
    last = res.output.strip().splitlines()[-1]
    assert last.startswith("Error: ") and message in last, res.output
    assert time.perf_counter() - t0 < 30.0  # no run started


@pytest.mark.fast
def test_the_caret_is_the_power_with_the_powers_precedence() -> None:
    """'1 + w^2' was read as (1 + w)**2 and '2*w^3' as 8*w**3: Python's XOR binds looser than + and *."""
    for caret, power in (
        ("1/(1+3*w) + 0.1*w^2", "1/(1+3*w) + 0.1*w**2"),
        ("2*w^3 + 1", "2*w**3 + 1"),
        ("1/(1 + w^2^0.5)", "1/(1 + w**2**0.5)"),
    ):
        assert ExpressionLaw(caret).spec.expr == ExpressionLaw(power).spec.expr, caret


def test_a_formula_beyond_double_precision_is_refused() -> None:
    for text, message in (
        ("1e200*1e200*w + 1", "1.00e\\+400 is beyond double precision"),
        ("2**2**26", "2\\*\\*67108864 is beyond double precision"),
        ("w" + "**w" * 600, "nested too deeply"),
    ):
        with pytest.raises(FormulaError, match=message):
            ExpressionLaw(text)
    law = ExpressionLaw("1/(1 + 1e200*w)")  # legitimate: its continuation's w**2 term (1e400) is dropped
    assert "inf" not in law.spec.kernel_source().split('"""', 2)[2]


def test_a_header_key_given_twice_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text("# v0 = 100 um/s\n# v0 = 200 um/s\n# load = 196 mN\ntime [s],force [N]\n0,1\n1,2\n")
    with pytest.raises(DataError, match=r"line 2 gives v0 = '200 um/s', an earlier line '100 um/s'"):
        read_record(path)
    # the same value written twice, or another way; notes, channels and comments that repeat (not read)
    path.write_text(
        "# v0 = 100 um/s\n# v0 = 0.1 mm/s\n# Note: cleaned with ethanol\n# Note: humidity 40%\n"
        "# Channel: Fx\n# Channel: Fz\n# load = 196 mN\ntime [s],force [N]\n0,1\n1,2\n2,1\n"
    )
    assert read_record(path).v0.to("um/s").magnitude == pytest.approx(100.0)


def test_an_index_naming_a_record_twice_is_refused(tmp_path: Path) -> None:
    for name in ("r1.csv", "r2.csv"):
        (tmp_path / name).write_text("time [s],force [N]\n0,1\n1,2\n2,1\n")
    (tmp_path / "index.csv").write_text(
        "file,v0 [um/s],load [mN]\nr1.csv,100,196\nr1.csv,200,196\nr2.csv,100,196\n"
    )
    with pytest.raises(DataError, match=r"line 3 names 'r1\.csv' again"):
        read_records(tmp_path)
    for day in ("day1", "day2"):  # two records of one name in two folders are two records
        (tmp_path / day).mkdir()
        (tmp_path / day / "run.csv").write_text("time [s],force [N]\n0,1\n1,2\n2,1\n")
    (tmp_path / "index.csv").write_text(
        "file,v0 [um/s],load [mN]\nday1/run.csv,100,196\nday2/run.csv,200,196\n"
    )
    with pytest.warns(UserWarning, match="not in the index"):
        assert len(read_records(tmp_path)) == 2


def test_chain_does_not_replace_a_file_it_did_not_write(tmp_path: Path) -> None:
    mine = tmp_path / "record.csv"
    mine.write_text("time [s],force [N]\n0,1\n")
    params = ChainParameters(blocks=5, law=WeakeningLaw(c=3.8), nu=0.01, ell=3)
    with pytest.raises(ForeignFileError, match="not a file stickslip wrote"):
        chain(params, 5, out=mine)
    assert mine.read_text() == "time [s],force [N]\n0,1\n"
    first = chain(params, 5, out=tmp_path / "catalog.nc")
    first.catalog.close()
    assert chain(params, 5, out=tmp_path / "catalog.nc").catalog.sizes["event"] == 5  # its own: replaced
    chain(params, 5, out=mine, overwrite=True).catalog.close()


def test_huge_requests_are_refused_before_they_run() -> None:
    t0 = time.perf_counter()
    params = ChainParameters(blocks=5, law=WeakeningLaw(c=3.8), nu=0.01, ell=3)
    with pytest.raises(ValueError, match="1000000000000 members; expected at most 1000000"):
        chain_ensemble(params, 5, seeds=range(10**12))
    with pytest.raises(ValueError, match=r"seeds\[0\]=99999999999999999999999: expected .* <= 2\*\*63 - 1"):
        chain_ensemble(params, 5, seeds=[99999999999999999999999])
    with pytest.raises(MemoryRequestError, match="nu: 999999999999 values needs about"):
        sweep(DimensionlessParameters(0.1, WeakeningLaw(c=3.8)), {"nu": range(1, 10**12)})
    with pytest.raises(ValueError, match="expected driving velocities from 1e-15 to 1e\\+12"):
        regime_map(WeakeningLaw(c=3.8), "c", [1.0, 2.0], 1e-20, 1.0)
    with pytest.raises(
        ValueError, match="n_nu=200000: expected a whole number of nu points from 5 to 100000"
    ):
        regime_map(WeakeningLaw(c=3.8), "c", [1.0, 2.0], 0.1, 1.0, n_nu=200_000)
    assert time.perf_counter() - t0 < 10.0
    assert np.isfinite(ExpressionLaw("1/(1+w)", static=1e12).static)


# --------------------------------------------------------------------------- MEDIUM findings


def test_errors_of_a_physical_set_up_name_what_was_typed() -> None:
    from stickslip import zv_parameters

    with pytest.raises(
        ValueError, match=r"nu=inf is infinite: .* \(made from mass=.*v0=1×10³⁰⁸ m/s: check their"
    ):
        zv_parameters("1e308 m/s").dimensionless()


def test_a_subnormal_atol_and_a_string_start_are_refused() -> None:
    import stickslip as S

    p = DimensionlessParameters(0.1, WeakeningLaw(c=3.8))
    for call in (lambda: S.cycle(p, atol=1e-320), lambda: S.simulate(p, atol=1e-300)):
        with pytest.raises(
            ValueError, match=r"atol=1e-3[02]0: expected an absolute tolerance between 1e-30 and 1"
        ):
            call()
    with pytest.raises(ValueError, match="initial='59': expected a pair"):
        S.simulate(p, initial="59")  # read as the pair (5, 9) once


def test_table_errors_say_what_is_wrong(tmp_path: Path) -> None:
    from stickslip import Q_
    from stickslip.laws import TabulatedLaw

    v = np.array([0.1, 0.01, 0.0, 0.05])
    with pytest.raises(ValueError, match="the row at v = 0 is row 3, not the first: sort the table"):
        TabulatedLaw(Q_(v, "m/s"), 0.46 / (1 + 160 * v))
    with pytest.raises(ValueError, match="row 4: velocity 1e\\+300 m/s is above 10000 m/s"):
        TabulatedLaw(Q_(np.array([0.0, 1.0, 2.0, 1e300]), "m/s"), np.array([0.5, 0.4, 0.3, 0.2]))


def test_a_record_sampled_beyond_reason_and_tiny_errors_are_refused(tmp_path: Path) -> None:
    from stickslip.data.criterion import classify

    path = tmp_path / "r.csv"
    femto = tmp_path / "md.csv"  # a molecular-dynamics trace, sampled every femtosecond: a record
    rows = "".join(f"{i},{float(np.sin(i / 5.0))!r}\n" for i in range(50))
    femto.write_text("time [fs],force [nN]\n" + rows)
    assert read_record(femto).time[1] == pytest.approx(1e-15)
    t = np.arange(50) * 2.6e-302
    path.write_text(
        "# v0 = 100 um/s\n# load = 196 mN\ntime [s],force [N]\n" + "".join(f"{float(x)!r},1\n" for x in t)
    )
    with pytest.raises(DataError, match=r"median sample interval is 2\.6e-302 s, below 1e-200 s"):
        read_record(path)
    with pytest.raises(ValueError, match=r"amplitude_err\[0\]=1e-320: below 1e-100 of its amplitude"):
        classify(np.geomspace(1, 100, 10), np.geomspace(1, 2, 10), np.full(10, 1e-320))


def test_a_history_whose_columns_disagree_is_said(tmp_path: Path) -> None:
    from stickslip.io.lab import read_lab_record

    path = tmp_path / "h.csv"
    head = "time [s],load-point velocity [um/s],load-point displacement [um]\n"
    path.write_text(head + "0,1,0\n10,10,500\n40,1,510\n50,1,520\n")
    with pytest.warns(UserWarning, match="disagrees with the velocity column by 490 um at line 3"):
        read_lab_record(path, need_friction=False)
    path.write_text(head + "0,1,0\n10,10,10\n40,1,310\n50,1,320\n")
    # a hold whose displacement is measured: its noise (0.02 um) is no disagreement
    x = np.random.default_rng(0).normal(0.0, 0.02, 200)
    rows = "".join(f"{5.0 * i},0,{float(x[i])!r}\n" for i in range(200))
    hold = tmp_path / "hold.csv"
    hold.write_text(head + rows)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_lab_record(path, need_friction=False)  # they agree: nothing said
        read_lab_record(hold, need_friction=False)


def test_a_fits_wild_trial_step_fails_the_model_not_the_fit(tmp_path: Path) -> None:
    """fit --fit-b --method features ended in 'lp[0]=1.99e+23: expected a finite value ...'."""
    from stickslip.data import fitting

    theta = np.log([0.46, 1e60, 62.0, 0.23, 1.0])  # mu_s, d = a - b (s/m), k, m, b: c = a/beta ~ 1e58
    got = fitting._model_features(theta, ("mu_s", "d", "k", "m", "b"), {}, 1e-4, 0.196)
    assert got.shape == (len(fitting.FEATURES),) and np.all(np.isnan(got))


def test_an_absurd_noise_level_is_refused() -> None:
    """--noise '1e-320 N' overflowed the weights (chi-square 1e6), '1e308 N' gave a chi-square of 0."""
    from stickslip.data.fitting import fit_record
    from stickslip.data.records import synthetic_record
    from stickslip.models import zv_parameters

    rec = synthetic_record(zv_parameters("100 um/s"), duration="2 s", rate="200 Hz", noise="0.5 mN")
    for noise in ("1e-320 N", "1e308 N"):
        with pytest.raises(
            ValueError, match="expected a noise level between 1e-9 and 1 times the record's force"
        ):
            fit_record(rec, noise=noise)
    with pytest.raises(ValueError, match="fit_b='no': expected True or False"):
        fit_record(rec, fit_b="no")


# --------------------------------------------------------------------------- LOW findings


def test_wrong_kinds_of_argument_are_type_errors_that_say_what_is_expected(tmp_path: Path) -> None:
    from stickslip.bifurcation.regimes import confirm
    from stickslip.data.fitting import fit_record
    from stickslip.data.records import analyze_records

    params = ChainParameters(blocks=5, law=WeakeningLaw(c=3.8), nu=0.01, ell=3)
    for call, message in (
        (lambda: analyze_records("x"), "expected a list of Record"),
        (lambda: fit_record("x"), "expected a Record"),
        (lambda: confirm("x"), "expected the RegimeDiagram"),
        (lambda: chain(params, 5, state="x"), "expected a ChainState"),
    ):
        with pytest.raises(TypeError, match=message):  # AttributeError from deep inside, before
            call()


def test_outputs_and_inputs_of_the_wrong_kind_are_refused(tmp_path: Path) -> None:
    res = CliRunner().invoke(
        main, ["sweep", "--nu", "0.1,0.2", "--c", "3.8", "--out", str(tmp_path / "p.xyz")]
    )
    assert (
        res.exit_code == 2
        and "expected a .nc (NetCDF; or .nc4, .cdf, .netcdf) or .csv file name" in res.output
    )
    assert not (tmp_path / "p.xyz").exists()  # NetCDF under another name, before
    with pytest.raises(DataError, match="/dev/zero: not a regular file"):
        read_record("/dev/zero")
    with pytest.raises(ValueError, match="workers=100000: expected at most"):
        sweep(DimensionlessParameters(0.1, WeakeningLaw(c=3.8)), {"nu": [0.1, 0.2]}, workers=100000)


def test_a_protocol_stage_of_absurd_length_is_refused() -> None:
    from stickslip.ratestate.model import RateStateParameters
    from stickslip.ratestate.protocols import velocity_steps

    p = RateStateParameters(a=0.01, b=0.015, dc="10 um", v_ref="1 um/s", mu0=0.6, stiffness_per_load="5 1/mm")
    with pytest.raises(ValueError, match=r"history\[1\] duration=1e\+308 s: expected at most 1e9 yr"):
        velocity_steps(p, ["1 um/s", "10 um/s"], durations=["5 s", "1e308 s"])
    from stickslip.ratestate.protocols import _history

    assert _history([("100 s", "1 um/s"), ("100 yr", "0 m/s")])[1][0] == pytest.approx(
        3.15576e9
    )  # a long hold


def test_numbers_derived_from_the_typed_ones_are_named_by_what_was_typed(tmp_path: Path) -> None:
    from stickslip import Q_, zv_parameters
    from stickslip.ratestate.cycles import SpringSliderFault
    from stickslip.ratestate.model import RateStateParameters

    with pytest.raises(ValueError, match="beta='1e-300 s/m' makes the mass 0 kg"):
        zv_parameters(beta="1e-300 s/m")  # was 'mass=0 kg must be positive'
    with pytest.raises(
        ValueError, match=r"at the grid point stiffness=1e\+308 N/m \(SI\), nu = beta v0 = 5\.3"
    ):
        sweep(zv_parameters("10 um/s"), {"stiffness": Q_([1e308, 62.0], "N/m")})  # was 'nu[0]=5.3e+149'
    for make in (
        lambda: SpringSliderFault(dc="1e-320 m"),  # was 'stiffness inf >= critical inf'
        lambda: RateStateParameters(a=0.01, b=0.015, dc="1e-320 m", v_ref="1 um/s", mu0=0.6),
    ):
        with pytest.raises(ValueError, match="dc=1×10⁻³²⁰ m: expected a slip distance between 1 pm and 1 km"):
            make()


@pytest.mark.fast
def test_an_exponent_without_digits_is_not_an_elementary_charge() -> None:
    """'5e um/s' read as 5 elementary charges um/s (a dimension error about [current]); now named."""
    from stickslip.units import parse_quantity

    with pytest.raises(ValueError, match=r"v0='5e um/s': 5e is a number's exponent without its digits"):
        parse_quantity("5e um/s", "v0", "[length] / [time]", "1 mm/s")
    assert parse_quantity("5e-6 m/s", "v0", "[length] / [time]", "1 mm/s").magnitude == 5e-6
    assert str(parse_quantity("5 eV", "energy", "[energy]", "1 J").units) == "electron_volt"
