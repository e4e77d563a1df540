"""BEM fingerprint ridge model (meso scale) against Hertz and Westergaard-per-ridge."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad.errors import FingerpadError
from fingerpad.finger import HertzArea, SinusoidalRidges
from fingerpad.meso.fingerprint import FingerprintBEMRidges, fingerprint_topography

E, R = 100e3, 9e-3


def test_no_ridges_is_hertz() -> None:
    model = FingerprintBEMRidges(height=0.0, max_load=0.3, modulus=E, pad_radius=R)
    hertz = HertzArea(R, E).area(0.3)
    assert abs(model.area(0.3) / hertz - 1) < 0.02
    assert abs(model.gross_area(0.3)[0] / hertz - 1) < 0.02


def test_parallel_sinusoidal_ridges_match_westergaard_per_ridge() -> None:
    """Ridges much narrower than the contact: each ridge is a Westergaard contact (1-D sinusoid
    of amplitude h/2) at the local Hertz pressure, the sinusoidal model of the thesis."""
    lam, h, load = 0.45e-3, 30e-6, 0.5
    bem = FingerprintBEMRidges(height=h, width=lam, wavelength=lam, pattern="parallel",
                               max_load=load, modulus=E, pad_radius=R, points_per_wavelength=8)
    sinus = SinusoidalRidges(wavelength=lam, amplitude=h / 2, modulus=E)
    expected = sinus.area(load, HertzArea(R, E).area(load))
    assert bem.solve(load).converged
    assert abs(bem.area(load) / expected - 1) < 0.05
    # ridges carry the load on part of the gross area only
    assert bem.area(load) < 0.9 * bem.gross_area(load)[0]


def test_ridge_fraction_grows_with_load() -> None:
    model = FingerprintBEMRidges(max_load=0.4, modulus=E, points_per_wavelength=8)
    loads = np.array([0.1, 0.4])
    frac = model.area(loads) / model.gross_area(loads)
    assert frac[1] > frac[0]


def test_bad_fingerprint_inputs() -> None:
    with pytest.raises(FingerpadError, match="width"):
        fingerprint_topography(pad_radius=R, wavelength=0.4e-3, width=0.5e-3, height=1e-5, extent=5e-3, grid=128)
    with pytest.raises(FingerpadError, match="fewer than 6"):
        fingerprint_topography(pad_radius=R, wavelength=0.4e-3, width=0.3e-3, height=1e-5, extent=5e-3, grid=32)
    model = FingerprintBEMRidges(max_load=0.1, modulus=E, points_per_wavelength=6)
    with pytest.raises(FingerpadError, match="edge"):
        model.area(2.0)
