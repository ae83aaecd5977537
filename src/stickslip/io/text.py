"""Reading delimited text files: encodings checked, numbers parsed fast, bad cells named.

Every table and record stickslip reads goes through here:

* :func:`inspect` reads the first 64 kB only: it refuses a binary file, UTF-16/32
  text and bytes that are not UTF-8 (naming the file and where), collects the
  ``# key = value`` lines before the header, finds the header and the delimiter
  (comma, semicolon or tab).
* :func:`read_frame` parses the data with pandas' C parser straight into float
  columns (no copy of the text, no Python per cell), after an estimate of the
  memory it will need (refused beyond what the machine has).
* When a file has a problem (a cell that is not a number, a ragged row, a field
  too long for the CSV module), :func:`diagnose` streams it line by line to name
  the first bad place: file, line, column, value. Every message counts lines as
  an editor does (the file's own lines, comments and blank lines included), and
  :func:`data_lines` turns a data row read into the line it came from.
"""

from __future__ import annotations

import codecs
import csv
import itertools
import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.memory import check_memory
from ..errors import ArgumentTypeError
from .errors import DataError

if TYPE_CHECKING:  # pandas is imported where a file is read (0.2 s at import)
    import pandas as pd

__all__ = [
    "TextLayout",
    "check_file",
    "data_lines",
    "diagnose",
    "header_lines",
    "inspect",
    "meta_key",
    "read_frame",
]

HEAD_BYTES = 1 << 16
_META = re.compile(r"^\s*#\s*([A-Za-z_][\w .\-]*?)\s*[=:;,\t]\s*(.*?)\s*$")
#: a metadata key as read back (lower case, ``_`` for spaces)
_KEY = re.compile(r"[a-z_][\w.\-]*")
#: the longest cell shown in a message
_SHOW = 40


def check_file(path: str | os.PathLike[str]) -> str:
    """Return the path as a string after checking that it is an existing, non-empty file.

    Raises
    ------
    ArgumentTypeError
        For a ``path`` that is neither a str nor a path.
    DataError
        Naming the file: missing, a folder, or empty.

    """
    if not isinstance(path, str | os.PathLike):
        raise ArgumentTypeError(f"path={path!r} (type {type(path).__name__}): expected a file's path")
    p = os.fspath(path)
    if os.path.isdir(p):
        raise DataError(f"{p}: is a folder, expected a file")
    if not os.path.isfile(p):
        if os.path.exists(p):  # /dev/zero, a pipe: there, but no file to read twice
            raise DataError(f"{p}: not a regular file (a device or a pipe): expected a file")
        raise DataError(f"{p}: no such file")
    if os.path.getsize(p) == 0:
        raise DataError(f"{p}: the file is empty")
    return p


def _show(cell: str) -> str:
    return repr(cell if len(cell) <= _SHOW else cell[:_SHOW] + "...")


@dataclass(frozen=True)
class TextLayout:
    """Where the header and the data of a text file are.

    Attributes
    ----------
    path : str
        The file.
    meta : dict
        ``# key = value`` lines before the header (keys lower-case, spaces as ``_``).
    header : list of str
        Header cells, trailing empty ones dropped (spreadsheet exports add them).
    width : int
        Number of cells in the header row as written (trailing empties included).
    sep : str
        Delimiter.
    header_line : int
        Line number (1-based) of the header.
    size : int
        File size in bytes.
    bytes_per_row : float
        Average length of the first data lines (for memory estimates).
    data_offset : int
        Bytes before the first data line (the header's line end included); ``-1``
        when not known (the data are then found by counting lines).

    """

    path: str
    meta: dict[str, str]
    header: list[str]
    width: int
    sep: str
    header_line: int
    size: int
    bytes_per_row: float = field(default=32.0)
    data_offset: int = field(default=-1)
    decimal: str = field(default=".")


_COMMA_NUMBER = re.compile(r"^[-+]?\d+,\d+(?:[eE][-+]?\d+)?$")
_POINT_NUMBER = re.compile(r"^[-+]?\d*\.\d+(?:[eE][-+]?\d+)?$")


