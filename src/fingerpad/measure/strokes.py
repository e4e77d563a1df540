"""Strokes: reciprocating strokes split at direction changes, steady windows, outliers, load bins."""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
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
        Standstill threshold as a fraction of the 90th percentile of ``|direction signal|``;
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
    min_travel
        Shortest stroke travel, m (from the position, or the integrated velocity): shorter
        back-and-forth movements are tremor or noise, not strokes.
    motion_threshold
        A channel moves only if its robust range (0.5th to 99.5th percentile) exceeds this many
        times its sample-to-sample noise (and is more than round-off): a dead or constant
        channel must not turn noise into strokes.
    """

    trim: float = 0.2
    deadband: float = 0.1
    smooth: int = 5
    min_stroke_fraction: float = 0.3
    min_strokes: int = 2
    min_load: float = 0.01
    direction_source: Literal["auto", "velocity", "position", "friction"] = "auto"
    min_travel: float = 1e-3
    motion_threshold: float = 10.0

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
        if not (self.min_travel >= 0 and math.isfinite(self.min_travel)):
            raise FingerpadError(f"min_travel must be a non-negative length, got {self.min_travel!r}")
        if not self.motion_threshold > 0:
            raise FingerpadError(f"motion_threshold must be positive, got {self.motion_threshold!r}")


@dataclass(frozen=True)
class Stroke:
    """One stroke: sample ranges ``[start, stop)`` and its steady part, the sense (+1/-1) and
    its travel (m; NaN when no position or velocity was recorded)."""

    start: int
    stop: int
    steady_start: int
    steady_stop: int
    sense: int
    travel: float = math.nan


@dataclass
class StrokeReport:
    """What stroke detection kept and dropped in one recording, and why (for messages and QC)."""

    source: str
    signal: np.ndarray | None = field(default=None, repr=False)
    candidates: int = 0
    fragments: int = 0
    short_travel: int = 0
    lifted: int = 0
    strokes: list[Stroke] = field(default_factory=list)
    used: list[Stroke] = field(default_factory=list)

    def reasons(self, options: StrokeOptions, rec: Recording) -> str:
        """Why strokes were dropped, in words."""
        parts = []
        if self.lifted:
            med = float(np.median(rec.normal))
            parts.append(f"{self.lifted} with the normal force below the {options.min_load:g} N lift-off threshold "
                         f"(median normal force of the file {med:.3g} N)")
        if self.short_travel:
            parts.append(f"{self.short_travel} shorter than the {1e3 * options.min_travel:g} mm minimum travel")
        if self.fragments:
            parts.append(f"{self.fragments} fragment(s) shorter than {options.min_stroke_fraction:g} of the median stroke")
        return "; ".join(parts)


def _noise(x: np.ndarray, order: int) -> float:
    """Sample-to-sample noise of ``x`` from the MAD of its ``order``-th difference (robust to
    smooth motion, which barely changes high differences at a high sampling rate)."""
    d = np.diff(x, n=order)
    if d.size == 0:
        return 0.0
    norm = math.sqrt(math.comb(2 * order, order))  # sd of the difference of white noise
    return 1.4826 * float(np.median(np.abs(d - np.median(d)))) / norm


def moves(x: np.ndarray, options: StrokeOptions, order: int = 1) -> tuple[bool, float, float]:
    """Whether channel ``x`` moves: ``(moving, robust range, noise)`` (see ``motion_threshold``)."""
    lo, hi = np.percentile(x, [0.5, 99.5])
    span = float(hi - lo)
    noise = _noise(x, order)
    roundoff = 1e-9 * float(np.max(np.abs(x))) if x.size else 0.0
    return bool(span > max(options.motion_threshold * noise, roundoff, 0.0)), span, noise


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


def _check_motion(rec: Recording, name: str, options: StrokeOptions) -> None:
    """Stop with the reason when the channel that gives the direction does not move."""
    channel = {"velocity": rec.velocity, "position": rec.position, "friction": rec.friction}[name]
    ok, span, noise = moves(channel, options, order=2 if name == "position" else 1)
    hint = ("check the column, or take the direction from another channel (--direction-source)"
            if name != "friction" else "check the friction column")
    unit, factor = {"position": ("mm", 1e3), "velocity": ("mm/s", 1e3), "friction": ("N", 1.0)}[name]
    if not ok:
        raise FingerpadError(
            f"{rec.source}: no motion found: the {name} channel does not move (range {span * factor:.3g} {unit}, "
            f"noise {noise * factor:.3g} {unit}, below {options.motion_threshold:g} x noise); {hint}"
        )
    if name == "position" and span < options.min_travel:
        raise FingerpadError(
            f"{rec.source}: no motion found: the position channel spans {span * 1e3:.3g} mm, less than the "
            f"{options.min_travel * 1e3:g} mm minimum stroke travel; {hint} (or lower --min-travel)"
        )


def _travel(rec: Recording, a: int, b: int, source: str, signal: np.ndarray, use_position: bool) -> float:
    if use_position and rec.position is not None:
        seg = rec.position[a:b]
        return float(abs(np.median(seg[-3:]) - np.median(seg[:3])))
    if source == "velocity" and rec.time is not None and b - a > 1:
        return float(np.sum(np.abs(signal[a:b - 1]) * np.diff(rec.time[a:b])))
    return math.nan


def find_strokes(rec: Recording, options: StrokeOptions = StrokeOptions()) -> StrokeReport:
    """Split a reciprocating recording into strokes at direction changes, with the reasons for
    every stroke dropped (see :func:`detect_strokes`)."""
    signal, name = direction_signal(rec, options)
    _check_motion(rec, name, options)
    report = StrokeReport(source=name, signal=signal)
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
    report.candidates = len(candidates)
    if not candidates:
        return report
    # a dead position channel cannot measure travel (the direction then comes from elsewhere)
    use_position = rec.position is not None and (name == "position" or moves(rec.position, options, order=2)[0])
    median = float(np.median([b - a for a, b, _ in candidates]))
    for a, b, s in candidates:
        length = b - a
        if length < max(5, options.min_stroke_fraction * median):
            report.fragments += 1
            continue
        travel = _travel(rec, a, b, name, signal, use_position)
        if math.isfinite(travel) and travel < options.min_travel:
            report.short_travel += 1
            continue
        cut = int(round(options.trim * length))
        if b - cut - (a + cut) < 3:
            report.fragments += 1
            continue
        report.strokes.append(Stroke(a, b, a + cut, b - cut, s, travel))
    return report


def detect_strokes(rec: Recording, options: StrokeOptions = StrokeOptions()) -> list[Stroke]:
    """Split a reciprocating recording into strokes at direction changes.

    The sense is the sign of :func:`direction_signal` with hysteresis: inside the dead band
    the previous sense holds, so noise at a reversal cannot split a stroke. A stroke spans the
    samples moving faster than the dead band; ``trim`` of it is dropped at each end. Strokes
    shorter than ``min_stroke_fraction`` of the median or with less than ``min_travel`` of
    travel are dropped.

    Raises
    ------
    FingerpadError
        If the channel giving the direction does not move (constant, dead or pure noise).
    """
    return find_strokes(rec, options).strokes


STROKE_COLUMNS = [
    "file", "participant", "sample", "direction", "repetition", "session", "stroke", "sense", "row_start",
    "row_end", "time_start", "time_end", "load", "load_sd", "mu", "mu_sd", "n_samples", "speed", "travel",
]


def measure_strokes(rec: Recording, options: StrokeOptions = StrokeOptions(), *,
                    report: StrokeReport | None = None) -> pd.DataFrame:
    """Steady-state friction of every stroke of one recording (one row per stroke).

    Columns: file, metadata, ``stroke`` (1-based), ``sense`` (``"+"``/``"-"``), ``row_start``,
    ``row_end`` (file rows of the stroke), ``time_start``/``time_end`` (s, NaN without time),
    ``load`` (mean F_n, N), ``mu`` (mean ``|F_t|/F_n`` over the steady part), their standard
    deviations, ``n_samples``, ``speed`` (m/s, NaN unknown) and ``travel`` (m, NaN unknown).

    Raises
    ------
    FingerpadError
        If fewer than ``options.min_strokes`` usable strokes are found, naming the file, its
        rows and why the strokes were dropped.
    """
    report = report or find_strokes(rec, options)
    signal, source = (report.signal, report.source) if report.signal is not None else direction_signal(rec, options)
    rows = []
    for st in report.strokes:
        sl = slice(st.steady_start, st.steady_stop)
        fn, ft = rec.normal[sl], rec.friction[sl]
        ok = fn > options.min_load
        if ok.sum() < 3:
            report.lifted += 1  # finger lifted off during the stroke
            continue
        report.used.append(st)
        ratio = np.abs(ft[ok]) / fn[ok]
        speed = float(np.mean(np.abs(signal[sl]))) if source != "friction" else math.nan
        t = rec.time
        rows.append({
            "file": rec.source, "participant": rec.participant, "sample": rec.sample,
            "direction": rec.direction, "repetition": rec.repetition, "session": rec.session,
            "stroke": len(rows) + 1, "sense": "+" if st.sense > 0 else "-", "row_start": rec.row(st.start),
            "row_end": rec.row(st.stop - 1),
            "time_start": float(t[st.start]) if t is not None else math.nan,
            "time_end": float(t[st.stop - 1]) if t is not None else math.nan,
            "load": float(fn[ok].mean()), "load_sd": float(fn[ok].std(ddof=1)), "mu": float(ratio.mean()),
            "mu_sd": float(ratio.std(ddof=1)), "n_samples": int(ok.sum()), "speed": speed, "travel": st.travel,
        })
    if len(rows) < options.min_strokes:
        span = f"rows {rec.row(0)}-{rec.row(len(rec) - 1)}"
        why = report.reasons(options, rec)
        if not report.candidates:
            why = f"the {source} signal never changes sense"
        if not rows:
            raise FingerpadError(f"{rec.source}: no usable strokes in {span} (direction from {source}): "
                                 f"{why or 'none found'}")
        raise FingerpadError(
            f"{rec.source}: found {len(rows)} usable stroke(s) in {span}, need at least {options.min_strokes} "
            f"(direction from {source}{'; dropped: ' + why if why else ''}; check the columns or --min-strokes)"
        )
    return pd.DataFrame(rows, columns=STROKE_COLUMNS)


def stroke_table(recordings: Iterable[Recording], options: StrokeOptions = StrokeOptions(), *,
                 reports: dict[str, StrokeReport] | None = None) -> pd.DataFrame:
    """:func:`measure_strokes` over all recordings, concatenated; ``reports`` (if given) collects
    each recording's :class:`StrokeReport` by file (for the QC figures)."""
    frames = []
    for rec in recordings:
        report = find_strokes(rec, options)
        frames.append(measure_strokes(rec, options, report=report))
        if reports is not None:
            reports[rec.source] = report
    if not frames:
        raise FingerpadError("no recordings to analyse")
    return pd.concat(frames, ignore_index=True)


