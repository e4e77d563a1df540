"""Macro and meso scales: gross-area and ridge-area models, pad pressure, Finger presets."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from fingerpad.errors import FingerpadError
from fingerpad.finger import FINGER_PRESETS, Finger, get_finger
from fingerpad.macro import DzidekArea, HertzArea, PowerLawArea, TwoRegimePowerLawArea
from fingerpad.macro.pressure import pad_pressure
from fingerpad.meso import CircularRidges, ConstantFractionRidges, PowerLawRidges, SinusoidalRidges
from fingerpad.plotting.ridges import ridge_models_figure

R_FP, E_FP = 9e-3, 40e3
LOADS = np.geomspace(0.05, 5.0, 25)


def local_slope(model, f: np.ndarray, rel: float = 1e-6) -> np.ndarray:
    """d ln A / d ln F by central differences."""
    up, dn = model.area(f * (1 + rel)), model.area(f * (1 - rel))
    return (np.log(up) - np.log(dn)) / (np.log1p(rel) - np.log1p(-rel))


# --------------------------------------------------------------------------------------------
# gross area
# --------------------------------------------------------------------------------------------


def test_hertz_area_value_and_two_thirds_exponent():
    hertz = HertzArea(R_FP, E_FP)
    # Hand value at 1 N: a = (3 * 9e-3 / 160e3)^(1/3) = 5.526 mm, A = pi a^2 = 95.93 mm^2.
    assert hertz.area(1.0) == pytest.approx(95.93e-6, rel=1e-3)
    slope = np.polyfit(np.log(LOADS), np.log(hertz.area(LOADS)), 1)[0]
    assert slope == pytest.approx(2.0 / 3.0, abs=1e-12)
    assert isinstance(hertz.area(1.0), float)
    assert hertz.area(LOADS).shape == LOADS.shape


def test_dzidek_reduces_to_hertz_without_stiffening():
    hertz = HertzArea(R_FP, E_FP)
    np.testing.assert_allclose(DzidekArea(R_FP, E_FP, 0.0).area(LOADS), hertz.area(LOADS), rtol=1e-14)
    # phi -> 0 continuously: tiny C gives Hertz to within phi F.
    tiny = DzidekArea(R_FP, E_FP, 1e-4)
    np.testing.assert_allclose(tiny.area(LOADS), hertz.area(LOADS), rtol=1e-12)


def test_dzidek_matches_eq_2_7_and_exponent_falls_with_load():
    model = DzidekArea(R_FP, E_FP, 5.0)
    phi = 3 * (0.2 * 5.0) ** 3 / (4 * R_FP**2 * E_FP)
    assert model.phi == pytest.approx(phi, rel=1e-14)
    eq27 = math.pi * (3 * R_FP * LOADS / (4 * E_FP * (1 + phi * LOADS))) ** (2 / 3)
    np.testing.assert_allclose(model.area(LOADS), eq27, rtol=1e-12)
    slopes = local_slope(model, LOADS)
    np.testing.assert_allclose(slopes, (2 / 3) / (1 + phi * LOADS), rtol=1e-6)
    assert np.all(np.diff(slopes) < 0)
    assert slopes[0] < 2 / 3


def test_power_law_gross_area():
    model = PowerLawArea(5e-5, 0.3)
    assert model.area(2.0) == pytest.approx(5e-5 * 2.0**0.3, rel=1e-14)
    assert np.polyfit(np.log(LOADS), np.log(model.area(LOADS)), 1)[0] == pytest.approx(0.3, abs=1e-12)


def test_two_regime_power_law_is_continuous_at_break_load():
    model = TwoRegimePowerLawArea(6e-5, 0.45, 0.15, break_load=2.0)
    fb = 2.0
    below, at, above = model.area(np.array([fb * (1 - 1e-12), fb, fb * (1 + 1e-12)]))
    assert below == pytest.approx(at, rel=1e-10)
    assert above == pytest.approx(at, rel=1e-10)
    assert at == pytest.approx(6e-5 * fb**0.45, rel=1e-14)
    low = np.array([0.1, 0.5, 1.5])
    high = np.array([2.5, 3.0, 4.0])
    assert local_slope(model, low) == pytest.approx([0.45] * 3, rel=1e-6)
    assert local_slope(model, high) == pytest.approx([0.15] * 3, rel=1e-6)


def test_gross_models_reject_bad_input():
    with pytest.raises(FingerpadError):
        HertzArea(-1e-3, E_FP)
    with pytest.raises(FingerpadError):
        HertzArea(R_FP, E_FP).area(-1.0)
    with pytest.raises(FingerpadError):
        HertzArea(R_FP, E_FP).area(np.array([1.0, np.nan]))
    with pytest.raises(FingerpadError):
        TwoRegimePowerLawArea(1e-5, 0.4, 0.2, break_load=0.0)


# --------------------------------------------------------------------------------------------
# ridge area
# --------------------------------------------------------------------------------------------


def test_constant_fraction_ridges():
    ag = HertzArea(R_FP, E_FP).area(LOADS)
    np.testing.assert_allclose(ConstantFractionRidges().area(LOADS, ag), 0.5 * ag, rtol=0)
    np.testing.assert_allclose(ConstantFractionRidges(0.3).area(LOADS, ag), 0.3 * ag, rtol=1e-15)
    for bad in (0.0, 1.2, float("nan")):
        with pytest.raises(FingerpadError):
            ConstantFractionRidges(bad)


def test_power_law_ridges_and_cap_at_gross_area():
    model = PowerLawRidges(3e-5, 0.5)
    assert model.area(4.0, 1.0) == pytest.approx(6e-5, rel=1e-14)
    assert model.area(4.0, 5e-5) == pytest.approx(5e-5, rel=0)


def westergaard_mean_pressure(a: float, wavelength: float, modulus: float, amplitude: float) -> float:
    """Mean of Johnson's (13.2) partial-contact pressure of a sinusoid over one wavelength."""
    p_star = math.pi * modulus * amplitude / wavelength
    s_a = math.sin(math.pi * a / wavelength) ** 2

    def p(x: float) -> float:
        return 2 * p_star * math.cos(math.pi * x / wavelength) * math.sqrt(
            max(s_a - math.sin(math.pi * x / wavelength) ** 2, 0.0))

    return quad(p, -a, a, limit=200)[0] / wavelength


