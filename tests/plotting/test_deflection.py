"""The deflection figure: a rigid texture's identity curve is drawn and says G = 1."""

from __future__ import annotations

from fingerpad.micro.deflection import GainCurve
from fingerpad.plotting.deflection import deflection_figure


def test_identity_curves_png(tmp_path, png_is_drawn):
    path = deflection_figure([GainCurve.identity(0.0), GainCurve.identity(90.0)], tmp_path / "deflection.png", dpi=50)
    img = png_is_drawn(path, min_colours=2)
    # two directions: two rows of panels, taller than wide at 13 x 7.2 in
    assert img.shape[0] / img.shape[1] == __import__("pytest").approx(7.2 / 13, rel=0.02)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deflection.png"]
