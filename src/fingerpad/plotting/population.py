"""The population figure of ``predict --population``: bands of A_re/A_fr and mu/mu_ref against the
load, and the distribution of the critical load (docs/population.md)."""

from __future__ import annotations

from typing import Any

import numpy as np

#: The result these figures read (:class:`~fingerpad.population.run.PopulationResult`), named for
#: the signatures only: plotting imports nothing of the layers above it, not even for type
#: checking.
PopulationResult = Any

__all__ = ["figure_population"]


def figure_population(result: PopulationResult) -> Any:
    """Shaded bands (the outer and inner pairs of the reported quantiles, e.g. 5-95 % and
    25-75 %) and the median of A_re/A_fr and mu/mu_ref against the load (log axis), and a
    histogram of the members' critical loads (N, log bins; members that never reach the
    transition are counted in the title)."""
    from matplotlib.figure import Figure

    loads = np.asarray(result.nominal.study.loads, float)
    levels = sorted(result.quantile_levels)
    # fixed margins, not the constrained layout: its text-extent passes over the log axes' tick
    # labels took two thirds of the figure's time (0.2 s of a population prediction)
    fig = Figure(figsize=(11, 3.6))
    fig.subplots_adjust(left=0.06, right=0.99, bottom=0.14, top=0.86, wspace=0.28)
    axes = fig.subplots(1, 3)
    for ax, name, label in ((axes[0], "area_ratio", "A_re / A_fr"), (axes[1], "mu_normalised", "μ / μ_ref")):
        values = result.values(name)
        table = np.quantile(values, levels, axis=0)
        pairs = [(i, len(levels) - 1 - i) for i in range(len(levels) // 2)]
        for depth, (lo, hi) in enumerate(pairs):
            ax.fill_between(loads, table[lo], table[hi], color="C0", alpha=0.2 + 0.15 * depth, lw=0,
                            label=f"{100 * levels[lo]:g}-{100 * levels[hi]:g} %")
        ax.plot(loads, np.median(values, axis=0), color="C0", lw=1.5, label="median")
        ax.set_xscale("log")
        ax.set_xlabel("normal load F (N)")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    crit = np.asarray(result.critical_load, float)
    finite = crit[np.isfinite(crit) & (crit > 0)]
    ax = axes[2]
    if finite.size:
        bins = np.geomspace(finite.min(), finite.max() * 1.0001, 25) if finite.max() > finite.min() else 10
        ax.hist(finite, bins=bins, color="C1")
        ax.set_xscale("log")
    ax.set_xlabel("critical load (N)")
    ax.set_ylabel("members")
    ax.set_title(f"{crit.size - finite.size} of {crit.size} never reach the transition", fontsize=9)
    fig.suptitle(f"population {result.population.name!r}: {len(result.members)} fingers")
    return fig
