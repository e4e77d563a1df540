"""Generated textures hold the material their geometry says: volume per cell (mean height times
cell area) against the closed form of each asperity, and contact-area fractions of flat tops."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fingerpad as fp

UM = 1e-6


def volume(tex) -> float:
    return float(tex.heights.mean()) * tex.area


@pytest.mark.parametrize("lattice, per_cell", [("square", 1), ("hexagonal", 2)])
def test_cap_volume(lattice, per_cell):
    r, h = 50 * UM, 10 * UM
    tex = fp.make_texture("caps", radius=r, height=h, spacing=100 * UM, lattice=lattice, grid=256)
    cap = math.pi * h**2 * (3 * r - h) / 3
    assert volume(tex) == pytest.approx(per_cell * cap, rel=2e-3)
    assert tex.peak_to_valley == pytest.approx(h, rel=1e-3)


def test_dimple_volume_is_the_cell_minus_the_caps():
    r, d, s = 50 * UM, 10 * UM, 100 * UM
    tex = fp.make_texture("dimples", radius=r, depth=d, spacing=s, grid=256)
    cap = math.pi * d**2 * (3 * r - d) / 3
    assert volume(tex) == pytest.approx(d * s * s - cap, rel=2e-3)
    assert tex.heights.max() == pytest.approx(d)


def test_half_ellipsoid_volume():
    a, b, h = 40 * UM, 20 * UM, 10 * UM
    tex = fp.make_texture("ellipsoids", semi_axis_x=a, semi_axis_y=b, height=h, spacing_x=120 * UM,
                          spacing_y=80 * UM, grid=256)
    assert volume(tex) == pytest.approx(2 / 3 * math.pi * a * b * h, rel=5e-3)
    # turned by 90 degrees the volume is the same
    turned = fp.make_texture("ellipsoids", semi_axis_x=a, semi_axis_y=b, height=h, spacing_x=120 * UM,
                             spacing_y=120 * UM, orientation=math.pi / 2, grid=256)
    assert volume(turned) == pytest.approx(2 / 3 * math.pi * a * b * h, rel=5e-3)


def test_pillar_volume_and_top_fraction():
    dia, h, s = 40 * UM, 15 * UM, 100 * UM
    tex = fp.make_texture("pillars", diameter=dia, height=h, spacing=s, grid=256)
    top = math.pi * dia**2 / 4
    assert volume(tex) == pytest.approx(top * h, rel=0.02)
    fraction = float(np.mean(tex.heights >= h * (1 - 1e-9)))
    assert fraction == pytest.approx(top / s**2, rel=0.05)


def test_sinusoid_mean_is_its_amplitude_exactly():
    amp, lam = 3 * UM, 100 * UM
    tex = fp.make_texture("sinusoid", amplitude=amp, wavelength=lam, grid=64)
    # z = h (1 + cos 2 pi x / lambda): the cosine averages to zero on the sampled period
    assert float(tex.heights.mean()) == pytest.approx(amp, rel=1e-12)
    assert tex.peak_to_valley == pytest.approx(2 * amp, rel=1e-12)
    assert np.ptp(tex.heights, axis=1).max() == 0.0, "constant along y"


def test_circular_ridge_cross_section():
    w, h, s = 60 * UM, 10 * UM, 100 * UM
    tex = fp.make_texture("ridges", width=w, height=h, spacing=s, grid=512)
    # a circular segment of chord w and height h: radius R = (w^2/4 + h^2) / (2 h)
    radius = (w**2 / 4 + h**2) / (2 * h)
    theta = 2 * math.asin(w / (2 * radius))
    segment = radius**2 / 2 * (theta - math.sin(theta))
    assert float(tex.heights.mean()) * s == pytest.approx(segment, rel=2e-3)


def test_flat_is_flat():
    tex = fp.make_texture("flat", size=100 * UM, grid=16)
    assert np.all(tex.heights == 0.0) and tex.shape == (16, 16) and tex.periodic
