"""One-line, cause-naming messages: a full disk under NetCDF output, a store's damaged array
metadata on resume, and refused runs that leave no folder behind."""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import signal
import subprocess
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

import stickslip as ss
from stickslip.cli import main
from stickslip.dynamics.sweep import load_sweep, save_sweep, sweep
from stickslip.io import output
from stickslip.io.output import OutputFolder, atomic_write, netcdf_writer
from stickslip.scale import StoreError

#: seconds any one test here may take (each takes about one)
LIMIT_S = 60


@pytest.fixture(autouse=True)
def _bounded() -> Iterator[None]:
    """Fail a test that runs longer than LIMIT_S (where SIGALRM exists, in the main thread)."""
    if not hasattr(signal, "SIGALRM") or threading.current_thread() is not threading.main_thread():
        yield
        return

    def expired(signum: int, frame: Any) -> None:
        raise TimeoutError(f"the test took longer than {LIMIT_S} s")

    old = signal.signal(signal.SIGALRM, expired)
    signal.alarm(LIMIT_S)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def _lines(text: str) -> list[str]:
    return [line for line in text.strip().splitlines() if line.strip()]


# ----------------------------------------------------------------------------- NetCDF on a full disk

SWEEP = ["sweep", "--nu", "0.01..0.1", "--c", "3.8", "--num", "4", "--quiet", "--no-plot"]


def _dataset(n: int) -> xr.Dataset:
    rng = np.random.default_rng(0)
    return xr.Dataset({"amplitude": ("v0", rng.random(n))}, coords={"v0": np.arange(n, dtype=float)})


def _full_disk_while_writing(monkeypatch: pytest.MonkeyPatch) -> None:
    """Make the next NetCDF write fail as netCDF4 does on a full disk: part of the file, then
    RuntimeError('NetCDF: HDF error'); from then on no file can be made in any folder."""
    full = {"now": False}
    made = output.temporary_file

    def temporary_file(folder: str, prefix: str, suffix: str = "") -> tuple[int, str]:
        if full["now"]:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), os.path.join(folder, prefix))
        return made(folder, prefix, suffix)

    def to_netcdf(self: xr.Dataset, path: str, *args: Any, **kwargs: Any) -> None:
        with open(path, "wb") as fh:
            fh.write(b"\x89HDF\r\n\x1a\n" + bytes(1000))  # what HDF5 wrote before the disk filled
        full["now"] = True
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr(output, "temporary_file", temporary_file)
    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)


def test_a_full_disk_under_netcdf_output_names_the_file_and_the_cause(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "s.nc"
    res = CliRunner().invoke(main, [*SWEEP, "--out", str(target)])
    assert res.exit_code == 0, res.output
    before = target.read_bytes()
    entries = sorted(os.listdir(tmp_path))
    _full_disk_while_writing(monkeypatch)
    res = CliRunner().invoke(main, [*SWEEP, "--out", str(target)])
    assert res.exit_code == 1
    lines = _lines(res.output)
    assert len(lines) == 1, res.output  # one line, no traceback
    assert lines[0] == (
        f"Error: {target}: cannot write (No space left on device; the NetCDF library said "
        "'NetCDF: HDF error') (the previous file, if any, is untouched)"
    )
    assert target.read_bytes() == before  # the previous complete file
    assert sorted(os.listdir(tmp_path)) == entries  # no partial file, no staging folder


def test_save_sweep_on_a_full_disk_raises_an_oserror_naming_the_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "new" / "s.nc"
    _full_disk_while_writing(monkeypatch)
    with pytest.raises(OSError) as err:
        save_sweep(_dataset(10), target)
    assert err.value.errno == errno.ENOSPC
    assert err.value.filename == str(target)
    assert "No space left on device" in str(err.value) and "NetCDF: HDF error" in str(err.value)
    assert os.listdir(tmp_path) == []  # neither the partial file nor the folder made for it


def test_another_netcdf_failure_names_the_file_and_the_librarys_words(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def to_netcdf(self: xr.Dataset, path: str, *args: Any, **kwargs: Any) -> None:
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)
    target = tmp_path / "s.nc"
    with pytest.raises(OSError) as err:
        atomic_write(target, netcdf_writer(_dataset(3), "sweep"), kind="sweep")
    assert err.value.filename == str(target)
    assert err.value.strerror == "cannot write (the NetCDF library failed: 'NetCDF: HDF error')"
    assert os.listdir(tmp_path) == []


def test_netcdf_errors_that_are_not_the_librarys_pass_unchanged(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def to_netcdf(self: xr.Dataset, path: str, *args: Any, **kwargs: Any) -> None:
        raise RuntimeError("something else")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)
    with pytest.raises(RuntimeError, match=r"^something else$"):
        atomic_write(tmp_path / "s.nc", netcdf_writer(_dataset(3), "sweep"), kind="sweep")


@contextlib.contextmanager
def _tmpfs(path: Path, size: str) -> Iterator[Path]:
    path.mkdir(parents=True, exist_ok=True)
    try:
        res = subprocess.run(
            ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(path)],
            capture_output=True,
            timeout=10,
        )
    except (OSError, subprocess.SubprocessError) as exc:
        pytest.skip(f"cannot mount a small tmpfs here: {exc}")
    if res.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here (needs root): {res.stderr.decode().strip()}")
    try:
        yield path
    finally:
        subprocess.run(["umount", "-l", str(path)], capture_output=True, timeout=10)


