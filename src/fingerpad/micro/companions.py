"""The coarser companions of a BEM unit cell, whose change measures a grid's error.

A cell's error estimate compares it with the same cell on half the grid: the texture's generator
at half the grid where there is one, else the height map block-averaged 2 x 2 (a measured map,
or a grid the generator refuses). Used by the grid choice (:mod:`fingerpad.micro.resolution`)
and by the pulled-in transition's extrapolation (:mod:`fingerpad.micro.pull_in`).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING

from ..errors import FingerpadError, ResolutionWarning

if TYPE_CHECKING:
    from ..textures import Texture

__all__ = ["MIN_COMPANION_GRID", "companion", "halve"]

#: Grids below this many points along x have no coarser companion for the estimate.
MIN_COMPANION_GRID = 16


def halve(texture: "Texture") -> "Texture | None":
    """The texture block-averaged 2 x 2 (``None`` if a side is odd or too short)."""
    nx, ny = texture.shape
    if nx % 2 or nx // 2 < MIN_COMPANION_GRID:
        return None
    h = texture.heights
    if ny == 1 or ny % 2:
        if ny % 2 and ny != 1:
            return None
        hc = h.reshape(nx // 2, 2, ny).mean(axis=1)
    else:
        hc = h.reshape(nx // 2, 2, ny // 2, 2).mean(axis=(1, 3))
    return replace(texture, heights=hc)


def companion(make_texture: Callable[[int], "Texture"] | None, tex: "Texture") -> "Texture | None":
    """The half-grid companion of ``tex``: the generator at half the grid, else the map
    block-averaged 2 x 2 (``None`` if neither exists)."""
    nx = tex.shape[0]
    if make_texture is not None and nx // 2 >= MIN_COMPANION_GRID and nx % 2 == 0:
        try:
            with warnings.catch_warnings():  # coarse on purpose: it only measures the convergence
                warnings.simplefilter("ignore", ResolutionWarning)
                return make_texture(nx // 2)
        except FingerpadError:
            return halve(tex)
    return halve(tex)
