"""Plot specifications: what a figure shows, independent of how it is drawn.

A :class:`PlotSpec` is one panel: lines, reference lines, contact-state bands, images, zone discs
and text labels on axes that carry their quantity, SI unit and the unit shown. A
:class:`FigureSpec` is a figure of panels side by side. Every value is held in SI; an
:class:`Axis` says how it is shown (``factor``: areas in m² shown in mm² have factor 1e6).

The same spec is drawn by matplotlib (:mod:`fingerpad.plotting.render`: the PNGs of
``fingerpad predict`` and the explorer's image downloads) and by Bokeh in the browser
(:mod:`fingerpad.explore.render_bokeh`), and written as data by :func:`spec_csv` and
:func:`spec_json` in SI, the unit in every header. This module imports neither toolkit.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "DESIGN_COLOURS",
    "STATE_COLOURS",
    "STATE_FILL",
    "Axis",
    "Band",
    "Disc",
    "FigureSpec",
    "Fill",
    "HLine",
    "Image",
    "Label",
    "Line",
    "PlotSpec",
    "VLine",
    "pale",
    "spec_csv",
    "spec_json",
]

#: Fill colours of the contact states at the pad centre (bands over load or radius).
STATE_FILL = {"asperity": "#dbe9f6", "transition": "#fde3c8", "full": "#f7c9c9"}
#: Line colours of the contact states (matplotlib's tab:blue, tab:orange, tab:red).
STATE_COLOURS = {"asperity": "#1f77b4", "transition": "#ff7f0e", "full": "#d62728"}
#: Colours of overlaid designs (the explorer's comparison).
DESIGN_COLOURS = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd")


def pale(colour: str, strength: float = 0.55) -> str:
    """``colour`` (``#rrggbb``) mixed with white: ``strength`` 1 keeps it, 0 gives white."""
    c = colour.lstrip("#")
    rgb = [int(c[i:i + 2], 16) / 255.0 for i in (0, 2, 4)]
    return "#" + "".join(f"{round(255 * (1.0 - strength * (1.0 - v))):02x}" for v in rgb)


@dataclass(frozen=True)
class Axis:
    """An axis (or an image's values): a quantity, its SI unit, and how it is shown.

    ``shown``/``factor``: the unit on the plot and the factor from SI to it (mm²: 1e6);
    ``limits`` are in SI (``None`` at an end: automatic); ``log`` a logarithmic scale.
    """

    name: str
    unit: str = "-"
    shown: str | None = None
    factor: float = 1.0
    log: bool = False
    limits: tuple[float | None, float | None] | None = None

    @property
    def label(self) -> str:
        """The label on the plot, e.g. ``contact area (mm²)``."""
        return f"{self.name} ({self.shown or self.unit})"

    @property
    def si_label(self) -> str:
        """The label of the data written (SI), e.g. ``contact area (m²)``."""
        return f"{self.name} ({self.unit})"

    def show(self, values: Any) -> Any:
        """SI values in the unit shown."""
        return np.asarray(values, dtype=float) * self.factor if self.factor != 1.0 else np.asarray(values, float)


@dataclass
class Line:
    """A data series drawn as a line (and/or markers); ``x``/``y`` in SI.

    ``name`` is its legend entry and its column in the CSV; ``axis`` the y axis it belongs to.
    """

    name: str
    x: np.ndarray
    y: np.ndarray
    color: str = "#d62728"
    dash: str = "solid"  # solid | dashed | dotted | dotdash
    width: float = 1.5
    markers: bool = False
    line: bool = True
    axis: str = "left"  # left | right (secondary y axis)
    legend: bool = True  # an entry in the legend
    tooltips: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass
class Fill:
    """A shaded band between two curves over ``x`` (SI): a quantile band of a population.

    ``name`` is its legend entry; in the data it gives two series, ``name lower`` and
    ``name upper``.
    """

    name: str
    x: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    color: str = "#1f77b4"
    alpha: float = 0.25


@dataclass
class VLine:
    """A vertical reference line at ``x`` (SI): a critical load, a state pressure."""

    x: float
    label: str | None
    color: str = "black"
    dash: str = "solid"
    width: float = 0.9


@dataclass
class HLine:
    """A horizontal reference line at ``y`` (SI), without a legend entry (a ratio of 1)."""

    y: float
    color: str = "black"
    width: float = 0.8


@dataclass
class Band:
    """A shaded x-interval (SI): the contact state at the pad centre over a load or radius range."""

    x0: float
    x1: float
    state: str
    legend: bool = True


@dataclass
class Image:
    """A map on a regular grid: ``z[j, i]`` (SI) at ``x0 + (i + 1/2) dx``, ``y0 + (j + 1/2) dy``."""

    z: np.ndarray
    x0: float
    x1: float
    y0: float
    y1: float
    value: Axis
    palette: str = "viridis"  # viridis | greys
    overlay: np.ndarray | None = None  # boolean mask drawn over z (contact)


@dataclass
class Disc:
    """A disc of ``radius`` (SI) about the origin: a zone of the ridge-contact disc.

    ``fill`` ``None`` draws the outline only (``dash``).
    """

    radius: float
    state: str
    label: str | None
    fill: str | None = None
    dash: str = "solid"


@dataclass
class Label:
    """A text at ``(x, y)`` (SI), offset a few points up and right."""

    x: float
    y: float
    text: str


@dataclass
class PlotSpec:
    """One panel: its data and how to label it.

    Attributes
    ----------
    key
        Short identifier, used in file names (``fingerpad-<key>.csv``) and element ids.
    title
        The panel's title.
    x, y, y2
        The axes (``y2``: a secondary y axis on the right, for lines with ``axis="right"``).
    lines, fills, vlines, hlines, bands, images, discs, labels
        The content (``fills``: shaded bands between two curves, drawn under the lines).
    legend
        Where the legend goes (matplotlib's words: ``best``, ``lower right``, ...).
    grid
        Grid lines.
    references_first
        The reference lines (vlines) before the data in the legend.
    equal_aspect
        Same scale on x and y (maps, discs).
    meta
        Extra values written to the JSON (inputs, notes).
    """

    key: str
    title: str
    x: Axis
    y: Axis
    y2: Axis | None = None
    lines: list[Line] = field(default_factory=list)
    fills: list[Fill] = field(default_factory=list)
    vlines: list[VLine] = field(default_factory=list)
    hlines: list[HLine] = field(default_factory=list)
    bands: list[Band] = field(default_factory=list)
    images: list[Image] = field(default_factory=list)
    discs: list[Disc] = field(default_factory=list)
    labels: list[Label] = field(default_factory=list)
    legend: str = "best"
    grid: bool = True
    references_first: bool = False
    equal_aspect: bool = False
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def empty(self) -> bool:
        return not (self.lines or self.fills or self.images or self.discs)

    def axis_of(self, line: Line) -> Axis:
        """The y axis a line is drawn on."""
        return self.y2 if line.axis == "right" and self.y2 is not None else self.y


@dataclass
class FigureSpec:
    """A figure: panels side by side under one title.

    ``size`` (inches), ``width_ratios`` and ``margins`` (fractions of the figure: ``left``,
    ``right``, ``bottom``, ``top``, ``wspace``) lay out an image; a browser shows each panel
    on its own.
    """

    key: str
    title: str | None
    panels: list[PlotSpec]
    size: tuple[float, float] = (7.0, 5.0)
    width_ratios: tuple[float, ...] | None = None
    margins: dict[str, float] | None = None


def _num(v: Any) -> Any:
    """A JSON-safe number (NaN as None, infinities as strings)."""
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, (float, np.floating)):
        f = float(v)
        if math.isnan(f):
            return None
        if math.isinf(f):
            return "inf" if f > 0 else "-inf"
        return f
    if isinstance(v, np.bool_):
        return bool(v)
    return v


