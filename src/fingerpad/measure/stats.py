"""Statistics that respect grouping: strokes of one recording (session) share its skin state.

Strokes from one recording share skin moisture, posture and sensor set-up, so they are not
independent: treating them as such makes intervals far too narrow (issue 10: 40 % coverage of a
nominal 95 % interval with 5-10 % session-to-session variation). Every interval of the
measurement analysis therefore comes from one of these models:

* :func:`random_intercept_fit` - linear model with a random intercept per cluster (recording or
  session), ``y_ij = x_ij' beta + u_j + e_ij``, ``u_j ~ N(0, s_b^2)``, ``e_ij ~ N(0, s^2)``,
  fitted by restricted maximum likelihood (REML); fixed effects by generalised least squares.
  Degrees of freedom by the between-within rule: a contrast that draws on levels compared
  across clusters has ``G - p_b`` (G clusters), one that draws only on variation inside the
  clusters has ``N - G - p_w``; Student-t intervals. In a balanced design this is the exact
  t-test on cluster means for the level, and at worst conservative.
* :func:`cluster_mean` - a mean with a cluster-robust (CR1) standard error, ``G - 1`` df.

The REML here is our own (one variance ratio, profiled with closed-form cluster sums); the
tests check it against :mod:`statsmodels`' ``MixedLM``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import optimize, special, stats

from ..errors import FingerpadError

__all__ = ["ClusterFit", "cluster_labels", "cluster_mean", "random_intercept_fit", "t_quantile"]


def t_quantile(level: float, df: float) -> float:
    """Two-sided Student-t quantile ``t_{df}(1/2 + level/2)`` (normal for infinite df)."""
    if not math.isfinite(df):
        return float(stats.norm.ppf(0.5 + level / 2.0))
    # scipy.stats.t.ppf's own function, without its argument checks (df > 0 here)
    return float(special.stdtrit(max(df, 1e-3), 0.5 + level / 2.0))


def cluster_labels(clusters: Sequence[Any] | np.ndarray | None, n: int) -> np.ndarray:
    """Integer cluster index (0..G-1) of each of ``n`` points; every point its own without labels."""
    if clusters is None:
        return np.arange(n)
    arr = np.asarray(clusters, dtype=object).ravel()
    if arr.size != n:
        raise FingerpadError(f"{arr.size} cluster labels for {n} points")
    _, inv = np.unique(arr.astype(str), return_inverse=True)
    return inv.ravel()


@dataclass(frozen=True)
class ClusterFit:
    """A random-intercept linear model fitted by REML (see module doc).

    Attributes
    ----------
    coef
        Fixed effects beta (GLS at the REML variance ratio).
    cov
        Their covariance ``s^2 (X' H^-1 X)^-1``.
    sigma2, sigma2_between
        Within-cluster (stroke) and between-cluster (session) variances.
    n, n_clusters
        Points and clusters.
    between
        Per coefficient: True when its information comes from comparing cluster levels (the
        intercept, and covariates that barely vary inside the clusters).
    df_between, df_within
        ``G - p_b`` and ``N - G - p_w`` (at least 1).
    note
        Why the grouping could not be used (e.g. a single recording), else empty.
    """

    coef: np.ndarray
    cov: np.ndarray
    sigma2: float
    sigma2_between: float
    n: int
    n_clusters: int
    between: tuple[bool, ...]
    df_between: float
    df_within: float
    note: str = ""
    residuals: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)

    def df(self, contrast: Sequence[float] | np.ndarray) -> float:
        """Degrees of freedom of ``contrast' beta``: between-cluster if it uses any between
        coefficient (conservative), else within."""
        c = np.asarray(contrast, dtype=float)
        uses_between = any(abs(ci) > 0 and b for ci, b in zip(c, self.between))
        return self.df_between if uses_between else self.df_within

    def estimate(self, contrast: Sequence[float] | np.ndarray) -> tuple[float, float, float]:
        """``(value, standard error, df)`` of ``contrast' beta``."""
        c = np.asarray(contrast, dtype=float)
        return float(c @ self.coef), float(math.sqrt(max(c @ self.cov @ c, 0.0))), self.df(c)

    def interval(self, contrast: Sequence[float] | np.ndarray, level: float = 0.95) -> tuple[float, float]:
        """Student-t interval of ``contrast' beta`` at ``level``."""
        value, se, df = self.estimate(contrast)
        q = t_quantile(level, df)
        return value - q * se, value + q * se


def _sums(values: np.ndarray, inv: np.ndarray, g: int) -> np.ndarray:
    """Cluster sums of a vector (G,) or of the columns of a matrix (G, p)."""
    if values.ndim == 1:
        return np.bincount(inv, weights=values, minlength=g)
    return np.column_stack([np.bincount(inv, weights=values[:, j], minlength=g) for j in range(values.shape[1])])


def random_intercept_fit(
    y: Sequence[float] | np.ndarray,
    X: np.ndarray,
    clusters: Sequence[Any] | np.ndarray | None,
    *,
    between_fraction: float = 0.5,
) -> ClusterFit:
    """Fit ``y = X beta + u_cluster + e`` by REML (random intercept per cluster).

    With ``H = V / s^2`` block-diagonal, ``H_j = I + gamma J`` (``gamma = s_b^2 / s^2``), every
    quantity reduces to cluster sums: ``H_j^-1 = I - w_j J`` with ``w_j = gamma / (1 + gamma m_j)``.
    The restricted log-likelihood, profiled over ``s^2``,

        ``l_R(gamma) = -1/2 [(N - p) log s^2 + sum_j log(1 + gamma m_j) + log det X'H^-1 X]``,

    is maximised over ``gamma >= 0`` (grid in ``log gamma``, then bounded Brent).

    Parameters
    ----------
    y
        Responses (N,).
    X
        Design (N, p), full column rank.
    clusters
        Cluster label per point (``None``: independent points, ordinary least squares).
    between_fraction
        A covariate counts as a between-cluster effect when at least this fraction of its
        sum of squares (about its mean) lies between the cluster means.

    Raises
    ------
    FingerpadError
        For too few points or a rank-deficient design.
    """
    yy = np.asarray(y, dtype=float).ravel()
    XX = np.asarray(X, dtype=float)
    if XX.ndim == 1:
        XX = XX[:, None]
    n, p = XX.shape
    if yy.size != n:
        raise FingerpadError(f"{yy.size} responses for {n} design rows")
    if n <= p:
        raise FingerpadError(f"need more than {p} points, got {n}")
    if np.linalg.matrix_rank(XX) < p:
        raise FingerpadError("the design is rank-deficient (e.g. all loads equal)")
    inv = cluster_labels(clusters, n)
    g = int(inv.max()) + 1
    m = np.bincount(inv, minlength=g).astype(float)
    # between or within: where does each covariate's variation lie?
    between = []
    for j in range(p):
        col = XX[:, j]
        total = float(np.sum((col - col.mean()) ** 2))
        if total <= 1e-14 * max(1.0, float(np.sum(col**2))):
            between.append(True)  # the intercept (a constant) is a level
            continue
        means = _sums(col, inv, g) / m
        between.append(float(np.sum(m * (means - col.mean()) ** 2)) >= between_fraction * total)
    p_b = sum(between)
    note = ""
    if g == n or g == 1:
        # no grouping (every point its own cluster), or a single cluster: ordinary least squares
        coef, *_ = np.linalg.lstsq(XX, yy, rcond=None)
        r = yy - XX @ coef
        s2 = float(r @ r) / (n - p)
        cov = s2 * np.linalg.inv(XX.T @ XX)
        if g == 1 and clusters is not None:
            note = "one recording: the interval cannot include session-to-session variation"
        df = float(n - p)
        return ClusterFit(coef, cov, s2, 0.0, n, g, tuple(between), df, df, note, r)
    reml = _Reml(_sums(XX, inv, g), _sums(yy, inv, g), m, XX.T @ XX, XX.T @ yy, float(yy @ yy), n, p)
    grid = np.r_[0.0, np.exp(np.linspace(-12.0, 9.0, 22))]
    lls = reml.log_likelihoods(grid)
    i = int(np.argmax(lls))
    gamma = float(grid[i])
    if 0 < i < grid.size - 1:
        lo, hi = math.log(max(grid[i - 1], 1e-12)), math.log(grid[i + 1])
        res = optimize.minimize_scalar(lambda t: -reml.solve(math.exp(t))[0], bounds=(lo, hi), method="bounded",
                                       options={"xatol": 1e-5})
        if -res.fun >= lls[i]:
            gamma = math.exp(float(res.x))
    _, beta, A, s2 = reml.solve(gamma)
    cov = s2 * np.linalg.inv(A)
    df_b = float(max(g - p_b, 1))
    df_w = float(max(n - g - (p - p_b), 1))
    r = yy - XX @ beta
    return ClusterFit(beta, cov, s2, gamma * s2, n, g, tuple(between), df_b, df_w, note, r)


@dataclass(frozen=True)
class _Reml:
    """The cluster sums of :func:`random_intercept_fit` and its profiled restricted
    log-likelihood at a variance ratio ``gamma`` (:meth:`solve`), or at many at once
    (:meth:`log_likelihoods`, the same numbers bit for bit: the same products, solves and sums
    row by row, the logarithm of ``s^2`` by ``math.log`` as in :meth:`solve`)."""

    Sx: np.ndarray  # (G, p) cluster sums of the design
    Sy: np.ndarray  # (G,) cluster sums of the response
    m: np.ndarray  # (G,) cluster sizes
    XtX: np.ndarray
    Xty: np.ndarray
    yty: float
    n: int
    p: int

    def solve(self, gamma: float) -> tuple[float, np.ndarray, np.ndarray, float]:
        """``(l_R, beta, X'H^-1X, s^2)`` at ``gamma``."""
        Sx, Sy, m, n, p = self.Sx, self.Sy, self.m, self.n, self.p
        w = gamma / (1.0 + gamma * m)
        A = self.XtX - (Sx * w[:, None]).T @ Sx
        b = self.Xty - Sx.T @ (w * Sy)
        beta = np.linalg.solve(A, b)
        q = max(self.yty - float(np.sum(w * Sy**2)) - float(b @ beta), 1e-300)
        s2 = q / (n - p)
        sign, logdet = np.linalg.slogdet(A)
        ll = -0.5 * ((n - p) * math.log(s2) + float(np.sum(np.log1p(gamma * m))) + logdet)
        return ll, beta, A, s2

    def log_likelihoods(self, gammas: np.ndarray) -> np.ndarray:
        """``l_R`` at every ``gamma`` of ``gammas``: ``[solve(g)[0] for g in gammas]`` in one
        pass of stacked products and solves (a fit's grid of 23 ratios: ~5x less time)."""
        Sx, Sy, m, n, p = self.Sx, self.Sy, self.m, self.n, self.p
        gam = np.asarray(gammas, dtype=float)
        w = gam[:, None] / (1.0 + gam[:, None] * m[None, :])  # (k, G)
        A = self.XtX[None] - np.matmul((Sx[None] * w[:, :, None]).transpose(0, 2, 1), Sx[None])  # (k, p, p)
        b = self.Xty[None] - np.matmul(Sx.T[None], (w * Sy[None])[:, :, None])[:, :, 0]  # (k, p)
        beta = np.linalg.solve(A, b[:, :, None])[:, :, 0]
        wsy = np.sum(w * Sy[None] ** 2, axis=1)
        _, logdet = np.linalg.slogdet(A)
        logs = np.sum(np.log1p(gam[:, None] * m[None, :]), axis=1)
        out = np.empty(gam.size)
        for k in range(gam.size):
            q = max(self.yty - float(wsy[k]) - float(b[k] @ beta[k]), 1e-300)
            out[k] = -0.5 * ((n - p) * math.log(q / (n - p)) + float(logs[k]) + float(logdet[k]))
        return out


def cluster_mean(values: Sequence[float] | np.ndarray, clusters: Sequence[Any] | np.ndarray | None,
                 level: float = 0.95) -> tuple[float, float, float, float]:
    """Mean with a cluster-robust (CR1) standard error: ``(mean, se, ci_low, ci_high)``.

    ``se^2 = G / (G - 1) sum_j (sum_{i in j} (y_i - ybar))^2 / N^2``, interval with ``G - 1``
    df. NaN standard error and interval for fewer than two clusters.
    """
    v = np.asarray(values, dtype=float).ravel()
    n = v.size
    if n == 0:
        return math.nan, math.nan, math.nan, math.nan
    mean = float(v.mean())
    inv = cluster_labels(clusters, n)
    g = int(inv.max()) + 1
    if g < 2:
        return mean, math.nan, math.nan, math.nan
    s = np.bincount(inv, weights=v - mean, minlength=g)
    se = math.sqrt(g / (g - 1) * float(np.sum(s**2))) / n
    q = t_quantile(level, g - 1)
    return mean, se, mean - q * se, mean + q * se
