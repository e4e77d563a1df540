"""Figures of a prediction: areas, friction and contact zones against load (matplotlib, Agg).

Fixed margins instead of a layout engine: a layout engine costs seconds per figure.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from ..study.run import Prediction

__all__ = ["STATE_FILL", "figure_areas", "figure_friction", "figure_zones"]

STATE_FILL = {"asperity": "#dbe9f6", "transition": "#fde3c8", "full": "#f7c9c9"}


def _state_ranges(pred: "Prediction") -> list[tuple[str, float, float]]:
    """Load intervals of the centre states within the plotted load range."""
    lo, hi = float(pred.primary.load.min()), float(pred.primary.load.max())
    fc = pred.critical_load[pred.primary_model]
    ff = pred.full_contact_load.get(pred.primary_model)
    fc = 0.0 if pred.cell is not None and pred.cell.flat else fc
    edges = [("asperity", 0.0), ("transition", fc if fc is not None and math.isfinite(fc) else math.inf),
             ("full", ff if ff is not None and math.isfinite(ff) else math.inf)]
    out = []
    for k, (state, start) in enumerate(edges):
        end = edges[k + 1][1] if k + 1 < len(edges) else math.inf
        a, b = max(start, lo), min(end, hi)
        if b > a:
            out.append((state, a, b))
    return out


def _shade(ax: Any, pred: Prediction) -> None:
    for state, a, b in _state_ranges(pred):
        ax.axvspan(a, b, color=STATE_FILL[state], alpha=0.8, lw=0, zorder=0, label=f"centre: {state}")


def _mark_critical(ax: Any, pred: Prediction) -> None:
    lo, hi = float(pred.primary.load.min()), float(pred.primary.load.max())
    for model, style in (("bem", "-"), ("hertz", "--")):
        f = pred.critical_load.get(model)
        if f is not None and math.isfinite(f) and lo <= f <= hi:
            ax.axvline(f, color="k", ls=style, lw=0.9, label=f"F_crit {model} = {f:.3g} N")


def _load_axis(ax: Any, f: np.ndarray) -> None:
    """Log load axis (for ranges over 5x) with plain tick labels at 1-2-5 steps."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    lo, hi = float(f.min()), float(f.max())
    if hi <= lo:  # a single load: a window around it, so the markers show
        ax.set_xlim(0.5 * lo, 1.5 * hi)
        return
    ax.set_xlim(lo, hi)
    if not (lo > 0 and hi / lo > 5):
        return
    ax.set_xscale("log")
    nice = [m * 10.0**k for k in range(-4, 5) for m in (1, 2, 5)]
    ticks = [t for t in nice if lo * (1 - 1e-9) <= t <= hi * (1 + 1e-9)]
    if ticks and hi / ticks[-1] > 1.5:
        ticks.append(hi)
    if ticks and ticks[0] / lo > 1.5:
        ticks.insert(0, lo)
    if len(ticks) >= 2:
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_formatter(NullFormatter())


def _line(f: np.ndarray, fmt: str) -> str:
    """A matplotlib format string, with markers when the loads are too few to draw a curve."""
    return fmt + ("o" if f.size < 4 else "")


def figure_areas(pred: "Prediction"):
    from matplotlib.figure import Figure

    cur = pred.primary
    f = cur.load
    fig = Figure(figsize=(7.0, 5.0))
    fig.subplots_adjust(left=0.12, right=0.97, bottom=0.11, top=0.9)
    ax = fig.subplots()
    ax.plot(f, cur.gross_area * 1e6, _line(f, "k-"), label="gross A_g")
    ax.plot(f, cur.ridge_area * 1e6, _line(f, "-"), color="tab:green", label="ridge A_fr")
    ax.plot(f, cur.real_area * 1e6, _line(f, "-"), color="tab:red", lw=2, label=f"real A_re ({pred.primary_model})")
    if pred.bem is not None and pred.hertz is not None:
        ax.plot(f, pred.hertz.real_area * 1e6, _line(f, "--"), color="tab:red", label="real A_re (hertz)")
    _mark_critical(ax, pred)
    _load_axis(ax, f)
    ax.set_yscale("log")
    ax.set_xlabel("normal load F (N)")
    ax.set_ylabel("contact area (mm²)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small", loc="lower right")
    ax.set_title(f"Contact areas: {pred.texture.name}, E1* = {pred.reduced_modulus / 1e3:.4g} kPa, "
                 f"finger {pred.study.finger.name}", fontsize="medium")
    return fig


