"""The skin micro-modulus E_s from friction: model fits with profile intervals, closed form from the transition (Eq. 3.6)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import optimize, stats

from ..errors import FingerpadError
from ..materials import DEFAULT_SKIN_POISSON, reduced_modulus
from .models import Model, TextureGeometry


@dataclass(frozen=True)
class ModulusFit:
    """Least-squares skin modulus E_s and its confidence interval.

    Attributes
    ----------
    skin_modulus
        Best E_s, Pa.
    ci_low, ci_high
        Interval at ``level``: the profile-likelihood interval, widened (in ``log E_s``, in
        quadrature) by the uncertainty of the reference curve when one was given. A bound of
        the search range when the profile does not rise far enough there (``at_bound``).
    profile_ci
        The profile-likelihood interval alone (data scatter only).
    reference_sd
        Standard deviation of ``log E_s`` due to the reference curve (delta method; 0 without).
    design_effect
        Variance inflation for strokes clustered in files (1 without ``clusters``): strokes
        of one session share its skin condition, so they carry less than independent weight.
    scale
        Fitted amplitude factor (1 unless ``fit_scale``).
    rss
        Residual sum of squares (of log residuals when ``log_residuals``).
    n
        Number of points.
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
    method: str = "profile likelihood"


def _check_xy(loads: Any, values: Any, what: str) -> tuple[np.ndarray, np.ndarray]:
    f = np.asarray(loads, dtype=float).ravel()
    v = np.asarray(values, dtype=float).ravel()
    if f.shape != v.shape:
        raise FingerpadError(f"{what}: loads and values differ in length ({f.size} vs {v.size})")
    if f.size < 3:
        raise FingerpadError(f"{what}: need at least 3 points, got {f.size}")
    if not (np.all(np.isfinite(f)) and np.all(f > 0) and np.all(np.isfinite(v)) and np.all(v > 0)):
        raise FingerpadError(f"{what}: loads and values must be positive and finite")
    return f, v


class ModelTable:
    """A model tabulated on a grid of skin moduli and loads, interpolated in between.

    The model (a disc integral per load) is the costly part of a fit; tabulating it once per
    texture -- ``n_moduli`` log-spaced E_s in ``bounds`` times ``n_loads`` log-spaced loads in
    ``load_range`` -- makes every fit, profile and participant that shares the texture nearly
    free. Interpolation: cubic spline in ``log E_s``, linear in ``log F`` of ``log model``.

    Parameters
    ----------
    model
        ``model(loads, skin_modulus) -> mu_normalised``.
    load_range
        (lowest, highest) load to cover, N.
    bounds
        (lowest, highest) skin modulus, Pa.
    n_loads, n_moduli
        Grid sizes.

    Raises
    ------
    FingerpadError
        For bad ranges, or a model returning the wrong shape, non-finite or non-positive values.
    """

    def __init__(
        self,
        model: Model,
        load_range: tuple[float, float],
        bounds: tuple[float, float] = (2e4, 2e7),
        *,
        n_loads: int = 32,
        n_moduli: int = 49,
    ) -> None:
        from scipy.interpolate import CubicSpline

        lo, hi = (float(v) for v in load_range)
        e_lo, e_hi = (float(v) for v in bounds)
        if not (0 < e_lo < e_hi and math.isfinite(e_hi)):
            raise FingerpadError(f"modulus bounds must satisfy 0 < low < high, got {bounds!r}")
        if not (0 < lo <= hi and math.isfinite(hi)):
            raise FingerpadError(f"load range must be positive, got {load_range!r}")
        if hi <= lo * 1.001:  # a single load: widen a little so interpolation is defined
            lo, hi = lo / 1.01, hi * 1.01
        self.model = model
        self.bounds = (e_lo, e_hi)
        self.loads = np.geomspace(lo, hi, int(n_loads))
        self.log_moduli = np.linspace(math.log(e_lo), math.log(e_hi), int(n_moduli))
        rows = []
        for le in self.log_moduli:
            curve = np.asarray(model(self.loads, math.exp(le)), dtype=float)
            if curve.shape != self.loads.shape or not np.all(np.isfinite(curve)) or np.any(curve <= 0):
                raise FingerpadError(
                    f"model returned {curve.shape} values for {self.loads.size} loads at "
                    f"E_s = {math.exp(le):.4g} Pa (need positive finite values)"
                )
            rows.append(np.log(curve))
        self.table = np.array(rows)
        self._spline = CubicSpline(self.log_moduli, self.table, axis=0)

    def covers(self, loads: np.ndarray) -> bool:
        """Whether ``loads`` lie inside the tabulated range."""
        return bool(np.min(loads) >= self.loads[0] * (1 - 1e-9) and np.max(loads) <= self.loads[-1] * (1 + 1e-9))

    def log_predict(self, loads: np.ndarray, log_modulus: float) -> np.ndarray:
        """``log model(loads, exp(log_modulus))`` by interpolation."""
        row = self._spline(float(np.clip(log_modulus, self.log_moduli[0], self.log_moduli[-1])))
        return np.interp(np.log(loads), np.log(self.loads), row)

    def __call__(self, loads: np.ndarray, skin_modulus: float) -> np.ndarray:
        """Interpolated ``model(loads, skin_modulus)``."""
        return np.exp(self.log_predict(np.asarray(loads, dtype=float), math.log(skin_modulus)))


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


