"""Study specs: every section of a study file read into SI values, and every mistake named once.

Through the package face ``fingerpad.study`` (``study_from_dict``, ``read_study_file``,
``load_study_file``, ``Study``, ``TextureSpec``), nothing solved: these tests take milliseconds.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import fingerpad as fp
from fingerpad import macro, study
from fingerpad.errors import FingerpadError

CAPS = {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"}


def make(**sections):
    return study.study_from_dict({"texture": dict(CAPS), **sections})


# ---------------------------------------------------------------------------------------------
# loads
# ---------------------------------------------------------------------------------------------


def test_default_loads_are_the_exploration_range():
    s = make()
    np.testing.assert_allclose(s.loads, np.geomspace(0.1, 4.0, 40), rtol=1e-12)
    assert s.zone_load == pytest.approx(4.0)


def test_range_log_and_linear():
    np.testing.assert_allclose(make(loads={"range": "1N:100N:3"}).loads, [1.0, 10.0, 100.0], rtol=1e-12)
    np.testing.assert_allclose(make(loads={"range": "1N:3N:3", "log": False}).loads, [1.0, 2.0, 3.0], rtol=1e-12)
    np.testing.assert_allclose(make(loads={"range": "100mN:0.4N:3"}).loads, [0.1, 0.2, 0.4], rtol=1e-12)


def test_values_with_units_and_lists_of_ranges():
    np.testing.assert_allclose(make(loads={"values": ["0.5N", 1, "2000mN"]}).loads, [0.5, 1.0, 2.0])
    np.testing.assert_allclose(make(loads={"values": "3N"}).loads, [3.0])
    both = make(loads={"range": ["1N:4N:3", "8N"]}).loads
    np.testing.assert_allclose(both, [1.0, 2.0, 4.0, 8.0], rtol=1e-12)


def test_comma_lists_are_lists_at_every_door():
    """A comma list is a list wherever loads are read (study file, --loads, the explorer's
    field, finger-models), as solve's --pressure reads its pressures: one rule."""
    from fingerpad.study.cell_job import _parse_pressures
    from fingerpad.study.values import parse_loads

    np.testing.assert_allclose(make(loads={"range": "0.5N, 1N,1N:4N:3"}).loads, [0.5, 1.0, 1.0, 2.0, 4.0],
                               rtol=1e-12)
    np.testing.assert_allclose(make(loads={"values": ["0.5N,2N", 3]}).loads, [0.5, 2.0, 3.0])
    np.testing.assert_allclose(parse_loads("100mN,0.3N", True, "--loads"), [0.1, 0.3])
    with pytest.raises(FingerpadError, match=r"^--loads: cannot read '' as a number"):
        parse_loads("1N,,2N", True, "--loads")
    with pytest.raises(FingerpadError, match=r"^--loads: loads must be positive"):
        parse_loads("1N,-2N", True, "--loads")
    with pytest.raises(FingerpadError, match=r"more than 100000 loads"):
        parse_loads(",".join(["1N:2N:60000"] * 2), True, "--loads")
    assert _parse_pressures(["1kPa,2kPa", "3kPa"], log=True) == [1e3, 2e3, 3e3]
    with pytest.raises(FingerpadError, match="zero and tensions need --work-of-adhesion"):
        _parse_pressures(["1kPa,-2kPa"], log=True)


def test_zones_at():
    s = make(loads={"range": "0.1N:4N:5", "zones_at": "2N"})
    assert s.zone_load == 2.0
    with pytest.raises(FingerpadError, match=r"\[loads\] zones_at: must be a positive load"):
        make(loads={"zones_at": 0})


@pytest.mark.parametrize("loads, message", [
    ({"range": "1N:2N:3", "values": [1]}, r"\[loads\]: give range or values, not both"),
    ({"range": "4N:1N:3"}, r"\[loads\] range: STOP '1N' is below START '4N'"),
    ({"range": "0.1N:4N:200001"}, r"200001 loads asked for; at most 100000"),
    ({"values": [1, -2]}, r"\[loads\] values: loads must be positive"),
    ({"values": ["1m"]}, r"\[loads\] values"),
    ({"values": [True]}, r"expected a number or a quantity"),
    ({"range": "1N:2N:3", "log": "maybe"}, r"\[loads\] log: expected true or false"),
])
def test_bad_loads_named(loads, message):
    with pytest.raises(FingerpadError, match=message):
        make(loads=loads)


