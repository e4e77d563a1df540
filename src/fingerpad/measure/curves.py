"""Friction curves: power law mu = k F^(n-1) per participant and sample, normalisation by the flat reference (docs/model.md "Normalisation"), spread between people.

Every fit respects the grouping of strokes into recordings (sessions): ``ln mu = ln k + (n-1) ln F
+ u_recording + e`` with a random intercept per recording (:func:`.stats.random_intercept_fit`),
so that session-to-session variation of skin moisture and posture widens the interval of k.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..errors import FingerpadError
from ..friction import PowerLaw, fit_inputs
from .stats import ClusterFit, random_intercept_fit, t_quantile
from .tables import GROUP, bin_index, cluster_column


def fit_power_law_clustered(
    loads: Sequence[float] | np.ndarray,
    mu: Sequence[float] | np.ndarray,
    clusters: Sequence[Any] | np.ndarray | None = None,
    *,
    level: float = 0.95,
) -> PowerLaw:
    """Fit ``ln mu = ln k + (n - 1) ln F`` with a random intercept per cluster (REML).

    Without ``clusters`` every stroke is independent (ordinary least squares, the t intervals of
    :func:`fingerpad.friction.fit_power_law`). Returns the same :class:`fingerpad.friction.PowerLaw`
    as that function, with the recordings' part filled in (``n_clusters``, ``df_level``,
    ``sigma_between``, ``sigma_within``, ``note``).

    Raises
    ------
    FingerpadError
        Fewer than 3 points, non-positive values, or all loads equal.
    """
    f, m = fit_inputs(loads, mu)
    x = np.log(f)
    fit: ClusterFit = random_intercept_fit(np.log(m), np.column_stack([np.ones_like(x), x]), clusters)
    ln_k, slope = (float(c) for c in fit.coef)
    se_lnk, se_n = (math.sqrt(max(v, 0.0)) for v in np.diag(fit.cov))
    q_k, q_n = t_quantile(level, fit.df([1, 0])), t_quantile(level, fit.df([0, 1]))
    k = math.exp(ln_k)
    jac = np.diag([k, 1.0])
    return PowerLaw(
        k=k, n=slope + 1.0, k_stderr=k * se_lnk, n_stderr=se_n,
        k_ci=(math.exp(ln_k - q_k * se_lnk), math.exp(ln_k + q_k * se_lnk)),
        n_ci=(slope + 1.0 - q_n * se_n, slope + 1.0 + q_n * se_n),
        covariance=jac @ fit.cov @ jac.T, log_covariance=fit.cov, dof=fit.df([0, 1]), df_level=fit.df([1, 0]),
        n_clusters=fit.n_clusters, sigma_between=math.sqrt(fit.sigma2_between), sigma_within=math.sqrt(fit.sigma2),
        level=level, note=fit.note,
    )


def sense_ratio(g: pd.DataFrame, level: float = 0.95) -> tuple[float, float, float]:
    """``mu(+) / mu(-)`` of one condition with its interval: ``ln mu = a + b ln F + c [sense +]``
    with a random intercept per recording, ratio ``exp(c)``. NaN without both senses."""
    g = g[~g["outlier"]]
    if g["sense"].nunique() < 2 or len(g) < 5 or g["load"].nunique() < 2:
        return math.nan, math.nan, math.nan
    x = np.log(g["load"].to_numpy())
    plus = (g["sense"] == "+").to_numpy(dtype=float)
    try:
        fit = random_intercept_fit(np.log(g["mu"].to_numpy()), np.column_stack([np.ones_like(x), x, plus]),
                                   cluster_column(g))
    except FingerpadError:
        return math.nan, math.nan, math.nan
    lo, hi = fit.interval([0, 0, 1], level)
    return math.exp(float(fit.coef[2])), math.exp(lo), math.exp(hi)


def _ci(obj: Any, name: str) -> tuple[float, float]:
    ci = getattr(obj, f"{name}_ci", None)
    if ci is None:
        return math.nan, math.nan
    lo, hi = ci
    return float(lo), float(hi)


def fit_row(fit: Any) -> dict[str, float]:
    k_lo, k_hi = _ci(fit, "k")
    n_lo, n_hi = _ci(fit, "n")
    return {
        "k": float(fit.k), "k_se": float(getattr(fit, "k_stderr", math.nan)), "k_ci_low": k_lo, "k_ci_high": k_hi,
        "n": float(fit.n), "n_se": float(getattr(fit, "n_stderr", math.nan)), "n_ci_low": n_lo, "n_ci_high": n_hi,
        "n_recordings": int(getattr(fit, "n_clusters", 0)),
        "sd_between_recordings": float(getattr(fit, "sigma_between", math.nan)),
    }


def _fit_group(g: pd.DataFrame, min_strokes: int, level: float = 0.95) -> tuple[Any | None, str]:
    g = g[~g["outlier"]]
    if len(g) < min_strokes or g["load"].nunique() < 3:
        return None, f"{len(g)} usable strokes at {g['load'].nunique()} loads, need {min_strokes} at 3 or more"
    try:
        return fit_power_law_clustered(g["load"].to_numpy(), g["mu"].to_numpy(), cluster_column(g), level=level), ""
    except FingerpadError as exc:
        return None, str(exc)


def fit_curves(strokes: pd.DataFrame, min_strokes: int = 4, *, level: float = 0.95, workers: int = 1
               ) -> tuple[pd.DataFrame, dict[tuple[str, ...], Any]]:
    """Power-law fits ``mu = k F^(n-1)`` per participant, sample, direction and sense.

    ``workers`` processes fit the groups (:func:`.parallel.forked_map`; the same fits, bit for
    bit, as one process's).

    Returns
    -------
    table, fits
        A table (one row per group and sense ``+``/``-``/``both``, with ``k``, ``n``, standard
        errors, intervals at ``level`` (random intercept per recording), ``n_strokes``,
        ``n_recordings``, ``note``) and the :class:`PowerLaw` fits keyed by
        ``(participant, sample, direction, sense)``.
    """
    from .parallel import forked_map

    groups = list(strokes.groupby(GROUP, sort=True))

    def group_fits(i: int) -> list[tuple[dict[str, Any], Any]]:
        key, g = groups[i]
        out = []
        for sense in ("+", "-", "both"):
            part = g if sense == "both" else g[g["sense"] == sense]
            fit, note = _fit_group(part, min_strokes, level)
            row = dict(zip(GROUP, key), sense=sense, n_strokes=int((~part["outlier"]).sum()), note=note)
            if fit is not None:
                row.update(fit_row(fit))
                row["note"] = fit.note
                row["load_min"] = float(part["load"].min())
                row["load_max"] = float(part["load"].max())
            out.append((row, fit))
        return out

    rows, fits = [], {}
    # a few dozen groups a message: one fit is ~2 ms
    chunk = max(1, len(groups) // (8 * max(workers, 1)))
    for (key, _), done in zip(groups, forked_map(group_fits, range(len(groups)), workers, chunk), strict=True):
        for row, fit in done:
            if fit is not None:
                fits[(*key, row["sense"])] = fit
            rows.append(row)
    return pd.DataFrame(rows), fits


def normalise(strokes: pd.DataFrame, reference: str, min_strokes: int = 4, *, level: float = 0.95
              ) -> tuple[pd.DataFrame, dict[tuple[str, str], Any]]:
    """Divide every stroke's mu by the participant's reference curve at the same load.

    ``mu_norm = mu / mu_ref(F)`` with ``mu_ref`` the power law fitted to the participant's
    strokes on the flat ``reference`` sample (all its directions pooled; the same sense where
    that fit exists, else both senses). By docs/model.md "Normalisation", ``mu_norm`` estimates
    ``A_re,tex / A_re,ref`` and no longer depends on the person's ridge area.

    Returns
    -------
    strokes, reference_fits
        A copy with ``mu_ref``, ``mu_norm`` and ``ref_extrapolated`` (load outside the
        reference's measured range by more than 25 %), and the fits keyed by (participant, sense).

    Raises
    ------
    FingerpadError
        If the reference sample is absent, or a participant has no (or too few) strokes on it.
    """
    samples = sorted(set(strokes["sample"]))
    if reference not in samples:
        raise FingerpadError(f"reference sample {reference!r} is not in the data (samples: {', '.join(samples)})")
    df = strokes.copy()
    df["mu_ref"] = math.nan
    df["ref_extrapolated"] = False
    ref_fits: dict[tuple[str, str], Any] = {}
    for participant, g in df.groupby("participant", sort=True):
        ref = g[g["sample"] == reference]
        if ref.empty:
            files = ", ".join(sorted({Path(f).name for f in g["file"]}))
            raise FingerpadError(
                f"participant {participant!r} has no recordings of the reference sample {reference!r} ({files})"
            )
        for sense in ("+", "-", "both"):
            part = ref if sense == "both" else ref[ref["sense"] == sense]
            fit, note = _fit_group(part, min_strokes, level)
            if fit is not None:
                ref_fits[(participant, sense)] = fit
        if (participant, "both") not in ref_fits:
            files = ", ".join(sorted({Path(f).name for f in ref["file"]}))
            raise FingerpadError(
                f"participant {participant!r}: cannot fit the reference sample {reference!r} ({note}; files: {files})"
            )
        lo, hi = ref["load"].min() / 1.25, ref["load"].max() * 1.25
        for sense, sub in g.groupby("sense"):
            fit = ref_fits.get((participant, sense), ref_fits[(participant, "both")])
            loads = sub["load"].to_numpy()
            df.loc[sub.index, "mu_ref"] = np.asarray(fit(loads), dtype=float)
            df.loc[sub.index, "ref_extrapolated"] = (loads < lo) | (loads > hi)
    df["mu_norm"] = df["mu"] / df["mu_ref"]
    return df, ref_fits


def spread_table(strokes: pd.DataFrame, edges: np.ndarray, reference: str) -> pd.DataFrame:
    """Spread between participants per sample, direction and load bin, before/after normalising.

    Each participant contributes the mean of its (non-outlier) strokes in the bin; the table
    gives the number of participants, mean, standard deviation and coefficient of variation
    (``cv = sd / mean``) of raw ``mu`` and of ``mu_norm`` (left NaN for the reference, which is 1
    by construction).
    """
    df = strokes[~strokes["outlier"]]
    df = df.assign(bin=bin_index(df["load"].to_numpy(), edges))
    per = df.groupby(GROUP + ["bin"]).agg(mu=("mu", "mean"), mu_norm=("mu_norm", "mean")).reset_index()
    rows = []
    for (sample, direction, b), g in per.groupby(["sample", "direction", "bin"], sort=True):
        row: dict[str, Any] = {"sample": sample, "direction": direction, "bin": int(b),
                               "bin_low": edges[b], "bin_high": edges[b + 1], "n_participants": len(g)}
        for col in ("mu", "mu_norm"):
            v = g[col].to_numpy()
            mean = float(v.mean())
            sd = float(v.std(ddof=1)) if len(v) > 1 else math.nan
            if col == "mu_norm" and sample == reference:
                mean = sd = math.nan
            row[f"{col}_mean"], row[f"{col}_sd"] = mean, sd
            row[f"{col}_cv"] = sd / mean if mean else math.nan
        rows.append(row)
    return pd.DataFrame(rows)


def spread_summary(spread: pd.DataFrame, reference: str, min_participants: int = 2) -> pd.DataFrame:
    """Mean coefficient of variation over load bins, before and after normalisation.

    ``reduction = 1 - cv_norm / cv_raw`` (positive when normalising brings people together).
    Only bins with at least ``min_participants`` participants count.
    """
    rows = []
    if spread.empty:
        return pd.DataFrame(columns=["sample", "direction", "n_bins", "cv_raw", "cv_norm", "reduction"])
    ok = spread[spread["n_participants"] >= min_participants]
    for (sample, direction), g in ok.groupby(["sample", "direction"], sort=True):
        cv_raw = float(g["mu_cv"].mean())
        cv_norm = float(g["mu_norm_cv"].mean()) if sample != reference else math.nan
        rows.append({"sample": sample, "direction": direction, "is_reference": sample == reference,
                     "n_bins": len(g), "cv_raw": cv_raw, "cv_norm": cv_norm,
                     "reduction": 1.0 - cv_norm / cv_raw if cv_raw > 0 else math.nan})
    return pd.DataFrame(rows)