def _decode_head(path: str, head: bytes) -> str:
    for bom, name in (
        (codecs.BOM_UTF32_LE, "UTF-32"),
        (codecs.BOM_UTF32_BE, "UTF-32"),
        (codecs.BOM_UTF16_LE, "UTF-16"),
        (codecs.BOM_UTF16_BE, "UTF-16"),
    ):
        if head.startswith(bom):
            raise DataError(
                f"{path}: the file is {name} text; save it as UTF-8 (CSV UTF-8) and read it again"
            )
    if b"\x00" in head:
        raise DataError(
            f"{path}: not a text file (it holds NUL bytes: binary, or UTF-16 without a byte-order mark)"
        )
    decoder = codecs.getincrementaldecoder("utf-8-sig")()
    try:
        text = decoder.decode(head, final=len(head) < HEAD_BYTES)
    except UnicodeDecodeError as exc:
        _raise_not_utf8(path, head, exc.start)
    controls = sum(1 for ch in text if ord(ch) < 32 and ch not in "\t\r\n\f")
    if controls > 0.01 * max(len(text), 1):
        raise DataError(f"{path}: not a text file (control characters: binary data?)")
    return text


def _raise_not_utf8(path: str, data: bytes, offset: int, base_line: int = 0) -> None:
    line = base_line + data[:offset].count(b"\n") + 1
    byte = data[offset : offset + 1].hex()
    raise DataError(
        f"{path}: not UTF-8 text (byte 0x{byte} on line {line}; Latin-1 or another encoding?): "
        "save it as UTF-8 and read it again"
    )


def inspect(path: str | os.PathLike[str], where: str | None = None) -> TextLayout:
    """Check the encoding and find the metadata, the header and the delimiter of a text file.

    Raises
    ------
    DataError
        Missing, empty, binary or not UTF-8; no header line.

    """
    p = check_file(path)
    shown = where or p
    with open(p, "rb") as fh:
        head = fh.read(HEAD_BYTES)
    text = _decode_head(shown, head)
    # the line ends pandas knows: str.splitlines also splits at U+2028, U+0085 and form feeds,
    # and a header found one line too late lost the first data row
    lines = re.split(r"\r\n|\r|\n", text)
    if len(head) == HEAD_BYTES and not text.endswith(("\n", "\r")):
        lines = lines[:-1]  # the last line may be cut in the middle
    meta: dict[str, str] = {}
    for i, line in enumerate(lines):
        if not line.strip():
            continue
        if line.lstrip().startswith("#"):
            m = _META.match(line)
            if m:
                key, value = meta_key(m.group(1)), m.group(2)
                if key in READ_KEYS and key in meta and not _same_value(meta[key], value):
                    # the last line won, silently (notes, channels, comments may repeat: not read)
                    raise DataError(
                        f"{shown}: line {i + 1} gives {m.group(1).strip()} = {value.strip()!r}, an earlier "
                        f"line {meta[key].strip()!r}: give it once"
                    )
                meta[key] = value
            continue
        sep = (
            "\t"
            if line.count("\t") > max(line.count(","), line.count(";"))
            else (";" if line.count(";") > line.count(",") else ",")
        )
        cells = next(csv.reader([line], delimiter=sep))
        width = len(cells)
        while cells and not cells[-1].strip():
            cells.pop()
        rest = [ln for ln in lines[i + 1 : i + 200] if ln.strip() and not ln.lstrip().startswith("#")]
        per_row = float(np.mean([len(ln) + 1 for ln in rest])) if rest else 32.0
        # where the data begin, in bytes: pandas' skiprows does not count the empty lines of
        # a file whose lines end in CR alone, and its first data row was lost
        ends = [m.end() for m in itertools.islice(re.finditer(r"\r\n|\r|\n", text), i + 1)]
        offset = len(text[: ends[i]].encode("utf-8")) if len(ends) > i else os.path.getsize(p)
        offset += len(codecs.BOM_UTF8) if head.startswith(codecs.BOM_UTF8) else 0
        header = [c.strip() for c in cells]
        # a decimal comma (European spreadsheets): with ';' or tab between the cells, numbers
        # written 0,005 and none written 0.005 in the first data lines
        decimal = "."
        if sep != "," and rest:
            cells_ = [c.strip() for ln in rest[:50] for c in next(csv.reader([ln], delimiter=sep))]
            if any(_COMMA_NUMBER.match(c) for c in cells_) and not any(
                _POINT_NUMBER.match(c) for c in cells_
            ):
                decimal = ","
        return TextLayout(p, meta, header, width, sep, i + 1, os.path.getsize(p), per_row, offset, decimal)
    if len(head) == HEAD_BYTES:
        raise DataError(f"{shown}: no header line within the first {HEAD_BYTES // 1024} kB")
    raise DataError(f"{shown}: no header row and no data")


