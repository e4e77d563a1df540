"""One parameter declaration (fingerpad.params), models and textures found by adding one file,
strict discovery, and sweep axes that refuse a length without a unit."""

from __future__ import annotations

import re
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import fingerpad.macro
import fingerpad.textures
from fingerpad.cli import app
from fingerpad.design.axes import resolve_axis
from fingerpad.design.spec import sweep_from_dict
from fingerpad.discover import DiscoveryError, collect
from fingerpad.errors import FingerpadError
from fingerpad.finger import FINGER_PARAMS, Finger, get_finger
from fingerpad.macro import GROSS_MODELS
from fingerpad.meso import RIDGE_MODELS, FingerprintBEMRidges
from fingerpad.params import REQUIRED, Param
from fingerpad.study.overrides import apply_flags
from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict

CAPS = {"name": "caps", "radius": "50um", "height": "10um", "spacing": "150um"}

# ------------------------------------------------------------------------------------------------
# the declaration


def test_bounds_give_one_message_on_every_route():
    """Python API, study file, --finger-param and a sweep axis: the same words after the name."""
    tail = "must lie in [0, 1], got 2.0"
    with pytest.raises(FingerpadError) as api:
        Finger(beta=2.0)
    with pytest.raises(FingerpadError) as study:
        study_from_dict({"texture": CAPS, "finger": {"beta": 2}})
    data, labels = apply_flags({"texture": CAPS}, {}, finger_params=["beta=2"])
    with pytest.raises(FingerpadError) as flag:
        study_from_dict(data, labels)
    with pytest.raises(FingerpadError) as sweep:
        sweep_from_dict({"texture": CAPS, "sweep": {"axes": {"beta": [0.1, 2]}}})
    assert str(api.value) == f"hysteresis loss fraction beta: {tail}"
    assert str(study.value) == f"[finger] beta: {tail}"
    assert str(flag.value) == f"--finger-param beta: {tail}"
    assert str(sweep.value) == f"[sweep.axes] beta: {tail}"


def test_param_reads_units_angles_choices_and_bounds():
    length = Param("gap", "length", "a gap", low=0, low_open=True)
    assert length.parse("50um") == 5e-05 and length.parse(2e-3) == 2e-3
    with pytest.raises(FingerpadError, match=r"^--gap: must be positive, got -1.0"):
        length.parse("-1um".replace("um", ""))
    with pytest.raises(FingerpadError, match="is a pressure, expected a length"):
        length.parse("3kPa")
    angle = Param("turn", "angle", "a turn", 0.0)
    assert angle.parse(90) == pytest.approx(np.pi / 2) and angle.parse("0.5rad") == 0.5
    assert angle.default_text() == "0 deg"
    choice = Param("shape", "choice", "a shape", "a", ("a", "b"))
    assert choice.parse(" B ") == "b"
    with pytest.raises(FingerpadError, match="must be one of a, b"):
        choice.parse("c")
    count = Param("n", "count", "a count", 3, low=2)
    assert count.parse("4") == 4
    with pytest.raises(FingerpadError, match="expected an integer"):
        count.parse("2.5")
    with pytest.raises(FingerpadError, match=r"must be >= 2, got 1"):
        count.parse("1")
    # a sweep axis: a dimensional value needs its unit; zero is zero in any unit
    with pytest.raises(FingerpadError, match=r"has no unit; a length needs one"):
        length.parse(7, "[sweep.axes] gap", require_unit=True)
    with pytest.raises(FingerpadError, match="must be positive"):
        length.parse(0, require_unit=True)
    assert Param("n", "ratio", "n").parse("7", require_unit=True) == 7.0  # dimensionless: no unit


def test_finger_fields_are_declared_once():
    """The finger's dataclass fields with numbers are exactly the declared ones, with the defaults."""
    default = Finger()
    for p in FINGER_PARAMS:
        assert getattr(default, p.name) == p.default or p.default is REQUIRED
        assert p.check(getattr(get_finger("default"), p.name)) == getattr(default, p.name)
    # every model class declares each of its fields
    for model in [*GROSS_MODELS.values(), *RIDGE_MODELS.values()]:
        import dataclasses

        fields = {f.name for f in dataclasses.fields(model.factory) if not f.name.startswith("_")}
        # not declared: a measured replica, and the finger's layered skin (the finger sets it)
        assert {p.name for p in model.params} == fields - {"topography", "layer"}, model.name


