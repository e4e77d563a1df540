"""QC sheets: every recording of one participant in one figure, as small multiples.

A per-recording QC figure (:func:`~fingerpad.plotting.qcfigure.qc_png`) costs some 0.12 s of CPU
to draw, most of it the fixed price of a figure (its axes, ticks, text and PNG), so 540
recordings (20 people x 9 samples x 3) cost a minute. A sheet draws the same check for all of a
participant's recordings at once: one small panel per recording (a row per sample, a column per
repetition), the normal and friction forces against time with every stroke shaded by sense, its
steady window darker, outliers outlined red, dropped strokes hatched grey, clipped strokes
cross-hatched magenta, the lift-off threshold dotted red. The panels share one time and one
force scale (tick labels on the outer ones only), and one figure is kept per grid, so a
recording adds a panel's lines and bands, not a figure: ~0.02 s of CPU. The full figure's
position trace and mu-per-stroke panel are left out (``strokes.csv`` has every stroke's mu);
``write_report(..., qc_recordings=True)`` draws the full figures too.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FingerpadError
from .drawonce import lay_out_ticks_once
from .png import figure_png
from .qcfigure import _BAND_STYLES, _SENSE_COLOURS, QCInputs, _decimate, _span_verts, qc_inputs_of, stroke_bands

StudyResult = Any

__all__ = ["QCSheet", "QC_SHEET_COLUMNS", "QC_SHEET_ROWS", "figure_qc_sheet", "natural_key", "qc_sheet_png", "qc_sheets"]

#: Panels per row of a sheet at most (a sample with more recordings takes several rows), and
#: rows per sheet at most (a participant with more takes several sheets, ``..._2.png`` ...).
QC_SHEET_COLUMNS, QC_SHEET_ROWS = 4, 12

#: Points drawn per trace: a panel is some 250 pixels wide, so 1200 points (each bucket's minimum
#: and maximum, in time order) reach every pixel column's extremes.
_SHEET_POINTS = 1200


@dataclass(frozen=True)
class QCSheet:
    """One QC sheet: ``participant``'s recordings ``cells`` (their :class:`QCInputs`) at
    positions ``places`` (row, column) of a ``rows`` x ``columns`` grid; ``page`` (1-based) of
    ``pages``."""

    participant: str
    cells: tuple[QCInputs, ...]
    places: tuple[tuple[int, int], ...]
    rows: int
    columns: int
    page: int = 1
    pages: int = 1


def natural_key(name: str) -> tuple[tuple[int, int | str], ...]:
    """Sort key of ``name`` with its digit runs as numbers: ``bumps8`` before ``bumps22``
    (plain string order puts ``bumps22`` first)."""
    return tuple((0, int(part)) if part.isdecimal() else (1, part) for part in re.split(r"(\d+)", name) if part)


def qc_sheets(result: StudyResult) -> list[QCSheet]:
    """Every participant's QC sheets (participants sorted, then pages), each recording with
    strokes found on exactly one of them: a row per sample (the reference first, then in
    natural order: :func:`natural_key`),
    the sample's recordings in the order of the study, at most :data:`QC_SHEET_COLUMNS` a row,
    at most :data:`QC_SHEET_ROWS` rows a sheet."""
    by_participant: dict[str, dict[str, list[Any]]] = {}
    for rec in result.recordings:
        if rec.source in result.stroke_reports:
            by_participant.setdefault(str(rec.participant), {}).setdefault(str(rec.sample), []).append(rec)
    reference = getattr(getattr(result, "options", None), "reference", None)
    inputs = qc_inputs_of(result)
    sheets = []
    for participant in sorted(by_participant):
        samples = by_participant[participant]
        columns = min(max(len(v) for v in samples.values()), QC_SHEET_COLUMNS)
        # lines of the grid: one or more per sample
        lines: list[list[Any]] = []
        # the reference first, then in natural order (bumps8 before bumps22)
        for sample in sorted(samples, key=lambda name: (name != reference, natural_key(name))):
            recs = samples[sample]
            lines += [recs[i:i + columns] for i in range(0, len(recs), columns)]
        pages = [lines[i:i + QC_SHEET_ROWS] for i in range(0, len(lines), QC_SHEET_ROWS)]
        for number, page in enumerate(pages, start=1):
            cells = tuple(inputs(rec.source) for line in page for rec in line)
            places = tuple((r, c) for r, line in enumerate(page) for c in range(len(line)))
            sheets.append(QCSheet(participant, cells, places, len(page), columns, number, len(pages)))
    return sheets


def figure_qc_sheet(sheet: QCSheet):
    """The figure of ``sheet`` (see the module doc), a new one."""
    return _draw_sheet(sheet, None)


# one sheet figure per grid (rows, columns), reused by qc_sheet_png: building the panels and their
# tick objects was most of a sheet's time; the image is the same as a new figure's
_KEPT: dict[tuple[int, int], Any] = {}

_LEGEND_LABELS = ("normal force F_n", "friction force F_t", "stroke + (steady part darker)", "stroke -",
                  "outlier", "dropped (lift-off)", "clipped (sensor saturated)", "lift-off threshold")


def _new_sheet_figure(rows: int, columns: int):
    """An empty sheet of ``rows`` x ``columns`` panels with what every sheet of that grid shares:
    each panel's two trace lines, its band collections (one per style), the threshold line and
    its title; the legend at the top. The panels are not shared axes (a shared axis passes every
    limit change on to all its siblings); they get the same limits and ticks instead."""
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    # panels of 2.9 in, the figure at least 9.5 in wide (the title and the legend's one row);
    # with one or two recordings a sample the panels widen instead
    width = max(2.9 * columns, 8.7) + 0.8
    height = 1.45 * rows + 1.0
    fig = Figure(figsize=(width, height))
    axes = fig.subplots(rows, columns, squeeze=False)
    fig.subplots_adjust(left=0.7 / width, right=1 - 0.15 / width, bottom=0.45 / height, top=1 - 0.75 / height,
                        hspace=0.42, wspace=0.06)
    for ax in axes.flat:
        ax.set_autoscale_on(False)  # the sheet sets every panel's limits
        for style in _BAND_STYLES:
            ax.add_collection(PolyCollection([], transform=ax.get_xaxis_transform(which="grid"),
                                             **{**style, "linewidth": min(style.get("linewidth", 0), 0.8)}),
                              autolim=False)
        ax.add_line(Line2D([], [], color="0.15", lw=0.5))
        ax.add_line(Line2D([], [], color="tab:green", lw=0.5))
        ax.add_line(Line2D([0.0, 1.0], [0.0, 0.0], color="red", lw=0.6, ls=":", transform=ax.get_yaxis_transform()))
        ax.tick_params(labelsize=6, length=2, pad=1)
        ax.grid(True, alpha=0.3, lw=0.5)
        ax.set_title(" ", fontsize=6.5, pad=2, y=1.0)
        lay_out_ticks_once(ax.xaxis)
        lay_out_ticks_once(ax.yaxis)
    handles = [Line2D([], [], color="0.15", lw=0.8), Line2D([], [], color="tab:green", lw=0.8),
               Patch(color=_SENSE_COLOURS[1], alpha=0.25), Patch(color=_SENSE_COLOURS[-1], alpha=0.25),
               Patch(facecolor="none", edgecolor="red", lw=1.2), Patch(facecolor="none", edgecolor="0.6", hatch="///"),
               Patch(facecolor="none", edgecolor="magenta", hatch="xx"), Line2D([], [], color="red", lw=0.8, ls=":")]
    fig.legend(handles=handles, labels=list(_LEGEND_LABELS), loc="upper center", ncol=8,
               fontsize=6.5, frameon=False, bbox_to_anchor=(0.5, 1 - 0.38 / height), handlelength=1.6,
               columnspacing=1.0)
    fig.suptitle(" ", fontsize=10, y=1 - 0.12 / height, va="top")
    return fig


def _limits(sheet: QCSheet) -> tuple[tuple[float, float], tuple[float, float]]:
    """The time and force limits every panel of ``sheet`` shares: all samples of all its
    recordings, the lift-off threshold and zero force in view, 3 % margins."""
    t_lo, t_hi, f_lo, f_hi = math.inf, -math.inf, 0.0, -math.inf
    for inputs in sheet.cells:
        rec = inputs.recording
        t = rec.time if rec.time is not None else np.arange(len(rec), dtype=float)
        if len(t):
            t_lo, t_hi = min(t_lo, float(np.nanmin(t))), max(t_hi, float(np.nanmax(t)))
        for y in (rec.normal, rec.friction):
            if len(y) and np.isfinite(y).any():
                f_lo, f_hi = min(f_lo, float(np.nanmin(y))), max(f_hi, float(np.nanmax(y)))
        f_hi = max(f_hi, inputs.min_load, *(c.level for c in getattr(inputs.report, "clips", [])))
    if not math.isfinite(t_lo) or t_hi <= t_lo:
        t_lo, t_hi = (t_lo, t_lo + 1.0) if math.isfinite(t_lo) else (0.0, 1.0)
    if not f_hi > f_lo:
        f_hi = f_lo + 1.0
    dt, df = 0.03 * (t_hi - t_lo), 0.05 * (f_hi - f_lo)
    return (t_lo - dt, t_hi + dt), (f_lo - df, f_hi + df)


def _draw_sheet(sheet: QCSheet, kept: dict[tuple[int, int], Any] | None):
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FixedLocator, MaxNLocator, NullLocator

    if not sheet.cells:
        raise FingerpadError(f"no recordings on the QC sheet of participant {sheet.participant!r}")
    shape = (sheet.rows, sheet.columns)
    fig = kept.get(shape) if kept is not None else None
    if fig is None:
        fig = _new_sheet_figure(*shape)
        if kept is not None:
            kept[shape] = fig
    axes = np.asarray(fig.axes).reshape(shape)
    (xlim, ylim) = _limits(sheet)
    xticks = FixedLocator(MaxNLocator(nbins=6).tick_values(*xlim))
    yticks = FixedLocator(MaxNLocator(nbins=4).tick_values(*ylim))
    xlabel = "time (s)" if sheet.cells[0].recording.time is not None else "sample"
    filled = dict(zip(sheet.places, sheet.cells))
    for r in range(sheet.rows):
        for c in range(sheet.columns):
            ax = axes[r, c]
            inputs = filled.get((r, c))
            for extra in ax.lines[3:]:  # the saturated levels of the last sheet's recording here
                extra.remove()
            ax.set_visible(inputs is not None)
            if inputs is None:
                continue
            _fill_panel(ax, inputs)
            for level in sorted(clip.level for clip in getattr(inputs.report, "clips", [])):
                ax.add_line(Line2D([0.0, 1.0], [level, level], color="magenta", lw=0.8, ls="--",
                                   transform=ax.get_yaxis_transform()))
            ax.set_xlim(xlim)
            ax.set_ylim(ylim)
            ax.xaxis.set_major_locator(xticks)
            ax.yaxis.set_major_locator(yticks)
            ax.xaxis.set_minor_locator(NullLocator())
            ax.yaxis.set_minor_locator(NullLocator())
            # tick labels on the outer panels only: a panel with another below it shows no
            # time labels, one right of another no force labels
            below = (r + 1, c) in filled
            ax.tick_params(labelbottom=not below, labelleft=c == 0)
            ax.set_ylabel("force (N)" if c == 0 else "", fontsize=7, labelpad=1)
            ax.set_xlabel("" if below else xlabel, fontsize=7, labelpad=1)
    page = f" (sheet {sheet.page} of {sheet.pages})" if sheet.pages > 1 else ""
    fig._suptitle.set_text(f"QC of participant {sheet.participant}{page}: every recording's forces and strokes")
    return fig


def _fill_panel(ax: Any, inputs: QCInputs) -> None:
    """One recording's panel: both forces against time, the stroke bands, the threshold, its
    title (sample, repetition, counts)."""
    rec, report, strokes = inputs.recording, inputs.report, inputs.strokes
    outlier = dict(zip(strokes["stroke"], strokes["outlier"]))
    t = rec.time if rec.time is not None else np.arange(len(rec), dtype=float)
    bands = stroke_bands(report, t, outlier, inputs.clipped)
    for collection, spans in zip(ax.collections, bands, strict=True):
        collection.set_verts(_span_verts(spans))
    for line, y in zip(ax.lines[:2], (rec.normal, rec.friction)):
        line.set_data(*_decimate(t, np.asarray(y, dtype=float), _SHEET_POINTS))
    ax.lines[2].set_ydata([inputs.min_load, inputs.min_load])
    n_out = int(strokes["outlier"].sum())
    n_drop = len(report.strokes) - len(report.used)
    label = f"{rec.sample} {rec.repetition}".strip() or Path(inputs.source).stem
    counts = f"{len(report.used)} strokes" + (f", {n_out} outl." if n_out else "") + \
        (f", {n_drop} dropped" if n_drop else "") + (f", {len(inputs.clipped)} clipped" if inputs.clipped else "")
    ax.title.set_text(f"{label}: {counts}")


def qc_sheet_png(sheet: QCSheet, dpi: int) -> bytes:
    """The PNG bytes of :func:`figure_qc_sheet` at ``dpi``; a module-level function, so that a
    process pool can call it."""
    return figure_png(_draw_sheet(sheet, _KEPT), dpi)
