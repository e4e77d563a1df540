"""The unit cell's geometry and cache key: a texture's lengths over its cell length, its heights
rounded, and the key that holds neither a modulus nor a length (docs/solver.md, "One curve for
every modulus and every scale"). Used by :class:`fingerpad.micro.bem.BEMUnitCell` and by a
sweep's grouping of points by cell (:func:`fingerpad.design.evaluate.cell_key`).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from ..contact.layered import Layer
from .layered_cell import layer_key

if TYPE_CHECKING:
    from ..textures import Texture

__all__ = ["HEIGHT_BITS", "POINTS_PER_DECADE", "unit_cell_key", "unit_texture"]

#: Computed pressures lie on the global grid p_k / E* = 10**(k / POINTS_PER_DECADE), so curves
#: computed for different load ranges, moduli or processes merge in the cache.
POINTS_PER_DECADE = 12

#: Heights of the unit cell are rounded to a power of two near 2**-HEIGHT_BITS of its peak-to-
#: valley height (~1e-9 of it), so that a texture and its uniformly scaled copy, whose heights
#: over Lx agree only to rounding, give the same key (a rare straddle of a rounding step only
#: costs a new solve, never a wrong number).
HEIGHT_BITS = 30


def _quantise(x: "np.ndarray | float", step: float) -> Any:
    return np.round(np.asarray(x, dtype=float) / step) * step


def unit_texture(texture: "Texture") -> "Texture":
    """The texture with every length divided by its cell length Lx (``size[0]``), its lowest point
    at zero, heights rounded to a power of two near 2**-:data:`HEIGHT_BITS` of the peak-to-valley
    height: the geometry a unit-modulus solve sees. A texture scaled uniformly in all lengths has
    the same unit texture (to that rounding), hence the same psi(p)."""
    lx, ly = (float(v) for v in texture.size)
    h = np.asarray(texture.heights, dtype=float)
    low = float(h.min())
    hn = (h - low) / lx
    ptv = float(hn.max())
    step = 2.0 ** (math.floor(math.log2(ptv)) - HEIGHT_BITS) if ptv > 0 else 1.0
    base = None if texture.base_level is None else float(_quantise((texture.base_level - low) / lx, step))
    aspect = float(_quantise(ly / lx, 2.0**-40))
    return replace(texture, heights=_quantise(hn, step), size=(1.0, aspect), base_level=base)


def unit_cell_key(texture: "Texture", *, tol: float, max_iter: int, rtol: float, layer: Layer | None = None,
                  **extra: Any) -> str:
    """Cache key of the unit cell of ``texture`` (:func:`unit_texture`) and the solver settings:
    no modulus, no absolute length. ``layer`` is the *unit* layer (:func:`unit_layer`), whose
    dimensionless numbers join the key. ``extra`` settings join the key (the sweep adds its grid
    choice; a cell its solver's ``arithmetic``, the FFT engine and kernels that decide the last
    bits of its nodes)."""
    from .cache import content_key

    unit = unit_texture(texture)  # idempotent: a unit texture is its own
    return content_key(unit.heights, cell="unit", size=unit.size, base_level=unit.base_level, tol=tol,
                       max_iter=max_iter, ppd=POINTS_PER_DECADE, rtol=rtol, **layer_key(layer), **extra)
