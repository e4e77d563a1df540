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
from fingerpad.design.spec import sweep_from_dict


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


def _store(tmp_path, population, kind=None, people=SPREAD):
    import xarray as xr

    spec = spec_for(people if population else None) if kind is None else sweep_from_dict(
        {**BASE, "model": {**BASE["model"], "kind": kind}, "sweep": SWEEP}, population=people if population else None)
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
    with pytest.raises(FingerpadError, match="reference values for the sweep's 24 fingers"):
        map_data(ds, "spacing", "height", at=load, population=True, tell_apart={"reference": "ref", "mu": 0.3,
                                                                                "weber": None})
    plain = _store(tmp_path / "plain", population=False)
    out = map_data(plain, "spacing", "height", at=load, tell_apart={"reference": "ref", "mu": 0.35, "weber": 0.2})
    mu = plain["mu"].isel(load=2).transpose("height", "spacing").values
    np.testing.assert_array_equal(out["tell_apart"].values, p_correct(mu, 0.35, 0.2))

    from fingerpad.plotting.designmap import figure_design_map

    fig = figure_design_map(out)
    assert "tells it from ref" in fig._suptitle.get_text()


REF_TOML = """
[texture]
name = "caps"
radius = "100um"
height = "20um"
spacing = "250um"

[material]
modulus = "0.5GPa"
poisson = 0.4

[model]
kind = "hertz"
"""


def test_population_map_tells_each_texture_from_any_reference(tmp_path):
    """With a population, the map's fraction telling a texture from REF (a study file) is the
    fraction of a direct comparison of that texture with REF on the same fingers, bit for bit."""
    from fingerpad.design.designmap import reference_member_friction
    from fingerpad.study.spec import load_study_file

    ref_file = tmp_path / "ref.toml"
    ref_file.write_text(REF_TOML, encoding="utf-8")
    ds = _store(tmp_path, population=True, kind="hertz")
    assert ds["mu_members"].sizes["member"] == SPREAD["size"]
    k = 2
    load = float(ds["load"].values[k])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref_mu = reference_member_friction(ds, str(ref_file), load)
    out = map_data(ds, "spacing", "height", at=load, population=True,
                   tell_apart={"reference": "ref", "mu": ref_mu, "weber": None})
    spec = sweep_from_dict({**BASE, "model": {**BASE["model"], "kind": "hertz"}, "sweep": SWEEP}, population=SPREAD)
    seen = []
    for i, j in [(0, 0), (1, 1)]:
        data = spec.study_data(spec.assignment((i, j)))
        data["loads"] = {"values": [float(f) for f in spec.loads]}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            direct = compare(study_from_dict(data), load_study_file(str(ref_file)), population=load_population(SPREAD))
        told = direct.summary()["fraction"][k]
        assert out["tell_apart"].sel(spacing=ds["spacing"].values[i], height=ds["height"].values[j]).item() == told
        seen.append(told)
    assert any(0 < f < 1 for f in seen)  # not a trivial case
    # a fixed W for a population that draws none is the user's to set; P grows as W falls
    low_w = map_data(ds, "spacing", "height", at=load, population=True,
                     tell_apart={"reference": "ref", "mu": ref_mu, "weber": 0.01})
    assert (low_w["tell_apart"].values >= out["tell_apart"].values).all()


def test_design_map_command_tells_the_population_from_a_reference(tmp_path):
    """``fingerpad design-map --population P --tell-apart REF.toml`` draws the fraction of the
    fingers telling each texture from REF (was refused: flat only); each finger's own W where the
    population draws W, and a W fixed beside it refused."""
    import xarray as xr
    from typer.testing import CliRunner

    from fingerpad.cli import app
    from fingerpad.design.designmap import reference_member_friction

    ref_file = tmp_path / "ref.toml"
    ref_file.write_text(REF_TOML, encoding="utf-8")
    pop_file = tmp_path / "people.toml"
    pop_file.write_text("""[population]
size = 24
skin_modulus = { distribution = "uniform", low = "0.2MPa", high = "0.5MPa" }
ridge_fraction = { distribution = "uniform", low = 0.1, high = 0.7 }
tau0 = { distribution = "uniform", low = "4kPa", high = "12kPa" }
""", encoding="utf-8")
    ds = _store(tmp_path, population=True, kind="hertz")
    store = str(tmp_path / "r.zarr")
    load = float(ds["load"].values[2])
    result = CliRunner().invoke(app, ["design-map", store, "--x", "spacing", "--y", "height", "--at", f"{load!r}N",
                                      "--population", str(pop_file), "--tell-apart", str(ref_file),
                                      "--out", str(tmp_path / "map")])
    assert result.exit_code == 0, result.output
    got = xr.open_dataset(tmp_path / "map" / "design_map.nc")["tell_apart"].load()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        want = map_data(ds, "spacing", "height", at=load, population=True,
                        tell_apart={"reference": "ref", "mu": reference_member_friction(ds, str(ref_file), load),
                                    "weber": None})["tell_apart"]
    np.testing.assert_array_equal(got.values, want.values)
    assert got.attrs["long_name"] == f"fraction of fingers telling it from ref at {load:g} N"
    # a population that draws W: each finger's own, a fixed W refused (flat or REF, one rule)
    ref_mu = reference_member_friction(ds, str(ref_file), load)
    drawn = ds.assign(member_weber_fraction=("member", np.full(ds.sizes["member"], 0.15)))
    own = map_data(drawn, "spacing", "height", at=load, population=True,
                   tell_apart={"reference": "ref", "mu": ref_mu, "weber": None})["tell_apart"]
    fixed = map_data(ds, "spacing", "height", at=load, population=True,
                     tell_apart={"reference": "ref", "mu": ref_mu, "weber": 0.15})["tell_apart"]
    np.testing.assert_array_equal(own.values, fixed.values)
    for ref, mu in (("ref", ref_mu), ("flat", None)):
        with pytest.raises(FingerpadError, match="draws each finger's W"):
            map_data(drawn, "spacing", "height", at=load, population=True,
                     tell_apart={"reference": ref, "mu": mu, "weber": 0.2})


