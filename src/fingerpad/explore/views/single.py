"""The single-texture view: a texture, its materials, finger and loads in; the model's curves out.

Every change of a field rebuilds the study from the form and validates it with the library
(:func:`..inputs.validate`); messages appear beside the fields. The per-asperity Hertz model
updates at once; the BEM unit cell runs as a background :class:`..jobs.Job` (progress bar,
cancel) through the on-disk cache, and a design seen before shows at once. The contact map at a
chosen pressure is one :class:`~fingerpad.contact.HalfSpaceSolver` solve, in a worker thread
(:mod:`.contactmaps`).

The numbers of a change come first: the background work of a design (its contact maps, a BEM run
on every change, its population) starts once the design has stayed shown for :data:`QUIET_S`, and
a change to another design cancels all of it within one solver iteration (:mod:`fingerpad.cancel`).
Changes in quick succession (arrow keys held, a slider dragged, two designs compared as soon as
their numbers show) show their numbers at once and the figures once they pause (:mod:`.sequence`):
the browser's drawing of designs passed over would otherwise hold the next numbers back.
"""

from __future__ import annotations

import copy
import html
from collections.abc import Callable
from functools import partial
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

from ...errors import FingerpadError, one_line
from .. import builders
from ..inputs import data_key, study_data, validate
from ..jobs import run_data
from . import exports
from .bemrun import BemRun, bem_data
from .common import PlotCard, download, html_pane, html_table, num_span, set_cards
from .contactmaps import ContactMaps
from .sequence import Sequence
from .fields import MEASURED, Field, Form
from .perception import PerceptionPanel
from .population import PopulationPanel
from ..uploads import StoredUpload, page_message
from .upload import Upload

__all__ = ["QUIET_S", "SingleView"]

#: Seconds a design stays shown before its background work starts (contact maps, a BEM run on
#: every change, a population): longer than the pause between the values of a designer who
#: steps or drags through them, short beside the work itself.
QUIET_S = 0.4

#: The results table of the design before, while a sequence passes over designs; and once it is
#: the design's (an empty style would not reach the page: Panel sends the keys it is given).
_DIMMED, _BRIGHT = {"opacity": "0.35"}, {"opacity": "1"}


def _prediction_json(pred: Any) -> dict[str, Any]:
    from ...study.outputs import prediction_json

    return prediction_json(pred)


_RESULT_COLUMNS = (
    ("load", "load F (N)"), ("gross_area", "A_g (m²)"), ("ridge_area", "A_fr (m²)"), ("real_area", "A_re (m²)"),
    ("area_ratio", "A_re/A_fr"), ("transition_radius", "r_trans (m)"), ("full_contact_radius", "r_full (m)"),
    ("mu", "μ"), ("mu_ref", "μ_ref"), ("mu_normalised", "μ/μ_ref"), ("contact_state", "centre"),
)


def _with_kind(data: dict[str, Any], kind: str) -> dict[str, Any]:
    out = copy.deepcopy(data)
    out.setdefault("model", {})["kind"] = kind
    return out



