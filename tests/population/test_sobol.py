"""Sobol sensitivity indices of a population (issue 22): the estimator against the Ishigami
function's exact indices, a one-parameter population, parameters that do not enter a quantity."""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.errors import FingerpadError
from fingerpad.population import population_from_table, run_population
from fingerpad.study.run import run_study
from fingerpad.population.sobol import population_sensitivity, saltelli_points, sobol_indices
from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict


def _ishigami_exact(a: float = 7.0, b: float = 0.1) -> tuple[np.ndarray, np.ndarray]:
    """First-order and total indices of f = sin x1 + a sin^2 x2 + b x3^4 sin x1, x_i ~ U(-pi, pi)."""
    v1 = 0.5 * (1 + b * math.pi**4 / 5) ** 2
    v2 = a**2 / 8
    v13 = 8 * b**2 * math.pi**8 / 225
    var = v1 + v2 + v13
    return np.array([v1, v2, 0.0]) / var, np.array([v1 + v13, v2, v13]) / var


def _ishigami(x: np.ndarray, a: float = 7.0, b: float = 0.1) -> np.ndarray:
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def _design(f, d: int, n: int, seed: int = 0):
    a, b = saltelli_points(d, n, seed)
    a, b = -math.pi + 2 * math.pi * a, -math.pi + 2 * math.pi * b
    ab = []
    for i in range(d):
        m = a.copy()
        m[:, i] = b[:, i]
        ab.append(f(m))
    return f(a), f(b), np.stack(ab)


@pytest.mark.parametrize("n", [1024, 4096])
def test_ishigami_indices_within_their_confidence(n):
    first, total = _ishigami_exact()
    res = sobol_indices(*_design(_ishigami, 3, n), bootstrap=300)
    assert np.all(np.abs(res["first"] - first) <= res["first_conf"]), (res["first"], first, res["first_conf"])
    assert np.all(np.abs(res["total"] - total) <= res["total_conf"]), (res["total"], total, res["total_conf"])
    assert np.all(res["first_conf"] < 0.15) and np.all(res["total_conf"] < 0.1)


def test_intervals_shrink_as_n_grows_and_an_absent_input_has_zero_indices():
    # x3 does not enter: f(AB_3) = f(A) exactly, so its total index is exactly 0
    def f(x):
        return np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2

    small = sobol_indices(*_design(f, 3, 256))
    large = sobol_indices(*_design(f, 3, 4096))
    assert np.all(large["first_conf"][:2] < small["first_conf"][:2])
    assert large["total"][2] == 0 and large["total_conf"][2] == 0
    assert abs(large["first"][2]) <= large["first_conf"][2] + 1e-12
    # additive: first = total, and they add up to 1
    np.testing.assert_allclose(large["first"][:2].sum(), 1.0, atol=0.05)


def _hertz_study():
    d = copy.deepcopy(DEFAULT_STUDY)
    d["model"] = {**d.get("model", {}), "kind": "hertz"}
    d["loads"] = {"range": "0.1N:4N:6", "log": True}
    return study_from_dict(d)


def test_one_varying_parameter_explains_everything():
    study = _hertz_study()
    pop = population_from_table({
        "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
        "radius": {"distribution": "normal", "mean": "9mm", "sd": "0mm"},
        "tau0": {"distribution": "uniform", "low": "8kPa", "high": "8kPa"},
    })
    res = population_sensitivity(run_study(study), pop, 128)
    assert res.parameters == ["skin_modulus", "radius", "tau0"] and res.evaluations == 128 * 3
    for quantity in ("mu_normalised", "log10_critical_load"):
        entry = res.indices[quantity]["skin_modulus"]
        assert np.all(np.abs(np.asarray(entry["first"]) - 1.0) <= np.asarray(entry["first_conf"]) + 1e-9)
        assert np.all(np.abs(np.asarray(entry["total"]) - 1.0) <= np.asarray(entry["total_conf"]) + 1e-9)
        for other in ("radius", "tau0"):
            assert np.all(np.asarray(res.indices[quantity][other]["total"]) == 0)


def test_parameters_that_do_not_enter_the_critical_load_have_zero_indices():
    """tau0, alpha and beta enter the friction, not the contact: their indices of the critical
    load are exactly 0 (the frozen column changes nothing), those of mu/mu_ref are not."""
    study = _hertz_study()
    pop = population_from_table({
        "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
        "ridge_fraction": {"distribution": "uniform", "low": 0.1, "high": 0.7},
        "tau0": {"distribution": "uniform", "low": "4kPa", "high": "12kPa"},
        "alpha": {"distribution": "uniform", "low": 0.0, "high": 0.2},
    })
    res = population_sensitivity(run_study(study), pop, 128)
    for name in ("tau0", "alpha"):
        for quantity in ("critical_load", "log10_critical_load"):
            entry = res.indices[quantity][name]
            assert entry["total"] == 0 and abs(entry["first"]) <= entry["first_conf"] + 1e-12
        assert np.max(res.indices["mu_normalised"][name]["total"]) > 0.01
    crit = res.indices["log10_critical_load"]
    assert crit["skin_modulus"]["first"] + crit["ridge_fraction"]["first"] == pytest.approx(1.0, abs=0.1)


