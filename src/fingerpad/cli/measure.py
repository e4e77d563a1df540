"""Command-line commands for tribometer measurements: ``analyse`` and ``simulate-measurement``.

``fingerpad analyse DATA... --reference SAMPLE --out DIR``
    Read recordings (files, folders with ``manifest.csv`` or matching file names, manifests),
    split strokes, fit mu = k F^(n-1), normalise by the reference sample, locate the contact
    transition and estimate the skin micro-modulus; write tables, figures, NetCDF curves and an
    HTML report into DIR (all at once: nothing is written if anything fails).
``fingerpad simulate-measurement --out DIR``
    Write a synthetic study (recordings, ``manifest.csv``, ``samples.csv``, ``truth.json``).

Options take text, so that every mistake is a one-line ``error: ...`` on stderr, exit code 2.
"""

from __future__ import annotations

import contextlib
import math
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any

import typer

from ..errors import FingerpadError, one_line, printable
from ..extras import require
from ..units import parse_int, parse_quantity
from .common import user_errors

_INPUT, _STROKES, _ANALYSIS, _OUTPUT = "Input", "Strokes", "Analysis", "Output"


def _opt(*names: str, panel: str, **kw: Any) -> Any:
    return typer.Option(*names, rich_help_panel=panel, **kw)


def _number(text: str, name: str, *, low: float | None = None, high: float | None = None) -> float:
    try:
        value = float(text)
    except (TypeError, ValueError):
        raise FingerpadError(f"{name}: expected a number, got {text!r}") from None
    if not math.isfinite(value) or (low is not None and value < low) or (high is not None and value > high):
        bounds = f"[{low if low is not None else '-inf'}, {high if high is not None else 'inf'}]"
        raise FingerpadError(f"{name}: must be a number in {bounds}, got {text!r}")
    return value


def _integer(text: str, name: str) -> int:
    """An integer, any value: its range is the options class's to decide."""
    return parse_int(text, name, minimum=-sys.maxsize)


def _word(text: str) -> str:
    """A choice as typed, case and spaces aside: the options class checks it."""
    return str(text).strip().lower()


def _load_range(text: str) -> tuple[float, float]:
    parts = str(text).split(":")
    if len(parts) != 2:
        raise FingerpadError(f"--loads: expected LOW:HIGH, e.g. 0.1N:5N, got {text!r}")
    lo, hi = (parse_quantity(p, "force", name="--loads") for p in parts)
    if not 0 < lo < hi:
        raise FingerpadError(f"--loads: need 0 < LOW < HIGH, got {text!r}")
    return lo, hi


def _find_samples_table(data: list[str]) -> Path | None:
    """``samples.csv`` beside the data (a folder's or a manifest's), if there is exactly one."""
    found = []
    for item in data:
        p = Path(item)
        folder = p if p.is_dir() else p.parent
        if (folder / "samples.csv").is_file():
            found.append((folder / "samples.csv").resolve())
    unique = sorted(set(found))
    return unique[0] if len(unique) == 1 else None


