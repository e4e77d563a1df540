"""The change of trend in normalised friction: segmented (hinge) regression in log-log, with a
test that accounts for searching the location.

Why a test: under the documented transition physics the log-log slope of mu/mu_ref changes only
slightly at F_crit, so the best hinge on data without any transition still "finds" a
breakpoint somewhere, with a precise-looking profile interval. The breakpoint is therefore
reported only when the improvement of the best hinge over one straight line is larger than the
best improvement found on data simulated from the fitted straight line (a parametric bootstrap
of the supremum likelihood ratio, which is what searching the location does to the null
distribution). The simulations keep the grouping of strokes into recordings (random intercept
per recording), so session-to-session scatter cannot pass for a transition.

Why an edge: a hinge near either end of the load range has one segment drawn from a handful of
strokes over a narrow range of loads. Any curvature of the data (a smooth transition, the bend
of asperity contact at light loads) then makes such a hinge beat the straight line, and the test
fires at the lowest (or highest) loads whatever the true transition: on smooth-transition data
it fired at 0.21-0.49 N when the true transition was at 0.3-3 N. A change of trend is therefore
reported only where both segments have support: at least ``edge`` of the load range and of
the points on each side. A best location in the outer part is stated, with the reason, and
neither its load nor an E_s from it is reported as a transition.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from scipy import stats

from ..errors import FingerpadError
from .stats import cluster_labels, random_intercept_fit

#: Outer fraction of the load range (of ``log F`` in log space) at each end, and least fraction of
#: the points on each side, where a breakpoint is not reported (see :func:`find_breakpoint`).
EDGE_FRACTION = 0.2


@dataclass(frozen=True)
class Breakpoint:
    """A continuous two-segment (hinge) fit ``y = c + s1 min(x - x0, 0) + s2 max(x - x0, 0)``.

    ``x`` is ``log F`` and ``y`` ``log value`` when ``space == "log"``, else F and value.

    Attributes
    ----------
    detected
        True when the sup-likelihood-ratio test rejects one straight line at ``1 - level``.
    load
        The best breakpoint load F_b, N (also when not detected: then only a candidate).
    ci_low, ci_high
        Interval of F_b at ``level`` when detected (parametric bootstrap, or profile), never of
        zero width; NaN when not detected.
    slope_below, slope_above
        Segment slopes (in log space: local exponents of value vs load).
    level_at_break
        Fitted y at the breakpoint (the hinge height ``c``).
    rss, rss_line
        Residual sums of squares of the hinge and of one straight line.
    statistic
        ``n log(rss_line / rss)`` maximised over the admissible locations.
    p_value
        Its p-value from ``n_null`` simulations of the fitted straight line (with a random
        intercept per recording): ``(1 + #{LR* >= LR}) / (1 + n_null)``; the simulations stop
        early once 50 exceed LR (Besag-Clifford sequential p-value ``50 / n_null``).
    search_low, search_high
        The loads searched (at least ``min_side`` points on each side), N.
    at_edge
        The interval reaches the edge of the searched range.
    edge_low, edge_high
        The part of the load range where a transition can be reported (N): the outer
        ``edge`` of the range and of the points at each end lie outside it.
    outside
        The test rejected one straight line (``p < 1 - level``) but its best location lies
        outside ``edge_low``-``edge_high``: not reported (``detected`` is False).
    """

    load: float
    ci_low: float
    ci_high: float
    slope_below: float
    slope_above: float
    level_at_break: float
    rss: float
    rss_line: float
    p_value: float
    n: int
    space: str
    method: str
    level: float
    detected: bool = True
    statistic: float = math.nan
    n_null: int = 0  # simulations run
    search_low: float = math.nan
    search_high: float = math.nan
    at_edge: bool = False
    edge_low: float = math.nan
    edge_high: float = math.nan
    outside: bool = False

    def predict(self, loads: np.ndarray) -> np.ndarray:
        """The fitted hinge at ``loads`` (in value units)."""
        f = np.asarray(loads, dtype=float)
        x = np.log(f) if self.space == "log" else f
        x0 = math.log(self.load) if self.space == "log" else self.load
        y = self.level_at_break + self.slope_below * np.minimum(x - x0, 0) + self.slope_above * np.maximum(x - x0, 0)
        return np.exp(y) if self.space == "log" else y

    def describe(self, unit: str = "N") -> str:
        """One line for tables and reports."""
        rng = f"{self.search_low:.3g}-{self.search_high:.3g} {unit}"
        if self.outside:
            where = (f"outside {self.edge_low:.3g}-{self.edge_high:.3g} {unit} where both segments have support"
                     if math.isfinite(self.edge_low) else "where no location has support on both sides")
            return (f"no transition reported: the best change of trend, at {self.load:.3g} {unit} "
                    f"(p = {format_p(self.p_value, self.n_null)}), lies at the edge of the load range, {where} "
                    f"(too few strokes on one side to tell a transition from curvature)")
        if not self.detected:
            return f"no transition detected in {rng} (p = {format_p(self.p_value, self.n_null)})"
        return (f"transition at {self.load:.3g} {unit} [{self.ci_low:.3g}, {self.ci_high:.3g}] "
                f"(p = {format_p(self.p_value, self.n_null)})")


def format_p(p: float, n_null: int = 0) -> str:
    """A p-value for people: ``< 0.001`` at the resolution of the simulations."""
    if not math.isfinite(p):
        return "n/a"
    floor = 1.0 / (n_null + 1) if n_null else 0.0
    if floor and p <= floor * (1 + 1e-9):
        return f"< {max(floor * 1.0001, 1e-4):.2g}" if floor >= 1e-4 else "< 0.0001"
    return f"{p:.2g}" if p < 0.01 else f"{p:.2f}"


class _HingeBasis:
    """The hinge profile in closed form for many responses at once.

    On the span ``[1, x]`` the best continuous hinge at ``x0`` adds one regressor,
    ``h = max(x - x0, 0)``; with ``h_perp`` its part orthogonal to ``[1, x]`` and ``e`` the
    straight-line residual, ``RSS(x0) = RSS_line - (h_perp' e)^2 / |h_perp|^2`` and the slope
    change is ``(h_perp' e) / |h_perp|^2``. A matrix product then profiles every candidate
    location for every simulated data set.
    """

    def __init__(self, x: np.ndarray, grid: np.ndarray, base: np.ndarray | None = None) -> None:
        self.x, self.grid = x, grid
        Q, _ = np.linalg.qr(np.column_stack([np.ones_like(x), x]) if base is None else base)
        self.Q = Q
        H = np.maximum(x[:, None] - grid[None, :], 0.0)
        self.Hp = H - Q @ (Q.T @ H)
        self.norm2 = np.einsum("ij,ij->j", self.Hp, self.Hp)
        self.ok = self.norm2 > 1e-12 * max(float(self.norm2.max()), 1e-300)

    def residualise(self, Y: np.ndarray) -> np.ndarray:
        return Y - self.Q @ (self.Q.T @ Y)

    def gains(self, E: np.ndarray, trend: str) -> np.ndarray:
        """RSS reduction of the hinge at each grid point (rows) for each column of ``E``;
        ``-inf`` where the slope change has the wrong sign or the location is degenerate."""
        proj = self.Hp.T @ E
        gain = np.where(self.ok[:, None], proj**2 / np.where(self.ok, self.norm2, 1.0)[:, None], -np.inf)
        if trend == "steeper":
            gain = np.where(proj > 0, gain, -np.inf)
        elif trend == "flatter":
            gain = np.where(proj < 0, gain, -np.inf)
        return gain


def _hinge_grid(x: np.ndarray, min_side: int, n_grid: int) -> np.ndarray:
    """Candidate locations: ``n_grid`` evenly spaced between the ``min_side``-th points from
    each end, plus the data points themselves when they are fewer (a large study's strokes
    would only multiply the work: the profile is smooth between them)."""
    xs = np.sort(x)
    lo, hi = xs[min_side - 1], xs[-min_side]
    inner = xs[(xs >= lo) & (xs <= hi)]
    if inner.size > n_grid:
        inner = inner[:0]
    return np.unique(np.r_[np.linspace(lo, hi, n_grid), inner])


def _simulate(rng: np.random.Generator, inv: np.ndarray, s2: float, s2b: float, size: int) -> np.ndarray:
    """``size`` columns of noise with a random intercept per cluster (variances s2b, s2)."""
    n = inv.size
    g = int(inv.max()) + 1
    noise = math.sqrt(s2) * rng.standard_normal((n, size))
    if s2b > 0 and g < n:
        noise += math.sqrt(s2b) * rng.standard_normal((g, size))[inv]
    return noise


def find_breakpoint(
    loads: Sequence[float] | np.ndarray,
    values: Sequence[float] | np.ndarray,
    *,
    space: Literal["log", "linear"] = "log",
    method: Literal["profile", "bootstrap"] = "bootstrap",
    trend: Literal["any", "steeper", "flatter"] = "any",
    level: float = 0.95,
    n_boot: int = 200,
    n_null: int = 999,
    seed: int = 0,
    min_side: int = 3,
    n_grid: int = 200,
    clusters: Sequence[Any] | np.ndarray | None = None,
    edge: float = EDGE_FRACTION,
) -> Breakpoint:
    """Test for, and locate, a change of trend of ``values`` vs load (segmented regression).

    The hinge location ``x0`` maximises the likelihood ratio ``LR = n log(RSS_line / RSS(x0))``
    over a grid that leaves at least ``min_side`` points on each side. Its p-value is the share
    of ``n_null`` parametric-bootstrap data sets, simulated from the fitted straight line with
    a random intercept per cluster (recording) and refitted the same way, whose maximal LR is
    at least as large: the search over locations is part of the null distribution (a
    simulation form of Davies' test; the simulations stop once 50 of them exceed the observed
    LR, Besag and Clifford's sequential p-value). A breakpoint is ``detected`` when
    ``p < 1 - level``. With loads varied inside the recordings the hinge is fitted with a level
    per recording, so session offsets are projected out of the test.

    When detected, its interval is either

    * ``"bootstrap"`` (default): percentiles of ``x0`` refitted on ``n_boot`` data sets
      simulated from the fitted hinge (with the cluster effects), or
    * ``"profile"``: the ``x0`` with ``n_eff log(RSS(x0)/RSS_min) <= chi2_1(level)``, with
      ``n_eff`` the number of points divided by the design effect of the clusters;

    widened if need be to the neighbouring grid points, so that it never has zero width.

    A best location in the outer ``edge`` of the load range (of ``log F`` in log space), or with
    fewer than ``edge`` of the points on one side, is not reported even when the test rejects
    the straight line (``outside``): one segment there rests on a few strokes over a narrow
    range of loads, and the curvature of a smooth transition passes for a break (module doc).

    Parameters
    ----------
    loads, values
        Loads (N, > 0) and the quantity (e.g. normalised friction; > 0 in log space).
    space
        ``"log"`` (log-log, slopes are power-law exponents) or ``"linear"``.
    trend
        Admit only breakpoints where the curve gets ``"steeper"`` (the contact transition on a
        texture) or ``"flatter"``; ``"any"`` takes the largest change.
    clusters
        Recording (session) of each point; ``None``: independent points.
    edge
        Fraction in [0, 0.5) of the load range and of the points at each end where no
        breakpoint is reported (0: anywhere in the searched range).

    Raises
    ------
    FingerpadError
        For fewer than ``2 min_side + 1`` points, non-finite or non-positive input.
    """
    f = np.asarray(loads, dtype=float).ravel()
    v = np.asarray(values, dtype=float).ravel()
    if f.shape != v.shape:
        raise FingerpadError("loads and values must be 1-D arrays of the same length")
    if space not in ("log", "linear"):
        raise FingerpadError(f"space must be 'log' or 'linear', got {space!r}")
    if method not in ("profile", "bootstrap"):
        raise FingerpadError(f"method must be 'profile' or 'bootstrap', got {method!r}")
    if trend not in ("any", "steeper", "flatter"):
        raise FingerpadError(f"trend must be 'any', 'steeper' or 'flatter', got {trend!r}")
    if not 0 < level < 1:
        raise FingerpadError(f"level must lie in (0, 1), got {level!r}")
    if not 0 <= edge < 0.5:
        raise FingerpadError(f"edge must lie in [0, 0.5), got {edge!r}")
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(v)) and np.all(f > 0)):
        raise FingerpadError("breakpoint: loads must be positive and values finite")
    if space == "log" and np.any(v <= 0):
        raise FingerpadError("breakpoint: values must be positive for a log-log fit")
    n = f.size
    if n < 2 * min_side + 1 or np.unique(f).size < 2 * min_side:
        raise FingerpadError(f"breakpoint: need at least {2 * min_side + 1} points at distinct loads, got {n}")
    x = np.log(f) if space == "log" else f
    y = np.log(v) if space == "log" else v
    back = np.exp if space == "log" else (lambda t: t)
    grid = _hinge_grid(x, min_side, n_grid)
    inv = cluster_labels(clusters, n)
    n_cl = int(inv.max()) + 1
    # With loads varied inside the recordings, the hinge is fitted with a level per recording
    # (fixed effects): session-to-session offsets are projected out and the test statistic no
    # longer depends on their size. Otherwise one level, and the null simulations carry the
    # recordings' random intercepts.
    within = False
    if clusters is not None and 1 < n_cl < n:
        base = np.column_stack([(inv[:, None] == np.arange(n_cl)[None, :]).astype(float), x])
        within = n - n_cl - 2 >= max(5, min_side) and np.linalg.matrix_rank(base) == n_cl + 1
    basis = _HingeBasis(x, grid, base if within else None)
    e = basis.residualise(y)
    rss_line = float(e @ e)
    gain = basis.gains(e[:, None], trend)[:, 0]
    search = (float(back(grid[0])), float(back(grid[-1])))
    tiny = 1e-300
    levels = base[:, :-1] if within else np.ones((n, 1))
    if np.any(np.isfinite(gain)):
        i = int(np.argmax(gain))
        x0 = float(grid[i])
        rss_min = max(rss_line - float(gain[i]), 0.0)
        coef = _hinge_coef(x, y, x0, levels)
        lr = n * math.log(max(rss_line, tiny) / max(rss_min, tiny))
    else:  # the curve never turns the wanted way: the straight line is the best "hinge"
        i = grid.size // 2
        x0 = float(grid[i])
        slope = float(np.linalg.lstsq(np.column_stack([levels, x]), y, rcond=None)[0][-1])
        coef = _hinge_coef(x, y, x0, levels)
        coef[1:] = slope
        rss_min, lr = rss_line, 0.0

    # null distribution of the maximal LR: the fitted line plus cluster and stroke noise
    X0 = np.column_stack([np.ones_like(x), x])
    null = random_intercept_fit(y, X0, inv if clusters is not None else None)
    s2_null, s2b_null = null.sigma2, (0.0 if within else null.sigma2_between)
    rng = np.random.default_rng(seed)
    exceed, done = 0, 0
    for start in range(0, int(n_null), 250):  # blocks keep the memory small
        size = min(250, int(n_null) - start)
        E = basis.residualise(_simulate(rng, inv, s2_null, s2b_null, size))
        rss0 = np.einsum("ij,ij->j", E, E)
        best = np.max(basis.gains(E, trend), axis=0)
        best = np.where(np.isfinite(best), best, 0.0)
        lr_star = n * np.log(np.maximum(rss0, tiny) / np.maximum(rss0 - best, tiny))
        exceed += int(np.sum(lr_star >= lr * (1 - 1e-12)))
        done += size
        if exceed >= 50:  # Besag-Clifford sequential stop: p is clearly large, p = h / l
            break
    if exceed >= 50:
        p_value = exceed / done
    else:
        p_value = (1.0 + exceed) / (1.0 + done) if done else math.nan
    detected = bool(done and p_value < 1.0 - level)
    # where both segments have support: inside the outer `edge` of the range and of the points
    xs = np.sort(x)
    span = float(xs[-1] - xs[0])
    k = int(math.ceil(edge * n))
    edge_lo = max(float(xs[0]) + edge * span, float(xs[max(k - 1, 0)]) if k else -math.inf)
    edge_hi = min(float(xs[-1]) - edge * span, float(xs[n - k]) if k else math.inf)
    outside = bool(detected and not (edge_lo <= x0 <= edge_hi))
    detected = detected and not outside

    lo = hi = math.nan
    at_edge = False
    if detected:
        step_lo = grid[max(i - 1, 0)]
        step_hi = grid[min(i + 1, grid.size - 1)]
        if method == "profile":
            rss_all = rss_line - gain
            resid = y - _design(x, x0) @ coef
            deff = _design_effect(resid, inv) if (clusters is not None and not within) else 1.0
            n_eff = n / deff
            ok = np.isfinite(rss_all) & (n_eff * np.log(np.maximum(rss_all, tiny) / max(rss_min, tiny))
                                         <= stats.chi2.ppf(level, 1))
            accepted = grid[ok]
            lo_x, hi_x = float(min(accepted.min(), x0)), float(max(accepted.max(), x0))
        else:
            fit_h = random_intercept_fit(y, _design(x, x0), inv if clusters is not None else None)
            mean = _design(x, x0) @ fit_h.coef
            locs = []
            for start in range(0, int(n_boot), 250):
                size = min(250, int(n_boot) - start)
                Y = mean[:, None] + _simulate(rng, inv, fit_h.sigma2, 0.0 if within else fit_h.sigma2_between, size)
                G = basis.gains(basis.residualise(Y), trend)
                valid = np.isfinite(G).any(axis=0)
                locs.append(grid[np.argmax(np.where(np.isfinite(G), G, -1.0), axis=0)[valid]])
            boots = np.concatenate(locs) if locs else np.zeros(0)
            if boots.size < 10:
                raise FingerpadError("breakpoint: too few valid bootstrap resamples")
            alpha = (1.0 - level) / 2.0
            lo_x, hi_x = (float(q) for q in np.quantile(boots, [alpha, 1.0 - alpha]))
        # never a zero-width interval: at least to the neighbouring candidate locations
        lo_x, hi_x = min(lo_x, float(step_lo)), max(hi_x, float(step_hi))
        at_edge = lo_x <= grid[0] + 1e-12 or hi_x >= grid[-1] - 1e-12
        lo, hi = float(back(lo_x)), float(back(hi_x))
    return Breakpoint(
        load=float(back(x0)), ci_low=lo, ci_high=hi,
        slope_below=float(coef[1]), slope_above=float(coef[2]), level_at_break=float(coef[0]),
        rss=rss_min, rss_line=rss_line, p_value=float(p_value), n=n, space=space, method=method, level=level,
        detected=detected, statistic=float(lr), n_null=int(done), search_low=search[0], search_high=search[1],
        at_edge=bool(at_edge), edge_low=float(back(edge_lo)) if edge_lo <= edge_hi else math.nan,
        edge_high=float(back(edge_hi)) if edge_lo <= edge_hi else math.nan, outside=outside,
    )


def _hinge_coef(x: np.ndarray, y: np.ndarray, x0: float, levels: np.ndarray) -> np.ndarray:
    """``(level at the break, slope below, slope above)``; with one level per recording the
    level is their size-weighted mean."""
    design = np.column_stack([levels, np.minimum(x - x0, 0.0), np.maximum(x - x0, 0.0)])
    c, *_ = np.linalg.lstsq(design, y, rcond=None)
    k = levels.shape[1]
    weights = levels.sum(axis=0)
    return np.array([float(c[:k] @ weights / weights.sum()), float(c[k]), float(c[k + 1])])


def _design(x: np.ndarray, x0: float) -> np.ndarray:
    return np.column_stack([np.ones_like(x), np.minimum(x - x0, 0.0), np.maximum(x - x0, 0.0)])


def _design_effect(residuals: np.ndarray, inv: np.ndarray) -> float:
    from .modulus import design_effect

    return max(design_effect(residuals, inv), 1.0)
