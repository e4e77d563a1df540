"""One prediction, one transition: where an adhesive cell reports its pulled-in transition
extrapolated to a vanishing pixel (docs/model.md 6.6, "The curve with the reported transition"),
psi(p), the zones and the critical load all put the jump there.

The default cell at w 0.3 J/m^2 on grids 16, 32 and 64 (~5 s): the caps' contacts pull the skin
onto the base, and into full contact, from about three ranges; the grid's own jump (9.5 kPa on
64) lies below the reported one (15.0 kPa).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from fingerpad.materials import reduced_modulus
from fingerpad.micro.adhesive_cell import AdhesiveUnitCell
from fingerpad.micro.pull_in import adopt_extrapolated, extrapolated_states
from fingerpad.study.run import centre_state
from fingerpad.textures import spherical_caps

E = reduced_modulus(0.3e6, 0.49, 0.5e9, 0.4)  # the default finger on PE: 0.3945 MPa
#: psi at or above this is full contact (a cell "full" is at most 1 % open)
FULL = 0.99


def default_cell(grid: int):
    return spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, lattice="hexagonal", grid=grid)


@pytest.fixture(scope="module")
def cells() -> dict[int, AdhesiveUnitCell]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the coarse grids are coarse on purpose
        out = {g: AdhesiveUnitCell(default_cell(g), E, work_of_adhesion=0.3, cache=False).prepare()
               for g in (16, 32, 64)}
    assert all(c.pulled_in for c in out.values())
    return out


@pytest.fixture
def reported(cells):
    """The grid-64 cell reporting its extrapolated states (and the grid-32 cell its own, from 16)."""
    got = adopt_extrapolated(cells, 64)
    yield cells[64], got
    for c in cells.values():
        for name in ("transition", "full"):
            c.adopt_pressure(name, None)


def test_adopting_is_the_extrapolation_and_the_half_grid_adopts_its_own(cells, reported):
    c64, got = reported
    assert got == extrapolated_states(cells[64], cells[32], cells[16])
    assert c64.transition_pressure == got["transition"][0] == c64.full_contact_pressure
    # the half grid reports its own extrapolation (from 32 and 16): the estimate compares like with like
    assert cells[32].transition_pressure == extrapolated_states(cells[32], cells[16])["transition"][0]
    assert c64.own_state_pressure("transition") < c64.transition_pressure < 32e3


def test_psi_and_the_states_agree_at_every_pressure(reported):
    cell, _ = reported
    p = np.geomspace(1e2, 1e5, 3001)
    psi = cell.contact_fraction(p)
    states = np.array([centre_state(float(q), cell) for q in p])
    # full contact where psi is (at most 1 % open) and only there; asperity contact below
    assert np.array_equal(states == "full", psi >= FULL)
    assert np.all(psi[states == "asperity"] < FULL)
    assert np.all(np.diff(psi) >= -1e-12)  # the loading branch never loses contact


def test_psi_jumps_at_the_reported_transition(reported):
    cell, _ = reported
    t = cell.transition_pressure
    own_lo, own_hi = cell.transition
    below, at = cell.contact_fraction(np.array([t * (1 - 1e-9), t]))
    assert below < 0.6 and at >= FULL  # the jump into full contact, there
    # below the grid's own jump psi is the grid's own branch; between it and the reported one
    # the branch continued at its slope, rising, below full contact
    ps, psi = cell._nodes()
    below_own = ps[(ps > 0) & (ps * cell.modulus < own_lo)]
    assert np.array_equal(cell.contact_fraction(below_own * cell.modulus), cell._own_fraction(below_own))
    mid = np.geomspace(own_hi, t * (1 - 1e-6), 20)
    cont = cell.contact_fraction(mid)
    assert np.all(np.diff(cont) > 0) and np.all(cont < FULL) and cont[0] > psi[ps * cell.modulus < own_lo][-1]
    # the coupling is told where psi kinks and jumps
    assert min(abs(b / t - 1) for b in cell.breakpoints if b > 0) < 1e-12


def test_a_cell_reporting_its_own_transition_keeps_its_curve(cells):
    cell = cells[64]
    p = np.geomspace(1e2, 1e5, 301)
    own = cell.contact_fraction(p)
    cell.adopt_pressure("transition", cell.own_state_pressure("transition"))
    try:
        assert np.array_equal(cell.contact_fraction(p), own)  # the same bits
    finally:
        cell.adopt_pressure("transition", None)


def test_a_prediction_puts_its_zones_and_critical_load_where_psi_jumps(tmp_path):
    # the README caps and the default finger at w 0.3 J/m2 on grid 32 (its half 16 extrapolated
    # with it): the state at the pad centre is full contact exactly where the cell's psi there is,
    # and the critical load's centre pressure is where psi jumps (~5 s)
    from fingerpad.micro.adhesive_pad import adhesive_pad
    from fingerpad.study.run import run_study
    from fingerpad.study.spec import study_from_dict

    study = study_from_dict({
        "texture": {"name": "caps", "radius": 100e-6, "height": 20e-6, "spacing": 175e-6, "lattice": "hexagonal"},
        "material": {"modulus": 0.5e9, "poisson": 0.4}, "finger": {"work_of_adhesion": 0.3},
        "model": {"kind": "bem", "grid": 32, "cache": str(tmp_path)},
        "loads": {"values": [float(f) for f in np.geomspace(0.002, 0.1, 15)]}})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pred = run_study(study)
    cell, curve = pred.cell, pred.bem
    assert cell.pulled_in and cell.transition_pressure > cell.own_state_pressure("transition")
    centre = adhesive_pad(study.finger, cell).centre_pressure(curve.load, curve.ridge_area)
    psi = cell.contact_fraction(centre)
    states = np.array(pred.states())
    assert {"asperity", "full"} <= set(states)  # the loads straddle the jump
    assert np.array_equal(states == "full", psi >= FULL)
    # the critical load: its centre pressure is the reported transition, where psi jumps
    crit = pred.critical_load["bem"]
    pad = adhesive_pad(study.finger, cell)
    pc = pad.centre_pressure(np.array([crit]), pad.areas(np.array([crit]))[1])
    assert float(pc[0]) == pytest.approx(cell.transition_pressure, rel=1e-6)
    below, above = cell.contact_fraction(np.array([0.999, 1.001]) * float(pc[0]))
    assert below < 0.6 and above >= FULL
    # the zone map at its load says what psi says at its centre
    z = pred.zones
    assert (z["contact_state"] == "full") == bool(cell.contact_fraction(np.array([z["peak_pressure"]]))[0] >= FULL)


def test_the_branch_is_continued_at_its_slope_away_from_the_precursor_of_its_jump():
    # a branch rising at 0.08 per e-fold of pressure, steepening sharply over the last 10 % before
    # the grid's own jump (as the default cell's does at w 0.3 J/m2: 0.06-0.10, then 0.13-0.33):
    # the continuation takes the branch's slope, not the precursor's
    from fingerpad.micro.reported_curve import jump_shift
    from fingerpad.micro.unit_key import POINTS_PER_DECADE

    step = 10.0 ** (1.0 / POINTS_PER_DECADE)
    nodes = 10.0 ** (np.arange(-40, -10) / POINTS_PER_DECADE)
    own_lo = float(nodes[-8]) * 1.01  # the own jump just past a node
    onset = 0.9 * own_lo

    def own(q):
        q = np.asarray(q, float)
        psi = 0.2 + 0.08 * np.log(q / nodes[0]) + 2.0 * np.log(np.maximum(q / onset, 1.0))
        return np.where(q > own_lo, 1.0, psi)

    loading = {"transition": (own_lo, own_lo * 1.001), "full": (own_lo, own_lo * 1.001)}
    a, b, fb, t, f, slope = jump_shift(nodes, own, loading, 1.3 * own_lo, own_lo, 1.3 * own_lo)
    assert a == float(nodes[-8]) and t == f == pytest.approx(1.3 * own_lo)
    assert a / 2 > nodes[0] and a / step < onset < a  # the span [a / 2, a / step] lies on the branch
    assert slope == pytest.approx(0.08, rel=1e-9)
