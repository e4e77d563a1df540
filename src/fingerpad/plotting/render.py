"""Drawing plot specifications with matplotlib (object API, Agg canvas; fixed margins).

:func:`figure` draws a :class:`~.specs.FigureSpec` (the PNGs of ``fingerpad predict``);
:func:`spec_image` gives PNG/SVG bytes of a panel or a figure (the explorer's image downloads);
:func:`map_image` the design map of a sweep. Fixed margins instead of a layout engine: a layout
engine costs seconds per figure.
"""

from __future__ import annotations

import io
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .specs import STATE_FILL, FigureSpec, PlotSpec

__all__ = ["IMAGE_FORMATS", "draw_panel", "figure", "load_drawing_modules", "map_image", "spec_image"]

IMAGE_FORMATS = ("png", "svg")
_DASH = {"solid": "-", "dashed": "--", "dotted": ":", "dotdash": "-."}


def load_drawing_modules() -> None:
    """Import now what the first figure and its PNG import: matplotlib's figure, Agg and
    collection modules, and Pillow's image plugins (``savefig`` loads them on its first PNG).

    For a caller that has the time now and not later: a process pool forked after this call
    gives its workers them already loaded (each worker importing them again cost ~0.25 s of
    CPU, issue 23: ``fingerpad analyse``), and ``predict --direction`` calls it on a core the
    deflection ramps left free, instead of after them (~0.4 s, issue 23).
    """
    import matplotlib.backends.backend_agg
    import matplotlib.collections
    import matplotlib.figure  # noqa: F401
    from PIL import Image

    Image.preinit()


