"""A population of fingers as distributions: the ``[population]`` table read and checked through
each parameter's declaration, and sampled quasi-randomly (issue 22).

A ``[population]`` table (a study file's, a file of one's own, or a preset of :mod:`.presets`)
reads::

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
:mod:`.correlations`. A folder written by ``fingerpad analyse`` is a population too, one member
per participant (:mod:`.measured`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FingerpadError
from ..finger import FINGER_PARAMS, RIDGE_FRACTION
from ..params import Param, _is_bare_number
from ..person import PERSON_PARAMS
from ..plausibility import check_plausible_range
from .correlations import Correlation, correlate, parse_correlations

__all__ = ["DISTRIBUTIONS", "MAX_MEMBERS", "POPULATION_PARAMS", "Distribution", "Population", "PopulationWarning",
           "members_plausible", "population_from_table"]

#: Most members of a population (or fingers of a Sobol design): each is a finger predicted, and
#: their curves and JSON grow with them (measured on the 2-core machine: 10 000 members of
#: ``adults`` took ~22 s, 390 MB of memory and 42 MB of JSON). Beyond it the Monte Carlo error of
#: a 5 % quantile, about sqrt(q (1 - q) / n), is under 0.2 % of the members.
MAX_MEMBERS = 20_000
#: A ``name`` of a ``[population]`` table: printable, at most this long.
MAX_NAME = 80


class PopulationWarning(UserWarning):
    """A population that will not give what its table seems to ask for."""

#: The distributions a parameter may follow, and their keys.
DISTRIBUTIONS: dict[str, tuple[str, ...]] = {
    "uniform": ("low", "high"),
    "normal": ("mean", "sd"),
    "lognormal": ("median", "sigma"),
    "truncnormal": ("mean", "sd", "low", "high"),
    "values": ("values",),
}
#: The parameters a population may vary, each declared once (:class:`~fingerpad.params.Param`): the
#: finger's numeric fields and the ridge fraction (all of them ``--finger-param`` names; not a
#: choice such as the skin's structure: a population's members share it), and a person's
#: parameters that are not the finger's (:data:`fingerpad.person.PERSON_PARAMS`: the Weber
#: fraction W); a member carries those and :func:`~.members.member_finger` leaves them to whoever
#: reads them (:mod:`fingerpad.perception`).
POPULATION_PARAMS: dict[str, Param] = {p.name: p for p in (*FINGER_PARAMS, RIDGE_FRACTION, *PERSON_PARAMS)
                                       if p.kind != "choice"}
#: The person's parameters of :data:`POPULATION_PARAMS`: drawn from a quasi-random sequence of
#: their own (:meth:`Population.sample`), so that drawing them changes no finger.
PERSON_NAMES: frozenset[str] = frozenset(p.name for p in PERSON_PARAMS)


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
    Gaussian copula (:mod:`.correlations`). ``measured``: fixed members (SI), e.g. the
    participants of an ``analyse`` folder (:mod:`.measured`), returned by
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

    def __post_init__(self) -> None:
        n = len(self.measured) or self.size
        if isinstance(self.size, bool) or not isinstance(self.size, int) or self.size < 1:
            raise FingerpadError(f"population size: expected a positive integer, got {self.size!r}")
        if n > MAX_MEMBERS:
            raise FingerpadError(f"population {self.name!r}: {n} members; at most {MAX_MEMBERS} (the quantiles of "
                                 f"{MAX_MEMBERS} members are within 0.2 % of the population's; a larger one would "
                                 "hold its curves in gigabytes)")

    def sample(self) -> list[dict[str, float]]:
        """The members' parameters (SI), by scrambled Sobol or Latin hypercube points (seeded,
        so the same table gives the same members), or the measured members as they are."""
        from scipy.stats import qmc

        if self.measured:
            return [dict(m) for m in self.measured]
        names = list(self.distributions)
        if not names:
            return [{} for _ in range(self.size)]
        # The finger's parameters, then the person's from a sequence of their own (its seed
        # spawned from the population's): a population that also draws W has the very fingers of
        # the one that does not, so a perception verdict changes with W alone.
        finger = [n for n in names if n not in PERSON_NAMES]
        person = [n for n in names if n in PERSON_NAMES]
        columns: dict[str, np.ndarray] = {}
        person_seed = np.random.default_rng(np.random.SeedSequence(self.seed).spawn(1)[0])
        for group, seed in ((finger, self.seed), (person, person_seed)):
            if not group:
                continue
            if self.method == "sobol":
                engine: Any = qmc.Sobol(len(group), scramble=True, seed=seed)
            else:
                engine = qmc.LatinHypercube(len(group), scramble=True, seed=seed)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # Sobol's note on sizes that are not powers of two
                u = engine.random(self.size)
            u = correlate(u, [c for c in self.correlations if c[0] in group], group)
            columns.update({n: self.distributions[n].ppf(u[:, j]) for j, n in enumerate(group)})
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


def _number(par: Param, value: Any, where: str, require_units: bool, bounds: bool = False) -> float:
    """A distribution's value read through the parameter's declaration (with ``require_units``,
    a length or pressure needs its unit), without the bounds unless ``bounds`` (a spread or a
    mean may sit anywhere, a listed value may not)."""
    if require_units and par.dimensional and _is_bare_number(value) and float(str(value).strip()) != 0:
        raise FingerpadError(f"{where}: {value!r} has no unit; a {par.kind} needs one, e.g. "
                             f"\"{str(value).strip()}{par.unit}\"")
    if bounds:
        return float(par.parse(value, where))
    # no bounds (a spread may sit anywhere) and, for a spread, no plausibility range either
    spread = where.endswith((" sd", " sigma"))
    bare = dataclasses.replace(par, low=None, high=None, plausible=None if spread else par.plausible)
    return float(bare.parse(value, where))


#: A truncated normal whose mean lies more than this many standard deviations outside its
#: [low, high] puts its members against the near bound: within sd / 3 of it (the truncated
#: tail's mean distance from the bound, ~sd / z).
FAR_MEAN = 3.0


def _far_mean(par: Param, args: Mapping[str, float], where: str) -> None:
    """Warn when a truncnormal's mean lies so far outside [low, high] that every member is drawn
    next to one bound (its spread then says nothing of the table's sd)."""
    mean, sd, low, high = args["mean"], args["sd"], args["low"], args["high"]
    if not sd > 0:
        return
    side, bound = ("below low", low) if mean < low else ("above high", high) if mean > high else ("", mean)
    z = abs(bound - mean) / sd
    if z > FAR_MEAN:
        warnings.warn(f"{where}: the mean {par.format(mean)} lies {z:.3g} sd {side} = {par.format(bound)}: every "
                      f"member is drawn within about {par.format(sd / z)} of {par.format(bound)}; center the mean "
                      "inside [low, high] or use a uniform distribution", PopulationWarning, stacklevel=4)


def population_from_table(table: Mapping[str, Any], where: str = "[population]", name: str = "custom", *,
                          require_units: bool = False) -> Population:
    """A :class:`Population` from a ``[population]`` table (see the module docstring).

    ``require_units``: a length or pressure given as a bare number is refused, naming the key
    (the tables of files, where a bare number would be metres or pascals by accident); a table
    built in Python takes SI numbers, as :func:`fingerpad.design.spec.sweep_from_dict` does.
    ``name``: the population's name unless the table gives its own ``name``.

    Raises
    ------
    FingerpadError
        Unknown parameter or distribution, a missing or unknown key, a length without a unit,
        a negative spread, a bad size (more than :data:`MAX_MEMBERS`), seed, method or name;
        naming the key.
    """
    if not isinstance(table, Mapping):
        raise FingerpadError(f"{where}: expected a table")
    body = dict(table)
    size, seed, method = body.pop("size", 200), body.pop("seed", 0), body.pop("method", "sobol")
    correlations = body.pop("correlations", [])
    name = body.pop("name", name)
    if not (isinstance(name, str) and 0 < len(name.strip()) <= MAX_NAME and name.isprintable()):
        raise FingerpadError(f"{where} name: expected a printable text of 1 to {MAX_NAME} characters, got "
                             f"{str(name)[:MAX_NAME]!r}")
    name = name.strip()
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        raise FingerpadError(f"{where} size: expected a positive integer, got {size!r}")
    if size > MAX_MEMBERS:
        raise FingerpadError(f"{where} size: {size} members; at most {MAX_MEMBERS} (the quantiles of {MAX_MEMBERS} "
                             "members are within 0.2 % of the population's; a larger one would hold its curves in "
                             "gigabytes)")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise FingerpadError(f"{where} seed: expected a non-negative integer, got {seed!r}")
    if method not in ("sobol", "lhs"):
        raise FingerpadError(f"{where} method: expected \"sobol\" or \"lhs\", got {method!r}")
    dists: dict[str, Distribution] = {}
    for key, spec in body.items():
        if key not in POPULATION_PARAMS:
            raise FingerpadError(f"{where}: unknown parameter {key!r} (known: {', '.join(POPULATION_PARAMS)}, "
                                 "size, seed, method, name, correlations)")
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
            if len(vals) > MAX_MEMBERS:
                raise FingerpadError(f"{w}: {len(vals)} values; at most {MAX_MEMBERS}")
            args["values"] = tuple(_number(par, v, f"{w} values", require_units, bounds=True) for v in vals)
        else:
            for k in keys:
                if k in spec:
                    # sigma of a lognormal is the log's sd: a plain number
                    args[k] = float(spec[k]) if k == "sigma" and _is_bare_number(spec[k]) else _number(
                        par, spec[k], f"{w} {k}", require_units)
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
                _far_mean(par, args, w)
            if kind == "lognormal" and not args["median"] > 0:
                raise FingerpadError(f"{w} median: must be positive, got {spec['median']!r}")
            for k in ("low", "high", "mean", "median"):
                if k in args and math.isfinite(args[k]) and not (kind == "truncnormal" and k in ("low", "high")):
                    par.check(args[k], f"{w} {k}")
        dists[key] = Distribution(par, kind, args)
    pairs = parse_correlations(correlations, list(dists), where)
    for a, b, _ in pairs:
        if (a in PERSON_NAMES) != (b in PERSON_NAMES):
            raise FingerpadError(f"{where} correlations: {a!r} with {b!r}: a person's {a if a in PERSON_NAMES else b} "
                                 "is drawn apart from the finger's parameters (so that drawing it changes no "
                                 "finger); it may be correlated with another of the person's parameters only")
    return Population(dists, size=size, seed=seed, method=method, name=name, correlations=pairs)



def members_plausible(population: Population, members: list[dict[str, float]]) -> None:
    """Warn once per parameter whose members lie outside its plausible range (the role of its
    declaration, :data:`fingerpad.plausibility.RANGES`), as a flag's value is warned about: a
    lognormal of sigma 50 gives pad moduli from 1e-53 to 1e52 Pa, a participants table in the
    wrong unit pads of metres."""
    for name in dict.fromkeys(k for m in members for k in m):
        par = POPULATION_PARAMS.get(name)
        if par is not None and par.plausible is not None:
            check_plausible_range([m[name] for m in members if name in m], par.plausible,
                                  f"population {population.name!r} {name}")
