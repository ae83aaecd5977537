"""Measured records: reading, cycle extraction on synthetic records, analyze, bad input."""

import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import stickslip as S
from stickslip.cli import main
from stickslip.data.records import analyze_records, measure_record, synthetic_record
from stickslip.io import records as records_io
from stickslip.io.records import read_record, read_records

CUBIC = S.PhysicalCubicLaw(mu_s=0.5, k1="5 s/m", k3=f"{0.5 * 8000 / 6} s**3/m**3")  # Hopf at 50 mm/s


def cubic_params(v_mm_s: float) -> S.PhysicalParameters:
    return S.PhysicalParameters(mass="1 kg", stiffness="100 N/m", load="1 N", v0=f"{v_mm_s} mm/s", law=CUBIC)


def write_record(path: Path, rec, header: str = "time [s],force [mN]", meta: str = "") -> Path:
    with open(path, "w") as fh:
        fh.write(meta + header + "\n")
        cols = [rec.time, rec.force * 1e3]
        if rec.velocity is not None and "velocity" in header:
            cols.append(rec.velocity * 1e6)
        np.savetxt(fh, np.column_stack(cols), delimiter=",", fmt="%.9g")
    return path


def steady_record(p: S.PhysicalParameters, cycles: int, rate: str, **kwargs):  # type: ignore[no-untyped-def]
    """Return the steady cycle of ``p`` and a record of ``cycles`` of them sampled at ``rate``."""
    true = S.cycle(p, probe=False)
    rec = synthetic_record(
        p, duration=f"{cycles * true.period} s", rate=rate, start=f"{true.transient_time} s", **kwargs
    )
    return true, rec


@pytest.mark.fast
@pytest.mark.parametrize(
    ("noise", "drift", "rate"),
    [
        ("0 N", "0 N/s", "100 Hz"),
        ("1 mN", "0 N/s", "100 Hz"),
        ("2 mN", "0.1 mN/s", "50 Hz"),
        ("2 mN", "-0.1 mN/s", "1 kHz"),
    ],
)
def test_stick_slip_record_measured(noise: str, drift: str, rate: str) -> None:
    """Tolerances: amplitude within 1.5%, period within 0.5%, noise up to 2% of the amplitude."""
    p = S.zv_parameters("100 um/s")
    true = S.cycle(p, probe=False)
    rec = synthetic_record(
        p,
        duration=f"{22 * true.period} s",
        rate=rate,
        noise=noise,
        drift=drift,
        with_velocity=True,
        start=f"{true.transient_time} s",
    )
    table, s = measure_record(rec)
    assert s.n_cycles >= 20
    for bad in (0, 2.5, "3"):
        with pytest.raises(ValueError, match="min_cycles="):
            measure_record(rec, min_cycles=bad)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="confidence=7"):
        analyze_records([rec], confidence=7)
    assert s.amplitude == pytest.approx(true.amplitude, rel=0.015)
    assert s.period == pytest.approx(true.period, rel=0.005)
    assert s.stick_fraction == pytest.approx(true.stick_fraction, abs=0.01)
    slip_time = true.period - true.stick_time
    assert 0.3 * slip_time < s.drop_time < slip_time + 2 / float(S.Q_(rate).to("Hz").magnitude)
    # the rise is the stick (the spring loads at k v0) plus the slow start of the slip
    assert np.median(table.rise_time) == pytest.approx(true.stick_time, rel=0.25)
    assert s.drift == pytest.approx(float(S.Q_(drift).to("N/s").magnitude), abs=2e-6)
    assert table.amplitude.size == s.n_cycles


def test_pure_slip_record_measured() -> None:
    p = cubic_params(48.5)
    true = S.cycle(p)
    assert true.regime == "pure-slip"
    rec = synthetic_record(
        p, duration=f"{15 * true.period} s", rate="500 Hz", noise="1 mN", start=f"{true.transient_time} s"
    )
    _, s = measure_record(rec)
    assert s.amplitude == pytest.approx(true.amplitude, rel=0.01)
    assert s.period == pytest.approx(true.period, rel=0.01)


@pytest.mark.parametrize("v_mm_s", [20.0, 45.0])
def test_stick_fraction_leaves_out_the_slow_start_of_a_slip(v_mm_s: float) -> None:
    """The stick fraction is within a sample per cycle (1/323 here) of the truth (cubic law,
    noise-free velocity): a rest threshold at 1% of the largest speed would take the slow start
    and end of each slip for rest (0.155 for 0.120 at 40 mm/s, 0.064 for 0.011 at 45 mm/s)."""
    p = cubic_params(v_mm_s)
    true = S.cycle(p, probe=False)
    assert true.regime == "stick-slip"
    rec = synthetic_record(
        p,
        duration=f"{12 * true.period} s",
        rate="500 Hz",
        noise="0.5 mN",
        with_velocity=True,
        start=f"{true.transient_time} s",
    )
    _, s = measure_record(rec)
    assert s.stick_fraction == pytest.approx(true.stick_fraction, abs=1.5 / (true.period * 500))


@pytest.mark.parametrize(
    ("column", "noise"), [("velocity", 2e-5), ("velocity", 3e-4), ("displacement", 1e-7)]
)
def test_stick_fraction_of_a_noisy_velocity(column: str, noise: float) -> None:
    """At rest is within four standard deviations of the velocity's noise, estimated from its
    fourth differences: the stick fraction is within 0.01 up to a noise of three times v0 (m/s),
    or 0.1 um on the displacement (m). A fixed threshold gives 0.38 for 0.984 with 20 um/s of
    noise (0.14% of the 14 mm/s peak), and 0.51 with 20 nm on the displacement."""
    from stickslip.io.records import Record

    p = S.zv_parameters("100 um/s")
    true, rec = steady_record(p, 22, "1 kHz", with_velocity=True)
    assert rec.velocity is not None
    rng = np.random.default_rng(3)
    if column == "velocity":
        noisy = Record(
            rec.name,
            rec.time,
            rec.force,
            None,
            rec.velocity + noise * rng.standard_normal(rec.time.size),
            p.v0,
        )
    else:
        x = np.cumsum(rec.velocity) * 1e-3 + noise * rng.standard_normal(rec.time.size)
        noisy = Record(rec.name, rec.time, rec.force, x, None, p.v0)
    table, s = measure_record(noisy)
    assert s.stick_fraction == pytest.approx(true.stick_fraction, abs=0.01)
    assert np.all(np.isfinite(table.stick_fraction))
    # noise as large as the slip speeds: rest cannot be told from slip, and the fraction says so
    drowned = Record(
        rec.name, rec.time, rec.force, None, rec.velocity + 0.02 * rng.standard_normal(rec.time.size)
    )
    assert np.isnan(measure_record(drowned)[1].stick_fraction)


