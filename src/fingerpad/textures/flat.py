"""A flat surface: the reference sample of the normalisation.
"""

from __future__ import annotations

from typing import Any

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from .base import Param, Texture, TextureFamily
from .geometry import (
    MAX_GRID,
    MIN_GRID,
    check_integer,
    parse_size,
)


def flat(*, size: Any, grid: Any = 64) -> Texture:
    """A flat surface (reference sample), periodic.

    Parameters
    ----------
    size
        Cell size, m: a number (square) or ``(Lx, Ly)``.
    grid
        Grid points along x (>= 8, default 64); ``ny = round(grid Ly / Lx)``, at least 1.

    Returns
    -------
    Texture
        All heights 0.
    """
    lx, ly = parse_size(size)
    nx = check_integer(grid, "grid", MIN_GRID, MAX_GRID)
    ny = max(1, int(round(nx * ly / lx)))
    return Texture(np.zeros((nx, ny)), (lx, ly), periodic=True, name="flat", family="flat",
                   params={"size": (lx, ly), "grid": nx})


FAMILIES = (
    TextureFamily(
        name="flat",
        generator=flat,
        params=(
            Param("size", "size", "cell size LX[,LY]", example="100um"),
            Param("grid", "grid", "grid points along x (default 64)", 64),
        ),
        summary="A flat surface (reference sample).",
    ),
)
