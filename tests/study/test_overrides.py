"""Command-line flags laid over a study file: the merged study, and errors naming the flag typed."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad import study
from fingerpad.errors import FingerpadError
from fingerpad.study.overrides import apply_flags, split_texture_options

FILE = {
    "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um", "grid": 24},
    "material": {"modulus": "0.5GPa", "poisson": 0.4},
    "loads": {"values": [1, 2]},
    "model": {"kind": "bem"},
}


def test_split_texture_options():
    assert split_texture_options(["--radius", "50um", "--lattice=hexagonal", "--semi-axis-x", "1mm"]) == \
        [("radius", "50um"), ("lattice", "hexagonal"), ("semi_axis_x", "1mm")]
    assert split_texture_options(["--offset", "-5um"]) == [("offset", "-5um")]  # a negative value is a value
    assert split_texture_options(["--x="]) == [("x", "")]
    with pytest.raises(FingerpadError, match="option --radius needs a value"):
        split_texture_options(["--radius"])
    with pytest.raises(FingerpadError, match="option --radius needs a value"):
        split_texture_options(["--radius", "--height", "1um"])
    with pytest.raises(FingerpadError, match=r"unexpected argument '50um'"):
        split_texture_options(["50um"])


def test_flags_replace_single_keys():
    data, labels = apply_flags(FILE, {"--material-modulus": "1GPa", "--model": "hertz", "--loads": ["0.5N:2N:3"],
                                      "--grid": None})
    assert data["material"] == {"modulus": "1GPa", "poisson": 0.4}
    assert data["model"]["kind"] == "hertz"
    assert data["loads"] == {"range": ["0.5N:2N:3"]}, "--loads replaces the file's values"
    assert labels == {("material", "modulus"): "--material-modulus", ("model", "kind"): "--model",
                      ("loads", "range"): "--loads"}
    assert FILE["material"]["modulus"] == "0.5GPa", "the file's sections are not changed"


def test_texture_options_update_and_texture_replaces():
    data, labels = apply_flags(FILE, {}, texture_options=[("spacing", "300um")])
    assert data["texture"]["spacing"] == "300um" and data["texture"]["radius"] == "50um"
    assert labels[("texture", "spacing")] == "--spacing"
    data, _ = apply_flags(FILE, {"--texture": "flat", "--size": "100um"})
    assert data["texture"] == {"name": "flat", "size": "100um"}


def test_grid_flag_replaces_the_texture_grid():
    data, _ = apply_flags(FILE, {"--grid": "32"})
    assert data["model"]["grid"] == "32" and "grid" not in data["texture"]
    assert study.study_from_dict(data).grid == 32


def test_rigid_material_drops_the_file_poisson():
    data, _ = apply_flags(FILE, {"--material-modulus": "rigid"})
    assert "poisson" not in data["material"]
    assert study.study_from_dict(data).material_modulus is None


@pytest.mark.parametrize("flags, file, message", [
    ({"--material-poisson": "0.3"}, {}, "it needs a material modulus, --material-modulus (the default material is rigid)"),
    ({"--material-poisson": "0.3"}, {"modulus": "rigid"}, "[material] modulus rigid is a rigid material, which has none"),
    ({"--material-poisson": "0.3", "--material-modulus": "inf"}, {},
     "--material-modulus inf is a rigid material, which has none"),
])
def test_a_poisson_ratio_without_a_modulus_is_one_message_at_every_door(flags, file, message, tmp_path):
    """Issue 30, item 19: --material-modulus inf --material-poisson 0.3 read as "needs
    --material-modulus"; predict and solve said it in two ways (and overrides in a third)."""
    from typer.testing import CliRunner

    from fingerpad.cli import app

    data, labels = apply_flags({"texture": {"name": "flat"}, "material": file}, flags)
    with pytest.raises(FingerpadError) as got:
        study.study_from_dict(data, labels)
    expected = f"--material-poisson: a Poisson ratio is given, but {message}"
    assert str(got.value) == expected
    if not file:  # the command lines of predict and solve
        args = [a for k, v in flags.items() for a in (k, v)]
        caps = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--grid", "16"]
        for command in (["predict", *caps, "--json", "-"], ["solve", *caps, "--pressure", "1kPa"]):
            res = CliRunner().invoke(app, [*command, *args])
            assert res.exit_code == 2 and res.stderr.strip() == f"error: {expected}", (command, res.output)


