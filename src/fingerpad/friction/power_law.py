"""Power-law fits of friction against load, ``mu = k F^(n-1)`` (docs/model.md, section 3): the one
result type of every such fit and the least-squares fit of independent points (a helper module of
:mod:`fingerpad.friction`: it declares no friction law).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..checks import ArrayLike, as_loads, scalar_out
from ..errors import FingerpadError

__all__ = ["PowerLaw", "PowerLawFit", "fit_power_law"]


# ---------------------------------------------------------------------------------------------
# power-law fit mu = k F^(n-1)
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PowerLaw:
    """A fitted power law ``mu = k F^(n-1)``: the one result type of every power-law fit.

    :func:`fit_power_law` (independent points, least squares) and
    :func:`fingerpad.measure.fit_power_law_clustered` (a random intercept per recording) both
    return it; the attributes that only a clustered fit knows have neutral defaults.

    Attributes
    ----------
    k, n
        Best estimates (k in the units of mu at 1 N).
    k_stderr, n_stderr
        Standard errors (``k_stderr`` by the delta method, ``k * se(ln k)``).
    k_ci, n_ci
        Confidence intervals at ``level``. ``k_ci`` is ``exp`` of the interval of ``ln k``, hence
        asymmetric about ``k``.
    covariance
        2x2 covariance of ``(k, n)`` (delta method).
    log_covariance
        2x2 covariance of ``(ln k, n - 1)``, the fitted linear parameters.
    dof
        Degrees of freedom of the exponent's interval (points - 2 for least squares).
    absolute_sigma
        True when ``sigma`` was given and taken as absolute (normal intervals); False when the
        scatter was estimated from the residuals (Student t intervals).
    level
        Confidence level of ``k_ci`` and ``n_ci``.
    df_level
        Degrees of freedom of the level ``ln k`` (recordings minus one for a clustered fit;
        ``dof`` for least squares).
    n_clusters
        Recordings (sessions) in a clustered fit; 0 when every point was taken as independent.
    sigma_between, sigma_within
        Standard deviations of ``ln mu`` between recordings and between strokes (NaN unknown).
    note
        Caveat (e.g. one recording only), else empty.
    """

    k: float
    n: float
    k_stderr: float
    n_stderr: float
    k_ci: tuple[float, float]
    n_ci: tuple[float, float]
    covariance: np.ndarray
    log_covariance: np.ndarray
    dof: float
    absolute_sigma: bool = False
    level: float = 0.95
    df_level: float = math.nan
    n_clusters: int = 0
    sigma_between: float = math.nan
    sigma_within: float = math.nan
    note: str = ""

    def __post_init__(self) -> None:
        if math.isnan(self.df_level):  # least squares: the level has the residual df too
            object.__setattr__(self, "df_level", float(self.dof))

    def __call__(self, load: ArrayLike) -> float | np.ndarray:
        """Fitted ``mu`` at ``load`` (N, positive)."""
        f = as_loads(load, strict=True)
        return scalar_out(self.k * f ** (self.n - 1.0))

    def log_level(self, loads: ArrayLike) -> tuple[float, float, float]:
        """Mean fitted ``ln mu`` over ``loads`` (N), its standard error and degrees of freedom.

        A normalisation by this curve shifts every ``ln mu_norm`` by the error of this level.
        """
        f = as_loads(loads, strict=True)
        v = np.array([1.0, float(np.mean(np.log(f)))])
        value = math.log(self.k) + (self.n - 1.0) * v[1]
        se = math.sqrt(max(float(v @ self.log_covariance @ v), 0.0))
        return value, se, float(self.df_level)


#: The earlier name of :class:`PowerLaw` (kept: user code may refer to it).
PowerLawFit = PowerLaw


def fit_inputs(loads: ArrayLike, values: ArrayLike, what: str = "a power-law fit", name: str = "mu",
               distinct: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The inputs of a fit of ``values`` against ``loads`` (N) in log space, checked: the one check
    of :func:`fit_power_law`, the measurements' clustered power law and the skin-modulus fits.

    Returns the two arrays, flattened. ``distinct``: the loads must not all be equal (a slope is
    fitted).

    Raises
    ------
    FingerpadError
        Lengths that differ, fewer than 3 points, a value that is not positive and finite, or
        (with ``distinct``) all loads equal; naming ``what``.
    """
    f = np.asarray(loads, dtype=float).ravel()
    v = np.asarray(values, dtype=float).ravel()
    if f.shape != v.shape:
        raise FingerpadError(f"{what}: loads and {name} differ in length ({f.size} vs {v.size})")
    if f.size < 3:
        raise FingerpadError(f"{what} needs at least 3 points, got {f.size}")
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(v)) and np.all(f > 0) and np.all(v > 0)):
        raise FingerpadError(f"{what}: loads and {name} must be positive and finite (no zero, negative, NaN or "
                             "infinite value)")
    if distinct and np.ptp(np.log(f)) == 0:
        raise FingerpadError(f"{what} needs at least two different loads")
    return f, v


