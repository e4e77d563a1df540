"""A sweep axis over the skin modulus costs no extra unit cells: the cell is stored in p/E*
(docs/sweeps.md, "Cells shared across modulus axes"), so the points that differ only in E_s
share one cell, solved once."""

from __future__ import annotations

import json

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
