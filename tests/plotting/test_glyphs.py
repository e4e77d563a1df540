"""Text drawn from glyphs rasterised once (plotting/glyphs.py): the same PNG bytes as matplotlib's
own text drawing, for every measurement figure, and the glyphs are in fact reused."""

from __future__ import annotations

import pytest

from fingerpad.plotting import glyphs
from fingerpad.plotting.measure import participant_png, qc_inputs, qc_png, sample_png

def _agg_draws_glyphs() -> bool:
    from matplotlib.backends import backend_agg

    return hasattr(backend_agg, "RenderMode") and hasattr(backend_agg.RendererAgg, "_draw_text_glyphs_and_boxes")


pytestmark = pytest.mark.skipif(not _agg_draws_glyphs(), reason="matplotlib draws text another way before 3.11")


def _figures(result, dpi: int) -> list[bytes]:
    out = [qc_png(qc_inputs(result, r.source), dpi) for r in result.recordings]
    out += [participant_png(result, p, dpi) for p in sorted(result.strokes["participant"].unique())]
    out += [sample_png(result, s, dpi) for s in sorted(result.strokes["sample"].unique())]
    return out


@pytest.mark.parametrize("dpi", [60, 100])
def test_measurement_figures_are_the_same_bytes(measured, monkeypatch, dpi):
    """Every QC, participant and sample figure of the small study, drawn twice with the caches
    (the second time from them) and once without: the same bytes. A bitmap drawn a pixel off,
    or a layout of another string or size, changes them."""
    glyphs._GLYPHS.clear()
    glyphs._LAYOUTS.clear()
    first = _figures(measured, dpi)
    before = dict(glyphs.counts)
    again = _figures(measured, dpi)
    hits, misses = (glyphs.counts[k] - before[k] for k in ("hits", "misses"))
    assert hits > 1000 and misses == 0  # the same figures again: every glyph from the cache
    with monkeypatch.context() as patch:
        patch.setattr(glyphs, "cache_glyphs", lambda renderer: None)
        from fingerpad.plotting import measure

        for kept in (*measure._QC_FIGURES.values(), *measure._KEPT.values()):  # renderers without the cache
            renderer = kept.canvas.get_renderer()
            vars(renderer).pop("draw_text", None)
        plain = _figures(measured, dpi)
    assert len(plain) == len(first) > 5
    assert [a == b for a, b in zip(first, plain)] == [True] * len(plain)
    assert again == plain


def test_rotated_text_and_glyphs_at_every_fraction_of_a_pixel(monkeypatch):
    """A figure of rotated labels and strings placed at 1/7-pixel steps (each glyph at many
    fractions of a pixel and at whole-pixel shifts of them): the same bytes with the cache."""
    from matplotlib.figure import Figure

    from fingerpad.plotting.png import figure_png

    def figure() -> Figure:
        fig = Figure(figsize=(4, 3))
        ax = fig.subplots()
        for i in range(40):
            ax.text(0.02 + i / 7 / 400, 0.02 + 0.024 * i, f"mu = {0.1 * i:.2f} N, E_s", fontsize=6 + i % 4,
                    rotation=(0, 30, 90)[i % 3])
        ax.set(xlabel="normal load F (N)", ylabel="friction coefficient mu", title="gly phs")
        return fig

    cached = figure_png(figure(), 100)
    again = figure_png(figure(), 100)
    with monkeypatch.context() as patch:
        patch.setattr(glyphs, "cache_glyphs", lambda renderer: None)
        plain = figure_png(figure(), 100)
    assert cached == plain and again == plain
