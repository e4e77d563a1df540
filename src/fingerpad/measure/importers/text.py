"""Delimited text recordings: CSV, TSV, semicolon-separated, decimal point or decimal comma.

The delimiter is sniffed from the header line (tab for ``.tsv``/``.tab``) unless the spec names
it; the decimal separator is detected from the first data lines (a comma between digits, with
a semicolon or tab as delimiter) unless the spec names it. The data are parsed in one
vectorised pass (pandas' C parser); the file line of every data row is found from the
positions of the line breaks, so messages still name the line. Files the fast parser cannot
take (ragged rows, stray text) are read line by line with the same result.
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...errors import FingerpadError
from . import Importer, RawTable, Rows

if TYPE_CHECKING:
    from ..columns import ColumnSpec

_COMMA_NUMBER = re.compile(r"^\s*[-+]?\d*,\d+(?:[eE][-+]?\d+)?\s*$")
_POINT_NUMBER = re.compile(r"^\s*[-+]?\d*\.\d+(?:[eE][-+]?\d+)?\s*$")


def sniff_delimiter(header: str) -> str:
    counts = {d: header.count(d) for d in ("\t", ";", ",")}
    best = max(counts, key=counts.get)  # type: ignore[arg-type]
    return best if counts[best] else ","


def detect_decimal(lines: list[str], delimiter: str) -> str:
    """``","`` when the data write numbers with a decimal comma, else ``"."``.

    Only possible when the delimiter is not itself a comma. Cells like ``0,52`` (and no
    ``0.52``) decide it.

    Raises
    ------
    FingerpadError
        When both forms appear (set ``decimal`` in the spec or ``--decimal``).
    """
    if delimiter == ",":
        return "."
    comma = point = 0
    for line in lines:
        for cell in line.split(delimiter):
            comma += bool(_COMMA_NUMBER.match(cell))
            point += bool(_POINT_NUMBER.match(cell))
    if comma and point:
        raise FingerpadError("numbers are written with both decimal points and decimal commas; "
                             "set decimal = \",\" or \".\" in the spec [files] (or --decimal)")
    return "," if comma else "."


def _lines_at_start(data: bytes, limit: int = 200) -> list[tuple[int, int, str]]:
    """The first ``limit`` lines as ``(line number, byte offset after the line, text)``."""
    out, pos = [], 0
    for number in range(1, limit + 1):
        end = data.find(b"\n", pos)
        stop = len(data) if end < 0 else end + 1
        if pos >= len(data):
            break
        out.append((number, stop, data[pos:stop].decode("utf-8").rstrip("\r\n")))
        pos = stop
    return out


def _skipped(text: str) -> bool:
    return not text.strip() or text.lstrip().startswith("#")


def _data_line_numbers(section: bytes, first_line: int) -> np.ndarray:
    """File line numbers of the data lines of ``section`` (lines that are neither empty nor
    start with ``#``), found from the positions of the line breaks."""
    if not section:
        return np.zeros(0, dtype=np.int64)
    arr = np.frombuffer(section, dtype=np.uint8)
    nl = np.flatnonzero(arr == 10)
    starts = np.r_[0, nl + 1]
    ends = np.r_[nl, arr.size]
    if starts[-1] >= arr.size:  # the file ends with a line break: no last line
        starts, ends = starts[:-1], ends[:-1]
    length = ends - starts
    # no comment and every line longer than one byte (so none empty, none a lone CR): every
    # line is a data line. Told from the line lengths: searching the bytes for b"\n\n" and
    # b"\n\r\n" took some 30 ms of a 60 000-line file, a fifth of reading it
    if b"#" not in section and (length > 1).all():
        return first_line + np.arange(starts.size, dtype=np.int64)
    cr = (length > 0) & (arr[np.maximum(ends - 1, 0)] == 13)
    length = length - cr
    first = np.where(length > 0, arr[np.minimum(starts, arr.size - 1)], 0)
    keep = (length > 0) & (first != ord("#"))
    return first_line + np.flatnonzero(keep).astype(np.int64)


def _slow_table(path: Path, text_lines: list[tuple[int, str]], header: list[str], delim: str,
                decimal: str) -> RawTable:
    """Line by line (exact, for files the fast parser rejects)."""
    rows = [(n, cells) for (n, _), cells in zip(text_lines, csv.reader([t for _, t in text_lines], delimiter=delim))]
    width = max([len(header)] + [len(c) for _, c in rows])
    cols = [np.array([(c[j].strip() if j < len(c) else "") for _, c in rows], dtype=object) for j in range(width)]
    for j in range(len(header), width):
        bad = np.flatnonzero(cols[j] != "")
        if bad.size:
            raise FingerpadError(f"{path}, row {rows[int(bad[0])][0]}: more fields than the header has columns "
                                 f"({len(header)}); check the delimiter {delim!r}")
    return RawTable(header=header, columns=cols[: len(header)], rows=np.array([n for n, _ in rows], dtype=np.int64),
                    decimal=decimal)


def read_text_table(path: Path, spec: "ColumnSpec") -> RawTable:
    """Read a delimited text recording (see the module doc)."""
    import pandas as pd

    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise FingerpadError(f"{path}: file not found") from None
    if b"\x00" in data[:8192]:
        raise FingerpadError(f"{path}: not a text file (binary content; is it an Excel, MATLAB or LabVIEW file "
                             "with the wrong suffix?)")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        start = _lines_at_start(data)
    except UnicodeDecodeError:
        raise FingerpadError(f"{path}: not a UTF-8 text file (is it a binary or Excel file?)") from None
    head = [(n, stop, t) for n, stop, t in start if n > spec.skip_rows and not _skipped(t)]
    if not head:
        raise FingerpadError(f"{path}: no header row")
    header_line, header_end, header_text = head[0]
    delim = spec.delimiter or ("\t" if path.suffix.lower() in (".tsv", ".tab") else sniff_delimiter(header_text))
    header = [c.strip() for c in next(csv.reader([header_text], delimiter=delim))]
    try:
        decimal = spec.decimal or detect_decimal([t for _, _, t in head[1:51]], delim)
    except FingerpadError as exc:
        raise FingerpadError(f"{path}: {exc}") from None
    if decimal == delim:
        raise FingerpadError(f"{path}: the decimal separator and the delimiter are both {delim!r}")
    section = data[header_end:]
    lines = _data_line_numbers(section, header_line + 1)
    try:
        frame = pd.read_csv(io.BytesIO(section), sep=delim, decimal=decimal, header=None, comment="#",
                            skip_blank_lines=True, engine="c", encoding="utf-8", low_memory=False,
                            skipinitialspace=True, dtype=None)
        fast = len(frame) == lines.size and frame.shape[1] >= len(header)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError):
        fast, frame = False, None
    except UnicodeDecodeError:
        raise FingerpadError(f"{path}: not a UTF-8 text file") from None
    if fast:
        extra = frame.iloc[:, len(header):]
        if extra.shape[1] and extra.notna().any().any():
            fast = False  # ragged rows: the exact reader names the line
    if not fast:
        text_lines = [(int(n), t) for n, t in _numbered_lines(section, header_line + 1)]
        return _slow_table(path, text_lines, header, delim, decimal)
    cols = [frame.iloc[:, j].to_numpy() for j in range(len(header))]
    return RawTable(header=header, columns=cols, rows=lines, decimal=decimal)