def _list(a: Any) -> list[Any]:
    return [_num(v) for v in np.asarray(a).ravel().tolist()]


def _axis_json(axis: Axis) -> dict[str, Any]:
    return {"label": axis.si_label, "quantity": axis.name, "unit": axis.unit, "log": axis.log}


def spec_json(spec: PlotSpec) -> str:
    """The panel's data as JSON text, in SI: every series, reference line, band, image and disc."""
    payload: dict[str, Any] = {
        "plot": spec.key,
        "title": spec.title,
        "units_system": "SI",
        "x": _axis_json(spec.x),
        "y": _axis_json(spec.y),
        **({"y2": _axis_json(spec.y2)} if spec.y2 is not None else {}),
        "series": [
            {"name": ln.name, "axis": ln.axis, "unit": spec.axis_of(ln).unit, "x": _list(ln.x), "y": _list(ln.y),
             **{k: [_num(v) if not isinstance(v, str) else v for v in np.asarray(t).tolist()]
                for k, t in ln.tooltips.items()}}
            for ln in spec.lines
        ],
        "bands": [{"name": f.name, "unit": spec.y.unit, "x": _list(f.x), "lower": _list(f.lower),
                   "upper": _list(f.upper)} for f in spec.fills],
        "reference_lines": [{"x": _num(v.x), "label": v.label} for v in spec.vlines],
        "state_bands": [{"from": _num(b.x0), "to": _num(b.x1), "state": b.state} for b in spec.bands],
        "images": [
            {"label": im.value.si_label, "unit": im.value.unit, "x_range": [_num(im.x0), _num(im.x1)],
             "y_range": [_num(im.y0), _num(im.y1)], "shape": list(np.asarray(im.z).shape),
             "z": [_list(row) for row in np.asarray(im.z, float)],
             **({"contact": np.asarray(im.overlay, bool).astype(int).tolist()} if im.overlay is not None else {})}
            for im in spec.images
        ],
        "zones": [{"radius": _num(d.radius), "state": d.state, "label": d.label} for d in spec.discs],
        "meta": spec.meta,
    }
    return json.dumps(payload, indent=1, default=_num, allow_nan=False) + "\n"


