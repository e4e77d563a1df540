"""Pieces every view shares: a plot card (Bokeh figure + CSV/JSON/PNG/SVG downloads), number
formatting, HTML tables of results."""

from __future__ import annotations

import html
import io
import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import ExitStack, contextmanager
from functools import partial
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

from ...plotting.specs import PlotSpec, spec_csv, spec_json

__all__ = ["PlotCard", "download", "fmt", "guard_choices", "html_pane", "html_table", "num_span", "one_walk",
           "set_cards"]

FORMATS = ("csv", "json", "png", "svg")


_HTML: Any = None


def html_pane(obj: str = "", **params: Any) -> Any:
    """An HTML pane whose changes send the browser what changed (its text), not its style sheets.

    Panel's HTML pane sends all its properties on every change of its text, the style sheets
    among them; in a served session the first such change brings new style-sheet models (the
    ones the page was built with are not found again), and BokehJS then re-renders the pane and
    restyles the page: 2.6-4.8 s in Chromium on 2 cores for the first change after the page
    opened, which touches the summary, the notes and the table (issue 37). The explorer never
    changes a pane's style sheets after it is made."""
    global _HTML
    if _HTML is None:
        class _Html(pn.pane.HTML):
            def _update(self, ref: str, model: Any) -> None:
                props = self._get_properties(model.document)
                props.pop("stylesheets", None)
                model.update(**props)

        _HTML = _Html
    return _HTML(obj, **params)


def guard_choices(widget: Any, on_refused: Callable[[str], None] | None = None) -> Any:
    """Check every value the page sends for the select ``widget`` here, before Panel's own check.

    Whatever a page sends is untrusted: a value outside the options reached Panel's select,
    which refused it by raising, so that the package's own check (a population choice reset to
    ``none`` with a message, docs/explorer.md) never ran, the page kept showing the forged
    value, and Panel logged the whole value with a traceback (5 MB into the server's output).
    Here such a value is dropped, one log line quotes a bounded excerpt of it, the page is sent
    the widget's value again, and ``on_refused(excerpt)`` is called (e.g. to reset the choice and
    say why). Returns ``widget``.
    """
    import logging

    from ...errors import excerpt

    process = widget._process_events  # Panel's handler of the page's changes (bound method)

    def checked(events: dict[str, Any]) -> None:
        if "value" in events and events["value"] not in list(widget.labels):
            events = dict(events)
            shown = excerpt(events.pop("value"))
            logging.getLogger("fingerpad.explore").warning("refused a value from the page for %r: %s",
                                                           widget.name or widget.css_classes, shown)
            widget.param.trigger("value")  # the page shows the widget's value again
            if on_refused is not None:
                on_refused(shown)
        if events:
            process(events)

    widget._process_events = checked
    return widget


def fmt(value: Any, digits: int = 4) -> str:
    """A number for display (``-`` for None/NaN, ``inf`` spelled out)."""
    if value is None:
        return "-"
    if isinstance(value, str):
        return value
    v = float(value)
    if math.isnan(v):
        return "-"
    if math.isinf(v):
        return "never (inf)" if v > 0 else "-inf"
    return f"{v:.{digits}g}"


def num_span(key: str, value: Any, unit: str = "", digits: int = 4) -> str:
    """A number in the page with its full-precision value in ``data-value`` (read by tests and
    scripts; what is shown is rounded)."""
    raw = "" if value is None else repr(float(value)) if not isinstance(value, str) else value
    text = fmt(value, digits) + (f" {unit}" if unit and value is not None and fmt(value) != "-" else "")
    return f'<span class="fp-num" data-key="{html.escape(key)}" data-value="{html.escape(raw)}">{html.escape(text)}</span>'


def html_table(columns: Sequence[tuple[str, str]], rows: Sequence[dict[str, Any]], css: str) -> str:
    """An HTML table; ``columns``: (key, header); each cell carries ``data-key``/``data-value``."""
    head = "".join(f"<th>{html.escape(h)}</th>" for _, h in columns)
    body = []
    for row in rows:
        cells = []
        for key, _ in columns:
            v = row.get(key)
            raw = "" if v is None else (repr(float(v)) if isinstance(v, (int, float)) and not isinstance(v, bool)
                                        else str(v))
            shown = fmt(v) if not isinstance(v, str) else v
            cells.append(f'<td data-key="{html.escape(key)}" data-value="{html.escape(raw)}">{html.escape(shown)}</td>')
        body.append("<tr>" + "".join(cells) + "</tr>")
    style = ("<style>.fp-table{border-collapse:collapse;font-size:12px}.fp-table th,.fp-table td{border-bottom:1px "
             "solid #ddd;padding:2px 6px;text-align:right;white-space:nowrap}.fp-table th{background:#f4f4f4}</style>")
    return f'{style}<table class="fp-table {css}"><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'


