"""Gross contact area of the pad (macro scale): Hertz Eq. 2.5, Dzidek Eqs. 2.6-2.7, power laws.

Every model is checked against its closed form or an exact identity, and through the package
face ``fingerpad.macro`` only (the models may move between files).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad import macro
from fingerpad.errors import FingerpadError

R = 9e-3  # pad radius, m
E = 40e3  # reduced modulus, Pa
LOADS = np.array([0.05, 0.1, 0.5, 1.0, 2.0, 4.0, 10.0])


def local_exponent(model, f: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """d ln A / d ln F by a central difference in ln F."""
    up = np.asarray(model.area(f * math.exp(h)))
    down = np.asarray(model.area(f * math.exp(-h)))
    return (np.log(up) - np.log(down)) / (2 * h)


# ---------------------------------------------------------------------------------------------
# Hertz
# ---------------------------------------------------------------------------------------------


def test_hertz_area_matches_closed_form():
    model = macro.HertzArea(radius=R, modulus=E)
    expected = math.pi * (3 * LOADS * R / (4 * E)) ** (2 / 3)
    np.testing.assert_allclose(model.area(LOADS), expected, rtol=1e-14)


def test_hertz_one_newton_value():
    # a = (3 * 1 N * 9 mm / (4 * 40 kPa))^(1/3) = (1.6875e-7 m^3)^(1/3) = 5.52605 mm
    model = macro.HertzArea(radius=9e-3, modulus=40e3)
    assert model.contact_radius(1.0) == pytest.approx(5.52605e-3, rel=1e-5)
    assert model.area(1.0) == pytest.approx(math.pi * 5.52605e-3**2, rel=1e-5)


def test_hertz_area_is_pi_a_squared():
    model = macro.HertzArea(radius=R, modulus=E)
    a = np.asarray(model.contact_radius(LOADS))
    np.testing.assert_allclose(model.area(LOADS), math.pi * a**2, rtol=1e-13)


def test_hertz_exponent_two_thirds_everywhere():
    model = macro.HertzArea(radius=R, modulus=E)
    np.testing.assert_allclose(local_exponent(model, LOADS), 2 / 3, rtol=1e-7)


def test_hertz_scalings_in_radius_and_modulus():
    base = macro.HertzArea(radius=R, modulus=E).area(1.0)
    # A ~ (R / E)^(2/3): doubling R and E together changes nothing; 8x R gives 4x A
    assert macro.HertzArea(radius=2 * R, modulus=2 * E).area(1.0) == pytest.approx(base, rel=1e-14)
    assert macro.HertzArea(radius=8 * R, modulus=E).area(1.0) == pytest.approx(4 * base, rel=1e-13)
    assert macro.HertzArea(radius=R, modulus=8 * E).area(1.0) == pytest.approx(base / 4, rel=1e-13)


def test_scalar_in_scalar_out_and_shape_kept():
    model = macro.HertzArea(radius=R, modulus=E)
    assert isinstance(model.area(1.0), float)
    assert np.asarray(model.area(np.ones((2, 3)))).shape == (2, 3)
    assert model(1.0) == model.area(1.0)  # the model is callable
    assert model.area(0.0) == 0.0


@pytest.mark.parametrize("kwargs", [dict(radius=0.0, modulus=E), dict(radius=-R, modulus=E),
                                    dict(radius=R, modulus=0.0), dict(radius=R, modulus=float("nan")),
                                    dict(radius="9mm", modulus=E)])
def test_hertz_refuses_bad_parameters(kwargs):
    with pytest.raises(FingerpadError, match="pad (radius|modulus)"):
        macro.HertzArea(**kwargs)


@pytest.mark.parametrize("load", [-1.0, float("nan"), float("inf"), [1.0, -0.1]])
def test_bad_loads_are_refused(load):
    with pytest.raises(FingerpadError, match="load"):
        macro.HertzArea(radius=R, modulus=E).area(load)


# ---------------------------------------------------------------------------------------------
# Dzidek
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("stiffening", [0.5, 5.0, 20.0])
def test_dzidek_eq_2_7_identity(stiffening):
    """For eta = 3 the strain-stiffened Hertz area is exactly Eq. 2.7."""
    model = macro.DzidekArea(radius=R, modulus=E, stiffening=stiffening)
    phi = 3 * (0.2 * stiffening) ** 3 / (4 * R**2 * E)
    assert model.phi == pytest.approx(phi, rel=1e-14)
    expected = math.pi * (3 * R * LOADS / (4 * E * (1 + phi * LOADS))) ** (2 / 3)
    np.testing.assert_allclose(model.area(LOADS), expected, rtol=1e-12)


def test_dzidek_secant_modulus_eq_2_6():
    c = 5.0
    model = macro.DzidekArea(radius=R, modulus=E, stiffening=c)
    a_h = np.asarray(macro.HertzArea(radius=R, modulus=E).contact_radius(LOADS))
    expected = E * (1 + (c * 0.2 * a_h / R) ** 3)
    np.testing.assert_allclose(model.secant_modulus(LOADS), expected, rtol=1e-12)
    assert model.secant_modulus(0.0) == pytest.approx(E)


def test_dzidek_local_exponent_falls_with_load():
    model = macro.DzidekArea(radius=R, modulus=E, stiffening=5.0)
    np.testing.assert_allclose(local_exponent(model, LOADS), (2 / 3) / (1 + model.phi * LOADS), rtol=1e-6)
    assert np.all(np.diff(local_exponent(model, LOADS)) < 0)


def test_dzidek_without_stiffening_is_hertz():
    hertz = macro.HertzArea(radius=R, modulus=E)
    dz = macro.DzidekArea(radius=R, modulus=E, stiffening=0.0)
    np.testing.assert_allclose(dz.area(LOADS), hertz.area(LOADS), rtol=1e-14)
    assert dz.phi == 0.0


def test_dzidek_area_below_hertz_and_exponent_changes_it():
    hertz = np.asarray(macro.HertzArea(radius=R, modulus=E).area(LOADS))
    eta3 = np.asarray(macro.DzidekArea(radius=R, modulus=E, stiffening=5.0).area(LOADS))
    eta2 = np.asarray(macro.DzidekArea(radius=R, modulus=E, stiffening=5.0, exponent=2.0).area(LOADS))
    assert np.all(eta3 < hertz) and np.all(eta2 < hertz)
    # C eps = 5 * 0.2 a_H / R crosses 1 between 4 N and 10 N: below it (C eps)^2 > (C eps)^3, so
    # eta = 2 stiffens more (smaller area); above it the order turns over
    c_eps = 5.0 * 0.2 * np.asarray(macro.HertzArea(radius=R, modulus=E).contact_radius(LOADS)) / R
    assert np.array_equal(eta2 < eta3, c_eps < 1) and (c_eps < 1).any() and (c_eps > 1).any()


@pytest.mark.parametrize("kwargs, word", [(dict(stiffening=-1.0), "stiffening"), (dict(stiffening=1.0, exponent=0.0), "exponent")])
def test_dzidek_refuses_bad_parameters(kwargs, word):
    with pytest.raises(FingerpadError, match=word):
        macro.DzidekArea(radius=R, modulus=E, **kwargs)


# ---------------------------------------------------------------------------------------------
# power laws
# ---------------------------------------------------------------------------------------------


def test_power_law_area():
    model = macro.PowerLawArea(coefficient=1.2e-4, exponent=0.3)
    np.testing.assert_allclose(model.area(LOADS), 1.2e-4 * LOADS**0.3, rtol=1e-14)
    np.testing.assert_allclose(local_exponent(model, LOADS), 0.3, rtol=1e-7)
    assert model.area(1.0) == pytest.approx(1.2e-4)


def test_two_regime_power_law_continuous_at_break():
    model = macro.TwoRegimePowerLawArea(coefficient=1e-4, exponent_low=0.5, exponent_high=0.2, break_load=2.0)
    below, at, above = model.area([2.0 * (1 - 1e-12), 2.0, 2.0 * (1 + 1e-12)])
    assert below == pytest.approx(at, rel=1e-10) and above == pytest.approx(at, rel=1e-10)
    assert at == pytest.approx(1e-4 * 2.0**0.5, rel=1e-14)


def test_two_regime_exponents_each_side():
    model = macro.TwoRegimePowerLawArea(coefficient=1e-4, exponent_low=0.5, exponent_high=0.2, break_load=2.0)
    np.testing.assert_allclose(local_exponent(model, np.array([0.1, 0.5, 1.5])), 0.5, rtol=1e-6)
    np.testing.assert_allclose(local_exponent(model, np.array([3.0, 5.0, 10.0])), 0.2, rtol=1e-6)
    # above the break: c F_b^m1 (F / F_b)^m2
    assert model.area(8.0) == pytest.approx(1e-4 * 2.0**0.5 * 4.0**0.2, rel=1e-14)


def test_two_regime_default_break_is_two_newtons():
    model = macro.TwoRegimePowerLawArea(coefficient=1e-4, exponent_low=0.5, exponent_high=0.2)
    assert model.break_load == 2.0


@pytest.mark.parametrize("cls, kwargs", [
    (macro.PowerLawArea, dict(coefficient=0.0, exponent=0.3)),
    (macro.PowerLawArea, dict(coefficient=1e-4, exponent=-0.3)),
    (macro.TwoRegimePowerLawArea, dict(coefficient=1e-4, exponent_low=0.5, exponent_high=0.2, break_load=0.0)),
    (macro.TwoRegimePowerLawArea, dict(coefficient=1e-4, exponent_low=0.0, exponent_high=0.2)),
])
def test_power_laws_refuse_non_positive_parameters(cls, kwargs):
    with pytest.raises(FingerpadError, match="must be positive"):
        cls(**kwargs)


# ---------------------------------------------------------------------------------------------
# registry and protocol
# ---------------------------------------------------------------------------------------------


def test_models_by_name_and_protocol():
    names = {"hertz": macro.HertzArea, "dzidek": macro.DzidekArea, "power_law": macro.PowerLawArea,
             "two_regime": macro.TwoRegimePowerLawArea}
    for name, cls in names.items():
        assert macro.GROSS_MODELS[name].factory is cls
    for model in (macro.HertzArea(R, E), macro.DzidekArea(R, E, 1.0), macro.PowerLawArea(1e-4, 0.3),
                  macro.TwoRegimePowerLawArea(1e-4, 0.5, 0.2)):
        assert isinstance(model, macro.GrossAreaModel)
        assert np.all(np.diff(np.asarray(model.area(LOADS))) > 0), "area must grow with load"


def test_models_are_frozen():
    model = macro.HertzArea(radius=R, modulus=E)
    with pytest.raises(AttributeError):
        model.radius = 1.0  # type: ignore[misc]
