"""f = v / lambda along the stroke for every lattice and direction; channels; threshold curve."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad import textures
from fingerpad.perception.vibration import channel, fingerprint_period, periods, threshold


@pytest.mark.parametrize("lattice", ["square", "hexagonal"])
def test_period_along_a_lattice_follows_its_geometry(lattice):
    s = 175e-6
    cell = textures.spherical_caps(radius=100e-6, height=20e-6, spacing=s, lattice=lattice, grid=64)
    along_x, along_y = periods(cell, 0.0), periods(cell, 90.0)
    assert along_x.fundamental == pytest.approx(s, rel=1e-9)
    # square: s both ways; hexagonal: rows along x, sqrt(3) s across them
    assert along_y.fundamental == pytest.approx(s if lattice == "square" else math.sqrt(3) * s, rel=1e-9)
    v = 0.05
    assert v / along_x.fundamental == pytest.approx(v / s)


def test_hexagonal_lattice_across_the_rows_is_strongest_at_the_row_spacing_or_the_fundamental():
    s = 175e-6
    cell = textures.spherical_caps(radius=100e-6, height=20e-6, spacing=s, lattice="hexagonal", grid=64)
    p = periods(cell, 90.0)
    assert p.harmonic in (1, 2)
    assert p.strongest == pytest.approx(math.sqrt(3) * s / p.harmonic, rel=1e-9)


def test_ridges_across_and_along():
    s = 120e-6
    cell = textures.ridges(width=40e-6, height=10e-6, spacing=s, grid=64)
    across = periods(cell, 0.0)
    along = periods(cell, 90.0)
    assert across.fundamental == pytest.approx(s, rel=1e-9)
    assert math.isinf(along.fundamental)  # sliding along the ridges: no period, no vibration
    assert channel(0.0) == "none"


def test_diagonal_of_a_square_lattice():
    s = 100e-6
    cell = textures.spherical_caps(radius=50e-6, height=10e-6, spacing=s, grid=64)
    assert periods(cell, 45.0).fundamental == pytest.approx(math.sqrt(2) * s, rel=1e-9)


def test_flat_has_no_period():
    assert math.isinf(periods(textures.flat(size=100e-6), 0.0).fundamental)


def test_channels_and_threshold_curve():
    assert [channel(f) for f in (5, 20, 250, 900)] == ["slow", "NP I", "P", "above P"]
    t = threshold(np.array([10.0, 40.0, 80.0, 250.0, 500.0]))
    assert t[0] == t[1]  # flat below 40 Hz
    assert t[1] / t[2] == pytest.approx(4.0)  # 12 dB per octave
    assert t[3] == pytest.approx(0.1e-6) and t[3] == t.min()


def test_fingerprint_period_from_the_ridge_model():
    from fingerpad.finger import FINGER_PRESETS

    assert fingerprint_period(FINGER_PRESETS["ridged"]) == pytest.approx(0.45e-3)
    assert fingerprint_period(FINGER_PRESETS["default"]) == pytest.approx(0.45e-3)
