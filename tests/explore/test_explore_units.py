"""The explorer's parts that need no browser: the form as a study (the CLI's validation), study
files that `fingerpad predict` reproduces, plot data, background jobs, uploads, the sweep adapter,
the command line."""

from __future__ import annotations

import copy
import csv
import io
import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cancel import Cancelled
from fingerpad.cli import app
from fingerpad.explore import builders
from fingerpad.explore.inputs import study_data, to_toml, validate
from fingerpad.explore.jobs import Job, Memo, contact_at, run_data
from fingerpad.plotting.specs import spec_csv, spec_json
from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict

runner = CliRunner()
HERTZ = {**copy.deepcopy(DEFAULT_STUDY), "model": {"kind": "hertz"}}


def form(**over: str) -> dict:
    values = {"texture.name": "caps", "texture.radius": "100um", "texture.height": "20um",
              "texture.spacing": "175um", "texture.lattice": "hexagonal", "model.grid": "",
              "material.modulus": "0.5GPa", "material.poisson": "0.4", "finger.preset": "default",
              "finger.skin_modulus": "", "loads.range": "0.1N:4N:40", "loads.log": True, "loads.zones_at": "",
              "model.kind": "hertz", "model.accuracy": ""}
    values.update(over)
    return values


def test_form_is_the_study_the_cli_reads():
    data = study_data(form())
    assert data == HERTZ | {"material": {"modulus": "0.5GPa", "poisson": "0.4"}}  # text, as typed
    check = validate(data)
    assert check.ok and not check.warnings
    ref = study_from_dict(HERTZ)
    assert check.study.reduced_modulus == ref.reduced_modulus
    assert np.array_equal(check.study.loads, ref.loads)


def test_rigid_material_drops_the_poisson_ratio():
    data = study_data(form(**{"material.modulus": "rigid"}))
    assert data["material"] == {"modulus": "rigid"}
    assert validate(data).ok


@pytest.mark.parametrize("field, value, needle", [
    ("texture.radius", "100 furlongs", "unknown unit 'furlongs'"),
    ("texture.lattice", "triangular", None),  # a Select offers only the choices; typed text is refused too
    ("loads.range", "4N:0.1N:10", "STOP"),
    ("material.poisson", "0.7", "material Poisson ratio"),
    ("finger.skin_modulus", "-3kPa", "skin modulus"),
    ("model.kind", "fem", "must be one of"),
])
def test_bad_values_are_reported_beside_their_field(field, value, needle):
    check = validate(study_data(form(**{field: value})))
    assert not check.ok
    mine = [e for e in check.errors if e.field == field]
    assert mine, check.errors
    if needle:
        assert needle in mine[0].message


def test_several_bad_fields_are_reported_at_once():
    check = validate(study_data(form(**{"texture.radius": "1 parsec", "loads.range": "4N:0.1N:10"})))
    assert {e.field for e in check.errors} == {"texture.radius", "loads.range"}


def test_implausible_value_is_a_warning_beside_its_field():
    check = validate(study_data(form(**{"finger.skin_modulus": "3"})))
    assert check.ok
    assert [w.field for w in check.warnings] == ["finger.skin_modulus"]
    assert "unit" in check.warnings[0].message


def test_geometry_error_of_the_generator_is_shown():
    check = validate(study_data(form(**{"texture.height": "200um"})))
    assert not check.ok and "exceeds the sphere radius" in check.errors[0].message


def test_exported_toml_reproduces_the_prediction(tmp_path):
    data = study_data(form(**{"loads.range": "0.2N:3N:7", "loads.zones_at": "1N", "finger.skin_modulus": "0.4MPa"}))
    text = to_toml(data)
    assert tomllib.loads(text) == data
    path = tmp_path / "study.toml"
    path.write_text(text)
    res = runner.invoke(app, ["predict", str(path), "--json", "-"])
    assert res.exit_code == 0, res.output
    from fingerpad.study.outputs import prediction_json

    mine = json.loads(json.dumps(prediction_json(run_data(data))))
    theirs = json.loads(res.stdout)
    assert mine["results"] == theirs["results"]  # exactly the same numbers
    assert mine["critical_load"] == theirs["critical_load"]


