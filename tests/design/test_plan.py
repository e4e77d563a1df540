"""A sweep's plan apart from its executor (design/plan.py, design/executor.py): which cells, which
chunks, what waits for what, tested without a cluster; the engine run in this process stores the
same numbers, bit for bit, whichever order its tasks run in."""

from __future__ import annotations

import numpy as np

from fingerpad.design.engine import SweepReport, execute_plan, sweep_pressures
from fingerpad.design.evaluate import cell_key
from fingerpad.design.executor import InProcessExecutor
from fingerpad.design.plan import plan_sweep
from fingerpad.design.spec import sweep_from_dict
from fingerpad.design.store import SweepStore, chunk_slices, open_sweep


def spec(cache=None, chunk=2, **axes):
    return sweep_from_dict({
        "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um"},
        "material": {"modulus": "0.5GPa", "poisson": 0.4},
        "model": {"kind": "bem", "grid": 16, **({"cache": str(cache)} if cache else {})},
        "sweep": {"loads": "0.1N:4N:6", "chunk": chunk, "axes": axes},
    })


def test_the_plan_of_a_grid_with_shared_cells():
    """2 heights x 3 skin moduli, chunks of 2 along the modulus: one cell per height (the modulus
    shares it), its first point the lowest index; each chunk waits for the cells of its points;
    every point in exactly one chunk, in index order."""
    s = spec(height=["12um", "20um"], skin_modulus=["0.2MPa", "0.3MPa", "0.4MPa"])
    plan = plan_sweep(s)
    assert (plan.points, plan.done_before, plan.to_compute) == (6, 0, 6)
    keys = {idx: cell_key(s.study_data(s.assignment(idx))) for idx in np.ndindex(*s.shape)}
    assert list(plan.cells) == [keys[0, 0], keys[1, 0]]  # in the order their first points come
    for key, task in plan.cells.items():
        mine = sorted(idx for idx, k in keys.items() if k == key)
        assert task.index == mine[0] and task.data == s.study_data(s.assignment(mine[0]))
        assert list(task.sharing) == [s.study_data(s.assignment(idx)) for idx in mine]
        assert task.name == f"cell-{key[:16]}"
    assert [c.region for c in plan.chunks] == chunk_slices(s.shape, 2)
    points = [idx for c in plan.chunks for idx, _ in c.items]
    assert points == sorted(keys)  # each point once, in index order
    for chunk in plan.chunks:
        assert chunk.cells == tuple(sorted({keys[idx] for idx, _ in chunk.items}))
        # (0, 0:2) holds a cell's first point and a point that only reads it: a task of its own
        assert chunk.from_cells is False
    assert plan.chunks[0].label == "[0:1, 0:2]"


def test_chunks_of_first_points_are_written_from_their_cells():
    """A sweep over the texture's shape: every point has a cell of its own, so no chunk needs a
    task; each waits for its points' cells."""
    s = spec(height=["8um", "12um", "16um", "20um"], chunk=2)
    plan = plan_sweep(s)
    assert len(plan.cells) == 4 and all(c.from_cells for c in plan.chunks)
    assert list(plan.chunk_tasks()) == []
    waiting = plan.written_from_cells()
    assert sorted(waiting.values()) == [[0], [0], [1], [1]]
    assert plan.first_points() == {task.index: key for key, task in plan.cells.items()}


def test_a_resumed_plan_computes_what_is_left_and_shares_cells_with_done_points():
    """Points done before are not computed again, chunks all done are left out, and a cell is
    still prepared over every point that shares it, the done ones included (a resumed sweep
    stores what a sweep run at once would)."""
    s = spec(height=["12um", "20um"], skin_modulus=["0.2MPa", "0.3MPa", "0.4MPa"])
    done = np.zeros(s.shape, bool)
    done[0, 0] = done[0, 1] = True  # the first chunk of the first height
    done[1, 2] = True
    plan = plan_sweep(s, done)
    assert (plan.done_before, plan.to_compute) == (3, 3)
    assert [c.label for c in plan.chunks] == ["[0:1, 2:3]", "[1:2, 0:2]"]
    assert [idx for c in plan.chunks for idx, _ in c.items] == [(0, 2), (1, 0), (1, 1)]
    first = plan.cells[cell_key(s.study_data(s.assignment((0, 2))))]
    assert first.index == (0, 2)  # the first point left to compute
    assert len(first.sharing) == 3  # with (0, 0) and (0, 1), done before
    assert len(plan.cells[cell_key(s.study_data(s.assignment((1, 0))))].sharing) == 3


