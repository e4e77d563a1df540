"""A finger with a layered skin (issue 24): its declaration, predict and sweep end to end, the
ridge models on the layer, populations over the layer, and the refusals of the command line."""

from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.contact.layered import effective_modulus
from fingerpad.errors import FingerpadError
from fingerpad.finger import FINGER_PRESETS, Finger
from fingerpad.meso import FingerprintBEMRidges, SinusoidalRidges
from fingerpad.population import population_from_table, run_population
from fingerpad.study.run import run_study
from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict

LAYER = {"skin_layer_thickness": "300um", "skin_layer_modulus": "0.4MPa", "skin_substrate_modulus": "40kPa"}
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "150um", "--grid", "16"]


def study(finger: dict, kind: str = "both", loads=(0.3, 1.0, 3.0)):
    return study_from_dict({
        "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "150um"},
        "finger": finger, "loads": {"values": list(loads)},
        "model": {"kind": kind, "grid": 16, "cache": False}})


def test_default_finger_predicts_what_it_did_before_the_layer():
    """Bit-identical to the package before the layered skin (numbers from commit e42882a; the BEM
    area ratio and mu since the coupling integrates the interpolated psi exactly, which moved
    them by up to 7e-4 relative on this 16-pixel cell; the critical load since one search of
    Eq. 3.14 serves a finger and a population's members, issue 34: 1e-15 relative from Brent's
    4.37642786242072e-05)."""
    pred = run_study(study({"preset": "ridged"}))
    assert [repr(float(x)) for x in pred.bem.area_ratio] == \
        ["0.7456450170713762", "0.78898520759537", "0.8031260545351184"]
    assert [repr(float(x)) for x in pred.bem.mu] == \
        ["0.442248723044651", "0.4158141050180432", "0.40934939452434366"]
    assert [repr(float(x)) for x in pred.hertz.mu] == \
        ["0.17800630133098172", "0.1783557935254782", "0.18220057312271495"]
    assert repr(pred.critical_load["bem"]) == "4.376427862420715e-05"
    assert pred.critical_load["bem"] == pytest.approx(4.37642786242072e-05, rel=1e-12)
    assert FINGER_PRESETS["default"].layer is None
    assert "skin" not in FINGER_PRESETS["default"].as_dict()


def test_equal_moduli_layer_predicts_the_homogeneous_finger():
    e = "0.3MPa"
    homog = run_study(study({"skin_modulus": e}, kind="bem"))
    layered = run_study(study({"skin_layer_thickness": "30um", "skin_layer_modulus": e,
                               "skin_substrate_modulus": e}, kind="bem"))
    assert layered.study.finger.skin == "layered"
    np.testing.assert_allclose(layered.bem.area_ratio, homog.bem.area_ratio, rtol=1e-10)
    np.testing.assert_allclose(layered.bem.mu, homog.bem.mu, rtol=1e-10)
    assert layered.critical_load["bem"] == pytest.approx(homog.critical_load["bem"], rel=1e-9)


def test_a_thin_stiff_layer_on_soft_tissue_reaches_the_transition_earlier():
    half = run_study(study({"skin_modulus": "0.4MPa"}, kind="bem"))
    thin = run_study(study({**LAYER, "skin_layer_thickness": "20um"}, kind="bem"))
    assert thin.critical_load["bem"] < 0.1 * half.critical_load["bem"]
    assert np.all(thin.bem.area_ratio > half.bem.area_ratio)


def test_layered_finger_fields():
    f = FINGER_PRESETS["default"].with_overrides(**LAYER)
    assert f.skin == "layered" and f.skin_modulus == 0.4e6
    assert f.layer.thickness == 300e-6 and f.layer.substrate_modulus == 40e3
    assert f.layer.substrate_poisson == f.skin_poisson
    # E_s of a layered skin is its layer's modulus: changing one changes the other
    g = f.with_overrides(skin_modulus="0.8MPa")
    assert g.skin_layer_modulus == 0.8e6 and g.layer.modulus == 0.8e6
    rigid = FINGER_PRESETS["default"].with_overrides(skin_layer_thickness="1mm", skin_layer_modulus="50kPa",
                                                     skin_base="rigid")
    assert rigid.layer.rigid_base and rigid.layer.base == "bonded"
    assert rigid.with_overrides(skin_base="rigid-frictionless").layer.base == "frictionless"
    assert f.as_dict()["skin_layer_thickness"] == 300e-6


