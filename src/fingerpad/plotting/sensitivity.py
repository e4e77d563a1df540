"""The sensitivity figure of ``predict --population ... --sensitivity``: first-order and total
Sobol indices per parameter, as bars with their confidence half-widths (docs/population.md)."""

from __future__ import annotations

from typing import Any

import numpy as np

#: The result these figures read (:class:`~fingerpad.population.sobol.SensitivityResult`), named
#: for the signatures only: plotting imports nothing of the layers above it, not even for type
#: checking.
SensitivityResult = Any

__all__ = ["figure_sensitivity", "shown_loads"]


def shown_loads(loads: Any) -> list[int]:
    """Indices of the loads shown of the per-load indices: the lightest, the one nearest 1 N
    and the heaviest (fewer when they coincide)."""
    loads = np.asarray(loads, float)
    picks = [0, int(np.argmin(np.abs(np.log(loads)))), loads.size - 1]
    return sorted(set(picks))


def figure_sensitivity(result: SensitivityResult) -> Any:
    """Bars of the first-order (dark) and total (light) indices of each parameter, with their
    confidence half-widths: mu/mu_ref at the lightest, ~1 N and heaviest loads and the critical
    load's logarithm (one panel each)."""
    from matplotlib.figure import Figure

    panels = [("mu_normalised", j, f"μ/μ_ref at {result.loads[j]:.3g} N") for j in shown_loads(result.loads)]
    panels.append(("log10_critical_load", None, "log10 critical load"))
    fig = Figure(figsize=(3.0 * len(panels) + 1.5, 3.8), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(panels), sharey=True))
    names = result.parameters
    y = np.arange(len(names))
    for ax, (quantity, j, title) in zip(axes, panels, strict=True):
        table = result.indices[quantity]

        def column(key: str, table: Any = table, j: Any = j) -> np.ndarray:
            return np.array([float(np.atleast_1d(table[p][key])[0 if j is None else j]) for p in names])

        ax.barh(y + 0.2, column("first"), height=0.38, xerr=column("first_conf"), color="C0", label="first order")
        ax.barh(y - 0.2, column("total"), height=0.38, xerr=column("total_conf"), color="C0", alpha=0.4,
                label="total")
        ax.set_title(title, fontsize=9)
        ax.set_xlim(-0.05, 1.05)
        ax.set_xlabel("Sobol index")
    axes[0].set_yticks(y, names)
    axes[0].invert_yaxis()
    axes[0].legend(fontsize=8, loc="lower right")
    fig.suptitle(f"which parameter drives the spread: N = {result.base_samples}, {result.evaluations} fingers, "
                 f"{100 * result.confidence:g} % bootstrap intervals", fontsize=10)
    return fig
