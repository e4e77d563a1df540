"""The change of trend in normalised friction: segmented (hinge) regression in log-log."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy import optimize, stats

from ..errors import FingerpadError


@dataclass(frozen=True)
class Breakpoint:
    """A continuous two-segment (hinge) fit ``y = c + s1 min(x - x0, 0) + s2 max(x - x0, 0)``.

    ``x`` is ``log F`` and ``y`` ``log value`` when ``space == "log"``, else F and value.

    Attributes
    ----------
    load
        Breakpoint load F_b, N.
    ci_low, ci_high
        Confidence interval of F_b at ``level`` (profile likelihood or bootstrap).
    slope_below, slope_above
        Segment slopes (in log space: local exponents of value vs load).
    level_at_break
        Fitted y at the breakpoint (the hinge height ``c``).
    rss, rss_line
        Residual sums of squares of the hinge and of one straight line.
    p_value
        Approximate F-test of the hinge against one line (2 extra parameters; the breakpoint
        is not identified under the null, so treat it as indicative).
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

    def predict(self, loads: np.ndarray) -> np.ndarray:
        """The fitted hinge at ``loads`` (in value units)."""
        f = np.asarray(loads, dtype=float)
        x = np.log(f) if self.space == "log" else f
        x0 = math.log(self.load) if self.space == "log" else self.load
        y = self.level_at_break + self.slope_below * np.minimum(x - x0, 0) + self.slope_above * np.maximum(x - x0, 0)
        return np.exp(y) if self.space == "log" else y


def _hinge_fit(x: np.ndarray, y: np.ndarray, x0: float) -> tuple[float, np.ndarray]:
    design = np.column_stack([np.ones_like(x), np.minimum(x - x0, 0.0), np.maximum(x - x0, 0.0)])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    r = y - design @ coef
    return float(r @ r), coef


def _hinge_profile(x: np.ndarray, y: np.ndarray, grid: np.ndarray, trend: str = "any") -> np.ndarray:
    """RSS of the hinge at each candidate breakpoint; ``inf`` where the slope change has the
    wrong sign for ``trend`` (``"steeper"``: slope_above > slope_below, ``"flatter"``: <)."""
    out = np.empty(grid.size)
    for i, g in enumerate(grid):
        rss, coef = _hinge_fit(x, y, g)
        bad = (trend == "steeper" and coef[2] <= coef[1]) or (trend == "flatter" and coef[2] >= coef[1])
        out[i] = math.inf if bad else rss
    return out


def _hinge_grid(x: np.ndarray, min_side: int, n_grid: int) -> np.ndarray:
    xs = np.sort(x)
    lo, hi = xs[min_side - 1], xs[-min_side]
    inner = xs[(xs >= lo) & (xs <= hi)]
    return np.unique(np.r_[np.linspace(lo, hi, n_grid), inner])


