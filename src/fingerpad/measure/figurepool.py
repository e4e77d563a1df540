"""The report's figures on several cores: the process pool that finds the strokes, draws the
QC figures while the analysis runs (:class:`EarlyQC`) and shares the participant and sample
figures with this process (:func:`draw_figures`).

The pool's workers are forked once the recordings are read, so they inherit them (nothing of
them is pickled); every figure is the same, byte for byte, whichever process draws it.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..plotting.measure import participant_png, qc_inputs_of, qc_png, sample_png
from ..plotting.qcsheet import qc_sheet_png, qc_sheets
from ..plotting.render import load_drawing_modules
from .parallel import fork_ready, one_blas_thread, own_streams, usable_cpus
from .study import StudyResult

__all__ = ["EarlyQC", "draw_figures", "qc_drawer", "qc_tasks", "safe_name"]


def safe_name(name: str) -> str:
    """File-name-safe version of a participant or sample label."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", str(name)).strip("_") or "unnamed"


def _qc_workers(workers: int | None, n_figures: int) -> int:
    """Processes for ``n_figures`` QC figures: ``workers``, or one per usable CPU (at most 8);
    never more than the figures, and one (no pool) for fewer than four figures, where
    starting the processes would cost more than it saves."""
    if workers is None:
        workers = min(usable_cpus(), 8) if n_figures >= 4 else 1
    return max(1, min(int(workers), n_figures))


def _start_pool(workers: int) -> Any:
    from concurrent.futures import ProcessPoolExecutor

    # matplotlib's figure, Agg and font modules loaded before the workers start: forked
    # workers inherit them instead of each importing them again (~0.25 s of CPU per worker)
    load_drawing_modules()
    return ProcessPoolExecutor(max_workers=workers, initializer=own_streams)


#: The recordings a pool's workers find strokes in: set before they fork, so that each worker
#: holds them without their being pickled (~430 MB for 150 one-minute recordings).
_FORKED: list[Any] = []


def _forked_strokes(index: int, options: Any) -> Any:
    from .tables import recording_strokes

    one_blas_thread()  # as analyse_study: the same last bits
    frame, report = recording_strokes(_FORKED[index], options)
    # the direction signal (one number per sample: 74 MB for 150 recordings) served only to
    # measure the strokes; sending it back cost more than finding the strokes
    report.signal = None
    return frame, report


def _forked_qc_png(inputs: Any, index: int, dpi: int) -> bytes:
    """:func:`qc_png` of ``inputs`` with its recording, left out of the message, taken from
    the worker's inherited copy."""
    from dataclasses import replace

    return qc_png(replace(inputs, recording=_FORKED[index]), dpi)


def _forked_sheet_png(sheet: Any, indices: list[int], dpi: int) -> bytes:
    """:func:`qc_sheet_png` of ``sheet`` with its recordings, left out of the message, taken
    from the worker's inherited copies (``indices``, one per cell)."""
    from dataclasses import replace

    cells = tuple(replace(cell, recording=_FORKED[i]) for cell, i in zip(sheet.cells, indices, strict=True))
    return qc_sheet_png(replace(sheet, cells=cells), dpi)


def _qc_task(task: tuple[str, Any], dpi: int) -> bytes:
    """The PNG of one QC task (:func:`qc_tasks`): a sheet, or one recording's full figure."""
    kind, inputs = task
    return qc_sheet_png(inputs, dpi) if kind == "sheet" else qc_png(inputs, dpi)


def qc_tasks(result: Any, recordings: bool) -> list[tuple[str, str, Any]]:
    """The QC figures of ``result``: ``(file name, kind, inputs)`` of every participant's QC
    sheets (:func:`~fingerpad.plotting.qcsheet.qc_sheets`; ``figures/qc_<participant>.png``,
    ``..._2.png`` for a second page), and with ``recordings`` each recording's full figure
    (``figures/qc/<recording>.png``)."""
    tasks: list[tuple[str, str, Any]] = []
    for sheet in qc_sheets(result):
        page = "" if sheet.page == 1 else f"_{sheet.page}"
        tasks.append((f"figures/qc_{safe_name(sheet.participant)}{page}.png", "sheet", sheet))
    if recordings:
        inputs = qc_inputs_of(result)
        used: set[str] = set()
        for rec in result.recordings:
            if rec.source not in result.stroke_reports:
                continue
            stem = safe_name(Path(rec.source).stem)
            while stem in used:  # two folders may hold files of one name
                stem += "_"
            used.add(stem)
            tasks.append((f"figures/qc/{stem}.png", "recording", inputs(rec.source)))
    return tasks


