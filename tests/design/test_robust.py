"""Inverse design for a population of fingers (issue 22): the search's vectorised screen is the
direct population prediction, the proposed texture meets the coverage or the quantile when
predicted directly (recomputed here with run_population), a population without spread gives the
plain design's texture, an unreachable target says how close the best gets, and inputs that make
no sense are refused before any prediction with nothing written."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.design import inverse_design, robust
from fingerpad.design.inverse import DesignProblem, parse_target
from fingerpad.design.inverse_design import design_textures, free_axes
from fingerpad.design.robust import population_candidate, population_goal, screen_candidate
from fingerpad.errors import FingerpadError
from fingerpad.population import population_from_table, run_population
from fingerpad.study.spec import read_study_file, study_from_dict

runner = CliRunner()

#: The example study (caps R 100 um, h 20 um, hexagonal spacing 175 um on a 0.5 GPa foil).
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "study.toml"

#: A narrow population (skin modulus and tau0 spread by a few per cent): reachable coverages.
NARROW = {"size": 32, "seed": 2,
          "skin_modulus": {"distribution": "uniform", "low": "0.29MPa", "high": "0.31MPa"},
          "tau0": {"distribution": "normal", "mean": "8.1kPa", "sd": "0.2kPa"}}
#: A wide one (the adults' ranges of E_s and the ridge fraction): 5 % holds few of them.
WIDE = {"size": 32, "seed": 1,
        "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
        "ridge_fraction": {"distribution": "uniform", "low": 0.1, "high": 0.7}}
VARY = {"spacing": ("150um", "400um")}


def study_file(tmp_path: Path, kind: str = "hertz") -> Path:
    """The example study with the model ``kind`` on a coarse grid (16 px along x)."""
    text = EXAMPLE.read_text(encoding="utf-8")
    text = re.sub(r'(?m)^kind = "both"', f'kind = "{kind}"\ngrid = 16', text)
    assert f'kind = "{kind}"' in text
    path = tmp_path / f"study-{kind}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def direct(study: Path, spacing: float, table: dict, load: float) -> np.ndarray:
    """Each member's mu/mu_ref at ``load`` (N) on caps of ``spacing`` (m), by run_population."""
    data = read_study_file(str(study))
    data["texture"]["spacing"] = spacing
    data["loads"] = {"values": [load]}
    res = run_population(study_from_dict(data), population_from_table(table))
    return res.values("mu_normalised")[:, 0]


@pytest.mark.parametrize("kind", ["hertz", "bem"])
def test_the_search_screen_is_the_direct_population_prediction(tmp_path, kind):
    """The screen (every member on the one cell at p E0/E_i, the member path of run_population)
    gives run_population's numbers: quantiles of the targets, critical loads (both by Brent's
    search, formerly interpolated on a load grid: 1e-9), coverage, objective. Round-off only
    where the two cells were prepared over different loads (other nodes)."""
    data = read_study_file(str(study_file(tmp_path, kind)))
    problem = DesignProblem(base=data, axes=free_axes(VARY, "caps"),
                            targets=[parse_target("mu_rel=0.5@1N"), parse_target("mu=0.2@2N")],
                            min_critical_load=0.05, tolerance=0.3)
    goal = population_goal(WIDE, "0.5", None)
    screened = screen_candidate(problem, goal)(problem, {"spacing": 200e-6})
    checked = population_candidate(problem, goal, {"spacing": 200e-6})
    assert not screened.reason and not checked.reason
    for t in problem.targets:
        a, b = screened.population["quantiles"][str(t)], checked.population["quantiles"][str(t)]
        np.testing.assert_allclose(list(a.values()), list(b.values()), rtol=1e-12)
    np.testing.assert_allclose(list(screened.population["critical_load"].values()),
                               list(checked.population["critical_load"].values()), rtol=1e-12)
    assert screened.population["coverage"] == checked.population["coverage"]
    assert 0 < checked.population["coverage"] < 1  # the case is not trivial
    assert screened.objective == pytest.approx(checked.objective, rel=1e-12)
    # with --coverage C the candidate's critical load is the (1 - C) quantile: the JSON's
    # critical_load levels name it, so the reported number can be checked from the file
    covered = population_candidate(problem, population_goal(WIDE, "0.7", None), {"spacing": 200e-6})
    assert covered.population["critical_load"]["0.3"] == covered.critical_load


