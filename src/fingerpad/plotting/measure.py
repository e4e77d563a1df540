"""Figures of a friction-measurement study: per participant and per sample (matplotlib, no pyplot)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FingerpadError
from .drawonce import lay_out_ticks_once, place_legend_once

#: The result these figures read (:class:`~fingerpad.measure.analysis.StudyResult`), named for the
#: signatures only: plotting imports nothing of the layers above it, not even for type checking.
StudyResult = Any

__all__ = ["QCInputs", "condition_label", "figure_participant", "figure_qc", "figure_sample", "log_subs",
           "participant_png", "png_bytes", "qc_inputs", "qc_inputs_of", "qc_png", "sample_png", "stroke_bands"]


def condition_label(sample: str, direction: str) -> str:
    """``sample/direction`` (or the sample alone): the label of one measured condition in
    figures, tables and reports."""
    return f"{sample}/{direction}" if direction else str(sample)

_SENSE_STYLE = {"+": ("o", "forward (+)"), "-": ("s", "backward (-)")}


def _new_figure(ncols: int, width: float = 5.2, height: float = 4.0):
    from matplotlib.figure import Figure  # no pyplot: no global backend state, Agg on savefig

    # fixed margins: constrained layout would redraw every log axis several times (slow)
    fig = Figure(figsize=(width * ncols, height))
    axes = fig.subplots(1, ncols, squeeze=False)[0]
    fig.subplots_adjust(left=0.5 / (width * ncols) + 0.04, right=0.98, bottom=0.13, top=0.9, wspace=0.28)
    for ax in axes:
        lay_out_ticks_once(ax.xaxis)
        lay_out_ticks_once(ax.yaxis)
    return fig, axes


# figures kept by participant_png and sample_png, one per kind and number of panels: a new
# figure builds its axes and, on the first draw, some 90 tick objects per log axis (a quarter
# of a participant figure's time); a kept one reuses them
_KEPT: dict[tuple[str, int], Any] = {}


def _empty_axes(ax: Any) -> None:
    """Take ``ax`` back to the state of a new axes as the figures below use it: no artists,
    no legend, linear scales (a figure sets its own), limits forgotten and autoscaled, no
    title or axis labels, the colour cycle from its start."""
    for container in list(ax.containers):  # errorbar: its lines go with it
        container.remove()
    for artist in [*ax.lines, *ax.collections, *ax.patches, *ax.texts, *ax.images]:
        artist.remove()
    if ax.get_legend() is not None:
        ax.get_legend().remove()
    ax.set_prop_cycle(None)
    ax.set_xscale("linear")
    ax.set_yscale("linear")
    ax.relim()
    ax.autoscale(True)
    ax.set(title="", xlabel="", ylabel="")


def _figure(kept: dict[tuple[str, int], Any] | None, kind: str, ncols: int, width: float = 5.2):
    """A new figure of ``ncols`` panels, or with ``kept`` the one kept there for ``kind``
    (emptied; kept for the next call)."""
    if kept is None:
        return _new_figure(ncols, width)
    fig = kept.get((kind, ncols))
    if fig is None:
        fig, axes = _new_figure(ncols, width)
        kept[(kind, ncols)] = fig
        return fig, axes
    for ax in fig.axes:
        _empty_axes(ax)
    return fig, fig.axes


def log_subs(low: float, high: float) -> tuple[float, ...]:
    """Mantissas of the labelled ticks of a log axis spanning ``low``-``high``: every integer
    below half a decade (so a narrow range still shows three or more labels), 1-2-5 up to three
    decades, decades beyond."""
    if not (low > 0 and high > low):
        return (1.0, 2.0, 5.0)
    decades = np.log10(high / low)
    if decades < 0.5:
        return tuple(float(k) for k in range(1, 10))
    if decades < 1.2:
        return (1.0, 1.5, 2.0, 3.0, 5.0, 7.0)
    if decades <= 3.0:
        return (1.0, 2.0, 5.0)
    return (1.0,)


def _tick_label(value: float, _pos: Any = None) -> str:
    """Plain numbers (0.2, 1.5, 30), never 2e-01; scientific only far from 1."""
    if value == 0 or 1e-3 <= abs(value) < 1e5:
        return f"{value:.6g}"
    return f"{value:.0e}"


def _finish(ax: Any) -> None:
    """Grid, legend, readable log ticks (plain numbers, enough of them on a narrow range, no
    minor tick labels: log axes label minor ticks by default, slow and busy)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    for axis, lim in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        if axis.get_scale() == "log":
            axis.set_major_locator(LogLocator(base=10, subs=log_subs(*sorted(lim)), numticks=30))
            axis.set_major_formatter(FuncFormatter(_tick_label))
        axis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="major", alpha=0.3)
    # the title at the top of the axes, where matplotlib's automatic placement puts it when
    # nothing is drawn above them (no top ticks, no offset text on these axes); the automatic
    # placement lays out every y tick label again at each draw to find out (~15 % of a figure)
    ax.set_title(ax.get_title(), y=1.0)
    if ax.get_legend_handles_labels()[0]:
        place_legend_once(ax.legend(fontsize=7, loc="best"))


