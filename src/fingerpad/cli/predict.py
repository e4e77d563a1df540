"""``fingerpad predict`` (the main job) and ``fingerpad run-default`` (the target of ``make run``).

The command parses its flags, lays them over the study file (:mod:`fingerpad.study.overrides`),
lets :func:`fingerpad.study.spec.study_from_dict` check everything once, runs the study and prints.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping, Sequence
from typing import Annotated, Any

import typer

from ..errors import FingerpadError
from ..units import format_percent as _percent  # one rule for per-cent estimates
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
    say_wrapped,
    stderr_console,
    stdout_console,
    user_errors,
    warnings_to,
)
from ._sensitivity import sensitivity_asked
from ._perception import perception_options
from .solve import _HELP

_SURFACE, _MATERIALS, _FINGER, _LOADS, _NUMERICS, _OUTPUT = "Surface", "Materials", "Finger", "Loads", "Numerics", "Output"

_STUDY, _FINGER, _PERCEPTION = "Study", "Finger", "Perception"

_PREDICT_HELP = {
    "--texture": _HELP["--texture"],
    "--surface": _HELP["--surface"],
    "--size": _HELP["--size"],
    "--height-unit": _HELP["--height-unit"],
    "--fill-missing": _HELP["--fill-missing"],
    "--periodic": "Take the texture as one period of a periodic surface (generated textures: yes).",
    "--no-periodic": "Take a --surface map as a finite patch.",
    "--pixel-size": "Pixel size DX[,DY] of a --surface map, instead of --size (for non-square pixels).",
    "--base-quantile": "Share of the lowest pixels of a --surface map taken as the bottom of its base; the base "
                       "level, whose touching starts the transition, lies 4 noise sigmas above (default 0.01).",
    "--periodize": "Mirror a --surface map into a periodic cell (needed by the BEM unless the map is one period).",
    "--material-modulus": "Counter-surface Young's modulus, or 'rigid' (default rigid), e.g. 0.5GPa.",
    "--material-poisson": "Counter-surface Poisson ratio (default 0.35).",
    "--skin-modulus": "Micro-scale skin modulus E_s (overrides the finger's skin_modulus), e.g. 0.3MPa.",
    "--skin-poisson": "Skin Poisson ratio (overrides the finger's skin_poisson).",
    "--skin-layer-thickness": "A layered skin (docs/model.md 6.4): thickness of its stiff outer layer (stratum "
                              "corneum, 0.2-0.35 mm), with a unit, e.g. 300um; needs --skin-layer-modulus and "
                              "--skin-substrate-modulus (or --skin-base rigid).",
    "--skin-layer-modulus": "Young's modulus E_1 of the skin's outer layer, e.g. 0.4MPa (it is the skin's E_s).",
    "--skin-substrate-modulus": "Young's modulus E_2 of the tissue under the layer, e.g. 40kPa, "
                                "or 'rigid' (as --skin-base rigid).",
    "--skin-substrate-poisson": "Poisson ratio of the tissue under the layer (default: the skin's).",
    "--skin-base": "What the layer rests on: elastic (the tissue, default), rigid or rigid-frictionless.",
    **ADHESION_HELP,
    "--finger": "Finger preset (default 'default'); see fingerpad.finger.FINGER_PRESETS.",
    "--finger-param": "Finger override NAME=VALUE (radius, modulus, beta, tau0, alpha, skin_modulus, "
                      "skin_poisson, skin_layer_thickness, ...: see `fingerpad fingers`; ridge_fraction: "
                      "the constant-fraction ridge model's A_fr/A_g); repeatable, e.g. --finger-param radius=8mm.",
    "--loads": "Normal loads: START:STOP:COUNT, one load or a comma list of either; repeatable (default 0.1N:4N:40, log).",
    "--log": "Log-spaced load ranges (the default, also when a study file says nothing).",
    "--linear": "Evenly spaced load ranges.",
    "--model": "Unit-cell model: bem (numerical), hertz (per-asperity Hertz, spherical caps only) or both.",
    "--grid": "Grid points along x of the generated unit cell (default: doubled from the generator's choice "
              "until the estimated error of A_re/A_fr is below --accuracy, 2 %).",
    "--direction": "Sliding direction, degrees from the texture's x axis: directional friction of compliant "
                   "ellipsoids or ridges from the deflection model (docs/deflection.md); also reports "
                   "mu_perpendicular/mu_parallel.",
    "--accuracy": "Target of the estimated relative error of A_re/A_fr when the grid is automatic (default 0.02).",
    "--tol": ("Relative residual at which a unit-cell solve stops (default 1e-8; the curve's nodes stop "
              "at the larger of it and 1e-7, the state brackets at it)."),
    "--max-iter": "Iteration cap per unit-cell solve (default 5000).",
    "--device": DEVICE_HELP,
    "--cache": "Folder of cached unit-cell curves (default $FINGERPAD_CACHE or ~/.cache/fingerpad).",
    "--zones-at": "Load of the zone map zones.png (default: the largest load).",
    "--out": "Output folder for predict.json, predict.nc, areas.png, friction.png, zones.png; replaced as a "
             "whole (default 'out', or none with --json -).",
    "--json": "Also write the JSON to PATH ('-' for stdout, which replaces the table).",
    "--csv": "Also write the per-load table to PATH.csv (SI units in the headers).",
    "--population": "Predict for a population of fingers: a preset (adults), a TOML file with a [population] "
                    "table, or a folder written by fingerpad analyse (one member per participant, its fitted "
                    "E_s; docs/population.md); a study file's own [population] table is used without it.",
    "--quantiles": "Quantiles of the population bands, comma-separated (default 0.05,0.25,0.5,0.75,0.95).",
    "--sensitivity": "With a population: Sobol indices (first-order and total) of mu/mu_ref and the critical load "
                     "per parameter; N (d + 2) more fingers (docs/population.md).",
    "--sensitivity-samples": "Base samples N of the sensitivity design (default 256; a power of two).",
    "--perception": "Add what a person feels (docs/perception.md): who tells the texture from the flat reference "
                    "by friction, its vibration frequencies and channels along x and y (or --direction), an "
                    "amplitude estimate and the roughness regime; JSON 'perception', perception.png.",
    "--speed": "With --perception: stroke speed(s), one speed or LOW:HIGH, e.g. 20mm/s:100mm/s (the default).",
    "--weber-fraction": "With --perception: the person's Weber fraction W, for every finger (the study file's "
                        "[perception] weber_fraction; default 0.11, or each member's own where the population "
                        "draws it).",
}


def _popt(*decls: str, panel: str, metavar: str | None = None, **kw: Any) -> Any:
    return option(*decls, help_texts=_PREDICT_HELP, panel=panel, metavar=metavar, **kw)


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
    *, ctx_args: Sequence[str], flags: Mapping[str, Any] | None = None, finger_param: Sequence[str] = (),
    base: Mapping[str, Mapping[str, Any]] | None = None, options: Sequence[str] = (),
    extra_sections: dict[str, Any] | None = None,
) -> Any:
    """A checked :class:`fingerpad.study.Study` from an optional study file (the first bare
    argument in ``ctx_args``, or ``base``) with the flags (see
    :data:`fingerpad.study.overrides.FLAGS`) laid over it; its texture is built. The study file's
    sections named by the keys of ``extra_sections`` (``population``) are taken out and stored
    there (``None`` when absent)."""
    from ..study.overrides import apply_flags, split_texture_options
    from ..study.spec import read_study_file, study_from_dict

    study_file, extra = _split_study_args(ctx_args)
    if study_file is not None and base is not None:
        raise FingerpadError(f"unexpected argument {study_file!r}")
    data: dict[str, dict[str, Any]] = {k: dict(v) for k, v in (base or {}).items()}
    if study_file is not None:
        data = read_study_file(study_file, extra_sections=tuple(extra_sections or ()))
    for section in extra_sections or {}:
        extra_sections[section] = data.pop(section, None)
    pairs = split_texture_options(extra)
    if options:
        texture = (flags or {}).get("--texture") or data.get("texture", {}).get("name")
        check_texture_options(pairs, texture if isinstance(texture, str) else None, list(options))
    merged, labels = apply_flags(data, dict(flags or {}), texture_options=pairs, finger_params=finger_param)
    study = study_from_dict(merged, labels)
    study.check()
    return study


def _zone_text(row: Mapping[str, Any]) -> str:
    parts = []
    for key, label in (("full_contact_radius", "full"), ("transition_radius", "trans"), ("ridge_radius", "asp")):
        r = row.get(key)
        if r:
            parts.append(f"{label}<{r * 1e3:.2f}")
    return " ".join(parts) + " mm" if parts else "-"


def _fmt(value: Any, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def _adhesion_text(adhesion: Mapping[str, Any]) -> str:
    """The adhesion's lines under the table: pull-off, works of adhesion, the threshold load."""
    threshold = adhesion.get("threshold_load")
    bound = adhesion.get("threshold_load_bound", "exact")
    where = "(not computed)" if threshold is None else f"{threshold:.3g} N" if bound == "exact" else \
        f"{threshold:.3g} N or more" if bound == "at least" else f"{threshold:.3g} N or less"
    p_off = adhesion.get("pull_off_pressure")
    # a flat cell's is unbounded (-inf, null in the JSON): it never lets go under load control
    cell = f"{p_off:.4g} Pa" if isinstance(p_off, (int, float)) and math.isfinite(p_off) else "none (a flat cell)"
    return (f"adhesion ({adhesion['law']}, w {adhesion['work_of_adhesion']:.3g} J/m2): pull-off force "
            f"{adhesion['pull_off_force'] * 1e3:.3g} mN{_plus_minus(adhesion.get('pull_off_force_error'))} "
            f"(pad w {adhesion['pad_work_of_adhesion']:.3g} J/m2, cell pull-off {cell}); adhesion changes A_re "
            f"by more than 10 % below {where}")