def test_plot_data_carry_the_prediction_numbers_in_si():
    """The downloads of a plot are in SI (the page says so), though the plot shows mm²."""
    from fingerpad.plotting.prediction_specs import state_bands

    pred = run_data(HERTZ)
    panels = builders.prediction_panels(pred)
    spec = panels["areas"]
    assert spec.y.label == "contact area (mm²)"  # shown
    rows = list(csv.reader(io.StringIO(spec_csv(spec))))
    assert rows[0][0] == "normal load F (N)"
    col = rows[0].index("real A_re (hertz) [contact area (m²)]")
    assert [float(r[0]) for r in rows[1:]] == list(pred.primary.load)
    assert [float(r[col]) for r in rows[1:]] == list(pred.primary.real_area)  # the numbers themselves
    payload = json.loads(spec_json(spec))
    assert payload["units_system"] == "SI" and payload["y"]["unit"] == "m²"
    assert payload["series"][2]["y"] == list(pred.primary.real_area)
    assert payload["reference_lines"][0]["x"] == pytest.approx(pred.critical_load["hertz"], rel=1e-15)
    assert json.loads(spec_json(panels["friction-normalised"]))["series"][0]["y"] == list(pred.primary.mu_normalised)
    # zones: radii in m though drawn in mm, the profile's pressure in Pa though drawn in kPa
    zones = json.loads(spec_json(panels["zones"]))
    assert zones["zones"][0]["radius"] == pred.zones["ridge_radius"] and zones["x"]["unit"] == "m"
    prof = list(csv.reader(io.StringIO(spec_csv(panels["zone-profile"]))))
    assert prof[0][:2] == ["radius r (m)", "pad pressure p(r) (Eq. 3.7) [pressure (Pa)]"]
    assert float(prof[-1][0]) == pytest.approx(pred.zones["ridge_radius"], rel=1e-12)
    hm = list(csv.reader(io.StringIO(spec_csv(builders.height_map_spec(pred.texture)))))
    assert hm[0] == ["x (m)", "y (m)", "height (m)"]
    assert max(float(r[2]) for r in hm[1:]) == pytest.approx(float(np.max(pred.texture.heights)), rel=1e-12)
    # the bands split the loads at the critical load
    bands = state_bands(pred)
    assert [b.state for b in bands] == ["asperity", "transition"]
    assert bands[0].x1 == pytest.approx(pred.critical_load["hertz"])


def test_images_are_png_and_svg():
    pytest.importorskip("matplotlib")
    from fingerpad.plotting.render import spec_image

    panels = builders.prediction_panels(run_data(HERTZ))
    assert spec_image(panels["zones"], "png").startswith(b"\x89PNG")
    assert b"<svg" in spec_image(panels["zone-profile"], "svg")[:2000]
    with pytest.raises(ValueError):
        spec_image(panels["zones"], "gif")


def test_contact_map_is_one_solver_solve():
    pred = run_data(HERTZ)
    res = contact_at(pred.texture, pred.reduced_modulus, 20e3)
    assert res.converged and math.isclose(res.mean_pressure, 20e3)
    pmap, cmap = builders.contact_specs(res)
    # the map's mean pressure is the one asked for: held in Pa, shown in kPa
    assert float(np.mean(pmap.images[0].z)) == pytest.approx(20e3, rel=1e-6)
    assert float(np.mean(pmap.images[0].value.show(pmap.images[0].z))) == pytest.approx(20.0, rel=1e-6)
    assert pmap.images[0].value.label == "contact pressure (kPa)"
    assert cmap.images[0].overlay.mean() == pytest.approx(res.contact_fraction)


def test_job_finishes_through_the_cache_and_is_remembered(tmp_path):
    data = {**copy.deepcopy(DEFAULT_STUDY), "model": {"kind": "bem", "grid": 32, "cache": str(tmp_path)}}
    memo = Memo()
    job = Job(data, memo)
    assert job.wait(300) and job.state == "done", job.error
    assert 0 < job.done <= job.total  # progress was reported, solve by solve
    assert memo.get(data) is job.result
    again = Job(data)  # a fresh job on the same cell: every node from the cache
    assert again.wait(120) and again.state == "done"
    assert again.result.resolution["solves"] == 0
    assert again.result.critical_load["bem"] == job.result.critical_load["bem"]