def test_explorer_starting_values_come_from_the_declarations():
    from fingerpad.explore.inputs import family_examples

    # the caps of the default study, and every family's examples build its texture
    assert {k: v for k, v in DEFAULT_STUDY["texture"].items() if k != "name"} == family_examples("caps")
    for name, family in fingerpad.textures.registry().items():
        examples = family_examples(name)
        assert all(p.name in examples for p in family.params if p.required), name
        tex = family.build(examples)
        assert tex.heights.size > 0


# ------------------------------------------------------------------------------------------------
# FingerprintBEMRidges from a study file


def test_fingerprint_bem_ridges_selectable_from_a_study():
    study = study_from_dict({
        "texture": CAPS, "model": {"kind": "hertz"}, "loads": {"values": ["0.1N", "0.3N"]},
        "finger": {"preset": "soft", "ridges": {"model": "fingerprint-bem", "points_per_wavelength": 6,
                                                "height": "30um", "width": "0.3mm"}},
    })
    ridges = study.finger.ridges
    assert isinstance(ridges, FingerprintBEMRidges)
    # inherited: the finger's pad radius, the study's largest load; the rest as declared
    assert ridges.pad_radius == get_finger("soft").radius and ridges.max_load == 0.3
    assert ridges.height == 30e-6 and ridges.points_per_wavelength == 6
    from fingerpad.study.run import run_study

    pred = run_study(study)
    direct = FingerprintBEMRidges(pad_radius=11e-3, max_load=0.3, points_per_wavelength=6, height=30e-6)
    np.testing.assert_allclose(pred.hertz.ridge_area, direct.area(np.array([0.1, 0.3])), rtol=1e-9)
    assert np.all(pred.hertz.ridge_area < pred.hertz.gross_area)
    with pytest.raises(FingerpadError, match=r"\[finger\] ridges points_per_wavelength: must be >= 6"):
        study_from_dict({"texture": CAPS, "finger": {"ridges": {"model": "fingerprint_bem",
                                                                "points_per_wavelength": 3}}})


# ------------------------------------------------------------------------------------------------
# strict discovery


def _package(tmp_path: Path, name: str, files: dict[str, str]) -> str:
    root = tmp_path / name
    root.mkdir()
    (root / "__init__.py").write_text("")
    for fname, body in files.items():
        (root / fname).write_text(textwrap.dedent(body))
    sys.path.insert(0, str(tmp_path))
    return str(root)


@pytest.fixture
def clean_modules():
    before = set(sys.modules)
    path = list(sys.path)
    yield
    for name in set(sys.modules) - before:
        if name.startswith(("discpkg", "fingerpad.macro.", "fingerpad.textures.")):
            del sys.modules[name]
    sys.path[:] = path


def test_discovery_refuses_a_module_that_declares_nothing(tmp_path, clean_modules):
    good = "from fingerpad.params import Param\nFAMILIES = (Param('a', 'length', 'a'),)\n"
    root = _package(tmp_path, "discpkg", {"good.py": good, "typo.py": good.replace("FAMILIES", "FAMILY"),
                                          "helper.py": "X = 1\n", "_private.py": ""})
    with pytest.raises(DiscoveryError) as info:
        collect("discpkg", [root], "FAMILIES", Param, skip={"helper"})
    msg = str(info.value)
    assert "typo.py" in msg and "declares no FAMILIES" in msg and "FAMILY: did you mean FAMILIES" in msg
    # listed helpers and _-prefixed modules are not asked; the rest is found
    (Path(root) / "typo.py").unlink()
    found = collect("discpkg", [root], "FAMILIES", Param, skip={"helper"})
    assert [p.name for p in found] == ["a"]
    with pytest.raises(DiscoveryError, match="helper.py.*declares no FAMILIES"):
        collect("discpkg", [root], "FAMILIES", Param)
    # something of the wrong type, or nothing at all in the tuple
    (Path(root) / "wrong.py").write_text("FAMILIES = ('caps',)\n")
    with pytest.raises(DiscoveryError, match=r"wrong.FAMILIES holds str 'caps'; expected FAMILIES = \(Param"):
        collect("discpkg", [root], "FAMILIES", Param, skip={"helper"})
    (Path(root) / "wrong.py").write_text("FAMILIES = ()\n")
    del sys.modules["discpkg.wrong"]  # read the file again
    with pytest.raises(DiscoveryError, match="is empty"):
        collect("discpkg", [root], "FAMILIES", Param, skip={"helper"})


