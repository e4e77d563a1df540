"""``fingerpad design-map`` (the design map of a sweep) and ``fingerpad design`` (inverse design)."""

from __future__ import annotations

from typing import Annotated

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
) -> None:
    """Draw the design map of a sweep: critical-load contours, mu/mu_ref, contact-state regions.

    Writes DIR/design_map.png and .svg, and the data behind them as design_map.nc and
    design_map.csv. Literature markers: spacing 160 um (felt smooth below), the fingerprint
    ridge wavelength 0.4-0.5 mm, ridge heights 33.5 um and 105 um (interlocking).
    """
    from .. import io as fio
    from .. import netcdf
    from ..design.designmap import map_data
    from ..design.store import open_sweep
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
            data = map_data(ds, x, y, at=at_v, select=sel, quantity=quantity)
            fig = figure_design_map(data)
        with fio.OutputFolder(out, MAP_FILES) as folder:  # errors name the user's path
            fig.savefig(folder.path("design_map.png"), format="png", dpi=120)
            fig.savefig(folder.path("design_map.svg"), format="svg")
            netcdf.to_netcdf(data.assign_attrs(fio.flatten_attrs(data.attrs)), folder.path("design_map.nc"))
            data.to_dataframe().reset_index().to_csv(folder.path("design_map.csv"), index=False)
            folder.commit()
        say(err, "wrote " + ", ".join(str(folder.final_path(n)) for n in MAP_FILES))


