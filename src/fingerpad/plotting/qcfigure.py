"""The QC figure of one recording: its forces (and position) against time with every stroke, and
mu per stroke (matplotlib, no pyplot); drawn on a figure kept per number of panels."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FingerpadError
from .drawonce import lay_out_ticks_once, place_legend_once
from .png import figure_png

#: The result these figures read (:class:`~fingerpad.measure.study.StudyResult`), named for the
#: signatures only: plotting imports nothing of the layers above it.
StudyResult = Any

__all__ = ["QCInputs", "figure_qc", "qc_inputs", "qc_inputs_of", "qc_png", "stroke_bands"]

#: Marker and legend label of each sense of sliding.
_SENSE_STYLE = {"+": ("o", "forward (+)"), "-": ("s", "backward (-)")}


def _decimate(t: np.ndarray, y: np.ndarray, max_points: int = 6000) -> tuple[np.ndarray, np.ndarray]:
    """At most ``max_points`` points that keep the envelope: the samples are cut into
    consecutive buckets (the last one may be shorter) and each bucket gives its minimum and its
    maximum, in time order, so the line reaches every bucket's extremes (a stroke's peak is drawn,
    or a higher sample next to it in its bucket) and ``max_points`` bounds its vertices: a 60 s
    recording at 1 kHz (60 000 samples) draws 6000, some three per pixel column of the figure,
    and looks the same; its spikes stay visible."""
    n = y.size
    if n <= max_points:
        return t, y
    k = int(np.ceil(n / (max_points // 2)))
    m = -(-n // k)  # buckets, the last one shorter where k does not divide n
    # pad the tail bucket with its own last sample (changes neither its min nor its max)
    yb = np.concatenate([y, np.repeat(y[-1:], m * k - n)]).reshape(m, k)
    lo, hi = yb.argmin(axis=1), yb.argmax(axis=1)  # first index of each; NaN where one is NaN
    base = np.arange(m) * k
    pick = np.minimum(np.column_stack([base + np.minimum(lo, hi), base + np.maximum(lo, hi)]).ravel(), n - 1)
    return t[pick], y[pick]

def _span_verts(spans: list[tuple[float, float]]) -> np.ndarray:
    """Vertical bands ``(x0, x1)`` (data units) as polygons in the axis's x-grid transform
    (x data, y axes fraction: full height), as ``axvspan`` draws them: an array of shape
    ``(bands, 4, 2)``, which ``PolyCollection.set_verts`` turns into paths without closing each
    one on its own (the same paths; a seventh of a QC figure's time as a list)."""
    if not spans:
        return np.zeros((0, 4, 2))
    x = np.asarray(spans, dtype=float)
    out = np.empty((len(spans), 4, 2))
    out[:, 0, 0] = out[:, 1, 0] = x[:, 0]
    out[:, 2, 0] = out[:, 3, 0] = x[:, 1]
    out[:, :, 1] = (0.0, 1.0, 1.0, 0.0)
    return out


def figure_qc(result: StudyResult, source: str):
    """Quality-control figure of one recording, to check the stroke detection by eye.

    Top three panels against time (or sample number): normal force, friction force and position
    (or velocity, or the friction-derived direction); every stroke shaded by sense (blue ``+``,
    orange ``-``), its steady window (where mu is averaged) darker, strokes flagged as
    outliers outlined in red, strokes dropped (lift-off) hatched grey, strokes left out because
    a force channel saturated cross-hatched magenta with the saturated level dashed; the
    lift-off threshold on the normal force. Bottom: mu of each stroke against its number (running-in, moisture
    drift), outliers as red crosses.
    """
    return _draw_qc(qc_inputs(result, source))


@dataclass(frozen=True)
class QCInputs:
    """What the QC figure of one recording reads: small enough to send to a worker process
    (one recording's samples, not the study's). Built by :func:`qc_inputs`."""

    source: str
    recording: Any  # measure.Recording
    report: Any  # measure.StrokeReport of the recording
    strokes: Any  # pandas.DataFrame: the recording's rows of the result's stroke table
    clipped: frozenset  # numbers of the strokes left out for a saturated sensor
    min_load: float  # lift-off threshold (N)


def qc_inputs(result: StudyResult, source: str) -> QCInputs:
    """The inputs of :func:`figure_qc` for recording ``source`` of ``result``."""
    return qc_inputs_of(result)(source)


def qc_inputs_of(result: StudyResult) -> Callable[[str], QCInputs]:
    """:func:`qc_inputs` of ``result`` for many recordings: the stroke tables split by file once
    (a selection over the whole table per recording cost ~3 ms, 1.7 s for 540 recordings); the
    same rows, in the same order, with the same index."""
    recordings: dict[str, Any] = {}
    for rec in result.recordings:
        recordings.setdefault(rec.source, rec)  # the first of a source, as a search in order
    strokes = result.strokes
    rows = strokes.groupby("file", sort=False).indices if len(strokes) else {}
    cs = getattr(result, "clipped_strokes", None)
    clipped: dict[str, frozenset] = {}
    if cs is not None and len(cs):
        for file, numbers in cs.groupby("file", sort=False)["stroke"]:
            clipped[file] = frozenset(numbers)
    min_load = float(result.options.strokes.min_load)

    def one(source: str) -> QCInputs:
        rec = recordings.get(source)
        report = result.stroke_reports.get(source)
        if rec is None or report is None:
            raise FingerpadError(f"no recording {source!r} in the result")
        at = rows.get(source)
        return QCInputs(source, rec, report, strokes.iloc[at] if at is not None else strokes.iloc[:0],
                        clipped.get(source, frozenset()), min_load)
    return one


# one QC figure per number of panels, reused by qc_png: building the axes and their ticks
# was half of a figure's time; the PNG is the same, byte for byte, as a new figure's
_QC_FIGURES: dict[int, Any] = {}


def qc_png(inputs: QCInputs, dpi: int) -> bytes:
    """The QC figure of ``inputs`` as PNG bytes, the same bytes as ``png_bytes(figure_qc(...))``.

    It redraws one figure kept by this process (its axes emptied and filled again) instead of
    building a new one; a module-level function, so that a process pool can call it. Not for
    use from several threads at once."""
    n_rows = 4 if inputs.recording.position is not None or inputs.recording.velocity is not None else 3
    fig = _draw_qc(inputs, _QC_FIGURES.get(n_rows))
    _QC_FIGURES[n_rows] = fig
    return figure_png(fig, dpi)


# the styles of the stroke bands, one collection each per time panel, in drawing order
# (shades, steady windows, outlines, clipped); colours of the two senses
_SENSE_COLOURS = {1: "tab:blue", -1: "tab:orange"}
_BAND_STYLES: tuple[dict[str, Any], ...] = (
    {"facecolor": "none", "edgecolor": "0.6", "hatch": "///", "linewidth": 0},  # dropped (lift-off)
    {"color": _SENSE_COLOURS[1], "alpha": 0.10, "linewidth": 0},  # stroke +
    {"color": _SENSE_COLOURS[-1], "alpha": 0.10, "linewidth": 0},  # stroke -
    {"color": _SENSE_COLOURS[1], "alpha": 0.25, "linewidth": 0},  # steady window +
    {"color": _SENSE_COLOURS[-1], "alpha": 0.25, "linewidth": 0},  # steady window -
    {"facecolor": "none", "edgecolor": "red", "linewidth": 1.5},  # outlier outline
    {"facecolor": "none", "edgecolor": "magenta", "hatch": "xx", "linewidth": 1.5},  # clipped
)


def _new_qc_figure(n_rows: int):
    """An empty QC figure of ``n_rows`` panels with what every recording's figure shares: the
    axes and their styles, and the artists that :func:`_draw_qc` gives data (each time panel
    one line and one band collection per style; the mu panel one line per marker). Set up once per kept figure: styling the ticks and adding the artists was
    about a fifth of a figure's time when done for every recording."""
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 2.0 * n_rows + 0.6))
    axes = fig.subplots(n_rows, 1, squeeze=True)
    fig.subplots_adjust(left=0.08, right=0.98, bottom=0.06, top=0.94, hspace=0.45)
    for ax in axes:
        lay_out_ticks_once(ax.xaxis)
        lay_out_ticks_once(ax.yaxis)
    for ax in axes[:-1]:
        ax.plot([], [], color="0.25", lw=0.6)
        for style in _BAND_STYLES:
            ax.add_collection(PolyCollection([], transform=ax.get_xaxis_transform(which="grid"), **style),
                              autolim=False)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
    for ax in axes[:-2]:
        # these panels never show an x label (time is labelled below the last time panel);
        # fixed coordinates spare placing the empty label below the tick labels at each draw,
        # which lays out every tick label once more (~4 % of a figure)
        ax.xaxis.set_label_coords(0.5, 0.0)
    ax = axes[-1]
    for sense, (marker, label) in _SENSE_STYLE.items():
        ax.plot([], [], marker, ms=4, ls="none", label=label, color=_SENSE_COLOURS[1 if sense == "+" else -1])
    ax.plot([], [], "x", color="red", ms=7, ls="none", label="outlier")
    ax.set(xlabel="stroke number", ylabel="mu of stroke")
    ax.xaxis.label.set_size(8)
    ax.yaxis.label.set_size(8)
    ax.tick_params(labelsize=7)
    ax.grid(True, alpha=0.3)
    return fig