def _print_prediction(payload: Mapping[str, Any]) -> None:
    """The per-load table (fitted to the terminal: fewer columns below 110) and the state loads."""
    from rich import box
    from rich.table import Table

    tex = payload["inputs"]["texture"]
    both = bool(payload["results"]) and "hertz" in payload["results"][0]
    shown = "bem (the Hertz curves are in the JSON)" if both else payload["model"]
    console = stdout_console(130)
    wide = console.width >= 110
    from ..finger import describe_skin

    skin = describe_skin(payload["inputs"]["finger"])
    table = Table(title=f"{tex['description']}\nmodel: {shown}" + (f"; {skin}" if skin else ""), box=box.SIMPLE_HEAD)
    columns = (["load (N)", "A_g (mm²)", "A_fr (mm²)", "A_re (mm²)", "A_re/A_fr", "zones (centre→edge)",
                "μ", "μ_ref", "μ/μ_ref"] if wide else ["load (N)", "A_re/A_fr", "centre", "μ", "μ/μ_ref"])
    for col in columns:
        table.add_column(col, justify="left" if col.startswith(("zones", "centre")) else "right", no_wrap=True)
    for row in payload["results"]:
        if wide:
            table.add_row(
                f"{row['load']:.3g}", f"{row['gross_area'] * 1e6:.4g}", f"{row['ridge_area'] * 1e6:.4g}",
                f"{row['real_area'] * 1e6:.4g}", f"{row['area_ratio']:.4f}", _zone_text(row),
                f"{row['mu']:.4f}", _fmt(row["mu_ref"], ".4f"), _fmt(row["mu_normalised"], ".4f"),
            )
        else:
            table.add_row(f"{row['load']:.3g}", f"{row['area_ratio']:.4f}", str(row["contact_state"]),
                          f"{row['mu']:.3f}", _fmt(row["mu_normalised"], ".3f"))
    console.print(table)
    if not wide:
        say(console, "(a narrow terminal: every column is in the JSON, the NetCDF and --csv)")
    crit, full = payload["critical_load"], payload.get("full_contact_load", {}).get("bem")
    brackets = payload.get("state_brackets") or {}
    texts = []
    for model, label in (("bem", "BEM"), ("hertz", "Hertz (Eq. 3.6)")):
        if model not in crit or (crit[model] is None and model != payload["model"]):
            continue
        if crit[model] is not None:
            error = (payload.get("critical_load_error") or {}).get(model)
            texts.append(f"{label} {crit[model]:.4g} N" + _plus_minus(error))
        elif model == "bem" and "transition" in brackets:
            texts.append(f"{label}: the cell never reaches its transition up to 10 E*")
        else:
            texts.append(f"{label}: none")
    if texts:
        say_wrapped(console, "critical load (pad centre reaches the transition): " + ", ".join(texts))
    if "full" in brackets:
        p_lo, p_hi = brackets["full"]["pressure"]
        if full is not None:
            st = brackets["full"]
            grids = ""
            if st.get("grid") and st.get("coarse_grid"):
                grids = f", grid {'x'.join(map(str, st['grid']))} against {'x'.join(map(str, st['coarse_grid']))}"
            pressure = f"cell pressure {p_lo / 1e3:.4g}-{p_hi / 1e3:.4g} kPa{_plus_minus(st.get('pressure_error'))}"
            if st.get("own_pressure") is not None:
                # pulled in by adhesion: extrapolated to a vanishing pixel (docs/model.md 6.6)
                reported = payload["cell"]["full_contact_pressure"]
                pressure = (f"cell pressure {reported / 1e3:.4g} kPa{_plus_minus(st.get('pressure_error'))} "
                            f"extrapolated to a vanishing pixel, the grid's own {p_lo / 1e3:.4g}-{p_hi / 1e3:.4g} kPa")
            say_wrapped(console, f"full contact at the pad centre (at most 1 % open) from: {full:.4g} N"
                         f"{_plus_minus((payload.get('full_contact_load_error') or {}).get('bem'))} "
                         f"({pressure}{grids})")
        else:
            say(console, f"full contact at the pad centre: not reached up to {p_lo / 1e3:.4g} kPa "
                         f"(the last node below 10 E*)")
    adhesion = payload.get("adhesion")
    if adhesion:
        say_wrapped(console, _adhesion_text(adhesion))
    directional = payload.get("directional")
    if directional and payload["results"] and "mu_perpendicular_over_parallel" in payload["results"][0]:
        ratios = [r["mu_perpendicular_over_parallel"] for r in payload["results"]]
        states = [r["contact_state"] for r in payload["results"]]
        say(console, f"directional friction: sliding at {directional['direction']:.4g}°; mu_perpendicular/mu_parallel "
                     f"{min(ratios):.3g}-{max(ratios):.3g} over {payload['results'][0]['load']:.3g}-"
                     f"{payload['results'][-1]['load']:.3g} N (centre: {states[0]} to {states[-1]}); "
                     f"per load in the JSON, the NetCDF and friction.png")
    res = (payload.get("cell") or {}).get("resolution")
    if res and res.get("area_ratio_error") is not None:
        grid = "x".join(str(g) for g in res["grid"])
        chosen = str(res["chosen"]).split(" (")[0]  # "automatic", "given", "the map's own"
        err = res["area_ratio_error"]
        # beyond 100 % the number says only that the grid does not resolve it (as _plus_minus)
        say(console, f"unit cell {grid} px ({chosen}): estimated error of A_re/A_fr {_percent(err)} %")


