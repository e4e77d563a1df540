"""The perception part of the single-texture view (issue 32): what a person feels of the design
shown, against the flat reference.

Per load: the friction on the texture and on the flat, the probability that the study's finger
tells them apart in a forced choice and, with a population shown, the fraction of its fingers
who do; the vibration frequencies along x and y over the stroke speeds with their receptor
channel and the fingerprint comparison; the roughness regime. Everything is
:func:`fingerpad.perception.compare.against_flat` on the prediction (and population) already
shown, as ``fingerpad predict --perception`` computes it, without the amplitude estimate (a cell
solve per load; the command gives it). The two fields (stroke speeds, Weber fraction) are read by
the library's own parsers, with its messages.
"""

from __future__ import annotations

import html
import math
from typing import Any

import lazy_loader
import numpy as np

pn = lazy_loader.load("panel")

from ...errors import FingerpadError, one_line
from ..inputs import data_key
from .common import html_table, num_span

__all__ = ["PerceptionPanel"]

#: Loads shown in the section's table (spread over the range).
ROWS = 8
#: The library's option names in its messages -> the fields of this section.
_FIELDS = {"--weber-fraction": "Weber fraction W", "--speed": "stroke speeds"}


class PerceptionPanel:
    """Two inputs (stroke speeds, Weber fraction) and a results section, updated with the view."""

    def __init__(self, view: Any) -> None:
        self.view = view
        self.speed = pn.widgets.TextInput(label="stroke speeds", value="20mm/s:100mm/s", width=300,
                                          css_classes=["fp-perception-speed"])
        # empty: the person's default 0.11, or each member's own W where the population draws it
        self.weber = pn.widgets.TextInput(label="Weber fraction W", value="", placeholder="0.11, or the population's",
                                          width=300, css_classes=["fp-perception-weber"])
        self.message = pn.pane.HTML("", css_classes=["fp-perception-msg"], sizing_mode="stretch_width")
        self.inputs = pn.Column(
            self.speed, self.weber, self.message,
            pn.pane.HTML("<div style='font-size:11px;color:#555'>one speed or LOW:HIGH; W: the relative friction "
                         "difference told apart in 75 % of forced choices (docs/perception.md)</div>"),
            sizing_mode="stretch_width")
        self.body = pn.pane.HTML("", css_classes=["fp-perception"], sizing_mode="stretch_width")
        self.panel = pn.Column(pn.pane.HTML("<h4 style='margin:6px 0'>What a person feels</h4>"), self.body,
                               sizing_mode="stretch_width", css_classes=["fp-perception-section"])
        for widget in (self.speed, self.weber):
            widget.param.watch(lambda e: self.update(), "value")
        self.result: Any = None

    def update(self) -> None:
        """Recompute from the prediction (and the population result) shown; called with the view."""
        from ...perception.compare import parse_speeds, parse_weber

        try:
            speeds = parse_speeds(self.speed.value.strip() or None)
            weber = parse_weber(self.weber.value.strip() or None)
            result = self._verdicts(speeds, weber)
        except FingerpadError as exc:
            text = self.view._words(one_line(str(exc)))
            for option, field in _FIELDS.items():  # the page's fields, not the command's options
                text = text.replace(option, field)
            self.message.object = (f'<div class="fp-error" style="font-size:12px;color:#b00020">'
                                   f"{html.escape(text)}</div>")
            self.result, self.body.object = None, ""  # no verdicts of another W left shown
            return
        self.message.object = ""
        self.result = result
        if result is None:
            self.body.object = "<div style='font-size:12px;color:#555'>shown once the design has a prediction</div>"
            return
        self.body.object = _html(result.as_dict(), result)

    def study_section(self) -> dict[str, Any]:
        """The ``[perception]`` table of the exported study file: the Weber fraction typed in (as
        :func:`~fingerpad.perception.compare.parse_weber` reads it), empty when the field is empty
        or holds what the section refuses (its message says why)."""
        from ...perception.compare import parse_weber

        try:
            weber = parse_weber(self.weber.value.strip() or None)
        except FingerpadError:
            return {}
        return {} if weber is None else {"weber_fraction": weber}

    def _verdicts(self, speeds: tuple[float, ...], weber: float | None) -> Any:
        """:func:`~fingerpad.perception.compare.against_flat` on what is shown, or ``None`` before a
        prediction; a W typed beside a population that draws W is refused by the population's rule."""
        from ...perception.compare import against_flat

        pred = self.view.pred
        if pred is None:
            return None
        shown = getattr(self.view.population, "result_key", None)
        data = self.view.shown_data
        # the population's fingers only when they are those of the design shown (not the last one's)
        pop = self.view.population.result if shown is not None and data is not None and \
            shown[0] == data_key(data) else None
        return against_flat(pred, pop, speeds=speeds, weber=weber, amplitudes=False)


