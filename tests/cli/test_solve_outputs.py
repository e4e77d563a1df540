"""Every output of ``fingerpad solve`` read back equal to the library's own solve: NetCDF fields,
the JSON document, the CSV table, and the figure; a failing output leaves no file at all."""

from __future__ import annotations

import csv
import json
import warnings

import numpy as np
import pytest
from typer.testing import CliRunner

import fingerpad as fp
from fingerpad import netcdf
from fingerpad.cli import app

PRESSURES = (1e3, 4e3)
ARGS = ["solve", "--texture", "sinusoid", "--amplitude", "2um", "--wavelength", "100um", "--grid", "16",
        "--modulus", "1MPa", "--pressure", "1kPa", "--pressure", "4kPa", "--tol", "1e-10"]


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture(scope="module")
def library():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tex = fp.make_texture("sinusoid", amplitude=2e-6, wavelength=100e-6, grid=16)
    solver = fp.HalfSpaceSolver(tex, 1e6, tol=1e-10)
    return [solver.solve_pressure(p) for p in PRESSURES]


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    d = tmp_path_factory.mktemp("solve")
    res = invoke(*ARGS, "--save", d / "cell.nc", "--json", d / "cell.json", "--csv", d / "cell.csv",
                 "--plot", d / "cell.png")
    assert res.exit_code == 0, (res.output, res.exception)
    return d


def test_netcdf_fields_equal_the_library(outputs, library):
    ds = netcdf.load_dataset(outputs / "cell.nc")
    np.testing.assert_allclose(ds["mean_pressure"].values, PRESSURES, rtol=1e-12)
    for k, res in enumerate(library):
        np.testing.assert_allclose(ds["pressure"].values[k], res.pressure, rtol=1e-7, atol=1e-7 * PRESSURES[k])
        assert ds["contact_fraction"].values[k] == pytest.approx(res.contact_fraction, abs=1e-12)
    assert ds.attrs["modulus"] == 1e6 and ds.attrs["texture_name"] == "sinusoid"
    assert ds["pressure"].attrs["units"] == "Pa"


def test_json_and_csv_equal_each_other_and_the_library(outputs, library):
    doc = json.loads((outputs / "cell.json").read_text())
    text = json.dumps(doc)
    assert "NaN" not in text
    with (outputs / "cell.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(PRESSURES)
    psi_column = next(c for c in rows[0] if c.startswith("contact_fraction"))
    for row, res in zip(rows, library, strict=True):
        assert float(row[psi_column]) == pytest.approx(res.contact_fraction, abs=1e-12)
    assert doc["converged"] is True and len(doc["results"]) == len(library)
    for row, res in zip(doc["results"], library, strict=True):
        assert row["mean_pressure"] == pytest.approx(res.mean_pressure, rel=1e-12)
        assert row["contact_fraction"] == pytest.approx(res.contact_fraction, abs=1e-12)
        assert row["contact_state"] == res.contact_state
        assert row["real_contact_area"] == pytest.approx(res.contact_fraction * 100e-6 * 50e-6, rel=1e-12)
        assert row["max_pressure"] == pytest.approx(res.max_pressure, rel=1e-6)


def test_figure_is_drawn(outputs):
    from matplotlib.image import imread

    img = imread(outputs / "cell.png")[..., :3]
    assert img.var() > 1e-3 and len(np.unique(img.reshape(-1, 3), axis=0)) > 10


def test_a_bad_output_name_writes_nothing(tmp_path):
    res = invoke(*ARGS, "--save", tmp_path / "cell.nc", "--plot", tmp_path / "cell.txt")
    assert res.exit_code == 2
    assert "error:" in res.output and "Traceback" not in res.output
    assert list(tmp_path.iterdir()) == []


def test_outputs_list_the_solver_references(outputs):
    """The JSON's ``references`` and the NetCDF's CF ``references`` attribute: the thesis, the
    package and the solver's method (a periodic cell: no Love kernel)."""
    doc = json.loads((outputs / "cell.json").read_text())
    keys = [e["key"] for e in doc["references"]]
    assert keys == ["sergachev2021", "fingerpad", "polonsky1999"]
    ds = netcdf.load_dataset(outputs / "cell.nc")
    assert ds.attrs["references"].splitlines() == [e["citation"] for e in doc["references"]]
