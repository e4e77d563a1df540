"""The three figures of ``fingerpad predict``: areas, friction, contact zones."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad.plotting.prediction import figure_areas, figure_friction, figure_zones


def save(fig, path):
    fig.savefig(path, format="png", dpi=60)
    return path


def test_areas_figure(tmp_path, prediction, png_is_drawn):
    fig = figure_areas(prediction)
    png_is_drawn(save(fig, tmp_path / "areas.png"))
    (ax,) = fig.axes
    assert ax.get_xlabel() == "normal load F (N)" and ax.get_ylabel() == "contact area (mm²)"
    assert ax.get_yscale() == "log"
    assert ax.get_title().startswith("Contact areas: caps, E1* = ")
    labels = [line.get_label() for line in ax.get_lines()]
    assert {"gross A_g", "ridge A_fr", "real A_re (bem)", "real A_re (hertz)"} <= set(labels)
    gross = next(line for line in ax.get_lines() if line.get_label() == "gross A_g")
    # the plotted numbers are the prediction's, in mm^2
    np.testing.assert_allclose(gross.get_ydata(), prediction.primary.gross_area * 1e6)


def test_friction_figure(tmp_path, prediction, png_is_drawn):
    fig = figure_friction(prediction)
    png_is_drawn(save(fig, tmp_path / "friction.png"))
    ax_mu, ax_n = fig.axes
    assert ax_mu.get_ylabel() == "friction coefficient μ (-)"
    assert ax_n.get_ylabel() == "μ_texture / μ_flat reference (-)"
    assert fig._suptitle.get_text().startswith("caps on finger default, E1* = ")
    texture = next(line for line in ax_mu.get_lines() if line.get_label() == "texture (bem)")
    np.testing.assert_allclose(texture.get_ydata(), prediction.primary.mu)


def test_zones_figure(tmp_path, prediction, png_is_drawn):
    fig = figure_zones(prediction)
    png_is_drawn(save(fig, tmp_path / "zones.png"))
    ax_map, ax_r = fig.axes[:2]
    z = prediction.zones
    assert ax_map.get_title() == f"ridge contact disc at F = {z['load']:.3g} N"
    assert ax_r.get_xlabel() == "radius r (mm)"
    assert fig._suptitle.get_text() == "Contact zones of caps (bem), finger default"
    # the pad pressure drawn is Hertzian: peak at r = 0, zero at the disc edge
    p = ax_r.get_lines()[0].get_ydata()
    assert p[0] == max(p) and p[-1] == 0.0


def _legend_clears_the_disc(fig) -> None:
    fig.canvas.draw()
    ax = fig.axes[0]
    legend = ax.get_legend().get_window_extent()
    outer = max(ax.patches, key=lambda p: p.get_window_extent().width).get_window_extent()
    assert legend.y0 >= outer.y1 or legend.x0 >= outer.x1 or legend.x1 <= outer.x0 or legend.y1 <= outer.y0, \
        (legend, outer)
    assert ax.get_window_extent().contains(legend.x0, legend.y0) and ax.get_window_extent().contains(legend.x1,
                                                                                                     legend.y1)


def test_zones_legend_does_not_cover_the_disc(prediction):
    """Issue 30, item 22: in the corner of the square box, zones.png's legend covered the
    disc's top left; it has a band of its own above the disc."""

    _legend_clears_the_disc(figure_zones(prediction))
    # four rows: the full-contact disc too (the zones of a load where the centre is in full contact)
    z = dict(prediction.zones)
    a = z["ridge_radius"]
    z.update(transition_radius=0.8 * a, full_contact_radius=0.4 * a, hertz_transition_radius=0.9 * a)

    class Shown:  # the prediction, with these zones
        def __getattr__(self, name):
            return z if name == "zones" else getattr(prediction, name)

    fig = figure_zones(Shown())
    assert len(fig.axes[0].get_legend().get_texts()) == 4
    _legend_clears_the_disc(fig)


@pytest.fixture(scope="module")
def hertz_prediction():
    from fingerpad.study import run as study_run
    from fingerpad.study import study_from_dict

    return study_run.run_study(study_from_dict({
        "texture": {"name": "caps", "radius": "50um", "height": "10um", "spacing": "100um"},
        "loads": {"values": [0.02, 0.2, 2.0]}, "model": {"kind": "hertz", "cache": False},
    }))


def test_critical_load_marked_and_states_shaded(hertz_prediction, prediction):
    f = hertz_prediction.critical_load["hertz"]
    assert 0.02 < f < 2.0
    ax_mu = figure_friction(hertz_prediction).axes[0]
    lines = {line.get_label(): line for line in ax_mu.get_lines()}
    assert list(lines[f"F_crit hertz = {f:.3g} N"].get_xdata()) == [f, f]
    # the centre passes from asperity to transition at F_crit: both spans are shaded, split there
    spans = {p.get_label(): p.get_x() for p in ax_mu.patches}
    assert set(spans) == {"centre: asperity", "centre: transition"}
    assert spans["centre: transition"] == pytest.approx(f)
    # a log load axis (0.02-2 N) with plain 1-2-5 tick labels
    assert ax_mu.get_xscale() == "log"
    assert {"0.02", "0.05", "0.1", "0.2", "0.5", "1", "2"} <= {t.get_text() for t in ax_mu.xaxis.get_majorticklabels()}
    # critical loads below the plotted range (0.2-3 N) are not drawn
    below = [line.get_label() for line in figure_friction(prediction).axes[0].get_lines()]
    assert not [label for label in below if label.startswith("F_crit")]


def test_hertz_only_figures(tmp_path, hertz_prediction, png_is_drawn):
    areas = figure_areas(hertz_prediction)
    labels = [line.get_label() for line in areas.axes[0].get_lines()]
    assert "real A_re (hertz)" in labels and "real A_re (bem)" not in labels
    # three loads: markers on the lines, so that they show
    assert areas.axes[0].get_lines()[0].get_marker() == "o"
    zones = figure_zones(hertz_prediction)
    assert zones._suptitle.get_text() == "Contact zones of caps (hertz), finger default"
    for name, fig in (("areas", areas), ("friction", figure_friction(hertz_prediction)), ("zones", zones)):
        png_is_drawn(save(fig, tmp_path / f"{name}.png"))
