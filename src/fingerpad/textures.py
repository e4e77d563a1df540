"""Textures: periodic height maps of the counter-surface over one unit cell.

Convention (used by every module): ``heights[i, j]`` is the surface height z (m, positive toward
the skin) at ``x = i * dx``, ``y = j * dy`` with ``dx = size[0] / nx``, ``dy = size[1] / ny``.

Generated textures
------------------
Every generator returns a periodic :class:`Texture` holding exactly one unit cell, with all
lengths in metres (numbers are SI; strings with a unit such as ``"50um"`` are accepted too).

* **Height datum.** Every generated map has its minimum at exactly ``z = 0``. For bumps,
  pillars and ridges ``z = 0`` is the flat base. For :func:`dimples` the flat top lies at
  ``z = depth`` and the dimple bottoms at ``z = 0`` (the dimple map is ``depth`` minus the
  matching cap map). A rigid shift of z changes nothing in a contact calculation.
* **Sampling.** Heights are sampled directly (no anti-aliasing, no pixel averaging) at the grid
  points ``x = i * dx``, ``y = j * dy``. Feature centres are placed on grid points (the cell
  centre ``(Lx/2, Ly/2)``, and the cell corner for the second site of a hexagonal cell), which is
  why lattice generators need an even ``grid``. Distances to a centre are computed from integer
  pixel offsets, so mirror-symmetric features give bit-for-bit mirror-symmetric arrays, e.g.
  ``np.roll(h[::-1], 1, axis=0) == h`` for a texture symmetric under ``x -> -x``.
* **Resolution.** ``grid`` is the number of grid points along x of the cell. By default it is
  chosen so that the smallest feature (cap base radius, dimple radius, pillar diameter, ridge
  width, smaller ellipsoid semi-axis, quarter wavelength of a sinusoid) spans at least 16 pixels,
  rounded up to ``2**k`` or ``3 * 2**k``, at least 64 and at most 2048. A
  :class:`~fingerpad.errors.ResolutionWarning` is issued when that feature spans fewer than 8
  pixels; ``grid < 8`` is an error. The number of points along y follows from the cell aspect
  ratio so that pixels are (nearly) square, except for the 1-D textures (ridges, sinusoid) whose
  cell is ``ny`` pixels (default 8) of size ``dx`` wide in y.

Measured surfaces
-----------------
:func:`read_surface` reads a measured height map (``.npy``, plain-text matrices, or any
instrument format SurfaceTopography reads). A measured map is not periodic: it is returned with
``periodic=False`` and solved in the non-periodic (zero-padded, linear convolution) mode by
default, i.e. as a finite patch of texture pressed by a flat. :func:`periodize` is the
documented alternative: it mirrors the map into a ``2 Lx x 2 Ly`` map that is exactly periodic
(and continuous across the cell edges), which can then be solved as a periodic unit cell; the
price is an artificial mirror symmetry and four times the pixels.
"""

from __future__ import annotations

import inspect
import math
import re
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import FingerpadError, ResolutionWarning
from .units import format_quantity, parse_positive, parse_quantity


@dataclass(frozen=True, eq=False)
class Texture:
    """A height map over a rectangle of known physical size.

    Attributes
    ----------
    heights
        2-D float array (nx, ny), metres, z positive toward the skin.
    size
        (Lx, Ly) physical size of the map, metres.
    periodic
        True for a unit cell of a periodic texture; False for a finite patch (measured map,
        single asperity), solved with zero-padded linear convolution.
    name
        Generator or file name.
    params
        Generator parameters in SI units (recorded as NetCDF attributes).
    """

    heights: np.ndarray
    size: tuple[float, float]
    periodic: bool = True
    name: str = "custom"
    params: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        h = np.asarray(self.heights, dtype=float)
        if h.ndim == 1:
            h = h[:, None]
        if h.ndim != 2:
            raise FingerpadError(f"texture {self.name!r}: height map must be 2-D, got shape {h.shape}")
        if h.size == 0:
            raise FingerpadError(f"texture {self.name!r}: empty height map")
        if not np.all(np.isfinite(h)):
            bad = int(np.count_nonzero(~np.isfinite(h)))
            raise FingerpadError(f"texture {self.name!r}: height map holds {bad} NaN or infinite values")
        lx, ly = (float(s) for s in self.size)
        if not (math.isfinite(lx) and math.isfinite(ly) and lx > 0 and ly > 0):
            raise FingerpadError(f"texture {self.name!r}: size must be positive, got {self.size!r}")
        object.__setattr__(self, "heights", h)
        object.__setattr__(self, "size", (lx, ly))

    @property
    def shape(self) -> tuple[int, int]:
        return self.heights.shape  # type: ignore[return-value]

    @property
    def spacing(self) -> tuple[float, float]:
        """Grid spacing (dx, dy), metres."""
        return self.size[0] / self.shape[0], self.size[1] / self.shape[1]

    @property
    def area(self) -> float:
        """Nominal (projected) area of the map, m^2."""
        return self.size[0] * self.size[1]

    @property
    def peak_to_valley(self) -> float:
        return float(self.heights.max() - self.heights.min())

    def coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """1-D pixel coordinates x (nx,) and y (ny,), metres."""
        dx, dy = self.spacing
        return np.arange(self.shape[0]) * dx, np.arange(self.shape[1]) * dy


