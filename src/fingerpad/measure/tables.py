"""The study's stroke table and what is computed on it: stroke table of all recordings, grouping
into conditions and recordings, plausibility, outliers, load bins and binned means."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import optimize

from ..errors import FingerpadError
from .recordings import Recording
from .strokes import StrokeOptions, StrokeReport, find_strokes, measure_strokes

__all__ = ["GROUP", "PLAUSIBLE_MU", "bin_index", "bin_strokes", "cluster_column", "flag_outliers", "load_bin_edges",
           "plausibility_warnings", "recording_strokes", "stroke_table"]


def recording_strokes(rec: Recording, options: StrokeOptions) -> tuple[pd.DataFrame, StrokeReport]:
    """One recording's strokes (:func:`measure_strokes`) and its :class:`StrokeReport`."""
    report = find_strokes(rec, options)
    return measure_strokes(rec, options, report=report), report


def stroke_table(recordings: Iterable[Recording], options: StrokeOptions = StrokeOptions(), *,
                 reports: dict[str, StrokeReport] | None = None,
                 found: Iterable[tuple[pd.DataFrame, StrokeReport]] | None = None) -> pd.DataFrame:
    """:func:`measure_strokes` over all recordings, concatenated; ``reports`` (if given) collects
    each recording's :class:`StrokeReport` by file (for the QC figures). ``found``: what
    :func:`recording_strokes` gives for each recording, in their order, if worked out
    elsewhere (e.g. by other processes); else it is worked out here."""
    recordings = list(recordings)
    if found is None:
        found = (recording_strokes(rec, options) for rec in recordings)
    frames = []
    for rec, (frame, report) in zip(recordings, found):
        frames.append(frame)
        if reports is not None:
            reports[rec.source] = report
    if not frames:
        raise FingerpadError("no recordings to analyse")
    return pd.concat(frames, ignore_index=True)


#: Friction coefficients outside this range are implausible for a finger (docs/model.md: ~0.5 dry, > 1 wet).
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
