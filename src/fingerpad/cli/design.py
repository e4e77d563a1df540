"""``fingerpad design-map`` (the design map of a sweep) and ``fingerpad design`` (inverse design)."""

from __future__ import annotations

from typing import Annotated, Any

import typer

from ..errors import FingerpadError
from .common import say, stderr_console, stdout_console, user_errors, warnings_to

#: Files of a design-map folder (replaced as a whole).
MAP_FILES = ("design_map.png", "design_map.svg", "design_map.nc", "design_map.csv")


def design_map_command(
    store: Annotated[str, typer.Argument(metavar="RESULTS.zarr", help="A sweep store (fingerpad sweep).",
                                         show_default=False)],
    x: Annotated[str, typer.Option("--x", metavar="AXIS", help="Swept axis along x, e.g. spacing.")],
    y: Annotated[str, typer.Option("--y", metavar="AXIS", help="Swept axis along y, e.g. height.")],
    at: Annotated[str | None, typer.Option("--at", metavar="LOAD",
                                           help="Load of mu/mu_ref (default 1N, inside the sweep's loads).")] = None,
    select: Annotated[list[str] | None, typer.Option("--select", metavar="NAME=VALUE",
                                                     help="Value of a further axis (repeatable); axes not "
                                                          "selected give one panel per value.")] = None,
    out: Annotated[str, typer.Option("--out", "-o", metavar="DIR",
                                     help="Folder of design_map.png/.svg/.nc/.csv (replaced as a whole).")]
    = "design-map",
    quantity: Annotated[str, typer.Option("--quantity", metavar="NAME",
                                          help="Colour: mu_rel (default), mu_perp_over_par (directional sweeps), "
                                               "mu or area_ratio.")] = "mu_rel",
    population: Annotated[str | None, typer.Option(
        "--population", metavar="NAME|FILE",
        help="Draw the population the sweep ran (fingerpad sweep --population NAME|FILE, the same one): median "
             "colour, critical loads of the 10/50/90 % fingers, the region in asperity contact over the range "
             "for >= 90 % of fingers.")] = None,
    tell_apart: Annotated[str | None, typer.Option(
        "--tell-apart", metavar="REF", help="Contours of who tells each texture from REF at --at by friction: "
                                            "'flat' or a study file; with --population the 10/50/90 % fractions "
                                            "of fingers (REF predicted for the same fingers), else the study's "
                                            "finger's P = 0.75 (docs/perception.md).")] = None,
    weber_fraction: Annotated[str | None, typer.Option(
        "--weber-fraction", metavar="W", help="With --tell-apart: the fingers' Weber fraction "
                                              "(default: the sweep study's [perception] weber_fraction, "
                                              "0.11).")] = None,
) -> None:
    """Draw the design map of a sweep: critical-load contours, mu/mu_ref, contact-state regions.

    Writes DIR/design_map.png and .svg, and the data behind them as design_map.nc and
    design_map.csv. Literature markers: spacing 160 um (felt smooth below), the fingerprint
    ridge wavelength 0.4-0.5 mm, ridge heights 33.5 um and 105 um (interlocking), the spacing
    felt at 250 Hz at 50 mm/s (200 um). --tell-apart adds who tells each texture from a
    reference (docs/perception.md).
    With --population (docs/sweeps.md): the colour is the median over the fingers.
    """
    from .. import io as fio
    from .. import netcdf
    from ..encode import flatten_attrs
    from ..design.designmap import map_data
    from ..design.store import open_sweep
    from ..design.store_population import check_store_population
    from ..plotting.designmap import figure_design_map
    from ..units import parse_positive

    with user_errors():
        err = stderr_console()
        sel = {}
        for item in select or []:
            if "=" not in item:
                raise FingerpadError(f"--select: expected NAME=VALUE, got {item!r}")
            name, value = (s.strip() for s in item.split("=", 1))
            sel[name] = value
        at_v = parse_positive(at, "force", name="--at") if at is not None else None
        fio.OutputFolder.check(out, MAP_FILES)
        with warnings_to(err):
            ds = open_sweep(store).load()
            if population is not None:
                check_store_population(ds, store, population)
            tell = _tell_apart(ds, tell_apart, weber_fraction, at_v, population is not None)
            data = map_data(ds, x, y, at=at_v, select=sel, quantity=quantity, population=population is not None,
                            tell_apart=tell)
            fig = figure_design_map(data)
        with fio.OutputFolder(out, MAP_FILES) as folder:  # errors name the user's path
            fig.savefig(folder.path("design_map.png"), format="png", dpi=120)
            fig.savefig(folder.path("design_map.svg"), format="svg")
            netcdf.to_netcdf(data.assign_attrs(flatten_attrs(data.attrs)), folder.path("design_map.nc"))
            data.to_dataframe().reset_index().to_csv(folder.path("design_map.csv"), index=False)
            folder.commit()
        say(err, "wrote " + ", ".join(str(folder.final_path(n)) for n in MAP_FILES))