def test_a_really_full_disk_under_netcdf_output(tmp_path: Path) -> None:
    """The same on a 512 KiB tmpfs: netCDF4 itself says only 'NetCDF: HDF error'."""
    with _tmpfs(tmp_path / "small", "512k") as disk:
        target = disk / "s.nc"
        atomic_write(target, netcdf_writer(_dataset(100), "sweep"), kind="sweep")
        before = target.read_bytes()
        st = os.statvfs(disk)
        (disk / "filler").write_bytes(bytes(max(0, st.f_bavail * st.f_frsize - 64 * 1024)))
        with pytest.raises(OSError) as err:
            atomic_write(target, netcdf_writer(_dataset(50_000), "sweep"), kind="sweep")  # 400 kB
        assert err.value.errno == errno.ENOSPC and err.value.filename == str(target)
        assert "No space left on device" in str(err.value) and "NetCDF" in str(err.value)
        assert target.read_bytes() == before
        assert sorted(os.listdir(disk)) == ["filler", "s.nc"]


# ----------------------------------------------------------------------------- a store's array metadata


def _grid() -> dict[str, Any]:
    return {
        "v0": ss.Q_(np.geomspace(5, 1000, 6), "um/s"),
        "stiffness": ss.Q_(np.linspace(30, 90, 4), "N/m"),
    }


@pytest.fixture(scope="module")
def base() -> Any:
    return ss.zv_parameters()


