"""The figures of a prediction, defined once: areas, friction and contact zones against load.

Each function returns a :class:`~.specs.FigureSpec` (what is plotted, labels, units, scales, the
shading of the contact states at the pad centre, reference lines). ``fingerpad predict`` draws
them with matplotlib (:mod:`.prediction`), the explorer with Bokeh
(:mod:`fingerpad.explore.render_bokeh`) and writes their data in SI; neither toolkit is imported
here. Values are taken from the prediction as ``predict`` computes them; the only evaluations made
are the library's own functions on the prediction's cells (the pad pressure of Eq. 3.7 along a
radius, psi(p) of the unit cell) to draw continuous curves.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .specs import STATE_COLOURS, Axis, Band, Disc, FigureSpec, HLine, Label, Line, PlotSpec, VLine, pale

#: The result these figures read (:class:`~fingerpad.study.run.Prediction`), named for the
#: signatures only: plotting imports nothing of the layers above it, not even for type checking.
Prediction = Any

__all__ = [
    "RED",
    "adhesion_lines",
    "areas_figure",
    "critical_lines",
    "friction_figure",
    "load_axis",
    "state_bands",
    "zones_figure",
]

RED, GREEN, PURPLE = "#d62728", "#2ca02c", "#9467bd"  # matplotlib's tab:red, tab:green, tab:purple
#: Area axis: m² shown in mm².
AREA = Axis("contact area", "m²", "mm²", 1e6, log=True)


def _finite(v: Any) -> bool:
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v)


def load_axis(load: np.ndarray) -> Axis:
    """The load axis: logarithmic for ranges over 5x."""
    lo, hi = float(np.min(load)), float(np.max(load))
    return Axis("normal load F", "N", log=bool(lo > 0 and hi / lo > 5))


def _markers(load: np.ndarray) -> bool:
    """Markers when the loads are too few to draw a curve."""
    return int(np.size(load)) < 4


def state_bands(pred: Prediction) -> list[Band]:
    """Load intervals (within the loads of the study) of the contact state at the pad centre:
    asperity below the critical load, transition up to the full-contact load, full above."""
    load = pred.primary.load
    lo, hi = float(load.min()), float(load.max())
    fc = pred.critical_load.get(pred.primary_model)
    ff = pred.full_contact_load.get(pred.primary_model)
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


def critical_lines(pred: Prediction) -> list[VLine]:
    """The critical loads (BEM solid, Hertz dashed) inside the loads of the study."""
    load = pred.primary.load
    lo, hi = float(load.min()), float(load.max())
    out = []
    for model, dash in (("bem", "solid"), ("hertz", "dashed")):
        f = pred.critical_load.get(model)
        if _finite(f) and lo <= f <= hi:
            out.append(VLine(float(f), f"F_crit {model} = {f:.3g} N", "black", dash))
    return out


def adhesion_lines(pred: Prediction) -> list[VLine]:
    """With adhesion: the threshold load below which it changes A_re by more than 10 %, where it
    lies inside the loads of the study."""
    adh = pred.adhesion or {}
    f = adh.get("threshold_load")
    load = pred.primary.load
    if not _finite(f) or adh.get("threshold_load_bound", "exact") != "exact":
        return []
    if not float(load.min()) <= f <= float(load.max()):
        return []
    return [VLine(float(f), f"adhesion > 10 % of A_re below {f:.3g} N", PURPLE, "dotted")]


def _adhesion_title(pred: Prediction) -> str:
    """``"; pull-off 0.06 mN"`` with adhesion, ``""`` without."""
    adh = pred.adhesion
    if not adh:
        return ""
    bound = adh.get("threshold_load_bound", "exact")
    f = adh.get("threshold_load")
    where = "" if f is None else (f"; adhesion > 10 % of A_re below {f:.3g} N" if bound == "exact" else
                                  f"; adhesion > 10 % of A_re up to {f:.3g} N and beyond" if bound == "at least"
                                  else "")
    return f"; w {adh['work_of_adhesion']:.3g} J/m², pull-off {adh['pull_off_force'] * 1e3:.3g} mN{where}"


def _meta(pred: Prediction) -> dict[str, Any]:
    return {
        "texture": pred.texture.name,
        "model": pred.primary_model,
        "reduced_modulus_Pa": pred.reduced_modulus,
        "critical_load_N": dict(pred.critical_load),
        "full_contact_load_N": dict(pred.full_contact_load),
        "finger": pred.study.finger.name,
    }


def areas_figure(pred: Prediction) -> FigureSpec:
    """Gross, ridge and real contact areas against load (log-log), critical loads marked."""
    cur = pred.primary
    f = cur.load
    m = _markers(f)
    spec = PlotSpec(
        key="areas", x=load_axis(f), y=AREA, legend="lower right", meta=_meta(pred),
        title=(f"Contact areas: {pred.texture.name}, E1* = {pred.reduced_modulus / 1e3:.4g} kPa, "
               f"finger {pred.study.finger.name}"),
        lines=[Line("gross A_g", f, cur.gross_area, "black", markers=m),
               Line("ridge A_fr", f, cur.ridge_area, GREEN, markers=m),
               Line(f"real A_re ({pred.primary_model})", f, cur.real_area, RED, width=2.0, markers=m)],
        vlines=critical_lines(pred) + adhesion_lines(pred),
    )
    if pred.bem is not None and pred.hertz is not None:
        spec.lines.append(Line("real A_re (hertz)", f, pred.hertz.real_area, RED, dash="dashed", markers=m))
    if pred.adhesion is not None and "real_area_without_adhesion" in pred.adhesion:
        spec.lines.append(Line("real A_re without adhesion", f, pred.adhesion["real_area_without_adhesion"], RED,
                               dash="dotted", markers=m))
        spec.title += _adhesion_title(pred).replace("; adhesion", "\nadhesion", 1)
    return FigureSpec("areas", None, [spec], size=(7.0, 5.0),
                      margins={"left": 0.12, "right": 0.97, "bottom": 0.11, "top": 0.9})


def friction_figure(pred: Prediction) -> FigureSpec:
    """Friction against load, normalised friction and (compliant asperities sliding in a
    direction) the directional ratio; the contact state at the pad centre shaded."""
    cur = pred.primary
    f = cur.load
    m = _markers(f)
    d = pred.directional
    x = load_axis(f)
    mu = PlotSpec(key="friction", title="friction against load (shaded: contact state at the pad centre)", x=x,
                  y=Axis("friction coefficient μ"), meta=_meta(pred))
    norm = PlotSpec(key="friction-normalised", title="normalised friction", x=x,
                    y=Axis("μ_texture / μ_flat reference"), meta=_meta(pred))
    panels = [mu, norm]
    if d is not None:
        ratio = PlotSpec(key="friction-directional", title="directional friction (compliant asperities)", x=x,
                         y=Axis("μ_perpendicular / μ_parallel"), meta=_meta(pred), hlines=[HLine(1.0)])
        mu.lines += [
            Line(f"across the long axis ({d['perpendicular_direction']:.0f}°)", f, d["mu_perpendicular"], PURPLE,
                 dash="dotted", markers=m),
            Line(f"along the long axis ({d['parallel_direction']:.0f}°)", f, d["mu_parallel"], PURPLE,
                 dash="dotdash", markers=m),
        ]
        ratio.lines.append(Line("μ_perpendicular / μ_parallel", f, d["mu_perpendicular_over_parallel"], PURPLE,
                                width=2.0, markers=m, legend=False))
        held = (np.asarray(d.get("gain_held_parallel", ()), bool)
                | np.asarray(d.get("gain_held_perpendicular", ()), bool))
        if held.size == np.size(f) and held.any():  # the gain is held there, not computed: say so
            ratio.lines.append(Line("gain held (past the shear its ramps reached)", np.asarray(f)[held],
                                    np.asarray(d["mu_perpendicular_over_parallel"])[held], RED, line=False,
                                    markers=True))
        panels.append(ratio)
    label = f"texture ({pred.primary_model})" if d is None else f"texture, sliding at {d['direction']:.0f}°"
    mu.lines.append(Line(label, f, cur.mu, RED, width=2.0, markers=m))
    if cur.mu_ref is not None:
        mu.lines.append(Line("flat reference", f, cur.mu_ref, "black", markers=m))
    if cur.mu_normalised is not None:
        norm.lines.append(Line(pred.primary_model, f, cur.mu_normalised, RED, width=2.0, markers=m))
    if pred.bem is not None and pred.hertz is not None:
        mu.lines.append(Line("texture (hertz)", f, pred.hertz.mu, RED, dash="dashed", markers=m))
        if pred.hertz.mu_normalised is not None:
            norm.lines.append(Line("hertz", f, pred.hertz.mu_normalised, RED, dash="dashed", markers=m))
    # Not the area ratio A_re,tex/A_re,ref: the alpha*p term and the hysteresis count too (Eqs. 2.1-2.4).
    top = float(np.nanmax(cur.mu_normalised)) * 1.05 if cur.mu_normalised is not None else 1.05
    norm.y = Axis(norm.y.name, limits=(0.0, max(1.05, top)))
    for panel in panels:
        panel.bands = state_bands(pred)
        panel.vlines = critical_lines(pred) + adhesion_lines(pred)
        panel.references_first = True
    n = len(panels)
    return FigureSpec("friction", f"{pred.texture.name} on finger {pred.study.finger.name}, "
                                  f"E1* = {pred.reduced_modulus / 1e3:.4g} kPa{_adhesion_title(pred)}", panels,
                      size=(6.0 * n, 4.8),
                      margins={"left": 0.065 if n == 2 else 0.045, "right": 0.985, "bottom": 0.12, "top": 0.88,
                               "wspace": 0.22})


def zones_figure(pred: Prediction) -> FigureSpec:
    """The zones of the ridge-contact disc at the zone load, and along a radius the pad pressure
    p(r) (Eq. 3.7) with the local real-area fraction psi(p(r)) of the unit cell."""
    from ..macro.pressure import pad_pressure

    z = pred.zones
    a, at, af = z["ridge_radius"], z["transition_radius"], z["full_contact_radius"]
    mm = {"unit": "m", "shown": "mm", "factor": 1e3}
    lim = 1.15 * a
    disc = PlotSpec(key="zones", title=f"ridge contact disc at F = {z['load']:.3g} N",
                    x=Axis("x", limits=(-lim, lim), **mm), y=Axis("y", limits=(-lim, lim), **mm), legend="upper left",
                    equal_aspect=True, grid=False, meta={**_meta(pred), "zones": dict(z)})
    for radius, inner, state in ((a, at, "asperity"), (at, af, "transition"), (af, 0.0, "full")):
        if radius > 0:
            span = f"{inner * 1e3:.3g} < r < {radius * 1e3:.3g} mm" if inner > 0 else f"r < {radius * 1e3:.3g} mm"
            disc.discs.append(Disc(radius, state, f"{state}: {span}", fill=pale(STATE_COLOURS[state])))
    ht = z.get("hertz_transition_radius")
    if ht:
        disc.discs.append(Disc(ht, "outline", f"hertz transition: r < {ht * 1e3:.3g} mm", dash="dashed"))
    # The legend goes above the disc, in a band of its own: in the corner of a square box it
    # covered the disc's top left (its rows are ~4.5 % of the box's height each, plus margins).
    rows = len(disc.discs)
    share = 0.045 * rows + 0.03
    top = (1.05 + 1.15 * share) * a / (1.0 - share)  # the disc's top (a) + 5 % clears the legend's band
    disc.y = Axis("y", limits=(-lim, max(lim, top)), **mm)
    for radius, angle in ((a, 60), (at, 30), (af, 0)):
        if radius > 0:
            t = math.radians(angle)
            disc.labels.append(Label(radius * math.cos(t), radius * math.sin(t), f"{radius * 1e3:.3g} mm"))

    r = np.linspace(0.0, a, 300)
    if getattr(pred.primary_cell, "adhesive", False):
        from ..micro.adhesive_pad import adhesive_pad

        # the JKR pad's pressure over the ridge disc (Eq. 3.17): a tension at its edge
        c_h, c_a = adhesive_pad(pred.study.finger, pred.primary_cell).pressure_coefficients(
            np.array([z["load"]]), np.array([z["ridge_area"]]))
        s_r = np.sqrt(np.clip(1.0 - (r[:-1] / a) ** 2, 0.0, None))
        r = r[:-1]
        p = c_h[0] * s_r - c_a[0] / s_r
        label, floor = "pad pressure p(r) (JKR, Eq. 3.17)", max(float(pred.primary_cell.pull_off_pressure), float(p.min()))
    else:
        p = np.asarray(pad_pressure(r, z["load"], z["ridge_area"]), float)
        label, floor = "pad pressure p(r) (Eq. 3.7)", 0.0
    psi = np.asarray(pred.primary_cell.contact_fraction(p), float)
    profile = PlotSpec(
        key="zone-profile", title=f"A_re/A_fr = {z['area_ratio']:.3g}, centre: {z['contact_state']}",
        x=Axis("radius r", limits=(0.0, a), **mm),
        y=Axis("pressure", "Pa", "kPa", 1e-3, limits=(1.1 * floor if floor < 0 else 0.0, None)),
        y2=Axis("local real-area fraction ψ", limits=(0.0, 1.02)), legend="lower left", grid=False,
        meta={**_meta(pred), "zones": dict(z)},
        lines=[Line(label, r, p, "black"),
               Line(f"ψ(p(r)) ({pred.primary_model})", r, psi, RED, axis="right")])
    for lo, hi, state in ((at, a, "asperity"), (af, at, "transition"), (0.0, af, "full")):
        if hi > lo:
            profile.bands.append(Band(lo, hi, state, legend=False))
    return FigureSpec("zones", f"Contact zones of {pred.texture.name} ({pred.primary_model}), finger "
                               f"{pred.study.finger.name}", [disc, profile], size=(11.5, 5.0), width_ratios=(1.0, 1.3),
                      margins={"left": 0.06, "right": 0.935, "bottom": 0.12, "top": 0.86, "wspace": 0.22})
