"""The design map figure: mu/mu_ref in colour, critical-load contours, contact-state regions and
the literature markers, on two swept axes (one panel per value of a further axis).

Everything the figure shows comes with the data (the region names in the ``region`` variable's
``flag_meanings``, the literature markers in the ``markers`` attribute): this module decides
only how it is drawn.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

__all__ = ["CRITICAL_CONTOURS", "POPULATION_STYLES", "figure_design_map"]

#: Contour levels of the critical load drawn on the map, N (those inside the data's range).
CRITICAL_CONTOURS = (0.1, 0.5, 1.0, 2.0, 4.0)

#: Line styles of the critical-load contours of a population map: the 10 %, 50 % and 90 % fingers.
POPULATION_STYLES = {"critical_load_q10": "dashed", "critical_load_q50": "solid", "critical_load_q90": "dotted"}

_SCALE = {"length": (1e6, "µm"), "pressure": (1e-3, "kPa"), "angle": (180 / math.pi, "deg")}


def _scaled(values: np.ndarray, kind: str) -> tuple[np.ndarray, str]:
    factor, unit = _SCALE.get(kind, (1.0, ""))
    return np.asarray(values, float) * factor, unit


def figure_design_map(data: Any) -> Any:
    """The figure of :func:`fingerpad.design.designmap.map_data`'s result."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator, ScalarFormatter

    meanings = str(data["region"].attrs.get("flag_meanings", ""))
    regions = dict(enumerate(m.strip() for m in meanings.split(";"))) if meanings else {}
    markers = json.loads(data.attrs["markers"]) if data.attrs.get("markers") else {"lines": [], "bands": []}

    x, y, design = data.attrs["x"], data.attrs["y"], data.attrs["design"]
    population = bool(data.attrs.get("population"))
    panels: list[tuple[str, Any]] = [("", data)]
    if design == "grid":
        others = [d for d in data["mu_rel"].dims if d not in (x, y)]
        if len(others) > 1:
            from ..errors import FingerpadError

            raise FingerpadError(f"more than one further axis ({', '.join(others)}): choose values with "
                                 f"--select NAME=VALUE for all but one")
        if others:
            dim = others[0]
            panels = [(f"{dim} = {_value_text(data[dim], v)}", data.sel({dim: v})) for v in data[dim].values]
    n = len(panels)
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    fig = Figure(figsize=(6.4 * cols + 1.2, 5.0 * rows + 1.0))
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    if population:
        fig.subplots_adjust(bottom=0.11 + 0.5 / (5.0 * rows + 1.0))  # the legend's two rows under the panels
    xs_kind, ys_kind = data.attrs.get("x_kind", ""), data.attrs.get("y_kind", "")
    vmin = float(np.nanmin(data["mu_rel"].values)) if np.isfinite(data["mu_rel"].values).any() else 0.0
    vmax = float(np.nanmax(data["mu_rel"].values)) if np.isfinite(data["mu_rel"].values).any() else 1.0
    mesh = None
    for ax, (title, panel) in zip(axes, panels, strict=False):
        if design == "grid":
            xv, xu = _scaled(panel[x].values, xs_kind)
            yv, yu = _scaled(panel[y].values, ys_kind)
            mu = panel["mu_rel"].transpose(y, x).values
            crit = panel["critical_load"].transpose(y, x).values
            region = panel["region"].transpose(y, x).values
            ax.set_facecolor("0.85")  # points that cannot exist (overlapping asperities) stay grey
            mesh = ax.pcolormesh(xv, yv, mu, shading="nearest", cmap="viridis", vmin=vmin, vmax=vmax)
            if population:
                _population_grid(ax, xv, yv, panel, x, y)
            elif np.isfinite(region).sum() >= 4 and len(xv) > 1 and len(yv) > 1:
                ax.contourf(xv, yv, np.where(np.isfinite(region), region, np.nan), levels=[-0.5, 0.5, 1.5, 2.5],
                            colors="none", hatches=["//", "", ".."])
            good = np.isfinite(crit) & (crit > 0) & (not population)
            if good.sum() >= 4 and len(xv) > 1 and len(yv) > 1:
                levels = [c for c in CRITICAL_CONTOURS if np.nanmin(crit[good]) < c < np.nanmax(crit[good])]
                if levels:
                    cs = ax.contour(xv, yv, np.log10(np.where(good, crit, np.nan)), levels=np.log10(levels),
                                    colors="white", linewidths=1.2, negative_linestyles="solid")
                    ax.clabel(cs, fmt={np.log10(c): f"{c:g} N" for c in levels}, fontsize="small")
        else:
            xv, xu = _scaled(panel[x].values, xs_kind)
            yv, yu = _scaled(panel[y].values, ys_kind)
            mu = panel["mu_rel"].values
            crit = panel["critical_load"].values
            region = panel["region"].values
            ok = np.isfinite(mu)
            ring = (panel["robust_asperity"].values[ok] == 1) if population else (region[ok] == 1)
            mesh = ax.scatter(xv[ok], yv[ok], c=mu[ok], cmap="viridis", vmin=vmin, vmax=vmax, s=36,
                              edgecolors=np.where(ring, "k", "none"))
            if population:
                _population_scatter(ax, xv, yv, panel)
            good = np.isfinite(crit) & (crit > 0) & (not population)
            if good.sum() >= 6:
                levels = [c for c in CRITICAL_CONTOURS if np.nanmin(crit[good]) < c < np.nanmax(crit[good])]
                if levels:
                    cs = ax.tricontour(xv[good], yv[good], np.log10(crit[good]), levels=np.log10(levels),
                                       colors="k", linewidths=1.0, negative_linestyles="solid")
                    ax.clabel(cs, fmt={np.log10(c): f"{c:g} N" for c in levels}, fontsize="small")
        if data.attrs.get("x_log"):
            ax.set_xscale("log")
        if data.attrs.get("y_log"):
            ax.set_yscale("log")
        for axis, values in ((ax.xaxis, xv), (ax.yaxis, yv)):
            finite = np.unique(np.asarray(values)[np.isfinite(values)])
            if design == "grid" and 1 < finite.size <= 12:  # ticks at the swept values, read plainly
                axis.set_major_locator(FixedLocator(finite))
                axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.3g}"))
                axis.set_minor_locator(NullLocator())
            else:
                axis.set_major_formatter(ScalarFormatter())
        if "tell_apart" in panel:
            _tell_apart(ax, xv, yv, panel, x, y, design, population)
        limits = ax.get_xlim(), ax.get_ylim()
        _markers(ax, x, y, xs_kind, ys_kind, markers, limits)
        ax.set_xlim(*limits[0])
        ax.set_ylim(*limits[1])
        ax.set_xlabel(f"{x} ({xu})" if xu else x)
        ax.set_ylabel(f"{y} ({yu})" if yu else y)
        if title:
            ax.set_title(title, fontsize="medium")
    for ax in axes[n:]:
        ax.set_visible(False)
    if mesh is not None:
        cbar = fig.colorbar(mesh, ax=list(axes[:n]), shrink=0.9)
        what = data.attrs.get("quantity_label", "μ/μ_ref")
        extra = " (friction against the flat reference)" if what == "μ/μ_ref" else ""
        # Two lines for a population: on one, the label ran past the colour bar's length and was
        # cut at the figure's edge.
        median = "median over the population of " if population else ""
        sep = "\n" if population and extra else ""
        cbar.set_label(f"{median}{what} at {data.attrs['at']:g} N{sep}{extra.lstrip() if sep else extra}")
    if population:
        _population_legend(fig, axes[:n], data)
        return fig
    legend = "; ".join(f"{'hatched' if k == 0 else 'dotted' if k == 2 else 'plain'}: {v}" for k, v in regions.items())
    tell = (f"; red: the study's finger tells it from {data.attrs['tell_apart']} at {data.attrs['at']:g} N "
            "(P = 0.75)") if data.attrs.get("tell_apart") else ""
    fig.suptitle(f"Design map: critical load (white contours), {data.attrs.get('quantity_label', 'μ/μ_ref')} at "
                 f"{data.attrs['at']:g} N (colour), "
                 f"exploration loads {data.attrs['load_min']:g}-{data.attrs['load_max']:g} N\n{legend}; "
                 f"grey: texture not possible{tell}", fontsize="small", wrap=True)
    return fig


