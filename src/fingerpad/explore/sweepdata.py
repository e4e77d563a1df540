"""Reading a sweep results store (Zarr, written by ``fingerpad sweep``) for the map view.

The store is opened by :func:`fingerpad.design.store.open_sweep` and a design's axis values are
routed into the study as :mod:`fingerpad.design.axes` does for the sweep itself; the interactive
map's data (one slice at a time, the nearest exploration load) and its ranking of designs against
a target are the view's own. What the view relies on:

* the swept axes (``attrs["axes"]``, JSON list), their coordinate units and ``log`` flags;
* per design ``valid``/``reason``, ``critical_load_bem``/``critical_load_hertz`` (N) and, along
  ``load``, ``mu_rel`` (= mu/mu_ref);
* the base study (``attrs["study"]``, JSON of study-file sections).

Grid designs have one dimension per axis; scattered designs (``lhs``, ``points``) one dimension
``point`` with one variable per axis.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from decimal import Decimal
from typing import Any

import numpy as np

from ..errors import FingerpadError

__all__ = ["axis_info", "design_data", "design_values", "map_data", "open_sweep", "rank_sweep", "sweep_axes",
           "tell_point"]

#: Regions of the design map: where the critical load lies against the exploration loads.
REGIONS = {0: "transition below the load range", 1: "transition inside the load range",
           2: "asperity contact over the whole range"}


def open_sweep(path: str | os.PathLike[str]) -> Any:
    """The sweep store at ``path`` as an :class:`xarray.Dataset` (lazy, read-only).

    Raises
    ------
    FingerpadError
        No such folder, or not a fingerpad sweep store.
    """
    from ..design.store import open_sweep as open_store

    p = os.fspath(path)
    try:
        ds = open_store(p).load()  # a sweep's results are small; the view reads them many times
    except FingerpadError as exc:
        raise FingerpadError(f"--sweep: {exc}") from None
    for var in ("valid", "critical_load_bem", "critical_load_hertz", "mu_rel"):
        if var not in ds:
            raise FingerpadError(f"--sweep {p!r}: the sweep store has no variable {var!r}")
    return ds


def sweep_axes(ds: Any) -> list[str]:
    """The swept axes, in the sweep's order."""
    axes = ds.attrs.get("axes")
    names = json.loads(axes) if isinstance(axes, str) else list(axes or [])
    if not names:
        raise FingerpadError("the sweep store names no axes")
    return [str(n) for n in names]


def _is_grid(ds: Any) -> bool:
    return "point" not in ds.dims


def _axis_values(ds: Any, name: str) -> Any:
    return ds[name]


def axis_info(ds: Any, name: str) -> dict[str, Any]:
    """Units, log flag and kind of an axis."""
    var = _axis_values(ds, name)
    log = str(var.attrs.get("log", "false")).lower() in ("true", "1", "yes")
    values = np.asarray(var.values)
    return {"name": name, "units": str(var.attrs.get("units", "")), "log": log,
            "kind": str(var.attrs.get("kind", "")), "numeric": values.dtype.kind in "fiu",
            "values": np.unique(values) if _is_grid(ds) else values}


def _critical(ds: Any) -> Any:
    """The critical load (N): the BEM's where it has one (NaN = not computed), else Hertz's."""
    bem, hertz = ds["critical_load_bem"], ds["critical_load_hertz"]
    return bem.where(~np.isnan(bem), hertz)


def _region(crit: Any, loads: np.ndarray) -> Any:
    lo, hi = float(np.min(loads)), float(np.max(loads))
    region = xr_where(crit < lo, 0.0, xr_where(crit > hi, 2.0, 1.0))
    return region.where(~np.isnan(crit))


def xr_where(cond: Any, a: Any, b: Any) -> Any:
    import xarray as xr

    return xr.where(cond, a, b)


def default_load(ds: Any) -> float:
    """The exploration load closest to 1 N (the map's default)."""
    loads = np.asarray(ds["load"].values, float)
    return float(loads[np.argmin(np.abs(np.log(loads)))])


