"""Writing outputs without losing anything: atomic files, own-file recognition, staged folders.

Every file stickslip writes goes to a temporary file in the same folder and is
renamed into place when complete (:func:`atomic_write`): a run killed while
writing leaves the previous complete file, never a partial one, and a full disk
fails before the old file is touched.

An existing file is replaced only if stickslip recognises it as its own output of
the same kind (:func:`own_kind`): NetCDF files carry a ``stickslip_output``
attribute, JSON files a ``generator`` entry, figures their metadata, reports a
first-line marker, CSV files their own header. Anything else needs
``overwrite=True`` (``--overwrite``).

A command that writes several files into a folder stages them in a hidden
staging folder and moves them into place only when all are written
(:class:`OutputFolder`); ``stickslip-manifest.json`` then records which run
wrote which file (with its SHA-256), so a folder never silently mixes two runs.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import time
import uuid
from collections.abc import Callable, Mapping
from importlib import metadata
from typing import Any, TypeVar

from .errors import DataError
from .jsonable import dumps as dumps_json

__all__ = [
    "MANIFEST",
    "ForeignFileError",
    "OutputFolder",
    "atomic_write",
    "check_target",
    "emit",
    "generator",
    "json_writer",
    "own_kind",
    "package_version",
    "temporary_file",
    "temporary_folder",
    "text_writer",
]

_T = TypeVar("_T")

MANIFEST = "stickslip-manifest.json"
STAGING_PREFIX = ".stickslip-staging-"
#: the mark of :func:`generator` in a file: ``stickslip VERSION (KIND)``
_MARK = re.compile(rb"stickslip (\d[\w.+-]*|unknown) \(([a-z][\w-]*)\)")
_HEAD_BYTES = 8192


def package_version() -> str:
    """Return stickslip's version from the package metadata (``unknown`` in an uninstalled tree)."""
    try:
        return metadata.version("stickslip")
    except metadata.PackageNotFoundError:  # pragma: no cover - running from a source tree
        return "unknown"


def generator(kind: str) -> str:
    """Return the marker stickslip writes into its outputs of ``kind``: ``'stickslip VERSION (KIND)'``."""
    return f"stickslip {package_version()} ({kind})"


class ForeignFileError(DataError):
    """An output path names a file that stickslip did not write (or not of that kind)."""


#: the header row (its start) of each kind of CSV that stickslip writes; a trajectory's
#: whole header, unit for unit (a user's "time [s],force [mN]" file was taken for one, and replaced)
CSV_HEADERS: dict[str, tuple[str | re.Pattern[str], ...]] = {
    "trajectory": (
        re.compile(r"time \[[^]]*\],position \[[^]]*\],velocity \[[^]]*\],spring_force \[[^]]*\],phase$"),
    ),
    "records-summary": ("name,n_cycles,",),
    "records-events": ("record,time [s],end_time [s],",),
    "friction-table": ("# stickslip friction table",),
    "amplitudes": ("# stickslip amplitudes",),
    "examples-readme": ("stickslip's example inputs",),
    "fit-parameters": ("parameter,value,error,unit",),
    "ratestate-record": ("# stickslip rate-and-state record",),
    "record": ("# stickslip force-time record",),
    "sweep": ("# stickslip sweep table",),  # save_sweep to a .csv path
    "regime-map": ("# stickslip regime-map table",),
}


def own_kind(path: str | os.PathLike[str]) -> str | None:
    """Return the kind of stickslip output a file is, or None if stickslip did not write it.

    Looks only at the start of the file (and, for NetCDF, its global attributes), so
    it is cheap for large files.
    """
    p = os.fspath(path)
    try:
        with open(p, "rb") as fh:
            head = fh.read(_HEAD_BYTES)
    except OSError:
        return None
    ext = os.path.splitext(p)[1].lower()
    if head.startswith((b"\x89HDF", b"CDF")):
        return _netcdf_kind(p)
    if ext in (".png", ".svg", ".json", ".md", ".html"):
        m = _MARK.search(head)
        return m.group(2).decode("ascii") if m else None
    if ext in (".csv", ".tsv", ".txt"):  # records are written as any of them
        first = head.split(b"\n", 1)[0].decode("utf-8", "replace").strip()
        for kind, starts in CSV_HEADERS.items():
            if any(st.match(first) if isinstance(st, re.Pattern) else first.startswith(st) for st in starts):
                return kind
    return None