def _value_text(coord: Any, value: Any) -> str:
    kind = coord.attrs.get("kind", "")
    if kind in _SCALE:
        factor, unit = _SCALE[kind]
        return f"{float(value) * factor:.4g} {unit}"
    return str(value)


def _markers(ax: Any, x: str, y: str, x_kind: str, y_kind: str, markers: dict[str, Any],
             limits: tuple[tuple[float, float], tuple[float, float]]) -> None:
    """Literature lines and bands on length axes whose name matches (spacing, height), where
    they fall inside the map."""
    for axis, kind, line, span, (lo, hi) in ((x, x_kind, ax.axvline, ax.axvspan, limits[0]),
                                            (y, y_kind, ax.axhline, ax.axhspan, limits[1])):
        if kind != "length":
            continue
        for fragment, value, label in markers["lines"]:
            if fragment in axis and lo <= value * 1e6 <= hi:
                line(value * 1e6, color="0.2", ls="--", lw=1.0)
                _annotate(ax, axis == x, value * 1e6, label)
        for fragment, low, high, label in markers["bands"]:
            if fragment in axis and low * 1e6 < hi and high * 1e6 > lo:
                span(max(low * 1e6, lo), min(high * 1e6, hi), color="0.5", alpha=0.15, lw=0)
                _annotate(ax, axis == x, max(low * 1e6, lo), label)


