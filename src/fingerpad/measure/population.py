"""What a paper reports: the population per texture, across participants.

* :func:`population_curves` - per sample, direction and load bin, the mean over participants of
  each participant's mean ``ln mu_norm`` (and ``ln mu``), back-transformed (a geometric mean),
  with a between-person interval: Student t with ``P - 1`` df on the participants' values
  (each person counts once, however many strokes they made).
* :func:`population_fits` - a linear mixed-effects model across participants (statsmodels
  ``MixedLM``): ``ln y = a + b ln F + (a_p + b_p ln F) + c_recording + e`` with a random
  intercept and slope per participant and a variance component per recording inside the
  participant; ``y`` is ``mu_norm`` on textures and ``mu`` on the reference. ``k = exp(a)``,
  ``n = b + 1``; intervals with ``P - 1`` df (few participants: a normal quantile would be
  too narrow). If the random slope cannot be estimated the model falls back to a random
  intercept, and says so.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pandas as pd

from .curves import cluster_column
from .stats import t_quantile
from .strokes import bin_index

POPULATION_CURVE_COLUMNS = [
    "sample", "direction", "quantity", "bin", "bin_low", "bin_high", "load", "n_participants", "mean",
    "ci_low", "ci_high", "sd_between_persons",
]


def population_curves(strokes: pd.DataFrame, edges: np.ndarray, reference: str, level: float = 0.95) -> pd.DataFrame:
    """Mean curve over participants per sample/direction/bin with a between-person interval.

    Returns
    -------
    DataFrame
        ``quantity`` is ``mu_norm`` (textures) or ``mu`` (every sample); ``mean`` the geometric
        mean over participants, ``ci_low``/``ci_high`` its interval at ``level``,
        ``sd_between_persons`` the standard deviation of the participants' ``ln`` values. Bins
        with one participant have no interval.
    """
    df = strokes[~strokes["outlier"]]
    df = df.assign(bin=bin_index(df["load"].to_numpy(), edges), ln_mu=np.log(df["mu"]),
                   ln_norm=np.log(df["mu_norm"]))
    per = df.groupby(["participant", "sample", "direction", "bin"]).agg(
        load=("load", "median"), ln_mu=("ln_mu", "mean"), ln_norm=("ln_norm", "mean")).reset_index()
    rows = []
    for (sample, direction, b), g in per.groupby(["sample", "direction", "bin"], sort=True):
        for quantity, col in (("mu", "ln_mu"), ("mu_norm", "ln_norm")):
            if quantity == "mu_norm" and sample == reference:
                continue  # 1 by construction
            v = g[col].to_numpy()
            p = v.size
            mean = float(v.mean())
            sd = float(v.std(ddof=1)) if p > 1 else math.nan
            q = t_quantile(level, p - 1) if p > 1 else math.nan
            half = q * sd / math.sqrt(p) if p > 1 else math.nan
            rows.append({
                "sample": sample, "direction": direction, "quantity": quantity, "bin": int(b),
                "bin_low": float(edges[b]), "bin_high": float(edges[b + 1]), "load": float(np.exp(np.log(g["load"]).mean())),
                "n_participants": p, "mean": math.exp(mean), "ci_low": math.exp(mean - half) if p > 1 else math.nan,
                "ci_high": math.exp(mean + half) if p > 1 else math.nan, "sd_between_persons": sd,
            })
    return pd.DataFrame(rows, columns=POPULATION_CURVE_COLUMNS)


POPULATION_FIT_COLUMNS = [
    "sample", "direction", "quantity", "model", "n_participants", "n_recordings", "n_strokes", "k", "k_ci_low",
    "k_ci_high", "n", "n_ci_low", "n_ci_high", "sd_participant_level", "sd_participant_slope", "sd_recording",
    "sd_stroke", "converged", "note",
]


def _mixed_fit(g: pd.DataFrame, col: str, level: float) -> dict[str, Any]:
    from statsmodels.regression.mixed_linear_model import MixedLM

    y = np.log(g[col].to_numpy(dtype=float))
    x = np.log(g["load"].to_numpy(dtype=float))
    participant = g["participant"].astype(str).to_numpy()
    recording = cluster_column(g)
    n_p = len(set(participant))
    n_rec = len(set(recording))
    out: dict[str, Any] = {"n_participants": n_p, "n_recordings": n_rec, "n_strokes": len(y)}
    if n_p < 3:
        out["note"] = f"{n_p} participant(s): a mixed model across participants needs at least 3"
        return out
    has_rec = n_rec > n_p
    exog = np.column_stack([np.ones_like(x), x])
    exog_vc = None
    if has_rec:
        # recordings nested in participants: one dummy matrix per participant (no formula parsing)
        exog_vc = {"recording": {}}
        for p in sorted(set(participant)):
            sel = participant == p
            recs = sorted(set(recording[sel]))
            exog_vc["recording"][p] = (recording[sel][:, None] == np.array(recs)[None, :]).astype(float)
    notes = []
    attempts = [(exog, "random intercept and slope per participant"), (exog[:, :1], "random intercept per participant")]
    if n_p < 5:  # a slope variance from fewer than five people is noise
        attempts = attempts[1:]
        notes.append("random slope not attempted with fewer than 5 participants")
    res = None
    for exog_re, name in attempts:
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                model = MixedLM(y, exog, groups=participant, exog_re=exog_re, exog_vc=exog_vc)
                res = model.fit(reml=True, method=["lbfgs"])
            bad = [w for w in caught if "converge" in str(w.message).lower() or "singular" in str(w.message).lower()
                   or "boundary" in str(w.message).lower()]
            if exog_re.shape[1] == 2 and (bad or not res.converged):
                notes.append("the random slope could not be estimated")
                res = None
                continue
            break
        except (np.linalg.LinAlgError, ValueError) as exc:
            notes.append(f"{name}: {exc}")
            res = None
    if res is None:
        out["note"] = "; ".join(notes)
        return out
    q = t_quantile(level, n_p - 1)
    a, b = (float(v) for v in np.asarray(res.fe_params)[:2])
    se_a, se_b = (float(v) for v in np.asarray(res.bse_fe)[:2])
    cov_re = np.asarray(res.cov_re, dtype=float)
    vcomp = getattr(res, "vcomp", np.zeros(0))
    out.update(
        model=name + (", variance component per recording" if has_rec else ""),
        k=math.exp(a), k_ci_low=math.exp(a - q * se_a), k_ci_high=math.exp(a + q * se_a),
        n=b + 1.0, n_ci_low=b + 1.0 - q * se_b, n_ci_high=b + 1.0 + q * se_b,
        sd_participant_level=math.sqrt(max(cov_re[0, 0], 0.0)),
        sd_participant_slope=math.sqrt(max(cov_re[1, 1], 0.0)) if cov_re.shape[0] > 1 else math.nan,
        sd_recording=math.sqrt(max(float(vcomp[0]), 0.0)) if has_rec and len(vcomp) else math.nan,
        sd_stroke=math.sqrt(float(res.scale)), converged=bool(res.converged), note="; ".join(notes),
    )
    return out


def population_fits(strokes: pd.DataFrame, reference: str, level: float = 0.95) -> pd.DataFrame:
    """Mixed-effects power law across participants per sample and direction (see module doc)."""
    df = strokes[~strokes["outlier"]]
    rows = []
    for (sample, direction), g in df.groupby(["sample", "direction"], sort=True):
        # the reference's own friction law; on textures the normalised friction (what compares
        # textures across people)
        for quantity in (("mu",) if sample == reference else ("mu_norm",)):
            row = {"sample": sample, "direction": direction, "quantity": quantity}
            row.update(_mixed_fit(g, quantity, level))
            rows.append(row)
    return pd.DataFrame(rows, columns=POPULATION_FIT_COLUMNS)
