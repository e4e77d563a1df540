"""``fingerpad deflection``."""

from __future__ import annotations

import json

import pytest
import typer
import xarray as xr
from typer.testing import CliRunner

from fingerpad.cli import app as fingerpad_app


@pytest.fixture(scope="module")
def app() -> typer.Typer:
    return fingerpad_app


def _run(app, *args):
    return CliRunner().invoke(app, ["deflection", *args])


@pytest.mark.parametrize("args, message", [
    (["--texture", "blobs", "--height", "10um"], "unknown texture 'blobs'"),
    (["--texture", "caps", "--height", "10um"], "has no deflection model"),
    (["--texture", "ridges", "--height", "40um", "--width", "50um", "--spacing", "200um"], "higher than half"),
    (["--texture", "ridges", "--height", "10um", "--width", "50um", "--spacing", "200um", "--pressure", "5kPa:1kPa"],
     "LOW must not exceed HIGH"),
    (["--texture", "ellipsoids", "--height", "10um", "--semi-axis-x", "120um", "--semi-axis-y", "20um",
      "--spacing-x", "200um", "--spacing-y", "200um"], "overlap"),
    (["--texture", "ellipsoids", "--height", "10um", "--semi-axis-x", "20um"], "needs --semi-axis-y"),
    (["--texture", "ridges", "--height", "10zz", "--width", "50um", "--spacing", "200um"], "error"),
])
def test_user_errors_are_one_line_exit_2(app, args, message):
    res = _run(app, *args)
    assert res.exit_code == 2
    lines = [ln for ln in res.output.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1 and message in lines[0]
    assert "Traceback" not in res.output


def test_rigid_texture_prints_gain_one(app):
    res = _run(app, "--texture", "ridges", "--height", "10um", "--width", "50um", "--spacing", "200um")
    assert res.exit_code == 0, res.output
    assert res.output.count("gain 1, rigid texture") == 2


RIDGE = ["--texture", "ridges", "--height", "10um", "--width", "50um", "--spacing", "200um",
         "--material-modulus", "0.3MPa", "--no-cache"]


@pytest.mark.parametrize("option, value", [
    ("--levels", "0"), ("--levels", "21"), ("--mu-max", "-1"), ("--mu-max", "0"), ("--mu-max", "nan"),
    ("--mu-max", "9"), ("--resolution", "1"), ("--resolution", "99"), ("--alpha", "-1"), ("--alpha", "nan"),
    ("--alpha", "inf"), ("--tau0", "-1kPa"), ("--tau0", "nan"), ("--material-poisson", "0.7"),
    ("--material-poisson", "nan"), ("--skin-poisson", "-2"), ("--time-limit", "-1"), ("--time-limit", "0"),
    ("--time-limit", "nan"), ("--max-steps", "0"), ("--direction", "nan"), ("--pressure", "0kPa"),
    ("--pressure", "-5kPa:5kPa"), ("--skin-modulus", "-1MPa"), ("--material-modulus", "0Pa"),
    ("--friction", "sticky"),
])
def test_every_numeric_option_refuses_values_that_make_no_sense(app, option, value):
    """Issue 20: `--time-limit=-1` ran and printed gains; every such value ends before any solve."""
    res = _run(app, *RIDGE, f"{option}={value}")
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1, res.output
    assert "shear ramp" not in res.output and "Traceback" not in res.output


def test_material_poisson_default_is_the_packages(app, tmp_path):
    """One default for the texture's Poisson ratio: the package's (predict's), stated in --help."""
    from fingerpad.materials import Materials

    res = _run(app, "--texture", "ellipsoids", "--height", "30um", "--semi-axis-x", "30um", "--semi-axis-y", "60um",
               "--spacing-x", "250um", "--spacing-y", "250um", "--material-modulus", "0.3MPa", "--pressure", "3kPa",
               "--levels", "1", "--mu-max", "0.1", "--resolution", "2", "--direction", "0", "--no-cache",
               "--out", str(tmp_path / "o"))
    assert res.exit_code == 0, res.output
    doc = json.loads((tmp_path / "o" / "deflection.json").read_text())
    assert doc["materials"]["texture_poisson"] == Materials().material_poisson == 0.35
    assert "default 0.35" in " ".join(CliRunner().invoke(app, ["deflection", "--help"]).output.split())


def test_compliant_run_writes_json_netcdf_png(app, tmp_path):
    out = tmp_path / "out"
    res = _run(app, "--texture", "ellipsoids", "--height", "30um", "--semi-axis-x", "30um", "--semi-axis-y", "60um",
               "--spacing-x", "250um", "--spacing-y", "250um", "--material-modulus", "0.3MPa",
               "--pressure", "3kPa", "--levels", "1", "--mu-max", "0.2", "--resolution", "4",
               "--direction", "0", "--out", str(out), "--no-cache")
    assert res.exit_code == 0, res.output
    doc = json.loads((out / "deflection.json").read_text())
    ramp = doc["directions"][0]["ramps"][0]
    assert ramp["mu"][0] == 0.0 and abs(ramp["mu"][-1]) == pytest.approx(0.2, rel=1e-3)
    assert ramp["gain"][0] == 1.0
    ds = xr.open_dataset(out / "deflection.nc", engine="h5netcdf")
    assert ds["gain"].dims == ("direction", "pressure", "step")
    assert float(ds["mu_reached"].values[0, 0]) == pytest.approx(0.2, rel=1e-3)
    ds.close()
    assert (out / "deflection.png").stat().st_size > 10_000
    assert not list(out.glob(".*part"))


def test_predict_direction_on_a_texture_without_direction_is_refused_before_the_cell(app, monkeypatch, tmp_path):
    """`predict --direction` with caps solved the BEM cell and only then refused: now it refuses
    first (the cell solve would raise here)."""
    import fingerpad.study.run as run

    monkeypatch.chdir(tmp_path)  # the default --out is ./out: not whatever the checkout holds there

    def no_solve(*args, **kwargs):
        raise AssertionError("the unit cell was solved before the texture was checked")

    monkeypatch.setattr(run, "_resolved_cell", no_solve)
    res = CliRunner().invoke(app, ["predict", "--texture", "caps", "--radius", "50um", "--height", "10um",
                                   "--spacing", "200um", "--direction", "0"])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1 and "has no deflection model" in lines[0]
