"""The population part of the single-texture view (issue 22): a population of fingers chosen by
preset name, its bands of A_re/A_fr and mu/mu_ref against load and its critical loads.

The population is :func:`fingerpad.population.run.run_population` on the study of the design
shown (the library computes everything; the unit cell is solved once for every finger). It runs
in one worker thread per server, once the design has stayed shown a moment, the latest request of
a session first (a request whose design is no longer shown is skipped, one under way is
cancelled: :mod:`fingerpad.cancel`), and the results are remembered per design and population,
so a design seen before shows its bands at once.

Only names are accepted from the page: the built-in presets and the populations the server was
started with (``fingerpad explore --population FILE|DIR``, read once at start, by the person who
started it). :func:`~fingerpad.population.sources.load_population` also reads files, and a page
must never name a file on the server.
"""

from __future__ import annotations

import asyncio
import html
import time
import warnings
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from collections.abc import Mapping
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

from ...cancel import CancelToken, Cancelled, cancellable
from ...errors import FingerpadError, one_line
from .. import builders
from ..inputs import data_key, labels_for
from .common import PlotCard, guard_choices, html_pane, num_span, set_cards

__all__ = ["NONE", "PopulationPanel", "population_choices", "run_preset"]

#: The choice that shows no population.
NONE = "none"
_KEYS = ("population-area-ratio", "population-normalised", "population-critical-load")
_POOL: ThreadPoolExecutor | None = None


def population_choices(extra: Mapping[str, Any] | None = None) -> list[str]:
    """The choices of the page: none, the built-in presets and the server's own populations
    ``extra`` (label -> :class:`~fingerpad.population.distributions.Population`; never a path)."""
    from ...population.presets import POPULATION_PRESETS

    return [NONE, *POPULATION_PRESETS, *(extra or {})]


