"""The measurement study's options and result, and the facts of an analysis as its report
states them (:func:`study_info`, :func:`study_references`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd

from .._version import __version__
from ..errors import FingerpadError
from .breakpoint import EDGE_FRACTION, Breakpoint
from .clipping import Clip
from .micro_models import Model, TextureGeometry, resolve_finger
from .modulus import ModelTable, ModulusFit
from .recordings import Recording
from .strokes import StrokeOptions, StrokeReport

__all__ = ["MAX_BINS", "MAX_SIMULATIONS", "REFERENCES", "AnalysisOptions", "MeasurementWarning", "StudyResult",
           "study_info", "study_references"]


class MeasurementWarning(UserWarning):
    """Something in the data a person should look at (implausible friction, a caveat)."""


#: Most simulations of the breakpoint test's null distribution or of its bootstrap interval
#: (``n_null``, ``n_boot``): 100 times the default 999, which already gives p-values to 0.001.
MAX_SIMULATIONS = 100_000
#: Most load bins (``n_bins``): a table row and a figure point each.
MAX_BINS = 1000


#: The ``fingerpad analyse`` option of each :class:`AnalysisOptions` field a user sets there
#: (named in the field's error message beside the field).
ANALYSIS_OPTION_NAMES = {"level": "--level", "n_bins": "--bins", "outlier_z": "--outlier-z", "n_null": "--n-null",
                         "breakpoint_space": "--breakpoint-space", "breakpoint_method": "--breakpoint-method",
                         "breakpoint_trend": "--trend", "seed": "--seed"}


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
        # one message per setting, naming the field and the option that sets it from the
        # command line (``fingerpad analyse``), so that the API and the CLI say the same thing
        def bad(field: str, rule: str) -> FingerpadError:
            option = ANALYSIS_OPTION_NAMES.get(field)
            return FingerpadError(f"{field}{f' ({option})' if option else ''}: {rule}, got {getattr(self, field)!r}")

        if not self.reference:
            raise FingerpadError("a reference sample must be named")
        if not 0 < self.level < 1:
            raise bad("level", "must lie in (0, 1)")
        if not 1 <= self.n_bins <= MAX_BINS:
            raise bad("n_bins", f"must lie in 1..{MAX_BINS}")
        if not 3 <= self.min_fit_strokes <= MAX_SIMULATIONS:
            raise bad("min_fit_strokes", f"must lie in 3..{MAX_SIMULATIONS}")
        if not self.outlier_z > 0:
            raise bad("outlier_z", "must be positive")
        if not 19 <= self.n_null <= MAX_SIMULATIONS:
            raise bad("n_null", f"must lie in 19..{MAX_SIMULATIONS}")
        if not 20 <= self.n_boot <= MAX_SIMULATIONS:
            raise bad("n_boot", f"must lie in 20..{MAX_SIMULATIONS}")
        if self.breakpoint_space not in ("log", "linear"):
            raise bad("breakpoint_space", "must be 'log' or 'linear'")
        if self.breakpoint_method not in ("profile", "bootstrap"):
            raise bad("breakpoint_method", "must be 'profile' or 'bootstrap'")
        if self.breakpoint_trend not in ("any", "steeper", "flatter"):
            raise bad("breakpoint_trend", "must be 'any', 'steeper' or 'flatter'")
        if not 0 <= self.breakpoint_edge < 0.5:
            raise bad("breakpoint_edge", "must lie in [0, 0.5)")
        if self.seed < 0:
            raise bad("seed", "must be a non-negative integer")


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
