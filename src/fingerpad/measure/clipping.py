"""Saturated sensors: a force channel held at the end of its range (clipping).

A load cell driven past its range, or an amplifier or converter at full scale, records the same
extreme value for as long as the true force stays beyond it: flat tops on the strokes. Nothing
else in a recording looks like that. Its noise makes the true extreme of a channel a single
sample (or a few, at the file's resolution), while a clipped channel sits at its extreme for a
run of samples far longer than any run of equal values elsewhere in the file. A clipped stroke
is biased (a capped normal force raises mu; capped friction lowers it), so the strokes whose
steady window touches a clipped level are left out of every fit, and the file and channel are
named in a warning.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

__all__ = ["CHANNELS", "Clip", "clipped_mask", "clipping_warnings", "find_clipping"]

#: The force channels checked, and their names in messages.
CHANNELS = {"normal": "normal force", "friction": "friction force"}


@dataclass(frozen=True)
class Clip:
    """One channel of one recording held at an extreme value.

    Attributes
    ----------
    channel
        ``"normal"`` or ``"friction"``.
    side
        ``"high"`` (its maximum) or ``"low"`` (its minimum).
    level
        The clipped value, N.
    tolerance
        Samples within this of ``level`` count as at it, N.
    n_samples
        Samples of the recording at the level.
    longest_run
        The longest run of consecutive samples at the level.
    """

    channel: str
    side: str
    level: float
    tolerance: float
    n_samples: int
    longest_run: int

    def describe(self) -> str:
        """``normal force held at its maximum 2 N (340 samples, runs up to 52)``."""
        where = "maximum" if self.side == "high" else "minimum"
        return (f"{CHANNELS[self.channel]} held at its {where} {self.level:.4g} N ({self.n_samples} samples, "
                f"runs up to {self.longest_run})")


def _runs(mask: np.ndarray) -> np.ndarray:
    """Lengths of the runs of True in ``mask``."""
    if not mask.any():
        return np.zeros(0, dtype=int)
    edges = np.diff(np.r_[0, mask.astype(np.int8), 0])
    return np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)


def find_clipping(rec: Any, *, min_run: int = 5, contrast: float = 3.0) -> list[Clip]:
    """The force channels of ``rec`` (a :class:`~fingerpad.measure.Recording`) that saturate.

    A channel is clipped at its maximum (or minimum) when it stays at that value (to round-off)
    for at least ``min_run`` consecutive
    samples, and for more than ``contrast`` times the longest run of equal values anywhere else
    in the channel (a coarsely quantised channel repeats values everywhere; that is not
    clipping). The normal force's minimum at or below zero is lift-off, not saturation.

    Returns
    -------
    list of Clip
        Empty for a clean recording.
    """
    out: list[Clip] = []
    for channel in CHANNELS:
        x = np.asarray(getattr(rec, channel), dtype=float)
        x = x[np.isfinite(x)]
        if x.size < min_run:
            continue
        lo, hi = float(x.min()), float(x.max())
        span = hi - lo
        if not span > 0:
            continue  # a constant channel: stroke detection says so
        # equal values: identical cells of a file, or a capped value, differ by round-off only
        # (a looser tolerance would make noise look repeated: 5e-6 N pairs occur in 0.002 N noise)
        tol = 1e-9 * max(span, abs(lo), abs(hi))
        extreme = {"high": np.abs(x - hi) <= tol, "low": np.abs(x - lo) <= tol}
        # the longest run of equal values away from both extremes: the channel's own repetition
        same = np.abs(np.diff(x)) <= tol
        inner = same & ~(extreme["high"][1:] | extreme["low"][1:])
        typical = int(_runs(inner).max(initial=0)) + 1
        for side, at in extreme.items():
            if channel == "normal" and side == "low" and lo <= 0:
                continue
            runs = _runs(at)
            longest = int(runs.max(initial=0))
            if longest >= min_run and longest > contrast * typical:
                out.append(Clip(channel, side, hi if side == "high" else lo, tol, int(at.sum()), longest))
    return out


def clipped_mask(values: np.ndarray, clip: Clip) -> np.ndarray:
    """Which ``values`` of the clip's channel sit at its clipped level."""
    return np.abs(np.asarray(values, dtype=float) - clip.level) <= clip.tolerance


def clipping_warnings(strokes: pd.DataFrame, clips: Mapping[str, list[Clip]]) -> list[str]:
    """One warning per clipped channel of a recording, with the strokes left out.

    ``strokes`` is the stroke table with its ``clipped`` column (the channels a stroke's steady
    window touches at a clipped level, ``""`` for none); ``clips`` the clips found per file.
    """
    out = []
    for file, found in clips.items():
        g = strokes[strokes["file"] == file]
        for channel in CHANNELS:
            mine = [c for c in found if c.channel == channel]
            if not mine:
                continue
            hit = int(g["clipped"].str.contains(channel, regex=False).sum()) if len(g) else 0
            what = " and ".join(c.describe() if i == 0 else c.describe().removeprefix(CHANNELS[channel] + " held ")
                                for i, c in enumerate(mine))
            out.append(f"{Path(str(file)).name}: {what}: the sensor saturated (clipped); {hit} of {len(g)} strokes "
                       f"touch the clipped level and are left out of the fits")
    return out
