"""What a paper reports: the population per texture, across participants.

* :func:`population_curves` - per sample, direction and load bin, the mean over participants of
  each participant's mean ``ln mu_norm`` (and ``ln mu``), back-transformed (a geometric mean),
  with a between-person interval: Student t with ``P - 1`` df on the participants' values
  (each person counts once, however many strokes they made).
* :func:`population_fits` - the power law across participants, ``k = exp(a)``, ``n = b + 1``,
  two ways: a linear mixed-effects model (statsmodels ``MixedLM``)
  ``ln y = a + b ln F + (a_p + b_p ln F) + c_recording + e`` with a random level and slope per
  participant and a variance component per recording inside the participant, and a two-stage
  estimate (each participant's own power law, then the mean and spread of their ``ln k`` and
  ``n``). ``y`` is ``mu_norm`` on textures and ``mu`` on the reference. The numbers come from
  the mixed model when its variance components are estimable (converged, positive-definite
  covariance of level and slope, an invertible Hessian: judged by the estimates, never by a
  warning's text) and its interval of n is not under half the two-stage one; otherwise from
  the two-stage estimate. Column ``source`` says which. Intervals with ``P - 1`` df (few
  participants: a normal quantile would be too narrow). People differ in their exponent n,
  and a model without the random slope would count every stroke as evidence on the mean n:
  its interval of n is then some four times too narrow (it covered the true n in about 30 %
  of simulated studies).
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pandas as pd

from ..errors import FingerpadError
from .curves import fit_power_law_clustered
from .stats import t_quantile
from .tables import bin_index, cluster_column

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
    "sample", "direction", "quantity", "source", "model", "n_participants", "n_recordings", "n_strokes", "k",
    "k_ci_low", "k_ci_high", "n", "n_ci_low", "n_ci_high", "sd_participant_level", "sd_participant_slope",
    "sd_recording", "sd_stroke", "converged", "mixed_k", "mixed_n", "mixed_n_se", "two_stage_k", "two_stage_n",
    "two_stage_n_se", "note",
]

#: ``source`` of the numbers of a population fit.
MIXED, TWO_STAGE = "mixed model", "two-stage"

#: Fewest participants for a random slope: a slope variance from fewer people is noise.
MIN_PARTICIPANTS_SLOPE = 5


def _two_stage(g: pd.DataFrame, col: str, level: float) -> dict[str, Any]:
    """Per-participant power laws (random intercept per recording), then the mean and spread of
    their ``ln k`` and ``n`` over participants: Student t with ``P - 1`` df.

    Each person counts once whatever their number of strokes; the spread of the per-person
    estimates holds both the true between-person spread and each fit's own error, which is what
    the interval of the mean needs (exact for a balanced design, robust otherwise)."""
    levels, slopes, var_a, var_b, failed = [], [], [], [], []
    for participant, gp in g.groupby("participant", sort=True):
        try:
            fit = fit_power_law_clustered(gp["load"].to_numpy(), gp[col].to_numpy(), cluster_column(gp))
        except FingerpadError as exc:
            failed.append(f"{participant} ({exc})")
            continue
        levels.append(math.log(fit.k))
        slopes.append(fit.n - 1.0)
        var_a.append(float(fit.log_covariance[0, 0]))
        var_b.append(float(fit.log_covariance[1, 1]))
    p = len(levels)
    out: dict[str, Any] = {"participants_fitted": p}
    if failed:
        out["note"] = "left out of the two-stage estimate: " + ", ".join(failed)
    if p < 3:
        return out
    a, b = np.array(levels), np.array(slopes)
    se_a, se_b = float(a.std(ddof=1)) / math.sqrt(p), float(b.std(ddof=1)) / math.sqrt(p)
    q = t_quantile(level, p - 1)
    out.update(
        a=float(a.mean()), b=float(b.mean()), se_a=se_a, se_b=se_b, q=q,
        # method of moments: the observed spread less the per-person fits' own error
        sd_level=math.sqrt(max(float(a.var(ddof=1)) - float(np.mean(var_a)), 0.0)),
        sd_slope=math.sqrt(max(float(b.var(ddof=1)) - float(np.mean(var_b)), 0.0)),
    )
    return out


def _estimable(res: Any) -> tuple[bool, str]:
    """Whether a fitted MixedLM's numbers can be used, judged by the estimates themselves.

    statsmodels warns "the MLE may be on the boundary of the parameter space" on nearly every
    fit with a variance component per recording (one of the variances is small), so a warning's
    text says nothing. What matters: the optimiser converged, the covariance of the random
    level and slope is positive definite (the slope variance is not collapsed to zero), and the
    Hessian of the restricted likelihood can be inverted at the estimate (every standard
    error finite and positive).
    """
    if not res.converged:
        return False, "did not converge"
    cov_re = np.asarray(res.cov_re, dtype=float)
    eig = np.linalg.eigvalsh(cov_re) if cov_re.size else np.zeros(0)
    if eig.size and not eig.min() > 1e-8 * max(float(eig.max()), 1e-300):
        return False, "the covariance of the random level and slope is singular (a variance at zero)"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bse = np.asarray(res.bse, dtype=float)
    if not (np.all(np.isfinite(bse)) and np.all(bse > 0)):
        return False, "the Hessian of the likelihood cannot be inverted at the estimate"
    return True, ""


def _mixed(g: pd.DataFrame, col: str) -> tuple[Any, str, bool, str]:
    """The mixed model ``ln y = a + b ln F + (a_p + b_p ln F) + c_recording + e``: the result
    (or None), its description, whether it has a variance component per recording, and why it
    was not usable."""
    from statsmodels.regression.mixed_linear_model import MixedLM

    y = np.log(g[col].to_numpy(dtype=float))
    x = np.log(g["load"].to_numpy(dtype=float))
    participant = g["participant"].astype(str).to_numpy()
    recording = cluster_column(g)
    has_rec = len(set(recording)) > len(set(participant))
    exog = np.column_stack([np.ones_like(x), x])
    exog_vc = None
    if has_rec:
        # recordings nested in participants: one dummy matrix per participant (no formula parsing)
        exog_vc = {"recording": {}}
        for p in sorted(set(participant)):
            sel = participant == p
            recs = sorted(set(recording[sel]))
            exog_vc["recording"][p] = (recording[sel][:, None] == np.array(recs)[None, :]).astype(float)
    name = "random level and slope per participant" + (", variance component per recording" if has_rec else "")
    try:
        with warnings.catch_warnings():
            # its warnings are judged by the numbers below (_estimable), not shown
            warnings.simplefilter("ignore")
            res = MixedLM(y, exog, groups=participant, exog_re=exog, exog_vc=exog_vc).fit(reml=True, method=["lbfgs"])
    except (np.linalg.LinAlgError, ValueError) as exc:
        return None, name, has_rec, f"mixed model failed ({exc})"
    ok, why = _estimable(res)
    return res, name, has_rec, "" if ok else f"mixed model not usable: {why}"


def _population_fit(g: pd.DataFrame, col: str, level: float) -> dict[str, Any]:
    """Mixed model and two-stage estimate of one sample and direction; the numbers come from
    the mixed model where its variance components are estimable, else from the two-stage
    estimate (``source`` says which; both are kept in the ``mixed_*``/``two_stage_*`` columns)."""
    participant = g["participant"].astype(str).to_numpy()
    n_p = len(set(participant))
    n_rec = len(set(cluster_column(g)))
    out: dict[str, Any] = {"n_participants": n_p, "n_recordings": n_rec, "n_strokes": len(g)}
    if n_p < 3:
        out["note"] = f"{n_p} participant(s): a fit across participants needs at least 3"
        return out
    notes = []
    two = _two_stage(g, col, level)
    if two.get("note"):
        notes.append(two["note"])
    if "a" in two:
        out.update(two_stage_k=math.exp(two["a"]), two_stage_n=two["b"] + 1.0, two_stage_n_se=two["se_b"])
    res, usable = None, False
    if n_p >= MIN_PARTICIPANTS_SLOPE:
        res, name, has_rec, why = _mixed(g, col)
        out["model"] = name
        usable = res is not None and not why
        if why:
            notes.append(why)
        if res is not None:
            out["converged"] = bool(res.converged)
    else:
        notes.append(f"mixed model not attempted: a slope variance from fewer than {MIN_PARTICIPANTS_SLOPE} "
                     "participants is noise")
    q = t_quantile(level, n_p - 1)
    if usable:
        a, b = (float(v) for v in np.asarray(res.fe_params)[:2])
        se_a, se_b = (float(v) for v in np.asarray(res.bse_fe)[:2])
        cov_re = np.asarray(res.cov_re, dtype=float)
        vcomp = np.asarray(getattr(res, "vcomp", np.zeros(0)), dtype=float)
        out.update(
            source=MIXED, mixed_k=math.exp(a), mixed_n=b + 1.0, mixed_n_se=se_b,
            sd_participant_level=math.sqrt(max(cov_re[0, 0], 0.0)),
            sd_participant_slope=math.sqrt(max(cov_re[1, 1], 0.0)),
            sd_recording=math.sqrt(max(float(vcomp[0]), 0.0)) if has_rec and vcomp.size else math.nan,
            sd_stroke=math.sqrt(float(res.scale)),
        )
        if "a" in two and se_b < 0.5 * two["se_b"]:
            # the per-person exponents scatter far more than the mixed model allows for: its
            # slope variance is underestimated, and the wider two-stage interval is the honest one
            usable = False
            notes.append(f"mixed-model error of n ({se_b:.2g}) under half the two-stage one ({two['se_b']:.2g}): "
                         "two-stage numbers reported")
    if not usable:
        if "a" not in two:
            out["note"] = "; ".join(notes + ["fewer than 3 participants could be fitted one by one"])
            return out
        a, b, se_a, se_b, q = two["a"], two["b"], two["se_a"], two["se_b"], two["q"]
        out.update(source=TWO_STAGE, sd_participant_level=two["sd_level"], sd_participant_slope=two["sd_slope"])
    out.update(
        k=math.exp(a), k_ci_low=math.exp(a - q * se_a), k_ci_high=math.exp(a + q * se_a),
        n=b + 1.0, n_ci_low=b + 1.0 - q * se_b, n_ci_high=b + 1.0 + q * se_b, note="; ".join(notes),
    )
    return out


def population_fits(strokes: pd.DataFrame, reference: str, level: float = 0.95) -> pd.DataFrame:
    """Power law across participants per sample and direction (see module doc).

    Returns
    -------
    DataFrame
        One row per sample and direction (:data:`POPULATION_FIT_COLUMNS`): ``k``, ``n`` and
        their intervals at ``level`` from ``source`` (``"mixed model"`` or ``"two-stage"``),
        the between-person standard deviations of ``ln k`` (``sd_participant_level``) and of
        ``n`` (``sd_participant_slope``), and both estimates side by side (``mixed_*``,
        ``two_stage_*``) for comparison.
    """
    return pd.DataFrame(population_fit_rows(strokes, reference, level), columns=POPULATION_FIT_COLUMNS)


def population_fit_rows(strokes: pd.DataFrame, reference: str, level: float = 0.95) -> list[dict[str, Any]]:
    """The rows of :func:`population_fits`, in its order: those of a study's samples one by one,
    put together, are the study's."""
    df = strokes[~strokes["outlier"]]
    rows = []
    for (sample, direction), g in df.groupby(["sample", "direction"], sort=True):
        # the reference's own friction law; on textures the normalised friction (what compares
        # textures across people)
        for quantity in (("mu",) if sample == reference else ("mu_norm",)):
            row = {"sample": sample, "direction": direction, "quantity": quantity}
            row.update(_population_fit(g, quantity, level))
            rows.append(row)
    return rows
