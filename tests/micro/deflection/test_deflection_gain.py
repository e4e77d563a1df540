"""Gain table, fixed point, directional cell and the elliptical Greenwood-Tabor term."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import dblquad

from fingerpad.coupling import adhesion_integral, predict_curve
from fingerpad.micro.hertz import HertzUnitCell
from fingerpad.errors import FingerpadError
from fingerpad.finger import Finger
from fingerpad.friction import hysteresis_force
from fingerpad.materials import Materials
from fingerpad.micro.deflection import (
    DeflectionSettings,
    DirectionalCell,
    EllipsoidGeometry,
    GainCurve,
    PressureRamp,
    RidgeGeometry,
    directional_gain,
    elliptical_hysteresis_force,
    hertz_ellipse,
    hysteresis_direction_factor,
    section_for,
    solve_local_shear,
    texture_geometry,
)

COMPLIANT = Materials(skin_modulus=0.3e6, skin_poisson=0.49, material_modulus=0.3e6, material_poisson=0.49)
RIGID = Materials(skin_modulus=0.3e6, skin_poisson=0.49)
FAST = DeflectionSettings(n_pressures=1, mu_max=0.3, resolution=4, check_stability=False)


def _ramp(pressure: float, mu: np.ndarray, gain: np.ndarray) -> PressureRamp:
    z = np.zeros_like(mu)
    return PressureRamp(pressure, 1.0, mu, gain, gain, z, z, z, z, z, z, math.nan, math.nan, False, None)


def _linear_gain(slope: float, pressures=(1e3, 1e5)) -> GainCurve:
    mu = np.linspace(0, 3, 61)
    return GainCurve(np.array(pressures), [_ramp(p, mu, 1 + slope * mu) for p in pressures])


# ---------------------------------------------------------------------------- identity cases
def test_rigid_texture_gives_exactly_gain_one():
    geo = EllipsoidGeometry(30e-6, 90e-6, 30e-6, 300e-6, 300e-6)
    g = directional_gain(geo, RIGID, 0.0, (1e3, 2e4), cache=False)
    assert g.is_identity
    p = np.geomspace(1e2, 1e5, 7)
    assert np.array_equal(g(p, 1.2), np.ones(7))
    cell = HertzUnitCell(radius=50e-6, height=10e-6, spacing=200e-6, reduced_modulus=1e5)
    d = DirectionalCell(cell, g, tau0=8.1e3, alpha=0.1)
    assert np.array_equal(d.contact_fraction(p), cell.contact_fraction(p))
    finger = Finger()
    a = predict_curve([0.5, 1.0, 2.0], finger, cell)
    b = predict_curve([0.5, 1.0, 2.0], finger, d)
    assert np.array_equal(a.mu, b.mu) and np.array_equal(a.real_area, b.real_area)


def test_ridges_parallel_to_the_sliding_give_gain_one():
    geo = RidgeGeometry(60e-6, 20e-6, 200e-6)
    assert directional_gain(geo, COMPLIANT, 90.0, (1e3, 1e4), cache=False).is_identity
    assert section_for(geo, 60.0).shear_factor == pytest.approx(0.5)


def test_sections_of_a_circular_asperity_are_the_same_in_every_direction():
    geo = EllipsoidGeometry(40e-6, 40e-6, 30e-6, 250e-6, 250e-6, orientation=0.3)
    s0 = section_for(geo, 0.0)
    for d in (17.0, 45.0, 90.0, 133.0):
        s = section_for(geo, d)
        assert (s.half_width, s.height, s.period, s.load_per_pressure) == pytest.approx(
            (s0.half_width, s0.height, s0.period, s0.load_per_pressure), rel=1e-12)


def test_section_of_an_ellipsoid_follows_the_direction():
    geo = EllipsoidGeometry(30e-6, 90e-6, 30e-6, 300e-6, 200e-6)
    assert section_for(geo, 0.0).half_width == pytest.approx(30e-6)
    assert section_for(geo, 90.0).half_width == pytest.approx(90e-6)
    assert section_for(geo, 0.0).period == pytest.approx(300e-6)
    assert section_for(geo, 90.0).period == pytest.approx(200e-6)
    # the section's mean footprint stress equals the asperity's: P / (2 r) = p sx sy / (pi a b)
    for d in (0.0, 30.0, 90.0):
        s = section_for(geo, d)
        assert s.load_per_pressure / (2 * s.half_width) == pytest.approx(300e-6 * 200e-6 / (math.pi * 30e-6 * 90e-6))


@pytest.mark.slow
def test_circular_asperity_is_isotropic_end_to_end(tmp_path):
    geo = EllipsoidGeometry(40e-6, 40e-6, 40e-6, 250e-6, 250e-6)
    g0 = directional_gain(geo, COMPLIANT, 0.0, (3e3, 3e3), settings=FAST, cache=str(tmp_path))
    g1 = directional_gain(geo, COMPLIANT, 90.0, (3e3, 3e3), settings=FAST, cache=False)  # solved again
    mu = np.linspace(0, 0.3, 7)
    assert np.allclose(g0(3e3, mu), g1(3e3, mu), rtol=1e-10)
    assert g0.ramps[0].mu_reached == pytest.approx(0.3, rel=1e-3)


def test_gain_table_is_cached_by_content(tmp_path):
    geo = EllipsoidGeometry(40e-6, 120e-6, 40e-6, 300e-6, 300e-6)
    a = directional_gain(geo, COMPLIANT, 0.0, (3e3, 3e3), settings=FAST, cache=str(tmp_path))
    assert list(tmp_path.glob("*.json"))
    b = directional_gain(geo, COMPLIANT, 180.0, (3e3, 3e3), settings=FAST, cache=str(tmp_path))  # same section
    assert b.cache_key == a.cache_key
    mu = np.linspace(0, 0.3, 5)
    assert np.array_equal(a(3e3, mu), b(3e3, mu))
    assert np.all(np.isfinite(a(3e3, mu)))


def test_texture_geometry_reads_generated_textures():
    from fingerpad.textures import ellipsoids, ridges

    t = ellipsoids(semi_axis_x="30um", semi_axis_y="90um", height="30um", spacing_x="300um", spacing_y="300um",
                   grid=128)
    g = texture_geometry(t)
    assert isinstance(g, EllipsoidGeometry)
    assert (g.semi_axis_x, g.semi_axis_y, g.height, g.spacing_x, g.spacing_y, g.orientation) == pytest.approx(
        (30e-6, 90e-6, 30e-6, 300e-6, 300e-6, 0.0))
    r = texture_geometry(ridges(width="60um", height="20um", spacing="200um", grid=64))
    assert isinstance(r, RidgeGeometry) and (r.width, r.height, r.spacing) == pytest.approx((60e-6, 20e-6, 200e-6))
    with pytest.raises(FingerpadError):
        texture_geometry(ridges(width="60um", height="20um", spacing="200um", profile="sinusoidal", grid=64))


# ---------------------------------------------------------------------------- interpolation
def test_gain_interpolation_and_saturation():
    g = _linear_gain(0.2)
    assert g(1e3, 1.0) == pytest.approx(1.2)
    assert g(1e4, 1.0) == pytest.approx(1.2)  # between levels (both 1.2)
    assert g(5e2, 1.0) == pytest.approx(1.1)  # linear in p toward 1 at p = 0
    assert g(1e3, 10.0) == pytest.approx(1.6)  # held beyond mu = 3 ...
    assert g.saturated(1e3, 10.0) and not g.saturated(1e3, 2.0)  # ... and flagged
    assert g(1e3, -1.0) == pytest.approx(g(1e3, 1.0))  # mirror symmetry


def test_branch_skips_the_unstable_part_past_a_limit_point():
    mu = np.array([0.0, 0.2, 0.4, 0.35, 0.3, 0.45, 0.6])
    gain = np.array([1.0, 1.05, 1.1, 1.2, 1.3, 1.4, 1.5])
    m, gn = _ramp(1e3, mu, gain).branch()
    assert np.array_equal(m, [0.0, 0.2, 0.4, 0.45, 0.6])
    assert np.array_equal(gn, [1.0, 1.05, 1.1, 1.4, 1.5])


# ---------------------------------------------------------------------------- fixed point
def test_local_shear_fixed_point_matches_the_closed_form():
    """G = 1 + c mu makes (*) linear: mu = (a + alpha) / (1 - a c), a = tau0 psi / p."""
    c, tau0, alpha = 0.2, 8.1e3, 0.1
    g = _linear_gain(c)
    p = np.array([2e3, 1e4, 5e4])
    psi = np.array([0.1, 0.3, 0.6])
    sol = solve_local_shear(p, psi, g, tau0, alpha)
    a = tau0 * psi / p
    expect = (a + alpha) / (1 - a * c)
    assert np.all(expect < 3)  # inside the table
    assert np.allclose(sol.mu, expect, rtol=1e-9)
    assert np.allclose(sol.gain, 1 + c * expect, rtol=1e-9)
    assert np.all(sol.converged) and not np.any(sol.saturated)


def test_directional_cell_feeds_the_coupling_consistently():
    g = _linear_gain(0.2)
    cell = HertzUnitCell(radius=50e-6, height=10e-6, spacing=200e-6, reduced_modulus=1e5)
    d = DirectionalCell(cell, g, tau0=8.1e3, alpha=0.1)
    p = np.geomspace(1e3, 3e4, 5)
    psi = cell.contact_fraction(p)
    sol = solve_local_shear(p, psi, g, 8.1e3, 0.1)
    assert np.allclose(d.contact_fraction(p), np.minimum(psi * sol.gain, d.max_fraction))
    assert d.transition_pressure == cell.transition_pressure  # delegated
    finger = Finger()
    base = predict_curve([0.5, 1.0], finger, cell)
    res = predict_curve([0.5, 1.0], finger, d)
    assert np.all(res.real_area > base.real_area) and np.all(res.mu > base.mu)
    # F_adh = tau0 A_re + alpha F still holds with the directional cell (Eqs. 2.2-2.3)
    f = np.array([0.5, 1.0])
    adh = adhesion_integral(f, finger.ridge_area(f), d, finger.tau0, finger.alpha, n_rings=24)
    assert np.allclose(adh, finger.tau0 * res.real_area + finger.alpha * f, rtol=1e-3)


# ---------------------------------------------------------------------------- hysteresis
def test_elliptical_greenwood_tabor_reduces_to_eq_2_4():
    for t in (0.0, 0.7, math.pi / 2):
        assert elliptical_hysteresis_force(1.3, 9e-3, 9e-3, 40e3, 0.1, t) == pytest.approx(
            hysteresis_force(1.3, 9e-3, 40e3, 0.1), rel=1e-12)
    assert hysteresis_direction_factor(50e-6, 50e-6, 20e-6, 0.4) == 1.0


def test_hertz_ellipse_satisfies_both_hertz_relations():
    from scipy.special import ellipe, ellipk

    rx, ry, load, e_star = 3e-3, 1e-3, 0.7, 2e5
    ax, ay = hertz_ellipse(load, rx, ry, e_star)
    a, b = max(ax, ay), min(ax, ay)
    m = 1 - (b / a) ** 2
    p0 = 3 * load / (2 * math.pi * a * b)
    k, e = ellipk(m), ellipe(m)
    coeff_a = p0 * b / (e_star * m * a * a) * (k - e)  # = 1/(2 R) along the long axis
    coeff_b = p0 * b / (e_star * m * a * a) * (a * a / (b * b) * e - k)
    assert (ax > ay) and coeff_a == pytest.approx(1 / (2 * rx), rel=1e-9)
    assert coeff_b == pytest.approx(1 / (2 * ry), rel=1e-9)
    ax2, ay2 = hertz_ellipse(8 * load, rx, ry, e_star)  # semi-axes scale as F^(1/3)
    assert (ax2 / ax, ay2 / ay) == pytest.approx((2.0, 2.0), rel=1e-9)
    near = hertz_ellipse(load, 1e-3 * (1 + 1e-4), 1e-3, e_star)  # continuous at the circle
    circ = (3 * load * 1e-3 / (4 * e_star)) ** (1 / 3)
    assert near == pytest.approx((circ, circ), rel=1e-4)


def test_elliptical_greenwood_tabor_is_the_work_integral():
    """Eq. 2.4e against direct integration of p (n . r) over the loaded half of the ellipse."""
    rx, ry, load, e_star, beta, t = 2e-3, 0.5e-3, 1.0, 1e5, 0.2, 0.6
    ax, ay = hertz_ellipse(load, rx, ry, e_star)
    p0 = 3 * load / (2 * math.pi * ax * ay)
    n = (math.cos(t) / rx, math.sin(t) / ry)

    def integrand(y: float, x: float) -> float:
        s = 1 - (x / ax) ** 2 - (y / ay) ** 2
        w = n[0] * x + n[1] * y
        return p0 * math.sqrt(max(s, 0.0)) * w if w > 0 else 0.0

    work, _ = dblquad(integrand, -ax, ax, lambda x: -ay * math.sqrt(max(0.0, 1 - (x / ax) ** 2)),
                      lambda x: ay * math.sqrt(max(0.0, 1 - (x / ax) ** 2)), epsabs=1e-14, epsrel=1e-9)
    assert elliptical_hysteresis_force(load, rx, ry, e_star, beta, t) == pytest.approx(beta * work, rel=1e-5)


def test_direction_factor_of_elongated_asperities():
    # sliding across the long axis (along the short semi-axis x) loses more than along it
    across = hysteresis_direction_factor(30e-6, 90e-6, 30e-6, 0.0)
    along = hysteresis_direction_factor(30e-6, 90e-6, 30e-6, math.pi / 2)
    assert across > 1.0 > along
    # the factor is the same for the mirrored and the reversed direction
    assert hysteresis_direction_factor(30e-6, 90e-6, 30e-6, math.pi) == pytest.approx(across)
    assert hysteresis_direction_factor(30e-6, 90e-6, 30e-6, -0.3) == pytest.approx(
        hysteresis_direction_factor(30e-6, 90e-6, 30e-6, 0.3))


def test_the_gain_enters_the_coupling_of_a_bem_cell():
    """Issue 31: a BEM cell integrates its own interpolated psi exactly (``disc_fraction``); the
    directional cell passed that on, so the coupling integrated the undeflected psi and the gain
    never entered (predict --direction gave the same real area across and along). The directional
    cell's A_re/A_fr is the disc average of its own psi G (Eq. 3.11), checked by Gauss-Legendre
    quadrature split at the transition (the kink of psi)."""
    from fingerpad.coupling import couple
    from fingerpad.micro.bem import BEMUnitCell
    from fingerpad.textures import spherical_caps

    tex = spherical_caps(radius=50e-6, height=10e-6, spacing=150e-6, grid=32)
    cell = BEMUnitCell(tex, 3e5, cache=False).prepare(50.0, 5e4)
    d = DirectionalCell(cell, _linear_gain(0.8), tau0=8.1e3, alpha=0.1)
    assert not hasattr(d, "disc_fraction")
    loads, ridge = np.array([0.2, 1.0]), np.array([2e-5, 5e-5])
    plain, directional = couple(loads, ridge, cell).area_ratio, couple(loads, ridge, d).area_ratio
    assert np.all(directional > 1.05 * plain)  # the gain enlarges the real area ...
    x, w = np.polynomial.legendre.leggauss(400)
    for f, a, r in zip(loads, ridge, directional):  # ... by exactly its disc average
        peak = 1.5 * f / a
        cuts = sorted({0.0, 1.0, *(q / peak for q in (cell.transition_pressure,) if q < peak)})
        exact = 0.0
        for lo, hi in zip(cuts[:-1], cuts[1:]):
            s_ = lo + (hi - lo) * (x + 1) / 2
            exact += (hi - lo) * float(np.sum(w * d.contact_fraction(peak * s_) * s_))
        assert r == pytest.approx(exact, rel=2e-4)
