"""Finger friction measured on a tribometer: import, strokes, curves, normalisation, skin modulus.

The pipeline (``fingerpad analyse``), one module a step:

1. :mod:`.columns`, :mod:`.importers`, :mod:`.recordings` - files (one importer per format) with a
   column spec and units, file-name templates and manifests -> recordings in SI units;
2. :mod:`.strokes` - reciprocating strokes of a recording split at direction changes, steady
   windows; :mod:`.clipping` - saturated force channels (their strokes are left out);
   :mod:`.tables` - the study's stroke table, outliers, load bins;
3. :mod:`.curves` - power law mu = k F^(n-1) per participant and sample, normalisation by the
   flat reference (mu_tex / mu_ref cancels the person's ridge area), spread between people;
   :mod:`.stats` - the random-intercept (per recording) models behind every interval;
4. :mod:`.breakpoint` - the change of trend of the normalised friction (segmented regression),
   reported only when a test that accounts for the search over locations finds one;
5. :mod:`.micro_models`, :mod:`.modulus`, :mod:`.transition`, :mod:`.modulus_sensitivity` - the skin
   micro-modulus E_s: model fits (BEM or Hertz unit cell) with the set of E_s the data allow,
   the closed form from the transition load (Eq. 3.6), and the sensitivity to the micro-model
   and the friction parameters;
6. :mod:`.across_participants` - mean curves and power laws across participants (mixed model with a
   random exponent per person, or a two-stage estimate; the table says which);
7. :mod:`.analysis` - the whole study; :mod:`.report` - tables, NetCDF and the HTML report;
   :mod:`.simulate` - synthetic recordings with known parameters.

SI units throughout (N, m, Pa, s).
"""

from .analysis import AnalysisOptions, MeasurementWarning, StudyResult, analyse_study
from .breakpoint import Breakpoint, find_breakpoint
from .clipping import Clip, find_clipping
from .columns import ColumnSpec, load_spec, parse_filename, template_regex, unit_factor
from .curves import PowerLaw, fit_curves, fit_power_law_clustered, normalise, sense_ratio, spread_summary, spread_table
from .importers import RawTable, read_table, supported_suffixes
from .micro_models import (
    BaseContactCell,
    TextureGeometry,
    bem_texture_model,
    hertz_texture_model,
    model_variant,
    read_textures,
    texture_model,
)
from .modulus import (
    ModelTable,
    ModulusFit,
    design_effect,
    estimate_skin_modulus,
    estimate_skin_modulus_joint,
    modulus_from_transition,
    transition_load,
)
from .across_participants import population_curves, population_fits
from .recordings import Recording, load_study, read_manifest, read_recording
from .modulus_sensitivity import PERTURBATIONS, other_micro_model, perturbed_models
from .simulate import SimulationConfig, simulate_recording, simulate_stroke_table, simulate_study
from .stats import ClusterFit, cluster_mean, random_intercept_fit
from .strokes import Stroke, StrokeOptions, StrokeReport, detect_strokes, direction_signal, find_strokes, measure_strokes
from .tables import PLAUSIBLE_MU, bin_strokes, flag_outliers, load_bin_edges, plausibility_warnings, stroke_table

__all__ = [
    "PERTURBATIONS",
    "PLAUSIBLE_MU",
    "Clip",
    "ClusterFit",
    "MeasurementWarning",
    "PowerLaw",
    "RawTable",
    "StrokeReport",
    "cluster_mean",
    "find_clipping",
    "find_strokes",
    "fit_power_law_clustered",
    "model_variant",
    "other_micro_model",
    "perturbed_models",
    "plausibility_warnings",
    "population_curves",
    "population_fits",
    "random_intercept_fit",
    "read_table",
    "sense_ratio",
    "supported_suffixes",
    "AnalysisOptions",
    "BaseContactCell",
    "Breakpoint",
    "ColumnSpec",
    "ModelTable",
    "ModulusFit",
    "Recording",
    "SimulationConfig",
    "Stroke",
    "StrokeOptions",
    "StudyResult",
    "TextureGeometry",
    "analyse_study",
    "bem_texture_model",
    "bin_strokes",
    "design_effect",
    "detect_strokes",
    "direction_signal",
    "estimate_skin_modulus",
    "estimate_skin_modulus_joint",
    "find_breakpoint",
    "fit_curves",
    "flag_outliers",
    "hertz_texture_model",
    "load_bin_edges",
    "load_spec",
    "load_study",
    "measure_strokes",
    "modulus_from_transition",
    "normalise",
    "parse_filename",
    "read_manifest",
    "read_recording",
    "read_textures",
    "simulate_recording",
    "simulate_stroke_table",
    "simulate_study",
    "spread_summary",
    "spread_table",
    "stroke_table",
    "template_regex",
    "texture_model",
    "transition_load",
    "unit_factor",
]
