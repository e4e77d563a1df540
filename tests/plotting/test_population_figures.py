"""The population's figures (issue 30, defects 5 and 22): population.png with any number of
quantile levels, the study's finger and the loads predicted marked; the population design map's
contour labels apart, its legend listing only what is drawn, under the panels."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest

from fingerpad.plotting.designmap import figure_design_map
from fingerpad.plotting.population import CENTRE_OPACITY, figure_population


@pytest.fixture(scope="module")
def result():
    from fingerpad.population import run_population
    from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict

    d = copy.deepcopy(DEFAULT_STUDY)
    d["model"] = {"kind": "hertz"}
    d["loads"] = {"range": "0.1N:4N:8"}
    return run_population(study_from_dict(d), "adults", quantiles=[i / 100 for i in range(101)])


def test_population_png_takes_any_number_of_levels(result, tmp_path, png_is_drawn):
    """14 levels and more gave matplotlib's "alpha must be between 0 and 1" traceback."""
    fig = figure_population(result)
    fig.savefig(tmp_path / "p.png", dpi=40)
    png_is_drawn(tmp_path / "p.png")
    for ax in fig.axes[:2]:
        fills = [c for c in ax.collections if c.get_alpha() is not None]
        assert len(fills) == 50 and all(0 < c.get_alpha() <= 1 for c in fills)
        # stacked, the bands reach the stated opacity at the centre, whatever their number
        assert 1 - np.prod([1 - c.get_alpha() for c in fills]) == pytest.approx(CENTRE_OPACITY)
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert labels == ["0-100 %", "49-51 %", "median", "the study's finger"]


def test_population_png_marks_the_studys_finger_and_the_loads_predicted(result):
    fig = figure_population(result)
    bands, hist = fig.axes[1], fig.axes[2]
    own = next(line for line in bands.get_lines() if line.get_label() == "the study's finger")
    np.testing.assert_array_equal(own.get_ydata(), result.nominal.primary.mu_normalised)
    labels = [t.get_text() for t in hist.get_legend().get_texts()]
    crit = result.nominal.critical_load["hertz"]
    assert "loads predicted (0.1-4 N)" in labels and f"the study's finger ({crit:.3g} N)" in labels
    assert any(np.allclose(line.get_xdata(), crit) for line in hist.get_lines())


def _map(robust: bool):
    """map_data's result for a population on a 6 x 5 grid whose 10/50/90 % contours crowd."""
    import xarray as xr

    s = np.geomspace(100e-6, 400e-6, 6)
    h = np.geomspace(5e-6, 40e-6, 5)
    S, H = np.meshgrid(s, h)
    q50 = 0.5 * (S / 175e-6) ** -2 * (H / 20e-6) ** 1.5
    frac = np.where((S > 300e-6) & (H < 10e-6), 0.95, 0.2) if robust else np.zeros_like(S)
    dims = ("height", "spacing")
    data = {"critical_load": (dims, q50), "mu_rel": (dims, 0.5 + 0.4 * np.tanh(1 / q50)),
            "region": (dims, np.zeros_like(S)), "critical_load_q10": (dims, q50 / 3),
            "critical_load_q50": (dims, q50), "critical_load_q90": (dims, 3 * q50),
            "asperity_over_range": (dims, frac), "robust_asperity": (dims, (frac >= 0.9).astype(float))}
    markers = {"lines": [], "bands": []}
    return xr.Dataset(data, coords={"spacing": s, "height": h}, attrs={
        "x": "spacing", "y": "height", "x_log": True, "y_log": True, "at": 1.0, "load_min": 0.1, "load_max": 4.0,
        "design": "grid", "x_kind": "length", "y_kind": "length", "quantity": "mu_rel", "quantity_label": "μ/μ_ref",
        "population": "adults (1000 fingers)", "coverage": 0.9, "markers": json.dumps(markers)})


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_population_map_labels_lie_apart_and_the_legend_is_under_the_panels():
    fig = figure_design_map(_map(robust=False))
    fig.canvas.draw()
    ax = fig.axes[0]
    assert ax.get_legend() is None and len(fig.legends) == 1  # not over the cells
    legend = fig.legends[0].get_window_extent()
    assert not _overlap(legend, ax.get_window_extent())
    texts = [t for t in ax.texts if t.get_text().endswith(" N")]
    assert len(texts) >= 3
    boxes = [t.get_window_extent() for t in texts]
    assert not any(_overlap(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:]), [t.get_text() for t in texts]


@pytest.mark.parametrize("robust", [False, True])
def test_population_map_legend_lists_only_what_is_drawn(robust: bool):
    """The legend listed a hatched region that was not drawn."""
    from matplotlib.patches import Patch

    fig = figure_design_map(_map(robust))
    legend = fig.legends[0]
    hatched = [h for h in legend.legend_handles if isinstance(h, Patch) and h.get_hatch()]
    drawn = [c for c in fig.axes[0].collections if any(getattr(c, "hatches", None) or ())]
    assert bool(hatched) == robust == bool(drawn)
    labels = " ".join(t.get_text() for t in legend.get_texts())
    assert ("no texture here keeps asperity contact" in labels) == (not robust)


def test_the_histogram_title_counts_members_past_the_transition_at_zero_load_apart():
    """With adhesion a member's critical load can be 0 (past the transition at zero load): it was
    counted among those that 'never reach the transition'."""
    from fingerpad.plotting.population import critical_title

    assert critical_title([0.1, float("inf"), 0.0, 0.0, 2.0]) == (
        "1 of 5 never reach the transition, 2 are past it at zero load")
    assert critical_title([0.1, float("inf")]) == "1 of 2 never reach the transition"
