"""The layer of a layered skin's unit cell: dimensionless, so that the cache stays modulus-free
and scale-free (docs/solver.md, "A layered cell").

With a layer, psi is a function of p/E* at fixed t/Lx, E_1/E*, E_2/E*, nu_1, nu_2 and base:
:func:`unit_layer` is the layer made of those numbers, which the unit cell
(:class:`fingerpad.micro.bem.BEMUnitCell`) is solved with, and :func:`layer_key` what they add to
its cache key (nothing for a half-space, whose keys are therefore as they always were).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..contact.layered import Layer

__all__ = ["layer_key", "unit_layer"]

#: Ratios are rounded to a power of two near 2**-RATIO_BITS of themselves: a uniformly scaled
#: skin, whose ratios agree only to rounding, gets the same key.
RATIO_BITS = 40


def _round(x: float) -> float:
    """``x`` rounded to a power of two near 2**-RATIO_BITS of it (a scaled copy's ratio agrees to that)."""
    if not (math.isfinite(x) and x > 0):
        return x
    step = 2.0 ** (math.floor(math.log2(x)) - RATIO_BITS)
    return float(np.round(x / step) * step)


def unit_layer(layer: Layer | None, modulus: float, length: float) -> Layer | None:
    """The layer a unit-cell solve sees: thickness over the cell length ``length`` (Lx, m), moduli
    over the pair's reduced modulus ``modulus`` (E*, Pa), Poisson ratios and base as they are,
    each ratio rounded like the unit texture's heights
    (:func:`fingerpad.micro.bem.unit_texture`). A skin whose moduli and thickness
    are all scaled with E* and Lx has the same unit layer, hence the same psi(p / E*)."""
    if layer is None:
        return None
    e2 = layer.substrate_modulus if layer.rigid_base else _round(layer.substrate_modulus / modulus)
    return Layer(_round(layer.thickness / length), _round(layer.modulus / modulus), layer.poisson, e2,
                 layer.substrate_poisson, layer.base)


def layer_key(layer: Layer | None) -> dict[str, Any]:
    """The settings a unit layer (:func:`unit_layer`) adds to the cache key; none for no layer,
    so that a half-space cell's key is the one it always had (no CACHE_VERSION change)."""
    if layer is None:
        return {}
    return {"layer": {"t_over_lx": layer.thickness, "e1_over_e": layer.modulus, "nu1": layer.poisson,
                      "e2_over_e": "rigid" if layer.rigid_base else layer.substrate_modulus,
                      "nu2": layer.substrate_poisson, "base": layer.base}}