def _colours(names: list[str]) -> dict[str, Any]:
    from matplotlib import colormaps

    cmap = colormaps["tab10"]
    return {name: cmap(i % 10) for i, name in enumerate(names)}


def figure_participant(result: StudyResult, participant: str):
    """Figure of one participant: mu(F) on every sample, and the normalised friction.

    Left: strokes (circles forward, squares backward, crosses outliers) with the power-law
    fits. Right: ``mu_tex / mu_ref`` on each textured sample with the segmented fit, the
    breakpoint and its interval, and the model at the fitted E_s.
    """
    return _draw_participant(result, participant, None)


def participant_png(result: StudyResult, participant: str, dpi: int) -> bytes:
    """The PNG of :func:`figure_participant`, drawn on a figure kept by this process (emptied
    and filled again: the same image as a new figure's). Not for several threads at once."""
    return png_bytes(_draw_participant(result, participant, _KEPT), dpi)


def sample_png(result: StudyResult, sample: str, dpi: int) -> bytes:
    """The PNG of :func:`figure_sample`, drawn on a figure kept by this process (emptied and
    filled again: the same image as a new figure's). Not for several threads at once."""
    return png_bytes(_draw_sample(result, sample, _KEPT), dpi)


def _draw_participant(result: StudyResult, participant: str, kept: dict[tuple[str, int], Any] | None):
    s = result.strokes[result.strokes["participant"] == participant]
    if s.empty:
        raise FingerpadError(f"no strokes of participant {participant!r}")
    conds = sorted({(a, b) for a, b in zip(s["sample"], s["direction"])})
    colours = _colours([condition_label(*c) for c in conds])
    ref = result.options.reference
    textured = [c for c in conds if c[0] != ref]
    fig, axes = _figure(kept, "participant", 2 if textured else 1)
    ax = axes[0]
    grid = result.load_grid()
    # each condition's rows (and each sense's usable ones) looked up once: the rows, in order,
    # of a boolean selection per condition, without a pass over the participant's table for each
    of_condition = dict(iter(s.groupby(["sample", "direction"], sort=False)))
    for sample, direction in conds:
        label = condition_label(sample, direction)
        g = of_condition[(sample, direction)]
        colour = colours[label]
        outlier = g["outlier"].to_numpy(dtype=bool)
        senses = g["sense"].to_numpy()
        loads, mus = g["load"].to_numpy(), g["mu"].to_numpy()
        for sense, (marker, _) in _SENSE_STYLE.items():
            keep = (senses == sense) & ~outlier
            ax.scatter(loads[keep], mus[keep], marker=marker, s=14, color=colour, alpha=0.6, linewidths=0)
        out = g[outlier]
        ax.scatter(out["load"], out["mu"], marker="x", s=24, color=colour)
        fit = result.power_laws.get((participant, sample, direction, "both"))
        if fit is not None:
            ax.plot(grid, fit(grid), color=colour, lw=1.5,
                    label=f"{label}: k={fit.k:.3g}, n={fit.n:.3g}")
        else:
            ax.plot([], [], color=colour, label=f"{label} (no fit)")
    ax.set(xscale="log", yscale="log", xlabel="normal load F (N)", ylabel="friction coefficient mu",
           title=f"{participant}: mu = k F^(n-1)")
    _finish(ax)
    if textured:
        ax = axes[1]
        for sample, direction in textured:
            label = condition_label(sample, direction)
            colour = colours[label]
            g = of_condition[(sample, direction)]
            g = g[~g["outlier"].to_numpy(dtype=bool)]
            ax.scatter(g["load"], g["mu_norm"], s=14, color=colour, alpha=0.6, linewidths=0)
            bp = result.breakpoints.get((participant, sample, direction))
            fine = np.geomspace(g["load"].min(), g["load"].max(), 80) if len(g) else grid
            if bp is not None and bp.detected:
                ax.plot(fine, bp.predict(fine), color=colour, lw=1, ls="--")
                ax.axvspan(bp.ci_low, bp.ci_high, color=colour, alpha=0.12)
                ax.axvline(bp.load, color=colour, lw=0.8, ls=":")
            mf = result.modulus_fits.get((participant, sample, direction))
            table = result.tables.get(sample)
            if mf is not None and table is not None:
                inside = fine[(fine >= table.loads[0]) & (fine <= table.loads[-1])]
                ax.plot(inside, mf.scale * table(inside, mf.skin_modulus), color=colour, lw=1.8,
                        label=f"{label}: E_s = {mf.skin_modulus / 1e6:.3g} MPa ({mf.model or 'model'}; "
                              f"{mf.describe_interval()}{'' if mf.determined else ', not determined'})")
            else:
                ax.plot([], [], color=colour, label=label)
        ax.set(xscale="log", yscale="log", xlabel="normal load F (N)", ylabel="mu_tex / mu_ref",
               title="mu_tex/mu_ref: model (solid), transition if detected")
        _finish(ax)
    return fig


