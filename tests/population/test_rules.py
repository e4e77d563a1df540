"""The rules of a population on a study (fingerpad.population.rules, issue 30): one place, so that
the library, predict, sweep, design and the explorer refuse the same things with the same message."""

from __future__ import annotations

import copy
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fingerpad.cli import app
from fingerpad.errors import FingerpadError
from fingerpad.population import attach, population_from_table, run_population
from fingerpad.population.distributions import MAX_MEMBERS, Population, PopulationWarning
from fingerpad.population.rules import MAX_QUANTILES, quantile_levels
from fingerpad.plausibility import PlausibilityWarning
from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict

runner = CliRunner()
STUDY = """
[texture]
name = "caps"
radius = "50um"
height = "10um"
spacing = "100um"
[model]
kind = "hertz"
[loads]
range = "0.1N:4N:5"
"""
#: What every door says of a fixed value the population would draw over.
OVERRIDE = "the population 'adults' draws {name} for every finger, which would override the value given here"


def invoke(*args):
    return runner.invoke(app, [str(a) for a in args])


def error_line(result) -> str:
    assert result.exit_code == 2, (result.stdout, result.stderr)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    return lines[0]


def _data(**finger) -> dict:
    d = copy.deepcopy(DEFAULT_STUDY)
    d["model"] = {"kind": "hertz"}
    d["loads"] = {"range": "0.1N:4N:5"}
    d["finger"] = {"preset": "default", **finger}
    return d


# ------------------------------------------------------------------------ defect 1: one rule everywhere


@pytest.mark.parametrize(("key", "value"), [("skin_modulus", "0.45MPa"), ("tau0", "5kPa")])
def test_a_study_files_finger_value_is_not_drawn_over(tmp_path: Path, key: str, value: str):
    """`[finger] skin_modulus = "0.45MPa"` with `--population adults` predicted members of
    0.20-0.50 MPa without a word (the flag was refused): refused at every door, one message."""
    study = tmp_path / "study.toml"
    study.write_text(STUDY + f'[finger]\n{key} = "{value}"\n')
    want = f"study.toml [finger] {key}: " + OVERRIDE.format(name=key)
    assert want in error_line(invoke("predict", study, "--population", "adults", "--out", tmp_path / "o"))
    assert not (tmp_path / "o").exists()
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(study.read_text() + '[sweep]\nloads = "0.1N:4N:5"\n[sweep.axes]\nspacing = ["100um", "150um"]\n')
    assert f"sweep.toml [finger] {key}: " + OVERRIDE.format(name=key) in error_line(
        invoke("sweep", sweep, "--population", "adults", "--out", tmp_path / "s.zarr"))
    assert not (tmp_path / "s.zarr").exists()
    assert want in error_line(invoke("design", study, "--vary", "spacing=100um:200um", "--target", "mu_rel=0.5@1N",
                                     "--population", "adults", "--coverage", "0.5"))
    # the library: run_population and design_textures
    from fingerpad.design.inverse_design import design_textures
    from fingerpad.study.spec import load_study_file

    with pytest.raises(FingerpadError, match=want.replace("[", r"\[")):
        run_population(load_study_file(study), "adults")
    with pytest.raises(FingerpadError, match=OVERRIDE.format(name=key)):
        design_textures(_data(**{key: value}), ["spacing=100um:200um"], ["mu_rel=0.5@1N"], population="adults",
                        coverage=0.5)


def test_flags_say_the_same():
    for args, label in ((["--skin-modulus", "0.45MPa"], "--skin-modulus"),
                        (["--finger-param", "tau0=5kPa"], "--finger-param tau0"),
                        (["--finger-param", "ridge_fraction=0.4"], "--finger-param ridge_fraction")):
        name = label.split()[-1].lstrip("-").replace("-", "_")
        line = error_line(invoke("predict", "--texture", "caps", "--radius", "50um", "--height", "10um", "--spacing",
                                 "100um", "--model", "hertz", *args, "--population", "adults"))
        assert f"error: {label}: " + OVERRIDE.format(name=name) in line


