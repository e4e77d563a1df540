"""The BEM unit cell's psi(p): bounded, monotone, its nodes exact solves, and the p/E* scaling
that lets one computed curve serve every skin modulus (a 16-point cell: milliseconds a solve)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import fingerpad as fp
from fingerpad import micro
from fingerpad.errors import FingerpadError

E = 0.4e6


@pytest.fixture(scope="module")
def cell():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tex = fp.make_texture("caps", radius=50e-6, height=10e-6, spacing=150e-6, grid=16)
    return micro.BEMUnitCell(tex, E, cache=False).prepare(50.0, 5e4)


def test_psi_bounded_and_monotone(cell):
    p = np.geomspace(1.0, 1e6, 200)
    psi = cell.contact_fraction(p)
    assert np.all((psi >= 0) & (psi <= 1))
    assert np.all(np.diff(psi) >= -1e-12)
    assert float(cell.contact_fraction(0.0)) == 0.0
    assert isinstance(cell, micro.UnitCellResponse)


def test_nodes_are_exact_solves(cell):
    nodes = cell.curve()
    solver = fp.HalfSpaceSolver(cell.texture, E)
    for p, psi in list(zip(nodes["pressure"], nodes["contact_fraction"]))[::4]:
        assert float(cell.contact_fraction(p)) == pytest.approx(psi, abs=1e-12)
        assert solver.solve_pressure(float(p)).contact_fraction == pytest.approx(psi, abs=2.0 / 256)
    assert np.all(np.diff(nodes["mean_gap"]) <= 1e-15), "more load, smaller gap"
    assert set(nodes["contact_state"]) <= {"asperity", "transition", "full"}


def test_states_in_order(cell):
    assert 0 < cell.transition_pressure < cell.full_contact_pressure
    lo, hi = cell.transition
    assert lo < hi and cell.transition_pressure == pytest.approx(math.sqrt(lo * hi))
    assert cell.interpolation_error >= 0


def test_modulus_scaling_is_exact(cell):
    """Linear elasticity: psi at (p, 2 E*) equals psi at (p / 2, E*); state pressures scale with E*."""
    double = cell.at_modulus(2 * E)
    p = np.geomspace(100.0, 5e4, 9)
    np.testing.assert_array_equal(double.contact_fraction(p), cell.contact_fraction(p / 2))
    assert double.transition_pressure == pytest.approx(2 * cell.transition_pressure, rel=1e-15)
    assert double.full_contact_pressure == pytest.approx(2 * cell.full_contact_pressure, rel=1e-15)
    # and it is what a solver at the other modulus computes
    solver = fp.HalfSpaceSolver(cell.texture, 2 * E)
    for pressure in (400.0, 4e3):
        assert float(double.contact_fraction(pressure)) == pytest.approx(
            solver.solve_pressure(pressure).contact_fraction, abs=max(cell.interpolation_error, 2.0 / 256) + 1e-3)
    for bad in (0.0, -1.0, math.inf):
        with pytest.raises(FingerpadError, match="modulus must be positive"):
            cell.at_modulus(bad)


def test_unprepared_cell_says_so():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tex = fp.make_texture("caps", radius=50e-6, height=10e-6, spacing=150e-6, grid=16)
    fresh = micro.BEMUnitCell(tex, E, cache=False)
    with pytest.raises(FingerpadError, match="unit cell not prepared"):
        fresh.transition_pressure