@pytest.fixture(scope="module")
def made(base: Any, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished store of 3 blocks (2 v0 rows each), never damaged: each test copies it."""
    store = tmp_path_factory.mktemp("store") / "ref.zarr"
    sweep(base, _grid(), progress=False, store=store, block_points=8)
    return store


@pytest.fixture
def store(made: Path, tmp_path: Path) -> Path:
    copy = tmp_path / "s.zarr"
    shutil.copytree(made, copy)
    return copy


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[:100])


def _garble(path: Path) -> None:
    path.write_text("{not json")


def _reshape(path: Path) -> None:
    meta = json.loads(path.read_text())
    meta["shape"] = [7, 4]
    path.write_text(json.dumps(meta))


def _delete(path: Path) -> None:
    path.unlink()


@pytest.mark.parametrize(
    ("damage", "said"),
    [
        (_truncate, "is not valid JSON (truncated or damaged)"),
        (_garble, "is not valid JSON (truncated or damaged)"),
        (_reshape, "has shape [7, 4], not [6, 4]"),
        (_delete, "is missing"),
    ],
)
def test_a_damaged_array_metadata_is_written_again_on_resume(
    base: Any, made: Path, store: Path, damage: Any, said: str
) -> None:
    import zarr

    damage(store / "amplitude" / "zarr.json")
    (store / "period" / "c" / "1" / "0").unlink()  # and one chunk: its block is computed again
    with pytest.warns(UserWarning) as seen:
        ds = sweep(base, _grid(), progress=False, store=store)
    assert json.loads(ds.attrs["run"])["computed"] == 1
    said_lines = [str(w.message) for w in seen if "zarr.json" in str(w.message)]
    assert said_lines == [
        f"store={str(store)!r}: amplitude/zarr.json {said}: written again from the copy in the "
        "store's zarr.json"
    ]
    assert json.loads((store / "amplitude" / "zarr.json").read_text()) == json.loads(
        (made / "amplitude" / "zarr.json").read_text()
    )
    # a plain Zarr reader, without the consolidated copy, reads every array as the undamaged store's
    plain = zarr.open_group(str(store), mode="r", use_consolidated=False)
    ref = zarr.open_group(str(made), mode="r", use_consolidated=False)
    for name in ("amplitude", "period", "v0", "stiffness"):
        assert np.array_equal(plain[name][...], ref[name][...], equal_nan=True), name
    xr.testing.assert_identical(load_sweep(store), load_sweep(made))


def test_a_damaged_coordinate_metadata_is_written_again(base: Any, made: Path, store: Path) -> None:
    _truncate(store / "v0" / "zarr.json")
    with pytest.warns(UserWarning, match=r"v0/zarr.json is not valid JSON"):
        sweep(base, _grid(), progress=False, store=store)
    xr.testing.assert_identical(load_sweep(store), load_sweep(made))


def test_a_damaged_consolidated_copy_is_written_again_from_the_array(
    base: Any, made: Path, store: Path
) -> None:
    group = json.loads((store / "zarr.json").read_text())
    group["consolidated_metadata"]["metadata"]["amplitude"]["shape"] = [9, 9]
    (store / "zarr.json").write_text(json.dumps(group))
    with pytest.warns(UserWarning, match=r"the copy in zarr.json of amplitude's metadata does not fit"):
        sweep(base, _grid(), progress=False, store=store)
    xr.testing.assert_identical(load_sweep(store), load_sweep(made))


def test_array_metadata_beyond_repair_is_one_line_naming_the_file(base: Any, store: Path) -> None:
    _garble(store / "amplitude" / "zarr.json")
    group = json.loads((store / "zarr.json").read_text())
    del group["consolidated_metadata"]["metadata"]["amplitude"]
    (store / "zarr.json").write_text(json.dumps(group))
    with pytest.raises(StoreError) as err:
        sweep(base, _grid(), progress=False, store=store)
    assert str(err.value) == (
        f"store={str(store)!r}: amplitude/zarr.json is not valid JSON (truncated or damaged), and the "
        "store's zarr.json has no copy of it that fits the job: delete the store and run the command again"
    )


def test_the_command_line_says_the_repair_or_the_refusal_in_one_line(tmp_path: Path) -> None:
    args = ["sweep", "--nu", "0.01..0.1", "--c", "3.8", "--num", "5", "--quiet", "--block-points", "2"]
    store = tmp_path / "c.zarr"
    res = CliRunner().invoke(main, [*args, "--store", str(store)])
    assert res.exit_code == 0, res.output
    _garble(store / "amplitude" / "zarr.json")
    res = CliRunner().invoke(main, [*args, "--store", str(store)])
    assert res.exit_code == 0, res.output
    said = [line for line in _lines(res.output) if line.startswith("warning:")]
    assert said == [
        f"warning: store={str(store)!r}: amplitude/zarr.json is not valid JSON (truncated or damaged): "
        "written again from the copy in the store's zarr.json"
    ]
    # beyond repair: one Error line, status 2
    _garble(store / "amplitude" / "zarr.json")
    group = json.loads((store / "zarr.json").read_text())
    del group["consolidated_metadata"]["metadata"]["amplitude"]
    (store / "zarr.json").write_text(json.dumps(group))
    res = CliRunner().invoke(main, [*args, "--store", str(store)])
    assert res.exit_code == 2
    assert _lines(res.output) == [
        f"Error: store={str(store)!r}: amplitude/zarr.json is not valid JSON (truncated or damaged), and "
        "the store's zarr.json has no copy of it that fits the job: delete the store and run the command "
        "again"
    ]


# ----------------------------------------------------------------------------- refused runs leave nothing

LONG = "x" * 300  # a folder name longer than any file system takes (255 bytes)

REFUSED = [
    # refused inside the run, after its output folder was made
    [
        "chain",
        "--law",
        "weakening",
        "--blocks",
        "3",
        "--nu",
        "0.1",
        "--c",
        "3",
        "--events",
        "0",
        "--out",
        "a/b",
    ],
    [
        "chain",
        "--law",
        "weakening",
        "--blocks",
        "3",
        "--nu",
        "0.1",
        "--c",
        "3",
        "--amplitude",
        "-1",
        "--out",
        "a/b",
    ],
    # the output folder cannot be made past its first part
    ["simulate", "--nu", "0.1", "--c", "3", "--out", f"a/{LONG}"],
    ["examples", f"a/{LONG}"],
    ["sweep", "--nu", "0.01..0.1", "--c", "3", "--num", "3", "--quiet", "--out", f"a/{LONG}/s.nc"],
    # bad values and inputs, with the default output folders (results/COMMAND)
    ["simulate", "--nu", "-1", "--c", "3"],
    ["sweep", "--nu", "0.01..0.1", "--c", "3", "--p", "-1..1", "--num", "3", "--quiet"],
    ["sweep", "--nu", "0.01..0.1", "--c", "3", "--p", "-1..1", "--num", "3", "--quiet", "--store", "s.zarr"],
    ["regimes", "--c", "3", "--map", "p=-1..2", "--map-n", "3", "--store", "m.zarr", "--out", "o"],
    ["analyze", "bad.csv"],
    ["fit", "bad.csv"],
    ["ratestate-fit", "bad.csv"],
    ["classify", "bad.csv"],
    ["earthquake-cycles", "--dc", "-1 mm"],
    ["reproduce", "--out", f"a/{LONG}"],
]


def test_refused_runs_leave_no_folder_or_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.csv").write_text("garbage,,\n1,2\n")
    for args in REFUSED:
        res = CliRunner().invoke(main, args)
        shown = " ".join(a if len(a) < 40 else a[:12] + "..." for a in args)
        assert res.exit_code in (1, 2), (shown, res.output)
        lines = _lines(res.output)
        assert lines and lines[-1].startswith("Error: "), (shown, res.output)
        assert sorted(os.listdir(tmp_path)) == ["bad.csv"], shown


def test_an_output_folder_that_cannot_be_entered_removes_what_it_made(tmp_path: Path) -> None:
    with pytest.raises(OSError) as err, OutputFolder(tmp_path / "a" / "b" / LONG, "test"):
        pass
    assert err.value.filename == str(tmp_path / "a" / "b" / LONG)
    assert os.listdir(tmp_path) == []