# ------------------------------------------------------------------------------------------------
# Argument checking and resolution
# ------------------------------------------------------------------------------------------------

#: Grid sizes the default resolution picks from: ``2**k`` and ``3 * 2**k`` (fast FFT lengths).
_NICE_GRIDS = sorted({2**k for k in range(3, 12)} | {3 * 2**k for k in range(2, 10)})
#: Bounds of the automatically chosen ``grid``; a ``grid`` given by the user may go to MAX_GRID.
DEFAULT_MIN_GRID = 64
DEFAULT_MAX_GRID = 2048
MIN_GRID = 8
MAX_GRID = 8192
#: The default grid resolves the smallest feature with this many pixels ...
TARGET_PIXELS = 16
#: ... and a ResolutionWarning is issued below this many.
WARN_PIXELS = 8
#: Cells of 1-D textures (ridges, sinusoid) are this many pixels wide in y by default.
DEFAULT_NY_1D = 8
#: Relative slack allowed when checking that features touch but do not overlap.
_OVERLAP_RTOL = 1e-9


def _fmt(value: float) -> str:
    return format_quantity(value, "length", digits=4)


def _length(value: Any, name: str) -> float:
    """A strictly positive length in metres (number in SI, or a string such as ``"50um"``)."""
    if isinstance(value, np.number):
        value = value.item()
    return parse_positive(value, "length", name=name)


def _choice(value: Any, name: str, options: tuple[str, ...]) -> str:
    if isinstance(value, str) and value.strip().lower() in options:
        return value.strip().lower()
    raise FingerpadError(f"{name} must be one of {', '.join(map(repr, options))}, got {value!r}")


def _integer(value: Any, name: str, minimum: int, maximum: int | None = None) -> int:
    if isinstance(value, bool):
        raise FingerpadError(f"{name} must be an integer, got {value!r}")
    if isinstance(value, (int, np.integer)):
        n = int(value)
    elif isinstance(value, (float, np.floating)) and float(value).is_integer():
        n = int(value)
    elif isinstance(value, str) and re.fullmatch(r"\s*\d+\s*", value):
        n = int(value)
    else:
        raise FingerpadError(f"{name} must be an integer, got {value!r}")
    if n < minimum:
        raise FingerpadError(f"{name} must be at least {minimum}, got {n}")
    if maximum is not None and n > maximum:
        raise FingerpadError(f"{name} must be at most {maximum}, got {n}")
    return n


def _default_grid(cell: float, feature: float) -> int:
    """Smallest nice grid (>= 64, <= 2048) giving ``feature`` at least TARGET_PIXELS pixels."""
    need = math.ceil(TARGET_PIXELS * cell / feature * (1.0 - 1e-12))
    target = max(DEFAULT_MIN_GRID, need)
    for g in _NICE_GRIDS:
        if g >= target:
            return min(g, DEFAULT_MAX_GRID)
    return DEFAULT_MAX_GRID


def _check_resolution(feature: float, pixel: float, what: str) -> None:
    pixels = feature / pixel
    if pixels < WARN_PIXELS:
        warnings.warn(
            f"{what} ({_fmt(feature)}) spans only {pixels:.3g} pixels (fewer than {WARN_PIXELS}); "
            f"results will be inaccurate, use a larger grid",
            ResolutionWarning,
            stacklevel=_caller_stacklevel(),
        )


def _caller_stacklevel() -> int:
    """``stacklevel`` pointing warnings at the first caller outside this module."""
    import sys

    frame = sys._getframe(1)
    level = 1
    while frame is not None and frame.f_globals.get("__name__") == __name__:
        frame = frame.f_back
        level += 1
    return level


def _resolve_grid(grid: Any, cell: float, feature: float, what: str) -> int:
    """Number of (even) grid points along x for a cell of length ``cell``."""
    if grid is None:
        n = _default_grid(cell, feature)
    else:
        n = _integer(grid, "grid", MIN_GRID, MAX_GRID)
        if n % 2:
            raise FingerpadError(
                f"grid must be even so that feature centres and valleys lie on grid points, got {n}"
            )
    _check_resolution(feature, cell / n, what)
    return n


def _even(value: float) -> int:
    """Nearest even integer, at least 2."""
    return max(2, 2 * int(round(value / 2.0)))


def _even_smooth(value: float) -> int:
    """Nearest even integer with no prime factor above 7 (FFT-friendly), at least 2.

    A cell side such as round(96 sqrt 3) = 166 = 2 x 83 makes every FFT of the solver several
    times slower than a neighbouring 7-smooth size; the pixels become slightly non-square
    (by under 2 % from 64 points on), which the solver handles exactly.
    """

    def smooth(n: int) -> bool:
        for f in (2, 3, 5, 7):
            while n % f == 0:
                n //= f
        return n == 1

    base = _even(value)
    for delta in range(0, base + 2, 2):
        found = [c for c in (base - delta, base + delta) if c >= 2 and smooth(c)]
        if found:
            return min(found, key=lambda c: abs(c - value))
    return base


