"""Figures of the deflection model (all matplotlib code of the package's deflection part).

:func:`deflection_figure` draws, for a set of directions: the deformed asperity surface at
several shear levels (one pressure level), the gain ``L(mu)/L(0)`` and the tip deflection against
the shear level at every pressure level. Written atomically as PNG with the Agg canvas.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..micro.deflection.gain import GainCurve


def deflection_figure(curves: list[GainCurve], path: str | os.PathLike[str], pressure_index: int = -1,
                      dpi: int = 120) -> Path:
    """Deformed shapes, gain and tip deflection against shear level, one row per direction.

    Parameters
    ----------
    curves
        Gain curves of one texture (identity curves are drawn as G = 1).
    path
        Output PNG.
    pressure_index
        Which pressure level's shapes to draw (default: the highest).
    """
    from matplotlib.figure import Figure

    from ..io import atomic_write

    rows = max(1, len(curves))
    fig = Figure(figsize=(13, 3.6 * rows), layout="constrained")
    axes = np.atleast_2d(fig.subplots(rows, 3))
    for row, curve in zip(axes, curves):
        ax_shape, ax_gain, ax_tip = row
        title = f"direction {curve.direction_deg:g}°"
        if curve.is_identity or not curve.ramps:
            for ax in row:
                ax.text(0.5, 0.5, f"G = 1: {curve.reason or 'no deflection'}",
                        ha="center", va="center", transform=ax.transAxes, fontsize="small", wrap=True)
            ax_shape.set_title(title)
            continue
        ramp = curve.ramps[pressure_index]
        mu_top = max([float(np.max(np.abs(r.mu))) for r in curve.ramps if r.mu.size] + [0.0])
        n = len(ramp.surfaces)
        picks = sorted(set(np.linspace(0, n - 1, min(n, 5)).astype(int))) if n else []
        cmap = __import__("matplotlib").colormaps["viridis"]
        for k, i in enumerate(picks):
            xs = ramp.surfaces[i] * 1e6
            color = cmap(k / max(1, len(picks) - 1))
            ax_shape.plot(xs[:, 0], xs[:, 1], "-", color=color, lw=1.2, label=f"μ = {abs(ramp.mu[i]):.2f}")
            if i < len(ramp.contact):
                c = ramp.contact[i]
                ax_shape.plot(xs[c, 0], xs[c, 1], "o", color=color, ms=2.5)
        ax_shape.set_aspect("equal")
        ax_shape.set_xlabel("x (µm)")
        ax_shape.set_ylabel("z (µm)")
        ax_shape.set_title(f"{title}: p = {ramp.pressure / 1e3:.3g} kPa (dots: skin contact)")
        ax_shape.legend(fontsize="x-small")
        for r in curve.ramps:
            if r.mu.size == 0:
                continue
            line, = ax_gain.plot(np.abs(r.mu), r.gain, "-", label=f"p = {r.pressure / 1e3:.3g} kPa")
            ax_tip.plot(np.abs(r.mu), r.tip_dx * 1e6, "--", color=line.get_color(), lw=0.8)
            if r.bend_dx.size == r.mu.size:
                ax_tip.plot(np.abs(r.mu), r.bend_dx * 1e6, "-", color=line.get_color())
            if np.isfinite(r.fold_onset_mu):
                ax_gain.axvline(r.fold_onset_mu, color=line.get_color(), ls=":", lw=0.8)
            if r.stopped:
                ax_gain.plot(abs(r.mu[-1]), r.gain[-1], "x", color=line.get_color())
            mu_b, g_b = r.branch()
            if mu_b.size and r.mu_reached < mu_top - 1e-9:  # the table holds the last gain past the reach
                ax_gain.plot([r.mu_reached, mu_top], [g_b[-1], g_b[-1]], ":", color=line.get_color(), lw=1.5)
        ax_gain.axhline(1.0, color="k", lw=0.5)
        ax_gain.set_xlabel("shear level μ (section)")
        ax_gain.set_ylabel("contact length gain L(μ)/L(0)")
        ax_gain.set_title("gain (x: ramp stopped, dotted: held past it; thin: fold-over onset)"
                          + (" INCOMPLETE: time limit" if curve.incomplete else ""), fontsize="small")
        ax_gain.legend(fontsize="x-small")
        ax_tip.set_xlabel("shear level μ (section)")
        ax_tip.set_ylabel("tip displacement (µm)")
        ax_tip.set_title("tip: bending (solid), with base shear (dashed)")
        for ax in (ax_gain, ax_tip):
            ax.grid(True, alpha=0.3)
    return atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi))