def _reference_shift_var(reference: Any, loads: np.ndarray) -> float:
    """Variance of the mean log-level error of a fitted reference power law over ``loads``."""
    cov = getattr(reference, "log_covariance", None)
    if cov is None:
        return 0.0
    v = np.array([1.0, float(np.mean(np.log(loads)))])
    return float(max(v @ np.asarray(cov, dtype=float) @ v, 0.0))


def _profile_fit(
    datasets: Sequence[tuple[np.ndarray, np.ndarray, ModelTable]],
    *,
    level: float,
    fit_scale: bool,
    log_residuals: bool,
    reference: Any = None,
    reference_design_effect: float = 1.0,
    clusters: np.ndarray | None = None,
) -> ModulusFit:
    if not 0 < level < 1:
        raise FingerpadError(f"level must lie in (0, 1), got {level!r}")
    ys = np.concatenate([v for _, v, _ in datasets])
    n = ys.size
    grid = datasets[0][2].log_moduli
    lo_b = max(t.log_moduli[0] for _, _, t in datasets)
    hi_b = min(t.log_moduli[-1] for _, _, t in datasets)

    def log_pred(log_e: float) -> np.ndarray:
        return np.concatenate([t.log_predict(f, log_e) for f, _, t in datasets])

    def rss_and_scale(log_e: float) -> tuple[float, float]:
        lp = log_pred(log_e)
        if log_residuals:
            r = np.log(ys) - lp
            shift = float(r.mean()) if fit_scale else 0.0
            return float(np.sum((r - shift) ** 2)), math.exp(shift)
        ps = np.exp(lp)
        scale = float(ys @ ps / (ps @ ps)) if fit_scale else 1.0
        r = ys - scale * ps
        return float(r @ r), scale

    def rss(log_e: float) -> float:
        return rss_and_scale(log_e)[0]

    scan = grid[(grid >= lo_b) & (grid <= hi_b)]
    values = np.array([rss(s) for s in scan])
    i = int(np.argmin(values))
    a, b = scan[max(i - 1, 0)], scan[min(i + 1, scan.size - 1)]
    res = optimize.minimize_scalar(rss, bounds=(a, b), method="bounded", options={"xatol": 1e-5})
    best = float(res.x) if res.fun <= values[i] else float(scan[i])
    rss_min, scale = rss_and_scale(best)
    threshold = stats.chi2.ppf(level, 1)
    deff = 1.0
    if clusters is not None:
        deff = design_effect(np.log(ys) - log_pred(best), clusters)
    n_eff = n / deff

    def excess(log_e: float) -> float:
        return n_eff * math.log(max(rss(log_e), 1e-300) / max(rss_min, 1e-300)) - threshold

    def edge(step: int) -> tuple[float, bool]:
        # walk outward from the best point until the profile crosses the threshold
        inner, j = best, i
        while 0 <= j + step < scan.size:
            j += step
            if (scan[j] - best) * step <= 0:
                continue
            if excess(scan[j]) > 0:
                return float(optimize.brentq(excess, min(inner, scan[j]), max(inner, scan[j]), xtol=1e-6)), False
            inner = scan[j]
        return float(scan[0] if step < 0 else scan[-1]), True

    lo, lo_hit = edge(-1)
    hi, hi_hit = edge(+1)
    ref_sd = 0.0
    if reference is not None and not fit_scale:
        # delta method: a reference curve off by d(log mu_ref) shifts every mu_norm by -d, which
        # moves log E_s by d / (d mean log model / d log E_s)
        h = 0.01
        slope = float(np.mean(log_pred(best + h) - log_pred(best - h)) / (2 * h))
        var = _reference_shift_var(reference, np.concatenate([f for f, _, _ in datasets]))
        var *= max(float(reference_design_effect), 1.0)
        ref_sd = math.sqrt(var) / abs(slope) if slope != 0 else math.inf
    z = stats.norm.ppf(0.5 + level / 2.0)
    lo_all = best - math.hypot(best - lo, z * ref_sd)
    hi_all = best + math.hypot(hi - best, z * ref_sd)
    return ModulusFit(
        skin_modulus=math.exp(best), ci_low=math.exp(max(lo_all, scan[0])), ci_high=math.exp(min(hi_all, scan[-1])),
        profile_ci=(math.exp(lo), math.exp(hi)), reference_sd=ref_sd, design_effect=deff, scale=scale, rss=rss_min, n=n,
        level=level, at_bound=bool(lo_hit or hi_hit or best <= scan[0] + 1e-9 or best >= scan[-1] - 1e-9),
        method="profile likelihood" + (" + reference delta method" if ref_sd else ""),
    )


