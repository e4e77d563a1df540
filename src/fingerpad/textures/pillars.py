"""Flat-topped cylindrical pillars on a flat base.
"""

from __future__ import annotations

from typing import Any

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from .base import Param, Texture, TextureFamily
from .geometry import (
    LATTICES,
    centred_field,
    check_choice,
    check_length,
    check_touching,
    fmt_length,
    lattice_cell,
    place_on_lattice,
)


def pillars(
    *, diameter: Any, height: Any, spacing: Any, lattice: str = "square", grid: Any = None
) -> Texture:
    """Flat-topped cylindrical pillars on a flat base, one unit cell.

    Parameters
    ----------
    diameter
        Pillar diameter d, m, ``d <= spacing``.
    height
        Pillar height h, m.
    spacing
        Nearest-neighbour distance, m.
    lattice
        ``"square"`` or ``"hexagonal"``; cells as for :func:`spherical_caps`.
    grid
        Grid points along x (even, >= 8). Default: the diameter over at least 16 pixels
        (64 ... 2048).

    Returns
    -------
    Texture
        Periodic cell: ``z = h`` at grid points within ``d/2`` of a pillar axis, 0 elsewhere.
    """
    d = check_length(diameter, "diameter")
    h = check_length(height, "height")
    s = check_length(spacing, "spacing")
    lat = check_choice(lattice, "lattice", LATTICES)
    check_touching(d, s, f"pillars overlap: diameter {fmt_length(d)} exceeds the nearest-neighbour distance {fmt_length(s)} (spacing)")
    size, nx, ny = lattice_cell(s, lat, grid, d, "pillar diameter")
    r2max = (d / 2.0) ** 2 * (1.0 + 1e-12)

    def shape(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.where(x * x + y * y <= r2max, h, 0.0)

    heights = place_on_lattice(centred_field(shape, nx, ny, size[0] / nx, size[1] / ny), lat)
    params = {"diameter": d, "height": h, "spacing": s, "lattice": lat, "grid": nx}
    return Texture(heights, size, periodic=True, name="pillars", params=params, family="pillars")


FAMILIES = (
    TextureFamily(
        name="pillars",
        features=lambda t: (t.params["diameter"], t.params["height"]),
        generator=pillars,
        params=(
            Param("diameter", "length", "pillar diameter d (d <= spacing)", example="60um"),
            Param("height", "length", "pillar height h", example="20um"),
            Param("spacing", "length", "centre-to-centre distance of neighbouring pillars", example="150um"),
            Param("lattice", "choice", "square: one asperity per spacing x spacing cell; hexagonal: six neighbours at spacing", "square", ("square", "hexagonal")),
            Param("grid", "grid", "grid points along x of the cell (even; default: the smallest feature over 16 pixels)", None),
        ),
        summary="Flat-topped cylindrical pillars on a flat base.",
    ),
)
