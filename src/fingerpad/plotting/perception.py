"""The figure of ``fingerpad compare`` (and ``predict --perception``): friction of both surfaces,
who tells them apart, and the vibration bands against the receptor channels (docs/perception.md).

It draws from the comparison's plain data (``Comparison.as_dict()``), so it knows no model.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["figure_comparison"]

#: Channel shading of the vibration panel: (low Hz, high Hz, colour).
_CHANNEL_COLOURS = {"slow": "0.93", "NP I": "#e8f0fb", "P": "#fdf0e0", "above P": "0.93"}


def figure_comparison(doc: Mapping[str, Any]) -> Any:
    """Three panels: mu of A and B against the load (median and 5-95 % band over the fingers);
    the fraction of fingers telling them apart and the median P; the vibration frequencies of
    each surface and direction over the stroke speeds (bars on a log frequency axis over the
    channels, the Pacinian optimum 250-300 Hz marked)."""
    from matplotlib.figure import Figure

    loads = np.asarray(doc["loads"], float)
    a, b = doc["a"]["label"], doc["b"]["label"]
    fig = Figure(figsize=(12, 3.8))
    fig.subplots_adjust(left=0.06, right=0.99, bottom=0.15, top=0.84, wspace=0.3)
    ax_mu, ax_p, ax_v = fig.subplots(1, 3)
    many = np.asarray(doc["members"]["mu_a"]).shape[0] > 1
    for i, label in enumerate((a, b)):
        band = doc["mu"][label]
        if many:
            ax_mu.fill_between(loads, band["0.05"], band["0.95"], color=f"C{i}", alpha=0.2, lw=0)
        ax_mu.plot(loads, band["0.5"], color=f"C{i}", lw=1.5, marker="o", ms=3,
                   label=label + (" (median, 5-95 %)" if many else ""))
    for ax in (ax_mu, ax_p):
        if loads.size > 1 and loads.max() / loads.min() > 3:
            from matplotlib.ticker import FuncFormatter

            ax.set_xscale("log")
            ax.xaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
            ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
            if loads.size <= 8:  # the loads themselves, not decades
                ax.set_xticks(loads)
        ax.set_xlabel("normal load F (N)")
    ax_mu.set_ylabel("μ")
    ax_mu.legend(fontsize=8)
    keys = list(doc["discrimination"]["fraction"])
    frac = np.array([doc["discrimination"]["fraction"][k] for k in keys], float)
    med = np.array([doc["discrimination"]["p_correct_median"][k] for k in keys], float)
    ax_p.plot(loads, frac, color="k", marker="o", ms=3, label="fraction telling them apart (P ≥ 0.75)")
    ax_p.plot(loads, med, color="C3", ls="--", marker="s", ms=3, label="median P (forced choice)")
    ax_p.axhline(0.5, color="0.6", lw=0.8, ls=":")
    ax_p.set_ylim(-0.02, 1.02)
    ax_p.set_ylabel("fraction / probability")
    ax_p.legend(fontsize=8, loc="lower left")
    _vibration_panel(ax_v, doc)
    w = doc["weber_fraction"]
    if w.get("drawn"):  # each finger's own W: its median [5-95 %]
        ws = np.asarray(doc["members"]["weber_fraction"], float)
        wtext = f"each finger's own W, median {np.median(ws):.2f} [{np.quantile(ws, 0.05):.2f}-" \
                f"{np.quantile(ws, 0.95):.2f}]"
    else:
        wtext = f"W = {w['value']:g}"
    pop = doc.get("population")
    who = f"{pop['size']} fingers of {pop['name']!r}" if pop else "the study's finger"
    fig.suptitle(f"{a} against {b}: {who}, {wtext}", fontsize=11)
    return fig


def _vibration_panel(ax: Any, doc: Mapping[str, Any]) -> None:
    entries = [e for e in doc["vibration"] if e["frequency_hz"] and e["frequency_hz"] > 0]
    rows: dict[tuple[str, float, int], list[float]] = {}
    for e in entries:
        rows.setdefault((e["texture"], e["direction_deg"], e["harmonic"]), []).append(float(e["frequency_hz"]))
    fmin = min([min(v) for v in rows.values()] + [5.0]) / 2
    fmax = max([max(v) for v in rows.values()] + [1000.0]) * 2
    for c in doc["channels"]:
        lo, hi = max(c["low_hz"], fmin), min(c["high_hz"], fmax)
        if hi > lo:
            ax.axvspan(lo, hi, color=_CHANNEL_COLOURS.get(c["channel"], "0.95"), lw=0)
            ax.text(math.sqrt(lo * hi), 1.0, c["channel"], transform=ax.get_xaxis_transform(), ha="center",
                    va="bottom", fontsize=8)
    ax.axvspan(250, 300, color="#f5c28a", lw=0)
    labels = []
    for y, ((tex, direction, harmonic), freqs) in enumerate(sorted(rows.items())):
        colour = "C0" if tex == doc["a"]["label"] else "C1"
        ax.plot([min(freqs), max(freqs)], [y, y], color=colour, lw=6, solid_capstyle="butt")
        labels.append(f"{tex} {direction:g}°" + (f" ×{harmonic}" if harmonic != 1 else ""))
    ax.set_xscale("log")
    ax.set_xlim(fmin, fmax)
    ax.set_yticks(range(len(labels)))
    ax.set_yticklabels(labels, fontsize=8)
    ax.set_ylim(-0.8, max(len(labels), 1) - 0.2)
    speeds = doc["speeds"]
    span = f"{1e3 * min(speeds):g}-{1e3 * max(speeds):g} mm/s" if len(speeds) > 1 else f"{1e3 * speeds[0]:g} mm/s"
    ax.set_xlabel(f"vibration frequency f = v/λ (Hz) at {span}")
    if not labels:
        ax.text(0.5, 0.5, "no periodic texture: no vibration", transform=ax.transAxes, ha="center", fontsize=9)
