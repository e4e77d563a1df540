"""The one-cell job of ``fingerpad solve``: a texture, the materials, mean pressures -> contact.

:func:`build_solve_job` checks every input once (cheap checks first, then the texture is built);
:func:`run_solve` solves the cell at each pressure (warm-started) and, if asked, brackets the
critical pressure; :func:`write_solve_outputs` writes the JSON, NetCDF and plot, all or none.
"""

from __future__ import annotations

import math
import os
import sys
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from .. import references
from .._version import __version__
from ..errors import FingerpadError
from ..materials import DEFAULT_SKIN_MODULUS, DEFAULT_SKIN_POISSON, check_modulus, check_poisson, reduced_modulus
import numpy as np

from ..units import parse_int, parse_positive, parse_quantity, parse_range, parse_size

__all__ = ["MaterialsSpec", "SolveJob", "SolveOutcome", "build_solve_job", "parse_materials", "run_solve",
           "write_solve_outputs"]


#: Units of the per-pressure results (CSV headers).
SUMMARY_UNITS = {"mean_pressure": "Pa", "real_contact_area": "m2", "max_pressure": "Pa", "mean_gap": "m",
                 "approach": "m", "seconds": "s", "work_of_adhesion": "J/m2", "adhesion_range": "m"}


def _parse_float(text: str, name: str) -> float:
    return parse_quantity(text, "none", name=name)


#: Most pressures one ``solve`` may ask for (each is a contact solve).
MAX_PRESSURES = 10_000


def _parse_pressures(texts: Sequence[str], log: bool, adhesive: bool = False) -> list[float]:
    """The mean pressures (Pa) of ``--pressure``: positive, or with adhesion of any sign; each
    option a value, a range or a comma list of either (``-2kPa,0Pa,5kPa``)."""
    from ..plausibility import check_plausible

    pressures: list[float] = []
    for text in texts:
        pieces = str(text).split(",")
        for piece in pieces:
            for value in parse_range(piece, "pressure", name="--pressure", log=log and not adhesive,
                                     max_count=MAX_PRESSURES):
                if not math.isfinite(value) or (value <= 0 and not adhesive):
                    raise FingerpadError(f"--pressure: must be positive, got {text!r}"
                                         + ("" if adhesive else " (zero and tensions need --work-of-adhesion)"))
                pressures.append(value)
        if len(pressures) > MAX_PRESSURES:
            raise FingerpadError(f"--pressure: more than {MAX_PRESSURES} pressures asked for (each is a solve)")
    if not pressures:
        raise FingerpadError("give at least one --pressure (e.g. --pressure 20kPa or --pressure 1kPa:100kPa:10)")
    for value in (min(pressures), max(pressures)):
        if value > 0:
            check_plausible(value, "pressure", "--pressure")
    return pressures


# --------------------------------------------------------------------------------------------
# materials

@dataclass
class MaterialsSpec:
    modulus: float  # reduced modulus E* (Pa)
    skin_modulus: float | None = None
    skin_poisson: float | None = None
    material_modulus: float | None = None  # None: rigid
    material_poisson: float | None = None
    layer: Any = None  # a layered skin (fingerpad.contact.Layer); None: the homogeneous half-space

    def as_dict(self) -> dict[str, Any]:
        # the layer's keys only with a layer: the homogeneous skin's outputs stay as they were
        layer = {} if self.layer is None else {
            "skin": "layered",
            "skin_layer_thickness": self.layer.thickness,
            "skin_layer_modulus": self.layer.modulus,
            "skin_substrate_modulus": self.layer.substrate_modulus if not self.layer.rigid_base else "rigid",
            "skin_substrate_poisson": self.layer.substrate_poisson,
            "skin_base": ("elastic" if not self.layer.rigid_base else
                          "rigid-frictionless" if self.layer.base == "frictionless" else "rigid"),
            # the layer's units with it (a half-space's materials are listed as they always were)
            "units": _skin_units(),
        }
        return {
            "reduced_modulus": self.modulus,
            "skin_modulus": self.skin_modulus,
            "skin_poisson": self.skin_poisson,
            "material_modulus": self.material_modulus,
            "material_poisson": self.material_poisson,
            "material_rigid": self.skin_modulus is not None and self.material_modulus is None,
            **layer,
        }


