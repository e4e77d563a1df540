"""The population figure of ``predict --population``: bands of A_re/A_fr and mu/mu_ref against the
load, and the distribution of the critical load (docs/population.md)."""

from __future__ import annotations

from typing import Any

import numpy as np

#: The result these figures read (:class:`~fingerpad.population.run.PopulationResult`), named for
#: the signatures only: plotting imports nothing of the layers above it, not even for type
#: checking.
PopulationResult = Any

__all__ = ["CENTRE_OPACITY", "band_opacity", "figure_population"]


#: Opacity at the centre of the nested bands, however many there are: each band's opacity is set
#: so that the bands stacked over the median reach it (14 levels and more gave an opacity above 1,
#: which matplotlib refuses).
CENTRE_OPACITY = 0.6


def band_opacity(pairs: int) -> float:
    """The opacity of each of ``pairs`` nested bands: ``1 - (1 - a)^pairs = CENTRE_OPACITY``."""
    return 1.0 - (1.0 - CENTRE_OPACITY) ** (1.0 / max(pairs, 1))


def figure_population(result: PopulationResult) -> Any:
    """Shaded bands (the pairs of the reported quantiles, e.g. 5-95 % and 25-75 %; any number of
    them, the outermost and innermost named) and the median of A_re/A_fr and mu/mu_ref against the
    load (log axis), the study's own finger dashed; a histogram of the members' critical loads (N,
    log bins; members that never reach the transition, or are past it at zero load, are counted in
    the title: :func:`critical_title`) with the range of
    the loads predicted shaded and the study's finger's critical load marked."""
    from matplotlib.figure import Figure

    nominal = result.nominal
    loads = np.asarray(nominal.study.loads, float)
    levels = sorted(result.quantile_levels)
    # fixed margins, not the constrained layout: its text-extent passes over the log axes' tick
    # labels took two thirds of the figure's time (0.2 s of a population prediction)
    fig = Figure(figsize=(11, 3.6))
    fig.subplots_adjust(left=0.06, right=0.99, bottom=0.14, top=0.86, wspace=0.28)
    axes = fig.subplots(1, 3)
    pairs = [(i, len(levels) - 1 - i) for i in range(len(levels) // 2)]
    alpha = band_opacity(len(pairs))
    for ax, name, label in ((axes[0], "area_ratio", "A_re / A_fr"), (axes[1], "mu_normalised", "μ / μ_ref")):
        values = result.values(name)
        table = np.quantile(values, levels, axis=0)
        for depth, (lo, hi) in enumerate(pairs):
            named = depth in (0, len(pairs) - 1)
            ax.fill_between(loads, table[lo], table[hi], color="C0", alpha=alpha, lw=0,
                            label=f"{100 * levels[lo]:g}-{100 * levels[hi]:g} %" if named else None)
        ax.plot(loads, np.median(values, axis=0), color="C0", lw=1.5, label="median")
        ax.plot(loads, np.asarray(getattr(nominal.primary, name), float), color="k", lw=1, ls="--",
                label="the study's finger")
        ax.set_xscale("log")
        ax.set_xlabel("normal load F (N)")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    crit = np.asarray(result.critical_load, float)
    finite = crit[np.isfinite(crit) & (crit > 0)]
    ax = axes[2]
    ax.axvspan(float(loads.min()), float(loads.max()), color="0.9", lw=0, zorder=0,
               label=f"loads predicted ({loads.min():.3g}-{loads.max():.3g} N)")
    if finite.size:
        bins = np.geomspace(finite.min(), finite.max() * 1.0001, 25) if finite.max() > finite.min() else 10
        counts, _, _ = ax.hist(finite, bins=bins, color="C1", label="members")
        ax.set_ylim(0, 1.55 * float(np.max(counts)))  # room for the legend above the bars
    ax.set_xscale("log")
    own = nominal.critical_load.get(nominal.primary_model)
    if own is not None and np.isfinite(own) and own > 0:
        ax.axvline(own, color="k", lw=1, ls="--", label=f"the study's finger ({own:.3g} N)")
    ax.set_xlabel("critical load (N)")
    ax.set_ylabel("members")
    ax.set_title(critical_title(crit), fontsize=9)
    ax.legend(fontsize=8, loc="upper left", framealpha=0.85)
    fig.suptitle(f"population {result.population.name!r}: {len(result.members)} fingers")
    return fig


def critical_title(critical_load: Any) -> str:
    """The critical-load histogram's title: how many members it cannot show, and why. A member
    never reaches the transition (critical load infinite), or is past it at zero load (0: adhesion
    alone pulls its skin onto the base); neither has a place on a log axis."""
    crit = np.asarray(critical_load, float)
    never = int(np.count_nonzero(np.isinf(crit) | np.isnan(crit)))
    at_zero = int(np.count_nonzero(crit <= 0))
    title = f"{never} of {crit.size} never reach the transition"
    return title + (f", {at_zero} are past it at zero load" if at_zero else "")