def _plus_minus(error: Any) -> str:
    """`` ± X %`` for a relative error estimate (nothing when there is none)."""
    if error is None or not isinstance(error, (int, float)) or error != error:
        return ""
    return f" ± {_percent(error)} %"


def _band(q: Mapping[str, Any], name: str, i: int) -> str:
    """``median [lowest-highest quantile]`` at load ``i``."""
    levels = sorted(q[name], key=float)
    if len(levels) == 1:  # one quantile asked for (--quantiles 0.9): its value, not a dash
        return f"{q[name][levels[0]][i]:.2f}"
    mid = q[name].get("0.5")
    lo, hi = q[name][levels[0]], q[name][levels[-1]]
    text = "-" if mid is None else f"{mid[i]:.2f}"
    return text + (f" [{lo[i]:.2f}-{hi[i]:.2f}]" if len(levels) > 1 else "")


def _print_population(payload: Mapping[str, Any]) -> None:
    """The population's table: per load the median and the 5-95 % band (80 columns)."""
    from rich import box
    from rich.table import Table

    pop = payload["population"]
    q = pop["quantiles"]
    console = stdout_console(80)
    levels = sorted(q["mu"], key=float)
    band = f"median [{100 * float(levels[0]):g}-{100 * float(levels[-1]):g} %]" if len(levels) > 1 else \
        "median" if float(levels[0]) == 0.5 else f"{100 * float(levels[0]):g} % quantile"
    table = Table(title=f"population {pop['name']!r}: {pop['size']} fingers ({pop['model']}); {band}",
                  box=box.SIMPLE_HEAD, pad_edge=False)
    for col in ("load N", "A_re/A_fr", "μ", "μ/μ_ref", "P(asp)"):
        table.add_column(col, justify="right", no_wrap=True)
    for i, load in enumerate(pop["loads"]):
        table.add_row(f"{load:.3g}", _band(q, "area_ratio", i), _band(q, "mu", i), _band(q, "mu_normalised", i),
                      f"{pop['state_probability']['asperity'][i]:.2f}")
    console.print(table)
    for name, label in (("critical_load", "critical load"), ("full_contact_load", "full-contact load")):
        values = [q[name][k] for k in levels]
        if any(v is not None for v in values):
            shown = " ".join("inf" if v is None else format(v, ".3g") for v in values)
            say(console, f"{label} (N), {'/'.join(format(100 * float(k), 'g') for k in levels)} %: {shown}")
    # the study's own finger beside the bands: where it stands among them (issue 30)
    own = [f"{label} {value:.3g} N" for label, value in (
        ("critical load", (payload.get("critical_load") or {}).get(pop["model"])),
        ("full-contact load", (payload.get("full_contact_load") or {}).get(pop["model"]))) if value is not None]
    if own:
        say(console, "the study's own finger: " + ", ".join(own))
    adhesion = pop.get("adhesion")
    if adhesion is not None:
        force = " ".join(format(1e3 * adhesion["pull_off_force"][k], ".3g") for k in levels)
        say(console, f"pull-off force (mN), {'/'.join(format(100 * float(k), 'g') for k in levels)} %: {force}")
        say(console, f"adhesion: {adhesion['cells']} adhesive cells ({adhesion['family_solves']} solves), each member "
                     "interpolated; estimated error of A_re (and μ) median "
                     f"{_percent(adhesion['interpolation_error_median'])} %, "
                     f"max {_percent(adhesion['interpolation_error_max'])} %; "
                     f"of the pull-off force max {_percent(adhesion['pull_off_force_error_max'])} %")
    say(console, "(each member and its curves: population.members, member_results in the JSON)")


