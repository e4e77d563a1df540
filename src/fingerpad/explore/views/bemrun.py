"""The BEM run of the single-texture view: *Run BEM*, *Cancel*, its progress, and *run the BEM on
every change*.

The run is a :class:`..jobs.Job` (a thread) on the design shown. A change to another design
cancels it (within one iteration of the contact solve under way: :mod:`fingerpad.cancel`); with
*run the BEM on every change*, the new design's run starts once it has stayed shown a moment
(:meth:`.single.SingleView.after_quiet`), and the Hertz numbers are shown at once meanwhile.
"""

from __future__ import annotations

import asyncio
import copy
import html
from typing import Any

import lazy_loader

pn = lazy_loader.load("panel")

from ..inputs import data_key
from ..jobs import Job
from .common import html_pane

__all__ = ["BemRun", "bem_data"]


def bem_data(data: dict[str, Any]) -> dict[str, Any]:
    """The study a BEM run of ``data`` computes (model both where ``data`` asks for Hertz only)."""
    if data.get("model", {}).get("kind") != "hertz":
        return data
    out = copy.deepcopy(data)
    out["model"]["kind"] = "both"
    return out


class BemRun:
    """The BEM bar of a view and the job behind it."""

    def __init__(self, view: Any) -> None:
        self.view = view
        self.job: Job | None = None
        self.run_button = pn.widgets.Button(label="Run BEM", color="primary", css_classes=["fp-run-bem"],
                                            width=110)
        self.cancel_button = pn.widgets.Button(label="Cancel", color="warning", css_classes=["fp-cancel-bem"],
                                               width=90, disabled=True)
        self.auto = pn.widgets.Checkbox(label="run the BEM on every change", value=False,
                                        css_classes=["fp-auto-bem"])
        self.progress = pn.indicators.Progress(value=0, max=100, width=220, visible=False,
                                               css_classes=["fp-progress"], bar_color="primary")
        self.status = html_pane("", css_classes=["fp-job-status"], sizing_mode="stretch_width")
        self.run_button.on_click(lambda e: self.start())
        # ticked with a design whose BEM is not computed: its run starts now
        self.auto.param.watch(lambda e: self.start() if e.new and view.pending else None, "value")
        self.cancel_button.on_click(lambda e: self.cancel())
        self.bar = pn.Row(self.run_button, self.cancel_button, self.progress, self.status, self.auto,
                          sizing_mode="stretch_width", css_classes=["fp-bem-bar"])

    @property
    def running(self) -> bool:
        return self.job is not None and not self.job.finished

    def allow(self, valid: bool) -> None:
        """*Run BEM* is offered for valid inputs while no run is under way."""
        self.run_button.disabled = not valid or self.running

    def supersede(self, data: dict[str, Any]) -> None:
        """The design shown is now ``data`` (its BEM study): a run of another design stops."""
        if self.running and data_key(self.job.data) != data_key(data):
            self.job.cancel()

    def start(self) -> None:
        """Run the BEM study of the design shown in the background (a run of another is cancelled)."""
        view = self.view
        if view.data is None:
            return
        data = bem_data(view.data)
        if self.running:
            if data_key(self.job.data) == data_key(data) and not self.job.cancelling:
                return  # already running for this design
            self.job.cancel()
        self.job = Job(data, view.app.memo, log=view.app.worklog)
        self.progress.value, self.progress.visible = 0, True
        self.cancel_button.disabled, self.run_button.disabled = False, True
        self.status.object = '<span class="fp-job-running">BEM unit cell: starting...</span>'
        view.run_async(self._watch)

    def cancel(self) -> None:
        if self.running:
            self.job.cancel()
            self.status.object = '<span class="fp-job-cancelling">cancelling...</span>'

    async def _watch(self) -> None:
        job = self.job
        while job is not None and not job.finished:
            if job is not self.job:
                return
            if not job.cancelling:
                self.progress.value = int(100 * job.fraction)
                self.status.object = (f'<span class="fp-job-running">BEM unit cell: {job.done} / {job.total} '
                                      f"solves, {job.elapsed:.0f} s</span>" if job.total else
                                      '<span class="fp-job-running">BEM unit cell: preparing...</span>')
            await asyncio.sleep(0.25)
        if job is None or job is not self.job:
            return
        self.view._locked(lambda: self._finished(job))

    def _finished(self, job: Job) -> None:
        view = self.view
        self.progress.visible = False
        self.cancel_button.disabled = True
        self.run_button.disabled = view.data is None
        if job.state == "done":
            solves = job.result.resolution["solves"] if job.result.resolution else 0
            self.status.object = (f'<span class="fp-job-done">BEM done in {job.seconds:.1f} s '
                                  f"({solves} solves{', from the cache' if solves == 0 else ''})</span>")
            if view.data is not None and data_key(job.data) == data_key(bem_data(view.data)):
                view.show(job.result, job.data, False)
        elif job.state == "cancelled":
            self.status.object = '<span class="fp-job-cancelled">BEM cancelled</span>'
        else:
            self.status.object = (f'<span class="fp-job-failed" style="color:#b00020">BEM failed: '
                                  f"{html.escape(view._words(job.error or ''))}</span>")
