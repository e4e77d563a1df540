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
