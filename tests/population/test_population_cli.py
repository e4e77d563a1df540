"""`fingerpad predict --population` from the command line (issue 22)."""

from __future__ import annotations

import csv
import json
import os
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
ridge_fraction = { distribution = "uniform", low = 0.2, high = 0.7 }
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
    # every parameter, the ridge fraction included, is a --finger-param name
    assert set(doc["members"][i]) == {"skin_modulus", "radius", "tau0", "alpha", "ridge_fraction"}
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
    # the CSV tables: the same numbers as the JSON, units in the headers
    pop = doc["population"]
    with open(tmp_path / "o" / "population_bands.csv", newline="") as fh:
        bands = list(csv.DictReader(fh))
    assert [float(r["load_N"]) for r in bands] == pop["loads"]
    assert [float(r["mu_over_mu_ref_q0.9"]) for r in bands] == pop["quantiles"]["mu_normalised"]["0.9"]
    assert [float(r["area_ratio_Are_over_Afr_q0.1"]) for r in bands] == pop["quantiles"]["area_ratio"]["0.1"]
    assert [float(r["p_asperity"]) for r in bands] == pop["state_probability"]["asperity"]
    with open(tmp_path / "o" / "population_members.csv", newline="") as fh:
        members = list(csv.DictReader(fh))
    assert len(members) == 12 and "participant" not in members[0]
    for row, member, result in zip(members, pop["members"], pop["member_results"], strict=True):
        assert float(row["radius_m"]) == member["radius"] and float(row["tau0_Pa"]) == member["tau0"]
        assert float(row["ridge_fraction"]) == member["ridge_fraction"]
        assert float(row["critical_load_N"]) == result["critical_load"]
        assert float(row["mu_over_mu_ref_at_4N"]) == result["mu_normalised"][-1]
        assert float(row["mu_at_0.1N"]) == result["mu"][0]


