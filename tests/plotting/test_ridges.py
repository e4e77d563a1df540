"""The ridge-model comparison figure (thesis Fig. 2.4 idea), through the public name."""

from __future__ import annotations

import numpy as np

import fingerpad as fp
from fingerpad import macro


def test_ridge_models_png(tmp_path, png_is_drawn):
    path = fp.ridge_models_figure(tmp_path / "ridges.png", loads=np.geomspace(0.1, 4, 6), dpi=60)
    png_is_drawn(path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ridges.png"]


def test_ridge_models_figure_numbers():
    from fingerpad.plotting.ridges import figure_ridge_models

    loads = np.geomspace(0.1, 4, 6)
    fig = figure_ridge_models(loads, skin_modulus=100e3, radius=9e-3)
    ax_area, ax_frac = fig.axes[:2]
    gross = [line for line in ax_area.get_lines() if "gross" in line.get_label().lower()]
    assert len(gross) == 1
    # the gross curve is Hertz (Eq. 2.5) with the figure's radius and modulus, in mm^2
    expected = macro.HertzArea(radius=9e-3, modulus=100e3).area(loads) * 1e6
    np.testing.assert_allclose(gross[0].get_ydata(), expected, rtol=1e-12)
    # fractions A_fr / A_g in per cent lie in (0, 100]; each is its model's area over the gross
    assert ax_frac.get_ylabel() == "ridge area / gross area (%)"
    by_label = {line.get_label(): np.asarray(line.get_ydata(), float) for line in ax_area.get_lines()}
    for line in ax_frac.get_lines():
        y = np.asarray(line.get_ydata(), float)
        assert np.all((y > 0) & (y <= 100.0 + 1e-9)), line.get_label()
        np.testing.assert_allclose(y, by_label[line.get_label()] / expected * 100, rtol=1e-12)
    assert "E_skin = 100 kPa, R_fp = 9 mm" in fig._suptitle.get_text()
