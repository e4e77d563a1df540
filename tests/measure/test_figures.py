"""Figures a person reads: QC per recording, readable log ticks."""

from __future__ import annotations

import numpy as np
import pytest

from fingerpad.plotting.measure import figure_participant, figure_qc, log_subs


def test_log_ticks_readable_on_narrow_ranges():
    assert log_subs(0.3, 0.5) == tuple(float(k) for k in range(1, 10))  # a fifth of a decade: every integer
    assert log_subs(0.1, 5.0) == (1.0, 2.0, 5.0)
    assert log_subs(1e-3, 1e3) == (1.0,)


def test_participant_figure_log_axes_have_labels(study_small):
    fig = figure_participant(study_small, "P01")
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    for ax in fig.axes:
        for axis, lim in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
            lo, hi = sorted(lim)
            labels = [t.get_text() for t in axis.get_ticklabels() if t.get_text()
                      and lo <= t.get_position()[0 if axis is ax.xaxis else 1] <= hi]
            assert len(labels) >= 3, (ax.get_title(), labels)
            assert not any("e-" in s or "10^" in s for s in labels), labels


def test_qc_figure_marks_every_stroke(study_small):
    source = study_small.recordings[0].source
    fig = figure_qc(study_small, source)
    report = study_small.stroke_reports[source]
    top = fig.axes[0]
    # one shaded span per stroke plus its steady window (and an outline per outlier), drawn as
    # one collection of bands per style
    spans = [path for c in top.collections for path in c.get_paths()]
    n_out = int(study_small.strokes.loc[study_small.strokes["file"] == source, "outlier"].sum())
    dropped = len(report.strokes) - len(report.used)
    assert len(spans) == 2 * len(report.used) + n_out + dropped
    mu_axis = fig.axes[-1]
    plotted = sum(len(line.get_xdata()) for line in mu_axis.get_lines())
    assert plotted == len(report.used)
    assert "strokes" in fig._suptitle.get_text()


def test_qc_figure_unknown_recording(study_small):
    from fingerpad.errors import FingerpadError

    with pytest.raises(FingerpadError, match="no recording"):
        figure_qc(study_small, "nope.csv")
    assert np.isfinite(study_small.strokes["mu"]).all()


def test_qc_figure_of_a_long_recording_is_bounded_and_keeps_every_stroke_extreme():
    """A 60 s recording at 1 kHz: each time-series line of its QC figure draws at most 6000
    vertices (not ~60 000), and still reaches the maximum and minimum of every stroke (within
    the stroke's span widened by one decimation bucket), the last samples included."""
    from fingerpad import measure as m

    rec = m.simulate_recording(m.SimulationConfig(strokes_per_file=52, sampling_rate=1000.0), seed=5)
    n = len(rec)
    assert n > 50_000
    result = m.analyse_study([rec], m.AnalysisOptions(sensitivity=False, population=False))
    report = result.stroke_reports[rec.source]
    fig = figure_qc(result, rec.source)
    k = int(np.ceil(n / 3000))  # samples per bucket
    dt = float(np.median(np.diff(rec.time)))
    for ax, y in zip(fig.axes, (rec.normal, rec.friction, rec.position * 1e3)):
        line = ax.get_lines()[0]
        tt, yy = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
        assert 2000 <= tt.size <= 6000
        assert np.all(np.diff(tt) >= 0)  # in time order
        assert tt[-1] >= rec.time[-k]  # the tail is drawn
        assert yy.max() == y.max() and yy.min() == y.min()
        for st in report.strokes:
            a, b = rec.time[st.start] - k * dt, rec.time[st.stop - 1] + k * dt
            near = (tt >= a) & (tt <= b)
            assert yy[near].max() >= y[st.start:st.stop].max()
            assert yy[near].min() <= y[st.start:st.stop].min()


def test_decimation_keeps_each_bucket_extremes_and_the_tail():
    from fingerpad.plotting.qcfigure import _decimate

    rng = np.random.default_rng(1)
    n = 60_001  # not a multiple of the bucket length: the last bucket is short
    t = np.arange(n) / 1000.0
    y = rng.normal(size=n)
    y[-1] = 50.0  # a spike in the very last sample
    y[12_345] = -40.0
    tt, yy = _decimate(t, y, max_points=6000)
    assert tt.size <= 6000
    k = int(np.ceil(n / 3000))
    for start in range(0, n, k):
        inside = (tt >= t[start]) & (tt <= t[min(start + k, n) - 1])
        assert yy[inside].max() == y[start:start + k].max()
        assert yy[inside].min() == y[start:start + k].min()
    assert 50.0 in yy and -40.0 in yy