@pytest.mark.parametrize(("values", "words"), [
    ({"skin_layer_thickness": "300um"}, "skin_layer_modulus, skin_substrate_modulus missing"),
    ({**LAYER, "skin": "half-space"}, "needs skin = layered"),
    ({**LAYER, "skin_modulus": "1MPa"}, "not both"),
    ({**LAYER, "skin_base": "rigid"}, "rigid base"),
    ({**LAYER, "skin_layer_thickness": "2"}, "has no unit"),
    ({**LAYER, "skin_layer_thickness": "-3um"}, "must lie in"),
    ({**LAYER, "skin": "foam"}, "must be one of half-space, layered"),
])
def test_layered_finger_mistakes(values, words):
    with pytest.raises(FingerpadError, match=words):
        FINGER_PRESETS["default"].with_overrides(**values)


def test_ridge_models_on_the_layer():
    f = FINGER_PRESETS["ridged"].with_overrides(**LAYER)
    k = 2 * math.pi / 0.45e-3
    assert isinstance(f.ridges, SinusoidalRidges)
    assert f.ridges.modulus == pytest.approx(float(effective_modulus(f.layer, k)), rel=1e-12)
    # between the tissue's and the layer's reduced moduli
    assert 40e3 / (1 - 0.49**2) < f.ridges.modulus < 0.4e6 / (1 - 0.49**2)
    bem = Finger(ridges=FingerprintBEMRidges(max_load=0.5, points_per_wavelength=6)).with_overrides(**LAYER)
    assert bem.ridges.layer == bem.layer and bem.ridges.modulus == bem.layer.reduced_modulus


@pytest.mark.slow
def test_fingerprint_bem_on_a_layer_of_equal_moduli_is_the_homogeneous_one():
    e = 100e3 * (1 - 0.49**2)  # E* = 100 kPa, the thesis' ridge modulus
    kw = dict(max_load=0.3, points_per_wavelength=6, pattern="parallel")
    homog = FingerprintBEMRidges(modulus=100e3, **kw)
    layered = Finger(ridges=FingerprintBEMRidges(**kw)).with_overrides(
        skin_layer_thickness="300um", skin_layer_modulus=e, skin_substrate_modulus=e).ridges
    assert layered.area(0.2) == pytest.approx(homog.area(0.2), rel=1e-6)
    soft = Finger(ridges=FingerprintBEMRidges(**kw)).with_overrides(
        skin_layer_thickness="300um", skin_layer_modulus=e, skin_substrate_modulus=e / 4).ridges
    # softer tissue under the layer: the pad spreads (gross area x 2.2, Hertz of the tissue alone
    # would give 4^(2/3) = 2.5), the ridges' own contact, set by the layer at their scale, little
    assert float(soft.gross_area(0.2)[0]) > 2.0 * float(homog.gross_area(0.2)[0])
    assert 1.02 * homog.area(0.2) < soft.area(0.2) < 1.3 * homog.area(0.2)


def test_population_over_the_layer_thickness():
    d = copy.deepcopy(DEFAULT_STUDY)
    d["model"] = {"kind": "bem", "grid": 16, "cache": False}
    d["loads"] = {"values": [0.5, 2.0]}
    d["finger"] = {"preset": "default", **LAYER}
    nominal = study_from_dict(d)
    table = {"size": 2, "skin_layer_thickness": {"values": ["20um", "300um"]}}
    res = run_population(nominal, population_from_table(table))
    for member, curve in zip(res.members, res.curves, strict=True):
        d1 = copy.deepcopy(d)
        d1["finger"]["skin_layer_thickness"] = f"{member['skin_layer_thickness'] * 1e6:.12g}um"
        plain = run_study(study_from_dict(d1)).primary
        np.testing.assert_allclose(curve.area_ratio, plain.area_ratio, rtol=1e-12)
    assert not np.allclose(res.curves[0].area_ratio, res.curves[1].area_ratio, rtol=1e-3)


# ----------------------------------------------------------------------------- command line


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def test_predict_with_a_layered_skin(tmp_path, monkeypatch):
    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path / "cache"))
    res = invoke("predict", *CAPS, "--loads", "0.2N:2N:3", "--skin-layer-thickness", "300um",
                 "--skin-layer-modulus", "0.4MPa", "--skin-substrate-modulus", "40kPa", "--model", "bem",
                 "--json", "-")
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    text = json.dumps(doc)
    assert '"skin": "layered"' in text and '"skin_layer_thickness": 0.0003' in text


