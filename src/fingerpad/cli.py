"""The ``fingerpad`` command line.

Commands
--------
``fingerpad solve``
    Solve the skin/texture contact on one unit cell at one or more mean pressures.
``fingerpad textures``
    List the texture generators and their parameters.
``fingerpad predict [STUDY.toml]``
    The main job: contact areas, contact zones and friction of a finger on a texture against
    load (BEM unit cell and/or per-asperity Hertz), written to ``--out`` as ``predict.json``,
    ``predict.nc``, ``areas.png``, ``friction.png`` and ``zones.png``.
``fingerpad run-default``
    ``predict`` on the default study (hot-embossed PE foil with spherical caps, default finger,
    0.1-4 N), plus ``ridge_models.png`` (the target of ``make run``).
``fingerpad finger-models``
    The ridge-area models compared in ``ridge_models.png``.

Every quantity accepts plain SI numbers or unit suffixes (``50um``, ``0.3MPa``, ``20kPa``).

Exit codes
----------
0
    Success.
1
    Every solve ran and all outputs were written, but at least one solve did not reach its
    tolerance (a warning names it; ``"converged": false`` in the JSON).
2
    A user error (bad option value, unknown unit, unreadable file, ...): one line
    ``error: <message>`` on stderr, nothing written.
"""

from __future__ import annotations

import contextlib
import inspect
import json
import math
import os
import sys
import warnings
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Annotated, Any

import typer

from . import __version__
from .errors import FingerpadError
from .study import DEFAULT_GRID, DEFAULT_STUDY
from .inputs import (
    GRID_NAMES,
    describe_exception,
    generator_params,
    generators,
    make_generated_texture,
    one_line,
    param_kind,
    parse_int,
    parse_size,
    read_surface_file,
    split_extra_options,
)
from .materials import DEFAULT_SKIN_MODULUS, DEFAULT_SKIN_POISSON, check_modulus, check_poisson, reduced_modulus
from .units import format_quantity, parse_positive, parse_quantity, parse_range

EXIT_UNCONVERGED = 1
EXIT_USER_ERROR = 2

app = typer.Typer(
    name="fingerpad",
    help="Finger-pad contact on micro-textured surfaces (SI units; unit suffixes such as 50um, 0.3MPa accepted).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_show_locals=False,
)


# =============================================================================================
# Error and warning reporting
# =============================================================================================


@contextlib.contextmanager
def user_errors() -> Iterator[None]:
    """Turn user errors into ``error: <message>`` on one stderr line and exit code 2."""
    try:
        yield
    except (FingerpadError, OSError) as exc:
        sys.stderr.write(f"error: {one_line(describe_exception(exc))}\n")
        sys.stderr.flush()
        raise typer.Exit(EXIT_USER_ERROR) from None


def _stderr_console():
    from rich.console import Console

    return Console(file=sys.stderr, soft_wrap=True, highlight=False)


@contextlib.contextmanager
def _warnings_to(console: Any) -> Iterator[None]:
    """Show Python warnings as single ``warning: ...`` lines on ``console`` (stderr)."""
    seen: set[str] = set()

    def show(message, category, filename, lineno, file=None, line=None):  # noqa: ANN001
        text = f"warning: {one_line(str(message))}"
        if text not in seen:
            seen.add(text)
            console.print(text, markup=False, highlight=False, soft_wrap=True)

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.filterwarnings("ignore", category=DeprecationWarning)
        warnings.filterwarnings("ignore", category=PendingDeprecationWarning)
        # SurfaceTopography's MPI layer announces its serial fallback on import: not for users.
        warnings.filterwarnings("ignore", message=".*mpi4py")
        warnings.showwarning = show
        yield


# =============================================================================================
# Parsing helpers (all values arrive as text so that every mistake is a one-line FingerpadError)
# =============================================================================================


def _parse_float(text: str, name: str) -> float:
    return parse_quantity(text, "none", name=name)


def _parse_pressures(texts: Sequence[str], log: bool) -> list[float]:
    pressures: list[float] = []
    for text in texts:
        for value in parse_range(text, "pressure", name="--pressure", log=log):
            if not (math.isfinite(value) and value > 0):
                raise FingerpadError(f"--pressure: must be positive, got {text!r}")
            pressures.append(value)
    if not pressures:
        raise FingerpadError("give at least one --pressure (e.g. --pressure 20kPa or --pressure 1kPa:100kPa:10 --log)")
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

    def as_dict(self) -> dict[str, Any]:
        return {
            "reduced_modulus": self.modulus,
            "skin_modulus": self.skin_modulus,
            "skin_poisson": self.skin_poisson,
            "material_modulus": self.material_modulus,
            "material_poisson": self.material_poisson,
            "material_rigid": self.skin_modulus is not None and self.material_modulus is None,
        }


def parse_materials(
    modulus: str | None,
    skin_modulus: str | None,
    skin_poisson: str | None,
    material_modulus: str | None,
    material_poisson: str | None,
) -> MaterialsSpec:
    """Either ``--modulus`` (reduced E*) or the skin/material constants (Eq. 3.4), never both."""
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
        return MaterialsSpec(modulus=e)
    es = DEFAULT_SKIN_MODULUS if skin_modulus is None else parse_quantity(skin_modulus, "pressure", name="--skin-modulus")
    check_modulus(es, "--skin-modulus")
    nus = DEFAULT_SKIN_POISSON if skin_poisson is None else _parse_float(skin_poisson, "--skin-poisson")
    check_poisson(nus, "--skin-poisson")
    em: float | None = None
    num: float | None = None
    if material_modulus is not None and material_modulus.strip().lower() not in ("rigid", "inf", "infinity"):
        em = parse_quantity(material_modulus, "pressure", name="--material-modulus")
        check_modulus(em, "--material-modulus")
        num = 0.35 if material_poisson is None else _parse_float(material_poisson, "--material-poisson")
        check_poisson(num, "--material-poisson")
    elif material_poisson is not None:
        raise FingerpadError("--material-poisson needs --material-modulus (the default material is rigid)")
    e_star = reduced_modulus(es, nus, em, num if num is not None else 0.35)
    return MaterialsSpec(modulus=e_star, skin_modulus=es, skin_poisson=nus, material_modulus=em, material_poisson=num)