#: Friction coefficients outside this range are implausible for a finger (MODEL.md: ~0.5 dry, > 1 wet).
PLAUSIBLE_MU = (0.02, 5.0)
_UNIT_MIXUPS = ((1000.0, "mN", "N"), (101.97, "gf", "N"), (9.80665, "kgf", "N"), (4.448, "lbf", "N"),
                (45.36, "lbf", "kgf"))


def plausibility_warnings(strokes: pd.DataFrame) -> list[str]:
    """One warning per recording whose median friction coefficient lies outside
    :data:`PLAUSIBLE_MU`, suggesting the unit mix-up that would explain it."""
    out = []
    lo, hi = PLAUSIBLE_MU
    for file, g in strokes.groupby("file", sort=True):
        mu = float(np.median(g["mu"]))
        if lo <= mu <= hi:
            continue
        guess = ""
        for factor, small, big in _UNIT_MIXUPS:
            if mu > hi and 0.05 <= mu / factor <= 3:
                guess = (f"; the friction force may be in {small} while the normal force is in {big} "
                         f"(mu would be {mu / factor:.3g})")
                break
            if mu < lo and 0.05 <= mu * factor <= 3:
                guess = (f"; the normal force may be in {small} while the friction force is in {big} "
                         f"(mu would be {mu * factor:.3g})")
                break
        out.append(f"{Path(str(file)).name}: median friction coefficient {mu:.3g} is implausible for a finger "
                   f"(expected {lo:g}-{hi:g}){guess}; check the force units (header 'Ft [mN]', "
                   f"[units] in the spec, or --normal-unit/--friction-unit)")
    return out


