"""The whole measurement study: options, result, and the pipeline of analyse_study."""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd

from .._version import __version__
from ..errors import FingerpadError
from ..extras import require
from .breakpoint import EDGE_FRACTION, Breakpoint, find_breakpoint
from .clipping import Clip, clipping_warnings
from .curves import fit_curves, fit_row, normalise, sense_ratio, spread_summary, spread_table
from .micro_models import Model, TextureGeometry, resolve_finger, texture_model
from .modulus import ModelTable, ModulusFit, estimate_skin_modulus, estimate_skin_modulus_joint
from .across_participants import POPULATION_FIT_COLUMNS, population_curves, population_fit_rows
from .recordings import Recording
from .modulus_sensitivity import Variants, sensitivity_rows, variant_tables
from .parallel import forked_map, resolve_workers
from .strokes import StrokeOptions, StrokeReport
from .tables import (
    GROUP,
    bin_strokes,
    cluster_column,
    flag_outliers,
    load_bin_edges,
    plausibility_warnings,
    stroke_table,
)
from .transition import modulus_from_transition


class MeasurementWarning(UserWarning):
    """Something in the data a person should look at (implausible friction, a caveat)."""


#: Most simulations of the breakpoint test's null distribution or of its bootstrap interval
#: (``n_null``, ``n_boot``): 100 times the default 999, which already gives p-values to 0.001.
MAX_SIMULATIONS = 100_000
#: Most load bins (``n_bins``): a table row and a figure point each.
MAX_BINS = 1000


@dataclass(frozen=True)
class AnalysisOptions:
    """Options of :func:`analyse_study`.

    Attributes
    ----------
    reference
        Name of the flat reference sample every participant slid on.
    strokes
        Stroke detection (:class:`StrokeOptions`).
    outlier_z
        Robust z-score threshold of :func:`flag_outliers`.
    n_bins
        Log-spaced load bins shared by the study (tables, spread, figures).
    min_fit_strokes
        Fewest strokes for a power-law fit.
    breakpoint_space, breakpoint_method, breakpoint_trend, n_boot, n_null, breakpoint_edge
        See :func:`find_breakpoint` (``breakpoint_edge`` is its ``edge``); the default trend
        ``"steeper"`` looks for the contact transition (friction rising faster once the skin
        reaches the texture's base).
    level
        Confidence level of every interval; a breakpoint is reported when its test gives
        ``p < 1 - level``.
    seed
        Random seed (simulations of the breakpoint test and interval).
    finger
        Finger preset (or :class:`fingerpad.finger.Finger`) for the default model and the
        closed-form route's ridge area.
    modulus_bounds
        Search range of E_s, Pa.
    fit_scale
        Fit an amplitude factor with E_s (:func:`estimate_skin_modulus`).
    sensitivity
        Refit E_s with the other micro-model and with the friction parameters varied
        (:mod:`.modulus_sensitivity`).
    population
        Per-texture population summary and power-law fits across participants (mixed model or
        two-stage, :mod:`.across_participants`).
    """

    reference: str = "flat"
    strokes: StrokeOptions = field(default_factory=StrokeOptions)
    outlier_z: float = 3.5
    n_bins: int = 8
    min_fit_strokes: int = 4
    breakpoint_space: Literal["log", "linear"] = "log"
    breakpoint_method: Literal["profile", "bootstrap"] = "bootstrap"
    breakpoint_trend: Literal["any", "steeper", "flatter"] = "steeper"
    n_boot: int = 200
    n_null: int = 999
    breakpoint_edge: float = EDGE_FRACTION
    level: float = 0.95
    seed: int = 0
    finger: Any = None
    modulus_bounds: tuple[float, float] = (2e4, 2e7)
    fit_scale: bool = False
    sensitivity: bool = True
    population: bool = True

    def __post_init__(self) -> None:
        if not self.reference:
            raise FingerpadError("a reference sample must be named")
        if not 0 < self.level < 1:
            raise FingerpadError(f"level must lie in (0, 1), got {self.level!r}")
        if not 1 <= self.n_bins <= MAX_BINS or self.min_fit_strokes < 3:
            raise FingerpadError(f"n_bins must lie in 1..{MAX_BINS} and min_fit_strokes be >= 3, got {self.n_bins!r} "
                                 f"and {self.min_fit_strokes!r}")
        if not self.outlier_z > 0:
            raise FingerpadError(f"outlier_z must be positive, got {self.outlier_z!r}")
        if not (19 <= self.n_null <= MAX_SIMULATIONS and 20 <= self.n_boot <= MAX_SIMULATIONS):
            raise FingerpadError(f"n_null must lie in 19..{MAX_SIMULATIONS} and n_boot in 20..{MAX_SIMULATIONS}, got "
                                 f"{self.n_null!r} and {self.n_boot!r}")
        if self.breakpoint_space not in ("log", "linear"):
            raise FingerpadError(f"breakpoint_space must be 'log' or 'linear', got {self.breakpoint_space!r}")
        if self.breakpoint_method not in ("profile", "bootstrap"):
            raise FingerpadError(f"breakpoint_method must be 'profile' or 'bootstrap', got {self.breakpoint_method!r}")
        if self.breakpoint_trend not in ("any", "steeper", "flatter"):
            raise FingerpadError(f"breakpoint_trend must be 'any', 'steeper' or 'flatter', got {self.breakpoint_trend!r}")
        if not 0 <= self.breakpoint_edge < 0.5:
            raise FingerpadError(f"breakpoint_edge must lie in [0, 0.5), got {self.breakpoint_edge!r}")
        if self.seed < 0:
            raise FingerpadError(f"seed must be a non-negative integer, got {self.seed!r}")


