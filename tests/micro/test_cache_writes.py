"""A unit cell's preparation writes the cache once, with the very nodes a cache-free cell computes;
a sweep's chunk takes the result its cell task computed instead of predicting the point again."""

from __future__ import annotations

import warnings

import pytest

from fingerpad.micro import cache
from fingerpad.micro.bem import BEMUnitCell
from fingerpad.textures import spherical_caps


@pytest.fixture(scope="module")
def cell_texture():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, lattice="hexagonal", grid=16)


def test_prepare_writes_the_cache_once_with_the_nodes_of_a_cache_free_cell(tmp_path, monkeypatch, cell_texture):
    updates: list[dict] = []
    real = cache.CurveCache.update

    def counted(self, key, new, check=None):
        updates.append(new)
        return real(self, key, new, check)

    monkeypatch.setattr(cache.CurveCache, "update", counted)
    store = cache.CurveCache(tmp_path / "cells")
    cached = BEMUnitCell(cell_texture, 2e5, cache=store).prepare(1e2, 1e5)
    assert len(updates) == 1  # nodes, refinements and both state brackets in one update
    assert cached.solves > 20 and len(updates[0]["points"]) == len(cached._unit_points)
    plain = BEMUnitCell(cell_texture, 2e5, cache=False).prepare(1e2, 1e5)
    assert cached._unit_points == plain._unit_points  # same nodes, same floats (JSON round-trips them)
    assert (cached.transition, cached.full) == (plain.transition, plain.full)
    again = BEMUnitCell(cell_texture, 2e5, cache=store).prepare(1e2, 1e5)
    assert again.solves == 0 and again._unit_points == plain._unit_points
    assert len(updates) == 1  # nothing new: nothing written
    wider = BEMUnitCell(cell_texture, 2e5, cache=store).prepare(1e1, 1e5)
    assert wider.solves > 0 and len(updates) == 2


def test_an_interrupted_prepare_keeps_what_it_had_stored(tmp_path, monkeypatch, cell_texture):
    cell = BEMUnitCell(cell_texture, 2e5, cache=cache.CurveCache(tmp_path))

    def interrupted(p_min, p_max):
        raise KeyboardInterrupt

    monkeypatch.setattr(cell, "_refine", interrupted)  # after the nodes and both state brackets
    with pytest.raises(KeyboardInterrupt):
        cell.prepare(1e2, 1e5)
    fresh = BEMUnitCell(cell_texture, 2e5, cache=cache.CurveCache(tmp_path))
    assert fresh._known and fresh._known == cell._known and set(cell._unit_points) <= set(fresh._known)
    assert fresh.transition == cell.transition and fresh.full == cell.full is not None


def test_a_chunk_takes_the_points_its_cell_tasks_predicted(monkeypatch):
    from fingerpad.design import evaluate

    evaluated = []
    monkeypatch.setattr(evaluate, "evaluate_point", lambda data, loads, ps, population=None: evaluated.append(data) or {"solves": 3})
    known = {(0, 1): {"solves": 7, "mu": "from the cell task"}}
    out = evaluate.evaluate_chunk([((0, 0), {"a": 0}), ((0, 1), {"a": 1})], [1.0], [1.0], known=known)
    assert out == [((0, 0), {"solves": 3}), ((0, 1), {"solves": 0, "mu": "from the cell task"})]
    assert evaluated == [{"a": 0}]  # only the point no cell task predicted


def test_the_nodes_read_are_those_of_the_cell_after_it_adds_more(cell_texture):
    """The node arrays every psi reads are kept until the cell's nodes change: a cell prepared
    over a wider range reads all its nodes, the new ones included."""
    import numpy as np

    cell = BEMUnitCell(cell_texture, 2e5, cache=False).prepare(1e3, 1e4)
    before = len(cell._nodes()[0])
    cell.contact_fraction(np.array([3e3]))
    cell.prepare(1e2, 1e5)
    ps, psi = cell._nodes()
    assert len(ps) == len(cell._unit_points) > before
    np.testing.assert_array_equal(ps, sorted(cell._unit_points))
    np.testing.assert_array_equal(psi, np.maximum.accumulate([cell._unit_points[p]["contact_fraction"] for p in ps]))
