"""Bad input found by a fuzz audit (helper-4, 2026-11-28): each a clear error, at once.

Before: a range typed with three dots swept another range; a constant power hung; a
repeated header line or index entry was read silently; ``chain(out=)`` replaced a
user's file; huge requests ran for hours or ended in a traceback.
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

CHAIN = [
    "chain",
    "--blocks",
    "10",
    "--law",
    "carlson-langer",
    "--alpha",
    "2.5",
    "--sigma",
    "0.01",
    "--nu",
    "0.01",
]


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
    path.write_text("# v0 = 100 um/s\n# v0 = 100 um/s\n# load = 196 mN\ntime [s],force [N]\n0,1\n1,2\n2,1\n")
    assert read_record(path).v0 is not None  # the same value twice is no contradiction


def test_an_index_naming_a_record_twice_is_refused(tmp_path: Path) -> None:
    for name in ("r1.csv", "r2.csv"):
        (tmp_path / name).write_text("time [s],force [N]\n0,1\n1,2\n2,1\n")
    (tmp_path / "index.csv").write_text(
        "file,v0 [um/s],load [mN]\nr1.csv,100,196\nr1.csv,200,196\nr2.csv,100,196\n"
    )
    with pytest.raises(DataError, match=r"line 3 names 'r1\.csv' again"):
        read_records(tmp_path)


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
    assert time.perf_counter() - t0 < 10.0
    assert np.isfinite(ExpressionLaw("1/(1+w)", static=1e12).static)
