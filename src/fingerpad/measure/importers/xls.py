"""Old Excel workbooks (``.xls``): recognised, but not read yet (save as .xlsx or CSV)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ...errors import FingerpadError
from . import Importer, Rows

if TYPE_CHECKING:
    from ..columns import ColumnSpec


def read_xls_rows(path: Path, spec: "ColumnSpec") -> Rows:
    raise FingerpadError(f"{path}: old .xls workbooks are not supported; save it as .xlsx or CSV")


IMPORTER = Importer(name="xls", suffixes=(".xls",), read_rows=read_xls_rows)
