"""The design map's perception overlay: who tells each texture from a reference (docs/perception.md).

A population sweep stores, per point and load, the fraction of its members telling the texture
from the flat reference; it is the fraction of a direct comparison on that texture."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from fingerpad.design.designmap import map_data
from fingerpad.design.store import SweepStore
from fingerpad.errors import FingerpadError
from fingerpad.perception.compare import compare
from fingerpad.perception.discrimination import p_correct
from fingerpad.population.sources import load_population
from fingerpad.study.spec import study_from_dict

from .test_population_sweep import BASE, SPREAD, SWEEP, point, spec_for


@pytest.fixture(autouse=True)
def cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path_factory.getbasetemp() / "perception-map-cache"))


@pytest.mark.parametrize("people", [SPREAD, {**SPREAD, "weber_fraction": {"distribution": "lognormal",
                                                                         "median": 0.11, "sigma": 0.36}}],
                         ids=["one W", "each member's own W"])
def test_stored_fraction_is_a_direct_comparison_with_flat(people):
    from fingerpad.design.spec import sweep_from_dict

    spec = sweep_from_dict({**BASE, "model": {**BASE["model"], "kind": "hertz"}, "sweep": SWEEP}, population=people)
    res = point(spec, (1, 0))
    data = spec.study_data(spec.assignment((1, 0)))
    data["loads"] = {"values": [float(f) for f in spec.loads]}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        direct = compare(study_from_dict(data), "flat", population=load_population(people))
    assert direct.as_dict()["weber_fraction"]["drawn"] is ("weber_fraction" in people)
    np.testing.assert_array_equal(res["tell_flat"], direct.summary()["fraction"])
    assert 0 < res["tell_flat"].max() and res["tell_flat"].min() < 1  # not a trivial case


def _store(tmp_path, population):
    import xarray as xr

    spec = spec_for(SPREAD if population else None)
    store = SweepStore(tmp_path / "r.zarr", spec, np.array([1e3, 1e4]))
    store.create()
    for i in range(2):
        store.write((slice(i, i + 1), slice(0, 2)), [((i, j), point(spec, (i, j))) for j in range(2)])
    return xr.open_zarr(store.path).load()


def test_map_overlay_population_and_finger(tmp_path):
    ds = _store(tmp_path, population=True)
    load = float(ds["load"].values[2])
    out = map_data(ds, "spacing", "height", at=load, population=True, tell_apart={"reference": "flat", "mu": None,
                                                                                  "weber": None})
    # at a sweep load the map shows the stored fraction itself
    np.testing.assert_array_equal(out["tell_apart"].values, ds["tell_flat"].isel(load=2).transpose(
        "height", "spacing").values)
    with pytest.raises(FingerpadError, match="flat reference only"):
        map_data(ds, "spacing", "height", at=load, population=True, tell_apart={"reference": "ref", "mu": 0.3,
                                                                                "weber": None})
    plain = _store(tmp_path / "plain", population=False)
    out = map_data(plain, "spacing", "height", at=load, tell_apart={"reference": "ref", "mu": 0.35, "weber": 0.2})
    mu = plain["mu"].isel(load=2).transpose("height", "spacing").values
    np.testing.assert_array_equal(out["tell_apart"].values, p_correct(mu, 0.35, 0.2))

    from fingerpad.plotting.designmap import figure_design_map

    fig = figure_design_map(out)
    assert "tells it from ref" in fig._suptitle.get_text()
