"""Strokes of one recording: reciprocating strokes split at direction changes, their steady windows
and friction (the study-wide stroke table, outliers and load bins are :mod:`.tables`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import pandas as pd
from scipy.ndimage import uniform_filter1d

from ..errors import FingerpadError
from .clipping import Clip, clipped_mask, find_clipping
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
    clips: list[Clip] = field(default_factory=list)

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


def _median3(values: np.ndarray) -> float:
    """``np.median`` of three samples (the middle one; NaN if one is NaN), without its overhead:
    ~20 us a call, two calls per stroke, a fifth of finding a recording's strokes."""
    if values.size != 3:
        return float(np.median(values))
    a, b, c = (float(v) for v in values)
    if a != a or b != b or c != c:
        return math.nan
    return max(min(a, b), min(max(a, b), c))


def _travel(rec: Recording, a: int, b: int, source: str, signal: np.ndarray, use_position: bool) -> float:
    if use_position and rec.position is not None:
        seg = rec.position[a:b]
        return float(abs(_median3(seg[-3:]) - _median3(seg[:3])))
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
    "row_end", "time_start", "time_end", "load", "load_sd", "mu", "mu_sd", "n_samples", "speed", "travel", "clipped",
]


def measure_strokes(rec: Recording, options: StrokeOptions = StrokeOptions(), *,
                    report: StrokeReport | None = None) -> pd.DataFrame:
    """Steady-state friction of every stroke of one recording (one row per stroke).

    Columns: file, metadata, ``stroke`` (1-based), ``sense`` (``"+"``/``"-"``), ``row_start``,
    ``row_end`` (file rows of the stroke), ``time_start``/``time_end`` (s, NaN without time),
    ``load`` (mean F_n, N), ``mu`` (mean ``|F_t|/F_n`` over the steady part), their standard
    deviations, ``n_samples``, ``speed`` (m/s, NaN unknown), ``travel`` (m, NaN unknown) and
    ``clipped``: the force channels (``"normal"``, ``"friction"``, joined by ``+``) that sit at a
    saturated level (:func:`.clipping.find_clipping`) inside the stroke's steady window, ``""``
    for none; such a stroke's mu is biased.

    Raises
    ------
    FingerpadError
        If fewer than ``options.min_strokes`` usable strokes are found, naming the file, its
        rows and why the strokes were dropped.
    """
    report = report or find_strokes(rec, options)
    report.clips = find_clipping(rec)
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
        channels = {"normal": fn[ok], "friction": ft[ok]}
        clipped = sorted({c.channel for c in report.clips if clipped_mask(channels[c.channel], c).any()})
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
            "clipped": "+".join(clipped),
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