def stroke_bands(report: Any, t: np.ndarray, outlier: dict[int, bool], clipped: set[int] | frozenset[int]
                 ) -> list[list[tuple[float, float]]]:
    """The time spans ``(start, end)`` of a recording's strokes grouped by the styles of
    :data:`_BAND_STYLES`, in its order: dropped (lift-off), strokes ``+`` and ``-``, their steady
    windows ``+`` and ``-``, outliers (``outlier``: stroke number -> flag), clipped (``clipped``:
    stroke numbers left out for a saturated channel)."""
    used = {id(st): i + 1 for i, st in enumerate(report.used)}
    dropped: list[tuple[float, float]] = []
    shade: dict[int, list[tuple[float, float]]] = {1: [], -1: []}
    steady: dict[int, list[tuple[float, float]]] = {1: [], -1: []}
    outlined: list[tuple[float, float]] = []
    cross: list[tuple[float, float]] = []
    for st in report.strokes:
        number = used.get(id(st))
        span = (t[st.start], t[min(st.stop, len(t)) - 1])
        if number is None:
            dropped.append(span)
            continue
        shade[st.sense].append(span)
        steady[st.sense].append((t[st.steady_start], t[st.steady_stop - 1]))
        if outlier.get(number, False):
            outlined.append(span)
        if number in clipped:  # left out: a force channel saturated during the stroke
            cross.append(span)
    return [dropped, shade[1], shade[-1], steady[1], steady[-1], outlined, cross]


