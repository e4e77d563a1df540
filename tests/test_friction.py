"""Friction: adhesion, hysteresis, flat reference, normalisation, power-law fit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.coupling import predict_curve
from fingerpad.errors import FingerpadError
from fingerpad.finger import HertzArea, get_finger
from fingerpad.friction import (
    adhesion_force,
    fit_power_law,
    friction_coefficient,
    hysteresis_force,
    normalised_friction,
    reference_friction_coefficient,
    reference_real_area,
    shear_strength,
)
from fingerpad.micro.response import PowerLawUnitCell

LOADS = np.geomspace(0.1, 4.0, 12)


def test_hysteresis_equals_greenwood_tabor_identity():
    radius, modulus, beta = 9e-3, 40e3, 0.2
    a = HertzArea(radius, modulus).contact_radius(LOADS)
    expected = beta * (3 / 16) * a * LOADS / radius
    np.testing.assert_allclose(hysteresis_force(LOADS, radius, modulus, beta), expected, rtol=1e-13)
    # exponent 4/3 in the load, and zero without loss
    assert hysteresis_force(2.0, radius, modulus, beta) / hysteresis_force(1.0, radius, modulus, beta) == \
        pytest.approx(2 ** (4 / 3), rel=1e-13)
    assert hysteresis_force(1.0, radius, modulus, 0.0) == 0.0
    with pytest.raises(FingerpadError):
        hysteresis_force(1.0, -radius, modulus, beta)


def test_adhesion_and_shear_strength():
    tau0, alpha = 8e3, 0.2
    area, load = 3e-5, 1.5
    p_re = load / area
    assert shear_strength(p_re, tau0, alpha) == pytest.approx(tau0 + alpha * p_re)
    # tau * A_re with p_re = F / A_re
    assert adhesion_force(load, area, tau0, alpha) == pytest.approx(shear_strength(p_re, tau0, alpha) * area,
                                                                   rel=1e-14)
    with pytest.raises(FingerpadError):
        adhesion_force(load, 0.0, tau0, alpha)
    with pytest.raises(FingerpadError):
        adhesion_force(0.0, area, tau0, alpha)


def test_default_finger_mu_about_half_on_smooth_flat():
    finger = get_finger("default")
    mu = reference_friction_coefficient(1.0, finger)
    assert mu == pytest.approx(0.5, abs=0.01)
    assert reference_real_area(1.0, finger) == pytest.approx(finger.ridge_area(1.0), rel=1e-14)
    # decreasing with load, as measured (negative n - 1)
    mus = reference_friction_coefficient(LOADS, finger)
    assert np.all(np.diff(mus) < 0)
    # the parts add up (Eq. 2.1)
    area = finger.ridge_area(1.0)
    parts = finger.tau0 * area + finger.alpha * 1.0 + hysteresis_force(1.0, finger.radius, finger.modulus, finger.beta)
    assert friction_coefficient(1.0, area, finger) == pytest.approx(parts, rel=1e-14)


@pytest.mark.parametrize(
    ("name", "mu"), [("default", 0.50), ("soft", 1.24), ("stiff", 0.29), ("stiffening", 0.45), ("ridged", 0.50)]
)
def test_preset_flat_friction_as_documented(name, mu):
    assert reference_friction_coefficient(1.0, get_finger(name)) == pytest.approx(mu, abs=0.006)


def test_normalisation_equals_area_ratio_without_hysteresis_and_alpha():
    cell = PowerLawUnitCell(coefficient=2e-3, exponent=0.6)  # p_full ~ 31 kPa, partly saturated
    pure = get_finger("default").with_overrides(beta=0.0, alpha=0.0)
    curve = predict_curve(LOADS, pure, cell)
    ratio = curve.real_area / curve.ridge_area  # A_re,tex / A_re,ref (reference A_re = A_fr)
    np.testing.assert_allclose(curve.mu_normalised, ratio, rtol=1e-13)
    np.testing.assert_allclose(normalised_friction(curve.mu, curve.mu_ref), ratio, rtol=1e-13)
    assert np.ptp(ratio) > 0.05  # a real texture effect, not a trivial 1
    # with the pressure term and hysteresis the equality no longer holds
    full = predict_curve(LOADS, get_finger("default"), cell)
    assert np.max(np.abs(full.mu_normalised / ratio - 1)) > 0.05
    with pytest.raises(FingerpadError):
        normalised_friction(0.5, 0.0)


def test_power_law_fit_recovers_parameters_within_ci():
    rng = np.random.default_rng(12345)
    k, n = 0.5, 0.2  # n - 1 = -0.8 (dry finger on glass, docs/model.md)
    loads = np.geomspace(0.2, 4.0, 20)
    mu = k * loads ** (n - 1) * np.exp(rng.normal(0, 0.05, loads.size))
    fit = fit_power_law(loads, mu)
    assert fit.k_ci[0] < k < fit.k_ci[1]
    assert fit.n_ci[0] < n < fit.n_ci[1]
    assert fit.n_stderr < 0.05 and fit.k_stderr / fit.k < 0.05
    assert fit.dof == 18 and not fit.absolute_sigma
    assert fit.covariance.shape == (2, 2)
    assert fit.covariance[0, 0] == pytest.approx(fit.k_stderr**2, rel=1e-12)
    assert fit.covariance[1, 1] == pytest.approx(fit.n_stderr**2, rel=1e-12)
    assert fit(2.0) == pytest.approx(fit.k * 2.0 ** (fit.n - 1), rel=1e-14)


def test_power_law_fit_interval_coverage():
    """The 95 % intervals must cover the truth ~95 % of the time (t-based, estimated scatter)."""
    rng = np.random.default_rng(7)
    k, n = 0.8, 0.3
    loads = np.geomspace(0.3, 3.0, 6)  # few points: a normal-quantile interval would undercover
    hits_k = hits_n = 0
    trials = 400
    for _ in range(trials):
        mu = k * loads ** (n - 1) * np.exp(rng.normal(0, 0.1, loads.size))
        fit = fit_power_law(loads, mu)
        hits_k += fit.k_ci[0] < k < fit.k_ci[1]
        hits_n += fit.n_ci[0] < n < fit.n_ci[1]
    assert 0.92 < hits_k / trials < 0.98
    assert 0.92 < hits_n / trials < 0.98


def test_power_law_fit_with_absolute_sigma():
    rng = np.random.default_rng(3)
    k, n = 0.6, 0.25
    loads = np.geomspace(0.2, 4.0, 15)
    truth = k * loads ** (n - 1)
    sigma = 0.02 * truth
    hits = 0
    for _ in range(300):
        fit = fit_power_law(loads, truth + rng.normal(0, sigma), sigma=sigma)
        hits += fit.n_ci[0] < n < fit.n_ci[1]
    assert fit.absolute_sigma
    assert 0.91 < hits / 300 < 0.985
    # exact data: exact parameters, uncertainty set by sigma alone
    exact = fit_power_law(loads, truth, sigma=sigma)
    assert exact.k == pytest.approx(k, rel=1e-12) and exact.n == pytest.approx(n, rel=1e-12)
    assert exact.n_stderr > 0


@pytest.mark.parametrize(
    ("loads", "mu", "sigma", "match"),
    [
        ([1.0, 2.0], [0.5, 0.4], None, "at least 3"),
        ([1.0, 2.0, 3.0], [0.5, 0.4], None, "differ in length"),
        ([1.0, -2.0, 3.0], [0.5, 0.4, 0.3], None, "positive"),
        ([1.0, 2.0, 3.0], [0.5, 0.0, 0.3], None, "positive"),
        ([1.0, float("nan"), 3.0], [0.5, 0.4, 0.3], None, "NaN"),
        ([1.0, 2.0, 3.0], [0.5, 0.4, float("nan")], None, "NaN"),
        ([2.0, 2.0, 2.0], [0.5, 0.4, 0.3], None, "two different loads"),
        ([1.0, 2.0, 3.0], [0.5, 0.4, 0.3], [0.01, 0.0, 0.01], "sigma"),
    ],
)
def test_power_law_fit_rejects_bad_input(loads, mu, sigma, match):
    with pytest.raises(FingerpadError, match=match):
        fit_power_law(loads, mu, sigma)


def test_friction_functions_reject_bad_loads():
    finger = get_finger("default")
    with pytest.raises(FingerpadError):
        reference_friction_coefficient(np.array([1.0, -1.0]), finger)
    with pytest.raises(FingerpadError):
        friction_coefficient(1.0, math.nan, finger)