def test_job_cancel_stops_at_the_next_solve(tmp_path):
    data = {**copy.deepcopy(DEFAULT_STUDY), "model": {"kind": "bem", "grid": 64, "cache": str(tmp_path)}}
    job = Job(data)
    for _ in range(600):
        if job.done > 0 or job.finished:
            break
        job.wait(0.05)
    job.cancel()
    assert job.wait(120)
    assert job.state == "cancelled" and job.result is None


def test_job_reports_a_user_error():
    job = Job({"texture": {"name": "ridges", "width": "40um", "height": "10um", "spacing": "120um"},
               "model": {"kind": "hertz"}})
    assert job.wait(60) and job.state == "failed" and "Hertz" in job.error


# ---------------------------------------------------------------------------------------------
# the sweep store


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    pytest.importorskip("zarr")
    from synthetic_sweep import synthetic_sweep

    return synthetic_sweep(tmp_path_factory.mktemp("sweep") / "s.zarr")


def test_open_sweep_refuses_what_is_not_a_store(tmp_path):
    from fingerpad.errors import FingerpadError
    from fingerpad.explore.sweepdata import open_sweep

    with pytest.raises(FingerpadError, match="no such sweep store"):
        open_sweep(tmp_path / "none.zarr")
    (tmp_path / "empty.zarr").mkdir()
    with pytest.raises(FingerpadError, match="not a fingerpad sweep store"):
        open_sweep(tmp_path / "empty.zarr")


def test_map_data_follows_the_schema(store):
    from synthetic_sweep import HEIGHTS, SPACINGS

    from fingerpad.explore import sweepdata as sd

    ds = sd.open_sweep(store)
    md = sd.map_data(ds, "spacing", "height", at=1.0)
    assert md["critical_load"].dims == ("height", "spacing")
    crit = md["critical_load"].values
    bem = ds["critical_load_bem"].transpose("height", "spacing").values
    hertz = ds["critical_load_hertz"].transpose("height", "spacing").values
    assert np.array_equal(crit, np.where(np.isnan(bem), hertz, bem), equal_nan=True)
    loads = ds["load"].values
    region = md["region"].values
    assert np.all(region[np.isinf(crit)] == 2)  # never reaching the transition: asperity contact throughout
    inside = np.isfinite(crit) & (crit >= loads.min()) & (crit <= loads.max())
    assert np.all(region[inside] == 1)
    assert np.isnan(region[~md["valid"].values]).all()
    assert md.attrs["at"] == pytest.approx(loads[np.argmin(abs(loads - 1.0))])
    assert list(md["spacing"].values) == list(SPACINGS) and list(md["height"].values) == list(HEIGHTS)


def test_rank_sweep_lists_designs_meeting_the_target(store):
    from fingerpad.explore import sweepdata as sd

    ds = sd.open_sweep(store)
    found = sd.rank_sweep(ds, {"mu_rel": 0.8, "at": 1.0, "tolerance": 0.05})
    assert found
    errors = [abs(c["mu_rel"] - 0.8) for c in found]
    assert errors == sorted(errors) and max(errors) <= 0.05
    for c in found:  # the values listed are the store's
        idx = c["index"]
        assert ds["mu_rel"].isel(**idx).sel(load=c["at"]).item() == c["mu_rel"]
    assert not sd.rank_sweep(ds, {"mu_rel": 5.0, "tolerance": 0.01})
    strict = sd.rank_sweep(ds, {"mu_rel": 0.8, "at": 1.0, "tolerance": 0.05}, min_critical_load=1.0)
    assert all(c["critical_load"] >= 1.0 for c in strict)


def test_a_design_of_the_map_is_a_study_with_its_exact_values(store):
    from fingerpad.explore import sweepdata as sd
    from fingerpad.textures import get_family

    ds = sd.open_sweep(store)
    values = sd.design_values(ds, {"spacing": 2, "height": 2})
    data = sd.design_data(ds, values)
    fam = get_family("caps")
    assert fam.param("spacing").parse(data["texture"]["spacing"]) == values["spacing"]
    assert fam.param("height").parse(data["texture"]["height"]) == values["height"]
    assert validate(data).ok


def test_points_design(tmp_path):
    pytest.importorskip("zarr")
    from synthetic_sweep import synthetic_sweep

    from fingerpad.explore import sweepdata as sd

    ds = sd.open_sweep(synthetic_sweep(tmp_path / "p.zarr", "points"))
    md = sd.map_data(ds, "spacing", "height")
    assert md["critical_load"].dims == ("point",)
    assert sd.rank_sweep(ds, {"mu_rel": 0.7, "tolerance": 1.0})[0]["index"] in range(4)


