"""The Weber fraction W is a parameter of the person: a population may draw it (the ``adults``
preset with its sourced spread) and a user may set it (a study file, ``--weber-fraction``, the
Python API, the explorer's field); a W set and a population drawing W are refused together,
with the one message of :func:`fingerpad.population.rules.attach`, at every door."""

from __future__ import annotations

import json
import math
from pathlib import Path
from statistics import NormalDist

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.errors import FingerpadError
from fingerpad.perception.compare import against_flat, compare, member_weber, with_weber
from fingerpad.perception.discrimination import p_correct
from fingerpad.person import WEBER_FRACTION, WEBER_SPREAD
from fingerpad.population.distributions import POPULATION_PARAMS, population_from_table
from fingerpad.population.presets import POPULATION_PRESETS
from fingerpad.population.rules import attach
from fingerpad.study.spec import study_from_dict

runner = CliRunner()

FINGERS = {"size": 16, "seed": 3, "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
           "modulus": {"distribution": "uniform", "low": "10kPa", "high": "100kPa"}}
#: the same fingers, every person with a W of their own
PEOPLE = {**FINGERS, "weber_fraction": {"distribution": "lognormal", "median": 0.11, "sigma": 0.36}}


def _data(cache: Path, **perception) -> dict:
    data = {"texture": {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um",
                        "lattice": "hexagonal"},
            "material": {"modulus": "0.5GPa", "poisson": 0.4}, "loads": {"values": ["0.5N", "1N", "2N"]},
            "model": {"kind": "bem", "grid": 32, "cache": str(cache)}}
    if perception:
        data["perception"] = perception
    return data


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("cells")


