"""Nothing lost: atomic files, staged folders, no foreign file overwritten (issue 11)."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from stickslip.cli import main
from stickslip.dynamics.sweep import load_sweep
from stickslip.io.output import MANIFEST, ForeignFileError, OutputFolder, atomic_write, own_kind

SWEEP = ["sweep", "--nu", "0.01..0.1", "--c", "3.8", "--num", "5", "--quiet"]


def _run(args: list[str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "stickslip.cli", *args], capture_output=True, text=True, timeout=300
    )


#: the header of a trajectory CSV (a file stickslip recognises as its own)
TRAJECTORY = "time [s],position [m],velocity [m/s],spring_force [N],phase"


def test_kill_during_a_write_leaves_the_previous_file(tmp_path: Path) -> None:
    """A process killed (SIGKILL) in the middle of writing: the old file is intact, no debris
    but the temporary file, which is never the target."""
    target = tmp_path / "data.csv"
    target.write_text(TRAJECTORY + "\n0,1\n")  # stickslip's trajectory header: replaceable
    before = target.read_bytes()
    script = textwrap.dedent(
        f"""
        import os, signal
        from stickslip.io.output import atomic_write

        def write(path):
            with open(path, "w") as fh:
                fh.write("time [s],position [m],velocity [m/s],spring_force [N],phase\\n" + "1,2\\n" * 100000)
                fh.flush()
                os.kill(os.getpid(), signal.SIGKILL)  # dies half way, the file still open

        atomic_write({str(target)!r}, write, kind="trajectory")
        """
    )
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=60)
    assert proc.returncode == -signal.SIGKILL
    assert target.read_bytes() == before
    debris = [p.name for p in tmp_path.iterdir() if p.name != "data.csv"]
    assert len(debris) == 1 and debris[0].startswith(".data.csv.") and ".part" in debris[0]
    # the next write replaces the file and removes the dead writer's temporary file
    atomic_write(target, lambda p: Path(p).write_text(TRAJECTORY + "\n2,3\n"), kind="trajectory")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data.csv"]


@pytest.mark.parametrize(
    "delay",
    [
        pytest.param(0.2, marks=pytest.mark.slow),
        1.0,
        pytest.param(2.5, marks=pytest.mark.slow),
    ],  # each a run: 1.0 in the default
)
def test_sigkill_of_a_sweep_never_leaves_a_partial_file(tmp_path: Path, delay: float) -> None:
    """Killed (SIGKILL) at any moment while `sweep` writes, sweep.nc is the previous complete
    sweep or the new one, never a 0-byte file where a good one stood."""
    out = tmp_path / "sweep.nc"
    first = _run([*SWEEP, "--out", str(out), "--no-plot"])
    assert first.returncode == 0, first.stderr
    old = load_sweep(out)
    proc = subprocess.Popen(
        [sys.executable, "-m", "stickslip.cli", *SWEEP[:3], "0.01..0.2", *SWEEP[4:], "--out", str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    time.sleep(delay)
    proc.kill()
    proc.wait(timeout=30)
    now = load_sweep(out)  # complete and readable, whichever it is
    assert float(now.nu.max()) in (0.1, 0.2)
    if float(now.nu.max()) == 0.1:  # the old sweep, untouched
        np.testing.assert_array_equal(now.amplitude.values, old.amplitude.values)
    else:  # the new one, whole
        assert now.amplitude.size == 5 and np.isfinite(now.amplitude.values).all()


@pytest.mark.fast
def test_foreign_file_is_not_overwritten(tmp_path: Path) -> None:
    """`sweep --out` never turns a user's file into NetCDF: a user's CSV is not overwritten, and a
    name other than .nc or .csv is refused as such."""
    target = tmp_path / "afile.csv"
    target.write_text("my notes\n")
    res = CliRunner().invoke(main, [*SWEEP, "--out", str(target), "--no-plot"])
    assert res.exit_code == 2
    assert target.read_text() == "my notes\n"
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: ") and "--overwrite" in lines[0]
    assert str(target) in lines[0]
    res = CliRunner().invoke(main, [*SWEEP, "--out", str(target), "--no-plot", "--overwrite"])
    assert res.exit_code == 0, res.output
    assert own_kind(target) == "sweep"


def test_own_outputs_are_replaced_without_asking(tmp_path: Path) -> None:
    for _ in range(2):
        res = CliRunner().invoke(main, ["simulate", "--nu", "0.1", "--c", "3", "--out", str(tmp_path)])
        assert res.exit_code == 0, res.output
    assert own_kind(tmp_path / "trajectory.csv") == "trajectory"
    assert own_kind(tmp_path / "spring_force.png") == "figure"
    assert own_kind(tmp_path / "spring_force.svg") == "figure"
    manifest = json.loads((tmp_path / MANIFEST).read_text())
    files = manifest["runs"]["simulate"]["files"]
    assert set(files) == {"trajectory.csv", "spring_force.png", "spring_force.svg"}
    # what made the folder: the command, its options, the source's commit where it runs from a
    # checkout ('stickslip 0.1.0' alone is shared by many commits)
    run = manifest["runs"]["simulate"]
    assert run["command"] == "stickslip simulate"
    assert run["options"]["nu"] == 0.1 and run["options"]["c"] == 3.0
    assert run.get("source", "git ").startswith("git ")
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".stickslip-staging")]


def test_a_foreign_file_in_an_output_folder_stops_the_run_before_anything_is_written(tmp_path: Path) -> None:
    (tmp_path / "trajectory.csv").write_text("a colleague's table\n")
    res = CliRunner().invoke(main, ["simulate", "--nu", "0.1", "--c", "3", "--out", str(tmp_path)])
    assert res.exit_code == 2
    assert (tmp_path / "trajectory.csv").read_text() == "a colleague's table\n"
    assert not (tmp_path / "spring_force.png").exists()


def test_a_failed_run_publishes_nothing(tmp_path: Path) -> None:
    """Files of one run appear together or not at all: an error half way leaves the folder as it was."""
    (tmp_path / "a.json").write_text(json.dumps({"generator": "stickslip 0.1.0 (x)", "v": 1}))
    with pytest.raises(RuntimeError), OutputFolder(tmp_path, "test") as out:
        out.write("a.json", "x", lambda p: Path(p).write_text('{"generator": "stickslip 0.1.0 (x)", "v": 2}'))
        out.write("b.json", "x", lambda p: Path(p).write_text("{}"))
        raise RuntimeError("killed half way")
    assert json.loads((tmp_path / "a.json").read_text())["v"] == 1
    assert not (tmp_path / "b.json").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json"]


def test_stale_staging_of_a_dead_run_is_removed(tmp_path: Path) -> None:
    stale = tmp_path / ".stickslip-staging-999999999-abc"
    stale.mkdir()
    (stale / "half.nc").write_bytes(b"CDF")
    with OutputFolder(tmp_path, "test") as out:
        out.write("x.json", "x", lambda p: Path(p).write_text('{"generator": "stickslip 0.1.0 (x)"}'))
    assert not stale.exists()


def test_disk_errors_name_the_file_and_keep_the_old_one(tmp_path: Path) -> None:
    target = tmp_path / "x.csv"
    target.write_text(TRAJECTORY + "\n")

    def full(path: str) -> None:
        with open(path, "w") as fh:
            fh.write("time [s]")
        raise OSError(28, "No space left on device", path)

    with pytest.raises(OSError) as info:
        atomic_write(target, full, kind="trajectory")
    assert info.value.filename == str(target)
    assert "No space left" in str(info.value)
    assert target.read_text() == TRAJECTORY + "\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.csv"]


def test_foreign_file_error_is_a_value_error() -> None:
    assert issubclass(ForeignFileError, ValueError)


def test_an_unwritable_output_folder_is_one_line(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    res = CliRunner().invoke(main, ["simulate", "--nu", "0.1", "--c", "3", "--out", str(blocker / "sub")])
    assert res.exit_code == 1
    assert res.output.count("\n") == 1 and str(blocker / "sub") in res.output and "cannot write" in res.output


def test_envelope_keeps_every_extremum_to_the_end() -> None:
    """The decimated series drawn in figures keeps each bin's extremes, the last samples included."""
    import numpy as np

    from stickslip.plots.style import envelope

    n = 42_829  # 10 000 bins of 4 leave 2 829 samples past the last whole bin
    x = np.arange(n, dtype=float)
    y = np.sin(x / 50.0)
    y[n - 1000] = 5.0  # a spike in the tail
    xs, ys = envelope(x, y)
    assert ys.size < 25_000
    assert np.all(np.diff(xs) >= 0)
    assert ys.max() == 5.0
    assert xs[-1] == n - 1
    # every stretch of 100 samples is represented
    assert np.max(np.diff(xs)) <= 100