def analyse_command(
    data: Annotated[list[str], typer.Argument(metavar="DATA...", help="Recordings, folders or manifest CSVs.",
                                              show_default=False)],
    reference: Annotated[str, _opt("--reference", "-r", panel=_INPUT, metavar="SAMPLE",
                                   help="Flat reference sample every participant slid on.")],
    out: Annotated[str, _opt("--out", "-o", panel=_OUTPUT, metavar="DIR", help="Output folder.")],
    spec: Annotated[str | None, _opt("--spec", panel=_INPUT, metavar="TOML",
                                     help="Column/unit/file spec ([columns], [units], [files]).")] = None,
    pattern: Annotated[str | None, _opt("--pattern", panel=_INPUT, metavar="TEMPLATE",
                                        help="File-name template, e.g. '{participant}_{sample}_{repetition}.csv'.")] = None,
    samples: Annotated[str | None, _opt("--samples", panel=_INPUT, metavar="CSV",
                                        help="Texture table (sample,radius,height,spacing,...); default: "
                                             "samples.csv beside the data.")] = None,
    normal_column: Annotated[str | None, _opt("--normal-column", panel=_INPUT, metavar="NAME")] = None,
    friction_column: Annotated[str | None, _opt("--friction-column", panel=_INPUT, metavar="NAME")] = None,
    time_column: Annotated[str | None, _opt("--time-column", panel=_INPUT, metavar="NAME")] = None,
    position_column: Annotated[str | None, _opt("--position-column", panel=_INPUT, metavar="NAME")] = None,
    velocity_column: Annotated[str | None, _opt("--velocity-column", panel=_INPUT, metavar="NAME")] = None,
    force_unit: Annotated[str | None, _opt("--force-unit", panel=_INPUT, metavar="UNIT",
                                           help="Unit of both forces (N, mN, gf, kgf, lbf).")] = None,
    normal_unit: Annotated[str | None, _opt("--normal-unit", panel=_INPUT, metavar="UNIT",
                                            help="Unit of the normal force (overrides --force-unit).")] = None,
    friction_unit: Annotated[str | None, _opt("--friction-unit", panel=_INPUT, metavar="UNIT",
                                              help="Unit of the friction force (overrides --force-unit).")] = None,
    delimiter: Annotated[str | None, _opt("--delimiter", panel=_INPUT, metavar="CHAR",
                                          help="Field separator of text files (',', ';', 'tab'); default: guessed.")] = None,
    decimal: Annotated[str | None, _opt("--decimal", panel=_INPUT, metavar=". or ,",
                                        help="Decimal separator of text files; default: detected.")] = None,
    position_unit: Annotated[str | None, _opt("--position-unit", panel=_INPUT, metavar="UNIT")] = None,
    time_unit: Annotated[str | None, _opt("--time-unit", panel=_INPUT, metavar="UNIT")] = None,
    velocity_unit: Annotated[str | None, _opt("--velocity-unit", panel=_INPUT, metavar="UNIT")] = None,
    invert_normal: Annotated[bool, _opt("--invert-normal", panel=_INPUT,
                                        help="Negate the normal force (compression recorded negative).")] = False,
    drop_nan: Annotated[bool, _opt("--drop-nan", panel=_INPUT, help="Skip rows with missing values.")] = False,
    trim: Annotated[str, _opt("--trim", panel=_STROKES, metavar="FRACTION",
                              help="Fraction of each stroke dropped at each end.")] = "0.2",
    direction_source: Annotated[str, _opt("--direction-source", panel=_STROKES,
                                          metavar="auto|velocity|position|friction")] = "auto",
    min_strokes: Annotated[str, _opt("--min-strokes", panel=_STROKES, metavar="N",
                                     help="Fewest strokes per file.")] = "2",
    outlier_z: Annotated[str, _opt("--outlier-z", panel=_STROKES, metavar="Z")] = "3.5",
    min_travel: Annotated[str, _opt("--min-travel", panel=_STROKES, metavar="LENGTH",
                                    help="Shortest stroke travel (e.g. 1mm); shorter movements are not strokes.")] = "1mm",
    min_load: Annotated[str, _opt("--min-load", panel=_STROKES, metavar="FORCE",
                                  help="Lift-off threshold of the normal force.")] = "0.01N",
    bins: Annotated[str, _opt("--bins", panel=_ANALYSIS, metavar="N", help="Load bins.")] = "8",
    breakpoint_space: Annotated[str, _opt("--breakpoint-space", panel=_ANALYSIS, metavar="log|linear")] = "log",
    breakpoint_method: Annotated[str, _opt("--breakpoint-method", panel=_ANALYSIS, metavar="bootstrap|profile",
                                           help="Interval of a detected transition.")] = "bootstrap",
    n_null: Annotated[str, _opt("--n-null", panel=_ANALYSIS, metavar="N",
                                help="Simulations of the breakpoint test (p-value resolution 1/(N+1)).")] = "999",
    trend: Annotated[str, _opt("--trend", panel=_ANALYSIS, metavar="steeper|flatter|any",
                               help="Change of trend sought in the normalised friction.")] = "steeper",
    level: Annotated[str, _opt("--level", panel=_ANALYSIS, metavar="P", help="Confidence level.")] = "0.95",
    finger: Annotated[str, _opt("--finger", panel=_ANALYSIS, metavar="PRESET",
                                help="Finger preset of the micro-model.")] = "default",
    fit_scale: Annotated[bool, _opt("--fit-scale", panel=_ANALYSIS,
                                    help="Fit an amplitude factor along with E_s.")] = False,
    seed: Annotated[str, _opt("--seed", panel=_ANALYSIS, metavar="N")] = "0",
    no_sensitivity: Annotated[bool, _opt("--no-sensitivity", panel=_ANALYSIS,
                                         help="Skip refitting E_s with the other micro-model and varied "
                                              "friction parameters.")] = False,
    no_figures: Annotated[bool, _opt("--no-figures", panel=_OUTPUT)] = False,
    no_qc: Annotated[bool, _opt("--no-qc", panel=_OUTPUT, help="Skip the QC figures (sheets and per recording).")
                     ] = False,
    qc_recordings: Annotated[bool, _opt("--qc-recordings", panel=_OUTPUT,
                                        help="Also draw a full QC figure per recording (figures/qc/; ~0.1 s of CPU "
                                             "each); the QC sheets show every recording either way.")] = False,
    title: Annotated[str, _opt("--title", panel=_OUTPUT, metavar="TEXT")] = "Finger friction study",
) -> None:
    """Analyse tribometer recordings: friction curves, normalisation, transition, skin modulus.

    Example: fingerpad analyse data/ --reference flat --out results/
    """
    with user_errors(), _measurement_warnings() as shown:
        require("measure")  # before any file is read: the same line as analyse_study's
        from .. import measure as m
        from ..finger import get_finger
        from ..io import OutputFolder
        from ..measure.report import write_report

        # Before anything is read or fitted; never a folder holding the recordings it reads.
        OutputFolder.check(out, inputs=[*data, *([spec] if spec else []), *([samples] if samples else [])])
        if decimal is not None and decimal not in (".", ","):
            raise FingerpadError(f"--decimal: expected '.' or ',', got {decimal!r}")
        if delimiter is not None and delimiter.lower() in ("tab", "\\t"):
            delimiter = "\t"
        if delimiter is not None and len(delimiter) != 1:
            raise FingerpadError(f"--delimiter: expected one character or 'tab', got {delimiter!r}")
        base = m.load_spec(spec) if spec else m.ColumnSpec()
        column_spec = base.with_options(
            columns={"normal": normal_column, "friction": friction_column, "time": time_column,
                     "position": position_column, "velocity": velocity_column},
            units={"normal": normal_unit or force_unit, "friction": friction_unit or force_unit,
                   "position": position_unit, "time": time_unit, "velocity": velocity_unit},
            invert_normal=True if invert_normal else None,
            nan_policy="drop" if drop_nan else None,
            delimiter=delimiter,
            decimal=decimal,
        )
        # the CLI only parses: every range and choice is decided by the options classes
        stroke_opts = m.StrokeOptions(
            trim=_number(trim, "--trim"),
            direction_source=_word(direction_source),  # type: ignore[arg-type]
            min_strokes=_integer(min_strokes, "--min-strokes"),
            min_travel=parse_quantity(min_travel, "length", name="--min-travel"),
            min_load=parse_quantity(min_load, "force", name="--min-load"),
        )
        options = m.AnalysisOptions(
            reference=reference,
            strokes=stroke_opts,
            outlier_z=_number(outlier_z, "--outlier-z"),
            n_bins=_integer(bins, "--bins"),
            breakpoint_space=_word(breakpoint_space),  # type: ignore[arg-type]
            breakpoint_method=_word(breakpoint_method),  # type: ignore[arg-type]
            breakpoint_trend=_word(trend),  # type: ignore[arg-type]
            level=_number(level, "--level"),
            seed=_integer(seed, "--seed"),
            finger=get_finger(finger),
            fit_scale=fit_scale,
            n_null=_integer(n_null, "--n-null"),
            sensitivity=not no_sensitivity,
        )
        table = Path(samples) if samples else _find_samples_table(data)
        textures = m.read_textures(table) if table else None
        recordings = m.load_study(data, column_spec, pattern=pattern)
        from ..measure.figurepool import EarlyQC
        from .common import ProgressBar, stderr_console

        # the QC figures start as soon as the strokes are known, and draw on the other
        # cores while the fits run
        with EarlyQC(recordings=qc_recordings) as early:
            # the fits that do not depend on one another on every usable CPU (at most 8)
            result = m.analyse_study(recordings, options, textures=textures,
                                     on_strokes=early.start if not (no_figures or no_qc) else None,
                                     find_strokes=early.find_strokes, workers=None)
            with ProgressBar(stderr_console(), "figures") as bar:
                written = write_report(result, out, figures=not no_figures, title=title, qc=not no_qc,
                                       qc_recordings=qc_recordings,
                                       progress=(lambda i, n, _what: bar(i, n)) if sys.stderr.isatty() else None,
                                       early_qc=early)
    _print_summary(result, written, Path(out), shown)


