"""The input form of the single-texture view: one widget per study value, a message beside it.

Fields are built from the library's declarations: a texture family's :class:`~fingerpad.textures.Param`
(kind, unit, doc, default, choices), the finger's :data:`~fingerpad.finger.FINGER_FIELDS` and
presets. A field holds the text a user would type on the command line; :mod:`..inputs` turns the
form into a study and routes the library's messages back to the fields. A number field steps with
the arrow keys and, for the texture's dimensions and the zone-map load, has a slider
(:mod:`..scan` decides the step, unit, limits and range; :mod:`.scanfield` are the widgets).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

from ...errors import FingerpadError
from ...finger import FINGER_FIELDS, FINGER_PARAMS, FINGER_PRESETS
from ...materials import MATERIAL_MODULUS, MATERIAL_POISSON
from ..inputs import FINGER_LABELS, family_examples, field_label
from ..scan import (MAX_TEXT, ZONE_LOAD, Scan, scan_for, shown_unit, slider_position, slider_text, step_text,
                    value_text)
from .common import guard_choices, html_pane
from .scanfield import scan_input, scan_slider

__all__ = ["Field", "Form", "css_name"]

MEASURED = "measured map (upload)"
_DIM_UNIT = {"length": "m", "pressure": "Pa", "force": "N", "none": "-", "surface energy": "J/m2"}


def css_name(fid: str) -> str:
    """The CSS class of a field's widget, e.g. ``fp-field-texture-radius``."""
    return "fp-field-" + fid.replace(".", "-").replace("_", "-")


def _fmt_default(value: Any, dim: str) -> str:
    from ...units import format_quantity

    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if dim in ("length", "pressure", "force"):
            return format_quantity(float(value), dim).replace(" ", "")
        return f"{value:g}"
    return str(value)


def _feature_size(family: Any) -> float | None:
    """The family's smallest typical length (m): the step of a length it gives no example of."""
    from ...units import parse_quantity

    sizes = []
    for p in family.user_params():
        if p.kind == "length" and isinstance(p.example, str):
            try:
                sizes.append(parse_quantity(p.example, "length"))
            except FingerpadError:
                pass
    return min(sizes) if sizes else None


