"""The same command stores the same bits whatever the unit-cell cache held before (issue 31).

A cell's curve uses the nodes of the ranges it is prepared over -- the global grid nodes, the
state brackets' bisection inside them and the refinement of those -- never every node the cache
holds, and a node's value is a function of its pressure alone (solved cold, not warm-started
from whichever nodes a run happened to solve). Each test runs two cache histories and compares
the numbers bit for bit."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from fingerpad.micro.bem import BEMUnitCell
from fingerpad.micro.cache import CurveCache
from fingerpad.textures import spherical_caps

E = 2.0e5


def caps(grid: int = 32):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return spherical_caps(radius=100e-6, height=20e-6, spacing=175e-6, lattice="hexagonal", grid=grid)


def numbers(cell: BEMUnitCell) -> dict:
    """Everything a prediction reads of a cell, as bytes (bit-for-bit comparison)."""
    p = np.geomspace(1.0, 3e5, 97)
    return {
        "nodes": sorted((q, tuple(sorted(row.items()))) for q, row in cell._unit_points.items()),
        "psi": cell.contact_fraction(p).tobytes(),
        "disc": cell.disc_fraction(p).tobytes(),
        "states": (cell.transition, cell.full),
        "error": repr(cell.interpolation_error),
    }


def test_a_cells_curve_is_the_same_after_any_cache_history(tmp_path):
    cold = BEMUnitCell(caps(), E, cache=CurveCache(tmp_path / "cold")).prepare(3e2, 3e4)
    # another history: a wider range at another modulus (a population's members), then a range
    # that starts inside this one (its warm-start chain began elsewhere), then this range
    store = CurveCache(tmp_path / "used")
    BEMUnitCell(caps(), 2.5 * E, cache=store).prepare(10.0, 2e5)
    BEMUnitCell(caps(), E, cache=store).prepare(2e3, 1e5)
    used = BEMUnitCell(caps(), E, cache=store).prepare(3e2, 3e4)
    assert used.solves == 0  # every node it needs was in the cache ...
    assert len(used._known) > len(used._unit_points)  # ... among others it does not use
    assert numbers(used) == numbers(cold)


def test_a_node_is_a_function_of_its_pressure(tmp_path):
    """The grid nodes a range shares with another range have the same bits whichever range
    solved them first (no warm start from the node below, whose presence depends on history)."""
    a = BEMUnitCell(caps(), E, cache=False).prepare(3e2, 3e4)
    b = BEMUnitCell(caps(), E, cache=False).prepare(5e3, 3e4)
    shared = set(a._unit_points) & set(b._unit_points)
    assert len(shared) > 5
    assert all(a._unit_points[q] == b._unit_points[q] for q in shared)


STUDY = {
    "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um", "lattice": "hexagonal"},
    "material": {"modulus": "0.5GPa", "poisson": 0.4},
    "loads": {"range": "0.1N:4N:6", "log": True},
    "model": {"kind": "bem", "grid": 32},
}
SPREAD = {"size": 12, "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
          "ridge_fraction": {"distribution": "uniform", "low": 0.1, "high": 0.7}}


def _payload(pred) -> dict:
    """predict.json without what depends on the run rather than the command (time, solves)."""
    from fingerpad.study.outputs import prediction_json

    out = prediction_json(pred)
    out.pop("timings")
    out["inputs"].pop("cache")  # the two histories' folders
    for key in ("seconds", "solves", "cached"):
        out["cell"].pop(key)
    out["cell"]["resolution"].pop("solves")
    return out


def _study(cache, loads=None):
    from fingerpad.study.spec import study_from_dict

    return study_from_dict({**STUDY, "model": {**STUDY["model"], "cache": str(cache)},
                            **({} if loads is None else {"loads": {"values": loads}})})


def test_predict_after_a_population_run_is_bit_identical(tmp_path):
    from fingerpad.population import population_from_table, run_population
    from fingerpad.study.run import run_study

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cold = _payload(run_study(_study(tmp_path / "cold")))
        run_population(_study(tmp_path / "used"), population_from_table(SPREAD))
        run_study(_study(tmp_path / "used", loads=["1N", "50N"]))  # other loads: a wider range
        after = _payload(run_study(_study(tmp_path / "used")))
    assert after == cold


@pytest.mark.parametrize("grid", [16, None])
def test_a_population_sweep_point_is_the_same_on_a_cold_and_a_filled_cache(tmp_path, monkeypatch, grid):
    """A sweep point with a population (the unit a sweep stores) on an empty cache and again on
    the cache it filled: every stored array the same, bit for bit (the nominal's too, which the
    members' wider p/E* range used to shift). ``None``: the automatic grid."""
    from fingerpad.design.evaluate import evaluate_point
    from fingerpad.design.spec import sweep_from_dict

    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path / "cache"))
    model = {"kind": "bem", **({} if grid is None else {"grid": grid})}
    spec = sweep_from_dict({**{k: v for k, v in STUDY.items() if k != "loads"}, "model": model,
                            "sweep": {"loads": "0.1N:4N:5", "axes": {"spacing": ["175um", "250um"]}}},
                           population=SPREAD)

    def run():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = evaluate_point(spec.study_data(spec.assignment((0,))), spec.loads, [1e3, 1e4, 1e5],
                                 spec.population_payload())
        res.pop("seconds")
        return res

    first, again = run(), run()
    assert first["valid"] and first["solves"] > 0 and again["solves"] == 0
    first.pop("solves"), again.pop("solves")
    assert set(first) == set(again)
    for key in first:
        assert np.array_equal(np.asarray(first[key]), np.asarray(again[key]), equal_nan=first[key] is not None
                              and np.asarray(first[key]).dtype.kind == "f"), key