# ---------------------------------------------------------------------------------------------
# material, finger
# ---------------------------------------------------------------------------------------------


def test_material_defaults_and_rigid():
    s = make()
    assert s.material_modulus is None and s.material_poisson is None
    s = make(material={"modulus": "0.5GPa"})
    assert s.material_modulus == 0.5e9 and s.material_poisson == 0.35  # the documented default
    s = make(material={"modulus": "rigid"})
    assert s.material_modulus is None
    with pytest.raises(FingerpadError, match=r"\[material\] poisson: a Poisson ratio is given, but it needs a material modulus"):
        make(material={"poisson": 0.4})


def test_reduced_modulus_eq_3_4():
    s = make(material={"modulus": "2MPa", "poisson": 0.3}, finger={"skin_modulus": "0.4MPa", "skin_poisson": 0.5})
    expected = 1.0 / ((1 - 0.5**2) / 0.4e6 + (1 - 0.3**2) / 2e6)
    assert s.reduced_modulus == pytest.approx(expected, rel=1e-12)
    rigid = make(finger={"skin_modulus": "0.4MPa", "skin_poisson": 0.5})
    assert rigid.reduced_modulus == pytest.approx(0.4e6 / (1 - 0.25), rel=1e-12)


def test_finger_preset_and_overrides():
    s = make(finger={"preset": "soft", "radius": "8mm", "tau0": "10kPa", "beta": 0.2})
    base = fp.get_finger("soft")
    assert s.finger.name == "soft"
    assert s.finger.radius == pytest.approx(8e-3) and s.finger.tau0 == pytest.approx(1e4)
    assert s.finger.beta == 0.2 and s.finger.skin_modulus == base.skin_modulus


def test_finger_models_by_name_and_table():
    s = make(finger={"gross": {"model": "dzidek", "stiffening": 5}})
    gross = s.finger.gross
    assert isinstance(gross, macro.DzidekArea)
    # a gross model takes the finger's radius and modulus unless given
    assert gross.radius == s.finger.radius and gross.modulus == s.finger.modulus and gross.stiffening == 5
    # Eq. 2.4 uses the finger's R_fp: a gross model with another radius contradicts it
    with pytest.raises(FingerpadError, match="gross-area model radius 0.007 differs from the finger's 0.009"):
        make(finger={"gross": {"model": "hertz", "radius": "7mm"}})
    s = make(finger={"radius": "7mm", "gross": "hertz"})
    assert s.finger.gross.radius == pytest.approx(7e-3)
    s = make(finger={"gross": {"model": "power_law", "coefficient": 1e-4, "exponent": 0.3}})
    assert s.finger.gross.area(1.0) == pytest.approx(1e-4)


@pytest.mark.parametrize("finger, message", [
    ({"preset": "thumb"}, "unknown finger preset"),
    ({"preset": 3}, r"\[finger\] preset: expected a preset name"),
    ({"radius": [1, 2]}, r"\[finger\] radius: expected a number or a quantity"),
    ({"radius": "2N"}, r"\[finger\] radius"),
    ({"gross": "sphere"}, r"\[finger\] gross: unknown model 'sphere'"),
    ({"gross": {"model": "dzidek", "stiffness": 5}}, r"model 'dzidek' has no parameter\(s\) stiffness"),
    ({"gross": {"stiffening": 5}}, r"expected a model name or a table with model = NAME"),
])
def test_bad_finger_named(finger, message):
    with pytest.raises(FingerpadError, match=message):
        make(finger=finger)


# ---------------------------------------------------------------------------------------------
# model
# ---------------------------------------------------------------------------------------------


def test_model_section():
    s = make(model={"kind": "HERTZ", "grid": 48, "accuracy": 0.05, "tol": 1e-6, "max_iter": "100",
                    "direction": 30})
    assert (s.model, s.grid, s.accuracy, s.tol, s.max_iter) == ("hertz", 48, 0.05, 1e-6, 100)
    assert s.direction == pytest.approx(30.0)
    assert make(model={"direction": "0.5rad"}).direction == pytest.approx(math.degrees(0.5))
    assert make(model={"cache": False}).cache is False
    assert make(model={"cache": True}).cache is None  # the default cache
    assert make(model={"grid": 40.0}).grid == 40  # an integral float from TOML