def test_finger_params():
    data, labels = apply_flags({}, {"--texture": "flat"}, finger_params=["radius = 8mm", "skin-modulus=0.2MPa"])
    assert data["finger"] == {"radius": "8mm", "skin_modulus": "0.2MPa"}
    assert labels[("finger", "skin_modulus")] == "--finger-param skin_modulus"


def test_finger_param_ridge_fraction_sets_constant_fraction_ridges():
    """ridge_fraction (a population's name for the constant-fraction model's A_fr/A_g) replaces
    the finger's ridge model, also that of a preset with other ridges; a bad value names the flag."""
    from fingerpad.meso import ConstantFractionRidges

    data, labels = apply_flags(FILE, {"--finger": "ridged"}, finger_params=["ridge_fraction=0.3"])
    finger = study.study_from_dict(data, labels).finger
    assert finger.ridges == ConstantFractionRidges(0.3) and finger.name == "ridged"
    data, labels = apply_flags(FILE, {}, finger_params=["ridge_fraction=1.5"])
    with pytest.raises(FingerpadError, match=r"^--finger-param ridge_fraction fraction: must lie in \(0, 1\]"):
        study.study_from_dict(data, labels)


@pytest.mark.parametrize("kwargs, message", [
    (dict(flags={"--texture": "caps", "--surface": "a.npy"}), "give either --texture NAME or --surface FILE"),
    (dict(flags={}, texture_options=[("radius", "1um")], data={}), r"unexpected option --radius \(texture "
                                                                    r"parameters follow --texture NAME\)"),
    (dict(flags={}, texture_options=[("grid", "32")]), "give the grid size once, as --grid"),
    (dict(flags={}, texture_options=[("size", "1mm")]), "--size is not a texture parameter here"),
    (dict(flags={}, finger_params=["radius"]), "--finger-param: expected NAME=VALUE"),
    (dict(flags={}, finger_params=["thumb=1"]), "--finger-param: unknown finger parameter 'thumb'"),
])
def test_flag_refusals(kwargs, message):
    data = kwargs.pop("data", FILE)
    with pytest.raises(FingerpadError, match=message):
        apply_flags(data, **kwargs)


def test_unknown_flag_is_a_programming_error():
    with pytest.raises(ValueError, match="not study flags: --colour"):
        apply_flags(FILE, {"--colour": "red"})


def test_errors_after_merging_name_the_flag():
    data, labels = apply_flags(FILE, {"--loads": ["4N:1N:3"]})
    with pytest.raises(FingerpadError, match=r"^--loads: STOP '1N' is below START '4N'"):
        study.study_from_dict(data, labels)
    data, labels = apply_flags(FILE, {"--material-modulus": "-1Pa"})
    with pytest.raises(FingerpadError, match=r"^--material-modulus"):
        study.study_from_dict(data, labels)
    data, labels = apply_flags(FILE, {}, texture_options=[("spacing", "2N")])
    with pytest.raises(FingerpadError, match=r"--spacing"):
        study.study_from_dict(data, labels).build_texture()


def test_merged_study_values():
    data, labels = apply_flags(FILE, {"--loads": ["1N:4N:3"], "--log": False, "--zones-at": "2N",
                                      "--skin-modulus": "0.2MPa", "--finger": "soft"})
    s = study.study_from_dict(data, labels)
    np.testing.assert_allclose(s.loads, [1.0, 2.5, 4.0])
    assert s.zone_load == 2.0 and s.finger.name == "soft" and s.finger.skin_modulus == pytest.approx(0.2e6)