def test_robust_design_round_trip(tmp_path):
    """The proposed texture, predicted directly for the whole population (recomputed here with
    run_population), has at least 90 % of the members within the tolerance of the target, and
    the command reports that coverage; the Python API gives the command's document."""
    study = study_file(tmp_path)
    goal_value = float(np.median(direct(study, 260e-6, NARROW, 1.0)))
    target = f"mu_rel={goal_value:.6g}@1N"
    pop_file = tmp_path / "panel.toml"
    pop_file.write_text("[population]\nsize = 32\nseed = 2\n"
                        'skin_modulus = { distribution = "uniform", low = "0.29MPa", high = "0.31MPa" }\n'
                        'tau0 = { distribution = "normal", mean = "8.1kPa", sd = "0.2kPa" }\n')
    res = runner.invoke(app, ["design", str(study), "--vary", "spacing=150um:400um", "--target", target,
                              "--population", str(pop_file), "--coverage", "0.9", "--evaluations", "16",
                              "--candidates", "2", "--json", "-"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert doc["met"] and doc["population"]["coverage"] == 0.9 and doc["population"]["size"] == 32
    best = doc["candidates"][0]
    values = direct(study, best["params"]["spacing"], NARROW, 1.0)
    within = np.abs(values / float(target.split("=")[1].split("@")[0]) - 1) <= 0.05
    assert within.mean() >= 0.9
    assert best["population"]["coverage"] == within.mean()
    assert best["population"]["members_meeting"] == int(within.sum())
    keys = [r["key"] for r in doc["references"]]  # a Hertz cell: no contact solver to cite
    assert keys[:2] == ["sergachev2021", "fingerpad"] and "johnson1985" in keys and "polonsky1999" not in keys
    np.testing.assert_allclose(best["population"]["quantiles"][target]["0.5"], np.quantile(values, 0.5), rtol=1e-12)
    api = design_textures(study, {"spacing": ("150um", "400um")}, [target], population=str(pop_file), coverage=0.9,
                          evaluations=16, candidates=2)
    assert json.loads(json.dumps(api.document())) == doc


def test_zero_spread_coverage_one_is_the_plain_design(tmp_path):
    """A population whose members are all the study's finger, asked for 100 % coverage, searches
    the same objective as the plain design and proposes the same texture."""
    study = study_file(tmp_path)
    target = f"mu_rel={float(direct(study, 230e-6, {'size': 1}, 1.0)[0]):.6g}@1N"
    plain = design_textures(study, VARY, [target], evaluations=14, candidates=2)
    same = {"size": 16, "skin_modulus": {"distribution": "normal", "mean": "0.3MPa", "sd": "0MPa"},
            "tau0": {"distribution": "uniform", "low": "8.1kPa", "high": "8.1kPa"}}
    robust_result = design_textures(study, VARY, [target], evaluations=14, candidates=2, population=same,
                                    coverage=1)
    assert plain.met and robust_result.met
    assert [c.params for c in robust_result.candidates] == [c.params for c in plain.candidates]
    best = robust_result.candidates[0]
    assert best.population["coverage"] == 1.0
    assert best.values[target] == pytest.approx(plain.candidates[0].values[target], rel=1e-12)


def test_quantile_target_met_by_the_median_of_a_direct_prediction(tmp_path):
    study = study_file(tmp_path)
    target_value = float(np.median(direct(study, 300e-6, WIDE, 1.0)))
    target = f"mu_rel={target_value:.6g}@1N"
    result = design_textures(study, VARY, [target], population=WIDE, quantile=0.5, evaluations=14, candidates=1)
    assert result.met
    best = result.candidates[0]
    median = float(np.median(direct(study, best.params["spacing"], WIDE, 1.0)))
    assert abs(median / float(f"{target_value:.6g}") - 1) <= 0.05
    assert best.values[target] == pytest.approx(median, rel=1e-12)
    # the wide population is not covered by the median's design: the coverage says so
    assert best.population["coverage"] < 0.9


def test_unreachable_coverage_reports_the_best_coverage(tmp_path):
    """When no texture holds 90 % of a wide population within 5 %, the command says how close the
    best gets (its coverage and quantiles), exits 0 and writes the candidates."""
    study = study_file(tmp_path)
    target_value = float(np.median(direct(study, 250e-6, WIDE, 1.0)))
    out = tmp_path / "d.json"
    wide = tmp_path / "wide.toml"
    wide.write_text("[population]\nsize = 32\nseed = 1\n"
                    'skin_modulus = { distribution = "uniform", low = "0.2MPa", high = "0.5MPa" }\n'
                    'ridge_fraction = { distribution = "uniform", low = 0.1, high = 0.7 }\n')
    res = runner.invoke(app, ["design", str(study), "--vary", "spacing=150um:400um", "--target",
                              f"mu_rel={target_value:.4g}@1N", "--population", str(wide), "--coverage", "0.9",
                              "--evaluations", "8", "--candidates", "2", "--json", str(out)])
    assert res.exit_code == 0, res.output
    doc = json.loads(out.read_text())
    assert doc["met"] is False and doc["population"]["name"] == "wide.toml"
    assert doc["population"]["size"] == 32 and len(doc["candidates"]) == 2
    best = max(c["population"]["coverage"] for c in doc["candidates"])
    assert 0 < best < 0.9
    message = " ".join(res.stderr.split())
    assert "no texture in the box meets the target" in message and "90 % of the population (wide" in message
    assert f"the best coverage reached is {100 * best:.3g} %" in message
    assert "5-95 %" in message and "error" not in message


@pytest.fixture
def no_prediction(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("a prediction started for an input that makes no sense")

    for name in ("predict_candidate", "search", "population_candidate"):
        monkeypatch.setattr(inverse_design, name, refuse)
    monkeypatch.setattr(robust, "run_population", refuse)


@pytest.mark.parametrize("extra, expect", [
    (["--coverage", "0.9"], "--coverage needs a population"),
    (["--quantile", "0.5"], "--quantile needs a population"),
    (["--population", "adults"], "exactly one of --coverage"),
    (["--population", "adults", "--coverage", "0.9", "--quantile", "0.5"], "exclude each other"),
    (["--population", "adults", "--coverage", "0"], "(0, 1]"),
    (["--population", "adults", "--coverage", "1.5"], "(0, 1]"),
    (["--population", "adults", "--coverage", "-0.2"], "(0, 1]"),
    (["--population", "adults", "--quantile", "-0.1"], "[0, 1]"),
    (["--population", "adults", "--quantile", "1.01"], "[0, 1]"),
    (["--population", "adults", "--quantile", "inf"], "--quantile"),
    (["--population", "nobody", "--coverage", "0.9"], "neither a preset"),
    (["--population", "adults", "--coverage", "0.9", "--vary", "skin_modulus=0.2MPa:0.4MPa"],
     "--vary skin_modulus: the population 'adults' draws skin_modulus for every finger"),
])
def test_bad_population_inputs_are_one_error_line_and_nothing_written(tmp_path, no_prediction, extra, expect):
    study = study_file(tmp_path)
    out = tmp_path / "d.json"
    res = runner.invoke(app, ["design", str(study), "--vary", "spacing=150um:400um", "--target", "mu_rel=0.5@1N",
                              *extra, "--json", str(out)])
    assert res.exit_code == 2, res.output
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ") and expect in lines[0], res.stderr
    assert not out.exists()


def test_a_ridge_fraction_needs_the_constant_fraction_model(tmp_path, no_prediction):
    """A population the study's finger cannot take is refused before any prediction."""
    data = read_study_file(str(study_file(tmp_path)))
    data["finger"] = {"preset": "default", "ridges": {"model": "power_law", "coefficient": 1e-4, "exponent": 0.5}}
    with pytest.raises(FingerpadError, match="constant-fraction"):
        design_textures(data, VARY, ["mu_rel=0.5@1N"], population=WIDE, coverage=0.5)


def test_the_goal_checks_its_ranges_in_python_too():
    pop = population_from_table(NARROW)
    for kwargs in ({"coverage": 0.0}, {"coverage": 1.1}, {"quantile": -0.5}, {"coverage": 0.5, "quantile": 0.5}, {}):
        with pytest.raises(FingerpadError):
            robust.PopulationGoal(pop, **kwargs)
    goal = robust.PopulationGoal(pop, coverage=0.9)
    assert goal.needed == math.ceil(0.9 * 32) and 0.5 in goal.levels
    assert robust.PopulationGoal(pop, quantile=0.3).levels == (0.05, 0.25, 0.3, 0.5, 0.75, 0.95)


def test_the_study_files_population_table_serves_coverage_and_quantile(tmp_path):
    """--coverage or --quantile without --population use the study file's [population] table, as
    predict does; without either the table is ignored and the plain design runs."""
    study = study_file(tmp_path)
    study.write_text(study.read_text(encoding="utf-8") + "\n[population]\nsize = 8\nseed = 2\n"
                     'skin_modulus = { distribution = "uniform", low = "0.29MPa", high = "0.31MPa" }\n',
                     encoding="utf-8")
    result = design_textures(study, VARY, ["mu_rel=0.4@1N"], quantile=0.5, evaluations=3, candidates=1)
    assert result.goal is not None and result.goal.population.size == 8
    assert result.goal.population.name == study.name and result.candidates[0].population["size"] == 8
    plain = design_textures(study, VARY, ["mu_rel=0.4@1N"], evaluations=3, candidates=1)
    assert plain.goal is None and not plain.candidates[0].population


def test_candidates_from_a_sweep_are_screened_and_predicted_for_the_population(tmp_path, monkeypatch):
    """--from-sweep with a population: the sweep's ranked points are screened for the population
    and the reported ones predicted directly for it (the store and its ranking stubbed here; the
    sweep itself is tested in test_sweep.py)."""
    from fingerpad.design import store

    class Store:
        variables = {"spacing": None}

        def load(self):
            return self

    monkeypatch.setattr(store, "open_sweep", lambda path: Store())
    ranked = [{"params": {"spacing": s}, "score": 0.0} for s in (200e-6, 260e-6, 500e-6)]  # 500 um: out of the box
    monkeypatch.setattr(inverse_design, "rank_sweep", lambda ds, targets, limit: ranked)
    study = study_file(tmp_path)
    result = design_textures(study, VARY, ["mu_rel=0.4@1N"], from_sweep="sweep.zarr", population=NARROW,
                             coverage=0.5, candidates=2)
    assert result.source == "sweep sweep.zarr"
    assert sorted(round(c.params["spacing"] * 1e6) for c in result.candidates) == [200, 260]
    for cand in result.candidates:
        values = direct(study, cand.params["spacing"], NARROW, 1.0)
        assert cand.population["coverage"] == np.mean(np.abs(values / 0.4 - 1) <= 0.05)
