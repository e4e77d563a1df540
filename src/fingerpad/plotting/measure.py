"""Figures of a friction-measurement study: per participant and per sample (matplotlib, no pyplot)."""

from __future__ import annotations

import io
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import FingerpadError
from ..measure.analysis import condition_label, load_grid

if TYPE_CHECKING:
    from ..measure.analysis import StudyResult

__all__ = ["figure_participant", "figure_sample", "png_bytes"]

_SENSE_STYLE = {"+": ("o", "forward (+)"), "-": ("s", "backward (-)")}


def _new_figure(ncols: int, width: float = 5.2, height: float = 4.0):
    from matplotlib.figure import Figure  # no pyplot: no global backend state, Agg on savefig

    # fixed margins: constrained layout would redraw every log axis several times (slow)
    fig = Figure(figsize=(width * ncols, height))
    axes = fig.subplots(1, ncols, squeeze=False)[0]
    fig.subplots_adjust(left=0.5 / (width * ncols) + 0.04, right=0.98, bottom=0.13, top=0.9, wspace=0.28)
    return fig, axes


def _finish(ax: Any) -> None:
    """Grid, legend, and no minor tick labels (log axes label minor ticks by default: slow, busy)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    for axis in (ax.xaxis, ax.yaxis):
        if axis.get_scale() == "log":
            # 1-2-5 labels: friction often spans less than a decade, where plain decades show none
            axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
            axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
        axis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="major", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="best")


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
    s = result.strokes[result.strokes["participant"] == participant]
    if s.empty:
        raise FingerpadError(f"no strokes of participant {participant!r}")
    conds = sorted({(a, b) for a, b in zip(s["sample"], s["direction"])})
    colours = _colours([condition_label(*c) for c in conds])
    ref = result.options.reference
    textured = [c for c in conds if c[0] != ref]
    fig, axes = _new_figure(2 if textured else 1)
    ax = axes[0]
    grid = load_grid(result)
    for sample, direction in conds:
        label = condition_label(sample, direction)
        g = s[(s["sample"] == sample) & (s["direction"] == direction)]
        colour = colours[label]
        for sense, (marker, _) in _SENSE_STYLE.items():
            part = g[(g["sense"] == sense) & ~g["outlier"]]
            ax.scatter(part["load"], part["mu"], marker=marker, s=14, color=colour, alpha=0.6, linewidths=0)
        out = g[g["outlier"]]
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
            g = s[(s["sample"] == sample) & (s["direction"] == direction) & ~s["outlier"]]
            ax.scatter(g["load"], g["mu_norm"], s=14, color=colour, alpha=0.6, linewidths=0)
            bp = result.breakpoints.get((participant, sample, direction))
            fine = np.geomspace(g["load"].min(), g["load"].max(), 80) if len(g) else grid
            if bp is not None:
                ax.plot(fine, bp.predict(fine), color=colour, lw=1, ls="--")
                ax.axvspan(bp.ci_low, bp.ci_high, color=colour, alpha=0.12)
                ax.axvline(bp.load, color=colour, lw=0.8, ls=":")
            mf = result.modulus_fits.get((participant, sample, direction))
            table = result.tables.get(sample)
            if mf is not None and table is not None:
                inside = fine[(fine >= table.loads[0]) & (fine <= table.loads[-1])]
                ax.plot(inside, mf.scale * table(inside, mf.skin_modulus), color=colour, lw=1.8,
                        label=f"{label}: E_s = {mf.skin_modulus / 1e6:.3g} MPa "
                              f"[{mf.ci_low / 1e6:.3g}, {mf.ci_high / 1e6:.3g}]")
            else:
                ax.plot([], [], color=colour, label=label)
        ax.set(xscale="log", yscale="log", xlabel="normal load F (N)", ylabel="mu_tex / mu_ref",
               title="normalised friction: breakpoint (dotted, band = CI), model (solid)")
        _finish(ax)
    return fig


def figure_sample(result: StudyResult, sample: str):
    """Figure of one sample: every participant's binned mu(F), the normalised curves, and the
    between-participant coefficient of variation before/after normalising."""
    s = result.bins[(result.bins["sample"] == sample) & (result.bins["sense"] == "both")]
    if s.empty:
        raise FingerpadError(f"no data on sample {sample!r}")
    is_ref = sample == result.options.reference
    participants = sorted(s["participant"].unique())
    colours = _colours(participants)
    fig, axes = _new_figure(1 if is_ref else 3, width=4.6)
    grid = load_grid(result)
    ax = axes[0]
    for p in participants:
        g = s[s["participant"] == p]
        for direction, gd in g.groupby("direction"):
            ax.errorbar(gd["load"], gd["mu"], yerr=gd["mu_sem"], fmt="o-", ms=3, lw=1, color=colours[p],
                        label=condition_label(p, direction))
    ax.set(xscale="log", yscale="log", xlabel="normal load F (N)", ylabel="mu (binned mean +- sem)",
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
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()