def _netcdf_kind(path: str) -> str | None:
    try:
        import netCDF4

        with netCDF4.Dataset(path) as nc:
            kind = getattr(nc, "stickslip_output", None)
            if kind is None and getattr(nc, "stickslip_version", None) is not None:
                return "sweep"  # sweeps written before the marker existed
            return str(kind) if kind is not None else None
    except Exception:  # not readable as NetCDF: not ours
        return None


def check_target(path: str | os.PathLike[str], kind: str, *, overwrite: bool = False) -> None:
    """Refuse to replace a file stickslip did not write as ``kind``, unless ``overwrite``.

    Raises
    ------
    ForeignFileError
        With one line naming the file, what it is, and the way out.
    ValueError
        If the path is an existing folder.

    """
    p = os.fspath(path)
    if os.path.isdir(p):
        raise ValueError(f"{p} is a folder: expected a file name for the {kind} output")
    if overwrite or not os.path.lexists(p):
        return
    found = own_kind(p)
    if found == kind:
        return
    what = "not a file stickslip wrote" if found is None else f"stickslip's {found} output, not {kind}"
    # in the words of where it was asked: a command's option, or Python's argument
    give = "--overwrite" if _click_context() is not None else "overwrite=True"
    raise ForeignFileError(
        f"{p} exists and is {what}: not replaced; give {give} to replace it, or choose another output"
    )


#: the key stickslip's command line sets in its click context's meta (another click app's
#: context is not stickslip's command line: it has no --overwrite, and no command of ours)
COMMAND_LINE = "stickslip.command_line"


def _click_context() -> Any:
    """Return stickslip's command line's click context when one of its commands runs, else None."""
    try:
        import click
    except ImportError:  # pragma: no cover - click is a dependency
        return None
    ctx = click.get_current_context(silent=True)
    return ctx if ctx is not None and ctx.meta.get(COMMAND_LINE) else None


def atomic_write(
    path: str | os.PathLike[str],
    write: Callable[[str], None],
    *,
    kind: str,
    overwrite: bool = False,
) -> str:
    """Write a file through ``write(temporary_path)`` and rename it into place when complete.

    Parameters
    ----------
    path : str or path-like
        The final file.
    write : callable
        Writes the complete file to the path it is given (same folder, same extension).
    kind : str
        What the file is (``sweep``, ``trajectory``, ...): an existing file is replaced
        only if it is stickslip's output of the same kind.
    overwrite : bool, optional
        Replace any existing file.

    Returns
    -------
    str
        The final path.

    Raises
    ------
    ForeignFileError
        The path names a file stickslip did not write.
    OSError
        Cannot write (permission, disk full): the error names the final path; the
        previous file is untouched.

    """
    p = os.fspath(path)
    check_target(p, kind, overwrite=overwrite)
    folder = os.path.dirname(p) or "."
    name = os.path.basename(p)
    created = _missing_folders(folder)  # removed again if the file is not written
    try:
        os.makedirs(folder, exist_ok=True)
        fd, tmp = temporary_file(folder, f".{name}.", ".part" + os.path.splitext(name)[1])
    except OSError as exc:
        _remove_empty(created)
        raise OSError(exc.errno, f"cannot write ({exc.strerror or exc})", p) from None
    os.close(fd)
    try:
        write(tmp)
        _fsync(tmp)
        os.replace(tmp, p)
        _clean_stale_parts(folder, name)
    except OSError as exc:
        _remove(tmp)
        _remove_empty(created)
        raise OSError(exc.errno, f"cannot write ({exc.strerror or exc})", p) from None
    except BaseException:
        _remove(tmp)
        _remove_empty(created)
        raise
    return p


