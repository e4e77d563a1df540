"""A population of fingers: distributions of the finger's parameters, sampled quasi-randomly, and
the prediction of every member from one unit cell (issue 22).

A ``[population]`` table (a study file's, a file of one's own, or a preset of
:mod:`.population_presets`) reads::

    [population]
    size = 200                      # members
    seed = 1                        # scrambling of the quasi-random sequence
    method = "sobol"                # or "lhs" (scipy.stats.qmc)
    skin_modulus = { distribution = "uniform", low = "0.2MPa", high = "0.5MPa" }
    radius = { distribution = "normal", mean = "9mm", sd = "1mm" }
    modulus = { distribution = "lognormal", median = "40kPa", sigma = 0.5 }
    tau0 = { distribution = "truncnormal", mean = "8kPa", sd = "3kPa", low = "1kPa" }
    alpha = { values = [0.05, 0.1, 0.12] }   # measured values, drawn with equal weight
    ridge_fraction = { distribution = "uniform", low = 0.1, high = 0.7 }
    correlations = [["radius", "modulus", 0.3]]   # Spearman rank correlations (Gaussian copula)

The names are the ``--finger-param`` names (:data:`fingerpad.finger.FINGER_PARAMS`) and
``ridge_fraction`` (the constant-fraction ridge model's A_fr/A_g). Every value is read and
checked through the parameter's declaration (:class:`fingerpad.params.Param`); lengths and
pressures need a unit. Parameters not listed keep the study's finger's value. Correlations:
:mod:`.population_correlations`. A folder written by ``fingerpad analyse`` is a population too,
one member per participant (:mod:`.population_measured`).

Cost: the unit cell's psi(p) depends on p/E* only (docs/solver.md, "One curve for every modulus
and every scale"), so the BEM cell is solved once, over the union of the members' pressures in
units of E*, and every member reads it at its own E1* (:meth:`BEMUnitCell.at_modulus`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..coupling import CurvePrediction
from ..errors import FingerpadError
from ..finger import FINGER_PARAMS, LAYER_FIELDS, RIDGE_FRACTION, Finger
from ..meso import ConstantFractionRidges
from ..params import Param, _is_bare_number
from .population_correlations import Correlation, correlate, parse_correlations
from .members import member_quantiles, predict_fingers
from .population_presets import POPULATION_PRESETS
from .run import Prediction, run_study
from .spec import Study

__all__ = [
    "DEFAULT_QUANTILES",
    "QUANTITIES",
    "Distribution",
    "Population",
    "PopulationResult",
    "load_population",
    "population_from_table",
    "run_population",
]

#: Quantiles reported by default.
DEFAULT_QUANTILES: tuple[float, ...] = (0.05, 0.25, 0.5, 0.75, 0.95)
#: The per-load quantities of each member (keys of ``member_results``).
QUANTITIES: tuple[str, ...] = ("area_ratio", "mu", "mu_ref", "mu_normalised")
#: The distributions a parameter may follow, and their keys.
DISTRIBUTIONS: dict[str, tuple[str, ...]] = {
    "uniform": ("low", "high"),
    "normal": ("mean", "sd"),
    "lognormal": ("median", "sigma"),
    "truncnormal": ("mean", "sd", "low", "high"),
    "values": ("values",),
}
#: The parameters a population may vary: the finger's numeric fields and the ridge fraction (all
#: of them ``--finger-param`` names; not a choice such as the skin's structure: a population's
#: members share it).
POPULATION_PARAMS: dict[str, Param] = {p.name: p for p in (*FINGER_PARAMS, RIDGE_FRACTION) if p.kind != "choice"}


@dataclass(frozen=True)
class Distribution:
    """One parameter's distribution, in SI.

    ``kind`` is a key of :data:`DISTRIBUTIONS`; ``args`` its values (SI; for ``lognormal``,
    ``median`` in SI and ``sigma`` the standard deviation of the logarithm; for ``truncnormal``
    ``low``/``high`` default to the parameter's bounds; for ``values`` a tuple of values).
    """

    param: Param
    kind: str
    args: Mapping[str, Any]

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """Values (SI) at unit-interval points ``u`` (inverse CDF), so that quasi-random points map
        to a quasi-random sample."""
        from scipy import stats

        a = self.args
        u = np.clip(np.asarray(u, float), 1e-12, 1 - 1e-12)
        if self.kind == "uniform":
            return a["low"] + u * (a["high"] - a["low"])
        if self.kind == "values":
            vals = np.asarray(a["values"], float)
            return vals[np.minimum((u * vals.size).astype(int), vals.size - 1)]
        if self.kind == "lognormal":
            return a["median"] * np.exp(a["sigma"] * stats.norm.ppf(u)) if a["sigma"] > 0 else \
                np.full(u.shape, float(a["median"]))
        if a["sd"] == 0:
            return np.full(u.shape, float(a["mean"]))
        if self.kind == "normal":
            return stats.norm.ppf(u, loc=a["mean"], scale=a["sd"])
        lo = (a["low"] - a["mean"]) / a["sd"]
        hi = (a["high"] - a["mean"]) / a["sd"]
        return stats.truncnorm.ppf(u, lo, hi, loc=a["mean"], scale=a["sd"])

    @property
    def spread(self) -> bool:
        a = self.args
        return {"uniform": lambda: a["high"] > a["low"], "normal": lambda: a["sd"] > 0,
                "truncnormal": lambda: a["sd"] > 0, "lognormal": lambda: a["sigma"] > 0,
                "values": lambda: len(set(a["values"])) > 1}[self.kind]()


@dataclass(frozen=True)
class Population:
    """Distributions of the finger's parameters, a sample size, a seed and a sampling method.

    ``correlations``: (name, name, Spearman rank correlation) pairs, laid on the points by a
    Gaussian copula (:mod:`.population_correlations`). ``measured``: fixed members (SI), e.g. the
    participants of an ``analyse`` folder (:mod:`.population_measured`), returned by
    :meth:`sample` as they are (``distributions`` then only records their values), labelled by
    ``labels``; ``notes`` are passed on to the result.
    """

    distributions: dict[str, Distribution]
    size: int = 200
    seed: int = 0
    method: str = "sobol"
    name: str = "custom"
    correlations: tuple[Correlation, ...] = ()
    measured: tuple[Mapping[str, float], ...] = ()
    labels: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()

    def sample(self) -> list[dict[str, float]]:
        """The members' parameters (SI), by scrambled Sobol or Latin hypercube points (seeded,
        so the same table gives the same members), or the measured members as they are."""
        from scipy.stats import qmc

        if self.measured:
            return [dict(m) for m in self.measured]
        names = list(self.distributions)
        if not names:
            return [{} for _ in range(self.size)]
        if self.method == "sobol":
            engine: Any = qmc.Sobol(len(names), scramble=True, seed=self.seed)
        else:
            engine = qmc.LatinHypercube(len(names), scramble=True, seed=self.seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # Sobol's note on sizes that are not powers of two
            u = engine.random(self.size)
        u = correlate(u, self.correlations, names)
        columns = {n: self.distributions[n].ppf(u[:, j]) for j, n in enumerate(names)}
        members = []
        for i in range(self.size):
            row = {}
            for n in names:
                value = float(columns[n][i])
                par = self.distributions[n].param
                where = f"population {n} (member {i}, {self.distributions[n].kind})"
                row[n] = par.check(value, where + ": use a truncnormal distribution to stay inside the bounds; value")
            members.append(row)
        return members


def _number(par: Param, value: Any, where: str) -> float:
    """A distribution's value read through the parameter's declaration (units required for
    lengths and pressures), without the bounds (a spread or a mean may sit anywhere)."""
    if par.dimensional and _is_bare_number(value) and float(str(value).strip()) != 0:
        raise FingerpadError(f"{where}: {value!r} has no unit; a {par.kind} needs one, e.g. "
                             f"\"{str(value).strip()}{par.unit}\"")
    # no bounds (a spread may sit anywhere) and, for a spread, no plausibility range either
    spread = where.endswith((" sd", " sigma"))
    bare = dataclasses.replace(par, low=None, high=None, plausible=None if spread else par.plausible)
    return float(bare.parse(value, where))


def population_from_table(table: Mapping[str, Any], where: str = "[population]", name: str = "custom") -> Population:
    """A :class:`Population` from a ``[population]`` table (see the module docstring).

    Raises
    ------
    FingerpadError
        Unknown parameter or distribution, a missing or unknown key, a length without a unit,
        a negative spread, a bad size, seed or method; naming the key.
    """
    if not isinstance(table, Mapping):
        raise FingerpadError(f"{where}: expected a table")
    body = dict(table)
    size, seed, method = body.pop("size", 200), body.pop("seed", 0), body.pop("method", "sobol")
    correlations = body.pop("correlations", [])
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        raise FingerpadError(f"{where} size: expected a positive integer, got {size!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise FingerpadError(f"{where} seed: expected a non-negative integer, got {seed!r}")
    if method not in ("sobol", "lhs"):
        raise FingerpadError(f"{where} method: expected \"sobol\" or \"lhs\", got {method!r}")
    dists: dict[str, Distribution] = {}
    for key, spec in body.items():
        if key not in POPULATION_PARAMS:
            raise FingerpadError(f"{where}: unknown parameter {key!r} (known: {', '.join(POPULATION_PARAMS)}, "
                                 "size, seed, method)")
        par = POPULATION_PARAMS[key]
        w = f"{where} {key}"
        if not isinstance(spec, Mapping):
            raise FingerpadError(f"{w}: expected a table {{ distribution = ..., ... }} or {{ values = [...] }}")
        spec = dict(spec)
        kind = spec.pop("distribution", "values" if "values" in spec else None)
        if kind not in DISTRIBUTIONS:
            raise FingerpadError(f"{w}: unknown distribution {kind!r} (choose one of: {', '.join(DISTRIBUTIONS)})")
        keys = DISTRIBUTIONS[kind]
        extra = sorted(set(spec) - set(keys))
        if extra:
            raise FingerpadError(f"{w}: unknown key(s) {', '.join(extra)} for {kind} (keys: {', '.join(keys)})")
        optional = ("low", "high") if kind == "truncnormal" else ()
        missing = [k for k in keys if k not in spec and k not in optional]
        if missing:
            raise FingerpadError(f"{w}: {kind} needs {', '.join(missing)}")
        args: dict[str, Any] = {}
        if kind == "values":
            vals = spec["values"]
            if not isinstance(vals, list) or not vals:
                raise FingerpadError(f"{w}: values must be a non-empty list")
            args["values"] = tuple(par.parse(v, f"{w} values") if not (par.dimensional and _is_bare_number(v)
                                   and float(str(v)) != 0) else _number(par, v, f"{w} values") for v in vals)
        else:
            for k in keys:
                if k in spec:
                    # sigma of a lognormal is the log's sd: a plain number
                    args[k] = float(spec[k]) if k == "sigma" and _is_bare_number(spec[k]) else _number(par, spec[k],
                                                                                                       f"{w} {k}")
            for k in ("sd", "sigma"):
                if k in args and args[k] < 0:
                    raise FingerpadError(f"{w} {k}: must be non-negative, got {spec[k]!r}")
            if kind == "uniform" and args["high"] < args["low"]:
                raise FingerpadError(f"{w}: high {spec['high']!r} lies below low {spec['low']!r}")
            if kind == "truncnormal":
                args.setdefault("low", par.low if par.low is not None else -math.inf)
                args.setdefault("high", par.high if par.high is not None else math.inf)
                if not args["low"] < args["high"]:
                    raise FingerpadError(f"{w}: low must lie below high")
            if kind == "lognormal" and not args["median"] > 0:
                raise FingerpadError(f"{w} median: must be positive, got {spec['median']!r}")
            for k in ("low", "high", "mean", "median"):
                if k in args and math.isfinite(args[k]) and not (kind == "truncnormal" and k in ("low", "high")):
                    par.check(args[k], f"{w} {k}")
        dists[key] = Distribution(par, kind, args)
    pairs = parse_correlations(correlations, list(dists), where)
    return Population(dists, size=size, seed=seed, method=method, name=name, correlations=pairs)


def load_population(source: str | Mapping[str, Any]) -> Population:
    """A population from a preset name (:data:`POPULATION_PRESETS`), a TOML file with a
    ``[population]`` table (a study file will do), a folder written by ``fingerpad analyse``
    (:func:`~.population_measured.population_from_results`), or a table."""
    if isinstance(source, Mapping):
        return population_from_table(source)
    key = str(source).strip().lower()
    if key in POPULATION_PRESETS:
        return population_from_table(POPULATION_PRESETS[key], where=f"population {key!r}", name=key)
    path = Path(source)
    if path.is_dir():
        from .population_measured import population_from_results

        return population_from_results(path)
    if not path.is_file():
        raise FingerpadError(f"--population: {source!r} is neither a preset ({', '.join(POPULATION_PRESETS)}), "
                             "a file nor a folder written by fingerpad analyse")
    import tomllib

    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError, OSError) as exc:
        raise FingerpadError(f"--population {source}: cannot read it as TOML: {exc}") from None
    if "population" not in data:
        raise FingerpadError(f"--population {source}: no [population] table")
    return population_from_table(data["population"], where=f"{path.name} [population]", name=path.stem)


def member_finger(finger: Finger, params: Mapping[str, float]) -> Finger:
    """The study's finger with a member's parameters (SI)."""
    values = {k: v for k, v in params.items() if k != "ridge_fraction"}
    if "ridge_fraction" in params:
        if not isinstance(finger.ridges, ConstantFractionRidges):
            raise FingerpadError("population ridge_fraction: the study's finger must use the constant-fraction "
                                 f"ridge model, not {type(finger.ridges).__name__}")
        values["ridges"] = ConstantFractionRidges(params["ridge_fraction"])
    layered = sorted(set(values) & set(LAYER_FIELDS))
    if layered and finger.skin != "layered":
        # Said in the population's terms: the finger's own check ("a layered skin needs ...
        # missing") names fields the user never asked the population for.
        raise FingerpadError(f"population {', '.join(layered)}: the study's finger has a half-space skin; a "
                             "population of layered skins needs a layered finger (--finger layered, or the "
                             "[finger] keys skin_layer_thickness, skin_layer_modulus, skin_substrate_modulus)")
    return finger.with_overrides(**values) if values else finger


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
        (:class:`~fingerpad.study.sensitivity.SensitivityResult`), when asked for.
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
        out = ds.assign(data).assign_coords(member=np.arange(len(self.members)),
                                            quantile=np.asarray(self.quantile_levels))
        out.attrs.update({"population_name": self.population.name, "population_size": self.population.size,
                          "population_seed": self.population.seed, "population_method": self.population.method})
        return out

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
                 "contact_state": st}
                for c, fc, ff, st in zip(self.curves, self.critical_load, self.full_contact_load, self.states,
                                         strict=True)
            ],
            "notes": self.notes,
            **({"sensitivity": self.sensitivity.as_dict()} if self.sensitivity is not None else {}),
        }


#: Why ``--population`` and ``--direction`` are refused together, and what to do instead.
DIRECTION_REFUSED = (
    "--population with --direction: not supported. The directional friction comes from the "
    "deflection of the compliant features under each finger's own shear (its E_s, tau0 and alpha), so "
    "every member would need its own directional ramps (a population of solves, not one cell); run the "
    "population without --direction for the bands, then predict --direction for the members of interest "
    "with their --finger-param values (population.members in the JSON)")


def run_population(study: Study, population: Population,
                   quantiles: Sequence[float] = DEFAULT_QUANTILES, sensitivity: int | None = None) -> PopulationResult:
    """Predict every member of ``population`` on the study's texture (see the module docstring).

    The nominal prediction (the study's finger) is run first; the BEM cell is then prepared over
    the union of the members' pressures in units of E* (no solve when that lies inside what is
    cached) and every member's curve is that of :func:`~fingerpad.coupling.predict_curve` on the
    cell at the member's E1*, the members coupled together in small blocks
    (:func:`~fingerpad.study.members.predict_members`). With the Hertz model each member gets its
    own per-asperity cell (no solve). ``sensitivity``: the base samples N of the Sobol indices
    (:func:`~fingerpad.study.sensitivity.population_sensitivity`, N (d + 2) more fingers), or
    ``None`` for none.

    Raises
    ------
    FingerpadError
        A sliding direction (refused: :data:`DIRECTION_REFUSED` says why), bad quantiles, a
        member outside its parameter's bounds.
    """
    levels = tuple(float(q) for q in quantiles)
    if not levels or any(not (0 <= q <= 1) for q in levels):
        raise FingerpadError(f"--quantiles: each must lie in [0, 1], got {list(quantiles)}")
    levels = tuple(sorted(set(levels)))  # the band runs from the first level to the last
    if study.direction is not None:
        raise FingerpadError(DIRECTION_REFUSED)
    if study.finger.adhesive or "work_of_adhesion" in population.distributions:
        from .members import ADHESION_REFUSED

        raise FingerpadError(ADHESION_REFUSED)
    members = population.sample()
    fingers = [member_finger(study.finger, m) for m in members]  # bounds checked before any solve
    nominal = run_study(study)
    curves, crit, full, states = predict_fingers(nominal, fingers)
    notes = list(population.notes)
    if study.model == "both":
        notes.append("population: the BEM curves only (model both)")
    # Hertz (Eqs. 3.1-3.6) sees a layered skin as the half-space of its layer: a spread of the
    # layer's thickness or the tissue under it changes no member's curve, which must be said.
    unseen = [n for n in ("skin_layer_thickness", "skin_substrate_modulus", "skin_substrate_poisson")
              if n in population.distributions]
    # A layered cell is scale-free only at fixed proportions (t / L, E_1 / E*, E_2 / E*, the
    # Poisson ratios): a member that changes any of them is a BEM cell of its own, a cost that
    # grows with the population (1-2 s a member on 2 cores) and would otherwise go unsaid.
    proportions = ("skin_modulus", "skin_poisson", *LAYER_FIELDS)
    varied = [n for n in proportions if n in population.distributions]
    if study.finger.skin == "layered" and study.model != "hertz" and varied:
        notes.append(f"population: a layered skin whose {', '.join(varied)} varies gives each such member a BEM "
                     "unit cell of its own (solved or read from the cache), not one cell for all")
    if study.model == "hertz" and unseen:
        notes.append(f"population: the Hertz model takes each member's skin as the half-space of its layer, so "
                     f"the spread of {', '.join(unseen)} does not enter its curves; --model bem has the layer")
    sens = None
    if sensitivity is not None:
        from .sensitivity import population_sensitivity

        sens = population_sensitivity(nominal, population, sensitivity)
    return PopulationResult(nominal, population, members, curves, crit, full, states, levels, notes, sens)