# ---------------------------------------------------------------------------------------------
# the command


def test_explore_command_help_and_lazy_imports():
    res = runner.invoke(app, ["explore", "--help"])
    assert res.exit_code == 0 and "--sweep" in res.output and "--no-browser" in res.output
    code = "import sys, fingerpad.cli\nprint([m for m in ('panel', 'bokeh', 'tornado') if m in sys.modules])"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.stdout.strip() == "[]", proc.stdout + proc.stderr


def test_explore_with_a_missing_store_is_a_user_error(tmp_path):
    pytest.importorskip("panel")
    res = runner.invoke(app, ["explore", "--no-browser", "--sweep", str(tmp_path / "nope.zarr")])
    assert res.exit_code == 2
    assert "no such sweep store" in res.output


def test_map_view_shows_lengths_in_um_and_downloads_si(store):
    pytest.importorskip("panel")
    from fingerpad.explore import sweepdata as sd
    from fingerpad.explore.views.mapview import MapView

    ds = sd.open_sweep(store)
    view = MapView(None, ds, str(store))
    view.x.value, view.y.value = "spacing", "height"
    fig = view.plot.object
    assert fig.xaxis[0].axis_label == "spacing (um)" and fig.yaxis[0].axis_label == "height (um)"
    data = fig.renderers[0].data_source.data
    spacing_um = np.unique(np.asarray(ds["spacing"].values, float)) * 1e6
    assert np.unique(np.round(data["xc"], 9)) == pytest.approx(spacing_um)
    assert all(label.endswith(" um") for label in data["xlabel"])
    header = view.csv().splitlines()[0]
    assert header.startswith("spacing (m),height (m)")  # downloads stay SI


def test_log_ticks_label_a_narrow_load_range():
    """A 0.1-4 N load axis gets 1-2-5 labels (Bokeh's own log ticker shows only 1 2 3 4 there);
    more than three decades get one label per decade; no positive value, no ticks."""
    from fingerpad.explore.render_bokeh import log_ticks

    major, minor = log_ticks(np.geomspace(0.1, 4.0, 20))
    inside = [t for t in major if 0.1 - 1e-12 <= t <= 4.0]
    assert np.allclose(inside, [0.1, 0.2, 0.5, 1.0, 2.0])
    assert any(abs(t - 0.3) < 1e-12 for t in minor)
    wide, _ = log_ticks(np.array([1e-3, 1e2]))
    assert np.allclose([t for t in wide if 1e-3 <= t <= 1e2], [1e-3, 1e-2, 1e-1, 1, 10, 100])
    narrow, _ = log_ticks(np.array([0.33, 0.9]))
    assert np.allclose([t for t in narrow if 0.33 <= t <= 0.9], [0.5])
    assert log_ticks(np.array([0.0, -1.0, np.nan])) is None


def test_design_values_read_in_the_units_of_the_map():
    """A log-spaced axis value (not round in um) opens as um text that reads back exactly."""
    from fingerpad.explore.sweepdata import _as_text
    from fingerpad.units import parse_quantity

    for v in [*np.geomspace(50e-6, 400e-6, 37), 0.0002519842099789746, 2e-4, 3e-10]:
        text = _as_text(float(v), "m")
        assert text.endswith(("mm", "um", "nm")) and parse_quantity(text, "length") == float(v), text
    for v in np.geomspace(1e3, 3e9, 41):
        text = _as_text(float(v), "Pa")
        assert text.endswith("Pa") and parse_quantity(text, "pressure") == float(v), text
    assert _as_text(0.0002519842099789746, "m").startswith("251.98")
    assert _as_text(2e-4, "m") == "200um"


def test_map_view_labels_the_colour_bar_and_reads_the_base_study(store):
    pytest.importorskip("panel")
    from bokeh.models import ColorBar

    from fingerpad.explore import sweepdata as sd
    from fingerpad.explore.views.mapview import MapView

    ds = sd.open_sweep(store)
    view = MapView(None, ds, str(store))
    bar = view.plot.object.select_one(ColorBar)
    assert bar.title == "critical load (N)"
    view.quantity.value = "mu_rel"
    assert view.plot.object.select_one(ColorBar).title.endswith("N (-)")
    about = view.panel.select(lambda o: "fp-map-about" in getattr(o, "css_classes", []))[0].object
    assert "[texture]" in about and 'name = &quot;caps&quot;' in about and "{&quot;" not in about