def test_explorer_tells_each_texture_from_a_point_of_the_map(tmp_path):
    """The explorer's map tells each design from a design of the map itself: per point, the
    fraction of the fingers with P >= 0.75, each with its own mu on both textures and its own W
    (recomputed here from the stored member arrays), the number ``design-map --tell-apart`` gives
    for that reference; without a population, P of the study's finger. A forged reference
    index from the page is refused with one line."""
    from fingerpad.design.designmap import member_weber_of_store, point_friction, study_weber
    from fingerpad.explore import sweepdata as sd

    people = {**SPREAD, "weber_fraction": {"distribution": "lognormal", "median": 0.11, "sigma": 0.36}}
    ds = _store(tmp_path, population=True, kind="hertz", people=people)
    k, ref = 2, 3  # the reference: the grid's design #3 = (spacing 200 um, height 20 um)
    load = float(ds["load"].values[k])
    md = sd.map_data(ds, "spacing", "height", at=load, reference=ref)
    got = md["tell_flat"].transpose("height", "spacing").values
    # by hand from the stored arrays: each finger's P (Eqs. P.1-P.3) against its own mu on #3
    mu = ds["mu_members"].isel(load=k).transpose("height", "spacing", "member").values
    ref_mu = ds["mu_members"].isel(spacing=1, height=1, load=k).values
    weber = ds["member_weber_fraction"].values
    assert np.ptp(weber) > 0  # each finger's own W
    expected = np.mean(p_correct(mu, ref_mu, weber) >= 0.75, axis=-1)
    np.testing.assert_array_equal(got, expected)
    assert got[1, 1] == 0 and got.max() > 0  # nobody tells #3 from itself; not a trivial case
    # the library's number for the same reference (design-map --tell-apart), bit for bit
    lib = map_data(ds, "spacing", "height", at=load, population=True,
                   tell_apart={"reference": "#3", "mu": point_friction(ds, ref, load), "weber": None})
    np.testing.assert_array_equal(got, lib["tell_apart"].values)
    np.testing.assert_array_equal(member_weber_of_store(ds), weber)
    # the page's reference is untrusted: only a whole number addressing a point of the store
    for forged in (4, -1, "3", 3.0, True, "x" * 10**6):
        with pytest.raises(FingerpadError, match="not a point of this sweep") as err:
            sd.map_data(ds, "spacing", "height", at=load, reference=forged)
        assert len(str(err.value)) < 200
    # without a population: P of the study's finger against its mu on #3, the study's W
    plain = _store(tmp_path / "plain", population=False, kind="hertz")
    one = sd.map_data(plain, "spacing", "height", at=load, reference=ref)
    mu = plain["mu"].isel(load=k).transpose("height", "spacing").values
    np.testing.assert_array_equal(one["tell_flat"].transpose("height", "spacing").values,
                                  p_correct(mu, mu[1, 1], study_weber(plain)))
    # the view: its reference choice lists flat and the map's designs, and colours by that
    pytest.importorskip("panel")
    from fingerpad.explore.views.mapview import MapView

    view = MapView(None, ds, "r.zarr")
    assert list(view.reference.options.values()) == ["flat", 0, 1, 2, 3]
    view.x.value, view.y.value, view.at.value = "spacing", "height", load
    view.quantity.value, view.reference.value = "tell_flat", ref
    values = np.asarray(view.plot.object.renderers[0].data_source.data["value"], float)
    np.testing.assert_array_equal(np.sort(values), np.sort(got.ravel()))
    bar = [a for a in view.plot.object.right if hasattr(a, "color_mapper")][0]
    assert bar.title.startswith("telling it from design #3")
