"""The whole measurement study: options, result, and the pipeline of analyse_study."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import pandas as pd

from ..errors import FingerpadError
from .breakpoint import Breakpoint, find_breakpoint
from .curves import fit_curves, fit_row, normalise, spread_summary, spread_table
from .models import Model, TextureGeometry, resolve_finger, texture_model
from .modulus import (
    ModelTable,
    ModulusFit,
    design_effect,
    estimate_skin_modulus,
    estimate_skin_modulus_joint,
    modulus_from_transition,
)
from .recordings import Recording
from .strokes import GROUP, StrokeOptions, bin_strokes, flag_outliers, load_bin_edges, stroke_table


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
    breakpoint_space, breakpoint_method, breakpoint_trend, n_boot
        See :func:`find_breakpoint`; the default trend ``"steeper"`` looks for the contact
        transition (friction rising faster once the skin reaches the texture's base).
    level
        Confidence level of every interval.
    seed
        Random seed (bootstrap).
    finger
        Finger preset (or :class:`fingerpad.finger.Finger`) for the default model and the
        closed-form route's ridge area.
    modulus_bounds
        Search range of E_s, Pa.
    fit_scale
        Fit an amplitude factor with E_s (:func:`estimate_skin_modulus`).
    """

    reference: str = "flat"
    strokes: StrokeOptions = field(default_factory=StrokeOptions)
    outlier_z: float = 3.5
    n_bins: int = 8
    min_fit_strokes: int = 4
    breakpoint_space: Literal["log", "linear"] = "log"
    breakpoint_method: Literal["profile", "bootstrap"] = "profile"
    breakpoint_trend: Literal["any", "steeper", "flatter"] = "steeper"
    n_boot: int = 200
    level: float = 0.95
    seed: int = 0
    finger: Any = None
    modulus_bounds: tuple[float, float] = (2e4, 2e7)
    fit_scale: bool = False

    def __post_init__(self) -> None:
        if not self.reference:
            raise FingerpadError("a reference sample must be named")
        if not 0 < self.level < 1:
            raise FingerpadError(f"level must lie in (0, 1), got {self.level!r}")
        if self.n_bins < 1 or self.min_fit_strokes < 3:
            raise FingerpadError("n_bins must be >= 1 and min_fit_strokes >= 3")
        if not self.outlier_z > 0:
            raise FingerpadError(f"outlier_z must be positive, got {self.outlier_z!r}")


