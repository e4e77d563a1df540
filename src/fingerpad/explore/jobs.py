"""Running predictions for the explorer: at once (cheap models) or as background jobs (the BEM).

A prediction is always :func:`fingerpad.study.run.run_study` on a study that
:func:`fingerpad.study.spec.study_from_dict` built: the explorer computes nothing itself.

* :func:`run_data` runs a study's sections in the calling thread (the Hertz cell: milliseconds).
* :class:`Job` runs one in a background thread, reports progress after each unit-cell solve and
  can be cancelled: the job runs in a cancellation scope (:mod:`fingerpad.cancel`), so the contact
  solve under way stops within one iteration of its conjugate gradient and nothing of it is
  stored (the BEM cell writes the nodes solved before, complete ones, under a file lock). The BEM
  curves go through the on-disk cache of unit cells (:mod:`fingerpad.micro.cache`), so a revisited
  design runs no solve; :class:`Memo` also remembers the last predictions in memory.
* :func:`contact_at` solves the contact on the unit cell at one mean pressure
  (:class:`fingerpad.contact.HalfSpaceSolver`), remembered in an :class:`LRU` by the texture's
  heights, the modulus and the pressure; given a token, it stops as a job does.
* :class:`WorkLog` counts the CPU time of the background work, and that of work whose design
  was no longer shown when it ended (``benchmarks/bench_explorer.py`` reads it).
"""

from __future__ import annotations

import hashlib
import threading
from contextlib import nullcontext
import time
import warnings
from collections import OrderedDict
from collections.abc import Callable, Hashable, Mapping
from typing import Any

import numpy as np

from ..cancel import CancelToken, Cancelled, cancellable
from ..errors import FingerpadError, one_line
from .inputs import data_key, labels_for

__all__ = ["LRU", "Job", "JobCancelled", "Memo", "WorkLog", "contact_at", "remembered_contact", "run_data", "texture_key"]

#: What a cancelled job raised (the library's :class:`fingerpad.cancel.Cancelled`).
JobCancelled = Cancelled


def run_data(data: Mapping[str, Mapping[str, Any]], progress: Callable[[int, int], None] | None = None) -> Any:
    """Run the study of ``data`` (validated by ``study_from_dict``) and return its Prediction.

    Warnings of the run (convergence, resolution) are recorded in the prediction's notes rather
    than printed.
    """
    from ..study.run import run_study
    from ..study.spec import study_from_dict

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        study = study_from_dict(data, labels_for(data))
        pred = run_study(study, progress=progress)
    for w in caught:
        if issubclass(w.category, (DeprecationWarning, PendingDeprecationWarning)):
            continue
        msg = one_line(str(w.message))
        if "mpi4py" in msg or "contact solve did not converge" in msg:
            continue
        if msg not in pred.notes and not issubclass(w.category, (ResourceWarning,)):
            if not any(msg in n for n in pred.notes):
                pred.notes.append(f"warning: {msg}")
    return pred


class LRU:
    """The last ``size`` values by a hashable key (in memory, per server; thread-safe: jobs put
    from their threads)."""

    def __init__(self, size: int = 24) -> None:
        self.size = size
        self._items: OrderedDict[Hashable, Any] = OrderedDict()
        self._lock = threading.Lock()

    def get_key(self, key: Hashable) -> Any:
        with self._lock:
            if key in self._items:
                self._items.move_to_end(key)
                return self._items[key]
        return None

    def put_key(self, key: Hashable, value: Any) -> None:
        with self._lock:
            self._items[key] = value
            self._items.move_to_end(key)
            while len(self._items) > self.size:
                self._items.popitem(last=False)

    def __len__(self) -> int:
        return len(self._items)


class Memo(LRU):
    """The last ``size`` predictions by their study (in memory, per server)."""

    def get(self, data: Mapping[str, Any]) -> Any:
        return self.get_key(data_key(data))

    def put(self, data: Mapping[str, Any], pred: Any) -> None:
        self.put_key(data_key(data), pred)


def texture_key(texture: Any) -> tuple[Any, ...]:
    """What a unit cell's contact depends on of its texture: the heights (a digest), the grid,
    the size, periodicity."""
    heights = np.ascontiguousarray(np.asarray(texture.heights, dtype=float))
    digest = hashlib.blake2b(heights.tobytes(), digest_size=16).hexdigest()
    return (digest, heights.shape, tuple(float(v) for v in texture.size), bool(texture.periodic))


