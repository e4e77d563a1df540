"""The explorer's plots filled from the library's results (a Prediction, a ContactResult).

The prediction's figures (areas, friction, zones) are the ones ``fingerpad predict`` draws,
defined once in :mod:`fingerpad.plotting.prediction_specs`: :func:`prediction_panels` takes their
panels. The plots only the explorer has (the unit cell's height map, psi(p), the contact maps at
one pressure, the comparison of pinned designs, the bands of a population) are defined here, on the same
:mod:`fingerpad.plotting.specs`. Every value is held in SI; the axes say how it is shown (lengths
of the cell in um, of the pad in mm, areas in mm², pressures in kPa).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..plotting.prediction_specs import RED, areas_figure, friction_figure, load_axis, zones_figure
from ..plotting.specs import DESIGN_COLOURS, Axis, Fill, Image, Line, PlotSpec, VLine

__all__ = [
    "compare_specs",
    "contact_specs",
    "height_map_spec",
    "population_specs",
    "prediction_panels",
    "psi_spec",
]

HERTZ_COLOUR = "#9e1b1b"
_UM = {"unit": "m", "shown": "um", "factor": 1e6}
_KPA = {"unit": "Pa", "shown": "kPa", "factor": 1e-3}


def _finite(v: Any) -> bool:
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v)


def prediction_panels(pred: Any) -> dict[str, PlotSpec]:
    """The panels of ``predict``'s figures by key: areas, friction, friction-normalised (and
    friction-directional), zones, zone-profile."""
    return {panel.key: panel for fig in (areas_figure(pred), friction_figure(pred), zones_figure(pred))
            for panel in fig.panels}


def height_map_spec(texture: Any) -> PlotSpec:
    """The unit cell's height map, x horizontal."""
    lx, ly = texture.size
    return PlotSpec(
        key="height-map", title=f"unit cell: {texture.name}, {texture.shape[0]} x {texture.shape[1]} px",
        x=Axis("x", **_UM), y=Axis("y", **_UM), equal_aspect=True, grid=False,
        images=[Image(np.asarray(texture.heights, float).T, 0.0, lx, 0.0, ly, Axis("height", **_UM), "greys")],
        meta={"texture": texture.name, "params": {k: v for k, v in texture.params.items()
                                                  if isinstance(v, (int, float, str))},
              "size_m": list(texture.size), "grid": list(texture.shape)},
    )


def psi_spec(pred: Any, mark_pressure: float | None = None) -> PlotSpec:
    """psi(p) of the unit cell(s): BEM nodes and interpolation, Hertz analytic; the transition
    and full-contact pressures as reference lines."""
    lo, hi = pred.pressure_range
    states = []
    for cell in (pred.cell, pred.hertz_cell):
        if cell is None:
            continue
        for p in (cell.transition_pressure, cell.full_contact_pressure):
            if _finite(p) and p > 0:
                states.append(float(p))
    lo = min([lo, *[0.5 * p for p in states]])
    hi = max([hi, *[2.0 * p for p in states]])
    ps = np.geomspace(lo, hi, 240)
    meta = {"texture": pred.texture.name, "model": pred.primary_model, "reduced_modulus_Pa": pred.reduced_modulus}
    spec = PlotSpec(key="psi", title="real-to-nominal contact fraction of the unit cell, ψ(p)",
                    x=Axis("mean cell pressure p", log=True, **_KPA),
                    y=Axis("ψ = A_re / A", limits=(0.0, 1.02)), meta=meta)
    if pred.cell is not None and not pred.cell.flat:
        c = pred.cell
        nodes = c.curve()
        spec.lines.append(Line("BEM (interpolated)", ps, np.asarray(c.contact_fraction(ps), float), RED))
        spec.lines.append(Line("BEM nodes", nodes["pressure"], nodes["contact_fraction"], RED, markers=True,
                               line=False, tooltips={"state": np.asarray(nodes["contact_state"]).astype(str)}))
        for p, label, dash in ((c.transition_pressure, "p_t bem", "solid"),
                               (c.full_contact_pressure, "p_full bem", "dotted")):
            if _finite(p):
                spec.vlines.append(VLine(float(p), f"{label} = {p / 1e3:.4g} kPa", "black", dash))
    if pred.hertz_cell is not None:
        h = pred.hertz_cell
        spec.lines.append(Line("Hertz (Eqs. 3.1-3.3)", ps, np.asarray(h.contact_fraction(ps), float), HERTZ_COLOUR,
                               dash="dashed"))
        spec.vlines.append(VLine(float(h.transition_pressure),
                                 f"p_t hertz = {h.transition_pressure / 1e3:.4g} kPa", "black", "dashed"))
    if mark_pressure is not None and _finite(mark_pressure):
        spec.vlines.append(VLine(float(mark_pressure), f"contact map at {mark_pressure / 1e3:.4g} kPa", "#2ca02c",
                                 "dotdash"))
    return spec


