"""Measured maps: a robust base level, one axis convention, a size that must fit the pixels."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.textures import read_surface, spherical_caps
from fingerpad.textures.measured import base_level_of, noise_level

E = 0.395e6


def noisy_caps_file(tmp_path, sigma: float, seed: int = 3):
    clean = spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, grid=64)
    rng = np.random.default_rng(seed)
    h = clean.heights + sigma * rng.standard_normal(clean.shape)
    path = tmp_path / "scan.npy"
    np.save(path, h * 1e6)  # stored in um, as an instrument export would
    return clean, path


def test_noisy_scan_of_caps_has_its_contact_states(tmp_path):
    """A scan of caps with 1.5 % noise on the base: transition and full contact are found, the
    transition near the clean cell's (touching "the lowest pixel", a noise pit, never happens)."""
    clean, path = noisy_caps_file(tmp_path, sigma=0.3e-6)
    noisy = read_surface(path, size=clean.size, height_unit="um", periodic=True, level=False)
    assert noisy.base_level is not None and 0.01 < noisy.base_mask().mean() < 0.9
    ref = BEMUnitCell(clean, E, cache=False).prepare(1e3, 1e5)
    cell = BEMUnitCell(noisy, E, cache=False).prepare(1e3, 1e5)
    assert math.isfinite(cell.transition_pressure) and math.isfinite(cell.full_contact_pressure)
    assert cell.transition_pressure == pytest.approx(ref.transition_pressure, rel=0.3)
    assert cell.full_contact_pressure == pytest.approx(ref.full_contact_pressure, rel=0.3)
    # with the single lowest pixel as the base (a noise pit) the transition comes much later
    lowest = dataclasses.replace(noisy, base_level=None)
    late = BEMUnitCell(lowest, E, cache=False).prepare(1e3, 1e5)
    assert late.transition_pressure > 1.5 * cell.transition_pressure


def test_noise_level_and_base_level():
    rng = np.random.default_rng(1)
    assert noise_level(0.5e-6 * rng.standard_normal((128, 128))) == pytest.approx(0.5e-6, rel=0.05)
    clean = spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, grid=64).heights
    assert noise_level(clean) == 0.0 and base_level_of(clean) == 0.0  # a clean map: its lowest level


def test_npy_and_text_hold_the_same_map_one_documented_way(tmp_path):
    """Axis 0 is x: a .npy holds the array, a text matrix holds it image-like (one line per y)."""
    h = np.arange(12.0).reshape(4, 3)  # 4 px along x, 3 along y
    np.save(tmp_path / "m.npy", h)
    np.savetxt(tmp_path / "m.txt", h.T)
    a = read_surface(tmp_path / "m.npy", size=(40e-6, 30e-6), height_unit="um", level=False)
    b = read_surface(tmp_path / "m.txt", size=(40e-6, 30e-6), height_unit="um", level=False)
    assert a.shape == b.shape == (4, 3)
    np.testing.assert_array_equal(a.heights, b.heights)


def test_size_that_contradicts_the_pixels_is_refused(tmp_path):
    np.save(tmp_path / "m.npy", np.random.default_rng(0).random((250, 200)))
    with pytest.raises(FingerpadError, match="aspect"):
        read_surface(tmp_path / "m.npy", size=(200e-6, 250e-6), height_unit="um")
    ok = read_surface(tmp_path / "m.npy", size=(250e-6, 200e-6), height_unit="um")
    assert ok.shape == (250, 200)
    with pytest.raises(FingerpadError, match="not both"):
        read_surface(tmp_path / "m.npy", size=(250e-6, 200e-6), pixel_size=1e-6, height_unit="um")
