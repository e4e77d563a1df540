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

Families
--------
Each generator lives in its own file of this package with its declared parameters
(:class:`TextureFamily`, :class:`Param`); :data:`GENERATORS` maps names to generator functions
and :func:`get_family` gives the declaration. A new texture is added by adding one file that
defines ``FAMILIES``.

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
from collections.abc import Callable
from typing import Any

from ..errors import FingerpadError
from .base import (
    KINDS,
    REQUIRED,
    HertzAsperity,
    Param,
    Texture,
    TextureFamily,
    base_mask,
    describe,
    get_family,
    parse_angle,
    register,
    registry,
)
from .geometry import DEFAULT_NY_1D, MAX_GRID, MIN_GRID, parse_size
from .measured import HEIGHT_UNITS, level_plane, periodize, read_surface

# Files of this package that are not texture families.
_NOT_FAMILIES = {"base", "geometry", "measured", "readers"}


def _collect() -> None:
    from ..discover import collect

    for family in collect(__name__, __path__, "FAMILIES", TextureFamily, skip=_NOT_FAMILIES):
        register(family)
        globals()[family.generator.__name__] = family.generator


_collect()

#: CLI names of the texture generators -> generator functions.
GENERATORS: dict[str, Callable[..., Texture]] = {name: fam.generator for name, fam in registry().items()}


def _signature_text(func: Callable[..., Any]) -> str:
    parts = []
    for pname, par in inspect.signature(func).parameters.items():
        parts.append(pname if par.default is inspect.Parameter.empty else f"{pname}={par.default!r}")
    return ", ".join(parts)


def make_texture(name: str, **params: Any) -> Texture:
    """Build a texture by its CLI name (a key of :data:`GENERATORS`) from keyword parameters.

    Values may be SI numbers or strings with units (``"50um"``, ``"30deg"``); this is the Python
    API, so a bare angle is in radians (SI). User input (command line, study files) goes through
    :meth:`TextureFamily.build`, where a bare angle is in degrees.

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


__all__ = [
    "DEFAULT_NY_1D",
    "GENERATORS",
    "HEIGHT_UNITS",
    "KINDS",
    "MAX_GRID",
    "MIN_GRID",
    "REQUIRED",
    "HertzAsperity",
    "Param",
    "Texture",
    "TextureFamily",
    "base_mask",
    "bisinusoid",
    "describe",
    "dimples",
    "ellipsoids",
    "flat",
    "get_family",
    "level_plane",
    "make_texture",
    "parse_angle",
    "parse_size",
    "periodize",
    "pillars",
    "read_surface",
    "register",
    "registry",
    "ridges",
    "sinusoid",
    "spherical_caps",
]