def _annotate(ax: Any, vertical: bool, value: float, label: str) -> None:
    if vertical:
        ax.annotate(label, (value, 1.0), xycoords=("data", "axes fraction"), rotation=90, va="top", ha="right",
                    fontsize="x-small", color="0.2")
    else:
        ax.annotate(label, (0.0, value), xycoords=("axes fraction", "data"), va="bottom", ha="left",
                    fontsize="x-small", color="0.2")


def _levels(crits: list[np.ndarray]) -> list[float]:
    """The :data:`CRITICAL_CONTOURS` inside the range of any of ``crits`` (N)."""
    good = np.concatenate([c[np.isfinite(c) & (c > 0)] for c in crits])
    if good.size == 0:
        return []
    return [c for c in CRITICAL_CONTOURS if good.min() < c < good.max()]


#: Who tells a texture from the reference: the contours drawn (fraction of a population, or the
#: study's finger's forced-choice threshold P = 0.75), in red.
TELL_LEVELS = {"population": (0.1, 0.5, 0.9), "finger": (0.75,)}


def _tell_apart(ax: Any, xv: np.ndarray, yv: np.ndarray, panel: Any, x: str, y: str, design: str,
                population: bool) -> None:
    """Red contours of who tells each texture from the reference (docs/perception.md): the
    fraction of a population's fingers (10/50/90 %), or the study's finger's P = 0.75."""
    levels = TELL_LEVELS["population" if population else "finger"]
    fmt = {v: (f"{100 * v:g} % tell apart" if population else "tells apart (P 0.75)") for v in levels}
    if design == "grid":
        values = panel["tell_apart"].transpose(y, x).values
        good = np.isfinite(values)
        if good.sum() >= 4 and len(xv) > 1 and len(yv) > 1:
            inside = [v for v in levels if np.nanmin(values) < v < np.nanmax(values)]
            if inside:
                cs = ax.contour(xv, yv, np.where(good, values, np.nan), levels=inside, colors="red",
                                linewidths=1.3, linestyles="dashdot")
                ax.clabel(cs, fmt={v: fmt[v] for v in inside}, fontsize="x-small")
    else:
        values = panel["tell_apart"].values
        good = np.isfinite(values)
        inside = [v for v in levels if good.any() and np.nanmin(values) < v < np.nanmax(values)]
        if good.sum() >= 6 and inside:
            cs = ax.tricontour(xv[good], yv[good], values[good], levels=inside, colors="red", linewidths=1.2,
                               linestyles="dashdot")
            ax.clabel(cs, fmt={v: fmt[v] for v in inside}, fontsize="x-small")


def _population_grid(ax: Any, xv: np.ndarray, yv: np.ndarray, panel: Any, x: str, y: str) -> None:
    """A population on a grid: the critical-load contours of the 10/50/90 % fingers and the
    region where >= 90 % stay in asperity contact over the range (hatched, outlined)."""
    if len(xv) < 2 or len(yv) < 2:
        return
    robust = panel["robust_asperity"].transpose(y, x).values
    if np.isfinite(robust).sum() >= 4 and np.nanmax(robust) == 1:
        ax.contourf(xv, yv, np.where(np.isfinite(robust), robust, np.nan), levels=[0.5, 1.5], colors="none",
                    hatches=["xx"])
        ax.contour(xv, yv, np.where(np.isfinite(robust), robust, 0.0), levels=[0.5], colors="k", linewidths=1.6)
    crits = {name: panel[name].transpose(y, x).values for name in POPULATION_STYLES}
    levels = _levels(list(crits.values()))
    for name, style in POPULATION_STYLES.items():
        crit = crits[name]
        good = np.isfinite(crit) & (crit > 0)
        if good.sum() >= 4 and levels:
            cs = ax.contour(xv, yv, np.log10(np.where(good, crit, np.nan)), levels=np.log10(levels), colors="white",
                            linewidths=1.2, linestyles=style)
            if style == "solid":
                _spread_labels(ax, cs, levels)


