"""The prediction's figures are defined once (plotting/prediction_specs.py) and drawn by both
matplotlib (``fingerpad predict``'s PNGs) and Bokeh (the explorer): the same labels, titles,
scales and the same numbers on both, in the unit each axis shows."""

from __future__ import annotations

import copy
import subprocess
import sys

import numpy as np
import pytest

from fingerpad.plotting.prediction_specs import areas_figure, friction_figure, zones_figure
from fingerpad.study.run import run_study
from fingerpad.study.spec import DEFAULT_STUDY, study_from_dict

pytest.importorskip("matplotlib")


@pytest.fixture(scope="module")
def pred():
    data = copy.deepcopy(DEFAULT_STUDY)
    data["model"] = {"kind": "hertz"}
    data["loads"] = {"range": "0.1N:4N:12", "log": True}
    return run_study(study_from_dict(data))


def _figures(pred):
    from fingerpad.plotting.prediction import figure_areas, figure_friction, figure_zones

    return [(areas_figure(pred), figure_areas(pred)), (friction_figure(pred), figure_friction(pred)),
            (zones_figure(pred), figure_zones(pred))]


def test_spec_module_imports_neither_toolkit():
    code = ("import sys, fingerpad.plotting.prediction_specs, fingerpad.plotting.specs; "
            "print(sorted(m for m in ('matplotlib', 'bokeh', 'panel') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_predict_figures_draw_the_spec(pred):
    """Every matplotlib panel of areas/friction/zones.png shows its spec's title, labels, scales
    and each line's values in the axis's unit."""
    for fs, fig in _figures(pred):
        axes = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
        main = [ax for ax in axes if ax.get_xlabel()]  # twin axes carry no x label
        assert len(main) == len(fs.panels)
        if fs.title:
            assert fig._suptitle.get_text() == fs.title
        for ax, spec in zip(main, fs.panels, strict=True):
            assert ax.get_title() == spec.title
            assert ax.get_xlabel() == spec.x.label and ax.get_ylabel() == spec.y.label
            assert ax.get_xscale() == ("log" if spec.x.log else "linear")
            assert ax.get_yscale() == ("log" if spec.y.log else "linear")
            drawn = {ln.get_label(): ln for a in axes for ln in a.get_lines() if not ln.get_label().startswith("_")}
            for line in spec.lines:
                if not line.legend:
                    continue
                art = drawn[line.name]
                assert np.allclose(art.get_xdata(), np.asarray(line.x) * spec.x.factor, rtol=1e-12)
                assert np.allclose(art.get_ydata(), spec.axis_of(line).show(line.y), rtol=1e-12, equal_nan=True)
            legend = ax.get_legend()
            texts = [t.get_text() for t in legend.get_texts()] if legend else []
            for band in spec.bands:
                if band.legend:
                    assert f"centre: {band.state}" in texts
            for v in spec.vlines:
                assert v.label in texts


def test_explorer_draws_the_same_spec(pred):
    """The explorer's Bokeh figure of each panel: same labels, title, scales, and the same shown
    values as the PNG."""
    pytest.importorskip("bokeh")
    from bokeh.models import ColumnDataSource, LinearAxis, LogAxis

    from fingerpad.explore.builders import prediction_panels
    from fingerpad.explore.render_bokeh import bokeh_figure

    panels = prediction_panels(pred)
    assert sorted(panels) == sorted(p.key for fs, _ in _figures(pred) for p in fs.panels)
    for fs, fig in _figures(pred):
        for spec in fs.panels:
            assert panels[spec.key].title == spec.title  # the same definition, not a second one
            p = bokeh_figure(spec).figure
            assert p.title.text == spec.title
            assert p.xaxis[0].axis_label == spec.x.label and p.yaxis[0].axis_label == spec.y.label
            assert isinstance(p.xaxis[0], LogAxis if spec.x.log else LinearAxis)
            assert isinstance(p.yaxis[0], LogAxis if spec.y.log else LinearAxis)
            if spec.y2 is not None:
                assert spec.y2.label in [ax.axis_label for ax in p.right if hasattr(ax, "axis_label")]
            sources = [r.data_source for r in p.renderers if isinstance(getattr(r, "data_source", None),
                                                                        ColumnDataSource)]
            for line in spec.lines:
                (src,) = {id(s): s for s in sources if list(s.data.get("name", [])[:1]) == [line.name]}.values()
                assert np.allclose(src.data["x"], np.asarray(line.x) * spec.x.factor, rtol=1e-12)
                assert np.allclose(src.data["y"], spec.axis_of(line).show(line.y), rtol=1e-12, equal_nan=True)
            legend = [item.label.value for item in p.legend[0].items] if p.legend else []
            for v in spec.vlines:
                assert v.label in legend
            for disc in spec.discs:
                assert disc.label in legend


def test_a_few_loads_get_markers_and_a_single_load_a_window(pred):
    data = copy.deepcopy(DEFAULT_STUDY)
    data["model"] = {"kind": "hertz"}
    data["loads"] = {"values": ["1N"]}
    one = run_study(study_from_dict(data))
    spec = areas_figure(one).panels[0]
    assert all(line.markers for line in spec.lines) and not spec.x.log
    from fingerpad.plotting.render import figure

    ax = figure(areas_figure(one)).axes[0]
    assert ax.get_xlim() == pytest.approx((0.5, 1.5))
    assert not any(line.markers for line in areas_figure(pred).panels[0].lines)


def test_explorer_updates_a_figure_in_place_for_new_limits(pred):
    """A new load moves the zone profile's radius limits: the Bokeh figure takes the new data
    and ranges in place (rebuilding costs the page far more)."""
    pytest.importorskip("bokeh")
    from fingerpad.explore.builders import prediction_panels
    from fingerpad.explore.render_bokeh import bokeh_figure, update_figure

    data = copy.deepcopy(DEFAULT_STUDY)
    data["model"] = {"kind": "hertz"}
    data["loads"] = {"range": "0.1N:4N:12", "log": True, "zones_at": "1N"}
    other = run_study(study_from_dict(data))
    first, second = prediction_panels(pred)["zone-profile"], prediction_panels(other)["zone-profile"]
    assert first.x.limits != second.x.limits
    drawn = bokeh_figure(first)
    assert update_figure(drawn, second)
    assert drawn.figure.x_range.end == pytest.approx(second.x.limits[1] * 1e3)


def test_log_axis_labels_stay_short():
    """1-2-5 ticks on a log axis, the range's ends to 3 digits (not 49.6397)."""
    from fingerpad.plotting.render import figure
    from fingerpad.plotting.specs import Axis, Line, PlotSpec

    x = np.geomspace(200.0, 49639.7, 50)
    spec = PlotSpec("t", "t", x=Axis("p", "Pa", "kPa", 1e-3, log=True), y=Axis("y"), lines=[Line("a", x, x)])
    fig = figure(spec)
    fig.canvas.draw()
    labels = [t.get_text() for t in fig.axes[0].get_xticklabels()]
    assert labels[-1] == "49.6" and "0.2" in labels and "10" in labels
    assert all(len(t) <= 4 for t in labels), labels
