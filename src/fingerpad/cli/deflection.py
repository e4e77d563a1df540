"""``fingerpad deflection``: the section model of a compliant asperity under sliding.

The command parses its options, calls :func:`~fingerpad.micro.deflection.job.run_deflection`
once, prints its table (contact length gain at a few shear levels, ``*`` where held, tip
deflection, tangential stiffness, flags) and, with ``--out``, writes ``deflection.json``,
``deflection.nc`` and ``deflection.png`` all or none. User mistakes: one ``error:`` line on
stderr, exit code 2.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Annotated, Any

import typer

from ..errors import FingerpadError
from .common import user_errors

#: The texture options of the command, by the families' keyword names.
_TEXTURE_OPTIONS = ("semi_axis_x", "semi_axis_y", "spacing_x", "spacing_y", "orientation", "width", "spacing")


def _pressure_range(text: str) -> tuple[float, float]:
    from ..units import parse_positive

    parts = text.split(":")
    if len(parts) == 1:
        p = parse_positive(parts[0], "pressure", name="--pressure")
        return p, p
    if len(parts) != 2:
        raise FingerpadError(f"--pressure: expected P or LOW:HIGH (e.g. 5kPa:40kPa), got {text!r}")
    lo, hi = (parse_positive(t, "pressure", name="--pressure") for t in parts)
    if lo > hi:
        raise FingerpadError(f"--pressure: LOW must not exceed HIGH, got {text!r}")
    return lo, hi


def deflection(
    texture: Annotated[str, typer.Option(help="A texture family with a deflection model: ellipsoids or ridges (circular profile).")],
    height: Annotated[str, typer.Option(help="Asperity height, e.g. 50um.")],
    material_modulus: Annotated[str | None, typer.Option(help="Texture Young's modulus, e.g. 0.3MPa; omit for a rigid texture (gain 1).")] = None,
    semi_axis_x: Annotated[str | None, typer.Option(help="Ellipsoids: semi-axis along x.")] = None,
    semi_axis_y: Annotated[str | None, typer.Option(help="Ellipsoids: semi-axis along y.")] = None,
    spacing_x: Annotated[str | None, typer.Option(help="Ellipsoids: lattice period along x.")] = None,
    spacing_y: Annotated[str | None, typer.Option(help="Ellipsoids: lattice period along y.")] = None,
    orientation: Annotated[str | None, typer.Option(help="Ellipsoids: rotation of the ellipse, e.g. 30deg (default 0).")] = None,
    width: Annotated[str | None, typer.Option(help="Ridges: base width.")] = None,
    spacing: Annotated[str | None, typer.Option(help="Ridges: period.")] = None,
    direction: Annotated[list[str] | None, typer.Option(help="Sliding direction(s), degrees from the texture's x axis (repeat; default 0 and 90).")] = None,
    pressure: Annotated[str, typer.Option(help="Nominal cell pressure P or range LOW:HIGH, e.g. 5kPa:40kPa.")] = "5kPa:40kPa",
    levels: Annotated[int, typer.Option(help="Pressure levels solved (log-spaced), 1-20.")] = 3,
    mu_max: Annotated[float, typer.Option(help="Largest shear level followed, in (0, 5].")] = 1.5,
    friction: Annotated[str, typer.Option(help="package (tau0 + alpha p shape) or coulomb.")] = "package",
    tau0: Annotated[str, typer.Option(help="Shear strength at zero pressure, Eq. 2.3.")] = "8.1kPa",
    alpha: Annotated[float, typer.Option(help="Pressure coefficient of the shear strength, Eq. 2.3, in [0, 10].")] = 0.1,
    skin_modulus: Annotated[str, typer.Option(help="Skin Young's modulus E_s.")] = "0.3MPa",
    skin_poisson: Annotated[float, typer.Option(help="Skin Poisson ratio.")] = 0.49,
    material_poisson: Annotated[float | None, typer.Option(help="Texture Poisson ratio (default 0.35, the package's material default, as predict; silicone: give 0.49; 0.5 is taken as 0.499).")] = None,
    resolution: Annotated[int, typer.Option(help="Elements per asperity half-width, 2-32.")] = 6,
    max_steps: Annotated[int, typer.Option(help="Largest number of shear steps per ramp (deterministic).")] = 300,
    time_limit: Annotated[float | None, typer.Option(help="Optional wall-clock safety stop per shear ramp, s (default: none); a ramp it cuts is marked INCOMPLETE and never cached.")] = None,
    out: Annotated[Path | None, typer.Option(help="Folder for deflection.json, deflection.nc, deflection.png (replaced as a whole; a folder of other files is refused).")] = None,
    no_cache: Annotated[bool, typer.Option("--no-cache", help="Do not read or write the result cache.")] = False,
) -> None:
    """Contact length against shear of a compliant asperity section, per sliding direction.

    A finite-strain neo-Hookean section of one asperity on its base, pressed by the skin (an
    elastic half-space) and sheared in full sliding: contact length gain, tip deflection,
    tangential stiffness, fold-over onset, limit point and buckling flags. SI units; unit
    suffixes accepted (50um, 0.3MPa, 20kPa).
    """
    options = dict(locals())
    with user_errors():  # one error: line (escaped, bounded), and --out held from its check to the end
        _run(**options)


def _run(**o: Any) -> None:
    from ..materials import Materials, check_poisson
    from ..micro.deflection.gain import DeflectionSettings
    from ..micro.deflection.job import run_deflection
    from ..units import parse_positive, parse_quantity

    height = o["height"]
    params = {"height": height, **{k: o[k] for k in _TEXTURE_OPTIONS if o[k] is not None}}
    em = None if o["material_modulus"] is None else parse_positive(o["material_modulus"], "pressure", name="--material-modulus")
    given = {} if o["material_poisson"] is None else {
        "material_poisson": check_poisson(o["material_poisson"], "--material-poisson")}
    mats = Materials(skin_modulus=parse_positive(o["skin_modulus"], "pressure", name="--skin-modulus"),
                     skin_poisson=check_poisson(o["skin_poisson"], "--skin-poisson"), material_modulus=em, **given)
    dirs = [parse_quantity(d, "none", name="--direction") for d in (o["direction"] or ["0", "90"])]
    lo, hi = _pressure_range(o["pressure"])
    tau0 = parse_quantity(o["tau0"], "pressure", name="--tau0")
    # every range is decided by the library (DeflectionSettings, run_deflection), once
    settings = DeflectionSettings(friction=o["friction"], mu_max=o["mu_max"], n_pressures=o["levels"],
                                  resolution=o["resolution"], max_steps=o["max_steps"], time_limit=o["time_limit"])
    out = o["out"]
    if out is not None:
        from ..io import OutputFolder

        OutputFolder.check(out, _FILES)  # before the work: a bad --out costs nothing

    def progress(msg: str) -> None:
        print(f"  {msg}", file=sys.stderr, flush=True)

    result = run_deflection(str(o["texture"]), params, mats, dirs, (lo, hi), tau0=tau0, alpha=o["alpha"],
                            settings=settings, cache=not o["no_cache"], progress=progress)
    typer.echo("\n".join(result.lines()))
    if result.incomplete:
        typer.echo("warning: INCOMPLETE: the --time-limit safety stop cut a ramp; not cached, not a result",
                   err=True)
    if out is None:
        return
    from ..io import OutputFolder, write_text
    from ..plotting.deflection import deflection_figure

    text = json.dumps(_finite(result.document()), indent=1, default=str, allow_nan=False)
    with OutputFolder(out, _FILES) as folder:  # replaced as a whole; errors name the user's path
        folder.write("deflection.json", lambda tmp: write_text(tmp, text))
        folder.write("deflection.nc", lambda tmp: result.dataset().to_netcdf(tmp, engine="h5netcdf"))
        folder.write("deflection.png", lambda tmp: deflection_figure(result.curves, tmp))
        folder.commit()
    typer.echo(f"wrote {out / 'deflection.json'}, {out / 'deflection.nc'}, {out / 'deflection.png'}")


#: The files of ``--out`` (a folder holding only these, or written by fingerpad, is replaced).
_FILES = ("deflection.json", "deflection.nc", "deflection.png")


def _finite(value: Any) -> Any:
    """NaN and infinities as JSON null (NaN is not JSON)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value


def register(app: typer.Typer) -> None:
    """Add ``fingerpad deflection`` to ``app``."""
    app.command("deflection")(deflection)


__all__ = ["deflection", "register"]