@dataclass
class StudyResult:
    """Everything :func:`analyse_study` found; tables are pandas DataFrames (SI units).

    Attributes
    ----------
    strokes
        One row per stroke: metadata, load, mu, robust_z, outlier, mu_ref, mu_norm.
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

    @property
    def summary(self) -> pd.DataFrame:
        """The summary table (alias of :attr:`conditions`)."""
        return self.conditions


def _closed_form(bp: Breakpoint, geom: TextureGeometry, finger: Any) -> tuple[float, float, float]:
    def one(load: float) -> float:
        try:
            return modulus_from_transition(load, geom.radius, geom.height, geom.spacing, finger,
                                           skin_poisson=finger.skin_poisson, material_modulus=geom.material_modulus,
                                           material_poisson=geom.material_poisson)
        except FingerpadError:
            return math.nan
    vals = [one(bp.load), one(bp.ci_low), one(bp.ci_high)]
    lo, hi = np.nanmin(vals[1:] + [vals[0]]), np.nanmax(vals[1:] + [vals[0]])
    return vals[0], float(lo), float(hi)


def analyse_study(
    recordings: Sequence[Recording],
    options: AnalysisOptions = AnalysisOptions(),
    *,
    textures: Mapping[str, TextureGeometry | None] | None = None,
    models: Mapping[str, Model] | None = None,
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
        (:func:`hertz_texture_model`) and the closed-form E_s for those samples.
    models
        Sample -> normalised-friction model; overrides the default for that sample.

    Raises
    ------
    FingerpadError
        For unreadable strokes, a missing reference, or a participant without one.
    """
    opts = options
    textures = dict(textures or {})
    strokes = stroke_table(recordings, opts.strokes)
    strokes = flag_outliers(strokes, opts.outlier_z)
    strokes, ref_fits = normalise(strokes, opts.reference, opts.min_fit_strokes)
    fits, power_laws = fit_curves(strokes, opts.min_fit_strokes)
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
    tables: dict[str, ModelTable] = {}
    for sample, model in all_models.items():
        loads = usable.loc[usable["sample"] == sample, "load"].to_numpy()
        if loads.size and sample != opts.reference:
            try:  # one table per texture, shared by every participant's fit
                tables[sample] = ModelTable(model, (float(loads.min()), float(loads.max())), opts.modulus_bounds)
            except FingerpadError as exc:
                raise FingerpadError(f"model of sample {sample!r}: {exc}") from None

    # session (file) effects on the reference: its residuals' design effect widens E_s intervals
    ref_deff: dict[str, float] = {}
    for participant, ref in usable[usable["sample"] == opts.reference].groupby("participant"):
        resid = np.log(ref["mu"].to_numpy()) - np.log(ref["mu_ref"].to_numpy())
        ref_deff[participant] = design_effect(resid, ref["file"].to_numpy())

    breakpoints: dict[tuple[str, str, str], Breakpoint] = {}
    modulus_fits: dict[tuple[str, ...], ModulusFit] = {}
    rows = []
    for key, g in strokes.groupby(GROUP, sort=True):
        participant, sample, direction = key
        good = usable[(usable["participant"] == participant) & (usable["sample"] == sample)
                      & (usable["direction"] == direction)]
        row: dict[str, Any] = dict(zip(GROUP, key))
        row.update(is_reference=sample == opts.reference, n_files=g["file"].nunique(), n_strokes=len(g),
                   n_outliers=int(g["outlier"].sum()), load_min=float(g["load"].min()),
                   load_max=float(g["load"].max()))
        fit = power_laws.get((*key, "both"))
        row.update(fit_row(fit) if fit is not None else {})
        row["mu_at_1N"] = float(fit(np.array([1.0]))[0]) if fit is not None else math.nan
        fp, fm = power_laws.get((*key, "+")), power_laws.get((*key, "-"))
        mid = float(np.sqrt(row["load_min"] * row["load_max"]))
        row["sense_ratio"] = (float(fp(np.array([mid]))[0] / fm(np.array([mid]))[0])
                              if fp is not None and fm is not None else math.nan)
        row["mu_norm_mean"] = float(good["mu_norm"].mean()) if sample != opts.reference else 1.0
        notes = []
        if sample != opts.reference:
            try:
                bp = find_breakpoint(good["load"].to_numpy(), good["mu_norm"].to_numpy(),
                                     space=opts.breakpoint_space, method=opts.breakpoint_method,
                                     trend=opts.breakpoint_trend, level=opts.level, n_boot=opts.n_boot, seed=opts.seed)
                breakpoints[key] = bp
                row.update(breakpoint_load=bp.load, breakpoint_ci_low=bp.ci_low, breakpoint_ci_high=bp.ci_high,
                           slope_below=bp.slope_below, slope_above=bp.slope_above, breakpoint_p=bp.p_value)
                geom = textures.get(sample)
                if geom is not None:
                    e, lo, hi = _closed_form(bp, geom, finger)
                    row.update(skin_modulus_closed_form=e, skin_modulus_closed_form_ci_low=lo,
                               skin_modulus_closed_form_ci_high=hi)
            except FingerpadError as exc:
                notes.append(f"breakpoint: {exc}")
            table = tables.get(sample)
            if table is not None:
                try:
                    mf = estimate_skin_modulus(good["load"], good["mu_norm"], table, level=opts.level,
                                               fit_scale=opts.fit_scale, reference=ref_fits[(participant, "both")],
                                               reference_design_effect=ref_deff[participant],
                                               clusters=good["file"].to_numpy())
                    modulus_fits[key] = mf
                    row.update(skin_modulus=mf.skin_modulus, skin_modulus_ci_low=mf.ci_low,
                               skin_modulus_ci_high=mf.ci_high, skin_modulus_at_bound=mf.at_bound,
                               model_scale=mf.scale)
                except FingerpadError as exc:
                    notes.append(f"modulus: {exc}")
        row["note"] = "; ".join(notes)
        rows.append(row)
    conditions = pd.DataFrame(rows)

    prow = []
    for participant, g in usable.groupby("participant", sort=True):
        ref = ref_fits[(participant, "both")]
        row = {"participant": participant, "n_strokes": int((strokes["participant"] == participant).sum())}
        row.update({f"ref_{k}": v for k, v in fit_row(ref).items()})
        keys = [(participant, s, d) for (s, d) in g.groupby(["sample", "direction"]).groups if s in tables]
        subs = [sub for (s, _), sub in g.groupby(["sample", "direction"]) if s in tables]
        data = [(sub["load"].to_numpy(), sub["mu_norm"].to_numpy(), tables[sub["sample"].iloc[0]]) for sub in subs]
        if data:
            try:
                if len(keys) == 1 and keys[0] in modulus_fits:
                    mf = modulus_fits[keys[0]]  # one texture: the joint fit is that fit
                else:
                    mf = estimate_skin_modulus_joint(data, level=opts.level, fit_scale=opts.fit_scale,
                                                     reference=ref, reference_design_effect=ref_deff[participant],
                                                     clusters=[sub["file"].to_numpy() for sub in subs])
                modulus_fits[(participant,)] = mf
                row.update(skin_modulus=mf.skin_modulus, skin_modulus_ci_low=mf.ci_low,
                           skin_modulus_ci_high=mf.ci_high, skin_modulus_at_bound=mf.at_bound,
                           n_textures=len(data))
            except FingerpadError as exc:
                row["note"] = f"modulus: {exc}"
        prow.append(row)
    return StudyResult(
        options=opts, strokes=strokes, bins=bins, fits=fits, spread=spread, spread_summary=summary_spread,
        conditions=conditions, participants=pd.DataFrame(prow), bin_edges=edges, power_laws=power_laws,
        reference_fits=ref_fits, breakpoints=breakpoints, modulus_fits=modulus_fits, models=all_models,
        tables=tables, textures=textures,
    )


def condition_label(sample: str, direction: str) -> str:
    """``sample/direction`` (or the sample alone): the label of one measured condition."""
    return f"{sample}/{direction}" if direction else str(sample)


def load_grid(result: StudyResult, n: int = 60) -> np.ndarray:
    """``n`` log-spaced loads (N) over the study's measured range, for curves and figures."""
    loads = result.strokes["load"].to_numpy()
    return np.geomspace(float(loads.min()), float(loads.max()), n)
