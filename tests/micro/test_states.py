"""Contact-state pressures of a BEM cell: wherever they lie, whatever was asked, whatever is cached."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.contact import FULL_CONTACT_TOL, HalfSpaceSolver
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.micro.cache import CurveCache
from fingerpad.textures import dimples, flat, spherical_caps

E = 0.395e6


def caps(grid: int = 32):
    return spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, lattice="hexagonal", grid=grid)


def test_state_pressures_do_not_depend_on_the_range_or_the_cache(tmp_path):
    """The default-study cell: transition and full contact bracketed the same from a narrow low
    range (fresh cache), from a wide range, and from a cache filled by another range."""
    fresh = BEMUnitCell(caps(), E, cache=False).prepare(1e2, 2e3)
    shared = CurveCache(tmp_path)
    wide = BEMUnitCell(caps(), E, cache=shared).prepare(1e3, 1e6)
    again = BEMUnitCell(caps(), E, cache=shared).prepare(1e2, 2e3)  # reads the wide one's nodes
    for cell in (wide, again):
        assert cell.transition == pytest.approx(fresh.transition, rel=1e-12)
        assert cell.full == pytest.approx(fresh.full, rel=1e-12)
    # both found, far above the narrow range that was asked for, each to rtol
    assert 2e3 < fresh.transition_pressure < fresh.full_contact_pressure < math.inf
    for lo, hi in (fresh.transition, fresh.full):
        assert (hi - lo) / hi <= fresh.rtol


def test_states_bracket_what_the_solver_says():
    cell = BEMUnitCell(caps(), E, cache=False).prepare(1e3, 1e4)
    solver = HalfSpaceSolver(caps(), E)
    lo, hi = cell.transition
    assert solver.solve_pressure(lo).contact_state == "asperity"
    assert solver.solve_pressure(hi).contact_state != "asperity"
    lo, hi = cell.full
    assert solver.solve_pressure(lo).contact_state != "full"
    res = solver.solve_pressure(hi)
    assert res.contact_state == "full" and 1 - res.contact_fraction <= FULL_CONTACT_TOL


def test_dimples_transition_found_beyond_the_range():
    """Dimples: the skin reaches the dimple bottoms at a pressure far above the loads asked for."""
    tex = dimples(radius=100e-6, depth=10e-6, spacing=150e-6, grid=32)
    cell = BEMUnitCell(tex, E, cache=False).prepare(10.0, 100.0)
    assert 100.0 < cell.transition_pressure < math.inf
    assert cell.transition_pressure <= cell.full_contact_pressure


def test_full_contact_pressure_converges_with_the_grid():
    """Full contact = at most 1 % open: at a sharp foot this converges (every-pixel contact does not)."""
    fulls = [BEMUnitCell(caps(g), E, cache=False).prepare(3e4, 3e5).full_contact_pressure for g in (32, 64, 128)]
    d1, d2 = fulls[1] - fulls[0], fulls[2] - fulls[1]
    assert 0 < d2 < 0.5 * d1  # differences shrink: convergence (measured 37 and 13 kPa)
    assert d2 / fulls[2] < 0.1


def test_flat_cell_is_in_full_contact_at_any_pressure():
    cell = BEMUnitCell(flat(size=100e-6, grid=16), E, cache=False).prepare(1.0, 1e4)
    assert cell.flat and cell.transition_pressure == 0 and cell.full_contact_pressure == 0
    np.testing.assert_allclose(cell.contact_fraction(np.array([1.0, 1e3])), 1.0)