class EarlyQC:
    """The QC figures drawn while the analysis still runs.

    Without it the analysis (reading aside, its larger part) runs on one core before any
    figure is started. Use as a context manager around :func:`analyse_study` and
    :func:`write_report`: pass :meth:`start` as ``analyse_study(..., on_strokes=...)`` and
    the object as ``write_report(..., early_qc=...)``. :meth:`start` hands every QC figure
    (each participant's QC sheets, and with ``recordings`` each recording's full figure, as
    :func:`write_report` draws them) to a pool of ``workers`` processes (default as
    :func:`write_report`'s) as soon as the strokes and their outliers are known; the figures
    are the same, byte for byte. Leaving the block cancels what is not drawn yet.
    """

    def __init__(self, dpi: int = 100, workers: int | None = None, recordings: bool = False) -> None:
        self.dpi = dpi
        self.workers = workers
        self.recordings = recordings
        self._pool: Any = None
        self._futures: dict[str, Any] = {}
        self._tasks: list[tuple[str, str, Any]] | None = None
        # source -> index in the recordings the pool's workers inherited (find_strokes)
        self._forked: dict[str, int] = {}
        self._forked_recordings: list[Any] = []

    def __enter__(self) -> EarlyQC:
        return self

    def __exit__(self, *exc: object) -> None:
        for future in self._futures.values():
            future.cancel()
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)

    def find_strokes(self, recordings: Any, options: Any) -> list[Any]:
        """Each recording's :func:`~.tables.recording_strokes`, in order (what
        ``analyse_study(..., find_strokes=...)`` takes), found by the pool that then draws
        the QC figures: it starts here, and its processes, forked once the recordings are
        read, inherit them. Without fork (or for a few recordings) they are found here."""
        import multiprocessing

        recordings = list(recordings)
        n = _qc_workers(self.workers, len(recordings))
        if n <= 1 or multiprocessing.get_start_method(allow_none=False) != "fork" or self._pool is not None:
            from .tables import recording_strokes

            return [recording_strokes(rec, options) for rec in recordings]
        _FORKED[:] = recordings
        try:
            self._pool = _start_pool(n)
            self._forked = {rec.source: i for i, rec in enumerate(recordings)}
            self._forked_recordings = recordings
            # a few recordings per task: one result each would cost more in messages than
            # the ~9 ms of finding one recording's strokes; the workers fork at the first task
            with fork_ready():
                return list(self._pool.map(_forked_strokes, range(len(recordings)),
                                           [options] * len(recordings), chunksize=4))
        finally:
            _FORKED.clear()  # the workers keep their copy

    def _inherited(self, inputs: Any) -> int | None:
        """The index of ``inputs``' recording in the workers' inherited copies, if they hold it."""
        index = self._forked.get(inputs.source)
        if index is not None and self._forked_recordings[index] is inputs.recording:
            return index
        return None

    def start(self, partial: Any) -> None:
        """Submit every QC figure of ``partial`` (what ``on_strokes`` gets)."""
        tasks = qc_tasks(partial, self.recordings)
        n = _qc_workers(self.workers, len(partial.stroke_reports))
        if n <= 1 or not tasks:  # drawn in this process by write_report, as without it
            return
        self._tasks = tasks
        if self._pool is None:
            self._pool = _start_pool(n)
        from dataclasses import replace

        def submit(kind: str, inputs: Any) -> Any:
            if kind == "sheet":
                indices = [self._inherited(cell) for cell in inputs.cells]
                if all(i is not None for i in indices):  # the workers hold the recordings already
                    light = replace(inputs, cells=tuple(replace(c, recording=None) for c in inputs.cells))
                    return self._pool.submit(_forked_sheet_png, light, indices, self.dpi)
            else:
                index = self._inherited(inputs)
                if index is not None:
                    return self._pool.submit(_forked_qc_png, replace(inputs, recording=None), index, self.dpi)
            return self._pool.submit(_qc_task, (kind, inputs), self.dpi)

        self._futures = {name: submit(kind, inputs) for name, kind, inputs in tasks}

    def tasks(self, recordings: bool, dpi: int) -> list[tuple[str, str, Any]] | None:
        """The QC tasks (:func:`qc_tasks`) :meth:`start` submitted, if they are those of a report
        with ``recordings`` at ``dpi`` (``None`` otherwise): the report takes them instead of
        building them again (each recording's rows of the stroke tables: ~2 s for 540)."""
        if self._tasks is None or recordings != self.recordings or dpi != self.dpi:
            return None
        return self._tasks

    def png(self, name: str, dpi: int) -> Any:
        """The future of QC figure ``name``'s PNG at ``dpi``, or ``None`` if it was not started."""
        return self._futures.get(name) if dpi == self.dpi else None

    @property
    def pool(self) -> Any:
        """The process pool drawing the QC figures (``None`` before :meth:`start` or
        :meth:`find_strokes` started one)."""
        return self._pool