def test_misspelt_models_attribute_in_the_macro_package_is_an_error(tmp_path, monkeypatch, clean_modules):
    extra = tmp_path / "extra"
    extra.mkdir()
    (extra / "misspelt.py").write_text("from fingerpad.params import Model\nMODELS_ = ()\n")
    monkeypatch.setattr(fingerpad.macro, "__path__", [*fingerpad.macro.__path__, str(extra)])
    try:
        with pytest.raises(DiscoveryError, match=r"misspelt.py: .*declares no MODELS \(it defines MODELS_"):
            fingerpad.macro.discover_models()
    finally:
        monkeypatch.undo()
        fingerpad.macro.discover_models()
    assert sorted(GROSS_MODELS) == ["dzidek", "hertz", "power_law", "two_regime"]


# ------------------------------------------------------------------------------------------------
# a pad model and a texture family are one file each

LINEAR_PAD = '''
"""A toy pad model: the gross area grows linearly with the load, A_g = c F."""
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from fingerpad.checks import as_loads, scalar_out
from fingerpad.params import Model, Param, check_fields


@dataclass(frozen=True)
class LinearArea:
    PARAMS: ClassVar = (Param("compliance", "ratio", "c of A_g = c F, m^2/N", low=0, low_open=True),)
    compliance: float

    def __post_init__(self):
        check_fields(self, self.PARAMS)

    def area(self, load):
        return scalar_out(self.compliance * as_loads(load))


MODELS = (Model("linear", LinearArea, LinearArea.PARAMS, "A_g = c F"),)
'''


def test_a_pad_model_is_one_file(tmp_path, monkeypatch, clean_modules):
    extra = tmp_path / "pads"
    extra.mkdir()
    (extra / "linear.py").write_text(LINEAR_PAD)
    monkeypatch.setattr(fingerpad.macro, "__path__", [*fingerpad.macro.__path__, str(extra)])
    try:
        fingerpad.macro.discover_models()
        assert "linear" in GROSS_MODELS
        study = study_from_dict({"texture": CAPS, "model": {"kind": "hertz"},
                                 "loads": {"values": ["0.5N", "1N", "2N"]},
                                 "finger": {"gross": {"model": "linear", "compliance": 4e-5}}})
        from fingerpad.study.run import run_study

        pred = run_study(study)
        # A_g = c F exactly, and the default finger's ridges are half of it
        np.testing.assert_allclose(pred.hertz.gross_area, 4e-5 * np.array([0.5, 1.0, 2.0]), rtol=1e-12)
        np.testing.assert_allclose(pred.hertz.ridge_area, 0.5 * pred.hertz.gross_area, rtol=1e-12)
        with pytest.raises(FingerpadError, match=r"\[finger\] gross compliance: must be positive"):
            study_from_dict({"texture": CAPS, "finger": {"gross": {"model": "linear", "compliance": -1}}})
        res = CliRunner().invoke(app, ["fingers"], terminal_width=200)
        assert "linear: A_g = c F" in res.stdout
    finally:
        monkeypatch.undo()
        fingerpad.macro.discover_models()
    assert "linear" not in GROSS_MODELS


STEPS = '''
"""A toy texture: square steps of a height h, half a period wide."""
import numpy as np

from fingerpad.textures.base import Param, Texture, TextureFamily


def steps(*, height, spacing, grid=None):
    n = 64 if grid is None else int(grid)
    h = np.zeros((n, 8))
    h[: n // 2] = height
    return Texture(h, (spacing, spacing * 8 / n), name="steps", family="steps",
                   params={"height": height, "spacing": spacing, "grid": n})


FAMILIES = (TextureFamily(
    name="steps", generator=steps, summary="Square steps.",
    params=(Param("height", "length", "step height", example="5um"),
            Param("spacing", "length", "period of the steps", example="100um"),
            Param("grid", "grid", "grid points along x", None)),
),)
'''


