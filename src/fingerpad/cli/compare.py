"""``fingerpad compare A.toml B.toml``: who tells two surfaces apart, and what each vibrates at.

Parses, calls :func:`fingerpad.perception.compare.compare` once, writes and prints; the table
and the lines after it are also what ``predict --perception`` prints (:func:`print_comparison`).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping, Sequence
from typing import Annotated, Any

import typer

from .common import ProgressBar, say, say_wrapped, stderr_console, stdout_console, user_errors, warnings_to

#: The files of a compare folder (replaced as a whole).
COMPARE_FILES = ("compare.json", "compare.nc", "compare.csv", "compare_vibration.csv", "compare.png")

_HELP = {
    "--population": "Compare on a population of fingers (the same members on both): a preset (adults), a TOML file "
                    "with a [population] table or a folder written by fingerpad analyse; default: the study's "
                    "finger, or A's own [population] table.",
    "--speed": "Stroke speed(s): one speed, LOW:HIGH (the two ends of a band) or START:STOP:COUNT; unit "
               "suffixes m/s, cm/s, mm/s (default 20mm/s:100mm/s).",
    "--loads": "Normal loads: START:STOP:COUNT or one load; repeatable (default: A's study loads).",
    "--directions": "Stroke directions, degrees from the texture's x axis, comma-separated (default 0,90).",
    "--weber-fraction": "Weber fraction W of every finger: the relative friction difference told apart in 75 % "
                        "of forced choices (default 0.11; docs/perception.md).",
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
            study_a = build_study(ctx_args=[a], flags={"--loads": loads or None}, extra_sections=sections)
            study_b = b if b.strip().lower() == "flat" else build_study(ctx_args=[b])
            with ProgressBar(err, "compare") as bar:
                result = compare(study_a, study_b, population=population, table=sections["population"],
                                 speeds=speeds, directions=dirs, weber=weber_fraction,
                                 notice=bar.stage("predictions"))
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


def _mu_cell(band: Mapping[str, Any], i: int, many: bool) -> str:
    mid = float(band["0.5"][i])
    return f"{mid:.3f} [{float(band['0.05'][i]):.2f}-{float(band['0.95'][i]):.2f}]" if many else f"{mid:.3f}"


def _band_text(freqs: Sequence[float]) -> str:
    lo, hi = min(freqs), max(freqs)
    return f"{lo:.3g} Hz" if lo == hi else f"{lo:.3g}-{hi:.3g} Hz"


def print_comparison(doc: Mapping[str, Any]) -> None:
    """The comparison in 80 columns: per load the friction of both surfaces, the fraction of the
    fingers telling them apart and the median P; then per surface and direction the vibration
    band and channel, the amplitude estimate and the roughness regime."""
    from rich import box
    from rich.table import Table

    console = stdout_console(80)
    a, b = doc["a"]["label"], doc["b"]["label"]
    many = len(doc["members"]["p_correct"]) > 1
    pop = doc.get("population")
    w = doc["weber_fraction"]
    wtext = f"W = {w['value']:g}" if not w["drawn"] else f"W {w['min']:.2g}-{w['max']:.2g}"
    who = f"{pop['size']} fingers of {pop['name']!r}" if pop else "the study's finger"
    table = Table(title=f"{a} against {b}: {who}, {wtext}", box=box.SIMPLE_HEAD, pad_edge=False)
    for col in ("load N", f"μ {a}", f"μ {b}", "tell apart", "median P"):
        table.add_column(col, justify="right", overflow="fold")
    fraction, median = doc["discrimination"]["fraction"], doc["discrimination"]["p_correct_median"]
    for i, (load, key) in enumerate(zip(doc["loads"], fraction, strict=True)):
        table.add_row(f"{float(load):.3g}", _mu_cell(doc["mu"][a], i, many), _mu_cell(doc["mu"][b], i, many),
                      f"{100 * fraction[key]:.3g} %", f"{median[key]:.3f}")
    console.print(table)
    say_wrapped(console, ("μ: median [5-95 %] over the fingers; " if many else "")
                + "tell apart: the fraction of fingers choosing right in at least 75 % of forced choices by "
                  "friction alone (docs/perception.md)")
    speeds = doc["speeds"]
    span = f"{1e3 * min(speeds):g}-{1e3 * max(speeds):g} mm/s" if len(speeds) > 1 else f"{1e3 * speeds[0]:g} mm/s"
    groups: dict[tuple[str, float, int], list[dict[str, Any]]] = {}
    for e in doc["vibration"]:
        groups.setdefault((e["texture"], e["direction_deg"], e["harmonic"]), []).append(e)
    ridge = 1e6 * float(doc["ridge_period"])
    for (tex, direction, harmonic), rows in groups.items():
        lam = rows[0]["wavelength_m"]
        if lam is None or not math.isfinite(lam):
            say_wrapped(console, f"{tex} at {direction:g}°: no period along the stroke, no vibration")
            continue
        freqs = [r["frequency_hz"] for r in rows]
        channels = sorted({r["channel"] for r in rows}, key=lambda c: [r["channel"] for r in rows].index(c))
        which = "" if harmonic == 1 else f" (strongest: harmonic {harmonic})"
        side = "shorter" if lam * 1e6 < ridge else "longer"
        say_wrapped(console, f"{tex} at {direction:g}°{which}: λ {1e6 * lam:.4g} µm -> {_band_text(freqs)} at {span}, "
                             f"channel {'/'.join(channels)}; {side} than the ridge period {ridge:.3g} µm")
    loads = [f"{float(f):g}" for f in doc["loads"]]
    for label in (a, b):
        amp = doc["amplitude"].get(label)
        if amp is not None and any(float(v) > 0 for v in amp):
            say_wrapped(console, f"{label} amplitude estimate at {'/'.join(loads)} N: "
                                 f"{'/'.join(f'{1e6 * float(v):.3g}' for v in amp)} µm p-p (threshold 0.1 µm "
                                 "near 250 Hz, flat below 40 Hz)")
        say_wrapped(console, f"{label} roughness: {roughness_text(doc['roughness'][label], loads)}")


def roughness_text(regimes: Sequence[Mapping[str, Any]], loads: Sequence[str]) -> str:
    """The roughness regimes of one surface over the loads in one sentence: its scale and cue
    once, then where the roughness stands (coarse) or the centre's contact state (fine), the
    loads of each listed together."""
    first = regimes[0]
    if first.get("scale") in (None, "flat"):
        return str(first["verdict"])
    key = "roughness" if first["scale"] == "coarse" else "state"
    groups: dict[str, list[str]] = {}
    for f, r in zip(loads, regimes, strict=True):
        groups.setdefault(str(r[key]), []).append(f)
    where = "; ".join(f"{v} at {', '.join(fs)} N" for v, fs in groups.items())
    head = ("coarse, judged by skin intrusion; roughness " if key == "roughness" else
            "fine, judged by its vibration; pad centre in ")
    tail = "; spacing below 160 µm: felt smooth" if first.get("felt_smooth") else ""
    return head + where.replace(" at ", " contact at " if key == "state" else " at ") + tail


def perception_options(asked: bool, speed: str | None, weber: str | None, study: Any) -> dict[str, Any] | None:
    """``--perception``'s options, checked before any solve (``--speed`` and ``--weber-fraction``
    without it are refused); the stroke directions are the study's sliding direction, else 0 and 90."""
    from ..errors import FingerpadError

    if not asked:
        for name, value in (("--speed", speed), ("--weber-fraction", weber)):
            if value is not None:
                raise FingerpadError(f"{name} needs --perception")
        return None
    from ..perception.compare import DEFAULT_DIRECTIONS, parse_speeds, weber_fractions

    weber_fractions(weber, 1)
    directions = DEFAULT_DIRECTIONS if study.direction is None else (float(study.direction),)
    return {"speeds": parse_speeds(speed), "directions": directions, "weber": weber}


def register(app: typer.Typer) -> None:
    app.command("compare")(compare_command)