def test_grid_given_twice():
    assert study.study_from_dict({"texture": {**CAPS, "grid": 24}}).grid == 24
    assert study.study_from_dict({"texture": {**CAPS, "grid": 24}, "model": {"grid": 24}}).grid == 24
    with pytest.raises(FingerpadError, match=r"give the grid once"):
        study.study_from_dict({"texture": {**CAPS, "grid": 24}, "model": {"grid": 32}})


@pytest.mark.parametrize("model, message", [
    ({"kind": "fem"}, r"\[model\] kind: must be one of bem, hertz, both"),
    ({"grid": 3}, r"\[model\] grid: must be at least 4"),
    ({"grid": 12.5}, r"\[model\] grid: expected an integer"),
    ({"accuracy": 1.5}, r"\[model\] accuracy: must lie in \(0, 1\)"),
    ({"tol": 0}, r"\[model\] tol: must lie in \(0, 1\)"),
    ({"max_iter": 0}, r"\[model\] max_iter: must be at least 1"),
    ({"cache": 3}, r"\[model\] cache: expected a folder or false"),
    ({"gird": 32}, r"unknown key\(s\) in \[model\]: gird"),
])
def test_bad_model_named(model, message):
    with pytest.raises(FingerpadError, match=message):
        make(model=model)


# ---------------------------------------------------------------------------------------------
# texture
# ---------------------------------------------------------------------------------------------


@pytest.mark.filterwarnings("ignore::fingerpad.errors.ResolutionWarning")
def test_texture_spec_builds_the_generator():
    s = make(model={"grid": 16})
    tex = s.build_texture()
    assert tex.name == "caps" and tex.shape == (16, 16)
    assert tex.params["radius"] == pytest.approx(50e-6) and tex.params["spacing"] == pytest.approx(100e-6)
    assert s.build_texture() is tex, "built once"


@pytest.mark.parametrize("texture, message", [
    ({}, "no texture given"),
    ({"radius": "50um"}, r"\[texture\]: give exactly one of a texture name"),
    ({"name": "caps", "surface": "a.npy"}, r"\[texture\]: give exactly one of a texture name"),
    ({"name": 5}, r"\[texture\] name: expected text"),
])
def test_bad_texture_named(texture, message):
    with pytest.raises(FingerpadError, match=message):
        study.study_from_dict({"texture": texture} if texture else {})


def test_unknown_section_and_labels():
    with pytest.raises(FingerpadError, match="unknown study section"):
        study.study_from_dict({"texture": dict(CAPS), "extras": {}})
    # a value set by a command-line flag is named by that flag
    with pytest.raises(FingerpadError, match=r"^--loads: STOP"):
        study.study_from_dict({"texture": dict(CAPS), "loads": {"range": "4N:1N:3"}},
                              labels={("loads", "range"): "--loads"})


# ---------------------------------------------------------------------------------------------
# the Study dataclass (the Python API)
# ---------------------------------------------------------------------------------------------


def test_study_from_python_checks_its_values():
    spec = study.TextureSpec(name="caps", params=dict(radius="50um", height="10um", spacing="100um"))
    s = study.Study(texture=spec, loads=[1.0, 2.0], material_modulus=1e9)
    assert s.material_poisson == 0.35 and list(s.loads) == [1.0, 2.0]
    for kwargs, message in ((dict(texture="caps"), "texture must be a TextureSpec or a Texture"),
                            (dict(texture=spec, model="fem"), "model must be one of"),
                            (dict(texture=spec, material_poisson=0.3), "needs a material modulus"),
                            (dict(texture=spec, loads=[0.0]), "loads must be positive"),
                            (dict(texture=spec, accuracy=0.0), r"accuracy must lie in \(0, 1\)"),
                            (dict(texture=spec, zones_at=-1.0), "zones_at must be a positive load"),
                            (dict(texture=spec, finger="default"), "finger must be a Finger")):
        with pytest.raises(FingerpadError, match=message):
            study.Study(**kwargs)


