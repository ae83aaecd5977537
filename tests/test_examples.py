"""The example inputs (`stickslip examples`) the README's commands read, and each command's own folder."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from stickslip.cli import main


@pytest.fixture(scope="module")
def examples(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("ex") / "examples"
    res = CliRunner().invoke(main, ["examples", str(folder)])
    assert res.exit_code == 0, res.output
    return folder


def test_examples_are_what_the_readme_reads_and_rewrite_themselves(examples: Path) -> None:
    names = sorted(p.name for p in examples.iterdir())
    assert names == [
        "README.txt",
        "amplitudes.csv",
        "mu_v.csv",
        "record.csv",
        "records",
        "stickslip-manifest.json",
    ]
    assert len(list((examples / "records").glob("*.csv"))) == 5
    before = (examples / "record.csv").read_bytes()
    res = CliRunner().invoke(main, ["examples", str(examples)])  # its own files: replaced, the same
    assert res.exit_code == 0, res.output
    assert (examples / "record.csv").read_bytes() == before


def test_the_example_amplitudes_and_table_give_the_zv_set_ups_answers(examples: Path) -> None:
    import json

    from stickslip import TabulatedLaw, cycle, zv_parameters
    from stickslip.models.parameters import PhysicalParameters

    res = CliRunner().invoke(main, ["classify", str(examples / "amplitudes.csv"), "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.output)["verdict"] == "stick-slip"  # F1 at the zv set-up: amplitude rises
    law = TabulatedLaw.from_csv(examples / "mu_v.csv")
    zv = zv_parameters("100 um/s")
    table = cycle(PhysicalParameters(mass=zv.mass, stiffness=zv.stiffness, load=zv.load, v0=zv.v0, law=law))
    assert str(table.regime) == "stick-slip"
    assert table.amplitude == pytest.approx(cycle(zv).amplitude, rel=2e-3)  # PCHIP over 25 rows of F1


def test_analyze_the_example_records_twice_into_its_own_folder(
    examples: Path, tmp_path: Path, monkeypatch
) -> None:
    import pandas as pd

    monkeypatch.chdir(tmp_path)
    for _ in range(2):  # the second run replaces its own summary and events
        res = CliRunner().invoke(main, ["analyze", str(examples / "records"), "--no-plot"])
        assert res.exit_code == 0, res.output
    table = pd.read_csv(tmp_path / "results" / "analyze" / "summary.csv")
    assert len(table) == 5 and set(table["observed_regime"]) == {"stick-slip"}
    assert (tmp_path / "results" / "analyze" / "events.csv").exists()


def test_a_failed_run_leaves_no_folder_it_made(tmp_path: Path) -> None:
    (tmp_path / "empty").mkdir()
    out = tmp_path / "new" / "deeper"
    res = CliRunner().invoke(main, ["analyze", str(tmp_path / "empty"), "--out", str(out)])
    assert res.exit_code != 0 and "no .csv" in res.output
    assert not (tmp_path / "new").exists()
    (tmp_path / "kept").mkdir()
    res = CliRunner().invoke(main, ["analyze", str(tmp_path / "empty"), "--out", str(tmp_path / "kept")])
    assert res.exit_code != 0 and (tmp_path / "kept").is_dir()  # a folder it did not make stays
