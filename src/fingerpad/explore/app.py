"""One browser session of the explorer: the views in tabs, the pinned designs."""

from __future__ import annotations

import copy
import os
from dataclasses import dataclass, field
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

from .jobs import LRU, Memo, WorkLog
from .methods import METHODS_MARKDOWN
from .views.common import html_pane

__all__ = ["ExplorerApp", "ServerState"]


@dataclass
class ServerState:
    """What the sessions of one server share: remembered predictions and unit-cell contacts, the
    sweep, the upload folder."""

    upload_dir: str
    max_upload_bytes: int = 20 * 2**20
    sweep: Any = None
    sweep_path: str | None = None
    memo: Memo = field(default_factory=Memo)
    # contact maps of designs seen (a map of a large measured surface holds megabytes: a few only)
    contacts: LRU = field(default_factory=lambda: LRU(12))
    # what the page shows of a prediction (its JSON payload, its figures' specs) by (prediction, what):
    # going back to a design computed before costs neither the payload's error estimates nor the specs
    derived: LRU = field(default_factory=lambda: LRU(96))
    # population results by (design, preset): a thousand fingers' curves, kilobytes each
    populations: LRU = field(default_factory=lambda: LRU(8))
    # populations given at start (`fingerpad explore --population`), by the label the page shows
    extra_populations: dict[str, Any] = field(default_factory=dict)
    # the CPU time of the background work (and of the work for designs no longer shown)
    worklog: WorkLog = field(default_factory=lambda: WorkLog(os.environ.get("FINGERPAD_EXPLORE_WORKLOG") or None))


class ExplorerApp:
    """The page of one session."""

    def __init__(self, state: ServerState) -> None:
        from .views.compare import MAX_PINS, CompareView, design_label
        from .views.single import SingleView

        self.state = state
        self.memo = state.memo
        self.contacts = state.contacts
        self.populations = state.populations
        self.derived = state.derived
        self.worklog = state.worklog
        self.upload_dir = state.upload_dir
        self.max_upload_bytes = state.max_upload_bytes
        self.pins: list[dict[str, Any]] = []
        self._max_pins = MAX_PINS
        self._label = design_label
        self.single = SingleView(self)
        self.compare = CompareView(self)
        tabs = [("Texture", self.single.panel), ("Compare", self.compare.panel)]
        self.map = None
        if state.sweep is not None:
            from .views.mapview import MapView

            self.map = MapView(self, state.sweep, state.sweep_path or "")
            tabs.append(("Design map", self.map.panel))
        tabs.append(("Methods and references", pn.pane.Markdown(METHODS_MARKDOWN, sizing_mode="stretch_width",
                                                                css_classes=["fp-methods"], max_width=1100)))
        self.tabs = pn.Tabs(*tabs, sizing_mode="stretch_width", css_classes=["fp-tabs"], dynamic=False)
        self.pin_message = html_pane("", css_classes=["fp-pin-message"])
        header = pn.pane.HTML(
            "<div style='display:flex;align-items:baseline;gap:12px'><span style='font-size:20px;font-weight:600'>"
            "fingerpad &middot; texture design explorer</span><span style='font-size:12px;color:#555'>finger-pad "
            "contact and tactile friction on micro-textured surfaces (SI units; unit suffixes such as 50um, 0.3MPa, "
            "2N accepted)</span></div>", sizing_mode="stretch_width")
        self.page = pn.Column(header, self.pin_message, self.tabs, sizing_mode="stretch_width",
                              css_classes=["fp-page"])

    # ------------------------------------------------------------------ pins

    def pin(self, data: dict[str, Any], pred: Any) -> None:
        if len(self.pins) >= self._max_pins:
            self.pin_message.object = (f"<div class='fp-warning' style='color:#8a5a00'>at most {self._max_pins} "
                                       "designs can be pinned: remove one in Compare first</div>")
            return
        self.pins.append({"label": f"#{len(self.pins) + 1} {self._label(data)}", "data": copy.deepcopy(data),
                          "pred": pred})
        self.pin_message.object = (f"<div class='fp-pinned' style='font-size:12px'>pinned "
                                   f"{len(self.pins)} of {self._max_pins} designs (see Compare)</div>")
        self.compare.update()

    def unpin(self, index: int) -> None:
        if 0 <= index < len(self.pins):
            del self.pins[index]
            self.compare.update()

    def open_design(self, data: dict[str, Any]) -> None:
        """Show a design (study sections) in the single-texture view and switch to it."""
        self.single.load_data(copy.deepcopy(data))
        # on the next tick: a change of the tabs inside a figure's own callback does not reach the page
        pn.state.execute(lambda: setattr(self.tabs, "active", 0), schedule=True)