def test_the_explorer_refuses_a_typed_value_the_population_draws():
    """The explorer with E_s typed and `adults` chosen predicted members of 0.2-0.5 MPa."""
    from fingerpad.explore.views.population import run_preset

    data = _data(skin_modulus="0.45MPa")
    with pytest.raises(FingerpadError, match="skin modulus E_s: " + OVERRIDE.format(name="skin_modulus")):
        run_preset(data, "adults")
    assert run_preset(_data(), "adults").population.name == "adults"  # nothing typed: runs


def test_a_value_the_population_does_not_draw_is_kept():
    study = study_from_dict(_data(skin_modulus="0.45MPa"))
    table = {"size": 4, "radius": {"distribution": "uniform", "low": 0.007, "high": 0.011}}
    res = run_population(study, table)
    assert all(f.skin_modulus == 0.45e6 for f in attach(study, table).fingers)
    assert res.members == [dict(m) for m in attach(study, table).members]


def test_the_layer_that_declares_a_layered_skin_is_noted_not_refused():
    """The exception, said: the layer's values given on a half-space preset declare the layered
    skin; a population of thicknesses draws its own for every member, and a note says so."""
    study = study_from_dict(_data(skin_layer_thickness="300um", skin_layer_modulus="0.4MPa",
                                  skin_substrate_modulus="40kPa"))
    plan = attach(study, {"size": 2, "skin_layer_thickness": {"values": [200e-6, 350e-6]}})
    assert sorted(m["skin_layer_thickness"] for m in plan.members) == [200e-6, 350e-6]
    assert any("declares the layered skin" in n and "skin_layer_thickness" in n for n in plan.notes)


def test_sweep_axes_and_design_vary_are_fixed_values_too():
    from fingerpad.design.spec import sweep_from_dict

    data = {**_data(), "sweep": {"axes": {"tau0": ["4kPa", "8kPa"]}}}
    with pytest.raises(FingerpadError, match=r"\[sweep.axes\] tau0: " + OVERRIDE.format(name="tau0")):
        sweep_from_dict(data, population="adults")
    with pytest.raises(FingerpadError, match=r"\[sweep.axes\] direction: a population of fingers with a sliding"):
        sweep_from_dict({**_data(), "sweep": {"axes": {"direction": ["0deg", "90deg"]}}}, population="adults")


def test_a_direction_is_refused_with_one_message_everywhere():
    d = _data()
    d["model"]["direction"] = 30
    with pytest.raises(FingerpadError, match="a population of fingers with a sliding direction is not supported"):
        run_population(study_from_dict(d), "adults")


# ------------------------------------------------------------------------ defect 4: caps


def test_population_size_is_capped_everywhere(tmp_path: Path):
    """1e7 members ran silently until killed (the explorer accepted it at start)."""
    with pytest.raises(FingerpadError, match=f"at most {MAX_MEMBERS}"):
        population_from_table({"size": 10_000_000})
    with pytest.raises(FingerpadError, match=f"at most {MAX_MEMBERS}"):
        Population({}, size=MAX_MEMBERS + 1)
    pop = tmp_path / "big.toml"
    pop.write_text("[population]\nsize = 10000000\n")
    assert f"at most {MAX_MEMBERS}" in error_line(invoke("explore", "--no-browser", "--population", pop))
    with pytest.raises(FingerpadError, match="values; at most"):
        population_from_table({"alpha": {"values": [0.1] * (MAX_MEMBERS + 1)}})


def test_sensitivity_samples_are_capped(tmp_path: Path):
    """`--sensitivity-samples 1e9` ended in a MemoryError traceback."""
    study = tmp_path / "study.toml"
    study.write_text(STUDY)
    line = error_line(invoke("predict", study, "--population", "adults", "--sensitivity", "--sensitivity-samples",
                             "1000000000"))
    assert "N (d + 2) = 10000000000 fingers for the 8 parameters with a spread; at most" in line
    assert "N <= 2000" in line
    with pytest.raises(FingerpadError, match="N <= 2000"):
        run_population(study_from_dict(_data()), "adults", sensitivity=2001)