class Field:
    """One input: a widget (text, choice or checkbox) and the message shown beside it."""

    def __init__(self, fid: str, title: str, *, kind: str = "text", value: Any = "", options: Any = None,
                 placeholder: str = "", doc: str = "", scan: Scan | None = None,
                 fallback: Callable[[], float | None] | None = None) -> None:
        self.fid = fid
        css = css_name(fid)
        self.scan = scan if kind == "text" else None
        self.fallback = fallback  # the SI value an empty field stands for (a preset's, a default)
        self.slider: Any = None
        if self.scan is not None:
            self.widget = scan_input(self._step, label=title, value=str(value), placeholder=placeholder,
                                     description=doc, hint=self.scan.hint, css_classes=[css],
                                     sizing_mode="stretch_width")
            if self.scan.slider is not None:
                self.slider = scan_slider(self._slide, label=title, css_classes=[css + "-slider"],
                                          sizing_mode="stretch_width")
                self.set_slider(self.scan)
                self.widget.param.watch(lambda e: self._follow(), "value")
        elif kind == "choice":
            self.widget = guard_choices(pn.widgets.Select(label=title, options=list(options), value=value,
                                                          css_classes=[css], description=doc or None,
                                                          sizing_mode="stretch_width"))
        elif kind == "bool":
            self.widget = pn.widgets.Checkbox(label=title, value=bool(value), css_classes=[css])
        else:
            self.widget = pn.widgets.TextInput(label=title, value=str(value), placeholder=placeholder,
                                               css_classes=[css], description=doc or None,
                                               sizing_mode="stretch_width")
        self.kind = kind
        self.message = html_pane("", css_classes=[css + "-msg", "fp-msg"], margin=(0, 10, 2, 10),
                                    sizing_mode="stretch_width", visible=False)
        self.panel = pn.Column(self.widget, *([self.slider] if self.slider is not None else []), self.message,
                               margin=0, sizing_mode="stretch_width")

    @property
    def value(self) -> Any:
        return self.widget.value

    # ------------------------------------------------------------------ scanning

    def _step(self, steps: Any, text: Any) -> None:
        """``steps`` arrow-key steps from ``text`` (the page's input; empty: the value the field
        stands for). A text the field refuses is not stepped: it becomes the field's value, whose
        check then says why."""
        if self.scan is None:
            return
        text = text if isinstance(text, str) and len(text) <= MAX_TEXT else self.widget.value
        base = text
        if not base.strip() and self.fallback is not None and (value := self.fallback()) is not None:
            base = value_text(self.scan, value)
        try:
            new = step_text(self.scan, base, steps)
        except FingerpadError:
            new = text
        self.widget.value = new

    def _slide(self, position: Any) -> None:
        """The slider stands at ``position`` (the field's unit): the field holds its text."""
        if self.scan is None or self.scan.slider is None:
            return
        try:
            self.widget.value = slider_text(self.scan, position)
        except FingerpadError:
            return

    def _follow(self) -> None:
        """The slider follows the field's value (typed, stepped or set)."""
        text = self.widget.value
        if not str(text).strip() and self.fallback is not None and (value := self.fallback()) is not None:
            text = value_text(self.scan, value)
        self.slider.position = slider_position(self.scan, str(text))

    def set_slider(self, scan: Scan) -> None:
        """Put the slider on ``scan``'s range (a new loads range for the zone-map load)."""
        self.scan = scan
        if self.slider is None or scan.slider is None:
            return
        lo, hi = scan.slider
        unit = f" {shown_unit(scan.unit)}" if scan.unit else ""
        self.slider.param.update(start=lo, end=hi, step=scan.step, start_text=f"{lo:g}{unit}",
                                 end_text=f"{hi:g}{unit}")
        self._follow()

    def set_value(self, value: Any) -> None:
        if self.kind == "bool":
            self.widget.value = bool(value) if not isinstance(value, str) else value.strip().lower() in (
                "1", "true", "yes", "on")
        elif self.kind == "choice":
            text = str(value).strip().lower()
            if text in self.widget.options:
                self.widget.value = text
        else:
            self.widget.value = "" if value is None else str(value)

    def show(self, text: str | None, warning: bool = False, level: str | None = None) -> None:
        """Show ``text`` beside the field (``level``: error in red, warning in amber, info in
        grey; ``warning=True`` is level warning); ``None`` clears."""
        import html

        if not text:
            self.message.object = ""
            self.message.visible = False
            return
        kind = level or ("warning" if warning else "error")
        colour = {"warning": "#8a5a00", "info": "#444444"}.get(kind, "#b00020")
        self.message.object = (f'<div class="fp-{kind}" style="color:{colour};font-size:12px;line-height:1.25">'
                               f"{html.escape(text)}</div>")
        self.message.visible = True


