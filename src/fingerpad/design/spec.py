"""A sweep: the ``predict`` study plus a ``[sweep]`` table of axes and a design.

Study file (the sections of ``fingerpad predict``, see :mod:`fingerpad.study.spec`, plus)::

    [sweep]
    design = "grid"                 # grid (default) | lhs | points
    loads = "0.1N:4N:40"            # exploration loads (log-spaced; default 0.1-4 N, 40)

    [sweep.axes]                    # grid: lists or START:STOP:COUNT ranges with units
    spacing = "100um:400um:7"       # ranges are log-spaced ...
    height = { values = ["5um", "10um", "20um"] }
    radius = { range = "20um:200um:5", log = false }   # ... unless log = false

    # lhs:    [sweep] points = 200, seed = 1; each axis "LOW:HIGH" (log-uniform unless log = false)
    # points: [[sweep.point]] tables, each giving every axis, e.g. { spacing = "150um", height = "10um" }

The grid of the unit cell and its accuracy come from ``[model]`` as for ``predict``.

Units: in a study file every length, pressure or force of an axis carries its unit
(``spacing = 7``, ``[100, 200]`` or ``"100:200:3"`` is refused, naming the axis: a bare number
would be metres). Sections built in Python (:func:`sweep_from_dict` on a dict without a study
file behind it) may give SI numbers; ``require_units`` decides it explicitly.
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..encode import to_jsonable
from ..errors import FingerpadError
from ..finger import LAYER_FIELDS
from .axes import Axis, resolve_axis

__all__ = ["DESIGNS", "DEFAULT_SWEEP_LOADS", "SweepSpec", "read_sweep_file", "sweep_from_dict"]

DESIGNS = ("grid", "lhs", "points")
#: Exploration loads of a sweep: 0.1-4 N, the loads of touch (docs/model.md, design map).
DEFAULT_SWEEP_LOADS = "0.1N:4N:40"
#: Most points one sweep may hold (checked before anything is allocated).
MAX_POINTS = 1_000_000
#: Most loads of a sweep's curve (each point stores every quantity over them).
MAX_SWEEP_LOADS = 10_000
#: Largest seed of a Latin hypercube (NumPy's seeds are non-negative; 2**63 - 1 is plenty).
MAX_SEED = 2**63 - 1

_SWEEP_KEYS = ("design", "loads", "axes", "points", "seed", "point", "chunk")


@dataclass
class SweepSpec:
    """A parsed sweep (SI units).

    Attributes
    ----------
    base
        The study sections (texture, material, finger, loads, model), without ``[sweep]``.
    design
        ``grid``, ``lhs`` or ``points``.
    axes
        The swept axes; for a grid their values span the dimensions, otherwise ``point_values``
        holds one value per axis per point.
    point_values
        ``{axis name: values along point}`` for lhs and points designs.
    loads
        Exploration loads, N.
    chunk
        Points per task along the last dimension (each task owns whole chunks of the store).
    raw
        The ``[sweep]`` table as given (recorded in the store).
    """

    base: dict[str, dict[str, Any]]
    design: str
    axes: list[Axis]
    loads: np.ndarray
    point_values: dict[str, list[Any]] = field(default_factory=dict)
    chunk: int = 8
    raw: dict[str, Any] = field(default_factory=dict)
    source: str | None = None
    #: A population of fingers (:class:`fingerpad.population.distributions.Population`) predicted at
    #: every point, or ``None``; its members (SI) and the quantile levels stored.
    population: Any = None
    members: list[dict[str, float]] = field(default_factory=list)
    quantiles: tuple[float, ...] = ()
    #: How ``--population`` named it (a preset name, or a file or folder as an absolute path),
    #: recorded so that a resume or repair command can name it again; ``None`` for a table.
    population_source: str | None = None

    @property
    def shape(self) -> tuple[int, ...]:
        if self.design == "grid":
            return tuple(len(a.values) for a in self.axes)
        return (len(next(iter(self.point_values.values()))),)

    @property
    def dims(self) -> tuple[str, ...]:
        return tuple(a.name for a in self.axes) if self.design == "grid" else ("point",)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def assignment(self, index: tuple[int, ...]) -> dict[str, Any]:
        """Axis values of the point at ``index`` of the store's dimensions."""
        if self.design == "grid":
            return {a.name: a.values[i] for a, i in zip(self.axes, index, strict=True)}
        return {a.name: self.point_values[a.name][index[0]] for a in self.axes}

    def references(self) -> tuple[str, ...]:
        """The publications of the methods every point uses (:mod:`fingerpad.references` keys):
        the base study's finger models and friction law, the BEM unit cell and its solver, the
        layered skin where the base or an axis makes one, the population's correlated sampling."""
        from ..contact.solver import solver_references
        from ..coupling import model_references
        from ..micro.bem import BEMUnitCell
        from ..references import keys_of
        from ..study.spec import study_from_dict

        finger = study_from_dict(self.base).finger
        layered = finger.layer is not None or any(
            a.section == "finger" and (a.key == "skin" or a.key in LAYER_FIELDS) for a in self.axes)
        sources: list[Any] = [model_references(finger, BEMUnitCell), solver_references(True, layered)]
        if self.population is not None and self.population.correlations:
            from ..population import correlations

            sources.append(correlations)
        if self.population is not None:  # tell_flat: who tells each texture from the flat
            from ..perception import discrimination

            sources.append(discrimination)
        return keys_of(*sources)

    def study_data(self, assignment: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
        """The study sections of one point: the base with the axis values written in."""
        data = copy.deepcopy(self.base)
        for axis in self.axes:
            section = data.setdefault(axis.section, {})
            if axis.section == "texture" and axis.key == "name":
                # another family: its own parameters only (the base's may not apply)
                section.clear()
            section[axis.key] = axis.study_value(assignment[axis.name])
        finger = data.get("finger", {})
        if finger.get("skin") == "half-space" and any(a.section == "finger" and a.key == "skin" for a in self.axes):
            # a half-space point of a `skin` axis has no layer: the base's and the layer axes'
            # values do not apply there (its result is the same at every one of them); its skin
            # is the half-space of the layer's modulus, as `skin = half-space` on a layered finger
            e1 = finger.get("skin_layer_modulus")
            for key in (*LAYER_FIELDS, "skin_base"):
                finger.pop(key, None)
            if e1 is not None:
                finger.setdefault("skin_modulus", e1)
        return data

    def population_description(self) -> dict[str, Any] | None:
        """The population as the store records it (SI; JSON-able), ``None`` without one."""
        if self.population is None:
            return None
        pop = self.population
        # the members themselves count (a digest of their values, SI): whatever shaped them
        # (correlations, measured members, a later way of drawing them) tells two populations apart
        digest = hashlib.sha256(json.dumps(self.members, sort_keys=True, default=repr).encode()).hexdigest()
        return to_jsonable({"name": pop.name, "size": pop.size, "seed": pop.seed, "method": pop.method,
                          "distributions": {k: {"distribution": d.kind, **d.args}
                                            for k, d in pop.distributions.items()},
                          "correlations": list(getattr(pop, "correlations", ()) or ()),
                          "quantiles": list(self.quantiles), "members_sha256": digest}, nonfinite=repr)

    def population_payload(self) -> dict[str, Any] | None:
        """What every point needs of the population (plain data for the Dask workers): the
        members' parameters (SI) and the quantile levels; ``None`` without a population."""
        if self.population is None:
            return None
        return {"members": [dict(m) for m in self.members], "quantiles": list(self.quantiles)}

    def population_text(self) -> str:
        """The population in a few words, for messages."""
        pop = self.population
        return "no population" if pop is None else \
            f"population {pop.name!r} ({pop.size} members, seed {pop.seed}, {pop.method})"

    def signature(self, population: bool = True) -> str:
        """Hash of everything that determines the results (a store of another sweep is refused).

        It depends on the study's content only: not on the path by which the study file was
        named (relative, absolute, a copy elsewhere), nor on the cache folder; a measured surface
        counts by the content of its file, not by its path. A population (its distributions,
        size, seed, method, quantiles and its members' values) is part of it; ``population=False`` gives the
        signature of the same sweep without it (that of a sweep without a population, so that
        stores written before populations existed still resume).
        """
        base = {k: dict(v) for k, v in self.base.items() if k != "_source"}
        base.get("model", {}).pop("cache", None)
        surface = base.get("texture", {}).get("surface")
        if isinstance(surface, str):
            base["texture"]["surface"] = _file_digest(surface)
        content: dict[str, Any] = {"base": base, "sweep": self.raw, "version": __version__}
        if population and self.population is not None:
            # what the members are, not what the population is called (a file or a table of the same)
            content["population"] = {k: v for k, v in (self.population_description() or {}).items() if k != "name"}
        payload = json.dumps(content, sort_keys=True, default=repr)
        return hashlib.sha256(payload.encode()).hexdigest()


def _file_digest(path: str) -> str:
    """``sha256:<hex>`` of a file's content, or the path itself when it cannot be read."""
    try:
        digest = hashlib.sha256()
        with open(path, "rb") as fh:
            for block in iter(lambda: fh.read(1 << 20), b""):
                digest.update(block)
        return "sha256:" + digest.hexdigest()
    except OSError:
        return path


def read_sweep_file(path: str) -> dict[str, Any]:
    """The sections of a sweep study file (a ``predict`` study file with a ``[sweep]`` table)."""
    from ..study.spec import read_study_file

    data = read_study_file(path, extra_sections=("sweep", "population"))
    if "sweep" not in data:
        raise FingerpadError(f"study file {Path(path).name!r} has no [sweep] table: nothing to sweep "
                             "(see docs/sweeps.md)")
    return data


def _axis_values(axis: Axis, spec: Any, design: str, where: str,
                 require_unit: bool = False) -> tuple[tuple[Any, ...], bool]:
    """Values (grid) or bounds (lhs) of an axis, and whether it is log-spaced."""
    from ..units import parse_range

    def parse(value: Any) -> Any:
        return axis.parse(value, where, require_unit=require_unit)

    log = True
    if isinstance(spec, dict):
        unknown = sorted(set(spec) - {"values", "range", "log"})
        if unknown:
            raise FingerpadError(f"{where}: unknown key(s) {', '.join(unknown)} (values, range, log)")
        if "log" in spec:
            if not isinstance(spec["log"], bool):
                raise FingerpadError(f"{where} log: expected true or false, got {spec['log']!r}")
            log = spec["log"]
        if ("values" in spec) == ("range" in spec):
            raise FingerpadError(f"{where}: give values = [...] or range = \"START:STOP:COUNT\"")
        spec = spec.get("values", spec.get("range"))
    if isinstance(spec, list):
        if not spec:
            raise FingerpadError(f"{where}: empty list of values")
        values = tuple(parse(v) for v in spec)
        if axis.numeric and len(values) > 1:
            arr = np.asarray(values, float)
            log = bool(np.all(arr > 0)) and bool(np.allclose(np.diff(np.log(arr)), np.log(arr[1] / arr[0]))) \
                if np.all(arr > 0) else False
        else:
            log = False
        if len(set(values)) != len(values):
            raise FingerpadError(f"{where}: a value is given twice")
        return values, log
    if not isinstance(spec, str):
        if design == "grid":
            return (parse(spec),), False
        raise FingerpadError(f"{where}: expected LOW:HIGH bounds, got {spec!r}")
    if not axis.numeric:
        raise FingerpadError(f"{where}: {axis.name} takes a list of names, e.g. [\"{axis.choices[0]}\"]")
    parts = spec.split(":")
    dim = {"angle": "angle", "count": "none"}.get(axis.kind, axis.kind)
    if design == "lhs":
        if len(parts) != 2:
            raise FingerpadError(f"{where}: a Latin-hypercube axis takes bounds LOW:HIGH, got {spec!r}")
        lo, hi = (parse(p) for p in parts)
        if not hi > lo:
            raise FingerpadError(f"{where}: the bounds must satisfy LOW < HIGH, got {spec!r}")
        if log and lo <= 0:
            raise FingerpadError(f"{where}: log-uniform bounds must be positive (or give log = false)")
        return (lo, hi), log
    if len(parts) == 1:
        return (parse(spec),), False
    if len(parts) != 3:
        raise FingerpadError(f"{where}: expected START:STOP:COUNT, a list, or one value, got {spec!r}")
    if dim == "angle":
        parts = [str(parse(parts[0])) + "rad", str(parse(parts[1])) + "rad", parts[2]]
    start = parse(parts[0])
    if dim != "angle":
        parse(parts[1])  # a unit on both ends (and within the bounds)
    if log and start <= 0:
        log = False  # a range from zero or below: evenly spaced
    values = tuple(parse_range(":".join(parts), dim, name=where, log=log, max_count=MAX_POINTS))
    if axis.param is not None and axis.kind != "count":
        values = tuple(axis.param.check(v, where) for v in values)  # the declared bounds, one message
    if axis.kind == "count":
        values = tuple(sorted({int(round(v)) for v in values}))
    if len(values) < 1:
        raise FingerpadError(f"{where}: empty range")
    return values, log


def sweep_from_dict(data: Mapping[str, Any], *, require_units: bool | None = None, population: Any = None,
                    quantiles: str | Sequence[float] | None = None) -> SweepSpec:
    """Build and check a :class:`SweepSpec` from the sections of a sweep study file.

    ``require_units``: whether a length, pressure or force of an axis must carry a unit (a bare
    number is refused, naming the axis). ``None`` (default): required for the sections of a study
    file (:func:`read_sweep_file`, as ``fingerpad sweep`` reads them), not for a dict built in
    Python, whose bare numbers are SI.

    ``population``: a :class:`~fingerpad.population.distributions.Population` (or a preset name,
    a file, an ``analyse`` folder, or a table in SI numbers) predicted at every point; without it,
    the study's ``[population]`` table if it has one (:func:`fingerpad.population.rules.attach`
    checks either against the base study and the axes). ``quantiles``: the levels of its bands
    (numbers or ``"0.1,0.5,0.9"``; default 5/25/50/75/95 %); the store always holds 10, 50 and
    90 % as well, which the design map draws.

    The base study (every point's study, before the axis values) is checked once here by
    :func:`fingerpad.study.spec.study_from_dict`; each point is checked again when it runs, and
    a point that cannot exist is stored as invalid with its reason, without stopping the sweep.
    """
    from ..study.spec import study_from_dict
    from ..study.values import integer, parse_loads

    sweep = dict(data.get("sweep") or {})
    base = {k: dict(v) for k, v in data.items() if k not in ("sweep", "_source", "population")}
    source = (data.get("_source") or {}).get("file")
    if "_source" in data:
        base["_source"] = dict(data["_source"])
    unknown = sorted(set(sweep) - set(_SWEEP_KEYS))
    if unknown:
        raise FingerpadError(f"[sweep]: unknown key(s) {', '.join(unknown)} (known: {', '.join(_SWEEP_KEYS)})")
    design = str(sweep.get("design", "grid")).strip().lower()
    if design not in DESIGNS:
        raise FingerpadError(f"[sweep] design: must be one of {', '.join(DESIGNS)}, got {sweep.get('design')!r}")
    loads_text = sweep.get("loads", DEFAULT_SWEEP_LOADS)
    # the study's loads rule (ranges, values, comma lists, sign), with a sweep's own cap: every
    # point stores a curve over these loads
    loads = parse_loads(loads_text, True, "[sweep] loads", max_count=MAX_SWEEP_LOADS)
    chunk = integer(sweep.get("chunk", 8), "[sweep] chunk", 1, MAX_POINTS)

    base_study = study_from_dict(base)  # the base must be a valid study on its own
    family = base.get("texture", {}).get("name")
    axes_spec: dict[str, Any] = {}
    if design == "points":
        rows = sweep.get("point")
        if not isinstance(rows, list) or not rows or not all(isinstance(r, dict) for r in rows):
            raise FingerpadError("[sweep] design = \"points\" needs [[sweep.point]] tables, each naming every axis")
        names = list(rows[0])
        for i, row in enumerate(rows):
            if sorted(row) != sorted(names):
                raise FingerpadError(f"[[sweep.point]] {i + 1}: names {', '.join(sorted(row))}; the first names "
                                     f"{', '.join(sorted(names))}: every point must give the same axes")
        axes_spec = {n: None for n in names}
    else:
        axes_spec = dict(sweep.get("axes") or {})
        if not axes_spec:
            raise FingerpadError("[sweep.axes] is empty: name at least one axis (e.g. spacing = \"100um:400um:7\")")
    strict = ("_source" in data) if require_units is None else bool(require_units)
    swept_family = "texture" in axes_spec
    axes: list[Axis] = []
    point_values: dict[str, list[Any]] = {}
    for name in axes_spec:
        axis = resolve_axis(name, None if swept_family else family)
        where = f"[sweep.axes] {name}"
        if design == "points":
            values = [axis.parse(row[name], f"[[sweep.point]] {i + 1} {name}", require_unit=strict)
                      for i, row in enumerate(sweep["point"])]
            point_values[name] = values
            axes.append(Axis(**{**axis.__dict__, "values": tuple(dict.fromkeys(values)), "log": False}))
            continue
        values, log = _axis_values(axis, axes_spec[name], design, where, strict)
        axes.append(Axis(**{**axis.__dict__, "values": values, "log": log}))
    size = int(np.prod([len(a.values) for a in axes])) if design == "grid" else 0
    if design == "lhs":
        from scipy.stats import qmc

        n = sweep.get("points")
        if n is None:
            raise FingerpadError("[sweep] design = \"lhs\" needs points = N (a positive integer)")
        n = integer(n, "[sweep] points", 1, MAX_POINTS)
        seed = integer(sweep.get("seed", 0), "[sweep] seed", 0, MAX_SEED)
        numeric = [a for a in axes if a.numeric]
        if len(numeric) != len(axes):
            raise FingerpadError("[sweep] a Latin hypercube samples numeric axes only (give names on a grid)")
        unit = qmc.LatinHypercube(d=len(axes), seed=seed).random(n)
        for j, axis in enumerate(axes):
            lo, hi = axis.values
            if axis.log:
                vals = np.exp(np.log(lo) + unit[:, j] * (np.log(hi) - np.log(lo)))
            else:
                vals = lo + unit[:, j] * (hi - lo)
            if axis.kind == "count":
                vals = np.round(vals)
            point_values[axis.name] = [float(v) for v in vals]
        size = n
    if design == "points":
        size = len(sweep["point"])
    if size > MAX_POINTS:
        raise FingerpadError(f"[sweep]: {size} points is more than the {MAX_POINTS} allowed")
    spec = SweepSpec(base=base, design=design, axes=axes, loads=loads, point_values=point_values, chunk=chunk,
                     raw=to_jsonable(sweep, nonfinite=repr), source=source)
    _add_population(spec, base_study, population, data.get("population"), quantiles)
    del base_study
    return spec


#: Quantile levels a population sweep always stores: the design map draws the critical loads of
#: the 10 % and 90 % fingers and colours by the median.
MAP_QUANTILES = (0.1, 0.5, 0.9)


def _add_population(spec: SweepSpec, base_study: Any, population: Any, table: Mapping[str, Any] | None,
                    quantiles: str | Sequence[float] | None) -> None:
    """Attach a population to ``spec`` (``population``, else the study file's ``table``), every
    rule of :func:`fingerpad.population.rules.attach` checked against the base study and the axes
    before anything runs: sampled once here (every point predicts the same members)."""
    from ..population.presets import POPULATION_PRESETS
    from ..population.rules import attach

    fixed = {axis.key: f"[sweep.axes] {axis.name}" for axis in spec.axes if axis.section == "finger"}
    directions = ["direction" for axis in spec.axes if (axis.section, axis.key) == ("model", "direction")]
    plan = attach(base_study, population, table=table, quantiles=quantiles, fixed=fixed, axes=directions)
    if plan is None:
        return
    spec.population = plan.population
    spec.members = [dict(m) for m in plan.members]
    if isinstance(population, (str, os.PathLike)):
        named = str(population).strip()
        spec.population_source = named if named.lower() in POPULATION_PRESETS else os.path.abspath(named)
    spec.quantiles = tuple(sorted(set(plan.quantiles) | set(MAP_QUANTILES)))