def _shared_x(lines: list[Line]) -> bool:
    if not lines:
        return False
    x0 = np.asarray(lines[0].x, float)
    return all(np.asarray(ln.x, float).shape == x0.shape and np.array_equal(np.asarray(ln.x, float), x0)
               for ln in lines)


def spec_csv(spec: PlotSpec) -> str:
    """The panel's data as CSV text, in SI with the unit in every header.

    Lines (and the two edges of each band) sharing one x: one column per series
    (``x, name1 [y], name2 [y], ...``); otherwise long form (``series, x, y``). Images:
    ``x, y, value`` (and ``contact``) per pixel; zone discs: ``zone, outer radius``.
    """
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")

    def cell(v: Any) -> Any:
        v = _num(v)
        return "" if v is None else repr(v) if isinstance(v, float) else v

    # the bands' edges are series of the y axis, after the lines
    edges = [Line(f"{f.name} {edge}", f.x, y) for f in spec.fills for edge, y in (("lower", f.lower),
                                                                                 ("upper", f.upper))]
    series = [*spec.lines, *edges]
    if series:
        if _shared_x(series):
            extra = {k: t for ln in spec.lines for k, t in ln.tooltips.items()}
            w.writerow([spec.x.si_label] + [f"{ln.name} [{spec.axis_of(ln).si_label}]" for ln in series]
                       + list(extra))
            for i, x in enumerate(np.asarray(series[0].x).tolist()):
                w.writerow([cell(x)] + [cell(np.asarray(ln.y)[i]) for ln in series]
                           + [cell(np.asarray(t)[i]) for t in extra.values()])
        else:
            w.writerow(["series", spec.x.si_label, "y", "unit of y"])
            for ln in series:
                unit = spec.axis_of(ln).unit
                for x, y in zip(np.asarray(ln.x).tolist(), np.asarray(ln.y).tolist(), strict=True):
                    w.writerow([ln.name, cell(x), cell(y), unit])
    for im in spec.images:
        z = np.asarray(im.z, float)
        ny, nx = z.shape
        xs = im.x0 + (np.arange(nx) + 0.5) * (im.x1 - im.x0) / nx
        ys = im.y0 + (np.arange(ny) + 0.5) * (im.y1 - im.y0) / ny
        w.writerow([spec.x.si_label, spec.y.si_label, im.value.si_label]
                   + (["contact"] if im.overlay is not None else []))
        for j in range(ny):
            for i in range(nx):
                row = [cell(xs[i]), cell(ys[j]), cell(z[j, i])]
                if im.overlay is not None:
                    row.append(int(bool(im.overlay[j, i])))
                w.writerow(row)
    if spec.discs:
        w.writerow(["zone", f"outer radius ({spec.x.unit})"])
        for d in spec.discs:
            w.writerow([d.state, cell(d.radius)])
    return out.getvalue()
