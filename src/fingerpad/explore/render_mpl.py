"""Drawing a :class:`~.specs.PlotSpec` as a PNG or SVG image (matplotlib, Agg; fixed margins)."""

from __future__ import annotations

import io
from typing import Any

import numpy as np

from .specs import STATE_FILL, PlotSpec

__all__ = ["IMAGE_FORMATS", "spec_image"]

IMAGE_FORMATS = ("png", "svg")
_DASH = {"solid": "-", "dashed": "--", "dotted": ":", "dotdash": "-."}


def _figure(spec: PlotSpec) -> Any:
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    square = bool(spec.images or spec.discs)
    fig = Figure(figsize=(6.4, 5.2) if square else (7.6, 4.6))
    fig.subplots_adjust(left=0.12, right=0.80 if (spec.images or spec.y2_label) else 0.97, bottom=0.12, top=0.88)
    ax = fig.subplots()
    for band in spec.bands:
        ax.axvspan(band.x0, band.x1, color=STATE_FILL.get(band.state, "#eeeeee"), alpha=0.8, lw=0, zorder=0)
    for state in dict.fromkeys(b.state for b in spec.bands):
        ax.fill_between([], [], [], color=STATE_FILL.get(state, "#eeeeee"), label=f"centre: {state}")
    for im in spec.images:
        cmap = "Greys_r" if im.palette == "greys" else "viridis"
        art = ax.imshow(np.asarray(im.z, float), origin="lower", extent=(im.x0, im.x1, im.y0, im.y1), cmap=cmap,
                        interpolation="nearest", aspect="equal")
        cax = fig.add_axes((0.83, 0.12, 0.03, 0.76))
        fig.colorbar(art, cax=cax, label=im.label)
        if im.overlay is not None:
            ov = np.ma.masked_where(~np.asarray(im.overlay, bool), np.ones(np.shape(im.overlay)))
            ax.imshow(ov, origin="lower", extent=(im.x0, im.x1, im.y0, im.y1), cmap=ListedColormap(["#d62728"]),
                      alpha=0.6, interpolation="nearest", vmin=0, vmax=1, aspect="equal")
    for disc in sorted(spec.discs, key=lambda d: (d.state == "outline", -d.radius)):
        if disc.state == "outline":
            ax.add_patch(Circle((0, 0), disc.radius, fill=False, ls="--", color="k", lw=1.2, label=disc.label))
        else:
            ax.add_patch(Circle((0, 0), disc.radius, color=STATE_FILL.get(disc.state, "#eeeeee"), ec="k", lw=0.8,
                                label=disc.label))
    if spec.discs:
        lim = 1.12 * max(d.radius for d in spec.discs)
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_aspect("equal")
    ax2 = None
    for ln in spec.lines:
        target = ax
        if ln.axis == "right" and spec.y2_label:
            if ax2 is None:
                ax2 = ax.twinx()
                ax2.set_ylabel(spec.y2_label)
                if spec.y2_range:
                    ax2.set_ylim(*spec.y2_range)
            target = ax2
        fmt = _DASH.get(ln.dash, "-") if ln.line else ""
        target.plot(np.asarray(ln.x, float), np.asarray(ln.y, float), fmt + ("o" if ln.markers else ""),
                    color=ln.color, lw=ln.width, ms=3.5, label=ln.name)
    for v in spec.vlines:
        ax.axvline(v.x, color=v.color, ls=_DASH.get(v.dash, "-"), lw=1.0, label=v.label)
    if spec.x_log:
        ax.set_xscale("log")
    if spec.y_log:
        ax.set_yscale("log")
    if spec.y_range and not spec.images and not spec.discs:
        ax.set_ylim(*spec.y_range)
    ax.set_xlabel(spec.x_label)
    ax.set_ylabel(spec.y_label)
    ax.set_title(spec.title, fontsize="small")
    if not spec.images:
        ax.grid(True, which="both", alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    if ax2 is not None:
        h2, l2 = ax2.get_legend_handles_labels()
        handles, labels = handles + h2, labels + l2
    if handles:
        ax.legend(handles, labels, fontsize="x-small", loc="best")
    return fig


def spec_image(spec: PlotSpec, fmt: str = "png", dpi: int = 130) -> bytes:
    """The plot of ``spec`` as image bytes (``fmt``: png or svg)."""
    if fmt not in IMAGE_FORMATS:
        raise ValueError(f"image format must be one of {IMAGE_FORMATS}, got {fmt!r}")
    fig = _figure(spec)
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, dpi=dpi)
    return buf.getvalue()