@dataclass
class StudyResult:
    """Everything :func:`analyse_study` found; tables are pandas DataFrames (SI units).

    Attributes
    ----------
    strokes
        One row per stroke used: metadata, load, mu, robust_z, outlier, mu_ref, mu_norm.
    clipped_strokes
        Strokes left out because a force channel was saturated in their steady window (column
        ``clipped`` names the channels; :mod:`.clipping`).
    clipping
        The saturated channels found per recording (:class:`~.clipping.Clip`; empty lists for
        clean files).
    bins
        Binned means per participant/sample/direction/sense (:func:`bin_strokes`).
    fits
        Power-law fits per participant/sample/direction/sense (:func:`fit_curves`).
    spread, spread_summary
        Between-participant variation before/after normalisation.
    conditions
        The summary table: one row per participant, sample and direction.
    participants
        One row per participant: reference power law and E_s fitted jointly to all textures.
    population_curves, population_fits
        Per texture: the mean curve over participants with a between-person interval, and
        the power law across participants, from the mixed model or the two-stage estimate
        (column ``source``; :mod:`.across_participants`).
    sensitivity
        E_s refitted with the other micro-model and varied friction parameters.
    warnings
        Messages about the data (also issued as :class:`MeasurementWarning`).
    recordings, stroke_reports
        The recordings and their stroke detection, for the QC figures.
    """

    options: AnalysisOptions
    strokes: pd.DataFrame
    bins: pd.DataFrame
    fits: pd.DataFrame
    spread: pd.DataFrame
    spread_summary: pd.DataFrame
    conditions: pd.DataFrame
    participants: pd.DataFrame
    bin_edges: np.ndarray
    power_laws: dict[tuple[str, ...], Any] = field(repr=False, default_factory=dict)
    reference_fits: dict[tuple[str, str], Any] = field(repr=False, default_factory=dict)
    breakpoints: dict[tuple[str, str, str], Breakpoint] = field(repr=False, default_factory=dict)
    modulus_fits: dict[tuple[str, ...], ModulusFit] = field(repr=False, default_factory=dict)
    models: dict[str, Model] = field(repr=False, default_factory=dict)
    tables: dict[str, ModelTable] = field(repr=False, default_factory=dict)
    textures: dict[str, TextureGeometry | None] = field(default_factory=dict)
    population_curves: pd.DataFrame = field(default_factory=pd.DataFrame)
    population_fits: pd.DataFrame = field(default_factory=pd.DataFrame)
    sensitivity: pd.DataFrame = field(default_factory=pd.DataFrame)
    warnings: list[str] = field(default_factory=list)
    recordings: list[Recording] = field(repr=False, default_factory=list)
    stroke_reports: dict[str, StrokeReport] = field(repr=False, default_factory=dict)
    clipped_strokes: pd.DataFrame = field(default_factory=pd.DataFrame)
    clipping: dict[str, list[Clip]] = field(default_factory=dict)

    @property
    def summary(self) -> pd.DataFrame:
        """The summary table (alias of :attr:`conditions`)."""
        return self.conditions

    def load_grid(self, n: int = 60) -> np.ndarray:
        """``n`` log-spaced loads (N) over the study's measured range, for curves and figures."""
        loads = self.strokes["load"].to_numpy()
        return np.geomspace(float(loads.min()), float(loads.max()), n)


