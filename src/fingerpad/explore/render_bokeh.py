"""Drawing a :class:`~fingerpad.plotting.specs.PlotSpec` as an interactive Bokeh figure (hover,
zoom, legend): the same specification ``fingerpad predict`` draws with matplotlib
(:mod:`fingerpad.plotting.render`), values shown in each axis's unit.

:func:`bokeh_figure` builds the figure and returns a :class:`Drawn` handle; :func:`update_figure`
puts a new spec into an existing figure. Both go through one function (:func:`_show`), so an
updated figure shows exactly what a fresh one of the same spec shows: each series of the spec is
a *slot* (a data source and its glyphs, named by what it looks like: a line by its name, style
and axis; a reference line by its style), reused when the new spec has a slot of the same name
(its data replaced in place), made when it has a new one, hidden (no data, out of the legend)
when it has one fewer. Only a change of the frame (the axes' quantities, units and scales, a
map's aspect) rebuilds the figure. Rebuilding costs the server and the browser far more than new
data: the explorer's page stays live on a busy machine only with updates in place (issue 23).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..plotting.specs import STATE_FILL, PlotSpec

__all__ = ["Drawn", "adds_models", "bokeh_figure", "figure_content", "rgba_overlay", "update_figure"]

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
    """The figure's data sources in drawing order: (slot name, data, legend label).

    A slot's name says how its glyphs look (kind, style, colour, axis); the same name in two
    specs is the same glyphs with other data. Repeated names get a counter."""
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
            out.append((("overlay", k), {"image": [rgba_overlay(im.overlay)], **place}, "in contact"))
    for disc in spec.discs:
        t = np.linspace(0.0, 2.0 * np.pi, 241)  # a polygon: exact in data units whatever the scales
        r = disc.radius * fx
        out.append((("disc", disc.fill, disc.dash), {"xs": [r * np.cos(t)], "ys": [r * np.sin(t)]}, disc.label))
    for f in spec.fills:
        out.append((("fill", f.name, f.color, f.alpha),
                    {"x": _clean(np.asarray(f.x, float) * fx, spec.x.log), "lower": _clean(spec.y.show(f.lower),
                                                                                          spec.y.log),
                     "upper": _clean(spec.y.show(f.upper), spec.y.log)}, f.name))
    for ln in spec.lines:
        axis = spec.axis_of(ln)
        x = _clean(np.asarray(ln.x, float) * fx, spec.x.log)
        y = _clean(axis.show(ln.y), axis.log)
        data: dict[str, Any] = {"x": x, "y": y, "name": [ln.name] * x.size}
        data.update({k: np.asarray(v) for k, v in ln.tooltips.items()})
        out.append((("line", ln.name, ln.line, ln.markers, ln.axis, ln.dash, ln.color, ln.width, tuple(ln.tooltips)),
                    data, ln.name if ln.legend else None))
    for v in spec.vlines:
        out.append((("vline", v.dash, v.color, v.width), {"x": [v.x * fx]}, v.label))
    for h in spec.hlines:
        out.append((("hline", h.color, h.width), {"y": [h.y * fy]}, None))
    if spec.labels:
        out.append((("labels",), {"x": [lb.x * fx for lb in spec.labels], "y": [lb.y * fy for lb in spec.labels],
                                  "text": [lb.text for lb in spec.labels]}, None))
    seen: dict[tuple[Any, ...], int] = {}
    named = []
    for key, data, label in out:
        n = seen.get(key, 0)
        seen[key] = n + 1
        named.append(((*key, n), data, label))
    return named


def _axis_kind(axis: Any) -> tuple[Any, ...] | None:
    """What of an axis the figure is built with (its limits are data: they update in place)."""
    return None if axis is None else (axis.name, axis.unit, axis.shown, axis.factor, axis.log, axis.limits is None)


def _frame(spec: PlotSpec, height: int, width: int | None) -> tuple[Any, ...]:
    """What a figure is built with; a spec with another frame needs a new figure."""
    return (spec.key, _axis_kind(spec.x), _axis_kind(spec.y), _axis_kind(spec.y2), spec.equal_aspect,
            _aspect(spec), bool(spec.images), bool(spec.discs), spec.legend, height, width)


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
    lines = [ln.y for ln in spec.lines if (ln.axis == "right") == right]
    if not right:
        lines += [y for f in spec.fills for y in (f.lower, f.upper)]
    axis = spec.y2 if right and spec.y2 is not None else spec.y
    return np.concatenate([axis.show(y).ravel() for y in lines] or [np.empty(0)])


@dataclass
class _Slot:
    """One slot's models: its data source, glyph renderers (in drawing order), those the legend
    names, those the line hover reads, and models beside them (a colour bar, a hover tool)."""

    source: Any
    renderers: list[Any]
    legend: list[Any]
    hover: list[Any] = field(default_factory=list)
    extras: list[Any] = field(default_factory=list)
    mapper: Any = None


@dataclass
class Drawn:
    """A drawn figure and what :func:`update_figure` needs to put new data in it."""

    figure: Any
    frame: tuple[Any, ...]
    slots: dict[tuple[Any, ...], _Slot] = field(default_factory=dict)
    shown: list[tuple[Any, ...]] = field(default_factory=list)  # the slots of the spec shown, in order
    legend: Any = None
    items: list[Any] = field(default_factory=list)  # the legend's items, reused in order
    hover: Any = None  # the hover tool of the lines

    @property
    def sources(self) -> list[Any]:
        """The data sources of the spec shown, in drawing order."""
        return [self.slots[k].source for k in self.shown]


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
    from bokeh.models import Legend, LinearAxis, Range1d
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
    if spec.images or (not spec.discs and spec.x.limits is not None):
        kwargs["x_range"] = Range1d(0.0, 1.0)  # set by _show
    if spec.images or (not spec.discs and spec.y.limits is not None):
        kwargs["y_range"] = Range1d(0.0, 1.0)
    p = figure(**kwargs)
    p.toolbar.logo = None
    p.title.text_font_size = "10pt"
    if spec.y2 is not None:
        p.extra_y_ranges = {"right": Range1d(0.0, 1.0)}
        p.add_layout(LinearAxis(y_range_name="right", axis_label=spec.y2.label), "right")
    legend = Legend(items=[], label_text_font_size="8pt", background_fill_alpha=0.75, spacing=0, padding=4,
                    click_policy="hide", location=_LEGEND.get(spec.legend, "top_left"))
    # beside the plot, not over the curves (maps and discs: inside)
    p.add_layout(legend, "center" if spec.images or spec.discs else "right")
    drawn = Drawn(p, _frame(spec, height, width), legend=legend)
    _show(drawn, spec)
    return drawn


def _make_slot(drawn: Drawn, spec: PlotSpec, key: tuple[Any, ...], data: dict[str, Any]) -> _Slot:
    """The glyphs of a new slot, drawn from ``data``."""
    from bokeh.models import ColorBar, ColumnDataSource, HoverTool, LabelSet, LinearColorMapper
    from bokeh.palettes import Greys256, Viridis256

    p = drawn.figure
    src = ColumnDataSource(data)
    kind = key[0]
    if kind == "band":
        r = p.vstrip(x0="x0", x1="x1", source=src, fill_color=STATE_FILL.get(key[1], "#eeeeee"), fill_alpha=0.7,
                     line_alpha=0, level="underlay")
        return _Slot(src, [r], [r])
    if kind == "image":
        mapper = LinearColorMapper(palette=Greys256 if key[2] == "greys" else Viridis256, low=0.0, high=1.0)
        r = p.image(image="image", x="x", y="y", dw="dw", dh="dh", color_mapper=mapper, source=src)
        tool = HoverTool(renderers=[r], tooltips=[(spec.x.label, "$x{0.00}"), (spec.y.label, "$y{0.00}"),
                                                  (key[3], "@image{0.0000}")])
        p.add_tools(tool)
        bar = ColorBar(color_mapper=mapper, title=key[3], width=10)
        p.add_layout(bar, "right")
        return _Slot(src, [r], [], extras=[bar], mapper=mapper)
    if kind == "overlay":
        r = p.image_rgba(image="image", x="x", y="y", dw="dw", dh="dh", source=src)
        # a legend swatch for the overlay: a point too small to see at the map's corner
        m = p.scatter("x", "y", source=src, marker="square", size=0.1, color="#d62728", alpha=0.6)
        return _Slot(src, [r, m], [m])
    if kind == "disc":
        fill, dash = key[1], key[2]
        if fill is None:
            r = p.patches(xs="xs", ys="ys", source=src, fill_color=None, line_color="black",
                          line_dash=_DASH.get(dash, "solid"), line_width=1.5)
        else:
            r = p.patches(xs="xs", ys="ys", source=src, fill_color=fill, fill_alpha=1.0, line_color="black",
                          line_width=0.8)
        return _Slot(src, [r], [r])
    if kind == "fill":
        r = p.varea(x="x", y1="lower", y2="upper", source=src, fill_color=key[2], fill_alpha=key[3])
        return _Slot(src, [r], [r])
    if kind == "line":
        _, _name, line, markers, axis, dash, color, width = key[:8]
        extra = {"y_range_name": "right"} if axis == "right" and spec.y2 is not None else {}
        rs = []
        if line:
            rs.append(p.line("x", "y", source=src, color=color, line_width=width, line_dash=_DASH.get(dash, "solid"),
                             **extra))
        if markers:
            rs.append(p.scatter("x", "y", source=src, color=color, size=6, **extra))
        return _Slot(src, rs, rs, hover=list(rs))
    if kind == "vline":
        _, dash, color, width = key[:4]
        r = p.vspan(x="x", source=src, line_color=color, line_dash=_DASH.get(dash, "solid"),
                    line_width=max(width, 1.0))
        return _Slot(src, [r], [r])
    if kind == "hline":
        _, color, width = key[:3]
        r = p.hspan(y="y", source=src, line_color=color, line_width=max(width, 1.0))
        return _Slot(src, [r], [])
    r = LabelSet(x="x", y="y", text="text", source=src, x_offset=4, y_offset=4, text_font_size="8pt")
    p.add_layout(r)
    return _Slot(src, [], [], extras=[r])


def _empty(data: dict[str, Any]) -> dict[str, Any]:
    return {k: [] for k in data}


def _show(drawn: Drawn, spec: PlotSpec) -> None:
    """Show ``spec`` in the figure of ``drawn`` (same frame): each slot's data in place, new slots
    made, slots the spec lacks hidden; legend, hover, title, ranges, ticks and colour scales."""
    from bokeh.core.property.vectorization import value
    from bokeh.models import HoverTool, LegendItem

    p = drawn.figure
    slots = _slots(spec)
    shown = [key for key, _, _ in slots]
    for key, data, _ in slots:
        slot = drawn.slots.get(key)
        if slot is None:
            drawn.slots[key] = _make_slot(drawn, spec, key, data)
        else:
            slot.source.data = data
    wanted = set(shown)
    for key, slot in drawn.slots.items():  # shown or not, in the spec's order; others hidden and empty
        on = key in wanted
        for model in (*slot.renderers, *slot.extras):
            model.visible = on
        if not on and slot.source.data and any(len(v) for v in slot.source.data.values()):
            slot.source.data = _empty(slot.source.data)
    order = [r for key in shown for r in drawn.slots[key].renderers]
    placed = {id(r) for r in p.renderers}
    if any(id(r) not in placed for r in order) or [r for r in p.renderers if r.visible] != order:
        # a new series, or the shown ones in another drawing order: the figure's list changes,
        # which makes BokehJS lay the whole page out again (seconds of Chromium for a page of ten
        # figures on a loaded machine); series only shown or hidden keep their places
        hidden = [r for key, slot in drawn.slots.items() if key not in wanted for r in slot.renderers]
        p.renderers = order + hidden
    drawn.shown = shown

    # the legend: one entry per label, in drawing order (as Bokeh groups legend_label)
    groups: dict[str, list[Any]] = {}
    for key, _, label in slots:
        if label:
            groups.setdefault(label, []).extend(drawn.slots[key].legend)
    while len(drawn.items) < len(groups):
        drawn.items.append(LegendItem(label=value(""), renderers=[]))
    for item, (label, renderers) in zip(drawn.items, groups.items(), strict=False):
        if getattr(item.label, "value", None) != label:
            item.label = value(label)
        item.renderers = renderers
    drawn.legend.items = drawn.items[:len(groups)]
    drawn.legend.visible = bool(groups)

    hover = [r for key in shown for r in drawn.slots[key].hover]
    if hover:
        tips = [("", "@name"), (spec.x.label, "@x{%0.5g}"), ("value", "@y{%0.5g}")]
        tips += [(k, f"@{k}") for ln in spec.lines for k in ln.tooltips]
        if drawn.hover is None:
            drawn.hover = HoverTool(renderers=hover, tooltips=tips, formatters={"@x": "printf", "@y": "printf"})
            p.add_tools(drawn.hover)
        else:
            drawn.hover.renderers, drawn.hover.tooltips = hover, tips
    elif drawn.hover is not None:
        drawn.hover.renderers = []

    p.title.text = spec.title
    _log_ticks(drawn, spec)
    if spec.images:
        im = spec.images[0]
        p.x_range.start, p.x_range.end = im.x0 * spec.x.factor, im.x1 * spec.x.factor
        p.y_range.start, p.y_range.end = im.y0 * spec.y.factor, im.y1 * spec.y.factor
        for k, img in enumerate(spec.images):
            slot = drawn.slots[("image", k, img.palette, img.value.label, 0)]
            slot.mapper.low, slot.mapper.high = _limits(img.value.show(img.z))
    elif not spec.discs:
        if spec.x.limits is not None:
            p.x_range.start, p.x_range.end = _range(spec.x, np.concatenate(
                [np.asarray(ln.x, float).ravel() * spec.x.factor for ln in (*spec.lines, *spec.fills)]
                or [np.empty(0)]))
        if spec.y.limits is not None:
            p.y_range.start, p.y_range.end = _range(spec.y, _values(spec, False))
    if spec.y2 is not None:
        right = p.extra_y_ranges["right"]
        right.start, right.end = _range(spec.y2, _values(spec, True)) or (0.0, 1.0)


def adds_models(drawn: Drawn | None, spec: PlotSpec) -> bool:
    """Whether showing ``spec`` in ``drawn`` adds models to the document (a new figure, a new
    slot, the first hover): each such change makes Bokeh walk the whole document, so a caller
    updating several figures holds the walks to one (:meth:`DocumentModelManager.freeze`)."""
    if drawn is None or _frame(spec, *drawn.frame[-2:]) != drawn.frame:
        return True
    keys = [key for key, _, _ in _slots(spec)]
    return any(k not in drawn.slots for k in keys) or (drawn.hover is None and any(k[0] == "line" for k in keys))


def update_figure(drawn: Drawn, spec: PlotSpec) -> bool:
    """Put ``spec`` into the figure of ``drawn`` if it has the same frame (axes' quantities, units
    and scales; a map's aspect): its data, legend, title and ranges in place, series added or
    hidden as the spec has them. ``False`` when the figure must be rebuilt."""
    height, width = drawn.frame[-2:]
    if _frame(spec, height, width) != drawn.frame:
        return False
    _show(drawn, spec)
    return True


def figure_content(drawn: Drawn) -> dict[str, Any]:
    """What the figure shows, as plain values: title, axes, ranges, ticks, legend, and per visible
    glyph its kind, style and data in drawing order (an updated figure and a fresh one of the same
    spec give the same content; the tests and the benchmark compare them)."""
    p = drawn.figure

    def plain(v: Any) -> Any:
        if isinstance(v, np.ndarray):
            return [plain(x) for x in v.tolist()] if v.dtype != object else [plain(x) for x in v]
        if isinstance(v, (list, tuple)):
            return [plain(x) for x in v]
        if isinstance(v, float) and v != v:
            return "nan"
        return v

    glyphs = []
    for r in p.renderers:
        if not r.visible:
            continue
        g = r.glyph
        style = {k: plain(getattr(g, k)) for k in ("line_color", "line_dash", "line_width", "fill_color", "size",
                                                  "marker") if hasattr(g, k)}
        glyphs.append({"glyph": type(g).__name__, "style": repr(style), "range": r.y_range_name,
                       "data": {k: plain(v) for k, v in sorted(r.data_source.data.items())}})
    extras = []
    for m in (*p.center, *p.right):
        if getattr(m, "visible", True) and type(m).__name__ in ("LabelSet", "ColorBar"):
            src = getattr(m, "source", None)
            extras.append((type(m).__name__, None if src is None else {k: plain(v) for k, v in src.data.items()},
                           getattr(getattr(m, "color_mapper", None), "low", None),
                           getattr(getattr(m, "color_mapper", None), "high", None)))
    shown = [r for r in p.renderers if r.visible]  # indices below: in the drawing order of what is shown
    legend = [(getattr(it.label, "value", None), [shown.index(r) if r in shown else None for r in it.renderers])
              for lg in p.legend for it in lg.items] if p.legend else []
    ticks = [(getattr(ax.ticker, "ticks", None), getattr(ax.ticker, "minor_ticks", None)) for ax in (*p.xaxis,
                                                                                                   *p.yaxis)]
    ranges = [(getattr(r, "start", None), getattr(r, "end", None)) for r in (p.x_range, p.y_range,
                                                                             *p.extra_y_ranges.values())]
    hover = [(t.tooltips if isinstance(t.tooltips, str) else [tuple(x) for x in t.tooltips],
              sorted(shown.index(r) for r in t.renderers if r.visible))
             for t in p.tools if type(t).__name__ == "HoverTool" and t.renderers and
             any(r.visible for r in t.renderers)]
    return {"title": p.title.text, "glyphs": glyphs, "extras": extras, "legend": legend, "ticks": ticks,
            "ranges": ranges, "hover": hover}


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
        if ticks is None:
            continue
        ticker = bk_axis[0].ticker if len(bk_axis) else None
        if isinstance(ticker, FixedTicker):  # a new ticker model per update costs the page a model
            ticker.ticks, ticker.minor_ticks = ticks[0], ticks[1]
        else:
            bk_axis.ticker = FixedTicker(ticks=ticks[0], minor_ticks=ticks[1])
