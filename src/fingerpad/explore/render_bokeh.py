"""Drawing a :class:`~fingerpad.plotting.specs.PlotSpec` as an interactive Bokeh figure (hover,
zoom, legend): the same specification ``fingerpad predict`` draws with matplotlib
(:mod:`fingerpad.plotting.render`), values shown in each axis's unit.

:func:`bokeh_figure` builds the figure and returns a :class:`Drawn` handle; :func:`update_figure`
puts a new spec of the same structure (same series, lines, bands, images) into an existing
figure by replacing its data only, which is what keeps the page live: rebuilding a figure costs
the server and the browser far more than new data.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..plotting.specs import STATE_FILL, PlotSpec

__all__ = ["Drawn", "bokeh_figure", "rgba_overlay", "update_figure"]

_DASH = {"solid": "solid", "dashed": "dashed", "dotted": "dotted", "dotdash": "dotdash"}
#: matplotlib's legend places (the spec's words) -> Bokeh's.
_LEGEND = {"best": "top_left", "upper left": "top_left", "upper right": "top_right", "lower left": "bottom_left",
           "lower right": "bottom_right", "center": "center"}


def _clean(a: Any, log: bool) -> np.ndarray:
    """Finite values (non-positive ones dropped on a log axis) as floats, others NaN (a gap)."""
    v = np.asarray(a, dtype=float).copy()
    bad = ~np.isfinite(v)
    if log:
        bad |= v <= 0
    v[bad] = np.nan
    return v


def rgba_overlay(mask: np.ndarray, rgb: tuple[int, int, int] = (214, 39, 40), alpha: int = 150) -> np.ndarray:
    """A uint32 RGBA image: ``rgb`` with ``alpha`` where ``mask``, transparent elsewhere."""
    m = np.asarray(mask, bool)
    img = np.zeros(m.shape, dtype=np.uint32)
    view = img.view(dtype=np.uint8).reshape(m.shape + (4,))
    view[m, 0], view[m, 1], view[m, 2], view[m, 3] = rgb[0], rgb[1], rgb[2], alpha
    return img


def _aspect(spec: PlotSpec) -> float:
    if spec.images:
        im = spec.images[0]
        return round(abs(im.x1 - im.x0) * spec.x.factor / max(abs(im.y1 - im.y0) * spec.y.factor, 1e-300), 3)
    return 1.0


def _slots(spec: PlotSpec) -> list[tuple[tuple[Any, ...], dict[str, Any], str | None]]:
    """The figure's data sources in drawing order: (structure key, data, legend label)."""
    out: list[tuple[tuple[Any, ...], dict[str, Any], str | None]] = []
    fx, fy = spec.x.factor, spec.y.factor
    for state in dict.fromkeys(b.state for b in spec.bands):
        mine = [b for b in spec.bands if b.state == state]
        out.append((("band", state), {"x0": [b.x0 * fx for b in mine], "x1": [b.x1 * fx for b in mine]},
                    f"centre: {state}" if any(b.legend for b in mine) else None))
    for k, im in enumerate(spec.images):
        place = {"x": [im.x0 * fx], "y": [im.y0 * fy], "dw": [(im.x1 - im.x0) * fx], "dh": [(im.y1 - im.y0) * fy]}
        out.append((("image", k, im.palette, im.value.label), {"image": [im.value.show(im.z)], **place}, None))
        if im.overlay is not None:
            out.append((("overlay", k), {"image": [rgba_overlay(im.overlay)], **place}, None))
    for k, disc in enumerate(spec.discs):
        t = np.linspace(0.0, 2.0 * np.pi, 241)  # a polygon: exact in data units whatever the scales
        r = disc.radius * fx
        out.append((("disc", k, disc.fill is None, disc.dash), {"xs": [r * np.cos(t)], "ys": [r * np.sin(t)]},
                    disc.label))
    for ln in spec.lines:
        axis = spec.axis_of(ln)
        x = _clean(np.asarray(ln.x, float) * fx, spec.x.log)
        y = _clean(axis.show(ln.y), axis.log)
        data: dict[str, Any] = {"x": x, "y": y, "name": [ln.name] * x.size}
        data.update({k: np.asarray(v) for k, v in ln.tooltips.items()})
        out.append((("line", ln.name, ln.line, ln.markers, ln.axis, ln.dash, ln.color, tuple(ln.tooltips)), data,
                    ln.name if ln.legend else None))
    for k, v in enumerate(spec.vlines):
        out.append((("vline", k, v.dash, v.color), {"x": [v.x * fx]}, v.label))
    for k, h in enumerate(spec.hlines):
        out.append((("hline", k, h.color), {"y": [h.y * fy]}, None))
    if spec.labels:
        out.append((("labels",), {"x": [lb.x * fx for lb in spec.labels], "y": [lb.y * fy for lb in spec.labels],
                                  "text": [lb.text for lb in spec.labels]}, None))
    return out


