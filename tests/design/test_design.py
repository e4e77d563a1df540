"""Inverse design: inputs that make no sense are refused before any prediction, near-identical
candidates are one design, and the command and the Python API give the same document."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.design import inverse_design
from fingerpad.design.inverse import XATOL, Candidate, DesignProblem, parse_target
from fingerpad.design.inverse_design import design_textures, free_axes, merge_close

runner = CliRunner()

STUDY = """
[texture]
name = "caps"
radius = "100um"
height = "20um"
spacing = "175um"

[material]
modulus = "0.5GPa"
poisson = 0.4

[model]
grid = 16
"""


@pytest.fixture
def study(tmp_path: Path) -> Path:
    path = tmp_path / "study.toml"
    path.write_text(STUDY)
    return path


@pytest.fixture
def no_prediction(monkeypatch):
    """Fail the test if any direct prediction or search starts."""
    def refuse(*args, **kwargs):
        raise AssertionError("a prediction started for an input that makes no sense")

    monkeypatch.setattr(inverse_design, "predict_candidate", refuse)
    monkeypatch.setattr(inverse_design, "search", refuse)


def error_line(result) -> str:
    assert result.exit_code == 2, (result.exit_code, result.output)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


@pytest.mark.parametrize("option, value, expect", [
    ("--tolerance", "-1", "--tolerance"),
    ("--tolerance", "0", "--tolerance"),
    ("--tolerance", "2", "between 0 and 1"),
    ("--tolerance", "nan", "--tolerance"),
    ("--max-aspect", "-1", "--max-aspect"),
    ("--max-aspect", "0", "--max-aspect"),
    ("--min-feature", "-20um", "--min-feature"),
    ("--min-feature", "20kPa", "--min-feature"),
    ("--min-critical-load", "0N", "--min-critical-load"),
    ("--min-critical-load", "inf", "--min-critical-load"),
    ("--candidates", "0", "--candidates"),
    ("--evaluations", "-3", "--evaluations"),
    ("--evaluations", "100000", "at most"),
    ("--vary", "spacing=400um:100um", "LOW < HIGH"),
    ("--vary", "spacing=-100um:100um", "negative"),
    ("--vary", "lattice=1:2", "only numeric"),
    ("--target", "mu_rel=-0.5@1N", "positive"),
    ("--target", "mu_rel=0.5@-1N", "--target"),
])
def test_inputs_that_make_no_sense_are_refused_before_any_prediction(study, no_prediction, option, value, expect):
    args = {"--vary": "spacing=100um:400um", "--target": "mu_rel=0.5@1N"}
    args[option] = value
    flat = [x for k, v in args.items() for x in (k, v)]
    line = error_line(runner.invoke(app, ["design", str(study), *flat]))
    assert expect in line


def test_the_python_api_checks_the_same_ranges(study, no_prediction):
    from fingerpad.errors import FingerpadError

    with pytest.raises(FingerpadError, match="--tolerance"):
        design_textures(study, {"spacing": ("100um", "400um")}, ["mu_rel=0.5@1N"], tolerance=-1)
    with pytest.raises(FingerpadError, match="--tolerance"):
        DesignProblem(base={}, axes=free_axes(["spacing=100um:400um"], "caps"),
                      targets=[parse_target("mu_rel=0.5@1N")], tolerance=-1)


def _problem() -> DesignProblem:
    return DesignProblem(base={}, axes=free_axes({"spacing": ("100um", "400um"), "height": ("5um", "40um")}, "caps"),
                         targets=[parse_target("mu_rel=0.5@1N")])


def test_candidates_closer_than_the_optimiser_tolerance_are_one_design():
    """The five 'candidates' 200.7-201.8 um of the issue are one design: the best of them stays."""
    problem = _problem()
    near = [Candidate(params={"spacing": s * 1e-6, "height": 10e-6}, objective=o)
            for s, o in ((201.8, 0.03), (200.7, 0.01), (201.2, 0.02), (201.5, 0.05), (200.9, 0.04))]
    far = Candidate(params={"spacing": 300e-6, "height": 10e-6}, objective=0.02)
    other_height = Candidate(params={"spacing": 201.0e-6, "height": 20e-6}, objective=0.5)
    merged = merge_close(problem, [*near, far, other_height])
    assert [round(c.params["spacing"] * 1e6, 1) for c in merged] == [200.7, 300.0, 201.0]
    # the distance is measured in the optimiser's unit box (log axes in log)
    u = problem.unit({"spacing": 200.7e-6, "height": 10e-6}) - problem.unit({"spacing": 201.8e-6, "height": 10e-6})
    assert np.max(np.abs(u)) < XATOL
    assert problem.unit({"spacing": 100e-6, "height": 40e-6}) == pytest.approx([0.0, 1.0])


def test_design_reports_merged_candidates(study, monkeypatch):
    """design_textures merges what the search found before choosing the candidates to report."""
    found = [Candidate(params={"spacing": s * 1e-6}, objective=o)
             for s, o in ((200.7, 0.01), (201.8, 0.02), (201.2, 0.03), (260.0, 0.04), (330.0, 0.05))]
    monkeypatch.setattr(inverse_design, "search", lambda problem, **kw: list(found))

    def direct(problem, params, loads=None, curve_loads=None):
        spacing = params["spacing"]
        return Candidate(params=dict(params), objective=abs(math.log(spacing / 200.7e-6)), values={"x": 1.0})

    monkeypatch.setattr(inverse_design, "predict_candidate", direct)
    result = design_textures(study, ["spacing=100um:400um"], ["mu_rel=0.5@1N"], candidates=3)
    assert [round(c.params["spacing"] * 1e6, 1) for c in result.candidates] == [200.7, 260.0, 330.0]
    doc = result.document()
    assert doc["source"].startswith("optimisation") and len(doc["candidates"]) == 3 and doc["tolerance"] == 0.05
