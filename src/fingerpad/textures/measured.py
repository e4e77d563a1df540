"""Measured height maps: reading, plane levelling, periodizing.

A measured map is not periodic: :func:`read_surface` returns it with ``periodic=False`` and it is
solved in the non-periodic (zero-padded, linear convolution) mode by default, i.e. as a finite
patch of texture pressed by a flat. :func:`periodize` is the documented alternative: it mirrors
the map into a ``2 Lx x 2 Ly`` map that is exactly periodic (and continuous across the cell
edges), which can then be solved as a periodic unit cell; the price is an artificial mirror
symmetry and four times the pixels. The file formats are in :mod:`fingerpad.textures.readers`.
"""

from __future__ import annotations

import math
import os
import pickle
from pathlib import Path
from typing import Any

import lazy_loader

# NumPy loads on first use: listing the texture families (`fingerpad textures`) must start fast.
np = lazy_loader.load("numpy")

from ..errors import FingerpadError, describe_exception, one_line
from ..units import UNITS
from .base import Texture
from .geometry import parse_size
from .readers import reader_for

#: Default share of the pixels taken as the bottom of a measured map's base (see :func:`base_level_of`).
DEFAULT_BASE_QUANTILE = 0.01
#: The base level lies this many noise standard deviations above that bottom.
BASE_NOISE_BAND = 4.0
#: A given size may make pixels non-square by this much before it is taken for a mistake.
ASPECT_RTOL = 0.02
#: Height units accepted for ``height_unit`` (factor to metres).
HEIGHT_UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "nm": 1e-9}


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


def read_surface(
    path: str | Path,
    size: Any = None,
    height_unit: Any = None,
    periodic: bool = False,
    level: bool = True,
    fill_missing: bool = False,
    *,
    pixel_size: Any = None,
    base_quantile: float = DEFAULT_BASE_QUANTILE,
) -> Texture:
    """Read a measured height map.

    Axis convention: ``heights[i, j]`` is at ``x = i dx``, ``y = j dy`` (axis 0 along x). A
    ``.npy`` file holds that array itself; a text matrix holds it image-like, one line per y
    (the layout of instrument exports and of SurfaceTopography). A size whose aspect ratio
    contradicts square pixels by more than :data:`ASPECT_RTOL` is refused, because it usually
    means the map is read the other way round; give ``pixel_size`` for truly non-square pixels.

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
        and text files (unless ``pixel_size`` is given) and for instrument files that carry no
        size; for other instrument files it overrides the size in the file.
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
    pixel_size
        ``(dx, dy)`` in metres (or one number for square pixels), instead of ``size``.
    base_quantile
        Share of the pixels taken as the bottom of the base (default 0.01); the base level, whose
        touching starts the *transition* state, lies :data:`BASE_NOISE_BAND` noise standard
        deviations above it (:func:`base_level_of`).

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
    if size is not None and pixel_size is not None:
        raise FingerpadError("give the map's size or its pixel size, not both")
    lsize = parse_size(size) if size is not None else None
    pixel = parse_size(pixel_size, "pixel_size") if pixel_size is not None else None
    factor = _height_factor(height_unit) if height_unit is not None else None
    if not (isinstance(base_quantile, (int, float)) and 0.0 <= base_quantile < 1.0):
        raise FingerpadError(f"base_quantile must lie in [0, 1), got {base_quantile!r}")
    reader = reader_for(p)
    if reader.bare:
        if lsize is None and pixel is None:
            raise FingerpadError(
                f"{p.name}: {ext} files carry no physical size; pass size=(Lx, Ly) in metres"
            )
        if factor is None:
            raise FingerpadError(
                f"{p.name}: {ext} files carry no height unit; pass height_unit (m, mm, um, nm or a factor)"
            )
    raw, lsize, factor = reader.load(p, lsize or (1.0, 1.0) if reader.bare else lsize, factor)
    raw = _check_map(raw, p)
    if pixel is not None:
        lsize = (pixel[0] * raw.shape[0], pixel[1] * raw.shape[1])
    elif size is not None:
        _check_aspect(lsize, raw.shape, p)
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
    base_level = base_level_of(heights, base_quantile)
    params: dict[str, Any] = {
        "path": str(p),
        "size": lsize,
        "height_factor": float(factor),
        "level": int(bool(level)),
        "filled_points": n_missing,
        "base_quantile": float(base_quantile),
    }
    return Texture(heights, lsize, periodic=bool(periodic), name=p.stem, params=params, base_level=base_level)


def noise_level(heights: np.ndarray) -> float:
    """Robust standard deviation (m) of the pixel noise of a height map.

    From the differences of neighbouring pixels along both axes: for white noise of standard
    deviation sigma they have sigma sqrt(2); a smooth texture adds only its slope times the pixel
    size, which the median (times 1.4826, the normal consistency factor) mostly ignores.
    """
    h = np.asarray(heights, float)
    diffs = [np.abs(np.diff(h, axis=a)).ravel() for a in (0, 1) if h.shape[a] > 1]
    if not diffs:
        return 0.0
    return float(1.4826 * np.median(np.concatenate(diffs)) / math.sqrt(2.0))


def base_level_of(heights: np.ndarray, quantile: float = DEFAULT_BASE_QUANTILE,
                  band: float = BASE_NOISE_BAND) -> float:
    """The base level (m) of a measured map: the skin touching a pixel at or below it starts the
    *transition* state.

    ``quantile(heights, quantile) + band * noise_level(heights)``: the bottom of the base (its
    lowest ``quantile`` share) lifted by a band of the pixel noise. On a noisy base the single
    lowest pixel is a noise pit that the skin reaches only by flattening the noise, long after
    it has reached the base; the band makes "the base" the base plane with its noise. A map
    without noise gets exactly its lowest level.
    """
    h = np.asarray(heights, float)
    floor = float(np.quantile(h, quantile))
    return floor + band * noise_level(h)


def _check_aspect(size: tuple[float, float], shape: tuple[int, ...], path: Path) -> None:
    """Refuse a size whose aspect contradicts square pixels (a map read the other way round)."""
    dx, dy = size[0] / shape[0], size[1] / shape[1]
    if abs(dx / dy - 1.0) > ASPECT_RTOL:
        raise FingerpadError(
            f"{path.name}: the map has {shape[0]} x {shape[1]} px (x by y), aspect {shape[0] / shape[1]:.4g} with "
            f"square pixels, but the size {size[0] * 1e6:.4g} um x {size[1] * 1e6:.4g} um has aspect "
            f"{size[0] / size[1]:.4g} (pixels of {dx * 1e6:.4g} um x {dy * 1e6:.4g} um): check the size and the "
            f"orientation (a .npy array has x along axis 0, a text matrix one line per y), "
            f"otherwise give the pixel size instead"
        )


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
    lx, ly = parse_size(size)
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

    Raises
    ------
    FingerpadError
        ``texture`` is not a :class:`Texture`.
    """
    if not isinstance(texture, Texture):
        raise FingerpadError(f"periodize takes a fingerpad Texture (a height map read or generated), got "
                             f"{type(texture).__name__}")
    h = texture.heights
    hx = np.concatenate([h, h[::-1, :]], axis=0)
    hh = np.concatenate([hx, hx[:, ::-1]], axis=1)
    params = dict(texture.params)
    params["periodized"] = 1
    lx, ly = texture.size
    return Texture(hh, (2.0 * lx, 2.0 * ly), periodic=True, name=f"{texture.name}-periodized", params=params,
                   base_level=texture.base_level)