def _skin_units() -> dict[str, str]:
    from ..finger import skin_units

    return skin_units()


def parse_materials(
    modulus: str | None,
    skin_modulus: str | None,
    skin_poisson: str | None,
    material_modulus: str | None,
    material_poisson: str | None,
    skin_layer_thickness: str | None = None,
    skin_layer_modulus: str | None = None,
    skin_substrate_modulus: str | None = None,
    skin_substrate_poisson: str | None = None,
    skin_base: str | None = None,
    *,
    skin_option: str = "--skin-modulus",
) -> MaterialsSpec:
    """Either ``--modulus`` (reduced E*) or the skin/material constants (Eq. 3.4), never both.

    A layered skin (``--skin-layer-thickness``, ``--skin-layer-modulus``, and
    ``--skin-substrate-modulus`` or ``--skin-base rigid|rigid-frictionless``; docs/model.md
    section 6.4) replaces ``--skin-modulus``: the layer is the skin's surface, its modulus enters
    Eq. 3.4, and ``--skin-poisson`` holds for the layer and, unless
    ``--skin-substrate-poisson`` says otherwise, for the substrate. ``skin_option`` names the
    option the skin's modulus came from (the layer's, for a layered skin) in messages.
    """
    from ..finger import SKIN_BASES

    base = None if skin_base is None else skin_base.strip().lower()
    if base is not None and base not in SKIN_BASES:
        raise FingerpadError(f"--skin-base must be one of {', '.join(SKIN_BASES)}, got {skin_base!r}")
    rigid_base = base in ("rigid", "rigid-frictionless")
    layered = {"--skin-layer-thickness": skin_layer_thickness, "--skin-layer-modulus": skin_layer_modulus,
               "--skin-substrate-modulus": skin_substrate_modulus}
    if any(v is not None for v in layered.values()) or base is not None or skin_substrate_poisson is not None:
        missing = [k for k, v in layered.items() if v is None and not (rigid_base and k == "--skin-substrate-modulus")]
        if missing:
            raise FingerpadError(f"a layered skin needs --skin-layer-thickness, --skin-layer-modulus and "
                                 f"--skin-substrate-modulus (or --skin-base rigid): {', '.join(missing)} missing")
        for name, value in (("--modulus", modulus), ("--skin-modulus", skin_modulus)):
            if value is not None:
                raise FingerpadError(f"give either {name} or the layered skin (--skin-layer-modulus is the skin's "
                                     "surface modulus), not both")
        spec = parse_materials(None, skin_layer_modulus, skin_poisson, material_modulus, material_poisson,
                               skin_option="--skin-layer-modulus")
        from ..contact import Layer

        from ..finger import finger_param

        # the finger's declaration: a unit is required (a bare 2 would be 2 m), positive
        t = finger_param("skin_layer_thickness").parse(skin_layer_thickness, "--skin-layer-thickness")
        said_rigid = skin_substrate_modulus is not None and \
            skin_substrate_modulus.strip().lower() in ("rigid", "inf", "infinity")
        if base == "elastic" and said_rigid:
            raise FingerpadError("--skin-base elastic contradicts --skin-substrate-modulus rigid: give one of them")
        if rigid_base and skin_substrate_modulus is not None and not said_rigid:
            raise FingerpadError(f"--skin-base {base} rests the layer on a rigid base: --skin-substrate-modulus "
                                 f"{skin_substrate_modulus} would be ignored; drop it")
        rigid = rigid_base or said_rigid
        if rigid:
            e2 = math.inf
        else:
            e2 = parse_quantity(skin_substrate_modulus, "pressure", name="--skin-substrate-modulus")
            check_modulus(e2, "--skin-substrate-modulus")
        nu2 = spec.skin_poisson
        if skin_substrate_poisson is not None:
            if rigid:
                raise FingerpadError("--skin-substrate-poisson needs an elastic substrate (a rigid base has none)")
            nu2 = _parse_float(skin_substrate_poisson, "--skin-substrate-poisson")
            check_poisson(nu2, "--skin-substrate-poisson")
        spec.layer = Layer(t, spec.skin_modulus, spec.skin_poisson, e2, nu2,
                           "frictionless" if base == "rigid-frictionless" else "bonded")
        return spec
    others = {
        "--skin-modulus": skin_modulus,
        "--skin-poisson": skin_poisson,
        "--material-modulus": material_modulus,
        "--material-poisson": material_poisson,
    }
    given = [k for k, v in others.items() if v is not None]
    if modulus is not None:
        if given:
            raise FingerpadError(
                f"give either --modulus (the reduced modulus E*) or {', '.join(given)}, not both"
            )
        e = parse_quantity(modulus, "pressure", name="--modulus")
        check_modulus(e, "--modulus")
        from ..plausibility import check_plausible

        check_plausible(e, "skin modulus", "--modulus")
        return MaterialsSpec(modulus=e)
    from ..finger import finger_param
    from .values import material

    # the finger's declarations (bounds, plausible ranges), as predict reads them
    es = DEFAULT_SKIN_MODULUS if skin_modulus is None else \
        finger_param(skin_option.removeprefix("--").replace("-", "_")).parse(skin_modulus, skin_option)
    nus = DEFAULT_SKIN_POISSON if skin_poisson is None else _parse_float(skin_poisson, "--skin-poisson")
    check_poisson(nus, "--skin-poisson")
    # the counter-surface as predict reads it ("rigid", "inf": rigid; same messages)
    em, num = material(material_modulus, material_poisson, "--material-modulus", "--material-poisson")
    e_star = reduced_modulus(es, nus, em, num if num is not None else 0.35)
    return MaterialsSpec(modulus=e_star, skin_modulus=es, skin_poisson=nus, material_modulus=em, material_poisson=num)