@pytest.mark.parametrize(("extra", "words"), [
    (["--skin-layer-thickness", "2"], "has no unit"),
    (["--skin-layer-thickness", "-300um"], "must lie in"),
    (["--skin-layer-thickness", "300um", "--skin-base", "soft"], "must be one of elastic"),
    (["--skin-layer-thickness", "300um", "--skin-modulus", "1MPa"], "not both"),
])
def test_predict_refusals_are_one_line(tmp_path, extra, words):
    out = tmp_path / "out"
    res = invoke("predict", *CAPS, "--skin-layer-modulus", "0.4MPa", "--skin-substrate-modulus", "40kPa",
                 *extra, "--out", str(out))
    assert res.exit_code == 2
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and words in lines[0], res.stderr
    assert not out.exists()


SWEEP = """
[texture]
name = "caps"
radius = "50um"
height = "10um"
spacing = "150um"

[finger]
skin_layer_thickness = "300um"
skin_layer_modulus = "0.4MPa"
skin_substrate_modulus = "40kPa"

[model]
kind = "bem"
grid = 16

[sweep]
loads = "0.1N:4N:3"
chunk = 2
[sweep.axes]
skin_layer_thickness = ["20um", "300um"]
"""


@pytest.mark.slow
def test_sweep_over_the_layer_thickness(tmp_path, monkeypatch):
    from fingerpad.design.store import open_sweep

    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path / "cache"))
    (tmp_path / "s.toml").write_text(SWEEP)
    res = invoke("sweep", str(tmp_path / "s.toml"), "--out", str(tmp_path / "r.zarr"), "--workers", "1")
    assert res.exit_code == 0, res.output
    data = open_sweep(str(tmp_path / "r.zarr")).load()
    assert bool(data["valid"].all())
    crit = data["critical_load_bem"].values
    for t, value in zip(("20um", "300um"), crit, strict=True):
        single = run_study(study_from_dict({
            "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "150um"},
            "finger": {**LAYER, "skin_layer_thickness": t}, "loads": {"values": [0.1, 0.632455532, 4.0]},
            "model": {"kind": "bem", "grid": 16, "cache": False}}))
        assert value == pytest.approx(single.critical_load["bem"], rel=1e-9)
    assert crit[0] < crit[1]


# ------------------------------------------------------------------ back to the half-space


def test_skin_half_space_on_a_layered_finger_clears_its_layer():
    """`skin = half-space` on the preset `layered` is the half-space of the layer's modulus: its
    layer fields are cleared (not refused), so it describes itself as the default finger does."""
    back = FINGER_PRESETS["layered"].with_overrides(skin="half-space")
    assert back.skin == "half-space" and back.layer is None
    assert all(getattr(back, n) is None for n in ("skin_layer_thickness", "skin_substrate_modulus"))
    assert back.skin_modulus == FINGER_PRESETS["layered"].skin_layer_modulus
    default = FINGER_PRESETS["default"].as_dict()
    assert {**back.as_dict(), "name": "default"} == default  # the preset is the default finger plus its layer
    # the study file's way
    spec = study({"preset": "layered", "skin": "half-space"})
    assert spec.finger.layer is None
    # a layer field in the same breath still contradicts it
    with pytest.raises(FingerpadError, match="needs skin = layered"):
        FINGER_PRESETS["layered"].with_overrides(skin="half-space", skin_layer_thickness="20um")


def test_skin_half_space_refused_where_the_ridges_took_the_layers_modulus():
    f = FINGER_PRESETS["ridged"].with_overrides(**LAYER)
    with pytest.raises(FingerpadError, match="ridge model .* took its modulus from the layer"):
        f.with_overrides(skin="half-space")
    # with the ridge model given again, it is the half-space finger with those ridges
    back = f.with_overrides(skin="half-space", ridges=FINGER_PRESETS["ridged"].ridges)
    assert back.layer is None and back.ridges == FINGER_PRESETS["ridged"].ridges