def test_sinusoidal_local_fraction_is_westergaard():
    model = SinusoidalRidges(wavelength=0.45e-3, modulus=100e3, amplitude=30e-6)
    p_star = math.pi * 100e3 * 30e-6 / 0.45e-3
    assert model.full_contact_pressure == pytest.approx(p_star, rel=1e-14)
    for p in (0.01 * p_star, 0.3 * p_star, 0.8 * p_star):
        frac = model.local_fraction(p)
        # Contact half-width a = frac * lambda / 2 must carry the mean pressure p (Johnson 13.2).
        a = frac * model.wavelength / 2
        assert westergaard_mean_pressure(a, model.wavelength, 100e3, 30e-6) == pytest.approx(p, rel=1e-7)
    np.testing.assert_array_equal(model.local_fraction(np.array([p_star, 1.5 * p_star, 10 * p_star])), 1.0)


def test_sinusoidal_uniform_pressure_limit():
    uniform = SinusoidalRidges(wavelength=0.45e-3, modulus=100e3, amplitude=30e-6, pressure_distribution="uniform")
    p_star = uniform.full_contact_pressure
    ag = 1e-4
    # above p* everywhere: full ridge contact
    for p in (1.0001 * p_star, 3 * p_star):
        assert uniform.area(p * ag, ag) == pytest.approx(ag, rel=1e-14)
    # below: (2/pi) arcsin(sqrt(p/p*)) of the gross area
    for p in (0.05 * p_star, 0.5 * p_star, 0.95 * p_star):
        expected = 2 / math.pi * math.asin(math.sqrt(p / p_star)) * ag
        assert uniform.area(p * ag, ag) == pytest.approx(expected, rel=1e-13)


def test_sinusoidal_ridges_under_hertz_pressure_closed_form():
    model = SinusoidalRidges(wavelength=0.45e-3, modulus=100e3, amplitude=30e-6)
    p_star = model.full_contact_pressure
    ag = 1e-4
    for k in (1.0, 1.3, 4.0, 50.0):  # k = 1.5 p_mean / p* >= 1: A_fr/A_g = 1 - 3/(8 k^2)
        load = k * p_star / 1.5 * ag
        assert model.area(load, ag) / ag == pytest.approx(1 - 3 / (8 * k * k), rel=1e-12)
    for k in (0.02, 0.4, 0.9):  # partial everywhere: independent adaptive quadrature in r
        load = k * p_star / 1.5 * ag
        a = math.sqrt(ag / math.pi)

        def integrand(r: float, k: float = k) -> float:
            s = math.sqrt(max(1 - (r / a) ** 2, 0.0))
            return 2 / math.pi * math.asin(math.sqrt(k * s)) * 2 * math.pi * r

        expected = quad(integrand, 0, a, epsabs=0, epsrel=1e-13, limit=200)[0]
        assert model.area(load, ag) == pytest.approx(expected, rel=1e-9)
    # the Hertzian edge pressure vanishes, so the ridge area stays below the gross area
    f = np.geomspace(0.1, 100, 20)
    ag_f = HertzArea(R_FP, E_FP).area(f)
    frac = model.area(f, ag_f) / ag_f
    assert np.all(frac < 1) and np.all(np.diff(frac) > 0)


