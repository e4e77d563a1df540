"""A population of fingers predicted on one texture: every member from one unit cell, the
quantile bands over them, and the Sobol indices when asked for (issue 22).

The population (:class:`~.distributions.Population`) is sampled once; the nominal prediction
(the study's own finger) is run first and every member is then predicted on its cell
(:func:`~.members.predict_fingers`).

Cost: the unit cell's psi(p) depends on p/E* only (docs/solver.md, "One curve for every modulus
and every scale"), so the BEM cell is solved once, over the union of the members' pressures in
units of E*, and every member reads it at its own E1* (:meth:`BEMUnitCell.at_modulus`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..coupling import CurvePrediction
from ..errors import FingerpadError
from ..units import format_percent
from ..study.run import Prediction, run_study
from ..study.spec import Study
from .rules import DEFAULT_QUANTILES, PopulationStudy, attach
from .distributions import Population
from .members import member_quantiles, predict_fingers

__all__ = ["DEFAULT_QUANTILES", "QUANTITIES", "PopulationResult", "run_population"]
#: The per-load quantities of each member (keys of ``member_results``).
QUANTITIES: tuple[str, ...] = ("area_ratio", "mu", "mu_ref", "mu_normalised")

@dataclass
class PopulationResult:
    """The prediction of every member and its quantiles (SI units).

    Attributes
    ----------
    nominal
        The study's own prediction (the study's finger).
    population
        The population sampled.
    members
        Each member's parameters (SI), named as ``--finger-param`` names them.
    curves
        Each member's :class:`~fingerpad.coupling.CurvePrediction`.
    critical_load, full_contact_load
        Per member, N (``inf`` if never reached; full contact ``nan`` for Hertz).
    states
        Per member, the contact state at the pad centre at each load.
    quantile_levels
        The quantiles reported.
    sensitivity
        Sobol indices of mu/mu_ref and the critical load
        (:class:`~fingerpad.population.sobol.SensitivityResult`), when asked for.
    own_cells, member_solves
        Members on a BEM unit cell of their own (a layered skin whose proportions vary) and the
        unit-cell solves the members added to the nominal's (0: the cache held them).
    adhesion
        With adhesive members: their :class:`~.adhesion.AdhesiveMembers` (the family of adhesive
        cells, each member's pull-off force and estimated interpolation error); ``None`` without.
    """

    nominal: Prediction
    population: Population
    members: list[dict[str, float]]
    curves: list[CurvePrediction]
    critical_load: np.ndarray
    full_contact_load: np.ndarray
    states: list[list[str]]
    quantile_levels: tuple[float, ...]
    notes: list[str] = field(default_factory=list)
    sensitivity: Any = None
    own_cells: int = 0
    member_solves: int = 0
    adhesion: Any = None

    def references(self) -> tuple[str, ...]:
        """The publications of the population's own methods (:mod:`fingerpad.references` keys):
        its correlated sampling and its Sobol indices, when used (the members vary the nominal
        finger's parameters, not its models, so the nominal prediction names those)."""
        from . import correlations

        keys: list[str] = list(correlations.REFERENCES) if self.population.correlations else []
        if self.sensitivity is not None:
            keys.extend(self.sensitivity.REFERENCES)
        return tuple(keys)

    def values(self, quantity: str) -> np.ndarray:
        """``(members, loads)`` array of a per-load quantity."""
        return np.array([np.asarray(getattr(c, quantity), float) for c in self.curves])

    def quantiles(self) -> dict[str, dict[str, Any]]:
        """``{quantity: {"0.5": values per load}}``; the loads' ``critical_load`` and
        ``full_contact_load`` give one value each."""
        q = np.asarray(self.quantile_levels)
        out: dict[str, dict[str, Any]] = {}
        for name in QUANTITIES:
            table = np.quantile(self.values(name), q, axis=0)
            out[name] = {f"{level:g}": table[i] for i, level in enumerate(q)}
        for name, arr in (("critical_load", self.critical_load), ("full_contact_load", self.full_contact_load)):
            finite = arr[~np.isnan(arr)]
            # a member that never reaches the transition has inf: numpy's quantile gives NaN
            # between two infinities, member_quantiles keeps inf
            table = member_quantiles(finite, q) if finite.size else np.full(q.size, math.nan)
            out[name] = {f"{level:g}": float(table[i]) for i, level in enumerate(q)}
        return out

    def monte_carlo_error(self) -> dict[str, np.ndarray]:
        """Standard error of the mean per load, sd / sqrt(n) (the plain Monte Carlo bound; the
        quasi-random sample converges at least as fast)."""
        n = len(self.curves)
        return {name: np.std(self.values(name), axis=0, ddof=1) / math.sqrt(n) if n > 1 else
                np.zeros(len(self.nominal.study.loads)) for name in QUANTITIES}

    def quantile_error(self, confidence: float = 0.95) -> dict[str, dict[str, Any]]:
        """Monte Carlo error of each reported quantile: the half-width of its distribution-free
        confidence interval ``[X_(l), X_(u)]`` between order statistics of the members,
        ``l, u = nq -+ z sqrt(n q (1 - q))`` (normal approximation of the binomial count below
        the quantile; 1-based, rounded outward, clipped to 1..n). Exact in coverage for
        independent members; the quasi-random sample converges at least as fast, so it is an
        upper estimate. Keyed as :meth:`quantiles`; the same units. A critical or full-contact
        load quantile that is infinite at both ends of its interval (most members never reach
        it) has the error 0; one whose interval reaches infinity has the error inf."""
        from scipy.stats import norm

        z = float(norm.ppf(0.5 + confidence / 2))

        def half_width(sorted_values: np.ndarray, q: float) -> Any:
            n = sorted_values.shape[0]
            if n == 0:
                return math.nan
            spread = z * math.sqrt(n * q * (1 - q))
            lo = min(max(math.floor(n * q - spread), 1), n) - 1
            hi = min(max(math.ceil(n * q + spread), 1), n) - 1
            lower, upper = sorted_values[lo], sorted_values[hi]
            # Both ends infinite (members that never reach the transition): the quantile is inf
            # for certain, an error of 0, not inf - inf = NaN. One end infinite: the interval is
            # unbounded, an error of inf.
            with np.errstate(invalid="ignore"):
                return np.where(upper == lower, 0.0, 0.5 * (upper - lower))

        out: dict[str, dict[str, Any]] = {}
        tables = {name: np.sort(self.values(name), axis=0) for name in QUANTITIES}
        for name, arr in (("critical_load", self.critical_load), ("full_contact_load", self.full_contact_load)):
            tables[name] = np.sort(arr[~np.isnan(arr)])  # the members quantiles() takes
        for name, table in tables.items():
            out[name] = {f"{level:g}": (float(half_width(table, level)) if table.ndim == 1 else half_width(table, level))
                         for level in self.quantile_levels}
        return out

    def state_probability(self) -> dict[str, np.ndarray]:
        """Per state, the fraction of members whose pad centre is in it, at each load."""
        states = np.array(self.states)
        return {s: np.mean(states == s, axis=0) for s in ("asperity", "transition", "full")}

    def add_to_dataset(self, ds: Any) -> Any:
        """``ds`` (the nominal ``predict.nc`` dataset) with the members along a ``member``
        dimension: each member's curves (``member_mu``, ...), parameters (``member_radius``, SI)
        and critical and full-contact loads; the quantile bands along ``quantile``."""
        import xarray as xr

        units = {"area_ratio": "1", "mu": "1", "mu_ref": "1", "mu_normalised": "1"}
        data: dict[str, Any] = {}
        for name in QUANTITIES:
            data[f"member_{name}"] = xr.Variable(("member", "load"), self.values(name), {"units": units[name]})
            table = np.quantile(self.values(name), np.asarray(self.quantile_levels), axis=0)
            data[f"band_{name}"] = xr.Variable(("quantile", "load"), table, {"units": units[name]})
        for name in self.population.distributions:
            par = self.population.distributions[name].param
            data[f"member_{name}"] = xr.Variable(("member",), [m[name] for m in self.members],
                                                 {"units": par.unit or "1", "long_name": par.doc})
        data["member_critical_load"] = xr.Variable(("member",), self.critical_load, {"units": "N"})
        data["member_full_contact_load"] = xr.Variable(("member",), self.full_contact_load, {"units": "N"})
        if self.adhesion is not None:
            data["member_pull_off_force"] = xr.Variable(("member",), self.adhesion.pull_off_force, {"units": "N"})
            data["member_pull_off_force_error"] = xr.Variable(
                ("member",), self.adhesion.pull_off_error,
                {"units": "1", "long_name": "estimated relative interpolation error of the pull-off force"})
            data["member_interpolation_error"] = xr.Variable(
                ("member",), self.adhesion.interpolation_error,
                {"units": "1", "long_name": "estimated relative interpolation error of A_re and mu (adhesive family)"})
        out = ds.assign(data).assign_coords(member=np.arange(len(self.members)),
                                            quantile=np.asarray(self.quantile_levels))
        out.attrs.update({"population_name": self.population.name, "population_size": self.population.size,
                          "population_seed": self.population.seed, "population_method": self.population.method})
        return out

    def _member_adhesion(self, i: int) -> dict[str, float]:
        """Member ``i``'s pull-off force (N) and estimated interpolation error; ``{}`` without adhesion."""
        if self.adhesion is None:
            return {}
        return {"pull_off_force": float(self.adhesion.pull_off_force[i]),
                "pull_off_force_error": float(self.adhesion.pull_off_error[i]),
                "interpolation_error": float(self.adhesion.interpolation_error[i])}

    def _adhesion_dict(self) -> dict[str, Any]:
        """The ``adhesion`` entry: the family, its error over the members, the pull-off force's quantiles."""
        q = np.asarray(self.quantile_levels)
        table = member_quantiles(self.adhesion.pull_off_force, q)
        return {**self.adhesion.describe(),
                "pull_off_force": {f"{level:g}": float(table[i]) for i, level in enumerate(q)}}

    def as_dict(self) -> dict[str, Any]:
        """The ``population`` entry of ``predict.json`` (SI units)."""
        return {
            "name": self.population.name,
            "size": self.population.size,
            "seed": self.population.seed,
            "method": self.population.method,
            "distributions": {k: {"distribution": d.kind, **d.args} for k, d in self.population.distributions.items()},
            "correlations": [list(c) for c in self.population.correlations],
            "labels": list(self.population.labels),
            "model": self.nominal.primary_model,
            "loads": self.nominal.study.loads,
            "quantiles": self.quantiles(),
            "monte_carlo_error": self.monte_carlo_error(),
            "quantile_error": self.quantile_error(),
            "state_probability": self.state_probability(),
            "members": self.members,
            "member_results": [
                {**{q: getattr(c, q) for q in QUANTITIES}, "critical_load": float(fc), "full_contact_load": float(ff),
                 "contact_state": st, **self._member_adhesion(i)}
                for i, (c, fc, ff, st) in enumerate(zip(self.curves, self.critical_load, self.full_contact_load,
                                                        self.states, strict=True))
            ],
            "notes": self.notes,
            **({"adhesion": self._adhesion_dict()} if self.adhesion is not None else {}),
            **({"sensitivity": self.sensitivity.as_dict()} if self.sensitivity is not None else {}),
        }


def run_population(study: Study | PopulationStudy, population: Population | Mapping[str, Any] | str | None = None,
                   quantiles: str | Sequence[float] | None = None, sensitivity: bool | int | str | None = None, *,
                   progress: Callable[[int, int], None] | None = None,
                   member_progress: Callable[[int, int], None] | None = None) -> PopulationResult:
    """Predict every member of ``population`` on the study's texture (see the module docstring).

    ``study`` and ``population`` are first joined by :func:`~.rules.attach` (every rule of a
    population on a study, with the message the command line gives), unless ``study`` is already
    a :class:`~.rules.PopulationStudy`. The nominal prediction (the study's finger) is run first;
    the BEM cell is then prepared over the union of the members' pressures in units of E* (no
    solve when that lies inside what is cached) and every member's curve is that of
    :func:`~fingerpad.coupling.predict_curve` on the cell at the member's E1*, the members coupled
    together in small blocks (:func:`~fingerpad.coupling.members.predict_members`). With the Hertz
    model each member gets its own per-asperity cell (no solve). ``quantiles``: the levels of the
    bands (default :data:`~.rules.DEFAULT_QUANTILES`); ``sensitivity``: the base samples N of the
    Sobol indices (:func:`~fingerpad.population.sobol.population_sensitivity`, N (d + 2) more
    fingers; ``True``: the default N), or ``None`` for none. ``progress(done, total)``: the
    nominal unit cell's solves; ``member_progress(done, total)``: the cells of members that need
    one of their own (a layered skin whose proportions vary).

    Raises
    ------
    FingerpadError
        What :func:`~.rules.attach` refuses (a sliding direction, a value the user fixed that
        the population draws, bad quantiles, a member outside its parameter's bounds, ...).
    """
    if isinstance(study, PopulationStudy):
        if population is not None or quantiles is not None or sensitivity is not None:
            raise FingerpadError("run_population: give the population, quantiles and sensitivity to attach(), "
                                 "not again here")
        plan = study
    else:
        plan = attach(study, population, quantiles=quantiles, sensitivity=sensitivity)
        if plan is None:
            raise FingerpadError("run_population: no population given")
    nominal = run_study(plan.study, progress=progress)
    stats: dict[str, Any] = {}
    curves, crit, full, states = predict_fingers(nominal, plan.fingers, progress=member_progress, stats=stats)
    notes = list(plan.notes)
    adhesion = stats.get("adhesion")
    if adhesion is not None:
        worst = float(np.max(adhesion.interpolation_error))
        if worst > plan.study.accuracy:
            notes.append(f"population: adhesion: the estimated interpolation error of A_re reaches "
                         f"{format_percent(worst)} % (median {format_percent(float(np.median(adhesion.interpolation_error)))} %) "
                         f"over the family's {len(adhesion.family.nodes)} cells, above the accuracy "
                         f"{100 * plan.study.accuracy:g} %")
    sens = None
    if plan.sensitivity is not None:
        from .sobol import population_sensitivity

        sens = population_sensitivity(nominal, plan.population, plan.sensitivity)
    return PopulationResult(nominal, plan.population, [dict(m) for m in plan.members], curves, crit, full, states,
                            plan.quantiles, notes, sens, own_cells=stats.get("own_cells", 0),
                            member_solves=stats.get("solves", 0), adhesion=adhesion)