def _tell_apart(ds: Any, reference: str | None, weber: str | None, at: float | None,
                population: bool) -> dict[str, Any] | None:
    """``--tell-apart REF``'s settings for :func:`fingerpad.design.designmap.map_data` (REF's
    friction at the map's load predicted directly for a study file)."""
    if reference is None:
        if weber is not None:
            raise FingerpadError("--weber-fraction needs --tell-apart")
        return None
    from ..perception.compare import parse_weber

    w = parse_weber(weber)
    if reference.strip().lower() == "flat":
        return {"reference": "flat", "mu": None, "weber": w}
    from pathlib import Path

    if not Path(reference).is_file():
        raise FingerpadError(f"--tell-apart {reference!r}: neither 'flat' nor a study file")
    from ..design.designmap import default_at, member_weber_of_store, reference_friction, reference_member_friction

    at_v = at if at is not None else default_at(ds["load"].values)
    if population:  # REF for each of the sweep's fingers, once, at the map's load
        if "mu_members" in ds.variables:
            member_weber_of_store(ds, w)  # a refused W before the prediction
        mu = reference_member_friction(ds, reference, at_v) if "mu_members" in ds.variables else None
        return {"reference": Path(reference).stem, "mu": mu, "weber": w}  # map_data refuses an older store
    return {"reference": Path(reference).stem, "mu": reference_friction(ds, reference, at_v), "weber": w}


def design_command(
    study: Annotated[str, typer.Argument(metavar="STUDY.toml", show_default=False,
                                         help="A predict study: the texture family, its fixed parameters, material, "
                                              "finger (a [sweep] table is ignored).")],
    vary: Annotated[list[str], typer.Option("--vary", metavar="NAME=LOW:HIGH",
                                            help="A free parameter and its bounds (repeatable), e.g. "
                                                 "spacing=100um:400um; log-uniform unless LOW is 0.")],
    target: Annotated[list[str], typer.Option("--target", metavar="QUANTITY=VALUE@LOAD",
                                              help="A friction target (repeatable), e.g. mu_rel=0.5@1N; quantities: "
                                                   "mu_rel, mu, mu_ref, area_ratio; or a perception target "
                                                   "feels-like=REF@1N or feels-different-from=REF@1N, REF a study "
                                                   "file or 'flat' (docs/perception.md).")],
    min_critical_load: Annotated[str | None, typer.Option(
        "--min-critical-load", metavar="LOAD", help="Stay in asperity contact up to this load, e.g. 4N.")] = None,
    min_feature: Annotated[str | None, typer.Option(
        "--min-feature", metavar="LENGTH", help="Smallest lateral feature the process makes, e.g. 20um.")] = None,
    max_aspect: Annotated[str | None, typer.Option(
        "--max-aspect", metavar="RATIO", help="Largest height / lateral feature the process makes, e.g. 1.")] = None,
    from_sweep: Annotated[str | None, typer.Option(
        "--from-sweep", metavar="RESULTS.zarr", help="Take the candidates from a sweep (then check each by a direct "
                                                     "prediction) instead of optimising.")] = None,
    candidates: Annotated[str, typer.Option("--candidates", metavar="N", help="Candidates to report.")] = "5",
    evaluations: Annotated[str, typer.Option("--evaluations", metavar="N",
                                             help="Direct predictions the optimisation may make.")] = "60",
    tolerance: Annotated[str, typer.Option("--tolerance", metavar="REL",
                                           help="Relative deviation within which a target is met.")] = "0.05",
    json_path: Annotated[str | None, typer.Option("--json", metavar="PATH|-",
                                                  help="Write the candidates with their curves as JSON.")] = None,
    population: Annotated[str | None, typer.Option(
        "--population", metavar="NAME|FILE", help="Design for a population of fingers: a preset (adults) or a TOML "
                                                  "file with a [population] table (docs/population.md); needs "
                                                  "--coverage or --quantile, which without it use the study "
                                                  "file's [population] table.")] = None,
    coverage: Annotated[str | None, typer.Option(
        "--coverage", metavar="C", help="With --population: at least this fraction of the fingers, in (0, 1], meets "
                                        "every target within --tolerance, e.g. 0.9.")] = None,
    quantile: Annotated[str | None, typer.Option(
        "--quantile", metavar="Q", help="With --population: this quantile of the fingers, in [0, 1], meets the "
                                        "targets, e.g. 0.5 (the median finger).")] = None,
    weber_fraction: Annotated[str | None, typer.Option(
        "--weber-fraction", metavar="W", help="With a perception target: the person's Weber fraction W, for every "
                                              "finger (default: the study's [perception] weber_fraction, 0.11, or "
                                              "each member's own where the population draws it).")] = None,
) -> None:
    """Find textures of a family, within bounds, that give a wanted friction (inverse design).

    Every number reported for a candidate comes from a direct prediction of that texture (with
    --population, a direct prediction of every finger of the population on it); candidates
    closer than the optimiser's tolerance are one design and listed once.
    Example: fingerpad design examples/study.toml --vary spacing=100um:400um --vary height=5um:40um
    --target mu_rel=0.5@1N --min-feature 20um --population adults --coverage 0.9
    """
    import json
    import sys

    from ..design.inverse_design import design_textures
    from ..io import check_writable, write_text
    from .common import ProgressBar

    with user_errors():
        err = stderr_console()
        if json_path not in (None, "-"):
            check_writable(json_path, "--json", (".json",))
        with warnings_to(err), ProgressBar(err, "direct predictions") as bar:
            result = design_textures(study, vary, target, min_critical_load=min_critical_load,
                                     min_feature=min_feature, max_aspect=max_aspect, tolerance=tolerance,
                                     from_sweep=from_sweep, candidates=candidates, evaluations=evaluations,
                                     progress=bar, population=population, coverage=coverage, quantile=quantile,
                                     weber=weber_fraction)
            bar.finish()  # the search may stop inside its --evaluations budget
    if json_path == "-":
        sys.stdout.write(json.dumps(result.document(), indent=2) + "\n")
    else:
        if json_path is not None:
            write_text(json_path, json.dumps(result.document(), indent=2) + "\n")
        if result.goal is None:
            _print_candidates(result.candidates, result.problem.axes, result.problem.targets)
        else:
            _print_population_candidates(result)
    shortfall = result.shortfall()
    if shortfall:
        say(err, shortfall)


