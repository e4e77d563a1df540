"""Inverse design: textures of a family, within bounds, that give a wanted tactile friction.

Targets are quantities of a prediction at exploration loads (``mu_rel=0.5@1N``: mu/mu_ref of
0.5 at 1 N; also ``mu``, ``mu_ref``, ``area_ratio``), optionally a minimum critical load (stay
in asperity contact over the loads of touch) and manufacturing limits (a minimum lateral
feature size, a maximum height-to-feature aspect ratio). Candidates come from an existing sweep
(ranked by their stored values) or from an optimisation with the BEM in the loop (a Latin
hypercube, then Nelder-Mead in the unit box from the best point, every evaluation a direct
prediction through the unit-cell cache). Whatever their origin, every number reported for a
candidate comes from a direct prediction of that texture, never from interpolation.
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import FingerpadError, SetupError
from .axes import Axis
from .perception_targets import PerceptionTarget, member_verdicts

__all__ = ["QUANTITIES", "XATOL", "Candidate", "DesignProblem", "Target", "candidate_study", "critical_penalty",
           "parse_target", "rank_sweep", "search", "texture_limits"]

#: The optimiser's parameter tolerance, in the unit box of the free parameters (log-scaled for
#: log axes): Nelder-Mead stops refining below it, and candidates closer than it are one design
#: (:func:`fingerpad.design.inverse_design.merge_close`). 1 % of a 100-400 um log box is 1.4 % of the
#: spacing (2.8 um at 200 um); the five "candidates" 200.7-201.8 um reported before were 0.4 %
#: of it apart.
XATOL = 0.01

#: Quantities a target can name: per-load values of a prediction.
QUANTITIES = {"mu_rel": "mu / mu_ref", "mu": "friction coefficient", "mu_ref": "flat-reference friction",
              "area_ratio": "A_re / A_fr"}


@dataclass(frozen=True)
class Target:
    """``quantity`` = ``value`` at ``load`` (N)."""

    quantity: str
    value: float
    load: float

    def __str__(self) -> str:
        return f"{self.quantity}={self.value:g}@{self.load:g}N"


def parse_target(text: str) -> Any:
    """``QUANTITY=VALUE@LOAD`` (e.g. ``mu_rel=0.5@1N``) -> :class:`Target`; a perception target
    ``feels-like=REF@LOAD`` or ``feels-different-from=REF@LOAD`` (REF a study file or ``flat``) ->
    :class:`~fingerpad.design.perception_targets.PerceptionTarget`."""
    from ..units import parse_positive, parse_quantity
    from .perception_targets import KINDS, parse_perception_target

    m = re.fullmatch(r"\s*([A-Za-z_-]+)\s*=\s*(.+)@\s*(\S+)\s*", str(text))
    if not m:
        raise FingerpadError(f"--target {text!r}: expected QUANTITY=VALUE@LOAD, e.g. mu_rel=0.5@1N")
    name, value, load = m.groups()
    if name in KINDS:
        return parse_perception_target(name, value, load, str(text))
    if name not in QUANTITIES:
        raise FingerpadError(f"--target {text!r}: no quantity {name!r} (quantities: {', '.join(QUANTITIES)}; "
                             f"perception: {', '.join(KINDS)})")
    v = parse_quantity(value, "none", name="--target")
    if not v > 0:
        raise FingerpadError(f"--target {text!r}: the value must be positive")
    return Target(name, v, parse_positive(load, "force", name="--target"))


@dataclass
class DesignProblem:
    """What is searched for (SI units).

    Attributes
    ----------
    base
        The study sections (the texture family and its fixed parameters, material, finger).
    axes
        The free parameters, each with ``values = (low, high)``.
    targets
        The friction targets.
    min_critical_load
        Lowest acceptable critical load (N), or ``None``.
    min_feature, max_aspect
        Manufacturing limits (m; height / lateral feature), or ``None``.
    tolerance
        Relative deviation within which a target counts as met.
    reference_mu
        Per perception target (``str(target)``), the reference surface's friction per member at its load
        (``None`` for the flat reference; :mod:`fingerpad.design.perception_targets`).
    weber
        The members' Weber fractions (one per member; the study's finger alone: one).
    """

    base: dict[str, dict[str, Any]]
    axes: list[Axis]
    targets: list[Any]  # Target or PerceptionTarget
    min_critical_load: float | None = None
    min_feature: float | None = None
    max_aspect: float | None = None
    tolerance: float = 0.05
    reference_mu: dict[str, Any] = field(default_factory=dict)
    weber: Any = None

    def __post_init__(self) -> None:
        # each range decided here, once, for the command line and the Python API alike
        if not (isinstance(self.tolerance, (int, float)) and 0 < self.tolerance <= 1):
            raise FingerpadError(f"--tolerance {self.tolerance!r}: a relative deviation between 0 and 1 "
                                 "(0.05 is 5 %)")
        for name, value in (("--min-critical-load", self.min_critical_load), ("--min-feature", self.min_feature),
                            ("--max-aspect", self.max_aspect)):
            if value is not None and not (math.isfinite(value) and value > 0):
                raise FingerpadError(f"{name}: must be a positive finite number, got {value!r}")
        if not self.axes:
            raise FingerpadError("give at least one --vary NAME=LOW:HIGH")
        if not self.targets:
            raise FingerpadError("give at least one --target QUANTITY=VALUE@LOAD")

    @property
    def loads(self) -> np.ndarray:
        return np.array(sorted({t.load for t in self.targets}))

    def unit(self, params: Mapping[str, float]) -> np.ndarray:
        """Parameter values -> the point of the unit box (log-scaled for log axes)."""
        out = []
        for axis in self.axes:
            lo, hi, v = float(axis.values[0]), float(axis.values[1]), float(params[axis.name])
            out.append((math.log(v) - math.log(lo)) / (math.log(hi) - math.log(lo)) if axis.log and v > 0
                       else (v - lo) / (hi - lo))
        return np.array(out)


@dataclass
class Candidate:
    """A texture and its directly predicted values."""

    params: dict[str, float]
    values: dict[str, float] = field(default_factory=dict)
    critical_load: float = math.nan
    feature: float = math.nan
    aspect: float = math.nan
    objective: float = math.inf
    meets: bool = False
    violations: list[str] = field(default_factory=list)
    curve: dict[str, list[float]] = field(default_factory=dict)
    reason: str = ""
    #: For a design for a population of fingers: its coverage and quantiles
    #: (:func:`fingerpad.design.robust.population_candidate`); empty otherwise.
    population: dict[str, Any] = field(default_factory=dict)
    #: The publications of the methods its prediction used (:mod:`fingerpad.references` keys;
    #: gathered into the result document's ``references``, not repeated per candidate).
    references: tuple[str, ...] = ()

    def as_dict(self) -> dict[str, Any]:
        out = {"params": self.params, "values": self.values, "critical_load": self.critical_load,
               "feature": self.feature, "aspect": self.aspect, "objective": self.objective, "meets": self.meets,
               "violations": self.violations, "curve": self.curve, "reason": self.reason}
        if self.population:
            out["population"] = self.population
        return out


def _study_data(problem: DesignProblem, params: Mapping[str, float]) -> dict[str, dict[str, Any]]:
    data = {k: dict(v) for k, v in problem.base.items()}
    for axis in problem.axes:
        data.setdefault(axis.section, {})[axis.key] = axis.study_value(params[axis.name])
    return data


def candidate_study(problem: DesignProblem, params: Mapping[str, float], loads: Sequence[float]) -> Any:
    """The study of one texture of the box (the base with ``params``) at ``loads`` (N).

    Raises
    ------
    FingerpadError
        A texture that cannot exist (overlapping asperities, say).
    """
    from ..study.spec import study_from_dict

    data = _study_data(problem, params)
    data.setdefault("loads", {}).pop("range", None)
    data["loads"]["values"] = [float(f) for f in loads]
    data["loads"].pop("zones_at", None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return study_from_dict(data)


def critical_penalty(critical_load: float, limit: float | None) -> tuple[float, str | None]:
    """The objective's penalty for a critical load (N) below ``limit`` (N) and the violation's
    text; ``(0, None)`` when it is met or there is no limit (a NaN load breaks the limit)."""
    if limit is None or critical_load >= limit:
        return 0.0, None
    ratio = critical_load / limit if critical_load > 0 else 0.0
    return (1.0 - min(ratio, 1.0)) ** 2 + 0.01, f"critical load {critical_load:.3g} N below {limit:g} N"


def texture_limits(problem: DesignProblem, cand: Candidate, texture: Any) -> float:
    """Fill ``cand.feature`` and ``cand.aspect`` from the texture family's feature and return
    the penalty of the manufacturing limits it breaks (each also added to ``cand.violations``)."""
    from ..textures import registry

    fam = registry().get(texture.family or "")
    if fam is not None and fam.features is not None:
        cand.feature, height = fam.features(texture)
        cand.aspect = height / cand.feature if cand.feature > 0 else math.inf
    penalty = 0.0
    if problem.min_feature is not None and not cand.feature >= problem.min_feature:
        cand.violations.append(f"feature {cand.feature * 1e6:.3g} um below {problem.min_feature * 1e6:g} um")
        penalty += (1.0 - cand.feature / problem.min_feature) ** 2 + 0.01
    if problem.max_aspect is not None and not cand.aspect <= problem.max_aspect:
        cand.violations.append(f"aspect ratio {cand.aspect:.3g} above {problem.max_aspect:g}")
        penalty += (cand.aspect / problem.max_aspect - 1.0) ** 2 + 0.01
    return penalty


def predict_candidate(problem: DesignProblem, params: Mapping[str, float], loads: Sequence[float] | None = None,
                      curve_loads: Sequence[float] | None = None) -> Candidate:
    """A direct prediction of one texture, scored against the problem (objective: the mean of
    the squared relative deviations from the targets, plus penalties for broken limits)."""
    from ..study.run import run_study

    cand = Candidate(params=dict(params))
    target_loads = problem.loads
    all_loads = np.unique(np.concatenate([target_loads, np.asarray(curve_loads if curve_loads is not None else [],
                                                                     float)]))
    try:
        study = candidate_study(problem, params, all_loads)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            pred = run_study(study)
    except SetupError:
        raise  # the machine's setting, not this texture's: every candidate would fail alike
    except FingerpadError as exc:
        cand.reason = str(exc)
        return cand
    from ..study.citations import prediction_references

    cand.references = prediction_references(pred)
    cur = pred.primary
    f = np.asarray(cur.load)
    series = {"mu": cur.mu, "mu_ref": cur.mu_ref, "mu_rel": cur.mu_normalised, "area_ratio": cur.area_ratio}
    errors = []
    for t in problem.targets:
        i = int(np.argmin(np.abs(f - t.load)))
        if isinstance(t, PerceptionTarget):  # the study's finger tells it from REF, or not
            verdict = member_verdicts(t, np.asarray(cur.mu)[i:i + 1], np.asarray(cur.mu_ref)[i:i + 1],
                                      problem.reference_mu.get(str(t)), np.asarray(problem.weber, float)[:1],
                                      problem.tolerance)
            cand.values[str(t)] = float(verdict["p_correct"][0])
            errors.append(float(verdict["score"][0]))
            continue
        got = float(np.asarray(series[t.quantity])[i])
        cand.values[str(t)] = got
        errors.append((got / t.value - 1.0) ** 2)
    crit = pred.critical_load.get("bem")
    if crit is None or not math.isfinite(crit) and not math.isinf(crit):
        crit = pred.critical_load.get("hertz")
    cand.critical_load = math.nan if crit is None else float(crit)
    penalty, violation = critical_penalty(cand.critical_load, problem.min_critical_load)
    if violation:
        cand.violations.append(violation)
    penalty += texture_limits(problem, cand, pred.texture)
    cand.objective = float(np.mean(errors)) + penalty
    cand.meets = not cand.violations and all(math.sqrt(e) <= problem.tolerance for e in errors)
    if curve_loads is not None:
        keep = np.isin(f, np.asarray(curve_loads, float))
        cand.curve = {"load": f[keep].tolist(), "mu": np.asarray(cur.mu)[keep].tolist(),
                      "mu_rel": np.asarray(cur.mu_normalised)[keep].tolist(),
                      "area_ratio": np.asarray(cur.area_ratio)[keep].tolist()}
    return cand


def _to_params(problem: DesignProblem, u: np.ndarray) -> dict[str, float]:
    """A point of the unit box -> parameter values (log-uniform axes in log)."""
    out = {}
    for axis, ui in zip(problem.axes, np.clip(u, 0.0, 1.0), strict=True):
        lo, hi = axis.values
        out[axis.name] = float(math.exp(math.log(lo) + ui * (math.log(hi) - math.log(lo)))) if axis.log else \
            float(lo + ui * (hi - lo))
    return out


def search(problem: DesignProblem, *, initial: int | None = None, max_evaluations: int = 60, seed: int = 0,
           progress: Callable[[int, int], None] | None = None,
           evaluate: Callable[[DesignProblem, dict[str, float]], Candidate] | None = None) -> list[Candidate]:
    """Candidates by optimisation with the BEM in the loop, best first (all evaluated points).

    A Latin hypercube of ``initial`` points (default: half the evaluations: a target met in a
    narrow band, next to a constraint, is found by covering the box first), then Nelder-Mead
    from the best of them in the unit box (log-scaled for log axes), up to ``max_evaluations``
    direct predictions in all. ``evaluate(problem, params)`` scores one texture (default
    :func:`predict_candidate`; a population design passes its own, see
    :mod:`fingerpad.design.robust`).
    """
    score = predict_candidate if evaluate is None else evaluate
    if initial is None:
        initial = max(8, max_evaluations // 2)
    from scipy.optimize import minimize
    from scipy.stats import qmc

    evaluated: dict[tuple[float, ...], Candidate] = {}

    def objective(u: np.ndarray) -> float:
        u = np.clip(np.asarray(u, float), 0.0, 1.0)
        key = tuple(np.round(u, 6))
        if key not in evaluated:
            if len(evaluated) >= max_evaluations:
                return math.inf
            evaluated[key] = score(problem, _to_params(problem, u))
            if progress is not None:
                progress(len(evaluated), max_evaluations)
        return evaluated[key].objective

    n = max(1, min(initial, max_evaluations))
    start = qmc.LatinHypercube(d=len(problem.axes), seed=seed).random(n)
    for u in start:
        objective(u)
    best = min(evaluated, key=lambda k: evaluated[k].objective)
    if len(evaluated) < max_evaluations and math.isfinite(evaluated[best].objective):
        minimize(objective, np.array(best), method="Nelder-Mead",
                 options={"maxfev": max_evaluations - len(evaluated), "xatol": XATOL, "fatol": 1e-5,
                          "initial_simplex": _simplex(np.array(best))})
    return sorted(evaluated.values(), key=lambda c: c.objective)


def _simplex(x0: np.ndarray, step: float = 0.15) -> np.ndarray:
    pts = [x0]
    for i in range(x0.size):
        p = x0.copy()
        p[i] = p[i] + step if p[i] + step <= 1.0 else p[i] - step
        pts.append(p)
    return np.array(pts)


def rank_sweep(ds: Any, targets: Sequence[Target], min_critical_load: float | None = None,
               problem: DesignProblem | None = None) -> list[dict[str, Any]]:
    """Points of a sweep ranked by their stored values against the targets (best first).

    Only a first selection: :func:`fingerpad.design.inverse.predict_candidate` checks each by a
    direct prediction before anything is reported.
    """
    from .designmap import swept_axes

    axes = swept_axes(ds)
    stacked = ds.stack(_point=[d for d in ds["valid"].dims]) if ds.attrs.get("design") == "grid" else ds
    dim = "_point" if ds.attrs.get("design") == "grid" else "point"
    loads = ds["load"].values
    for t in targets:
        if not loads.min() * (1 - 1e-9) <= t.load <= loads.max() * (1 + 1e-9):
            raise FingerpadError(f"--target {t}: the load is outside the sweep's loads {loads.min():g}-{loads.max():g} N")
    score = np.zeros(stacked.sizes[dim])
    for t in targets:
        series = stacked[t.quantity].interp(load=t.load).values
        score += (series / t.value - 1.0) ** 2
    score /= max(len(targets), 1)
    ok = stacked["valid"].values & stacked["done"].values & np.isfinite(score)
    if min_critical_load is not None:
        crit = stacked["critical_load_bem"].values
        crit = np.where(np.isnan(crit), stacked["critical_load_hertz"].values, crit)
        ok &= crit >= min_critical_load
    order = np.argsort(np.where(ok, score, np.inf))
    out = []
    for i in order[: int(ok.sum())]:
        params = {a: _scalar(stacked[a].values[i]) for a in axes}
        out.append({"params": params, "score": float(score[i])})
    return out


def _scalar(value: Any) -> Any:
    try:
        return float(value)
    except (TypeError, ValueError):
        return str(value)