class SingleView:
    """The single-texture view of one browser session."""

    def __init__(self, app: Any) -> None:
        self.app = app
        self.form = Form()
        self.upload = Upload(app.upload_dir, app.max_upload_bytes, self._on_upload)
        self.data: dict[str, Any] | None = None  # the last valid inputs
        self.shown_data: dict[str, Any] | None = None  # the study of the results shown
        self.pred: Any = None
        self.pending = False  # the BEM of the design shown is not computed
        self.texture: Any = None
        self._design: str | None = None  # the design the background work is for (its data key)
        self._generation = 0  # designs shown so far: background work waits for a quiet one
        self._loading = False
        self.doc = pn.state.curdoc  # the session's document: async work changes it on its next tick

        self.form_error = html_pane("", css_classes=["fp-form-error"], visible=False, sizing_mode="stretch_width")
        self.status = html_pane("", css_classes=["fp-status"], sizing_mode="stretch_width")
        self.summary = html_pane("", css_classes=["fp-summary"], sizing_mode="stretch_width")
        self.notes = html_pane("", css_classes=["fp-notes"], sizing_mode="stretch_width")
        self.table = html_pane("", css_classes=["fp-results-pane"], sizing_mode="stretch_width",
                                  styles={"overflow-x": "auto", "max-height": "420px", "overflow-y": "auto"})
        self.bem = BemRun(self)
        self.pin_button = pn.widgets.Button(label="Pin for comparison", color="default",
                                            css_classes=["fp-pin"], width=160)
        self.pressure = Field("view.pressure", "contact-map pressure (Pa)",
                              placeholder="centre pressure at the zone load",
                              doc="mean nominal pressure on the unit cell for the contact and pressure maps")
        self.pin_button.on_click(lambda e: self.pin())

        self.cards = {k: PlotCard(k, height=h) for k, h in (
            ("areas", 330), ("friction", 330), ("friction-normalised", 330), ("friction-directional", 330),
            ("psi", 330), ("height-map", 360),
            ("pressure-map", 360), ("contact-map", 360), ("zones", 330), ("zone-profile", 330))}
        self.exports = pn.Row(
            pn.pane.HTML("<b style='font-size:12px'>export:</b>", margin=(6, 4)),
            download("study TOML", "fingerpad-study.toml", partial(exports.study_toml, self), "fp-export-toml"),
            download("results JSON", "fingerpad-predict.json", partial(exports.results_json, self), "fp-export-json"),
            download("results CSV", "fingerpad-predict.csv", partial(exports.results_csv, self), "fp-export-csv"),
        )
        for w in self.exports.objects[1:]:
            w.width = 120
        self.population = PopulationPanel(self)
        self.maps = ContactMaps(self)
        self.sequence = Sequence(self)
        self.perception = PerceptionPanel(self)
        self._watch_form()
        self.panel = self._layout()
        self.refresh()

    # ------------------------------------------------------------------ layout

    def _card(self, title: str, *items: Any) -> Any:
        return pn.Card(*items, title=title, collapsible=True, sizing_mode="stretch_width", margin=(4, 0))

    def _layout(self) -> Any:
        f = self.form
        texture_card = self._card("Texture", f.family.panel, f.texture_box, self.upload.panel, f.grid.panel)
        inputs = pn.Column(
            self.form_error,
            texture_card,
            self._card("Counter-surface material", *(x.panel for x in f.material.values())),
            self._card("Finger", f.preset.panel, *(x.panel for x in f.finger.values())),
            self._card("Loads", *(x.panel for x in f.loads.values())),
            self._card("Model", *(x.panel for x in f.model.values())),
            self._card("Population", self.population.inputs),
            self._card("Perception", self.perception.inputs),
            width=340, css_classes=["fp-inputs"], styles={"overflow-y": "auto"}, margin=(0, 8, 0, 0),
        )
        bem = self.bem.bar
        c = self.cards
        results = pn.Column(
            self.status, bem, self.summary, pn.Row(self.pin_button, self.exports), self.notes,
            pn.GridBox(c["areas"].panel, c["friction"].panel, c["friction-normalised"].panel, c["psi"].panel,
                       ncols=2, sizing_mode="stretch_width"),
            c["friction-directional"].panel,
            self.population.panel,
            self.perception.panel,
            pn.pane.HTML("<h4 style='margin:6px 0'>Unit cell</h4>"),
            pn.Row(self.pressure.panel, width=340),
            pn.GridBox(c["height-map"].panel, c["pressure-map"].panel, c["contact-map"].panel, ncols=3,
                       sizing_mode="stretch_width"),
            pn.pane.HTML("<h4 style='margin:6px 0'>Contact zones of the ridge disc</h4>"),
            pn.GridBox(c["zones"].panel, c["zone-profile"].panel, ncols=2, sizing_mode="stretch_width"),
            pn.pane.HTML("<h4 style='margin:6px 0'>Numbers (as <code>fingerpad predict</code>)</h4>"),
            self.table,
            sizing_mode="stretch_width",
        )
        return pn.Row(inputs, results, self.sequence.panel, sizing_mode="stretch_width", css_classes=["fp-single"])

    def _changed(self, event: Any) -> None:
        if not self._loading:
            self.refresh()

    def _watch_fields(self, fields: Any) -> None:
        """Refresh on a change of each field, watched once: the measured map's fields come back
        on every switch to that family (they are the form's own, not made anew), and a watcher
        added twice would refresh twice per change."""
        for fl in fields:
            if id(fl.widget) not in self._watched:
                self._watched.add(id(fl.widget))
                fl.widget.param.watch(self._changed, "value")

    def _watch_form(self) -> None:
        self._watched: set[int] = set()

        def family_changed(event: Any) -> None:
            if self._loading:
                return
            self.form.set_family(event.new)
            self.upload.show(event.new == MEASURED)
            self._watch_fields(self.form.texture_fields.values())
            self.refresh()

        self.form.family.widget.param.watch(family_changed, "value")
        self._watch_fields(fl for fl in self.form.all_fields() if fl is not self.form.family)
        self._watch_fields(self.form.measured.values())
        self.pressure.widget.param.watch(lambda e: self.maps.update(mark_psi=True, defer=False), "value")

    # ------------------------------------------------------------------ inputs

    def load_data(self, data: dict[str, Any]) -> None:
        """Show the design of study sections ``data`` (from a pin or the design map)."""
        self._loading = True
        try:
            self.form.load(data)
            self._watch_fields(self.form.texture_fields.values())
            self.upload.show(self.form.family.value == MEASURED)
        finally:
            self._loading = False
        self.refresh()

    def _on_upload(self, upload: StoredUpload | None, message: str | None, reading: bool) -> None:
        """Show the upload's state at once; read the map a moment later (``reading``), so that
        ``reading NAME ...`` reaches the page before the seconds of reading and checking."""
        self._loading = True
        try:
            self.form.surface.set_value("" if upload is None else upload.name)
        finally:
            self._loading = False
        self.form.surface.show(message, level="info" if reading or message and message.startswith("receiving")
                               else "error" if upload is None else "info")
        if not reading:
            if upload is None and message is None:
                self.refresh()
            return
        if self.doc is not None and self.doc.session_context is not None:
            self.doc.add_timeout_callback(self.refresh, 150)
        else:
            self.refresh()

    def current_data(self) -> dict[str, Any]:
        """The study of the form. The measured map's path is the server's own upload, never the
        widget's value: a client can set a disabled field's value to any text."""
        values = self.form.values()
        measured = "texture.surface" in values
        values.pop("texture.surface", None)
        data = study_data(values)
        if measured:
            shown = "" if self.upload.current is None else self.upload.current.name
            if self.form.surface.value != shown:  # a forged value: show the truth again
                self._loading = True
                try:
                    self.form.surface.set_value(shown)
                finally:
                    self._loading = False
            if self.upload.current is not None:
                data.setdefault("texture", {})["surface"] = str(self.upload.current.path)
        return data

    # ------------------------------------------------------------------ computing

    def refresh(self) -> None:
        """Rebuild and check the study from the form; show what is known for it."""
        data = self.current_data()
        check = validate(data, uploads=self.upload.area, upload=self.upload.current)
        loose = self.form.show_messages(check.errors, check.warnings)
        errors = [e for e in loose if not e.warning]
        warns = [e for e in loose if e.warning]
        self.form_error.object = "".join(
            f'<div class="fp-{"warning" if e.warning else "error"}" style="color:{"#8a5a00" if e.warning else "#b00020"};'
            f'font-size:12px">{html.escape(e.message)}</div>' for e in [*errors, *warns])
        self.form_error.visible = bool(errors or warns)
        if not check.ok:
            self.data = None
            self.bem.allow(False)
            self.status.object = ('<div class="fp-stale" style="background:#fff3cd;padding:4px 8px">Fix the inputs '
                                  'marked in red; the plots show the last valid design.</div>')
            return
        self.data = data
        self._supersede(data)
        self.bem.allow(True)
        self.texture = check.study.build_texture()
        kind = data.get("model", {}).get("kind", "both")
        pred, shown, pending = None, None, False
        try:
            if kind == "hertz":
                pred = self._hertz(data)
                shown = data
            else:
                pred = self.app.memo.get(data)
                shown = data if pred is not None else None
                if pred is None:
                    pending = True
                    if kind == "both" and self._supports_hertz():
                        shown = _with_kind(data, "hertz")
                        pred = self._hertz(shown)
        except FingerpadError as exc:
            self.status.object = (f'<div class="fp-error" style="color:#b00020">'
                                  f"{html.escape(self._words(one_line(str(exc))))}</div>")
            return
        if self.upload.current is not None and "surface" in data.get("texture", {}):
            self.form.surface.show(f"{self.upload.current.name}: {self.texture.shape[0]} x {self.texture.shape[1]} "
                                   "points", level="info")
        self.show(pred, shown, pending)
        if pending and self.bem.auto.value:
            self.after_quiet(self.bem.start)

    def _supersede(self, data: dict[str, Any]) -> None:
        """``data`` is another design than the one the background work is for: stop that work (a
        BEM run of another design, the contact maps, the population's fingers) and wait for a
        quiet time before starting the new design's."""
        key = data_key(data)
        if key == self._design:
            return
        self._design = key
        self._generation += 1
        self.sequence.change()
        self.bem.supersede(bem_data(data))
        self.maps.cancel()
        self.population.cancel()

    @property
    def generation(self) -> int:
        """How many designs the view has shown (a new one for every change of design)."""
        return self._generation

    def after_quiet(self, fn: Callable[[], None], seconds: float = QUIET_S) -> None:
        """Call ``fn`` (holding the document) once the design shown now has stayed shown for
        ``seconds``; never if another design is shown first. At once without a session."""
        generation = self._generation

        def run() -> None:
            if generation == self._generation:
                fn()

        if self.doc is not None and self.doc.session_context is not None:
            self.doc.add_timeout_callback(run, int(1000 * seconds))
        else:
            run()

    def run_async(self, fn: Callable[[], Any]) -> None:
        """Run the coroutine function ``fn`` on the server's loop (Panel's ``state.execute``)."""
        pn.state.execute(fn)

    def _words(self, text: str) -> str:
        """A library message in the page's words (the user's file name, the page's fields)."""
        return page_message(text, self.upload.current, self.upload.area.root)

    def _supports_hertz(self) -> bool:
        from ...micro.hertz import supports_hertz

        return self.texture is not None and supports_hertz(self.texture)

    def _hertz(self, data: dict[str, Any]) -> Any:
        pred = self.app.memo.get(data)
        if pred is None:
            pred = run_data(data)
            self.app.memo.put(data, pred)
        return pred

    def _locked(self, fn: Any) -> None:
        """Run ``fn`` holding the document's lock (from async work: on the document's next tick)."""
        if self.doc is not None and self.doc.session_context is not None:
            self.doc.add_next_tick_callback(fn)
        else:
            fn()

    # ------------------------------------------------------------------ showing

    def show(self, pred: Any, shown: dict[str, Any] | None, pending: bool) -> None:
        self.pred, self.shown_data, self.pending = pred, shown, pending
        kind = (self.data or {}).get("model", {}).get("kind", "both")
        if pending:
            what = "BEM not computed for these inputs: press Run BEM (the curves shown are Hertz's)" \
                if pred is not None else "BEM not computed for these inputs: press Run BEM"
            self.status.object = f'<div class="fp-pending" style="background:#e8f0fe;padding:4px 8px">{what}</div>'
        else:
            self.status.object = (f'<div class="fp-current" style="background:#e6f4ea;padding:4px 8px">showing: '
                                  f"model {html.escape(pred.primary_model if pred else kind)} for the inputs on the "
                                  "left</div>")
        self.pin_button.disabled = pred is None
        if pred is None:
            self.summary.object = ""
            self.table.object = ""
            if self.table.styles == _DIMMED:
                self.table.styles = _BRIGHT
            self.notes.object = ""
        else:
            self._show_numbers(pred)
        self.sequence.numbers_sent()
        self.sequence.figures(self._show_figures)  # in a sequence: once it pauses

    def _show_figures(self) -> None:
        """The figures of the prediction shown (and its population, its contact maps)."""
        pred, c = self.pred, self.cards
        if pred is not None and self.table.styles == _DIMMED:  # dimmed in a sequence: its numbers now
            self._show_table(self._derived(pred, "json", lambda: _prediction_json(pred)))
        updates = [(c["height-map"], builders.height_map_spec(pred.texture if pred is not None and pred.cell
                                                              is not None else self.texture), None)]
        if pred is None:
            updates += [(c[key], None, "run the BEM to see this plot")
                        for key in ("areas", "friction", "friction-normalised", "psi", "zones", "zone-profile")]
            updates.append((c["friction-directional"], None, None))
        else:
            panels = self._derived(pred, "panels", lambda: builders.prediction_panels(pred))  # predict's figures
            updates += [(c[key], panels.get(key), None) for key in ("areas", "friction", "friction-normalised",
                                                                    "friction-directional", "zones", "zone-profile")]
            mark = self._contact_pressure()
            updates.append((c["psi"], self._derived(pred, ("psi", mark), lambda: builders.psi_spec(pred, mark)), None))
        set_cards(updates)
        self.population.update()
        self.perception.update()
        self.maps.update()  # psi was drawn above with the contact map's pressure

    def _derived(self, pred: Any, what: Any, make: Any) -> Any:
        """``make()``, remembered per prediction (the server's, shared by its sessions): what the
        page shows of a prediction does not change."""
        key = (id(pred), what)
        hit = self.app.derived.get_key(key)
        if hit is not None and hit[0] is pred:  # the id of a prediction still held, not a reused one
            return hit[1]
        value = make()
        self.app.derived.put_key(key, (pred, value))
        return value

    def _show_numbers(self, pred: Any) -> None:
        payload = self._derived(pred, "json", lambda: _prediction_json(pred))
        crit, full = payload["critical_load"], payload["full_contact_load"]
        parts = [f"<b>shown model:</b> {html.escape(payload['model'])}",
                 f"E1* = {num_span('reduced_modulus', payload['inputs']['reduced_modulus'], 'Pa')}"]
        for model in ("bem", "hertz"):
            if crit.get(model) is not None:
                parts.append(f"critical load ({model}) = {num_span('critical_load_' + model, crit[model], 'N')}")
        if full.get("bem") is not None:
            parts.append(f"full contact from = {num_span('full_contact_load_bem', full['bem'], 'N')}")
        res = (payload.get("cell") or {}).get("resolution")
        if res and res.get("area_ratio_error") is not None:
            parts.append(f"grid {'x'.join(map(str, res['grid']))} px, estimated error of A_re/A_fr "
                         f"{num_span('area_ratio_error', 100 * res['area_ratio_error'], '%', 2)}")
        z = payload["zones"]
        parts.append(f"at {num_span('zones_load', z['load'], 'N')}: A_re/A_fr = "
                     f"{num_span('zones_area_ratio', z['area_ratio'])}, centre {html.escape(z['contact_state'])}")
        # each pane's change goes to the page as a message of its own: the table first, the
        # summary last, so that a page whose summary shows a design has its table too (in a
        # sequence the table is dimmed, and filled with the figures once the sequence pauses)
        self._show_table(payload if not self.sequence.rapid else None)
        self.notes.object = "".join(f'<div style="font-size:12px;color:#555">note: {html.escape(self._words(n))}</div>'
                                    for n in payload["notes"])
        self.summary.object = '<div style="font-size:13px;line-height:1.6">' + " &middot; ".join(parts) + "</div>"

    def _show_table(self, payload: dict[str, Any] | None) -> None:
        """The table of the prediction shown (``payload``: its JSON), or, with ``None``, the table
        of the design before dimmed: in a sequence the browser would parse and lay out the table's
        ~1000 nodes for every design passed over (a third of Chromium's work for a change's
        numbers, issue 37); its summary is the number a designer reads while the hand moves."""
        if payload is None:
            if self.table.object:
                self.table.styles = _DIMMED
            return
        self.table.object = html_table(_RESULT_COLUMNS, payload["results"], "fp-results")
        if self.table.styles == _DIMMED:
            self.table.styles = _BRIGHT

    def _contact_pressure(self) -> float | None:
        """The pressure of the contact map: the field's value, else the centre pressure at the zone load."""
        from ...study.values import quantity

        text = str(self.pressure.value).strip()
        if text:
            try:
                p = quantity(text, "pressure", "contact-map pressure")
                if p <= 0:
                    raise FingerpadError(f"contact-map pressure: must be positive, got {text!r}")
            except FingerpadError as exc:
                self.pressure.show(one_line(str(exc)))
                return None
            self.pressure.show(None)
            return p
        self.pressure.show(None)
        if self.pred is not None:
            return float(self.pred.zones["peak_pressure"])
        return None

    # ------------------------------------------------------------------ pins and exports

    def pin(self) -> None:
        if self.pred is not None and self.shown_data is not None:
            self.app.pin(self.shown_data, self.pred)