@contextmanager
def qc_drawer(tasks: list[tuple[str, str, Any]], n_recordings: int, dpi: int, workers: int | None,
               early: EarlyQC | None = None) -> Iterator[tuple[Any, Any]]:
    """Start drawing every QC figure of ``tasks`` (:func:`qc_tasks`); yields ``png(i)``, the
    PNG bytes of ``tasks[i]``, and the process pool drawing them (``None`` where they are drawn
    here).

    With more than one worker (as many as for ``n_recordings`` per-recording figures) a process
    pool starts on all of them at once, so that it draws while this process draws the
    participant and sample figures; each task carries only its own recordings (pickled when a
    worker takes it, so any start method, fork or spawn, works). Leaving the block cancels what
    is not drawn yet. Figures ``early`` started are taken from it."""
    started = [early.png(name, dpi) for name, _, _ in tasks] if early is not None else []
    if started and all(f is not None for f in started):
        yield (lambda i: started[i].result()), early.pool  # type: ignore[union-attr]
        return
    n = _qc_workers(workers, n_recordings) if tasks else 1
    if n <= 1:
        yield (lambda i: _qc_task(tasks[i][1:], dpi)), None
        return
    with _start_pool(n) as pool:
        futures = [pool.submit(_qc_task, (kind, inputs), dpi) for _, kind, inputs in tasks]
        try:
            yield (lambda i: futures[i].result()), pool
        finally:
            for future in futures:
                future.cancel()


#: A result the pool's workers draw participant and sample figures of, by its token (each
#: worker unpickles it once).
_FIGURE_RESULTS: dict[str, Any] = {}


def _pool_figure(kind: str, key: str, dpi: int, token: str, payload: bytes) -> bytes:
    """:func:`participant_png` or :func:`sample_png` in a pool's worker, of the result pickled in
    ``payload`` (:func:`_figure_payload`)."""
    import pickle

    result = _FIGURE_RESULTS.get(token)
    if result is None:
        _FIGURE_RESULTS.clear()
        result = _FIGURE_RESULTS[token] = pickle.loads(payload)
    return (participant_png if kind == "participant" else sample_png)(result, key, dpi)


def _figure_payload(result: StudyResult) -> bytes:
    """``result`` pickled with what the participant and sample figures read: without the
    recordings and stroke reports (hundreds of MB) and the models (closures), the tables
    without their models (~2 MB for 150 recordings, 20 ms)."""
    import dataclasses
    import pickle

    light = dataclasses.replace(result, recordings=[], stroke_reports={}, models={},
                                tables={name: table.detached() for name, table in result.tables.items()})
    return pickle.dumps(light, protocol=pickle.HIGHEST_PROTOCOL)


def draw_figures(result: StudyResult, drawn: list[tuple[str, str, Any]], dpi: int, pool: Any) -> Iterator[bytes]:
    """The PNG bytes of each figure of ``drawn`` (kind, key, function), in order, drawn here or,
    with a ``pool``, by whichever is free first: every figure is also a task of the pool, queued
    behind its QC figures, and this process draws the figures from the last one back, each whose
    task no worker has started (it cancels the task). So the workers take over figures only when
    their QC figures are done and this process is still drawing, and neither waits on the other
    until the two meet. The same bytes either way (each process keeps its own figures)."""
    if pool is None or not drawn:
        for _kind, key, draw in drawn:
            yield draw(result, key, dpi)
        return
    import uuid

    payload, token = _figure_payload(result), uuid.uuid4().hex
    futures = [pool.submit(_pool_figure, kind, key, dpi, token, payload) for kind, key, _ in drawn]
    pngs: dict[int, bytes] = {}
    try:
        for i in reversed(range(len(drawn))):
            if futures[i].cancel():
                pngs[i] = drawn[i][2](result, drawn[i][1], dpi)
        for i in range(len(drawn)):
            if i not in pngs:
                try:
                    pngs[i] = futures[i].result()
                except Exception:  # noqa: BLE001 - a worker that failed: the figure drawn here says why
                    pngs[i] = drawn[i][2](result, drawn[i][1], dpi)
            yield pngs.pop(i)
    finally:
        for future in futures:
            future.cancel()
