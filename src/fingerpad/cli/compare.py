"""``fingerpad compare A.toml B.toml``: who tells two surfaces apart, and what each vibrates at.

Parses, calls :func:`fingerpad.perception.compare.compare` once, writes and prints; the table
and the lines after it are also what ``predict --perception`` prints
(:func:`._perception.print_comparison`).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping, Sequence
from typing import Annotated, Any

import typer

from ._perception import print_comparison
from .common import ProgressBar, say, stderr_console, user_errors, warnings_to

#: The files of a compare folder (replaced as a whole).
COMPARE_FILES = ("compare.json", "compare.nc", "compare.csv", "compare_vibration.csv", "compare.png")

_HELP = {
    "--population": "Compare on a population of fingers (the same members on both): a preset (adults), a TOML file "
                    "with a [population] table or a folder written by fingerpad analyse; default: the study's "
                    "finger, or A's own [population] table.",
    "--speed": "Stroke speed(s): one speed, LOW:HIGH (the two ends of a band) or START:STOP:COUNT; unit "
               "suffixes m/s, cm/s, mm/s (default 20mm/s:100mm/s).",
    "--loads": "Normal loads: START:STOP:COUNT, one load or a comma list of either; repeatable (default: A's study loads).",
    "--directions": "Stroke directions, degrees from the texture's x axis, comma-separated (default 0,90).",
    "--weber-fraction": "The person's Weber fraction W, for every finger: the relative friction difference told "
                        "apart in 75 % of forced choices (A's [perception] weber_fraction; default 0.11, or each "
                        "member's own where the population draws it; docs/perception.md).",
    "--out": "Output folder: compare.json, compare.nc, compare.csv, compare_vibration.csv, compare.png "
             "(replaced as a whole; default 'compare', none with --json -).",
    "--json": "Also write the JSON to PATH ('-' for stdout, which replaces the table).",
}


def compare_command(
    a: Annotated[str, typer.Argument(metavar="A.toml", show_default=False, help="The study of surface A (its "
                                     "texture, material, finger and loads).")],
    b: Annotated[str, typer.Argument(metavar="B.toml|flat", show_default=False,
                                     help="The study of surface B (a texture or a measured map; taken on A's "
                                          "fingers and loads), or 'flat' for the flat reference.")],
    population: Annotated[str | None, typer.Option("--population", metavar="NAME|FILE|DIR",
                                                   help=_HELP["--population"])] = None,
    speed: Annotated[str | None, typer.Option("--speed", metavar="V|LOW:HIGH", help=_HELP["--speed"])] = None,
    loads: Annotated[list[str] | None, typer.Option("--loads", "-F", metavar="START:STOP:COUNT",
                                                    help=_HELP["--loads"])] = None,
    directions: Annotated[str | None, typer.Option("--directions", metavar="DEG,DEG",
                                                   help=_HELP["--directions"])] = None,
    weber_fraction: Annotated[str | None, typer.Option("--weber-fraction", metavar="W",
                                                       help=_HELP["--weber-fraction"])] = None,
    out: Annotated[str | None, typer.Option("--out", "-o", metavar="DIR", help=_HELP["--out"])] = None,
    json_path: Annotated[str | None, typer.Option("--json", metavar="PATH|-", help=_HELP["--json"])] = None,
) -> None:
    """Compare two surfaces on the same fingers: who tells them apart by friction, what each vibrates at.

    Per load: the friction on each, the fraction of the fingers that tell them apart in a forced
    choice (P >= 0.75) and the median P; per surface the vibration frequency f = v / lambda and
    receptor channel at the stroke speeds and directions, an amplitude estimate, and the
    roughness regime. Example: fingerpad compare examples/study.toml flat --population adults
    --loads 0.5N --loads 1N --loads 2N
    """
    from .. import io as fio
    from ..perception.compare import compare, parse_directions, parse_speeds
    from .predict import build_study

    with user_errors():
        err = stderr_console()
        speeds = parse_speeds(speed)
        dirs = parse_directions(directions)
        if out is None and json_path != "-":
            out = "compare"
        if out is not None:
            fio.OutputFolder.check(out, COMPARE_FILES)
        if json_path not in (None, "-"):
            fio.check_writable(json_path, "--json", (".json",))
        sections: dict[str, Any] = {"population": None}
        with warnings_to(err):
            study_a = build_study(ctx_args=[a], flags={"--loads": loads or None, "--weber-fraction": weber_fraction},
                                  extra_sections=sections)
            study_b = b if b.strip().lower() == "flat" else build_study(ctx_args=[b])
            with ProgressBar(err, "compare") as bar:
                result = compare(study_a, study_b, population=population, table=sections["population"],
                                 speeds=speeds, directions=dirs, notice=bar.stage("predictions"))
        perception = result.as_dict()
        doc = {"perception": perception, "references": perception["references"]}  # `fingerpad cite` reads these
        written = write_comparison(result, doc, out, json_path)
        if json_path == "-":
            from ..encode import json_text, to_jsonable

            sys.stdout.write(json_text(to_jsonable(doc)))
        else:
            print_comparison(doc["perception"])
        for note in result.notes:
            say(err, f"note: {note}")
        if written:
            say(err, "wrote " + ", ".join(str(p) for p in written))


def write_comparison(result: Any, doc: Mapping[str, Any], out: str | None, json_path: str | None) -> list[Any]:
    """The outputs of a comparison, all or none: the folder's files and ``--json PATH``."""
    from .. import io as fio
    from .. import netcdf
    from ..encode import flatten_attrs, json_text, to_jsonable

    written: list[Any] = []
    text = json_text(to_jsonable(doc))
    if out is not None:
        from ..plotting.perception import figure_comparison

        fig = figure_comparison(doc["perception"])
        ds = result.dataset()
        with fio.OutputFolder(out, COMPARE_FILES) as folder:
            folder.write("compare.json", lambda p: p.write_text(text, encoding="utf-8"))
            folder.write("compare.nc", lambda p: netcdf.to_netcdf(ds.assign_attrs(flatten_attrs(ds.attrs)), p))
            folder.write("compare.csv", lambda p: p.write_text(result.csv_text(), encoding="utf-8"))
            folder.write("compare_vibration.csv", lambda p: p.write_text(result.vibration_csv_text(),
                                                                         encoding="utf-8"))
            folder.write("compare.png", lambda p: fig.savefig(p, format="png", dpi=110))
            folder.commit()
        written += [folder.final_path(n) for n in COMPARE_FILES]
    if json_path not in (None, "-"):
        written.append(fio.write_text(json_path, text))
    return written


def register(app: typer.Typer) -> None:
    app.command("compare")(compare_command)
