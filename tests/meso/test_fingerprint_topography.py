"""The fingerprint height map: a paraboloid pad (Hertz's sphere) carrying raised-cosine ridges."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad import meso
from fingerpad.errors import FingerpadError

R, LAM, W, H = 9e-3, 0.45e-3, 0.3e-3, 30e-6


def topo(pattern="whorl", height=H, grid=128, extent=4.5e-3):
    return meso.fingerprint_topography(pad_radius=R, wavelength=LAM, width=W, height=height, extent=extent,
                                       grid=grid, pattern=pattern)


def test_without_ridges_it_is_the_paraboloid():
    tex = topo(height=0.0)
    x = (np.arange(128) + 0.5) * 4.5e-3 / 128 - 4.5e-3 / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    np.testing.assert_allclose(tex.heights, -(X**2 + Y**2) / (2 * R), rtol=1e-13, atol=1e-18)
    assert not tex.periodic and tex.name == "fingerprint" and tex.size == (4.5e-3, 4.5e-3)


def test_ridges_add_a_raised_cosine_of_the_given_height():
    plain, ridged = topo(height=0.0), topo()
    bumps = ridged.heights - plain.heights
    assert bumps.min() >= 0.0 and bumps.max() <= H * (1 + 1e-12)
    assert bumps.max() == pytest.approx(H, rel=0.02)  # a pixel near a ridge crest
    # the share of the patch under ridges is width / wavelength
    assert float(np.mean(bumps > 0)) == pytest.approx(W / LAM, abs=0.04)


def test_parallel_ridges_are_constant_along_y():
    bumps = topo("parallel", grid=160).heights - topo("parallel", height=0.0, grid=160).heights
    assert np.ptp(bumps, axis=1).max() < 1e-18
    # 160 points over 4.5 mm: 16 per wavelength, so the ridges repeat every 16 rows exactly
    np.testing.assert_allclose(bumps[16:], bumps[:-16], atol=1e-12 * H)


def test_whorl_ridges_are_rings():
    bumps = topo().heights - topo(height=0.0).heights
    # rotationally symmetric up to pixels: the map equals its transpose and its mirror images
    np.testing.assert_allclose(bumps, bumps.T, atol=1e-18)
    np.testing.assert_allclose(bumps, bumps[::-1, :], atol=1e-18)


def test_apex_is_on_a_ridge_crest():
    tex = topo(grid=256)
    c = 128
    centre = tex.heights[c - 1 : c + 1, c - 1 : c + 1]
    assert centre.max() == pytest.approx(tex.heights.max())


@pytest.mark.parametrize("kwargs, message", [
    (dict(pattern="loop"), "fingerprint pattern must be 'whorl' or 'parallel'"),
    (dict(height=-1e-6), "ridge height must be non-negative"),
    (dict(extent=0.0), "extent must be positive"),
])
def test_refusals(kwargs, message):
    with pytest.raises(FingerpadError, match=message):
        topo(**kwargs)