def _closed_form(bp: Breakpoint, geom: TextureGeometry, finger: Any) -> tuple[float, float, float]:
    def one(load: float) -> float:
        try:
            return modulus_from_transition(load, geom.radius, geom.height, geom.spacing, finger,
                                           skin_poisson=finger.skin_poisson, material_modulus=geom.material_modulus,
                                           material_poisson=geom.material_poisson)
        except FingerpadError:
            return math.nan
    vals = [one(bp.load), one(bp.ci_low), one(bp.ci_high)]
    if not any(math.isfinite(v) for v in vals):
        return math.nan, math.nan, math.nan
    lo, hi = np.nanmin(vals), np.nanmax(vals)
    return vals[0], float(lo), float(hi)


def _modulus_columns(mf: ModulusFit) -> dict[str, Any]:
    return {"skin_modulus": mf.skin_modulus, "skin_modulus_ci_low": mf.ci_low, "skin_modulus_ci_high": mf.ci_high,
            "skin_modulus_interval": mf.describe_interval(), "skin_modulus_model": mf.model,
            "skin_modulus_determined": mf.determined, "skin_modulus_at_bound": mf.at_bound,
            "skin_modulus_note": mf.note, "model_scale": mf.scale}


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
        ``options`` as the result will (the QC figures need no more: :class:`.report.EarlyQC`
        starts them there).
    find_strokes
        ``find_strokes(recordings, options.strokes)``: each recording's
        :func:`~.tables.recording_strokes`, in order, worked out elsewhere (by other processes:
        :meth:`.report.EarlyQC.find_strokes`); by default here, one recording after another.
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

    usable = strokes[~strokes["outlier"]]
    plan: list[tuple[str, Model, tuple[float, float]]] = []
    for sample, model in all_models.items():
        loads = usable.loc[usable["sample"] == sample, "load"].to_numpy()
        if loads.size and sample != opts.reference:
            plan.append((sample, model, (float(loads.min()), float(loads.max()))))

    def sample_tables(i: int) -> tuple[ModelTable, Variants | None] | str:
        """The table of one texture, shared by every participant's fit, and its variants' (or
        why there is none); detached, to come back from a worker."""
        sample, model, load_range = plan[i]
        try:
            table = ModelTable(model, load_range, opts.modulus_bounds)
        except FingerpadError as exc:
            return f"model of sample {sample!r}: {exc}"
        if not opts.sensitivity:
            return table.detached(), None
        found = variant_tables(textures.get(sample), model, finger, load_range, opts.modulus_bounds)
        return table.detached(), Variants({key: t.detached() for key, t in found.tables.items()})

    tables: dict[str, ModelTable] = {}
    variants: dict[str, Variants] = {}
    for (sample, _, _), made in zip(plan, forked_map(sample_tables, range(len(plan)),
                                                     resolve_workers(workers, len(plan))), strict=True):
        if isinstance(made, str):
            raise FingerpadError(made)
        tables[sample] = made[0]
        if made[1] is not None:
            variants[sample] = made[1]

    fit_kw = dict(level=opts.level, fit_scale=opts.fit_scale)
    # each condition's usable strokes, looked up once (the rows and their order of a boolean
    # selection per condition, without a pass over the whole table for each)
    usable_of = {key: g for key, g in usable.groupby(GROUP, sort=True)}
    no_strokes = usable.iloc[:0]

    def condition(item: tuple[tuple[str, str, str], pd.DataFrame]
                  ) -> tuple[dict[str, Any], Breakpoint | None, ModulusFit | None, list[dict[str, Any]]]:
        """The summary row of one condition, its breakpoint test, E_s fit and sensitivity refits."""
        key, g = item
        participant, sample, direction = key
        good = usable_of.get(key, no_strokes)
        bp_out: Breakpoint | None = None
        mf_out: ModulusFit | None = None
        srows_out: list[dict[str, Any]] = []
        clusters = cluster_column(good)
        row: dict[str, Any] = dict(zip(GROUP, key))
        row.update(is_reference=sample == opts.reference, n_files=g["file"].nunique(), n_strokes=len(g),
                   n_outliers=int(g["outlier"].sum()), load_min=float(g["load"].min()),
                   load_max=float(g["load"].max()))
        fit = power_laws.get((*key, "both"))
        row.update(fit_row(fit) if fit is not None else {})
        row["mu_at_1N"] = float(fit(np.array([1.0]))[0]) if fit is not None else math.nan
        ratio, r_lo, r_hi = sense_ratio(g, opts.level)
        row.update(sense_ratio=ratio, sense_ratio_ci_low=r_lo, sense_ratio_ci_high=r_hi)
        row["mu_norm_mean"] = float(good["mu_norm"].mean()) if sample != opts.reference else 1.0
        notes_row = [fit.note] if fit is not None and fit.note else []
        if sample != opts.reference:
            try:
                bp = find_breakpoint(good["load"].to_numpy(), good["mu_norm"].to_numpy(),
                                     space=opts.breakpoint_space, method=opts.breakpoint_method,
                                     trend=opts.breakpoint_trend, level=opts.level, n_boot=opts.n_boot,
                                     n_null=opts.n_null, seed=opts.seed, clusters=clusters,
                                     edge=opts.breakpoint_edge)
                bp_out = bp
                row.update({c: math.nan for c in ("breakpoint_load", "breakpoint_ci_low", "breakpoint_ci_high",
                                                  "slope_below", "slope_above")})
                # a best location at the edge of the load range is named in `transition` (with
                # why it is not a transition) but gives no breakpoint load and no closed-form E_s
                row.update(breakpoint_detected=bp.detected, breakpoint_p=bp.p_value,
                           breakpoint_search_low=bp.search_low, breakpoint_search_high=bp.search_high,
                           breakpoint_edge_low=bp.edge_low, breakpoint_edge_high=bp.edge_high,
                           breakpoint_outside=bp.outside, transition=bp.describe())
                if bp.detected:
                    row.update(breakpoint_load=bp.load, breakpoint_ci_low=bp.ci_low, breakpoint_ci_high=bp.ci_high,
                               slope_below=bp.slope_below, slope_above=bp.slope_above)
                    geom = textures.get(sample)
                    if geom is not None:
                        e, lo, hi = _closed_form(bp, geom, finger)
                        row.update(skin_modulus_closed_form=e, skin_modulus_closed_form_ci_low=lo,
                                   skin_modulus_closed_form_ci_high=hi)
            except FingerpadError as exc:
                notes_row.append(f"breakpoint: {exc}")
            table = tables.get(sample)
            if table is not None:
                ref = ref_fits[(participant, "both")]

                def refit(t: ModelTable, good: pd.DataFrame = good, ref: Any = ref, clusters: Any = clusters
                          ) -> ModulusFit:
                    return estimate_skin_modulus(good["load"], good["mu_norm"], t, reference=ref,
                                                 clusters=clusters, **fit_kw)
                try:
                    mf = refit(table)
                    mf_out = mf
                    row.update(_modulus_columns(mf))
                    if sample in variants:
                        refits = [(p, v, (lambda t=t: refit(t))) for (p, v), t in variants[sample].tables.items()]
                        srows, summary = sensitivity_rows(mf, refits, dict(zip(GROUP, key)))
                        srows_out = srows
                        row.update(summary)
                except FingerpadError as exc:
                    notes_row.append(f"modulus: {exc}")
        row["note"] = "; ".join(n for n in notes_row if n)
        return row, bp_out, mf_out, srows_out

    def participant_row(item: tuple[str, pd.DataFrame]
                        ) -> tuple[dict[str, Any], ModulusFit | None, list[dict[str, Any]]]:
        """One participant's row: the reference fit and the joint E_s over its textures, with
        its sensitivity refits."""
        participant, g = item
        mf_out: ModulusFit | None = None
        srows_out: list[dict[str, Any]] = []
        ref = ref_fits[(participant, "both")]
        row = {"participant": participant, "n_strokes": int((strokes["participant"] == participant).sum())}
        row.update({f"ref_{k}": v for k, v in fit_row(ref).items()})
        subs = [sub for (s, _), sub in g.groupby(["sample", "direction"]) if s in tables]
        if subs:
            def joint(pick: Any, subs: list[pd.DataFrame] = subs, ref: Any = ref) -> ModulusFit:
                data = [(sub["load"].to_numpy(), sub["mu_norm"].to_numpy(), pick(sub["sample"].iloc[0]))
                        for sub in subs]
                if len(data) == 1:
                    return estimate_skin_modulus(*data[0], reference=ref, clusters=cluster_column(subs[0]),
                                                 **fit_kw)
                return estimate_skin_modulus_joint(data, reference=ref, clusters=[cluster_column(s) for s in subs],
                                                   **fit_kw)
            try:
                mf = joint(tables.get)
                mf_out = mf
                row.update({k: v for k, v in _modulus_columns(mf).items() if k != "model_scale"},
                           n_textures=len(subs))
                samples = {sub["sample"].iloc[0] for sub in subs}
                if opts.sensitivity and samples <= set(variants):
                    # the same variant for every texture of the participant
                    common = set.intersection(*(set(variants[s].tables) for s in samples))
                    refits = [(p, v, (lambda k=(p, v): joint(lambda s: variants[s].tables[k])))
                              for (p, v) in sorted(common, key=lambda k: (k[0] != "micro_model", k))]
                    srows, summary = sensitivity_rows(mf, refits, {"participant": participant,
                                                                    "sample": "all textures", "direction": ""})
                    srows_out = srows
                    row.update(summary)
            except FingerpadError as exc:
                row["note"] = f"modulus: {exc}"
        return row, mf_out, srows_out

    by_condition = list(strokes.groupby(GROUP, sort=True))
    by_participant = list(usable.groupby("participant", sort=True))
    # the population fits per sample (each reads only its own strokes)
    by_sample = [g for _, g in strokes.groupby("sample", sort=True)] if opts.population else []

    def piece(item: tuple[str, int]) -> Any:
        """One independent piece of the fits: a population fit, a condition or a participant
        (``(kind, index)``: the workers hold the groups, only the index travels)."""
        kind, i = item
        if kind == "condition":
            return condition(by_condition[i])
        if kind == "participant":
            return participant_row(by_participant[i])
        return population_fit_rows(by_sample[i], opts.reference, opts.level)

    # the population fits (the longest pieces) first, so that no worker starts one last
    items = ([("population", i) for i in range(len(by_sample))] + [("condition", i) for i in range(len(by_condition))]
             + [("participant", i) for i in range(len(by_participant))])
    done = forked_map(piece, items, workers=resolve_workers(workers, len(items)))
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


