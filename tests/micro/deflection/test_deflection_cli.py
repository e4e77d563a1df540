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
    (["--texture", "blobs", "--height", "10um"], "--texture must be ellipsoids or ridges"),
    (["--texture", "ridges", "--height", "40um", "--width", "50um", "--spacing", "200um"], "higher than half"),
    (["--texture", "ridges", "--height", "10um", "--width", "50um", "--spacing", "200um", "--pressure", "5kPa:1kPa"],
     "LOW must not exceed HIGH"),
    (["--texture", "ellipsoids", "--height", "10um", "--semi-axis-x", "120um", "--semi-axis-y", "20um",
      "--spacing-x", "200um", "--spacing-y", "200um"], "overlap"),
    (["--texture", "ellipsoids", "--height", "10um", "--semi-axis-x", "20um"], "--semi-axis-y is required"),
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
    assert res.output.count("gain 1") == 2


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