def _axis_kind(axis: Any) -> tuple[Any, ...]:
    """What of an axis the figure is built with (its limits are data: they update in place)."""
    return None if axis is None else (axis.name, axis.unit, axis.shown, axis.factor, axis.log, axis.limits is None)


def _structure(spec: PlotSpec) -> tuple[Any, ...]:
    return (spec.key, _axis_kind(spec.x), _axis_kind(spec.y), _axis_kind(spec.y2), spec.equal_aspect,
            _aspect(spec), spec.legend, tuple(s for s, _, _ in _slots(spec)))


def _range(axis: Any, values: np.ndarray) -> tuple[float, float] | None:
    """The shown range of an axis with limits (an open end from the data), else None."""
    if axis.limits is None:
        return None
    lo, hi = (None if v is None else v * axis.factor for v in axis.limits)
    finite = values[np.isfinite(values)]
    if lo is None:
        lo = float(finite.min()) if finite.size else 0.0
    if hi is None:
        hi = 1.05 * float(finite.max()) if finite.size else 1.0
    return (lo, hi if hi > lo else lo + 1.0)


def _values(spec: PlotSpec, right: bool) -> np.ndarray:
    lines = [ln for ln in spec.lines if (ln.axis == "right") == right]
    axis = spec.y2 if right and spec.y2 is not None else spec.y
    return np.concatenate([axis.show(ln.y).ravel() for ln in lines] or [np.empty(0)])


@dataclass
class Drawn:
    """A drawn figure and what :func:`update_figure` needs to put new data in it."""

    figure: Any
    structure: tuple[Any, ...]
    sources: list[Any] = field(default_factory=list)
    legend: list[Any] = field(default_factory=list)  # LegendItem per slot (None: not in the legend)
    mappers: list[Any] = field(default_factory=list)


