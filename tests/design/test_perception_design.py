"""Design for perception: feels-like / feels-different-from targets (docs/perception.md)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from fingerpad.design.inverse import parse_target
from fingerpad.design.perception_targets import PerceptionTarget, member_verdicts
from fingerpad.design.inverse_design import design_textures
from fingerpad.errors import FingerpadError
from fingerpad.perception.compare import compare
from fingerpad.population.distributions import population_from_table
from fingerpad.study.spec import load_study_file

POP = {"size": 16, "seed": 5, "skin_modulus": {"distribution": "uniform", "low": "0.2MPa", "high": "0.5MPa"},
       "modulus": {"distribution": "uniform", "low": "10kPa", "high": "100kPa"},
       "ridge_fraction": {"distribution": "uniform", "low": 0.1, "high": 0.7}}


def _write_study(path: Path, spacing: str, cache: Path) -> Path:
    path.write_text(
        '[texture]\nname = "caps"\nradius = "100um"\nheight = "20um"\n'
        f'spacing = "{spacing}"\nlattice = "hexagonal"\n'
        '[material]\nmodulus = "0.5GPa"\npoisson = 0.4\n'
        '[loads]\nvalues = ["1N"]\n'
        f'[model]\nkind = "bem"\ngrid = 32\ncache = "{cache}"\n')
    return path


def test_parse_perception_targets(tmp_path):
    ref = _write_study(tmp_path / "ref.toml", "175um", tmp_path)
    t = parse_target(f"feels-like={ref}@1N")
    assert isinstance(t, PerceptionTarget) and t.reference == str(ref) and t.load == 1.0 and not t.different
    assert parse_target("feels-different-from=flat@0.5N").different
    with pytest.raises(FingerpadError, match="neither 'flat' nor a study file"):
        parse_target("feels-like=missing.toml@1N")


def test_member_verdicts_meet_exactly_where_p_says():
    mu = np.array([0.30, 0.32, 0.40, 0.5])
    ref = np.full(4, 0.30)
    w = np.full(4, 0.11)
    like = member_verdicts(PerceptionTarget("feels-like", "r", 1.0), mu, ref, ref, w, 0.05)
    diff = member_verdicts(PerceptionTarget("feels-different-from", "r", 1.0), mu, ref, ref, w, 0.05)
    tells = like["p_correct"] >= 0.75
    assert tells.tolist() == [False, False, True, True]
    assert np.array_equal(like["ok"], ~tells) and np.array_equal(diff["ok"], tells)
    for v in (like, diff):  # a member's score lies within tolerance^2 exactly when it meets the target
        assert np.array_equal(v["score"] <= 0.05**2, v["ok"])


@pytest.mark.parametrize("people", [POP, {**POP, "weber_fraction": {"distribution": "lognormal", "median": 0.11,
                                                                    "sigma": 0.36}}],
                         ids=["one W", "each member's own W"])
def test_feels_like_round_trip(tmp_path, people):
    """The proposed texture's direct comparison with REF on the same fingers meets the coverage."""
    cache = tmp_path / "cells"
    ref = _write_study(tmp_path / "ref.toml", "175um", cache)
    study = _write_study(tmp_path / "study.toml", "175um", cache)
    pop = population_from_table(people)
    result = design_textures(study, ["spacing=150um:300um"], [f"feels-like={ref}@1N"], population=pop,
                             coverage=0.9, evaluations=8, candidates=1)
    best = result.candidates[0]
    assert best.meets, result.shortfall()
    assert np.array_equal(result.problem.weber, [m.get("weber_fraction", 0.11) for m in pop.sample()])
    reported = best.population["perception"][f"feels-like={ref}@1N"]["fraction_telling_apart"]
    assert reported <= 0.1 + 1e-12
    # the direct comparison: the candidate's study against REF, on the same members
    from fingerpad.design.inverse import candidate_study

    cand = candidate_study(result.problem, best.params, [1.0])
    direct = compare(cand, load_study_file(ref), population=pop)
    assert direct.summary()["fraction"][0] == reported
    assert direct.summary()["fraction"][0] <= 0.1
    doc = json.loads(json.dumps(result.document()))
    assert doc["candidates"][0]["population"]["perception"][f"feels-like={ref}@1N"]["fraction_telling_apart"] == \
        reported


def test_perception_target_refusals(tmp_path):
    study = _write_study(tmp_path / "study.toml", "175um", tmp_path)
    with pytest.raises(FingerpadError, match="use --coverage"):
        design_textures(study, ["spacing=150um:300um"], ["feels-like=flat@1N"], population=POP, quantile=0.5)
    with pytest.raises(FingerpadError, match="needs a perception target"):
        design_textures(study, ["spacing=150um:300um"], ["mu_rel=0.5@1N"], weber=0.2, evaluations=1)