def _nice_log_ticks(ax: Any, lo: float, hi: float) -> None:
    """Plain tick labels at 1-2-5 steps on a log x axis (and its ends when far from a tick)."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    if not (lo > 0 and hi > lo):
        return
    first, last = math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1
    nice = [m * 10.0**k for k in range(first, last + 1) for m in (1, 2, 5)]
    ticks = [t for t in nice if lo * (1 - 1e-9) <= t <= hi * (1 + 1e-9)]
    if ticks and hi / ticks[-1] > 1.5:
        ticks.append(hi)
    if ticks and ticks[0] / lo > 1.5:
        ticks.insert(0, lo)
    if len(ticks) >= 2:
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        # 1-2-5 values as they are, an end of the range (49.6397 kPa) to 3 digits
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}" if v in nice else f"{v:.3g}"))
        ax.xaxis.set_minor_formatter(NullFormatter())


def _limits(ax: Any, which: str, limits: tuple[float | None, float | None] | None, factor: float) -> None:
    """Axis limits given in SI (``None`` at an end: automatic)."""
    if limits is None:
        return
    lo, hi = (None if v is None else v * factor for v in limits)
    if which == "x":
        ax.set_xlim(left=lo, right=hi)
    else:
        ax.set_ylim(bottom=lo, top=hi)


def draw_panel(fig: Any, ax: Any, spec: PlotSpec, colorbar_at: tuple[float, float, float, float] | None = None) -> None:
    """Draw the panel ``spec`` on the axes ``ax`` of ``fig``."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Circle

    fx, fy = spec.x.factor, spec.y.factor
    seen: set[str] = set()
    for band in spec.bands:
        label = f"centre: {band.state}" if band.legend and band.state not in seen else None
        seen.add(band.state)
        ax.axvspan(band.x0 * fx, band.x1 * fx, color=STATE_FILL.get(band.state, "#eeeeee"), alpha=0.8, lw=0,
                   zorder=0, label=label)
    for f in spec.fills:  # quantile bands, under the lines
        ax.fill_between(np.asarray(f.x, float) * fx, spec.y.show(f.lower), spec.y.show(f.upper), color=f.color,
                        alpha=f.alpha, lw=0, label=f.name)
    for im in spec.images:
        extent = (im.x0 * fx, im.x1 * fx, im.y0 * fy, im.y1 * fy)
        art = ax.imshow(im.value.show(im.z), origin="lower", extent=extent, interpolation="nearest", aspect="equal",
                        cmap="Greys_r" if im.palette == "greys" else "viridis")
        fig.colorbar(art, cax=fig.add_axes(colorbar_at or (0.83, 0.12, 0.03, 0.76)), label=im.value.label)
        if im.overlay is not None:
            ov = np.ma.masked_where(~np.asarray(im.overlay, bool), np.ones(np.shape(im.overlay)))
            ax.imshow(ov, origin="lower", extent=extent, cmap=ListedColormap(["#d62728"]), alpha=0.6,
                      interpolation="nearest", vmin=0, vmax=1, aspect="equal")
    for disc in spec.discs:
        r = disc.radius * fx
        if disc.fill is not None:
            ax.add_patch(Circle((0, 0), r, color=disc.fill, lw=0, label=disc.label))
            ax.add_patch(Circle((0, 0), r, fill=False, color="k", lw=0.8))
        else:
            ax.add_patch(Circle((0, 0), r, fill=False, color="k", ls=_DASH.get(disc.dash, "-"), lw=1.2,
                                label=disc.label))
    for text in spec.labels:
        ax.annotate(text.text, (text.x * fx, text.y * fy), xytext=(4, 4), textcoords="offset points",
                    fontsize="small")
    ax2 = None
    if spec.y2 is not None:
        ax2 = ax.twinx()
    def references() -> None:
        for v in spec.vlines:
            ax.axvline(v.x * fx, color=v.color, ls=_DASH.get(v.dash, "-"), lw=v.width, label=v.label)

    if spec.references_first:
        references()
    for ln in spec.lines:
        target, axis = (ax2, spec.y2) if ln.axis == "right" and ax2 is not None else (ax, spec.y)
        fmt = (_DASH.get(ln.dash, "-") if ln.line else "") + ("o" if ln.markers else "")
        target.plot(np.asarray(ln.x, float) * fx, axis.show(ln.y), fmt, color=ln.color, lw=ln.width,
                    label=ln.name if ln.legend else None)
    if not spec.references_first:
        references()
    for h in spec.hlines:
        ax.axhline(h.y * fy, color=h.color, lw=h.width)
    if spec.x.log:
        ax.set_xscale("log")
    if spec.y.log:
        ax.set_yscale("log")
    if spec.x.limits is not None:
        _limits(ax, "x", spec.x.limits, fx)
    elif (spec.lines or spec.fills) and not spec.images and not spec.discs:  # the data's x range (one x: a window)
        xs = np.concatenate([np.asarray(ln.x, float) for ln in (*spec.lines, *spec.fills)]) * fx
        xs = xs[np.isfinite(xs)]
        if xs.size:
            lo, hi = float(xs.min()), float(xs.max())
            if hi > lo:
                ax.set_xlim(lo, hi)
                if spec.x.log and hi / lo > 5:
                    _nice_log_ticks(ax, lo, hi)
            elif lo > 0:
                ax.set_xlim(0.5 * lo, 1.5 * hi)
    _limits(ax, "y", spec.y.limits, fy)
    if spec.equal_aspect:
        ax.set_aspect("equal")
    ax.set_xlabel(spec.x.label)
    ax.set_ylabel(spec.y.label)
    if ax2 is not None:
        ax2.set_ylabel(spec.y2.label)
        _limits(ax2, "y", spec.y2.limits, spec.y2.factor)
    ax.set_title(spec.title, fontsize="medium")
    if spec.grid:
        ax.grid(True, which="both", alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    if ax2 is not None:
        h2, l2 = ax2.get_legend_handles_labels()
        handles, labels = handles + h2, labels + l2
    if handles:
        ax.legend(handles, labels, fontsize="small", loc=spec.legend)


def _as_figure(spec: PlotSpec | FigureSpec) -> FigureSpec:
    """A panel alone as a figure (the explorer's image downloads)."""
    if isinstance(spec, FigureSpec):
        return spec
    square = bool(spec.images or spec.discs)
    right = 0.80 if (spec.images or spec.y2 is not None) else 0.97
    return FigureSpec(spec.key, None, [spec], size=(6.4, 5.2) if square else (7.6, 4.6),
                      margins={"left": 0.12, "right": right, "bottom": 0.12, "top": 0.9})


def figure(spec: PlotSpec | FigureSpec) -> Any:
    """The matplotlib Figure of a figure spec (or of one panel)."""
    from matplotlib.figure import Figure

    fs = _as_figure(spec)
    fig = Figure(figsize=fs.size)
    if fs.margins:
        fig.subplots_adjust(**fs.margins)
    n = len(fs.panels)
    axes = fig.subplots(1, n, gridspec_kw={"width_ratios": list(fs.width_ratios)} if fs.width_ratios else None,
                        squeeze=False)[0]
    for ax, panel in zip(axes, fs.panels, strict=True):
        draw_panel(fig, ax, panel)
    if fs.title:
        fig.suptitle(fs.title)
    return fig


def spec_image(spec: PlotSpec | FigureSpec, fmt: str = "png", dpi: int = 130) -> bytes:
    """The image of ``spec`` as bytes (``fmt``: png or svg)."""
    if fmt not in IMAGE_FORMATS:
        raise ValueError(f"image format must be one of {IMAGE_FORMATS}, got {fmt!r}")
    buf = io.BytesIO()
    figure(spec).savefig(buf, format=fmt, dpi=dpi)
    return buf.getvalue()


def map_image(x: Sequence[Any], y: Sequence[Any], values: Sequence[Any], *, grid: bool, x_label: str,
              y_label: str, colour_label: str, title: str, x_log: bool = False, y_log: bool = False,
              fmt: str = "png", markers: Sequence[Mapping[str, Any]] = ()) -> bytes:
    """A design map as image bytes: ``values[j, i]`` over the axis values ``x[i]``, ``y[j]``
    (``grid``), or one value per point at ``(x[n], y[n])``. ``markers``: dashed lines
    ``{"kind": "line", "value", "vertical", "label"}`` and grey bands ``{"kind": "band", "low",
    "high", "vertical", "label"}`` in the axes' units, as the page's map draws them."""
    from matplotlib.figure import Figure

    if fmt not in IMAGE_FORMATS:
        raise ValueError(f"image format must be one of {IMAGE_FORMATS}, got {fmt!r}")
    fig = Figure(figsize=(7, 5.2))
    ax = fig.subplots()
    if grid:
        art = ax.pcolormesh(np.asarray(x, float), np.asarray(y, float), np.asarray(values, float), shading="nearest")
    else:
        art = ax.scatter(np.asarray(x, float), np.asarray(y, float), c=np.asarray(values, float), s=80)
    fig.colorbar(art, ax=ax, label=colour_label)
    if x_log:
        ax.set_xscale("log")
    if y_log:
        ax.set_yscale("log")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title, fontsize="small")
    for item in markers:
        vertical, label = bool(item["vertical"]), str(item["label"])
        if item["kind"] == "line":
            v = float(item["value"])
            (ax.axvline if vertical else ax.axhline)(v, color="#333333", linestyle="--", linewidth=1,
                                                     gid=f"marker-{label}")
            # the label along the line, at the axes' edge (as the page writes it)
            ax.annotate(label, (v, 0.02) if vertical else (0.01, v), xycoords=ax.get_xaxis_transform() if vertical
                        else ax.get_yaxis_transform(), rotation=90 if vertical else 0, fontsize=7, color="#333333",
                        va="bottom", ha="right" if vertical else "left",
                        bbox={"boxstyle": "square,pad=0.1", "facecolor": "white", "alpha": 0.6, "linewidth": 0})
        else:
            (ax.axvspan if vertical else ax.axhspan)(float(item["low"]), float(item["high"]), color="#888888",
                                                     alpha=0.15, linewidth=0, gid=f"marker-{label}")
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, dpi=130)
    return buf.getvalue()