def design_command(
    study: Annotated[str, typer.Argument(metavar="STUDY.toml", show_default=False,
                                         help="A predict study: the texture family, its fixed parameters, material, "
                                              "finger (a [sweep] table is ignored).")],
    vary: Annotated[list[str], typer.Option("--vary", metavar="NAME=LOW:HIGH",
                                            help="A free parameter and its bounds (repeatable), e.g. "
                                                 "spacing=100um:400um; log-uniform unless LOW is 0.")],
    target: Annotated[list[str], typer.Option("--target", metavar="QUANTITY=VALUE@LOAD",
                                              help="A friction target (repeatable), e.g. mu_rel=0.5@1N; quantities: "
                                                   "mu_rel, mu, mu_ref, area_ratio.")],
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
) -> None:
    """Find textures of a family, within bounds, that give a wanted friction (inverse design).

    Every number reported for a candidate comes from a direct prediction of that texture.
    Example: fingerpad design study.toml --vary spacing=100um:400um --vary height=5um:40um
    --target mu_rel=0.5@1N --min-feature 20um
    """
    import json
    import sys

    from ..design.axes import resolve_axis
    from ..design.inverse import DesignProblem, parse_target, predict_candidate, rank_sweep, search
    from ..design.spec import DEFAULT_SWEEP_LOADS
    from ..io import check_writable, to_jsonable, write_text
    from ..study.spec import read_study_file, study_from_dict
    from ..units import parse_int, parse_positive, parse_quantity, parse_range

    with user_errors():
        err = stderr_console()
        if json_path not in (None, "-"):
            check_writable(json_path, "--json", (".json",))
        data = read_study_file(study, extra_sections=("sweep",))
        data.pop("sweep", None)
        with warnings_to(err):
            study_from_dict(data)  # the base must be a valid study
        family = data.get("texture", {}).get("name")
        axes = []
        for item in vary:
            if "=" not in item:
                raise FingerpadError(f"--vary: expected NAME=LOW:HIGH, got {item!r}")
            name, bounds = (t.strip() for t in item.split("=", 1))
            axis = resolve_axis(name, family)
            if not axis.numeric:
                raise FingerpadError(f"--vary {name}: only numeric parameters can be optimised")
            parts = bounds.split(":")
            if len(parts) != 2:
                raise FingerpadError(f"--vary {item!r}: expected LOW:HIGH bounds")
            lo, hi = (axis.parse(p, f"--vary {name}") for p in parts)
            if not hi > lo:
                raise FingerpadError(f"--vary {item!r}: the bounds must satisfy LOW < HIGH")
            axes.append(type(axis)(**{**axis.__dict__, "values": (lo, hi), "log": lo > 0}))
        if not axes:
            raise FingerpadError("give at least one --vary NAME=LOW:HIGH")
        targets = [parse_target(t) for t in target]
        problem = DesignProblem(
            base=data, axes=axes, targets=targets,
            min_critical_load=parse_positive(min_critical_load, "force", name="--min-critical-load")
            if min_critical_load is not None else None,
            min_feature=parse_positive(min_feature, "length", name="--min-feature") if min_feature is not None else None,
            max_aspect=parse_quantity(max_aspect, "none", name="--max-aspect") if max_aspect is not None else None,
            tolerance=parse_quantity(tolerance, "none", name="--tolerance"),
        )
        n_cand = parse_int(candidates, "--candidates")
        curve_loads = parse_range(DEFAULT_SWEEP_LOADS, "force", log=True)
        from .common import ProgressBar

        with warnings_to(err), ProgressBar(err, "direct predictions") as bar:
            if from_sweep is not None:
                from ..design.store import open_sweep

                ds = open_sweep(from_sweep).load()
                missing = [a.name for a in axes if a.name not in ds.variables]
                if missing:
                    raise FingerpadError(f"--from-sweep: the sweep has no axis {', '.join(missing)}")
                ranked = rank_sweep(ds, targets, problem.min_critical_load)[: max(3 * n_cand, n_cand)]
                found = []
                for i, row in enumerate(ranked):
                    params = {a.name: row["params"][a.name] for a in axes}
                    if all(a.values[0] <= params[a.name] <= a.values[1] for a in axes):
                        found.append(predict_candidate(problem, params))
                    bar(i + 1, len(ranked))
                found.sort(key=lambda c: c.objective)
            else:
                found = search(problem, max_evaluations=parse_int(evaluations, "--evaluations"), progress=bar)
            best = found[:n_cand]
            # the reported candidates, predicted once more over the exploration loads (their curves)
            best = [predict_candidate(problem, c.params, curve_loads=curve_loads) for c in best]
    best.sort(key=lambda c: c.objective)
    payload = to_jsonable({
        "targets": [str(t) for t in targets], "axes": {a.name: list(a.values) for a in axes},
        "min_critical_load": problem.min_critical_load, "min_feature": problem.min_feature,
        "max_aspect": problem.max_aspect, "tolerance": problem.tolerance,
        "source": "sweep " + str(from_sweep) if from_sweep else "optimisation (BEM in the loop)",
        "met": any(c.meets for c in best), "candidates": [c.as_dict() for c in best],
        "units": {"params": "SI (m, Pa, rad)", "critical_load": "N", "feature": "m", "curve.load": "N"},
    })
    if json_path == "-":
        sys.stdout.write(json.dumps(payload, indent=2) + "\n")
    else:
        if json_path is not None:
            write_text(json_path, json.dumps(payload, indent=2) + "\n")
        _print_candidates(best, axes, targets)
    if not best or not best[0].meets:
        closest = best[0] if best else None
        what = ", ".join(f"{k} = {v:.3g}" for k, v in closest.values.items()) if closest else "nothing valid"
        say(err, f"no texture in the box meets the target within {100 * problem.tolerance:g} %; the closest: {what}"
                 + (f" ({'; '.join(closest.violations)})" if closest and closest.violations else ""))


def _print_candidates(best: list, axes: list, targets: list) -> None:
    from rich import box
    from rich.table import Table

    table = Table(title="candidates (each a direct prediction), best first", box=box.SIMPLE_HEAD)
    for a in axes:
        table.add_column(a.label(), justify="right")
    for t in targets:
        table.add_column(str(t), justify="right")
    for col in ("F_crit (N)", "meets"):
        table.add_column(col, justify="right")
    for c in best:
        table.add_row(*[f"{a.display(c.params[a.name]):.4g}" for a in axes],
                      *[f"{c.values.get(str(t), float('nan')):.4g}" for t in targets],
                      f"{c.critical_load:.3g}", "yes" if c.meets else "no: " + "; ".join(c.violations or ["off target"]))
    stdout_console(120).print(table)


def register(app: typer.Typer) -> None:
    app.command("design-map")(design_map_command)
    app.command("design")(design_command)