def test_direction_is_refused_with_its_reason(tmp_path: Path):
    pop = tmp_path / "pop.toml"
    pop.write_text(POP)
    res = invoke("predict", *CAPS, "--model", "hertz", "--population", pop, "--direction", "30", "--out", tmp_path / "o")
    line = _user_error(res)
    assert "--direction" in line and "--finger-param" in line
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(("table", "words"), [
    ('shoe = { distribution = "uniform", low = 1, high = 2 }', "unknown parameter 'shoe'"),
    ('radius = { distribution = "uniform", low = 0.007, high = "11mm" }', "has no unit"),
    ('tau0 = { distribution = "normal", mean = "8kPa", sd = "-1kPa" }', "must be non-negative"),
    ('tau0 = { distribution = "weibull", mean = "8kPa" }', "unknown distribution"),
    ('radius = { distribution = "uniform", low = "7mm", high = "11mm" }\ncorrelations = [["radius", "modulus", 0.3]]',
     "correlations: 'modulus' has no distribution"),
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


def test_quantiles_sorted_and_once_each(tmp_path: Path):
    """`--quantiles 0.9,0.5,0.1,0.5`: the band runs from the lowest level to the highest and each
    level gets one CSV column (given as typed, the terminal said "[90-10 %]" and the CSV had two
    columns named mu_q0.5)."""
    study = tmp_path / "study.toml"
    study.write_text('[texture]\nname = "caps"\nradius = "50um"\nheight = "10um"\nspacing = "100um"\n'
                     '[model]\nkind = "hertz"\n[loads]\nrange = "0.1N:4N:5"\n' + POP)
    res = invoke("predict", study, "--out", tmp_path / "o", "--quantiles", "0.9,0.5,0.1,0.5")
    assert res.exit_code == 0, res.stderr
    assert "[10-90 %]" in res.stdout
    with open(tmp_path / "o" / "population_bands.csv", newline="") as fh:
        header = next(csv.reader(fh))
    assert len(header) == len(set(header))
    assert [h for h in header if h.startswith("mu_q")] == ["mu_q0.1", "mu_q0.5", "mu_q0.9"]
    doc = json.loads((tmp_path / "o" / "predict.json").read_text())
    mu = np.array([m["mu"] for m in doc["population"]["member_results"]])
    np.testing.assert_array_equal(doc["population"]["quantiles"]["mu"]["0.1"], np.quantile(mu, 0.1, axis=0))


LAYERED = ["--skin-layer-thickness", "300um", "--skin-layer-modulus", "0.4MPa", "--skin-substrate-modulus", "40kPa"]
THICKNESS = '[population]\nsize = 4\nskin_layer_thickness = { distribution = "uniform", low = "200um", high = "350um" }\n'


def test_layer_population_on_a_half_space_finger_says_so(tmp_path: Path):
    """A population of layer thicknesses on a half-space study finger: the error names the
    population's parameter and the remedy, not fields the user never asked it for."""
    pop = tmp_path / "pop.toml"
    pop.write_text(THICKNESS)
    line = _user_error(invoke("predict", *CAPS, "--model", "hertz", "--population", pop, "--out", tmp_path / "o"))
    assert "population skin_layer_thickness" in line and "half-space" in line and "--finger layered" in line
    assert not (tmp_path / "o").exists()


def test_hertz_population_of_layer_thicknesses_says_they_do_not_enter(tmp_path: Path):
    """Hertz takes a layered skin as the half-space of its layer: a spread of the thickness gives
    identical members (no band), and the note says why rather than leaving a zero-width band."""
    pop = tmp_path / "pop.toml"
    pop.write_text(THICKNESS)
    res = invoke("predict", *CAPS, *LAYERED, "--model", "hertz", "--population", pop, "--out", tmp_path / "o")
    assert res.exit_code == 0, res.stderr
    assert "spread of skin_layer_thickness does not enter its curves" in res.stderr.replace("\n", " ")
    doc = json.loads((tmp_path / "o" / "predict.json").read_text())
    mu = np.array([m["mu"] for m in doc["population"]["member_results"]])
    assert np.all(mu == mu[0])  # the invariant the note explains


def test_layered_bem_population_notes_a_cell_per_member(tmp_path: Path):
    """On a layered finger a spread of E_s (= E_1) changes the cell's proportions: each member
    is a cell of its own, which the notes say (it cost ~1-2 s a member, unannounced)."""
    pop = tmp_path / "pop.toml"
    pop.write_text('[population]\nsize = 2\nskin_modulus = { values = ["0.3MPa", "0.45MPa"] }\n')
    grid = ["--grid", "16", "--loads", "0.1N:4N:3"]
    res = invoke("predict", *CAPS[:-4], *grid, *LAYERED, "--model", "bem", "--population", pop,
                 "--out", tmp_path / "o")
    assert res.exit_code == 0, res.stderr
    err = res.stderr.replace("\n", " ")
    assert "skin_modulus varies gives each such member a BEM unit cell of its own" in err
    # issue 30, defect 6: the cost note came at the end, under "0 solves (cached)" of the nominal
    # cell; it is said before the work, and the members' own cells are counted
    assert err.index("a BEM unit cell of its own") < err.index("unit cell: bem")
    assert "members: 2 on a unit cell of their own," in err


def test_the_members_own_cells_report_their_progress():
    """Issue 30, defect 6: a layered population solved one cell per member for minutes with no
    progress; run_population reports each member's cell."""
    import copy

    from fingerpad.population import run_population
    from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict

    d = copy.deepcopy(DEFAULT_STUDY)
    d["model"] = {"kind": "bem", "grid": 16, "cache": False}
    d["loads"] = {"values": [0.5, 2.0]}
    d["finger"] = {"preset": "layered"}
    seen = []
    res = run_population(study_from_dict(d), {"size": 3, "skin_modulus": {"values": [0.35e6, 0.4e6, 0.45e6]}},
                         member_progress=lambda i, n: seen.append((i, n)))
    assert seen == [(1, 3), (2, 3), (3, 3)]
    assert res.own_cells == 3 and res.member_solves > 0


def test_a_population_file_is_named_by_its_file_or_its_name_key(tmp_path: Path):
    """Issue 30, defect 21: a file's population was named by its stem, `examples/population.toml`
    reading "population 'population': 256 fingers"; it is named by the file's name, or by the
    table's own `name`, which must be printable text."""
    pop = tmp_path / "population.toml"
    pop.write_text(POP)
    res = invoke("predict", *CAPS, "--model", "hertz", "--population", pop, "--out", tmp_path / "o")
    assert res.exit_code == 0, res.stderr
    assert "population 'population.toml': 12 fingers" in res.stdout
    pop.write_text(POP.replace("[population]\n", '[population]\nname = "lab panel 2026"\n'))
    res = invoke("predict", *CAPS, "--model", "hertz", "--population", pop, "--json", "-")
    assert res.exit_code == 0, res.stderr
    assert json.loads(res.stdout)["population"]["name"] == "lab panel 2026"
    pop.write_text(POP.replace("[population]\n", '[population]\nname = "a\\u001b[2Jb"\n'))
    assert "name: expected a printable text" in _user_error(invoke("predict", *CAPS, "--population", pop))


def test_a_flag_the_population_overrides_is_refused(tmp_path: Path):
    """`--skin-modulus 0.45MPa --population adults` gave members of 0.2-0.5 MPa without a word:
    a finger flag naming a parameter the population draws is refused (as a sweep axis or a
    design --vary is); one the population leaves alone is taken."""
    line = _user_error(invoke("predict", *CAPS, "--model", "hertz", "--population", "adults",
                              "--skin-modulus", "0.45MPa", "--out", tmp_path / "o"))
    assert "--skin-modulus" in line and "draws skin_modulus" in line
    line = _user_error(invoke("predict", *CAPS, "--model", "hertz", "--population", "adults",
                              "--finger-param", "tau0=20kPa", "--out", tmp_path / "o"))
    assert "--finger-param tau0" in line
    assert not (tmp_path / "o").exists()
    pop = tmp_path / "pop.toml"
    pop.write_text(POP)  # draws skin_modulus, radius, tau0, alpha, ridge_fraction: not beta
    res = invoke("predict", *CAPS, "--model", "hertz", "--population", pop, "--finger-param", "beta=0.2",
                 "--out", tmp_path / "o")
    assert res.exit_code == 0, res.stderr


def test_one_quantile_is_shown_not_dashed(tmp_path: Path):
    """`--quantiles 0.9` alone: the table showed '-' in every cell (it printed the median, absent);
    it shows the 90 % quantile and says so."""
    study = tmp_path / "study.toml"
    study.write_text('[texture]\nname = "caps"\nradius = "50um"\nheight = "10um"\nspacing = "100um"\n'
                     '[model]\nkind = "hertz"\n[loads]\nrange = "0.1N:4N:5"\n' + POP)
    res = invoke("predict", study, "--out", tmp_path / "o", "--quantiles", "0.9")
    assert res.exit_code == 0, res.stderr
    words = " ".join(res.stdout.split())
    assert "90 % quantile" in words
    doc = json.loads((tmp_path / "o" / "predict.json").read_text())
    first = next(line for line in res.stdout.splitlines() if line.strip().startswith("0.1 "))
    assert f"{doc['population']['quantiles']['mu']['0.9'][0]:.2f}" in first and " - " not in f"{first} "


def test_a_population_file_with_a_byte_order_mark_is_read(tmp_path: Path):
    """Issue 30, defect 14: a population file saved with a UTF-8 byte-order mark (Windows editors)
    was refused, where a study file is read; other text that is not UTF-8 TOML is one error line."""
    pop = tmp_path / "pop.toml"
    pop.write_bytes(b"\xef\xbb\xbf" + POP.encode())
    res = invoke("predict", *CAPS, "--model", "hertz", "--population", pop, "--json", "-")
    assert res.exit_code == 0, res.stderr
    assert len(json.loads(res.stdout)["population"]["members"]) == 12
    pop.write_bytes(POP.encode("utf-16"))
    assert "is saved as UTF-16" in _user_error(invoke("predict", *CAPS, "--population", pop))
    pop.write_text("[population]\nx = " + "[" * 3000 + "]" * 3000 + "\n")
    assert "nested too deeply" in _user_error(invoke("predict", *CAPS, "--population", pop))


def test_a_population_file_is_read_by_the_one_toml_reader(tmp_path: Path):
    """Every TOML a user gives goes through io.read_toml: a FIFO named as --population is refused
    without being opened (reading one waits for a writer), a binary file is said to be one."""
    fifo = tmp_path / "pop.toml"
    os.mkfifo(fifo)
    line = _user_error(invoke("predict", *CAPS, "--population", fifo))
    assert "cannot read --population file" in line and "a FIFO (named pipe)" in line
    binary = tmp_path / "pop.bin"
    binary.write_bytes(b"\x00\x01" * 64)
    assert "is a binary file" in _user_error(invoke("predict", *CAPS, "--population", binary))
    assert "--population: empty" in _user_error(invoke("predict", *CAPS, "--population", ""))


def test_the_studys_own_finger_is_shown_beside_the_bands(tmp_path: Path):
    """Issue 30, defect 21: `predict --population` never showed the nominal finger's critical load."""
    pop = tmp_path / "pop.toml"
    pop.write_text(POP)
    res = invoke("predict", *CAPS, "--model", "hertz", "--population", pop, "--out", tmp_path / "o")
    assert res.exit_code == 0, res.stderr
    crit = json.loads((tmp_path / "o" / "predict.json").read_text())["critical_load"]["hertz"]
    assert f"the study's own finger: critical load {crit:.3g} N" in res.stdout
    assert all(len(line) <= 80 for line in res.stdout.splitlines())