class Form:
    """All fields of the view, grouped in cards; the texture's own fields change with the family."""

    def __init__(self) -> None:
        from ...textures import registry

        self.families = registry()
        self.family = Field("texture.name", "texture family", kind="choice", value="caps",
                            options=[*self.families, MEASURED],
                            doc="generators of `fingerpad textures`; or a measured height map")
        self.texture_fields: dict[str, Field] = {}
        self.texture_box = pn.Column(margin=0, sizing_mode="stretch_width")
        self.grid = Field("model.grid", "grid (points along x)", placeholder="automatic (by accuracy)",
                          doc="grid of the BEM unit cell; empty: doubled until the estimated error of A_re/A_fr "
                              "is below the accuracy")
        self.material = {
            "modulus": Field("material.modulus", "material modulus E_m (Pa)", value="0.5GPa",
                             placeholder="rigid", doc="Young's modulus of the textured material, or 'rigid'",
                             scan=scan_for(MATERIAL_MODULUS, field_label("material", "modulus"))),
            "poisson": Field("material.poisson", "material Poisson ratio (-)", value="0.4", placeholder="0.35",
                             scan=scan_for(MATERIAL_POISSON, field_label("material", "poisson")),
                             fallback=lambda: MATERIAL_POISSON.default),
        }
        self.preset = Field("finger.preset", "finger preset", kind="choice", value="default",
                            options=list(FINGER_PRESETS),
                            doc="; ".join(f"{k}: {f.description}" for k, f in FINGER_PRESETS.items()))
        # titles from the declarations: a choice lists its choices, a number its unit; a number
        # field steps by its declaration (a choice has no scan)
        self.finger = {p.name: Field(f"finger.{p.name}", f"{FINGER_LABELS[p.name]} ("
                                     f"{', '.join(p.choices) if p.choices else _DIM_UNIT[p.dimension]})",
                                     doc=f"overrides the preset's {p.name}",
                                     scan=scan_for(p, field_label("finger", p.name),
                                                   fallback=self._preset_value(p.name)),
                                     fallback=lambda k=p.name: self._preset_value(k))
                       for p in FINGER_PARAMS}
        self.loads = {
            "range": Field("loads.range", "loads (N)", value="0.1N:4N:40", placeholder="0.1N:4N:40",
                           doc="START:STOP:COUNT, one load, or a comma list of either"),
            "log": Field("loads.log", "log-spaced loads", kind="bool", value=True),
            "zones_at": Field("loads.zones_at", "zone-map load (N)", placeholder="the largest load",
                              doc="load of the zone map", scan=scan_for(ZONE_LOAD, field_label("loads", "zones_at"),
                                                                         fallback=4.0, slider=True),
                              fallback=lambda: self._loads_span()[1]),
        }
        self.model = {
            "kind": Field("model.kind", "unit-cell model", kind="choice", value="both", options=["hertz", "bem", "both"],
                          doc="hertz: per-asperity Hertz (Eqs. 3.1-3.6, live); bem: numerical unit cell (background)"),
            "accuracy": Field("model.accuracy", "accuracy (-)", placeholder="0.02",
                              doc="target of the estimated relative error of A_re/A_fr (automatic grid)"),
        }
        self.measured = {
            "size": Field("texture.size", "map size LX[,LY] (m)", placeholder="from the file",
                          doc="physical size of the map (bare files)"),
            "pixel_size": Field("texture.pixel_size", "pixel size DX[,DY] (m)", doc="instead of the map size"),
            "height_unit": Field("texture.height_unit", "height unit", placeholder="from the file",
                                 doc="unit of the heights of a bare file (um, nm, m)"),
            "periodize": Field("texture.periodize", "periodize (mirror into a periodic cell)", kind="bool", value=True),
            "periodic": Field("texture.periodic", "the map is one period", kind="bool", value=False),
            "fill_missing": Field("texture.fill_missing", "fill missing points", kind="bool", value=False),
            "base_quantile": Field("texture.base_quantile", "base quantile (-)", placeholder="0.05"),
        }
        self.surface = Field("texture.surface", "measured map", placeholder="upload a file")
        self.surface.widget.disabled = True
        self.set_family("caps")
        self._refresh_finger_placeholders()
        self.preset.widget.param.watch(lambda e: self._refresh_finger_placeholders(), "value")
        self._follow_loads()
        self.loads["range"].widget.param.watch(lambda e: self._follow_loads(), "value")

    def _preset_value(self, key: str) -> float | None:
        """The chosen preset's value of finger field ``key`` (SI; ``None`` if it has none)."""
        finger = FINGER_PRESETS.get(getattr(getattr(self, "preset", None), "value", "default"))
        value = getattr(finger, key, None) if finger is not None else None
        return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None

    def _loads_span(self) -> tuple[float, float]:
        """The smallest and largest load of the loads field (N; the last readable ones)."""
        from ...units import parse_quantity

        loads = getattr(self, "loads", None)  # None: the form is being made
        text = str(loads["range"].value) if loads is not None else ""
        try:  # START:STOP:COUNT, one load, or a list of them: their ends
            values = [parse_quantity(end, "force") for part in text.split(",") if part.strip()
                      for end in part.split(":")[:2]]
        except FingerpadError:
            values = []
        if values and min(values) > 0:
            self._span = (min(values), max(values))
        return getattr(self, "_span", (0.1, 4.0))

    def _follow_loads(self) -> None:
        """The zone-map load's slider runs over the loads."""
        zone = self.loads["zones_at"]
        if zone.scan is not None:
            lo, hi = self._loads_span()
            zone.set_slider(scan_for(ZONE_LOAD, zone.scan.label, fallback=hi).with_slider(lo, hi))

    # ------------------------------------------------------------------ families

    def set_family(self, name: str, values: Mapping[str, Any] | None = None) -> None:
        """Show the fields of family ``name`` (its declared parameters), filled with ``values``
        or the family's example values."""
        self.texture_fields = {}
        if name == MEASURED:
            self.texture_fields = {"surface": self.surface, **self.measured}
        else:
            family = self.families[name]
            examples = family_examples(name) if values is None else dict(values)
            feature = _feature_size(family)
            for p in family.user_params():
                unit = p.unit if p.kind != "choice" else ""
                title = f"{field_label('texture', p.name)}" + (f" ({unit})" if unit else "")
                if p.kind == "choice":
                    default = p.default if isinstance(p.default, str) else p.choices[0]
                    f = Field(f"texture.{p.name}", title, kind="choice", options=list(p.choices),
                              value=str(examples.get(p.name, default)).lower(), doc=p.doc)
                else:
                    if p.required:
                        placeholder = "required"
                    elif p.default is None:
                        placeholder = "automatic"
                    elif p.kind == "angle":
                        placeholder = f"{math.degrees(p.default):g} deg"
                    else:
                        placeholder = _fmt_default(p.default, "length" if p.kind in ("length", "size") else "none")
                    scan = scan_for(p, field_label("texture", p.name), fallback=feature, slider=p.kind == "length")
                    default = p.default if isinstance(p.default, (int, float)) and not isinstance(p.default, bool) \
                        else None
                    f = Field(f"texture.{p.name}", title, value=examples.get(p.name, ""), placeholder=placeholder,
                              doc=p.doc + (" (a bare number is in degrees)" if p.kind == "angle" else ""),
                              scan=scan, fallback=lambda d=default: d)
                self.texture_fields[p.name] = f
        self.texture_box.objects = [f.panel for f in self.texture_fields.values()]

    def _refresh_finger_placeholders(self) -> None:
        finger = FINGER_PRESETS.get(self.preset.value)
        if finger is None:
            return
        for key, f in self.finger.items():
            f.widget.placeholder = f"{_fmt_default(getattr(finger, key), FINGER_FIELDS[key])} (preset)"

    # ------------------------------------------------------------------ values

    def all_fields(self) -> list[Field]:
        return [self.family, *self.texture_fields.values(), self.grid, *self.material.values(), self.preset,
                *self.finger.values(), *self.loads.values(), *self.model.values()]

    def values(self) -> dict[str, Any]:
        """``"section.key" -> value`` of every field shown (the input of :func:`..inputs.study_data`)."""
        out: dict[str, Any] = {}
        for f in self.all_fields():
            if f is self.family:
                if f.value != MEASURED:
                    out["texture.name"] = f.value
                continue
            if f.kind == "bool" and f.fid in ("texture.periodize", "texture.periodic", "texture.fill_missing"):
                if f.value:
                    out[f.fid] = True
                continue
            out[f.fid] = f.value
        return out

    def load(self, data: Mapping[str, Mapping[str, Any]]) -> None:
        """Fill the form from study sections (a pinned design, a design of the map)."""
        tex = dict(data.get("texture", {}))
        name = tex.pop("name", None)
        if name is not None and name in self.families:
            self.family.widget.value = name
            self.set_family(name, {k: v for k, v in tex.items() if k != "grid"})
        grid = data.get("model", {}).get("grid", tex.get("grid"))
        self.grid.set_value("" if grid is None else grid)
        mat = data.get("material", {})
        self.material["modulus"].set_value(mat.get("modulus", "rigid"))
        self.material["poisson"].set_value(mat.get("poisson", ""))
        fin = data.get("finger", {})
        self.preset.set_value(fin.get("preset", "default"))
        for key, f in self.finger.items():
            f.set_value(fin.get(key, ""))
        loads = data.get("loads", {})
        rng = loads.get("range", loads.get("values", "0.1N:4N:40"))
        self.loads["range"].set_value(", ".join(map(str, rng)) if isinstance(rng, list) else rng)
        self.loads["log"].set_value(loads.get("log", True))
        self.loads["zones_at"].set_value(loads.get("zones_at", ""))
        model = data.get("model", {})
        self.model["kind"].set_value(model.get("kind", "both"))
        self.model["accuracy"].set_value(model.get("accuracy", ""))

    def show_messages(self, errors: list[Any], warnings: list[Any]) -> list[Any]:
        """Put each message beside its field; return those naming no field shown."""
        by_field: dict[str, tuple[str, bool]] = {}
        loose = []
        for item in [*warnings, *errors]:  # errors win over warnings
            if item.field is not None and any(f.fid == item.field for f in self.all_fields()):
                by_field[item.field] = (item.message, item.warning)
            else:
                loose.append(item)
        for f in self.all_fields():
            text, warn = by_field.get(f.fid, (None, False))
            f.show(text, warn)
        return loose
