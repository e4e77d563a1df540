"""The design-map view (``fingerpad explore --sweep RESULTS.zarr``): the sweep's map over two
axes, values on hover, a click opens the design in the single-texture view; the inverse-design
form lists the designs meeting a target.

The store is read through :mod:`..sweepdata` (the reading API of the sweep issue).
"""

from __future__ import annotations

import csv
import html
import io
import json
import math
from typing import Any

import lazy_loader
import numpy as np

pn = lazy_loader.load("panel")

from ...errors import FingerpadError, one_line
from .. import sweepdata as sd
from .common import download, fmt, guard_choices, html_pane, html_table

__all__ = ["MapView", "map_table"]

_QUANTITIES = {"critical load (N)": "critical_load", "mu / mu_ref at the load": "mu_rel", "region": "region",
               "telling it from the reference at the load": "tell_flat"}
_NAMES = {v: k for k, v in _QUANTITIES.items()}
_REGION_COLOURS = ("#f7c9c9", "#fde3c8", "#dbe9f6")


#: Axes stored in SI are shown in the unit a designer reads (lengths in um); downloads stay SI.
_SHOWN_UNITS = {"m": (1e6, "um")}


def _shown(info: dict[str, Any]) -> tuple[float, str]:
    """Factor from the stored (SI) unit of an axis to the unit shown, and the shown unit."""
    return _SHOWN_UNITS.get(info["units"], (1.0, info["units"])) if info["numeric"] else (1.0, info["units"])


def _edges(values: np.ndarray, log: bool) -> tuple[np.ndarray, np.ndarray]:
    """Cell edges around sorted centres (geometric midpoints on a log axis)."""
    v = np.asarray(values, float)
    if v.size == 1:
        return (v / 1.5, v * 1.5) if log else (v - 0.5 * max(abs(v[0]), 1e-12), v + 0.5 * max(abs(v[0]), 1e-12))
    mid = np.sqrt(v[1:] * v[:-1]) if log else 0.5 * (v[1:] + v[:-1])
    first = v[0] ** 2 / mid[0] if log else 2 * v[0] - mid[0]
    last = v[-1] ** 2 / mid[-1] if log else 2 * v[-1] - mid[-1]
    return np.concatenate([[first], mid]), np.concatenate([mid, [last]])


def marker_items(axes: Any) -> list[dict[str, Any]]:
    """The literature's and perception's markers that fall inside the map, in the units shown
    (:data:`fingerpad.design.designmap.MARKERS`, as the command's map draws them): lines
    ``{"kind": "line", "value", "vertical", "label"}`` (160 µm felt smooth, the interlocking
    heights, lambda = v / 250 Hz at 50 mm/s) and bands ``{"kind": "band", "low", "high",
    "vertical", "label"}`` (the fingerprint ridge band), on length axes whose name matches. The
    one list that the page's map and its PNG/SVG download both draw."""
    from ...design.designmap import MARKERS

    items: list[dict[str, Any]] = []
    for name, info, factor, values, vertical in axes:
        if not info["numeric"] or info["units"] != "m" or not len(values):
            continue
        lo, hi = float(np.min(values)) * factor, float(np.max(values)) * factor
        for fragment, value, label in MARKERS["lines"]:
            v = value * factor
            if fragment in name and lo <= v <= hi:
                items.append({"kind": "line", "value": v, "vertical": vertical, "label": label})
        for fragment, low, high, label in MARKERS["bands"]:
            a, b = low * factor, high * factor
            if fragment in name and a < hi and b > lo:
                items.append({"kind": "band", "low": max(a, lo), "high": min(b, hi), "vertical": vertical,
                              "label": label})
    return items


def _markers(p: Any, axes: Any) -> None:
    """Draw :func:`marker_items` on the Bokeh map: dashed lines with their labels, grey bands."""
    from bokeh.models import BoxAnnotation, Label, Span

    for item in marker_items(axes):
        vertical, label = item["vertical"], item["label"]
        if item["kind"] == "line":
            v = item["value"]
            p.add_layout(Span(location=v, dimension="height" if vertical else "width", line_dash="dashed",
                              line_color="#333333", line_width=1, name=f"marker-{label}"))
            p.add_layout(Label(x=v, y=5, x_units="data", y_units="screen", text=label, angle=math.pi / 2,
                               text_font_size="9px", text_color="#333333") if vertical else
                         Label(x=5, y=v, x_units="screen", y_units="data", text=label, text_font_size="9px",
                               text_color="#333333"))
        else:
            a, b = item["low"], item["high"]
            box = dict(left=a, right=b) if vertical else dict(bottom=a, top=b)
            p.add_layout(BoxAnnotation(**box, fill_color="#888888", fill_alpha=0.15, name=f"marker-{label}"))