def test_clipped_peaks_are_said() -> None:
    """A sensor saturating at 97 % of the peak-to-trough range takes 1.2 % off the amplitude
    (4 % on a record clipped deeper): samples piling up at the record's extreme value are a
    rail, and the record's warning and a fit's say so. Neither a
    continuous force, nor one quantized by an ADC (1 and 5 mN steps over 0.5 mN of noise), nor
    a flat-bottomed one without a pile-up, is taken for one."""
    from stickslip.data.fitting import fit_record
    from stickslip.data.records import saturation
    from stickslip.io.records import Record

    p = S.zv_parameters("100 um/s")
    true = S.cycle(p, probe=False)
    rec = synthetic_record(
        p,
        duration=f"{12 * true.period} s",
        rate="500 Hz",
        noise="0.5 mN",
        seed=0,
        start=f"{true.transient_time} s",
    )
    _, clean = measure_record(rec)
    assert clean.warning == ""
    lo, hi = float(rec.force.min()), float(rec.force.max())
    rail = lo + 0.97 * (hi - lo)
    clipped = Record(rec.name, rec.time, np.minimum(rec.force, rail), None, None, rec.v0, rec.load, {})
    _, s = measure_record(clipped)
    assert s.amplitude < 0.995 * clean.amplitude  # what the warning is for
    assert f"its largest value, {rail:.6g} N" in s.warning and "clipped the peaks" in s.warning
    n_rail = int(np.sum(rec.force >= rail))
    assert f"for {n_rail} samples" in s.warning
    floor = Record(
        rec.name, rec.time, np.maximum(rec.force, lo + 0.02 * (hi - lo)), None, None, rec.v0, rec.load, {}
    )
    assert "clipped the troughs" in measure_record(floor)[1].warning
    fit = fit_record(clipped)
    assert any("clipped the peaks" in w for w in fit.warnings)
    for step in (1e-3, 5e-3):
        assert saturation(np.round(rec.force / step) * step) is None
    assert saturation(rec.force) is None
    # three equal extremes, none two in a row: a coincidence of a quantized record, not a rail
    assert saturation(np.array([0.0, 1.0, 0.5, 1.0, 0.2, 1.0, 0.3])) is None
    assert saturation(np.array([0.0, 1.0, 1.0, 1.0, 0.2, 0.5, 0.3])) is not None


def make_folder(folder: Path, params_list, *, index: bool) -> Path:
    folder.mkdir()
    lines = ["file,v0 [mm/s],load [N]"]
    for i, p in enumerate(params_list):
        true = S.cycle(p, probe=False)
        rec = synthetic_record(
            p,
            duration=f"{12 * true.period} s",
            rate="500 Hz",
            noise="0.5 mN",
            seed=i,
            start=f"{true.transient_time} s",
        )
        v = p.v0.to("mm/s").magnitude
        meta = "" if index else f"# v0 = {v} mm/s\n# load = {p.load.to('N').magnitude} N\n"
        write_record(folder / f"r{i}.csv", rec, meta=meta)
        lines.append(f"r{i}.csv,{v},{p.load.to('N').magnitude}")
    if index:
        (folder / "index.csv").write_text("\n".join(lines) + "\n")
    return folder


