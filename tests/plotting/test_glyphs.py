"""Text laid out and drawn from glyphs rasterised once (plotting/glyphs.py): the same PNG bytes as
matplotlib's own text drawing, for every measurement figure, and the caches are in fact used."""

from __future__ import annotations

import contextlib

import pytest

from fingerpad.plotting import glyphs
from fingerpad.plotting.measure import participant_png, qc_inputs, qc_png, sample_png

def _agg_draws_glyphs() -> bool:
    from matplotlib.backends import backend_agg

    return hasattr(backend_agg, "RenderMode") and hasattr(backend_agg.RendererAgg, "_draw_text_glyphs_and_boxes")


pytestmark = pytest.mark.skipif(not _agg_draws_glyphs(), reason="matplotlib draws text another way before 3.11")


def _without_caches(patch: pytest.MonkeyPatch) -> None:
    patch.setattr(glyphs, "cache_glyphs", lambda renderer: None)
    patch.setattr(glyphs, "laid_out_once", contextlib.nullcontext)


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
    for cache in (glyphs._GLYPHS, glyphs._LAYOUTS, glyphs._TEXTS):
        cache.clear()
    first = _figures(measured, dpi)
    before = dict(glyphs.counts)
    again = _figures(measured, dpi)
    used = {k: glyphs.counts[k] - before[k] for k in before}
    # the same figures again: every glyph and every text's layout from the caches
    assert used["hits"] > 1000 and used["misses"] == 0
    assert used["layouts"] > 500 and used["new_layouts"] == 0
    with monkeypatch.context() as patch:
        _without_caches(patch)
        from fingerpad.plotting import measure, qcfigure

        for kept in (*qcfigure._QC_FIGURES.values(), *measure._KEPT.values()):  # renderers without the cache
            renderer = kept.canvas.get_renderer()
            vars(renderer).pop("draw_text", None)
        plain = _figures(measured, dpi)
    assert len(plain) == len(first) > 5
    assert [a == b for a, b in zip(first, plain)] == [True] * len(plain)
    assert again == plain


def test_rotated_text_and_glyphs_at_every_fraction_of_a_pixel(monkeypatch):
    """A figure of strings placed at 1/7-pixel steps (each glyph at many fractions of a pixel
    and at whole-pixel shifts of them), each at several rotations, alignments and sizes: the same
    bytes with the caches."""
    from matplotlib.figure import Figure

    from fingerpad.plotting.png import figure_png

    def figure() -> Figure:
        fig = Figure(figsize=(4, 3))
        ax = fig.subplots()
        # each string as it is and with one property changed at a time: a layout cached without
        # that property in its key would be reused for the other
        changes = [{}, {"rotation": 30}, {"rotation": 90}, {"ha": "center"}, {"ha": "right"}, {"va": "top"},
                   {"fontsize": 7}, {"linespacing": 2.0}, {"fontweight": "bold"}]
        for i in range(54):
            ax.text(0.02 + i / 7 / 400, 0.02 + 0.017 * i, f"mu = {0.1 * (i // 9):.2f} N,\nE_s",
                    **{"fontsize": 6, **changes[i % 9]})
        ax.set(xlabel="normal load F (N)", ylabel="friction coefficient mu", title="gly phs")
        return fig

    cached = figure_png(figure(), 100)
    again = figure_png(figure(), 100)
    with monkeypatch.context() as patch:
        _without_caches(patch)
        plain = figure_png(figure(), 100)
    assert cached == plain and again == plain


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="no fork on this platform")
def test_a_forked_process_draws_with_fonts_of_its_own(measured):
    """A QC pool's worker is forked from a process that drew figures already: it must not draw
    from the fonts the parent opened (their file offset is shared across the fork, and two
    processes reading through it read each other's bytes: 'failed to load glyph' now and then).
    The child finds the caches that hold fonts empty, draws the same bytes with its own fonts,
    and the parent's caches are untouched."""
    import os

    first = qc_png(qc_inputs(measured, measured.recordings[0].source), 60)
    assert glyphs._LAYOUTS and glyphs._GLYPHS
    parent_fonts = {item[0] for items in glyphs._LAYOUTS.values() for item in items}
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: report through the pipe, never return into pytest
        code = 1
        try:
            empty = not glyphs._LAYOUTS and not glyphs._GLYPHS
            again = qc_png(qc_inputs(measured, measured.recordings[0].source), 60)
            own = {item[0] for items in glyphs._LAYOUTS.values() for item in items}
            code = 0 if empty and again == first and own and not (own & parent_fonts) else 2
        finally:
            os.write(write, bytes([code]))
            os._exit(0)
    os.close(write)
    try:
        answer = os.read(read, 1)
    finally:
        os.close(read)
        os.waitpid(pid, 0)
    assert answer == b"\x00"
    assert parent_fonts <= {item[0] for items in glyphs._LAYOUTS.values() for item in items}