def figure_friction(pred: "Prediction"):
    from matplotlib.figure import Figure

    cur = pred.primary
    f = cur.load
    d = pred.directional
    panels = 3 if d is not None else 2
    fig = Figure(figsize=(6.0 * panels, 4.8))
    fig.subplots_adjust(left=0.065 if panels == 2 else 0.045, right=0.985, bottom=0.12, top=0.88, wspace=0.22)
    axes = fig.subplots(1, panels)
    ax_mu, ax_n = axes[0], axes[1]
    for ax in axes:
        _shade(ax, pred)
        _mark_critical(ax, pred)
    if d is not None:
        ax_d = axes[2]
        ax_mu.plot(f, d["mu_perpendicular"], _line(f, ":"), color="tab:purple",
                   label=f"across the long axis ({d['perpendicular_direction']:.0f}°)")
        ax_mu.plot(f, d["mu_parallel"], _line(f, "-."), color="tab:purple",
                   label=f"along the long axis ({d['parallel_direction']:.0f}°)")
        ax_d.plot(f, d["mu_perpendicular_over_parallel"], _line(f, "-"), color="tab:purple", lw=2)
        held = np.asarray(d.get("gain_held_parallel", ()), bool) | np.asarray(d.get("gain_held_perpendicular", ()), bool)
        if held.size == np.size(f) and held.any():  # the gain is held there, not computed
            ax_d.plot(np.asarray(f)[held], np.asarray(d["mu_perpendicular_over_parallel"])[held], "o", mfc="none",
                      color="tab:red", label="gain held (past the shear its ramps reached)")
        ax_d.axhline(1.0, color="k", lw=0.8)
        ax_d.set_ylabel("μ_perpendicular / μ_parallel (-)")
        ax_d.set_title("directional friction (compliant asperities)", fontsize="medium")
    label = f"texture ({pred.primary_model})" if d is None else f"texture, sliding at {d['direction']:.0f}°"
    ax_mu.plot(f, cur.mu, _line(f, "-"), color="tab:red", lw=2, label=label)
    if cur.mu_ref is not None:
        ax_mu.plot(f, cur.mu_ref, _line(f, "-"), color="k", label="flat reference")
    if cur.mu_normalised is not None:
        ax_n.plot(f, cur.mu_normalised, _line(f, "-"), color="tab:red", lw=2, label=pred.primary_model)
    if pred.bem is not None and pred.hertz is not None:
        ax_mu.plot(f, pred.hertz.mu, _line(f, "--"), color="tab:red", label="texture (hertz)")
        if pred.hertz.mu_normalised is not None:
            ax_n.plot(f, pred.hertz.mu_normalised, _line(f, "--"), color="tab:red", label="hertz")
    ax_mu.set_ylabel("friction coefficient μ (-)")
    # Not the area ratio A_re,tex/A_re,ref: the alpha*p term and the hysteresis count too (Eqs. 2.1-2.4).
    ax_n.set_ylabel("μ_texture / μ_flat reference (-)")
    ax_n.set_ylim(0, max(1.05, float(np.nanmax(cur.mu_normalised)) * 1.05 if cur.mu_normalised is not None else 1.05))
    ax_mu.set_title("friction against load (shaded: contact state at the pad centre)", fontsize="medium")
    ax_n.set_title("normalised friction", fontsize="medium")
    for ax in axes:
        _load_axis(ax, f)
        ax.set_xlabel("normal load F (N)")
        ax.grid(True, which="both", alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize="small")
    fig.suptitle(f"{pred.texture.name} on finger {pred.study.finger.name}, E1* = {pred.reduced_modulus / 1e3:.4g} kPa")
    return fig


