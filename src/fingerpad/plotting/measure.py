"""Figures of a friction-measurement study: per participant and per sample (matplotlib, no pyplot).

The QC figure of one recording is :mod:`.qcfigure`'s (its names importable here too)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import FingerpadError
from .drawonce import lay_out_ticks_once, place_legend_once
from .qcfigure import _SENSE_STYLE, QCInputs, figure_qc, qc_inputs, qc_inputs_of, qc_png, stroke_bands

#: The result these figures read (:class:`~fingerpad.measure.analysis.StudyResult`), named for the
#: signatures only: plotting imports nothing of the layers above it, not even for type checking.
StudyResult = Any

__all__ = ["QCInputs", "condition_label", "figure_participant", "figure_qc", "figure_sample", "log_subs",
           "participant_png", "png_bytes", "qc_inputs", "qc_inputs_of", "qc_png", "sample_png", "stroke_bands"]


def condition_label(sample: str, direction: str) -> str:
    """``sample/direction`` (or the sample alone): the label of one measured condition in
    figures, tables and reports."""
    return f"{sample}/{direction}" if direction else str(sample)



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
    _legend_lines(ax)


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
    # the strokes of every condition in one scatter per marker (each point in its condition's
    # colour, conditions in order): one collection per marker instead of three per condition,
    # whose making and drawing was ~40 % of a figure of nine conditions
    points: dict[str, list[tuple[np.ndarray, np.ndarray, Any]]] = {}
    for sample, direction in conds:
        g = of_condition[(sample, direction)]
        colour = colours[condition_label(sample, direction)]
        outlier = g["outlier"].to_numpy(dtype=bool)
        senses = g["sense"].to_numpy()
        loads, mus = g["load"].to_numpy(), g["mu"].to_numpy()
        for sense, (marker, _) in _SENSE_STYLE.items():
            keep = (senses == sense) & ~outlier
            points.setdefault(marker, []).append((loads[keep], mus[keep], colour))
        points.setdefault("x", []).append((loads[outlier], mus[outlier], colour))
    for marker, parts in points.items():
        _scatter_parts(ax, parts, marker=marker, **(dict(s=24) if marker == "x" else dict(s=14, alpha=0.6,
                                                                                           linewidths=0)))
    for sample, direction in conds:
        label = condition_label(sample, direction)
        colour = colours[label]
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
        usable = {c: of_condition[c][~of_condition[c]["outlier"].to_numpy(dtype=bool)] for c in textured}
        _scatter_parts(ax, [(usable[c]["load"].to_numpy(), usable[c]["mu_norm"].to_numpy(),
                             colours[condition_label(*c)]) for c in textured], s=14, alpha=0.6, linewidths=0)
        for sample, direction in textured:
            label = condition_label(sample, direction)
            colour = colours[label]
            g = usable[(sample, direction)]
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


def _scatter_parts(ax: Any, parts: list[tuple[np.ndarray, np.ndarray, Any]], **style: Any) -> None:
    """One scatter of the points of every ``(x, y, colour)`` of ``parts``, in order, each point
    in its part's colour; nothing where no part has a point."""
    if not any(len(x) for x, _, _ in parts):
        return
    colour = np.concatenate([np.tile(np.asarray(c, dtype=float)[None, :4], (len(x), 1)) for x, _, c in parts])
    ax.scatter(np.concatenate([x for x, _, _ in parts]), np.concatenate([y for _, y, _ in parts]), c=colour,
               **style)


#: The gid of a data line whose error bars :func:`_error_bars` draws (:func:`_legend_lines` lists
#: such lines last)
_WITH_BARS = "fingerpad-error-bars"


def _error_bars(ax: Any, bars: list[tuple[Any, Any, Any, Any]], **style: Any) -> None:
    """The vertical error bars ``y +- err`` at ``x`` of every ``(x, y, err, colour)`` of
    ``bars``, as one collection (zorder 2, below the data lines at 2.1, as ``errorbar`` draws
    them): ``errorbar`` made a collection, a container and their styles per call, ~40 % of a
    sample figure with 20 participants."""
    if not bars:
        return
    x = np.concatenate([np.asarray(b[0], dtype=float) for b in bars])
    y = np.concatenate([np.asarray(b[1], dtype=float) for b in bars])
    err = np.concatenate([np.asarray(b[2], dtype=float) for b in bars])
    colours = [b[3] for b in bars for _ in range(len(b[0]))]
    ax.vlines(x, y - err, y + err, colors=colours, zorder=2, **style)


def _legend_lines(ax: Any) -> None:
    """The legend of ``ax`` (if anything has a label), the data lines of :func:`_error_bars`
    last, where matplotlib lists ``errorbar`` plots (its containers follow the other artists);
    each shown by its line and markers: ``errorbar``'s legend handler drew two collections
    per entry (~25 % of a sample figure with 20 participants) for a tick the eye does not need
    to match an entry to its curve."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        order = sorted(range(len(handles)), key=lambda i: handles[i].get_gid() == _WITH_BARS)
        place_legend_once(ax.legend([handles[i] for i in order], [labels[i] for i in order], fontsize=7,
                                    loc="best"))


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
    bars: list[tuple[Any, Any, Any, Any]] = []
    for p in participants:
        g = s[s["participant"] == p]
        for direction, gd in g.groupby("direction"):
            ax.plot(gd["load"], gd["mu"], "o-", ms=3, lw=1, color=colours[p], zorder=2.1, gid=_WITH_BARS,
                    label=condition_label(p, direction))
            bars.append((gd["load"], gd["mu"], gd["mu_sem"], colours[p]))
    _error_bars(ax, bars, linewidth=1)
    ax.set(xscale="log", yscale="log", xlabel="normal load F (N)", ylabel="mu (binned mean +- s.e. over recordings)",
           title=f"{sample}{' (reference)' if is_ref else ''}: raw friction")
    _finish(ax)
    if not is_ref:
        ax = axes[1]
        bars = []
        for p in participants:
            g = s[s["participant"] == p]
            ax.plot(g["load"], g["mu_norm"], "o", ms=3, color=colours[p], zorder=2.1, gid=_WITH_BARS, label=p)
            bars.append((g["load"], g["mu_norm"], g["mu_norm_sem"], colours[p]))
        # every participant's error bars under every model line (errorbar drew each
        # participant's bars under its own line, over the lines before it)
        _error_bars(ax, bars)
        for p in participants:
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


def png_bytes(fig: Any, dpi: int) -> bytes:
    """``fig`` drawn by Agg at ``dpi`` (dots per inch), as PNG bytes: the pixels ``savefig``
    writes, encoded by :func:`fingerpad.plotting.png.figure_png` (zlib level
    :data:`~fingerpad.plotting.png.PNG_COMPRESS_LEVEL`)."""
    from .png import figure_png

    return figure_png(fig, dpi)