def test_sweeping_the_skin_choice_with_layer_keys():
    """A `skin` axis next to layer keys: its half-space points drop the layer (valid, the same at
    every layer value), its layered points keep it."""
    from fingerpad.design.spec import sweep_from_dict
    import tomllib

    data = tomllib.loads(SWEEP.replace("[sweep.axes]", '[sweep.axes]\nskin = ["half-space", "layered"]'))
    spec = sweep_from_dict(data)
    for t in ("20um", "300um"):
        half = study_from_dict(spec.study_data({"skin": "half-space", "skin_layer_thickness": t}))
        layered = study_from_dict(spec.study_data({"skin": "layered", "skin_layer_thickness": t}))
        assert half.finger.layer is None and half.finger.skin_modulus == 0.4e6
        assert layered.finger.layer.thickness == pytest.approx(float(t[:-2]) * 1e-6, rel=1e-12)
    # without a skin axis nothing is dropped: a half-space base with layer keys is layered
    plain = sweep_from_dict(tomllib.loads(SWEEP))
    assert "skin_layer_thickness" in plain.study_data({"skin_layer_thickness": "20um"})["finger"]


def test_outputs_name_the_layer_with_units(tmp_path, monkeypatch):
    import xarray as xr

    monkeypatch.setenv("FINGERPAD_CACHE", str(tmp_path / "cache"))
    res = invoke("solve", *CAPS, "--pressure", "1kPa:30kPa:2", "--skin-layer-thickness", "30um",
                 "--skin-layer-modulus", "0.4MPa", "--skin-substrate-modulus", "40kPa",
                 "--json", str(tmp_path / "s.json"), "--save", str(tmp_path / "s.nc"))
    assert res.exit_code == 0, res.output
    assert "skin: layered, t 30 um, E_1 400 kPa on E_2 40 kPa" in res.stdout  # the table says so too
    mat = json.loads((tmp_path / "s.json").read_text())["inputs"]["materials"]
    assert mat["skin"] == "layered" and mat["skin_layer_thickness"] == pytest.approx(30e-6)
    assert mat["units"]["skin_layer_thickness"] == "m" and mat["units"]["skin_substrate_modulus"] == "Pa"
    with xr.open_dataset(tmp_path / "s.nc") as ds:
        assert ds.attrs["skin"] == "layered" and ds.attrs["units_skin_layer_thickness"] == "m"
    res = invoke("predict", *CAPS, "--loads", "0.2N:2N:2", "--finger", "layered", "--model", "bem",
                 "--out", str(tmp_path / "p"))
    assert res.exit_code == 0, res.output
    doc = json.loads((tmp_path / "p" / "predict.json").read_text())
    assert doc["inputs"]["finger"]["skin_layer_thickness"] == pytest.approx(0.3e-3)
    assert doc["units"]["skin_layer_thickness"] == "m" and doc["units"]["skin_layer_modulus"] == "Pa"
    with xr.open_dataset(tmp_path / "p" / "predict.nc") as ds:
        assert ds.attrs["inputs_finger_skin"] == "layered" and ds.attrs["units_skin_layer_modulus"] == "Pa"
    # a half-space prediction's units are as they were
    res = invoke("predict", *CAPS, "--loads", "0.2N:2N:2", "--model", "bem", "--json", "-")
    assert "skin_layer_thickness" not in json.loads(res.stdout)["units"]


def test_predict_takes_solves_rigid_substrate_spelling(tmp_path):
    """`solve` spells a rigid base `--skin-substrate-modulus rigid`; `predict` refused those words
    ("cannot read 'rigid' as a number") and wanted --skin-base rigid. Both now give the same finger."""
    base = ["predict", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um",
            "--model", "hertz", "--loads", "1N:1N:1", "--skin-layer-thickness", "300um",
            "--skin-layer-modulus", "0.4MPa", "--json", "-"]
    runner = CliRunner()
    words = runner.invoke(app, [*base, "--skin-substrate-modulus", "rigid"])
    flag = runner.invoke(app, [*base, "--skin-base", "rigid"])
    assert words.exit_code == 0 and flag.exit_code == 0, (words.stderr, flag.stderr)
    finger = json.loads(words.stdout)["inputs"]["finger"]
    assert finger == json.loads(flag.stdout)["inputs"]["finger"] and finger["skin_base"] == "rigid"
    bad = runner.invoke(app, [*base, "--skin-substrate-modulus", "rigid", "--skin-base", "elastic"])
    assert bad.exit_code == 2 and bad.stderr.strip() == \
        "error: --skin-substrate-modulus rigid contradicts --skin-base elastic"
