"""Old Excel workbooks (``.xls``, BIFF) read with xlrd."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ...errors import FingerpadError
from ...extras import load
from . import Importer, RawTable
from .excel import sheet_table

if TYPE_CHECKING:
    from ..columns import ColumnSpec


def read_xls_table(path: Path, spec: "ColumnSpec") -> RawTable:
    xlrd = load("xlrd", f"{path}: reading .xls workbooks")
    try:
        book = xlrd.open_workbook(str(path), on_demand=True)
    except FileNotFoundError:
        raise FingerpadError(f"{path}: file not found") from None
    except Exception as exc:  # xlrd raises XLRDError, CompDocError, struct errors... for a bad file
        raise FingerpadError(f"{path}: cannot open as an .xls workbook ({type(exc).__name__}: {exc})") from None
    try:
        names = book.sheet_names()
        if spec.sheet is None:
            sheet = book.sheet_by_index(0)
        elif spec.sheet in names:
            sheet = book.sheet_by_name(spec.sheet)
        else:
            raise FingerpadError(f"{path}: no sheet {spec.sheet!r} (sheets: {', '.join(names)})")
        values = [sheet.row_values(i) for i in range(sheet.nrows)]
    finally:
        book.release_resources()
    return sheet_table(path, values, spec)


IMPORTER = Importer(name="xls", suffixes=(".xls",), read_table=read_xls_table)
