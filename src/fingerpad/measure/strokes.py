"""Strokes: reciprocating strokes split at direction changes, steady windows, outliers, load bins."""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Literal

import numpy as np
import pandas as pd
from scipy import optimize
from scipy.ndimage import uniform_filter1d

from ..errors import FingerpadError
from .recordings import Recording


@dataclass(frozen=True)
class StrokeOptions:
    """Stroke detection and steady-state extraction.

    Attributes
    ----------
    trim
        Fraction of each stroke dropped at its start and at its end (static-friction peak,
        acceleration, deceleration), in [0, 0.45].
    deadband
        Standstill threshold as a fraction of the 90th percentile of |direction signal|;
        a sense change needs the signal to cross the opposite threshold (hysteresis).
    smooth
        Samples in the moving average applied before differentiating position (or to the
        friction force when it gives the direction).
    min_stroke_fraction
        Strokes shorter than this fraction of the median stroke are dropped (fragments).
    min_strokes
        Fewest usable strokes a file must give.
    min_load
        Normal force (N) below which a sample counts as lifted off and is ignored.
    direction_source
        ``"auto"`` (velocity, else position, else friction sign) or one of ``"velocity"``,
        ``"position"``, ``"friction"``.
    """

    trim: float = 0.2
    deadband: float = 0.1
    smooth: int = 5
    min_stroke_fraction: float = 0.3
    min_strokes: int = 2
    min_load: float = 0.01
    direction_source: Literal["auto", "velocity", "position", "friction"] = "auto"

    def __post_init__(self) -> None:
        if not 0.0 <= self.trim <= 0.45:
            raise FingerpadError(f"trim must lie in [0, 0.45], got {self.trim!r}")
        if not 0.0 < self.deadband < 1.0:
            raise FingerpadError(f"deadband must lie in (0, 1), got {self.deadband!r}")
        if self.smooth < 1 or self.min_strokes < 1:
            raise FingerpadError("smooth and min_strokes must be at least 1")
        if self.direction_source not in ("auto", "velocity", "position", "friction"):
            raise FingerpadError(f"unknown direction source {self.direction_source!r}")
        if not self.min_load >= 0:
            raise FingerpadError(f"min_load must be non-negative, got {self.min_load!r}")


@dataclass(frozen=True)
class Stroke:
    """One stroke: sample ranges ``[start, stop)`` and its steady part, and the sense (+1/-1)."""

    start: int
    stop: int
    steady_start: int
    steady_stop: int
    sense: int


def direction_signal(rec: Recording, options: StrokeOptions = StrokeOptions()) -> tuple[np.ndarray, str]:
    """The signal whose sign gives the sliding sense, and its name.

    Velocity if recorded; else the derivative of the (smoothed) position; else minus the
    smoothed friction force: the force on the finger opposes its motion, so sense ``+`` (as with
    a positive velocity) is where ``F_t < 0``. (A force recorded on the sample has the other
    sign; the two senses then swap labels but stay apart.)
    """
    src = options.direction_source
    if src in ("auto", "velocity") and rec.velocity is not None:
        return rec.velocity, "velocity"
    if src == "velocity":
        raise FingerpadError(f"{rec.source}: no velocity column (direction source 'velocity')")
    if src in ("auto", "position") and rec.position is not None:
        pos = uniform_filter1d(rec.position, size=options.smooth, mode="nearest")
        return (np.gradient(pos, rec.time) if rec.time is not None else np.gradient(pos)), "position"
    if src == "position":
        raise FingerpadError(f"{rec.source}: no position column (direction source 'position')")
    return -uniform_filter1d(rec.friction, size=options.smooth, mode="nearest"), "friction"


