"""The layered skin's unit cell (issue 24): the modulus-free, scale-free cache with a layer.

With a layer, psi is a function of p/E1* at fixed t/Lx, moduli ratios and Poisson ratios: a cell
at (E1, E2, p) is the cell at (2 E1, 2 E2, 2 p), and a texture scaled in every length, the
layer's thickness included, is the same cell. Both must be served by one cache entry; a
half-space cell's key must stay the one it always was (its cache entries stay valid).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import fingerpad as fp
from fingerpad.contact import Layer
from fingerpad.micro import BEMUnitCell
from fingerpad.micro.bem import CURVE_TOL, DEFAULT_RTOL, POINTS_PER_DECADE, unit_cell_key, unit_layer, unit_texture
from fingerpad.micro.cache import CurveCache, content_key

E1, E2, NU = 0.4e6, 40e3, 0.49
E1_STAR = E1 / (1 - NU**2)
P_RANGE = (50.0, 5e4)


def caps(scale: float = 1.0):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fp.make_texture("caps", radius=50e-6 * scale, height=10e-6 * scale, spacing=150e-6 * scale, grid=16)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("layered-cells")


@pytest.fixture(scope="module")
def layered(folder):
    cell = BEMUnitCell(caps(), E1_STAR, cache=CurveCache(folder), layer=Layer(30e-6, E1, NU, E2, NU))
    return cell.prepare(*P_RANGE)


def test_doubled_moduli_and_pressure_are_the_same_cell_from_the_cache(folder, layered):
    assert layered.solves > 0
    double = BEMUnitCell(caps(), 2 * E1_STAR, cache=CurveCache(folder), layer=Layer(30e-6, 2 * E1, NU, 2 * E2, NU))
    assert double.key == layered.key
    double.prepare(2 * P_RANGE[0], 2 * P_RANGE[1])
    assert double.solves == 0, "the cache serves the doubled skin"
    p = np.geomspace(100.0, 4e4, 11)
    # p/E* is the same number bit for bit (factor 2): so is psi
    np.testing.assert_array_equal(double.contact_fraction(2 * p), layered.contact_fraction(p))
    assert double.transition_pressure == 2 * layered.transition_pressure
    # and a fresh solve at the doubled skin, without the cache, agrees with the scaled curve
    fresh = BEMUnitCell(caps(), 2 * E1_STAR, cache=False, layer=Layer(30e-6, 2 * E1, NU, 2 * E2, NU))
    fresh.prepare(2 * P_RANGE[0], 2 * P_RANGE[1])
    np.testing.assert_allclose(fresh.contact_fraction(2 * p), layered.contact_fraction(p), atol=1e-12)


def test_scaling_every_length_with_the_layer_keeps_psi(folder, layered):
    big = BEMUnitCell(caps(3.0), E1_STAR, cache=CurveCache(folder), layer=Layer(90e-6, E1, NU, E2, NU))
    assert big.key == layered.key
    big.prepare(*P_RANGE)
    assert big.solves == 0
    p = np.geomspace(100.0, 4e4, 11)
    np.testing.assert_array_equal(big.contact_fraction(p), layered.contact_fraction(p))
    # the cell's lengths are presented in metres of its own size
    assert big.curve()["mean_gap"][0] == pytest.approx(3 * layered.curve()["mean_gap"][0], rel=1e-12)


def test_another_thickness_ratio_or_modulus_ratio_is_another_cell(layered):
    thicker = BEMUnitCell(caps(), E1_STAR, cache=False, layer=Layer(60e-6, E1, NU, E2, NU))
    stiffer_base = BEMUnitCell(caps(), E1_STAR, cache=False, layer=Layer(30e-6, E1, NU, 2 * E2, NU))
    half_space = BEMUnitCell(caps(), E1_STAR, cache=False)
    keys = {layered.key, thicker.key, stiffer_base.key, half_space.key}
    assert len(keys) == 4
    # and the layer changes the answer: a stiff layer on soft tissue is softer than the layer alone
    half_space.prepare(*P_RANGE)
    assert layered.transition_pressure < 0.9 * half_space.transition_pressure


def test_half_space_key_is_the_one_it_always_was():
    """No layer adds nothing to the key: the cached half-space curves stay valid (no version bump).
    The curve's node tolerance (CURVE_TOL, looser than tol) joins it: such a curve is another entry."""
    tex = caps()
    unit = unit_texture(tex)
    before = content_key(unit.heights, cell="unit", size=unit.size, base_level=unit.base_level, tol=1e-8,
                         max_iter=5000, ppd=POINTS_PER_DECADE, rtol=DEFAULT_RTOL)
    assert unit_cell_key(tex, tol=1e-8, max_iter=5000, rtol=DEFAULT_RTOL) == before
    # a cell adds its solver's arithmetic (FFT engine and kernels; CACHE_VERSION 5)
    cell = BEMUnitCell(tex, 1e6, cache=False, curve_tol=0)
    arithmetic = cell.solver.arithmetic
    with_arithmetic = unit_cell_key(tex, tol=1e-8, max_iter=5000, rtol=DEFAULT_RTOL, arithmetic=arithmetic)
    assert cell.key == with_arithmetic != before
    assert BEMUnitCell(tex, 1e6, cache=False).key == unit_cell_key(tex, tol=1e-8, max_iter=5000, rtol=DEFAULT_RTOL,
                                                                   arithmetic=arithmetic, node_tol=CURVE_TOL) != before
    assert BEMUnitCell(tex, 1e6, cache=False, layer=Layer(30e-6, 1e6, NU, E2, NU)).key != with_arithmetic


def test_equal_moduli_are_the_homogeneous_cell():
    tex = caps()
    homog = BEMUnitCell(tex, E1_STAR, cache=False).prepare(*P_RANGE)
    same = BEMUnitCell(tex, E1_STAR, cache=False, layer=Layer(30e-6, E1, NU, E1, NU)).prepare(*P_RANGE)
    p = np.geomspace(100.0, 4e4, 11)
    np.testing.assert_allclose(same.contact_fraction(p), homog.contact_fraction(p), rtol=0, atol=1e-12)
    assert same.transition_pressure == pytest.approx(homog.transition_pressure, rel=1e-12)


def test_unit_layer_is_dimensionless():
    layer = Layer(30e-6, E1, NU, E2, 0.45)
    unit = unit_layer(layer, E1_STAR, 150e-6)
    assert unit.thickness == pytest.approx(0.2, rel=1e-12)
    assert unit.reduced_modulus == pytest.approx(1.0, rel=1e-12)
    assert unit.modulus / unit.substrate_modulus == pytest.approx(E1 / E2, rel=1e-12)
    assert (unit.poisson, unit.substrate_poisson) == (NU, 0.45)
    rigid = unit_layer(Layer(30e-6, E1, NU), E1_STAR, 150e-6)
    assert rigid.rigid_base
    assert unit_layer(None, E1_STAR, 150e-6) is None


def test_for_skin_reads_the_same_unit_cell_and_solves_another(layered):
    same = layered.for_skin(2 * E1_STAR, Layer(30e-6, 2 * E1, NU, 2 * E2, NU))
    assert same.contact_fraction(2e3) == layered.contact_fraction(1e3)
    other = layered.for_skin(E1_STAR, Layer(60e-6, E1, NU, E2, NU), P_RANGE)
    assert isinstance(other, BEMUnitCell) and other.key != layered.key and other.transition_pressure > 0
