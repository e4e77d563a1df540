"""The three figures of ``fingerpad predict``: areas, friction, contact zones."""

from __future__ import annotations

import numpy as np

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