def detect_strokes(rec: Recording, options: StrokeOptions = StrokeOptions()) -> list[Stroke]:
    """Split a reciprocating recording into strokes at direction changes.

    The sense is the sign of :func:`direction_signal` with hysteresis: inside the dead band
    the previous sense holds, so noise at a reversal cannot split a stroke. A stroke spans the
    samples moving faster than the dead band; ``trim`` of it is dropped at each end.

    Raises
    ------
    FingerpadError
        If the direction signal is constant (no motion).
    """
    signal, name = direction_signal(rec, options)
    scale = float(np.percentile(np.abs(signal), 90))
    if not scale > 0:
        raise FingerpadError(f"{rec.source}: no motion found (the {name} signal is constant)")
    thr = options.deadband * scale
    raw = np.where(signal > thr, 1, np.where(signal < -thr, -1, 0))
    last = np.where(raw != 0, np.arange(raw.size), 0)
    np.maximum.accumulate(last, out=last)
    state = raw[last]
    bounds = np.flatnonzero(np.diff(state) != 0) + 1
    candidates = []
    for a, b in zip(np.r_[0, bounds], np.r_[bounds, state.size]):
        s = int(state[a])
        if s == 0:
            continue
        moving = np.flatnonzero(raw[a:b] == s)
        candidates.append((a + int(moving[0]), a + int(moving[-1]) + 1, s))
    if not candidates:
        return []
    median = float(np.median([b - a for a, b, _ in candidates]))
    strokes = []
    for a, b, s in candidates:
        length = b - a
        if length < max(5, options.min_stroke_fraction * median):
            continue
        cut = int(round(options.trim * length))
        if b - cut - (a + cut) < 3:
            continue
        strokes.append(Stroke(a, b, a + cut, b - cut, s))
    return strokes


STROKE_COLUMNS = [
    "file", "participant", "sample", "direction", "repetition", "stroke", "sense", "row_start",
    "row_end", "load", "load_sd", "mu", "mu_sd", "n_samples", "speed",
]


def measure_strokes(rec: Recording, options: StrokeOptions = StrokeOptions()) -> pd.DataFrame:
    """Steady-state friction of every stroke of one recording (one row per stroke).

    Columns: file, metadata, ``stroke`` (1-based), ``sense`` (``"+"``/``"-"``), ``row_start``,
    ``row_end`` (file rows of the stroke), ``load`` (mean F_n, N), ``mu`` (mean |F_t|/F_n over
    the steady part), their standard deviations, ``n_samples`` and ``speed`` (m/s, NaN unknown).

    Raises
    ------
    FingerpadError
        If fewer than ``options.min_strokes`` usable strokes are found (naming file and rows).
    """
    strokes = detect_strokes(rec, options)
    signal, source = direction_signal(rec, options)
    rows = []
    for st in strokes:
        sl = slice(st.steady_start, st.steady_stop)
        fn, ft = rec.normal[sl], rec.friction[sl]
        ok = fn > options.min_load
        if ok.sum() < 3:
            continue  # finger lifted off during the stroke
        ratio = np.abs(ft[ok]) / fn[ok]
        speed = float(np.mean(np.abs(signal[sl]))) if source != "friction" else math.nan
        rows.append({
            "file": rec.source, "participant": rec.participant, "sample": rec.sample,
            "direction": rec.direction, "repetition": rec.repetition, "stroke": len(rows) + 1,
            "sense": "+" if st.sense > 0 else "-", "row_start": rec.row(st.start),
            "row_end": rec.row(st.stop - 1), "load": float(fn[ok].mean()),
            "load_sd": float(fn[ok].std(ddof=1)), "mu": float(ratio.mean()),
            "mu_sd": float(ratio.std(ddof=1)), "n_samples": int(ok.sum()), "speed": speed,
        })
    if len(rows) < options.min_strokes:
        raise FingerpadError(
            f"{rec.source}: found {len(rows)} usable stroke(s) in rows {rec.row(0)}-{rec.row(len(rec) - 1)}, "
            f"need at least {options.min_strokes} (direction from {source}; check the columns or --min-strokes)"
        )
    return pd.DataFrame(rows, columns=STROKE_COLUMNS)


def stroke_table(recordings: Iterable[Recording], options: StrokeOptions = StrokeOptions()) -> pd.DataFrame:
    """:func:`measure_strokes` over all recordings, concatenated."""
    frames = [measure_strokes(rec, options) for rec in recordings]
    if not frames:
        raise FingerpadError("no recordings to analyse")
    return pd.concat(frames, ignore_index=True)


GROUP = ["participant", "sample", "direction"]