def figure_zones(pred: "Prediction"):
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    from ..macro.pressure import pad_pressure
    from .solution import STATE_COLOURS

    z = pred.zones
    a, at, af = z["ridge_radius"], z["transition_radius"], z["full_contact_radius"]
    fig = Figure(figsize=(11.5, 5.0))
    fig.subplots_adjust(left=0.06, right=0.935, bottom=0.12, top=0.86, wspace=0.22)
    ax_map, ax_r = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1, 1.3]})
    from matplotlib.colors import to_rgb

    s = 1e3
    for radius, inner, state in ((a, at, "asperity"), (at, af, "transition"), (af, 0.0, "full")):
        if radius > 0:
            pale = tuple(1.0 - 0.55 * (1.0 - c) for c in to_rgb(STATE_COLOURS[state]))
            span = f"{inner * s:.3g} < r < {radius * s:.3g} mm" if inner > 0 else f"r < {radius * s:.3g} mm"
            ax_map.add_patch(Circle((0, 0), radius * s, color=pale, lw=0, label=f"{state}: {span}"))
            ax_map.add_patch(Circle((0, 0), radius * s, fill=False, color="k", lw=0.8))
    ht = z.get("hertz_transition_radius")
    if ht:
        ax_map.add_patch(Circle((0, 0), ht * s, fill=False, color="k", ls="--", lw=1.2,
                                label=f"hertz transition: r < {ht * s:.3g} mm"))
    for radius, ang in ((a, 60), (at, 30), (af, 0)):
        if radius > 0:
            t = math.radians(ang)
            ax_map.annotate(f"{radius * s:.3g} mm", (radius * s * math.cos(t), radius * s * math.sin(t)),
                            xytext=(4, 4), textcoords="offset points", fontsize="small")
    lim = 1.15 * a * s
    ax_map.set_xlim(-lim, lim)
    ax_map.set_ylim(-lim, lim)
    ax_map.set_aspect("equal")
    ax_map.set_xlabel("x (mm)")
    ax_map.set_ylabel("y (mm)")
    ax_map.legend(fontsize="small", loc="upper left")
    ax_map.set_title(f"ridge contact disc at F = {z['load']:.3g} N", fontsize="medium")

    r = np.linspace(0, a, 300)
    p = np.asarray(pad_pressure(r, z["load"], z["ridge_area"]), float)
    cell = pred.primary_cell
    psi = np.asarray(cell.contact_fraction(p), float)
    for lo, hi, state in ((at, a, "asperity"), (af, at, "transition"), (0, af, "full")):
        if hi > lo:
            ax_r.axvspan(lo * s, hi * s, color=STATE_FILL[state], alpha=0.8, lw=0)
    ax_r.plot(r * s, p / 1e3, "k-", label="pad pressure p(r) (Eq. 3.7)")
    ax_r.set_xlabel("radius r (mm)")
    ax_r.set_ylabel("pressure (kPa)")
    ax2 = ax_r.twinx()
    ax2.plot(r * s, psi, "-", color="tab:red", label=f"ψ(p(r)) ({pred.primary_model})")
    ax2.set_ylim(0, 1.02)
    ax2.set_ylabel("local real-area fraction ψ (-)")
    ax_r.set_xlim(0, a * s)
    ax_r.set_ylim(bottom=0)
    h1, l1 = ax_r.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax_r.legend(h1 + h2, l1 + l2, fontsize="small", loc="lower left")
    ax_r.set_title(f"A_re/A_fr = {z['area_ratio']:.3g}, centre: {z['contact_state']}", fontsize="medium")
    fig.suptitle(f"Contact zones of {pred.texture.name} ({pred.primary_model}), finger {pred.study.finger.name}")
    return fig
