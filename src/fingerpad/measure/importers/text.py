"""Delimited text recordings: CSV, TSV, semicolon-separated (the delimiter is sniffed from the header)."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TYPE_CHECKING

from ...errors import FingerpadError
from . import Importer, Rows

if TYPE_CHECKING:
    from ..columns import ColumnSpec


def sniff_delimiter(header: str) -> str:
    counts = {d: header.count(d) for d in ("\t", ";", ",")}
    best = max(counts, key=counts.get)  # type: ignore[arg-type]
    return best if counts[best] else ","


def read_text_rows(path: Path, spec: "ColumnSpec") -> Rows:
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


IMPORTER = Importer(name="text", suffixes=(".csv", ".tsv", ".tab", ".txt", ".dat"), read_rows=read_text_rows)