def run_preset(data: dict[str, Any], name: str, extra: Mapping[str, Any] | None = None) -> Any:
    """The :class:`~fingerpad.population.run.PopulationResult` of population ``name`` on the
    study of ``data``: one of the server's populations ``extra`` (by label) or a preset; any other
    name is refused (never read as a file)."""
    from ...population.run import run_population
    from ...population.sources import load_population
    from ...population.presets import POPULATION_PRESETS
    from ...study.spec import study_from_dict

    if extra and name in extra:
        population = extra[name]
    elif name in POPULATION_PRESETS:
        population = load_population(name)
    else:
        raise FingerpadError(f"population: choose one of {', '.join(population_choices(extra))}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_population(study_from_dict(data, labels_for(data)), population)


def _pool() -> ThreadPoolExecutor:
    """One worker for the populations of the server: a population costs a second of the CPU, and
    queued requests of designs no longer shown are skipped."""
    global _POOL
    if _POOL is None:
        _POOL = ThreadPoolExecutor(max_workers=1, thread_name_prefix="fingerpad-explore-population")
    return _POOL


class PopulationPanel:
    """The population choice (an input) and its results (a section of the results)."""

    def __init__(self, view: Any) -> None:
        self.view = view
        self.cache = view.app.populations
        # those given to `fingerpad explore --population` (none for a page built without a server state)
        self.extra = getattr(getattr(view.app, "state", None), "extra_populations", {})
        self.choice = pn.widgets.Select(label="population of fingers", options=population_choices(self.extra),
                                        value=NONE,
                                        css_classes=["fp-population"], width=300)
        self.help = pn.pane.HTML(
            "<div style='font-size:11px;color:#555'>the fingers of a built-in population (docs/population.md): "
            "bands of the results over the population, the critical loads' distribution</div>")
        self.message = html_pane("", css_classes=["fp-population-msg"], sizing_mode="stretch_width")
        self.status = html_pane("", css_classes=["fp-population-status"], sizing_mode="stretch_width")
        self.summary = html_pane("", css_classes=["fp-population-summary"], sizing_mode="stretch_width")
        self.cards = {k: PlotCard(k, height=330) for k in _KEYS}
        self.result: Any = None
        self._token = CancelToken()
        self._key: tuple[str, str] | None = None  # what the token's work computes
        #: (the design's data key, the population's name) of :attr:`result`
        self.result_key: tuple[str, str] | None = None
        self.inputs = pn.Column(self.choice, self.message, self.help, sizing_mode="stretch_width")
        self.panel = pn.Column(
            pn.pane.HTML("<h4 style='margin:6px 0'>Population of fingers</h4>"), self.status, self.summary,
            pn.GridBox(*(c.panel for c in self.cards.values()), ncols=2, sizing_mode="stretch_width"),
            sizing_mode="stretch_width", visible=False, css_classes=["fp-population-section"])
        self.choice.param.watch(lambda e: self.update(), "value")
        guard_choices(self.choice, self._forged)

    def _forged(self, shown: str) -> None:
        """A choice outside the options (a path, a name the server does not hold): nothing is
        read; the selector goes back to none, and the page says which choices there are."""
        self.message.object = (f'<div class="fp-error" style="font-size:12px;color:#b00020">population: choose '
                               f"one of {html.escape(', '.join(population_choices(self.extra)))}</div>")
        self.choice.value = NONE

    def _say(self, text: str, css: str, colour: str = "#555") -> None:
        self.status.object = f'<div class="{css}" style="font-size:12px;color:{colour}">{html.escape(text)}</div>'

    def update(self) -> None:
        """Show the chosen population for the design shown (from memory, else computed in the
        background); called on a new choice and on every new design shown."""
        name = self.choice.value
        data = self.view.shown_data
        key = None if data is None else (data_key(data), name)
        if key is not None and key == self._key and not self._token.cancelled:
            return  # under way for this design and population
        self.cancel()
        self._token = token = CancelToken()
        if name == NONE:
            self.panel.visible = False
            self.result = self.result_key = None
            self._changed()
            return
        self.panel.visible = True
        if name not in population_choices(self.extra):  # a forged choice: nothing is read, the choice is reset
            self._forged(name)
            return
        self.message.object = ""
        pred = self.view.pred
        if data is None or pred is None:
            self._clear()
            self._say("population: shown once the design has a prediction", "fp-population-pending")
            return
        hit = self.cache.get_key(key)
        if hit is not None:
            self._show(hit, key)
            return
        self._key = key
        self._say(f"population {name}: computing its fingers...", "fp-population-running")
        # a coroutine function, awaited; once the design has stayed shown
        self.view.after_quiet(lambda: self.view.run_async(partial(self._compute, token, key, data, name)))

    def cancel(self) -> None:
        """Stop the population under way (the design it is for is no longer shown)."""
        self._token.cancel()
        self._key = None

    async def _compute(self, token: CancelToken, key: tuple[str, str], data: dict[str, Any], name: str) -> None:
        def work() -> tuple[Any, str | None]:
            if token.cancelled:  # a newer request of this session: skip
                return None, None
            hit = self.cache.get_key(key)
            if hit is not None:
                return hit, None
            cpu = time.thread_time()
            try:
                with cancellable(token):
                    result = run_preset(data, name, self.extra)
            except Cancelled:
                return None, None
            except FingerpadError as exc:
                return None, one_line(str(exc))
            finally:
                self.view.app.worklog.add("population", time.thread_time() - cpu, token.cancelled, token)
            self.cache.put_key(key, result)
            return result, None

        result, error = await asyncio.get_running_loop().run_in_executor(_pool(), work)

        def apply() -> None:
            if self._token is not token or token.cancelled:
                return
            self._key = None  # done: a request of this design reads the cache from now on
            if error is not None:
                self._clear()
                self._say(f"population {name}: {self.view._words(error)}", "fp-population-error", "#b00020")
            elif result is not None:
                self._show(result, key)

        self.view._locked(apply)

    def _clear(self) -> None:
        self.result = self.result_key = None
        self.summary.object = ""
        for card in self.cards.values():
            card.set(None)

    def _show(self, result: Any, key: tuple[str, str] | None = None) -> None:
        self.result, self.result_key = result, key
        set_cards((card, spec, None) for card, spec in zip(self.cards.values(), builders.population_specs(result),
                                                           strict=True))
        q = result.quantiles()["critical_load"]
        levels = sorted(result.quantile_levels)
        lo, hi = levels[0], levels[-1]
        crit = result.critical_load
        never = int((~(crit < float("inf"))).sum())
        parts = [f"<b>population {html.escape(result.population.name)}:</b> "
                 f"{num_span('population_members', len(result.members), '', 6)} fingers, model "
                 f"{html.escape(result.nominal.primary_model)}",
                 f"critical load median {num_span('population_critical_load_0.5', q.get('0.5'), 'N')}, "
                 f"{100 * lo:g}-{100 * hi:g} %: {num_span(f'population_critical_load_{lo:g}', q.get(f'{lo:g}'), 'N')}"
                 f" to {num_span(f'population_critical_load_{hi:g}', q.get(f'{hi:g}'), 'N')}",
                 f"{num_span('population_never', never, '', 6)} never reach the transition"]
        self.summary.object = '<div style="font-size:13px;line-height:1.6">' + " &middot; ".join(parts) + "</div>"
        notes = "; ".join(result.notes)
        self._say(f"population {result.population.name}: the study shown, {len(result.members)} fingers"
                  + (f" ({notes})" if notes else ""), "fp-population-done")
        self._changed()

    def _changed(self) -> None:
        """The view's perception section follows the population shown (issue 32)."""
        perception = getattr(self.view, "perception", None)
        if perception is not None:
            perception.update()