def fit_power_law(loads: ArrayLike, mu: ArrayLike, sigma: ArrayLike | None = None, *,
                  level: float = 0.95) -> PowerLaw:
    """Fit ``mu = k F^(n-1)`` by weighted least squares on ``ln mu = ln k + (n-1) ln F``.

    Why log-linear: the scatter of measured friction coefficients grows with their size
    (multiplicative noise), which a fit in log space treats as constant; it is then linear, so
    the estimate is unique and needs no starting guess. A given absolute ``sigma`` of mu is
    carried into log space to first order, ``sigma_ln = sigma / mu``, and used as absolute
    weights (normal 95 % intervals). Without ``sigma`` the log-space scatter is estimated from
    the residuals (``s^2 = RSS / (N - 2)``) and the intervals use Student's t with N - 2 degrees
    of freedom.

    Parameters
    ----------
    loads
        Normal loads F (N), positive.
    mu
        Friction coefficients, positive.
    sigma
        Optional standard deviations of ``mu`` (same shape), positive.
    level
        Confidence level of the intervals, in (0, 1).

    Returns
    -------
    PowerLaw

    Raises
    ------
    FingerpadError
        Fewer than 3 points, mismatched shapes, NaN/inf, non-positive values, or all loads equal.
    """
    from scipy import stats

    if not (isinstance(level, (int, float)) and 0 < level < 1):
        raise FingerpadError(f"level must lie in (0, 1), got {level!r}")
    f, m = fit_inputs(loads, mu)
    if sigma is not None:
        s = np.asarray(sigma, dtype=float).ravel()
        if s.shape != m.shape:
            raise FingerpadError(f"sigma and mu differ in length ({s.size} vs {m.size})")
        if not np.all(np.isfinite(s)) or np.any(s <= 0):
            raise FingerpadError("sigma must be finite and positive")
        s_log = s / m
    else:
        s_log = np.ones_like(m)

    x = np.log(f)
    y = np.log(m)
    design = np.column_stack([np.ones_like(x), x]) / s_log[:, None]
    rhs = y / s_log
    coef, *_ = np.linalg.lstsq(design, rhs, rcond=None)
    dof = f.size - 2
    cov = np.linalg.inv(design.T @ design)
    if sigma is None:
        resid = rhs - design @ coef
        cov = cov * float(resid @ resid) / dof  # dof >= 1: at least 3 points
        q = float(stats.t.ppf(0.5 + level / 2, dof))
    else:
        q = float(stats.norm.ppf(0.5 + level / 2))
    ln_k, slope = (float(c) for c in coef)
    se_lnk, se_n = (math.sqrt(max(v, 0.0)) for v in np.diag(cov))
    k = math.exp(ln_k)
    jac = np.diag([k, 1.0])  # d(k, n)/d(ln k, n - 1)
    return PowerLaw(
        k=k,
        n=slope + 1.0,
        k_stderr=k * se_lnk,
        n_stderr=se_n,
        k_ci=(math.exp(ln_k - q * se_lnk), math.exp(ln_k + q * se_lnk)),
        n_ci=(slope + 1.0 - q * se_n, slope + 1.0 + q * se_n),
        covariance=jac @ cov @ jac.T,
        log_covariance=cov,
        dof=dof,
        absolute_sigma=sigma is not None,
        level=level,
    )


