"""The half-grid companion of an error estimate: a lighter plan (issue 34), the reported cell's
bits untouched, the estimate floored at the widths the companion's brackets resolve."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad.coupling import couple
from fingerpad.errors import FingerpadError
from fingerpad.micro.bem import MAX_PSI_STEP, BEMUnitCell
from fingerpad.micro.resolution import COMPANION_OPTIONS, _state_error, choose_grid, choose_state_grids, state_width
from fingerpad.textures import spherical_caps

E = 0.395e6
LOADS = np.array([0.2, 1.0, 4.0])
RIDGE = 0.5 * np.pi * (3 * LOADS * 9e-3 / (4 * 40e3)) ** (2 / 3)  # the default finger's A_fr (m^2)
RANGE = (1e2, 2e5)

pytestmark = pytest.mark.filterwarnings("ignore::fingerpad.errors.ResolutionWarning")  # grid 16 on purpose


def make(nx: int):
    return spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, lattice="hexagonal", grid=nx)


def ratio(cell):
    return couple(LOADS, RIDGE, cell).area_ratio


@pytest.fixture(scope="module")
def cells():
    """The grid-16 cell prepared with the companion's plan and with the reported cell's."""
    light = BEMUnitCell(make(16), E, cache=False, **COMPANION_OPTIONS).prepare(*RANGE)
    full = BEMUnitCell(make(16), E, cache=False).prepare(*RANGE)
    return light, full


def test_the_full_contact_bracket_of_the_companion_holds_the_fine_bisections_bracket(cells):
    """The bisection to 1e-2 is the first steps of the one to 1e-3 (the same mid-points from the
    same grid interval), so the narrow bracket lies inside the wide one; the transition keeps
    its 1e-3."""
    light, full = cells
    lo, hi = light.full
    flo, fhi = full.full
    assert 1e-3 < (hi - lo) / hi <= 1e-2 and (fhi - flo) / fhi <= 1e-3
    assert lo <= flo <= fhi <= hi
    assert light.transition == full.transition  # the same bisection, bit for bit
    assert state_width(light, "full") == 1e-2 and state_width(light, "transition") == light.rtol == 1e-3
    assert light.key != full.key  # a bracket of another width: another cache entry


def test_the_companion_refines_less_and_its_nodes_are_the_full_plans(cells):
    """Refinement to psi steps of 0.06: a subset of the nodes refined to 0.04 (each refinement
    bisects the intervals whose step is too large, the coarser ones among them), every step
    inside the range within 0.06, and fewer nodes."""
    light, full = cells
    ps, psi = light._nodes()
    assert set(ps) < set(full._nodes()[0])
    inside = (ps[1:] >= RANGE[0] / E) & (ps[:-1] <= RANGE[1] / E) & (ps[1:] / ps[:-1] > 1 + 2 * light.rtol)
    steps = np.diff(psi)[inside]
    assert steps.max() <= COMPANION_OPTIONS["psi_step"]
    # the refinement alone (the full-contact bracket's width apart) leaves nodes out
    refined = BEMUnitCell(make(16), E, cache=False, psi_step=COMPANION_OPTIONS["psi_step"]).prepare(*RANGE)
    assert set(refined._nodes()[0]) < set(full._nodes()[0])
    assert light.solves < refined.solves < full.solves


def test_choose_grid_prepares_only_the_first_companion_lighter():
    """The first grid's companion takes the companion's plan; the cell reported keeps the full
    plan and has the bits of a cell prepared alone; after a doubling the companion is the grid
    before, fully prepared."""
    narrow = (1e3, 3e4)  # a short range: the doubling is what is tested (estimate 3.7 % at 32, 2.4 % at 64)
    choice = choose_grid(make, make(32), E, narrow, ratio, target=0.03, cell_options={"cache": False})
    assert [g for g, _ in choice.history] == [32, 64]
    first = choice.cells[16]
    assert first.psi_step == COMPANION_OPTIONS["psi_step"] and first.full_rtol == COMPANION_OPTIONS["full_rtol"]
    for cell in (choice.cell, choice.coarse):  # grid 64 reported, grid 32 its companion
        assert cell.psi_step == MAX_PSI_STEP and cell.full_rtol == cell.rtol
    alone = BEMUnitCell(make(32), E, cache=False).prepare(*narrow)  # the first grid reported
    assert np.array_equal(alone._nodes()[0], choice.coarse._nodes()[0])
    assert np.array_equal(alone._nodes()[1], choice.coarse._nodes()[1])
    assert alone.full == choice.coarse.full and alone.transition == choice.coarse.transition


def test_a_state_estimate_is_at_least_the_companions_bracket_width(cells):
    """Below the companion's bracket width the change is not resolved: the estimate says that
    width, not less; the choice of the state grids reads the companion's brackets."""
    light, full = cells
    assert _state_error(full, light, "full") >= 1e-2
    assert _state_error(full, full, "full") == full.rtol  # no change, the fine width
    choices, _ = choose_state_grids(make, make(32), E, target=None, cell_options={"cache": False},
                                    cells={16: light})
    assert choices["full"].coarse is light and choices["full"].error >= 1e-2
    assert math.isclose(choices["full"].coarse_pressure, light.full_contact_pressure)


def test_a_load_estimates_floor_is_the_wider_brackets_load_change(cells):
    """The load's estimate is at least the load change of the wider bracket's width, the
    companion's 1e-2 for full contact (as the pressure's), the cell's own 1e-3 without one."""
    from fingerpad.micro.resolution import StateChoice
    from fingerpad.study.run import _load_floor

    light, full = cells
    load = lambda p: (p / 1e3) ** 1.5  # noqa: E731  (a Hertz-like pad: F ~ p^(3/2))
    with_companion = StateChoice("full", full, light, _state_error(full, light, "full"), None)
    alone = StateChoice("full", full, None, math.nan, None)
    assert _load_floor(load, with_companion) == pytest.approx(1.01**1.5 - 1, rel=1e-9)
    assert _load_floor(load, alone) == pytest.approx(1.001**1.5 - 1, rel=1e-9)


def test_bad_companion_settings_are_refused():
    with pytest.raises(FingerpadError, match="full_rtol"):
        BEMUnitCell(make(16), E, cache=False, full_rtol=0.0)
    with pytest.raises(FingerpadError, match="psi_step"):
        BEMUnitCell(make(16), E, cache=False, psi_step=1.5)