def run_prediction(study: Any, out: str | None, json_path: str | None, csv_path: str | None = None,
                   extra: Mapping[str, Any] | None = None, population: Any = None,
                   perception: Mapping[str, Any] | None = None) -> int:
    """Run ``study``, write its outputs (all or none), report. Returns the exit code.

    ``out``: the output folder (replaced as a whole), or ``None`` for none; ``extra``: more
    figures for it (name -> callable returning a Figure); ``population``: a
    :class:`~fingerpad.population.rules.PopulationStudy` of ``study`` to predict as well;
    ``perception``: the single-texture verdicts against the flat reference
    (:func:`fingerpad.perception.compare.against_flat`'s ``speeds`` and ``directions``; the
    Weber fraction is the study's, or each member's own).
    """
    import warnings

    from ..encode import json_text, to_jsonable
    from ..study.outputs import FOLDER_FILES, check_outputs, prediction_json, write_outputs
    from ..study.run import run_study

    pop_files: tuple[str, ...] = ()
    if population is not None:
        from ..population.outputs import population_files

        pop_files = population_files(population.sensitivity is not None)
    if perception is not None:
        pop_files = (*pop_files, "perception.png")
    check_outputs(out, json_path, csv_path, sorted({*FOLDER_FILES, *(extra or {}), *pop_files}))  # before solving
    err = stderr_console()
    with warnings_to(err):
        warnings.filterwarnings("ignore", message="contact solve did not converge", category=RuntimeWarning)
        result = None
        if population is not None:
            from ..population.outputs import write_population_outputs
            from ..population.run import run_population

            for note in population.notes:  # what the numbers will not show, and what the work costs: first
                say(err, f"note: {note}")
            with ProgressBar(err, "unit cell ψ(p)") as bar:
                adhesive = population.study.finger.adhesive or "work_of_adhesion" in population.population.distributions
                show = bar.stage("the members' family of adhesive cells" if adhesive else "members' own unit cells")
                result = run_population(population, progress=bar,
                                        member_progress=lambda i, n: show(f"{i}/{n} solved or read"))
            pred = result.nominal
        else:
            from ..study.outputs import load_output_modules

            with ProgressBar(err, "unit cell ψ(p)") as bar:
                # the deflection ramps (tens of seconds with a direction) say which is done, and
                # where they leave a core free the outputs' modules are imported there (~0.7 s
                # less after the last ramp, issue 23)
                pred = run_study(study, progress=bar, notice=bar.stage("deflection ramps"),
                                 on_free_core=load_output_modules if out is not None else None)
        figures = {name: make() for name, make in (extra or {}).items()}
        verdicts, sections = None, None
        if perception is not None:
            from ..perception.compare import against_flat
            from ..references import keys_of, metadata
            from ..study.citations import prediction_references

            doc = against_flat(pred, result, **perception).as_dict()
            if out is not None:  # from the numbers themselves (the JSON writes infinities as null)
                from ..plotting.perception import figure_comparison

                figures["perception.png"] = figure_comparison(doc)
            verdicts = to_jsonable(doc)
            # the JSON's references: the prediction's (and its population's) and the perception models'
            keys = keys_of(prediction_references(pred, result), [r["key"] for r in verdicts["references"]])
            sections = {"perception": verdicts, "references": to_jsonable(metadata(keys))}
        if result is not None:
            paths = write_population_outputs(result, out, json_path=json_path, csv_path=csv_path, extra=figures,
                                             sections=sections)
        else:
            paths = write_outputs(pred, out, json_path=json_path, csv_path=csv_path, extra=figures,
                                  sections=sections)
    payload = to_jsonable(prediction_json(pred, result))
    if result is not None:
        payload["population"] = to_jsonable(result.as_dict())
    if sections is not None:
        payload.update(sections)
    if json_path == "-":
        sys.stdout.write(json_text(payload))
        sys.stdout.flush()
    elif result is not None:
        _print_population(payload)
        if result.sensitivity is not None:
            from ._sensitivity import print_sensitivity

            print_sensitivity(payload["population"]["sensitivity"])
    else:
        _print_prediction(payload)
    if verdicts is not None and json_path != "-":
        from ._perception import print_comparison

        print_comparison(payload["perception"])
    for note in pred.notes:
        say(err, f"note: {note}")
    cell = payload["cell"]
    say(err, f"unit cell: {cell['model']}, {cell['solves']} solves ({'cached' if cell['cached'] else 'computed'}) "
             f"in {pred.timings['cell']:.2f} s; coupling {pred.timings['coupling']:.3f} s")
    if result is not None and (result.own_cells or result.member_solves):
        own = f"{result.own_cells} on a unit cell of their own, " if result.own_cells else ""
        say(err, f"members: {own}{result.member_solves} more solves"
                 f"{' (cached)' if not result.member_solves else ''}")
    if paths:
        say(err, "wrote " + ", ".join(str(p) for p in paths))
    if pred.unconverged:
        say(err, f"warning: {pred.unconverged} unit-cell solve(s) did not converge (exit code 1)")
        return EXIT_UNCONVERGED
    return 0