@dataclass
class SolveJob:
    texture: Any
    materials: MaterialsSpec
    pressures: list[float]
    tol: float = 1e-8
    max_iter: int = 5000
    formulation: str = "auto"
    texture_source: dict[str, Any] = field(default_factory=dict)
    json_path: str | None = None
    csv_path: str | None = None
    save_path: str | None = None
    plot_path: str | None = None
    plot_at: float | None = None  # mean pressure whose maps are plotted (nearest solved); None: last
    show_table: bool = True
    critical_rtol: float | None = None  # bracket the transition pressure to this relative width
    #: Adhesion: ``{"work_of_adhesion": J/m2, "adhesion_range": m, "adhesion_law": name}``; None without.
    adhesion: dict[str, Any] | None = None

    def inputs(self) -> dict[str, Any]:
        from ..textures import describe

        tex = self.texture
        return {
            "texture": {
                "name": tex.name,
                "description": describe(tex),
                **self.texture_source,
                "params": dict(tex.params),
                "size": list(tex.size),
                "grid": list(tex.shape),
                "periodic": bool(tex.periodic),
            },
            "materials": self.materials.as_dict(),
            "modulus": self.materials.modulus,
            "pressures": list(self.pressures),
            "tol": self.tol,
            "max_iter": self.max_iter,
            "formulation": self.formulation,
            **({} if self.adhesion is None else {"adhesion": dict(self.adhesion)}),
            "fingerpad_version": __version__,
        }

    def netcdf_attrs(self) -> dict[str, Any]:
        m = self.materials.as_dict()
        attrs: dict[str, Any] = {k: v for k, v in m.items() if k != "reduced_modulus"}
        attrs.update(
            {
                "texture_source": self.texture_source.get("source", "generator"),
                "surface_file": self.texture_source.get("file"),
                "requested_pressures": list(self.pressures),
                "max_iter": self.max_iter,
                "requested_formulation": self.formulation,
                "command": " ".join(["fingerpad", *sys.argv[1:]]) if sys.argv else "fingerpad",
                "references": references.netcdf_attribute(self.references()),
            }
        )
        return attrs

    def references(self) -> tuple[str, ...]:
        """The publications of the solve's method (:mod:`fingerpad.references` keys)."""
        from .citations import solve_references

        return solve_references(self.texture, self.materials.layer, self.adhesion)


def _check_outputs(job: SolveJob) -> None:
    from ..io import check_writable

    seen: dict[str, str] = {}
    for opt, path, suffixes in (("--json", job.json_path, (".json",)), ("--save", job.save_path, (".nc",)),
                                ("--plot", job.plot_path, (".png", ".svg", ".pdf")),
                                ("--csv", job.csv_path, (".csv",))):
        if path is None or (opt == "--json" and path == "-"):
            continue
        key = os.path.abspath(path)
        if key in seen:
            raise FingerpadError(f"{opt} and {seen[key]} name the same file {path!r}")
        seen[key] = opt
        check_writable(path, opt, suffixes)