def map_data(ds: Any, x: str, y: str, at: float | None = None, select: Mapping[str, Any] | None = None,
             reference: Any = "flat") -> Any:
    """The design map: ``critical_load`` (N), ``mu_rel`` at load ``at`` (N) and ``region`` over
    axes ``x`` and ``y`` (dims ``(y, x)`` for grids, ``point`` otherwise), the other axes fixed
    by ``select`` (their first value by default); ``valid`` and ``reason`` ride along.
    ``tell_flat``: who tells each design from ``reference`` at the load, ``"flat"`` (:func:`tell_flat`)
    or a point of the store (:func:`tell_point`)."""
    axes = sweep_axes(ds)
    for name in (x, y):
        if name not in axes:
            raise FingerpadError(f"{name!r} is not an axis of this sweep (axes: {', '.join(axes)})")
    if x == y:
        raise FingerpadError("choose two different axes for the map")
    at_v = default_load(ds) if at is None else float(at)
    sub = ds
    if _is_grid(ds):
        fixed = {}
        for name in axes:
            if name in (x, y):
                continue
            if select and name in select:
                fixed[name] = select[name]
            else:
                fixed[name] = ds[name].values[0]
        sub = ds.sel(fixed) if fixed else ds
    at_sel = float(sub["load"].sel(load=at_v, method="nearest"))
    crit = _critical(sub)
    out = sub[["valid"]].copy()
    out["critical_load"] = crit
    out["mu_rel"] = sub["mu_rel"].sel(load=at_sel)
    out["region"] = _region(crit, np.asarray(ds["load"].values, float))
    tell = tell_flat(sub, at_sel) if reference == "flat" else tell_point(ds, sub, reference, at_sel)
    if tell is not None:  # none for a texture that is not possible
        out["tell_flat"] = tell.where(sub["valid"])
    if "reason" in sub:
        out["reason"] = sub["reason"]
    if "done" in sub:
        out["done"] = sub["done"]
    if _is_grid(ds):
        out = out.transpose(y, x, ...)
    else:
        out[x] = sub[x]
        out[y] = sub[y]
    out.attrs.update({"x_log": axis_info(ds, x)["log"], "y_log": axis_info(ds, y)["log"], "at": at_sel,
                      "x": x, "y": y, "reference": reference,
                      "fixed": {k: _plain(v) for k, v in (select or {}).items()}})
    return out.load()


def tell_flat(sub: Any, at: float) -> Any:
    """Who tells each design from the flat reference by friction at the load ``at`` (N), as
    ``fingerpad design-map --tell-apart flat`` reads it: a population store's stored fraction of its
    members (each with its own W where the population draws it), else the probability that the
    study's finger does (Eqs. P.1-P.3 on the stored mu and mu_ref, the study's W); ``None`` for a
    store without them."""
    if "tell_flat" in sub:
        return sub["tell_flat"].sel(load=at)
    if "mu" not in sub or "mu_ref" not in sub:
        return None
    from ..design.designmap import study_weber
    from ..perception.discrimination import p_correct

    mu, ref = sub["mu"].sel(load=at), sub["mu_ref"].sel(load=at)
    return mu.copy(data=p_correct(mu.values, ref.values, study_weber(sub)))


def tell_point(ds: Any, sub: Any, reference: Any, at: float) -> Any:
    """Who tells each design of ``sub`` (a slice of the store ``ds``) from the store's point
    ``reference`` (a number from the page, checked by
    :func:`fingerpad.design.designmap.store_point`) at the exploration load ``at`` (N), as
    ``fingerpad design-map --tell-apart`` counts it: for a population store, the fraction of its
    members with P >= 0.75, each finger with its own mu on both textures (``mu_members``) and its
    own W; else the probability that the study's finger does (the study's W)."""
    from ..design.designmap import (fraction_telling, member_weber_of_store, point_friction,
                                    study_weber)
    from ..perception.discrimination import p_correct

    if "tell_flat" in ds and "mu_members" not in ds:
        raise FingerpadError("telling it from a point of the map: this sweep store holds no friction per finger "
                             "(made before it was stored): run the sweep again, or tell it from flat")
    ref_mu = point_friction(ds, reference, at)
    if "mu_members" in ds:
        mu = sub["mu_members"].sel(load=at).transpose(..., "member")
        told = fraction_telling(mu.values, ref_mu, member_weber_of_store(ds))
        return mu.isel(member=0, drop=True).copy(data=told)
    if "mu" not in sub:
        return None
    mu = sub["mu"].sel(load=at)
    return mu.copy(data=p_correct(mu.values, ref_mu, study_weber(sub)))


def _plain(v: Any) -> Any:
    if isinstance(v, np.generic):
        return v.item()
    return v


def design_values(ds: Any, index: Mapping[str, int] | int) -> dict[str, Any]:
    """The axis values (SI numbers, or text for choices) of one design: ``index`` maps the
    grid's axes to indices, or is the ``point`` index."""
    out = {}
    for name in sweep_axes(ds):
        if _is_grid(ds):
            out[name] = _plain(ds[name].values[int(index[name])])  # type: ignore[index]
        else:
            out[name] = _plain(ds[name].values[int(index)])  # type: ignore[arg-type]
    return out


