"""One solved curve serves every modulus and every uniform scale of a texture: the BEM cell is
stored as the unit cell (pressures over E*, lengths over the cell length), keyed without either.

Checks: exact p/E* invariance (the solver's and the cache's), the cache serving the second
modulus without a solve, geometric similarity, the stored quantities' scaling, and a prediction
at E_s 0.2 MPa after one at 0.3 MPa solving only the pressure range the first did not reach."""

from __future__ import annotations

import dataclasses
import json
import warnings

import numpy as np
import pytest

from fingerpad.contact import HalfSpaceSolver
from fingerpad.micro.bem import BEMUnitCell, unit_cell_key, unit_texture
from fingerpad.micro.cache import CurveCache
from fingerpad.textures import Texture, spherical_caps

E = 0.4e6


def caps(scale: float = 1.0, grid: int = 32, height: float = 10e-6) -> Texture:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a coarse grid on purpose: milliseconds a solve
        return spherical_caps(radius=50e-6 * scale, height=height * scale, spacing=150e-6 * scale, grid=grid)


def test_the_solver_is_invariant_under_p_over_e():
    """Linear elasticity, rigid texture: (E*, p) and (2 E*, 2 p) are the same contact problem."""
    tex = caps()
    for p in (2e2, 3e3, 4e4):
        one = HalfSpaceSolver(tex, E).solve_pressure(p)
        two = HalfSpaceSolver(tex, 2 * E).solve_pressure(2 * p)
        assert two.contact_fraction == one.contact_fraction
        assert two.contact_state == one.contact_state
        assert two.mean_gap == pytest.approx(one.mean_gap, rel=1e-9, abs=1e-9 * tex.peak_to_valley)
        assert two.max_pressure == pytest.approx(2 * one.max_pressure, rel=1e-9)


def test_a_cell_at_twice_the_modulus_is_served_from_the_first(tmp_path):
    """psi at (E*, p) equals psi at (2 E*, 2 p) bit for bit, and the second cell solves nothing."""
    store = CurveCache(tmp_path)
    first = BEMUnitCell(caps(), E, cache=store).prepare(1e2, 1e5)
    assert first.solves > 0
    second = BEMUnitCell(caps(), 2 * E, cache=store).prepare(2e2, 2e5)
    assert second.solves == 0 and second.key == first.key
    assert len(list(tmp_path.glob("*.json"))) == 1
    p = np.geomspace(10.0, 1e6, 301)  # below, inside and above the computed nodes
    np.testing.assert_array_equal(second.contact_fraction(2 * p), first.contact_fraction(p))
    assert second.transition_pressure == pytest.approx(2 * first.transition_pressure, rel=1e-15)
    assert second.full_contact_pressure == pytest.approx(2 * first.full_contact_pressure, rel=1e-15)
    # the nodes as presented: pressures and peak pressures scale with E*, the mean gap does not
    a, b = first.curve(), second.curve()
    np.testing.assert_allclose(b["pressure"], 2 * a["pressure"], rtol=1e-15)
    np.testing.assert_allclose(b["max_pressure"], 2 * a["max_pressure"], rtol=1e-15)
    np.testing.assert_array_equal(b["mean_gap"], a["mean_gap"])
    np.testing.assert_array_equal(b["contact_fraction"], a["contact_fraction"])


def test_the_stored_curve_holds_no_modulus(tmp_path):
    """The entry's nodes are p/E* (the same file whichever modulus solved it), its gaps over Lx."""
    tex = caps()
    BEMUnitCell(tex, E, cache=CurveCache(tmp_path / "a")).prepare(1e3, 1e4)
    BEMUnitCell(tex, 3 * E, cache=CurveCache(tmp_path / "b")).prepare(3e3, 3e4)
    (fa,), (fb,) = (tmp_path / "a").glob("*.json"), (tmp_path / "b").glob("*.json")
    assert fa.name == fb.name
    a, b = json.loads(fa.read_text()), json.loads(fb.read_text())
    assert set(a["points"]) == set(b["points"])
    for q in a["points"]:
        assert a["points"][q]["contact_fraction"] == b["points"][q]["contact_fraction"]
        assert 0 <= a["points"][q]["mean_gap"] < tex.peak_to_valley / tex.size[0]  # in units of Lx
    assert max(float(q) for q in a["points"]) < 1.0  # pressures in units of E*, not Pa


