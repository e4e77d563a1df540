"""The fits of a study that do not depend on one another: each texture's model tables, each
condition's summary row (transition test, E_s fit and sensitivity refits), each participant's
joint E_s, each sample's population fit.

:class:`StudyFits` holds what they read (the study's strokes, power laws, reference fits and
tables); its methods take an index or a group and return plain results, so that
:func:`~.parallel.forked_map` can run them in worker processes that inherit the object (only the
indices and the results travel).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd

from ..errors import FingerpadError
from .across_participants import population_fit_rows
from .breakpoint import Breakpoint, find_breakpoint
from .curves import fit_row, sense_ratio
from .micro_models import Model, TextureGeometry
from .modulus import ModelTable, ModulusFit, estimate_skin_modulus, estimate_skin_modulus_joint
from .modulus_sensitivity import Variants, sensitivity_rows, variant_tables
from .study import AnalysisOptions
from .tables import GROUP, cluster_column
from .transition import modulus_from_transition

__all__ = ["StudyFits"]


def _closed_form(bp: Breakpoint, geom: TextureGeometry, finger: Any) -> tuple[float, float, float]:
    """E_s (Pa) from the transition load of ``bp`` and the texture's geometry in closed form
    (:func:`~.transition.modulus_from_transition`), and its range over the load's interval;
    NaN where the closed form has no answer."""
    def one(load: float) -> float:
        try:
            return modulus_from_transition(load, geom.radius, geom.height, geom.spacing, finger,
                                           skin_poisson=finger.skin_poisson, material_modulus=geom.material_modulus,
                                           material_poisson=geom.material_poisson)
        except FingerpadError:
            return math.nan
    vals = [one(bp.load), one(bp.ci_low), one(bp.ci_high)]
    if not any(math.isfinite(v) for v in vals):
        return math.nan, math.nan, math.nan
    lo, hi = np.nanmin(vals), np.nanmax(vals)
    return vals[0], float(lo), float(hi)


def _modulus_columns(mf: ModulusFit) -> dict[str, Any]:
    """The summary table's columns of an E_s fit."""
    return {"skin_modulus": mf.skin_modulus, "skin_modulus_ci_low": mf.ci_low, "skin_modulus_ci_high": mf.ci_high,
            "skin_modulus_interval": mf.describe_interval(), "skin_modulus_model": mf.model,
            "skin_modulus_determined": mf.determined, "skin_modulus_at_bound": mf.at_bound,
            "skin_modulus_note": mf.note, "model_scale": mf.scale}