def _write(path: Path, data: dict) -> Path:
    lines = []
    for section, values in data.items():
        lines.append(f"[{section}]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in values.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_w_is_a_population_parameter_with_its_sourced_spread():
    assert POPULATION_PARAMS["weber_fraction"] is WEBER_FRACTION
    assert POPULATION_PRESETS["adults"]["weber_fraction"] == WEBER_SPREAD
    members = population_from_table(POPULATION_PRESETS["adults"], name="adults").sample()
    w = np.array([m["weber_fraction"] for m in members])
    # median 0.11 (Gueorguiev et al. 2017), 95th percentile 0.2 (Fehlberg et al. 2022)
    assert np.percentile(w, 50) == pytest.approx(0.11, rel=0.01)
    assert np.percentile(w, 95) == pytest.approx(0.2, rel=0.02)
    assert WEBER_SPREAD["sigma"] == pytest.approx(math.log(0.2 / 0.11) / NormalDist().inv_cdf(0.95), abs=0.005)


@pytest.mark.parametrize("method", ["sobol", "lhs"])
def test_drawing_w_changes_no_finger(method):
    """W comes from a sequence of its own: the fingers of a population are the same with or
    without it (so a verdict changes with W alone), for both sampling methods and adults."""
    for table in ({**FINGERS, "method": method}, POPULATION_PRESETS["adults"]):
        without = {k: v for k, v in table.items() if k != "weber_fraction"}
        with_w = {**without, "weber_fraction": WEBER_SPREAD}
        a, b = population_from_table(without).sample(), population_from_table(with_w).sample()
        assert [{k: v for k, v in m.items() if k != "weber_fraction"} for m in b] == a
        assert len({m["weber_fraction"] for m in b}) == len(b)


def test_sobol_indices_spend_no_fingers_on_w():
    from fingerpad.population.sobol import check_design

    adults = population_from_table(POPULATION_PRESETS["adults"], name="adults")
    assert "weber_fraction" in adults.distributions and "weber_fraction" not in check_design(adults, 4)
    with pytest.raises(FingerpadError, match="no parameter of the population's fingers has a spread"):
        check_design(population_from_table({"size": 8, "weber_fraction": WEBER_SPREAD}), 4)


def test_w_correlated_with_a_finger_parameter_is_refused():
    with pytest.raises(FingerpadError, match="weber_fraction.*drawn apart"):
        population_from_table({**PEOPLE, "correlations": [["weber_fraction", "modulus", 0.3]]})


def test_the_study_file_sets_w_and_fixes_it(cache, tmp_path):
    from fingerpad.study.spec import load_study_file

    study = load_study_file(_write(tmp_path / "s.toml", _data(cache, weber_fraction=0.2)))
    assert study.weber == 0.2 and study.fixed["weber_fraction"] == "s.toml [perception] weber_fraction"
    assert study_from_dict(_data(cache)).weber == 0.11 and "weber_fraction" not in study_from_dict(_data(cache)).fixed
    with pytest.raises(FingerpadError, match=r"s.toml \[perception\] weber_fraction"):
        load_study_file(_write(tmp_path / "s.toml", _data(cache, weber_fraction=-1)))
    with pytest.raises(FingerpadError, match="unknown key"):
        study_from_dict({**_data(cache), "perception": {"weber": 0.2}})


def test_one_rule_refuses_a_set_w_with_a_population_that_draws_it(cache):
    study = study_from_dict(_data(cache, weber_fraction=0.2))
    with pytest.raises(FingerpadError, match=r"\[perception\] weber_fraction: the population 'custom' draws "
                                             "weber_fraction for every finger"):
        attach(study, PEOPLE)
    # the API's keyword fixes it as well, named as the library names it
    with pytest.raises(FingerpadError, match="--weber-fraction: the population 'adults' draws weber_fraction"):
        attach(with_weber(study_from_dict(_data(cache)), 0.2), "adults")
    # a population that does not draw W takes the person's W for every finger
    plan = attach(study, FINGERS)
    assert np.all(member_weber(plan.study, plan.members) == 0.2)


def test_members_judge_with_their_own_w(cache):
    """With the same fingers, the fraction telling the texture from flat changes with W alone;
    every member's P is Eqs. P.1-P.3 at its own W."""
    a = study_from_dict(_data(cache))
    fixed = compare(a, "flat", population=FINGERS)
    drawn = compare(a, "flat", population=PEOPLE)
    assert np.array_equal(fixed.mu_a, drawn.mu_a) and np.array_equal(fixed.mu_b, drawn.mu_b)
    w = np.array([m["weber_fraction"] for m in drawn.members])
    assert np.all(fixed.weber == 0.11) and np.array_equal(drawn.weber, w) and np.ptp(w) > 0.1
    assert np.array_equal(drawn.p, p_correct(drawn.mu_a, drawn.mu_b, w[:, None]))
    assert not np.array_equal(drawn.p, fixed.p)
    assert drawn.as_dict()["weber_fraction"]["drawn"] is True


def test_the_explorers_door_a_w_typed_beside_a_population_drawing_it(cache):
    """against_flat (predict --perception, the explorer's section) with a W typed and a population
    result that drew W: the population's rule, not a silent override of the members' W."""
    from fingerpad.population.run import run_population

    a = study_from_dict(_data(cache))
    result = run_population(a, PEOPLE)
    with pytest.raises(FingerpadError, match="--weber-fraction: the population 'custom' draws weber_fraction"):
        against_flat(result.nominal, result, weber="0.2", amplitudes=False)
    own = against_flat(result.nominal, result, amplitudes=False)
    assert np.array_equal(own.weber, [m["weber_fraction"] for m in result.members])


@pytest.mark.parametrize("command", [
    ["compare", "{a}", "flat", "--population", "adults", "--weber-fraction", "0.2"],
    ["predict", "{a}", "--perception", "--population", "adults", "--weber-fraction", "0.2"],
    ["predict", "{w}", "--perception", "--population", "adults"],
    ["design", "{a}", "--vary", "height=5um:30um", "--target", "feels-like=flat@1N", "--population", "adults",
     "--coverage", "0.9", "--weber-fraction", "0.2", "--json", "{o}.json"],
])
def test_every_command_refuses_with_the_one_message(cache, tmp_path, command):
    a = _write(tmp_path / "a.toml", _data(cache))
    w = _write(tmp_path / "w.toml", _data(cache, weber_fraction=0.2))
    args = [c.format(a=a, w=w, o=tmp_path / "o") for c in command]
    res = runner.invoke(app, args if command[0] == "design" else [*args, "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, (res.stdout, res.stderr)
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), res.stderr
    assert "the population 'adults' draws weber_fraction for every finger" in " ".join(res.stderr.split())
    assert not (tmp_path / "o").exists() and not (tmp_path / "o.json").exists()


def test_predict_perception_uses_the_study_files_w(cache, tmp_path):
    w = _write(tmp_path / "w.toml", _data(cache, weber_fraction=0.3))
    res = runner.invoke(app, ["predict", str(w), "--perception", "--json", "-"])
    assert res.exit_code == 0, res.stderr
    doc = json.loads(res.stdout)["perception"]
    assert doc["weber_fraction"] == {"value": 0.3, "drawn": False}
    mu_a, mu_b = (np.array(doc["members"][k], float) for k in ("mu_a", "mu_b"))
    assert np.array_equal(np.array(doc["members"]["p_correct"]), p_correct(mu_a, mu_b, 0.3))
