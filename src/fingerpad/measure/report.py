"""Outputs of a friction-measurement study: tables, figures, NetCDF curves and an HTML report.

:func:`write_report` writes everything for a :class:`fingerpad.measure.StudyResult` into a
folder, all at once: the files are made in a temporary folder beside it and moved into place
only when every one of them is complete, so an error never leaves a half-written report.

Layout of ``OUT``::

    summary.csv, summary.json   one row per participant, sample and direction (+ study info)
    participants.csv            reference power law and E_s per participant
    strokes.csv                 every stroke (load, mu, outlier flag, mu_norm; ``clipped``: the saturated
                                force channels of a stroke left out of the fits)
    fits.csv, bins.csv          power-law fits per sense; binned means
    spread.csv                  between-participant spread per load bin, before/after
    population_curves.csv       mean curve over participants per texture, between-person interval
    population_fits.csv         power law across participants per texture (mixed model or two-stage,
                                column ``source``; both estimates side by side)
    sensitivity.csv             E_s refitted with the other micro-model and varied friction parameters
    curves.nc                   binned and fitted curves (xarray, h5netcdf)
    figures/participant_<P>.png, figures/sample_<S>.png
    figures/qc_<P>.png          QC sheet per participant: every recording's forces with its strokes
                                (small multiples; ``qc_<P>_2.png`` ... for a participant with more
                                than 12 rows of recordings)
    figures/qc/<recording>.png  with ``qc_recordings``: per recording, forces and position with the
                                strokes, mu per stroke
    report.html                 one page: summary tables and the figures (embedded; full QC linked)
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .. import references
from .._version import __version__
from ..encode import to_jsonable
from ..io import OutputFolder
from ..plotting.measure import condition_label, participant_png, qc_inputs, qc_png, sample_png
from ..plotting.qcsheet import qc_sheet_png, qc_sheets
from ..plotting.render import load_drawing_modules
from .analysis import StudyResult, study_info, study_references
from .htmlreport import html_report
from .parallel import frozen_heap, own_streams, usable_cpus

__all__ = ["EarlyQC", "curves_dataset", "html_report", "write_report"]


def _safe(name: str) -> str:
    """File-name-safe version of a participant or sample label."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", str(name)).strip("_") or "unnamed"



# =============================================================================================
# NetCDF
# =============================================================================================