def contact_specs(res: Any) -> tuple[PlotSpec, PlotSpec]:
    """The contact pressure map and the contact over the height map at one mean pressure."""
    tex = res.texture
    lx, ly = tex.size
    meta = {"mean_pressure_Pa": float(res.mean_pressure), "contact_fraction": float(res.contact_fraction),
            "contact_state": str(res.contact_state), "max_pressure_Pa": float(res.max_pressure),
            "converged": bool(res.converged), "iterations": int(res.iterations), "grid": list(tex.shape)}
    title = (f"at p = {res.mean_pressure / 1e3:.4g} kPa: ψ = {res.contact_fraction:.3g}"
             + ("" if res.converged else " (NOT converged)"))
    pmap = PlotSpec(key="pressure-map", title="pressure " + title, x=Axis("x", **_UM), y=Axis("y", **_UM),
                    equal_aspect=True, grid=False, meta=meta,
                    images=[Image(np.asarray(res.pressure, float).T, 0.0, lx, 0.0, ly,
                                  Axis("contact pressure", **_KPA), "viridis")])
    cmap = PlotSpec(key="contact-map", title=f"contact (red), state {res.contact_state}", x=Axis("x", **_UM),
                    y=Axis("y", **_UM), equal_aspect=True, grid=False, meta=meta,
                    images=[Image(np.asarray(tex.heights, float).T, 0.0, lx, 0.0, ly, Axis("height", **_UM),
                                  "greys", overlay=np.asarray(res.pressure > 0).T)])
    return pmap, cmap


def compare_specs(designs: Sequence[tuple[str, Any]]) -> list[PlotSpec]:
    """A_re/A_fr, mu and mu/mu_ref of the pinned designs overlaid, critical loads marked."""
    out = []
    for key, title, name, attr in (
        ("compare-area-ratio", "real-to-ridge area A_re / A_fr", "A_re / A_fr", "area_ratio"),
        ("compare-friction", "friction coefficient μ", "μ", "mu"),
        ("compare-normalised", "normalised friction μ / μ_ref", "μ / μ_ref", "mu_normalised"),
    ):
        x = Axis("normal load F", "N", log=bool(designs) and all(load_axis(p.primary.load).log for _, p in designs))
        spec = PlotSpec(key=key, title=title, x=x, y=Axis(name), meta={"designs": [label for label, _ in designs]})
        for k, (label, pred) in enumerate(designs):
            cur = pred.primary
            y = getattr(cur, attr)
            if y is None:
                continue
            colour = DESIGN_COLOURS[k % len(DESIGN_COLOURS)]
            short = label.split(" ", 1)[0]  # "#1": the list above the plots names the design
            spec.lines.append(Line(f"{short} ({pred.primary_model})", cur.load, np.asarray(y, float), colour,
                                   width=2.0))
            f = pred.critical_load.get(pred.primary_model)
            if _finite(f) and float(cur.load.min()) <= f <= float(cur.load.max()):
                spec.vlines.append(VLine(float(f), f"F_crit {short} = {f:.4g} N", colour, "dashed", width=1.3))
        out.append(spec)
    return out


