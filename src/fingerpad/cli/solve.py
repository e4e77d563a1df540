"""``fingerpad solve``: the skin on one texture cell at one or more mean pressures."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from typing import Annotated, Any

import typer

from ..materials import DEFAULT_SKIN_MODULUS, DEFAULT_SKIN_POISSON
from .common import (
    ADHESION_HELP,
    DEVICE_HELP,
    EXIT_UNCONVERGED,
    EXTRA_ARGS,
    ProgressBar,
    check_texture_options,
    command_options,
    device_option,
    flag_pair,
    option,
    say,
    stderr_console,
    stdout_console,
    user_errors,
    warnings_to,
)

_SURFACE, _MATERIALS, _LOADS, _NUMERICS, _OUTPUT = "Surface", "Materials", "Loads", "Numerics", "Output"

_HELP = {
    "--texture": "Texture generator (see `fingerpad textures`); its parameters follow as --NAME VALUE, "
                 "e.g. --radius 50um.",
    "--surface": "Height-map file instead of a generator (.npy, text, or a SurfaceTopography format).",
    "--size": "Physical size of the --surface map, e.g. 200um or 200um,150um.",
    "--height-unit": "Unit of the heights in a --surface file (m, mm, um, nm); required for .npy and text.",
    "--fill-missing": "Replace missing points (NaN) of a --surface map by the nearest valid height.",
    "--periodic": "Periodic unit cell (default: yes for generated textures, no for files).",
    "--no-periodic": "A finite patch (zero-padded kernel), also for a generated texture.",
    "--periodize": "Mirror a --surface map into a periodic 2Lx x 2Ly cell (see docs/formats.md).",
    "--pixel-size": "Pixel size DX[,DY] of a --surface map, instead of --size (for non-square pixels).",
    "--base-quantile": "Share of the lowest pixels of a --surface map taken as the bottom of its base; the base "
                       "level, whose touching starts the transition, lies 4 noise sigmas above (default 0.01).",
    "--grid": "Grid points along x, passed to the generator (default: the generator's choice).",
    "--modulus": "Reduced modulus E* of skin and material (Eq. 3.4), e.g. 0.4MPa. Excludes the skin/material "
                 "options.",
    "--skin-modulus": f"Skin Young's modulus (default {DEFAULT_SKIN_MODULUS / 1e6:g}MPa).",
    "--skin-poisson": f"Skin Poisson ratio (default {DEFAULT_SKIN_POISSON:g}).",
    "--skin-layer-thickness": "A layered skin: thickness of its stiff outer layer (stratum corneum), e.g. 300um; "
                              "needs --skin-layer-modulus and --skin-substrate-modulus (docs/model.md 6.4).",
    "--skin-layer-modulus": "Young's modulus of the skin's outer layer, e.g. 0.4MPa (replaces --skin-modulus).",
    "--skin-substrate-modulus": "Young's modulus of the tissue under the layer, e.g. 40kPa, or 'rigid'.",
    "--skin-substrate-poisson": "Poisson ratio of the tissue under the layer (default: --skin-poisson).",
    "--skin-base": "What the layer rests on: elastic (the tissue, default), rigid or rigid-frictionless.",
    "--material-modulus": "Counter-surface Young's modulus, or 'rigid' (default rigid).",
    "--material-poisson": "Counter-surface Poisson ratio (default 0.35).",
    **ADHESION_HELP,
    "--pressure": "Mean nominal pressure over the cell; repeat it, or give a range START:STOP:COUNT or a comma "
                  "list (with --work-of-adhesion also zero and tensions, e.g. -2kPa,0Pa,5kPa).",
    "--log": "Log-spaced pressure ranges (the default).",
    "--linear": "Evenly spaced pressure ranges.",
    "--tol": "Relative residual at which a solve stops.",
    "--max-iter": "Iteration cap per solve.",
    "--formulation": "auto, primal (pressure unknowns) or dual (gap unknowns).",
    "--json": "Write results as JSON ('-' for stdout, which replaces the table).",
    "--save": "Write the fields (pressure, gap, displacement, contact, heights) to NetCDF.",
    "--plot": "Write pressure map, contact map and psi(p) to an image (.png, .svg or .pdf).",
    "--csv": "Write the per-pressure results to a CSV table (SI units in the headers).",
    "--plot-at": "Pressure whose maps --plot shows (the nearest solved one; default: the last given).",
    "--device": DEVICE_HELP,
    "--critical": "Also bracket the critical (transition) pressure, where the skin first touches the texture's "
                  "lowest level, to this relative width, e.g. 1e-3.",
}


def _opt(*decls: str, panel: str, metavar: str | None = None, **kw: Any) -> Any:
    return option(*decls, help_texts=_HELP, panel=panel, metavar=metavar, **kw)


def solve(
    ctx: typer.Context,
    texture: Annotated[str | None, _opt("--texture", "-t", panel=_SURFACE, metavar="NAME")] = None,
    surface: Annotated[str | None, _opt("--surface", panel=_SURFACE, metavar="FILE")] = None,
    size: Annotated[str | None, _opt("--size", panel=_SURFACE, metavar="LX[,LY]")] = None,
    height_unit: Annotated[str | None, _opt("--height-unit", panel=_SURFACE, metavar="UNIT")] = None,
    fill_missing: Annotated[bool, _opt("--fill-missing", panel=_SURFACE)] = False,
    periodic: Annotated[bool, _opt("--periodic", panel=_SURFACE)] = False,
    no_periodic: Annotated[bool, _opt("--no-periodic", panel=_SURFACE)] = False,
    periodize: Annotated[bool, _opt("--periodize", panel=_SURFACE)] = False,
    pixel_size: Annotated[str | None, _opt("--pixel-size", panel=_SURFACE, metavar="DX[,DY]")] = None,
    base_quantile: Annotated[str | None, _opt("--base-quantile", panel=_SURFACE, metavar="Q")] = None,
    modulus: Annotated[str | None, _opt("--modulus", panel=_MATERIALS, metavar="E*")] = None,
    skin_modulus: Annotated[str | None, _opt("--skin-modulus", panel=_MATERIALS, metavar="E")] = None,
    skin_poisson: Annotated[str | None, _opt("--skin-poisson", panel=_MATERIALS, metavar="NU")] = None,
    skin_layer_thickness: Annotated[str | None, _opt("--skin-layer-thickness", panel=_MATERIALS, metavar="T")] = None,
    skin_layer_modulus: Annotated[str | None, _opt("--skin-layer-modulus", panel=_MATERIALS, metavar="E")] = None,
    skin_substrate_modulus: Annotated[str | None, _opt("--skin-substrate-modulus", panel=_MATERIALS,
                                                       metavar="E")] = None,
    skin_substrate_poisson: Annotated[str | None, _opt("--skin-substrate-poisson", panel=_MATERIALS,
                                                       metavar="NU")] = None,
    skin_base: Annotated[str | None, _opt("--skin-base", panel=_MATERIALS,
                                          metavar="elastic|rigid|rigid-frictionless")] = None,
    material_modulus: Annotated[str | None, _opt("--material-modulus", panel=_MATERIALS, metavar="E")] = None,
    material_poisson: Annotated[str | None, _opt("--material-poisson", panel=_MATERIALS, metavar="NU")] = None,
    work_of_adhesion: Annotated[str | None, _opt("--work-of-adhesion", panel=_MATERIALS, metavar="W")] = None,
    adhesion_range: Annotated[str | None, _opt("--adhesion-range", panel=_MATERIALS, metavar="RHO")] = None,
    adhesion_law: Annotated[str | None, _opt("--adhesion-law", panel=_MATERIALS, metavar="exponential|maugis")] = None,
    pressure: Annotated[list[str] | None, _opt("--pressure", "-p", panel=_LOADS, metavar="P|START:STOP:COUNT")] = None,
    log: Annotated[bool, _opt("--log", panel=_LOADS)] = False,
    linear: Annotated[bool, _opt("--linear", panel=_LOADS)] = False,
    grid: Annotated[str | None, _opt("--grid", panel=_NUMERICS, metavar="N")] = None,
    tol: Annotated[str, _opt("--tol", panel=_NUMERICS, metavar="TOL")] = "1e-8",
    max_iter: Annotated[str, _opt("--max-iter", panel=_NUMERICS, metavar="N")] = "5000",
    formulation: Annotated[str, _opt("--formulation", panel=_NUMERICS, metavar="auto|primal|dual")] = "auto",
    json_path: Annotated[str | None, _opt("--json", panel=_OUTPUT, metavar="PATH")] = None,
    save: Annotated[str | None, _opt("--save", panel=_OUTPUT, metavar="PATH.nc")] = None,
    plot: Annotated[str | None, _opt("--plot", panel=_OUTPUT, metavar="PATH.png")] = None,
    csv_path: Annotated[str | None, _opt("--csv", panel=_OUTPUT, metavar="PATH.csv")] = None,
    plot_at: Annotated[str | None, _opt("--plot-at", panel=_OUTPUT, metavar="P")] = None,
    critical: Annotated[str | None, _opt("--critical", panel=_LOADS, metavar="RTOL")] = None,
    device: Annotated[str | None, _opt("--device", panel=_NUMERICS, metavar="cpu|cupy|torch")] = None,
) -> None:
    """Solve the skin contact on one texture cell at one or more mean pressures.

    Example: fingerpad solve --texture caps --radius 50um --height 10um --spacing 200um
    --lattice hexagonal --pressure 1kPa:100kPa:10 --log --json out.json

    Exit code 0 on success, 1 if some solve did not converge (outputs still written),
    2 on a user error (nothing written).
    """
    from ..study.overrides import split_texture_options
    from ..study.cell_job import build_solve_job

    with user_errors(), device_option(device):
        check_texture_options(split_texture_options(ctx.args), texture, command_options(ctx))
        with warnings_to(stderr_console()):
            job = build_solve_job(
                ctx_args=list(ctx.args), texture=texture, surface=surface, size=size, height_unit=height_unit,
                periodic=flag_pair(periodic, no_periodic, "--periodic", "--no-periodic"), periodize=periodize,
                pixel_size=pixel_size, base_quantile=base_quantile, fill_missing=fill_missing, grid=grid,
                modulus=modulus,
                skin_modulus=skin_modulus, skin_poisson=skin_poisson, material_modulus=material_modulus,
                material_poisson=material_poisson, pressure=pressure or [],
                log=flag_pair(log, linear, "--log", "--linear") is not False, tol=tol, max_iter=max_iter,
                formulation=formulation, json_path=json_path, save=save, plot=plot, plot_at=plot_at, csv_path=csv_path,
                critical=critical, skin_layer_thickness=skin_layer_thickness,
                skin_layer_modulus=skin_layer_modulus, skin_substrate_modulus=skin_substrate_modulus,
                skin_substrate_poisson=skin_substrate_poisson, skin_base=skin_base,
                work_of_adhesion=work_of_adhesion, adhesion_range=adhesion_range, adhesion_law=adhesion_law,
            )
        code = run_job(job)
    if code:
        raise typer.Exit(code)


def resolved(value: float, resolution: float) -> float:
    """``value``, or 0 when it lies below ``resolution`` (round-off is not shown as a value)."""
    return 0.0 if abs(value) <= resolution else value


def _print_table(results: Sequence[Any], texture: Any, tol: float = 0.0, skin: str = "") -> None:
    from rich import box
    from rich.table import Table

    from ..units import format_quantity

    table = Table(
        title=f"{texture.name}: {texture.shape[0]}x{texture.shape[1]} px, "
              f"{format_quantity(texture.size[0], 'length')} x {format_quantity(texture.size[1], 'length')}"
              f"{'' if texture.periodic else ' (finite patch)'}" + (f"\n{skin}" if skin else ""),
        box=box.SIMPLE_HEAD,
    )
    console = stdout_console(120)
    wide = console.width >= 100  # a narrow terminal gets the essential columns (the rest: --json, --csv)
    columns = (("mean p", "psi", "A_re (m²)", "max p", "mean gap", "state", "iter", "conv", "time (s)") if wide
               else ("mean p", "psi", "state", "iter", "conv"))
    for col in columns:
        table.add_column(col, justify="left" if col == "state" else "right", no_wrap=True)
    # The gap is solved to the relative tolerance of the heights' range: below that it is round-off
    # (a full contact's mean gap of -2e-23 m is 0).
    gap_resolution = tol * float(getattr(texture, "peak_to_valley", 0.0))
    for r in results:
        cells = {
            "mean p": format_quantity(r.mean_pressure, "pressure", 3),
            "psi": f"{r.contact_fraction:.4f}",
            "A_re (m²)": f"{r.real_contact_area:.3e}",
            "max p": format_quantity(r.max_pressure, "pressure", 3),
            "mean gap": format_quantity(resolved(r.mean_gap, gap_resolution), "length", 3),
            "state": str(r.contact_state),
            "iter": str(r.iterations),
            "conv": "yes" if r.converged else "NO",
            "time (s)": f"{r.seconds:.2f}",
        }
        table.add_row(*(cells[c] for c in columns))
    console.print(table)


#: Grids of at least this many points (1024^2) show the solver's iterations while they run.
_ITERATION_PROGRESS_POINTS = 1024 * 1024


def run_job(job: Any) -> int:
    """Solve, write the outputs (all or none), report. Returns the exit code (0 or 1)."""
    import json

    from ..study.cell_job import run_solve, write_solve_outputs
    from ..units import format_quantity

    err = stderr_console()
    n = len(job.pressures)
    with warnings_to(err), ProgressBar(err, "solving", total=n) as bar:
        iterations = None
        # Only on a terminal: piped, the bar is drawn once, at its end, which tells nothing the
        # results do not, and starting and stopping it cost ~0.05-0.1 s of a 1024^2 command.
        if job.texture.heights.size >= _ITERATION_PROGRESS_POINTS and err.is_terminal:
            # A 2048^2 solve takes seconds, 4096^2 tens of seconds: show that it moves.
            def iterations(shape: tuple[int, int], it: int, residual: float) -> None:
                bar.detail(f"grid {shape[0]}x{shape[1]}  iteration {it}  residual {residual:.1e} (tol {job.tol:.0e})")

        outcome = run_solve(job, progress=bar if n > 1 else None, iterations=iterations)
    write_solve_outputs(job, outcome)
    results, critical = outcome.results, outcome.critical
    if job.json_path == "-":
        sys.stdout.write(json.dumps(outcome.payload, indent=2) + "\n")
        sys.stdout.flush()
    elif job.show_table:
        from ..finger import describe_skin

        _print_table(results, job.texture, job.tol, describe_skin(job.materials.as_dict()))
        pull_off = outcome.payload.get("pull_off_pressure")
        if pull_off is not None:
            print(f"pull-off pressure: {format_quantity(pull_off, 'pressure')} (loading branch, pulled apart from "
                  f"zero load; work of separation {outcome.payload['adhesion']['work_of_separation']:.3g} J/m2)")
        if critical is not None:
            print(f"critical (transition) pressure: {format_quantity(critical.estimate, 'pressure')} "
                  f"(bracket {format_quantity(critical.lower, 'pressure')} - {format_quantity(critical.upper, 'pressure')}, "
                  f"{critical.solves} solves)")
    # a lift-off (adhesion, a tension beyond the pull-off) is a result, not a failed solve
    for r in results:
        if r.contact_state == "detached":
            say(err, f"note: at mean pressure {format_quantity(r.mean_pressure, 'pressure')} the skin lifts off "
                     "(a tension beyond the pull-off pressure: no contact holds it)")
    bad = [r for r in results if not r.converged and r.contact_state != "detached"]
    for r in bad:
        say(err, f"warning: not converged at mean pressure {format_quantity(r.mean_pressure, 'pressure')} "
                 f"(residual {r.residual:.3g} > tol {job.tol:.3g} after {r.iterations} iterations)")
    if bad:
        say(err, f"warning: {len(bad)} of {len(results)} solves did not converge (exit code 1)")
        return EXIT_UNCONVERGED
    return 0


def register(app: typer.Typer) -> None:
    app.command("solve", context_settings=EXTRA_ARGS)(solve)