def _as_table(model: Model | ModelTable, loads: np.ndarray, bounds: tuple[float, float], n_grid: int) -> ModelTable:
    if isinstance(model, ModelTable):
        if not model.covers(loads):
            raise FingerpadError("model table does not cover the loads of the data")
        return model
    return ModelTable(model, (float(loads.min()), float(loads.max())), bounds, n_loads=n_grid)


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
) -> ModulusFit:
    """Fit the skin micro-modulus E_s to normalised friction with an injected model.

    Minimises ``sum (log y - log(c model(F, E_s)))^2`` (or linear residuals) over ``log E_s``
    in ``bounds`` (grid scan, then bounded Brent). The interval is the set of E_s with
    ``n log(RSS/RSS_min) <= chi2_1(level)`` (profile likelihood: noise variance and ``c``
    profiled out), widened by the reference curve's uncertainty when ``reference`` is given.

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
        Also fit an amplitude ``c`` (absorbs a shear-strength difference between samples);
        otherwise ``c = 1`` as MODEL.md's normalisation assumes the same tau.
    log_residuals
        Residuals of ``log mu`` (multiplicative scatter, the default) or of ``mu``.
    reference
        The reference power-law fit used to normalise (with ``log_covariance``, as from
        :func:`fingerpad.friction.fit_power_law`): its uncertainty is propagated into the interval.
    reference_design_effect
        Variance inflation of the reference fit for strokes clustered in files
        (:func:`design_effect` of its residuals by file).
    clusters
        Cluster label (e.g. file) of each point: the profile uses ``n / design_effect``
        effective points, so session-to-session variation widens the interval.
    n_grid
        Loads in the model table (when ``model`` is a callable).

    Returns
    -------
    ModulusFit

    Raises
    ------
    FingerpadError
        For invalid data or bounds, or a model returning the wrong shape or non-finite values.
    """
    f, v = _check_xy(loads, mu_normalised, "skin modulus fit")
    table = _as_table(model, f, bounds, n_grid)
    labels = None if clusters is None else np.asarray(clusters).ravel()
    if labels is not None and labels.size != f.size:
        raise FingerpadError(f"skin modulus fit: {labels.size} cluster labels for {f.size} points")
    return _profile_fit([(f, v, table)], level=level, fit_scale=fit_scale, log_residuals=log_residuals,
                        reference=reference, reference_design_effect=reference_design_effect, clusters=labels)


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
) -> ModulusFit:
    """One E_s fitted to several textures of one participant: ``datasets = [(loads, mu_norm, model), ...]``.

    Arguments as for :func:`estimate_skin_modulus`; ``clusters`` holds one label array per data set.
    """
    if not datasets:
        raise FingerpadError("joint skin modulus fit: no data sets")
    checked = []
    for f, v, m in datasets:
        ff, vv = _check_xy(f, v, "skin modulus fit")
        checked.append((ff, vv, _as_table(m, ff, bounds, n_grid)))
    labels = None
    if clusters is not None:
        labels = np.concatenate([np.asarray(c, dtype=object).ravel() for c in clusters])
        if labels.size != sum(f.size for f, _, _ in checked):
            raise FingerpadError("joint skin modulus fit: cluster labels do not match the data")
    return _profile_fit(checked, level=level, fit_scale=fit_scale, log_residuals=log_residuals,
                        reference=reference, reference_design_effect=reference_design_effect, clusters=labels)