def temporary_file(folder: str, prefix: str, suffix: str = "") -> tuple[int, str]:
    """Create an empty file ``prefix<pid>.<random><suffix>`` in ``folder``; return its descriptor and path.

    As :func:`tempfile.mkstemp`, but with the mode a plain ``open`` gives (0666 less the
    umask): mkstemp's 0600 stayed with a file renamed into place, so every output (a
    record, a table, a figure, a store) was readable by its owner only.
    """
    return _unique(folder, prefix, suffix, lambda p: os.open(p, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))


def temporary_folder(folder: str, prefix: str) -> str:
    """Create an empty folder ``prefix<pid>.<random>`` in ``folder`` (0777 less the umask); return its path.

    As :func:`tempfile.mkdtemp`, whose 0700 a store renamed into place kept.
    """
    return _unique(folder, prefix, "", lambda p: os.mkdir(p, 0o777))[1]


def _unique(folder: str, prefix: str, suffix: str, make: Callable[[str], _T]) -> tuple[_T, str]:
    """Make ``prefix<pid>.<random><suffix>`` in ``folder`` with ``make`` (which fails if it exists)."""
    for _ in range(100):
        path = os.path.join(folder, f"{prefix}{os.getpid()}.{uuid.uuid4().hex[:8]}{suffix}")
        try:
            return make(path), path
        except FileExistsError:
            continue
    raise FileExistsError(errno.EEXIST, "no free temporary name", os.path.join(folder, prefix))


def _fsync(path: str) -> None:
    with contextlib.suppress(OSError), open(path, "rb+") as fh:
        os.fsync(fh.fileno())


def _remove(path: str) -> None:
    with contextlib.suppress(OSError):
        if os.path.isdir(path):
            shutil.rmtree(path)
        else:
            os.remove(path)


def _missing_folders(folder: str) -> list[str]:
    """Return the folders that making ``folder`` would create, deepest first (absolute paths)."""
    out = []
    missing = os.path.abspath(folder)
    while missing and not os.path.exists(missing):
        out.append(missing)
        parent = os.path.dirname(missing)
        missing = parent if parent != missing else ""
    return out


def _remove_empty(folders: list[str]) -> None:
    """Remove ``folders`` (deepest first) where they are empty; stop at the first that holds anything.

    One that was never made (its name too long, a parent refused) is passed over.
    """
    for folder in folders:
        if not os.path.isdir(folder):
            continue
        try:
            os.rmdir(folder)  # only an empty one
        except OSError:
            break


def _sha256(path: str) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