def rank_sweep(ds: Any, targets: Mapping[str, Any], min_critical_load: float | None = None,
               limit: int = 20) -> list[dict[str, Any]]:
    """Designs meeting a target, best first.

    ``targets``: ``{"mu_rel": value, "at": load (N), "tolerance": absolute}``; a design qualifies
    when it is valid, ``|mu_rel(at) - value| <= tolerance`` and (with ``min_critical_load``) its
    critical load is at least that. Ranked by ``|mu_rel - value|``, then by the larger critical
    load. Each candidate: ``index``, the axis values, ``critical_load``, ``mu_rel``, ``at``.
    """
    target = float(targets["mu_rel"])
    at = float(targets.get("at", default_load(ds)))
    tol = float(targets.get("tolerance", math.inf))
    at_sel = float(ds["load"].sel(load=at, method="nearest"))
    crit = _critical(ds).load()
    mu = ds["mu_rel"].sel(load=at_sel).load()
    valid = ds["valid"].load()
    axes = sweep_axes(ds)
    dims = list(crit.dims)
    flat_c = np.asarray(crit.values, float).ravel()
    flat_m = np.asarray(mu.transpose(*dims).values, float).ravel()
    flat_v = np.asarray(valid.transpose(*dims).values, bool).ravel()
    ok = flat_v & np.isfinite(flat_m) & (np.abs(flat_m - target) <= tol)
    if min_critical_load is not None:
        ok &= ~np.isnan(flat_c) & (flat_c >= float(min_critical_load))
    idx = np.flatnonzero(ok)
    key = np.lexsort((-np.nan_to_num(flat_c[idx], nan=-np.inf), np.abs(flat_m[idx] - target)))
    out = []
    for flat in idx[key][:limit]:
        if _is_grid(ds):
            multi = dict(zip(dims, np.unravel_index(int(flat), crit.shape), strict=True))
            index: Any = {a: int(multi[a]) for a in axes}
        else:
            index = int(flat)
        out.append({"index": index, **design_values(ds, index), "critical_load": float(flat_c[flat]),
                    "mu_rel": float(flat_m[flat]), "at": at_sel})
    return out


# ---------------------------------------------------------------------------------------------
# a design as a study


_LENGTH_UNITS = (("mm", 1e-3), ("um", 1e-6), ("nm", 1e-9))
_PRESSURE_UNITS = (("GPa", 1e9), ("MPa", 1e6), ("kPa", 1e3))


def _as_text(value: Any, units: str) -> Any:
    """An SI value as the text a field shows: with a unit where that reads back exactly."""
    from ..units import parse_quantity

    if isinstance(value, str) or not isinstance(value, (int, float)):
        return str(value)
    v = float(value)
    if units == "rad":
        return f"{v!r}rad"
    table = _LENGTH_UNITS if units == "m" else _PRESSURE_UNITS if units == "Pa" else ()
    dim = "length" if units == "m" else "pressure"
    for unit, factor in table:
        if abs(v) >= factor or unit == table[-1][0]:
            # the shortest number in that unit that reads back as exactly v (a log-spaced axis
            # gives 251.98420997897458um, not 0.0002519842099789746); units are read by moving
            # the decimal point, so repr(v) with its point moved always reads back exactly
            shown = v / factor
            exact = Decimal(repr(v)).scaleb(-round(math.log10(factor)))
            candidates = [f"{shown:.{d}g}" for d in range(12, 18)] + [format(exact.normalize(), "f")]
            for number in candidates:
                try:
                    if parse_quantity(f"{number}{unit}", dim) == v:
                        return f"{number}{unit}"
                except FingerpadError:
                    pass
            break
    return repr(v)


def design_data(ds: Any, values: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
    """The study sections of one design: the sweep's base study with the axis values put in.

    An axis named ``section.key`` goes to that section; ``material_modulus`` and
    ``material_poisson`` to ``[material]``; a finger field (``skin_modulus``, ...) to ``[finger]``;
    anything else is a parameter of the texture.
    """
    from ..design.axes import resolve_axis

    base = ds.attrs.get("study")
    data = json.loads(base) if isinstance(base, str) else dict(base or {})
    data = {k: dict(v) for k, v in data.items() if isinstance(v, Mapping) and not k.startswith("_")}
    family = None if "texture" in values else data.get("texture", {}).get("name")
    for name, value in sorted(values.items(), key=lambda kv: kv[0] != "texture"):  # the family first
        units = str(ds[name].attrs.get("units", ""))
        text = _as_text(value, units)
        axis = resolve_axis(name, family)
        if axis.section == "texture" and axis.key == "name":
            data["texture"] = {"name": text}
            continue
        data.setdefault(axis.section, {})[axis.key] = text
    return data
