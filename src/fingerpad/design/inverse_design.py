"""Inverse design as one call: a study, free parameters and targets in; ranked candidates, each a
direct prediction, and the result document out (``fingerpad design``, the Python API and the
explorer all get the same thing).

The search itself (the objective, the optimiser, the ranking of a sweep) is in
:mod:`fingerpad.design.inverse`; this module decides the inputs (each numeric option checked in
one place, here), takes the candidates from a sweep or from the optimiser, merges those that
are one design, and predicts the reported ones once more over the exploration loads (their curves).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import FingerpadError
from ..population.distributions import Population
from .axes import Axis
from .inverse import XATOL, Candidate, DesignProblem, Target, parse_target, predict_candidate, rank_sweep, search
from .perception_targets import PerceptionTarget, is_perception
from .robust import PopulationGoal, population_candidate, population_goal, screen_candidate

__all__ = ["DesignResult", "design_textures", "free_axes", "merge_close"]

#: Largest number of direct predictions an optimisation may be asked for (each is a BEM
#: prediction of seconds to minutes; beyond this a sweep is the tool).
MAX_EVALUATIONS = 10_000


@dataclass
class DesignResult:
    """The candidates of an inverse design, best first, and what was asked.

    Attributes
    ----------
    problem
        The problem solved (SI units).
    candidates
        The reported candidates, best first, each predicted directly over the exploration loads
        (``curve``); near-identical ones merged (:func:`merge_close`).
    source
        Where the candidates came from (``"sweep PATH"`` or the optimisation).
    goal
        For a design for a population: the population and its coverage or quantile
        (:class:`~fingerpad.design.robust.PopulationGoal`); every candidate then carries the
        numbers of its direct population prediction (``Candidate.population``).
    """

    problem: DesignProblem
    candidates: list[Candidate] = field(default_factory=list)
    source: str = ""
    goal: PopulationGoal | None = None

    @property
    def met(self) -> bool:
        """Whether a candidate meets every target within the tolerance and every limit."""
        return any(c.meets for c in self.candidates)

    def document(self) -> dict[str, Any]:
        """The result as plain data (JSON-ready; SI units, stated under ``units``)."""
        from ..encode import to_jsonable
        from ..references import keys_of, metadata

        p = self.problem
        doc = {
            "targets": [str(t) for t in p.targets], "axes": {a.name: list(a.values) for a in p.axes},
            "min_critical_load": p.min_critical_load, "min_feature": p.min_feature,
            "max_aspect": p.max_aspect, "tolerance": p.tolerance, "source": self.source,
            "met": self.met, "candidates": [c.as_dict() for c in self.candidates],
            "units": {"params": "SI (m, Pa, rad)", "critical_load": "N", "feature": "m", "curve.load": "N"},
            # the publications of the methods the reported candidates' predictions used
            "references": metadata(keys_of(*(c.references for c in self.candidates))),
        }
        if self.goal is not None:
            doc["population"] = self.goal.as_dict()
            doc["units"].update({"population.coverage": "fraction of the members (0-1)",
                                 "population.critical_load": "N", "population.bands.load": "N"})
        return to_jsonable(doc)

    def shortfall(self) -> str | None:
        """One sentence when no candidate meets the targets (and how close the best gets), else None."""
        best = self.candidates[0] if self.candidates else None
        if best is not None and best.meets:
            return None
        if self.goal is not None:
            return None if self.met else _population_shortfall(self.problem, self.goal, self.candidates)
        what = ", ".join(f"{k} = {'P ' if k in self.problem.reference_mu else ''}{v:.3g}"
                         for k, v in best.values.items()) if best else "nothing valid"
        if best is not None and best.violations:
            what += f" ({'; '.join(best.violations)})"
        return (f"no texture in the box meets the target within {100 * self.problem.tolerance:g} %; "
                f"the closest: {what}")


def _population_shortfall(problem: DesignProblem, goal: PopulationGoal, candidates: Sequence[Candidate]) -> str:
    """How close a design for a population gets: the best coverage reached and its quantiles."""
    tol = f"{100 * problem.tolerance:g} %"
    valid = [c for c in candidates if c.population]
    if not valid:
        reason = candidates[0].reason if candidates and candidates[0].reason else "nothing valid"
        return f"no texture in the box meets the target for {goal.describe()}: {reason}"
    if goal.coverage is not None:
        best = max(valid, key=lambda c: (c.population["coverage"], -c.objective))
        head = (f"no texture in the box meets the target within {tol} for {goal.describe()}; the best coverage "
                f"reached is {100 * best.population['coverage']:.3g} %")
    else:
        best = valid[0]
        head = f"no texture in the box meets the target within {tol} at {goal.describe()}; the closest"
    q = goal.quantile if goal.quantile is not None else 0.5
    parts = []
    for t, table in best.population["quantiles"].items():
        parts.append(f"{t}: {q:g} quantile {table[f'{q:g}']:.3g}, 5-95 % {table['0.05']:.3g}-{table['0.95']:.3g}")
    params = ", ".join(f"{a.label()} {a.display(best.params[a.name]):.4g}" for a in problem.axes)
    extra = [v for v in best.violations if not v.startswith("coverage")]
    return f"{head} ({params}; {'; '.join(parts)}{'; ' + '; '.join(extra) if extra else ''})"


def free_axes(vary: Mapping[str, Any] | Sequence[str], family: str | None) -> list[Axis]:
    """The free parameters: ``{"spacing": ("100um", "400um")}`` or ``["spacing=100um:400um"]``.

    Bounds take units (numbers are SI); the axis is log-uniform unless its low bound is 0.

    Raises
    ------
    FingerpadError
        A parameter the family does not have, a non-numeric one, bounds not LOW < HIGH.
    """
    from .axes import resolve_axis

    items: list[tuple[str, Any]] = []
    if isinstance(vary, Mapping):
        items = list(vary.items())
    else:
        for item in vary:
            if "=" not in str(item):
                raise FingerpadError(f"--vary: expected NAME=LOW:HIGH, got {item!r}")
            name, bounds = (t.strip() for t in str(item).split("=", 1))
            items.append((name, bounds))
    axes = []
    for name, bounds in items:
        axis = resolve_axis(name, family, "--vary")
        if not axis.numeric:
            raise FingerpadError(f"--vary {name}: only numeric parameters can be optimised")
        parts = bounds.split(":") if isinstance(bounds, str) else list(bounds)
        if len(parts) != 2:
            raise FingerpadError(f"--vary {name}={bounds}: expected LOW:HIGH bounds")
        lo, hi = (axis.parse(p, f"--vary {name}") for p in parts)
        if not hi > lo:
            raise FingerpadError(f"--vary {name}={bounds}: the bounds must satisfy LOW < HIGH")
        if lo < 0 and axis.kind == "length":
            raise FingerpadError(f"--vary {name}={bounds}: a length cannot be negative")
        axes.append(Axis(**{**axis.__dict__, "values": (lo, hi), "log": lo > 0}))
    if not axes:
        raise FingerpadError("give at least one --vary NAME=LOW:HIGH")
    if len({a.name for a in axes}) != len(axes):
        raise FingerpadError("--vary: a parameter is given twice")
    return axes


def merge_close(problem: DesignProblem, candidates: Sequence[Candidate], distance: float = XATOL) -> list[Candidate]:
    """Candidates with one from each group closer than ``distance`` (in the unit box of the free
    parameters, log-scaled for log axes, largest coordinate difference): the best of each group.

    ``distance`` defaults to the optimiser's own parameter tolerance: points closer than that are
    one design to the optimiser (200.7 and 201.8 um in a 100-400 um box are 0.4 % of it apart).
    """
    kept: list[tuple[np.ndarray, Candidate]] = []
    for cand in sorted(candidates, key=lambda c: c.objective):
        u = problem.unit(cand.params)
        if all(np.max(np.abs(u - v)) >= distance for v, _ in kept):
            kept.append((u, cand))
    return [c for _, c in kept]


def _number(value: Any, dimension: str, name: str) -> float | None:
    from ..units import parse_positive

    return None if value is None else parse_positive(value, dimension, name=name)


def design_textures(
    study: str | os.PathLike[str] | Mapping[str, Any],
    vary: Mapping[str, Any] | Sequence[str],
    targets: Sequence[str | Target],
    *,
    min_critical_load: str | float | None = None,
    min_feature: str | float | None = None,
    max_aspect: str | float | None = None,
    tolerance: str | float = 0.05,
    from_sweep: str | os.PathLike[str] | None = None,
    candidates: int | str = 5,
    evaluations: int | str = 60,
    progress: Callable[[int, int], None] | None = None,
    population: str | Mapping[str, Any] | Population | None = None,
    coverage: str | float | None = None,
    quantile: str | float | None = None,
    weber: str | float | None = None,
) -> DesignResult:
    """Find textures of the study's family, within bounds, that give a wanted friction.

    Parameters
    ----------
    study
        A study file, or its sections (texture family and fixed parameters, material, finger;
        a ``[sweep]`` table is ignored).
    vary
        The free parameters and their bounds (:func:`free_axes`).
    targets
        ``QUANTITY=VALUE@LOAD`` texts or :class:`~fingerpad.design.inverse.Target`.
    min_critical_load
        Stay in asperity contact up to this load (N, or text with a unit).
    min_feature, max_aspect
        Manufacturing limits: smallest lateral feature (m), largest height / feature.
    tolerance
        Relative deviation within which a target is met, in (0, 1].
    from_sweep
        Take the candidates from this sweep store (then predict each directly) instead of
        optimising.
    candidates
        Candidates to report (at least 1).
    evaluations
        Direct predictions the optimisation may make (1 to :data:`MAX_EVALUATIONS`).
    progress
        Called with ``(done, total)`` after each direct prediction of the search.
    population
        Design for a population of fingers (a preset name such as ``"adults"``, a TOML file
        with a ``[population]`` table, the table itself, or a
        :class:`~fingerpad.population.distributions.Population`); needs ``coverage`` or ``quantile``
        (:mod:`fingerpad.design.robust`). Without it, ``coverage`` or ``quantile`` use the
        study's own ``[population]`` table; the table is ignored when neither is given.
    coverage
        With ``population``: least fraction of the members, in (0, 1], that must meet every
        target within ``tolerance`` (and have a critical load of at least
        ``min_critical_load``).
    quantile
        With ``population``: the quantile, in [0, 1], of the members' values that must meet the
        targets (0.5: the median finger); excludes ``coverage``.
    weber
        The Weber fraction W of every finger for perception targets (``feels-like=REF@LOAD``,
        ``feels-different-from=REF@LOAD``; default 0.11, :mod:`fingerpad.perception`).

    Returns
    -------
    DesignResult
        Every number of a candidate from a direct prediction of that texture (with a
        population: from :func:`~fingerpad.population.run.run_population` on it).

    Raises
    ------
    FingerpadError
        An input that makes no sense (each checked before any prediction), a sweep without the
        free parameters.
    SetupError
        The device or FFT engine of ``FINGERPAD_DEVICE``/``FINGERPAD_FFT`` is absent
        (:func:`~fingerpad.contact.greens.check_setup`).
    """
    from ..contact.greens import check_setup
    from ..study.spec import read_study_file, study_from_dict
    from ..units import parse_int, parse_quantity, parse_range
    from .spec import DEFAULT_SWEEP_LOADS

    # an absent device or FFT engine stops the design here, not as NaN in every candidate
    check_setup()

    if isinstance(study, Mapping):
        data = {k: dict(v) for k, v in study.items() if k != "sweep"}
    else:
        data = read_study_file(study, extra_sections=("sweep", "population"))
        data.pop("sweep", None)
    table = data.pop("population", None)
    if weber is not None:  # the person's W, for every candidate's study: a value the user fixed
        from ..perception.compare import parse_weber

        data["perception"] = {**data.get("perception", {}), "weber_fraction": parse_weber(weber)}
    base = study_from_dict(data, {("perception", "weber_fraction"): "--weber-fraction"} if weber is not None else None)
    axes = free_axes(vary, data.get("texture", {}).get("name"))
    members = None
    if population is not None or (table is not None and (coverage is not None or quantile is not None)):
        # the population, else the study file's own [population] table (as predict uses it),
        # checked against the study and the free parameters by the one set of rules
        from ..population.rules import attach

        plan = attach(base, population, table=table if population is None else None,
                      fixed={a.key: f"--vary {a.name}" for a in axes if a.section == "finger"})
        population = None if plan is None else plan.population
        members = None if plan is None else plan.members
    goal = population_goal(population, coverage, quantile)
    parsed = [t if isinstance(t, (Target, PerceptionTarget)) else parse_target(t) for t in targets]
    if not parsed:
        raise FingerpadError("give at least one --target QUANTITY=VALUE@LOAD")
    from .perception_targets import check_goal, reference_friction

    check_goal(parsed, goal, from_sweep)
    n_cand = parse_int(candidates, "--candidates", 1, MAX_EVALUATIONS)
    n_eval = parse_int(evaluations, "--evaluations", 1, MAX_EVALUATIONS)
    problem = DesignProblem(
        base=data, axes=axes, targets=parsed,
        min_critical_load=_number(min_critical_load, "force", "--min-critical-load"),
        min_feature=_number(min_feature, "length", "--min-feature"),
        max_aspect=_number(max_aspect, "none", "--max-aspect"),
        tolerance=parse_quantity(tolerance, "none", name="--tolerance"),
    )
    if weber is not None and not any(is_perception(t) for t in parsed):
        raise FingerpadError("--weber-fraction needs a perception target (feels-like=REF@LOAD or "
                             "feels-different-from=REF@LOAD)")
    if any(is_perception(t) for t in parsed):
        from ..perception.compare import member_weber

        # every finger's W: a member's own where the population draws it, else the study's person's
        problem.weber = member_weber(base, None if goal is None else members)
        # REF predicted once, directly, on the same fingers; every candidate is compared with it
        problem.reference_mu = reference_friction(parsed, data, None if goal is None else goal.population,
                                                problem.weber)
    curve_loads = parse_range(DEFAULT_SWEEP_LOADS, "force", log=True)
    screen = None if goal is None else screen_candidate(problem, goal)
    if from_sweep is not None:
        found = _from_sweep(problem, from_sweep, n_cand, progress, screen)
        source = f"sweep {from_sweep}"
    else:
        found = search(problem, max_evaluations=n_eval, progress=progress, evaluate=screen)
        source = "optimisation (BEM in the loop)"
    best = merge_close(problem, found)[:n_cand]
    # the reported candidates, predicted once more over the exploration loads (their curves);
    # for a population by a direct population prediction of each
    if goal is None:
        best = [predict_candidate(problem, c.params, curve_loads=curve_loads) for c in best]
        best.sort(key=lambda c: c.objective)
    else:
        best = [population_candidate(problem, goal, c.params, curve_loads=curve_loads) for c in best]
        best.sort(key=_population_rank(goal))
    return DesignResult(problem=problem, candidates=best, source=source, goal=goal)


def _population_rank(goal: PopulationGoal) -> Callable[[Candidate], Any]:
    """Best first: those that meet the goal, then for a coverage the highest coverage (then the
    objective), for a quantile the objective; candidates without a prediction last."""
    def key(c: Candidate) -> Any:
        obj = c.objective if math.isfinite(c.objective) else math.inf
        if goal.coverage is not None:
            return (not c.meets, -c.population.get("coverage", -1.0), obj)
        return (not c.meets, obj)

    return key


def _from_sweep(problem: DesignProblem, path: str | os.PathLike[str], n_cand: int,
                progress: Callable[[int, int], None] | None,
                screen: Callable[[DesignProblem, dict[str, float]], Candidate] | None = None) -> list[Candidate]:
    """The best points of a sweep for the targets, each predicted directly, best first."""
    from .store import open_sweep

    ds = open_sweep(path).load()
    missing = [a.name for a in problem.axes if a.name not in ds.variables]
    if missing:
        raise FingerpadError(f"--from-sweep: the sweep has no axis {', '.join(missing)}")
    # three times the candidates asked for: some fall outside the bounds, some merge
    ranked = rank_sweep(ds, problem.targets, problem.min_critical_load)[: 3 * n_cand]
    found = []
    for i, row in enumerate(ranked):
        params = {a.name: row["params"][a.name] for a in problem.axes}
        if all(a.values[0] <= params[a.name] <= a.values[1] for a in problem.axes):
            found.append(predict_candidate(problem, params) if screen is None else screen(problem, params))
        if progress is not None:
            progress(i + 1, len(ranked))
    return sorted(found, key=lambda c: c.objective if math.isfinite(c.objective) else math.inf)