def _print_candidates(best: list, axes: list, targets: list) -> None:
    """The candidates of a plain design: each target's value (P, the probability of telling the
    texture from REF in a forced choice, for a perception target), the critical load, a verdict."""
    from rich import box
    from rich.table import Table

    from ..design.perception_targets import is_perception

    table = Table(title="candidates (each a direct prediction), best first", box=box.SIMPLE_HEAD)
    for a in axes:
        table.add_column(a.label(), justify="right")
    for t in targets:
        table.add_column(str(t), justify="right")
    for col in ("F_crit (N)", "meets"):
        table.add_column(col, justify="right")
    for c in best:
        table.add_row(*[f"{a.display(c.params[a.name]):.4g}" for a in axes],
                      *[("P " if is_perception(t) else "") + f"{c.values.get(str(t), float('nan')):.4g}"
                        for t in targets],
                      f"{c.critical_load:.3g}", "yes" if c.meets else "no: " + "; ".join(c.violations or ["off target"]))
    stdout_console(120).print(table)


def _print_population_candidates(result: Any) -> None:
    """The candidates of a design for a population: per target the members' median and 5-95 %
    band (or the quantile asked for), the coverage, the critical load, whether it meets."""
    from rich import box
    from rich.table import Table

    goal, problem = result.goal, result.problem
    q = goal.quantile
    level = f"{q:g}" if q is not None else "0.5"
    title = (f"candidates for {goal.describe()} (each a direct population prediction), best first; "
             f"per target the {'median' if q is None else f'{q:g} quantile'} [5-95 %]")
    table = Table(title=title, box=box.SIMPLE_HEAD)
    for a in problem.axes:
        table.add_column(a.label(), justify="right")
    for t in problem.targets:
        table.add_column(str(t), justify="right")
    crit_level = f"{1 - goal.coverage:g}" if goal.coverage is not None else level
    for col in ("coverage", f"F_crit q{crit_level} (N)", "meets"):
        table.add_column(col, justify="right")
    for c in result.candidates:
        pop = c.population
        if not pop:
            table.add_row(*[f"{a.display(c.params[a.name]):.4g}" for a in problem.axes],
                          *["-" for _ in problem.targets], "-", "-", "no: " + (c.reason or "no prediction"))
            continue
        cells = []
        for t in problem.targets:
            if str(t) in pop.get("perception", {}):  # the fraction that tells it from REF
                cells.append(f"{100 * pop['perception'][str(t)]['fraction_telling_apart']:.3g} % tell apart")
                continue
            qs = pop["quantiles"][str(t)]
            cells.append(f"{qs[level]:.3g} [{qs['0.05']:.3g}-{qs['0.95']:.3g}]")
        verdict = "yes" if c.meets else "no: " + "; ".join(c.violations or ["off target"])
        table.add_row(*[f"{a.display(c.params[a.name]):.4g}" for a in problem.axes], *cells,
                      f"{100 * pop['coverage']:.3g} %", f"{c.critical_load:.3g}", verdict)
    stdout_console(120).print(table)


def register(app: typer.Typer) -> None:
    app.command("design-map")(design_map_command)
    app.command("design")(design_command)
