"""Unit-cell response psi(p): interpolation accuracy, content-keyed cache, concurrent writers."""

from __future__ import annotations

import math
import multiprocessing as mp

import numpy as np
import pytest

from fingerpad.contact import HalfSpaceSolver
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.micro.cache import CurveCache
from fingerpad.textures import flat, sinusoid, spherical_caps

E = 1.0e6


def caps64():
    return spherical_caps(radius=50e-6, height=10e-6, spacing=150e-6, grid=64)


def test_interpolated_curve_matches_direct_solves(tmp_path) -> None:
    tex = caps64()
    cell = BEMUnitCell(tex, E, cache=CurveCache(tmp_path)).prepare(1e2, 1e5)
    solver = HalfSpaceSolver(tex, E)
    err = cell.interpolation_error
    assert 0 <= err < 0.1
    for p in (3.3e2, 2.2e3, 4.7e4):
        direct = solver.solve_pressure(p).contact_fraction
        assert abs(float(cell.contact_fraction(p)) - direct) <= max(err, 2.0 / tex.heights.size)
    # states: below the transition pressure the cell is in asperity contact, above in transition
    assert solver.solve_pressure(0.99 * cell.transition[0]).contact_state == "asperity"
    assert solver.solve_pressure(1.01 * cell.transition[1]).contact_state != "asperity"
    assert cell.transition_pressure < cell.full_contact_pressure


def test_westergaard_cell_response(tmp_path) -> None:
    n, lam, h = 256, 1e-4, 0.5e-6  # amplitude h: peak-to-valley 2h
    tex = sinusoid(amplitude=h, wavelength=lam, grid=n)
    p_star = math.pi * E * h / lam
    cell = BEMUnitCell(tex, E, cache=CurveCache(tmp_path)).prepare(1e-3 * p_star, 0.99 * p_star)
    p = np.array([0.01, 0.1, 0.5, 0.9]) * p_star
    exact = 2 / math.pi * np.arcsin(np.sqrt(p / p_star))
    assert np.max(np.abs(cell.contact_fraction(p) - exact)) < 3.0 / n + cell.interpolation_error
    assert abs(cell.full_contact_pressure / p_star - 1) < 0.01
    assert float(cell.contact_fraction(1.1 * p_star)) == 1.0


def test_flat_cell_is_always_in_full_contact() -> None:
    cell = BEMUnitCell(flat(size=1e-4, grid=16), E, cache=False).prepare(1.0, 1e4)
    assert np.all(cell.contact_fraction(np.array([1e-3, 1.0, 1e5])) == 1.0)
    assert cell.transition_pressure == 0.0


def test_cache_reuses_and_extends(tmp_path) -> None:
    tex = caps64()
    first = BEMUnitCell(tex, E, cache=CurveCache(tmp_path)).prepare(1e3, 1e4)
    assert first.solves > 0
    again = BEMUnitCell(tex, E, cache=CurveCache(tmp_path)).prepare(1e3, 1e4)
    assert again.solves == 0
    wider = BEMUnitCell(tex, E, cache=CurveCache(tmp_path)).prepare(1e3, 1e5)
    assert set(first.points) < set(wider.points)
    # no node is computed twice (but for the warm start of each new bracket's bisection)
    assert 0 < wider.solves <= len(wider.points) - len(first.points) + 2
    # one stored curve in p/E* serves another modulus: twice E* over twice the pressures solves nothing
    other = BEMUnitCell(tex, 2 * E, cache=CurveCache(tmp_path)).prepare(2e3, 2e4)
    assert other.solves == 0 and other.key == first.key
    taller = BEMUnitCell(spherical_caps(radius=50e-6, height=12e-6, spacing=150e-6, grid=64), E,
                         cache=CurveCache(tmp_path))
    assert taller.prepare(1e3, 1e4).solves > 0  # another shape is other content, another key
    assert len(list(tmp_path.glob("*.json"))) == 2


def _worker(args):
    folder, lo, hi = args
    cell = BEMUnitCell(caps64(), E, cache=CurveCache(folder)).prepare(lo, hi)
    return sorted(cell.points)


def test_concurrent_writers_merge(tmp_path) -> None:
    ranges = [(str(tmp_path), 1e2, 1e3), (str(tmp_path), 1e3, 1e4), (str(tmp_path), 1e4, 1e5)]
    with mp.get_context("spawn").Pool(3) as pool:
        parts = pool.map(_worker, ranges)
    union = set().union(*map(set, parts))
    merged = BEMUnitCell(caps64(), E, cache=CurveCache(tmp_path))
    # nothing lost: every process's nodes are in the entry (a cell's curve uses those of the
    # ranges it prepares, not all it finds)
    assert {q * merged.modulus for q in merged._known} >= union
    assert len(list(tmp_path.glob("*.tmp"))) == 0


def test_unprepared_cell_says_so() -> None:
    from fingerpad.errors import FingerpadError

    cell = BEMUnitCell(caps64(), E, cache=False)
    with pytest.raises(FingerpadError, match="prepare"):
        cell.contact_fraction(1e3)


def test_modulus_scaling_matches_direct_solves(tmp_path) -> None:
    """psi depends on p/E* only: a cell computed at E* answers for 2.5 E* without solving."""
    tex = caps64()
    cell = BEMUnitCell(tex, E, cache=CurveCache(tmp_path)).prepare(1e2, 1e5)
    scaled = cell.at_modulus(2.5 * E)
    solver = HalfSpaceSolver(tex, 2.5 * E)
    for p in (2.5e3, 2.5e4):
        assert abs(float(scaled.contact_fraction(p)) - solver.solve_pressure(p).contact_fraction) <= max(
            cell.interpolation_error, 2.0 / tex.heights.size)
    assert scaled.transition_pressure == pytest.approx(2.5 * cell.transition_pressure)


def test_curve_tolerance_keeps_the_curve_and_the_states() -> None:
    """The curve's nodes at CURVE_TOL (with the refinement's warm starts) against every solve at
    tol 1e-8: the state brackets are the same (their bisection keeps tol) and psi agrees within
    its interpolation error's 1/10 or a pixel, whichever is larger; the curves are separate cache
    entries."""
    from fingerpad.micro.bem import CURVE_TOL

    tex = caps64()
    loose = BEMUnitCell(tex, E, cache=False).prepare(1e2, 1e5)
    tight = BEMUnitCell(tex, E, cache=False, curve_tol=0).prepare(1e2, 1e5)
    assert loose.node_tol == CURVE_TOL > tight.node_tol == tight.tol == 1e-8
    assert loose.key != tight.key
    assert loose.transition == pytest.approx(tight.transition, rel=1e-12)
    assert loose.full == pytest.approx(tight.full, rel=1e-12)
    p = np.geomspace(1e2, 1e5, 40)
    diff = np.abs(loose.contact_fraction(p) - tight.contact_fraction(p))
    assert diff.max() <= max(tight.interpolation_error / 10, 1.0 / tex.heights.size)
    with pytest.raises(Exception, match="curve_tol"):
        BEMUnitCell(tex, E, cache=False, curve_tol=-1.0)
