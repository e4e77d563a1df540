"""Inverse design for a population of fingers (issue 22, "robust inverse design").

Two goals (:class:`PopulationGoal`), for targets ``QUANTITY=VALUE@LOAD`` and the tolerance of
the plain design:

* **coverage** ``c`` in (0, 1]: at least the fraction ``c`` of the members meets every target
  within the tolerance (and, with ``min_critical_load``, has its own critical load at or above
  it). The search minimises the ``ceil(c n)``-th smallest member score, a member's score being
  the largest squared relative deviation over the targets plus the plain design's penalty for
  its critical load: that order statistic lies within ``tolerance**2`` exactly when the coverage
  is reached (for a single target and no limit; the limit's penalty adds at least 0.01).
* **quantile** ``q`` in [0, 1]: the ``q``-quantile over the members of each target quantity at
  its load meets the target (the plain design's objective on those quantiles); a
  ``min_critical_load`` applies to the ``q``-quantile of the members' critical loads.

Cost: a candidate texture costs one unit cell, as in the plain design. psi(p) depends on p/E*
only (docs/solver.md, "One curve for every modulus and every scale"), so member ``i`` with
reduced modulus ``E_i`` reads the cell solved at ``E_0`` at the pressure ``p E_0 / E_i``. While
searching, :class:`MemberTable` evaluates all members at once with the package's one member
path (:func:`fingerpad.population.members.predict_fingers`, the path of ``predict --population``, so
the screen's numbers are the direct prediction's, bit for bit); every number *reported* for a
candidate comes from :func:`fingerpad.population.run.run_population` on that texture
(:func:`population_candidate`), the direct population prediction of ``predict --population``.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FingerpadError, SetupError
from ..population.distributions import Population
from ..population.members import member_finger
from ..population.run import DEFAULT_QUANTILES, run_population
from ..population.sources import load_population
from .perception_targets import is_perception, member_verdicts
from .inverse import (
    Candidate,
    DesignProblem,
    candidate_study,
    critical_penalty,
    texture_limits,
)

__all__ = ["MemberTable", "PopulationGoal", "population_candidate", "population_goal", "screen_candidate"]

#: The per-load quantities a target names, as :class:`~fingerpad.coupling.CurvePrediction` names them.
_CURVE_NAME = {"mu_rel": "mu_normalised", "mu": "mu", "mu_ref": "mu_ref", "area_ratio": "area_ratio"}


@dataclass(frozen=True)
class PopulationGoal:
    """What a design for a population asks: a coverage or a quantile (exactly one).

    Attributes
    ----------
    population
        The population of fingers (:class:`~fingerpad.population.distributions.Population`).
    coverage
        Least fraction of the members that must meet the targets, in (0, 1]; or ``None``.
    quantile
        The quantile of the members whose values must meet the targets, in [0, 1]; or ``None``.
    """

    population: Population
    coverage: float | None = None
    quantile: float | None = None

    def __post_init__(self) -> None:
        if (self.coverage is None) == (self.quantile is None):
            raise FingerpadError("--population needs exactly one of --coverage C (a fraction of the fingers) or "
                                 "--quantile Q (a quantile of the fingers)")
        if self.coverage is not None and not (0 < self.coverage <= 1):
            raise FingerpadError(f"--coverage {self.coverage!r}: a fraction of the population in (0, 1] "
                                 "(0.9 is 90 %)")
        if self.quantile is not None and not (0 <= self.quantile <= 1):
            raise FingerpadError(f"--quantile {self.quantile!r}: a quantile in [0, 1] (0.5 is the median)")

    @property
    def levels(self) -> tuple[float, ...]:
        """The quantiles reported: the default bands and the one asked for."""
        extra = () if self.quantile is None else (self.quantile,)
        return tuple(sorted({*DEFAULT_QUANTILES, *extra}))

    @property
    def needed(self) -> int:
        """Members that must meet the targets: ``ceil(coverage n)`` (coverage goals only)."""
        n = self.population.size
        return max(1, math.ceil(round(float(self.coverage or 0) * n, 9)))

    def describe(self) -> str:
        """The goal in words, e.g. ``90 % of the population (adults, 1000 fingers)``."""
        which = f"({self.population.name}, {self.population.size} fingers)"
        if self.coverage is not None:
            return f"{100 * self.coverage:g} % of the population {which}"
        return f"the {self.quantile:g} quantile of the population {which}"

    def as_dict(self) -> dict[str, Any]:
        """The ``population`` entry of the design document (plain data)."""
        pop = self.population
        return {"name": pop.name, "size": pop.size, "seed": pop.seed, "method": pop.method,
                "varied": list(pop.distributions), "coverage": self.coverage, "quantile": self.quantile,
                "quantile_levels": list(self.levels)}


def population_goal(population: str | Mapping[str, Any] | Population | None, coverage: str | float | None,
                    quantile: str | float | None) -> PopulationGoal | None:
    """The goal of a design for a population, its inputs checked (``None`` without one).

    Raises
    ------
    FingerpadError
        ``--coverage`` or ``--quantile`` without a population, both or neither with one, a value
        outside its range, an unknown preset or unreadable file.
    """
    from ..units import parse_quantity

    cov = None if coverage is None else parse_quantity(coverage, "none", name="--coverage")
    qua = None if quantile is None else parse_quantity(quantile, "none", name="--quantile")
    if population is None:
        if cov is not None or qua is not None:
            raise FingerpadError(f"{'--coverage' if cov is not None else '--quantile'} needs a population "
                                 "(--population NAME|FILE, or a [population] table in the study file)")
        return None
    if cov is not None and qua is not None:
        raise FingerpadError("--coverage and --quantile exclude each other: give one")
    for name, value in (("--coverage", cov), ("--quantile", qua)):
        if value is not None and not math.isfinite(value):
            raise FingerpadError(f"{name} {value!r}: must be a finite number")
    pop = population if isinstance(population, Population) else load_population(population)
    return PopulationGoal(pop, coverage=cov, quantile=qua)


class MemberTable:
    """The members of a population as fingers of one study's finger and material, predicted on
    each candidate's unit cell by the one member path of the package
    (:func:`~fingerpad.population.members.predict_fingers`, what ``predict --population`` runs).

    Parameters
    ----------
    study
        The study whose finger and material the members vary (its loads are the targets' loads).
    members
        The members' parameters (SI), from ``Population.sample()``.

    Raises
    ------
    FingerpadError
        A member the finger cannot take (``ridge_fraction`` with another ridge model).
    """

    def __init__(self, study: Any, members: Sequence[Mapping[str, float]]) -> None:
        self.fingers = [member_finger(study.finger, m) for m in members]
        self.loads = np.asarray(study.loads, float)

    def evaluate(self, pred: Any) -> dict[str, np.ndarray]:
        """Every member on the texture of ``pred`` (the nominal finger's
        :class:`~fingerpad.study.run.Prediction`; its cell is read at each member's E1*, Eq. 3.4,
        and prepared over the members' pressures, solving only what they add).

        Returns
        -------
        dict
            ``area_ratio``, ``mu``, ``mu_ref``, ``mu_rel``: ``(members, loads)`` arrays;
            ``critical_load``: per member (N; ``inf`` when the cell never reaches its transition,
            NaN when no crossing lies in the coupling's load range), each member's numbers those
            of a plain ``predict`` of it.
        """
        from ..population.members import predict_fingers

        curves, crit, _, _ = predict_fingers(pred, self.fingers, full_contact=False)

        def rows(name: str) -> np.ndarray:
            return np.array([np.asarray(getattr(c, name), float) for c in curves])

        return {"area_ratio": rows("area_ratio"), "mu": rows("mu"), "mu_ref": rows("mu_ref"),
                "mu_rel": rows("mu_normalised"), "critical_load": crit}


def _quantile(values: np.ndarray, q: float) -> float:
    """``np.quantile`` (linear, as ``predict --population`` reports) of values that may be inf."""
    v = np.asarray(values, float)
    v = v[~np.isnan(v)]
    if v.size == 0:
        return math.nan
    big = np.isinf(v) & (v > 0)
    if not big.any():
        return float(np.quantile(v, q))
    # inf ranks last: interpolating between a finite value and inf is inf
    out = float(np.quantile(np.where(big, np.finfo(float).max, v), q))
    return math.inf if out >= np.finfo(float).max / 2 else out


def _target_values(problem: DesignProblem, row: Any) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """The members' values at each target (``row(name, load)``: a per-load member quantity at the
    load, ``name`` one of mu, mu_ref, mu_rel, area_ratio) and, per perception target, its member
    verdicts (:func:`~fingerpad.design.perception_targets.member_verdicts`; the value is then P)."""
    values: dict[str, np.ndarray] = {}
    verdicts: dict[str, Any] = {}
    for t in problem.targets:
        if is_perception(t):
            v = member_verdicts(t, row("mu", t.load), row("mu_ref", t.load), problem.reference_mu.get(str(t)),
                                problem.weber, problem.tolerance)
            verdicts[str(t)] = v
            values[str(t)] = v["p_correct"]
        else:
            values[str(t)] = row(t.quantity, t.load)
    return values, verdicts


def _score(problem: DesignProblem, goal: PopulationGoal, cand: Candidate, values: Mapping[str, np.ndarray],
          critical: np.ndarray, penalty: float, verdicts: Mapping[str, Any] | None = None) -> None:
    """Score ``cand`` from its members' values at the targets (``values[str(target)]``, one per
    member; P for a perception target, whose ``verdicts`` give each member's score and whether it
    meets it) and critical loads (N), plus the texture's own ``penalty``; see the module
    docstring. Sets ``objective``, ``meets``, ``values``, ``critical_load``, ``violations`` and the
    ``population`` summary (coverage, quantiles; per perception target the fraction telling the
    textures apart and the median P)."""
    from ..perception.discrimination import summarise

    targets = problem.targets
    verdicts = verdicts or {}
    # (targets, members): a friction target's squared relative deviation, a perception target's score
    dev = {str(t): np.asarray(values[str(t)], float) / t.value - 1.0 for t in targets if str(t) not in verdicts}
    scores = np.array([verdicts[str(t)]["score"] if str(t) in verdicts else dev[str(t)] ** 2 for t in targets])
    member_ok = np.all([verdicts[str(t)]["ok"] if str(t) in verdicts else np.abs(dev[str(t)]) <= problem.tolerance
                        for t in targets], axis=0)
    limit = problem.min_critical_load
    if limit is not None:
        member_ok &= critical >= limit
    coverage = float(np.mean(member_ok))
    summary: dict[str, Any] = {
        "coverage": coverage, "members_meeting": int(member_ok.sum()), "size": int(member_ok.size),
        "quantiles": {str(t): {f"{q:g}": _quantile(values[str(t)], q) for q in goal.levels} for t in targets},
        "critical_load": {f"{q:g}": _quantile(critical, q) for q in goal.levels},
    }
    if verdicts:
        summary["perception"] = {}
        for key, v in verdicts.items():
            s = summarise(np.asarray(v["p_correct"], float)[:, None])
            summary["perception"][key] = {"fraction_telling_apart": float(s["fraction"][0]),
                                          "p_correct_median": float(s["p_correct_median"][0])}
    if goal.coverage is not None:
        # the critical load that the covered fraction of the members reaches or exceeds
        cand.critical_load = _quantile(critical, 1.0 - goal.coverage)
        # the JSON beside it names that level too, so the number can be checked from the file
        summary["critical_load"][f"{1.0 - goal.coverage:g}"] = cand.critical_load
        member_pen = np.array([critical_penalty(float(c), limit)[0] for c in critical])
        member_score = np.max(scores, axis=0) + member_pen
        kth = float(np.sort(member_score)[goal.needed - 1])
        cand.objective = kth + penalty
        for t in targets:
            cand.values[str(t)] = summary["perception"][str(t)]["fraction_telling_apart"] if str(t) in verdicts \
                else summary["quantiles"][str(t)]["0.5"]
        if coverage < goal.coverage - 1e-12:
            cand.violations.append(f"coverage {100 * coverage:.3g} % below {100 * goal.coverage:g} %")
        cand.meets = not cand.violations
    else:
        q = float(goal.quantile)  # type: ignore[arg-type]
        cand.critical_load = _quantile(critical, q)
        errors = []
        for t in targets:
            got = summary["quantiles"][str(t)][f"{q:g}"]
            cand.values[str(t)] = got
            errors.append((got / t.value - 1.0) ** 2)
        crit_pen, violation = critical_penalty(cand.critical_load, limit)
        if violation:
            cand.violations.append(f"{q:g} quantile of the {violation}")
        cand.objective = float(np.mean(errors)) + crit_pen + penalty
        cand.meets = not cand.violations and all(math.sqrt(e) <= problem.tolerance for e in errors)
    cand.population = summary


class _Screen:
    """The search's evaluation of one texture for a population: the plain design's direct
    prediction of the nominal finger (which solves or reads the one unit cell), then every
    member on that cell at once (:class:`MemberTable`)."""

    def __init__(self, goal: PopulationGoal) -> None:
        self.goal = goal
        self.members = goal.population.sample()
        self._tables: dict[str, MemberTable] = {}

    def table(self, study: Any) -> MemberTable:
        # the members depend on the study's finger and material only (a free axis may set them)
        key = repr((study.finger, study.material_modulus, study.material_poisson, tuple(study.loads)))
        if key not in self._tables:
            self._tables[key] = MemberTable(study, self.members)
        return self._tables[key]

    def __call__(self, problem: DesignProblem, params: dict[str, float]) -> Candidate:
        from ..study.run import run_study

        cand = Candidate(params=dict(params))
        try:
            study = candidate_study(problem, params, problem.loads)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                pred = run_study(study)
                got = self.table(study).evaluate(pred)
        except SetupError:
            raise  # the machine's setting, not this texture's: every candidate would fail alike
        except FingerpadError as exc:
            cand.reason = str(exc)
            return cand
        index = {float(f): i for i, f in enumerate(np.asarray(study.loads, float))}
        values, verdicts = _target_values(problem, lambda name, load: got[name][:, index[float(load)]])
        _score(problem, self.goal, cand, values, got["critical_load"], texture_limits(problem, cand, pred.texture),
               verdicts)
        return cand


def screen_candidate(problem: DesignProblem, goal: PopulationGoal) -> Any:
    """The search's cheap evaluation of a texture for ``goal`` (see the module docstring).

    Parameters
    ----------
    problem
        The design problem (targets, tolerance, limits; SI units).
    goal
        The population and its coverage or quantile.

    Returns
    -------
    callable
        ``(problem, params) -> Candidate`` for :func:`fingerpad.design.inverse.search`: the
        nominal finger's direct prediction (one unit cell), then every member on that cell at
        once; a texture that cannot exist gives a candidate with its ``reason``.
    """
    return _Screen(goal)


def population_candidate(problem: DesignProblem, goal: PopulationGoal, params: Mapping[str, float],
                         curve_loads: Sequence[float] | None = None) -> Candidate:
    """A direct population prediction of one texture, scored against the problem and the goal.

    :func:`~fingerpad.population.run.run_population` on the texture at the targets' loads
    (and ``curve_loads``, N): every member predicted by :func:`~fingerpad.coupling.predict_curve`
    on the cell at its own E1*. The candidate's ``population`` holds the coverage, the members
    meeting the targets, the quantiles of each target quantity at its load and of the members'
    critical loads (N), and with ``curve_loads`` the bands of ``mu_rel`` and ``mu`` per load;
    ``curve`` is the nominal finger's, as in the plain design.
    """
    cand = Candidate(params=dict(params))
    loads = np.unique(np.concatenate([problem.loads, np.asarray(curve_loads if curve_loads is not None else [],
                                                                  float)]))
    try:
        study = candidate_study(problem, params, loads)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = run_population(study, goal.population, quantiles=goal.levels)
    except SetupError:
        raise  # the machine's setting, not this texture's: every candidate would fail alike
    except FingerpadError as exc:
        cand.reason = str(exc)
        return cand
    from ..study.citations import prediction_references

    cand.references = prediction_references(res.nominal, res)
    f = np.asarray(study.loads, float)
    values, verdicts = _target_values(problem, lambda name, load: res.values(_CURVE_NAME[name])[
        :, int(np.argmin(np.abs(f - load)))])
    _score(problem, goal, cand, values, res.critical_load, texture_limits(problem, cand, res.nominal.texture),
           verdicts)
    if curve_loads is not None:
        keep = np.isin(f, np.asarray(curve_loads, float))
        cur = res.nominal.primary
        cand.curve = {"load": f[keep].tolist(), "mu": np.asarray(cur.mu)[keep].tolist(),
                      "mu_rel": np.asarray(cur.mu_normalised)[keep].tolist(),
                      "area_ratio": np.asarray(cur.area_ratio)[keep].tolist()}
        bands = res.quantiles()
        cand.population["bands"] = {"load": f[keep].tolist(), **{
            name: {level: np.asarray(v)[keep].tolist() for level, v in bands[src].items()}
            for name, src in (("mu_rel", "mu_normalised"), ("mu", "mu"))}}
    return cand
