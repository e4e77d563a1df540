"""Plot specifications: what a plot of the explorer shows, independent of how it is drawn.

Every plot of the explorer is first a :class:`PlotSpec` (lines, reference lines, contact-state
bands, images, zone discs, with axis labels and units). The same spec is drawn in the browser by
:mod:`.render_bokeh`, saved as PNG/SVG by :mod:`.render_mpl`, and written as data by
:func:`spec_csv` and :func:`spec_json`: so a download carries exactly the numbers on the screen.

Nothing here computes physics; the builders in :mod:`.builders` fill specs from the library's
results.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Band", "Disc", "Image", "Line", "PlotSpec", "VLine", "spec_csv", "spec_json"]

#: Fill colours of the contact states at the pad centre (as in fingerpad.plotting.prediction).
STATE_FILL = {"asperity": "#dbe9f6", "transition": "#fde3c8", "full": "#f7c9c9"}
#: Line colours of the contact states (as in fingerpad.plotting.solution).
STATE_COLOURS = {"asperity": "#1f77b4", "transition": "#ff7f0e", "full": "#d62728"}
#: Colours of pinned designs in the comparison.
DESIGN_COLOURS = ("#d62728", "#1f77b4", "#2ca02c", "#9467bd")


@dataclass
class Line:
    """A data series drawn as a line (and/or markers).

    ``name`` is its legend entry and its column in the CSV; ``x``/``y`` are in the plot's units
    (as labelled on the axes).
    """

    name: str
    x: np.ndarray
    y: np.ndarray
    color: str = "#d62728"
    dash: str = "solid"  # solid | dashed | dotted
    width: float = 2.0
    markers: bool = False
    line: bool = True
    axis: str = "left"  # left | right (secondary y axis)
    tooltips: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass
class VLine:
    """A vertical reference line (a critical load, a state pressure)."""

    x: float
    label: str
    color: str = "black"
    dash: str = "solid"


@dataclass
class Band:
    """A shaded x-interval: the contact state at the pad centre over a load range."""

    x0: float
    x1: float
    state: str


@dataclass
class Image:
    """A map on a regular grid: ``z[j, i]`` at ``x0 + (i + 1/2) dx``, ``y0 + (j + 1/2) dy``."""

    z: np.ndarray
    x0: float
    x1: float
    y0: float
    y1: float
    label: str
    palette: str = "viridis"  # viridis | greys | contact
    overlay: np.ndarray | None = None  # boolean mask drawn over z (contact)


@dataclass
class Disc:
    """A zone of the ridge-contact disc: the disc of ``radius`` filled with its state colour."""

    radius: float
    state: str
    label: str


@dataclass
class PlotSpec:
    """One plot: its data and how to label it.

    Attributes
    ----------
    key
        Short identifier, used in file names (``fingerpad-<key>.csv``) and element ids.
    title, x_label, y_label, y2_label
        Texts; labels carry units, e.g. ``"normal load F (N)"``.
    x_log, y_log
        Logarithmic axes.
    lines, vlines, bands, images, discs
        The content.
    y_range, y2_range
        Fixed y ranges (``None``: automatic).
    equal_aspect
        Same scale on x and y (maps).
    meta
        Extra values written to the JSON (units, inputs, notes).
    """

    key: str
    title: str
    x_label: str
    y_label: str
    x_log: bool = False
    y_log: bool = False
    lines: list[Line] = field(default_factory=list)
    vlines: list[VLine] = field(default_factory=list)
    bands: list[Band] = field(default_factory=list)
    images: list[Image] = field(default_factory=list)
    discs: list[Disc] = field(default_factory=list)
    y_range: tuple[float, float] | None = None
    y2_label: str | None = None
    y2_range: tuple[float, float] | None = None
    equal_aspect: bool = False
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def empty(self) -> bool:
        return not (self.lines or self.images or self.discs)


def _num(v: Any) -> Any:
    """A JSON-safe number (NaN and infinities as None / strings)."""
    if isinstance(v, (np.integer,)):
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


def spec_json(spec: PlotSpec) -> str:
    """The plot's data as JSON text: every series, reference line, band, image and disc."""
    payload: dict[str, Any] = {
        "plot": spec.key,
        "title": spec.title,
        "x_label": spec.x_label,
        "y_label": spec.y_label,
        "x_log": spec.x_log,
        "y_log": spec.y_log,
        "series": [
            {"name": ln.name, "axis": ln.axis, "x": _list(ln.x), "y": _list(ln.y),
             **{k: [_num(v) if not isinstance(v, str) else v for v in np.asarray(t).tolist()]
                for k, t in ln.tooltips.items()}}
            for ln in spec.lines
        ],
        "reference_lines": [{"x": _num(v.x), "label": v.label} for v in spec.vlines],
        "state_bands": [{"from": _num(b.x0), "to": _num(b.x1), "state": b.state} for b in spec.bands],
        "images": [
            {"label": im.label, "x_range": [_num(im.x0), _num(im.x1)], "y_range": [_num(im.y0), _num(im.y1)],
             "shape": list(np.asarray(im.z).shape), "z": np.where(np.isfinite(im.z), im.z, np.nan).tolist(),
             **({"contact": np.asarray(im.overlay, bool).astype(int).tolist()} if im.overlay is not None else {})}
            for im in spec.images
        ],
        "zones": [{"radius": _num(d.radius), "state": d.state, "label": d.label} for d in spec.discs],
        "meta": spec.meta,
    }
    if spec.y2_label:
        payload["y2_label"] = spec.y2_label
    text = json.dumps(payload, indent=1, default=_num, allow_nan=False)
    return text + "\n"