def _draw_qc(inputs: QCInputs, reuse: Any = None):
    """Draw the QC figure of ``inputs`` on a new figure, or on ``reuse`` (a figure this function
    drew before with the same number of panels): the same artists get the new data, so a
    reused figure and a new one draw the same image."""
    source, rec, report, strokes = inputs.source, inputs.recording, inputs.report, inputs.strokes
    outlier = dict(zip(strokes["stroke"], strokes["outlier"]))
    clipped = set(inputs.clipped)
    clips = getattr(report, "clips", [])
    t = rec.time if rec.time is not None else np.arange(len(rec), dtype=float)
    xlabel = "time (s)" if rec.time is not None else "sample"
    third, third_label = ((rec.position * 1e3, "position (mm)") if rec.position is not None else
                          (rec.velocity * 1e3, "velocity (mm/s)") if rec.velocity is not None else
                          (None, ""))
    n_rows = 4 if third is not None else 3
    fig = reuse if reuse is not None and len(reuse.axes) == n_rows else _new_qc_figure(n_rows)
    axes = fig.axes
    series = [(rec.normal, "normal force F_n (N)"), (rec.friction, "friction force F_t (N)")]
    if third is not None:
        series.append((third, third_label))
    # the spans of every stroke, grouped by style: one collection per style and axis instead of
    # one patch per span (some 320 patches per figure cost most of its time to add and draw)
    bands = stroke_bands(report, t, outlier, clipped)
    span_x = np.asarray([x for spans in bands for span in spans for x in span], dtype=float)
    for ax, (y, label) in zip(axes, series):
        for extra in ax.lines[1:]:  # the threshold and saturated levels of the last recording
            extra.remove()
        tt, yy = _decimate(t, np.asarray(y, dtype=float))
        ax.lines[0].set_data(tt, yy)
        for collection, spans in zip(ax.collections, bands, strict=True):
            collection.set_verts(_span_verts(spans))
        ax.relim()  # data limits of this recording's line only, autoscaled
        if span_x.size:  # the bands widen the time axis as axvspan's would
            ax.update_datalim(np.column_stack([span_x, np.zeros_like(span_x)]), updatey=False)
        ax.autoscale(True)
        ax.set_ylabel(label, fontsize=8)
        ax.set_xlabel("")
    # added after the limits are set, as on a new figure: axhline widens them only where the
    # level is outside the data's
    axes[0].axhline(inputs.min_load, color="red", lw=0.8, ls=":")
    for clip in clips:  # the saturated level of each clipped channel
        axes[0 if clip.channel == "normal" else 1].axhline(clip.level, color="magenta", lw=1.0, ls="--")
    axes[n_rows - 2].set_xlabel(xlabel, fontsize=8)
    ax = axes[-1]
    number, mu = np.asarray(strokes["stroke"]), np.asarray(strokes["mu"])
    sense, flagged = np.asarray(strokes["sense"]), np.asarray(strokes["outlier"], dtype=bool)
    picks = [(sense == s) & ~flagged for s in _SENSE_STYLE] + [flagged]
    for line, pick in zip(ax.lines, picks, strict=True):
        line.set_data(number[pick], mu[pick])
    # the legend (the same three entries on every recording, placed at each draw) is made once
    # per kept figure and taken out for a recording without strokes
    legend = getattr(fig, "_fingerpad_qc_legend", None)
    if legend is None and len(strokes):
        legend = fig._fingerpad_qc_legend = ax.legend(fontsize=7, loc="best", ncol=3)
        place_legend_once(legend)
    if legend is not None:
        ax.legend_ = legend if len(strokes) else None
        legend.stale = True
    ax.relim()
    if len(strokes):
        ax.autoscale(True)
    else:
        # no data to scale to: autoscaling would keep a reused figure's last limits (matplotlib
        # keeps set limits when there is nothing to fit), so both kinds of figure get these
        ax.set(xlim=(0.0, 1.0), ylim=(0.0, 1.0))
    from pathlib import Path

    n_drop = len(report.strokes) - len(report.used)
    fig.suptitle(f"{Path(source).name}: {len(report.used)} strokes (direction from {report.source}), "
                 f"{int(strokes['outlier'].sum())} outlier(s), {n_drop} dropped (lift-off)"
                 + (f", {report.short_travel} shorter than the minimum travel" if report.short_travel else "")
                 + (f", {len(clipped)} clipped (sensor saturated, left out)" if clipped else ""),
                 fontsize=10)
    return fig