@dataclass
class SolveOutcome:
    """What :func:`run_solve` computed: the load curve, the critical-pressure bracket, the JSON."""

    curve: Any
    critical: Any
    payload: dict[str, Any]

    @property
    def results(self) -> list[Any]:
        return list(self.curve.results)


def run_solve(
    job: SolveJob,
    progress: Callable[[int, int], None] | None = None,
    iterations: Callable[[tuple[int, int], int, float], None] | None = None,
) -> SolveOutcome:
    """Solve the cell at each pressure of ``job`` (and bracket the critical pressure if asked).

    ``progress(i, n)`` is called after each pressure; ``iterations(shape, iteration, residual)``
    on every conjugate-gradient iteration (see :class:`fingerpad.contact.HalfSpaceSolver`).
    """
    from ..contact import HalfSpaceSolver
    from ..micro.loadcurve import critical_pressure, load_curve

    if job.adhesion is not None:
        return _run_adhesive(job, progress, iterations)
    with warnings.catch_warnings():
        # Unconverged solves are reported by the caller, once per pressure, with the exit code.
        warnings.filterwarnings("ignore", message="contact solve did not converge", category=RuntimeWarning)
        solver = HalfSpaceSolver(job.texture, job.materials.modulus, layer=job.materials.layer, tol=job.tol,
                                 max_iter=job.max_iter,
                                 formulation=job.formulation, progress=iterations)
        curve = load_curve(solver, job.pressures, progress=progress)
        critical = critical_pressure(solver, rtol=job.critical_rtol) if job.critical_rtol is not None else None
    return SolveOutcome(curve, critical, _results_json(job, list(curve.results), critical))


def _run_adhesive(job: SolveJob, progress: Callable[[int, int], None] | None,
                  iterations: Callable[[tuple[int, int], int, float], None] | None) -> SolveOutcome:
    """The adhesive solves of ``job`` along the loading branch (docs/model.md 6.6): zero mean
    pressure first (the skin resting on the texture's top, the adhesion pulling it on), the
    positive pressures upward from it and the negative ones downward, each from the last; then the
    pull-off pressure by pulling the skin apart from the zero-load state (its range regularised
    to the grid where it is below a pixel)."""
    from ..contact import HalfSpaceSolver
    from ..contact.interaction import regularised_interaction
    from ..micro.pull_apart import SEPARATION_STEP, pull_apart
    from ..micro.loadcurve import LoadCurve

    adh = job.adhesion
    assert adh is not None
    tex = job.texture
    e = job.materials.modulus
    law = regularised_interaction(adh["adhesion_law"], adh["work_of_adhesion"], float(adh["adhesion_range"]), e,
                                  float(min(tex.spacing)))
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="contact solve did not converge", category=RuntimeWarning)
        solver = HalfSpaceSolver(tex, e, layer=job.materials.layer, tol=job.tol, max_iter=job.max_iter,
                                 progress=iterations, interaction=law)
        zero = solver.solve_pressure(0.0)
        n = len(job.pressures)
        results: list[Any] = [None] * n
        done = 0
        for branch in (sorted((p, i) for i, p in enumerate(job.pressures) if p >= 0),
                       sorted(((p, i) for i, p in enumerate(job.pressures) if p < 0), reverse=True)):
            previous = zero
            for p, i in branch:
                previous = results[i] = zero if p == 0 else solver.solve_pressure(p, initial=previous)
                done += 1
                if progress is not None:
                    progress(done, n)
        pulled = pull_apart(solver, zero, SEPARATION_STEP * law.range)
    curve = LoadCurve(
        mean_pressure=np.array([r.mean_pressure for r in results]),
        contact_fraction=np.array([r.contact_fraction for r in results]),
        mean_gap=np.array([r.mean_gap for r in results]), max_pressure=np.array([r.max_pressure for r in results]),
        contact_state=[r.contact_state for r in results], iterations=np.array([r.iterations for r in results]),
        converged=np.array([r.converged for r in results]), seconds=np.array([r.seconds for r in results]),
        results=results,
    )
    payload = _results_json(job, results)
    payload["pull_off_pressure"] = pulled["pull_off"]
    payload["adhesion"] = {**law.describe(), "adhesion_range_given": float(adh["adhesion_range"]),
                           "range_regularised": bool(law.range > float(adh["adhesion_range"])),
                           "pull_off_pressure": pulled["pull_off"], "work_of_separation": pulled["work"],
                           "pull_off_solves": pulled["solves"],
                           "branch": "loading: from zero load up through the positive pressures and down through the "
                                     "negative ones; pull-off by pulling apart from zero load"}
    return SolveOutcome(curve, None, payload)