def map_table(md: Any, x: str, y: str) -> list[dict[str, Any]]:
    """One row per design of a map (what the hover shows, what the downloads carry)."""
    rows = []
    grid = "point" not in md.dims
    if grid:
        xs, ys = np.asarray(md[x].values), np.asarray(md[y].values)
        for j in range(ys.size):
            for i in range(xs.size):
                rows.append({"i": i, "j": j, x: xs[i].item(), y: ys[j].item(),
                             **{k: _val(md[k].values[j, i]) for k in ("critical_load", "mu_rel", "region", "valid")},
                             "tell_flat": _val(md["tell_flat"].values[j, i]) if "tell_flat" in md else None,
                             "reason": str(md["reason"].values[j, i]) if "reason" in md else ""})
    else:
        for n in range(md.sizes["point"]):
            rows.append({"i": n, "j": n, x: _val(md[x].values[n]), y: _val(md[y].values[n]),
                         **{k: _val(md[k].values[n]) for k in ("critical_load", "mu_rel", "region", "valid")},
                         "tell_flat": _val(md["tell_flat"].values[n]) if "tell_flat" in md else None,
                         "reason": str(md["reason"].values[n]) if "reason" in md else ""})
    return rows


def base_study_html(ds: Any) -> str:
    """The sweep's base study as the study file it reads as (TOML), folded under a summary."""
    from ..inputs import to_toml

    base = ds.attrs.get("study")
    try:
        data = json.loads(base) if isinstance(base, str) else dict(base or {})
        text = to_toml({k: v for k, v in data.items() if isinstance(v, dict) and not k.startswith("_")})
        text = "\n".join(line for line in text.splitlines() if not line.startswith("# ")).strip()
    except (ValueError, TypeError, FingerpadError):
        text = str(base)
    return ("<details class='fp-map-study' style='font-size:12px'><summary>base study (the values the axes do "
            f"not set)</summary><pre style='margin:2px 0;font-size:11px'>{html.escape(text)}</pre></details>")


def reference_options(ds: Any) -> dict[str, Any]:
    """The references a map can tell its designs from: ``flat``, then every possible texture of
    the store by its axis values (the value: its point number,
    :func:`fingerpad.design.designmap.store_point`)."""
    grid = "point" not in ds.dims
    axes = sd.sweep_axes(ds)
    dims = axes if grid else ["point"]
    shape = tuple(int(ds.sizes[d]) for d in dims)
    valid = np.asarray(ds["valid"].transpose(*dims).values, bool).ravel()
    options: dict[str, Any] = {"flat": "flat"}
    for n in np.flatnonzero(valid):
        index = dict(zip(axes, (int(i) for i in np.unravel_index(int(n), shape)), strict=True)) if grid else int(n)
        values = sd.design_values(ds, index)
        shown = []
        for k, v in values.items():
            factor, unit = _shown(sd.axis_info(ds, k))
            shown.append(f"{k} {fmt(float(v) * factor)} {unit}".strip() if isinstance(v, (int, float)) else f"{k} {v}")
        options[f"#{int(n)}: " + ", ".join(shown)] = int(n)
    return options


def colour_label(quantity: str, at: float, reference: str = "flat") -> str:
    """The colour bar's title: the quantity with its unit (and the load of mu / mu_ref)."""
    if quantity == "mu_rel":
        return f"mu / mu_ref at {at:.4g} N (-)"
    if quantity == "tell_flat":
        return f"telling it from {reference} at {at:.4g} N (fraction of fingers, or P)"
    if quantity == "region":
        return "region at the load: " + ", ".join(f"{k} {v}" for k, v in sorted(sd.REGIONS.items()))
    return _NAMES[quantity]


def _val(v: Any) -> Any:
    return v.item() if isinstance(v, np.generic) else v