def curves_dataset(result: StudyResult):
    """The study's curves as an :class:`xarray.Dataset`.

    Dimensions: ``participant``, ``condition`` (sample, or ``sample/direction``), ``sense``
    (``+``, ``-``, ``both``), ``bin`` (load bins shared by the study) and ``load`` (a
    log-spaced grid over the measured loads).

    Variables: binned ``mu_mean``/``mu_sd``/``mu_n``/``mu_norm_mean``/``mu_norm_sd`` and
    ``bin_load`` (median load per bin); power-law ``k``, ``n`` and the fitted ``mu_fit`` on the
    grid; the reference curve ``mu_ref_fit``; per condition ``skin_modulus`` (+ CI),
    ``breakpoint_load`` (+ CI) and the model ``mu_norm_model`` at the fitted E_s. Missing
    combinations are NaN. All SI (N, Pa).
    """
    import xarray as xr

    strokes = result.strokes
    participants = sorted(strokes["participant"].unique())
    conds = sorted({(s, d) for s, d in zip(strokes["sample"], strokes["direction"])})
    labels = [condition_label(s, d) for s, d in conds]
    senses = ["+", "-", "both"]
    nbins = len(result.bin_edges) - 1
    grid = result.load_grid()
    shape_b = (len(participants), len(conds), len(senses), nbins)
    binned = {k: np.full(shape_b, np.nan) for k in ("mu_mean", "mu_sd", "mu_n", "mu_norm_mean", "mu_norm_sd",
                                                     "bin_load")}
    pi = {p: i for i, p in enumerate(participants)}
    ci = {c: i for i, c in enumerate(conds)}
    si = {s: i for i, s in enumerate(senses)}
    for row in result.bins.itertuples(index=False):
        idx = (pi[row.participant], ci[(row.sample, row.direction)], si[row.sense], int(row.bin))
        binned["mu_mean"][idx] = row.mu
        binned["mu_sd"][idx] = row.mu_sd
        binned["mu_n"][idx] = row.n
        binned["mu_norm_mean"][idx] = getattr(row, "mu_norm", np.nan)
        binned["mu_norm_sd"][idx] = getattr(row, "mu_norm_sd", np.nan)
        binned["bin_load"][idx] = row.load
    shape_f = (len(participants), len(conds), len(senses))
    k = np.full(shape_f, np.nan)
    n = np.full(shape_f, np.nan)
    mu_fit = np.full((*shape_f, grid.size), np.nan)
    for (p, s, d, sense), fit in result.power_laws.items():
        idx = (pi[p], ci[(s, d)], si[sense])
        k[idx], n[idx] = fit.k, fit.n
        mu_fit[idx] = np.asarray(fit(grid), dtype=float)
    mu_ref = np.full((len(participants), grid.size), np.nan)
    for (p, sense), fit in result.reference_fits.items():
        if sense == "both":
            mu_ref[pi[p]] = np.asarray(fit(grid), dtype=float)
    shape_c = (len(participants), len(conds))
    per_cond = {name: np.full(shape_c, np.nan) for name in (
        "skin_modulus", "skin_modulus_ci_low", "skin_modulus_ci_high", "breakpoint_load",
        "breakpoint_ci_low", "breakpoint_ci_high", "breakpoint_p", "skin_modulus_closed_form",
        "skin_modulus_other", "skin_modulus_sens_low", "skin_modulus_sens_high", "sense_ratio",
        "sense_ratio_ci_low", "sense_ratio_ci_high")}
    mu_model = np.full((*shape_c, grid.size), np.nan)
    for row in result.conditions.to_dict("records"):
        idx = (pi[row["participant"]], ci[(row["sample"], row["direction"])])
        for name in per_cond:
            value = row.get(name)
            if value is not None and not (isinstance(value, float) and math.isnan(value)):
                per_cond[name][idx] = float(value)
        table = result.tables.get(row["sample"])
        e = row.get("skin_modulus")
        if table is not None and e is not None and np.isfinite(e):
            inside = (grid >= table.loads[0]) & (grid <= table.loads[-1])
            mu_model[idx][inside] = table(grid[inside], float(e))
    dims_b = ("participant", "condition", "sense", "bin")
    dims_f = ("participant", "condition", "sense")
    ds = xr.Dataset(
        data_vars={
            **{name: (dims_b, arr) for name, arr in binned.items()},
            "k": (dims_f, k),
            "n": (dims_f, n),
            "mu_fit": ((*dims_f, "load"), mu_fit),
            "mu_ref_fit": (("participant", "load"), mu_ref),
            **{name: (("participant", "condition"), arr) for name, arr in per_cond.items()},
            "mu_norm_model": (("participant", "condition", "load"), mu_model),
        },
        coords={
            "participant": participants,
            "condition": labels,
            "sample": ("condition", [s for s, _ in conds]),
            "direction": ("condition", [d for _, d in conds]),
            "sense": senses,
            "bin": np.arange(nbins),
            "bin_low": ("bin", result.bin_edges[:-1]),
            "bin_high": ("bin", result.bin_edges[1:]),
            "load": grid,
        },
        attrs={
            "title": "fingerpad friction measurements",
            "fingerpad_version": __version__,
            "reference_sample": result.options.reference,
            "confidence_level": result.options.level,
            "power_law": "mu = k F^(n-1)",
            "references": references.netcdf_attribute(study_references(result)),
        },
    )
    units = {"bin_load": "N", "load": "N", "bin_low": "N", "bin_high": "N", "breakpoint_load": "N",
             "breakpoint_ci_low": "N", "breakpoint_ci_high": "N", "skin_modulus": "Pa",
             "skin_modulus_ci_low": "Pa", "skin_modulus_ci_high": "Pa", "skin_modulus_closed_form": "Pa",
             "skin_modulus_other": "Pa", "skin_modulus_sens_low": "Pa", "skin_modulus_sens_high": "Pa",
             "breakpoint_p": "1", "sense_ratio": "1", "sense_ratio_ci_low": "1", "sense_ratio_ci_high": "1",
             "k": "1", "n": "1", "mu_mean": "1", "mu_sd": "1", "mu_fit": "1", "mu_ref_fit": "1",
             "mu_norm_mean": "1", "mu_norm_sd": "1", "mu_norm_model": "1", "mu_n": "count"}
    for name, unit in units.items():
        ds[name].attrs["units"] = unit
    return ds