def _centred_field(
    profile: Callable[[np.ndarray, np.ndarray], np.ndarray], nx: int, ny: int, dx: float, dy: float
) -> np.ndarray:
    """One feature ``profile(x, y) >= 0`` centred on grid point (nx/2, ny/2) of a periodic cell.

    ``x`` and ``y`` are integer pixel offsets times the spacing, so offsets +-k give exactly
    opposite coordinates (bitwise mirror symmetry). The footprint must fit in the cell; the edge
    rows/columns (offset -n/2 == +n/2) take the larger of both periodic images.
    """
    kx = np.arange(-(nx // 2), nx // 2 + 1)
    ky = np.arange(-(ny // 2), ny // 2 + 1)
    f = np.broadcast_to(profile((kx * dx)[:, None], (ky * dy)[None, :]), (nx + 1, ny + 1))
    g = np.array(f[:-1, :-1], dtype=float)
    g[0, :] = np.maximum(g[0, :], f[-1, :-1])
    g[:, 0] = np.maximum(g[:, 0], f[:-1, -1])
    g[0, 0] = max(g[0, 0], f[-1, -1])
    return g


_LATTICES = ("square", "hexagonal")


def _lattice_cell(spacing: float, lattice: str, grid: Any, feature: float, what: str):
    """Cell size and grid of a square (one site) or hexagonal (two sites) lattice."""
    if lattice == "square":
        size = (spacing, spacing)
    else:
        size = (spacing, math.sqrt(3.0) * spacing)
    nx = _resolve_grid(grid, size[0], feature, what)
    ny = nx if lattice == "square" else _even_smooth(nx * math.sqrt(3.0))
    return size, nx, ny


def _place(field_: np.ndarray, lattice: str) -> np.ndarray:
    """Square: the centred feature alone. Hexagonal: plus its copy at the cell corner (0, 0)."""
    if lattice == "square":
        return field_
    nx, ny = field_.shape
    return np.maximum(field_, np.roll(field_, (nx // 2, ny // 2), axis=(0, 1)))


def _check_touching(extent: float, distance: float, message: str) -> None:
    if extent > distance * (1.0 + _OVERLAP_RTOL):
        raise FingerpadError(message)


# ------------------------------------------------------------------------------------------------
# Generators
# ------------------------------------------------------------------------------------------------


def _cap_profile(radius: float, height: float) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    def profile(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        r2 = x * x + y * y
        # h - (R - sqrt(R^2 - r^2)) without cancellation; exactly h at r = 0.
        z = height - r2 / (radius + np.sqrt(np.maximum(radius * radius - r2, 0.0)))
        return np.maximum(z, 0.0)

    return profile


def _caps_field(radius: Any, height: Any, spacing: Any, lattice: Any, grid: Any, kind: str, hname: str):
    r = _length(radius, "radius")
    h = _length(height, hname)
    s = _length(spacing, "spacing")
    lat = _choice(lattice, "lattice", _LATTICES)
    if h > r:
        raise FingerpadError(
            f"{kind} {hname} {_fmt(h)} exceeds the sphere radius {_fmt(r)}; a spherical {kind} "
            f"needs {hname} <= radius"
        )
    a = math.sqrt(h * (2.0 * r - h))
    _check_touching(
        2.0 * a,
        s,
        f"{kind}s overlap: base diameter 2a = {_fmt(2 * a)} (a = sqrt(2 R h - h^2)) exceeds the "
        f"nearest-neighbour distance {_fmt(s)} (spacing) of the {lat} lattice",
    )
    size, nx, ny = _lattice_cell(s, lat, grid, a, f"{kind} base radius")
    g = _centred_field(_cap_profile(r, h), nx, ny, size[0] / nx, size[1] / ny)
    return _place(g, lat), size, lat, nx


def spherical_caps(
    *, radius: Any, height: Any, spacing: Any, lattice: str = "square", grid: Any = None
) -> Texture:
    """Spherical-cap bumps on a flat base, one unit cell.

    Parameters
    ----------
    radius
        Sphere radius R, m.
    height
        Cap height h above the base, m, ``0 < h <= R``. The base radius is
        ``a = sqrt(2 R h - h^2)``.
    spacing
        Nearest-neighbour (centre-to-centre) distance of the caps, m; ``2 a <= spacing``.
    lattice
        ``"square"``: cell ``spacing x spacing`` with one cap at its centre ``(Lx/2, Ly/2)``.
        ``"hexagonal"``: exactly periodic rectangular cell ``Lx = spacing``,
        ``Ly = sqrt(3) spacing`` holding two caps, at ``(0, 0)`` and ``(Lx/2, Ly/2)``; every cap
        has six neighbours at ``spacing``. ``ny`` = round(nx sqrt(3)) moved to the nearest even
        7-smooth size (fast FFTs), so pixels are nearly square (``dy / dx`` within 2 % of 1
        from 64 points on).
    grid
        Grid points along x (even, >= 8). Default: base radius over at least 16 pixels
        (64 ... 2048).

    Returns
    -------
    Texture
        Periodic cell; heights (m) with the flat base at 0 and cap tops at ``h``.

    Raises
    ------
    FingerpadError
        Non-positive dimensions, ``h > R``, overlapping caps, odd or too small ``grid``.
    """
    heights, size, lat, nx = _caps_field(radius, height, spacing, lattice, grid, "cap", "height")
    params = {
        "radius": _length(radius, "radius"),
        "height": _length(height, "height"),
        "spacing": _length(spacing, "spacing"),
        "lattice": lat,
        "grid": nx,
    }
    return Texture(heights, size, periodic=True, name="caps", params=params)


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
    caps, size, lat, nx = _caps_field(radius, depth, spacing, lattice, grid, "dimple", "depth")
    d = _length(depth, "depth")
    params = {"radius": _length(radius, "radius"), "depth": d, "spacing": _length(spacing, "spacing"),
              "lattice": lat, "grid": nx}
    return Texture(d - caps, size, periodic=True, name="dimples", params=params)


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
    w = _length(width, "width")
    h = _length(height, "height")
    s = _length(spacing, "spacing")
    prof = _choice(profile, "profile", _RIDGE_PROFILES)
    nyy = _integer(ny, "ny", 1)
    _check_touching(w, s, f"ridge width {_fmt(w)} exceeds the ridge spacing {_fmt(s)}")
    params: dict[str, Any] = {"width": w, "height": h, "spacing": s, "profile": prof}
    if prof == "trapezoidal":
        if top_width is None:
            t = w / 2.0
        else:
            t = parse_quantity(top_width, "length", name="top_width")
            if not 0.0 <= t <= w * (1.0 + _OVERLAP_RTOL):
                raise FingerpadError(f"top_width must lie between 0 and the width {_fmt(w)}, got {_fmt(t)}")
            t = min(t, w)
        params["top_width"] = t
    elif top_width is not None:
        raise FingerpadError(f"top_width applies to the trapezoidal profile only, not {prof!r}")
    if prof == "circular" and h > w / 2.0 * (1.0 + _OVERLAP_RTOL):
        raise FingerpadError(
            f"a circular-arc ridge cannot be higher than half its width: height {_fmt(h)} > "
            f"width/2 = {_fmt(w / 2)}"
        )
    nx = _resolve_grid(grid, s, w, "ridge width")
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

    heights = _centred_field(shape, nx, nyy, dx, dx)
    params.update(grid=nx, ny=nyy)
    return Texture(heights, (s, nyy * dx), periodic=True, name="ridges", params=params)


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
    a = _length(semi_axis_x, "semi_axis_x")
    b = _length(semi_axis_y, "semi_axis_y")
    h = _length(height, "height")
    sx = _length(spacing_x, "spacing_x")
    sy = _length(spacing_y, "spacing_y")
    theta = parse_quantity(orientation, "angle", name="orientation")
    c, s = math.cos(theta), math.sin(theta)
    ex = math.hypot(a * c, b * s)
    ey = math.hypot(a * s, b * c)
    _check_touching(2 * ex, sx, f"ellipsoids overlap along x: footprint extent {_fmt(2 * ex)} exceeds spacing_x {_fmt(sx)}")
    _check_touching(2 * ey, sy, f"ellipsoids overlap along y: footprint extent {_fmt(2 * ey)} exceeds spacing_y {_fmt(sy)}")
    feature = min(a, b)
    nx = _resolve_grid(grid, sx, feature, "smaller ellipsoid semi-axis")
    ny = _even_smooth(nx * sy / sx)
    if sy / ny > sx / nx:  # coarser along y (rounding of ny): check that direction too
        _check_resolution(feature, sy / ny, "smaller ellipsoid semi-axis")

    def shape(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        xp = (x * c + y * s) / a
        yp = (y * c - x * s) / b
        return h * np.sqrt(np.maximum(1.0 - xp * xp - yp * yp, 0.0))

    heights = _centred_field(shape, nx, ny, sx / nx, sy / ny)
    params = {"semi_axis_x": a, "semi_axis_y": b, "height": h, "spacing_x": sx, "spacing_y": sy,
              "orientation": theta, "grid": nx}
    return Texture(heights, (sx, sy), periodic=True, name="ellipsoids", params=params)


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
    d = _length(diameter, "diameter")
    h = _length(height, "height")
    s = _length(spacing, "spacing")
    lat = _choice(lattice, "lattice", _LATTICES)
    _check_touching(d, s, f"pillars overlap: diameter {_fmt(d)} exceeds the nearest-neighbour distance {_fmt(s)} (spacing)")
    size, nx, ny = _lattice_cell(s, lat, grid, d, "pillar diameter")
    r2max = (d / 2.0) ** 2 * (1.0 + 1e-12)

    def shape(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.where(x * x + y * y <= r2max, h, 0.0)

    heights = _place(_centred_field(shape, nx, ny, size[0] / nx, size[1] / ny), lat)
    params = {"diameter": d, "height": h, "spacing": s, "lattice": lat, "grid": nx}
    return Texture(heights, size, periodic=True, name="pillars", params=params)


def _cosines(n: int) -> np.ndarray:
    """cos(2 pi i / n), i = 0..n-1, exactly symmetric under i -> n - i."""
    i = np.arange(n)
    return np.cos(2.0 * math.pi * np.minimum(i, n - i) / n)


def sinusoid(*, amplitude: Any, wavelength: Any, grid: Any = None, ny: Any = DEFAULT_NY_1D) -> Texture:
    """One-dimensional sinusoidal waviness ``z = h (1 + cos(2 pi x / lambda))``, one wavelength.

    Parameters
    ----------
    amplitude
        Amplitude h, m (peak-to-valley 2h; peaks at x = 0, valley at x = lambda/2, min 0).
    wavelength
        Wavelength lambda = cell length Lx, m.
    grid
        Grid points along x (even, >= 8); default 64 (a quarter wavelength over 16 pixels).
    ny
        Grid points along y (>= 1, default 8); ``Ly = ny * dx``, heights constant along y.

    Returns
    -------
    Texture
        Periodic cell.
    """
    h = _length(amplitude, "amplitude")
    lam = _length(wavelength, "wavelength")
    nyy = _integer(ny, "ny", 1)
    nx = _resolve_grid(grid, lam, lam / 4.0, "quarter wavelength")
    heights = np.repeat((h * (1.0 + _cosines(nx)))[:, None], nyy, axis=1)
    heights -= heights.min()
    params = {"amplitude": h, "wavelength": lam, "grid": nx, "ny": nyy}
    return Texture(heights, (lam, nyy * lam / nx), periodic=True, name="sinusoid", params=params)


def bisinusoid(*, amplitude: Any, wavelength: Any, form: str = "sum", grid: Any = None) -> Texture:
    """Two-dimensional sinusoidal waviness over one ``lambda x lambda`` cell.

    Parameters
    ----------
    amplitude
        Amplitude h, m.
    wavelength
        Wavelength lambda in x and y, m.
    form
        ``"sum"`` (default, the Johnson-Greenwood-Higginson surface):
        ``z = h [cos(2 pi x/lambda) + cos(2 pi y/lambda)] + 2h``, peak-to-valley 4h, one peak
        (at the corner) and one valley (at the centre) per cell.
        ``"product"`` (egg box): ``z = h cos(2 pi x/lambda) cos(2 pi y/lambda) + h``,
        peak-to-valley 2h, two peaks and two valleys per cell.
    grid
        Grid points along x and y (even, >= 8); default 64.

    Returns
    -------
    Texture
        Periodic cell with minimum 0.
    """
    h = _length(amplitude, "amplitude")
    lam = _length(wavelength, "wavelength")
    frm = _choice(form, "form", ("sum", "product"))
    n = _resolve_grid(grid, lam, lam / 4.0, "quarter wavelength")
    c = _cosines(n)
    if frm == "sum":
        heights = h * (c[:, None] + c[None, :]) + 2.0 * h
    else:
        heights = h * (c[:, None] * c[None, :]) + h
    heights -= heights.min()
    params = {"amplitude": h, "wavelength": lam, "form": frm, "grid": n}
    return Texture(heights, (lam, lam), periodic=True, name="bisinusoid", params=params)


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
    lx, ly = _parse_size(size)
    nx = _integer(grid, "grid", MIN_GRID, MAX_GRID)
    ny = max(1, int(round(nx * ly / lx)))
    return Texture(np.zeros((nx, ny)), (lx, ly), periodic=True, name="flat",
                   params={"size": (lx, ly), "grid": nx})


#: CLI names of the texture generators.
GENERATORS: dict[str, Callable[..., Texture]] = {
    "caps": spherical_caps,
    "dimples": dimples,
    "ridges": ridges,
    "ellipsoids": ellipsoids,
    "pillars": pillars,
    "sinusoid": sinusoid,
    "bisinusoid": bisinusoid,
    "flat": flat,
}


def _signature_text(func: Callable[..., Any]) -> str:
    parts = []
    for pname, par in inspect.signature(func).parameters.items():
        parts.append(pname if par.default is inspect.Parameter.empty else f"{pname}={par.default!r}")
    return ", ".join(parts)


def make_texture(name: str, **params: Any) -> Texture:
    """Build a texture by its CLI name (a key of :data:`GENERATORS`) from keyword parameters.

    Values may be SI numbers or strings with units (``"50um"``, ``"30deg"``).

    Raises
    ------
    FingerpadError
        Unknown texture name, unknown or missing parameters (the message lists the valid ones),
        or any error of the generator itself.
    """
    gen = GENERATORS.get(str(name).strip().lower()) if isinstance(name, str) else None
    if gen is None:
        raise FingerpadError(f"unknown texture {name!r}; choose one of: {', '.join(GENERATORS)}")
    sig = inspect.signature(gen).parameters
    unknown = [p for p in params if p not in sig]
    if unknown:
        raise FingerpadError(
            f"texture {name!r}: unknown parameter(s) {', '.join(unknown)}; valid: {_signature_text(gen)}"
        )
    missing = [p for p, par in sig.items() if par.default is inspect.Parameter.empty and p not in params]
    if missing:
        raise FingerpadError(
            f"texture {name!r}: missing parameter(s) {', '.join(missing)}; valid: {_signature_text(gen)}"
        )
    return gen(**params)


# ------------------------------------------------------------------------------------------------
# Measured surfaces
# ------------------------------------------------------------------------------------------------

_TEXT_EXTENSIONS = (".txt", ".csv", ".dat", ".asc")
#: Height units accepted for ``height_unit`` (factor to metres).
HEIGHT_UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "nm": 1e-9}
#: Length units found in instrument files (SurfaceTopography ``.unit``), factor to metres.
_FILE_UNITS = {
    "km": 1e3, "m": 1.0, "dm": 0.1, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6,
    "nm": 1e-9, "Å": 1e-10, "A": 1e-10, "pm": 1e-12,
}


def _parse_size(size: Any, name: str = "size") -> tuple[float, float]:
    """``(Lx, Ly)`` in metres from a number (square), a pair, or a string ``"Lx,Ly"``."""
    if size is None:
        raise FingerpadError(f"{name} is required: give (Lx, Ly) in metres or one number for a square")
    if isinstance(size, str):
        parts: list[Any] = [p for p in re.split(r"[,;\s]+", size.strip()) if p]
    elif isinstance(size, (int, float, np.number)):
        parts = [size]
    else:
        try:
            parts = list(size)
        except TypeError:
            raise FingerpadError(f"{name} must be a number or a pair (Lx, Ly), got {size!r}") from None
    if len(parts) == 1:
        parts = parts * 2
    if len(parts) != 2:
        raise FingerpadError(f"{name} must be a number or a pair (Lx, Ly), got {size!r}")
    return _length(parts[0], name), _length(parts[1], name)


def _height_factor(unit: Any) -> float:
    if isinstance(unit, bool):
        raise FingerpadError(f"height_unit must be one of m, mm, um, nm or a factor to metres, got {unit!r}")
    if isinstance(unit, str) and unit.strip() in HEIGHT_UNITS:
        return HEIGHT_UNITS[unit.strip()]
    try:
        factor = float(unit)
    except (TypeError, ValueError):
        raise FingerpadError(
            f"height_unit must be one of m, mm, um, nm or a factor to metres, got {unit!r}"
        ) from None
    if not (math.isfinite(factor) and factor > 0):
        raise FingerpadError(f"height_unit factor must be a positive number, got {unit!r}")
    return factor


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _load_npy(path: Path) -> np.ndarray:
    try:
        data = np.load(path, allow_pickle=False)
    except Exception as exc:
        raise FingerpadError(f"cannot read {path}: not a valid .npy file ({_one_line(exc)})") from None
    if not isinstance(data, np.ndarray):
        raise FingerpadError(f"cannot read {path}: expected a single array")
    return data


def _load_text(path: Path) -> np.ndarray:
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise FingerpadError(f"cannot read {path}: {_one_line(exc)}") from None
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


def _check_map(data: np.ndarray, path: Path) -> np.ndarray:
    if data.dtype.kind not in "iuf":
        raise FingerpadError(f"{path}: heights must be real numbers, got array of type {data.dtype}")
    if data.ndim == 1 or (data.ndim == 2 and min(data.shape) == 1):
        raise FingerpadError(
            f"{path}: holds a line scan of {data.size} points; a 2-D height map is needed"
        )
    if data.ndim != 2:
        raise FingerpadError(f"{path}: expected a 2-D height map, got an array of shape {data.shape}")
    if min(data.shape) < 2:
        raise FingerpadError(f"{path}: height map of shape {data.shape} is too small")
    return np.asarray(data, dtype=float)


def _load_instrument(path: Path, size: tuple[float, float] | None, factor: float | None):
    """Heights (file units, NaN where undefined), lateral size (m) and height factor to m."""
    try:
        from SurfaceTopography import open_topography
    except ImportError as exc:  # pragma: no cover - dependency is declared
        raise FingerpadError(f"reading {path.suffix} files needs SurfaceTopography ({_one_line(exc)})") from None
    try:
        with open_topography(str(path)) as reader:
            channel = reader.default_channel
            if channel.dim is not None and channel.dim != 2:
                raise FingerpadError(f"{path}: holds a line scan; a 2-D height map is needed")
            kwargs: dict[str, Any] = {}
            if channel.physical_sizes is None:
                if size is None:
                    raise FingerpadError(
                        f"{path}: the file gives no physical size; pass size=(Lx, Ly) in metres"
                    )
                kwargs["physical_sizes"] = size  # metres; replaced below anyway
            topo = reader.topography(**kwargs)
    except FingerpadError:
        raise
    except Exception as exc:
        if type(exc).__name__ in ("CannotDetectFileFormat", "UnknownFileFormat"):
            reason = "file format not recognised (neither by fingerpad nor by SurfaceTopography)"
        else:
            reason = _one_line(exc)
            if len(reason) > 300:
                reason = reason[:300] + " ..."
        raise FingerpadError(f"cannot read surface file {path}: {reason}") from None
    if topo.dim != 2:
        raise FingerpadError(f"{path}: holds a line scan; a 2-D height map is needed")
    raw = topo.heights()
    mask = np.ma.getmaskarray(raw)
    heights = np.array(np.ma.getdata(raw), dtype=float)
    heights[mask] = np.nan
    unit = topo.unit
    unit_factor = None
    if unit is not None:
        unit_factor = _FILE_UNITS.get(str(unit).strip())
        if unit_factor is None and factor is None:
            raise FingerpadError(f"{path}: unknown length unit {unit!r} in the file; pass height_unit")
    if factor is None:
        if unit_factor is None:
            raise FingerpadError(f"{path}: the file gives no height unit; pass height_unit")
        factor = unit_factor
    if size is None:
        lateral = unit_factor if unit_factor is not None else factor
        lx, ly = (float(s) * lateral for s in topo.physical_sizes)
        size = (lx, ly)
    return heights, size, factor


def read_surface(
    path: str | Path,
    size: Any = None,
    height_unit: Any = None,
    periodic: bool = False,
    level: bool = True,
    fill_missing: bool = False,
) -> Texture:
    """Read a measured height map.

    Parameters
    ----------
    path
        ``.npy`` (2-D array, axis 0 along x: ``np.save(path, texture.heights)`` round-trips),
        plain-text matrix ``.txt``, ``.csv``, ``.dat``, ``.asc`` (whitespace, comma or semicolon
        separated; lines starting with ``#`` or ``%`` are comments; stored image-like, i.e. each
        row is a profile along x at one y, as written by ``np.savetxt(path, heights.T)``, by
        SurfaceTopography and by most instrument exports; empty fields and ``nan`` are missing
        points), or any instrument format SurfaceTopography reads (``.sur``, ``.x3p``, ``.plu``,
        ``.datx``, ``.opd``, ``.di``, ``.gwy``, ``.nc``, ...).
    size
        Physical size ``(Lx, Ly)`` in metres, or one number for a square. Required for ``.npy``
        and text files and for instrument files that carry no size; for other instrument files
        it overrides the size in the file.
    height_unit
        Unit of the stored heights: ``"m"``, ``"mm"``, ``"um"``, ``"nm"`` or a float factor to
        metres. Required for ``.npy`` and text files; for instrument files it overrides the
        file's unit (the heights as stored are multiplied by it) and is required only if the file
        gives none.
    periodic
        Whether the map is one period of a periodic surface (default False: a finite patch,
        solved with zero padding; see also :func:`periodize`).
    level
        Remove the least-squares plane (:func:`level_plane`) before use (default True).
    fill_missing
        Missing points (NaN, or masked in an instrument file) raise an error by default; with
        True each is replaced by the height of the nearest valid point (and the number filled
        is recorded in ``params["filled_points"]``).

    Returns
    -------
    Texture
        Heights in metres shifted so that the minimum is 0 (with or without levelling), named
        after the file stem.

    Raises
    ------
    FingerpadError
        Missing or unreadable file, missing ``size`` or ``height_unit``, a line scan instead of a
        map, missing data points without ``fill_missing``.
    """
    p = Path(path)
    if not p.exists():
        raise FingerpadError(f"surface file not found: {p}")
    if not p.is_file():
        raise FingerpadError(f"not a file: {p}")
    ext = p.suffix.lower()
    lsize = _parse_size(size) if size is not None else None
    factor = _height_factor(height_unit) if height_unit is not None else None
    if ext == ".npy" or ext in _TEXT_EXTENSIONS:
        if lsize is None:
            raise FingerpadError(
                f"{p.name}: {ext} files carry no physical size; pass size=(Lx, Ly) in metres"
            )
        if factor is None:
            raise FingerpadError(
                f"{p.name}: {ext} files carry no height unit; pass height_unit (m, mm, um, nm or a factor)"
            )
        raw = _check_map(_load_npy(p) if ext == ".npy" else _load_text(p), p)
    else:
        raw, lsize, factor = _load_instrument(p, lsize, factor)
        raw = _check_map(raw, p)
    heights = raw * factor
    missing = ~np.isfinite(heights)
    n_missing = int(np.count_nonzero(missing))
    if n_missing:
        if n_missing == heights.size:
            raise FingerpadError(f"{p}: all {heights.size} height values are missing")
        if not fill_missing:
            raise FingerpadError(
                f"{p}: {n_missing} of {heights.size} height values are missing (NaN or masked); "
                f"clean the map or pass fill_missing=True to use the nearest valid height"
            )
        from scipy import ndimage

        index = ndimage.distance_transform_edt(missing, return_distances=False, return_indices=True)
        heights = heights[tuple(index)]
    if level:
        heights = level_plane(heights, lsize)
    heights = heights - heights.min()
    params: dict[str, Any] = {
        "path": str(p),
        "size": lsize,
        "height_factor": float(factor),
        "level": int(bool(level)),
        "filled_points": n_missing,
    }
    return Texture(heights, lsize, periodic=bool(periodic), name=p.stem, params=params)


def level_plane(heights: np.ndarray, size: Any) -> np.ndarray:
    """Subtract the least-squares plane ``c0 + c1 x + c2 y`` from a height map.

    Parameters
    ----------
    heights
        2-D array (nx, ny), m, sampled at ``x = i Lx/nx``, ``y = j Ly/ny``.
    size
        ``(Lx, Ly)`` in metres (a number for a square).

    Returns
    -------
    numpy.ndarray
        The residual heights (same shape; mean 0, no tilt).
    """
    h = np.asarray(heights, dtype=float)
    if h.ndim != 2:
        raise FingerpadError(f"level_plane: expected a 2-D height map, got shape {h.shape}")
    if not np.all(np.isfinite(h)):
        raise FingerpadError("level_plane: the height map holds NaN or infinite values")
    lx, ly = _parse_size(size)
    nx, ny = h.shape
    # Centred coordinates make the three basis functions orthogonal on the regular grid.
    x = ((np.arange(nx) - (nx - 1) / 2.0) * (lx / nx))[:, None]
    y = ((np.arange(ny) - (ny - 1) / 2.0) * (ly / ny))[None, :]
    out = h - h.mean()
    sxx = float(np.sum(x * x)) * ny
    syy = float(np.sum(y * y)) * nx
    if sxx > 0:
        out = out - x * (float(np.sum(out * x)) / sxx)
    if syy > 0:
        out = out - y * (float(np.sum(out * y)) / syy)
    return out


def periodize(texture: Texture) -> Texture:
    """Mirror a (measured, non-periodic) map into an exactly periodic ``2 Lx x 2 Ly`` cell.

    The map is reflected across its right and top edges (even extension), so the result is
    continuous across every cell edge and exactly periodic; it can then be solved as a periodic
    unit cell. The mirror images are artificial (each feature appears four times), and the
    pixel count is four times larger. The default for measured maps is instead the non-periodic,
    zero-padded solution of the map as it is.

    Returns
    -------
    Texture
        Periodic, size ``(2 Lx, 2 Ly)``, shape ``(2 nx, 2 ny)``, name ``"<name>-periodized"``.
    """
    h = texture.heights
    hx = np.concatenate([h, h[::-1, :]], axis=0)
    hh = np.concatenate([hx, hx[:, ::-1]], axis=1)
    params = dict(texture.params)
    params["periodized"] = 1
    lx, ly = texture.size
    return Texture(hh, (2.0 * lx, 2.0 * ly), periodic=True, name=f"{texture.name}-periodized", params=params)


# ------------------------------------------------------------------------------------------------
# Helpers
# ------------------------------------------------------------------------------------------------


def base_mask(texture: Texture, rel_tol: float = 1e-6) -> np.ndarray:
    """Boolean (nx, ny) mask of the pixels at the lowest level of the texture.

    A pixel belongs to the base when ``height <= min + rel_tol * peak_to_valley`` (all pixels for
    a flat texture). For bumps, pillars and ridges this is the flat base between features; for
    dimples it is the dimple bottoms.
    """
    h = texture.heights
    lowest = float(h.min())
    return h <= lowest + float(rel_tol) * texture.peak_to_valley


_LENGTH_KEYS = {
    "radius", "height", "depth", "spacing", "width", "top_width", "semi_axis_x", "semi_axis_y",
    "spacing_x", "spacing_y", "diameter", "amplitude", "wavelength",
}
_HIDDEN_KEYS = {"grid", "ny", "size", "height_factor", "filled_points"}


def describe(texture: Texture) -> str:
    """One-line human description, e.g. ``caps (radius=50 um, ...): periodic cell 100 um x ...``."""
    parts = []
    for key, value in texture.params.items():
        if key in _HIDDEN_KEYS:
            continue
        if key in _LENGTH_KEYS and isinstance(value, (int, float)):
            parts.append(f"{key}={_fmt(float(value))}")
        elif key == "orientation" and isinstance(value, (int, float)):
            parts.append(f"orientation={math.degrees(value):.4g} deg")
        elif key == "level":
            parts.append("levelled" if value else "not levelled")
        elif key == "path":
            parts.append(f"from {value}")
        else:
            parts.append(f"{key}={value}")
    if texture.params.get("filled_points"):
        parts.append(f"{texture.params['filled_points']} missing points filled")
    lx, ly = texture.size
    nx, ny = texture.shape
    kind = "periodic cell" if texture.periodic else "finite patch"
    head = f"{texture.name} ({', '.join(parts)})" if parts else texture.name
    return (
        f"{head}: {kind} {_fmt(lx)} x {_fmt(ly)}, {nx} x {ny} px, "
        f"peak-to-valley {_fmt(texture.peak_to_valley)}"
    )