def _spread_labels(ax: Any, cs: Any, levels: list[float]) -> None:
    """Label each contour of ``cs`` (levels in N, drawn as log10) once, where its label lies
    farthest from those placed before (in the axes' own fraction, so both axes count alike):
    matplotlib's own placement put the labels of neighbouring levels on top of one another where
    the contours crowd (the population map's 10/50/90 % lines)."""
    to_axes = ax.transData + ax.transAxes.inverted()
    placed: list[np.ndarray] = []
    manual = []
    for level, segments in zip(cs.levels, cs.allsegs, strict=True):
        points = np.concatenate([s for s in segments if len(s)]) if any(len(s) for s in segments) else None
        if points is None:
            continue
        frac = to_axes.transform(points)
        inside = np.all((frac > 0.06) & (frac < 0.94), axis=1)  # not on the frame, not half cut
        if inside.any():
            points, frac = points[inside], frac[inside]
        if placed:
            gap = np.min(np.linalg.norm(frac[:, None, :] - np.array(placed)[None, :, :], axis=2), axis=1)
            i = int(np.argmax(gap))
        else:
            i = len(points) // 2
        placed.append(frac[i])
        manual.append(tuple(points[i]))
    if manual:
        ax.clabel(cs, fmt={lv: f"{10 ** lv:g} N" for lv in cs.levels}, fontsize="small", manual=manual)


def _population_scatter(ax: Any, xv: np.ndarray, yv: np.ndarray, panel: Any) -> None:
    """A population on scattered points: the 10/50/90 % critical-load contours."""
    crits = {name: panel[name].values for name in POPULATION_STYLES}
    levels = _levels(list(crits.values()))
    for name, style in POPULATION_STYLES.items():
        crit = crits[name]
        good = np.isfinite(crit) & (crit > 0)
        if good.sum() >= 6 and levels:
            cs = ax.tricontour(xv[good], yv[good], np.log10(crit[good]), levels=np.log10(levels), colors="k",
                               linewidths=1.0, linestyles=style)
            if style == "solid":
                _spread_labels(ax, cs, levels)


def _population_legend(fig: Any, axes: Any, data: Any) -> None:
    """Legend and title of a population map (units in every label)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    lo, hi = data.attrs["load_min"], data.attrs["load_max"]
    share = 100 * float(data.attrs.get("coverage", 0.9))
    colour = "white" if data.attrs["design"] == "grid" else "k"
    handles = [Line2D([], [], color=colour, linestyle=style, label=f"critical load (N), {q} % finger")
               for q, style in zip((10, 50, 90), POPULATION_STYLES.values(), strict=True)]
    if data.attrs.get("tell_apart"):
        handles.append(Line2D([], [], color="red", linestyle="dashdot",
                              label=f"fingers telling it from {data.attrs['tell_apart']} at {data.attrs['at']:g} N"))
    region = f"asperity contact over {lo:g}-{hi:g} N for >= {share:g} % of fingers"
    robust = np.asarray(data["robust_asperity"].values)
    if not np.any(robust == 1):  # said, not drawn: the legend lists only what the map shows
        handles.append(Line2D([], [], linestyle="none", label=f"no texture here keeps {region.replace('asperity', 'its')}"
                              .replace("keeps its contact", "keeps asperity contact")))
    elif data.attrs["design"] == "grid":
        handles.append(Patch(facecolor="none", edgecolor="k", hatch="xx", label=region))
    else:  # scattered points: ringed in black
        handles.append(Line2D([], [], linestyle="none", marker="o", markerfacecolor="0.8", markeredgecolor="k",
                              label=region))
    # below the panels (room made in figure_design_map), not over them: it hid a corner of cells
    fig.legend(handles=handles, loc="lower center", ncol=2, fontsize="x-small", facecolor="0.6", framealpha=0.8)
    fig.suptitle(f"Design map for a population, {data.attrs['population']}: median "
                 f"{data.attrs.get('quantity_label', 'μ/μ_ref')} at {data.attrs['at']:g} N (colour), critical loads "
                 f"of the 10/50/90 % fingers (contours, N), exploration loads {lo:g}-{hi:g} N; "
                 f"grey: texture not possible", fontsize="small", wrap=True)