POPULATION_COLOUR = "#1f77b4"


def population_specs(result: Any) -> list[PlotSpec]:
    """A population's bands against load and its critical loads (a
    :class:`~fingerpad.population.run.PopulationResult`).

    ``population-area-ratio`` and ``population-normalised``: A_re/A_fr and mu/mu_ref, the median
    and the bands between the outer and inner pairs of the reported quantiles (5-95 % and
    25-75 % by default: the values of ``result.quantiles()``, as ``predict --population``
    reports them), the study's own finger dashed. ``population-critical-load``: the share of the
    fingers whose pad centre has left asperity contact at a load, i.e. the empirical distribution
    of the members' critical loads (N), their 5/50/95 % quantiles marked.
    """
    nominal = result.nominal
    loads = np.asarray(nominal.primary.load, float)
    x = load_axis(loads)
    levels = sorted(result.quantile_levels)
    table = result.quantiles()
    meta = {"population": result.population.name, "members": len(result.members), "model": nominal.primary_model,
            "texture": nominal.texture.name, "quantiles": [float(q) for q in levels]}
    out = []
    for key, title, name, quantity in (
        ("population-area-ratio", "real-to-ridge area A_re / A_fr", "A_re / A_fr", "area_ratio"),
        ("population-normalised", "normalised friction μ / μ_ref", "μ / μ_ref", "mu_normalised"),
    ):
        spec = PlotSpec(key=key, title=f"{title}, {len(result.members)} fingers ({result.population.name})",
                        x=x, y=Axis(name, limits=(0.0, None)), legend="upper right", meta=meta)
        bands = table[quantity]
        for depth in range(len(levels) // 2):
            lo, hi = levels[depth], levels[-1 - depth]
            spec.fills.append(Fill(f"{100 * lo:g}-{100 * hi:g} % of fingers", loads, np.asarray(bands[f"{lo:g}"]),
                                   np.asarray(bands[f"{hi:g}"]), POPULATION_COLOUR, alpha=0.2 + 0.15 * depth))
        if 0.5 in levels:
            spec.lines.append(Line("median", loads, np.asarray(bands["0.5"], float), POPULATION_COLOUR, width=2.0))
        own = getattr(nominal.primary, quantity)
        if own is not None:
            spec.lines.append(Line(f"the study's finger ({nominal.primary_model})", loads, np.asarray(own, float),
                                   "black", dash="dashed"))
        out.append(spec)
    crit = np.asarray(result.critical_load, float)
    reached = np.sort(crit[np.isfinite(crit) & (crit > 0)])
    never = crit.size - reached.size
    spec = PlotSpec(key="population-critical-load",
                    title=f"critical loads: {never} of {crit.size} fingers never reach the transition",
                    x=Axis("critical load F_crit", "N", log=bool(reached.size and reached[-1] / reached[0] > 5)),
                    y=Axis("fingers past the transition at F (share)", limits=(0.0, 1.02)), legend="upper left",
                    meta={**meta, "never_reaching": int(never)})
    if reached.size:
        share = np.arange(1, reached.size + 1) / crit.size  # of all fingers: those never reaching count as not past
        spec.lines.append(Line("share of fingers with F_crit <= F", reached, share, POPULATION_COLOUR, width=2.0))
        for level, dash in ((levels[0], "dashed"), (0.5, "solid"), (levels[-1], "dashed")):
            f = table["critical_load"].get(f"{level:g}")
            if _finite(f):
                spec.vlines.append(VLine(float(f), f"{100 * level:g} % quantile = {f:.3g} N", "black", dash))
    out.append(spec)
    return out
