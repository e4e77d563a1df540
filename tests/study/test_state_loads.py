"""A state load is a property of the texture and the finger (issue 31): the critical and
full-contact loads do not depend on the loads asked for, and each carries its own error estimate
(its state pressure's grid convergence), reported beside it in predict.json, the NetCDF and on
the terminal.

The README texture picks its curve's grid from the loads (128 x 224 over 0.1-4 N, 64 x 112 over
1 and 1000 N at the 2 % accuracy); its full-contact pressure moves 6 % between those grids, so
before, the full-contact load read 161.6 N in one study and 135.6 N in the other."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from fingerpad.study.run import load_at_centre_pressure, run_study
from fingerpad.study.spec import study_from_dict

TEXTURE = {"name": "caps", "radius": "100um", "height": "20um", "spacing": "175um", "lattice": "hexagonal"}


def study(loads, cache, **model):
    return study_from_dict({"texture": TEXTURE, "material": {"modulus": "0.5GPa", "poisson": 0.4},
                            "loads": {"values": loads}, "model": {"kind": "bem", "cache": str(cache), **model}})


@pytest.fixture(scope="module")
def two(tmp_path_factory):
    """The README texture over 0.1-4 N and over 1 and 1000 N, each on an empty cache."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        low = run_study(study(["0.1N", "0.3N", "1N", "4N"], tmp_path_factory.mktemp("low")))
        high = run_study(study(["1N", "1000N"], tmp_path_factory.mktemp("high")))
    return low, high


def test_the_curves_grids_differ_but_the_state_loads_do_not(two):
    low, high = two
    assert low.cell.texture.shape != high.cell.texture.shape  # the loads chose the curve's grid ...
    for key in ("critical_load", "full_contact_load"):  # ... not the state loads (bit for bit)
        assert getattr(low, key)["bem"] == getattr(high, key)["bem"]
    for state in ("transition", "full"):
        a, b = low.state_brackets[state], high.state_brackets[state]
        assert {k: v for k, v in a.items()} == {k: v for k, v in b.items()}
    # and the pad's zones follow the reported pressures: full contact at 1000 N, as the load says
    assert (high.bem.full_contact_radius[-1] > 0) == (1000.0 >= high.full_contact_load["bem"])


def test_each_state_load_carries_its_grid_convergence(two):
    from fingerpad.micro.resolution import MAX_STATE_GRID

    low, _ = two
    finger = low.study.finger
    for state, pressure in (("transition", low.cell.transition_pressure), ("full", low.cell.full_contact_pressure)):
        st = low.state_brackets[state]
        # the estimate is what it says: the change from the half grid, in pressure and in load
        fine, coarse = pressure, st["coarse_pressure"]
        assert st["pressure_error"] == pytest.approx(max(abs(fine / coarse - 1), 1e-3), rel=1e-12)
        f, fc = load_at_centre_pressure(finger, fine), load_at_centre_pressure(finger, coarse)
        # (at least the load change of the bracket's width, the floor of the pressure's estimate)
        assert abs(f / fc - 1) <= st["load_error"] <= max(abs(f / fc - 1), 0.01)
        # the grid was doubled until the estimate met the accuracy, or the state grids' cap
        assert st["met"] == (st["pressure_error"] <= 0.02)
        assert st["met"] or st["grid"][0] == MAX_STATE_GRID
        assert [h["grid"] for h in st["history"]][-1] == st["grid"][0]
        assert st["coarse_grid"][0] * 2 == st["grid"][0]
    # this texture's full contact converges slowly: the estimate says so, and a note too
    assert low.state_brackets["full"]["pressure_error"] > 0.02
    assert any("full-contact pressure" in n and "exceeds the target" in n for n in low.notes)
    assert low.state_brackets["transition"]["met"]


def test_the_state_errors_are_in_the_json_the_netcdf_and_on_the_terminal(two, capsys, monkeypatch):
    from fingerpad.cli.predict import _print_prediction
    from fingerpad.study.outputs import prediction_dataset, prediction_json

    low, _ = two
    doc = prediction_json(low)
    assert doc["full_contact_load_error"]["bem"] == low.state_brackets["full"]["load_error"] > 0
    assert doc["critical_load_error"]["bem"] == low.state_brackets["transition"]["load_error"] > 0
    attrs = prediction_dataset(low).attrs
    assert attrs["full_contact_load_error_bem"] == doc["full_contact_load_error"]["bem"]
    assert list(attrs["state_brackets_full_grid"]) == low.state_brackets["full"]["grid"]
    monkeypatch.setenv("COLUMNS", "80")
    capsys.readouterr()
    _print_prediction(doc)
    printed = capsys.readouterr().out
    text = " ".join(printed.split())
    full, err = doc["full_contact_load"]["bem"], doc["full_contact_load_error"]["bem"]
    assert f"from: {full:.4g} N ± {100 * err:.2g} %" in text
    grid = "x".join(map(str, low.state_brackets["full"]["grid"]))
    assert f"grid {grid} against" in text
    lines = [line for line in printed.splitlines() if "full contact" in line or "critical load" in line]
    assert lines and max(len(line) for line in lines) <= 80


def test_a_given_grid_keeps_its_states(tmp_path):
    """With --grid the states are the given cell's own, with the half grid's estimate."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pred = run_study(study(["1N"], tmp_path, grid=32))
    st = pred.state_brackets["full"]
    assert st["grid"][0] == 32 and st["coarse_grid"][0] == 16 and st["target"] is None and st["met"] is None
    assert math.isfinite(st["pressure_error"]) and np.isfinite(pred.full_contact_load["bem"])
