"""Readers of height-map files, one file per format, found by file suffix.

Each module of this package defines ``READER = Reader(...)``: the suffixes it reads, whether the
file carries its own lateral size and height unit, and ``load(path, size, factor)`` returning the
raw heights (file units, NaN where undefined), the lateral size (m) and the height factor to
metres. A new format is added by adding one file; the instrument reader (SurfaceTopography) takes
every suffix no other reader claims.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

__all__ = ["Reader", "reader_for", "readers"]

Loader = Callable[[Path, "tuple[float, float] | None", "float | None"], "tuple[np.ndarray, tuple[float, float], float]"]


@dataclass(frozen=True)
class Reader:
    """A height-map format.

    Attributes
    ----------
    name
        Short name (``npy``, ``text``, ``instrument``).
    suffixes
        Lower-case suffixes it reads; empty for the fallback reader.
    bare
        True when the file stores bare numbers: the caller must give the size and the height unit.
    load
        ``load(path, size, factor) -> (heights in file units, (Lx, Ly) in m, factor to m)``.
    """

    name: str
    suffixes: tuple[str, ...]
    bare: bool
    load: Loader


_READERS: list[Reader] | None = None


def readers() -> list[Reader]:
    """Every reader of this package (the fallback last)."""
    global _READERS
    if _READERS is None:
        from ...discover import collect

        _READERS = sorted(collect(__name__, __path__, "READER", Reader), key=lambda r: (not r.suffixes, r.name))
    return list(_READERS)


def reader_for(path: Path) -> Reader:
    """The reader of ``path`` by its suffix (the fallback for unknown suffixes)."""
    ext = path.suffix.lower()
    all_readers = readers()
    for reader in all_readers:
        if ext in reader.suffixes:
            return reader
    return all_readers[-1]