def test_a_texture_family_is_one_file(tmp_path, monkeypatch, clean_modules):
    from fingerpad.textures import base

    extra = tmp_path / "fams"
    extra.mkdir()
    (extra / "steps.py").write_text(STEPS)
    monkeypatch.setattr(fingerpad.textures, "__path__", [*fingerpad.textures.__path__, str(extra)])
    try:
        fingerpad.textures._collect()
        tex = study_from_dict({"texture": {"name": "steps", "height": "5um", "spacing": "100um"}}).build_texture()
        assert tex.peak_to_valley == pytest.approx(5e-6) and tex.size[0] == pytest.approx(100e-6)
        # the explorer's starting values, the sweep axes and the listing follow the declaration
        from fingerpad.explore.inputs import family_examples

        assert family_examples("steps") == {"height": "5um", "spacing": "100um"}
        assert resolve_axis("spacing", "steps").param.doc == "period of the steps"
        res = CliRunner().invoke(app, ["textures"], terminal_width=200)
        assert "steps" in res.stdout and "period of the steps" in res.stdout
    finally:
        monkeypatch.undo()
        base._REGISTRY.pop("steps", None)
    assert "steps" not in fingerpad.textures.registry()


# ------------------------------------------------------------------------------------------------
# a sweep axis without a unit


SWEEP = """
[texture]
name = "caps"
radius = "50um"
height = "10um"
spacing = "150um"

[model]
kind = "hertz"

[sweep.axes]
{axis}
"""


@pytest.mark.parametrize("axis, shown, unit", [
    ("spacing = 7", "7", "length"),
    ("spacing = [100, 200]", "100", "length"),
    ('spacing = "100:200:3"', "'100'", "length"),
    ('spacing = "100um:200:3"', "'200'", "length"),
    ('spacing = { values = ["100um", 2e-4] }', "0.0002", "length"),
    ("material_modulus = [1e6, 2e6]", "1000000.0", "pressure"),
    ("tau0 = \"1000:2000:2\"", "'1000'", "pressure"),
])
def test_sweep_refuses_a_dimensional_axis_without_unit(tmp_path, monkeypatch, axis, shown, unit):
    import fingerpad.design.engine as engine

    def no_cluster(*args, **kwargs):
        raise AssertionError("a cluster was started")

    monkeypatch.setattr(engine, "run_sweep", no_cluster)
    study = tmp_path / "s.toml"
    study.write_text(SWEEP.format(axis=axis))
    out = tmp_path / "o.zarr"
    res = CliRunner().invoke(app, ["sweep", str(study), "--out", str(out)])
    assert res.exit_code == 2, res.output
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, res.stderr
    name = axis.split(" =")[0]
    assert lines[0].startswith(f"error: [sweep.axes] {name}: {shown} has no unit; a {unit} needs one")
    assert not out.exists()


def test_sweep_axis_units_from_python_are_si():
    """Sections built in Python keep SI numbers; asked for, units are required there too."""
    data = {"texture": dict(CAPS), "model": {"kind": "hertz"}, "sweep": {"axes": {"spacing": [150e-6, 200e-6]}}}
    spec = sweep_from_dict(data)
    assert spec.axes[0].values == (150e-6, 200e-6)
    with pytest.raises(FingerpadError, match=r"\[sweep.axes\] spacing: 0.00015 has no unit"):
        sweep_from_dict(data, require_units=True)
    with_units = sweep_from_dict({**data, "sweep": {"axes": {"spacing": ["150um", "200um"]}}}, require_units=True)
    assert with_units.axes[0].values == spec.axes[0].values


@pytest.mark.parametrize("sweep, where", [
    ('design = "lhs"\npoints = 4\n[sweep.axes]\nspacing = "100:200"', "[sweep.axes] spacing: '100'"),
    ('design = "points"\n[[sweep.point]]\nspacing = "150um"\n[[sweep.point]]\nspacing = 2e-4',
     "[[sweep.point]] 2 spacing: 0.0002"),
])
def test_lhs_and_point_designs_refuse_lengths_without_unit(tmp_path, sweep, where):
    from fingerpad.design.spec import read_sweep_file

    study = tmp_path / "s.toml"
    study.write_text(SWEEP.split("[sweep.axes]")[0] + "[sweep]\n" + sweep + "\n")
    with pytest.raises(FingerpadError, match=rf"^{re.escape(where)} has no unit; a length needs one"):
        sweep_from_dict(read_sweep_file(str(study)))
    fixed = study.read_text().replace('"100:200"', '"100um:200um"').replace("2e-4", '"200um"')
    study.write_text(fixed)
    assert sweep_from_dict(read_sweep_file(str(study))).size in (2, 4)
