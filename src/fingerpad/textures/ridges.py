"""Parallel ridges (circular, sinusoidal or trapezoidal profile) running along y.
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
    DEFAULT_NY_1D,
    OVERLAP_RTOL,
    centred_field,
    check_choice,
    check_integer,
    check_length,
    check_touching,
    fmt_length,
    resolve_grid,
)

_RIDGE_PROFILES = ("circular", "sinusoidal", "trapezoidal")


def ridges(
    *,
    width: Any,
    height: Any,
    spacing: Any,
    profile: str = "circular",
    top_width: Any = None,
    grid: Any = None,
    ny: Any = DEFAULT_NY_1D,
) -> Texture:
    """Parallel ridges running along y (heights vary in x only), one unit cell.

    One ridge is centred at ``x = Lx/2`` of a cell ``Lx = spacing`` wide.

    Parameters
    ----------
    width
        Base width w of a ridge, m, ``w <= spacing``.
    height
        Ridge height h, m.
    spacing
        Ridge period (centre-to-centre distance), m.
    profile
        ``"circular"``: circular-arc segment of chord w and height h (``h <= w/2``).
        ``"sinusoidal"``: raised cosine ``h (1 + cos(2 pi u / w)) / 2`` for ``|u| <= w/2``;
        with ``w == spacing`` this is a full sinusoid.
        ``"trapezoidal"``: flat top of ``top_width`` with linear flanks down to the base at
        ``|u| = w/2`` (``top_width == width`` gives a rectangular ridge, 0 a triangular one).
    top_width
        Width of the flat top, m, trapezoidal profile only; default ``width / 2``.
    grid
        Grid points along x (even, >= 8). Default: ridge width over at least 16 pixels
        (64 ... 2048).
    ny
        Grid points along y (>= 1, default 8). The cell is ``Ly = ny * dx`` wide (square pixels);
        the map is constant along y, so any ny gives the same (plane-strain) periodic solution.

    Returns
    -------
    Texture
        Periodic cell, heights (m) with the base at 0 and ridge tops at h.
    """
    w = check_length(width, "width")
    h = check_length(height, "height")
    s = check_length(spacing, "spacing")
    prof = check_choice(profile, "profile", _RIDGE_PROFILES)
    nyy = check_integer(ny, "ny", 1)
    check_touching(w, s, f"ridge width {fmt_length(w)} exceeds the ridge spacing {fmt_length(s)}")
    params: dict[str, Any] = {"width": w, "height": h, "spacing": s, "profile": prof}
    if prof == "trapezoidal":
        if top_width is None:
            t = w / 2.0
        else:
            t = parse_quantity(top_width, "length", name="top_width")
            if not 0.0 <= t <= w * (1.0 + OVERLAP_RTOL):
                raise FingerpadError(f"top_width must lie between 0 and the width {fmt_length(w)}, got {fmt_length(t)}")
            t = min(t, w)
        params["top_width"] = t
    elif top_width is not None:
        raise FingerpadError(f"top_width applies to the trapezoidal profile only, not {prof!r}")
    if prof == "circular" and h > w / 2.0 * (1.0 + OVERLAP_RTOL):
        raise FingerpadError(
            f"a circular-arc ridge cannot be higher than half its width: height {fmt_length(h)} > "
            f"width/2 = {fmt_length(w / 2)}"
        )
    nx = resolve_grid(grid, s, w, "ridge width")
    dx = s / nx
    half = w / 2.0

    def shape(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        u = np.abs(x)
        inside = u <= half * (1.0 + 1e-12)
        if prof == "circular":
            rad = (half * half + h * h) / (2.0 * h)
            z = h - u * u / (rad + np.sqrt(np.maximum(rad * rad - u * u, 0.0)))
        elif prof == "sinusoidal":
            z = 0.5 * h * (1.0 + np.cos(2.0 * math.pi * u / w))
        else:
            flank = half - t / 2.0
            if flank <= 0.0:
                z = np.full_like(u, h)
            else:
                z = np.minimum(h, h * (half - u) / flank)
        return np.where(inside, np.maximum(z, 0.0), 0.0)

    heights = centred_field(shape, nx, nyy, dx, dx)
    params.update(grid=nx, ny=nyy)
    return Texture(heights, (s, nyy * dx), periodic=True, name="ridges", params=params, family="ridges")


@dataclass(frozen=True)
class RidgeGeometry:
    """Parallel ridges along y (as :func:`fingerpad.textures.ridges`), SI units."""

    width: float
    height: float
    spacing: float
    profile: str = "circular"

    def __post_init__(self) -> None:
        for name in ("width", "height", "spacing"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise FingerpadError(f"ridge {name} must be a positive length, got {v!r}")
        if self.profile != "circular":
            raise FingerpadError(
                f"the deflection model supports circular ridges only, not {self.profile!r} "
                "(a sinusoidal ridge meets its base tangentially and a trapezoid has corners)")
        if self.height > self.width / 2 * (1 + 1e-9):
            raise FingerpadError("a circular ridge cannot be higher than half its width")

    def section(self, direction_deg: float) -> Section:
        """The ridge's cross-section; only the shear component across the ridges acts in it."""
        t = section_radians(direction_deg)
        # |cos| of an angle that is an odd multiple of 90 deg is exactly 0 (not 6e-17)
        across = 0.0 if math.isclose(math.fmod(abs(direction_deg), 180.0), 90.0, abs_tol=1e-9) else abs(math.cos(t))
        return Section("circular", self.width / 2, self.height, self.spacing, self.spacing, across)

    def principal_directions(self) -> tuple[float, float]:
        """(parallel, perpendicular): along the ridges (y) and across them, degrees."""
        return 90.0, 0.0

    def tip_radii(self) -> None:
        """Parallel ridges have no elliptical tip contact (the hysteresis factor is 1)."""
        return None


def _deflection(params: Any) -> Any:
    """The compliant-asperity model's geometry of these ridges (their cross-section; circular only)."""
    return RidgeGeometry(float(params["width"]), float(params["height"]), float(params["spacing"]),
                         str(params.get("profile", "circular")))


FAMILIES = (
    TextureFamily(
        name="ridges",
        features=lambda t: (t.params["width"], t.params["height"]),
        generator=ridges,
        params=(
            Param("width", "length", "base width w of a ridge (w <= spacing)", example="40um"),
            Param("height", "length", "ridge height h", example="10um"),
            Param("spacing", "length", "ridge period (centre-to-centre distance)", example="120um"),
            Param("profile", "choice", "ridge cross-section", "circular", _RIDGE_PROFILES),
            Param("top_width", "length", "flat top width of a trapezoidal ridge (default width/2)", None),
            Param("grid", "grid", "grid points along x of the cell (even; default: the smallest feature over 16 pixels)", None),
            Param("ny", "count", "grid points along the ridges (the map is constant along y)", DEFAULT_NY_1D),
        ),
        summary="Parallel ridges running along y.",
        deflection=_deflection,
    ),
)