class OutputFolder:
    """The files of one run of a command, staged and published together.

    Use as a context manager::

        with OutputFolder("results", "simulate") as out:
            out.write("trajectory.csv", "trajectory", traj.to_csv)
            out.write("spring_force.png", "figure", save_png)

    Every target is checked when it is declared (:meth:`expect`, :meth:`write`):
    a foreign file stops the run before anything is written. Files are written into
    a hidden staging folder inside the output folder; when the block ends without an
    error they are renamed into place and ``stickslip-manifest.json`` records the
    run. An error or a kill leaves the previous files as they were (a stale staging
    folder of a dead run is removed by the next run), and a run that fails leaves no
    folder it made: the folders it created are removed again where they are empty.
    """

    def __init__(self, folder: str | os.PathLike[str], command: str, *, overwrite: bool = False) -> None:
        self.folder = os.fspath(folder)
        if os.path.exists(self.folder) and not os.path.isdir(self.folder):
            raise ValueError(f"{self.folder} exists and is not a folder: expected an output folder")
        self.command = command
        self.overwrite = overwrite
        self.run = uuid.uuid4().hex[:12]
        self._staged: dict[str, str] = {}
        self._kinds: dict[str, str] = {}
        self._staging: str | None = None
        self._created: list[str] = []  # the folders this run made, deepest first

    # ------------------------------------------------------------------ context
    def __enter__(self) -> OutputFolder:
        # a failure here has no __exit__: the folders made so far are removed before it is raised
        self._created = _missing_folders(self.folder)
        try:
            os.makedirs(self.folder, exist_ok=True)
            check_target(os.path.join(self.folder, MANIFEST), "manifest", overwrite=self.overwrite)
            _clean_stale_staging(self.folder)
            staging = os.path.join(self.folder, f"{STAGING_PREFIX}{os.getpid()}-{self.run}")
            os.makedirs(staging)
        except OSError as exc:
            _remove_empty(self._created)
            raise OSError(
                exc.errno, f"cannot write into this folder ({exc.strerror or exc})", self.folder
            ) from None
        except BaseException:
            _remove_empty(self._created)
            raise
        self._staging = staging
        return self

    def __exit__(self, exc_type: Any, exc: Any, tb: Any) -> None:
        published = False
        try:
            if exc_type is None:
                self._publish()
                published = True
        finally:
            if self._staging is not None:
                _remove(self._staging)
            if not published:
                _remove_empty(self._created)

    # ------------------------------------------------------------------ files
    def expect(self, names: Mapping[str, str]) -> None:
        """Declare files (name to kind) that the run will write, and check them now."""
        for name, kind in names.items():
            check_target(os.path.join(self.folder, name), kind, overwrite=self.overwrite)
            self._kinds[name] = kind

    def path(self, name: str, kind: str) -> str:
        """Return the staging path for ``name`` (checked against the folder's existing file)."""
        if self._staging is None:
            raise RuntimeError("OutputFolder.path outside its with-block")
        if name not in self._kinds:
            self.expect({name: kind})
        staged = os.path.join(self._staging, name)
        os.makedirs(os.path.dirname(staged), exist_ok=True)
        self._staged[name] = staged
        return staged

    def write(self, name: str, kind: str, write: Callable[[str], None]) -> str:
        """Write ``name`` through ``write(path)`` into the staging folder; return its final path."""
        staged = self.path(name, kind)
        try:
            write(staged)
        except OSError as exc:
            final = os.path.join(self.folder, name)
            raise OSError(exc.errno, f"cannot write ({exc.strerror or exc})", final) from None
        return os.path.join(self.folder, name)

    def final(self, name: str) -> str:
        """Return the final path of ``name``."""
        return os.path.join(self.folder, name)

    def staged_path(self, name: str) -> str:
        """Return where ``name`` (already written in this run) lies until the run is published."""
        return self._staged[name]

    def _publish(self) -> None:
        entry: dict[str, Any] = {
            "run": self.run,
            "finished": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
            "generator": generator(self.command),
            **_provenance(),
            "files": {},
        }
        for name, staged in self._staged.items():
            entry["files"][name] = {"kind": self._kinds.get(name, ""), "sha256": _sha256(staged)}
            _fsync(staged)
        for name, staged in self._staged.items():
            final = os.path.join(self.folder, name)
            try:
                os.makedirs(os.path.dirname(final), exist_ok=True)
                os.replace(staged, final)
            except OSError as exc:
                raise OSError(exc.errno, f"cannot write ({exc.strerror or exc})", final) from None
        _update_manifest(self.folder, self.command, entry)


def _provenance() -> dict[str, Any]:
    """Return what made a run: the command and its options (from the command line), the source.

    A version alone ('stickslip 0.1.0') is shared by many commits and says nothing of the
    options (--quick) that made the folder: the manifest records both.
    """
    out: dict[str, Any] = {}
    ctx = _click_context()
    if ctx is not None:
        out["options"] = {
            k: _plain(v)
            for k, v in sorted(ctx.params.items())
            if v is not None and v is not False and not (isinstance(v, tuple) and not v)
        }
        names = []  # the subcommands' names; the root's is the program's (python -m stickslip, main)
        while ctx.parent is not None:
            names.append(ctx.info_name or "")
            ctx = ctx.parent
        out["command"] = " ".join(["stickslip", *reversed(names)])
    source = _source_revision()
    if source:
        out["source"] = source
    return out


def _plain(value: Any) -> Any:
    """Return an option's value as JSON: numbers and text as they are, tuples as lists, the rest as text."""
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)  # strict JSON has no NaN
    if isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, tuple | list):
        return [_plain(v) for v in value]
    return str(value)


