"""``fingerpad fingers`` (the finger presets) and ``fingerpad finger-models`` (ridge-area models)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import typer

from ..errors import FingerpadError
from .common import say, stdout_console, user_errors


def fingers_command() -> None:
    """List the finger presets and their parameters (use them with --finger NAME)."""
    from rich.table import Table

    from ..finger import FINGER_PRESETS
    from ..units import format_quantity

    table = Table(title="finger presets: fingerpad predict --finger NAME [--finger-param NAME=VALUE]",
                  show_lines=True)
    for col in ("preset", "R_fp", "E_fp*", "gross area", "ridge area", "E_s", "nu_s", "tau0", "alpha", "beta"):
        table.add_column(col, no_wrap=col not in ("gross area", "ridge area"))
    for name, f in FINGER_PRESETS.items():
        table.add_row(
            f"{name}\n{f.description}", format_quantity(f.radius, "length"), format_quantity(f.modulus, "pressure"),
            repr(f.gross_model), repr(f.ridges), format_quantity(f.skin_modulus, "pressure"), f"{f.skin_poisson:g}",
            format_quantity(f.tau0, "pressure"), f"{f.alpha:g}", f"{f.beta:g}",
        )
    console = stdout_console(160)
    if console.width >= 130:
        console.print(table)
    else:  # a narrow terminal: one block per preset
        for name, f in FINGER_PRESETS.items():
            say(console, f"{name}: {f.description}")
            say(console, f"  R_fp {format_quantity(f.radius, 'length')}, E_fp* {format_quantity(f.modulus, 'pressure')}, "
                         f"E_s {format_quantity(f.skin_modulus, 'pressure')}, nu_s {f.skin_poisson:g}, "
                         f"tau0 {format_quantity(f.tau0, 'pressure')}, alpha {f.alpha:g}, beta {f.beta:g}")
            say(console, f"  gross area: {f.gross_model!r}")
            say(console, f"  ridge area: {f.ridges!r}")
    say(console, "R_fp pad radius, E_fp* pad reduced modulus (Eqs. 2.4-2.5), E_s/nu_s micro-scale skin modulus and "
                 "Poisson ratio (Eq. 3.4), tau0 + alpha p interfacial shear strength (Eq. 2.3), beta hysteresis loss "
                 "fraction (Eq. 2.4).")


def finger_models(
    out: Annotated[str, typer.Option("--out", metavar="DIR", help="Output directory (created if missing).")] = "out",
    loads: Annotated[
        str, typer.Option("--loads", metavar="START:STOP:COUNT", help="Log-spaced load range.")
    ] = "0.1N:4N:30",
    finger: Annotated[str | None, typer.Option(
        "--finger", metavar="PRESET",
        help="Take the pad radius, pad modulus and ridge geometry from a finger preset (default: the inputs of "
             "the thesis' Fig. 2.4, E_skin = 100 kPa, R_fp = 9 mm).")] = None,
) -> None:
    """Compare the ridge-area models (idea of the thesis Fig. 2.4) in DIR/ridge_models.png."""
    from ..units import parse_range

    with user_errors():
        values = parse_range(loads, "force", name="--loads", log=True)
        if min(values) <= 0:
            raise FingerpadError("--loads: loads must be positive")
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
            from ..meso.ridges import SinusoidalRidges

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