@contextlib.contextmanager
def _measurement_warnings() -> Iterator[list[str]]:
    """Show :class:`MeasurementWarning` as ``warning: ...`` lines on stderr (once each); other
    warnings of the numerical libraries are not for users."""
    import warnings

    shown: list[str] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield shown
        finally:
            from ..measure.study import MeasurementWarning

            for w in caught:
                if issubclass(w.category, MeasurementWarning):
                    line = one_line(str(w.message))
                    if line not in shown:
                        shown.append(line)
                        sys.stderr.write(f"warning: {line}\n")
            sys.stderr.flush()


def _fit_widths(natural: list[int], minimum: list[int], budget: int) -> list[int]:
    """Column widths (characters) within ``budget``: each column's natural width, the widest
    narrowed first, never below its ``minimum`` (its longest word: a number is never cut)."""
    widths = list(natural)
    while sum(widths) > budget:
        slack = [w - lo for w, lo in zip(widths, minimum)]
        j = max(range(len(widths)), key=lambda i: (slack[i] > 0, widths[i]))
        if slack[j] <= 0:
            break  # a terminal narrower than the longest words: Rich folds the rest
        widths[j] -= 1
    return widths


def _print_summary(result: Any, written: list[Path], out: Path, shown: list[str] | None = None) -> None:
    from rich.table import Table
    from rich.text import Text

    from .common import stdout_console

    console = stdout_console(min_width=140)

    def show(text: str) -> None:  # wrapped at the console's width; labels from files as text (escapes shown)
        console.print(printable(text), markup=False, highlight=False)

    s = result.strokes
    show(f"{s['participant'].nunique()} participants, {s['sample'].nunique()} samples, "
                  f"{s['file'].nunique()} files, {len(s)} strokes ({int(s['outlier'].sum())} outliers)")
    parts = result.participants
    if "skin_modulus" in parts:
        # compact, so that it fits an 80-column terminal: the unit once in the title, no
        # borders, and no number ever cut or folded (a column is at least as wide as its
        # longest word; cells wrap only at spaces, "not determined", "0.1-0.2 or 0.5-0.7")
        header = ("participant", "ref. k", "ref. n", "E_s", f"{100 * result.options.level:.0f} % set", "model",
                  "other model", "friction params")
        cells = []
        for row in parts.to_dict("records"):
            e = row.get("skin_modulus", math.nan)
            ok = isinstance(e, float) and math.isfinite(e)
            determined = bool(row.get("skin_modulus_determined", True))
            other = row.get("skin_modulus_other", math.nan)
            lo, hi = row.get("skin_modulus_sens_low", math.nan), row.get("skin_modulus_sens_high", math.nan)
            interval = str(row.get("skin_modulus_interval") or "-").removesuffix(" MPa")
            cells.append((
                # a label read from a file: its escapes shown, not run
                printable(str(row["participant"])), f"{row['ref_k']:.3g}", f"{row['ref_n']:.3g}",
                (f"{e / 1e6:.3g}" if determined else f"not determined ({e / 1e6:.3g})") if ok else "-",
                interval if ok else "-",
                str(row.get("skin_modulus_model") or "") if ok else "",
                f"{other / 1e6:.3g} {row.get('skin_modulus_other_model')}"
                if isinstance(other, float) and math.isfinite(other) else "",
                f"{lo / 1e6:.3g}-{hi / 1e6:.3g}" if isinstance(lo, float) and math.isfinite(lo) else "",
            ))
        table = Table(title="skin micro-modulus E_s per participant (MPa)", box=None, pad_edge=False,
                      title_justify="left", header_style="bold underline")
        columns = [[name] + [c[j] for c in cells] for j, name in enumerate(header)]
        widths = _fit_widths([max(map(len, col)) for col in columns],
                             [max((len(w) for text in col for w in text.split()), default=1) for col in columns],
                             console.width - 2 * (len(header) - 1))
        for name, width in zip(header, widths):
            table.add_column(name, width=width, overflow="fold")
        for c in cells:
            table.add_row(*(Text(x) for x in c))  # text, not markup: a label "[b]" is shown as written
        console.print(table)
    for row in result.conditions.to_dict("records"):
        text = row.get("transition")
        if isinstance(text, str) and text:
            label = row["participant"] + " " + row["sample"] + (f"/{row['direction']}" if row["direction"] else "")
            show(f"{label}: {text}")
    for row in result.spread_summary.to_dict("records"):
        if not row["is_reference"] and math.isfinite(row["reduction"]):
            label = row["sample"] + (f"/{row['direction']}" if row["direction"] else "")
            show(f"{label}: spread between people CV {100 * row['cv_raw']:.1f} % -> "
                         f"{100 * row['cv_norm']:.1f} % after normalising")
    show(f"wrote {len(written)} files to {out} (report: {out / 'report.html'})")


