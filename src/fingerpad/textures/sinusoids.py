"""Sinusoidal waviness: one-dimensional (Westergaard) and two-dimensional (Johnson-Greenwood-Higginson).
"""

from __future__ import annotations

import math
from typing import Any

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from .base import Param, Texture, TextureFamily
from .geometry import (
    DEFAULT_NY_1D,
    check_choice,
    check_integer,
    check_length,
    resolve_grid,
)


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
    h = check_length(amplitude, "amplitude")
    lam = check_length(wavelength, "wavelength")
    nyy = check_integer(ny, "ny", 1)
    nx = resolve_grid(grid, lam, lam / 4.0, "quarter wavelength")
    heights = np.repeat((h * (1.0 + _cosines(nx)))[:, None], nyy, axis=1)
    heights -= heights.min()
    params = {"amplitude": h, "wavelength": lam, "grid": nx, "ny": nyy}
    return Texture(heights, (lam, nyy * lam / nx), periodic=True, name="sinusoid", params=params, family="sinusoid")


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
    h = check_length(amplitude, "amplitude")
    lam = check_length(wavelength, "wavelength")
    frm = check_choice(form, "form", ("sum", "product"))
    n = resolve_grid(grid, lam, lam / 4.0, "quarter wavelength")
    c = _cosines(n)
    if frm == "sum":
        heights = h * (c[:, None] + c[None, :]) + 2.0 * h
    else:
        heights = h * (c[:, None] * c[None, :]) + h
    heights -= heights.min()
    params = {"amplitude": h, "wavelength": lam, "form": frm, "grid": n}
    return Texture(heights, (lam, lam), periodic=True, name="bisinusoid", params=params, family="bisinusoid")


FAMILIES = (
    TextureFamily(
        name="sinusoid",
        features=lambda t: (t.params["wavelength"] / 2, 2 * t.params["amplitude"]),
        generator=sinusoid,
        params=(
            Param("amplitude", "length", "amplitude h (peak-to-valley 2h)", example="10um"),
            Param("wavelength", "length", "wavelength lambda (the cell length)", example="150um"),
            Param("grid", "grid", "grid points along x (even; default 64)", None),
            Param("ny", "count", "grid points along y (the map is constant along y)", DEFAULT_NY_1D),
        ),
        summary="One-dimensional sinusoidal waviness, one wavelength.",
    ),
    TextureFamily(
        name="bisinusoid",
        features=lambda t: (t.params["wavelength"] / 2, 4 * t.params["amplitude"]),
        generator=bisinusoid,
        params=(
            Param("amplitude", "length", "amplitude h", example="10um"),
            Param("wavelength", "length", "wavelength lambda in x and y", example="150um"),
            Param("form", "choice", "sum: the Johnson-Greenwood-Higginson surface; product: egg box", "sum",
                  ("sum", "product")),
            Param("grid", "grid", "grid points along x and y (even; default 64)", None),
        ),
        summary="Two-dimensional sinusoidal waviness over one wavelength square.",
    ),
)
