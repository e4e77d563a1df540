"""The unit cell's contact and pressure maps of the single-texture view: one contact solve at the
contact-map pressure, in a worker thread, for the design shown only.

A map solved before (the server remembers the last ones) is shown right after the design's
numbers (on the document's next tick: the numbers' patch goes out first). A new one is solved once the design has stayed shown for
:data:`~fingerpad.explore.views.single.QUIET_S` (a designer stepping or dragging through values
makes the page solve no map of the designs passed over), and a change stops the solve under way
within one iteration of the solver (:mod:`fingerpad.cancel`): the numbers of the next design never
wait for the maps of the last one. The solve uses one FFT thread: the server's other core is the
numbers'.
"""

from __future__ import annotations

import asyncio
import time
from functools import partial
from typing import Any

from ...cancel import CancelToken, Cancelled
from ...errors import FingerpadError, one_line
from .. import builders
from ..inputs import validate
from ..jobs import contact_at, remembered_contact
from .common import set_cards

__all__ = ["ContactMaps"]

_KEYS = ("pressure-map", "contact-map")


class ContactMaps:
    """The two map cards of a view and the solve behind them."""

    def __init__(self, view: Any) -> None:
        self.view = view
        self.token = CancelToken()
        self.token.cancel()  # nothing under way

    def cancel(self) -> None:
        """Stop the solve under way (its result is never shown)."""
        self.token.cancel()

    def update(self, mark_psi: bool = False, defer: bool = True) -> None:
        """Show the maps of the design shown at the contact-map pressure: at once when solved
        before, else by a solve in the background (after the quiet time with ``defer``).
        ``mark_psi``: the pressure changed, mark it on psi(p) too."""
        view = self.view
        self.cancel()
        self.token = token = CancelToken()
        pressure = view._contact_pressure()
        if pressure is None or view.data is None:
            note = "give a valid contact-map pressure" if view.data else None
            view._locked(lambda: set_cards((view.cards[k], None, note) for k in _KEYS))
            return
        pred = view.pred
        texture = pred.texture if pred is not None and pred.cell is not None else view.texture
        study = validate(view.data, check=False).study
        if texture is None or study is None or not texture.periodic:
            return
        args = (texture, study.reduced_modulus, pressure)
        opts = {"tol": study.tol, "max_iter": study.max_iter}
        hit = remembered_contact(*args, **opts, cache=view.app.contacts)
        if hit is not None:  # on the next tick: the change's numbers go to the page first
            view._locked(lambda: self._apply(token, hit, pressure, mark_psi))
            return

        def start() -> None:
            if not token.cancelled:
                view.run_async(partial(self._solve, token, args, opts, pressure, mark_psi))

        if defer:
            view.after_quiet(start)
        else:
            start()

    async def _solve(self, token: CancelToken, args: tuple[Any, ...], opts: dict[str, Any], pressure: float,
                     mark_psi: bool) -> None:
        view, log = self.view, self.view.app.worklog

        def work() -> Any:
            cpu = time.thread_time()
            try:
                return contact_at(*args, **opts, cache=view.app.contacts, token=token, workers=1)
            finally:
                log.add("contact maps", time.thread_time() - cpu, token.cancelled, token)

        try:
            res = await asyncio.get_running_loop().run_in_executor(None, work)
        except Cancelled:
            return
        except FingerpadError as exc:
            if not token.cancelled:
                view._locked(lambda: view.pressure.show(one_line(str(exc))))
            return
        view._locked(lambda: self._apply(token, res, pressure, mark_psi))

    def _apply(self, token: CancelToken, res: Any, pressure: float, mark_psi: bool) -> None:
        if token.cancelled:
            return
        view = self.view
        pmap, cmap = builders.contact_specs(res)
        updates = [(view.cards["pressure-map"], pmap, None), (view.cards["contact-map"], cmap, None)]
        if mark_psi and view.pred is not None:
            updates.append((view.cards["psi"], builders.psi_spec(view.pred, pressure), None))
        set_cards(updates)