def read_surface_option(
    path: str, size: tuple[float, float] | None, height_unit: str | None, periodic: bool,
    fill_missing: bool = False, pixel_size: tuple[float, float] | None = None,
    base_quantile: float = DEFAULT_BASE_QUANTILE,
) -> Texture:
    """:func:`read_surface` for user input: the file checked first, errors naming the
    command-line options (``--size``, ``--height-unit``, ``--fill-missing``)."""
    p = Path(path)
    if not p.exists():
        raise FingerpadError(f"cannot read surface {path!r}: no such file")
    if p.is_dir():
        raise FingerpadError(f"cannot read surface {path!r}: it is a directory")
    if not os.access(p, os.R_OK):
        raise FingerpadError(f"cannot read surface {path!r}: permission denied")
    if reader_for(p).bare:
        missing = [opt for opt, v in (("--size", size if pixel_size is None else pixel_size),
                                      ("--height-unit", height_unit)) if v is None]
        if missing:
            raise FingerpadError(
                f"surface {p.name!r} stores bare numbers: give {' and '.join(missing)} "
                "(e.g. --size 200um,200um --height-unit um)"
            )
    factor: float | None = None
    if height_unit is not None:
        unit = height_unit.strip()
        if unit not in UNITS or UNITS[unit][0] != "length":
            known = ", ".join(k for k, v in UNITS.items() if v[0] == "length")
            raise FingerpadError(f"--height-unit: unknown length unit {height_unit!r} (use one of: {known})")
        factor = UNITS[unit][1]
    try:
        return read_surface(p, size=size, height_unit=factor, periodic=periodic, level=True,
                            fill_missing=fill_missing, pixel_size=pixel_size, base_quantile=base_quantile)
    except FingerpadError as exc:
        # Name the command-line option rather than the Python keyword.
        text = str(exc).replace("pass fill_missing=True", "give --fill-missing")
        text = text.replace("pass size=(Lx, Ly) in metres", "give --size LX[,LY]")
        text = text.replace("pass height_unit", "give --height-unit")
        text = text.replace("otherwise give the pixel size instead", "otherwise give --pixel-size DX[,DY] instead")
        text = text.replace("give the map's size or its pixel size, not both", "give --size or --pixel-size, not both")
        if text != str(exc):
            raise FingerpadError(text) from None
        raise
    except (OSError, ValueError, EOFError, pickle.UnpicklingError) as exc:
        raise FingerpadError(f"cannot read surface {path!r}: {one_line(describe_exception(exc))}") from None
    except Exception as exc:
        # SurfaceTopography's readers raise their own exception types on a bad file.
        if type(exc).__module__.split(".")[0] == "SurfaceTopography":
            raise FingerpadError(f"cannot read surface {path!r}: {one_line(str(exc))}") from None
        raise