def _robust_trend(x: np.ndarray, y: np.ndarray, group: np.ndarray) -> np.ndarray:
    """Robust trend of y(x): a quadratic (linear below 8 points) plus an offset per ``group``
    level, fitted with a soft-L1 loss so that a few outliers barely pull it."""
    deg = 2 if x.size >= 8 else 1
    xc = x - x.mean()
    levels = np.unique(group)
    design = np.column_stack([xc**d for d in range(deg, 0, -1)] + [(group == lv).astype(float) for lv in levels])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    r0 = y - design @ coef
    scale = max(1.4826 * float(np.median(np.abs(r0 - np.median(r0)))), 1e-6)
    res = optimize.least_squares(lambda c: y - design @ c, coef, loss="soft_l1", f_scale=scale)
    return design @ res.x


def flag_outliers(strokes: pd.DataFrame, threshold: float = 3.5, min_strokes: int = 6) -> pd.DataFrame:
    """Flag strokes whose mu departs from the trend of their group (robust z-score).

    Within each participant, sample and direction, ``log mu`` against ``log F`` gets a robust
    (soft-L1) quadratic trend with a separate level per sliding sense -- it follows a power
    law, the gentle bend of a contact transition and a direction asymmetry, while a few
    outliers barely pull it. Residuals are scaled by their median absolute deviation,
    ``z = 0.6745 (r - median r) / MAD`` (Iglewicz-Hoaglin). Groups of fewer than
    ``min_strokes`` strokes are not flagged.

    Returns
    -------
    DataFrame
        A copy with ``robust_z`` and ``outlier`` (``|z| > threshold``) columns.
    """
    df = strokes.copy()
    df["robust_z"] = 0.0
    df["outlier"] = False
    for _, g in df.groupby(GROUP, sort=False):
        if len(g) < max(min_strokes, 5):
            continue
        x = np.log(g["load"].to_numpy())
        y = np.log(np.clip(g["mu"].to_numpy(), 1e-12, None))
        r = y - _robust_trend(x, y, g["sense"].to_numpy())
        mad = float(np.median(np.abs(r - np.median(r))))
        z = np.zeros(r.size) if mad == 0 else 0.6745 * (r - np.median(r)) / mad
        df.loc[g.index, "robust_z"] = z
        df.loc[g.index, "outlier"] = np.abs(z) > threshold
    return df


def load_bin_edges(loads: np.ndarray, n_bins: int) -> np.ndarray:
    """Log-spaced bin edges spanning ``loads`` (shared by the whole study, so bins compare)."""
    lo, hi = float(np.min(loads)), float(np.max(loads))
    if not (lo > 0 and hi > lo):
        return np.array([lo * 0.9, hi * 1.1]) if lo > 0 else np.array([0.0, max(hi, 1e-3)])
    return np.geomspace(lo * (1 - 1e-9), hi * (1 + 1e-9), int(n_bins) + 1)


def bin_index(loads: np.ndarray, edges: np.ndarray) -> np.ndarray:
    return np.clip(np.searchsorted(edges, loads, side="right") - 1, 0, len(edges) - 2)


def bin_strokes(strokes: pd.DataFrame, edges: np.ndarray) -> pd.DataFrame:
    """Mean mu (and mu_norm) per participant, sample, direction, sense and load bin.

    Outliers are left out. ``sense`` is ``"+"``, ``"-"`` or ``"both"`` (pooled).
    """
    df = strokes[~strokes["outlier"]]
    df = pd.concat([df, df.assign(sense="both")], ignore_index=True)
    df = df.assign(bin=bin_index(df["load"].to_numpy(), edges))
    agg: dict[str, tuple[str, str]] = {
        "load": ("load", "median"), "n": ("mu", "size"), "mu": ("mu", "mean"), "mu_sd": ("mu", "std"),
    }
    if "mu_norm" in df:
        agg.update(mu_norm=("mu_norm", "mean"), mu_norm_sd=("mu_norm", "std"))
    out = df.groupby(GROUP + ["sense", "bin"], sort=True).agg(**agg).reset_index()
    out["mu_sem"] = out["mu_sd"] / np.sqrt(out["n"])
    if "mu_norm" in out:
        out["mu_norm_sem"] = out["mu_norm_sd"] / np.sqrt(out["n"])
    out["bin_low"] = edges[out["bin"].to_numpy()]
    out["bin_high"] = edges[out["bin"].to_numpy() + 1]
    return out
