"""The design map (thesis ch. 5): friction and contact states of textures on two swept axes.

For each texture of a sweep: the critical load (the load at which the pad centre reaches the
transition; BEM, or Hertz where the BEM did not run), the friction change against the flat
reference mu/mu_ref at a chosen load, and the contact-state region over the exploration loads:

* 0 - *transition below the range*: already past the transition at the lightest exploration
  load; the skin follows the texture and friction hardly tells it apart ("invisible");
* 1 - *transition inside the range*: the change of trend shows in friction;
* 2 - *asperity contact over the whole range*: the skin rides on the asperity tops.

Literature markers (docs/model.md, design map): textures with a spacing below 160 um are felt
smooth; the fingerprint ridge wavelength is 0.4-0.5 mm (the finger filters it out); ridges of
33.5 um and more bring interlocking, dominant from 105 um; a spacing of v / 250 Hz (200 um at
50 mm/s) is felt at the Pacinian optimum (docs/perception.md). With ``tell_apart``, who tells
each texture from a reference surface (:func:`map_data`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import FingerpadError, excerpt
from ..perception.vibration import PACINIAN_BEST

__all__ = ["MARKERS", "POPULATION_COVERAGE", "REGIONS", "default_at", "fraction_telling", "map_data",
           "member_weber_of_store", "point_friction", "reference_friction", "reference_member_friction",
           "store_point", "store_members", "swept_axes"]

#: The share of a population for which the design map marks "asperity contact over the whole
#: range" (and whose complement's quantiles give the contours: 10 % and 90 % fingers).
POPULATION_COVERAGE = 0.9

#: The contact-state regions (the ``region`` variable's ``flag_meanings``, in this order).
REGIONS = {0: "transition below the range", 1: "transition inside the range", 2: "asperity contact over the range"}
#: The stroke speed of the map's lambda = v / 250 Hz line, m/s: 50 mm/s, inside the 20-100 mm/s of
#: active touch (docs/perception.md); f = v / lambda moves the line in proportion to the speed.
TYPICAL_SPEED = 0.05
#: Literature markers: (axis-name fragment, value in m, label); bands as (fragment, low, high, label).
MARKERS = {
    "lines": [("spacing", 160e-6, "felt smooth below 160 µm"), ("height", 33.5e-6, "interlocking from 33.5 µm"),
              ("height", 105e-6, "interlocking dominant from 105 µm"),
              # lambda = v / 250 Hz: the period felt at the Pacinian optimum at a typical stroke speed
              ("spacing", TYPICAL_SPEED / PACINIAN_BEST[0], f"250 Hz at {1e3 * TYPICAL_SPEED:g} mm/s")],
    "bands": [("spacing", 400e-6, 500e-6, "fingerprint ridge wavelength")],
}


def study_weber(ds: Any) -> float:
    """The Weber fraction W of a sweep's person: its base study's ``[perception] weber_fraction``,
    else the default 0.11 (a population that draws W stores its members' fractions instead)."""
    from ..perception.discrimination import WEBER_FRACTION

    try:
        base = json.loads(ds.attrs.get("study") or "{}")
    except (TypeError, ValueError):
        base = {}
    value = (base.get("perception") or {}).get("weber_fraction") if isinstance(base, dict) else None
    return WEBER_FRACTION.default if value is None else float(WEBER_FRACTION.parse(value, "[perception] weber_fraction"))


def swept_axes(ds: Any) -> list[str]:
    """The axes of a sweep store, in order."""
    return list(json.loads(ds.attrs["axes"]))


def _axis_values(ds: Any, name: str) -> Any:
    return ds[name] if name in ds.variables else None


#: Quantities the map can colour by (per-load variables of the store).
COLOUR_QUANTITIES = {"mu_rel": "μ/μ_ref", "mu_perp_over_par": "μ⊥/μ∥", "mu": "μ", "area_ratio": "A_re/A_fr"}


def map_data(ds: Any, x: str, y: str, at: float | None = None, select: Mapping[str, Any] | None = None,
             quantity: str = "mu_rel", population: bool = False, tell_apart: Mapping[str, Any] | None = None) -> Any:
    """The data behind a design map: ``critical_load`` (N), ``mu_rel`` (at load ``at``) and
    ``region`` (see the module docstring) on the axes ``x`` and ``y``, with the literature
    markers (:data:`MARKERS`, JSON) in the attribute ``markers``.

    Parameters
    ----------
    ds
        A sweep store (:func:`fingerpad.design.store.open_sweep`).
    x, y
        Two numeric swept axes.
    at
        Load (N) of mu/mu_ref, inside the exploration range (default: 1 N, or the middle of the
        range in log if 1 N is outside it).
    select
        Values of further axes of a grid sweep (nearest); axes not selected stay as dimensions
        (one panel each on the figure).
    quantity
        The colour: ``mu_rel`` (default), ``mu_perp_over_par`` (directional sweeps), ``mu`` or
        ``area_ratio``; stored as the variable ``mu_rel`` of the result with its name in ``attrs``.
    population
        Draw the population of a sweep run with ``--population``: ``mu_rel`` is then the median
        over the members (of ``quantity``, at ``at``), and the result gains
        ``critical_load_q10``, ``critical_load_q50``, ``critical_load_q90`` (N: the critical
        loads of the 10 %, 50 % and 90 % fingers, quantiles over the members),
        ``asperity_over_range`` (the fraction of members in asperity contact at the pad centre at
        every exploration load) and ``robust_asperity`` (1 where that fraction is at least
        :data:`POPULATION_COVERAGE`, else 0). ``critical_load`` and ``region`` stay the
        nominal finger's.
    tell_apart
        Who tells each texture from a reference surface at ``at`` (docs/perception.md):
        ``{"reference": "flat" or a label, "mu": REF's friction at ``at`` for the study's finger
        (``None`` for flat), "weber": W}``. Adds ``tell_apart``: with ``population``, the stored
        fraction of the members telling the texture from the flat reference (``tell_flat``,
        interpolated in log load to ``at``, with the W the sweep stored), or for a reference
        surface ``"mu"``: REF's friction for each of the sweep's members at ``at``
        (:func:`reference_member_friction`) and the fraction of members with P >= 0.75 against
        their own mu (``mu_members`` interpolated in log load to ``at``, each member's W);
        otherwise the study's finger's probability P of telling them apart in a forced choice.

    Returns
    -------
    xarray.Dataset
        On ``(y, x, *others)`` for a grid sweep, on ``point`` otherwise (with ``x`` and ``y`` as
        variables); attributes ``x``, ``y``, ``x_log``, ``y_log``, ``at``, ``load_min``,
        ``load_max``, ``design``.

    Raises
    ------
    FingerpadError
        Unknown or non-numeric axes, a load outside the range, an unknown selection.
    """
    import xarray as xr

    axes = swept_axes(ds)
    for name, flag in ((x, "--x"), (y, "--y")):
        if name not in axes:
            raise FingerpadError(f"{flag} {name!r}: not an axis of this sweep (axes: {', '.join(axes)})")
        if ds[name].attrs.get("kind") == "choice":
            raise FingerpadError(f"{flag} {name!r} is a list of names, not a numeric axis: use --select {name}=...")
    if x == y:
        raise FingerpadError("--x and --y must be two different axes")
    loads = ds["load"].values
    lo, hi = float(loads.min()), float(loads.max())
    if at is None:
        at = default_at(loads)
    if not lo * (1 - 1e-9) <= at <= hi * (1 + 1e-9):
        raise FingerpadError(f"--at {at:g} N is outside the sweep's exploration loads {lo:g}-{hi:g} N")
    sel = dict(select or {})
    for name in sel:
        if name not in axes or name in (x, y):
            raise FingerpadError(f"--select {name}: not a further axis of this sweep (axes: {', '.join(axes)})")
    if quantity not in COLOUR_QUANTITIES:
        raise FingerpadError(f"--quantity {quantity!r}: one of {', '.join(COLOUR_QUANTITIES)}")
    if quantity not in ds.variables:
        raise FingerpadError(f"--quantity {quantity}: this sweep store does not hold it (an older store?)")
    if not np.isfinite(ds[quantity].values).any():
        raise FingerpadError(f"--quantity {quantity}: no point of this sweep has it"
                             + (" (give the study a [model] direction or sweep a direction axis)"
                                if quantity == "mu_perp_over_par" else ""))
    design = ds.attrs.get("design", "grid")
    names = ["critical_load_bem", "critical_load_hertz", "valid", "done"]
    if population:
        if "band_mu_rel" not in ds.variables:
            raise FingerpadError("--population: this sweep store holds no population (run fingerpad sweep with "
                                 "--population)")
        band = f"band_{quantity}"
        if band not in ds.variables:
            raise FingerpadError(f"--quantity {quantity}: the population is banded in area_ratio, mu and "
                                 "mu_rel only")
        names += ["band_critical_load", "asperity_over_range"]
        colour = ds[band].sel(quantile=0.5)
    else:
        colour = ds[quantity]
    if tell_apart is not None:
        if population and tell_apart.get("reference") == "flat":
            if "tell_flat" not in ds.variables:
                raise FingerpadError("--tell-apart: this sweep store holds no perception fractions (made before "
                                     "they were stored): run the sweep again")
            stored_w = float(ds.attrs.get("weber_fraction", math.nan))
            if tell_apart.get("weber") is not None:
                member_weber_of_store(ds, tell_apart["weber"])  # refused where the population draws W
                if float(tell_apart["weber"]) != stored_w:
                    raise FingerpadError(f"--weber-fraction: this sweep stored its fractions with W = {stored_w:g}")
            names.append("tell_flat")
        elif population:
            if "mu_members" not in ds.variables:
                raise FingerpadError("--tell-apart REF with --population: this sweep store holds no friction per "
                                     "finger (made before it was stored): run the sweep again, or use --tell-apart flat")
            ref_mu = np.asarray(tell_apart["mu"], float)
            if ref_mu.shape != (ds.sizes["member"],):
                raise FingerpadError(f"--tell-apart: {ref_mu.size} reference values for the sweep's "
                                     f"{ds.sizes['member']} fingers")
            names.append("mu_members")
        else:
            names += ["mu", "mu_ref"]
    data = ds[names].assign(mu_rel=colour)
    if design == "grid":
        for name, value in sel.items():
            kind = ds[name].attrs.get("kind")
            if kind == "choice":
                if str(value) not in ds[name].values.astype(str):
                    raise FingerpadError(f"--select {name}={value}: not a value of the sweep "
                                         f"({', '.join(ds[name].values.astype(str))})")
                data = data.sel({name: str(value)})
            else:
                from ..units import parse_quantity

                dim = {"length": "length", "pressure": "pressure", "angle": "angle"}.get(kind, "none")
                data = data.sel({name: parse_quantity(value, dim, name=f"--select {name}")}, method="nearest")
    elif sel:
        raise FingerpadError("--select applies to grid sweeps; a scattered design is drawn as it is")
    def at_load(var: Any) -> Any:
        return _at_load(var, loads, at)

    mu_at = at_load(data["mu_rel"])
    crit = data["critical_load_bem"].where(np.isfinite(data["critical_load_bem"]) | np.isinf(data["critical_load_bem"]),
                                           data["critical_load_hertz"])
    region = xr.where(crit < lo, 0, xr.where(crit > hi, 2, 1)).where(data["valid"] & data["done"])
    out = xr.Dataset({
        "critical_load": crit.where(data["valid"] & data["done"]).assign_attrs(units="N", long_name="critical load"),
        "mu_rel": mu_at.where(data["valid"] & data["done"]).assign_attrs(
            units="1", long_name=f"{quantity} at {at:g} N"),
        "region": region.assign_attrs(units="1", long_name="contact-state region over the exploration loads",
                                      flag_values="0 1 2", flag_meanings="; ".join(REGIONS.values())),
    })
    ok = data["valid"] & data["done"]
    if tell_apart is not None:
        ref = str(tell_apart["reference"])
        if population and ref == "flat":
            out["tell_apart"] = at_load(data["tell_flat"]).where(ok).assign_attrs(
                units="1", long_name=f"fraction of fingers telling it from the flat reference at {at:g} N "
                                     "(interpolated in log load)")
        elif population:
            # each finger's mu at the map's load (the same log-load interpolation as the colour)
            # against REF's for the same finger, each with its own W (Eqs. P.1-P.3)
            mu = at_load(data["mu_members"]).transpose(..., "member")
            told = fraction_telling(mu.values, tell_apart["mu"], member_weber_of_store(ds, tell_apart.get("weber")))
            out["tell_apart"] = mu.isel(member=0, drop=True).copy(data=told).where(ok).assign_attrs(
                units="1", long_name=f"fraction of fingers telling it from {ref} at {at:g} N")
        else:
            from ..perception.discrimination import p_correct

            mu = at_load(data["mu"])
            ref_mu = at_load(data["mu_ref"]) if ref == "flat" else float(tell_apart["mu"])
            weber = tell_apart.get("weber")  # --weber-fraction, else the sweep study's W
            p = p_correct(mu.values, np.asarray(ref_mu), study_weber(ds) if weber is None else float(weber))
            out["tell_apart"] = mu.copy(data=p).where(ok).assign_attrs(
                units="1", long_name=f"probability that the study's finger tells it from {ref} at {at:g} N")
    if population:
        if quantity == "mu_rel":
            out["mu_rel"].attrs["long_name"] = f"median over the population of mu/mu_ref at {at:g} N"
        for q in (0.1, 0.5, 0.9):
            out[f"critical_load_q{round(100 * q)}"] = data["band_critical_load"].sel(quantile=q).drop_vars(
                "quantile").where(ok).assign_attrs(units="N", long_name=f"critical load of the {100 * q:g} % finger "
                                                                        f"(quantile over the population)")
        frac = data["asperity_over_range"].where(ok)
        out["asperity_over_range"] = frac.assign_attrs(
            units="1", long_name=f"fraction of fingers in asperity contact over {lo:g}-{hi:g} N")
        out["robust_asperity"] = xr.where(frac >= POPULATION_COVERAGE, 1.0, 0.0).where(ok).assign_attrs(
            units="1", long_name=f"asperity contact over {lo:g}-{hi:g} N for >= {100 * POPULATION_COVERAGE:g} % "
                                 "of fingers (1) or not (0)")
        if "quantile" in out.coords:
            out = out.drop_vars("quantile")
    if design != "grid":
        out[x] = ds[x]
        out[y] = ds[y]
    else:
        others = [d for d in out.dims if d not in (x, y)]
        out = out.transpose(y, x, *others)
    out.attrs = {"x": x, "y": y, "x_log": ds[x].attrs.get("log") == "true", "y_log": ds[y].attrs.get("log") == "true",
                 "at": float(at), "load_min": lo, "load_max": hi, "design": design,
                 "x_kind": ds[x].attrs.get("kind", ""), "y_kind": ds[y].attrs.get("kind", ""),
                 "quantity": quantity, "quantity_label": COLOUR_QUANTITIES[quantity],
                 "population": _population_name(ds) if population else "",
                 "coverage": POPULATION_COVERAGE,
                 "tell_apart": "" if tell_apart is None else str(tell_apart["reference"]),
                 # the literature markers travel with the data (plotting draws them, knows none)
                 "markers": json.dumps(MARKERS)}
    return out


def _at_load(var: Any, loads: Any, at: float) -> Any:
    """``var`` at the load ``at`` (N), interpolated in log load between the two bracketing
    exploration ``loads`` (at an exploration load, that load's value)."""
    log_load = np.log(np.asarray(loads, float))
    k = int(np.clip(np.searchsorted(loads, at), 1, log_load.size - 1))
    w = (math.log(at) - log_load[k - 1]) / (log_load[k] - log_load[k - 1])
    return (1 - w) * var.isel(load=k - 1) + w * var.isel(load=k)


def fraction_telling(mu: Any, ref_mu: Any, weber: Any) -> np.ndarray:
    """The fraction of a population's members telling a texture from a reference by friction:
    those with P >= 0.75 (Eqs. P.1-P.3), each member with its own friction on both surfaces and
    its own W. ``mu``: members on the last axis; ``ref_mu`` and ``weber``: one per member."""
    from ..perception.discrimination import discriminates, p_correct

    told = discriminates(p_correct(np.asarray(mu, float), np.asarray(ref_mu, float), np.asarray(weber, float)))
    return np.mean(told, axis=-1)


#: The most points a reference index may address (a sweep's designs are capped far below it).
_MAX_POINTS = 10**7


def store_point(ds: Any, index: Any) -> dict[str, int]:
    """The point ``index`` of a sweep store as ``isel`` indices: a grid's designs numbered over
    its swept axes in order (C order), a scattered design's its point number. The index may come
    from a page: it must be a whole number addressing a possible texture of the store.

    Raises
    ------
    FingerpadError
        Not a whole number, outside the store, or a texture that is not possible (no friction).
    """
    axes = swept_axes(ds)
    dims = ["point"] if "point" in ds.dims else axes
    shape = tuple(int(ds.sizes[d]) for d in dims)
    size = int(np.prod(shape))
    whole = not isinstance(index, bool) and isinstance(index, (int, np.integer))
    if not whole or not 0 <= int(index) < min(size, _MAX_POINTS):
        raise FingerpadError(f"reference point {excerpt(index)}: not a point of this sweep (0-{size - 1})")
    where = dict(zip(dims, (int(i) for i in np.unravel_index(int(index), shape)), strict=True))
    if not bool(ds["valid"].isel(where).values):
        raise FingerpadError(f"reference point {int(index)}: that texture is not possible "
                             f"({str(ds['reason'].isel(where).values) if 'reason' in ds else 'not valid'})")
    return where


def point_friction(ds: Any, index: Any, at: float) -> Any:
    """The friction (mu) on the store's point ``index`` (:func:`store_point`) at ``at`` (N), as
    :func:`map_data` reads the textures (log-load interpolation): each member's (``mu_members``,
    an array over the members) for a population store that holds them, else the study's finger's
    (a number). The reference of ``map_data(tell_apart=...)`` when REF is a texture of the map."""
    point = ds.isel(store_point(ds, index))
    loads = ds["load"].values
    if "mu_members" in ds.variables:
        return np.asarray(_at_load(point["mu_members"], loads, at).values, float)
    return float(_at_load(point["mu"], loads, at).values)


def default_at(loads: Any) -> float:
    """The map's load when none is given: 1 N, or the middle of the exploration loads in log."""
    lo, hi = float(np.min(loads)), float(np.max(loads))
    return 1.0 if lo <= 1.0 <= hi else float(np.sqrt(lo * hi))


def _population_name(ds: Any) -> str:
    """The population of a store, in a few words (its name and size)."""
    return f"{ds.attrs.get('population_name', 'population')} ({ds.attrs.get('population_size', '?')} fingers)"


def reference_friction(ds: Any, reference: str, at: float) -> float:
    """The friction (mu) of a reference surface for the sweep study's finger at ``at`` (N): a
    direct prediction of the study file ``reference`` (its texture, material and numerics) with
    the finger of the sweep's study."""
    from ..study.run import run_study

    return float(np.asarray(run_study(_reference_study(ds, reference, at)).primary.mu, float)[0])


def _reference_study(ds: Any, reference: str, at: float) -> Any:
    """The study file ``reference`` (its texture, material and numerics) with the finger of the
    sweep's study, at the one load ``at`` (N)."""
    import dataclasses

    from ..study.spec import load_study_file, study_from_dict

    base = json.loads(ds.attrs["study"])
    finger = study_from_dict({k: v for k, v in base.items() if k in ("finger", "material", "texture")}).finger
    return dataclasses.replace(load_study_file(reference), finger=finger, loads=np.array([float(at)]), zones_at=None)


def store_members(ds: Any) -> list[dict[str, float]]:
    """The members of a population sweep store (their drawn parameters, SI, from the
    ``member_NAME`` variables)."""
    names = [str(v)[len("member_"):] for v in ds.variables if str(v).startswith("member_")]
    return [{n: float(ds[f"member_{n}"].values[i]) for n in names} for i in range(ds.sizes["member"])]


def member_weber_of_store(ds: Any, weber: float | None = None) -> np.ndarray:
    """Each member's Weber fraction in a population sweep store: its own where the population
    draws W, else ``weber`` (``--weber-fraction``), else the sweep study's (:func:`study_weber`).

    Raises
    ------
    FingerpadError
        ``weber`` given for a population that draws W.
    """
    members = store_members(ds)
    drawn = "member_weber_fraction" in ds.variables
    if weber is not None and drawn:
        raise FingerpadError("--weber-fraction: this sweep's population draws each finger's W; its fractions are "
                             "those of the members' own")
    own = study_weber(ds) if weber is None else float(weber)
    return np.array([float(m.get("weber_fraction", own)) for m in members])


def reference_member_friction(ds: Any, reference: str, at: float) -> np.ndarray:
    """The friction (mu) of a reference surface for each member of a population sweep store at
    ``at`` (N): one direct prediction of the study file ``reference`` (its texture, material and
    numerics) with the sweep study's finger, then every member on it
    (:func:`fingerpad.population.members.evaluate_members`, the members' path of every point)."""
    from ..population.members import evaluate_members, member_finger
    from ..study.run import run_study

    ref = _reference_study(ds, reference, at)
    values = evaluate_members(run_study(ref), [member_finger(ref.finger, m) for m in store_members(ds)])
    return np.asarray(values.mu, float)[:, 0]
