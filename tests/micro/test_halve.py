"""The coarse companion of a cell (its error estimate): an exact 2 x 2 block average."""

from __future__ import annotations

import numpy as np
import pytest

import fingerpad as fp
from fingerpad.micro.companions import MIN_COMPANION_GRID, halve


def test_block_average_is_exact():
    h = np.arange(32 * 16, dtype=float).reshape(32, 16)
    tex = fp.Texture(h, (2e-4, 1e-4), periodic=True, name="map")
    half = halve(tex)
    assert half.shape == (16, 8) and half.size == tex.size and half.periodic and half.name == "map"
    np.testing.assert_array_equal(half.heights, h.reshape(16, 2, 8, 2).mean(axis=(1, 3)))
    assert half.heights.mean() == h.mean()


def test_constant_along_y_maps_keep_one_column():
    h = np.tile(np.linspace(0, 1, 32)[:, None], (1, 1))
    half = halve(fp.Texture(h, (1e-4, 1e-4), periodic=True))
    assert half.shape == (16, 1)
    np.testing.assert_allclose(half.heights[:, 0], h.reshape(16, 2).mean(axis=1))


@pytest.mark.parametrize("shape", [(31, 16), (32, 15), (2 * (MIN_COMPANION_GRID - 1), 16)])
def test_no_companion_for_odd_or_small_grids(shape):
    assert halve(fp.Texture(np.zeros(shape), (1e-4, 1e-4), periodic=True)) is None
