"""A sweep axis over the skin modulus costs no extra unit cells: the cell is stored in p/E*
(docs/sweeps.md, "Cells shared across modulus axes"), so the points that differ only in E_s
share one cell, solved once, and prepared for all of them before any is predicted: what they
store does not depend on the order their chunks run in."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fingerpad.design.engine import run_sweep
from fingerpad.design.evaluate import cell_key
from fingerpad.design.spec import sweep_from_dict


def spec(cache, **axes):
    return sweep_from_dict({
        "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um"},
        "material": {"modulus": "0.5GPa", "poisson": 0.4},
        "model": {"kind": "bem", "grid": 16, "cache": str(cache)},
        "sweep": {"loads": "0.1N:4N:6", "chunk": 4, "axes": {"height": ["12um", "20um"], **axes}},
    })


def test_cell_key_ignores_the_moduli_not_the_shape(tmp_path):
    s = spec(tmp_path, skin_modulus=["0.2MPa", "0.5MPa"])
    keys = {(i, j): cell_key(s.study_data(s.assignment((i, j)))) for i in range(2) for j in range(2)}
    assert keys[0, 0] == keys[0, 1] and keys[1, 0] == keys[1, 1]  # skin modulus: same cell
    assert keys[0, 0] != keys[1, 0]  # height: another cell
    m = sweep_from_dict({**s.base, "sweep": {"loads": "1N", "axes": {"material_modulus": ["5MPa", "0.5GPa"]}}})
    assert cell_key(m.study_data(m.assignment((0,)))) == cell_key(m.study_data(m.assignment((1,))))


@pytest.fixture(scope="module")
def cluster():
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None,
                      silence_logs=50) as local:
        yield local.scheduler_address


def _cells(folder) -> tuple[int, int]:
    """Cache entries (cells) and the nodes they hold."""
    entries = list(folder.glob("*.json"))
    return len(entries), sum(len(json.loads(p.read_text())["points"]) for p in entries)


def test_a_skin_modulus_axis_solves_no_more_cells(tmp_path, cluster):
    """2 heights x 4 skin moduli solve the 2 cells of the 2 heights alone. The solves beyond
    those of the sweep without the axis are the nodes at the ends of the wider p/E* range the
    softer and stiffer skins reach (here 145 -> 153; before the cells were keyed by E*: 8 cells,
    596 solves). Every solve is a stored node: none is solved twice."""
    plain = run_sweep(spec(tmp_path / "plain"), tmp_path / "plain.zarr", scheduler=cluster)
    axis = run_sweep(spec(tmp_path / "axis", skin_modulus=["0.2MPa", "0.3MPa", "0.4MPa", "0.5MPa"]),
                     tmp_path / "axis.zarr", scheduler=cluster)
    assert not plain.failures and not axis.failures
    assert (plain.points, axis.points) == (2, 8)
    assert axis.cells == plain.cells == 2 and axis.cells_solved == plain.cells_solved == 2
    entries_plain, nodes_plain = _cells(tmp_path / "plain")
    entries_axis, nodes_axis = _cells(tmp_path / "axis")
    assert entries_axis == entries_plain == 2
    assert (plain.solves, axis.solves) == (nodes_plain, nodes_axis)
    # the 0.2-0.5 MPa range widens p/E* by a factor 2.5, 0.4 decade: ~5 nodes of 12 per decade per cell
    assert nodes_plain < nodes_axis <= nodes_plain + 2 * 6
    # every stored point is what a prediction of it reads from the filled cache, bit for bit and
    # without a solve: no point read the cell before another point of it added nodes
    from fingerpad.design.engine import sweep_pressures
    from fingerpad.design.evaluate import evaluate_point
    from fingerpad.design.store import open_sweep

    s = spec(tmp_path / "axis", skin_modulus=["0.2MPa", "0.3MPa", "0.4MPa", "0.5MPa"])
    ds = open_sweep(tmp_path / "axis.zarr").load()
    for index in np.ndindex(*s.shape):
        again = evaluate_point(s.study_data(s.assignment(index)), s.loads, sweep_pressures(s))
        assert again["solves"] == 0
        stored = ds.isel(dict(zip(s.dims, index)))
        for name in ("area_ratio", "mu", "psi"):
            np.testing.assert_array_equal(stored[name].values, again[name], err_msg=f"{index} {name}")


def _arrays(results):
    """The stored numbers of each point (``seconds`` and ``solves`` say how, not what)."""
    return {tuple(idx): {k: v for k, v in r.items() if k not in ("seconds", "solves")} for idx, r in results}


def _same(a, b) -> list[str]:
    """The (point, quantity) pairs whose values differ, NaNs equal, bit for bit."""
    import numpy as np

    return [f"{idx} {k}" for idx in a for k in a[idx]
            if not np.array_equal(np.asarray(a[idx][k]), np.asarray(b[idx][k]),
                                  equal_nan=np.asarray(a[idx][k]).dtype.kind == "f")]


def _in_order(s, cache, order):
    """A modulus-axis sweep done as the engine does it, without Dask: the cell task of the first
    point, then the other points, one chunk each, in ``order`` (indices)."""
    from fingerpad.design.evaluate import evaluate_chunk, prepare_cell
    from fingerpad.design.store import pressure_grid

    s.base["model"]["cache"] = str(cache)
    loads, ps = s.loads.tolist(), pressure_grid(1e3, 1e5).tolist()
    points = {(i,): s.study_data(s.assignment((i,))) for i in range(s.size)}
    first = prepare_cell(points[(0,)], loads, ps, None, (0,), [points[k] for k in sorted(points)])
    out = [((0,), first["result"])]
    for i in order:
        out += evaluate_chunk([((i,), points[(i,)])], loads, ps)
    return _arrays(out)


def test_a_shared_cell_gives_the_same_numbers_whatever_order_its_points_run_in(tmp_path):
    """Points sharing a cell through p/E* (here the skin modulus over a factor 5, each reaching
    nodes the others do not) store the same numbers, bit for bit, whichever order the chunks run
    in: the cell task prepares the cell for all of them first. Before, each point added the
    nodes of its own range's ends in its chunk, and a point read the curve with the nodes that
    the points before it had added (here A_re/A_fr moved by up to 2e-6 relative between the two
    orders, mu by 1.3e-6)."""
    s = sweep_from_dict({
        "texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um"},
        "material": {"modulus": "0.5GPa", "poisson": 0.4},
        "model": {"kind": "bem", "grid": 16},
        "sweep": {"loads": "0.1N:4N:6", "axes": {"skin_modulus": ["0.3MPa", "0.1MPa", "0.5MPa", "0.2MPa"]}},
    })
    forward = _in_order(s, tmp_path / "forward", [1, 2, 3])
    backward = _in_order(s, tmp_path / "backward", [3, 2, 1])
    assert set(forward) == {(0,), (1,), (2,), (3,)}
    assert _same(forward, backward) == []
    # what the cache holds afterwards is what a plain prediction of any point reads: the same numbers
    from fingerpad.design.evaluate import evaluate_point

    again = evaluate_point(s.study_data(s.assignment((3,))), s.loads.tolist(), [1e3, 1e4])
    assert again["solves"] == 0
    np.testing.assert_array_equal(again["area_ratio"], forward[(3,)]["area_ratio"])