@functools.cache
def _source_revision() -> str:
    """Return the git commit of the stickslip checkout this package runs from ('-dirty' if changed).

    '' for an installed package, even one inside a user's own repository (git looks upward:
    the user's commit was taken for stickslip's, the review). Read once per process: a
    notebook keeps the state it started with.
    """
    here = os.path.dirname(os.path.abspath(__file__))
    env = {k: v for k, v in os.environ.items() if k not in ("GIT_DIR", "GIT_WORK_TREE", "GIT_INDEX_FILE")}

    def git(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            ["git", "--no-optional-locks", "-C", here, *args],
            capture_output=True,
            text=True,
            timeout=5,
            env=env,
        )

    try:
        top = git("rev-parse", "--show-toplevel")
        if top.returncode != 0 or git("ls-files", "--error-unmatch", __file__).returncode != 0:
            return ""  # not a checkout, or one in which this file is not tracked (an install)
        with open(os.path.join(top.stdout.strip(), "pyproject.toml"), encoding="utf-8") as fh:
            if not re.search(r'^name\s*=\s*"stickslip"', fh.read(), re.MULTILINE):
                return ""
        head = git("rev-parse", "--short=12", "HEAD")
        if head.returncode != 0:
            return ""
    except (OSError, subprocess.SubprocessError):  # no git, no pyproject: an installed wheel
        return ""
    try:
        dirty = bool(git("status", "--porcelain", "--untracked-files=no").stdout.strip())
    except subprocess.SubprocessError:  # a slow status: the commit alone
        return f"git {head.stdout.strip()}"
    return f"git {head.stdout.strip()}" + ("-dirty" if dirty else "")


def _update_manifest(folder: str, command: str, entry: Mapping[str, Any]) -> None:
    path = os.path.join(folder, MANIFEST)
    runs: dict[str, Any] = {}
    with contextlib.suppress(OSError, ValueError), open(path, encoding="utf-8") as fh:
        loaded = json.load(fh)
        if isinstance(loaded, dict) and isinstance(loaded.get("runs"), dict):
            runs = loaded["runs"]
    runs[command] = dict(entry)
    text = dumps_json({"generator": generator("manifest"), "runs": runs}, indent=2)

    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)

    atomic_write(path, write, kind="manifest", overwrite=True)  # checked when the run began


def _clean_stale_parts(folder: str, name: str) -> None:
    """Remove temporary files of ``name`` left by writers that were killed (their process is gone)."""
    prefix = f".{name}."
    with contextlib.suppress(OSError):
        for entry in os.listdir(folder):
            if entry.startswith(prefix) and ".part" in entry:
                pid_text = entry[len(prefix) :].split(".", 1)[0]
                if pid_text.isdigit() and not _alive(int(pid_text)):
                    _remove(os.path.join(folder, entry))


def _clean_stale_staging(folder: str) -> None:
    """Remove staging folders left by runs whose process is gone."""
    try:
        names = os.listdir(folder)
    except OSError:
        return
    for name in names:
        if not name.startswith(STAGING_PREFIX):
            continue
        pid_text = name[len(STAGING_PREFIX) :].split("-", 1)[0]
        if pid_text.isdigit() and not _alive(int(pid_text)):
            _remove(os.path.join(folder, name))


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except OSError as exc:
        return exc.errno == errno.EPERM
    return True


def emit(
    name: str,
    kind: str,
    write: Callable[[str], None],
    *,
    out: OutputFolder | None = None,
    overwrite: bool = False,
) -> str:
    """Write one output: into the staged folder ``out`` (``name`` relative to it), else atomically."""
    if out is not None:
        return out.write(name, kind, write)
    return atomic_write(name, write, kind=kind, overwrite=overwrite)


def json_writer(obj: Mapping[str, Any], kind: str) -> Callable[[str], None]:
    """Return a writer of ``obj`` as indented JSON with a ``generator`` entry first."""
    text = dumps_json({"generator": generator(kind), **obj}, indent=2)

    def write(path: str) -> None:
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text)

    return write


def text_writer(text: str) -> Callable[[str], None]:
    """Return a writer of ``text`` (UTF-8)."""

    def write(path: str) -> None:
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text)

    return write


def __getattr__(name: str) -> Any:
    """``netcdf_writer``, now in :mod:`stickslip.io.netcdf`, by its former path."""
    if name == "netcdf_writer":
        from .netcdf import netcdf_writer

        return netcdf_writer
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