def predict(
    ctx: typer.Context,
    texture: Annotated[str | None, _popt("--texture", "-t", panel=_SURFACE, metavar="NAME")] = None,
    surface: Annotated[str | None, _popt("--surface", panel=_SURFACE, metavar="FILE")] = None,
    size: Annotated[str | None, _popt("--size", panel=_SURFACE, metavar="LX[,LY]")] = None,
    height_unit: Annotated[str | None, _popt("--height-unit", panel=_SURFACE, metavar="UNIT")] = None,
    fill_missing: Annotated[bool, _popt("--fill-missing", panel=_SURFACE)] = False,
    periodic: Annotated[bool, _popt("--periodic", panel=_SURFACE)] = False,
    no_periodic: Annotated[bool, _popt("--no-periodic", panel=_SURFACE)] = False,
    pixel_size: Annotated[str | None, _popt("--pixel-size", panel=_SURFACE, metavar="DX[,DY]")] = None,
    base_quantile: Annotated[str | None, _popt("--base-quantile", panel=_SURFACE, metavar="Q")] = None,
    periodize: Annotated[bool, _popt("--periodize", panel=_SURFACE)] = False,
    material_modulus: Annotated[str | None, _popt("--material-modulus", panel=_MATERIALS, metavar="E")] = None,
    material_poisson: Annotated[str | None, _popt("--material-poisson", panel=_MATERIALS, metavar="NU")] = None,
    skin_modulus: Annotated[str | None, _popt("--skin-modulus", panel=_MATERIALS, metavar="E")] = None,
    skin_poisson: Annotated[str | None, _popt("--skin-poisson", panel=_MATERIALS, metavar="NU")] = None,
    skin_layer_thickness: Annotated[str | None, _popt("--skin-layer-thickness", panel=_MATERIALS,
                                                      metavar="T")] = None,
    skin_layer_modulus: Annotated[str | None, _popt("--skin-layer-modulus", panel=_MATERIALS, metavar="E")] = None,
    skin_substrate_modulus: Annotated[str | None, _popt("--skin-substrate-modulus", panel=_MATERIALS,
                                                        metavar="E")] = None,
    skin_substrate_poisson: Annotated[str | None, _popt("--skin-substrate-poisson", panel=_MATERIALS,
                                                        metavar="NU")] = None,
    skin_base: Annotated[str | None, _popt("--skin-base", panel=_MATERIALS,
                                           metavar="elastic|rigid|rigid-frictionless")] = None,
    work_of_adhesion: Annotated[str | None, _popt("--work-of-adhesion", panel=_FINGER, metavar="W")] = None,
    adhesion_range: Annotated[str | None, _popt("--adhesion-range", panel=_FINGER, metavar="RHO")] = None,
    adhesion_law: Annotated[str | None, _popt("--adhesion-law", panel=_FINGER, metavar="exponential|maugis")] = None,
    finger: Annotated[str | None, _popt("--finger", panel=_FINGER, metavar="PRESET")] = None,
    finger_param: Annotated[list[str] | None, _popt("--finger-param", panel=_FINGER, metavar="NAME=VALUE")] = None,
    loads: Annotated[list[str] | None, _popt("--loads", "-F", panel=_LOADS, metavar="START:STOP:COUNT")] = None,
    log: Annotated[bool, _popt("--log", panel=_LOADS)] = False,
    linear: Annotated[bool, _popt("--linear", panel=_LOADS)] = False,
    zones_at: Annotated[str | None, _popt("--zones-at", panel=_LOADS, metavar="LOAD")] = None,
    model: Annotated[str | None, _popt("--model", panel=_NUMERICS, metavar="bem|hertz|both")] = None,
    grid: Annotated[str | None, _popt("--grid", panel=_NUMERICS, metavar="N")] = None,
    accuracy: Annotated[str | None, _popt("--accuracy", panel=_NUMERICS, metavar="REL")] = None,
    direction: Annotated[str | None, _popt("--direction", panel=_LOADS, metavar="ANGLE")] = None,
    tol: Annotated[str | None, _popt("--tol", panel=_NUMERICS, metavar="TOL")] = None,
    max_iter: Annotated[str | None, _popt("--max-iter", panel=_NUMERICS, metavar="N")] = None,
    cache: Annotated[str | None, _popt("--cache", panel=_NUMERICS, metavar="DIR")] = None,
    out: Annotated[str | None, _popt("--out", "-o", panel=_OUTPUT, metavar="DIR")] = None,
    csv_path: Annotated[str | None, _popt("--csv", panel=_OUTPUT, metavar="PATH.csv")] = None,
    json_path: Annotated[str | None, _popt("--json", panel=_OUTPUT, metavar="PATH|-")] = None,
    population: Annotated[str | None, _popt("--population", panel=_FINGER, metavar="NAME|FILE|DIR")] = None,
    quantiles: Annotated[str | None, _popt("--quantiles", panel=_OUTPUT, metavar="Q,Q,...")] = None,
    sensitivity: Annotated[bool, _popt("--sensitivity", panel=_FINGER)] = False,
    sensitivity_samples: Annotated[str | None, _popt("--sensitivity-samples", panel=_FINGER, metavar="N")] = None,
    device: Annotated[str | None, _popt("--device", panel=_NUMERICS, metavar="cpu|cupy|torch")] = None,
    perception: Annotated[bool, _popt("--perception", panel=_PERCEPTION)] = False,
    speed: Annotated[str | None, _popt("--speed", panel=_PERCEPTION, metavar="V|LOW:HIGH")] = None,
    weber_fraction: Annotated[str | None, _popt("--weber-fraction", panel=_PERCEPTION, metavar="W")] = None,
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
    flags = {
        "--texture": texture, "--surface": surface, "--size": size, "--height-unit": height_unit,
        "--fill-missing": fill_missing or None, "--periodize": periodize or None,
        "--pixel-size": pixel_size, "--base-quantile": base_quantile,
        "--material-modulus": material_modulus, "--material-poisson": material_poisson,
        "--skin-modulus": skin_modulus, "--skin-poisson": skin_poisson, "--finger": finger,
        "--skin-layer-thickness": skin_layer_thickness, "--skin-layer-modulus": skin_layer_modulus,
        "--skin-substrate-modulus": skin_substrate_modulus, "--skin-substrate-poisson": skin_substrate_poisson,
        "--skin-base": skin_base,
        "--work-of-adhesion": work_of_adhesion, "--adhesion-range": adhesion_range, "--adhesion-law": adhesion_law,
        "--loads": loads or None, "--zones-at": zones_at, "--model": model, "--grid": grid,
        "--accuracy": accuracy, "--direction": direction,
        "--tol": tol, "--max-iter": max_iter, "--cache": cache, "--weber-fraction": weber_fraction,
    }
    with user_errors(), device_option(device):
        flags["--periodic"] = flag_pair(periodic, no_periodic, "--periodic", "--no-periodic")
        flags["--log"] = flag_pair(log, linear, "--log", "--linear")
        sections: dict[str, Any] = {"population": None}
        with warnings_to(stderr_console()):
            study = build_study(ctx_args=list(ctx.args), flags=flags, finger_param=finger_param or [],
                                options=command_options(ctx), extra_sections=sections)
            verdicts = perception_options(perception, speed, weber_fraction, study)
            from ..population.rules import attach

            plan = attach(study, population, table=sections["population"], quantiles=quantiles,
                          sensitivity=sensitivity_asked(sensitivity, sensitivity_samples))
        if out is None and json_path != "-":
            out = "out"  # files only where asked: with --json - and no --out, none
        code = run_prediction(study, out, json_path, csv_path, population=plan, perception=verdicts)
    if code:
        raise typer.Exit(code)





def run_default(
    out: Annotated[str, typer.Option("--out", metavar="DIR",
                                     help="Output folder (created if missing, replaced as a whole).")] = "out",
    grid: Annotated[str | None, typer.Option("--grid", metavar="N",
                                             help="Grid points along x of the unit cell (default: by accuracy).")] = None,
    loads: Annotated[
        str, typer.Option("--loads", metavar="START:STOP:COUNT", help="Log-spaced load range.")
    ] = "0.1N:4N:40",
    cache: Annotated[str | None, typer.Option("--cache", metavar="DIR", help=_PREDICT_HELP["--cache"])] = None,
) -> None:
    """Predict the default study into DIR: predict.json, .nc, areas/friction/zones.png, ridge_models.png.

    The study: a hot-embossed polyethylene foil (E = 0.5 GPa, nu = 0.4) with hexagonal spherical caps
    R = 100um, h = 20um, spacing 175um; the default finger; loads 0.1-4 N (40, log); BEM and Hertz.
    """
    from ..study.spec import DEFAULT_STUDY

    with user_errors():
        err = stderr_console()
        with warnings_to(err):
            study = build_study(ctx_args=[], base=DEFAULT_STUDY,
                                flags={"--loads": [loads], "--log": True, "--grid": grid, "--cache": cache})
        from ..plotting.ridges import figure_ridge_models

        code = run_prediction(study, out, None, extra={"ridge_models.png": figure_ridge_models})
    if code:
        raise typer.Exit(code)


def register(app: typer.Typer) -> None:
    app.command("predict", context_settings=EXTRA_ARGS)(predict)
    app.command("run-default")(run_default)
