"""The skin micro-modulus E_s from friction: model fits whose intervals respect the recordings.

The model fit draws its information from the level of mu/mu_ref (and, with ``fit_scale``, from
the shape of the curve). Strokes of one recording share its skin state, so the level is known
only as well as the recordings agree with one another. The interval is therefore a test
inversion on the recordings, not a likelihood on independent strokes:

* level (default): for each trial E_s the residuals ``r = ln mu_norm - ln model(F, E_s)`` are
  averaged per recording; the weighted mean of those recording means is tested against zero
  with a cluster-robust standard error (``G - 1`` df; in a balanced study the exact t-test on
  recording means), with the error of the participant's reference level (which shifts every
  mu_norm alike) added in quadrature, Welch-Satterthwaite df;
* shape (``fit_scale``): the level is free, so the residuals are centred per recording and the
  within-recording residual sum of squares is compared with its minimum by an F test.

E_s is accepted where the test does not reject at ``1 - level``. That set may be several
disjoint pieces (a non-monotone model, or two near-equal minima with ``fit_scale``): all of
them are reported. A set that reaches a search bound, or that is empty, means the data cannot
determine E_s, and the result says so.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import special, stats

from ..errors import FingerpadError
from ..friction import fit_inputs
from .micro_models import Model, ModelTable
from .stats import cluster_labels, random_intercept_fit
from .transition import modulus_from_transition, transition_load

__all__ = ["ModelTable", "ModulusFit", "design_effect", "estimate_skin_modulus", "estimate_skin_modulus_joint",
           "modulus_from_transition", "transition_load"]


@dataclass(frozen=True)
class ModulusFit:
    """Skin modulus E_s fitted with a micro-model, and the set of E_s the data allow.

    Attributes
    ----------
    skin_modulus
        Best E_s, Pa (where the level residual vanishes, or the shape fits best).
    ci_low, ci_high
        Lowest and highest E_s of the accepted set at ``level`` (its hull), Pa.
    pieces
        The accepted set as disjoint intervals ``((low, high), ...)``, Pa.
    profile_ci
        The hull again (kept for callers of earlier versions).
    reference_sd
        Standard deviation of ``ln E_s`` due to the reference curve's level (0 without).
    design_effect
        Kish design effect of the residuals by recording (information only).
    scale
        Fitted amplitude factor (1 unless ``fit_scale``).
    rss
        Residual sum of squares at the best E_s.
    n, n_clusters
        Points and recordings.
    determined
        False when the accepted set reaches a search bound or is empty: the data do not
        determine E_s (``note`` says how).
    at_bound
        The accepted set (or the estimate) reaches a bound of the search range.
    statistic, df
        ``"level t"`` or ``"shape F"`` and the (denominator) degrees of freedom.
    model
        Name of the micro-model that produced it (``bem``, ``hertz``, or a caller's label).
    note
        Plain-language caveat, else empty.
    """

    skin_modulus: float
    ci_low: float
    ci_high: float
    profile_ci: tuple[float, float]
    reference_sd: float
    design_effect: float
    scale: float
    rss: float
    n: int
    level: float
    at_bound: bool
    method: str = "level t-test over recordings"
    pieces: tuple[tuple[float, float], ...] = ()
    determined: bool = True
    statistic: str = "level t"
    df: float = math.nan
    n_clusters: int = 0
    model: str = ""
    note: str = ""
    bounds: tuple[float, float] = field(default=(math.nan, math.nan))

    def describe_interval(self, unit: float = 1e6, name: str = "MPa") -> str:
        """The accepted set, e.g. ``0.21-0.34 MPa`` or ``0.1-0.2 or 0.5-0.7 MPa``."""
        if not self.pieces:
            return "none"
        return " or ".join(f"{a / unit:.3g}-{b / unit:.3g}" for a, b in self.pieces) + f" {name}"


def design_effect(residuals: np.ndarray, clusters: np.ndarray) -> float:
    """Kish design effect ``1 + (m - 1) rho`` of residuals grouped in clusters (files).

    ``rho`` is the intra-class correlation from a one-way ANOVA (clipped at 0), ``m`` the mean
    cluster size; 1 for fewer than two clusters.
    """
    r = np.asarray(residuals, dtype=float)
    labels, inv = np.unique(np.asarray(clusters), return_inverse=True)
    k, n = labels.size, r.size
    if k < 2 or n <= k:
        return 1.0
    counts = np.bincount(inv, minlength=k).astype(float)
    means = np.bincount(inv, weights=r, minlength=k) / counts
    msw = float(np.sum((r - means[inv]) ** 2) / (n - k))
    msb = float(np.sum(counts * (means - r.mean()) ** 2) / (k - 1))
    m = n / k
    if msb + (m - 1) * msw <= 0:
        return 1.0
    rho = max(0.0, (msb - msw) / (msb + (m - 1) * msw))
    return 1.0 + (m - 1.0) * rho


def _reference_level(reference: Any, loads: np.ndarray, design: float = 1.0) -> tuple[float, float]:
    """Variance and df of the reference curve's mean ``ln mu_ref`` over ``loads``."""
    if reference is None:
        return 0.0, math.inf
    if hasattr(reference, "log_level"):
        _, se, df = reference.log_level(loads)
        # a fit that took every stroke as independent (no recordings) is inflated by the design
        # effect the caller measured; a clustered fit already carries its recordings
        inflate = max(float(design), 1.0) if getattr(reference, "n_clusters", 1) == 0 else 1.0
        return se**2 * inflate, float(df)
    cov = getattr(reference, "log_covariance", None)
    if cov is None:
        return 0.0, math.inf
    v = np.array([1.0, float(np.mean(np.log(loads)))])
    var = float(max(v @ np.asarray(cov, dtype=float) @ v, 0.0)) * max(float(design), 1.0)
    return var, float(getattr(reference, "dof", math.inf))


def _log_predictions(datasets: Sequence[tuple[np.ndarray, np.ndarray, ModelTable]], scan: np.ndarray) -> np.ndarray:
    """``ln model`` of every point (columns) at every trial ``ln E_s`` (rows), from the tables."""
    cols = []
    for f, _, t in datasets:
        rows = t.log_rows(scan)  # (scan, table loads)
        lx, tx = np.log(f), np.log(t.loads)
        j = np.clip(np.searchsorted(tx, lx) - 1, 0, tx.size - 2)
        w = np.clip((lx - tx[j]) / (tx[j + 1] - tx[j]), 0.0, 1.0)
        cols.append(rows[:, j] * (1 - w) + rows[:, j + 1] * w)
    return np.concatenate(cols, axis=1)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges ``[a, b]`` (inclusive) of the True runs of ``mask``."""
    edges = np.diff(np.r_[0, mask.astype(int), 0])
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _crossing(scan: np.ndarray, excess: np.ndarray, i: int, j: int) -> float:
    """Where ``excess`` (accepted <= 0) crosses zero between scan points i and j (linear)."""
    a, b = excess[i], excess[j]
    if not (np.isfinite(a) and np.isfinite(b)) or a == b:
        return float(scan[i])
    return float(scan[i] + (scan[j] - scan[i]) * a / (a - b))


def _infer(
    datasets: Sequence[tuple[np.ndarray, np.ndarray, ModelTable]],
    *,
    level: float,
    fit_scale: bool,
    log_residuals: bool,
    reference: Any = None,
    reference_design_effect: float = 1.0,
    clusters: np.ndarray | None = None,
    n_scan: int = 241,
    model_name: str = "",
) -> ModulusFit:
    if not 0 < level < 1:
        raise FingerpadError(f"level must lie in (0, 1), got {level!r}")
    loads = np.concatenate([f for f, _, _ in datasets])
    ys = np.concatenate([v for _, v, _ in datasets])
    n = ys.size
    lo_b = max(t.log_moduli[0] for _, _, t in datasets)
    hi_b = min(t.log_moduli[-1] for _, _, t in datasets)
    inv = cluster_labels(clusters, n)
    g = int(inv.max()) + 1
    m = np.bincount(inv, minlength=g).astype(float)
    onehot = (inv[:, None] == np.arange(g)[None, :]).astype(float) if g < n else None
    var_ref, df_ref = (0.0, math.inf) if fit_scale else _reference_level(reference, loads, reference_design_effect)
    df_w = float(n - g - 1) if g < n else float(n - 2)
    if fit_scale and df_w < 1:
        raise FingerpadError("skin modulus fit with a free scale: too few points within the recordings")
    gamma: list[float] = []

    def evaluate(scan: np.ndarray) -> dict[str, np.ndarray]:
        """Residuals and test statistics at every trial ln E_s of ``scan``."""
        logp = _log_predictions(datasets, scan)  # (scan, n)
        if log_residuals:
            R = np.log(ys)[None, :] - logp
            c = np.ones(scan.size)
        else:
            P = np.exp(logp)
            c = (P @ ys) / np.einsum("ij,ij->i", P, P) if fit_scale else np.ones(scan.size)
            R = ys[None, :] - c[:, None] * P
        means = R if onehot is None else (R @ onehot) / m  # (scan, g)
        if onehot is None:  # independent points: centre on the overall mean
            centred = R - R.mean(axis=1, keepdims=True)
        else:
            centred = R - means[:, inv]
        within = np.einsum("ij,ij->i", centred, centred)
        out = {"logp": logp, "R": R, "within": within, "scale": c}
        if fit_scale:
            return out
        if not gamma:
            # weights of the recording means: GLS with the between/within variance ratio at the
            # best level (one REML fit); the variance itself is estimated cluster-robustly
            j0 = int(np.argmin(np.abs(R.mean(axis=1))))
            ratio = 0.0
            if onehot is not None and g > 1:
                fit0 = random_intercept_fit(R[j0], np.ones((n, 1)), inv)
                ratio = fit0.sigma2_between / max(fit0.sigma2, 1e-300)
            gamma.append(ratio)
        a = m / (1.0 + gamma[0] * m)
        delta = means @ a / a.sum()
        if g > 1:
            var_tex = g / (g - 1) * np.sum((a[None, :] * (means - delta[:, None])) ** 2, axis=1) / a.sum() ** 2
        else:
            var_tex = np.full(scan.size, math.inf)
        df_tex = float(max(g - 1, 1))
        var = var_tex + var_ref
        with np.errstate(divide="ignore", invalid="ignore"):  # Welch-Satterthwaite df of the sum
            df_all = var**2 / (var_tex**2 / df_tex + (var_ref**2 / df_ref if math.isfinite(df_ref) else 0.0))
        df_all = np.where(np.isfinite(df_all), np.maximum(df_all, 1.0), df_tex)
        tstat = np.abs(delta) / np.sqrt(np.maximum(var, 1e-300))
        # the t quantile of every df: scipy.stats.t.ppf's own function, without its argument
        # checks (all df >= 1, the level in (0, 1)), ~10 % of a fit
        out.update(delta=delta, df=df_all, excess=tstat - special.stdtrit(df_all, 0.5 + level / 2.0))
        return out

    coarse = np.linspace(lo_b, hi_b, int(n_scan))
    ev = evaluate(coarse)
    if fit_scale:
        rss_min = max(float(ev["within"].min()), 1e-300)
        excess = (ev["within"] - rss_min) / (rss_min / df_w) - stats.f.ppf(level, 1, df_w)
        turns = np.diff(np.sign(np.diff(ev["within"])), append=0.0) != 0  # local minima and maxima
        interesting = np.flatnonzero((np.diff(np.sign(excess)) != 0) | turns)
    else:
        d = ev["delta"]
        interesting = np.flatnonzero((np.diff(np.sign(d)) != 0) | (np.diff(np.sign(ev["excess"])) != 0))
    # refine where the level changes sign or the test changes its answer: an accepted piece may
    # be narrower than the coarse step
    step = coarse[1] - coarse[0]
    extra = [np.linspace(coarse[k] - step, coarse[k] + 2 * step, 49) for k in interesting]
    scan = np.unique(np.clip(np.concatenate([coarse, *extra]), lo_b, hi_b)) if extra else coarse
    ev = evaluate(scan) if extra else ev
    within, R, logp = ev["within"], ev["R"], ev["logp"]
    if fit_scale:
        best = int(np.argmin(within))
        rss_min = max(float(within[best]), 1e-300)
        excess = (within - rss_min) / (rss_min / df_w) - stats.f.ppf(level, 1, df_w)
        statistic, method, df, ref_sd = "shape F", "F test of the within-recording shape", df_w, 0.0
        scale = math.exp(float(np.mean(R[best]))) if log_residuals else float(ev["scale"][best])
        est = float(scan[best])
        if 0 < best < scan.size - 1:  # parabola through the three smallest
            x3, y3 = scan[best - 1:best + 2], within[best - 1:best + 2]
            coef = np.polyfit(x3, y3, 2)
            if coef[0] > 0:
                est = float(np.clip(-coef[1] / (2 * coef[0]), x3[0], x3[2]))
    else:
        delta, excess = ev["delta"], ev["excess"]
        # the estimate: where the level residual changes sign; among several, the best shape
        roots = [int(i) for i in np.flatnonzero(np.sign(delta[:-1]) != np.sign(delta[1:]))]
        if roots:
            k = min(roots, key=lambda i: within[i])
            est = float(scan[k] + (scan[k + 1] - scan[k]) * delta[k] / (delta[k] - delta[k + 1]))
            best = k if abs(delta[k]) <= abs(delta[k + 1]) else k + 1
        else:
            best = int(np.argmin(np.abs(delta)))
            est = float(scan[best])
        df = float(ev["df"][best])
        statistic, method, scale = "level t", "level t-test over recordings", 1.0
        slope = float(np.gradient(logp.mean(axis=1), scan)[best])
        ref_sd = math.sqrt(var_ref) / abs(slope) if var_ref and slope else 0.0

    accepted = excess <= 0
    pieces = []
    for a_i, b_i in _runs(accepted):
        lo = scan[0] if a_i == 0 else _crossing(scan, excess, a_i - 1, a_i)
        hi = scan[-1] if b_i == scan.size - 1 else _crossing(scan, excess, b_i, b_i + 1)
        pieces.append((math.exp(lo), math.exp(hi)))
    at_bound = bool(accepted[0] or accepted[-1] or best in (0, scan.size - 1))
    determined = bool(pieces) and not at_bound
    e_lo, e_hi = math.exp(scan[0]), math.exp(scan[-1])
    note = ""
    if not pieces:
        note = (f"no E_s in {e_lo / 1e6:.3g}-{e_hi / 1e6:.3g} MPa reproduces the measured "
                f"{'shape' if fit_scale else 'level'} of mu/mu_ref with this micro-model: E_s not determined")
    elif accepted[0] and accepted[-1]:
        note = f"E_s not determined: every E_s in {e_lo / 1e6:.3g}-{e_hi / 1e6:.3g} MPa fits the data"
    elif accepted[-1]:
        note = (f"E_s not determined: only a lower bound, E_s > {pieces[0][0] / 1e6:.3g} MPa "
                f"(the accepted set reaches the search bound {e_hi / 1e6:.3g} MPa)")
    elif accepted[0]:
        note = (f"E_s not determined: only an upper bound, E_s < {pieces[-1][1] / 1e6:.3g} MPa "
                f"(the accepted set reaches the search bound {e_lo / 1e6:.3g} MPa)")
    elif best in (0, scan.size - 1):
        note = "E_s not determined: the best fit lies at a search bound"
    if len(pieces) > 1 and not note:
        note = f"the data allow {len(pieces)} separate ranges of E_s"
    hull = (pieces[0][0], pieces[-1][1]) if pieces else (math.nan, math.nan)
    deff = design_effect(R[best] - R[best].mean(), inv) if g < n else 1.0
    return ModulusFit(
        skin_modulus=math.exp(est), ci_low=hull[0], ci_high=hull[1], profile_ci=hull, reference_sd=ref_sd,
        design_effect=deff, scale=scale, rss=float(within[best]) if fit_scale else float(np.sum(R[best] ** 2)),
        n=n, level=level, at_bound=at_bound, method=method, pieces=tuple(pieces), determined=determined,
        statistic=statistic, df=df, n_clusters=g, model=model_name, note=note, bounds=(e_lo, e_hi),
    )


def _as_table(model: Model | ModelTable, loads: np.ndarray, bounds: tuple[float, float], n_grid: int) -> ModelTable:
    if isinstance(model, ModelTable):
        if not model.covers(loads):
            raise FingerpadError("model table does not cover the loads of the data")
        return model
    return ModelTable(model, (float(loads.min()), float(loads.max())), bounds, n_loads=n_grid)


def _model_name(model: Any) -> str:
    inner = getattr(model, "model", model)
    geom = getattr(inner, "geometry", None)
    return str(getattr(geom, "micro_model", "")) if geom is not None else ""


def estimate_skin_modulus(
    loads: Sequence[float] | np.ndarray,
    mu_normalised: Sequence[float] | np.ndarray,
    model: Model | ModelTable,
    *,
    bounds: tuple[float, float] = (2e4, 2e7),
    level: float = 0.95,
    fit_scale: bool = False,
    log_residuals: bool = True,
    reference: Any = None,
    reference_design_effect: float = 1.0,
    clusters: Sequence[Any] | np.ndarray | None = None,
    n_grid: int = 32,
    model_name: str | None = None,
) -> ModulusFit:
    """Fit the skin micro-modulus E_s to normalised friction with an injected model.

    The estimate is the E_s where the mean residual ``ln mu_norm - ln model(F, E_s)`` over the
    recordings vanishes (or, with ``fit_scale``, where the within-recording shape fits best);
    the accepted set is every E_s the test of the module doc does not reject at ``1 - level``.

    Parameters
    ----------
    loads, mu_normalised
        Strokes' loads (N) and ``mu_tex / mu_ref``.
    model
        ``model(loads, skin_modulus) -> predicted mu_normalised`` (e.g. :func:`hertz_texture_model`),
        or a :class:`ModelTable` of it (shared between fits).
    bounds
        Search range of E_s, Pa.
    fit_scale
        Also fit an amplitude ``c`` (absorbs a shear-strength difference between samples); the
        information then comes from the shape of the curve alone.
    log_residuals
        Residuals of ``ln mu`` (multiplicative scatter, the default) or of ``mu``.
    reference
        The reference power law used to normalise (a :class:`fingerpad.friction.PowerLaw`,
        or any fit with ``log_covariance`` and ``dof``): the error of its level shifts every
        mu_norm alike and is added to the level test.
    reference_design_effect
        Variance inflation of a reference fit that ignored recordings (``log_covariance`` only).
    clusters
        Recording (session) of each point; ``None``: independent points.
    n_grid
        Loads in the model table (when ``model`` is a callable).
    model_name
        Label of the micro-model in the result (default: the model's ``geometry.micro_model``).

    Returns
    -------
    ModulusFit

    Raises
    ------
    FingerpadError
        For invalid data or bounds, or a model returning the wrong shape or non-finite values.
    """
    f, v = fit_inputs(loads, mu_normalised, "skin modulus fit", "values", distinct=False)
    table = _as_table(model, f, bounds, n_grid)
    labels = None if clusters is None else np.asarray(clusters, dtype=object).ravel()
    if labels is not None and labels.size != f.size:
        raise FingerpadError(f"skin modulus fit: {labels.size} cluster labels for {f.size} points")
    return _infer([(f, v, table)], level=level, fit_scale=fit_scale, log_residuals=log_residuals,
                  reference=reference, reference_design_effect=reference_design_effect, clusters=labels,
                  model_name=model_name if model_name is not None else _model_name(model))


def estimate_skin_modulus_joint(
    datasets: Sequence[tuple[Sequence[float] | np.ndarray, Sequence[float] | np.ndarray, Model | ModelTable]],
    *,
    bounds: tuple[float, float] = (2e4, 2e7),
    level: float = 0.95,
    fit_scale: bool = False,
    log_residuals: bool = True,
    reference: Any = None,
    reference_design_effect: float = 1.0,
    clusters: Sequence[Sequence[Any] | np.ndarray] | None = None,
    n_grid: int = 32,
    model_name: str | None = None,
) -> ModulusFit:
    """One E_s fitted to several textures of one participant: ``datasets = [(loads, mu_norm, model), ...]``.

    Arguments as for :func:`estimate_skin_modulus`; ``clusters`` holds one label array per data
    set (labels of different data sets are kept apart).
    """
    if not datasets:
        raise FingerpadError("joint skin modulus fit: no data sets")
    checked = []
    for f, v, mdl in datasets:
        ff, vv = fit_inputs(f, v, "skin modulus fit", "values", distinct=False)
        checked.append((ff, vv, _as_table(mdl, ff, bounds, n_grid)))
    labels = None
    if clusters is not None:
        labels = np.concatenate([np.array([f"{i}:{c}" for c in np.asarray(cl, dtype=object).ravel()], dtype=object)
                                 for i, cl in enumerate(clusters)])
        if labels.size != sum(f.size for f, _, _ in checked):
            raise FingerpadError("joint skin modulus fit: cluster labels do not match the data")
    names = sorted({_model_name(mdl) for _, _, mdl in datasets} - {""})
    return _infer(checked, level=level, fit_scale=fit_scale, log_residuals=log_residuals,
                  reference=reference, reference_design_effect=reference_design_effect, clusters=labels,
                  model_name=model_name if model_name is not None else "+".join(names))
