"""Changes in quick succession: which change belongs to one, and when its figures are drawn.

A designer who holds an arrow key, drags a slider or goes back and forth between two designs as
soon as their numbers show makes changes faster than the browser draws ten figures: the drawing of
a design already passed over (a few tenths of a second of Chromium per change on a loaded 2-core
machine) holds the next numbers back. So a change in a sequence shows its numbers at once and the
figures once the sequence pauses.

What counts is the browser, not the server's clock: the page reports when it has shown a change's
numbers (a small component answers each numbers update on the animation frame after it is
applied), and a change is in a sequence when it comes before the numbers of the one before were
shown or less than :data:`SEQUENCE_S` after. Its figures are drawn :data:`FIGURES_AFTER_S` after
the page has shown its numbers, if no change came meanwhile (at the latest :data:`LATEST_S` after
the change, should the page never answer). A change after a pause draws its figures at once.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

__all__ = ["FIGURES_AFTER_S", "LATEST_S", "SEQUENCE_S", "Sequence"]

#: A change less than SEQUENCE_S after the numbers of the one before were shown is in a sequence.
SEQUENCE_S = 0.7
#: A change in a sequence draws its figures FIGURES_AFTER_S after the page showed its numbers.
FIGURES_AFTER_S = 0.3
#: ... and at the latest LATEST_S after the change (a page that does not answer).
LATEST_S = 1.5

_BEACON_ESM = """
export function render({ model }) {
  // after the numbers' patch is applied and drawn: the frame after it, then the next task
  model.on("seq", () => {
    const seq = model.seq
    requestAnimationFrame(() => setTimeout(() => model.send_msg({shown: seq}), 0))
  })
}
"""
_BEACON: Any = None


def _beacon(on_shown: Callable[[Any], None]) -> Any:
    global _BEACON
    if _BEACON is None:
        import panel as pn
        import param

        class Beacon(pn.custom.JSComponent):
            seq = param.Integer(default=0)
            _esm = _BEACON_ESM

            def __init__(self, on_shown: Callable[[Any], None], **params: Any) -> None:
                super().__init__(**params)
                self._on_shown = on_shown

            def _handle_msg(self, msg: Any) -> None:
                if isinstance(msg, dict):
                    self._on_shown(msg.get("shown"))

        _BEACON = Beacon
    return _BEACON(on_shown, height=0, width=0, margin=0)


class Sequence:
    """The sequence state of a view; ``panel`` goes into its layout (it shows nothing)."""

    def __init__(self, view: Any) -> None:
        self.view = view
        self.panel = _beacon(self._shown)
        self.sent = 0  # numbers updates sent
        self.seen = 0  # ... and shown by the page, the last at ``seen_at`` (time.monotonic)
        self.seen_at = -math.inf
        self.rapid = False
        self._pending: tuple[int, Callable[[], None]] | None = None  # figures waiting, by generation

    def change(self) -> bool:
        """A new design is shown: whether it is in a sequence (see the module)."""
        self.rapid = self.seen < self.sent or time.monotonic() - self.seen_at < SEQUENCE_S
        return self.rapid

    def numbers_sent(self) -> None:
        """The numbers of the design shown went to the page (in this change's patch)."""
        self.sent += 1
        self.panel.seq = self.sent

    def figures(self, draw: Callable[[], None]) -> None:
        """Draw the figures now, or, in a sequence, once the page has shown the numbers and no
        change came for FIGURES_AFTER_S (LATEST_S at the latest)."""
        if not self.rapid:
            self._pending = None
            draw()
            return
        self._pending = (self.view.generation, draw)
        self.view.after_quiet(self._draw, LATEST_S)

    def _draw(self) -> None:
        """Draw the figures waiting, if they are the design shown's (once: the page's answer or
        the latest time, whichever comes first)."""
        pending, self._pending = self._pending, None
        if pending is not None and pending[0] == self.view.generation:
            pending[1]()

    def _shown(self, seq: Any) -> None:
        """The page showed numbers update ``seq`` (what it sends is untrusted: an integer only)."""
        if isinstance(seq, bool) or not isinstance(seq, int) or not 0 < seq <= self.sent:
            return
        if seq > self.seen:
            self.seen, self.seen_at = seq, time.monotonic()
        if seq == self.sent and self._pending is not None:
            self.view.after_quiet(self._draw, FIGURES_AFTER_S)
