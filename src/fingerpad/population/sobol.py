"""Which parameter drives the spread of a population: variance-based (Sobol) sensitivity indices
of mu/mu_ref at every load and of the critical load (issue 22).

For an output ``Y = f(X_1, ..., X_d)`` of independent parameters, the **first-order index**
``S_i = Var(E[Y | X_i]) / Var(Y)`` is the share of the variance that ``X_i`` explains alone (what
would remain of the spread if only ``X_i`` varied, on average), the **total index**
``S_Ti = E[Var(Y | X_~i)] / Var(Y)`` the share in which ``X_i`` has any part, alone or through
interactions (what would vanish if ``X_i`` were known). ``S_Ti >= S_i``; ``sum S_i <= 1``, with
equality for an additive output; ``S_Ti ~ 0`` means the parameter can be fixed anywhere in its range.

Sample plan (Saltelli's pick-and-freeze design): a scrambled Sobol sequence of dimension ``2d``
gives two ``N x d`` matrices A and B (unit cube, mapped through each parameter's inverse
distribution function, as the population's members are); ``AB_i`` is A with its column ``i``
from B. The output is evaluated on A, B and every ``AB_i``: ``N (d + 2)`` fingers, ``d`` the
parameters with a spread. Estimators (per output, per load):

* first order, Saltelli et al. (2010): ``S_i = mean(f(B) (f(AB_i) - f(A))) / V``;
* total, Jansen (1999): ``S_Ti = mean((f(A) - f(AB_i))^2) / (2 V)``;

``V`` the variance of ``f`` over A and B together, ``f`` centred on its mean over A and B (the
first-order estimator's scatter grows with the mean; centring removes that, the Jansen estimator
is unchanged by it). Confidence: a bootstrap over the N rows
(``bootstrap`` resamples, seeded), reported as the half-width ``z_{(1+c)/2} sd`` of the
bootstrap estimates at confidence ``c`` (0.95), as SALib reports it.

The parameters are taken as independent (the indices of correlated inputs are not these): a
population's correlations are left out of the design, with a note; a population of measured
members (an ``analyse`` folder) has no distributions and is refused.
An output with zero variance (e.g. mu/mu_ref where no parameter acts) has no indices (NaN).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from ..errors import FingerpadError
from .distributions import MAX_MEMBERS, PERSON_NAMES, Population
from .members import member_finger, predict_fingers
from ..study.run import Prediction

__all__ = ["DEFAULT_SAMPLES", "SensitivityResult", "check_design", "population_sensitivity", "saltelli_points",
           "sobol_indices"]

#: Base samples N of the design by default: N (d + 2) evaluations (2560 for the 8 parameters of
#: ``adults``), about as long as 2.5 populations of 1000; indices to about +-0.05 (95 %).
DEFAULT_SAMPLES = 256
#: Bootstrap resamples of the confidence intervals.
BOOTSTRAP = 200
#: Quantities whose indices are reported: mu/mu_ref per load, the critical load (N) and its
#: decimal logarithm (the critical load spreads over decades and depends on the parameters as a
#: product: the indices of its log tell which factor moves it most, those of the load itself are
#: dominated by the fingers of the upper tail and by interactions).
SENSITIVITY_QUANTITIES: tuple[str, ...] = ("mu_normalised", "critical_load", "log10_critical_load")


def saltelli_points(d: int, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """The unit-cube matrices A and B (each ``n x d``) of the pick-and-freeze design: the first
    and last ``d`` columns of a scrambled Sobol sequence of dimension ``2d`` (seeded)."""
    from scipy.stats import qmc

    if d < 1 or n < 2:
        raise FingerpadError(f"sensitivity: needs at least one varying parameter and 2 samples (d={d}, N={n})")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Sobol's note on sizes that are not powers of two
        u = qmc.Sobol(2 * d, scramble=True, seed=seed).random(n)
    return u[:, :d], u[:, d:]


def _estimates(f_a: np.ndarray, f_b: np.ndarray, f_ab: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """First-order (Saltelli 2010) and total (Jansen 1999) indices, ``(d, q)`` each, from
    ``f_a``, ``f_b`` (``N x q``) and ``f_ab`` (``d x N x q``)."""
    both = np.concatenate([f_a, f_b])
    var = np.var(both, axis=0)
    # centred on the sample mean: the same estimators (shift-invariant in expectation), with far
    # less scatter where the mean is large against the spread (mu/mu_ref ~ 0.4 +- 0.05)
    mean = np.mean(both, axis=0)
    f_a, f_b, f_ab = f_a - mean, f_b - mean, f_ab - mean
    with np.errstate(divide="ignore", invalid="ignore"):
        first = np.mean(f_b[None] * (f_ab - f_a[None]), axis=1) / var
        total = 0.5 * np.mean((f_a[None] - f_ab) ** 2, axis=1) / var
    flat = ~(var > 0)
    first[:, flat] = np.nan
    total[:, flat] = np.nan
    return first, total


def sobol_indices(f_a: Any, f_b: Any, f_ab: Any, *, bootstrap: int = BOOTSTRAP, confidence: float = 0.95,
                  seed: int = 0) -> dict[str, np.ndarray]:
    """First-order and total Sobol indices with bootstrap confidence half-widths.

    Parameters
    ----------
    f_a, f_b
        The output on the rows of A and B: shape ``(N,)`` or ``(N, q)`` (q outputs, e.g. one per
        load).
    f_ab
        The output on ``AB_i``: shape ``(d, N)`` or ``(d, N, q)``.
    bootstrap, confidence, seed
        Resamples of the N rows, the confidence level of the half-widths and the resampling seed.

    Returns
    -------
    dict
        ``first``, ``total``, ``first_conf``, ``total_conf``: arrays ``(d,)`` or ``(d, q)``.
    """
    from scipy.stats import norm

    a, b, ab = (np.asarray(x, dtype=float) for x in (f_a, f_b, f_ab))
    scalar = a.ndim == 1
    if scalar:
        a, b, ab = a[:, None], b[:, None], ab[..., None]
    if a.shape != b.shape or ab.shape[1:] != a.shape:
        raise FingerpadError(f"sobol_indices: shapes {a.shape}, {b.shape}, {ab.shape} do not match")
    first, total = _estimates(a, b, ab)
    rng = np.random.default_rng(seed)
    n = a.shape[0]
    boot_first, boot_total = [], []
    for _ in range(int(bootstrap)):
        rows = rng.integers(0, n, n)
        s1, st = _estimates(a[rows], b[rows], ab[:, rows])
        boot_first.append(s1)
        boot_total.append(st)
    z = float(norm.ppf(0.5 + confidence / 2))
    first_conf = z * np.std(boot_first, axis=0) if bootstrap else np.full_like(first, np.nan)
    total_conf = z * np.std(boot_total, axis=0) if bootstrap else np.full_like(total, np.nan)
    out = {"first": first, "total": total, "first_conf": first_conf, "total_conf": total_conf}
    return {k: v[:, 0] for k, v in out.items()} if scalar else out


@dataclass
class SensitivityResult:
    """Sobol indices of a population's outputs (see the module docstring).

    Attributes
    ----------
    parameters
        The parameters with a spread, in the design's column order, then those listed without
        one (their indices 0: a fixed parameter explains no variance).
    loads
        The loads (N) of the per-load quantities.
    indices
        ``{quantity: {parameter: {"first", "total", "first_conf", "total_conf"}}}``: arrays per
        load for ``mu_normalised``, numbers for ``critical_load`` and ``log10_critical_load``.
    base_samples, evaluations, seed, bootstrap, confidence
        The sample plan: N, ``N (d + 2)`` fingers evaluated, the Sobol scrambling seed, the
        bootstrap resamples and the confidence level of the half-widths.
    notes
        Remarks (a quantity left without indices and why).
    """

    #: The publications of the indices (:mod:`fingerpad.references` keys): Sobol's indices,
    #: Saltelli's design and first-order estimator, Jansen's total-index estimator.
    REFERENCES: ClassVar[tuple[str, ...]] = ("sobol2001", "saltelli2010", "jansen1999")

    parameters: list[str]
    loads: np.ndarray
    indices: dict[str, dict[str, dict[str, Any]]]
    base_samples: int
    evaluations: int
    seed: int
    bootstrap: int
    confidence: float
    notes: list[str] = field(default_factory=list)

    def plan(self) -> dict[str, Any]:
        """The sample plan, as the JSON states it."""
        return {
            "design": "Saltelli pick-and-freeze: matrices A, B (N x d) from a scrambled Sobol sequence of "
                      "dimension 2d, and A with column i from B for each i",
            "first_order": "Saltelli et al. 2010", "total": "Jansen 1999",
            "base_samples": self.base_samples, "parameters_varied": self.evaluations // self.base_samples - 2,
            "evaluations": self.evaluations, "seed": self.seed,
            "confidence_interval": f"bootstrap over the N rows, {self.bootstrap} resamples; half-width "
                                   f"z sd at {self.confidence:g}",
            "confidence": self.confidence,
        }

    def as_dict(self) -> dict[str, Any]:
        """``{"plan": ..., "loads": ..., quantity: {parameter: {first, total, first_conf,
        total_conf}}}`` (the ``population.sensitivity`` entry of ``predict.json``)."""
        return {"plan": self.plan(), "loads": self.loads, **self.indices, "notes": self.notes}

    def rows(self) -> list[dict[str, Any]]:
        """One row per quantity, load and parameter (the CSV; the critical loads have no load)."""
        out = []
        for quantity, table in self.indices.items():
            for param, entry in table.items():
                values = {k: np.atleast_1d(np.asarray(v, float)) for k, v in entry.items()}
                loads = self.loads if quantity == "mu_normalised" else [None]
                for j, load in enumerate(loads):
                    out.append({"quantity": quantity, "load_N": load, "parameter": param,
                                **{k: float(v[j]) for k, v in values.items()}})
        return out

    def csv_text(self) -> str:
        """:meth:`rows` as CSV (indices are ratios; empty cells where undefined)."""
        import csv
        import io

        buf = io.StringIO()
        keys = ["quantity", "load_N", "parameter", "first", "first_conf", "total", "total_conf"]
        writer = csv.DictWriter(buf, fieldnames=keys, lineterminator="\n")
        writer.writeheader()
        for row in self.rows():
            writer.writerow({k: ("" if v is None or (isinstance(v, float) and not math.isfinite(v)) else v)
                             for k, v in row.items()})
        return buf.getvalue()


def check_design(population: Population, samples: int) -> list[str]:
    """The parameters of the design (those with a spread), or the reason there is none: a
    panel of measured people (the members are the people, not draws of independent parameters),
    no parameter with a spread, fewer than 2 base samples, or more than
    :data:`~.distributions.MAX_MEMBERS` fingers to predict, ``N (d + 2)``.

    Raises
    ------
    FingerpadError
        Naming ``--sensitivity`` or ``--sensitivity-samples``.
    """
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
        raise FingerpadError(f"--sensitivity-samples: expected an integer of at least 2, got {samples!r}")
    if getattr(population, "measured", ()):
        raise FingerpadError("--sensitivity: a population of measured members (an analyse folder) has no "
                             "distributions to vary; give a [population] table of distributions")
    # a person's parameter (the Weber fraction) changes no finger's curve: not a parameter of the
    # design (its indices would be 0 exactly), it costs no design fingers and is not listed
    names = [k for k, d in population.distributions.items() if d.spread and k not in PERSON_NAMES]
    if not names:
        raise FingerpadError("--sensitivity: no parameter of the population's fingers has a spread")
    fingers = samples * (len(names) + 2)
    if fingers > MAX_MEMBERS:
        raise FingerpadError(f"--sensitivity-samples {samples}: N (d + 2) = {fingers} fingers for the {len(names)} "
                             f"parameters with a spread; at most {MAX_MEMBERS}, so N <= "
                             f"{MAX_MEMBERS // (len(names) + 2)}")
    return names


def _design_members(population: Population, names: list[str], a: np.ndarray, b: np.ndarray) -> list[dict[str, float]]:
    """The members of the rows of A, B and each AB_i (in that order), parameters in SI; the
    parameters without spread at their one value; each value checked against its bounds."""
    fixed = {k: float(d.ppf(np.array([0.5]))[0]) for k, d in population.distributions.items() if k not in names}
    blocks = [a, b]
    for i in range(len(names)):
        ab = a.copy()
        ab[:, i] = b[:, i]
        blocks.append(ab)
    u = np.concatenate(blocks)
    columns = {n: population.distributions[n].ppf(u[:, j]) for j, n in enumerate(names)}
    members = []
    for i in range(u.shape[0]):
        row = dict(fixed)
        for n in names:
            dist = population.distributions[n]
            row[n] = dist.param.check(float(columns[n][i]), f"population {n} (sensitivity design point {i}, "
                                      f"{dist.kind}): use a truncnormal distribution to stay inside the bounds; value")
        members.append(row)
    return members


def population_sensitivity(
    nominal: Prediction, population: Population, samples: int = DEFAULT_SAMPLES, *, seed: int | None = None,
    bootstrap: int = BOOTSTRAP, confidence: float = 0.95,
    evaluate: Callable[[Prediction, list[Any]], Mapping[str, np.ndarray]] | None = None,
) -> SensitivityResult:
    """Sobol indices of mu/mu_ref (per load) and of the critical load over ``population``.

    Parameters
    ----------
    nominal
        The study's own prediction (its cell is reused: no solve beyond the pressures the design's
        fingers add).
    population
        The distributions; those with a spread are the design's parameters.
    samples
        N, the base samples (a power of two keeps the Sobol points balanced); ``N (d + 2)``
        fingers are predicted.
    seed
        Scrambling seed of the design (default: the population's).
    bootstrap, confidence
        Of the confidence half-widths.
    evaluate
        ``evaluate(nominal, fingers) -> {"mu_normalised": (M, loads), "critical_load": (M,),
        "log10_critical_load": (M,)}``;
        by default the vectorised coupling (:func:`~fingerpad.population.members.predict_fingers`).

    Raises
    ------
    FingerpadError
        No parameter with a spread, fewer than 2 samples, too many fingers (:func:`check_design`),
        a design point outside a bound.
    """
    names = check_design(population, samples)
    seed = population.seed if seed is None else int(seed)
    a, b = saltelli_points(len(names), samples, seed)
    members = _design_members(population, names, a, b)
    fingers = [member_finger(nominal.study.finger, m) for m in members]
    outputs = (evaluate or _evaluate)(nominal, fingers)
    n, d = samples, len(names)
    unvaried = [p for p in population.distributions if p not in names and p not in PERSON_NAMES]
    notes: list[str] = []
    if getattr(population, "correlations", ()):
        notes.append("the population's correlations are not used here: Sobol indices are defined for "
                     "independent parameters, and these are the indices of the parameters drawn independently")
    indices: dict[str, dict[str, dict[str, Any]]] = {}
    for quantity in SENSITIVITY_QUANTITIES:
        y = np.asarray(outputs[quantity], dtype=float)
        if not np.all(np.isfinite(y)):
            bad = int(np.sum(~np.all(np.isfinite(y.reshape(y.shape[0], -1)), axis=1)))
            notes.append(f"{quantity}: {bad} of {y.shape[0]} design fingers have none (never reach the "
                         "transition, or beyond the searched loads): no indices")
            nan = np.full((d,) + y.shape[1:], np.nan)
            res = {"first": nan, "total": nan, "first_conf": nan, "total_conf": nan}
        else:
            ab = np.stack([y[(2 + i) * n:(3 + i) * n] for i in range(d)])
            res = sobol_indices(y[:n], y[n:2 * n], ab, bootstrap=bootstrap, confidence=confidence, seed=seed)
        indices[quantity] = {p: {k: (float(v[i]) if v.ndim == 1 else v[i]) for k, v in res.items()}
                             for i, p in enumerate(names)}
        # a listed parameter without spread explains no variance: its indices are 0 by definition
        zero = np.zeros(np.shape(y)[1:]) if y.ndim > 1 else 0.0
        for p in unvaried:
            indices[quantity][p] = {k: zero for k in ("first", "total", "first_conf", "total_conf")}
    note = first_above_total_note(indices, confidence)
    if note:
        notes.append(note)
    return SensitivityResult(names + unvaried, np.asarray(nominal.study.loads, float), indices, n, n * (d + 2), seed,
                             int(bootstrap), float(confidence), notes)


def first_above_total_note(indices: dict[str, dict[str, dict[str, Any]]], confidence: float = 0.95) -> str | None:
    """A note when a first-order estimate exceeds its parameter's total estimate (``None`` if
    none does). The true indices obey ``S_Ti >= S_i``, but the two are estimated apart (Saltelli
    2010 and Jansen 1999 on the same rows), each with its own sampling error: for a parameter that
    acts alone (``S_Ti ~ S_i``) either may come out above the other. The note says by how much,
    and whether that is within the two estimates' intervals."""
    worst, count, outside = 0.0, 0, 0
    for quantity, params in indices.items():
        for entry in params.values():
            first, total = (np.atleast_1d(np.asarray(entry[k], float)) for k in ("first", "total"))
            fc, tc = (np.atleast_1d(np.asarray(entry[k], float)) for k in ("first_conf", "total_conf"))
            above = np.isfinite(first) & np.isfinite(total) & (first > total)
            if not np.any(above):
                continue
            excess = (first - total)[above]
            count += int(above.sum())
            worst = max(worst, float(excess.max()))
            outside += int(np.sum(excess > np.hypot(fc, tc)[above]))
    if not count:
        return None
    within = ("all within" if not outside else f"{count - outside} of them within")
    return (f"first-order above total in {count} entries (by up to {worst:.2f}; {within} the two estimates' "
            f"{100 * confidence:g} % intervals combined): the true indices have S_T >= S, but each is "
            "estimated with its own sampling error, and for a parameter acting alone (S_T ~ S) either "
            "may come out higher; read such a pair as equal within its intervals"
            + ("" if not outside else "; more samples (--sensitivity-samples) narrow them"))


def _evaluate(nominal: Prediction, fingers: list[Any]) -> dict[str, np.ndarray]:
    """mu/mu_ref per load and the critical load of each finger (vectorised coupling)."""
    curves, crit, _, _ = predict_fingers(nominal, fingers)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_crit = np.log10(crit)
    return {"mu_normalised": np.array([c.mu_normalised for c in curves], dtype=float), "critical_load": crit,
            "log10_critical_load": log_crit}
