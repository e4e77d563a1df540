"""Outputs of a friction-measurement study: tables, figures, NetCDF curves and an HTML report.

:func:`write_report` writes everything for a :class:`fingerpad.measure.StudyResult` into a
folder, all at once: the files are made in a temporary folder beside it and moved into place
only when every one of them is complete, so an error never leaves a half-written report. The
NetCDF curves are made by :mod:`.curves_netcdf`; the figures are drawn on several cores by
:mod:`.figurepool`.

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
import os
from pathlib import Path
from typing import Any

import pandas as pd

from .. import references
from ..encode import to_jsonable
from ..io import OutputFolder
from ..plotting.measure import participant_png, sample_png
from .curves_netcdf import curves_dataset
from .figurepool import EarlyQC, draw_figures, qc_drawer, qc_tasks, safe_name
from .htmlreport import html_report
from .study import StudyResult, study_info, study_references

__all__ = ["EarlyQC", "curves_dataset", "html_report", "write_report"]


def _records(df: pd.DataFrame) -> list[dict[str, Any]]:
    return [to_jsonable(r) for r in df.to_dict("records")]


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
        tasks = ((early_qc.tasks(qc_recordings, dpi) if early_qc is not None else None) or qc_tasks(result, qc_recordings)
                 if qc and figures else [])
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
            with qc_drawer(tasks, len(result.stroke_reports), dpi, workers, early_qc) as (qc_png_of, pool):
                # each kind drawn on one kept figure (the same image as a new one's)
                drawn = [("participant", p, participant_png) for p in participants] + \
                        [("sample", s, sample_png) for s in samples]
                for (kind, key, _), png in zip(drawn, draw_figures(result, drawn, dpi, pool), strict=True):
                    pngs[f"{kind} {key}"] = png
                    name = f"figures/{kind}_{safe_name(key)}.png"
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