#: The publications of the analysis's own statistics (:mod:`fingerpad.references` keys): the
#: stroke outlier flag (robust z-score), the transition test that searches its location, and its
#: early stop.
REFERENCES = ("iglewicz1993", "davies1987", "besag1991")


def study_references(result: StudyResult) -> tuple[str, ...]:
    """The publications of the methods an analysis used (:mod:`fingerpad.references` keys): its
    statistics, the friction law and the finger's models, and the micro-models of the E_s fits
    (the textures' own, and the other one when the sensitivity refits ran)."""
    from ..coupling import model_references
    from ..micro.bem import BEMUnitCell
    from ..micro.hertz import HertzUnitCell
    from ..references import keys_of

    cells = {"bem": BEMUnitCell, "hertz": HertzUnitCell}
    used = {g.micro_model for g in result.textures.values() if g is not None}
    if used and result.options.sensitivity:
        used = set(cells)  # every E_s is refitted with the other micro-model
    finger = resolve_finger(result.options.finger)
    return keys_of(REFERENCES, model_references(finger, *(cells[name] for name in sorted(used))))


def study_info(result: StudyResult) -> dict[str, Any]:
    """The facts of a study and the analysis settings, as written to the report and its JSON."""
    s = result.strokes
    opts = result.options
    return {
        "fingerpad_version": __version__,
        "reference_sample": opts.reference,
        "participants": sorted(s["participant"].unique()),
        "samples": sorted(s["sample"].unique()),
        "n_files": int(s["file"].nunique()),
        "n_strokes": int(len(s)),
        "n_outliers": int(s["outlier"].sum()),
        "n_clipped_strokes": int(len(result.clipped_strokes)),
        "clipping": {Path(str(f)).name: [c.describe() for c in clips]
                     for f, clips in sorted(result.clipping.items()) if clips},
        "confidence_level": opts.level,
        "stroke_trim": opts.strokes.trim,
        "outlier_z": opts.outlier_z,
        "breakpoint": {"space": opts.breakpoint_space, "method": opts.breakpoint_method,
                       "trend": opts.breakpoint_trend, "test": "sup likelihood ratio, parametric bootstrap",
                       "n_null": opts.n_null, "alpha": 1 - opts.level,
                       "edge_fraction": opts.breakpoint_edge},
        "population": "mixed model (random level and slope per participant, variance component per "
                      "recording) where its variance components are estimable, else two-stage "
                      "(per-participant fits, their mean and spread); Student t with participants - 1 df",
        "intervals": "random intercept per recording (session), REML; Student t with between-recording df",
        "warnings": list(result.warnings),
        "modulus_bounds_pa": list(opts.modulus_bounds),
        "finger": getattr(opts.finger, "name", opts.finger) or "default",
        "textures": {k: (None if v is None else vars(v)) for k, v in result.textures.items()},
    }