def write_solve_outputs(job: SolveJob, outcome: SolveOutcome) -> None:
    """Write the JSON (unless to stdout), NetCDF and plot of ``job``: all of them or none."""
    import json

    from .. import io as fio
    from .. import netcdf

    results = outcome.results
    staging = fio.Staging()
    try:
        if job.json_path is not None and job.json_path != "-":
            text = json.dumps(outcome.payload, indent=2) + "\n"
            staging.stage(job.json_path, lambda tmp: fio.write_text(tmp, text))
        if job.save_path is not None:
            attrs = job.netcdf_attrs()
            if len(results) == 1:
                staging.stage(job.save_path, lambda tmp: netcdf.save_result(results[0], tmp, attrs))
            else:
                staging.stage(job.save_path, lambda tmp: netcdf.save_load_curve(outcome.curve, tmp, attrs))
        if job.plot_path is not None:
            from ..plotting.solution import plot_solution

            index = -1
            if job.plot_at is not None:
                index = min(range(len(results)), key=lambda i: abs(math.log(results[i].mean_pressure / job.plot_at)))
            fmt = job.plot_path.rsplit(".", 1)[-1].lower()
            staging.stage(job.plot_path, lambda tmp: plot_solution(results, tmp, index=index, fmt=fmt))
        if job.csv_path is not None:
            import csv

            def write_csv(tmp: Any) -> None:
                rows = [r.summary() for r in results]
                with open(tmp, "w", newline="", encoding="utf-8") as fh:
                    writer = csv.writer(fh)
                    writer.writerow([f"{k}_{SUMMARY_UNITS[k]}" if SUMMARY_UNITS.get(k) else k for k in rows[0]])
                    writer.writerows([list(row.values()) for row in rows])

            staging.stage(job.csv_path, write_csv)
        staging.commit()
    finally:
        staging.discard()


def _results_json(job: SolveJob, results: Sequence[Any], critical: Any = None) -> dict[str, Any]:
    from ..encode import to_jsonable

    payload: dict[str, Any] = {
        "inputs": job.inputs(),
        "converged": all(bool(r.converged) or r.contact_state == "detached" for r in results),
        "references": references.metadata(job.references()),
        "results": [r.summary() for r in results],
    }
    if critical is not None:
        payload["critical_pressure"] = {
            "lower": critical.lower, "upper": critical.upper, "estimate": critical.estimate,
            "relative_width": critical.relative_width, "solves": critical.solves,
            "definition": "lowest mean pressure (Pa) at which the skin touches the texture's base level "
                          "(generated textures: their lowest level; measured maps: see docs/formats.md)",
        }
    return to_jsonable(payload)


def parse_adhesion(work: str | None, range_: str | None, law: str | None) -> dict[str, Any] | None:
    """``--work-of-adhesion``, ``--adhesion-range``, ``--adhesion-law`` checked by the finger's
    declarations (:data:`fingerpad.finger.FINGER_PARAMS`): the adhesion, or ``None`` without a
    positive work of adhesion (a range or law alone is refused: it would do nothing)."""
    from ..finger import finger_param

    w = finger_param("work_of_adhesion").parse(work, "--work-of-adhesion") if work is not None else 0.0
    if w == 0:
        given = [o for o, v in (("--adhesion-range", range_), ("--adhesion-law", law)) if v is not None]
        if given:
            raise FingerpadError(f"{', '.join(given)} needs a positive --work-of-adhesion")
        return None
    rho = finger_param("adhesion_range")
    return {"work_of_adhesion": w,
            "adhesion_range": rho.parse(range_, "--adhesion-range") if range_ is not None else rho.default,
            "adhesion_law": finger_param("adhesion_law").parse(law, "--adhesion-law") if law is not None
            else finger_param("adhesion_law").default}