def read_frame(
    layout: TextLayout,
    names: Sequence[str],
    *,
    numeric: Sequence[str],
    text: Sequence[str] = (),
    where: str | None = None,
) -> pd.DataFrame:
    """Parse the data rows into a frame: ``numeric`` columns as float64, ``text`` columns as strings.

    ``names`` are the parsed header names (one per header cell, trailing empties
    dropped). NaN and empty cells become NaN (the caller decides what they mean);
    anything else that is not a number, a ragged row or an encoding error is named
    by :func:`diagnose` (by its line in the file).

    Raises
    ------
    DataError
        Naming the file and the first bad place; or when the file would need more
        memory than the machine has.

    """
    shown = where or layout.path
    rows = max(1.0, (layout.size - layout.header_line * layout.bytes_per_row) / layout.bytes_per_row)
    wanted = [n for n in names if n in numeric or n in text]
    check_memory(
        rows * (8.0 * len(wanted) + 48.0 * len([n for n in wanted if n in text])) * 2.5,
        f"{shown} ({layout.size / 1e6:.0f} MB, about {rows:.3g} rows)",
        "split the record into parts",
    )
    import pandas as pd

    all_names = [*names, *(f"_unused_{k}" for k in range(len(names), layout.width))]
    dtype: dict[str, object] = {n: "float64" for n in wanted if n in numeric}
    dtype.update({n: str for n in wanted if n in text})
    try:
        with open(layout.path, "rb") as fh:
            if layout.data_offset >= 0:
                fh.seek(layout.data_offset)
            frame = pd.read_csv(
                fh,
                sep=layout.sep,
                decimal=layout.decimal,
                header=None,
                names=all_names,
                usecols=wanted,
                skiprows=0 if layout.data_offset >= 0 else layout.header_line,
                comment="#",
                skip_blank_lines=True,
                dtype=dtype,
                engine="c",
                encoding="utf-8" if layout.data_offset >= 0 else "utf-8-sig",
                index_col=False,
                skipinitialspace=True,
            )
    except UnicodeDecodeError as exc:
        _locate_bad_bytes(layout.path, shown, exc)
        raise  # pragma: no cover - _locate_bad_bytes raises
    except (ValueError, pd.errors.ParserError, csv.Error, OverflowError):
        diagnose(layout, names, numeric=numeric, where=shown)
        raise DataError(f"{shown}: malformed rows (pandas could not read them)") from None
    for n in wanted:
        if n in numeric and np.isinf(frame[n].to_numpy()).any():
            diagnose(layout, names, numeric=numeric, where=shown)
    _check_widths(layout, names, shown)
    return frame


def _check_widths(layout: TextLayout, names: Sequence[str], shown: str) -> None:
    """Raise at the first data line with more (non-empty) cells than the header.

    pandas drops such cells without a word when it reads chosen columns (and with them
    the decimals of a decimal comma). numpy finds, block by block, the lines with more
    delimiters than the header (a delimiter ``width - 1`` places on in the same line);
    only those are parsed, as CSV (quotes, trailing empty cells and comments allowed).
    About 0.3 s per 100 MB (pandas takes 1.3 s to parse them).
    """
    sep = ord(layout.sep)
    limit = layout.width - 1  # delimiters in a line as wide as the header
    line0 = 1  # the number of the block's first line
    tail = b""
    with open(layout.path, "rb") as fh:
        while True:
            block = fh.read(1 << 24)
            if line0 == 1 and not tail and b"\r" in block and b"\n" not in block:
                return  # lines ended by CR alone (old Mac files): pandas reads them; not counted here
            data = tail + block
            if not data:
                return
            cut = len(data) if not block else data.rfind(b"\n") + 1
            if cut == 0:  # one line longer than the block: wait for its end
                tail = data
                continue
            part, tail = data[:cut], data[cut:]
            buf = np.frombuffer(part, dtype=np.uint8)
            newlines = np.flatnonzero(buf == 10)
            at = np.searchsorted(newlines, np.flatnonzero(buf == sep))  # each delimiter's line
            wide = np.unique(at if limit == 0 else at[limit:][at[limit:] == at[:-limit]])
            if wide.size:
                starts = np.concatenate([[0], newlines + 1])
                for k in wide:
                    line_no = line0 + int(k)
                    stop = int(starts[k + 1]) - 1 if k + 1 < starts.size else len(part)
                    cells = _cells(part[int(starts[k]) : stop], layout.sep)
                    if line_no > layout.header_line and cells > len(names):
                        hint = " (decimal commas? the delimiter is ',')" if layout.sep == "," else ""
                        raise DataError(
                            f"{shown}: line {line_no} has {cells} cells, the header has {len(names)}{hint}"
                        )
            line0 += newlines.size
            if not block:
                return


