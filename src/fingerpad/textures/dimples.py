"""Spherical dimples pressed into a flat top (the dimple matrix of the thesis).
"""

from __future__ import annotations

import math
from typing import Any

from .base import Param, Texture, TextureFamily
from .caps import caps_field
from .geometry import check_length


def dimples(
    *, radius: Any, depth: Any, spacing: Any, lattice: str = "square", grid: Any = None
) -> Texture:
    """Spherical dimples pressed into a flat top, one unit cell.

    The geometry is that of :func:`spherical_caps` turned upside down: sphere radius R, dimple
    depth d <= R, rim radius ``a = sqrt(2 R d - d^2)``, same lattices and cells.

    Parameters
    ----------
    radius
        Sphere radius R, m.
    depth
        Dimple depth d below the flat top, m, ``0 < d <= R``.
    spacing
        Nearest-neighbour distance of the dimple centres, m; ``2 a <= spacing``.
    lattice
        ``"square"`` or ``"hexagonal"``, as for :func:`spherical_caps`.
    grid
        Grid points along x (even, >= 8); default as for :func:`spherical_caps`.

    Returns
    -------
    Texture
        Periodic cell. Height convention: the minimum is 0 like every generated texture, so the
        dimple bottoms are at ``z = 0`` and the flat top at ``z = depth``; the map equals
        ``depth - spherical_caps(radius, depth, spacing).heights``.
    """
    caps, size, lat, nx = caps_field(radius, depth, spacing, lattice, grid, "dimple", "depth")
    d = check_length(depth, "depth")
    params = {"radius": check_length(radius, "radius"), "depth": d, "spacing": check_length(spacing, "spacing"),
              "lattice": lat, "grid": nx}
    return Texture(d - caps, size, periodic=True, name="dimples", params=params, family="dimples")


FAMILIES = (
    TextureFamily(
        name="dimples",
        features=lambda t: (2 * math.sqrt(t.params["depth"] * (2 * t.params["radius"] - t.params["depth"])), t.params["depth"]),
        generator=dimples,
        params=(
            Param("radius", "length", "sphere radius R of a dimple", example="100um"),
            Param("depth", "length", "dimple depth d below the flat top (d <= R)", example="20um"),
            Param("spacing", "length", "centre-to-centre distance of neighbouring dimples", example="175um"),
            Param("lattice", "choice", "square: one asperity per spacing x spacing cell; hexagonal: six neighbours at spacing", "square", ("square", "hexagonal")),
            Param("grid", "grid", "grid points along x of the cell (even; default: the smallest feature over 16 pixels)", None),
        ),
        summary="Spherical dimples pressed into a flat top.",
    ),
)
