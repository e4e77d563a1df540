"""`fingerpad predict --population` from the command line (issue 22)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from fingerpad.cli import app

runner = CliRunner()
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um",
        "--lattice", "hexagonal", "--grid", "32", "--loads", "0.1N:4N:6"]
POP = """
[population]
size = 12
seed = 2
skin_modulus = { distribution = "uniform", low = "0.2MPa", high = "0.5MPa" }
radius = { distribution = "uniform", low = "7mm", high = "11mm" }
tau0 = { distribution = "normal", mean = "8kPa", sd = "1kPa" }
alpha = { values = [0.05, 0.1] }
"""


def invoke(*args):
    return runner.invoke(app, [str(a) for a in args])


def _user_error(result) -> str:
    assert result.exit_code == 2, (result.stdout, result.stderr)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


@pytest.mark.parametrize("model", ["hertz", "bem"])
def test_member_reproduced_by_predict_finger_param(tmp_path: Path, model: str):
    pop = tmp_path / "pop.toml"
    pop.write_text(POP)
    cache = tmp_path / "cache"
    res = invoke("predict", *CAPS, "--model", model, "--cache", cache, "--population", pop, "--json", "-")
    assert res.exit_code == 0, res.stderr
    doc = json.loads(res.stdout)["population"]
    assert len(doc["members"]) == 12 and len(doc["member_results"]) == 12
    i = 7
    params = [f"--finger-param={k}={v!r}" for k, v in doc["members"][i].items()]
    plain = invoke("predict", *CAPS, "--model", model, "--cache", cache, *params, "--json", "-")
    assert plain.exit_code == 0, plain.stderr
    rows = json.loads(plain.stdout)["results"]
    for q in ("area_ratio", "mu", "mu_ref", "mu_normalised"):
        got = np.array([r[q] for r in rows])
        if model == "hertz":
            np.testing.assert_array_equal(doc["member_results"][i][q], got)
        else:  # the member reads the one cell at its E1* (p / E* scaling): round-off apart, the same
            np.testing.assert_allclose(doc["member_results"][i][q], got, rtol=1e-12)
    # the reported quantiles are those of the member curves
    mu = np.array([m["mu"] for m in doc["member_results"]])
    np.testing.assert_allclose(doc["quantiles"]["mu"]["0.95"], np.quantile(mu, 0.95, axis=0), rtol=0, atol=0)


def test_study_file_table_netcdf_and_terminal(tmp_path: Path):
    study = tmp_path / "study.toml"
    study.write_text('[texture]\nname = "caps"\nradius = "50um"\nheight = "10um"\nspacing = "100um"\n'
                     '[model]\nkind = "hertz"\n[loads]\nrange = "0.1N:4N:5"\n' + POP)
    res = invoke("predict", study, "--out", tmp_path / "o", "--quantiles", "0.1,0.5,0.9")
    assert res.exit_code == 0, res.stderr
    assert "median" in res.stdout and max(len(line) for line in res.stdout.splitlines()) <= 80
    ds = xr.open_dataset(tmp_path / "o" / "predict.nc")
    assert ds["member_mu"].shape == (12, 5) and ds["member_skin_modulus"].attrs["units"] == "Pa"
    assert list(ds["quantile"].values) == [0.1, 0.5, 0.9]
    doc = json.loads((tmp_path / "o" / "predict.json").read_text())
    assert set(doc["population"]["quantiles"]["mu"]) == {"0.1", "0.5", "0.9"}
    assert (tmp_path / "o" / "population.png").stat().st_size > 10_000  # the bands figure
    ds.close()


@pytest.mark.parametrize(("table", "words"), [
    ('shoe = { distribution = "uniform", low = 1, high = 2 }', "unknown parameter 'shoe'"),
    ('radius = { distribution = "uniform", low = 0.007, high = "11mm" }', "has no unit"),
    ('tau0 = { distribution = "normal", mean = "8kPa", sd = "-1kPa" }', "must be non-negative"),
    ('tau0 = { distribution = "weibull", mean = "8kPa" }', "unknown distribution"),
])
def test_bad_population_files(tmp_path: Path, table: str, words: str):
    pop = tmp_path / "pop.toml"
    pop.write_text("[population]\nsize = 4\n" + table + "\n")
    res = invoke("predict", *CAPS, "--model", "hertz", "--population", pop, "--out", tmp_path / "o")
    assert words in _user_error(res)
    assert not (tmp_path / "o").exists()


def test_bad_population_name_and_quantiles(tmp_path: Path):
    assert "neither a preset" in _user_error(invoke("predict", *CAPS, "--population", "martians"))
    assert "--quantiles" in _user_error(invoke("predict", *CAPS, "--population", "adults", "--quantiles", "0.5,2"))
    assert "needs a population" in _user_error(invoke("predict", *CAPS, "--quantiles", "0.5"))