def _run(s, folder, order=None):
    pressures = sweep_pressures(s)
    store = SweepStore(folder / "s.zarr", s, pressures)
    store.create()
    executor = InProcessExecutor(order=order)
    report = execute_plan(plan_sweep(s), executor, store, s.loads, pressures, SweepReport(points=s.size))
    return report, executor, open_sweep(folder / "s.zarr").load()


def test_the_engine_in_this_process_stores_the_same_bits_in_any_order(tmp_path):
    """A modulus axis sharing one cell, chunks of one point: the plan run with its tasks in
    submission order and in reverse (every chunk task that is ready, last first) stores the same
    numbers, bit for bit, and each point what a prediction of it gives from the filled cache."""
    s = spec(tmp_path / "cache-a", chunk=1, skin_modulus=["0.3MPa", "0.1MPa", "0.5MPa", "0.2MPa"])
    forward, ran_forward, a = _run(s, tmp_path / "a")
    t = spec(tmp_path / "cache-b", chunk=1, skin_modulus=["0.3MPa", "0.1MPa", "0.5MPa", "0.2MPa"])
    backward, ran_backward, b = _run(t, tmp_path / "b", order=lambda ready: ready[-1])
    assert not forward.failures and not backward.failures
    assert forward.computed == backward.computed == 4 and forward.cells == 1 and forward.cells_solved == 1
    assert ran_forward.ran[0] == ran_backward.ran[0]  # the cell task first
    assert ran_forward.ran[1:] == list(reversed(ran_backward.ran[1:]))  # then the chunks, in two orders
    assert bool(a["done"].all()) and bool(b["done"].all())
    for name in ("area_ratio", "mu", "mu_rel", "psi", "critical_load_bem"):
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    from fingerpad.design.evaluate import evaluate_point

    again = evaluate_point(s.study_data(s.assignment((3,))), s.loads, sweep_pressures(s))
    assert again["solves"] == 0
    np.testing.assert_array_equal(a["area_ratio"].values[3], again["area_ratio"])


def test_a_failed_cell_fails_the_chunks_that_wait_for_it(tmp_path, monkeypatch):
    """A cell task that raises: every chunk of its points is named in the failures (those with a
    task and those written from the cell), the others are written."""
    import fingerpad.design.engine as engine

    s = spec(tmp_path / "cache", chunk=2, height=["12um", "20um"], skin_modulus=["0.2MPa", "0.3MPa", "0.4MPa"])
    bad = cell_key(s.study_data(s.assignment((1, 0))))
    prepare = engine.prepare_cell

    def failing(data, *args, **kwargs):
        if cell_key(data) == bad:
            raise RuntimeError("cell exploded")
        return prepare(data, *args, **kwargs)

    monkeypatch.setattr(engine, "prepare_cell", failing)
    report, _, ds = _run(s, tmp_path)
    assert sorted(report.failures) == ["chunk [1:2, 0:2]: RuntimeError('cell exploded')",
                                       "chunk [1:2, 2:3]: RuntimeError('cell exploded')"]
    assert report.computed == 3
    assert ds["done"].values.tolist() == [[True, True, True], [False, False, False]]


def test_planning_solves_and_writes_nothing(tmp_path):
    """Planning reads every point's study and cell key and nothing more: a 10 x 10 grid of cells
    plans without a solve (its cache folder is not even made)."""
    s = spec(tmp_path / "cache", spacing=[f"{v}um" for v in range(130, 230, 10)],
             height=[f"{v}um" for v in range(6, 26, 2)])
    plan = plan_sweep(s)
    assert plan.to_compute == 100 and len(plan.cells) == 100
    assert not (tmp_path / "cache").exists()
