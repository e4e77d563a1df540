"""Directional friction in predict (the deflection model of compliant asperities)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app

runner = CliRunner()
ELLIPSOIDS = ["--texture", "ellipsoids", "--semi-axis-x", "45um", "--semi-axis-y", "135um", "--height", "90um",
              "--spacing-x", "300um", "--spacing-y", "300um", "--grid", "16", "--model", "bem",
              "--loads", "0.1N:4N:3"]


def predict(*args, cache):
    res = runner.invoke(app, ["predict", *ELLIPSOIDS, *args, "--cache", str(cache), "--json", "-"])
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def test_a_rigid_texture_is_isotropic(tmp_path):
    plain = predict(cache=tmp_path)
    for direction in ("0", "90", "30deg"):
        d = predict("--direction", direction, cache=tmp_path)
        assert d["directional"]["identity"]
        np.testing.assert_array_equal([r["mu"] for r in d["results"]], [r["mu"] for r in plain["results"]])
        assert all(r["mu_perpendicular_over_parallel"] == 1.0 for r in d["results"])


def test_direction_needs_a_known_asperity(tmp_path):
    res = runner.invoke(app, ["predict", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing",
                              "150um", "--grid", "16", "--direction", "0", "--material-modulus", "0.3MPa",
                              "--cache", str(tmp_path), "--json", "-"])
    assert res.exit_code == 2 and "has no deflection model" in res.stderr and "ellipsoids, ridges" in res.stderr


@pytest.mark.slow
def test_circular_asperities_are_isotropic_and_slender_ellipsoids_are_not(tmp_path):
    """A circular asperity has the same section in every direction: mu_perp/mu_par = 1 exactly;
    slender ellipsoids of a modulus close to the skin's give more friction across their long axis."""
    circ = ["--texture", "ellipsoids", "--semi-axis-x", "45um", "--semi-axis-y", "45um", "--height", "90um",
            "--spacing-x", "300um", "--spacing-y", "300um", "--grid", "16", "--model", "bem", "--loads", "0.2N:2N:2",
            "--material-modulus", "0.3MPa", "--material-poisson", "0.49", "--direction", "0",
            "--cache", str(tmp_path), "--json", "-"]
    res = runner.invoke(app, ["predict", *circ])
    assert res.exit_code == 0, res.output
    assert all(r["mu_perpendicular_over_parallel"] == pytest.approx(1.0, abs=1e-12)
               for r in json.loads(res.stdout)["results"])
    d = predict("--direction", "0", "--material-modulus", "0.3MPa", "--material-poisson", "0.49", cache=tmp_path)
    ratios = [r["mu_perpendicular_over_parallel"] for r in d["results"]]
    assert all(r > 1.02 for r in ratios)


@pytest.mark.slow
def test_a_stiff_finite_modulus_is_computed_not_silently_rigid(tmp_path):
    """At 1 GPa the ramps never got pressed on and predict used G = 1 without a word: now the
    gain comes from ramps that ran (and is 1 to round-off: the stiff texture barely deflects)."""
    d = predict("--direction", "0", "--material-modulus", "1GPa", cache=tmp_path)
    report = d["directional"]
    assert not report["identity"]
    assert not any(report["gain_held_parallel"]) and not any(report["gain_held_perpendicular"])
    assert not any("held" in n or "stopped" in n for n in d.get("notes", []))


def test_the_friction_figure_circles_the_loads_where_the_gain_is_held(tmp_path):
    """The ratio panel marks the loads where a gain is held (past the shear its ramps reached).
    A rigid texture gives the directional report cheaply; its held flags are set by hand at the
    two upper loads, as the slender ellipsoids' ramps give them from ~1.6 N."""
    from fingerpad.cli.predict import build_study
    from fingerpad.plotting.prediction import figure_friction
    from fingerpad.study.run import run_study

    flags = {"--texture": "ellipsoids", "--loads": ["0.1N:4N:3"], "--model": "bem", "--direction": "0",
             "--grid": "16", "--cache": str(tmp_path)}
    args = ["--semi-axis-x", "45um", "--semi-axis-y", "135um", "--height", "90um", "--spacing-x", "300um",
            "--spacing-y", "300um"]
    pred = run_study(build_study(ctx_args=args, flags=flags, finger_param=[], options={}))
    ratio_panel = figure_friction(pred).axes[2]
    assert not any("held" in str(line.get_label()) for line in ratio_panel.lines)
    pred.directional["gain_held_parallel"] = [False, True, True]
    pred.directional["gain_held_perpendicular"] = [False, False, True]
    ratio_panel = figure_friction(pred).axes[2]
    marks = [line for line in ratio_panel.lines if "held" in str(line.get_label())]
    assert len(marks) == 1
    np.testing.assert_allclose(marks[0].get_xdata(), np.asarray(pred.primary.load)[1:])
