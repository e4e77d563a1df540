"""The whole measurement study's pipeline, :func:`analyse_study`: strokes, normalisation, power
laws, tables, then the fits that do not depend on one another (:mod:`.condition_fits`), on
every usable core.

The study's options and result live in :mod:`.study` (imported here too, where callers found
them before).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd

from ..errors import FingerpadError
from ..extras import require
from .across_participants import POPULATION_FIT_COLUMNS, population_curves
from .breakpoint import Breakpoint
from .clipping import clipping_warnings
from .condition_fits import StudyFits
from .curves import fit_curves, normalise, spread_summary, spread_table
from .micro_models import Model, TextureGeometry, resolve_finger, texture_model
from .modulus import ModulusFit
from .parallel import forked_map, resolve_workers
from .recordings import Recording
from .strokes import StrokeReport
from .study import (MAX_BINS, MAX_SIMULATIONS, REFERENCES, AnalysisOptions, MeasurementWarning, StudyResult,
                    study_info, study_references)
from .tables import bin_strokes, flag_outliers, load_bin_edges, plausibility_warnings, stroke_table

__all__ = ["MAX_BINS", "MAX_SIMULATIONS", "REFERENCES", "AnalysisOptions", "MeasurementWarning", "StudyResult",
           "analyse_study", "study_info", "study_references"]


def analyse_study(
    recordings: Sequence[Recording],
    options: AnalysisOptions = AnalysisOptions(),
    *,
    textures: Mapping[str, TextureGeometry | None] | None = None,
    models: Mapping[str, Model] | None = None,
    on_strokes: Any = None,
    find_strokes: Any = None,
    workers: int | None = 1,
) -> StudyResult:
    """Run the whole analysis on a set of recordings.

    Parameters
    ----------
    recordings
        From :func:`load_study`.
    options
        :class:`AnalysisOptions` (the reference sample among them).
    textures
        Geometry of textured samples (:func:`read_textures`); enables the default model
        (:func:`texture_model`) and the closed-form E_s for those samples.
    models
        Sample -> normalised-friction model; overrides the default for that sample.
    on_strokes
        Called once the strokes are found and their outliers flagged, before any fit, with an
        object holding ``recordings``, ``stroke_reports``, ``strokes``, ``clipped_strokes`` and
        ``options`` as the result will (the QC figures need no more: :class:`.figurepool.EarlyQC`
        starts them there).
    find_strokes
        ``find_strokes(recordings, options.strokes)``: each recording's
        :func:`~.tables.recording_strokes`, in order, worked out elsewhere (by other processes:
        :meth:`.figurepool.EarlyQC.find_strokes`); by default here, one recording after another.
    workers
        Processes for the fits that do not depend on one another (each condition's breakpoint
        test, E_s fit and sensitivity refits, each participant's joint E_s, each sample's
        population fit): forked from this one (:func:`.parallel.forked_map`); ``None``: one
        per usable CPU (at most 8); ``1`` (default): all here. The result is the same, bit for
        bit, whatever the number.

    Raises
    ------
    FingerpadError
        For unreadable strokes, a missing reference, or a participant without one.

    Notes
    -----
    BLAS runs on one thread: on the fits' small products a second one saves nothing, and its
    spinning between calls doubled the analysis's CPU (11 against 6 s, 150 recordings); one
    thread also makes the last bits of a fit independent of the machine's core count.

    Needs the ``measure`` extra (:class:`~fingerpad.extras.MissingExtraError` without it).
    """
    require("measure")
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _analyse(recordings, options, textures, models, on_strokes, find_strokes, workers)


def _analyse(recordings: Sequence[Recording], options: AnalysisOptions,
             textures: Mapping[str, TextureGeometry | None] | None,
             models: Mapping[str, Model] | None, on_strokes: Any, find_strokes: Any,
             workers: int | None = 1) -> StudyResult:
    opts = options
    textures = dict(textures or {})
    reports: dict[str, StrokeReport] = {}
    strokes = stroke_table(recordings, opts.strokes, reports=reports,
                           found=find_strokes(recordings, opts.strokes) if find_strokes is not None else None)
    clipping = {source: report.clips for source, report in reports.items()}
    notes = clipping_warnings(strokes, clipping)
    # a saturated sensor biases mu (a capped normal force raises it, capped friction lowers it):
    # such strokes are left out of every fit, and kept apart for the tables and QC figures
    is_clipped = strokes["clipped"] != ""
    clipped_strokes = strokes[is_clipped].reset_index(drop=True)
    strokes = strokes[~is_clipped].reset_index(drop=True)
    if strokes.empty:
        raise FingerpadError("every stroke touches a saturated (clipped) force channel: " + "; ".join(notes))
    notes += plausibility_warnings(strokes)
    strokes = flag_outliers(strokes, opts.outlier_z)
    if on_strokes is not None:  # later steps add columns, never change these rows or flags
        from types import SimpleNamespace

        on_strokes(SimpleNamespace(recordings=list(recordings), stroke_reports=reports, strokes=strokes,
                                   clipped_strokes=clipped_strokes, options=opts))
    strokes, ref_fits = normalise(strokes, opts.reference, opts.min_fit_strokes, level=opts.level)
    fits, power_laws = fit_curves(strokes, opts.min_fit_strokes, level=opts.level,
                                  workers=resolve_workers(workers, strokes["participant"].nunique()))
    edges = load_bin_edges(strokes["load"].to_numpy(), opts.n_bins)
    bins = bin_strokes(strokes, edges)
    spread = spread_table(strokes, edges, opts.reference)
    summary_spread = spread_summary(spread, opts.reference)

    finger = resolve_finger(opts.finger) if (textures or models) else None
    all_models: dict[str, Model] = {}
    for sample, geom in textures.items():
        if geom is not None and sample != opts.reference:
            all_models[sample] = texture_model(geom, finger)
    all_models.update(models or {})

    fitter = StudyFits(opts, strokes, power_laws, ref_fits, textures, finger, all_models)
    # each texture's tables first (the conditions' E_s fits read them), then every other piece
    fitter.set_tables(forked_map(fitter.sample_tables, range(len(fitter.plan)),
                                 resolve_workers(workers, len(fitter.plan))))
    tables = fitter.tables
    items = fitter.pieces()
    done = forked_map(fitter.piece, items, workers=resolve_workers(workers, len(items)))
    by_sample, by_condition, by_participant = fitter.by_sample, fitter.by_condition, fitter.by_participant

    pop_parts = done[:len(by_sample)]
    cond_out = done[len(by_sample):len(by_sample) + len(by_condition)]
    part_out = done[len(by_sample) + len(by_condition):]

    breakpoints: dict[tuple[str, str, str], Breakpoint] = {}
    modulus_fits: dict[tuple[str, ...], ModulusFit] = {}
    sens_rows: list[dict[str, Any]] = []
    rows = []
    for (key, _), (row, bp, mf, srows) in zip(by_condition, cond_out, strict=True):
        if bp is not None:
            breakpoints[key] = bp
        if mf is not None:
            modulus_fits[key] = mf
        sens_rows += srows
        rows.append(row)
    conditions = pd.DataFrame(rows)
    prow = []
    for (participant, _), (row, mf, srows) in zip(by_participant, part_out, strict=True):
        if mf is not None:
            modulus_fits[(participant,)] = mf
        sens_rows += srows
        prow.append(row)

    pop_curves = population_curves(strokes, edges, opts.reference, opts.level) if opts.population else pd.DataFrame()
    pop_fits = (pd.DataFrame([row for part in pop_parts for row in part], columns=POPULATION_FIT_COLUMNS)
                if opts.population else pd.DataFrame())
    for message in notes:
        warnings.warn(message, MeasurementWarning, stacklevel=3)
    return StudyResult(
        options=opts, strokes=strokes, bins=bins, fits=fits, spread=spread, spread_summary=summary_spread,
        conditions=conditions, participants=pd.DataFrame(prow), bin_edges=edges, power_laws=power_laws,
        reference_fits=ref_fits, breakpoints=breakpoints, modulus_fits=modulus_fits, models=all_models,
        tables=tables, textures=textures, population_curves=pop_curves, population_fits=pop_fits,
        sensitivity=pd.DataFrame(sens_rows), warnings=notes, recordings=list(recordings), stroke_reports=reports,
        clipped_strokes=clipped_strokes, clipping=clipping,
    )