def test_study_of_a_ready_texture():
    tex = fp.make_texture("flat", size=100e-6, grid=8)
    s = study.Study(texture=tex, loads=[1.0])
    assert s.build_texture() is tex
    assert s.texture_source == {"source": "texture", "file": None}


@pytest.mark.filterwarnings("ignore::fingerpad.errors.ResolutionWarning")
def test_check_refuses_a_patch_for_the_bem_and_hertz_on_ridges():
    patch = study.TextureSpec(name="caps", params=dict(radius="50um", height="10um", spacing="100um"), periodic=False)
    with pytest.raises(FingerpadError, match="needs a periodic texture"):
        study.Study(texture=patch, model="bem", grid=16).check()
    ridges = study.TextureSpec(name="ridges", params=dict(width="50um", height="10um", spacing="100um"))
    with pytest.raises(FingerpadError):
        study.Study(texture=ridges, model="hertz", grid=16).check()
    study.Study(texture=ridges, model="bem", grid=16).check()  # fine for the BEM


# ---------------------------------------------------------------------------------------------
# study files
# ---------------------------------------------------------------------------------------------


def test_study_file_round_trip(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[texture]\nname = "caps"\nradius = "50um"\nheight = "10um"\nspacing = 1e-4\n'
                    '[loads]\nvalues = [1, "2N"]\n[model]\ncache = "cells"\nkind = "hertz"\n')
    s = study.load_study_file(path)
    assert s.source == str(path)
    assert list(s.loads) == [1.0, 2.0] and s.model == "hertz"
    assert s.cache == str(tmp_path.resolve() / "cells"), "relative to the study file"


def test_relative_surface_path(tmp_path):
    (tmp_path / "maps").mkdir()
    path = tmp_path / "maps" / "s.toml"
    path.write_text('[texture]\nsurface = "scan.npy"\nsize = "1mm"\nheight_unit = "um"\n')
    sections = study.read_study_file(path)
    assert sections["texture"]["surface"] == str(tmp_path.resolve() / "maps" / "scan.npy")
    assert sections["_source"] == {"file": str(path)}


def test_file_errors_name_the_file_and_key(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text('[texture]\nname = "caps"\nradius = "50um"\nheight = "10um"\nspacing = "100um"\n'
                    '[loads]\nrange = "4N:1N:3"\n')
    with pytest.raises(FingerpadError, match=r"^mine\.toml \[loads\] range: STOP"):
        study.load_study_file(path)


@pytest.mark.parametrize("content, message", [
    (b'[texture\nname = "caps"', r"study file '.*bad\.toml': "),
    (b"\xff\xfe[texture]", "is saved as UTF-16"),
    (b'[sweep]\nspacing = "1um:2um:2"\n', r"unknown section\(s\) or key\(s\) sweep .*read by `fingerpad sweep`"),
    (b'texture = 3\n', r"'texture' must be a \[texture\] section"),
])
def test_unreadable_study_files(tmp_path, content, message):
    path = tmp_path / "bad.toml"
    path.write_bytes(content)
    with pytest.raises(FingerpadError, match=message):
        study.read_study_file(path)


def test_missing_study_file_and_folder(tmp_path):
    with pytest.raises(FingerpadError, match="no such file"):
        study.read_study_file(tmp_path / "none.toml")
    with pytest.raises(FingerpadError, match="it is a directory"):
        study.read_study_file(tmp_path)


def test_extra_sections_are_returned_unchecked(tmp_path):
    path = tmp_path / "sweep.toml"
    path.write_text('[texture]\nname = "flat"\n[sweep]\nspacing = "100um:200um:3"\n')
    sections = study.read_study_file(path, extra_sections=("sweep",))
    assert sections["sweep"] == {"spacing": "100um:200um:3"}


def test_default_study_is_valid_and_documented_numbers():
    s = study.study_from_dict(study.DEFAULT_STUDY)
    assert s.texture.name == "caps" and s.material_modulus == 0.5e9 and s.material_poisson == 0.4
    # the default finger: E_s = 0.3 MPa, so E1* = 0.395 MPa (the module's comment)
    assert s.reduced_modulus == pytest.approx(0.395e6, rel=0.005)
