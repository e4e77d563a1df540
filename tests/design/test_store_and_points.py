"""A sweep without a cluster: one point evaluated at a 16-point cell equals ``predict`` at that
point; the Zarr store laid out, written chunk by chunk, reopened; store helpers."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from fingerpad.design import evaluate, store
from fingerpad.design.spec import sweep_from_dict
from fingerpad.errors import FingerpadError

BASE = {
    "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "150um"},
    "material": {"modulus": "0.5GPa", "poisson": 0.4},
    "model": {"kind": "hertz"},
}


def spec(**table):
    return sweep_from_dict({**BASE, "sweep": {"loads": "0.1N:4N:6", **table}})


def test_pressure_grid_nodes():
    grid = store.pressure_grid(15.0, 2e3, per_decade=12)
    assert grid[0] <= 15.0 and grid[-1] >= 2e3
    np.testing.assert_allclose(np.diff(np.log10(grid)), 1 / 12, rtol=1e-12)
    # nodes are the global grid 10^(k/12): two ranges share their common nodes
    other = store.pressure_grid(100.0, 1e3)
    assert set(np.round(np.log10(other) * 12).astype(int)) <= set(np.round(np.log10(grid) * 12).astype(int))


def test_chunk_slices_cover_every_point_once():
    shape = (3, 10)
    slices = store.chunk_slices(shape, 4)
    count = np.zeros(shape, int)
    for sl in slices:
        count[sl] += 1
        assert sl[0].stop - sl[0].start == 1 and sl[1].stop - sl[1].start <= 4
    assert np.all(count == 1)
    assert len(slices) == 3 * 3
    assert store.chunk_slices((5,), 8) == [(slice(0, 5),)]


def test_evaluate_a_hertz_point_equals_eq_3_6():
    s = spec(axes={"spacing": ["150um"]})
    data = s.study_data(s.assignment((0,)))
    out = evaluate.evaluate_point(data, s.loads, store.pressure_grid(10.0, 1e5))
    assert out["valid"] and out["reason"] == ""
    from fingerpad import critical_load_hertz
    from fingerpad.study import study_from_dict

    st = study_from_dict(data)
    expected = critical_load_hertz(st.finger.ridge_area, radius=50e-6, height=10e-6, spacing=150e-6,
                                   reduced_modulus=st.reduced_modulus)
    assert out["critical_load_hertz"] == pytest.approx(expected, rel=1e-12)
    assert math.isnan(out["critical_load_bem"])
    # the centre state changes where the load passes the critical load
    np.testing.assert_array_equal(out["contact_state"] > 0, s.loads >= expected)
    np.testing.assert_allclose(out["mu_rel"], out["mu"] / out["mu_ref"], rtol=1e-12)
    assert np.all((out["psi"] >= 0) & (out["psi"] <= 1))


def test_an_impossible_point_is_returned_with_its_reason():
    s = spec(axes={"spacing": ["50um"]})  # caps of base diameter 60 um cannot sit 50 um apart
    out = evaluate.evaluate_point(s.study_data(s.assignment((0,))), s.loads, [1e3])
    assert out["valid"] is False and "overlap" in out["reason"].lower()
    assert np.all(out["contact_state"] == -1) and np.all(np.isnan(out["mu"]))


def test_evaluate_a_bem_point_on_a_tiny_grid(tmp_path):
    data = {**BASE, "model": {"kind": "bem", "grid": 16, "cache": str(tmp_path / "cells")}}
    loads = np.array([0.2, 1.0, 4.0])
    out = evaluate.evaluate_point(data, loads, [1e2, 1e3, 1e4])
    assert out["valid"] and out["converged"] and out["grid"] == 16.0
    assert out["critical_load_bem"] > 0 and math.isnan(out["critical_load_hertz"])
    assert out["solves"] > 0
    # the second evaluation reads the cell from the cache: no solve, same numbers
    again = evaluate.evaluate_point(data, loads, [1e2, 1e3, 1e4])
    assert again["solves"] == 0 and again["critical_load_bem"] == out["critical_load_bem"]
    assert evaluate.cell_key(data) is not None
    assert evaluate.cell_key({**BASE}) is None  # Hertz only: no BEM cell


def test_store_layout_write_and_reopen(tmp_path):
    s = spec(axes={"spacing": ["150um", "200um", "300um"], "height": ["5um", "10um"]}, chunk=2)
    pressures = store.pressure_grid(10.0, 1e5)
    st = store.SweepStore(tmp_path / "sweep.zarr", s, pressures)
    st.create()
    assert not st.done().any() and st.done().shape == (3, 2)
    region = store.chunk_slices(s.shape, s.chunk)[0]  # spacing 0, both heights
    results = []
    for j in range(2):
        index = (0, j)
        results.append((index, evaluate.evaluate_point(s.study_data(s.assignment(index)), s.loads, pressures)))
    st.write(region, results)
    done = st.done()
    assert done[0].all() and not done[1:].any()
    ds = store.open_sweep(tmp_path / "sweep.zarr").load()
    assert json.loads(ds.attrs["axes"]) == ["spacing", "height"] and ds.attrs["design"] == "grid"
    assert ds["critical_load_hertz"].attrs["units"] == "N" and ds["load"].attrs["units"] == "N"
    np.testing.assert_allclose(ds["spacing"].values, [150e-6, 200e-6, 300e-6])
    assert ds["critical_load_hertz"].values[0, 1] == pytest.approx(results[1][1]["critical_load_hertz"], rel=1e-15)
    assert np.isnan(ds["critical_load_hertz"].values[1:]).all()
    np.testing.assert_array_equal(ds["contact_state"].values[0, 0], results[0][1]["contact_state"])
    # taller caps reach the transition later
    assert ds["critical_load_hertz"].values[0, 1] > ds["critical_load_hertz"].values[0, 0]
    # the same sweep resumes, another is refused
    store.SweepStore(tmp_path / "sweep.zarr", s, pressures).create()
    assert st.done()[0].all()
    other = spec(axes={"spacing": ["150um"]})
    with pytest.raises(FingerpadError, match="holds another sweep"):
        store.SweepStore(tmp_path / "sweep.zarr", other, pressures).create()
    store.SweepStore(tmp_path / "sweep.zarr", other, pressures).create(overwrite=True)
    assert store.open_sweep(tmp_path / "sweep.zarr")["done"].shape == (1,)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sweep.zarr"]


def test_store_refuses_foreign_folders(tmp_path):
    s = spec(axes={"spacing": ["150um"]})
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "thesis.tex").write_text("mine")
    with pytest.raises(FingerpadError, match="exists and is not a fingerpad sweep store"):
        store.SweepStore(tmp_path / "data", s, np.array([1.0])).create()
    assert (tmp_path / "data" / "thesis.tex").read_text() == "mine"
    with pytest.raises(FingerpadError, match="no such sweep store"):
        store.open_sweep(tmp_path / "none")
    with pytest.raises(FingerpadError, match="is not a fingerpad sweep store"):
        store.open_sweep(tmp_path / "data")


def test_points_store_holds_the_axis_values(tmp_path):
    s = spec(design="points", point=[{"spacing": "150um"}, {"spacing": "250um"}])
    st = store.SweepStore(tmp_path / "p.zarr", s, np.array([1e3]))
    ds = st.template()
    assert ds["spacing"].dims == ("point",)
    np.testing.assert_allclose(ds["spacing"].values, [150e-6, 250e-6])
    assert ds["mu"].dims == ("point", "load") and ds["psi"].dims == ("point", "cell_pressure")
