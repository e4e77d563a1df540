"""Half-ellipsoid asperities on a rectangular lattice (directional textures, Paper C).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from ..errors import FingerpadError
from ..units import parse_quantity
from .base import Param, Section, Texture, TextureFamily, section_radians
from .geometry import (
    centred_field,
    check_length,
    check_resolution,
    check_touching,
    even_smooth,
    fmt_length,
    resolve_grid,
)


def ellipsoids(
    *,
    semi_axis_x: Any,
    semi_axis_y: Any,
    height: Any,
    spacing_x: Any,
    spacing_y: Any,
    orientation: Any = 0.0,
    grid: Any = None,
) -> Texture:
    """Half-ellipsoid asperities on a rectangular lattice, one unit cell.

    ``z = h sqrt(1 - (x'/a)^2 - (y'/b)^2)`` with ``(x', y')`` the coordinates rotated by
    ``orientation`` about the asperity centre ``(Lx/2, Ly/2)``.

    Parameters
    ----------
    semi_axis_x, semi_axis_y
        Semi-axes a and b of the footprint ellipse, m, along x and y before rotation.
    height
        Asperity height h, m.
    spacing_x, spacing_y
        Lattice periods along x and y, m (the cell is ``spacing_x x spacing_y``).
    orientation
        Rotation of the ellipse in the x-y plane, radians (or a string such as ``"30deg"``),
        counter-clockwise from x.
    grid
        Grid points along x (even, >= 8). Default: the smaller semi-axis over at least 16 pixels
        (64 ... 2048). ``ny = round(nx spacing_y / spacing_x)`` moved to the nearest even
        7-smooth size.

    Returns
    -------
    Texture
        Periodic cell, heights (m) with the base at 0 and asperity tops at h.

    Raises
    ------
    FingerpadError
        When the bounding box of the rotated footprint, ``2 sqrt((a cos t)^2 + (b sin t)^2)`` by
        ``2 sqrt((a sin t)^2 + (b cos t)^2)``, exceeds the spacings (neighbouring asperities
        overlap), or for non-positive dimensions.
    """
    a = check_length(semi_axis_x, "semi_axis_x")
    b = check_length(semi_axis_y, "semi_axis_y")
    h = check_length(height, "height")
    sx = check_length(spacing_x, "spacing_x")
    sy = check_length(spacing_y, "spacing_y")
    theta = parse_quantity(orientation, "angle", name="orientation")
    c, s = math.cos(theta), math.sin(theta)
    ex = math.hypot(a * c, b * s)
    ey = math.hypot(a * s, b * c)
    check_touching(2 * ex, sx, f"ellipsoids overlap along x: footprint extent {fmt_length(2 * ex)} exceeds spacing_x {fmt_length(sx)}")
    check_touching(2 * ey, sy, f"ellipsoids overlap along y: footprint extent {fmt_length(2 * ey)} exceeds spacing_y {fmt_length(sy)}")
    feature = min(a, b)
    nx = resolve_grid(grid, sx, feature, "smaller ellipsoid semi-axis")
    ny = even_smooth(nx * sy / sx)
    if sy / ny > sx / nx:  # coarser along y (rounding of ny): check that direction too
        check_resolution(feature, sy / ny, "smaller ellipsoid semi-axis")

    def shape(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        xp = (x * c + y * s) / a
        yp = (y * c - x * s) / b
        return h * np.sqrt(np.maximum(1.0 - xp * xp - yp * yp, 0.0))

    heights = centred_field(shape, nx, ny, sx / nx, sy / ny)
    params = {"semi_axis_x": a, "semi_axis_y": b, "height": h, "spacing_x": sx, "spacing_y": sy,
              "orientation": theta, "grid": nx}
    return Texture(heights, (sx, sy), periodic=True, name="ellipsoids", params=params, family="ellipsoids")


@dataclass(frozen=True)
class EllipsoidGeometry:
    """Half-ellipsoid asperities (as :func:`fingerpad.textures.ellipsoids`), SI units.

    ``orientation`` in radians (counter-clockwise from x).
    """

    semi_axis_x: float
    semi_axis_y: float
    height: float
    spacing_x: float
    spacing_y: float
    orientation: float = 0.0

    def __post_init__(self) -> None:
        for name in ("semi_axis_x", "semi_axis_y", "height", "spacing_x", "spacing_y"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise FingerpadError(f"ellipsoid {name} must be a positive length, got {v!r}")
        if not math.isfinite(self.orientation):
            raise FingerpadError("ellipsoid orientation must be finite")

    def section(self, direction_deg: float) -> Section:
        """The semi-elliptical section sheared when sliding at ``direction_deg`` (module docstring)."""
        t = section_radians(direction_deg)
        phi = t - self.orientation
        r = 1.0 / math.sqrt(math.cos(phi) ** 2 / self.semi_axis_x**2 + math.sin(phi) ** 2 / self.semi_axis_y**2)
        lam = 1.0 / math.sqrt(math.cos(t) ** 2 / self.spacing_x**2 + math.sin(t) ** 2 / self.spacing_y**2)
        lam = max(lam, 2.0 * r)
        per_p = self.spacing_x * self.spacing_y * 2.0 * r / (math.pi * self.semi_axis_x * self.semi_axis_y)
        return Section("ellipse", r, self.height, lam, per_p, 1.0)

    def principal_directions(self) -> tuple[float, float]:
        """(parallel, perpendicular): along the long axis of the footprint and across it, degrees."""
        long = math.degrees(self.orientation) + (0.0 if self.semi_axis_x >= self.semi_axis_y else 90.0)
        return long % 180.0, (long + 90.0) % 180.0

    def tip_radii(self) -> tuple[float, float, float]:
        """The asperity tip's principal radii of curvature ``(a^2/h, b^2/h)`` (m) and the
        direction of the first one (radians from x): what the elliptical hysteresis needs."""
        return self.semi_axis_x**2 / self.height, self.semi_axis_y**2 / self.height, self.orientation


def _deflection(params: Any) -> Any:
    """The compliant-asperity model's geometry of these ellipsoids (a semi-ellipse per direction)."""
    return EllipsoidGeometry(float(params["semi_axis_x"]), float(params["semi_axis_y"]), float(params["height"]),
                             float(params["spacing_x"]), float(params["spacing_y"]),
                             float(params.get("orientation", 0.0)))


FAMILIES = (
    TextureFamily(
        name="ellipsoids",
        features=lambda t: (2 * min(t.params["semi_axis_x"], t.params["semi_axis_y"]), t.params["height"]),
        generator=ellipsoids,
        params=(
            Param("semi_axis_x", "length", "footprint semi-axis a along x (before rotation)", example="60um"),
            Param("semi_axis_y", "length", "footprint semi-axis b along y (before rotation)", example="30um"),
            Param("height", "length", "asperity height h", example="20um"),
            Param("spacing_x", "length", "lattice period along x", example="175um"),
            Param("spacing_y", "length", "lattice period along y", example="120um"),
            Param("orientation", "angle", "rotation of the ellipse, counter-clockwise from x", 0.0),
            Param("grid", "grid", "grid points along x of the cell (even; default: the smallest feature over 16 pixels)", None),
        ),
        summary="Half-ellipsoid asperities on a rectangular lattice.",
        deflection=_deflection,
    ),
)
