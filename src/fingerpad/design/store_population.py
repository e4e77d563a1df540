"""The population part of a sweep store (``fingerpad sweep --population``, docs/sweeps.md "With
a population of fingers"): its variables along ``quantile``, ``state`` and ``member``, the
version of their layout, and the checks that a store holds the population asked for."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FingerpadError
from .evaluate import POPULATION_BANDS, POPULATION_LOAD_BANDS, STATE_CODES
from .spec import SweepSpec

__all__ = ["POPULATION_LAYOUT", "POP_FRACTION_VARS", "POP_LOAD_VARS", "POP_MEMBER_VARS", "POP_QUANTILE_VARS", "check_store_population",
           "population_flags", "population_template", "shell_path", "stored_population_text"]

#: Population variables (a sweep with ``--population``): name -> (units, long name).
POP_LOAD_VARS = {
    "band_area_ratio": ("1", "quantiles over the population of A_re / A_fr"),
    "band_mu": ("1", "quantiles over the population of mu"),
    "band_mu_ref": ("1", "quantiles over the population of mu on the flat reference"),
    "band_mu_rel": ("1", "quantiles over the population of mu / mu_ref"),
}
POP_QUANTILE_VARS = {
    "band_critical_load": ("N", "quantiles over the population of the critical load (members that reach "
                                "none left out)"),
    "band_full_contact_load": ("N", "quantiles over the population of the full-contact load (members that "
                                    "reach none left out)"),
}
#: Per-load fractions of the members (a sweep with ``--population``): name -> (units, long name).
#: ``tell_flat``: the members telling the texture from the flat reference by friction (P >= 0.75
#: in a forced choice, docs/perception.md; each member's Weber fraction, the attribute
#: ``weber_fraction`` when it is one for all).
POP_FRACTION_VARS = {
    "tell_flat": ("1", "fraction of the population's members telling the texture from the flat reference by "
                       "friction (P >= 0.75)"),
}
#: Per-member variables (a sweep with ``--population``): name -> (units, long name), on
#: ``(*axes, member, load)``. ``mu_members``: each member's own mu on the texture, from which the
#: design map tells who tells the texture from any reference surface (``design-map --population
#: --tell-apart REF``, docs/perception.md), REF predicted for the same members.
POP_MEMBER_VARS = {
    "mu_members": ("1", "each member's friction coefficient mu on the texture"),
}
assert set(POP_LOAD_VARS) == set(POPULATION_BANDS) and set(POP_QUANTILE_VARS) == set(POPULATION_LOAD_BANDS)
#: Version of the population variables' layout (attribute ``fingerpad_sweep_population``). The
#: store's own ``fingerpad_sweep`` stays 1: the population adds variables and changes none, so
#: readers of stores without a population read these stores unchanged.
POPULATION_LAYOUT = 1


def population_template(spec: SweepSpec, coords: dict[str, Any], data: dict[str, Any]) -> None:
    """Add the population's coordinates and variables of a sweep store to ``coords`` and
    ``data`` (docs/sweeps.md, "With a population of fingers")."""
    import xarray as xr

    shape, dims = spec.shape, spec.dims
    nl, nq = spec.loads.size, len(spec.quantiles)
    coords["quantile"] = xr.Variable("quantile", np.asarray(spec.quantiles, float),
                                     {"units": "1", "long_name": "quantile over the population's members"})
    coords["state"] = xr.Variable("state", np.asarray(list(STATE_CODES), dtype="<U10"),
                                  {"long_name": "contact state at the pad centre"})
    coords["member"] = xr.Variable("member", np.arange(len(spec.members)), {"long_name": "population member"})
    for name, (unit, long) in POP_LOAD_VARS.items():
        data[name] = xr.Variable((*dims, "quantile", "load"), np.full((*shape, nq, nl), np.nan),
                                 {"units": unit, "long_name": long})
    for name, (unit, long) in POP_QUANTILE_VARS.items():
        data[name] = xr.Variable((*dims, "quantile"), np.full((*shape, nq), np.nan),
                                 {"units": unit, "long_name": long})
    data["state_probability"] = xr.Variable(
        (*dims, "state", "load"), np.full((*shape, len(STATE_CODES), nl), np.nan),
        {"units": "1", "long_name": "fraction of the population's members whose pad centre is in each state"})
    for name, (unit, long) in POP_FRACTION_VARS.items():
        data[name] = xr.Variable((*dims, "load"), np.full((*shape, nl), np.nan), {"units": unit, "long_name": long})
    for name, (unit, long) in POP_MEMBER_VARS.items():
        data[name] = xr.Variable((*dims, "member", "load"), np.full((*shape, len(spec.members), nl), np.nan),
                                 {"units": unit, "long_name": long})
    data["asperity_over_range"] = xr.Variable(
        dims, np.full(shape, np.nan),
        {"units": "1", "long_name": "fraction of the population's members in asperity contact at the pad "
                                    "centre at every exploration load"})
    for pname, dist in spec.population.distributions.items():
        data[f"member_{pname}"] = xr.Variable(
            "member", np.array([m[pname] for m in spec.members], float),
            {"units": dist.param.unit or "1", "long_name": f"member's {dist.param.doc}"})


def stored_population_text(attrs: dict[str, Any]) -> str:
    """The population a store holds, in a few words (as
    :meth:`fingerpad.design.spec.SweepSpec.population_text`)."""
    if "population" not in attrs:
        return "no population"
    try:
        pop = json.loads(attrs["population"])
        return f"population {pop['name']!r} ({pop['size']} members, seed {pop['seed']}, {pop['method']})"
    except (ValueError, KeyError, TypeError):
        return "a population"


def shell_path(path: str | Path) -> str:
    """``path`` as a command to type names it: relative to the working folder (where the user
    stands), quoted for the shell where it needs it."""
    import os
    import shlex

    try:
        shown = os.path.relpath(path)
    except ValueError:  # another drive
        shown = str(path)
    return shlex.quote(shown)


def population_flags(attrs: dict[str, Any]) -> str:
    """The flags that name the population of the sweep that wrote a store (``" --population
    adults"``, with its ``--quantiles`` when they were not the default), for a resume or repair
    command; ``""`` for a store without one, or whose population came with the study file."""
    source = attrs.get("population_source")
    if "population" not in attrs or not source:
        return ""
    from ..population.presets import POPULATION_PRESETS
    from ..population.rules import DEFAULT_QUANTILES
    from .spec import MAP_QUANTILES

    flags = f" --population {source if source in POPULATION_PRESETS else shell_path(source)}"
    try:
        stored = tuple(float(q) for q in json.loads(attrs["population"]).get("quantiles", ()))
    except (ValueError, TypeError, AttributeError):
        return flags
    if stored and stored != tuple(sorted(set(DEFAULT_QUANTILES) | set(MAP_QUANTILES))):
        flags += " --quantiles " + ",".join(f"{q:g}" for q in stored)
    return flags


def check_store_population(ds: Any, path: str | Path, source: str) -> None:
    """Refuse a store that does not hold the population ``source`` (a preset name or a file):
    the design map of one population must not be drawn from another's bands.

    Raises
    ------
    FingerpadError
        The store holds no population, or another one (other distributions, size, seed, method
        or members); a bad ``source``.
    """
    from ..population.run import DEFAULT_QUANTILES
    from ..population.sources import load_population
    from .spec import SweepSpec

    pop = load_population(source)
    if "population" not in ds.attrs:
        raise FingerpadError(f"{path}: holds no population; sweep one with fingerpad sweep STUDY.toml --population "
                             f"{source} --out ANOTHER.zarr (or --overwrite to replace this store)")
    stored = json.loads(ds.attrs["population"])
    probe = SweepSpec(base={}, design="grid", axes=[], loads=np.zeros(0), population=pop, members=pop.sample(),
                      quantiles=tuple(stored.get("quantiles", DEFAULT_QUANTILES)))
    mine = probe.population_description() or {}
    if {k: v for k, v in mine.items() if k != "name"} != {k: v for k, v in stored.items() if k != "name"}:
        raise FingerpadError(f"{path}: holds {stored_population_text(dict(ds.attrs))}, not "
                             f"{probe.population_text()} (other distributions, size, seed, method or members); "
                             "draw it with the population it was swept with")
