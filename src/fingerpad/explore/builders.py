"""The explorer's plots filled from the library's results (a Prediction, a ContactResult).

Each builder returns a :class:`~.specs.PlotSpec`. Values are taken from the prediction as
``fingerpad predict`` computes them (areas, friction, critical loads, zones); the only evaluations
made here are the library's own functions on the prediction's cells (psi(p) of the unit cell,
the pad pressure of Eq. 3.7 along a radius) to draw continuous curves.

Display units: lengths of the cell in um, of the pad in mm, areas in mm^2, pressures in Pa on
psi(p) (log axis) and kPa on maps, loads in N.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .specs import DESIGN_COLOURS, Band, Disc, Image, Line, PlotSpec, VLine

__all__ = [
    "areas_spec",
    "compare_specs",
    "contact_specs",
    "friction_specs",
    "height_map_spec",
    "psi_spec",
    "state_bands",
    "zone_specs",
]

BEM_COLOUR, HERTZ_COLOUR = "#d62728", "#9e1b1b"


def _finite(v: Any) -> bool:
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v)


def state_bands(pred: Any) -> list[Band]:
    """Load intervals (within the loads of the study) of the contact state at the pad centre:
    asperity below the critical load, transition up to the full-contact load, full above."""
    load = pred.primary.load
    lo, hi = float(load.min()), float(load.max())
    model = pred.primary_model
    fc = pred.critical_load.get(model)
    ff = pred.full_contact_load.get(model)
    if pred.cell is not None and pred.cell.flat:
        fc = 0.0
    edges = [("asperity", 0.0), ("transition", fc if _finite(fc) else math.inf),
             ("full", ff if _finite(ff) else math.inf)]
    out = []
    for k, (state, start) in enumerate(edges):
        end = edges[k + 1][1] if k + 1 < len(edges) else math.inf
        a, b = max(start, lo), min(end, hi)
        if b > a:
            out.append(Band(a, b, state))
    return out


def _critical_lines(pred: Any) -> list[VLine]:
    load = pred.primary.load
    lo, hi = float(load.min()), float(load.max())
    out = []
    for model, dash in (("bem", "solid"), ("hertz", "dashed")):
        f = pred.critical_load.get(model)
        if _finite(f) and lo <= f <= hi:
            out.append(VLine(float(f), f"F_crit {model} = {f:.4g} N", "black", dash))
    ff = pred.full_contact_load.get("bem")
    if _finite(ff) and lo <= ff <= hi and ff > 0:
        out.append(VLine(float(ff), f"F_full bem = {ff:.4g} N", "#7f7f7f", "dotted"))
    return out


def _load_log(load: np.ndarray) -> bool:
    lo, hi = float(np.min(load)), float(np.max(load))
    return lo > 0 and hi / lo > 5


def _meta(pred: Any) -> dict[str, Any]:
    return {
        "texture": pred.texture.name,
        "model": pred.primary_model,
        "reduced_modulus_Pa": pred.reduced_modulus,
        "critical_load_N": dict(pred.critical_load),
        "full_contact_load_N": dict(pred.full_contact_load),
        "finger": pred.study.finger.name,
    }


def height_map_spec(texture: Any) -> PlotSpec:
    """The unit cell's height map (um), x horizontal."""
    lx, ly = texture.size
    z = np.asarray(texture.heights, float).T * 1e6
    return PlotSpec(
        key="height-map", title=f"unit cell: {texture.name}, {texture.shape[0]} x {texture.shape[1]} px",
        x_label="x (um)", y_label="y (um)", equal_aspect=True,
        images=[Image(z, 0.0, lx * 1e6, 0.0, ly * 1e6, "height (um)", "greys")],
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
    spec = PlotSpec(key="psi", title="real-to-nominal contact fraction of the unit cell, psi(p)",
                    x_label="mean cell pressure p (Pa)", y_label="psi = A_re / A (-)", x_log=True,
                    y_range=(0.0, 1.02), meta=_meta(pred))
    if pred.cell is not None and not pred.cell.flat:
        c = pred.cell
        nodes = c.curve()
        spec.lines.append(Line("BEM (interpolated)", ps, np.asarray(c.contact_fraction(ps), float), BEM_COLOUR))
        spec.lines.append(Line("BEM nodes", nodes["pressure"], nodes["contact_fraction"], BEM_COLOUR, markers=True,
                               line=False, tooltips={"state": np.asarray(nodes["contact_state"]).astype(str)}))
        for p, label, dash in ((c.transition_pressure, "p_t bem", "solid"), (c.full_contact_pressure, "p_full bem",
                                                                              "dotted")):
            if _finite(p):
                spec.vlines.append(VLine(float(p), f"{label} = {p:.4g} Pa", "black", dash))
    if pred.hertz_cell is not None:
        h = pred.hertz_cell
        spec.lines.append(Line("Hertz (Eqs. 3.1-3.3)", ps, np.asarray(h.contact_fraction(ps), float), HERTZ_COLOUR,
                               dash="dashed"))
        spec.vlines.append(VLine(float(h.transition_pressure), f"p_t hertz = {h.transition_pressure:.4g} Pa",
                                 "black", "dashed"))
    if mark_pressure is not None and _finite(mark_pressure):
        spec.vlines.append(VLine(float(mark_pressure), f"contact map at {mark_pressure:.4g} Pa", "#2ca02c",
                                 "dotdash"))
    return spec


def areas_spec(pred: Any) -> PlotSpec:
    """A_g, A_fr, A_re (BEM and/or Hertz) against load (mm^2)."""
    cur = pred.primary
    f = cur.load
    spec = PlotSpec(key="areas", title="contact areas against load", x_label="normal load F (N)",
                    y_label="contact area (mm^2)", x_log=_load_log(f), y_log=True, meta=_meta(pred))
    spec.lines += [
        Line("gross A_g", f, cur.gross_area * 1e6, "black", width=1.5),
        Line("ridge A_fr", f, cur.ridge_area * 1e6, "#2ca02c", width=1.5),
        Line(f"real A_re ({pred.primary_model})", f, cur.real_area * 1e6, BEM_COLOUR if pred.bem is not None
             else HERTZ_COLOUR, dash="solid" if pred.bem is not None else "dashed", width=2.5),
    ]
    if pred.bem is not None and pred.hertz is not None:
        spec.lines.append(Line("real A_re (hertz)", f, pred.hertz.real_area * 1e6, HERTZ_COLOUR, dash="dashed"))
    spec.vlines = _critical_lines(pred)
    spec.bands = state_bands(pred)
    return spec


def friction_specs(pred: Any) -> tuple[PlotSpec, PlotSpec]:
    """mu and mu_ref, and mu / mu_ref, against load, with the centre's contact states."""
    cur = pred.primary
    f = cur.load
    both = pred.bem is not None and pred.hertz is not None
    mu = PlotSpec(key="friction", title="friction coefficient against load (shaded: state at the pad centre)",
                  x_label="normal load F (N)", y_label="friction coefficient mu (-)", x_log=_load_log(f),
                  meta=_meta(pred))
    mu.lines.append(Line(f"mu texture ({pred.primary_model})", f, cur.mu,
                         BEM_COLOUR if pred.bem is not None else HERTZ_COLOUR,
                         dash="solid" if pred.bem is not None else "dashed", width=2.5))
    if both:
        mu.lines.append(Line("mu texture (hertz)", f, pred.hertz.mu, HERTZ_COLOUR, dash="dashed"))
    if cur.mu_ref is not None:
        mu.lines.append(Line("mu_ref flat reference", f, cur.mu_ref, "black", width=1.5))
    norm = PlotSpec(key="friction-normalised", title="normalised friction mu / mu_ref against load",
                    x_label="normal load F (N)", y_label="mu / mu_ref (-)", x_log=_load_log(f), meta=_meta(pred))
    if cur.mu_normalised is not None:
        norm.lines.append(Line(f"mu/mu_ref ({pred.primary_model})", f, cur.mu_normalised,
                               BEM_COLOUR if pred.bem is not None else HERTZ_COLOUR,
                               dash="solid" if pred.bem is not None else "dashed", width=2.5))
        top = float(np.nanmax(cur.mu_normalised))
        if both and pred.hertz.mu_normalised is not None:
            norm.lines.append(Line("mu/mu_ref (hertz)", f, pred.hertz.mu_normalised, HERTZ_COLOUR, dash="dashed"))
            top = max(top, float(np.nanmax(pred.hertz.mu_normalised)))
        norm.y_range = (0.0, max(1.05, 1.05 * top))
    for spec in (mu, norm):
        spec.vlines = _critical_lines(pred)
        spec.bands = state_bands(pred)
    return mu, norm


def zone_specs(pred: Any) -> tuple[PlotSpec, PlotSpec]:
    """The zones of the ridge-contact disc at the zone load (mm), and along a radius the pad
    pressure p(r) (Eq. 3.7, kPa) and the local fraction psi(p(r))."""
    from ..macro.pressure import pad_pressure

    z = pred.zones
    a, at, af = z["ridge_radius"], z["transition_radius"], z["full_contact_radius"]
    zones = PlotSpec(key="zones", title=f"zones at F = {z['load']:.4g} N (centre: {z['contact_state']})",
                     x_label="x (mm)", y_label="y (mm)", equal_aspect=True, meta={**_meta(pred), "zones": dict(z)})
    for radius, inner, state in ((a, at, "asperity"), (at, af, "transition"), (af, 0.0, "full")):
        if radius > 0:
            span = f"{inner * 1e3:.4g} < r < {radius * 1e3:.4g} mm" if inner > 0 else f"r < {radius * 1e3:.4g} mm"
            zones.discs.append(Disc(radius * 1e3, state, f"{state}: {span}"))
    ht = z.get("hertz_transition_radius")
    if ht:
        zones.discs.append(Disc(ht * 1e3, "outline", f"hertz transition: r < {ht * 1e3:.4g} mm"))
    r = np.linspace(0.0, a, 241)
    p = np.asarray(pad_pressure(r, z["load"], z["ridge_area"]), float)
    psi = np.asarray(pred.primary_cell.contact_fraction(p), float)
    profile = PlotSpec(key="zone-profile", title="along a radius: pad pressure (Eq. 3.7) and local psi",
                       x_label="radius r (mm)", y_label="pad pressure p(r) (kPa)", y2_label="local psi (-)",
                       y2_range=(0.0, 1.02), meta={**_meta(pred), "zones": dict(z)})
    profile.lines += [Line("p(r) (Eq. 3.7)", r * 1e3, p / 1e3, "black"),
                      Line(f"psi(p(r)) ({pred.primary_model})", r * 1e3, psi, BEM_COLOUR, axis="right")]
    for lo, hi, state in ((at, a, "asperity"), (af, at, "transition"), (0.0, af, "full")):
        if hi > lo:
            profile.bands.append(Band(lo * 1e3, hi * 1e3, state))
    return zones, profile


def contact_specs(res: Any) -> tuple[PlotSpec, PlotSpec]:
    """The contact pressure map (kPa) and the contact over the height map at one mean pressure."""
    tex = res.texture
    lx, ly = tex.size
    pressure = np.asarray(res.pressure, float).T / 1e3
    meta = {"mean_pressure_Pa": float(res.mean_pressure), "contact_fraction": float(res.contact_fraction),
            "contact_state": str(res.contact_state), "max_pressure_Pa": float(res.max_pressure),
            "converged": bool(res.converged), "iterations": int(res.iterations), "grid": list(tex.shape)}
    title = (f"at p = {res.mean_pressure / 1e3:.4g} kPa: psi = {res.contact_fraction:.3g}"
             + ("" if res.converged else " (NOT converged)"))
    pmap = PlotSpec(key="pressure-map", title="pressure " + title, x_label="x (um)", y_label="y (um)",
                    equal_aspect=True, meta=meta,
                    images=[Image(pressure, 0.0, lx * 1e6, 0.0, ly * 1e6, "contact pressure (kPa)", "viridis")])
    cmap = PlotSpec(key="contact-map", title=f"contact (red), state {res.contact_state}", x_label="x (um)",
                    y_label="y (um)", equal_aspect=True, meta=meta,
                    images=[Image(np.asarray(tex.heights, float).T * 1e6, 0.0, lx * 1e6, 0.0, ly * 1e6, "height (um)",
                                  "greys", overlay=np.asarray(res.pressure > 0).T)])
    return pmap, cmap


def compare_specs(designs: Sequence[tuple[str, Any]]) -> list[PlotSpec]:
    """A_re/A_fr, mu and mu/mu_ref of the pinned designs overlaid, critical loads marked."""
    out = []
    for key, title, y_label, attr in (
        ("compare-area-ratio", "real-to-ridge area A_re / A_fr", "A_re / A_fr (-)", "area_ratio"),
        ("compare-friction", "friction coefficient mu", "mu (-)", "mu"),
        ("compare-normalised", "normalised friction mu / mu_ref", "mu / mu_ref (-)", "mu_normalised"),
    ):
        spec = PlotSpec(key=key, title=title, x_label="normal load F (N)", y_label=y_label,
                        meta={"designs": [label for label, _ in designs]})
        logs = []
        for k, (label, pred) in enumerate(designs):
            cur = pred.primary
            y = getattr(cur, attr)
            if y is None:
                continue
            colour = DESIGN_COLOURS[k % len(DESIGN_COLOURS)]
            short = label.split(" ", 1)[0]  # "#1": the list above the plots names the design
            spec.lines.append(Line(f"{short} ({pred.primary_model})", cur.load, np.asarray(y, float), colour))
            logs.append(_load_log(cur.load))
            f = pred.critical_load.get(pred.primary_model)
            if _finite(f) and float(cur.load.min()) <= f <= float(cur.load.max()):
                spec.vlines.append(VLine(float(f), f"F_crit {short} = {f:.4g} N", colour, "dashed"))
        spec.x_log = bool(logs) and all(logs)
        out.append(spec)
    return out