def test_a_uniformly_scaled_texture_shares_the_curve(tmp_path):
    """Geometric similarity: all lengths times 1.7 (same grid in pixels) is the same unit cell;
    psi(p) is the same, the mean gap 1.7 times larger, and no solve is needed."""
    store = CurveCache(tmp_path)
    small, large = caps(), caps(1.7)
    assert unit_cell_key(small, tol=1e-8, max_iter=5000, rtol=1e-3) == unit_cell_key(large, tol=1e-8, max_iter=5000,
                                                                                    rtol=1e-3)
    first = BEMUnitCell(small, E, cache=store).prepare(1e2, 1e5)
    scaled = BEMUnitCell(large, E, cache=store).prepare(1e2, 1e5)
    assert scaled.solves == 0
    p = np.geomspace(1e2, 1e5, 50)
    np.testing.assert_array_equal(scaled.contact_fraction(p), first.contact_fraction(p))
    np.testing.assert_allclose(scaled.curve()["mean_gap"], 1.7 * first.curve()["mean_gap"], rtol=1e-12)
    # and it is what a solve of the scaled texture itself gives
    for q in (3e2, 1e4):
        direct = HalfSpaceSolver(large, E).solve_pressure(q).contact_fraction
        tolerance = max(first.interpolation_error, 2.0 / large.heights.size)
        assert abs(float(scaled.contact_fraction(q)) - direct) <= tolerance
    # another shape (taller caps), or the same shape on another grid, is another cell
    assert unit_cell_key(caps(height=12e-6), tol=1e-8, max_iter=5000, rtol=1e-3) != first.key
    assert unit_cell_key(caps(grid=64), tol=1e-8, max_iter=5000, rtol=1e-3) != first.key


def test_the_unit_texture():
    tex = caps()
    unit = unit_texture(tex)
    assert unit.size[0] == 1.0 and unit.size[1] == pytest.approx(tex.size[1] / tex.size[0], rel=1e-12)
    assert float(unit.heights.min()) == 0.0
    np.testing.assert_allclose(unit.heights, (tex.heights - tex.heights.min()) / tex.size[0],
                               atol=2e-9 * tex.peak_to_valley / tex.size[0])
    assert unit_texture(unit).heights.tobytes() == unit.heights.tobytes()  # idempotent
    # a rigid shift of the heights is the same cell; a measured map's base level is part of it
    shifted = dataclasses.replace(tex, heights=tex.heights + 3e-6)
    key = unit_cell_key(tex, tol=1e-8, max_iter=5000, rtol=1e-3)
    assert unit_cell_key(shifted, tol=1e-8, max_iter=5000, rtol=1e-3) == key
    based = dataclasses.replace(tex, base_level=float(tex.heights.min()) + 1e-6)
    assert unit_cell_key(based, tol=1e-8, max_iter=5000, rtol=1e-3) != key
    assert unit_cell_key(tex, tol=1e-7, max_iter=5000, rtol=1e-3) != key


def _study(e_s: str, cache) -> dict:
    return {
        "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um"},
        "finger": {"skin_modulus": e_s},
        "loads": {"values": [0.3, 1.0, 3.0]},
        "model": {"kind": "bem", "grid": 32, "cache": str(cache)},
    }


def test_a_second_skin_modulus_solves_no_new_cell(tmp_path):
    """A prediction at E_s 0.2 MPa after one at 0.3 MPa on the same texture finds the same cache
    entries (the cell and its half-grid companion) and solves only the nodes of the pressure range
    (in p/E*) the first did not cover: its pressures over E* are 1.5 times higher. The state
    brackets are searched on the global p/E* grid, so they are the first's: none is solved again."""
    from fingerpad.study.run import run_study
    from fingerpad.study.spec import study_from_dict

    cache = tmp_path / "cells"
    first = run_study(study_from_dict(_study("0.3MPa", cache)))
    entries = sorted(p.name for p in cache.glob("*.json"))
    before = {p.name: set(json.loads(p.read_text())["points"]) for p in cache.glob("*.json")}
    second = run_study(study_from_dict(_study("0.2MPa", cache)))
    assert sorted(p.name for p in cache.glob("*.json")) == entries  # no new cell
    after = {p.name: set(json.loads(p.read_text())["points"]) for p in cache.glob("*.json")}
    new = {name: {float(q) for q in after[name] - before[name]} for name in after}
    assert second.resolution["solves"] == sum(map(len, new.values()))  # each solve a new node
    lo, hi = (p / first.reduced_modulus for p in first.pressure_range)
    assert all(q < lo or q > hi for qs in new.values() for q in qs)  # outside the first's range
    assert second.cell.transition == pytest.approx(
        tuple(b * second.reduced_modulus / first.reduced_modulus for b in first.cell.transition), rel=1e-15)
    # and the second is what a cold prediction at 0.2 MPa gives: the same state brackets, and psi
    # to the interpolation error (the warm curve holds the first's nodes as well)
    cold = run_study(study_from_dict(_study("0.2MPa", tmp_path / "cold")))
    assert second.critical_load["bem"] == pytest.approx(cold.critical_load["bem"], rel=1e-12)
    assert second.full_contact_load["bem"] == pytest.approx(cold.full_contact_load["bem"], rel=1e-12)
    np.testing.assert_allclose(second.bem.area_ratio, cold.bem.area_ratio, rtol=0,
                               atol=max(cold.cell.interpolation_error, second.cell.interpolation_error))