def test_analyze_stick_slip_folder(tmp_path: Path) -> None:
    folder = make_folder(
        tmp_path / "ss", [S.zv_parameters(f"{v} um/s") for v in (20, 50, 100, 200, 500)], index=True
    )
    _, verdict = analyze_records(read_records(folder))
    assert verdict is not None and verdict.verdict == "stick-slip"
    # the model that made them agrees
    model = S.data.criterion.classify(
        [20, 50, 100, 200, 500],
        [S.cycle(S.zv_parameters(f"{v} um/s"), probe=False).amplitude for v in (20, 50, 100, 200, 500)],
    )
    assert model.verdict == verdict.verdict
    res = CliRunner().invoke(main, ["analyze", str(folder), "--out", str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    assert "criterion: stick-slip" in res.output
    # the printed table in the records' units (um/s, not v0 0.0001 [m/s]);
    # summary.csv stays SI
    head, *rows = res.output.split("v0 [um/s]", 1)[1].splitlines()[:6]
    assert "load [mN]" in head and "amplitude [mN]" in head
    printed = [float(r.split()[2]) for r in rows if r.strip().startswith("r")]
    assert printed == [20, 50, 100, 200, 500]
    import pandas as pd

    assert pd.read_csv(tmp_path / "out" / "summary.csv")["v0 [m/s]"].tolist() == pytest.approx(
        [2e-5, 5e-5, 1e-4, 2e-4, 5e-4], rel=1e-12
    )
    assert (tmp_path / "out" / "records_vs_v0.png").stat().st_size > 5000
    assert "with a warning above" not in res.output
    # one file in mN labelled N: its warning, and the verdict line counts it
    rec = read_records(folder / "r4.csv")[0]
    write_record(folder / "r4.csv", rec, header="time [s],force [N]")  # the mN values, labelled N
    res = CliRunner().invoke(main, ["analyze", str(folder), "--out", str(tmp_path / "out2"), "--no-plot"])
    assert res.exit_code == 0, res.output
    assert "warning: r4.csv: the force reaches" in res.output and "times the normal load" in res.output
    assert "from 5 records at load 196 mN; 1 of them with a warning above" in res.output, res.output


@pytest.mark.parametrize("index", [True, pytest.param(False, marks=pytest.mark.slow)])
def test_a_record_that_cannot_be_read_does_not_stop_the_folder(tmp_path: Path, index: bool) -> None:
    """Three NaN samples in one file of a folder do not stop the folder: with on_error="warn"
    (what `analyze` uses) the file is a row of the table saying why, naming the column as the
    file does ('Fx [mN]', not stickslip's 'friction_force'), and the verdict comes from the
    others: the same as without it."""
    vs = (20, 50, 100, 200)
    folder = make_folder(tmp_path / "f", [S.zv_parameters(f"{v} um/s") for v in vs], index=index)
    _, whole = analyze_records(read_records(folder))
    bad = folder / "r4.csv"
    lines = (folder / "r1.csv").read_text().replace("time [s],force [mN]", "Time (s),Fx [mN]").splitlines()
    start = 3 if not index else 1
    for i in (start + 500, start + 501, start + 900):
        lines[i] = lines[i].split(",")[0] + ",nan"
    bad.write_text("\n".join(lines) + "\n")
    if index:
        with open(folder / "index.csv", "a") as fh:
            fh.write("r4.csv,0.3,0.196\n")
    with pytest.raises(ValueError, match=r"column 'Fx \[mN\]' has 3 missing/NaN values in 2 run"):
        read_records(folder)  # on_error="raise", the default
    with pytest.warns(records_io.UnreadableRecord) as caught:
        recs = read_records(folder, on_error="warn")
    assert [r.name for r in recs] == [f"r{i}.csv" for i in range(4)]
    (w,) = [x.message for x in caught if isinstance(x.message, records_io.UnreadableRecord)]
    assert w.name == "r4.csv" and "'Fx [mN]' has 3 missing/NaN" in w.reason
    table, verdict = analyze_records(recs, unreadable={w.name: w.reason})
    assert verdict is not None and verdict.as_dict() == whole.as_dict()
    row = table[table["name"] == "r4.csv"].iloc[0]
    assert row["warning"].startswith("not read: ") and not row["in_verdict"]
    assert np.isnan(row["amplitude [N]"]) and row["n_cycles"] == 0
    res = CliRunner().invoke(main, ["analyze", str(folder), "--out", str(tmp_path / "out"), "--no-plot"])
    assert res.exit_code == 0, res.output
    assert "warning: r4.csv: not read: " in res.output and "criterion: stick-slip" in res.output
    with pytest.raises(ValueError, match="on_error='skip'"):
        read_records(folder, on_error="skip")
    # none readable: an error, naming the first reason
    for f in folder.glob("r[0-3].csv"):
        f.write_text(bad.read_text())
    if index:
        (folder / "index.csv").write_text("file,v0 [mm/s],load [N]\nr4.csv,0.3,0.196\nr0.csv,0.02,0.196\n")
    with pytest.raises(ValueError, match=r"none of its .* could be read: .*'Fx \[mN\]' has 3"):
        read_records(folder, on_error="warn")
    res = CliRunner().invoke(main, ["analyze", str(folder), "--out", str(tmp_path / "out2"), "--no-plot"])
    assert res.exit_code == 2 and "could be read" in res.output


def test_a_long_table_record_that_cannot_be_read_is_a_row(tmp_path: Path) -> None:
    """The same in a long table: a record whose rows hold a NaN is left out with a warning."""
    rows = ["record,v0 [um/s],load [mN],time [s],force [N]"]
    for name, v in (("a", 100), ("b", 200), ("c", 300)):
        rows += [
            f"{name},{v},196,{0.1 * i},{'nan' if name == 'b' and i == 5 else 0.1 + 0.01 * (i % 7)}"
            for i in range(50)
        ]
    path = tmp_path / "all.csv"
    path.write_text("\n".join(rows) + "\n")
    with pytest.warns(records_io.UnreadableRecord, match="b: not read: .*record 'b'.*1 missing/NaN"):
        recs = read_records(path, on_error="warn")
    assert [r.name for r in recs] == ["a", "c"]


def test_analyze_pure_slip_folder(tmp_path: Path) -> None:
    folder = make_folder(
        tmp_path / "ps", [cubic_params(v) for v in (47.6, 48.0, 48.5, 49.0, 49.5)], index=False
    )
    table, verdict = analyze_records(read_records(folder))
    assert verdict is not None and verdict.verdict == "pure-slip"
    np.testing.assert_allclose(table["v0 [m/s]"], [0.0476, 0.048, 0.0485, 0.049, 0.0495])


def test_long_table_and_tsv(tmp_path: Path) -> None:
    rows = ["record\tv0 [um/s]\tload [mN]\ttime [s]\tforce [N]"]
    for name, v in (("a", 100), ("b", 200)):
        p = S.zv_parameters(f"{v} um/s")
        true = S.cycle(p, probe=False)
        rec = synthetic_record(
            p, duration=f"{6 * true.period} s", rate="50 Hz", start=f"{true.transient_time} s"
        )
        rows += [
            f"{name}\t{v}\t196\t{float(t)!r}\t{float(f)!r}" for t, f in zip(rec.time, rec.force, strict=True)
        ]
    path = tmp_path / "all.tsv"
    path.write_text("\n".join(rows) + "\n")
    recs = read_records(path)
    assert [r.name for r in recs] == ["a", "b"]
    assert recs[1].v0.to("um/s").magnitude == pytest.approx(200)
    assert recs[0].load.to("N").magnitude == pytest.approx(0.196)
    # a row without a record name was dropped by the grouping, without a word
    lines = path.read_text().splitlines()
    lines[3] = "\t" + lines[3].split("\t", 1)[1]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match="line 4 has no record name"):
        read_records(path)


@pytest.mark.fast
def test_header_metadata_and_units(tmp_path: Path) -> None:
    p = S.zv_parameters("100 um/s")
    rec = synthetic_record(p, duration="100 s", rate="20 Hz", with_velocity=True)
    path = write_record(
        tmp_path / "r.csv",
        rec,
        header="time [s],force [mN],velocity [um/s]",
        meta="# sample = PMMA\n# v0 = 100 um/s\n# load = 196 mN\n",
    )
    r = read_record(path)
    assert r.metadata["sample"] == "PMMA"
    assert r.v0.to("um/s").magnitude == pytest.approx(100)
    np.testing.assert_allclose(r.force, rec.force, rtol=1e-8)
    np.testing.assert_allclose(r.velocity, rec.velocity, rtol=1e-8, atol=1e-12)


BAD = [
    ("", "is empty"),
    ("# only comments\n", "no header"),
    ("time [s],force [N]\n", "no data rows"),
    ("clock [s],force [N]\n0,1\n1,2\n2,3\n", "missing column 'time'"),
    ("time [s],load [N]\n0,1\n1,2\n2,3\n", "missing a force column"),
    ("time [s],force [N]\n0,1\n1,x\n2,3\n", "line 3, column 'force': 'x' is not a number"),
    ("time [s],force [blarg]\n0,1\n1,2\n2,3\n", "unknown unit"),
    ("time [s],force [m]\n0,1\n1,2\n2,3\n", "expected [force]"),
    ("time,force [N]\n0,1\n1,2\n2,3\n", "column 'time' has no unit"),
    ("time [s],force [N]\n0,1\n2,2\n1,3\n", "not strictly increasing at lines 3-4"),
    ("time [s],force [N]\n0,1\n1,\n2,\n3,4\n", "2 missing/NaN values in 1 run(s), the longest 2"),
    ("time [s],force [N]\n0,1\n1,nan\n2,3\n", "missing/NaN"),
    ("# v0 = fast\ntime [s],force [N]\n0,1\n1,2\n2,3\n", "v0='fast'"),
    # a cell too many (decimal commas): pandas kept the first cells and dropped the rest, unsaid
    ("time [s],force [mN]\n0,1,5\n1,2,5\n2,3,5\n", "line 2 has 3 cells, the header has 2 (decimal commas?"),
    ("time [s],force [mN]\n0,1\n1,2\n2,3,4", "line 4 has 3 cells, the header has 2"),
]


@pytest.mark.fast
@pytest.mark.parametrize(("content", "message"), BAD)
def test_malformed_records(tmp_path: Path, content: str, message: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("(", r"\(").replace(")", r"\)")):
        read_record(path)
    res = CliRunner().invoke(main, ["analyze", str(path), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert "Traceback" not in res.output


def test_huge_file_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "big.csv"
    path.write_text("time [s],force [N]\n" + "0,1\n" * 1000)
    monkeypatch.setattr(records_io, "MAX_BYTES", 100)
    with pytest.raises(ValueError, match="larger than"):
        read_record(path)


def test_folder_errors(tmp_path: Path) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match=r"no \.csv"):
        read_records(empty)
    bad_index = tmp_path / "idx"
    bad_index.mkdir()
    (bad_index / "index.csv").write_text("file,v0 [um/s]\nmissing.csv,10\n")
    with pytest.raises(ValueError, match="which is not in"):
        read_records(bad_index)
    with pytest.raises(ValueError, match="no such file or folder"):
        read_records(tmp_path / "nope")


@pytest.mark.parametrize(
    ("lines", "v0_um_s", "load_mn"),
    [
        ("# v0;200 um/s\n# load;196 mN\n", 200.0, 196.0),
        ("# v0\t200 um/s\n# Load\t0.196 N\n", 200.0, 196.0),
        ("# v0,200 um/s\n", 200.0, None),
        ("# Driving velocity = 0.2 mm/s\n# Normal force: 196 mN\n", 200.0, 196.0),
        ("# Sliding speed = 200 um/s\n# Fn = 196 mN\n", 200.0, 196.0),
        ("# v0 = 200 um/s\n# speed = 0.2 mm/s\n", 200.0, None),  # two names, one value
    ],
)
def test_an_instruments_metadata_give_v0_and_load(
    tmp_path: Path, lines: str, v0_um_s: float, load_mn: float | None
) -> None:
    """An export's `v0;200 um/s` metadata line (the file's own separator) is read: `;`, tabs and
    `,` separate a key from its value as `=` and `:` do, and the names
    an index accepts for v0 and load (driving velocity, normal force, ...) are read in the
    header lines too."""
    path = tmp_path / "r.csv"
    path.write_text(lines + "time [s];force [mN]\n0;1\n1;2\n2;3\n")
    rec = read_record(path)
    assert rec.v0.to("um/s").magnitude == pytest.approx(v0_um_s, rel=1e-12)
    if load_mn is None:
        assert rec.load is None
    else:
        assert rec.load.to("mN").magnitude == pytest.approx(load_mn, rel=1e-12)


def test_metadata_that_disagree_or_are_missing_are_said(tmp_path: Path) -> None:
    """Two lines giving v0 different values are an error naming both; a record measured without
    a driving velocity says in its row that it is not in the verdict (the row was empty)."""
    path = tmp_path / "r.csv"
    path.write_text("# v0 = 200 um/s\n# speed = 20 um/s\ntime [s],force [mN]\n0,1\n1,2\n2,3\n")
    with pytest.raises(
        ValueError, match=r"'# v0 = 200 um/s' and '# speed = 20 um/s' both give v0 and disagree"
    ):
        read_record(path)
    folder = make_folder(tmp_path / "f", [S.zv_parameters(f"{v} um/s") for v in (20, 50, 100)], index=False)
    text = (folder / "r2.csv").read_text().replace("# v0 = 0.1 mm/s\n", "")
    (folder / "r2.csv").write_text(text)
    table, verdict = analyze_records(read_records(folder))
    assert verdict is not None
    row = table[table["name"] == "r2.csv"].iloc[0]
    assert (
        not row["in_verdict"] and "no driving velocity, so not in the criterion's verdict" in row["warning"]
    )
    assert all(table[table["name"] != "r2.csv"]["warning"] == "")


def test_given_v0_and_load_are_what_the_metadata_say(tmp_path: Path) -> None:
    """An override left the header's value in .metadata; v0=nan dropped the header's value."""
    path = tmp_path / "hdr.csv"
    path.write_text("# v0 = 10 um/s\n# load = 196 mN\ntime [s],force [mN]\n0,1\n1,2\n2,3\n")
    rec = read_record(path, v0="5 um/s")
    assert rec.v0.to("um/s").magnitude == pytest.approx(5.0)
    assert S.Q_(rec.metadata["v0"]).to("um/s").magnitude == pytest.approx(5.0)
    assert rec.metadata["load"] == "196 mN"
    with pytest.raises(ValueError, match="v0=nan"):
        read_record(path, v0=float("nan"))


def test_writers_and_tables_refuse_what_would_not_read_back(tmp_path: Path) -> None:
    """A title line crashed in pandas; a line break in metadata corrupted the file; and more."""
    from stickslip.io.lab import format_lab_record
    from stickslip.io.records import Record, format_record
    from stickslip.io.tables import read_table

    title = tmp_path / "title.csv"
    title.write_text("Experiment 12\ntime [s],force [mN]\n0,1\n1,2\n2,3\n")
    with pytest.raises(ValueError, match="a title line\\? put '# ' before it"):
        read_record(title)
    rec = Record("x", np.arange(3.0), np.ones(3), metadata={"note": "a\nb"})
    with pytest.raises(ValueError, match="a line break in a header line"):
        format_record(rec)
    with pytest.raises(ValueError, match="force_unit='mN]'"):
        format_record(Record("x", np.arange(3.0), np.ones(3)), force_unit="mN]")
    with pytest.raises(ValueError, match="v0=1e-05 has no unit"):
        Record("x", np.arange(3.0), np.ones(3), v0=1e-5)
    with pytest.raises(ValueError, match="expected 1-d columns of one length"):
        format_lab_record(np.arange(3.0), np.ones(2), np.ones(3))
    table = tmp_path / "t.csv"
    table.write_text("Velocity [um/s],mu [1]\n1,0.5\n2,0.4\n")
    assert set(read_table(table, ["Velocity"], ["MU"])) == {"velocity", "mu"}  # case-insensitive
    with pytest.raises(ValueError, match="required='velocity': expected a sequence"):
        read_table(table, "velocity")


def test_text_layouts_that_read(tmp_path: Path) -> None:
    """Trailing empty cells, quotes, CR line ends, a U+2028 in a comment: every row read."""
    layouts = {
        "trailing.csv": "time [s],force [mN],\n0,1,\n1,2,\n2,3,\n",
        "quoted.csv": 'time [s],force [mN]\n0,"1"\n1,2\n2,3\n',
        "cr.csv": "time [s],force [mN]\r0,1\r1,2\r2,3\r",
        # str.splitlines split the comment here, found the header a line late, and lost t = 0
        "u2028.csv": "# note = a\u2028# b\ntime [s],force [mN]\n0,1\n1,2\n2,3\n",
    }
    for name, content in layouts.items():
        (tmp_path / name).write_bytes(content.encode())
        rec = read_record(tmp_path / name)
        np.testing.assert_array_equal(rec.time, [0.0, 1.0, 2.0])
        np.testing.assert_allclose(rec.force, [1e-3, 2e-3, 3e-3], rtol=1e-12)


def test_too_few_cycles(tmp_path: Path) -> None:
    p = S.zv_parameters("100 um/s")
    rec = synthetic_record(p, duration="30 s", rate="50 Hz")
    with pytest.raises(ValueError, match=r"complete cycles|no oscillation"):
        measure_record(rec)


@pytest.mark.fast
def test_write_record_round_trip(tmp_path: Path) -> None:
    from stickslip.io.output import ForeignFileError
    from stickslip.io.records import write_record

    rec = synthetic_record(S.zv_parameters(v0="100 um/s"), duration="20 s", rate="50 Hz", noise="0.5 mN",
                           with_velocity=True)  # fmt: skip
    path = write_record(rec, tmp_path / "r.csv")
    back = read_record(path)
    np.testing.assert_array_equal(back.time, rec.time)
    np.testing.assert_allclose(back.force, rec.force, rtol=1e-15, atol=0)
    np.testing.assert_allclose(back.velocity, rec.velocity, rtol=1e-15, atol=0)
    assert back.v0 is not None and back.load is not None
    assert back.v0.to("um/s").magnitude == pytest.approx(100.0)
    assert back.load.to("mN").magnitude == pytest.approx(196.0)
    # stickslip's own record is replaced on a rerun; a foreign file is not
    write_record(rec, path, force_unit="N")
    assert read_record(path).force[5] == pytest.approx(rec.force[5], rel=1e-15)
    (tmp_path / "mine.csv").write_text("time [s],force [N]\n0,1\n1,2\n")
    with pytest.raises(ForeignFileError, match=r"mine\.csv"):
        write_record(rec, tmp_path / "mine.csv")
    with pytest.raises(ValueError, match="force_unit='m/s'"):
        write_record(rec, tmp_path / "x.csv", force_unit="m/s")
    # as .tsv and .txt too: a rerun replaces its own file, not taken for a foreign one
    for ext in ("tsv", "txt"):
        for _ in range(2):
            again = write_record(rec, tmp_path / f"r.{ext}")
        np.testing.assert_array_equal(read_record(again).time, rec.time)


def test_metadata_read_back_as_written(tmp_path: Path) -> None:
    """Metadata read back as written: a key with '-' is kept, an empty value stays empty, and a
    key that would not read back ('k:v', '#x', two that read as one) is refused;
    write_record(path, record), the arguments swapped, is a TypeError in words (not "'str'
    object has no .metadata")."""
    from stickslip.io.records import Record, write_record

    t = np.linspace(0.0, 1.0, 10)
    meta = {"Sample Name": "PMMA #2", "note": "a = b", "empty": "", "unit": "µm", "x-y": "z", "v.1": 3.5}
    rec = Record("r", t, np.sin(t), v0=S.Q_(10, "um/s"), metadata={**meta, "V0": "dropped"})
    back = read_record(write_record(rec, tmp_path / "r.csv"))
    assert back.metadata == {
        "sample_name": "PMMA #2", "note": "a = b", "empty": "", "unit": "µm", "x-y": "z", "v.1": "3.5",
        "v0": "10.0 um/s",
    }  # fmt: skip
    again = read_record(write_record(back, tmp_path / "again.csv"))
    assert again.metadata == back.metadata  # read, write, read: the same
    for bad, message in [
        ({"k:v": 1}, "metadata key 'k:v'"),
        ({"#x": 1}, "metadata key '#x'"),
        ({"a b": 1, "A_B": 2}, "'a b' and 'A_B' both read back as 'a_b'"),
    ]:
        with pytest.raises(ValueError, match=message):
            write_record(Record("r", t, np.sin(t), metadata=bad), tmp_path / "bad.csv")
        assert not (tmp_path / "bad.csv").exists()
    with pytest.raises(TypeError, match="record: expected a stickslip Record, got str"):
        write_record(str(tmp_path / "x.csv"), rec)  # type: ignore[arg-type]


def test_messages_name_the_line_an_editor_shows(tmp_path: Path) -> None:
    """Messages name the file's line, as an editor shows it: not data rows counted from the
    header as row 1 (comment and blank lines left out), within one record of a long table, or
    from 1 at the first data row."""
    from stickslip.data.criterion import classify_file
    from stickslip.io.lab import read_lab_record
    from stickslip.io.tables import read_table
    from stickslip.laws import TabulatedLaw

    head = "# sample = PMMA\n# v0 = 10 um/s\n"
    cases = [
        (head + "time [s],force [N]\n0,1\n\n# a note\n1,2\n1,3\n", read_record, "lines 7-8"),
        (head + "time [s],force [N]\n0,1\n1,x\n", read_record, "line 5, column 'force'"),
        (head + "time [s],force [N]\n0,1\n# a note\n1,\n2,\n3,4\n", read_record, "samples at lines 6-7"),
        # the second record of a long table: its rows were counted from its own first row
        ("record,time [s],force [N]\na,0,1\na,1,2\na,2,3\nb,0,1\nb,2,2\nb,1,3\n", read_records, "lines 6-7"),
        ("record,time [s],force [N]\na,0,1\n\n,1,2\n", read_records, "line 4 has no record name"),
        (
            head + "time [s],load-point velocity [um/s],friction [1]\n0,1,0.6\n# hold\n1,1,0.6\n1,1,0.6\n",
            read_lab_record,
            "lines 6-7",
        ),
        (
            head + "time [s],load-point velocity [um/s],friction [1]\n0,1,0.6\n1,1,0.6\n\n2,-1,0.6\n",
            read_lab_record,
            "negative at line 7",
        ),
        (
            head + "time [s],load-point displacement [um],friction [1]\n0,0,0.6\n1,2,0.6\n# x\n2,1,0.6\n",
            read_lab_record,
            "negative at line 7",
        ),
        (
            head + "velocity [um/s],amplitude [mN]\n1,2\n# x\n2,0\n3,4\n4,5\n",
            classify_file,
            "line 6: amplitude 0.0",
        ),
        (
            head + "velocity [um/s],friction coefficient [1]\n0,0.5\n1,0.49\n\n3,0.48\n2,0.47\n4,0.46\n",
            TabulatedLaw.from_csv,
            "line 8: velocity 2e-06 m/s is not above",
        ),
    ]
    for content, reader, message in cases:
        path = tmp_path / "f.csv"
        path.write_text(content)
        with pytest.raises(ValueError) as err:
            reader(path)
        assert message in str(err.value), (content, str(err.value))
        assert "np.float64" not in str(err.value)
    # pandas reads a line of blanks as nothing and an indented '#' as a row of empty cells
    path = tmp_path / "g.csv"
    path.write_text("velocity [um/s],amplitude [mN]\n1,2\n \t \n  # indented\n3,4\n")
    with pytest.raises(ValueError, match="line 4 has 1 cells"):
        read_table(path, ["velocity", "amplitude"])
    # a line of blanks holding the delimiter is a row for pandas (a TSV's tab line);
    # interleaved records; a CR-only file keeps its first row after a blank line (pandas'
    # skiprows does not count it); a trailing comment is not blamed for a later NaN, nor its
    # commas counted as cells; mixed line ends are read (the csv module fails on them)
    cases = [
        ("time [s]\tforce [N]\n0\t1\n1\t2\n \t \n3\t1\n4\t2\n", read_record, "1 samples at line 4"),
        (
            "record,time [s],force [N]\na,0,1\nb,0,1\na,1,1\nb,0,1\na,2,1\nb,2,1\n",
            read_records,
            "time is not strictly increasing at lines 3 and 5",
        ),
        (
            "record,time [s],force [N]\nb,0,1\nb,,1\na,1,1\nb,,1\nb,,1\nb,3,1\n",
            read_records,
            "3 samples at lines 3 to 6 (among other",
        ),
        (
            "time [s],load-point velocity [um/s],friction [1]\n0,1,0.6 # start, slow\n1,1,0.6\n2,1,\n",
            read_lab_record,
            "line 4, column 'friction': '' is not a number",
        ),
    ]
    for content, reader, message in cases:
        path = tmp_path / ("f.tsv" if "\t" in content else "f.csv")
        path.write_text(content)
        with pytest.raises(ValueError) as err:
            reader(path)
        assert message in str(err.value), (content, str(err.value))
    path = tmp_path / "cr.csv"
    path.write_bytes(b"# v0 = 10 um/s\r\rtime [s],force [N]\r0,1\r1,2\r2,3\r3,1\r")
    np.testing.assert_array_equal(read_record(path).time, [0.0, 1.0, 2.0, 3.0])
    path.write_bytes(b"time [s],force [N]\r\n2,1\n3,1\r4,1 # a, b, c\r\n5,2\n")
    np.testing.assert_array_equal(read_record(path).time, [2.0, 3.0, 4.0, 5.0])
    # an empty header value is none, as a missing line ('# Load:' titles a section)
    path.write_text("# Load:\n# V0: 10 um/s\ntime [s],force [N]\n0,1\n1,2\n2,3\n")
    rec = read_record(path)
    assert rec.load is None and rec.v0 is not None and rec.metadata["load"] == ""
    # a table given as arrays names its rows
    with pytest.raises(ValueError, match=r"row 2: friction coefficient -0\.4"):
        TabulatedLaw(S.Q_([0.0, 1.0, 2.0, 3.0, 4.0], "um/s"), [0.5, -0.4, 0.4, 0.4, 0.4])


def test_a_record_made_in_python_is_checked_as_a_file_is() -> None:
    """Record checks its arrays as a file's are checked: a 2-D force is refused (broadcast into
    an n x n array it exhausts memory at 36k samples), lists are taken as arrays, a velocity of
    the wrong length, a NaN force and repeated times are refused."""
    from stickslip.io.records import Record

    t = np.arange(100) * 0.01
    f = np.sin(t)
    ok = Record("r", list(t), list(f))  # lists are taken as arrays
    assert isinstance(ok.time, np.ndarray) and ok.force.dtype == float
    bad = [
        (dict(force=f[:, None]), r"r: force: expected a 1-D array of samples \(N\), got shape \(100, 1\)"),
        (dict(force=f[:50]), "r: force has 50 samples, time has 100"),
        (dict(velocity=f[:99]), "r: velocity has 99 samples, time has 100"),
        (dict(force=np.where(t > 0.5, np.nan, f)), r"r: force\[51\]=nan: expected finite values \(N\)"),
        (dict(time=np.r_[t[:10], t[9:99]]), "r: time is not strictly increasing at samples 9 and 10"),
        (dict(time=t[::-1]), "r: time is not strictly increasing at samples 0 and 1"),
        (dict(force=["a"] * 100), r"r: force: expected numbers \(N\), got list"),
    ]
    for change, message in bad:
        kwargs = {"time": t, "force": f} | change
        with pytest.raises(ValueError, match=message):
            Record("r", **kwargs)


def test_no_verdict_says_why(tmp_path: Path) -> None:
    """No verdict says why: one record with its v0 is told that the criterion needs two driving
    velocities, not that records need driving velocities."""
    p = S.zv_parameters("100 um/s")
    true = S.cycle(p, probe=False)
    rec = synthetic_record(
        p, duration=f"{6 * true.period} s", rate="200 Hz", noise="0.5 mN", start=f"{true.transient_time} s"
    )
    with_v0 = write_record(tmp_path / "a.csv", rec, meta="# v0 = 100 um/s\n# load = 196 mN\n")
    bare = write_record(tmp_path / "b.csv", rec)
    for path, why in (
        (with_v0, "it needs at least 2 measured records at different driving velocities, and 1 of 1"),
        (bare, "1 of 1 records read have no driving velocity; give it in index.csv"),
    ):
        out = str(tmp_path / path.stem)
        res = CliRunner().invoke(main, ["analyze", str(path), "--out", out, "--no-plot"])
        assert res.exit_code == 0, res.output
        assert f"criterion: no verdict ({why}" in res.output, res.output


@pytest.mark.parametrize("sep", [";", "\t"])
def test_a_decimal_comma_is_named_whatever_the_delimiter(tmp_path: Path, sep: str) -> None:
    """The decimal-comma hint comes with every delimiter, not only ','."""
    path = tmp_path / "r.csv"
    path.write_text(f"time [s]{sep}force [mN]\n0{sep}10,5\n0.1{sep}11,25\n")
    with pytest.raises(ValueError, match=r"'10,5' is not a number \(a decimal comma\? write a decimal point"):
        read_record(path)


@pytest.mark.parametrize("sep", [";", "\t"])
def test_an_instruments_export_is_read(tmp_path: Path, sep: str) -> None:
    """A tribometer's export: units in parentheses ('Time (s)'), 'Fx' for the friction force,
    decimal commas between ';' or tab. It was 'not a record' (no known column); now read, the
    values against the ones written. Parentheses that hold no unit stay part of the name, and
    a file that mixes decimal points in keeps the decimal-comma hint."""
    t = np.arange(6) * 0.005
    f = np.array([-18.1251, -18.3674, 12.5, 40.0, 80.25, 90.0])  # mN
    rows = "".join(f"{a:.4f}{sep}{b:.4f}\n".replace(".", ",") for a, b in zip(t, f, strict=True))
    path = tmp_path / "umt.csv"
    path.write_text(f"# v0 = 50 um/s\nTime (s){sep}Fx (mN){sep}Fz (raw)\n" + rows.replace("\n", f"{sep}1\n"))
    rec = read_record(path)
    np.testing.assert_allclose(rec.time, t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(rec.force, f * 1e-3, rtol=1e-12)
    mixed = tmp_path / "mixed.csv"
    mixed.write_text(f"Time (s){sep}Fx (mN)\n0{sep}10,5\n0.1{sep}11,25\n")
    with pytest.raises(ValueError, match=r"'10,5' is not a number \(a decimal comma\?"):
        read_record(mixed)


def test_folders_indexes_and_columns_say_what_they_read_and_skip(tmp_path: Path) -> None:
    """An index's `driving velocity` column is read; an unknown unit in a column stickslip does
    not read does not stop the analysis; an index's bad v0 is blamed on the index, in words
    (not a Quantity's repr); files left out of the index, and a README.txt in a folder without
    one, are named; a choice between two force columns is said; the verdict names its load;
    classify refuses an amplitude in seconds and a negative error."""
    folder = tmp_path / "f"
    folder.mkdir()
    for i, v in enumerate((50, 100)):
        rec = synthetic_record(
            S.zv_parameters(f"{v} um/s"), duration="150 s", rate="200 Hz", noise="0.5 mN", seed=i
        )
        write_record(folder / f"r{i}.csv", rec)  # no v0 in the file: the index gives it
    index = folder / "index.csv"
    index.write_text(
        "file,driving velocity [um/s],normal load [mN],raw [LSB]\nr0.csv,50,196,1\nr1.csv,100,196,2\n"
    )
    recs = read_records(folder)
    assert [r.v0.to("um/s").magnitude for r in recs] == pytest.approx([50, 100])
    assert [r.load.to("mN").magnitude for r in recs] == pytest.approx([196, 196])
    res = CliRunner().invoke(main, ["analyze", str(folder), "--no-plot", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    assert "from 2 records at load 196 mN" in res.output
    index.write_text("file,v0 [um/s]\nr0.csv,-50\nr1.csv,100\n")
    with pytest.raises(
        ValueError, match=r"index.csv: line 2 \(r0.csv\): v0='-50.0 micrometer / second'"
    ) as e:
        read_records(folder)
    assert "Quantity" not in str(e.value)
    index.write_text("file,v0 [um/s]\nr0.csv,50\n")
    with pytest.warns(
        UserWarning, match=r"1 file\(s\) in the folder are not in the index and were not read: r1.csv"
    ):
        assert len(read_records(folder)) == 1
    index.unlink()
    (folder / "README.txt").write_text("Scratch test, 2026-11-25\n")
    with pytest.warns(UserWarning, match=r"not a record, skipped: .*README.txt"):
        assert len(read_records(folder)) == 2
    both = tmp_path / "both.csv"
    both.write_text("time [s],force [mN],friction_force [mN]\n0,1,2\n0.1,1,2\n0.2,1,2\n0.3,1,2\n")
    with pytest.warns(UserWarning, match="columns 'force', 'friction_force': the force analysed is 'force'"):
        read_record(both)
    from stickslip.data.criterion import classify_file

    c = tmp_path / "c.csv"
    c.write_text("velocity [um/s],amplitude [s]\n10,1\n20,2\n40,3\n80,4\n")
    with pytest.raises(ValueError, match=r"has unit \[s\], of dimension \[time\]: expected a force"):
        classify_file(c)
    c.write_text(
        "velocity [um/s],amplitude [mN],amplitude_err [mN]\n10,1,0.1\n20,2,-0.1\n40,3,0.1\n80,4,0.1\n"
    )
    with pytest.raises(ValueError, match=r"c.csv: line 3: amplitude_err -0.1 is negative"):
        classify_file(c)


def test_the_features_fit_does_not_blame_the_model_for_its_own_bias() -> None:
    """On a noise-free record the model itself made, `--method features` does not warn that 'the
    model does not describe the record': its chi-square is over features that carry a sampling
    bias their spread does not show, so a large one is not the model's fault."""
    from stickslip.data.fitting import fit_record

    rec = synthetic_record(
        S.zv_parameters("100 um/s"), duration="150 s", rate="500 Hz", noise="0 N", start="20 s"
    )
    r = fit_record(rec, method="features")
    assert r.reduced_chi2 > 2
    assert "over the cycle features" in r.warnings[0] and "sample interval, 0.002 s" in r.warnings[0]
    assert not any("does not describe" in w for w in r.warnings)


def test_a_stage_displacement_is_not_taken_for_the_sliders(tmp_path: Path) -> None:
    """A scratch tester logs its stage, v0 t; read as the slider's it would give a stick fraction
    of 0 for a record that sticks 99 % of the time. A column moving
    steadily at the driving velocity is named as the load point's and gives no stick fraction;
    the slider's displacement gives the stick fraction it has."""
    import dataclasses

    from stickslip.io.records import Record

    p = S.zv_parameters("100 um/s")
    tr = S.simulate(p, duration="100 s", n_points=20000)
    slider = Record("r", tr.time, tr.spring_force, displacement=tr.position, v0=p.v0, load=p.load)
    stage = dataclasses.replace(slider, displacement=1e-4 * tr.time)
    _, good = measure_record(slider)
    assert good.stick_fraction > 0.9 and "load point" not in good.warning
    _, bad = measure_record(stage)
    assert math.isnan(bad.stick_fraction)
    assert "the displacement column moves steadily at 100 um/s, the driving velocity" in bad.warning


def test_a_header_of_unknown_names_lists_the_names(tmp_path: Path) -> None:
    """A header of the right shape with names stickslip does not know ('Zeit [s];Reibkraft [N]')
    lists the names it reads, not 'a title line? put # before it' (kept for a real title)."""
    de = tmp_path / "de.csv"
    de.write_text("Zeit [s];Reibkraft [N]\n0;1\n1;2\n2;3\n")
    with pytest.raises(ValueError, match=r"\(columns are named .*friction_force.*time.*rename yours"):
        read_record(de)
    title = tmp_path / "title.csv"
    title.write_text("My scratch test\n0,1\n1,2\n")
    with pytest.raises(ValueError, match=r"a title line\? put '# ' before it"):
        read_record(title)


def _f1_setup(v0: str) -> S.PhysicalParameters:
    """A fast, light set-up: 50 g, 2 kN/m, 2 N, mu_s 0.4, F1 with a = 50 s/m."""
    law = S.PhysicalWeakeningLaw(mu_s=0.4, a="50 s/m")
    return S.PhysicalParameters(mass="50 g", stiffness="2000 N/m", load="2 N", v0=v0, law=law)


def test_stick_fraction_force_plausibility_and_dead_columns() -> None:
    """Three checks on one record each:

    * velocity noise of v0 at 5 mm/s (here 0.8 v0), where slip is 15 % of the cycle: the slow
      start and end of each slip lie below four noise deviations (counted as rest they give
      0.904 for 0.847); a slip is grown over the samples that still move its way;
    * a velocity column of zeros gives no stick fraction (not 1), with a warning;
    * a force column in mN read as N (amplitudes of 1000 N against a 2 N load) is warned."""
    from stickslip.io.records import Record

    true, rec = steady_record(_f1_setup("5 mm/s"), 12, "1 kHz", with_velocity=True)
    assert rec.velocity is not None
    rng = np.random.default_rng(11)
    noisy = Record(
        rec.name, rec.time, rec.force, None, rec.velocity + 4e-3 * rng.standard_normal(rec.time.size)
    )
    s = measure_record(noisy)[1]
    assert true.stick_fraction == pytest.approx(0.8466, abs=1e-4)
    assert s.stick_fraction == pytest.approx(true.stick_fraction, abs=0.02)  # +0.017; ungrown slips: +0.046
    assert measure_record(rec)[1].stick_fraction == pytest.approx(true.stick_fraction, abs=2e-3)  # noise-free
    dead = Record(rec.name, rec.time, rec.force, None, np.zeros(rec.time.size), rec.v0, rec.load)
    s = measure_record(dead)[1]
    assert math.isnan(s.stick_fraction) and "the velocity column is zero (or missing) throughout" in s.warning
    mislabelled = Record(rec.name, rec.time, 1e3 * rec.force, None, None, rec.v0, rec.load)
    s = measure_record(mislabelled)[1]
    assert "times the normal load 2 N: a friction coefficient above 5 is not plausible" in s.warning
    assert "coefficient above 5" not in measure_record(rec)[1].warning


def test_the_noise_of_a_quantized_fast_record_and_a_fit_better_than_its_noise() -> None:
    """1 mN ADC steps over 0.3 mN of noise (0.41 mN of error) on a record of 136 samples a cycle:
    the second differences are clipped at four deviations until none is left, since their RMS
    with the fast drops kept (only their largest 1 % left out) reads 1.98 mN. A fit whose
    reduced chi-square falls below 0.25 says that the noise it read, and the errors with it,
    are too large."""
    from stickslip.core.noise import noise_level
    from stickslip.data.fitting import fit_record
    from stickslip.io.records import Record

    _, rec = steady_record(_f1_setup("5 mm/s"), 8, "1 kHz")
    rng = np.random.default_rng(7)
    error = 1e-3 * np.round(1e3 * rec.force + 0.3 * rng.standard_normal(rec.time.size)) - rec.force
    adc = Record(rec.name, rec.time, rec.force + error, None, None, rec.v0, rec.load)
    assert noise_level(adc.force) == pytest.approx(float(np.std(error)), rel=0.15)  # was 4.8 times it
    res = fit_record(rec, noise=None)  # noise-free: the noise read is the rounding's, far above the misfit
    assert any("the record fits better than the noise read off it" in w for w in res.warnings), res.warnings
    res = fit_record(adc)
    assert not any("fits better than the noise" in w for w in res.warnings), res.warnings
    assert 0.5 < res.reduced_chi2 < 1.5


def test_a_decimal_point_among_decimal_commas_is_named_at_its_line(tmp_path: Path) -> None:
    """A file of decimal commas with one row written with a point far down is refused at that
    row, named with what is wrong with it (not at a good row near the top, with the advice to
    write decimal points)."""
    rows = [f"{i},0;{10 + i % 7},25" for i in range(60)]
    rows[57] = "57.0;12.25"
    path = tmp_path / "r.csv"
    path.write_text("# v0;500 um/s\ntime [s];force [mN]\n" + "\n".join(rows) + "\n")
    with pytest.raises(
        ValueError, match=r"r.csv: line 60, column 'time': '57.0' has a decimal point, and the"
    ):
        read_record(path)


def test_an_f1_fit_of_a_record_that_never_sticks_says_so() -> None:
    """A record whose velocity shows no rest says that F1 cannot make its motion: the F1 fit of
    a pure-slip record gives k and m to 0.06 % for half their true values (only m/k is set),
    with no more than a chi-square warning."""
    from stickslip.data.fitting import fit_record

    _, rec = steady_record(cubic_params(48.5), 10, "500 Hz", with_velocity=True)
    assert measure_record(rec)[1].stick_fraction == 0.0
    res = fit_record(rec, method="features")
    assert any("the record never sticks (stick fraction 0" in w for w in res.warnings), res.warnings


def test_a_folder_of_title_lines_says_why_none_is_a_record(tmp_path: Path) -> None:
    """A folder of exports that open with a title line says 'none of its 2 files is a record'
    with the first file's reason."""
    for name in ("a.csv", "b.csv"):
        (tmp_path / name).write_text("Pin-on-disc test PMMA/steel\ntime [s],force [N]\n0,1\n0.1,2\n")
    with pytest.raises(
        ValueError, match=r"none of its 2 .* is a record \(the first: .*a.csv: line 1 .*a title line"
    ):
        read_records(tmp_path)


def test_slips_grow_the_same_from_any_start_through_gaps_and_over_an_offset() -> None:
    """Slips grow the same whatever the record's start: one that starts mid-slip pairs the runs'
    starts and ends rightly (paired wrongly, half the slips are not grown: 0.700 for 0.660 from
    rest); a rest biased one way (an offset of 2 noise deviations) does not let a slip grow
    through the stick (0.225 for 0.61); missing samples are not rest. Slip shapes sin^2 over 40
    of 100 samples."""
    from stickslip.data.records import _at_rest

    one = np.zeros(100)
    one[:40] = np.sin(np.linspace(0.0, np.pi, 40)) ** 2
    v = np.tile(one, 4)
    fractions = {float(np.nanmean(_at_rest(np.roll(v, -shift), 0.6))) for shift in (0, 20, 50)}
    assert len(fractions) == 1 and abs(fractions.pop() - 0.61) < 0.06
    rng = np.random.default_rng(1)
    one[:40] = np.sin(np.linspace(0.0, np.pi, 40))
    v = np.tile(one, 4)
    for offset in (0.0, 0.05, 0.1):  # the noise deviation is 0.05, the rest limit four of them
        noisy = v + rng.normal(0.0, 0.05, v.size) + offset * (v == 0)
        assert float(np.nanmean(_at_rest(noisy, 0.2))) == pytest.approx(0.61, abs=0.03), offset
    gaps = v.copy()
    gaps[[5, 6, 30, 105, 106, 130]] = np.nan  # inside slips
    rest = _at_rest(gaps, 0.2)
    assert np.isnan(rest[[5, 6, 30]]).all() and float(np.nanmean(rest)) == pytest.approx(
        float(np.nanmean(_at_rest(v, 0.2)[np.isfinite(gaps)])), abs=0.01
    )


def test_the_velocity_shows_the_regime_of_each_record(tmp_path: Path) -> None:
    """Each record's observed regime: at rest in every cycle (stick-slip, down to a stick of 1 %
    of the cycle), in none (pure slip), unknown without a velocity; analyze sets it against the
    criterion's verdict, which infers the regime from the amplitudes alone."""
    from types import SimpleNamespace

    from stickslip.data.records import observed_line, observed_regime

    cases = {"zv": S.zv_parameters("100 um/s"), "c45": cubic_params(45.0), "c48": cubic_params(48.5)}
    folder = tmp_path / "v"
    folder.mkdir()
    recs = {}
    for i, (name, p) in enumerate(cases.items()):
        true, rec = steady_record(p, 12, "500 Hz", noise="0.5 mN", seed=i, with_velocity=True)
        assert true.regime == ("pure-slip" if name == "c48" else "stick-slip")
        v0 = p.v0.to("um/s").magnitude
        meta = f"# v0 = {v0} um/s\n# load = {p.load.to('N').magnitude} N\n"
        write_record(folder / f"{name}.csv", rec, "time [s],force [mN],velocity [um/s]", meta)
        recs[name] = rec
    assert 0.005 < S.cycle(cases["c45"], probe=False).stick_fraction < 0.02  # a short stick
    got = {k: measure_record(r)[1].observed_regime for k, r in recs.items()}
    assert got == {"zv": "stick-slip", "c45": "stick-slip", "c48": "pure-slip"}
    no_velocity = records_io.Record("f", recs["zv"].time, recs["zv"].force, None, None, None, None, {})
    assert measure_record(no_velocity)[1].observed_regime == "unknown"
    assert observed_regime([1.0, 0.0, np.nan]) == "mixed" and observed_regime([np.nan]) == "unknown"
    assert observed_regime([1.0, 0.5]) == "stick-slip" and observed_regime([0.0, 0.5]) == "unresolved"
    table, _ = analyze_records(read_records(folder))
    named = dict(zip(table["name"], table["observed_regime"], strict=True))
    assert named == {f"{k}.csv": v for k, v in got.items()}
    line = observed_line(table, SimpleNamespace(verdict="stick-slip"))  # over the verdict's: at 1 N
    assert line is not None
    assert line.startswith(
        "observed: of the 2 records in the verdict, the velocity of 2 shows 1 stick-slip, 1 pure"
    )
    assert line.endswith("; 1 pure-slip where the criterion says stick-slip (c48.csv)")
    agree = observed_line(table[table["name"] != "c48.csv"], SimpleNamespace(verdict="stick-slip"))
    assert agree is not None and agree.endswith(
        "; none shows pure-slip, as the criterion's stick-slip has it"
    )
    res = CliRunner().invoke(
        main, ["analyze", str(folder / "c48.csv"), "--no-plot", "--out", str(tmp_path / "o")]
    )
    assert res.exit_code == 0, res.output
    assert "observed: of the 1 record measured, the velocity of 1 shows 1 pure-slip" in res.output
    assert "pure-slip" in res.output.split("observed:", 1)[0]  # the table's column


@pytest.mark.parametrize(
    ("rate", "seen"), [("200 Hz", "unresolved"), ("300 Hz", "unresolved"), ("1 kHz", "stick-slip")]
)
def test_a_stick_of_a_sample_or_two_is_unresolved_not_pure_slip(rate: str, seen: str) -> None:
    """The cubic law's stick of 1 % of the cycle, sampled 300 times a cycle, is a rest of a sample
    or two: rests shorter than 3 samples are unresolved, not pure slip (read as pure slip, or
    mixed at 400 Hz, analyze would set the record against a criterion that is right)."""
    p = cubic_params(45.0)
    true, rec = steady_record(p, 12, rate, noise="0.5 mN", with_velocity=True)
    assert true.regime == "stick-slip" and true.stick_fraction < 0.011
    _, s = measure_record(rec)
    assert s.observed_regime == seen
    assert s.stick_fraction > 0.0  # the short rests are counted in the stick fraction all the same


def test_a_slip_that_slows_into_the_velocitys_noise_reads_as_stick_slip() -> None:
    """What docs/records.md says the observed regime cannot tell: pure slip at 47.6 mm/s, whose
    slowest speed lies within the noise band (velocity noise of a tenth of v0) for several samples."""
    import dataclasses

    p = cubic_params(47.6)
    true, rec = steady_record(p, 12, "500 Hz", noise="0.5 mN", with_velocity=True)
    assert true.regime == "pure-slip"
    rng = np.random.default_rng(3)
    noisy = dataclasses.replace(
        rec, velocity=rec.velocity + 0.1 * 0.0476 * rng.standard_normal(rec.time.size)
    )
    assert measure_record(rec)[1].observed_regime == "pure-slip"
    assert measure_record(noisy)[1].observed_regime == "stick-slip"