def test_a_list_of_loads_typed_with_commas_is_the_study_list():
    """A pinned design with a list of loads fills the field as "0.5N, 1N, 2N": that text is read
    back as the study's list (it was one unreadable quantity), by the study's own loads rule
    (the CLI's --loads reads the same text the same way)."""
    from fingerpad.explore.inputs import study_data, validate

    data = study_data({"texture.name": "caps", "texture.radius": "100um", "texture.height": "20um",
                       "texture.spacing": "175um", "loads.range": "0.5N, 1N, 2N", "model.kind": "hertz"})
    check = validate(data)
    assert not check.errors, check.errors
    assert list(check.study.loads) == [0.5, 1.0, 2.0]


def test_switching_families_watches_each_field_once(tmp_path, monkeypatch):
    """The measured map's fields are the form's own and come back on every switch to that
    family: each is watched once (a watcher added per switch made every change refresh the page
    once more per switch)."""
    pytest.importorskip("panel")
    from types import SimpleNamespace

    from fingerpad.explore.views.single import MEASURED, SingleView

    monkeypatch.setattr(SingleView, "refresh", lambda self, *a, **k: None)  # no predictions here
    view = SingleView(SimpleNamespace(upload_dir=tmp_path, max_upload_bytes=1 << 20, memo=None, state=None,
                                      populations=None))
    def counts() -> list[int]:
        return [len(f.widget.param.watchers.get("value", {}).get("value", [])) for f in view.form.measured.values()]

    view.form.family.widget.value = MEASURED
    first = counts()
    for name in ("caps", MEASURED, "ridges", MEASURED, "caps", MEASURED):
        view.form.family.widget.value = name
    assert counts() == first, (first, counts())


# ---------------------------------------------------------------------------------------------
# superseded work stops (issue 37)


def test_superseded_contact_map_stops_and_is_not_remembered(cancel_midway):
    from fingerpad.explore.jobs import LRU, remembered_contact

    pred = run_data(HERTZ)
    cache = LRU(4)
    out, token = cancel_midway(lambda: contact_at(pred.texture, pred.reduced_modulus, 20e3, cache=cache), 0.01, 3)
    assert isinstance(out, Cancelled)
    assert token.checks <= token.at_cancel + 1  # within one iteration
    assert len(cache) == 0 and remembered_contact(pred.texture, pred.reduced_modulus, 20e3, cache=cache) is None
    res = contact_at(pred.texture, pred.reduced_modulus, 20e3, cache=cache)  # not superseded: remembered
    assert res.converged and remembered_contact(pred.texture, pred.reduced_modulus, 20e3, cache=cache) is res


def test_superseded_bem_job_stops_mid_solve_and_stores_nothing_partial(tmp_path, slow_token):
    """A BEM run cancelled in the middle of a contact solve (each iteration made slow) ends
    within one iteration; every node it left in the cache is the node an uninterrupted run
    stores, bit for bit (nothing partial), and a run afterwards gives the numbers of a run on an
    empty cache."""
    def rows(folder):
        return {(p.name, q): row for p in folder.rglob("*.json") for q, row in json.loads(p.read_text())
                .get("points", {}).items()}

    data = {**copy.deepcopy(DEFAULT_STUDY), "model": {"kind": "bem", "grid": 32, "cache": str(tmp_path / "a")}}
    token = slow_token(0.002, 400)  # the coarse cell done, the fine one in the middle of a solve
    job = Job(data, token=token)
    assert token.reached.wait(300), job.state
    job.cancel()
    assert job.wait(60) and job.state == "cancelled" and job.result is None
    assert token.checks <= token.at_cancel + 1
    left = rows(tmp_path / "a")
    assert left  # the coarse cell's nodes, complete before the cancel
    fresh = Job({**data, "model": {**data["model"], "cache": str(tmp_path / "b")}})
    assert fresh.wait(300) and fresh.state == "done"
    full = rows(tmp_path / "b")
    assert len(left) < len(full) and all(full[k] == row for k, row in left.items())
    again = Job(data)
    assert again.wait(300) and again.state == "done"
    assert again.result.critical_load["bem"] == fresh.result.critical_load["bem"]
    assert np.array_equal(again.result.bem.area_ratio, fresh.result.bem.area_ratio)