#: header keys that stickslip reads (a record's v0 and load under their other names, a
#: rate-and-state record's set-up): one given twice with different values is refused; other
#: keys (notes, channels, comments) may repeat, and the last line is kept
READ_KEYS = frozenset(
    {"v0", "load", "mu0", "v_ref", "stiffness_per_load", "law", "radiation_damping", "mass", "nagata_c"}
    | {"driving_velocity", "drive_velocity", "velocity", "v_0", "driving_speed", "sliding_velocity"}
    | {"sliding_speed", "speed", "normal_load", "normal_force", "fn", "f_n"}
)


def _same_value(a: str, b: str) -> bool:
    """Return whether two header values agree: as quantities ('100 um/s', '0.1 mm/s'), else as text."""
    from ..units import ureg

    try:
        qa: Any = ureg.Quantity(a.strip())
        qb: Any = ureg.Quantity(b.strip())
        ratio = float((qb / qa).to("").magnitude)
        return bool(abs(ratio - 1.0) <= 1e-12)
    except Exception:  # not quantities, or of different dimensions: the texts
        return a.strip().lower() == b.strip().lower()


def meta_key(key: str) -> str:
    """Return a metadata key as it reads back: stripped, lower case, ``_`` for spaces."""
    return re.sub(r"\s+", "_", key.strip().lower())


def header_lines(kind: str, metadata: Mapping[str, Any], columns: Mapping[str, Any]) -> list[str]:
    """Return a written record's first lines: its mark, ``# key = value`` lines and the header.

    Checks what the readers need back: one line per key and value (a newline in
    one ended the metadata and corrupted the file), keys that read back (letters,
    digits, ``_``, ``-``, ``.`` and spaces, written as :func:`meta_key` reads them:
    ``Sample Name`` as ``sample_name``), one value per key so written, values
    without leading or trailing blanks, and equal-length 1-d columns.

    Raises
    ------
    ValueError
        Naming the metadata key or the columns.

    """
    written: dict[str, str] = {}
    for key, value in metadata.items():
        if any(c in f"{key}{value}" for c in "\r\n\u2028\u2029\x0b\x0c\x1c\x1d\x1e\x85"):
            raise ValueError(f"metadata[{key!r}]={value!r}: a line break in a header line")
        k = meta_key(str(key))
        if not _KEY.fullmatch(k):  # 'x-y' was dropped on reading, 'k:v' read as k = 'v = ...'
            raise ValueError(
                f"metadata key {key!r}: expected a letter or '_', then letters, digits, '_', '-', '.' "
                "or spaces (it would not read back)"
            )
        if k in written:
            raise ValueError(f"metadata keys {written[k]!r} and {key!r} both read back as {k!r}")
        written[k] = str(key)
    meta = [f"# {meta_key(str(k))} = {str(v).strip()}" for k, v in metadata.items()]
    lengths = {k: np.shape(v) for k, v in columns.items()}
    if len({s for s in lengths.values()}) > 1 or any(len(s) != 1 for s in lengths.values()):
        raise ValueError(f"columns: expected 1-d columns of one length, got shapes {lengths}")
    return [f"# stickslip {kind}", *meta, ",".join(columns)]


def _cells(raw: bytes, sep: str) -> int:
    """Return the cells of a data line, trailing empty ones not counted (0: a comment or blank line)."""
    widest = 0
    # a CR alone ends a line for pandas too (a file of mixed line ends)
    for part in raw.decode("utf-8", errors="replace").rstrip("\r").split("\r"):
        line = _uncomment(part)
        if not line.strip():
            continue
        cells = next(csv.reader([line], delimiter=sep))
        while cells and not cells[-1].strip():
            cells.pop()
        widest = max(widest, len(cells))
    return widest


def _uncomment(line: str) -> str:
    """Return ``line`` up to a ``#`` outside quotes, as pandas reads it (``comment="#"``)."""
    if "#" not in line:
        return line
    quoted = False
    for i, ch in enumerate(line):
        if ch == '"':
            quoted = not quoted
        elif ch == "#" and not quoted:
            return line[:i]
    return line


