"""The per-asperity Hertz cell (thesis Eqs. 3.1-3.6, 3.8-3.10) against its closed forms."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import fingerpad as fp
from fingerpad import macro, micro
from fingerpad.errors import FingerpadError
from fingerpad.micro import hertz as h

R, H, LAM, E1 = 50e-6, 10e-6, 150e-6, 0.4e6


@pytest.fixture
def cell():
    return micro.HertzUnitCell(radius=R, height=H, spacing=LAM, reduced_modulus=E1)


def test_critical_force_eq_3_3(cell):
    fc = 4 / 3 * E1 * math.sqrt(R * H**3)
    assert cell.critical_force == pytest.approx(fc, rel=1e-14)
    # at F_icrit the Hertz approach equals the cap height (that is what defines it)
    assert h.hertz_approach(fc, R, E1) == pytest.approx(H, rel=1e-12)
    assert cell.transition_pressure == pytest.approx(fc / LAM**2, rel=1e-14)
    assert cell.full_contact_pressure == math.inf


def test_contact_radius_and_approach_are_hertz():
    f = np.array([1e-4, 1e-3, 1e-2])
    a = np.asarray(h.hertz_contact_radius(f, R, E1))
    np.testing.assert_allclose(a, (3 * f * R / (4 * E1)) ** (1 / 3), rtol=1e-14)
    # delta = a^2 / R for a sphere on a flat
    np.testing.assert_allclose(h.hertz_approach(f, R, E1), a**2 / R, rtol=1e-12)


def test_psi_closed_form_and_saturation(cell):
    p = np.array([0.0, 10.0, 1e3, 1e4])
    a = (3 * p * LAM**2 * R / (4 * E1)) ** (1 / 3)
    np.testing.assert_allclose(cell.contact_fraction(p), np.minimum(math.pi * a**2 / LAM**2, 1.0), rtol=1e-13)
    ps = cell.saturation_pressure
    assert cell.contact_fraction(np.array([ps]))[0] == pytest.approx(1.0, rel=1e-12)
    assert cell.contact_fraction(np.array([10 * ps]))[0] == 1.0
    assert cell.breakpoints == (ps,)
    # psi ~ p^(2/3) below saturation
    lo = cell.contact_fraction(np.array([1.0, 8.0]))
    assert lo[1] / lo[0] == pytest.approx(4.0, rel=1e-12)
    assert isinstance(cell, micro.UnitCellResponse)


def test_critical_load_eq_3_6_constant_area(cell):
    area = 1e-4
    expected = 8 / 9 * E1 * math.sqrt(H**3 * R) * area / LAM**2
    assert fp.critical_load_hertz(area, radius=R, height=H, spacing=LAM, reduced_modulus=E1) == \
        pytest.approx(expected, rel=1e-14)
    assert cell.critical_load(area) == pytest.approx(expected, rel=1e-14)
    # at that load the centre asperity (1.5 x the mean, Eq. 3.5) carries exactly F_icrit
    assert h.centre_asperity_force(expected, area, LAM) == pytest.approx(cell.critical_force, rel=1e-12)


def test_critical_load_with_load_dependent_area(cell):
    """A_fr = c F^(2/3): F = k c F^(2/3), so F = (k c)^3 exactly."""
    k = 8 / 9 * E1 * math.sqrt(H**3 * R) / LAM**2
    c = 5e-5
    got = cell.critical_load(lambda f: c * f ** (2 / 3))
    assert got == pytest.approx((k * c) ** 3, rel=1e-10)
    with pytest.raises(FingerpadError, match=r"no critical load \(Eq. 3.6\) between"):
        cell.critical_load(lambda f: 1e-30 * f + 1e-30, load_range=(1.0, 2.0))
    with pytest.raises(FingerpadError, match="is not a positive area"):
        cell.critical_load(lambda f: -1.0)


def test_asperity_counts_and_forces():
    assert h.asperity_count(1e-4, 100e-6) == pytest.approx(1e4)
    assert h.asperity_force(2.0, 1e-4, 100e-6) == pytest.approx(2.0 / 1e4)
    assert h.centre_asperity_force(2.0, 1e-4, 100e-6) == pytest.approx(3.0 / 1e4)


def test_transition_zone_eqs_3_8_to_3_10(cell):
    area = 1e-4
    fcrit = cell.critical_load(area)
    fc = cell.critical_force
    # no zone below the critical load, the zone opens at it
    assert h.transition_area_fraction(0.5 * fcrit, area, LAM, fc) == 0.0
    assert h.transition_area_fraction(fcrit, area, LAM, fc) == pytest.approx(0.0, abs=1e-12)
    f = 4 * fcrit
    fi = f * LAM**2 / area
    frac = 1 - (2 / 3 * fc / fi) ** 2
    assert h.transition_area_fraction(f, area, LAM, fc) == pytest.approx(frac, rel=1e-12)
    assert h.transition_radius(f, area, LAM, fc) == pytest.approx(math.sqrt(area / math.pi * frac), rel=1e-12)
    # where the pad pressure 1.5 p_mean sqrt(1 - r^2/a^2) equals p_t: the same radius (Eq. 3.7)
    r = h.transition_radius(f, area, LAM, fc)
    assert macro.pad_pressure(r, f, area) == pytest.approx(cell.transition_pressure, rel=1e-10)


def test_cell_refusals():
    with pytest.raises(FingerpadError, match="cannot be higher"):
        micro.HertzUnitCell(radius=10e-6, height=20e-6, spacing=LAM, reduced_modulus=E1)
    with pytest.raises(FingerpadError, match="asperity spacing"):
        micro.HertzUnitCell(radius=R, height=H, spacing=0.0, reduced_modulus=E1)
    with pytest.raises(FingerpadError, match="reduced modulus"):
        h.hertz_contact_radius(1.0, R, -1.0)


def test_for_finger_uses_eq_3_4():
    finger = fp.get_finger("default")
    cell = micro.HertzUnitCell.for_finger(finger, radius=R, height=H, spacing=LAM, material_modulus=1e9,
                                          material_poisson=0.3)
    assert cell.reduced_modulus == pytest.approx(finger.micro_modulus(1e9, 0.3), rel=1e-14)


@pytest.mark.filterwarnings("ignore::fingerpad.errors.ResolutionWarning")
def test_hertz_cell_of_textures():
    square = fp.make_texture("caps", radius=R, height=H, spacing=LAM, grid=16)
    cell, note = micro.hertz_cell_for(square, E1)
    assert (cell.radius, cell.height, cell.spacing, note) == (R, H, LAM, None)
    hexa = fp.make_texture("caps", radius=R, height=H, spacing=LAM, lattice="hexagonal", grid=16)
    cell, note = micro.hertz_cell_for(hexa, E1)
    # the square spacing of the same asperity density: one cap per (sqrt(3)/2) s^2
    assert cell.spacing**2 == pytest.approx(math.sqrt(3) / 2 * LAM**2, rel=1e-14)
    assert "hexagonal" in note
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ridges = fp.make_texture("ridges", width=50e-6, height=H, spacing=100e-6, grid=16)
    assert not h.supports_hertz(ridges)
    with pytest.raises(FingerpadError, match=r"texture 'ridges' needs --model bem"):
        micro.hertz_cell_for(ridges, E1)