def test_run_population_attaches_the_indices_to_the_json():
    study = _hertz_study()
    pop = population_from_table({"size": 8, "skin_modulus": {"distribution": "uniform", "low": "0.2MPa",
                                                              "high": "0.5MPa"}})
    doc = run_population(study, pop, sensitivity=16).as_dict()["sensitivity"]
    entry = doc["mu_normalised"]["skin_modulus"]
    assert set(entry) == {"first", "total", "first_conf", "total_conf"} and len(entry["first"]) == 6
    assert doc["plan"]["evaluations"] == 16 * 3 and doc["plan"]["base_samples"] == 16
    with pytest.raises(FingerpadError, match="no parameter"):
        population_sensitivity(run_study(study), population_from_table({}), 16)


runner = CliRunner()
POP = """
[population]
size = 8
skin_modulus = { distribution = "uniform", low = "0.2MPa", high = "0.5MPa" }
alpha = { distribution = "uniform", low = 0.0, high = 0.2 }
"""
CAPS = ["--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing", "100um", "--model", "hertz",
        "--loads", "0.1N:4N:5"]


def test_cli_table_json_csv_and_figure(tmp_path: Path):
    pop = tmp_path / "pop.toml"
    pop.write_text(POP)
    res = runner.invoke(app, ["predict", *CAPS, "--population", str(pop), "--sensitivity",
                              "--sensitivity-samples", "32", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.stderr
    assert "Sobol indices" in res.stdout and max(len(line) for line in res.stdout.splitlines()) <= 80
    whole = json.loads((tmp_path / "o" / "predict.json").read_text())
    doc = whole["population"]["sensitivity"]
    assert doc["plan"]["evaluations"] == 32 * 4
    # the indices' publications among the run's references (fingerpad.references)
    assert {"sobol2001", "saltelli2010", "jansen1999"} <= {e["key"] for e in whole["references"]}
    rows = (tmp_path / "o" / "sensitivity.csv").read_text().splitlines()
    assert rows[0] == "quantity,load_N,parameter,first,first_conf,total,total_conf"
    assert len(rows) == 1 + 2 * 5 + 2 * 2  # mu/mu_ref per load and parameter, two critical-load rows each
    assert (tmp_path / "o" / "sensitivity.png").stat().st_size > 10_000


@pytest.mark.parametrize(("args", "words"), [
    (["--sensitivity"], "needs a population"),
    (["--sensitivity-samples", "64"], "needs --sensitivity"),
    (["--population", "POP", "--sensitivity", "--sensitivity-samples", "1"], "at least 2"),
])
def test_cli_refusals(tmp_path: Path, args, words):
    pop = tmp_path / "pop.toml"
    pop.write_text(POP)
    args = [str(pop) if a == "POP" else a for a in args]
    res = runner.invoke(app, ["predict", *CAPS, *args, "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ") and words in lines[0], res.stderr
    assert not (tmp_path / "o").exists()


def test_measured_populations_refused_and_correlations_noted():
    """A measured panel (pop-sources' Population.measured) has no design; correlations (its
    Population.correlations) are left out with a note. Stand-ins carry just those fields."""
    from types import SimpleNamespace

    study = _hertz_study()
    pop = population_from_table({"skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
                                 "radius": {"distribution": "uniform", "low": "7mm", "high": "11mm"}})
    measured = SimpleNamespace(distributions=pop.distributions, seed=0, measured=({"skin_modulus": 3e5},))
    with pytest.raises(FingerpadError, match="measured members"):
        population_sensitivity(run_study(study), measured, 16)
    correlated = SimpleNamespace(distributions=pop.distributions, seed=0, correlations=(("skin_modulus", "radius",
                                                                                          0.5),))
    res = population_sensitivity(run_study(study), correlated, 16)
    assert any("correlations are not used" in n for n in res.notes)


def test_a_first_order_estimate_above_its_total_is_marked_and_explained(capsys, monkeypatch):
    """Issue 31: the table showed first-order indices above total ones without saying why. The
    estimates come from two estimators with their own sampling error; a parameter acting alone
    (S_T ~ S) may show either above the other. The table marks such a pair and a note explains."""
    from fingerpad.cli._sensitivity import print_sensitivity
    from fingerpad.population.sobol import first_above_total_note

    def entry(first, total, fc=0.05, tc=0.04):
        return {"first": first, "total": total, "first_conf": fc, "total_conf": tc}

    fine = {"log10_critical_load": {"a": entry(0.3, 0.4), "b": entry(0.5, 0.6)}}
    assert first_above_total_note(fine) is None
    within = {"log10_critical_load": {"a": entry(0.55, 0.53), "b": entry(0.4, 0.45)}}
    note = first_above_total_note(within)
    assert "first-order above total in 1 entries" in note and "0.02" in note and "all within" in note
    beyond = {"log10_critical_load": {"a": entry(0.9, 0.5)}}
    assert "0 of them within" in first_above_total_note(beyond) and "--sensitivity-samples" in \
        first_above_total_note(beyond)
    sens = {"plan": {"base_samples": 64, "evaluations": 64 * 5}, "loads": [1.0],
            "mu_normalised": {"a": {**entry([0.55], [0.53]), "first_conf": [0.05], "total_conf": [0.04]},
                              "b": {**entry([0.3], [0.4]), "first_conf": [0.05], "total_conf": [0.04]}},
            "log10_critical_load": {"a": entry(0.5, 0.6), "b": entry(0.3, 0.35)},
            "notes": [note]}
    monkeypatch.setenv("COLUMNS", "80")
    print_sensitivity(sens)
    out = capsys.readouterr().out
    assert "0.55/0.53*" in out and "0.30/0.40 " in out + " "
    assert "* first-order above total" in out and "note: first-order above total" in " ".join(out.split())
    assert max(len(line) for line in out.splitlines()) <= 80
