"""Excel workbooks (``.xlsx``, ``.xlsm``) read with openpyxl."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ...errors import FingerpadError
from . import Importer, Rows

if TYPE_CHECKING:
    from ..columns import ColumnSpec


def read_excel_rows(path: Path, spec: "ColumnSpec") -> Rows:
    try:
        import openpyxl
    except ImportError:  # pragma: no cover - openpyxl ships with the environment
        raise FingerpadError(f"{path}: reading Excel files needs openpyxl (pip install openpyxl)") from None
    if not path.exists():
        raise FingerpadError(f"{path}: file not found")
    try:
        book = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as exc:  # openpyxl raises many types for a corrupt workbook
        raise FingerpadError(f"{path}: cannot open as an Excel workbook ({type(exc).__name__}: {exc})") from None
    try:
        if spec.sheet is None:
            sheet = book.worksheets[0]
        elif spec.sheet in book.sheetnames:
            sheet = book[spec.sheet]
        else:
            raise FingerpadError(f"{path}: no sheet {spec.sheet!r} (sheets: {', '.join(book.sheetnames)})")
        rows = []
        for i, values in enumerate(sheet.iter_rows(values_only=True), start=1):
            if i <= spec.skip_rows:
                continue
            cells = ["" if v is None else str(v) for v in values]
            if not any(c.strip() for c in cells) or (cells and cells[0].lstrip().startswith("#")):
                continue
            rows.append((i, cells))
    finally:
        book.close()
    if not rows:
        raise FingerpadError(f"{path}: no header row")
    return [c.strip() for c in rows[0][1]], rows[1:]


IMPORTER = Importer(name="excel", suffixes=(".xlsx", ".xlsm"), read_rows=read_excel_rows)
