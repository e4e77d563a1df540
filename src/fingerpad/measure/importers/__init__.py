"""Readers of tribometer files, one file per format, found by file suffix.

Each module of this package defines ``IMPORTER = Importer(...)``: the suffixes it reads and
``read_table(path, spec) -> RawTable``: the column names, one array per column (numbers, or
text where a cell is not a number) and the file row of every data row, so that messages can
name the row at fault. :mod:`fingerpad.measure.recordings` turns a table into SI time series.
A new format is added by adding one file.

Formats: delimited text (:mod:`.text`: CSV, TSV, semicolon, decimal comma), Excel
(:mod:`.excel`: .xlsx/.xlsm; :mod:`.xls`: old .xls), MATLAB (:mod:`.matlab`: .mat, v5 and
v7.3) and LabVIEW (:mod:`.tdms`: .tdms).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...errors import FingerpadError

if TYPE_CHECKING:
    from ..columns import ColumnSpec

__all__ = ["Importer", "RawTable", "Rows", "importer_for", "importers", "read_rows", "read_table",
           "supported_suffixes"]

#: ``(header, rows)``: column names, and data rows as (file row number, cells as text).
Rows = tuple[list[str], list[tuple[int, list[str]]]]


@dataclass
class RawTable:
    """A recording as read from its file, before units and column roles.

    Attributes
    ----------
    header
        Column (channel, variable) names.
    columns
        One 1-D array per name: ``float64``, or ``object`` holding text where a cell is not
        a number (converted, with the row named in any message, by the reader of recordings).
    rows
        The file row of each data row (1-based line of a text file, row of a sheet, or sample
        index of a binary file).
    units
        Units known from the file itself (LabVIEW ``unit_string``, MATLAB ``units``), ``""``
        where unknown; a unit in the column name (``"Fn [mN]"``) and the spec come first.
    row_word
        How messages name a row: ``"row"`` (text, sheets) or ``"sample"`` (binary formats).
    decimal
        Decimal separator of text cells (``","`` for decimal-comma files).
    """

    header: list[str]
    columns: list[np.ndarray]
    rows: np.ndarray
    units: list[str] = field(default_factory=list)
    row_word: str = "row"
    decimal: str = "."

    def __post_init__(self) -> None:
        if not self.units:
            self.units = [""] * len(self.header)


@dataclass(frozen=True)
class Importer:
    """A tribometer file format.

    Attributes
    ----------
    name
        Short name (``text``, ``excel``, ``xls``, ``matlab``, ``tdms``).
    suffixes
        Lower-case file suffixes it reads.
    read_table
        ``read_table(path, spec) -> RawTable``.
    """

    name: str
    suffixes: tuple[str, ...]
    read_table: Callable[[Path, "ColumnSpec"], RawTable]


_IMPORTERS: list[Importer] | None = None


def importers() -> list[Importer]:
    """Every importer of this package."""
    global _IMPORTERS
    if _IMPORTERS is None:
        from ...discover import collect

        _IMPORTERS = sorted(collect(__name__, __path__, "IMPORTER", Importer), key=lambda i: i.name)
    return list(_IMPORTERS)


def importer_for(path: Path) -> Importer | None:
    """The importer of ``path`` by its suffix, or ``None``."""
    ext = path.suffix.lower()
    return next((imp for imp in importers() if ext in imp.suffixes), None)


def supported_suffixes() -> tuple[str, ...]:
    """Every suffix some importer reads."""
    return tuple(sorted({s for imp in importers() for s in imp.suffixes}))


def read_table(path: Path, spec: "ColumnSpec") -> RawTable:
    """The table of a recording, by the importer of its suffix.

    Raises
    ------
    FingerpadError
        For a missing file, a suffix no importer reads, or a file its importer cannot read.
    """
    if not path.exists():
        raise FingerpadError(f"{path}: file not found")
    imp = importer_for(path)
    if imp is None:
        raise FingerpadError(
            f"{path}: cannot read {path.suffix or 'suffix-less'} files (readable: {', '.join(supported_suffixes())})"
        )
    return imp.read_table(path, spec)


def read_rows(path: Path, spec: "ColumnSpec") -> Rows:
    """Header and data rows as text (small files; :func:`read_table` is the fast reader)."""
    table = read_table(path, spec)
    cells = [np.asarray(c, dtype=object).astype(str) for c in table.columns]
    rows = [(int(r), [str(c[i]) for c in cells]) for i, r in enumerate(table.rows)]
    return list(table.header), rows


def unsupported(path: Path, why: str) -> FingerpadError:
    """The error for a file whose format is known but cannot be read."""
    return FingerpadError(f"{path}: {why}")


def first_data_row(rows: list[list[object]], skip: int, start: int = 1) -> int:
    """Index of the header among ``rows`` (lists of cells): after ``skip`` rows, the first row
    that is neither empty nor a ``#`` comment; -1 if none."""
    for i, cells in enumerate(rows):
        if i < skip:
            continue
        text = [str(c).strip() for c in cells if c is not None]
        if any(text) and not text[0].startswith("#"):
            return i
    return -1