def test_qc_png_on_a_reused_figure_is_the_same_as_on_a_new_one(study_small):
    """qc_png redraws one kept figure: each recording's PNG is byte-identical to the PNG of a
    new figure, whatever recording was drawn on it before (limits, labels, legend, title),
    including a recording without strokes (no legend) before and after ones with strokes."""
    import dataclasses

    from fingerpad.plotting.measure import png_bytes, qc_inputs, qc_png
    from fingerpad.plotting.qcfigure import _draw_qc

    sources = [r.source for r in study_small.recordings][:4]
    inputs = [qc_inputs(study_small, s) for s in sources]
    empty = dataclasses.replace(inputs[0], strokes=inputs[0].strokes.iloc[:0])
    fresh = [png_bytes(figure_qc(study_small, s), 40) for s in sources]
    fresh_empty = png_bytes(_draw_qc(empty), 40)
    assert fresh_empty not in fresh
    order = [*zip(inputs, fresh), (empty, fresh_empty), *zip(inputs[::-1], fresh[::-1]), (empty, fresh_empty),
             (inputs[0], fresh[0])]
    for i, (given, want) in enumerate(order):
        assert qc_png(given, 40) == want, i


def test_participant_and_sample_pngs_on_kept_figures_are_the_same_as_on_new_ones(study_small):
    """participant_png and sample_png redraw one kept figure per kind and shape: each PNG is
    byte-identical to that of a new figure, whichever participant or sample was drawn on the
    kept figure before (scales, limits, ticks, legend, error bars, bands, titles)."""
    from fingerpad.plotting.measure import figure_sample, participant_png, png_bytes, sample_png

    participants = sorted(study_small.strokes["participant"].unique())
    samples = sorted(study_small.strokes["sample"].unique())
    assert len(participants) >= 2 and len(samples) >= 2  # something drawn before each one
    fresh = {p: png_bytes(figure_participant(study_small, p), 40) for p in participants}
    fresh.update({s: png_bytes(figure_sample(study_small, s), 40) for s in samples})
    for order in (1, -1, 1):
        for p in participants[::order]:
            assert participant_png(study_small, p, 40) == fresh[p], p
        for s in samples[::order]:
            assert sample_png(study_small, s, 40) == fresh[s], s


def test_participant_figure_draws_every_stroke_in_its_condition_s_colour(study_small):
    """The strokes of all conditions share one scatter per marker: each stroke is drawn once,
    where it lies, in its condition's colour (outliers as crosses), on both panels."""
    from matplotlib.colors import to_rgba

    from fingerpad.plotting.measure import _colours, condition_label

    s = study_small.strokes[study_small.strokes["participant"] == "P01"]
    conds = sorted({(a, b) for a, b in zip(s["sample"], s["direction"])})
    colours = _colours([condition_label(*c) for c in conds])
    fig = figure_participant(study_small, "P01")

    def drawn(ax):
        points = []
        for c in ax.collections:
            if not hasattr(c, "get_offsets") or type(c).__name__ != "PathCollection":
                continue
            rgba = c.get_edgecolor() if len(c.get_facecolor()) == 0 else c.get_facecolor()
            for (x, y), colour in zip(c.get_offsets(), np.broadcast_to(rgba, (len(c.get_offsets()), 4))):
                points.append((round(float(x), 12), round(float(y), 12), tuple(np.round(colour[:3], 6))))
        return sorted(points)

    def expected(column, rows):
        return sorted((round(float(x), 12), round(float(y), 12),
                       tuple(np.round(to_rgba(colours[condition_label(a, b)])[:3], 6)))
                      for x, y, a, b in zip(rows["load"], rows[column], rows["sample"], rows["direction"]))

    assert drawn(fig.axes[0]) == expected("mu", s)
    ref = study_small.options.reference
    usable = s[(~s["outlier"].to_numpy(dtype=bool)) & (s["sample"] != ref).to_numpy()]
    assert drawn(fig.axes[1]) == expected("mu_norm", usable)


def test_sample_figure_error_bars_and_legend_order(study_small):
    """Each participant's binned mean has its bar, mean +- s.e., in its colour, under the data
    lines; the legend lists the population curve first and the participants after it."""
    from matplotlib.colors import to_rgba

    from fingerpad.plotting.measure import _colours, figure_sample

    sample = next(s for s in sorted(study_small.strokes["sample"].unique()) if s != study_small.options.reference)
    fig = figure_sample(study_small, sample)
    b = study_small.bins[(study_small.bins["sample"] == sample) & (study_small.bins["sense"] == "both")]
    colours = _colours(sorted(b["participant"].unique()))
    for ax, mu, sem in ((fig.axes[0], "mu", "mu_sem"), (fig.axes[1], "mu_norm", "mu_norm_sem")):
        bars = [c for c in ax.collections if type(c).__name__ == "LineCollection"]
        assert len(bars) == 1 and bars[0].get_zorder() < min(line.get_zorder() for line in ax.lines if line.get_gid())
        got = sorted((round(float(seg[0, 0]), 12), round(float(seg[0, 1]), 12), round(float(seg[1, 1]), 12),
                      tuple(np.round(col[:3], 6)))
                     for seg, col in zip(bars[0].get_segments(), bars[0].get_color()) if np.isfinite(seg).all())
        want = sorted((round(float(x), 12), round(float(y - e), 12), round(float(y + e), 12),
                       tuple(np.round(to_rgba(colours[p])[:3], 6)))
                      for x, y, e, p in zip(b["load"], b[mu], b[sem], b["participant"]) if np.isfinite(e))
        assert got == want and got
    labels = [t.get_text() for t in fig.axes[1].get_legend().get_texts()]
    assert labels[0].startswith("mean of participants") and labels[-1] == sorted(colours)[-1]
