"""Micro scale and coupling: Hertz asperities, unit-cell protocol, disc integral, critical load."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import pytest
from scipy.integrate import quad

from fingerpad.coupling import adhesion_integral, couple, critical_load, predict_curve
from fingerpad.errors import FingerpadError, ResolutionWarning
from fingerpad.finger import get_finger
from fingerpad.micro.hertz import (
    HertzUnitCell,
    asperity_count,
    asperity_force,
    centre_asperity_force,
    critical_asperity_force,
    critical_load_hertz,
    hertz_approach,
    transition_area_fraction,
    transition_radius,
)
from fingerpad.micro.response import PowerLawUnitCell, UnitCellResponse

E1 = 0.3e6 / (1 - 0.49**2)  # skin on a rigid texture, Eq. 3.4
LOADS = np.geomspace(0.1, 4.0, 15)


def eq_3_6(e1: float, h: float, r: float, lam: float, area: float) -> float:
    return 8 / 9 * e1 * math.sqrt(h**3 * r) * area / lam**2


@dataclass(frozen=True)
class FlatCell:
    """A smooth flat: the skin touches everywhere at any pressure (psi = 1)."""

    transition_pressure: float = 1e-12
    full_contact_pressure: float = 1e-12

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        return np.ones_like(np.asarray(p, dtype=float))


# --------------------------------------------------------------------------------------------
# per-asperity relations
# --------------------------------------------------------------------------------------------


def test_asperity_count_force_and_transition_force():
    area, lam, load = 4e-5, 100e-6, 2.0
    assert asperity_count(area, lam) == pytest.approx(4000.0, rel=1e-14)
    assert asperity_force(load, area, lam) == pytest.approx(load / 4000.0, rel=1e-14)
    assert centre_asperity_force(load, area, lam) == pytest.approx(1.5 * load / 4000.0, rel=1e-14)
    h, r = 10e-6, 20e-6
    f_crit = critical_asperity_force(h, r, E1)
    assert hertz_approach(f_crit, r, E1) == pytest.approx(h, rel=1e-13)  # Eq. 3.3


def test_hertz_cell_protocol_and_psi():
    cell = HertzUnitCell(radius=20e-6, height=10e-6, spacing=100e-6, reduced_modulus=E1)
    assert isinstance(cell, UnitCellResponse)
    assert isinstance(PowerLawUnitCell(1e-3, 0.5), UnitCellResponse)
    assert isinstance(FlatCell(), UnitCellResponse)
    assert cell.full_contact_pressure == math.inf
    p = np.array([500.0, 5e3])
    fi = p * cell.spacing**2
    a = (3 * fi * cell.radius / (4 * E1)) ** (1 / 3)
    np.testing.assert_allclose(cell.contact_fraction(p), math.pi * a**2 / cell.spacing**2, rtol=1e-14)
    assert cell.contact_fraction(np.array([1.01 * cell.saturation_pressure]))[0] == 1.0
    assert cell.contact_fraction(np.array([0.99 * cell.saturation_pressure]))[0] < 1.0
    with pytest.raises(FingerpadError):
        HertzUnitCell(radius=5e-6, height=10e-6, spacing=100e-6, reduced_modulus=E1)


# --------------------------------------------------------------------------------------------
# the coupling integral
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("m", [0.2, 2 / 3, 1.0, 1.7])
def test_couple_power_law_closed_form(m):
    area = 4.5e-5
    loads = np.array([0.1, 0.7, 2.0, 4.0])
    p_peak = 1.5 * loads.max() / area
    c = 0.5 / p_peak**m  # psi stays below 0.5: never saturates
    res = couple(loads, area, PowerLawUnitCell(c, m))
    a = math.sqrt(area / math.pi)
    expected = 2 * math.pi * a**2 * c * (1.5 * loads / area) ** m / (m + 2)
    np.testing.assert_allclose(res.real_area, expected, rtol=1e-10, atol=0)
    np.testing.assert_allclose(res.real_pressure, loads / expected, rtol=1e-10)
    assert np.all(res.transition_radius == 0) and not np.any(res.centre_past_transition)


def test_couple_saturating_power_law_splits_at_the_kink():
    m, c, area = 0.6, 2e-3, 4e-5
    cell = PowerLawUnitCell(c, m)
    p_full = c ** (-1 / m)
    loads = np.array([1.0, 2.0, 3.0])
    peak = 1.5 * loads / area
    assert np.all(peak > p_full)
    s_sat = p_full / peak  # psi = c (peak s)^m below, 1 above
    expected = area * 2 * (c * peak**m * s_sat ** (m + 2) / (m + 2) + (1 - s_sat**2) / 2)
    res = couple(loads, area, cell)
    np.testing.assert_allclose(res.real_area, expected, rtol=1e-10)
    a = math.sqrt(area / math.pi)
    np.testing.assert_allclose(res.full_contact_radius, a * np.sqrt(1 - s_sat**2), rtol=1e-13)
    assert np.all(res.centre_in_full_contact)


def test_couple_flat_surface_gives_ridge_area():
    area = np.array([1e-5, 3e-5, 6e-5])
    res = couple(np.array([0.2, 1.0, 3.0]), area, FlatCell())
    np.testing.assert_allclose(res.real_area, area, rtol=1e-13)
    np.testing.assert_allclose(res.area_ratio, 1.0, rtol=1e-13)
    np.testing.assert_allclose(res.full_contact_radius, res.ridge_radius, rtol=1e-12)


def test_couple_hertz_cell_matches_adaptive_quadrature():
    cell = HertzUnitCell(radius=100e-6, height=10e-6, spacing=100e-6, reduced_modulus=E1)
    load, area = 3.0, 3e-5
    assert 1.5 * load / area > cell.saturation_pressure  # the capped centre is exercised
    a = math.sqrt(area / math.pi)

    def integrand(r: float) -> float:
        p = 1.5 * load / area * math.sqrt(max(1 - (r / a) ** 2, 0.0))
        return float(cell.contact_fraction(np.array([p]))[0]) * 2 * math.pi * r

    r_sat = a * math.sqrt(1 - (cell.saturation_pressure / (1.5 * load / area)) ** 2)
    expected = sum(quad(integrand, lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
                   for lo, hi in ((0, r_sat), (r_sat, a)))
    assert couple(load, area, cell).real_area == pytest.approx(expected, rel=1e-9)
    # coarse rings already converge: the grading, not brute force, carries the accuracy
    assert couple(load, area, cell, n_rings=6).real_area == pytest.approx(expected, rel=1e-8)


def test_adhesion_integral_equals_global_adhesion():
    cell = HertzUnitCell(radius=20e-6, height=10e-6, spacing=100e-6, reduced_modulus=E1)
    loads, area = np.array([0.2, 1.0, 3.0]), 4e-5
    tau0, alpha = 8.1e3, 0.1
    res = couple(loads, area, cell)
    np.testing.assert_allclose(adhesion_integral(loads, area, cell, tau0, alpha),
                               tau0 * res.real_area + alpha * loads, rtol=1e-12)


def test_couple_rejects_bad_input():
    cell = PowerLawUnitCell(1e-3, 0.5)
    with pytest.raises(FingerpadError):
        couple(np.array([1.0, -1.0]), 1e-5, cell)
    with pytest.raises(FingerpadError):
        couple(1.0, 0.0, cell)
    with pytest.raises(FingerpadError, match="not a unit-cell response"):
        couple(1.0, 1e-5, object())  # type: ignore[arg-type]

    @dataclass(frozen=True)
    class BadCell:
        transition_pressure: float = 1e3
        full_contact_pressure: float = 2e3

        def contact_fraction(self, p: np.ndarray) -> np.ndarray:
            return 2.0 * np.ones_like(p)

    with pytest.raises(FingerpadError, match="outside"):
        couple(1.0, 1e-5, BadCell())


# --------------------------------------------------------------------------------------------
# critical load (3.6) and zones (3.8-3.10)
# --------------------------------------------------------------------------------------------


def test_critical_load_constant_ridge_area_is_eq_3_6():
    h, r, lam, area = 10e-6, 20e-6, 100e-6, 4e-5
    cell = HertzUnitCell(radius=r, height=h, spacing=lam, reduced_modulus=E1)
    expected = eq_3_6(E1, h, r, lam, area)
    assert critical_load(cell, area) == pytest.approx(expected, rel=1e-12)
    assert critical_load_hertz(area, radius=r, height=h, spacing=lam, reduced_modulus=E1) == \
        pytest.approx(expected, rel=1e-14)
    # at the critical load the centre asperity carries exactly F_icrit (Eq. 3.5)
    assert centre_asperity_force(expected, area, lam) == pytest.approx(cell.critical_force, rel=1e-12)


@pytest.mark.parametrize("n", [0.3, 2 / 3])
def test_critical_load_power_law_ridge_area_solved_consistently(n):
    h, r, lam, k = 8e-6, 25e-6, 80e-6, 5e-5
    cell = HertzUnitCell(radius=r, height=h, spacing=lam, reduced_modulus=E1)
    factor = eq_3_6(E1, h, r, lam, 1.0)
    expected = (factor * k) ** (1 / (1 - n))  # F = factor k F^n

    def ridge_area(f):
        return k * f**n

    assert critical_load(cell, ridge_area) == pytest.approx(expected, rel=1e-12)
    assert cell.critical_load(ridge_area) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(eq_3_6(E1, h, r, lam, ridge_area(expected)), rel=1e-12)


def test_predict_curve_critical_load_with_finger_ridge_area():
    finger = get_finger("default")
    h, r, lam = 20e-6, 50e-6, 100e-6
    cell = HertzUnitCell.for_finger(finger, radius=r, height=h, spacing=lam)
    # A_fr = 0.5 pi (3 R F / (4 E))^(2/3) = k F^(2/3)
    k = 0.5 * math.pi * (3 * finger.radius / (4 * finger.modulus)) ** (2 / 3)
    expected = (eq_3_6(cell.reduced_modulus, h, r, lam, 1.0) * k) ** 3
    assert 0.1 < expected < 4.0  # inside the touch range
    curve = predict_curve(np.array([0.5 * expected, 2 * expected]), finger, cell)
    assert curve.critical_load_hertz == pytest.approx(expected, rel=1e-12)
    assert curve.critical_load == pytest.approx(expected, rel=1e-12)
    assert list(curve.centre_past_transition) == [False, True]
    assert curve.transition_radius[0] == 0 and curve.transition_radius[1] > 0


def test_critical_load_errors():
    cell = HertzUnitCell(radius=20e-6, height=10e-6, spacing=100e-6, reduced_modulus=E1)
    with pytest.raises(FingerpadError, match="no critical load"):
        critical_load(cell, 4e-5, load_range=(1.0, 2.0))
    with pytest.raises(FingerpadError, match="no critical load"):
        critical_load_hertz(lambda f: 4e-5 * f**0.5, radius=20e-6, height=10e-6, spacing=100e-6,
                            reduced_modulus=E1, load_range=(100.0, 200.0))
    with pytest.raises(FingerpadError, match="no finite transition"):
        critical_load(FlatCell(math.inf, math.inf), 4e-5)
    with pytest.raises(FingerpadError):
        critical_load(cell, lambda f: -1.0)


def test_stiff_texture_low_load_stays_in_asperity_contact():
    finger = get_finger("default")
    # tall, closely spaced caps on a rigid material: transition far above the load
    cell = HertzUnitCell.for_finger(finger, radius=50e-6, height=40e-6, spacing=100e-6)
    loads = np.array([0.1, 0.5, 1.0])
    res = couple(loads, finger.ridge_area(loads), cell)
    assert np.all(res.peak_pressure < cell.transition_pressure)
    np.testing.assert_array_equal(res.transition_radius, 0.0)
    assert not np.any(res.centre_past_transition)


def test_soft_texture_high_load_transition_zone_matches_eq_3_9_3_10():
    finger = get_finger("soft").with_overrides(skin_modulus=0.2e6)
    h, r, lam = 3e-6, 30e-6, 150e-6
    cell = HertzUnitCell.for_finger(finger, radius=r, height=h, spacing=lam, material_modulus=1e6,
                                    material_poisson=0.5)  # silicone-like texture
    loads = np.array([2.0, 3.0, 4.0])
    area = finger.ridge_area(loads)
    res = couple(loads, area, cell)
    assert np.all(res.centre_past_transition)
    f_icrit = cell.critical_force
    fi = loads * lam**2 / area  # Eq. 3.2
    frac = 1 - (2 / 3 * f_icrit / fi) ** 2  # Eq. 3.9
    assert np.all((frac > 0.1) & (frac < 1))
    expected = np.sqrt(area / math.pi) * np.sqrt(frac)  # Eq. 3.10
    np.testing.assert_allclose(res.transition_radius, expected, rtol=1e-12)
    np.testing.assert_allclose(transition_area_fraction(loads, area, lam, f_icrit), frac, rtol=1e-12)
    np.testing.assert_allclose(transition_radius(loads, area, lam, f_icrit), expected, rtol=1e-12)
    assert np.all(res.full_contact_radius == 0)  # Hertz cannot give full contact


def test_predict_curve_fields():
    finger = get_finger("ridged")
    cell = HertzUnitCell.for_finger(finger, radius=20e-6, height=10e-6, spacing=100e-6)
    curve = predict_curve(LOADS, finger, cell)
    for name in ("load", "gross_area", "ridge_area", "real_area", "area_ratio", "ridge_radius",
                 "transition_radius", "full_contact_radius", "mu", "mu_ref", "mu_normalised"):
        assert getattr(curve, name).shape == LOADS.shape, name
    assert np.all(curve.real_area < curve.ridge_area) and np.all(curve.ridge_area < curve.gross_area)
    assert np.all(curve.mu < curve.mu_ref)  # less real area than on the flat
    assert np.all(curve.transition_radius <= curve.ridge_radius)
    no_ref = predict_curve(LOADS, finger, PowerLawUnitCell(1e-3, 0.5), reference=False)
    assert no_ref.mu_ref is None and no_ref.mu_normalised is None and no_ref.critical_load_hertz is None
    assert set(no_ref.as_dict()) >= {"mu", "critical_load"}
    with pytest.raises(FingerpadError):
        predict_curve(LOADS, "default", cell)  # type: ignore[arg-type]
    # a transition beyond the searched loads is reported as NaN, not an exception
    tall = HertzUnitCell.for_finger(finger, radius=1e-3, height=1e-3, spacing=50e-6)
    assert math.isnan(predict_curve(LOADS, finger, tall).critical_load)


@pytest.fixture(scope="module")
def bem_caps():
    from fingerpad import textures
    from fingerpad.micro.bem import BEMUnitCell

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResolutionWarning)  # a coarse cell: the integral is the point
        tex = textures.spherical_caps(radius=50e-6, height=10e-6, spacing=100e-6, lattice="square", grid=16)
    return BEMUnitCell(tex, 0.3e6, cache=False).prepare(50.0, 2e6)


def _disc_mean_by_quad(cell, peak: float) -> float:
    """``2 int_0^1 psi(peak s) s ds`` by adaptive quadrature, split at every node of the cell's
    interpolated curve and at its state pressures (the kinks of the interpolant)."""
    nodes = np.asarray(cell.base.curve()["pressure"] if hasattr(cell, "base") else cell.curve()["pressure"])
    if hasattr(cell, "factor"):
        nodes = nodes * cell.factor
    cuts = sorted({float(p) / peak for p in (*nodes, cell.transition_pressure, cell.full_contact_pressure)
                   if 0 < p < peak})
    edges = [0.0, *cuts, 1.0]

    def f(s: float) -> float:
        return float(cell.contact_fraction(np.array([peak * s]))[0]) * s

    return 2.0 * sum(quad(f, a, b, epsabs=0.0, epsrel=1e-13, limit=200)[0] for a, b in zip(edges[:-1], edges[1:]))


@pytest.mark.parametrize("factor", [1.0, 1.7])
def test_couple_bem_cell_matches_adaptive_quadrature(bem_caps, factor):
    # The coupling integrates the BEM cell's interpolated psi(p) exactly up to round-off. The
    # graded quadrature split only at the state pressures was off by ~1e-4 here (kinks at the nodes).
    cell = bem_caps if factor == 1.0 else bem_caps.at_modulus(factor * bem_caps.modulus)
    loads = np.geomspace(0.05, 20.0, 13)
    ridge = 4e-5 * (loads / 1.0) ** 0.3
    got = couple(loads, ridge, cell).area_ratio
    ref = np.array([_disc_mean_by_quad(cell, 1.5 * f / a) for f, a in zip(loads, ridge)])
    assert np.max(np.abs(got / ref - 1.0)) < 1e-12


def test_predict_curve_without_critical_loads_gives_the_same_curve():
    """critical_loads=False skips the two root searches and nothing else: every other field is
    the same array, bit for bit (a Hertz cell, which also has the Eq. 3.6 load)."""
    from fingerpad.coupling import predict_curve
    from fingerpad.finger import get_finger
    from fingerpad.micro.hertz import HertzUnitCell

    finger = get_finger("default")
    cell = HertzUnitCell.for_finger(finger, radius=50e-6, height=18e-6, spacing=100e-6)
    loads = np.geomspace(0.05, 5.0, 17)
    full = predict_curve(loads, finger, cell)
    light = predict_curve(loads, finger, cell, critical_loads=False)
    assert math.isfinite(full.critical_load) and full.critical_load_hertz is not None
    assert math.isnan(light.critical_load) and light.critical_load_hertz is None
    for name, value in full.as_dict().items():
        if name not in ("critical_load", "critical_load_hertz"):
            np.testing.assert_array_equal(getattr(light, name), value, err_msg=name)