def _locate_bad_bytes(path: str, shown: str, exc: UnicodeDecodeError) -> None:
    """Find the first byte that is not UTF-8 by streaming the file, and raise naming its line."""
    line = 0
    decoder = codecs.getincrementaldecoder("utf-8-sig")()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            try:
                decoder.decode(block)
            except UnicodeDecodeError as err:
                _raise_not_utf8(shown, block, err.start, line)
            line += block.count(b"\n")
    raise DataError(f"{shown}: not UTF-8 text ({exc.reason}); save it as UTF-8 and read it again")


def _is_data(line: str, sep: str) -> bool:
    """Whether pandas reads ``line`` as a data row (with ``comment="#"``, blank lines skipped).

    pandas skips a line of blanks (spaces and tabs, the delimiter not among them: in a
    tab-separated file a line of tabs is a row of empty cells) and a line starting with
    ``#``; an indented ``#`` ends the line's cells (the row is read, its cells empty).
    """
    blanks = " \t".replace(sep, "")
    return bool(line.strip(blanks + "\r\n")) and not line.startswith("#")


def data_lines(layout: TextLayout, rows: Sequence[int]) -> list[int]:
    """Return the file line (1-based) of each data row in ``rows`` (0-based, in the order read).

    Streams the file up to the last row asked for; for messages, not for every row.

    Raises
    ------
    ValueError
        For a row beyond the file's data.

    """
    want = sorted({int(r) for r in rows})
    found: dict[int, int] = {}
    if want:
        k = -1
        with open(layout.path, encoding="utf-8-sig", errors="replace", newline="") as fh:
            for line_no, line in enumerate(fh, start=1):
                if line_no <= layout.header_line or not _is_data(line, layout.sep):
                    continue
                k += 1
                if k == want[len(found)]:
                    found[k] = line_no
                    if len(found) == len(want):
                        break
    missing = [r for r in want if r not in found]
    if missing:
        raise ValueError(f"{layout.path}: no data row {missing[0]} (0-based) in the file")
    return [found[int(r)] for r in rows]


def diagnose(
    layout: TextLayout,
    names: Sequence[str],
    *,
    numeric: Sequence[str],
    where: str | None = None,
    nan_is_error: bool = False,
) -> None:
    """Stream the data rows and raise at the first bad one (does nothing if none is bad).

    Raises
    ------
    DataError
        ``FILE: line N has K cells, the header has M``, ``FILE: line N, column 'x': 'abc'
        is not a number``, a field too long, and the like.

    """
    shown = where or layout.path
    cols = {n: names.index(n) for n in numeric if n in names}
    old_limit = csv.field_size_limit()
    with open(layout.path, encoding="utf-8-sig", errors="strict", newline="") as fh:
        for line_no, line in enumerate(fh, start=1):
            if line_no <= layout.header_line or not _is_data(line, layout.sep):
                continue
            place = f"{shown}: line {line_no}"
            try:
                cells = next(csv.reader([_uncomment(line)], delimiter=layout.sep))  # '1,2 # note' is 2
            except csv.Error:
                raise DataError(
                    f"{place}: a field is longer than {old_limit} characters (the CSV limit)"
                ) from None
            while len(cells) > len(names) and not cells[-1].strip():
                cells.pop()
            if len(cells) != len(names):
                raise DataError(
                    f"{shown}: line {line_no} has {len(cells)} cells, the header has {len(names)}"
                )
            for name, j in cols.items():
                cell = cells[j].strip()
                if layout.decimal == ",":  # the file's decimal comma (its first lines said so)
                    if _POINT_NUMBER.match(cell):
                        raise DataError(
                            f"{place}, column {name!r}: {_show(cell)} has a decimal point, and the file's "
                            "first lines decimal commas: write one kind"
                        )  # the line that mixes the two, and the one kind to write
                    cell = cell.replace(",", ".")
                try:
                    x = float(cell)
                except ValueError:
                    comma = re.fullmatch(r"[+-]?\d*,\d+([eE][+-]?\d+)?", cell) is not None
                    hint = " (a decimal comma? write a decimal point: 10.5, not 10,5)" if comma else ""
                    message = f"{place}, column {name!r}: {_show(cell)} is not a number{hint}"
                    raise DataError(message) from None
                if math.isinf(x):
                    raise DataError(f"{place}, column {name!r}: {_show(cell)} is not a finite number")
                if nan_is_error and math.isnan(x):
                    raise DataError(f"{place}, column {name!r} is NaN")