def find_breakpoint(
    loads: Sequence[float] | np.ndarray,
    values: Sequence[float] | np.ndarray,
    *,
    space: Literal["log", "linear"] = "log",
    method: Literal["profile", "bootstrap"] = "profile",
    trend: Literal["any", "steeper", "flatter"] = "any",
    level: float = 0.95,
    n_boot: int = 200,
    seed: int = 0,
    min_side: int = 3,
    n_grid: int = 200,
) -> Breakpoint:
    """Locate the change of trend of ``values`` vs load by segmented regression.

    The breakpoint ``x0`` minimises the residual sum of squares of a continuous two-segment
    line (profiled over a grid that leaves at least ``min_side`` points on each side, then
    refined). Its confidence interval is either

    * ``"profile"``: the ``x0`` with ``n log(RSS(x0)/RSS_min) <= chi2_1(level)`` (likelihood
      ratio with the noise variance profiled out), or
    * ``"bootstrap"``: percentiles of ``x0`` refitted on ``n_boot`` case resamples.

    Parameters
    ----------
    loads, values
        Loads (N, > 0) and the quantity (e.g. normalised friction; > 0 in log space).
    space
        ``"log"`` (log-log, slopes are power-law exponents) or ``"linear"``.
    trend
        Admit only breakpoints where the curve gets ``"steeper"`` (the contact transition on a
        texture: friction rises faster once the skin touches the base) or ``"flatter"``;
        ``"any"`` takes the largest change. A curve may bend twice in the measured range (onset
        of base contact, then saturation towards full contact); the sign picks the one wanted.

    Raises
    ------
    FingerpadError
        For fewer than ``2 min_side + 1`` points, non-finite or non-positive input.
    """
    f = np.asarray(loads, dtype=float)
    v = np.asarray(values, dtype=float)
    if f.shape != v.shape or f.ndim != 1:
        raise FingerpadError("loads and values must be 1-D arrays of the same length")
    if space not in ("log", "linear"):
        raise FingerpadError(f"space must be 'log' or 'linear', got {space!r}")
    if method not in ("profile", "bootstrap"):
        raise FingerpadError(f"method must be 'profile' or 'bootstrap', got {method!r}")
    if trend not in ("any", "steeper", "flatter"):
        raise FingerpadError(f"trend must be 'any', 'steeper' or 'flatter', got {trend!r}")
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(v)) and np.all(f > 0)):
        raise FingerpadError("breakpoint: loads must be positive and values finite")
    if space == "log" and np.any(v <= 0):
        raise FingerpadError("breakpoint: values must be positive for a log-log fit")
    n = f.size
    if n < 2 * min_side + 1 or np.unique(f).size < 2 * min_side:
        raise FingerpadError(f"breakpoint: need at least {2 * min_side + 1} points at distinct loads, got {n}")
    x = np.log(f) if space == "log" else f
    y = np.log(v) if space == "log" else v
    grid = _hinge_grid(x, min_side, n_grid)
    rss = _hinge_profile(x, y, grid, trend)
    if not np.any(np.isfinite(rss)):
        raise FingerpadError(f"breakpoint: the curve never turns {trend} within the data")
    i = int(np.argmin(rss))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    x0, rss_min = float(grid[i]), float(rss[i])
    if b > a:
        # The trend filter makes the profile infinite where the curve turns the other way; the
        # bounded search then does inf - inf internally. Its result is only taken if it improves
        # on the grid minimum, so the warnings are noise.
        with np.errstate(invalid="ignore"):
            res = optimize.minimize_scalar(lambda t: float(_hinge_profile(x, y, np.array([t]), trend)[0]),
                                           bounds=(a, b), method="bounded",
                                           options={"xatol": 1e-6 * max(1.0, abs(x0))})
        if np.isfinite(res.fun) and res.fun < rss_min:
            x0, rss_min = float(res.x), float(res.fun)
    _, coef = _hinge_fit(x, y, x0)
    line = np.polyfit(x, y, 1)
    rss_line = float(np.sum((y - np.polyval(line, x)) ** 2))
    dof = n - 4
    if dof > 0 and rss_min > 0:
        fstat = max(rss_line - rss_min, 0.0) / 2.0 / (rss_min / dof)
        p_value = float(stats.f.sf(fstat, 2, dof))
    else:
        p_value = math.nan
    if method == "profile":
        tiny = max(rss_min, 1e-300)
        accepted = grid[n * np.log(np.maximum(rss, tiny) / tiny) <= stats.chi2.ppf(level, 1)]
        lo, hi = float(min(accepted.min(), x0)), float(max(accepted.max(), x0))
    else:
        rng = np.random.default_rng(seed)
        boots = []
        for _ in range(int(n_boot)):
            idx = rng.integers(0, n, n)
            xb, yb = x[idx], y[idx]
            if np.unique(xb).size < 2 * min_side:
                continue
            gb = _hinge_grid(xb, min_side, max(50, n_grid // 4))
            rb = _hinge_profile(xb, yb, gb, trend)
            if np.any(np.isfinite(rb)):
                boots.append(gb[int(np.argmin(rb))])
        if len(boots) < 10:
            raise FingerpadError("breakpoint: too few valid bootstrap resamples")
        alpha = (1.0 - level) / 2.0
        lo, hi = (float(q) for q in np.quantile(boots, [alpha, 1.0 - alpha]))
    back = np.exp if space == "log" else (lambda t: t)
    return Breakpoint(
        load=float(back(x0)), ci_low=float(back(lo)), ci_high=float(back(hi)),
        slope_below=float(coef[1]), slope_above=float(coef[2]), level_at_break=float(coef[0]),
        rss=rss_min, rss_line=rss_line, p_value=p_value, n=n, space=space, method=method, level=level,
    )