# =============================================================================================
# tables and HTML
# =============================================================================================


def _records(df: pd.DataFrame) -> list[dict[str, Any]]:
    return [to_jsonable(r) for r in df.to_dict("records")]


# =============================================================================================
# writing everything
# =============================================================================================


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
    from threadpoolctl import threadpool_limits

    from .tables import recording_strokes

    with threadpool_limits(limits=1, user_api="blas"):  # as analyse_study: the same last bits
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
    """The PNG of one QC task (:func:`_qc_tasks`): a sheet, or one recording's full figure."""
    kind, inputs = task
    return qc_sheet_png(inputs, dpi) if kind == "sheet" else qc_png(inputs, dpi)


def _qc_tasks(result: Any, recordings: bool) -> list[tuple[str, str, Any]]:
    """The QC figures of ``result``: ``(file name, kind, inputs)`` of every participant's QC
    sheets (:func:`~fingerpad.plotting.qcsheet.qc_sheets`; ``figures/qc_<participant>.png``,
    ``..._2.png`` for a second page), and with ``recordings`` each recording's full figure
    (``figures/qc/<recording>.png``)."""
    tasks: list[tuple[str, str, Any]] = []
    for sheet in qc_sheets(result):
        page = "" if sheet.page == 1 else f"_{sheet.page}"
        tasks.append((f"figures/qc_{_safe(sheet.participant)}{page}.png", "sheet", sheet))
    if recordings:
        used: set[str] = set()
        for rec in result.recordings:
            if rec.source not in result.stroke_reports:
                continue
            stem = _safe(Path(rec.source).stem)
            while stem in used:  # two folders may hold files of one name
                stem += "_"
            used.add(stem)
            tasks.append((f"figures/qc/{stem}.png", "recording", qc_inputs(result, rec.source)))
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
            with frozen_heap():
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
        tasks = _qc_tasks(partial, self.recordings)
        n = _qc_workers(self.workers, len(partial.stroke_reports))
        if n <= 1 or not tasks:  # drawn in this process by write_report, as without it
            return
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

    def png(self, name: str, dpi: int) -> Any:
        """The future of QC figure ``name``'s PNG at ``dpi``, or ``None`` if it was not started."""
        return self._futures.get(name) if dpi == self.dpi else None

    @property
    def pool(self) -> Any:
        """The process pool drawing the QC figures (``None`` before :meth:`start` or
        :meth:`find_strokes` started one)."""
        return self._pool