def test_quantile_levels_are_capped_and_checked_once():
    assert quantile_levels("0.9,0.1,0.5,0.1") == (0.1, 0.5, 0.9)
    assert len(quantile_levels([i / 100 for i in range(101)])) == MAX_QUANTILES
    with pytest.raises(FingerpadError, match=f"at most {MAX_QUANTILES}"):
        quantile_levels([i / 1000 for i in range(1001)])
    for bad in ("0.5,nan", "x", "", "1.5"):
        with pytest.raises(FingerpadError, match="--quantiles"):
            quantile_levels(bad)


# ------------------------------------------------------------------------ defects 10, 11: said, not silent


def test_implausible_members_are_warned_about():
    """A lognormal of sigma 50 gave pad moduli from 1e-53 to 1e52 Pa without a word; the flags warn."""
    study = study_from_dict(_data())
    table = {"size": 16, "modulus": {"distribution": "lognormal", "median": 40e3, "sigma": 50}}
    with pytest.warns(PlausibilityWarning, match=r"population 'custom' modulus: \d+ of 16 values lie outside the "
                                                 r"plausible 1 kPa - 10 MPa for a pad modulus"):
        attach(study, table)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        attach(study, "adults")  # the preset is plausible


def test_an_empty_table_is_noted():
    plan = attach(study_from_dict(_data()), {"size": 3})
    assert any("draws no parameter, so its 3 members are copies of the study's finger" in n for n in plan.notes)


def test_a_truncnormal_mean_far_outside_its_bounds_warns():
    """Every member sat on a bound without a word."""
    table = {"size": 8, "tau0": {"distribution": "truncnormal", "mean": "50kPa", "sd": "2kPa", "low": "1kPa",
                                 "high": "12kPa"}}
    with pytest.warns(PopulationWarning, match=r"tau0: the mean 50 kPa lies 19 sd above high = 12 kPa"):
        pop = population_from_table(table)
    assert all(11.5e3 < m["tau0"] <= 12e3 for m in pop.sample())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        population_from_table({"tau0": {"distribution": "truncnormal", "mean": "13kPa", "sd": "2kPa", "high": "12kPa"}})


def test_a_panel_of_three_is_told_its_outer_bands_are_its_range():
    from fingerpad.population.distributions import Distribution, POPULATION_PARAMS

    values = (0.25e6, 0.3e6, 0.4e6)
    pop = Population({"skin_modulus": Distribution(POPULATION_PARAMS["skin_modulus"], "values", {"values": values})},
                     size=3, method="measured", name="panel", measured=tuple({"skin_modulus": v} for v in values))
    plan = attach(study_from_dict(_data()), pop)
    assert any("3 people; the 5 %, 25 %, 75 %, 95 % bands lie beyond what 3 people show" in n for n in plan.notes)
    assert not any("people" in n for n in attach(study_from_dict(_data()), pop, quantiles=[0.5]).notes)
    one = Population({"skin_modulus": Distribution(POPULATION_PARAMS["skin_modulus"], "values", {"values": values[:1]})},
                     size=1, method="measured", name="one", measured=({"skin_modulus": values[0]},))
    assert any("1 person; the 5 %, 25 %, 50 %, 75 %, 95 % bands lie beyond what 1 person shows" in n
               for n in attach(study_from_dict(_data()), one).notes)  # not '1 people show'


def test_members_of_a_big_panel_get_no_such_note():
    assert not any("people" in n for n in attach(study_from_dict(_data()), "adults").notes)
    assert np.isclose(sorted(quantile_levels(None))[0], 0.05)


def test_a_population_of_another_type_is_a_fingerpad_error():
    """A Python caller giving a list, a number or bytes as the population got a TypeError from
    pathlib (found by trying bad inputs on attach)."""
    study = study_from_dict(_data())
    for bad in ([1, 2], 3, b"adults"):
        with pytest.raises(FingerpadError, match=f"population: expected a preset name .*got {type(bad).__name__}"):
            attach(study, bad)
        with pytest.raises(FingerpadError, match="population: expected a preset name"):
            run_population(study, bad)
