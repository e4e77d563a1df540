"""Studies and `fingerpad predict`: study files, flags, outputs, Hertz vs BEM critical loads.

Unit cells are kept at 32 points along x (BEM) and the cache in a temporary folder, so that the
module runs in a few seconds.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.cli.predict import build_study
from fingerpad.errors import FingerpadError
from fingerpad.finger import get_finger
from fingerpad.io import MANIFEST
from fingerpad.micro.hertz import critical_load_hertz
from fingerpad.study.outputs import OUTPUT_FILES, prediction_json, write_outputs
from fingerpad.study.run import run_study
from fingerpad.study.spec import Study, TextureSpec, load_study_file, study_from_dict

runner = CliRunner()
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "study.toml"

STUDY_TOML = """
[texture]
name = "caps"
radius = "50um"
height = "10um"
spacing = 100e-6
lattice = "square"

[material]
modulus = "0.5GPa"
poisson = 0.4

[finger]
preset = "stiff"
skin_modulus = "0.4MPa"

[loads]
range = "0.1N:4N:5"
log = true
zones_at = "2N"

[model]
kind = "bem"
grid = 32
tol = 1e-7
max_iter = 3000
"""

CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--grid", "32"]


def invoke(*args):
    return runner.invoke(app, [str(a) for a in args])


def caps_study(tmp_path, *, spacing=100e-6, model="both", loads=(0.2, 1.0, 3.0), lattice="square", grid=32):
    spec = TextureSpec(name="caps", params={"radius": "50um", "height": "10um", "spacing": spacing,
                                            "lattice": lattice})
    return Study(texture=spec, material_modulus=0.5e9, material_poisson=0.4, loads=np.array(loads),
                 model=model, grid=grid, cache=tmp_path / "cache")


def assert_user_error(result, out: Path) -> str:
    assert result.exit_code == 2, (result.exit_code, result.output, result.exception)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    assert "Traceback" not in result.output
    assert not out.exists() or not any(out.iterdir()), "files were written"
    return lines[0]


# ------------------------------------------------------------------------------------------------
# study files and flags


def test_study_file_parsing(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(STUDY_TOML)
    study = load_study_file(path)
    assert study.model == "bem" and study.grid == 32 and study.tol == 1e-7 and study.max_iter == 3000
    assert study.material_modulus == 0.5e9 and study.material_poisson == 0.4
    assert study.finger.name == "stiff" and study.finger.skin_modulus == pytest.approx(0.4e6)
    np.testing.assert_allclose(study.loads, np.geomspace(0.1, 4.0, 5), rtol=1e-12)
    assert study.zone_load == 2.0
    tex = study.build_texture()
    assert tex.name == "caps" and tex.shape == (32, 32)
    assert tex.params["spacing"] == pytest.approx(100e-6) and tex.params["radius"] == pytest.approx(50e-6)
    # E1* from the finger's skin and the material, Eq. 3.4
    e1 = 1 / ((1 - study.finger.skin_poisson**2) / 0.4e6 + (1 - 0.4**2) / 0.5e9)
    assert study.reduced_modulus == pytest.approx(e1, rel=1e-12)


@pytest.mark.filterwarnings("ignore::fingerpad.errors.ResolutionWarning")
def test_flags_override_the_study_file(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(STUDY_TOML)
    study = build_study(
        ctx_args=[str(path), "--spacing", "300um"], finger_param=["radius=8mm"],
        flags={"--grid": "16", "--model": "hertz", "--finger": "default", "--skin-modulus": "0.2MPa",
               "--loads": ["1N:2N:3"], "--material-modulus": "rigid"},
    )
    tex = study.build_texture()
    assert tex.params["spacing"] == pytest.approx(300e-6) and tex.params["radius"] == pytest.approx(50e-6)
    assert tex.shape == (16, 16) and study.model == "hertz"
    assert study.finger.name == "default" and study.finger.radius == pytest.approx(8e-3)
    assert study.finger.skin_modulus == pytest.approx(0.2e6)
    assert study.material_modulus is None and study.material_poisson is None
    # the file says log = true and no --linear is given: the range is log-spaced (one rule, issue 8)
    np.testing.assert_allclose(study.loads, [1.0, 2.0**0.5, 2.0])
    assert study.tol == 1e-7 and study.zone_load == 2.0  # kept from the file
    # --texture replaces the file's texture section
    other = build_study(ctx_args=[str(path)], flags={"--texture": "flat", "--size": "100um", "--grid": "16"})
    assert other.build_texture().name == "flat"


def test_example_study_file_loads():
    study = load_study_file(EXAMPLE)
    assert study.model == "both" and study.grid is None and study.accuracy == 0.02 and study.material_modulus == 0.5e9
    assert study.loads.size == 40 and study.loads[0] == pytest.approx(0.1) and study.loads[-1] == pytest.approx(4.0)
    assert study.build_texture().params["lattice"] == "hexagonal"


@pytest.mark.parametrize(
    "old, new, named",
    [
        ('preset = "stiff"', 'preset = "stiff"\nradiuss = "9mm"', "radiuss"),
        ('kind = "bem"', 'kind = "bem"\ngird = 32', "gird"),
        ('[model]', '[extras]\na = 1\n[model]', "extras"),
        ('lattice = "square"', 'lattice = "square"\nradios = 1', "radios"),
    ],
)
def test_unknown_keys_are_named(tmp_path, old, new, named):
    path = tmp_path / "s.toml"
    path.write_text(STUDY_TOML.replace(old, new))
    with pytest.raises(FingerpadError, match=named):
        load_study_file(path).check()


def test_bad_study_values():
    base = {"texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"}}
    with pytest.raises(FingerpadError, match="positive"):
        study_from_dict({**base, "loads": {"values": [1, -2]}})
    with pytest.raises(FingerpadError, match="kind"):
        study_from_dict({**base, "model": {"kind": "fem"}})
    with pytest.raises(FingerpadError, match="unknown finger preset"):
        study_from_dict({**base, "finger": {"preset": "thumb"}})


# ------------------------------------------------------------------------------------------------
# running


def test_json_schema(tmp_path):
    pred = run_study(caps_study(tmp_path, model="both"))
    data = prediction_json(pred)
    json.dumps(data, allow_nan=False)  # NaN and inf are written as null
    assert set(data["critical_load"]) == {"bem", "hertz"}
    assert {"units", "inputs", "cell", "results"} <= set(data)
    assert {"transition_pressure", "full_contact_pressure", "interpolation_error", "grid", "solves",
            "seconds"} <= set(data["cell"])
    assert data["cell"]["grid"] == [32, 32] and data["cell"]["solves"] > 0
    row = data["results"][0]
    assert {"load", "gross_area", "ridge_area", "real_area", "area_ratio", "ridge_radius", "transition_radius",
            "full_contact_radius", "mu", "mu_ref", "mu_normalised", "contact_state", "hertz"} <= set(row)
    assert {"real_area", "area_ratio", "transition_radius", "mu", "mu_normalised"} <= set(row["hertz"])
    assert [r["contact_state"] for r in data["results"]] == pred.states()
    assert all(r["contact_state"] in ("asperity", "transition", "full") for r in data["results"])
    assert data["units"]["load"] == "N" and data["units"]["real_area"].startswith("m^2")
    # a second run takes the unit-cell curve from the cache
    again = run_study(caps_study(tmp_path, model="both"))
    assert again.cell.solves == 0
    assert again.critical_load == pred.critical_load


@pytest.mark.parametrize("lattice", ["square", "hexagonal"])
def test_hertz_only_reproduces_eq_3_6(tmp_path, lattice):
    study = caps_study(tmp_path, model="hertz", lattice=lattice)
    pred = run_study(study)
    assert pred.bem is None and pred.cell is None
    lam = 100e-6 * (math.sqrt(math.sqrt(3) / 2) if lattice == "hexagonal" else 1.0)
    expected = critical_load_hertz(study.finger.ridge_area, radius=50e-6, height=10e-6, spacing=lam,
                                   reduced_modulus=study.reduced_modulus)
    assert pred.critical_load["hertz"] == pytest.approx(expected, rel=1e-12)
    assert pred.critical_load["bem"] is None
    # the centre state follows the critical load
    for f, state in zip(pred.hertz.load, pred.states(), strict=True):
        assert (state != "asperity") == (f >= expected)
    if lattice == "hexagonal":
        assert any("sqrt(sqrt(3)/2)" in note for note in pred.notes)


def test_bem_critical_load_above_hertz_for_close_caps(tmp_path):
    """Spacing 1.4 x the cap base diameter: the neighbours hold the skin up, so the BEM cell needs
    a higher pressure to touch the base than per-asperity Hertz, which ignores them."""
    r, h = 50e-6, 10e-6
    base_diameter = 2 * math.sqrt(2 * r * h - h * h)  # 60 um
    study = caps_study(tmp_path, spacing=1.4 * base_diameter, model="both", loads=(0.1, 1.0, 4.0))
    pred = run_study(study)
    assert pred.cell.transition_pressure > pred.hertz_cell.transition_pressure
    assert pred.critical_load["bem"] > pred.critical_load["hertz"] > 0


def test_flat_texture_real_area_equals_ridge_area(tmp_path):
    study = Study(texture=TextureSpec(name="flat", size="100um"), grid=16, model="both",
                  loads=np.array([0.1, 1.0, 4.0]), cache=False)
    pred = run_study(study)
    np.testing.assert_allclose(pred.bem.real_area, pred.bem.ridge_area, rtol=1e-12)
    np.testing.assert_allclose(pred.bem.mu_normalised, 1.0, rtol=1e-12)
    assert pred.hertz is None and any("BEM only" in n for n in pred.notes)
    assert pred.states() == ["full"] * 3
    assert json.dumps(prediction_json(pred), allow_nan=False)


def test_texture_checks(tmp_path):
    ridges = TextureSpec(name="ridges", params={"width": "50um", "height": "10um", "spacing": "100um"})
    with pytest.raises(FingerpadError, match="spherical caps"):
        run_study(Study(texture=ridges, model="hertz", grid=32, cache=False))
    patch = TextureSpec(name="caps", params={"radius": "50um", "height": "10um", "spacing": "100um"}, periodic=False)
    with pytest.raises(FingerpadError, match="periodi"):
        run_study(Study(texture=patch, model="bem", grid=32, cache=False))


def test_write_outputs(tmp_path):
    pred = run_study(caps_study(tmp_path, model="both"))
    out = tmp_path / "new" / "out"
    paths = write_outputs(pred, out)
    assert sorted(p.name for p in paths) == sorted(OUTPUT_FILES)
    assert sorted(p.name for p in out.iterdir()) == sorted([*OUTPUT_FILES, MANIFEST])  # no staging leftovers
    from fingerpad.netcdf import load_dataset

    ds = load_dataset(out / "predict.nc")
    assert ds["load"].attrs["units"] == "N" and ds["real_area"].attrs["units"] == "m^2"
    assert ds["cell_contact_fraction"].dims == ("cell_pressure",)
    assert ds["cell_pressure"].attrs["units"] == "Pa"
    np.testing.assert_allclose(ds["real_area"].values, pred.bem.real_area)
    np.testing.assert_allclose(ds["hertz_real_area"].values, pred.hertz.real_area)
    for name in ("areas.png", "friction.png", "zones.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG"


# ------------------------------------------------------------------------------------------------
# command line


def test_predict_cli_end_to_end(tmp_path):
    out = tmp_path / "out"
    res = invoke("predict", *CAPS, "--material-modulus", "0.5GPa", "--material-poisson", "0.4",
                 "--loads", "0.2N:2N:3", "--log", "--cache", tmp_path / "cache", "--out", out,
                 "--json", tmp_path / "copy.json")
    assert res.exit_code == 0, (res.output, res.exception)
    assert sorted(p.name for p in out.iterdir()) == sorted([*OUTPUT_FILES, MANIFEST])
    data = json.loads((out / "predict.json").read_text())
    assert data == json.loads((tmp_path / "copy.json").read_text())
    assert len(data["results"]) == 3 and data["inputs"]["model"] == "both"
    assert "critical load" in res.stdout and "A_re/A_fr" in res.stdout
    # cached second run, JSON on stdout instead of the table
    res = invoke("predict", *CAPS, "--material-modulus", "0.5GPa", "--material-poisson", "0.4",
                 "--loads", "0.2N:2N:3", "--log", "--cache", tmp_path / "cache", "--out", out, "--json", "-")
    assert res.exit_code == 0, res.output
    again = json.loads(res.stdout)
    assert again["cell"]["solves"] == 0 and again["cell"]["cached"] is True
    assert again["critical_load"] == data["critical_load"]


def test_predict_cli_with_study_file(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(STUDY_TOML.replace('kind = "bem"', 'kind = "hertz"'))
    out = tmp_path / "out"
    res = invoke("predict", path, "--loads", "1N", "--out", out, "--json", "-")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert data["inputs"]["model"] == "hertz" and data["inputs"]["loads"] == [1.0]
    assert data["inputs"]["finger"]["name"] == "stiff"


@pytest.mark.parametrize(
    "args, message",
    [
        ([*CAPS, "--finger", "thumb"], "finger preset"),
        ([*CAPS, "--loads", "-1N"], "positive"),
        (["--texture", "ridges", "--width", "50um", "--height", "10um", "--spacing", "100um", "--grid", "32",
          "--model", "hertz"], "spherical caps"),
        ([*CAPS, "--finger-param", "size=3"], "size"),
        ([*CAPS, "--radiuss", "3um"], "radiuss"),
        ([*CAPS, "--model", "fem"], "--model"),
        ([*CAPS, "--material-poisson", "0.3"], "--material-modulus"),
    ],
)
def test_predict_cli_user_errors(tmp_path, args, message):
    out = tmp_path / "out"
    res = invoke("predict", *args, "--cache", tmp_path / "cache", "--out", out)
    line = assert_user_error(res, out)
    assert message in line
    assert not out.exists()


def test_finger_models_command(tmp_path):
    res = invoke("finger-models", "--out", tmp_path, "--loads", "0.1N:4N:5")
    assert res.exit_code == 0, res.output
    assert (tmp_path / "ridge_models.png").read_bytes()[:4] == b"\x89PNG"


def test_finger_presets_all_run_hertz(tmp_path):
    for name in ("default", "soft", "stiff", "stiffening", "ridged"):
        study = caps_study(tmp_path, model="hertz")
        study.finger = get_finger(name)
        pred = run_study(study)
        assert np.all(np.isfinite(pred.hertz.mu)) and np.all(pred.hertz.real_area > 0)