def _limits(z: np.ndarray) -> tuple[float, float]:
    finite = z[np.isfinite(z)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    return (low, high if high > low else low + 1.0)


def log_ticks(values: np.ndarray) -> tuple[list[float], list[float]] | None:
    """Major (1-2-3-5 within one decade, 1-2-5 up to 3 decades, 1 per decade beyond) and minor
    (1..9 per decade) tick positions spanning the positive finite ``values``; None if none."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    if v.size == 0:
        return None
    lo, hi = int(np.floor(np.log10(v.min()))), int(np.ceil(np.log10(v.max())))
    span = hi - lo
    mantissas = (1.0, 2.0, 3.0, 5.0) if span <= 1 else (1.0, 2.0, 5.0) if span <= 3 else (1.0,)
    decades = [10.0 ** e for e in range(lo - 1, hi + 1)]
    major = [m * d for d in decades for m in mantissas]
    minor = [m * d for d in decades for m in range(1, 10)]
    return major, minor


def bokeh_figure(spec: PlotSpec, *, height: int = 330, width: int | None = None) -> Drawn:
    """The Bokeh figure of ``spec`` (named ``spec.key`` so tests and scripts can find it)."""
    from bokeh.models import ColorBar, ColumnDataSource, HoverTool, LinearAxis, LinearColorMapper, Range1d
    from bokeh.palettes import Greys256, Viridis256
    from bokeh.plotting import figure

    kwargs: dict[str, Any] = {
        "title": spec.title, "x_axis_label": spec.x.label, "y_axis_label": spec.y.label,
        "x_axis_type": "log" if spec.x.log else "linear", "y_axis_type": "log" if spec.y.log else "linear",
        "tools": "pan,wheel_zoom,box_zoom,reset,save", "name": spec.key, "output_backend": "canvas",
    }
    if spec.discs:  # the same scale on x and y: data ranges matched to the frame's aspect
        kwargs["height"] = height
        kwargs["sizing_mode"] = "stretch_width"
        kwargs["match_aspect"] = True
    elif spec.images:  # maps: the same scale on x and y
        frame = height - 70
        kwargs["frame_height"] = frame
        kwargs["frame_width"] = int(min(max(frame * _aspect(spec), 120), 2.2 * frame))
    else:
        kwargs["height"] = height
        if width is not None:
            kwargs["width"] = width
        else:
            kwargs["sizing_mode"] = "stretch_width"
    if spec.images:
        im = spec.images[0]
        kwargs["x_range"] = Range1d(im.x0 * spec.x.factor, im.x1 * spec.x.factor)
        kwargs["y_range"] = Range1d(im.y0 * spec.y.factor, im.y1 * spec.y.factor)
    elif spec.discs:
        pass  # ranges from the data, matched to the frame's aspect (match_aspect): circles stay round
    else:
        if spec.x.limits is not None:
            kwargs["x_range"] = Range1d(*_range(spec.x, np.concatenate(
                [np.asarray(ln.x, float).ravel() * spec.x.factor for ln in spec.lines] or [np.empty(0)])))
        if spec.y.limits is not None:
            kwargs["y_range"] = Range1d(*_range(spec.y, _values(spec, False)))
    p = figure(**kwargs)
    p.toolbar.logo = None
    drawn = Drawn(p, _structure(spec))
    _log_ticks(drawn, spec)
    p.title.text_font_size = "10pt"
    if spec.y2 is not None:
        p.extra_y_ranges = {"right": Range1d(*(_range(spec.y2, _values(spec, True)) or (0.0, 1.0)))}
        p.add_layout(LinearAxis(y_range_name="right", axis_label=spec.y2.label), "right")

    lines_by_name = {ln.name: ln for ln in spec.lines}
    hover_lines = []
    renderers = []
    for key, data, label in _slots(spec):
        src = ColumnDataSource(data)
        drawn.sources.append(src)
        legend = {"legend_label": label} if label else {}
        kind = key[0]
        if kind == "band":
            r = p.vstrip(x0="x0", x1="x1", source=src, fill_color=STATE_FILL.get(key[1], "#eeeeee"), fill_alpha=0.7,
                         line_alpha=0, level="underlay", **legend)
        elif kind == "image":
            im = spec.images[key[1]]
            low, high = _limits(im.value.show(im.z))
            mapper = LinearColorMapper(palette=Greys256 if im.palette == "greys" else Viridis256, low=low, high=high)
            drawn.mappers.append(mapper)
            r = p.image(image="image", x="x", y="y", dw="dw", dh="dh", color_mapper=mapper, source=src)
            p.add_tools(HoverTool(renderers=[r], tooltips=[(spec.x.label, "$x{0.00}"), (spec.y.label, "$y{0.00}"),
                                                           (im.value.label, "@image{0.0000}")]))
            p.add_layout(ColorBar(color_mapper=mapper, title=im.value.label, width=10), "right")
        elif kind == "overlay":
            r = p.image_rgba(image="image", x="x", y="y", dw="dw", dh="dh", source=src)
            im = spec.images[key[1]]
            p.scatter([im.x0 * spec.x.factor], [im.y0 * spec.y.factor], marker="square", size=0.1,
                      color="#d62728", alpha=0.6, legend_label="in contact")
        elif kind == "disc":
            disc = spec.discs[key[1]]
            if disc.fill is None:
                r = p.patches(xs="xs", ys="ys", source=src, fill_color=None, line_color="black",
                              line_dash=_DASH.get(disc.dash, "solid"), line_width=1.5, **legend)
            else:
                r = p.patches(xs="xs", ys="ys", source=src, fill_color=disc.fill, fill_alpha=1.0,
                              line_color="black", line_width=0.8, **legend)
        elif kind == "line":
            ln = lines_by_name[key[1]]
            extra = {"y_range_name": "right"} if ln.axis == "right" and spec.y2 is not None else {}
            r = None
            if ln.line:
                r = p.line("x", "y", source=src, color=ln.color, line_width=ln.width,
                           line_dash=_DASH.get(ln.dash, "solid"), **legend, **extra)
                hover_lines.append(r)
            if ln.markers:
                m = p.scatter("x", "y", source=src, color=ln.color, size=6, **legend, **extra)
                hover_lines.append(m)
                r = r or m
        elif kind == "vline":
            v = spec.vlines[key[1]]
            r = p.vspan(x="x", source=src, line_color=v.color, line_dash=_DASH.get(v.dash, "solid"),
                        line_width=max(v.width, 1.0), **legend)
        elif kind == "hline":
            h = spec.hlines[key[1]]
            r = p.hspan(y="y", source=src, line_color=h.color, line_width=max(h.width, 1.0))
        else:  # labels
            from bokeh.models import LabelSet

            r = LabelSet(x="x", y="y", text="text", source=src, x_offset=4, y_offset=4, text_font_size="8pt")
            p.add_layout(r)
        renderers.append((r, label))
    if hover_lines:
        tips = [("", "@name"), (spec.x.label, "@x{%0.5g}"), ("value", "@y{%0.5g}")]
        tips += [(k, f"@{k}") for ln in spec.lines for k in ln.tooltips]
        p.add_tools(HoverTool(renderers=hover_lines, tooltips=tips, formatters={"@x": "printf", "@y": "printf"}))

    if p.legend:
        legend = p.legend[0]
        legend.label_text_font_size = "8pt"
        legend.background_fill_alpha = 0.75
        legend.spacing = 0
        legend.padding = 4
        legend.click_policy = "hide"
        legend.location = _LEGEND.get(spec.legend, "top_left")
        if not spec.images and not spec.discs:  # beside the plot, not over the curves
            p.add_layout(legend, "right")
        items = {id(r): item for item in legend.items for r in item.renderers}
        drawn.legend = [items.get(id(r)) if label else None for r, label in renderers]
    else:
        drawn.legend = [None] * len(renderers)
    return drawn


def update_figure(drawn: Drawn, spec: PlotSpec) -> bool:
    """Put ``spec`` into the figure of ``drawn`` if its structure is the same (new data, labels,
    title, ranges); ``False`` when the figure must be rebuilt."""
    from bokeh.core.property.vectorization import value

    if _structure(spec) != drawn.structure:
        return False
    p = drawn.figure
    slots = _slots(spec)
    for src, item, (_, data, label) in zip(drawn.sources, drawn.legend, slots, strict=True):
        src.data = data
        if item is not None and label is not None and getattr(item.label, "value", None) != label:
            item.label = value(label)
    p.title.text = spec.title
    _log_ticks(drawn, spec)
    if spec.images:
        im = spec.images[0]
        p.x_range.start, p.x_range.end = im.x0 * spec.x.factor, im.x1 * spec.x.factor
        p.y_range.start, p.y_range.end = im.y0 * spec.y.factor, im.y1 * spec.y.factor
        for mapper, img in zip(drawn.mappers, spec.images, strict=False):
            mapper.low, mapper.high = _limits(img.value.show(img.z))
    elif not spec.discs:
        if spec.x.limits is not None:
            p.x_range.start, p.x_range.end = _range(spec.x, np.concatenate(
                [np.asarray(ln.x, float).ravel() * spec.x.factor for ln in spec.lines] or [np.empty(0)]))
        if spec.y.limits is not None:
            p.y_range.start, p.y_range.end = _range(spec.y, _values(spec, False))
        if spec.y2 is not None and spec.y2.limits is not None:
            p.extra_y_ranges["right"].start, p.extra_y_ranges["right"].end = _range(spec.y2, _values(spec, True))
    return True


def _log_ticks(drawn: Drawn, spec: PlotSpec) -> None:
    """Bokeh's log ticker falls back to linear steps on ranges under about two decades (a load
    axis of 0.1-4 N then shows only "1 2 3 4"): label a 1-2-5 sequence, decades on wide ranges."""
    from bokeh.models import FixedTicker

    p = drawn.figure
    for axis, bk_axis, which in ((spec.x, p.xaxis, "x"), (spec.y, p.yaxis, "y")):
        if not axis.log:
            continue
        values = np.concatenate([axis.show(getattr(ln, which)).ravel() for ln in spec.lines
                                 if which == "x" or ln.axis == "left"] or [np.empty(0)])
        ticks = log_ticks(values)
        if ticks is not None:
            bk_axis.ticker = FixedTicker(ticks=ticks[0], minor_ticks=ticks[1])
