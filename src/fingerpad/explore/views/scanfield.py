"""The widgets of a number field that can be scanned: a text input stepped by the arrow keys, and
a slider beside it (Panel ``JSComponent``s, their JavaScript below).

The page decides nothing: an arrow key sends "n steps from this text" and the slider sends its
position; the server answers with the field's new text (:mod:`..scan`), which it then reads and
checks as a typed value. Both send **the latest only**: while the server has not answered, key
presses are added up and the slider's last position is kept; the server's answer (an ``ack``
message, sent after the change's numbers) releases the next request; the slider keeps two on their
way (the server computes one while the page shows the other) and sends its release at once. A
designer who holds a key or drags the slider thus sees the numbers of designs as fast as the
server and the browser give them, never a queue of designs already passed, and where the hand
stops, the numbers of that very value.

Everything a page sends is checked on the server (:meth:`ScanInput._handle_msg`): a step count
outside ``[-MAX_STEPS, MAX_STEPS]``, a text longer than ``MAX_TEXT``, a slider position that is
not a finite number are ignored.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["scan_input", "scan_slider"]

_CLASSES: dict[str, Any] = {}

_INPUT_CSS = """
:host { display: block; width: 100%; }
.fp-scan { display: flex; flex-direction: column; margin: 5px 10px; font-size: 12px; }
.fp-scan label { font-size: 12px; color: #212529; margin-bottom: 3px; }
.fp-scan input { font-size: 13px; padding: 4px 8px; border: 1px solid #dfe2e6; border-radius: 4px;
                 background: #fff; min-height: 31px; box-sizing: border-box; width: 100%; }
.fp-scan input:focus { outline: 2px solid #0072b566; border-color: #0072b5; }
.fp-scan input:disabled { background: #f1f1f1; color: #666; }
.fp-scan-hint { font-size: 11px; color: #777; margin-top: 2px; }
"""

_INPUT_ESM = """
export function render({ model, el }) {
  const box = document.createElement("div")
  box.className = "fp-scan"
  const label = document.createElement("label")
  const input = document.createElement("input")
  input.type = "text"
  input.id = "fp-scan-input"
  label.htmlFor = input.id
  const hint = document.createElement("div")
  hint.className = "fp-scan-hint"
  const show = () => {
    label.textContent = model.label
    label.title = model.description
    input.placeholder = model.placeholder
    input.disabled = model.disabled
    input.title = model.description
    hint.textContent = model.hint
    hint.style.display = model.hint ? "" : "none"
  }
  show()
  input.value = model.value
  box.append(label, input, hint)
  // the latest only: steps pressed while the server has not answered are added up
  let pending = 0, inflight = false, since = 0
  const flush = () => {
    if (pending === 0 || (inflight && performance.now() - since < 5000)) return
    inflight = true
    since = performance.now()
    model.send_msg({step: pending, text: input.value})
    pending = 0
  }
  const commit = () => { if (input.value !== model.value) model.value = input.value }
  input.addEventListener("change", commit)
  input.addEventListener("keydown", (e) => {
    if (e.key === "Enter") { commit(); return }
    if ((e.key !== "ArrowUp" && e.key !== "ArrowDown") || !model.hint || model.disabled) return
    e.preventDefault()
    pending += (e.key === "ArrowUp" ? 1 : -1) * (e.shiftKey ? 10 : 1)
    flush()
  })
  model.on("msg:custom", (msg) => { if (msg && msg.ack) { inflight = false; flush() } })
  model.on("value", () => { if (input.value !== model.value) input.value = model.value })
  model.on(["label", "placeholder", "disabled", "hint", "description"], show)
  el.append(box)
}
"""

_SLIDER_CSS = """
:host { display: block; width: 100%; }
.fp-slide { display: flex; align-items: center; gap: 6px; margin: 0 10px 4px; font-size: 11px; color: #777; }
.fp-slide input { flex: 1; min-width: 60px; accent-color: #0072b5; }
"""

_SLIDER_ESM = """
export function render({ model, el }) {
  const box = document.createElement("div")
  box.className = "fp-slide"
  const lo = document.createElement("span"), hi = document.createElement("span")
  const range = document.createElement("input")
  range.type = "range"
  range.setAttribute("aria-label", model.label)
  const show = () => {
    range.min = model.start
    range.max = model.end
    range.step = model.step
    lo.textContent = model.start_text
    hi.textContent = model.end_text
    range.disabled = model.disabled
    // the field's value (typed, stepped) moves the thumb, not while the hand's own are on their way
    if (!dragging && inflight === 0 && pending === null && model.position !== null) range.value = model.position
  }
  // the latest only: at most two positions on their way (the server computes one while the page
  // shows the other); those passed meanwhile are dropped, and the release is sent at once
  let dragging = false, inflight = 0, since = 0, pending = null, sent = null
  const send = (v) => {
    inflight += 1
    since = performance.now()
    sent = v
    model.send_msg({position: v})
  }
  const propose = (v) => {
    if (inflight >= 2 && performance.now() - since < 5000) pending = v
    else send(v)
  }
  range.addEventListener("input", () => { dragging = true; propose(Number(range.value)) })
  range.addEventListener("change", () => {
    dragging = false
    pending = null
    if (Number(range.value) !== sent) send(Number(range.value))
  })
  model.on("msg:custom", (msg) => {
    if (!(msg && msg.ack)) return
    inflight = Math.max(0, inflight - 1)
    if (pending !== null) { const v = pending; pending = null; send(v) }
    else if (inflight === 0) show()
  })
  model.on(["start", "end", "step", "start_text", "end_text", "disabled", "position"], show)
  show()
  box.append(lo, range, hi)
  el.append(box)
}
"""


def _classes() -> dict[str, Any]:
    """The two component classes, made on first use (Panel is imported only when serving)."""
    if _CLASSES:
        return _CLASSES
    import param
    import panel as pn

    class ScanInput(pn.custom.JSComponent):
        """A text field whose arrow keys ask the server for steps (``on_step(steps, text)``)."""

        value = param.String(default="")
        label = param.String(default="")
        placeholder = param.String(default="")
        description = param.String(default="")
        hint = param.String(default="", doc="the step and its unit; empty: not steppable")
        disabled = param.Boolean(default=False)

        _esm = _INPUT_ESM
        _stylesheets = [_INPUT_CSS]

        def __init__(self, on_step: Callable[[int, str], None] | None = None, **params: Any) -> None:
            super().__init__(**params)
            self._on_step = on_step

        def _handle_msg(self, msg: Any) -> None:
            try:
                if isinstance(msg, dict) and self._on_step is not None and not self.disabled:
                    self._on_step(msg.get("step"), msg.get("text"))
            finally:
                self._send_msg({"ack": 1})  # after the change's numbers: the page may send the next

    class ScanSlider(pn.custom.JSComponent):
        """A slider whose positions the server turns into the field's text (``on_position(x)``)."""

        label = param.String(default="")
        start = param.Number(default=0.0)
        end = param.Number(default=1.0)
        step = param.Number(default=1.0)
        start_text = param.String(default="")
        end_text = param.String(default="")
        position = param.Number(default=None, allow_None=True)
        disabled = param.Boolean(default=False)

        _esm = _SLIDER_ESM
        _stylesheets = [_SLIDER_CSS]

        def __init__(self, on_position: Callable[[Any], None] | None = None, **params: Any) -> None:
            super().__init__(**params)
            self._on_position = on_position

        def _handle_msg(self, msg: Any) -> None:
            try:
                if isinstance(msg, dict) and self._on_position is not None and not self.disabled:
                    self._on_position(msg.get("position"))
            finally:
                self._send_msg({"ack": 1})

    _CLASSES.update(input=ScanInput, slider=ScanSlider)
    return _CLASSES


def scan_input(on_step: Callable[[int, str], None], **params: Any) -> Any:
    """A :class:`ScanInput` (``value``, ``label``, ``placeholder``, ``description``, ``hint``)."""
    return _classes()["input"](on_step, **params)


def scan_slider(on_position: Callable[[Any], None], **params: Any) -> Any:
    """A :class:`ScanSlider` (``start``, ``end``, ``step`` in the field's unit, ``position``)."""
    return _classes()["slider"](on_position, **params)