@contextmanager
def _qc_drawer(tasks: list[tuple[str, str, Any]], n_recordings: int, dpi: int, workers: int | None,
               early: EarlyQC | None = None) -> Iterator[tuple[Any, Any]]:
    """Start drawing every QC figure of ``tasks`` (:func:`_qc_tasks`); yields ``png(i)``, the
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


def _draw_figures(result: StudyResult, drawn: list[tuple[str, str, Any]], dpi: int, pool: Any) -> Iterator[bytes]:
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


def write_report(
    result: StudyResult,
    out: str | os.PathLike[str],
    *,
    figures: bool = True,
    dpi: int = 100,
    title: str = "Finger friction study",
    qc: bool = True,
    progress: Any = None,
    workers: int | None = None,
    early_qc: EarlyQC | None = None,
    qc_recordings: bool = False,
) -> list[Path]:
    """Write tables, figures, NetCDF curves and the HTML report into ``out`` (see module doc).

    Everything is written into a temporary folder next to ``out``, which replaces ``out`` as a
    whole at the end (an earlier report's files never mix with these); on any error ``out`` is
    left as it was. A folder holding anything but an earlier report is refused.
    ``qc`` adds the quality-control sheets, every recording's forces and strokes as small
    multiples, one sheet per participant (``figures/qc_<participant>.png``, embedded in the
    report); ``qc_recordings`` also the full figure of each recording (``figures/qc/``,
    linked from the report; some 0.1 s of CPU each). ``progress(done, total, what)`` is called
    as figures are drawn. The QC figures are drawn by a pool of ``workers`` processes (default:
    one per CPU this process may use, at most 8; ``1`` draws them here); the files are the
    same, byte for byte, whatever the number of workers. ``early_qc``: QC figures started
    during the analysis (:class:`EarlyQC`), used where it holds all of them at ``dpi``.

    Returns
    -------
    list of Path
        The files written, inside ``out``.

    Raises
    ------
    FingerpadError
        If ``out`` exists and is not a folder.
    """
    out_path = Path(out)
    with OutputFolder(out_path) as folder:  # refuses a folder of the user's files; errors name the user's path
        tmp = folder.build
        written: list[str] = []

        def csv_file(name: str, df: pd.DataFrame) -> None:
            df.to_csv(tmp / name, index=False)
            written.append(name)

        csv_file("summary.csv", result.conditions)
        csv_file("participants.csv", result.participants)
        # every stroke, those left out for a saturated sensor included (column `clipped` says so)
        csv_file("strokes.csv", pd.concat([result.strokes, result.clipped_strokes], ignore_index=True)
                 if len(result.clipped_strokes) else result.strokes)
        csv_file("fits.csv", result.fits)
        csv_file("bins.csv", result.bins)
        csv_file("spread.csv", result.spread)
        csv_file("population_curves.csv", result.population_curves)
        csv_file("population_fits.csv", result.population_fits)
        csv_file("sensitivity.csv", result.sensitivity)
        summary = {
            "study": to_jsonable(study_info(result)),
            "spread": _records(result.spread_summary),
            "participants": _records(result.participants),
            "conditions": _records(result.conditions),
            "population_fits": _records(result.population_fits),
            "references": references.metadata(study_references(result)),
        }
        (tmp / "summary.json").write_text(json.dumps(summary, indent=2, allow_nan=False), encoding="utf-8")
        written.append("summary.json")
        ds = curves_dataset(result)
        ds.to_netcdf(tmp / "curves.nc", engine="h5netcdf")
        written.append("curves.nc")
        pngs: dict[str, bytes] = {}
        qc_links: dict[str, str] = {}
        qc_sheets_png: dict[str, bytes] = {}
        participants = sorted(result.strokes["participant"].unique())
        samples = sorted(result.strokes["sample"].unique())
        tasks = _qc_tasks(result, qc_recordings) if qc and figures else []
        total, done = len(participants) + len(samples) + len(tasks), 0

        def tick(what: str) -> None:
            nonlocal done
            done += 1
            if progress is not None:
                progress(done, total, what)

        if figures:
            (tmp / "figures").mkdir()
            # the pool starts on the QC figures now and draws them while the participant
            # and sample figures are drawn here
            with _qc_drawer(tasks, len(result.stroke_reports), dpi, workers, early_qc) as (qc_png_of, pool):
                # each kind drawn on one kept figure (the same image as a new one's)
                drawn = [("participant", p, participant_png) for p in participants] + \
                        [("sample", s, sample_png) for s in samples]
                for (kind, key, _), png in zip(drawn, _draw_figures(result, drawn, dpi, pool), strict=True):
                    pngs[f"{kind} {key}"] = png
                    name = f"figures/{kind}_{_safe(key)}.png"
                    (tmp / name).write_bytes(png)
                    written.append(name)
                    tick(name)
                if any(kind == "recording" for _, kind, _ in tasks):
                    (tmp / "figures" / "qc").mkdir()
                for i, (name, kind, inputs) in enumerate(tasks):
                    png = qc_png_of(i)
                    (tmp / name).write_bytes(png)
                    written.append(name)
                    if kind == "sheet":
                        page = f" (sheet {inputs.page} of {inputs.pages})" if inputs.pages > 1 else ""
                        qc_sheets_png[f"QC of participant {inputs.participant}{page}"] = png
                    else:
                        qc_links[inputs.source] = name
                    tick(name)
        (tmp / "report.html").write_text(html_report(result, pngs, title, qc_links=qc_links, qc_sheets=qc_sheets_png), encoding="utf-8")
        written.append("report.html")
        folder.commit()
    return [out_path / name for name in written]
