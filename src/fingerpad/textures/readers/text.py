"""Plain-text height matrices (``.txt``, ``.csv``, ``.dat``, ``.asc``), stored image-like."""

from __future__ import annotations

import math
import re
from pathlib import Path

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from ...errors import FingerpadError
from . import Reader
from .npy import one_line_exception


def _load_text(path: Path) -> np.ndarray:
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise FingerpadError(f"cannot read {path}: {one_line_exception(exc)}") from None
    rows: list[list[float]] = []
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped[0] in "#%;":
            continue
        if "," in stripped or ";" in stripped:
            tokens = [t.strip() for t in re.split(r"[,;]", stripped)]
            if tokens and tokens[-1] == "":  # trailing separator
                tokens = tokens[:-1]
        else:
            tokens = stripped.split()
        row = []
        for tok in tokens:
            if tok == "":
                row.append(math.nan)
                continue
            try:
                row.append(float(tok))
            except ValueError:
                raise FingerpadError(
                    f"{path}: line {lineno}: cannot read {tok!r} as a number "
                    f"(comment lines must start with #)"
                ) from None
        if rows and len(row) != len(rows[0]):
            raise FingerpadError(
                f"{path}: line {lineno} has {len(row)} values, earlier lines have {len(rows[0])}"
            )
        rows.append(row)
    if not rows:
        raise FingerpadError(f"{path}: no height data found")
    # Text matrices are stored image-like: each row is a line along x at one y.
    return np.array(rows, dtype=float).T


def _load(path: Path, size: tuple[float, float] | None, factor: float | None):
    assert size is not None and factor is not None  # bare format: checked by read_surface
    return _load_text(path), size, factor


READER = Reader(name="text", suffixes=(".txt", ".csv", ".tsv", ".dat", ".asc"), bare=True, load=_load)