def _ridge_area_of(ridge_area: float | Callable[[float], float] | Any, load: float) -> float:
    if hasattr(ridge_area, "ridge_area"):
        return float(ridge_area.ridge_area(load))
    if callable(ridge_area):
        return float(ridge_area(load))
    return float(ridge_area)


def modulus_from_transition(
    critical_load: float,
    radius: float,
    height: float,
    spacing: float,
    ridge_area: float | Callable[[float], float] | Any,
    *,
    skin_poisson: float = DEFAULT_SKIN_POISSON,
    material_modulus: float | None = None,
    material_poisson: float = 0.35,
) -> float:
    """Skin modulus E_s from the transition load, closed form (MODEL.md Eq. 3.6 and 3.4).

    ``F_crit = (8/9) E1* sqrt(h^3 R) A_fr / lambda^2`` gives
    ``E1* = 9 F_crit lambda^2 / (8 sqrt(h^3 R) A_fr(F_crit))``, and Eq. 3.4 solved for E_s:
    ``E_s = (1 - nu_s^2) / (1/E1* - (1 - nu_m^2)/E_m)``.

    Parameters
    ----------
    critical_load
        F_crit, N.
    radius, height, spacing
        Asperity radius R, height h and lattice spacing lambda, m.
    ridge_area
        A_fr in m^2: a number, a callable of the load, or a finger (``ridge_area(load)``).

    Raises
    ------
    FingerpadError
        For non-positive input, or if E1* exceeds what the counter-surface alone allows.
    """
    geometry = TextureGeometry(radius, height, spacing, material_modulus, material_poisson)
    if not (math.isfinite(critical_load) and critical_load > 0):
        raise FingerpadError(f"critical load must be positive, got {critical_load!r}")
    a_fr = _ridge_area_of(ridge_area, critical_load)
    if not a_fr > 0:
        raise FingerpadError(f"ridge area must be positive, got {a_fr!r}")
    e1 = 9.0 * critical_load * spacing**2 / (8.0 * math.sqrt(height**3 * radius) * a_fr)
    compliance = 1.0 / e1
    if geometry.material_modulus is not None:
        compliance -= (1.0 - material_poisson**2) / geometry.material_modulus
    if compliance <= 0:
        raise FingerpadError(
            f"transition at {critical_load:.4g} N implies E1* = {e1:.4g} Pa, stiffer than the counter-surface allows"
        )
    return (1.0 - skin_poisson**2) / compliance


def transition_load(
    skin_modulus: float,
    radius: float,
    height: float,
    spacing: float,
    ridge_area: float | Callable[[float], float] | Any,
    *,
    skin_poisson: float = DEFAULT_SKIN_POISSON,
    material_modulus: float | None = None,
    material_poisson: float = 0.35,
    bracket: tuple[float, float] = (1e-6, 1e4),
) -> float:
    """Transition load F_crit for a skin modulus: Eq. 3.6 solved for F with A_fr(F).

    The inverse of :func:`modulus_from_transition`.

    Raises
    ------
    FingerpadError
        If no load in ``bracket`` satisfies Eq. 3.6.
    """
    e1 = reduced_modulus(skin_modulus, skin_poisson, material_modulus, material_poisson)
    TextureGeometry(radius, height, spacing)
    c = (8.0 / 9.0) * e1 * math.sqrt(height**3 * radius) / spacing**2

    def g(log_f: float) -> float:
        f = math.exp(log_f)
        return math.log(f) - math.log(c * _ridge_area_of(ridge_area, f))

    a, b = (math.log(x) for x in bracket)
    if g(a) * g(b) > 0:
        raise FingerpadError(f"no transition load within {bracket[0]:.3g}-{bracket[1]:.3g} N")
    return math.exp(optimize.brentq(g, a, b, xtol=1e-10))