# =============================================================================================
# Solving and writing
# =============================================================================================


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
    save_path: str | None = None
    plot_path: str | None = None
    plot_at: float | None = None  # mean pressure whose maps are plotted (nearest solved); None: last
    show_table: bool = True
    critical_rtol: float | None = None  # bracket the transition pressure to this relative width

    def inputs(self) -> dict[str, Any]:
        from . import textures

        tex = self.texture
        describe = getattr(textures, "describe", None)
        return {
            "texture": {
                "name": tex.name,
                "description": describe(tex) if describe is not None else tex.name,
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
            }
        )
        return attrs


def _check_outputs(job: SolveJob) -> None:
    from .io import check_writable

    seen: dict[str, str] = {}
    for opt, path in (("--json", job.json_path), ("--save", job.save_path), ("--plot", job.plot_path)):
        if path is None or (opt == "--json" and path == "-"):
            continue
        key = os.path.abspath(path)
        if key in seen:
            raise FingerpadError(f"{opt} and {seen[key]} name the same file {path!r}")
        seen[key] = opt
        check_writable(path, opt)


def _solve_curve(job: SolveJob, solver: Any, err_console: Any):
    from .unitcell import load_curve

    n = len(job.pressures)
    if n == 1:
        return load_curve(solver, job.pressures)
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(
        TextColumn("solving"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(), console=err_console,
    ) as bar:
        task = bar.add_task("solve", total=n)

        def progress(i: int, total: int) -> None:
            bar.update(task, completed=min(i, total), total=total)

        curve = load_curve(solver, job.pressures, progress=progress)
        bar.update(task, completed=n)
    return curve


def _results_json(job: SolveJob, results: Sequence[Any], critical: Any = None) -> dict[str, Any]:
    from .io import to_jsonable

    payload: dict[str, Any] = {
        "inputs": job.inputs(),
        "converged": all(bool(r.converged) for r in results),
        "results": [r.summary() for r in results],
    }
    if critical is not None:
        payload["critical_pressure"] = {
            "lower": critical.lower, "upper": critical.upper, "estimate": critical.estimate,
            "relative_width": critical.relative_width, "solves": critical.solves,
            "definition": "lowest mean pressure (Pa) at which the skin touches the texture's lowest level",
        }
    return to_jsonable(payload)


def _print_table(results: Sequence[Any], texture: Any) -> None:
    from rich import box
    from rich.console import Console
    from rich.table import Table

    table = Table(
        title=f"{texture.name}: {texture.shape[0]}x{texture.shape[1]} px, "
              f"{format_quantity(texture.size[0], 'length')} x {format_quantity(texture.size[1], 'length')}"
              f"{'' if texture.periodic else ' (finite patch)'}",
        box=box.SIMPLE_HEAD,
    )
    columns = ("mean p", "psi", "A_re (m²)", "max p", "mean gap", "state", "iter", "conv", "time (s)")
    for col in columns:
        table.add_column(col, justify="left" if col == "state" else "right", no_wrap=True)
    for r in results:
        table.add_row(
            format_quantity(r.mean_pressure, "pressure", 3),
            f"{r.contact_fraction:.4f}",
            f"{r.real_contact_area:.3e}",
            format_quantity(r.max_pressure, "pressure", 3),
            format_quantity(r.mean_gap, "length", 3),
            str(r.contact_state),
            str(r.iterations),
            "yes" if r.converged else "NO",
            f"{r.seconds:.2f}",
        )
    console = Console(file=sys.stdout)
    if not console.is_terminal:  # piped or captured: do not squeeze the table into 80 columns
        console = Console(file=sys.stdout, width=max(console.width, 120))
    console.print(table)


def run_job(job: SolveJob) -> int:
    """Solve, write the outputs (all or none), report. Returns the exit code (0 or 1)."""
    from . import io as fio

    err = _stderr_console()
    _check_outputs(job)
    with _warnings_to(err):
        # Unconverged solves are reported below, once per pressure, with the exit code.
        warnings.filterwarnings("ignore", message="contact solve did not converge", category=RuntimeWarning)
        from .halfspace import HalfSpaceSolver

        solver = HalfSpaceSolver(job.texture, job.materials.modulus, tol=job.tol, max_iter=job.max_iter,
                                 formulation=job.formulation)
        curve = _solve_curve(job, solver, err)
        critical = None
        if job.critical_rtol is not None:
            from .unitcell import critical_pressure

            critical = critical_pressure(solver, rtol=job.critical_rtol)
    results = list(curve.results)
    payload = _results_json(job, results, critical)
    staging = fio.Staging()
    try:
        if job.json_path is not None and job.json_path != "-":
            text = json.dumps(payload, indent=2) + "\n"
            staging.stage(job.json_path, lambda tmp: fio.write_text(tmp, text))
        if job.save_path is not None:
            attrs = job.netcdf_attrs()
            if len(results) == 1:
                staging.stage(job.save_path, lambda tmp: fio.save_result(results[0], tmp, attrs))
            else:
                staging.stage(job.save_path, lambda tmp: fio.save_load_curve(curve, tmp, attrs))
        if job.plot_path is not None:
            from .plotting import plot_solution

            index = -1
            if job.plot_at is not None:
                index = min(range(len(results)), key=lambda i: abs(math.log(results[i].mean_pressure / job.plot_at)))
            staging.stage(job.plot_path, lambda tmp: plot_solution(results, tmp, index=index))
        staging.commit()
    finally:
        staging.discard()
    if job.json_path == "-":
        sys.stdout.write(json.dumps(payload, indent=2) + "\n")
        sys.stdout.flush()
    elif job.show_table:
        _print_table(results, job.texture)
        if critical is not None:
            print(f"critical (transition) pressure: {format_quantity(critical.estimate, 'pressure')} "
                  f"(bracket {format_quantity(critical.lower, 'pressure')} - {format_quantity(critical.upper, 'pressure')}, "
                  f"{critical.solves} solves)")
    bad = [r for r in results if not r.converged]
    for r in bad:
        err.print(
            f"warning: not converged at mean pressure {format_quantity(r.mean_pressure, 'pressure')} "
            f"(residual {r.residual:.3g} > tol {job.tol:.3g} after {r.iterations} iterations)",
            markup=False, highlight=False, soft_wrap=True,
        )
    if bad:
        err.print(f"warning: {len(bad)} of {len(results)} solves did not converge (exit code 1)",
                  markup=False, highlight=False, soft_wrap=True)
        return EXIT_UNCONVERGED
    return 0


# =============================================================================================
# Commands
# =============================================================================================

_EXTRA = {"allow_extra_args": True, "ignore_unknown_options": True}

_SURFACE, _MATERIALS, _LOADS, _NUMERICS, _OUTPUT = "Surface", "Materials", "Loads", "Numerics", "Output"

#: Help text of the `solve` options, by option name.
_HELP = {
    "--texture": "Texture generator (see `fingerpad textures`); its parameters follow as --NAME VALUE, "
                 "e.g. --radius 50um.",
    "--surface": "Height-map file instead of a generator (.npy, text, or a SurfaceTopography format).",
    "--size": "Physical size of the --surface map, e.g. 200um or 200um,150um.",
    "--height-unit": "Unit of the heights in a --surface file (m, mm, um, nm); required for .npy and text.",
    "--fill-missing": "Replace missing points (NaN) of a --surface map by the nearest valid height.",
    "--periodic": "Periodic unit cell (default: yes for generated textures, no for files).",
    "--grid": "Grid points along x, passed to the generator (default: the generator's choice).",
    "--modulus": "Reduced modulus E* of skin and material (Eq. 3.4), e.g. 0.4MPa. Excludes the skin/material "
                 "options.",
    "--skin-modulus": f"Skin Young's modulus (default {DEFAULT_SKIN_MODULUS / 1e6:g}MPa).",
    "--skin-poisson": f"Skin Poisson ratio (default {DEFAULT_SKIN_POISSON:g}).",
    "--material-modulus": "Counter-surface Young's modulus, or 'rigid' (default rigid).",
    "--material-poisson": "Counter-surface Poisson ratio (default 0.35).",
    "--pressure": "Mean nominal pressure over the cell; repeat it, or give a range START:STOP:COUNT.",
    "--log": "Log-spaced pressure ranges.",
    "--tol": "Relative residual at which a solve stops.",
    "--max-iter": "Iteration cap per solve.",
    "--formulation": "auto, primal (pressure unknowns) or dual (gap unknowns).",
    "--json": "Write results as JSON ('-' for stdout, which replaces the table).",
    "--save": "Write the fields (pressure, gap, displacement, contact, heights) to NetCDF.",
    "--plot": "Write pressure map, contact map and psi(p) to a PNG.",
    "--plot-at": "Pressure whose maps --plot shows (the nearest solved one; default: the last given).",
    "--critical": "Also bracket the critical (transition) pressure, where the skin first touches the texture's "
                  "lowest level, to this relative width, e.g. 1e-3.",
}


def _opt(*decls: str, panel: str, metavar: str | None = None, **kw: Any) -> Any:
    return typer.Option(*decls, help=_HELP[decls[0].split("/")[0]], rich_help_panel=panel, metavar=metavar, **kw)


@app.command(context_settings=_EXTRA)
def solve(
    ctx: typer.Context,
    texture: Annotated[str | None, _opt("--texture", "-t", panel=_SURFACE, metavar="NAME")] = None,
    surface: Annotated[str | None, _opt("--surface", panel=_SURFACE, metavar="FILE")] = None,
    size: Annotated[str | None, _opt("--size", panel=_SURFACE, metavar="LX[,LY]")] = None,
    height_unit: Annotated[str | None, _opt("--height-unit", panel=_SURFACE, metavar="UNIT")] = None,
    fill_missing: Annotated[bool, _opt("--fill-missing", panel=_SURFACE)] = False,
    periodic: Annotated[bool | None, _opt("--periodic/--no-periodic", panel=_SURFACE, show_default=False)] = None,
    modulus: Annotated[str | None, _opt("--modulus", panel=_MATERIALS, metavar="E*")] = None,
    skin_modulus: Annotated[str | None, _opt("--skin-modulus", panel=_MATERIALS, metavar="E")] = None,
    skin_poisson: Annotated[str | None, _opt("--skin-poisson", panel=_MATERIALS, metavar="NU")] = None,
    material_modulus: Annotated[str | None, _opt("--material-modulus", panel=_MATERIALS, metavar="E")] = None,
    material_poisson: Annotated[str | None, _opt("--material-poisson", panel=_MATERIALS, metavar="NU")] = None,
    pressure: Annotated[list[str] | None, _opt("--pressure", "-p", panel=_LOADS, metavar="P|START:STOP:COUNT")] = None,
    log: Annotated[bool, _opt("--log", panel=_LOADS)] = False,
    grid: Annotated[str | None, _opt("--grid", panel=_NUMERICS, metavar="N")] = None,
    tol: Annotated[str, _opt("--tol", panel=_NUMERICS, metavar="TOL")] = "1e-8",
    max_iter: Annotated[str, _opt("--max-iter", panel=_NUMERICS, metavar="N")] = "5000",
    formulation: Annotated[str, _opt("--formulation", panel=_NUMERICS, metavar="auto|primal|dual")] = "auto",
    json_path: Annotated[str | None, _opt("--json", panel=_OUTPUT, metavar="PATH")] = None,
    save: Annotated[str | None, _opt("--save", panel=_OUTPUT, metavar="PATH.nc")] = None,
    plot: Annotated[str | None, _opt("--plot", panel=_OUTPUT, metavar="PATH.png")] = None,
    plot_at: Annotated[str | None, _opt("--plot-at", panel=_OUTPUT, metavar="P")] = None,
    critical: Annotated[str | None, _opt("--critical", panel=_LOADS, metavar="RTOL")] = None,
) -> None:
    """Solve the skin contact on one texture cell at one or more mean pressures.

    Example: fingerpad solve --texture caps --radius 50um --height 10um --spacing 200um
    --lattice hexagonal --pressure 1kPa:100kPa:10 --log --json out.json

    Exit code 0 on success, 1 if some solve did not converge (outputs still written),
    2 on a user error (nothing written).
    """
    with user_errors():
        job = build_job(
            ctx_args=list(ctx.args), texture=texture, surface=surface, size=size, height_unit=height_unit,
            periodic=periodic, fill_missing=fill_missing, grid=grid, modulus=modulus, skin_modulus=skin_modulus,
            skin_poisson=skin_poisson, material_modulus=material_modulus, material_poisson=material_poisson, pressure=pressure or [],
            log=log, tol=tol, max_iter=max_iter, formulation=formulation, json_path=json_path, save=save,
            plot=plot, plot_at=plot_at, critical=critical,
        )
        code = run_job(job)
    if code:
        raise typer.Exit(code)


def build_job(
    *, ctx_args: Sequence[str], texture: str | None, surface: str | None, size: str | None,
    height_unit: str | None, periodic: bool | None, fill_missing: bool = False, grid: str | None,
    modulus: str | None, skin_modulus: str | None, skin_poisson: str | None, material_modulus: str | None,
    material_poisson: str | None, pressure: Sequence[str], log: bool, tol: str, max_iter: str,
    formulation: str, json_path: str | None, save: str | None, plot: str | None,
    plot_at: str | None = None, critical: str | None = None,
) -> SolveJob:
    """Validate every option of ``fingerpad solve`` (cheap checks first) and build the texture."""
    if (texture is None) == (surface is None):
        raise FingerpadError("give exactly one of --texture NAME or --surface FILE")
    materials = parse_materials(modulus, skin_modulus, skin_poisson, material_modulus, material_poisson)
    pressures = _parse_pressures(pressure, log)
    tol_v = _parse_float(tol, "--tol")
    if not (0 < tol_v < 1):
        raise FingerpadError(f"--tol must lie in (0, 1), got {tol!r}")
    max_iter_v = parse_int(max_iter, "--max-iter")
    if formulation not in ("auto", "primal", "dual"):
        raise FingerpadError(f"--formulation must be auto, primal or dual, got {formulation!r}")
    grid_v = parse_int(grid, "--grid") if grid is not None else None
    size_v = parse_size(size) if size is not None else None
    plot_at_v = parse_positive(plot_at, "pressure", name="--plot-at") if plot_at is not None else None
    if plot_at_v is not None and plot is None:
        raise FingerpadError("--plot-at needs --plot")
    critical_v = _parse_float(critical, "--critical") if critical is not None else None
    if critical_v is not None and not (0 < critical_v < 1):
        raise FingerpadError(f"--critical: the relative bracket width must lie in (0, 1), got {critical!r}")
    job = SolveJob(texture=None, materials=materials, pressures=pressures, tol=tol_v, max_iter=max_iter_v,
                   formulation=formulation, json_path=json_path, save_path=save, plot_path=plot, plot_at=plot_at_v,
                   critical_rtol=critical_v)
    _check_outputs(job)
    err = _stderr_console()
    with _warnings_to(err):
        if texture is not None:
            if height_unit is not None:
                raise FingerpadError("--height-unit applies to --surface files only")
            if fill_missing:
                raise FingerpadError("--fill-missing applies to --surface files only")
            tex = make_generated_texture(texture, ctx_args, grid_v, size_v)
            if periodic is False:
                tex = replace(tex, periodic=False)
            job.texture_source = {"source": "generator", "file": None}
        else:
            if ctx_args:
                raise FingerpadError(
                    f"unexpected arguments {' '.join(ctx_args)!r} (texture parameters need --texture)"
                )
            if grid_v is not None:
                raise FingerpadError("--grid applies to generated textures; a --surface file keeps its own grid")
            tex = read_surface_file(surface, size_v, height_unit, bool(periodic) if periodic is not None else False,
                                    fill_missing)
            job.texture_source = {"source": "file", "file": os.path.abspath(surface)}
    job.texture = tex
    return job


@app.command("textures")
def textures_command() -> None:
    """List the texture generators and their parameters (give them to `solve` as --NAME VALUE)."""
    from rich.console import Console
    from rich.table import Table

    with user_errors():
        gens = generators()
    from rich.markup import escape

    table = Table(title="texture generators: fingerpad solve --texture NAME --PARAM VALUE ...", show_lines=True)
    table.add_column("texture", no_wrap=True)
    table.add_column("parameters (default)", no_wrap=True)
    table.add_column("description")
    metavars = {"length": "LENGTH", "angle": "ANGLE", "int": "INT", "str": "TEXT", "bool": "BOOL",
                "none": "NUMBER", "pressure": "PRESSURE", "lengths": "LENGTH[,LENGTH]"}
    for name, fn in gens.items():
        lines = []
        for pname, p in generator_params(fn).items():
            if pname in GRID_NAMES:
                opt, meta = "--grid", "N"
            else:
                opt, meta = "--" + pname.replace("_", "-"), metavars.get(param_kind(pname, p), "VALUE")
                if pname == "size":
                    meta = "LX[,LY]"
            default = "required" if p.default is inspect.Parameter.empty else (
                "auto" if p.default is None else repr(p.default))
            lines.append(f"{opt} {meta} ({default})")
        doc = inspect.getdoc(fn) or ""
        summary = doc.splitlines()[0].replace("``", "") if doc else ""
        table.add_row(name, escape("\n".join(lines)), escape(summary))
    console = Console(file=sys.stdout)
    if not console.is_terminal:
        console = Console(file=sys.stdout, width=max(console.width, 120))
    console.print(table)
    console.print(
        "Lengths take unit suffixes (50um, 0.2mm) or metres; angles deg or rad; see the generator docstrings.",
        markup=False, highlight=False,
    )


# ---------------------------------------------------------------------------------------------
# predict: areas, contact zones and friction against load (the package's main job), and
# run-default (the target of `make run`): predict on a documented default study.
# ---------------------------------------------------------------------------------------------

_STUDY, _FINGER = "Study", "Finger"

_PREDICT_HELP = {
    "--texture": _HELP["--texture"],
    "--surface": _HELP["--surface"],
    "--size": _HELP["--size"],
    "--height-unit": _HELP["--height-unit"],
    "--fill-missing": _HELP["--fill-missing"],
    "--periodic": "Take the texture as one period of a periodic surface (generated textures: yes).",
    "--periodize": "Mirror a --surface map into a periodic cell (needed by the BEM unless the map is one period).",
    "--material-modulus": "Counter-surface Young's modulus, or 'rigid' (default rigid), e.g. 0.5GPa.",
    "--material-poisson": "Counter-surface Poisson ratio (default 0.35).",
    "--skin-modulus": "Micro-scale skin modulus E_s (overrides the finger's skin_modulus), e.g. 0.3MPa.",
    "--skin-poisson": "Skin Poisson ratio (overrides the finger's skin_poisson).",
    "--finger": "Finger preset (default 'default'); see fingerpad.finger.FINGER_PRESETS.",
    "--finger-param": "Finger override NAME=VALUE (radius, modulus, beta, tau0, alpha, skin_modulus, "
                      "skin_poisson); repeatable, e.g. --finger-param radius=8mm.",
    "--loads": "Normal loads: START:STOP:COUNT or one load; repeatable (default 0.1N:4N:40, log).",
    "--log": "Log-spaced load ranges (--linear: evenly spaced).",
    "--model": "Unit-cell model: bem (numerical), hertz (per-asperity Hertz, spherical caps only) or both.",
    "--grid": "Grid points along x of the generated unit cell (default: the generator's choice).",
    "--tol": "Relative residual at which a unit-cell solve stops (default 1e-8).",
    "--max-iter": "Iteration cap per unit-cell solve (default 5000).",
    "--cache": "Folder of cached unit-cell curves (default $FINGERPAD_CACHE or ~/.cache/fingerpad).",
    "--zones-at": "Load of the zone map zones.png (default: the largest load).",
    "--out": "Output directory for predict.json, predict.nc, areas.png, friction.png, zones.png.",
    "--json": "Also write the JSON to PATH ('-' for stdout, which replaces the table).",
}


def _popt(*decls: str, panel: str, metavar: str | None = None, **kw: Any) -> Any:
    return typer.Option(*decls, help=_PREDICT_HELP[decls[0].split("/")[0]], rich_help_panel=panel,
                        metavar=metavar, **kw)


def _split_study_args(args: Sequence[str]) -> tuple[str | None, list[str]]:
    """Separate the optional study file (a bare word) from the texture's ``--NAME VALUE`` pairs."""
    positional: list[str] = []
    rest: list[str] = []
    args = list(args)
    i = 0
    while i < len(args):
        tok = args[i]
        if tok.startswith("--") and len(tok) > 2:
            if "=" in tok:
                rest.append(tok)
                i += 1
            elif i + 1 < len(args) and not args[i + 1].startswith("--"):
                rest += [tok, args[i + 1]]
                i += 2
            else:
                rest.append(tok)  # split_extra_options reports the missing value
                i += 1
        else:
            positional.append(tok)
            i += 1
    if len(positional) > 1:
        raise FingerpadError(f"unexpected argument(s) {' '.join(positional[1:])!r}: give at most one study file")
    return (positional[0] if positional else None), rest


def build_study(
    *, ctx_args: Sequence[str], texture: str | None = None, surface: str | None = None, size: str | None = None,
    height_unit: str | None = None, fill_missing: bool = False, periodic: bool | None = None,
    periodize: bool = False, material_modulus: str | None = None, material_poisson: str | None = None,
    skin_modulus: str | None = None, skin_poisson: str | None = None, finger: str | None = None,
    finger_param: Sequence[str] = (), loads: Sequence[str] = (), log: bool | None = None,
    model: str | None = None, grid: str | None = None, tol: str | None = None, max_iter: str | None = None,
    cache: str | None = None, zones_at: str | None = None, base: Mapping[str, Mapping[str, Any]] | None = None,
):
    """A :class:`fingerpad.study.Study` from an optional study file (first bare argument in
    ``ctx_args``, or ``base``) with the flags laid over it; checked and with its texture built."""
    from .finger import _FIELD_DIMENSIONS
    from .study import MODELS, read_study_file, study_from_dict

    study_file, extra = _split_study_args(ctx_args)
    if study_file is not None and base is not None:
        raise FingerpadError(f"unexpected argument {study_file!r}")
    data: dict[str, dict[str, Any]] = {k: dict(v) for k, v in (base or {}).items()}
    if study_file is not None:
        data = read_study_file(study_file)

    # texture: --texture/--surface replace the file's section, the other options update it
    if texture is not None and surface is not None:
        raise FingerpadError("give either --texture NAME or --surface FILE, not both")
    tex = data.get("texture", {})
    if texture is not None:
        tex = {"name": texture}
    elif surface is not None:
        tex = {"surface": surface}
    pairs = split_extra_options(extra)
    if pairs and not tex:
        raise FingerpadError(f"unexpected option --{pairs[0][0].replace('_', '-')} "
                             "(texture parameters follow --texture NAME)")
    for key, value in pairs:
        if key in ("name", "surface"):
            raise FingerpadError(f"use --texture or --surface, not --{key}")
        tex[key] = value
    for key, value in (("size", size), ("height_unit", height_unit), ("periodic", periodic)):
        if value is not None:
            tex[key] = value
    if fill_missing:
        tex["fill_missing"] = True
    if periodize:
        tex["periodize"] = True
    if tex:
        data["texture"] = tex

    # material (the flags are parsed here so that messages name them)
    if material_modulus is not None or material_poisson is not None:
        mat = data.setdefault("material", {})
        if material_modulus is not None:
            if material_modulus.strip().lower() in ("rigid", "inf", "infinity"):
                mat["modulus"] = "rigid"
                mat.pop("poisson", None)
            else:
                mat["modulus"] = check_modulus(
                    parse_quantity(material_modulus, "pressure", name="--material-modulus"), "--material-modulus")
        if material_poisson is not None:
            if mat.get("modulus") in (None, "rigid"):
                raise FingerpadError("--material-poisson needs --material-modulus (the default material is rigid)")
            mat["poisson"] = check_poisson(_parse_float(material_poisson, "--material-poisson"), "--material-poisson")

    # finger
    fin = data.setdefault("finger", {})
    if finger is not None:
        fin["preset"] = finger
    for item in finger_param:
        if "=" not in item:
            raise FingerpadError(f"--finger-param: expected NAME=VALUE, got {item!r}")
        name, value = (s.strip() for s in item.split("=", 1))
        name = name.replace("-", "_")
        if name not in _FIELD_DIMENSIONS:
            raise FingerpadError(f"--finger-param: unknown finger parameter {name!r} "
                                 f"(known: {', '.join(_FIELD_DIMENSIONS)})")
        fin[name] = value
    if skin_modulus is not None:
        fin["skin_modulus"] = check_modulus(parse_quantity(skin_modulus, "pressure", name="--skin-modulus"),
                                            "--skin-modulus")
    if skin_poisson is not None:
        fin["skin_poisson"] = check_poisson(_parse_float(skin_poisson, "--skin-poisson"), "--skin-poisson")

    # loads
    lsec = data.setdefault("loads", {})
    if loads:
        use_log = bool(log) if log is not None else False
        values: list[float] = []
        for text in loads:
            for value in parse_range(text, "force", name="--loads", log=use_log):
                if not (math.isfinite(value) and value > 0):
                    raise FingerpadError(f"--loads: loads must be positive, got {text!r}")
                values.append(value)
        lsec.pop("range", None)
        lsec["values"] = values
        lsec["log"] = use_log
    elif log is not None:
        lsec["log"] = log
    if zones_at is not None:
        lsec["zones_at"] = parse_positive(zones_at, "force", name="--zones-at")

    # model and numerics
    msec = data.setdefault("model", {})
    if model is not None:
        if model.strip().lower() not in MODELS:
            raise FingerpadError(f"--model must be one of {', '.join(MODELS)}, got {model!r}")
        msec["kind"] = model.strip().lower()
    if grid is not None:
        msec["grid"] = parse_int(grid, "--grid", minimum=4)
        data.get("texture", {}).pop("grid", None)
    if tol is not None:
        tol_v = _parse_float(tol, "--tol")
        if not 0 < tol_v < 1:
            raise FingerpadError(f"--tol must lie in (0, 1), got {tol!r}")
        msec["tol"] = tol_v
    if max_iter is not None:
        msec["max_iter"] = parse_int(max_iter, "--max-iter")
    if cache is not None:
        msec["cache"] = cache
    study = study_from_dict(data)
    study.check()
    return study


class _CellProgress:
    """Rich progress bar on stderr, started on the first unit-cell solve (none when cached)."""

    def __init__(self, console: Any) -> None:
        self.console = console
        self.bar: Any = None
        self.task: Any = None

    def __call__(self, i: int, n: int) -> None:
        if self.bar is None:
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

            self.bar = Progress(TextColumn("unit cell ψ(p)"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                                console=self.console)
            self.bar.start()
            self.task = self.bar.add_task("cell", total=n)
        self.bar.update(self.task, completed=min(i, n), total=n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
            self.bar = None


def _zone_text(row: Mapping[str, Any]) -> str:
    parts = []
    for key, label in (("full_contact_radius", "full"), ("transition_radius", "trans"), ("ridge_radius", "asp")):
        r = row.get(key)
        if r:
            parts.append(f"{label}<{r * 1e3:.2f}")
    return " ".join(parts) + " mm" if parts else "-"


def _fmt(value: Any, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def _print_prediction(payload: Mapping[str, Any]) -> None:
    from rich import box
    from rich.console import Console
    from rich.table import Table

    tex = payload["inputs"]["texture"]
    both = bool(payload["results"]) and "hertz" in payload["results"][0]
    shown = "bem (the Hertz curves are in predict.json)" if both else payload["model"]
    table = Table(title=f"{tex['description']}\nmodel: {shown}", box=box.SIMPLE_HEAD)
    for col in ("load (N)", "A_g (mm²)", "A_fr (mm²)", "A_re (mm²)", "A_re/A_fr", "zones (centre→edge)",
                "μ", "μ_ref", "μ_norm"):
        table.add_column(col, justify="left" if col.startswith("zones") else "right", no_wrap=True)
    for row in payload["results"]:
        table.add_row(
            f"{row['load']:.3g}", f"{row['gross_area'] * 1e6:.4g}", f"{row['ridge_area'] * 1e6:.4g}",
            f"{row['real_area'] * 1e6:.4g}", f"{row['area_ratio']:.4f}", _zone_text(row),
            f"{row['mu']:.4f}", _fmt(row["mu_ref"], ".4f"), _fmt(row["mu_normalised"], ".4f"),
        )
    console = Console(file=sys.stdout, highlight=False)
    if not console.is_terminal:
        console = Console(file=sys.stdout, width=max(console.width, 130), highlight=False)
    console.print(table)
    crit = payload["critical_load"]
    texts = []
    for model, label in (("bem", "BEM"), ("hertz", "Hertz (Eq. 3.6)")):
        if model in crit and (crit[model] is not None or model == payload["model"]):
            texts.append(f"{label} {crit[model]:.4g} N" if crit[model] is not None else f"{label} none in 1e-6..1e3 N")
    if texts:
        console.print("critical load (pad centre reaches the transition): " + ", ".join(texts), markup=False)
    full = payload.get("full_contact_load", {}).get("bem")
    if payload["model"] == "bem":
        console.print("full contact at the pad centre from: "
                      + (f"{full:.4g} N" if full is not None else "never (below 1e3 N)"), markup=False)


def run_prediction(study: Any, out: str, json_path: str | None) -> int:
    """Run ``study``, write its outputs into ``out`` (all or none), report. Returns the exit code."""
    from .io import check_writable, to_jsonable
    from .study import OUTPUT_FILES, prediction_json, run_study, write_outputs

    out_dir = Path(out)
    if out_dir.exists() and not out_dir.is_dir():
        raise FingerpadError(f"--out {out!r} exists and is not a directory")
    if json_path is not None and json_path != "-":
        check_writable(json_path, "--json")
        if Path(json_path).resolve().parent == out_dir.resolve() and Path(json_path).name in OUTPUT_FILES:
            raise FingerpadError(f"--json {json_path!r} would overwrite an output of --out")
    err = _stderr_console()
    bar = _CellProgress(err)
    with _warnings_to(err):
        warnings.filterwarnings("ignore", message="contact solve did not converge", category=RuntimeWarning)
        try:
            pred = run_study(study, progress=bar)
        finally:
            bar.close()
        paths = write_outputs(pred, out_dir)
    payload = to_jsonable(prediction_json(pred))
    text = json.dumps(payload, indent=2) + "\n"
    if json_path == "-":
        sys.stdout.write(text)
        sys.stdout.flush()
    else:
        if json_path is not None:
            from .io import write_text

            write_text(json_path, text)
        _print_prediction(payload)
    for note in pred.notes:
        err.print(f"note: {note}", markup=False, highlight=False, soft_wrap=True)
    cell = payload["cell"]
    err.print(
        f"unit cell: {cell['model']}, {cell['solves']} solves ({'cached' if cell['cached'] else 'computed'}) in "
        f"{pred.timings['cell']:.2f} s; coupling {pred.timings['coupling']:.3f} s",
        markup=False, highlight=False, soft_wrap=True,
    )
    err.print("wrote " + ", ".join(str(p) for p in paths), markup=False, highlight=False, soft_wrap=True)
    if pred.unconverged:
        err.print(f"warning: {pred.unconverged} unit-cell solve(s) did not converge (exit code 1)",
                  markup=False, highlight=False, soft_wrap=True)
        return EXIT_UNCONVERGED
    return 0


@app.command(context_settings=_EXTRA)
def predict(
    ctx: typer.Context,
    texture: Annotated[str | None, _popt("--texture", "-t", panel=_SURFACE, metavar="NAME")] = None,
    surface: Annotated[str | None, _popt("--surface", panel=_SURFACE, metavar="FILE")] = None,
    size: Annotated[str | None, _popt("--size", panel=_SURFACE, metavar="LX[,LY]")] = None,
    height_unit: Annotated[str | None, _popt("--height-unit", panel=_SURFACE, metavar="UNIT")] = None,
    fill_missing: Annotated[bool, _popt("--fill-missing", panel=_SURFACE)] = False,
    periodic: Annotated[bool | None, _popt("--periodic/--no-periodic", panel=_SURFACE, show_default=False)] = None,
    periodize: Annotated[bool, _popt("--periodize", panel=_SURFACE)] = False,
    material_modulus: Annotated[str | None, _popt("--material-modulus", panel=_MATERIALS, metavar="E")] = None,
    material_poisson: Annotated[str | None, _popt("--material-poisson", panel=_MATERIALS, metavar="NU")] = None,
    skin_modulus: Annotated[str | None, _popt("--skin-modulus", panel=_MATERIALS, metavar="E")] = None,
    skin_poisson: Annotated[str | None, _popt("--skin-poisson", panel=_MATERIALS, metavar="NU")] = None,
    finger: Annotated[str | None, _popt("--finger", panel=_FINGER, metavar="PRESET")] = None,
    finger_param: Annotated[list[str] | None, _popt("--finger-param", panel=_FINGER, metavar="NAME=VALUE")] = None,
    loads: Annotated[list[str] | None, _popt("--loads", "-F", panel=_LOADS, metavar="START:STOP:COUNT")] = None,
    log: Annotated[bool | None, _popt("--log/--linear", panel=_LOADS, show_default=False)] = None,
    zones_at: Annotated[str | None, _popt("--zones-at", panel=_LOADS, metavar="LOAD")] = None,
    model: Annotated[str | None, _popt("--model", panel=_NUMERICS, metavar="bem|hertz|both")] = None,
    grid: Annotated[str | None, _popt("--grid", panel=_NUMERICS, metavar="N")] = None,
    tol: Annotated[str | None, _popt("--tol", panel=_NUMERICS, metavar="TOL")] = None,
    max_iter: Annotated[str | None, _popt("--max-iter", panel=_NUMERICS, metavar="N")] = None,
    cache: Annotated[str | None, _popt("--cache", panel=_NUMERICS, metavar="DIR")] = None,
    out: Annotated[str, _popt("--out", "-o", panel=_OUTPUT, metavar="DIR")] = "out",
    json_path: Annotated[str | None, _popt("--json", panel=_OUTPUT, metavar="PATH|-")] = None,
) -> None:
    """Predict contact areas, contact zones and friction of a finger on a texture against load.

    Usage: fingerpad predict [STUDY.toml] [OPTIONS]; the options override the study file
    (see examples/study.toml). Example: fingerpad predict --texture caps --radius 100um
    --height 20um --spacing 175um --lattice hexagonal --material-modulus 0.5GPa
    --material-poisson 0.4 --loads 0.1N:4N:40 --log --model both --out out

    Writes DIR/predict.json, predict.nc, areas.png, friction.png and zones.png (all or none).
    Exit code 0 on success, 1 if a unit-cell solve did not converge (outputs still written),
    2 on a user error (nothing written).
    """
    with user_errors():
        err = _stderr_console()
        with _warnings_to(err):
            study = build_study(
                ctx_args=list(ctx.args), texture=texture, surface=surface, size=size, height_unit=height_unit,
                fill_missing=fill_missing, periodic=periodic, periodize=periodize,
                material_modulus=material_modulus, material_poisson=material_poisson,
                skin_modulus=skin_modulus, skin_poisson=skin_poisson, finger=finger,
                finger_param=finger_param or [], loads=loads or [], log=log, model=model, grid=grid, tol=tol,
                max_iter=max_iter, cache=cache, zones_at=zones_at,
            )
        code = run_prediction(study, out, json_path)
    if code:
        raise typer.Exit(code)




@app.command("run-default")
def run_default(
    out: Annotated[str, typer.Option("--out", metavar="DIR", help="Output directory (created if missing).")] = "out",
    grid: Annotated[str, typer.Option("--grid", metavar="N", help="Grid points along x of the unit cell.")] = DEFAULT_GRID,
    loads: Annotated[
        str, typer.Option("--loads", metavar="START:STOP:COUNT", help="Log-spaced load range.")
    ] = "0.1N:4N:40",
    cache: Annotated[str | None, typer.Option("--cache", metavar="DIR", help=_PREDICT_HELP["--cache"])] = None,
) -> None:
    """Predict the default study into DIR: predict.json, .nc, areas/friction/zones.png, ridge_models.png.

    The study: a hot-embossed polyethylene foil (E = 0.5 GPa, nu = 0.4) with hexagonal spherical caps
    R = 100um, h = 20um, spacing 175um; the default finger; loads 0.1-4 N (40, log); BEM and Hertz.
    """
    with user_errors():
        err = _stderr_console()
        with _warnings_to(err):
            study = build_study(ctx_args=[], base=DEFAULT_STUDY, loads=[loads], log=True, grid=grid, cache=cache)
        code = run_prediction(study, out, None)
        from .finger import ridge_models_figure

        path = ridge_models_figure(Path(out) / "ridge_models.png")
        err.print(f"wrote {path}", markup=False, highlight=False, soft_wrap=True)
    if code:
        raise typer.Exit(code)


@app.command("finger-models")
def finger_models(
    out: Annotated[str, typer.Option("--out", metavar="DIR", help="Output directory (created if missing).")] = "out",
    loads: Annotated[
        str, typer.Option("--loads", metavar="START:STOP:COUNT", help="Log-spaced load range.")
    ] = "0.1N:4N:30",
) -> None:
    """Compare the ridge-area models (idea of the thesis Fig. 2.4) in DIR/ridge_models.png."""
    with user_errors():
        values = parse_range(loads, "force", name="--loads", log=True)
        if min(values) <= 0:
            raise FingerpadError("--loads: loads must be positive")
        out_dir = Path(out)
        if out_dir.exists() and not out_dir.is_dir():
            raise FingerpadError(f"--out {out!r} exists and is not a directory")
        out_dir.mkdir(parents=True, exist_ok=True)
        from .finger import ridge_models_figure

        path = ridge_models_figure(out_dir / "ridge_models.png", values)
        sys.stderr.write(f"wrote {path}\n")


def _version_callback(value: bool) -> None:
    if value:
        sys.stdout.write(f"fingerpad {__version__}\n")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: Annotated[
        bool, typer.Option("--version", help="Show the version and exit.", is_eager=True, callback=_version_callback)
    ] = False,
) -> None:
    """Finger-pad contact on micro-textured surfaces (SI units; unit suffixes such as 50um, 0.3MPa)."""


def main() -> None:
    """Console-script entry point (``fingerpad``)."""
    app()


# =============================================================================================
# Commands from other modules. `fingerpad.cli_measurements.register(app)` adds the measurement
# commands when that module exists. The lead adds `predict` (and the final `run-default`) here.
# =============================================================================================


def _register_optional_commands() -> None:
    import importlib

    try:
        cli_measurements = importlib.import_module(f"{__package__}.cli_measurements")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__package__}.cli_measurements":
            raise
        return
    register = getattr(cli_measurements, "register", None)
    if callable(register):
        register(app)


_register_optional_commands()