#: The options of ``simulate-measurement`` that describe its one texture, which ``--samples`` replaces.
_ONE_TEXTURE = ("texture", "radius", "height", "spacing", "micro_model", "full_contact_ratio")


def simulate_command(
    ctx: typer.Context,
    out: Annotated[str, _opt("--out", "-o", panel=_OUTPUT, metavar="DIR", help="Output folder.")],
    seed: Annotated[str, _opt("--seed", panel=_INPUT, metavar="N", help="Random seed.")] = "0",
    participants: Annotated[str, _opt("--participants", panel=_INPUT, metavar="N")] = "4",
    repetitions: Annotated[str, _opt("--repetitions", panel=_INPUT, metavar="N",
                                     help="Files per participant and sample.")] = "2",
    strokes: Annotated[str, _opt("--strokes", panel=_INPUT, metavar="N", help="Strokes per file.")] = "12",
    loads: Annotated[str, _opt("--loads", panel=_INPUT, metavar="LOW:HIGH")] = "0.1N:5N",
    reference: Annotated[str, _opt("--reference", panel=_INPUT, metavar="NAME")] = "flat",
    texture: Annotated[str, _opt("--texture", panel=_INPUT, metavar="NAME",
                                 help="Name of the textured sample.")] = "bumps",
    radius: Annotated[str, _opt("--radius", panel=_INPUT, metavar="R")] = "50um",
    height: Annotated[str, _opt("--height", panel=_INPUT, metavar="H")] = "18um",
    spacing: Annotated[str, _opt("--spacing", panel=_INPUT, metavar="LAMBDA")] = "100um",
    micro_model: Annotated[str, _opt("--micro-model", panel=_INPUT, metavar="bem|hertz",
                                     help="Unit-cell model the recordings follow.")] = "bem",
    full_contact_ratio: Annotated[str, _opt("--full-contact-ratio", panel=_INPUT, metavar="RATIO",
                                            help="Hertz model only: full contact at RATIO x the "
                                                 "transition pressure (empirical).")] = "",
    skin_modulus: Annotated[str, _opt("--skin-modulus", panel=_INPUT, metavar="LOW:HIGH",
                                      help="Range of the participants' E_s.")] = "0.25MPa:0.4MPa",
    sampling_rate: Annotated[str, _opt("--sampling-rate", panel=_INPUT, metavar="HZ")] = "200",
    samples: Annotated[str | None, _opt("--samples", panel=_INPUT, metavar="CSV",
                                        help="Several textures: a sample table as `analyse --samples` reads "
                                             "it; replaces --texture and its geometry options.")] = None,
) -> None:
    """Write synthetic tribometer recordings with known skin modulus and friction law.

    Example: fingerpad simulate-measurement --out sim/ --seed 1 && fingerpad analyse sim/ --reference flat --out res/
    """
    with user_errors():
        from .. import measure as m
        from ..io import OutputFolder

        OutputFolder.check(out, inputs=[samples] if samples else [])  # before anything is simulated
        if samples is not None:
            given = [f"--{name.replace('_', '-')}" for name in _ONE_TEXTURE
                     if getattr(ctx.get_parameter_source(name), "name", "DEFAULT") != "DEFAULT"]
            if given:
                raise FingerpadError(f"--samples gives the textures: leave out {', '.join(given)}")
        parts = skin_modulus.split(":")
        if len(parts) != 2:
            raise FingerpadError(f"--skin-modulus: expected LOW:HIGH, got {skin_modulus!r}")
        e_range = tuple(parse_quantity(p, "pressure", name="--skin-modulus") for p in parts)
        if not 0 < e_range[0] <= e_range[1]:
            raise FingerpadError(f"--skin-modulus: need 0 < LOW <= HIGH, got {skin_modulus!r}")
        textures = _simulated_textures(samples, reference) if samples is not None else {texture: m.TextureGeometry(
            radius=parse_quantity(radius, "length", name="--radius"),
            height=parse_quantity(height, "length", name="--height"),
            spacing=parse_quantity(spacing, "length", name="--spacing"),
            full_contact_ratio=(_number(full_contact_ratio, "--full-contact-ratio", low=1.0 + 1e-9)
                                if full_contact_ratio else None),
            micro_model=micro_model,
        )}
        config = m.SimulationConfig(
            participants=parse_int(participants, "--participants"),
            repetitions=parse_int(repetitions, "--repetitions"),
            strokes_per_file=parse_int(strokes, "--strokes", minimum=2),
            load_range=_load_range(loads),
            reference=reference,
            textures=textures,
            skin_modulus_range=e_range,  # type: ignore[arg-type]
            sampling_rate=_number(sampling_rate, "--sampling-rate", low=1.0),
        )
        truth = m.simulate_study(out, config, seed=parse_int(seed, "--seed", minimum=0))
    from rich.console import Console

    console = Console(highlight=False, soft_wrap=True)
    for pid, p in truth["participants"].items():
        console.print(f"{pid}: E_s = {p['skin_modulus'] / 1e6:.3f} MPa, k = {p['k']:.3f}, n = {p['n']:.3f}")
    console.print(f"wrote {len(truth['files'])} recordings, manifest.csv, samples.csv and truth.json to {out}")


def _simulated_textures(path: str, reference: str) -> dict[str, Any]:
    """The textured samples of a sample table (:func:`~fingerpad.measure.read_textures`): every
    row but a flat one of the reference, which needs none."""
    from .. import measure as m

    table = m.read_textures(path)
    flat = [name for name, geom in table.items() if geom is None and name != reference]
    if flat:
        raise FingerpadError(f"{path}: sample {flat[0]!r} has no geometry (radius, height, spacing); a "
                             f"simulated texture needs them, and the flat reference is --reference ({reference!r})")
    textures = {name: geom for name, geom in table.items() if geom is not None}
    if not textures:
        raise FingerpadError(f"{path}: no textured sample (rows with radius, height and spacing)")
    return textures


def register(app: typer.Typer) -> None:
    """Add ``analyse`` and ``simulate-measurement`` to the Typer ``app``."""
    app.command("analyse")(analyse_command)
    app.command("simulate-measurement")(simulate_command)
