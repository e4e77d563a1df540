"""Figures of unit-cell solutions (matplotlib, Agg backend, files written atomically).

:func:`plot_solution` draws, in one PNG:

1. the contact pressure map of one solution (kPa),
2. its contact map (texture heights in grey, contact in colour),
3. psi(p): the real-to-nominal contact area ratio against the mean pressure, points coloured by
   contact state (asperity / transition / full); log pressure axis when the pressures span more
   than a decade.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FingerpadError
from ..io import atomic_write

#: Colours of the contact states in psi(p) plots.
STATE_COLOURS = {"asperity": "tab:blue", "transition": "tab:orange", "full": "tab:red"}


def _as_results(results: Any) -> list[Any]:
    """Accept one ContactResult, a sequence of them, or a LoadCurve."""
    if hasattr(results, "pressure") and hasattr(results, "texture"):
        return [results]
    if hasattr(results, "results") and not isinstance(results, (list, tuple)):
        return list(results.results)
    out = list(results)
    if not out:
        raise FingerpadError("nothing to plot: no results")
    return out


def _length_scale(size: float) -> tuple[float, str]:
    if size >= 1e-3:
        return 1e3, "mm"
    return 1e6, "µm"


def _pressure_scale(pmax: float) -> tuple[float, str]:
    if pmax >= 1e6:
        return 1e-6, "MPa"
    if pmax >= 1e3:
        return 1e-3, "kPa"
    return 1.0, "Pa"


def figure_solution(results: Any, *, index: int = -1, title: str | None = None):
    """Build the figure of :func:`plot_solution` and return it (caller closes it)."""
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure

    res = _as_results(results)
    try:
        sel = res[index]
    except IndexError:
        raise FingerpadError(f"plot index {index} out of range for {len(res)} results") from None
    tex = sel.texture
    lx, ly = tex.size
    ls, lunit = _length_scale(max(lx, ly))
    extent = (0.0, lx * ls, 0.0, ly * ls)  # x along the horizontal axis
    pressure = np.asarray(sel.pressure, float)
    ps, punit = _pressure_scale(float(np.max(pressure)) if pressure.size else 0.0)

    # Fixed margins: a layout engine would cost seconds per figure (tick-label bounding boxes).
    fig = Figure(figsize=(16.0, 4.8))
    fig.subplots_adjust(left=0.045, right=0.985, bottom=0.12, top=0.84, wspace=0.42)
    ax_p, ax_c, ax_psi = fig.subplots(1, 3)

    # 1. pressure map (heights[i, j] at x_i, y_j -> transpose so x is horizontal)
    im = ax_p.imshow(pressure.T * ps, origin="lower", extent=extent, cmap="viridis", interpolation="nearest")
    fig.colorbar(im, ax=ax_p, label=f"contact pressure ({punit})")
    ax_p.set_title(f"pressure at p = {sel.mean_pressure * _pressure_scale(sel.mean_pressure)[0]:.3g} "
                   f"{_pressure_scale(sel.mean_pressure)[1]}")

    # 2. contact map over the texture
    heights = np.asarray(tex.heights, float)
    hs = 1e6
    im_h = ax_c.imshow(heights.T * hs, origin="lower", extent=extent, cmap="Greys_r", interpolation="nearest")
    fig.colorbar(im_h, ax=ax_c, label="texture height (µm)")
    # with adhesion a contact is a closed gap (it may carry tension): the result's own mask
    closed = np.asarray(sel.contact) if getattr(sel, "adhesion", None) is not None else pressure > 0
    contact = np.ma.masked_where(~closed, np.ones_like(pressure))
    ax_c.imshow(contact.T, origin="lower", extent=extent, cmap=ListedColormap(["tab:red"]), alpha=0.6,
                interpolation="nearest", vmin=0, vmax=1)
    ax_c.set_title(f"contact in red ({sel.contact_state}, psi = {sel.contact_fraction:.3g})")

    for ax in (ax_p, ax_c):
        ax.set_xlabel(f"x ({lunit})")
        ax.set_ylabel(f"y ({lunit})")
        ax.set_aspect("equal")

    # 3. psi(p)
    mp = np.array([float(r.mean_pressure) for r in res])
    psi = np.array([float(r.contact_fraction) for r in res])
    states = [str(r.contact_state) for r in res]
    order = np.argsort(mp)
    positive = mp[mp > 0]
    log_x = positive.size == mp.size and positive.size > 1 and positive.max() / positive.min() > 10
    xs, xunit = (1.0, "Pa") if log_x else _pressure_scale(float(mp.max()) if mp.size else 0.0)
    ax_psi.plot(mp[order] * xs, psi[order], "-", color="0.6", lw=1, zorder=1)
    for state, colour in STATE_COLOURS.items():
        m = np.array([s == state for s in states])
        if m.any():
            ax_psi.scatter(mp[m] * xs, psi[m], color=colour, label=state, zorder=2, s=24)
    other = np.array([s not in STATE_COLOURS for s in states])
    if other.any():
        ax_psi.scatter(mp[other] * xs, psi[other], color="k", label="other", zorder=2, s=24)
    unconverged = np.array([not bool(getattr(r, "converged", True)) for r in res])
    if unconverged.any():
        ax_psi.scatter(mp[unconverged] * xs, psi[unconverged], marker="x", color="k", s=60,
                       label="not converged", zorder=3)
    ax_psi.scatter([sel.mean_pressure * xs], [sel.contact_fraction], facecolors="none", edgecolors="k", s=90,
                   zorder=3, label="shown left")
    if log_x:
        ax_psi.set_xscale("log")
    ax_psi.set_xlabel(f"mean pressure p ({xunit})")
    ax_psi.set_ylabel("contact fraction psi = A_re / A (-)")
    ax_psi.set_ylim(-0.02, 1.02)
    ax_psi.grid(True, which="both", alpha=0.3)
    ax_psi.legend(loc="lower right", fontsize="small")
    ax_psi.set_title("real contact area ratio psi(p)")

    name = getattr(tex, "name", "")
    fig.suptitle(title or f"texture {name}: {lx * ls:.4g} x {ly * ls:.4g} {lunit} cell, "
                          f"E* = {sel.modulus / 1e6:.3g} MPa")
    return fig


def plot_solution(results: Any, path: str | os.PathLike[str], *, index: int = -1, title: str | None = None,
                  dpi: int = 120, fmt: str = "png") -> Path:
    """Write the pressure map, contact map (of ``results[index]``, default the last/highest
    pressure) and psi(p) of ``results`` (one ContactResult, a list, or a LoadCurve) to an image
    (``fmt``: png, svg or pdf).

    The file is written atomically; returns its path.
    """
    fig = figure_solution(results, index=index, title=title)
    return atomic_write(path, lambda tmp: fig.savefig(tmp, format=fmt, dpi=dpi))


def plot_load_curves(curves: Sequence[Any], labels: Sequence[str], path: str | os.PathLike[str]) -> Path:
    """psi(p) of several load curves on one axis (log pressure axis when spanning > 1 decade)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6, 4.5))
    fig.subplots_adjust(left=0.13, right=0.97, bottom=0.12, top=0.95)
    ax = fig.subplots()
    allp = []
    for curve, label in zip(curves, labels, strict=True):
        mp = np.asarray(curve.mean_pressure, float)
        allp.append(mp)
        order = np.argsort(mp)
        ax.plot(mp[order], np.asarray(curve.contact_fraction, float)[order], "o-", ms=3, label=label)
    p = np.concatenate(allp) if allp else np.array([])
    if p.size and p.min() > 0 and p.max() / p.min() > 10:
        ax.set_xscale("log")
    ax.set_xlabel("mean pressure p (Pa)")
    ax.set_ylabel("contact fraction psi (-)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    return atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=120))