def test_a_node_does_not_depend_on_the_solver_s_past_work(tmp_path, monkeypatch):
    """The element-wise kernels a solver runs on are chosen from its grid alone, not from the
    work it has done: the compiled loops sum in another order than NumPy's (last bits), so a
    switch after so much work made a node's bits depend on how many nodes the run had to solve
    before it (those the cache lacked) -- at 512^2 after about 25 solves of a cell."""
    pytest.importorskip("numba")
    import fingerpad.contact.solver as solver_mod

    # a threshold of work passed within the first few solves of a grid-32 cell (raising=False:
    # a rule that has no such threshold passes as it is)
    monkeypatch.setattr(solver_mod, "COMPILED_AFTER_WORK", 32 * 32 * 20, raising=False)
    a = BEMUnitCell(caps(), E, cache=False).prepare(3e2, 3e4)
    b = BEMUnitCell(caps(), E, cache=False).prepare(5e3, 3e4)
    shared = set(a._unit_points) & set(b._unit_points)
    assert len(shared) > 5
    assert all(a._unit_points[q] == b._unit_points[q] for q in shared)


def test_an_entry_of_other_arithmetic_is_not_read(tmp_path, monkeypatch):
    """Two installations sharing a cache folder (the default ~/.cache/fingerpad), one with
    ducc0's FFTs and one with SciPy's, give their nodes different last bits: a cell keys its
    entry by its solver's arithmetic, so neither reads the other's and each gives its own
    bits whatever the folder held."""
    pytest.importorskip("ducc0")
    store = CurveCache(tmp_path / "shared")
    monkeypatch.setenv("FINGERPAD_FFT", "scipy")
    scipy_cell = BEMUnitCell(caps(), E, cache=store).prepare(3e2, 3e4)
    assert scipy_cell.solver.arithmetic.startswith("scipy/")
    monkeypatch.setenv("FINGERPAD_FFT", "ducc0")
    shared = BEMUnitCell(caps(), E, cache=store).prepare(3e2, 3e4)
    own = BEMUnitCell(caps(), E, cache=CurveCache(tmp_path / "own")).prepare(3e2, 3e4)
    assert shared.solver.arithmetic.startswith("ducc0/")
    assert shared.solves == own.solves > 0  # nothing read from the other installation's entry
    assert numbers(shared) == numbers(own)
    assert numbers(shared) != numbers(scipy_cell)  # (the case the key keeps apart)