def _numbered_lines(section: bytes, first_line: int) -> list[tuple[int, str]]:
    text = section.decode("utf-8")
    return [(first_line + i, line) for i, line in enumerate(text.splitlines()) if not _skipped(line)]


def read_text_rows(path: Path, spec: "ColumnSpec") -> Rows:
    """Header and rows as text, line by line (manifests and sample tables: small files)."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise FingerpadError(f"{path}: file not found") from None
    except UnicodeDecodeError:
        raise FingerpadError(f"{path}: not a UTF-8 text file (is it a binary or Excel file?)") from None
    numbered = [
        (i + 1, line) for i, line in enumerate(text.splitlines())
        if i >= spec.skip_rows and line.strip() and not line.lstrip().startswith("#")
    ]
    if not numbered:
        raise FingerpadError(f"{path}: no header row")
    delim = spec.delimiter or ("\t" if path.suffix.lower() in (".tsv", ".tab") else sniff_delimiter(numbered[0][1]))
    parsed = csv.reader([line for _, line in numbered], delimiter=delim)
    rows = [(n, cells) for (n, _), cells in zip(numbered, parsed)]
    return [c.strip() for c in rows[0][1]], rows[1:]


IMPORTER = Importer(name="text", suffixes=(".csv", ".tsv", ".tab", ".txt", ".dat"), read_table=read_text_table)
