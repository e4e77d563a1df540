"""The comparison view: up to four pinned designs, their curves overlaid."""

from __future__ import annotations

import html
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

from .. import builders
from ...plotting.specs import DESIGN_COLOURS
from .common import PlotCard, num_span

__all__ = ["MAX_PINS", "CompareView", "design_label"]

#: Designs that can be pinned at once.
MAX_PINS = 4


def design_label(data: dict[str, Any]) -> str:
    """A short name of a design: the family and its parameters as typed."""
    tex = data.get("texture", {})
    name = tex.get("name") or "measured map"
    params = ", ".join(f"{k}={v}" for k, v in tex.items() if k not in ("name", "surface"))
    kind = data.get("model", {}).get("kind", "both")
    return f"{name} ({params}) [{kind}]" if params else f"{name} [{kind}]"


class CompareView:
    """Pinned designs (in the session) and their overlaid curves."""

    def __init__(self, app: Any) -> None:
        self.app = app
        self.list = pn.Column(sizing_mode="stretch_width", css_classes=["fp-pins"])
        self.cards = {k: PlotCard(k) for k in ("compare-area-ratio", "compare-friction", "compare-normalised")}
        self.panel = pn.Column(
            pn.pane.HTML("<p style='font-size:13px'>Pin up to four designs in the Texture view "
                         "(<i>Pin for comparison</i>); their curves are overlaid here, critical loads dashed.</p>"),
            self.list,
            pn.GridBox(*(c.panel for c in self.cards.values()), ncols=2, sizing_mode="stretch_width"),
            sizing_mode="stretch_width", css_classes=["fp-compare"],
        )
        self.update()

    def update(self) -> None:
        pins = self.app.pins
        rows = []
        for k, pin in enumerate(pins):
            colour = DESIGN_COLOURS[k % len(DESIGN_COLOURS)]
            pred = pin["pred"]
            crit = pred.critical_load.get(pred.primary_model)
            text = (f"<span style='display:inline-block;width:12px;height:12px;background:{colour}'></span> "
                    f"<b>{html.escape(pin['label'])}</b> &middot; critical load "
                    f"{num_span(f'pin{k}_critical_load', crit, 'N')}")
            open_b = pn.widgets.Button(label="open", width=70, css_classes=[f"fp-pin-open-{k}"])
            remove_b = pn.widgets.Button(label="remove", width=80, css_classes=[f"fp-pin-remove-{k}"])
            open_b.on_click(lambda e, d=pin["data"]: self.app.open_design(d))
            remove_b.on_click(lambda e, i=k: self.app.unpin(i))
            rows.append(pn.Row(pn.pane.HTML(text, sizing_mode="stretch_width"), open_b, remove_b,
                               sizing_mode="stretch_width"))
        if not rows:
            rows = [pn.pane.HTML("<i style='font-size:13px'>no design pinned yet</i>")]
        self.list.objects = rows
        specs = builders.compare_specs([(p["label"], p["pred"]) for p in pins]) if pins else []
        for card, spec in zip(self.cards.values(), specs or [None] * len(self.cards), strict=True):
            card.set(spec)
