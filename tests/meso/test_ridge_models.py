"""Ridge-area models (meso scale, thesis ch. 2.2.2) against their closed forms.

Through the package face ``fingerpad.meso`` only (the models may move to one file each).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad import macro, meso
from fingerpad.errors import FingerpadError

E, LAM, HR, RR = 100e3, 0.45e-3, 30e-6, 0.1e-3
LOADS = np.array([0.1, 0.5, 1.0, 2.0, 4.0])
GROSS = np.asarray(macro.HertzArea(radius=9e-3, modulus=40e3).area(LOADS))


def test_constant_fraction():
    model = meso.ConstantFractionRidges(0.5)
    np.testing.assert_array_equal(model.area(LOADS, GROSS), 0.5 * GROSS)
    assert meso.ConstantFractionRidges().fraction == 0.5  # Duvefelt's 50 %
    assert meso.ConstantFractionRidges(1.0).area(1.0, 2e-4) == 2e-4
    for bad in (0.0, 1.2, -0.5):
        with pytest.raises(FingerpadError, match="ridge fraction"):
            meso.ConstantFractionRidges(bad)


def test_power_law_capped_at_the_gross_area():
    model = meso.PowerLawRidges(coefficient=5e-5, exponent=0.45)
    np.testing.assert_allclose(model.area(LOADS, np.full(LOADS.shape, 1.0)), 5e-5 * LOADS**0.45, rtol=1e-14)
    # a gross area smaller than k F^n caps it
    assert model.area(4.0, 1e-6) == 1e-6
    with pytest.raises(FingerpadError, match="exponent n"):
        meso.PowerLawRidges(coefficient=5e-5, exponent=0.0)


def test_sinusoidal_westergaard_local_fraction():
    model = meso.SinusoidalRidges(wavelength=LAM, amplitude=HR, modulus=E)
    p_star = math.pi * E * HR / LAM
    assert model.full_contact_pressure == pytest.approx(p_star, rel=1e-14)
    p = np.array([0.0, 0.25, 0.5, 1.0, 2.0]) * p_star
    np.testing.assert_allclose(model.local_fraction(p), (2 / math.pi) * np.arcsin(np.sqrt(np.minimum(p / p_star, 1))),
                               rtol=1e-14)
    assert model.local_fraction(0.5 * p_star) == pytest.approx(0.5, rel=1e-14)  # arcsin(1/sqrt 2) = pi/4


@pytest.mark.parametrize("k", [1.0, 1.5, 3.0, 10.0])
def test_sinusoidal_under_hertz_pressure_closed_form(k):
    """A_fr/A_g = 1 - 3 / (8 k^2) for k = 1.5 p_mean / p* >= 1."""
    model = meso.SinusoidalRidges(wavelength=LAM, amplitude=HR, modulus=E)
    ag = 1e-4
    load = k * model.full_contact_pressure / 1.5 * ag
    assert model.area(load, ag) / ag == pytest.approx(1 - 3 / (8 * k**2), rel=1e-12)


def test_uniform_pressure_uses_the_mean():
    model = meso.SinusoidalRidges(wavelength=LAM, amplitude=HR, modulus=E, pressure_distribution="uniform")
    ag = 1e-4
    load = 0.5 * model.full_contact_pressure * ag
    assert model.area(load, ag) == pytest.approx(0.5 * ag, rel=1e-14)
    hertz = meso.SinusoidalRidges(wavelength=LAM, amplitude=HR, modulus=E)
    # the same mean pressure spread as a Hertz dome touches less (psi is concave in p)
    assert hertz.area(load, ag) < model.area(load, ag)


def test_circular_hertz_line_contact():
    model = meso.CircularRidges(wavelength=LAM, ridge_radius=RR, modulus=E)
    pc = math.pi * E * LAM / (16 * RR)
    assert model.full_contact_pressure == pytest.approx(pc, rel=1e-14)
    p = np.array([0.01, 0.25, 1.0, 4.0]) * pc
    b = np.sqrt(4 * p * LAM * RR / (math.pi * E))
    np.testing.assert_allclose(model.half_width(p), b, rtol=1e-14)
    np.testing.assert_allclose(model.local_fraction(p), np.minimum(np.sqrt(p / pc), 1.0), rtol=1e-13)


@pytest.mark.parametrize("k, expected", [(0.25, 0.8 * 0.5), (0.64, 0.8 * 0.8), (1.0, 0.8), (2.0, 1 - 1 / 20)])
def test_circular_under_hertz_pressure_closed_form(k, expected):
    """(4/5) sqrt(k) for k = 1.5 p_mean / p_c <= 1 and 1 - 1/(5 k^2) above."""
    model = meso.CircularRidges(wavelength=LAM, ridge_radius=RR, modulus=E)
    ag = 2e-4
    load = k * model.full_contact_pressure / 1.5 * ag
    assert model.area(load, ag) / ag == pytest.approx(expected, rel=1e-12)


def test_profile_models_never_exceed_the_gross_area_and_grow_with_load():
    for model in (meso.SinusoidalRidges(wavelength=LAM, amplitude=HR, modulus=E),
                  meso.CircularRidges(wavelength=LAM, ridge_radius=RR, modulus=E)):
        area = np.asarray(model.area(LOADS, GROSS))
        assert np.all(area <= GROSS * (1 + 1e-12)) and np.all(area > 0)
        assert np.all(np.diff(area / GROSS) > 0)
        assert model.area(0.0, 1e-4) == 0.0
        assert isinstance(model, meso.RidgeAreaModel)
        assert np.asarray(model.area(np.ones((2, 3)), 1e-4)).shape == (2, 3)


@pytest.mark.parametrize("kwargs, word", [
    (dict(wavelength=0.0), "ridge wavelength"),
    (dict(modulus=-1.0), "ridge modulus"),
    (dict(amplitude=0.0), "ridge amplitude"),
    (dict(pressure_distribution="parabolic"), "pressure distribution: must be one of hertz, uniform"),
])
def test_sinusoidal_refusals(kwargs, word):
    with pytest.raises(FingerpadError, match=word):
        meso.SinusoidalRidges(**kwargs)


def test_models_by_name():
    assert meso.RIDGE_MODELS["constant_fraction"].factory is meso.ConstantFractionRidges
    assert meso.RIDGE_MODELS["power_law"].factory is meso.PowerLawRidges
    assert meso.RIDGE_MODELS["sinusoidal"].factory is meso.SinusoidalRidges
    assert meso.RIDGE_MODELS["circular"].factory is meso.CircularRidges


def test_model_curves_share_their_inputs():
    curves = meso.ridge_model_curves(LOADS, skin_modulus=E, radius=9e-3)
    np.testing.assert_array_equal(curves["load"], LOADS)
    gross = curves["gross (Hertz)"]
    np.testing.assert_allclose(gross, macro.HertzArea(9e-3, E).area(LOADS), rtol=1e-14)
    np.testing.assert_allclose(curves["constant fraction"], 0.5 * gross, rtol=1e-14)
    # the power law is anchored to the constant fraction at 1 N
    i = int(np.flatnonzero(LOADS == 1.0)[0])
    assert curves["power law"][i] == pytest.approx(curves["constant fraction"][i], rel=1e-12)
    for label in ("sinusoidal", "circular"):
        assert np.all(curves[label] <= gross * (1 + 1e-12))
    with pytest.raises(FingerpadError, match="must be positive"):
        meso.ridge_model_curves([0.0, 1.0])
