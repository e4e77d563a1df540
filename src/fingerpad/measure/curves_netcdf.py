"""The study's curves as NetCDF (:func:`curves_dataset`, written to ``curves.nc`` by
:func:`~.report.write_report`)."""

from __future__ import annotations

import math

import numpy as np

from .. import references
from .._version import __version__
from ..plotting.measure import condition_label
from .study import StudyResult, study_references

__all__ = ["curves_dataset"]


def curves_dataset(result: StudyResult):
    """The study's curves as an :class:`xarray.Dataset`.

    Dimensions: ``participant``, ``condition`` (sample, or ``sample/direction``), ``sense``
    (``+``, ``-``, ``both``), ``bin`` (load bins shared by the study) and ``load`` (a
    log-spaced grid over the measured loads).

    Variables: binned ``mu_mean``/``mu_sd``/``mu_n``/``mu_norm_mean``/``mu_norm_sd`` and
    ``bin_load`` (median load per bin); power-law ``k``, ``n`` and the fitted ``mu_fit`` on the
    grid; the reference curve ``mu_ref_fit``; per condition ``skin_modulus`` (+ CI),
    ``breakpoint_load`` (+ CI) and the model ``mu_norm_model`` at the fitted E_s. Missing
    combinations are NaN. All SI (N, Pa).
    """
    import xarray as xr

    strokes = result.strokes
    participants = sorted(strokes["participant"].unique())
    conds = sorted({(s, d) for s, d in zip(strokes["sample"], strokes["direction"])})
    labels = [condition_label(s, d) for s, d in conds]
    senses = ["+", "-", "both"]
    nbins = len(result.bin_edges) - 1
    grid = result.load_grid()
    shape_b = (len(participants), len(conds), len(senses), nbins)
    binned = {k: np.full(shape_b, np.nan) for k in ("mu_mean", "mu_sd", "mu_n", "mu_norm_mean", "mu_norm_sd",
                                                     "bin_load")}
    pi = {p: i for i, p in enumerate(participants)}
    ci = {c: i for i, c in enumerate(conds)}
    si = {s: i for i, s in enumerate(senses)}
    for row in result.bins.itertuples(index=False):
        idx = (pi[row.participant], ci[(row.sample, row.direction)], si[row.sense], int(row.bin))
        binned["mu_mean"][idx] = row.mu
        binned["mu_sd"][idx] = row.mu_sd
        binned["mu_n"][idx] = row.n
        binned["mu_norm_mean"][idx] = getattr(row, "mu_norm", np.nan)
        binned["mu_norm_sd"][idx] = getattr(row, "mu_norm_sd", np.nan)
        binned["bin_load"][idx] = row.load
    shape_f = (len(participants), len(conds), len(senses))
    k = np.full(shape_f, np.nan)
    n = np.full(shape_f, np.nan)
    mu_fit = np.full((*shape_f, grid.size), np.nan)
    for (p, s, d, sense), fit in result.power_laws.items():
        idx = (pi[p], ci[(s, d)], si[sense])
        k[idx], n[idx] = fit.k, fit.n
        mu_fit[idx] = np.asarray(fit(grid), dtype=float)
    mu_ref = np.full((len(participants), grid.size), np.nan)
    for (p, sense), fit in result.reference_fits.items():
        if sense == "both":
            mu_ref[pi[p]] = np.asarray(fit(grid), dtype=float)
    shape_c = (len(participants), len(conds))
    per_cond = {name: np.full(shape_c, np.nan) for name in (
        "skin_modulus", "skin_modulus_ci_low", "skin_modulus_ci_high", "breakpoint_load",
        "breakpoint_ci_low", "breakpoint_ci_high", "breakpoint_p", "skin_modulus_closed_form",
        "skin_modulus_other", "skin_modulus_sens_low", "skin_modulus_sens_high", "sense_ratio",
        "sense_ratio_ci_low", "sense_ratio_ci_high")}
    mu_model = np.full((*shape_c, grid.size), np.nan)
    for row in result.conditions.to_dict("records"):
        idx = (pi[row["participant"]], ci[(row["sample"], row["direction"])])
        for name in per_cond:
            value = row.get(name)
            if value is not None and not (isinstance(value, float) and math.isnan(value)):
                per_cond[name][idx] = float(value)
        table = result.tables.get(row["sample"])
        e = row.get("skin_modulus")
        if table is not None and e is not None and np.isfinite(e):
            inside = (grid >= table.loads[0]) & (grid <= table.loads[-1])
            mu_model[idx][inside] = table(grid[inside], float(e))
    dims_b = ("participant", "condition", "sense", "bin")
    dims_f = ("participant", "condition", "sense")
    ds = xr.Dataset(
        data_vars={
            **{name: (dims_b, arr) for name, arr in binned.items()},
            "k": (dims_f, k),
            "n": (dims_f, n),
            "mu_fit": ((*dims_f, "load"), mu_fit),
            "mu_ref_fit": (("participant", "load"), mu_ref),
            **{name: (("participant", "condition"), arr) for name, arr in per_cond.items()},
            "mu_norm_model": (("participant", "condition", "load"), mu_model),
        },
        coords={
            "participant": participants,
            "condition": labels,
            "sample": ("condition", [s for s, _ in conds]),
            "direction": ("condition", [d for _, d in conds]),
            "sense": senses,
            "bin": np.arange(nbins),
            "bin_low": ("bin", result.bin_edges[:-1]),
            "bin_high": ("bin", result.bin_edges[1:]),
            "load": grid,
        },
        attrs={
            "title": "fingerpad friction measurements",
            "fingerpad_version": __version__,
            "reference_sample": result.options.reference,
            "confidence_level": result.options.level,
            "power_law": "mu = k F^(n-1)",
            "references": references.netcdf_attribute(study_references(result)),
        },
    )
    units = {"bin_load": "N", "load": "N", "bin_low": "N", "bin_high": "N", "breakpoint_load": "N",
             "breakpoint_ci_low": "N", "breakpoint_ci_high": "N", "skin_modulus": "Pa",
             "skin_modulus_ci_low": "Pa", "skin_modulus_ci_high": "Pa", "skin_modulus_closed_form": "Pa",
             "skin_modulus_other": "Pa", "skin_modulus_sens_low": "Pa", "skin_modulus_sens_high": "Pa",
             "breakpoint_p": "1", "sense_ratio": "1", "sense_ratio_ci_low": "1", "sense_ratio_ci_high": "1",
             "k": "1", "n": "1", "mu_mean": "1", "mu_sd": "1", "mu_fit": "1", "mu_ref_fit": "1",
             "mu_norm_mean": "1", "mu_norm_sd": "1", "mu_norm_model": "1", "mu_n": "count"}
    for name, unit in units.items():
        ds[name].attrs["units"] = unit
    return ds