def figure_sample(result: StudyResult, sample: str):
    """Figure of one sample: every participant's binned mu(F), the normalised curves, and the
    between-participant coefficient of variation before/after normalising."""
    return _draw_sample(result, sample, None)


def _draw_sample(result: StudyResult, sample: str, kept: dict[tuple[str, int], Any] | None):
    s = result.bins[(result.bins["sample"] == sample) & (result.bins["sense"] == "both")]
    if s.empty:
        raise FingerpadError(f"no data on sample {sample!r}")
    is_ref = sample == result.options.reference
    participants = sorted(s["participant"].unique())
    colours = _colours(participants)
    fig, axes = _figure(kept, "sample", 1 if is_ref else 3, width=4.6)
    grid = result.load_grid()
    ax = axes[0]
    for p in participants:
        g = s[s["participant"] == p]
        for direction, gd in g.groupby("direction"):
            ax.errorbar(gd["load"], gd["mu"], yerr=gd["mu_sem"], fmt="o-", ms=3, lw=1, color=colours[p],
                        label=condition_label(p, direction))
    ax.set(xscale="log", yscale="log", xlabel="normal load F (N)", ylabel="mu (binned mean +- s.e. over recordings)",
           title=f"{sample}{' (reference)' if is_ref else ''}: raw friction")
    _finish(ax)
    if not is_ref:
        ax = axes[1]
        for p in participants:
            g = s[s["participant"] == p]
            ax.errorbar(g["load"], g["mu_norm"], yerr=g["mu_norm_sem"], fmt="o", ms=3, color=colours[p], label=p)
            # the model at each participant's fitted E_s (one line per direction)
            table = result.tables.get(sample)
            for key, mf in result.modulus_fits.items():
                if table is not None and len(key) == 3 and key[:2] == (p, sample):
                    inside = grid[(grid >= table.loads[0]) & (grid <= table.loads[-1])]
                    ax.plot(inside, mf.scale * table(inside, mf.skin_modulus), color=colours[p], lw=1)
        pop = result.population_curves
        if not pop.empty:
            pc = pop[(pop["sample"] == sample) & (pop["quantity"] == "mu_norm")]
            for direction, pd_ in pc.groupby("direction"):
                pd_ = pd_.sort_values("load")
                ax.plot(pd_["load"], pd_["mean"], color="black", lw=2,
                        label="mean of participants" + (f" ({direction})" if direction else ""))
                band = pd_.dropna(subset=["ci_low", "ci_high"])
                ax.fill_between(band["load"], band["ci_low"], band["ci_high"], color="black", alpha=0.12,
                                label=f"{100 * result.options.level:.0f} % between-person interval")
        ax.set(xscale="log", yscale="log", xlabel="normal load F (N)", ylabel="mu_tex / mu_ref",
               title="normalised by each participant's reference")
        _finish(ax)
        ax = axes[2]
        sp = result.spread[(result.spread["sample"] == sample) & (result.spread["n_participants"] >= 2)]
        centre = np.sqrt(sp["bin_low"] * sp["bin_high"])
        for i, (direction, idx) in enumerate(sp.groupby("direction").groups.items()):
            part = sp.loc[idx]
            c = centre.loc[idx]
            suffix = f" ({direction})" if direction else ""
            style = ("-", "--", ":", "-.")[i % 4]  # one line style per sliding direction
            ax.plot(c, 100 * part["mu_cv"], "o", ls=style, color="tab:red", label=f"raw mu{suffix}")
            ax.plot(c, 100 * part["mu_norm_cv"], "s", ls=style, color="tab:blue", label=f"normalised{suffix}")
        ax.set(xscale="log", xlabel="normal load F (N)", ylabel="CV between participants (%)",
               title="spread between people")
        ax.set_ylim(bottom=0)
        _finish(ax)
    return fig


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
    return png_bytes(fig, dpi)


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


def png_bytes(fig: Any, dpi: int) -> bytes:
    """``fig`` drawn by Agg at ``dpi`` (dots per inch), as PNG bytes: the pixels ``savefig``
    writes, encoded by :func:`fingerpad.plotting.png.figure_png` (zlib level
    :data:`~fingerpad.plotting.png.PNG_COMPRESS_LEVEL`)."""
    from .png import figure_png

    return figure_png(fig, dpi)
