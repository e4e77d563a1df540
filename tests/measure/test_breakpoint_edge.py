"""A change of trend at the edge of the load range is not reported as a transition.

Before: data that bend at the lightest loads (as the bend of asperity contact, or low-load
artefacts, make them) and are straight elsewhere had a "transition" reported at 0.13-0.3 N in
40 of 40 data sets, with a closed-form E_s beside it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fingerpad import measure as m
from fingerpad.errors import FingerpadError


def low_end_bend(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """60 strokes in 3 recordings over 0.1-5 N: a straight power law (exponent 0.25) plus a bend
    confined to the lightest loads, recording and stroke scatter; no transition inside."""
    cl = np.repeat(np.arange(3), 20)
    f = np.exp(rng.uniform(math.log(0.1), math.log(5), 60))
    x = np.log(f)
    y = (0.25 * x + 0.25 * np.exp(-(x - math.log(0.1)) / 0.25) + 0.03 * rng.standard_normal(60)
         + 0.05 * rng.standard_normal(3)[cl])
    return f, np.exp(y), cl


def test_low_end_bend_not_reported():
    rng = np.random.default_rng(1)
    reported = rejected_at_edge = 0
    reps = 25
    for i in range(reps):
        f, y, cl = low_end_bend(rng)
        bp = m.find_breakpoint(f, y, trend="steeper", clusters=cl, n_null=99, seed=i)
        # the test does reject the straight line (the data bend), at the lowest loads...
        assert bp.p_value < 0.05 and bp.load < 0.35
        reported += bp.detected
        rejected_at_edge += bp.outside
        if bp.detected:  # ...so anything reported lies inside the supported range
            assert bp.edge_low <= bp.load <= bp.edge_high
        else:
            assert math.isnan(bp.ci_low) and "edge of the load range" in bp.describe()
    assert reported <= 2 and rejected_at_edge >= reps - 2
    # with the rule switched off the old behaviour returns: reported at the lowest loads
    f, y, cl = low_end_bend(np.random.default_rng(1))
    old = m.find_breakpoint(f, y, trend="steeper", clusters=cl, n_null=99, seed=0, edge=0.0)
    assert old.detected and old.load < 0.35


def test_edge_range_from_loads_and_points():
    """The supported range leaves ``edge`` of the log-load range and of the points each side."""
    f = np.geomspace(0.1, 10, 41)
    y = np.exp(np.where(f < 1.0, 0.2 * np.log(f), 0.6 * np.log(f)))
    bp = m.find_breakpoint(f, y, trend="steeper", n_null=49, edge=0.25)
    assert bp.detected and bp.load == pytest.approx(1.0, rel=0.05)
    assert bp.edge_low == pytest.approx(10 ** -0.5, rel=1e-6) and bp.edge_high == pytest.approx(10 ** 0.5, rel=1e-6)
    # points crowded at heavy loads: the count rule moves the lower limit up to the 11th point
    g = np.r_[np.geomspace(0.1, 1, 10), np.geomspace(3, 10, 31)]
    bp = m.find_breakpoint(g, np.exp(0.3 * np.log(g)), n_null=49, edge=0.25)
    assert bp.edge_low == pytest.approx(g[int(math.ceil(0.25 * g.size)) - 1]) == pytest.approx(3.0)
    assert bp.edge_high == pytest.approx(10 ** 0.5)
    # so crowded that no location has support on both sides: no range, nothing can be reported
    g = np.r_[np.geomspace(0.1, 1, 5), np.geomspace(8, 10, 36)]
    bp = m.find_breakpoint(g, np.exp(0.3 * np.log(g)), n_null=49, edge=0.25)
    assert math.isnan(bp.edge_low) and math.isnan(bp.edge_high) and not bp.detected
    with pytest.raises(FingerpadError, match="edge must lie in"):
        m.find_breakpoint(f, y, edge=0.5)


def test_no_closed_form_from_an_edge_break(tmp_path):
    """Through the whole analysis: a study whose texture bends only at its lightest loads gets
    no transition load and no closed-form E_s, and the summary says why."""
    from fingerpad.measure.simulate import simulate_study

    def bend_model(geometry, finger):
        def model(loads, skin_modulus):
            x = np.log(np.clip(np.asarray(loads, dtype=float), 0.05, None))
            return 0.6 * np.exp(0.25 * x + 0.25 * np.exp(-(x - math.log(0.1)) / 0.25))
        return model

    cfg = m.SimulationConfig(participants=1, repetitions=3, strokes_per_file=30, stroke_noise=0.02,
                             file_noise=0.01)
    simulate_study(tmp_path / "s", cfg, seed=4, model_factory=bend_model)
    recs = m.load_study([tmp_path / "s"])
    textures = m.read_textures(tmp_path / "s" / "samples.csv")
    result = m.analyse_study(recs, m.AnalysisOptions(reference="flat", n_null=199, sensitivity=False,
                                                     population=False),
                             textures=textures, models={"bumps": bend_model(None, None)})
    row = result.conditions[result.conditions["sample"] == "bumps"].iloc[0]
    assert row["breakpoint_outside"] and not row["breakpoint_detected"]
    assert math.isnan(row["breakpoint_load"]) and math.isnan(row.get("skin_modulus_closed_form", math.nan))
    assert "edge of the load range" in row["transition"]