def build_solve_job(
    *, ctx_args: Sequence[str] = (), texture: str | None, surface: str | None, size: str | None,
    height_unit: str | None, periodic: bool | None, fill_missing: bool = False, grid: str | None,
    periodize: bool = False, pixel_size: str | None = None, base_quantile: str | None = None,
    modulus: str | None, skin_modulus: str | None, skin_poisson: str | None, material_modulus: str | None,
    material_poisson: str | None, pressure: Sequence[str], log: bool, tol: str, max_iter: str,
    formulation: str, json_path: str | None, save: str | None, plot: str | None, csv_path: str | None = None,
    plot_at: str | None = None, critical: str | None = None, skin_layer_thickness: str | None = None,
    skin_layer_modulus: str | None = None, skin_substrate_modulus: str | None = None,
    skin_substrate_poisson: str | None = None, skin_base: str | None = None,
    work_of_adhesion: str | None = None, adhesion_range: str | None = None, adhesion_law: str | None = None,
) -> SolveJob:
    """Validate every option of ``fingerpad solve`` (cheap checks first) and build the texture."""
    if (texture is None) == (surface is None):
        raise FingerpadError("give exactly one of --texture NAME or --surface FILE")
    materials = parse_materials(modulus, skin_modulus, skin_poisson, material_modulus, material_poisson,
                                skin_layer_thickness, skin_layer_modulus, skin_substrate_modulus,
                                skin_substrate_poisson, skin_base)
    adhesion = parse_adhesion(work_of_adhesion, adhesion_range, adhesion_law)
    pressures = _parse_pressures(pressure, log, adhesive=adhesion is not None)
    tol_v = _parse_float(tol, "--tol")
    if not (0 < tol_v < 1):
        raise FingerpadError(f"--tol must lie in (0, 1), got {tol!r}")
    from ..contact.solver import MAX_ITER

    max_iter_v = parse_int(max_iter, "--max-iter", 1, MAX_ITER)
    if formulation not in ("auto", "primal", "dual"):
        raise FingerpadError(f"--formulation must be auto, primal or dual, got {formulation!r}")
    from ..textures import MAX_GRID

    grid_v = parse_int(grid, "--grid", 4, MAX_GRID) if grid is not None else None
    size_v = parse_size(size) if size is not None else None
    plot_at_v = parse_positive(plot_at, "pressure", name="--plot-at") if plot_at is not None else None
    if plot_at_v is not None and plot is None:
        raise FingerpadError("--plot-at needs --plot")
    critical_v = _parse_float(critical, "--critical") if critical is not None else None
    if critical_v is not None and not (0 < critical_v < 1):
        raise FingerpadError(f"--critical: the relative bracket width must lie in (0, 1), got {critical!r}")
    job = SolveJob(texture=None, materials=materials, pressures=pressures, tol=tol_v, max_iter=max_iter_v,
                   formulation=formulation, json_path=json_path, csv_path=csv_path, save_path=save, plot_path=plot,
                   plot_at=plot_at_v,
                   critical_rtol=critical_v, adhesion=adhesion)
    if adhesion is not None:
        for option, given in (("--critical", critical_v), ("--formulation", formulation if formulation != "auto" else None)):
            if given is not None:
                raise FingerpadError(f"{option} is not available with --work-of-adhesion (the adhesive solve has its "
                                     "own formulation; the pull-off pressure is reported)")
    _check_outputs(job)
    from .overrides import split_texture_options
    from .texture import TextureSpec

    if surface is not None and ctx_args:
        raise FingerpadError(f"unexpected arguments {' '.join(ctx_args)!r} (texture parameters need --texture)")
    params = dict(split_texture_options(ctx_args))
    if "grid" in params:
        raise FingerpadError("give the grid size once, as --grid")
    spec = TextureSpec(name=texture, surface=surface, params=params, size=size_v, height_unit=height_unit,
                       periodic=periodic, periodize=periodize, fill_missing=fill_missing, pixel_size=pixel_size,
                       base_quantile=None if base_quantile is None else _parse_float(base_quantile, "--base-quantile"))
    tex = spec.build(grid_v)
    if periodic is False and texture is not None:
        tex = replace(tex, periodic=False)
    job.texture_source = spec.source
    job.texture = tex
    return job