def download(label: str, filename: str, make: Callable[[], bytes | str], css: str) -> Any:
    """A download button whose file is made when clicked (in memory, nothing written on disk)."""

    def callback() -> io.BytesIO:
        # the name is the server's: a client may have set the widget's filename to anything
        widget.filename = filename
        data = make()
        return io.BytesIO(data.encode("utf-8") if isinstance(data, str) else data)

    widget = pn.widgets.FileDownload(callback=callback, filename=filename, label=label, color="light",
                                     css_classes=[css], embed=False, width=70, height=30, margin=(0, 4))
    return widget


class PlotCard:
    """A plot of the explorer: its Bokeh figure and downloads of its data and image.

    A new spec goes into the figure shown (its data, legend, title and ranges replaced in place:
    :func:`..render_bokeh.update_figure`); the figure is rebuilt only when its frame changes (the
    axes' quantities or scales). ``in_place = False`` rebuilds it on every change, as the explorer
    did before issue 23 (``benchmarks/bench_explorer.py`` measures both).
    """

    in_place = True

    def __init__(self, key: str, height: int = 330, width: int | None = None) -> None:
        self.key = key
        self.height = height
        self.width = width
        self.spec: PlotSpec | None = None
        self.drawn: Any = None
        self.pane = pn.pane.Bokeh(None, sizing_mode="stretch_width" if width is None else "fixed",
                                  css_classes=[f"fp-plot-{key}"], min_height=height)
        self.note = html_pane("", css_classes=[f"fp-plot-{key}-note"], visible=False,
                                 styles={"color": "#666", "font-size": "12px"})
        buttons = [download(f.upper(), f"fingerpad-{key}.{f}", partial(self._data, f), f"fp-dl-{key}-{f}")
                   for f in FORMATS]
        self.downloads = pn.Row(pn.pane.HTML("<span style='font-size:12px;color:#555'>download:</span>",
                                             margin=(6, 4)), *buttons, visible=False)
        self.panel = pn.Column(self.pane, self.note, self.downloads, sizing_mode="stretch_width",
                               css_classes=["fp-card", f"fp-card-{key}"],
                               styles={"border": "1px solid #e3e3e3", "border-radius": "4px"}, margin=(4, 4))

    def _data(self, fmt_: str) -> bytes | str:
        spec = self.spec
        if spec is None:
            return b""
        if fmt_ == "csv":
            return spec_csv(spec)
        if fmt_ == "json":
            return spec_json(spec)
        from ...plotting.render import spec_image

        return spec_image(spec, fmt_)

    def set(self, spec: PlotSpec | None, note: str | None = None) -> None:
        """Show ``spec`` (``None``: nothing, with ``note`` saying why). A spec of the same structure
        as the one shown only replaces the figure's data."""
        from ..render_bokeh import bokeh_figure, update_figure

        self.spec = spec if spec is not None and not spec.empty else None
        if self.spec is None:
            self.pane.visible = False
            self.downloads.visible = False
        else:
            with pn.io.unlocked():  # changes the figure's models directly (Panel dispatches them)
                updated = self.in_place and self.drawn is not None and update_figure(self.drawn, self.spec)
            if not updated:
                self.drawn = bokeh_figure(self.spec, height=self.height, width=self.width)
                self.pane.object = self.drawn.figure
            self.pane.visible = True
            self.downloads.visible = True
        self.note.object = html.escape(note) if note else ""
        self.note.visible = bool(note)
        self.panel.visible = self.spec is not None or bool(note)  # nothing to say: no empty card


def set_cards(updates: Iterable[tuple[PlotCard, PlotSpec | None, str | None]]) -> None:
    """``card.set(spec, note)`` for each update, with Bokeh's walk over the document's models
    done at most once for all of them (:func:`one_walk`).

    Every change of a property that refers to models (a new series, a figure's renderers in
    another order, a legend's items, the hover tool's renderers) makes Bokeh walk the whole
    document: tenths of a second each on a full page. Going from one design to another of other
    contact states or series changes such lists in every figure; the page once walked its
    document 25 times for one BEM design shown (issue 23)."""
    todo = list(updates)
    docs = {id(d): d for card, _, _ in todo if card.drawn is not None
            and (d := card.drawn.figure.document) is not None}
    with ExitStack() as stack:
        for doc in docs.values():
            stack.enter_context(one_walk(doc))
        for card, spec, note in todo:
            card.set(spec, note)


@contextmanager
def one_walk(doc: Any) -> Iterator[None]:
    """Defer the walks over ``doc``'s models that changes in the body ask for to one walk at its
    end, and none if none was asked for.

    Bokeh's own :meth:`~bokeh.document.models.DocumentModelManager.freeze` walks the document at
    its end whether or not a change asked for it (a walk costs as much as the change of several
    figures' data); the only caller of ``invalidate`` is a model's change of a property that
    refers to models (``Model.trigger``), so deferring those calls defers exactly what ``freeze``
    defers. Nested uses defer to the outermost."""
    models = doc.models
    if "invalidate" in vars(models):  # an enclosing update defers already
        yield
        return
    asked = False

    def invalidate() -> None:
        nonlocal asked
        asked = True

    models.invalidate = invalidate
    try:
        yield
    finally:
        del models.invalidate
        if asked:
            models.invalidate()
