"""Readers of tribometer files, one file per format, found by file suffix.

Each module of this package defines ``IMPORTER = Importer(...)``: the suffixes it reads and
``read_rows(path, spec) -> (header, rows)``, where ``header`` is the list of column names and
``rows`` the data rows as ``(file row number, cells as text)``; :mod:`fingerpad.measure.recordings`
turns them into SI time series. A new format is added by adding one file.
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ...errors import FingerpadError

if TYPE_CHECKING:
    from ..columns import ColumnSpec

__all__ = ["Importer", "Rows", "importer_for", "importers", "read_rows"]

#: ``(header, rows)``: column names, and data rows as (file row number, cells as text).
Rows = tuple[list[str], list[tuple[int, list[str]]]]


@dataclass(frozen=True)
class Importer:
    """A tribometer file format.

    Attributes
    ----------
    name
        Short name (``text``, ``excel``).
    suffixes
        Lower-case file suffixes it reads.
    read_rows
        ``read_rows(path, spec) -> (header, rows)``.
    """

    name: str
    suffixes: tuple[str, ...]
    read_rows: Callable[[Path, "ColumnSpec"], Rows]


_IMPORTERS: list[Importer] | None = None


def importers() -> list[Importer]:
    """Every importer of this package."""
    global _IMPORTERS
    if _IMPORTERS is None:
        found = []
        for info in pkgutil.iter_modules(__path__):
            module = importlib.import_module(f"{__name__}.{info.name}")
            imp = getattr(module, "IMPORTER", None)
            if isinstance(imp, Importer):
                found.append(imp)
        _IMPORTERS = sorted(found, key=lambda i: i.name)
    return list(_IMPORTERS)


def importer_for(path: Path) -> Importer | None:
    """The importer of ``path`` by its suffix, or ``None``."""
    ext = path.suffix.lower()
    return next((imp for imp in importers() if ext in imp.suffixes), None)


def read_rows(path: Path, spec: "ColumnSpec") -> Rows:
    """Header and data rows of a recording, by the importer of its suffix (text if unknown)."""
    imp = importer_for(path)
    if imp is None:
        from .text import read_text_rows

        return read_text_rows(path, spec)
    return imp.read_rows(path, spec)


def supported_suffixes() -> tuple[str, ...]:
    """Every suffix some importer reads."""
    return tuple(sorted({s for imp in importers() for s in imp.suffixes}))


def unsupported(path: Path, why: str) -> FingerpadError:
    """The error for a file whose format is known but cannot be read."""
    return FingerpadError(f"{path}: {why}")
