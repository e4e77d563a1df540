"""``fingerpad fingers`` (the finger presets) and ``fingerpad finger-models`` (ridge-area models)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import typer

from ..errors import FingerpadError
from .common import say, say_wrapped, stdout_console, user_errors


def model_text(model: object, registry: dict[str, object]) -> str:
    """A pad or ridge model as a study file names it, with its values in their units
    (``hertz: R_fp 9 mm, E_fp* 40 kPa``), from the model's declaration (:class:`~fingerpad.params.Model`)."""
    decl = next((m for m in registry.values() if type(model) is m.factory), None)  # type: ignore[attr-defined]
    if decl is None:
        return type(model).__name__
    parts = [f"{p.symbol or p.name} {p.format(getattr(model, p.name))}" for p in decl.params  # type: ignore[attr-defined]
             if getattr(model, p.name, None) is not None]
    return f"{decl.name}: {', '.join(parts)}" if parts else decl.name  # type: ignore[attr-defined]


def fingers_command() -> None:
    """List the finger presets, the finger's parameters and the pad and ridge models (with their
    parameters, units and defaults); use them with --finger NAME and --finger-param NAME=VALUE."""
    from rich.markup import escape
    from rich.table import Table

    from ..finger import FINGER_PARAMS, FINGER_PRESETS, LAYER_FIELDS, RIDGE_FRACTION
    from ..macro import GROSS_MODELS
    from ..meso import RIDGE_MODELS

    def head(p: object) -> str:
        return f"{p.symbol or p.name}"  # type: ignore[attr-defined]

    # the layer's fields are shown in the skin column (a half-space skin has none)
    shown = [p for p in FINGER_PARAMS if p.name not in (*LAYER_FIELDS, "skin_base")]
    by_name = {p.name: p for p in FINGER_PARAMS}

    def cell(f: object, p: object) -> str:
        value = getattr(f, p.name)  # type: ignore[attr-defined]
        if p.name != "skin" or value != "layered":  # type: ignore[attr-defined]
            return p.format(value)  # type: ignore[attr-defined]
        parts = [f"{by_name[n].symbol} {by_name[n].format(getattr(f, n))}" for n in LAYER_FIELDS
                 if getattr(f, n) is not None]
        return "layered: " + ", ".join(parts) + ("" if f.skin_base == "elastic" else f", {f.skin_base} base")  # type: ignore[attr-defined]

    table = Table(title="finger presets: fingerpad predict --finger NAME [--finger-param NAME=VALUE]",
                  show_lines=True)
    table.add_column("preset")
    for p in shown:
        table.add_column(head(p), no_wrap=p.name != "skin")
    table.add_column("gross area", overflow="fold")
    table.add_column("ridge area", overflow="fold")
    for name, f in FINGER_PRESETS.items():
        table.add_row(f"{name}\n{f.description}", *(cell(f, p) for p in shown),
                      escape(model_text(f.gross_model, GROSS_MODELS)), escape(model_text(f.ridges, RIDGE_MODELS)))
    console = stdout_console(160)
    if console.width >= 130:
        console.print(table)
    else:  # a narrow terminal: one block per preset
        for name, f in FINGER_PRESETS.items():
            say_wrapped(console, f"{name}: {f.description}")
            # a finger without adhesion: its range and law say nothing
            own = [p for p in shown if f.work_of_adhesion > 0 or p.name not in ("adhesion_range", "adhesion_law")]
            say_wrapped(console, "  " + ", ".join(f"{head(p)} {cell(f, p)}" for p in own))
            say_wrapped(console, f"  gross area: {model_text(f.gross_model, GROSS_MODELS)}")
            say_wrapped(console, f"  ridge area: {model_text(f.ridges, RIDGE_MODELS)}")
    say(console, "")
    say_wrapped(console, "finger parameters (--finger-param NAME=VALUE, [finger] NAME = VALUE in a study file):")
    for p in FINGER_PARAMS:
        bounds = f", {p.bounds_text()}" if p.bounds_text() else ""
        say_wrapped(console, f"  {p.name} [{p.unit}]{bounds}: {head(p)}, {p.doc}")
    say_wrapped(console, f"  {RIDGE_FRACTION.name} [{RIDGE_FRACTION.unit}], {RIDGE_FRACTION.bounds_text()}: --finger-param "
                         "only, the constant-fraction ridge model with this A_fr/A_g (replaces the finger's ridge model)")
    for title, key, registry in (("pad (gross-area) models", "gross", GROSS_MODELS),
                                 ("ridge-area models", "ridges", RIDGE_MODELS)):
        say(console, "")
        say_wrapped(console, f"{title} ([finger] {key} = {{ model = NAME, PARAM = VALUE }} in a study file):")
        for model in registry.values():
            say_wrapped(console, f"  {model.name}: {model.summary}")
            for p in model.params:
                unit = f" [{p.unit}]" if p.unit else ""
                default = p.default_text()
                if p.name in model.inherits:
                    default = "the finger's" if model.inherits[p.name].startswith("finger.") else \
                        "the study's largest load" if model.inherits[p.name] == "loads.max" else default
                choices = f" ({' | '.join(p.choices)})" if p.choices else ""
                say_wrapped(console, f"    {p.name}{unit}, {default}: {p.doc}{choices}")


def finger_models(
    out: Annotated[str, typer.Option("--out", metavar="DIR", help="Output directory (created if missing).")] = "out",
    loads: Annotated[
        str, typer.Option("--loads", metavar="START:STOP:COUNT", help="Log-spaced load range START:STOP:COUNT, one load or a comma list.")
    ] = "0.1N:4N:30",
    finger: Annotated[str | None, typer.Option(
        "--finger", metavar="PRESET",
        help="Take the pad radius, pad modulus and ridge geometry from a finger preset (default: the inputs of "
             "the thesis' Fig. 2.4, E_skin = 100 kPa, R_fp = 9 mm).")] = None,
) -> None:
    """Compare the ridge-area models (idea of the thesis Fig. 2.4) in DIR/ridge_models.png."""
    from ..study.values import parse_loads

    with user_errors():
        values = [float(v) for v in parse_loads(loads, True, "--loads")]  # the loads' one rule (cap, sign)
        from ..io import check_output_location, check_writable

        check_output_location(out, "--out", replaces=False)  # only adds ridge_models.png: '.' is fine
        out_dir = Path(out)
        if out_dir.exists() and not out_dir.is_dir():
            raise FingerpadError(f"--out {out!r} exists and is not a directory")
        if out_dir.is_dir():
            check_writable(out_dir / "ridge_models.png", "--out")
        inputs: dict[str, object] = {}
        if finger is not None:
            from ..finger import get_finger
            from ..meso.sinusoidal import SinusoidalRidges

            f = get_finger(finger)
            inputs = {"skin_modulus": f.modulus, "radius": f.radius, "source": f"finger preset {f.name!r}"}
            if isinstance(f.ridges, SinusoidalRidges):
                inputs.update(wavelength=f.ridges.wavelength, amplitude=f.ridges.amplitude)
        out_dir.mkdir(parents=True, exist_ok=True)
        from ..plotting.ridges import ridge_models_figure

        path = ridge_models_figure(out_dir / "ridge_models.png", values, **inputs)
        sys.stderr.write(f"wrote {path}\n")


def register(app: typer.Typer) -> None:
    app.command("fingers")(fingers_command)
    app.command("finger-models")(finger_models)