# ---------------------------------------------------------------------------------------------
# scanning a number field (issue 37): steps, units, limits and slider ranges from the Param


def test_scan_steps_in_the_declared_unit_and_stays_in_the_limits():
    from fingerpad.errors import FingerpadError
    from fingerpad.explore.scan import ZONE_LOAD, scan_for, slider_text, step_text
    from fingerpad.finger import finger_param
    from fingerpad.materials import MATERIAL_MODULUS, MATERIAL_POISSON
    from fingerpad.textures import get_family

    spacing = scan_for(get_family("caps").param("spacing"), "spacing", slider=True)
    assert (spacing.unit, spacing.step, spacing.hint) == ("um", 10.0, "↑↓ 10 µm (Shift ×10)")
    assert step_text(spacing, "175um", 1) == "185um" and step_text(spacing, "175um", -10) == "75um"
    assert step_text(spacing, "0.175mm", 2) == "195um"  # read as the field reads it, written in um
    assert step_text(spacing, "15um", -3) == "5um"  # a length is positive: the last step above zero
    assert spacing.slider == (50.0, 700.0)  # 175 um / 4 .. x 4 on the 10 um grid
    assert slider_text(spacing, 183.3) == "180um" and slider_text(spacing, 1e9) == "700um"
    with pytest.raises(FingerpadError, match="cannot read"):
        step_text(spacing, "abc", 1)  # what the field refuses is not stepped
    with pytest.raises(FingerpadError):
        step_text(spacing, "175um", 10**6)  # a forged count of steps
    with pytest.raises(FingerpadError):
        slider_text(spacing, float("nan"))
    beta = scan_for(finger_param("beta"), "beta")  # in [0, 1], closed
    assert (beta.unit, beta.step) == ("", 0.01)
    assert step_text(beta, "0.95", 10) == "1" and step_text(beta, "1", 1) == "1" and step_text(beta, "0.05", -10) == "0"
    poisson = scan_for(MATERIAL_POISSON, "material Poisson ratio")  # in (-1, 0.5]
    assert step_text(poisson, "0.4", 1) == "0.41" and step_text(poisson, "0.45", 10) == "0.5"
    assert step_text(poisson, "-0.99", -1) == "-0.99"  # -1 is open: the last step short of it
    modulus = scan_for(MATERIAL_MODULUS, "material modulus")
    assert (modulus.unit, modulus.step) == ("MPa", 10.0) and step_text(modulus, "0.5GPa", 1) == "510MPa"
    with pytest.raises(FingerpadError):
        step_text(modulus, "rigid", 1)
    pad = scan_for(finger_param("radius"), "pad radius")
    assert (pad.unit, pad.step) == ("mm", 0.1) and step_text(pad, "9mm", -1) == "8.9mm"
    zone = scan_for(ZONE_LOAD, "zone-map load", fallback=4.0).with_slider(0.1, 4.0)
    assert zone.slider == (0.1, 4.0) and step_text(zone, "0.1N", -1) == "0.1N" and step_text(zone, "2N", 3) == "2.3N"
    assert scan_for(get_family("caps").param("lattice"), "lattice") is None  # a choice: no steps


def test_every_declared_number_of_the_finger_steps_and_reads_back():
    """Every number the finger declares gets a step in a unit its own field reads back (a new
    dimension, e.g. the work of adhesion's surface energy, must not break the page)."""
    from fingerpad.explore.scan import scan_for, step_text, value_text
    from fingerpad.finger import FINGER_PARAMS, finger_param

    for p in FINGER_PARAMS:
        scan = scan_for(p, p.name, fallback=1.0)
        if scan is None:
            assert p.kind == "choice"
            continue
        text = step_text(scan, value_text(scan, scan.step * scan.factor * 3), 1)
        assert scan.read(text) > 0, (p.name, text)
    w = scan_for(finger_param("work_of_adhesion"), "work of adhesion")
    assert (w.unit, w.step) == ("mJ/m2", 1.0) and step_text(w, "0.05J/m2", 1) == "51mJ/m2"
    assert step_text(w, "5mJ/m2", -10) == "0mJ/m2"  # w >= 0, closed: stops on it