class Job:
    """A prediction in a background thread, with progress and cancellation.

    Attributes
    ----------
    state
        ``"running"``, ``"done"``, ``"cancelled"`` or ``"failed"``.
    done, total
        Unit-cell solves so far and the current estimate of their number.
    result
        The Prediction once done; ``error`` the message once failed.
    token
        Its :class:`~fingerpad.cancel.CancelToken` (given: cancelled with the work it belongs to).
    """

    def __init__(self, data: Mapping[str, Mapping[str, Any]], memo: Memo | None = None, *,
                 token: CancelToken | None = None, log: WorkLog | None = None) -> None:
        self.data = {k: dict(v) for k, v in data.items()}
        self.memo = memo
        self.state = "running"
        self.done = 0
        self.total = 0
        self.result: Any = None
        self.error: str | None = None
        self.started = time.monotonic()
        self.seconds = 0.0
        self.token = token if token is not None else CancelToken()
        self._log = log
        self._thread = threading.Thread(target=self._run, name="fingerpad-explore-job", daemon=True)
        self._thread.start()

    def _progress(self, i: int, n: int) -> None:
        self.done, self.total = i, n

    def _run(self) -> None:
        cpu = time.thread_time()
        try:
            with cancellable(self.token):
                pred = run_data(self.data, self._progress)
        except Cancelled:
            self.state = "cancelled"
        except FingerpadError as exc:
            self.error, self.state = one_line(str(exc)), "failed"
        except Exception as exc:  # noqa: BLE001 -- a bug must show in the page, not kill the thread silently
            self.error, self.state = f"internal error: {type(exc).__name__}: {one_line(str(exc))}", "failed"
        else:
            if self.token.cancelled:
                self.state = "cancelled"
            else:
                self.result = pred
                if self.memo is not None:
                    self.memo.put(self.data, pred)
                self.state = "done"
        finally:
            self.seconds = time.monotonic() - self.started
            if self._log is not None:
                self._log.add("bem", time.thread_time() - cpu, self.token.cancelled, self.token)

    def cancel(self) -> None:
        """Stop the job: the contact solve under way ends within one iteration."""
        self.token.cancel()

    @property
    def cancelling(self) -> bool:
        return self.token.cancelled and self.state == "running"

    @property
    def finished(self) -> bool:
        return self.state != "running"

    def wait(self, timeout: float | None = None) -> bool:
        self._thread.join(timeout)
        return self.finished

    @property
    def elapsed(self) -> float:
        """Seconds since the job started (its duration once finished)."""
        return self.seconds or time.monotonic() - self.started

    @property
    def fraction(self) -> float:
        return min(1.0, self.done / self.total) if self.total else 0.0


class WorkLog:
    """CPU seconds of the explorer's background work (contact maps, BEM jobs, populations), in
    all and of the work that ended for a design no longer shown (cancelled, or its result thrown
    away). Thread-safe; with ``path`` (``$FINGERPAD_EXPLORE_WORKLOG`` for the server) each piece of
    work is appended there as a JSON line, for benchmarks."""

    def __init__(self, path: str | None = None) -> None:
        self.path = path
        self.cpu_s = 0.0
        self.superseded_cpu_s = 0.0
        self.counts: dict[str, int] = {}
        self._lock = threading.Lock()
        if path:
            open(path, "a", encoding="utf-8").close()  # there from the start: this server keeps a log

    def add(self, kind: str, cpu_s: float, superseded: bool, token: CancelToken | None = None) -> None:
        """Record ``cpu_s`` seconds of ``kind`` work (``superseded``: its design no longer shown;
        ``token``: the work's, whose cancellation time gives how long the work took to stop)."""
        import json

        stopped = None
        if token is not None and token.cancelled_at is not None:
            stopped = time.monotonic() - token.cancelled_at
        with self._lock:
            self.cpu_s += cpu_s
            if superseded:
                self.superseded_cpu_s += cpu_s
            key = f"{kind} {'superseded' if superseded else 'shown'}"
            self.counts[key] = self.counts.get(key, 0) + 1
            if self.path:
                with open(self.path, "a", encoding="utf-8") as fh:
                    fh.write(json.dumps({"t": time.time(), "kind": kind, "cpu_s": cpu_s, "superseded": superseded,
                                         "stopped_s": stopped}) + "\n")


def contact_at(texture: Any, modulus: float, pressure: float, *, tol: float = 1e-8, max_iter: int = 5000,
               cache: LRU | None = None, token: CancelToken | None = None, workers: int | None = None) -> Any:
    """The contact of the skin on the unit cell at mean nominal pressure ``pressure`` (Pa):
    a :class:`~fingerpad.contact.ContactResult` of :class:`~fingerpad.contact.HalfSpaceSolver`
    with the reduced modulus E1* (Eq. 3.4).

    With ``cache``, a contact solved before (same heights, grid, size, modulus, pressure, tolerance
    and iteration cap) is returned without a solve: a design seen before costs nothing. With
    ``token`` (else the caller's cancellation scope), the solve stops within one iteration once the
    token is cancelled (:class:`~fingerpad.cancel.Cancelled` is raised; nothing is remembered). ``workers``: the FFT
    threads (default: all cores).
    """
    from ..contact import HalfSpaceSolver

    key = _contact_key(texture, modulus, pressure, tol, max_iter) if cache is not None else None
    if key is not None:
        hit = cache.get_key(key)
        if hit is not None:
            return hit
    with warnings.catch_warnings(), (cancellable(token) if token is not None else nullcontext()):
        warnings.simplefilter("ignore")
        res = HalfSpaceSolver(texture, modulus, tol=tol, max_iter=max_iter,
                              workers=workers).solve_pressure(pressure)
    if key is not None:
        cache.put_key(key, res)
    return res


def remembered_contact(texture: Any, modulus: float, pressure: float, *, tol: float = 1e-8,
                       max_iter: int = 5000, cache: LRU) -> Any:
    """The contact :func:`contact_at` remembered in ``cache`` (``None``: not solved yet)."""
    return cache.get_key(_contact_key(texture, modulus, pressure, tol, max_iter))


def _contact_key(texture: Any, modulus: float, pressure: float, tol: float, max_iter: int) -> tuple[Any, ...]:
    return (texture_key(texture), float(modulus), float(pressure), float(tol), int(max_iter))