class MapView:
    """The design map of one sweep store."""

    def __init__(self, app: Any, ds: Any, path: str) -> None:
        self.app = app
        self.ds = ds
        self.path = path
        self.axes = sd.sweep_axes(ds)
        loads = np.asarray(ds["load"].values, float)
        self.load_options = {f"{v:.4g} N": float(v) for v in loads}
        at = sd.default_load(ds)
        self.x = pn.widgets.Select(label="x axis", options=self.axes, value=self.axes[0], css_classes=["fp-map-x"])
        self.y = pn.widgets.Select(label="y axis", options=self.axes, value=self.axes[1 % len(self.axes)],
                                   css_classes=["fp-map-y"])
        self.quantity = pn.widgets.Select(label="colour", options=_QUANTITIES, value="critical_load",
                                          css_classes=["fp-map-quantity"])
        self.at = pn.widgets.Select(label="load for mu / mu_ref", options=self.load_options, value=at,
                                    css_classes=["fp-map-at"])
        self.reference = pn.widgets.Select(label="tell apart from", options=reference_options(ds), value="flat",
                                           css_classes=["fp-map-reference"])
        self.fixed = {a: pn.widgets.Select(label=f"{a} (fixed)", options=self._axis_options(a),
                                           css_classes=[f"fp-map-fixed-{a}"]) for a in self.axes}
        self.fixed_box = pn.Column(margin=0)
        self.plot = pn.pane.Bokeh(None, css_classes=["fp-plot-design-map"], min_height=480, sizing_mode="stretch_width")
        self.info = html_pane("", css_classes=["fp-map-info"], sizing_mode="stretch_width")
        self.message = html_pane("", css_classes=["fp-map-message"], sizing_mode="stretch_width")
        self.md: Any = None
        self.rows: list[dict[str, Any]] = []
        for w in (self.x, self.y, self.quantity, self.at, self.reference, *self.fixed.values()):
            guard_choices(w)
            w.param.watch(lambda e: self.redraw(), "value")
        # inverse design
        self.target = pn.widgets.TextInput(label="target mu / mu_ref", value="0.8", css_classes=["fp-inv-target"])
        self.tolerance = pn.widgets.TextInput(label="tolerance (+/-)", value="0.05", css_classes=["fp-inv-tol"])
        self.inv_at = pn.widgets.Select(label="at load", options=self.load_options, value=at, css_classes=["fp-inv-at"])
        self.min_crit = pn.widgets.TextInput(label="minimum critical load (N)", value="", placeholder="none",
                                             css_classes=["fp-inv-mincrit"])
        self.find = pn.widgets.Button(label="Find designs", color="primary", css_classes=["fp-inv-find"])
        self.candidates = html_pane("", css_classes=["fp-inv-results"], sizing_mode="stretch_width")
        self.pick = pn.widgets.Select(label="candidate", options={}, css_classes=["fp-inv-pick"])
        guard_choices(self.inv_at)
        guard_choices(self.pick)
        self.open_pick = pn.widgets.Button(label="Open in the texture view", css_classes=["fp-inv-open"],
                                           disabled=True)
        self.find.on_click(lambda e: self.rank())
        self.open_pick.on_click(lambda e: self.open_candidate())
        self._candidates: list[dict[str, Any]] = []
        downloads = pn.Row(pn.pane.HTML("<span style='font-size:12px'>download:</span>", margin=(6, 4)),
                           download("CSV", "fingerpad-design-map.csv", self.csv, "fp-dl-design-map-csv"),
                           download("JSON", "fingerpad-design-map.json", self.json, "fp-dl-design-map-json"),
                           download("PNG", "fingerpad-design-map.png", lambda: self.image("png"),
                                    "fp-dl-design-map-png"),
                           download("SVG", "fingerpad-design-map.svg", lambda: self.image("svg"),
                                    "fp-dl-design-map-svg"))
        self.panel = pn.Row(
            pn.Column(
                pn.pane.HTML(f"<div style='font-size:12px'>sweep <code>{html.escape(path)}</code>, design "
                             f"{html.escape(str(ds.attrs.get('design', '?')))}, axes {html.escape(', '.join(self.axes))}"
                             f"</div>{base_study_html(ds)}", css_classes=["fp-map-about"]),
                self.x, self.y, self.quantity, self.at, self.reference, self.fixed_box,
                pn.pane.HTML("<h4 style='margin:8px 0 2px'>Inverse design</h4><div style='font-size:12px'>designs "
                             "whose mu / mu_ref at the load is within the tolerance of the target</div>"),
                self.target, self.tolerance, self.inv_at, self.min_crit, self.find, self.pick, self.open_pick,
                width=320,
            ),
            pn.Column(self.message, self.plot, downloads, self.info, self.candidates, sizing_mode="stretch_width"),
            sizing_mode="stretch_width", css_classes=["fp-map"],
        )
        self.redraw()

    def _axis_options(self, name: str) -> dict[str, Any]:
        info = sd.axis_info(self.ds, name)
        vals = np.asarray(info["values"])
        return {f"{fmt(v) if info['numeric'] else v} {info['units']}".strip(): _val(v) for v in vals}

    # ------------------------------------------------------------------ the map

    def redraw(self) -> None:
        x, y = self.x.value, self.y.value
        others = [a for a in self.axes if a not in (x, y)]
        self.fixed_box.objects = [self.fixed[a] for a in others] if "point" not in self.ds.dims else []
        try:
            self.md = sd.map_data(self.ds, x, y, at=self.at.value,
                                  select={a: self.fixed[a].value for a in others} if "point" not in self.ds.dims
                                  else None, reference=self.reference.value)
        except FingerpadError as exc:
            self.message.object = f"<div class='fp-error' style='color:#b00020'>{html.escape(one_line(str(exc)))}</div>"
            self.plot.object = None
            return
        self.message.object = ""
        self.rows = map_table(self.md, x, y)
        self.plot.object = self._figure()

    def _figure(self) -> Any:
        from bokeh.models import ColorBar, ColumnDataSource, HoverTool, LinearColorMapper, LogColorMapper, TapTool
        from bokeh.palettes import Viridis256
        from bokeh.plotting import figure

        md, x, y, q = self.md, self.x.value, self.y.value, self.quantity.value
        grid = "point" not in md.dims
        xi, yi = sd.axis_info(self.ds, x), sd.axis_info(self.ds, y)
        data: dict[str, list[Any]] = {k: [] for k in ("left", "right", "bottom", "top", "xc", "yc", "value", "crit",
                                                      "mu", "region", "valid", "reason", "i", "j")}
        xs = np.asarray(md[x].values)
        ys = np.asarray(md[y].values)
        (fx, ux), (fy, uy) = _shown(xi), _shown(yi)
        xpos = xs.astype(float) * fx if xi["numeric"] else np.arange(xs.size, dtype=float)
        ypos = ys.astype(float) * fy if yi["numeric"] else np.arange(ys.size, dtype=float)
        xlog, ylog = xi["log"] and xi["numeric"], yi["log"] and yi["numeric"]
        if grid:
            xl, xr = _edges(xpos, xlog)
            yb, yt = _edges(ypos, ylog)
        for row in self.rows:
            i, j = row["i"], row["j"]
            if grid:
                data["left"].append(xl[i]), data["right"].append(xr[i])
                data["bottom"].append(yb[j]), data["top"].append(yt[j])
                data["xc"].append(xpos[i]), data["yc"].append(ypos[j])
            else:
                data["xc"].append(float(row[x]) * fx), data["yc"].append(float(row[y]) * fy)
                for k in ("left", "right", "bottom", "top"):
                    data[k].append(math.nan)
            v = row[q]
            data["value"].append(math.nan if v is None else float(v))
            data["crit"].append(fmt(row["critical_load"]))
            data["mu"].append(fmt(row["mu_rel"]))
            data.setdefault("tell", []).append(fmt(row["tell_flat"]) if row.get("tell_flat") is not None else "-")
            data["region"].append(sd.REGIONS.get(int(row["region"]), "-") if row["region"] is not None and
                                  not math.isnan(float(row["region"])) else "-")
            data["valid"].append("yes" if row["valid"] else f"no: {row['reason']}")
            data["reason"].append(row["reason"])
            data["i"].append(i), data["j"].append(j)
        data["xlabel"] = [f"{fmt(r[x] * fx)} {ux}" if xi["numeric"] else str(r[x]) for r in self.rows]
        data["ylabel"] = [f"{fmt(r[y] * fy)} {uy}" if yi["numeric"] else str(r[y]) for r in self.rows]
        src = ColumnDataSource(data)
        vals = np.asarray(data["value"], float)
        fin = vals[np.isfinite(vals)]
        if q == "tell_flat":  # a fraction or a probability: the whole of [0, 1], not the range shown
            mapper = LinearColorMapper(palette=Viridis256, low=0.0, high=1.0, nan_color="#dddddd")
        elif q == "region":
            mapper = LinearColorMapper(palette=list(_REGION_COLOURS), low=-0.5, high=2.5, nan_color="#dddddd")
        elif q == "critical_load" and fin.size and fin.min() > 0:
            mapper = LogColorMapper(palette=Viridis256, low=float(fin.min()), high=float(max(fin.max(), fin.min() * 1.01)),
                                    nan_color="#dddddd")
        else:
            lo, hi = (float(fin.min()), float(fin.max())) if fin.size else (0.0, 1.0)
            mapper = LinearColorMapper(palette=Viridis256, low=lo, high=hi if hi > lo else lo + 1, nan_color="#dddddd")
        p = figure(name="design-map", height=480, sizing_mode="stretch_width",
                   x_axis_type="log" if xlog else "linear", y_axis_type="log" if ylog else "linear",
                   x_axis_label=f"{x} ({ux})", y_axis_label=f"{y} ({uy})",
                   title=f"design map: {_NAMES[q]} (mu / mu_ref at {md.attrs['at']:.4g} N); click a design to open it",
                   tools="pan,wheel_zoom,box_zoom,reset,save,tap")
        p.toolbar.logo = None
        fill = {"field": "value", "transform": mapper}
        if grid:
            r = p.quad(left="left", right="right", bottom="bottom", top="top", source=src, fill_color=fill,
                       line_color="white", line_width=0.5, selection_line_color="black", selection_line_width=2,
                       nonselection_fill_alpha=0.8)
        else:
            r = p.scatter("xc", "yc", source=src, size=14, fill_color=fill, line_color="black",
                          nonselection_fill_alpha=0.8)
        if not xi["numeric"]:
            p.xaxis.ticker = list(range(xs.size))
            p.xaxis.major_label_overrides = {k: str(v) for k, v in enumerate(xs)}
        if not yi["numeric"]:
            p.yaxis.ticker = list(range(ys.size))
            p.yaxis.major_label_overrides = {k: str(v) for k, v in enumerate(ys)}
        p.add_tools(HoverTool(renderers=[r], tooltips=[(x, "@xlabel"), (y, "@ylabel"), ("critical load (N)", "@crit"),
                                                        ("mu / mu_ref", "@mu"), ("region", "@region"),
                                                        (f"telling it from {self._reference_name()}", "@tell"),
                                                        ("valid", "@valid")]))
        _markers(p, ((x, xi, fx, xs, True), (y, yi, fy, ys, False)))
        p.select_one(TapTool).renderers = [r]
        p.add_layout(ColorBar(color_mapper=mapper, title=colour_label(q, md.attrs["at"], self._reference_name()),
                               width=12), "right")
        src.selected.on_change("indices", self._tapped)
        return p

    def _reference_name(self) -> str:
        ref = self.reference.value
        return "flat" if ref == "flat" else f"design #{ref}"

    def _tapped(self, attr: str, old: Any, new: Any) -> None:
        # the indices come from the client: only a row of the map shown opens
        try:
            index = int(new[0]) if new else -1
        except (TypeError, ValueError):
            return
        if 0 <= index < len(self.rows):
            self.open_row(self.rows[index])

    def _index(self, row: dict[str, Any]) -> Any:
        if "point" in self.ds.dims:
            return int(row["i"])
        x, y = self.x.value, self.y.value
        index = {}
        for a in self.axes:
            values = list(np.asarray(self.ds[a].values))
            if a == x:
                index[a] = values.index(row[x]) if row[x] in values else int(row["i"])
            elif a == y:
                index[a] = values.index(row[y]) if row[y] in values else int(row["j"])
            else:
                index[a] = values.index(self.fixed[a].value)
        return index

    def open_row(self, row: dict[str, Any]) -> None:
        values = sd.design_values(self.ds, self._index(row))
        self.open_values(values, row.get("critical_load"), row.get("mu_rel"))

    def open_values(self, values: dict[str, Any], crit: Any = None, mu: Any = None) -> None:
        data = sd.design_data(self.ds, values)
        shown = []
        for k, v in values.items():  # as the map shows them (lengths in um)
            factor, unit = _shown(sd.axis_info(self.ds, k))
            shown.append(f"{k} = {fmt(float(v) * factor)} {unit}".strip() if isinstance(v, (int, float))
                         and not isinstance(v, bool) else f"{k} = {v}")
        self.info.object = (f"<div class='fp-map-opened' style='font-size:12px'>opened "
                            f"{html.escape(', '.join(shown))} "
                            f"(critical load {fmt(crit)} N, mu/mu_ref {fmt(mu)}) in the texture view</div>")
        self.app.open_design(data)

    # ------------------------------------------------------------------ inverse design

    def rank(self) -> None:
        from ...study.values import quantity

        try:
            target = quantity(self.target.value, "none", "target mu / mu_ref")
            tol = quantity(self.tolerance.value, "none", "tolerance")
            mc = self.min_crit.value.strip()
            min_crit = quantity(mc, "force", "minimum critical load") if mc else None
            if tol < 0:
                raise FingerpadError("tolerance: must not be negative")
            found = sd.rank_sweep(self.ds, {"mu_rel": target, "at": self.inv_at.value, "tolerance": tol},
                                  min_critical_load=min_crit)
        except FingerpadError as exc:
            self.candidates.object = f"<div class='fp-error' style='color:#b00020'>{html.escape(one_line(str(exc)))}</div>"
            return
        self._candidates = found
        if not found:
            self.candidates.object = "<div class='fp-inv-none'>no design of the sweep meets the target</div>"
            self.pick.options, self.open_pick.disabled = {}, True
            return
        cols = [("rank", "#"), *((a, a) for a in self.axes), ("critical_load", "critical load (N)"),
                ("mu_rel", f"mu/mu_ref at {found[0]['at']:.4g} N")]
        rows = [{"rank": str(k + 1), **c} for k, c in enumerate(found)]
        self.candidates.object = f"<div style='font-size:12px'>{len(found)} candidate(s), best first</div>" + \
            html_table(cols, rows, "fp-inv-table")
        self.pick.options = {f"#{k + 1}: " + ", ".join(f"{a}={fmt(c[a]) if not isinstance(c[a], str) else c[a]}"
                                                        for a in self.axes): k for k, c in enumerate(found)}
        self.pick.value = 0
        self.open_pick.disabled = False

    def open_candidate(self) -> None:
        if not self._candidates or self.pick.value is None:
            return
        c = self._candidates[int(self.pick.value)]
        self.open_values({a: c[a] for a in self.axes}, c["critical_load"], c["mu_rel"])

    # ------------------------------------------------------------------ downloads

    def csv(self) -> str:
        out = io.StringIO()
        x, y = self.x.value, self.y.value
        cols = [x, y, "critical_load", "mu_rel", "region", "valid", "reason"]
        w = csv.writer(out, lineterminator="\n")
        w.writerow([f"{x} ({sd.axis_info(self.ds, x)['units']})", f"{y} ({sd.axis_info(self.ds, y)['units']})",
                    "critical_load_N", f"mu_rel_at_{self.md.attrs['at']:.6g}N", "region", "valid", "reason"])
        for r in self.rows:
            w.writerow(["" if r[c] is None else repr(r[c]) if isinstance(r[c], float) else r[c] for c in cols])
        return out.getvalue()

    def json(self) -> str:
        payload = {"sweep": self.path, "x": self.x.value, "y": self.y.value, "at_N": self.md.attrs["at"],
                   "tell_apart_from": self._reference_name(), "regions": sd.REGIONS, "designs": self.rows}
        return json.dumps(payload, indent=1, default=lambda v: None if isinstance(v, float) and math.isnan(v) else
                          _val(v)) + "\n"

    def image(self, fmt_: str) -> bytes:
        from ...plotting.render import map_image

        md, x, y, q = self.md, self.x.value, self.y.value, self.quantity.value
        xi, yi = sd.axis_info(self.ds, x), sd.axis_info(self.ds, y)
        (fx, ux), (fy, uy) = _shown(xi), _shown(yi)
        grid = "point" not in md.dims and xi["numeric"] and yi["numeric"]
        if grid:
            xs, ys = np.asarray(md[x].values, float) * fx, np.asarray(md[y].values, float) * fy
            values = np.asarray(md[q].values, float)
        else:
            xs = [float(r[x]) * fx if not isinstance(r[x], str) else r["i"] for r in self.rows]
            ys = [float(r[y]) * fy if not isinstance(r[y], str) else r["j"] for r in self.rows]
            values = [math.nan if r[q] is None else r[q] for r in self.rows]
        return map_image(xs, ys, values, grid=grid, x_label=f"{x} ({ux})", y_label=f"{y} ({uy})",
                         colour_label=colour_label(q, md.attrs["at"], self._reference_name()),
                         x_log=xi["log"], y_log=yi["log"],
                         title=f"design map: {_NAMES[q]} (mu/mu_ref at {md.attrs['at']:.4g} N)", fmt=fmt_,
                         markers=marker_items(((x, xi, fx, md[x].values, True), (y, yi, fy, md[y].values, False))))
