"""Shared geometry of the generated unit cells: argument checks, grid resolution, lattices.

The conventions of every generator (see :mod:`fingerpad.textures`): ``heights[i, j]`` at
``x = i dx``, ``y = j dy``; feature centres on grid points; the default grid resolves the
smallest feature with :data:`TARGET_PIXELS` pixels; a :class:`~fingerpad.errors.ResolutionWarning`
below :data:`WARN_PIXELS`.
"""

from __future__ import annotations

import math
import re
import sys
import warnings
from collections.abc import Callable
from typing import Any

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from ..errors import FingerpadError, ResolutionWarning
from ..units import format_quantity, parse_positive

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
OVERLAP_RTOL = 1e-9


def fmt_length(value: float) -> str:
    return format_quantity(value, "length", digits=4)


def check_length(value: Any, name: str) -> float:
    """A strictly positive length in metres (number in SI, or a string such as ``"50um"``)."""
    if isinstance(value, np.number):
        value = value.item()
    return parse_positive(value, "length", name=name)


def check_choice(value: Any, name: str, options: tuple[str, ...]) -> str:
    if isinstance(value, str) and value.strip().lower() in options:
        return value.strip().lower()
    raise FingerpadError(f"{name} must be one of {', '.join(map(repr, options))}, got {value!r}")


def check_integer(value: Any, name: str, minimum: int, maximum: int | None = None) -> int:
    from ..units import parse_int

    if not isinstance(value, (int, float, str, np.integer, np.floating)):
        raise FingerpadError(f"{name}: expected an integer, got {value!r}")
    return parse_int(value, name, minimum, maximum)


def _default_grid(cell: float, feature: float) -> int:
    """Smallest nice grid (>= 64, <= 2048) giving ``feature`` at least TARGET_PIXELS pixels."""
    need = math.ceil(TARGET_PIXELS * cell / feature * (1.0 - 1e-12))
    target = max(DEFAULT_MIN_GRID, need)
    for g in _NICE_GRIDS:
        if g >= target:
            return min(g, DEFAULT_MAX_GRID)
    return DEFAULT_MAX_GRID


def check_resolution(feature: float, pixel: float, what: str) -> None:
    pixels = feature / pixel
    if pixels < WARN_PIXELS:
        warnings.warn(
            f"{what} ({fmt_length(feature)}) spans only {pixels:.3g} pixels (fewer than {WARN_PIXELS}); "
            f"results will be inaccurate, use a larger grid",
            ResolutionWarning,
            stacklevel=_caller_stacklevel(),
        )


def _caller_stacklevel() -> int:
    """``stacklevel`` pointing warnings at the first caller outside the textures package."""
    frame = sys._getframe(1)
    level = 1
    while frame is not None and str(frame.f_globals.get("__name__", "")).startswith("fingerpad.textures"):
        frame = frame.f_back
        level += 1
    return level


def resolve_grid(grid: Any, cell: float, feature: float, what: str) -> int:
    """Number of (even) grid points along x for a cell of length ``cell``."""
    if grid is None:
        n = _default_grid(cell, feature)
    else:
        n = check_integer(grid, "grid", MIN_GRID, MAX_GRID)
        if n % 2:
            raise FingerpadError(
                f"grid must be even so that feature centres and valleys lie on grid points, got {n}"
            )
    check_resolution(feature, cell / n, what)
    return n


def _even(value: float) -> int:
    """Nearest even integer, at least 2."""
    return max(2, 2 * int(round(value / 2.0)))


def even_smooth(value: float) -> int:
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


def centred_field(
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


LATTICES = ("square", "hexagonal")


def lattice_cell(spacing: float, lattice: str, grid: Any, feature: float, what: str):
    """Cell size and grid of a square (one site) or hexagonal (two sites) lattice."""
    if lattice == "square":
        size = (spacing, spacing)
    else:
        size = (spacing, math.sqrt(3.0) * spacing)
    nx = resolve_grid(grid, size[0], feature, what)
    ny = nx if lattice == "square" else even_smooth(nx * math.sqrt(3.0))
    return size, nx, ny


def place_on_lattice(field_: np.ndarray, lattice: str) -> np.ndarray:
    """Square: the centred feature alone. Hexagonal: plus its copy at the cell corner (0, 0)."""
    if lattice == "square":
        return field_
    nx, ny = field_.shape
    return np.maximum(field_, np.roll(field_, (nx // 2, ny // 2), axis=(0, 1)))


def check_touching(extent: float, distance: float, message: str) -> None:
    if extent > distance * (1.0 + OVERLAP_RTOL):
        raise FingerpadError(message)



def parse_size(size: Any, name: str = "size") -> tuple[float, float]:
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
    return check_length(parts[0], name), check_length(parts[1], name)