def test_circular_ridges_closed_form():
    model = CircularRidges(wavelength=0.45e-3, modulus=100e3, ridge_radius=0.1e-3)
    # Hertz line contact by hand: w = p lambda, b = sqrt(4 w R / (pi E)), fraction 2b/lambda.
    p = 2e3
    b = math.sqrt(4 * p * 0.45e-3 * 0.1e-3 / (math.pi * 100e3))
    assert model.half_width(p) == pytest.approx(b, rel=1e-14)
    assert model.local_fraction(p) == pytest.approx(2 * b / 0.45e-3, rel=1e-14)
    p_c = math.pi * 100e3 * 0.45e-3 / (16 * 0.1e-3)
    assert model.full_contact_pressure == pytest.approx(p_c, rel=1e-14)
    assert model.local_fraction(1.01 * p_c) == 1.0
    ag = 1e-4
    for k in (0.01, 0.5, 1.0):  # A_fr/A_g = 2 int_0^1 sqrt(k s) s ds = (4/5) sqrt(k)
        assert model.area(k * p_c / 1.5 * ag, ag) / ag == pytest.approx(0.8 * math.sqrt(k), rel=1e-12)
    for k in (1.5, 10.0):  # saturated centre: 1 - 1/(5 k^2)
        assert model.area(k * p_c / 1.5 * ag, ag) / ag == pytest.approx(1 - 1 / (5 * k * k), rel=1e-12)


def test_ridge_models_vectorised_and_validated():
    model = SinusoidalRidges()
    ag = HertzArea(R_FP, E_FP).area(LOADS)
    out = model.area(LOADS, ag)
    assert out.shape == LOADS.shape
    assert model.area(0.0, 0.0) == 0.0
    with pytest.raises(FingerpadError):
        SinusoidalRidges(amplitude=-1e-6)
    with pytest.raises(FingerpadError):
        CircularRidges(pressure_distribution="parabolic")  # type: ignore[arg-type]


# --------------------------------------------------------------------------------------------
# pad pressure (3.7)
# --------------------------------------------------------------------------------------------


def test_pad_pressure_integrates_to_load():
    load, area = 1.3, 4e-5
    a = math.sqrt(area / math.pi)
    total = quad(lambda r: pad_pressure(r, load, area) * 2 * math.pi * r, 0, a, epsrel=1e-12)[0]
    assert total == pytest.approx(load, rel=1e-9)
    assert pad_pressure(0.0, load, area) == pytest.approx(1.5 * load / area, rel=1e-14)
    np.testing.assert_array_equal(pad_pressure(np.array([a, 2 * a]), load, area), 0.0)
    with pytest.raises(FingerpadError):
        pad_pressure(-1e-3, load, area)


# --------------------------------------------------------------------------------------------
# Finger and presets
# --------------------------------------------------------------------------------------------


def test_presets_are_valid_and_in_documented_ranges():
    assert "default" in FINGER_PRESETS
    for name, finger in FINGER_PRESETS.items():
        assert finger.name == name
        assert 7e-3 <= finger.radius <= 11e-3
        assert 10e3 <= finger.modulus <= 100e3
        assert 0.2e6 <= finger.skin_modulus <= 0.5e6
        assert 0.48 <= finger.skin_poisson <= 0.5
        frac = finger.ridge_area(np.array([0.1, 1.0, 4.0])) / finger.gross_area(np.array([0.1, 1.0, 4.0]))
        assert np.all((frac >= 0.1) & (frac <= 0.75)), name
    default = get_finger("default")
    assert default.gross_area(1.0) == pytest.approx(HertzArea(9e-3, 40e3).area(1.0), rel=1e-14)
    assert default.ridge_area(1.0) == pytest.approx(0.5 * default.gross_area(1.0), rel=1e-14)


def test_get_finger_unknown_lists_presets():
    assert get_finger(" Default ") is FINGER_PRESETS["default"]
    with pytest.raises(FingerpadError) as info:
        get_finger("sweaty")
    message = str(info.value)
    assert "\n" not in message
    for name in FINGER_PRESETS:
        assert name in message


def test_with_overrides():
    base = get_finger("default")
    other = base.with_overrides(radius="11mm", modulus="20kPa", beta=0.0)
    assert other.radius == pytest.approx(11e-3) and other.modulus == pytest.approx(20e3) and other.beta == 0.0
    assert base.radius == 9e-3  # frozen original untouched
    assert other.gross_area(1.0) == pytest.approx(HertzArea(11e-3, 20e3).area(1.0), rel=1e-14)
    # a Dzidek gross model follows radius/modulus overrides
    stiff = get_finger("stiffening").with_overrides(radius=10e-3)
    assert stiff.gross.radius == 10e-3
    with pytest.raises(FingerpadError, match="unknown finger parameter"):
        base.with_overrides(radiuss=1e-3)
    for bad in ({"radius": -1e-3}, {"beta": 1.5}, {"tau0": -1.0}, {"skin_poisson": 0.7},
                {"modulus": "40kN"}, {"ridges": 0.5}, {"alpha": float("nan")}):
        with pytest.raises(FingerpadError):
            base.with_overrides(**bad)
    with pytest.raises(FingerpadError, match="differs"):
        Finger(radius=9e-3, modulus=40e3, gross=HertzArea(8e-3, 40e3))


def test_micro_modulus_rigid_texture():
    finger = get_finger("default")
    assert finger.micro_modulus() == pytest.approx(0.3e6 / (1 - 0.49**2), rel=1e-14)


def test_ridge_models_figure(tmp_path):
    out = ridge_models_figure(tmp_path / "fig24.png", np.geomspace(0.1, 4, 8))
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    with pytest.raises(FingerpadError):
        ridge_models_figure(tmp_path / "missing" / "fig.png")
