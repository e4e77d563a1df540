"""Excel workbooks (``.xlsx``, ``.xlsm``) read with openpyxl."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...errors import FingerpadError
from ...extras import load
from . import Importer, RawTable, first_data_row

if TYPE_CHECKING:
    from ..columns import ColumnSpec


def sheet_table(path: Path, values: list[list[object]], spec: "ColumnSpec") -> RawTable:
    """A table from a sheet's rows (lists of cell values; row ``i`` is sheet row ``i + 1``):
    the header after ``skip_rows`` rows and any empty or ``#`` rows, then one column per name."""
    h = first_data_row(values, spec.skip_rows)
    if h < 0:
        raise FingerpadError(f"{path}: no header row")
    header = ["" if c is None else str(c).strip() for c in values[h]]
    while header and not header[-1]:
        header.pop()
    keep = [i for i in range(h + 1, len(values))
            if any(c not in (None, "") for c in values[i])
            and not (values[i] and isinstance(values[i][0], str) and values[i][0].lstrip().startswith("#"))]
    cols = []
    for j in range(len(header)):
        cells = [values[i][j] if j < len(values[i]) else None for i in keep]
        arr = np.array([np.nan if c is None or c == "" else c for c in cells], dtype=object)
        try:
            cols.append(arr.astype(float))
        except (TypeError, ValueError):
            cols.append(arr)
    return RawTable(header=header, columns=cols, rows=np.array(keep, dtype=np.int64) + 1)


def read_excel_table(path: Path, spec: "ColumnSpec") -> RawTable:
    openpyxl = load("openpyxl", f"{path}: reading Excel files")
    try:
        book = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except FileNotFoundError:
        raise FingerpadError(f"{path}: file not found") from None
    except Exception as exc:  # openpyxl raises many types for a corrupt workbook
        raise FingerpadError(f"{path}: cannot open as an Excel workbook ({type(exc).__name__}: {exc})") from None
    try:
        if spec.sheet is None:
            sheet = book.worksheets[0]
        elif spec.sheet in book.sheetnames:
            sheet = book[spec.sheet]
        else:
            raise FingerpadError(f"{path}: no sheet {spec.sheet!r} (sheets: {', '.join(book.sheetnames)})")
        values = [list(r) for r in sheet.iter_rows(values_only=True)]
    finally:
        book.close()
    return sheet_table(path, values, spec)


IMPORTER = Importer(name="excel", suffixes=(".xlsx", ".xlsm"), read_table=read_excel_table)
