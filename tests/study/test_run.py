"""A prediction's numbers agree with each other: critical loads, centre states, zone radii, the
pad pressure at the zone edges and the unit cell's state pressures (BEM 32-point cell and Hertz)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad import macro
from fingerpad.study import run as study_run
from fingerpad.study import study_from_dict


def test_critical_load_is_where_the_centre_reaches_the_transition(prediction):
    for model, cell in (("bem", prediction.cell), ("hertz", prediction.hertz_cell)):
        f = prediction.critical_load[model]
        finger = prediction.study.finger
        assert 1.5 * f / finger.ridge_area(f) == pytest.approx(cell.transition_pressure, rel=1e-9), model
        assert study_run.load_at_centre_pressure(finger, cell.transition_pressure) == pytest.approx(f, rel=1e-9)


def test_centre_states_follow_the_critical_loads(prediction):
    loads = prediction.primary.load
    for model in ("bem", "hertz"):
        states = prediction.states(model if model == "hertz" else None)
        f = prediction.critical_load[model]
        assert [s != "asperity" for s in states] == list(loads >= f), model
    fc = prediction.full_contact_load["bem"]
    assert fc > prediction.critical_load["bem"]
    assert all((s == "full") == (load >= fc) for s, load in zip(prediction.states(), loads, strict=True))


def test_centre_state_thresholds():
    class Cell:
        transition_pressure = 100.0
        full_contact_pressure = 1000.0

    assert [study_run.centre_state(p, Cell()) for p in (99.9, 100.0, 999.0, 1000.0, math.inf)] == \
        ["asperity", "transition", "transition", "full", "full"]


def test_zone_radii(prediction):
    z = prediction.zones
    assert z["load"] == pytest.approx(3.0) and z["ridge_area"] == pytest.approx(prediction.study.finger.ridge_area(3.0))
    assert z["ridge_radius"] == pytest.approx(math.sqrt(z["ridge_area"] / math.pi), rel=1e-12)
    assert 0 <= z["full_contact_radius"] <= z["transition_radius"] <= z["ridge_radius"]
    assert z["peak_pressure"] == pytest.approx(1.5 * z["mean_pressure"], rel=1e-12)
    assert z["mean_pressure"] == pytest.approx(z["load"] / z["ridge_area"], rel=1e-12)
    # the transition zone ends where the pad pressure falls to the cell's transition pressure (Eq. 3.7)
    if z["transition_radius"] > 0:
        p_edge = macro.pad_pressure(z["transition_radius"], z["load"], z["ridge_area"])
        assert p_edge == pytest.approx(prediction.cell.transition_pressure, rel=1e-6)
    # the zone area ratio is the curve's at that load
    i = int(np.argmin(np.abs(prediction.primary.load - z["load"])))
    assert z["area_ratio"] == pytest.approx(prediction.primary.area_ratio[i], rel=1e-9)


def test_bem_transition_above_hertz_and_hertz_note(prediction):
    """Caps 100 um apart (1.7 base diameters): the neighbours hold the skin up, so the BEM
    transition needs more pressure than isolated Hertz."""
    assert prediction.cell.transition_pressure > prediction.hertz_cell.transition_pressure
    assert prediction.critical_load["bem"] > prediction.critical_load["hertz"]
    assert prediction.zones["hertz_transition_radius"] >= prediction.zones["transition_radius"]


def test_pressure_range_covers_the_loads(prediction):
    lo, hi = prediction.pressure_range
    p_mean = prediction.primary.load / prediction.primary.ridge_area
    assert lo <= study_run.P_LOW * p_mean.min() * (1 + 1e-12)
    assert hi >= study_run.P_HIGH * p_mean.max() * (1 - 1e-12)
    assert prediction.reduced_modulus == pytest.approx(prediction.study.reduced_modulus)
    assert prediction.timings["cell"] >= 0 and prediction.timings["coupling"] >= 0


def test_hertz_only_on_a_hexagonal_lattice_notes_its_spacing(tmp_path):
    study = study_from_dict({
        "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um", "lattice": "hexagonal"},
        "loads": {"values": [0.5, 2.0]}, "model": {"kind": "hertz", "cache": False},
    })
    calls = []
    pred = study_run.run_study(study, progress=lambda i, n: calls.append((i, n)))
    assert pred.bem is None and pred.cell is None and pred.primary_model == "hertz"
    assert any("sqrt(sqrt(3)/2)" in note for note in pred.notes)
    assert pred.hertz_cell.spacing == pytest.approx(math.sqrt(math.sqrt(3) / 2) * 100e-6, rel=1e-14)
    assert pred.unconverged == 0


def test_load_at_centre_pressure_edges(prediction):
    finger = prediction.study.finger
    assert study_run.load_at_centre_pressure(finger, math.inf) == math.inf
    assert math.isnan(study_run.load_at_centre_pressure(finger, 0.0))
    assert math.isnan(study_run.load_at_centre_pressure(finger, math.nan))