def _shared_x(lines: list[Line]) -> bool:
    if not lines:
        return False
    x0 = np.asarray(lines[0].x, float)
    return all(np.asarray(ln.x, float).shape == x0.shape and np.array_equal(np.asarray(ln.x, float), x0)
               for ln in lines)


def spec_csv(spec: PlotSpec) -> str:
    """The plot's data as CSV text.

    Lines sharing one x: one column per series (``x_label, name1, name2, ...``); otherwise long
    form (``series, x, y``). Images: ``x, y, value`` (and ``contact``) per pixel; zone discs:
    ``zone, outer_radius``. Headers carry the units of the axis labels.
    """
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")

    def cell(v: Any) -> Any:
        v = _num(v)
        return "" if v is None else repr(v) if isinstance(v, float) else v

    if spec.lines:
        if _shared_x(spec.lines):
            extra = {k: t for ln in spec.lines for k, t in ln.tooltips.items()}
            w.writerow([spec.x_label] + [f"{ln.name} [{spec.y2_label if ln.axis == 'right' else spec.y_label}]"
                                          for ln in spec.lines] + list(extra))
            for i, x in enumerate(np.asarray(spec.lines[0].x).tolist()):
                w.writerow([cell(x)] + [cell(np.asarray(ln.y)[i]) for ln in spec.lines]
                           + [cell(np.asarray(t)[i]) for t in extra.values()])
        else:
            w.writerow(["series", spec.x_label, spec.y_label])
            for ln in spec.lines:
                for x, y in zip(np.asarray(ln.x).tolist(), np.asarray(ln.y).tolist(), strict=True):
                    w.writerow([ln.name, cell(x), cell(y)])
    for im in spec.images:
        z = np.asarray(im.z, float)
        ny, nx = z.shape
        xs = im.x0 + (np.arange(nx) + 0.5) * (im.x1 - im.x0) / nx
        ys = im.y0 + (np.arange(ny) + 0.5) * (im.y1 - im.y0) / ny
        header = [spec.x_label, spec.y_label, im.label] + (["contact"] if im.overlay is not None else [])
        w.writerow(header)
        for j in range(ny):
            for i in range(nx):
                row = [cell(xs[i]), cell(ys[j]), cell(z[j, i])]
                if im.overlay is not None:
                    row.append(int(bool(im.overlay[j, i])))
                w.writerow(row)
    if spec.discs:
        w.writerow(["zone", f"outer radius [{spec.x_label}]"])
        for d in spec.discs:
            w.writerow([d.state, cell(d.radius)])
    return out.getvalue()