@pytest.mark.fast
def test_a_figure_is_laid_out_once_for_all_its_formats(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The SVG reuses the PNG's layout (one constrained layout, not two); the figure keeps its engine."""
    import numpy as np
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    from stickslip.plots.figures import figure_bytes, save_figure
    from stickslip.plots.style import subplots

    runs = []
    execute = ConstrainedLayoutEngine.execute

    def counted(self: ConstrainedLayoutEngine, fig: object) -> object:
        runs.append(1)
        return execute(self, fig)

    monkeypatch.setattr(ConstrainedLayoutEngine, "execute", counted)
    fig, ax = subplots(figsize=(4.0, 3.0))
    sc = ax.scatter(np.arange(5.0), np.arange(5.0), c=np.arange(5.0))
    fig.colorbar(sc, ax=ax, label=r"$\mu_s W$")
    ax.set_xlabel(r"time $\tau$ [$\sqrt{m/k}$]")
    engine = fig.get_layout_engine()
    assert isinstance(engine, ConstrainedLayoutEngine)
    save_figure(fig, tmp_path / "f")
    assert {p.name for p in tmp_path.iterdir()} >= {"f.png", "f.svg"}
    assert len(runs) == 1
    assert fig.get_layout_engine() is engine  # a figure changed later is laid out again
    blobs = figure_bytes(fig)
    assert set(blobs) == {"png", "svg"} and len(runs) == 2


def test_a_measured_record_is_not_taken_for_a_trajectory(tmp_path: Path) -> None:
    """Any CSV starting 'time [' counted as stickslip's trajectory, and was replaced without a word."""
    from stickslip import Q_
    from stickslip.io import write_columns

    mine = tmp_path / "trajectory.csv"
    mine.write_text("time [s],force [mN]\n0,1\n1,2\n")
    assert own_kind(mine) is None
    with pytest.raises(ForeignFileError, match="not a file stickslip wrote"):
        write_columns(mine, {"time [s]": [0.0, 1.0]})
    assert mine.read_text() == "time [s],force [mN]\n0,1\n1,2\n"
    sim = ["simulate", "--nu", "0.1", "--c", "3", "--no-plot", "--out"]
    res = CliRunner().invoke(main, [*sim, str(tmp_path)])
    assert res.exit_code != 0 and "trajectory.csv" in res.output
    assert mine.read_text() == "time [s],force [mN]\n0,1\n1,2\n"
    # its own trajectory is replaced, as before
    ours = tmp_path / "ours"
    for _ in range(2):
        res = CliRunner().invoke(main, [*sim, str(ours)])
        assert res.exit_code == 0, res.output
    assert own_kind(ours / "trajectory.csv") == "trajectory"
    # pint columns in the unit of their header (numpy stripped the units: 1 mN was written as 1 N)
    path = write_columns(tmp_path / "q.csv", {"force [N]": Q_([1.0, 2.0], "mN")})
    assert Path(path).read_text().splitlines()[1:] == ["0.001", "0.002"]
    with pytest.raises(ValueError, match="do not convert to m"):
        write_columns(tmp_path / "r.csv", {"force [m]": Q_([1.0], "mN")})


def test_the_spring_force_legend_hides_no_data() -> None:
    """A saw-tooth fills its axes corner to corner: the stick/slip legend sat in the lower right
    corner over the last drop's bottom; it is drawn below the axes, outside them."""
    import stickslip as S
    from stickslip.plots.figures import plot_spring_force

    traj = S.simulate(S.zv_parameters("100 um/s"), duration="70 s")
    fig = plot_spring_force(traj, title="zv")
    fig.draw_without_rendering()  # the constrained layout places the legend
    ax = fig.axes[0]
    assert ax.get_legend() is None and len(fig.legends) == 1
    box, axes_box = fig.legends[0].get_window_extent(), ax.get_window_extent()
    assert box.y1 <= axes_box.y0  # below the plotting area
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert labels == ["stick (block at rest)", "slip (block moving)"]


def test_outputs_have_the_mode_a_plain_open_gives(tmp_path: Path) -> None:
    """Files stickslip writes get 0666, folders 0777, less the umask, as open() and mkdir() give:
    not tempfile.mkstemp's 0600 kept through the rename into place (nor 0700 for a store's
    folder), which a lab sharing results by group cannot read."""
    import os
    import stat

    import stickslip as S
    from stickslip.data.records import synthetic_record
    from stickslip.io.output import temporary_folder
    from stickslip.io.records import write_record

    old = os.umask(0o022)
    try:
        rec = synthetic_record(S.zv_parameters("100 um/s"), duration="20 s", rate="20 Hz")
        for path in (
            write_record(rec, tmp_path / "r.csv"),
            atomic_write(tmp_path / "a.txt", lambda p: Path(p).write_text("x"), kind="test"),
        ):
            assert stat.S_IMODE(os.stat(path).st_mode) == 0o644, path
        assert stat.S_IMODE(os.stat(temporary_folder(str(tmp_path), ".t-")).st_mode) == 0o755
        os.umask(0o077)  # a private umask is kept
        path = atomic_write(tmp_path / "b.txt", lambda p: Path(p).write_text("x"), kind="test")
        assert stat.S_IMODE(os.stat(path).st_mode) == 0o600
    finally:
        os.umask(old)


def test_the_same_figure_is_the_same_svg_and_errors_speak_the_callers_language(tmp_path: Path) -> None:
    """Two identical runs write the same SVG bytes (no date, no ids from a random salt); a
    foreign file's error names --overwrite to a command's user and overwrite=True to a Python
    caller, each only the one they can give."""
    import matplotlib.pyplot as plt

    from stickslip.io.output import ForeignFileError, check_target
    from stickslip.plots.figures import figure_bytes

    def svg() -> bytes:
        fig, ax = plt.subplots()
        ax.plot([1, 2, 3], [1, 4, 9], marker="o", label="a")
        ax.legend()
        try:
            return figure_bytes(fig, ("svg",))["svg"]
        finally:
            plt.close(fig)

    first = svg()
    assert first == svg() and b"<dc:date>" not in first
    target = tmp_path / "notes.csv"
    target.write_text("a colleague's notes\n")
    with pytest.raises(ForeignFileError, match=r"give overwrite=True to replace it"):
        check_target(str(target), "sweep")
    res = CliRunner().invoke(main, [*SWEEP, "--out", str(target), "--no-plot"])
    assert "give --overwrite to replace it" in res.output and "overwrite=True" not in res.output


def test_provenance_is_stickslips_own_command_line_only(tmp_path: Path) -> None:
    """The manifest's provenance is stickslip's own: under `python -m stickslip` the command reads
    'stickslip simulate' (not 'stickslip -m stickslip simulate'); another click app calling the
    Python API is not taken for stickslip's command line (no 'give --overwrite', not its
    command in the manifest); an install inside a user's own git repository does not record
    the user's commit."""
    import click

    import stickslip as ss
    from stickslip.io.output import _source_revision, check_target

    out = tmp_path / "m"
    res = subprocess.run(
        [
            sys.executable,
            "-m",
            "stickslip",
            "simulate",
            "--nu",
            "0.1",
            "--c",
            "3",
            "--out",
            str(out),
            "--no-plot",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert res.returncode == 0, res.stderr
    run = json.loads((out / MANIFEST).read_text())["runs"]["simulate"]
    assert run["command"] == "stickslip simulate" and run["options"]["points"] == 4000

    target = tmp_path / "notes.txt"
    target.write_text("a colleague's notes\n")

    @click.command()
    def their_app() -> None:
        check_target(str(target), "sweep")

    res = CliRunner().invoke(their_app, [])
    assert isinstance(res.exception, ForeignFileError) and "give overwrite=True" in str(res.exception)
    # a copy of the package inside another git repository (a project's .venv) is not a checkout
    if shutil.which("git") is not None:
        repo = tmp_path / "project"
        (repo / "site").mkdir(parents=True)
        subprocess.run(["git", "init", "-q", str(repo)], check=True)
        who = ["-c", "user.email=a@example.org", "-c", "user.name=a"]
        subprocess.run(
            ["git", "-C", str(repo), *who, "commit", "-q", "--allow-empty", "-m", "theirs"], check=True
        )
        package = Path(ss.__file__).parent
        shutil.copytree(package, repo / "site" / "stickslip", ignore=shutil.ignore_patterns("__pycache__"))
        code = "from stickslip.io.output import _source_revision; print(repr(_source_revision()))"
        res = subprocess.run(
            [sys.executable, "-c", code],
            capture_output=True,
            text=True,
            env={**os.environ, "PYTHONPATH": str(repo / "site")},
        )
        assert res.stdout.strip() == "''", (res.stdout, res.stderr)
    assert _source_revision() in ("",) or _source_revision().startswith("git ")