def _html(doc: dict[str, Any], result: Any) -> str:
    """The section's HTML: a table per load, the vibration lines, the roughness verdicts."""
    a = doc["a"]["label"]
    many = result.p.shape[0] > 1
    rows = []
    s = result.summary()
    n = len(doc["loads"])
    # at most ROWS loads, spread over the range (every load: predict --perception)
    for i in sorted({int(round(j)) for j in np.linspace(0, n - 1, min(n, ROWS))}):
        load = doc["loads"][i]
        row = {"load": float(load), "mu": float(result.mu_a[:, i].mean() if not many else doc["mu"][a]["0.5"][i]),
               "mu_flat": float(doc["mu"]["flat"]["0.5"][i]), "tell": float(s["fraction"][i]),
               "p": float(s["p_correct_median"][i]), "roughness": doc["roughness"][a][i]["verdict"]}
        rows.append(row)
    who = f"{doc['population']['size']} fingers of {doc['population']['name']}" if many else "the study's finger"
    columns = [("load", "load (N)"), ("mu", "μ (median)" if many else "μ"), ("mu_flat", "μ flat"),
               ("tell", "fraction telling it from flat" if many else "tells it from flat (1 = yes)"),
               ("p", "median P" if many else "P (forced choice)"), ("roughness", "roughness")]
    some = f"; {len(rows)} of the {n} loads" if len(rows) < n else ""
    parts = [f"<div style='font-size:12px;margin-bottom:4px'>against the flat reference, {html.escape(who)}, "
             f"W = {num_span('perception_weber', float(result.weber[0]))}{some}</div>",
             html_table(columns, rows, "fp-perception-table")]
    lines = []
    for e in doc["vibration"]:
        lam = e["wavelength_m"]
        key = f"perception_f_{e['direction_deg']:g}_{e['harmonic']}_{1e3 * e['speed_m_s']:g}"
        if lam is None or not math.isfinite(lam):
            lines.append(f"{e['direction_deg']:g}°: no period along the stroke, no vibration")
            continue
        lines.append(f"{e['direction_deg']:g}°{'' if e['harmonic'] == 1 else ' (harmonic ' + str(e['harmonic']) + ')'}"
                     f": λ {1e6 * lam:.4g} µm at {1e3 * e['speed_m_s']:g} mm/s → "
                     f"{num_span(key, e['frequency_hz'], 'Hz')} ({html.escape(e['channel'])}"
                     f"{', shorter than' if e['below_ridge_period'] else ', longer than'} the ridge period)")
    if lines:
        parts.append("<div style='font-size:12px;line-height:1.6;margin-top:6px'>vibration: "
                     + "<br>".join(lines) + "</div>")
    parts.append("<div style='font-size:11px;color:#555;margin-top:4px'>amplitude estimate: fingerpad predict "
                 "--perception; two textures: fingerpad compare A.toml B.toml</div>")
    return "".join(parts)