class StudyFits:
    """The independent fits of one study (see the module doc).

    Parameters
    ----------
    opts
        The analysis options.
    strokes
        Every usable stroke with ``mu_norm`` (:func:`~.curves.normalise`), outliers flagged.
    power_laws, ref_fits
        The power laws per condition and sense, and each participant's reference fit.
    textures
        Sample -> geometry (or ``None``).
    finger
        The finger of the closed-form E_s and the variant tables.
    models
        Sample -> model of the normalised friction; a table is made for each textured sample
        (:meth:`sample_tables`) before the conditions are fitted.
    """

    def __init__(self, opts: AnalysisOptions, strokes: pd.DataFrame, power_laws: dict[tuple[str, ...], Any],
                 ref_fits: dict[tuple[str, str], Any], textures: dict[str, TextureGeometry | None], finger: Any,
                 models: dict[str, Model]) -> None:
        self.opts, self.strokes, self.power_laws, self.ref_fits = opts, strokes, power_laws, ref_fits
        self.textures, self.finger = textures, finger
        self.fit_kw = dict(level=opts.level, fit_scale=opts.fit_scale)
        self.usable = strokes[~strokes["outlier"]]
        #: (sample, model, load range) of every textured sample with usable strokes
        self.plan: list[tuple[str, Model, tuple[float, float]]] = []
        for sample, model in models.items():
            loads = self.usable.loc[self.usable["sample"] == sample, "load"].to_numpy()
            if loads.size and sample != opts.reference:
                self.plan.append((sample, model, (float(loads.min()), float(loads.max()))))
        self.tables: dict[str, ModelTable] = {}
        self.variants: dict[str, Variants] = {}
        # each condition's usable strokes, looked up once (the rows and their order of a boolean
        # selection per condition, without a pass over the whole table for each)
        self.usable_of = {key: g for key, g in self.usable.groupby(GROUP, sort=True)}
        self.no_strokes = self.usable.iloc[:0]
        self.by_condition = list(strokes.groupby(GROUP, sort=True))
        self.by_participant = list(self.usable.groupby("participant", sort=True))
        # the population fits per sample (each reads only its own strokes)
        self.by_sample = [g for _, g in strokes.groupby("sample", sort=True)] if opts.population else []

    def set_tables(self, made: list[tuple[ModelTable, Variants | None] | str]) -> None:
        """Keep the tables :meth:`sample_tables` made for each sample of :attr:`plan`, in order.

        Raises
        ------
        FingerpadError
            For a sample whose table could not be made (the message says why)."""
        for (sample, _, _), one in zip(self.plan, made, strict=True):
            if isinstance(one, str):
                raise FingerpadError(one)
            self.tables[sample] = one[0]
            if one[1] is not None:
                self.variants[sample] = one[1]

    def pieces(self) -> list[tuple[str, int]]:
        """Every piece :meth:`piece` computes: the population fits (the longest) first, so that no
        worker starts one last, then the conditions, then the participants."""
        return ([("population", i) for i in range(len(self.by_sample))]
                + [("condition", i) for i in range(len(self.by_condition))]
                + [("participant", i) for i in range(len(self.by_participant))])

    def sample_tables(self, i: int) -> tuple[ModelTable, Variants | None] | str:
        """The table of one texture, shared by every participant's fit, and its variants' (or
        why there is none); detached, to come back from a worker."""
        sample, model, load_range = self.plan[i]
        try:
            table = ModelTable(model, load_range, self.opts.modulus_bounds)
        except FingerpadError as exc:
            return f"model of sample {sample!r}: {exc}"
        if not self.opts.sensitivity:
            return table.detached(), None
        found = variant_tables(self.textures.get(sample), model, self.finger, load_range, self.opts.modulus_bounds)
        return table.detached(), Variants({key: t.detached() for key, t in found.tables.items()})

    def condition(self, item: tuple[tuple[str, str, str], pd.DataFrame]
                  ) -> tuple[dict[str, Any], Breakpoint | None, ModulusFit | None, list[dict[str, Any]]]:
        """The summary row of one condition, its breakpoint test, E_s fit and sensitivity refits."""
        key, g = item
        participant, sample, direction = key
        good = self.usable_of.get(key, self.no_strokes)
        bp_out: Breakpoint | None = None
        mf_out: ModulusFit | None = None
        srows_out: list[dict[str, Any]] = []
        clusters = cluster_column(good)
        row: dict[str, Any] = dict(zip(GROUP, key))
        row.update(is_reference=sample == self.opts.reference, n_files=g["file"].nunique(), n_strokes=len(g),
                   n_outliers=int(g["outlier"].sum()), load_min=float(g["load"].min()),
                   load_max=float(g["load"].max()))
        fit = self.power_laws.get((*key, "both"))
        row.update(fit_row(fit) if fit is not None else {})
        row["mu_at_1N"] = float(fit(np.array([1.0]))[0]) if fit is not None else math.nan
        ratio, r_lo, r_hi = sense_ratio(g, self.opts.level)
        row.update(sense_ratio=ratio, sense_ratio_ci_low=r_lo, sense_ratio_ci_high=r_hi)
        row["mu_norm_mean"] = float(good["mu_norm"].mean()) if sample != self.opts.reference else 1.0
        notes_row = [fit.note] if fit is not None and fit.note else []
        if sample != self.opts.reference:
            try:
                bp = find_breakpoint(good["load"].to_numpy(), good["mu_norm"].to_numpy(),
                                     space=self.opts.breakpoint_space, method=self.opts.breakpoint_method,
                                     trend=self.opts.breakpoint_trend, level=self.opts.level, n_boot=self.opts.n_boot,
                                     n_null=self.opts.n_null, seed=self.opts.seed, clusters=clusters,
                                     edge=self.opts.breakpoint_edge)
                bp_out = bp
                row.update({c: math.nan for c in ("breakpoint_load", "breakpoint_ci_low", "breakpoint_ci_high",
                                                  "slope_below", "slope_above")})
                # a best location at the edge of the load range is named in `transition` (with
                # why it is not a transition) but gives no breakpoint load and no closed-form E_s
                row.update(breakpoint_detected=bp.detected, breakpoint_p=bp.p_value,
                           breakpoint_search_low=bp.search_low, breakpoint_search_high=bp.search_high,
                           breakpoint_edge_low=bp.edge_low, breakpoint_edge_high=bp.edge_high,
                           breakpoint_outside=bp.outside, transition=bp.describe())
                if bp.detected:
                    row.update(breakpoint_load=bp.load, breakpoint_ci_low=bp.ci_low, breakpoint_ci_high=bp.ci_high,
                               slope_below=bp.slope_below, slope_above=bp.slope_above)
                    geom = self.textures.get(sample)
                    if geom is not None:
                        e, lo, hi = _closed_form(bp, geom, self.finger)
                        row.update(skin_modulus_closed_form=e, skin_modulus_closed_form_ci_low=lo,
                                   skin_modulus_closed_form_ci_high=hi)
            except FingerpadError as exc:
                notes_row.append(f"breakpoint: {exc}")
            table = self.tables.get(sample)
            if table is not None:
                ref = self.ref_fits[(participant, "both")]

                def refit(t: ModelTable, good: pd.DataFrame = good, ref: Any = ref, clusters: Any = clusters
                          ) -> ModulusFit:
                    return estimate_skin_modulus(good["load"], good["mu_norm"], t, reference=ref,
                                                 clusters=clusters, **self.fit_kw)
                try:
                    mf = refit(table)
                    mf_out = mf
                    row.update(_modulus_columns(mf))
                    if sample in self.variants:
                        refits = [(p, v, (lambda t=t: refit(t))) for (p, v), t in self.variants[sample].tables.items()]
                        srows, summary = sensitivity_rows(mf, refits, dict(zip(GROUP, key)))
                        srows_out = srows
                        row.update(summary)
                except FingerpadError as exc:
                    notes_row.append(f"modulus: {exc}")
        row["note"] = "; ".join(n for n in notes_row if n)
        return row, bp_out, mf_out, srows_out

    def participant_row(self, item: tuple[str, pd.DataFrame]
                        ) -> tuple[dict[str, Any], ModulusFit | None, list[dict[str, Any]]]:
        """One participant's row: the reference fit and the joint E_s over its textures, with
        its sensitivity refits."""
        participant, g = item
        mf_out: ModulusFit | None = None
        srows_out: list[dict[str, Any]] = []
        ref = self.ref_fits[(participant, "both")]
        row = {"participant": participant, "n_strokes": int((self.strokes["participant"] == participant).sum())}
        row.update({f"ref_{k}": v for k, v in fit_row(ref).items()})
        subs = [sub for (s, _), sub in g.groupby(["sample", "direction"]) if s in self.tables]
        if subs:
            def joint(pick: Any, subs: list[pd.DataFrame] = subs, ref: Any = ref) -> ModulusFit:
                data = [(sub["load"].to_numpy(), sub["mu_norm"].to_numpy(), pick(sub["sample"].iloc[0]))
                        for sub in subs]
                if len(data) == 1:
                    return estimate_skin_modulus(*data[0], reference=ref, clusters=cluster_column(subs[0]),
                                                 **self.fit_kw)
                return estimate_skin_modulus_joint(data, reference=ref, clusters=[cluster_column(s) for s in subs],
                                                   **self.fit_kw)
            try:
                mf = joint(self.tables.get)
                mf_out = mf
                row.update({k: v for k, v in _modulus_columns(mf).items() if k != "model_scale"},
                           n_textures=len(subs))
                samples = {sub["sample"].iloc[0] for sub in subs}
                if self.opts.sensitivity and samples <= set(self.variants):
                    # the same variant for every texture of the participant
                    common = set.intersection(*(set(self.variants[s].tables) for s in samples))
                    refits = [(p, v, (lambda k=(p, v): joint(lambda s: self.variants[s].tables[k])))
                              for (p, v) in sorted(common, key=lambda k: (k[0] != "micro_model", k))]
                    srows, summary = sensitivity_rows(mf, refits, {"participant": participant,
                                                                    "sample": "all textures", "direction": ""})
                    srows_out = srows
                    row.update(summary)
            except FingerpadError as exc:
                row["note"] = f"modulus: {exc}"
        return row, mf_out, srows_out

    def piece(self, item: tuple[str, int]) -> Any:
        """One independent piece of the fits: a population fit, a condition or a participant
        (``(kind, index)``: the workers hold the groups, only the index travels)."""
        kind, i = item
        if kind == "condition":
            return self.condition(self.by_condition[i])
        if kind == "participant":
            return self.participant_row(self.by_participant[i])
        return population_fit_rows(self.by_sample[i], self.opts.reference, self.opts.level)