GROUP = ["participant", "sample", "direction"]


def cluster_column(strokes: pd.DataFrame) -> np.ndarray:
    """The cluster of each stroke: its session where the study names one, else its recording."""
    files = strokes["file"].astype(str).to_numpy()
    if "session" not in strokes:
        return files
    sess = strokes["session"].fillna("").astype(str).to_numpy()
    part = strokes["participant"].astype(str).to_numpy()
    return np.where(sess != "", np.char.add(np.char.add(part, "/session:"), sess.astype(str)), files)


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


def _cluster_sem(df: pd.DataFrame, keys: list[str], col: str) -> pd.Series:
    """Cluster-robust (CR1) standard error of the mean of ``col`` per ``keys`` group, the
    clusters being recordings (sessions); NaN for a group from fewer than two recordings."""
    mean = df.groupby(keys, sort=True)[col].transform("mean")
    dev = df.assign(_dev=df[col] - mean)
    per = dev.groupby(keys + ["_cluster"], sort=True)["_dev"].sum().pow(2).groupby(level=keys).agg(["sum", "size"])
    n = df.groupby(keys, sort=True)[col].size()
    g = per["size"]
    se = np.sqrt(g / (g - 1) * per["sum"]) / n
    return se.where(g >= 2)


def bin_strokes(strokes: pd.DataFrame, edges: np.ndarray) -> pd.DataFrame:
    """Mean mu (and mu_norm) per participant, sample, direction, sense and load bin.

    Outliers are left out. ``sense`` is ``"+"``, ``"-"`` or ``"both"`` (pooled). ``mu_sem`` is
    the cluster-robust standard error over recordings (strokes of one recording share its
    skin state), NaN where the bin holds strokes of one recording only; ``n_recordings`` counts them.
    """
    df = strokes[~strokes["outlier"]]
    df = pd.concat([df, df.assign(sense="both")], ignore_index=True)
    df = df.assign(bin=bin_index(df["load"].to_numpy(), edges), _cluster=cluster_column(df))
    agg: dict[str, tuple[str, str]] = {
        "load": ("load", "median"), "n": ("mu", "size"), "n_recordings": ("_cluster", "nunique"),
        "mu": ("mu", "mean"), "mu_sd": ("mu", "std"),
    }
    if "mu_norm" in df:
        agg.update(mu_norm=("mu_norm", "mean"), mu_norm_sd=("mu_norm", "std"))
    keys = GROUP + ["sense", "bin"]
    out = df.groupby(keys, sort=True).agg(**agg)
    out["mu_sem"] = _cluster_sem(df, keys, "mu")
    if "mu_norm" in out:
        out["mu_norm_sem"] = _cluster_sem(df, keys, "mu_norm")
    out = out.reset_index()
    out["bin_low"] = edges[out["bin"].to_numpy()]
    out["bin_high"] = edges[out["bin"].to_numpy() + 1]
    return out
