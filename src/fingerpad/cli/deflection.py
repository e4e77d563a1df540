"""``fingerpad deflection``: the section model of a compliant asperity under sliding.

The command parses its options, calls
:func:`~fingerpad.micro.deflection.gain.directional_gain` once per direction, prints a table
(contact length gain at a few shear levels, tip deflection, tangential stiffness, flags) and,
with ``--out``, writes ``deflection.json``, ``deflection.nc`` and ``deflection.png`` all or none.
User mistakes: one ``error:`` line on stderr, exit code 2.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Annotated, Any

import typer

from ..errors import FingerpadError

EXIT_USER_ERROR = 2
#: Shear levels of the printed table.
TABLE_MU = (0.3, 0.6, 1.0, 1.5)


def _length(text: str | None, name: str) -> float:
    from ..units import parse_positive

    if text is None:
        raise FingerpadError(f"--{name} is required for this texture")
    return parse_positive(text, "length", name=f"--{name}")


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


def _table(curves: list[Any]) -> str:
    """Per direction: the gains (one table), the ramp's state and flags (a second one) and why
    a ramp stopped (a line each), so that every line fits an 80-column terminal."""
    lines = []
    for c in curves:
        head = f"direction {c.direction_deg:g} deg"
        if c.is_identity:
            lines.append(f"{head}: gain 1 (rigid texture or no shear across the section)")
            continue
        s = c.section
        lines.append(f"{head}: half-width {s.half_width * 1e6:.4g} um, height {s.height * 1e6:.4g} um, "
                     f"period {s.period * 1e6:.4g} um, shear factor {c.shear_factor:.3g}")
        lines.append("  p (kPa)  " + "  ".join(f"G(mu={m:g})" for m in TABLE_MU) + "  mu reached")
        for r in c.ramps:
            g = [c(r.pressure, m) for m in TABLE_MU]
            lines.append(f"  {r.pressure / 1e3:7.3g}  " + "  ".join(f"{float(v):9.3f}" for v in g)
                         + f"  {r.mu_reached:10.3g}")
        lines.append("  p (kPa)  bend@max (um)  k_t0 (kPa)  fold@mu  limit@mu  buckled")
        for r in c.ramps:
            kt0 = r.tangential_stiffness[1] if r.tangential_stiffness.size > 1 else math.nan
            tip = r.bend_dx[-1] * 1e6 if r.bend_dx.size else math.nan
            lines.append(f"  {r.pressure / 1e3:7.3g}  {tip:13.3g}  {kt0 / 1e3:10.3g}  {r.fold_onset_mu:7.3g}  "
                         f"{r.limit_mu:8.3g}  {r.buckled}")
        for r in c.ramps:
            if r.stopped:
                lines += [f"  the ramp at {r.pressure / 1e3:.3g} kPa stopped:", f"    {r.stopped}"]
    return "\n".join(lines)


def deflection(
    texture: Annotated[str, typer.Option(help="ellipsoids or ridges (circular profile).")],
    height: Annotated[str, typer.Option(help="Asperity height, e.g. 50um.")],
    material_modulus: Annotated[str | None, typer.Option(help="Texture Young's modulus, e.g. 0.3MPa; omit for a rigid texture (gain 1).")] = None,
    semi_axis_x: Annotated[str | None, typer.Option(help="Ellipsoids: semi-axis along x.")] = None,
    semi_axis_y: Annotated[str | None, typer.Option(help="Ellipsoids: semi-axis along y.")] = None,
    spacing_x: Annotated[str | None, typer.Option(help="Ellipsoids: lattice period along x.")] = None,
    spacing_y: Annotated[str | None, typer.Option(help="Ellipsoids: lattice period along y.")] = None,
    orientation: Annotated[str, typer.Option(help="Ellipsoids: rotation of the ellipse, e.g. 30deg.")] = "0deg",
    width: Annotated[str | None, typer.Option(help="Ridges: base width.")] = None,
    spacing: Annotated[str | None, typer.Option(help="Ridges: period.")] = None,
    direction: Annotated[list[str] | None, typer.Option(help="Sliding direction(s), degrees from the texture's x axis (repeat; default 0 and 90).")] = None,
    pressure: Annotated[str, typer.Option(help="Nominal cell pressure P or range LOW:HIGH, e.g. 5kPa:40kPa.")] = "5kPa:40kPa",
    levels: Annotated[int, typer.Option(help="Pressure levels solved (log-spaced).")] = 3,
    mu_max: Annotated[float, typer.Option(help="Largest shear level followed.")] = 1.5,
    friction: Annotated[str, typer.Option(help="package (tau0 + alpha p shape) or coulomb.")] = "package",
    tau0: Annotated[str, typer.Option(help="Shear strength at zero pressure, Eq. 2.3.")] = "8.1kPa",
    alpha: Annotated[float, typer.Option(help="Pressure coefficient of the shear strength, Eq. 2.3.")] = 0.1,
    skin_modulus: Annotated[str, typer.Option(help="Skin Young's modulus E_s.")] = "0.3MPa",
    skin_poisson: Annotated[float, typer.Option(help="Skin Poisson ratio.")] = 0.49,
    material_poisson: Annotated[float, typer.Option(help="Texture Poisson ratio (0.5 is taken as 0.499).")] = 0.49,
    resolution: Annotated[int, typer.Option(help="Elements per asperity half-width.")] = 6,
    time_limit: Annotated[float, typer.Option(help="Wall-clock budget of one shear ramp, s.")] = 120.0,
    out: Annotated[Path | None, typer.Option(help="Folder for deflection.json, deflection.nc, deflection.png (replaced as a whole; a folder of other files is refused).")] = None,
    no_cache: Annotated[bool, typer.Option("--no-cache", help="Do not read or write the result cache.")] = False,
) -> None:
    """Contact length against shear of a compliant asperity section, per sliding direction.

    A finite-strain neo-Hookean section of one asperity on its base, pressed by the skin (an
    elastic half-space) and sheared in full sliding: contact length gain, tip deflection,
    tangential stiffness, fold-over onset, limit point and buckling flags. SI units; unit
    suffixes accepted (50um, 0.3MPa, 20kPa).
    """
    try:
        _run(**locals())
    except FingerpadError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(EXIT_USER_ERROR) from None


def _run(**o: Any) -> None:
    from ..materials import Materials, check_poisson
    from ..units import parse_positive, parse_quantity
    from ..micro.deflection.gain import DeflectionSettings, as_dataset, directional_gain
    from ..micro.deflection.section import EllipsoidGeometry, RidgeGeometry

    kind = str(o["texture"]).strip().lower()
    h = _length(o["height"], "height")
    if kind == "ellipsoids":
        geometry: Any = EllipsoidGeometry(
            _length(o["semi_axis_x"], "semi-axis-x"), _length(o["semi_axis_y"], "semi-axis-y"), h,
            _length(o["spacing_x"], "spacing-x"), _length(o["spacing_y"], "spacing-y"),
            parse_quantity(o["orientation"], "angle", name="--orientation"))
        c, sn = math.cos(geometry.orientation), math.sin(geometry.orientation)
        ex = 2 * math.hypot(geometry.semi_axis_x * c, geometry.semi_axis_y * sn)
        ey = 2 * math.hypot(geometry.semi_axis_x * sn, geometry.semi_axis_y * c)
        if ex > geometry.spacing_x * (1 + 1e-9) or ey > geometry.spacing_y * (1 + 1e-9):
            raise FingerpadError("ellipsoids overlap: the footprint extent exceeds the spacing")
    elif kind == "ridges":
        geometry = RidgeGeometry(_length(o["width"], "width"), h, _length(o["spacing"], "spacing"))
        if geometry.width > geometry.spacing:
            raise FingerpadError("ridge width exceeds the ridge spacing")
    else:
        raise FingerpadError(f"--texture must be ellipsoids or ridges, got {o['texture']!r}")
    em = None if o["material_modulus"] is None else parse_positive(o["material_modulus"], "pressure", name="--material-modulus")
    mats = Materials(skin_modulus=parse_positive(o["skin_modulus"], "pressure", name="--skin-modulus"),
                     skin_poisson=check_poisson(o["skin_poisson"], "--skin-poisson"),
                     material_modulus=em, material_poisson=check_poisson(o["material_poisson"], "--material-poisson"))
    dirs = [parse_quantity(d, "none", name="--direction") for d in (o["direction"] or ["0", "90"])]
    if not all(math.isfinite(d) for d in dirs):
        raise FingerpadError("--direction must be finite angles in degrees")
    lo, hi = _pressure_range(o["pressure"])
    tau0 = parse_quantity(o["tau0"], "pressure", name="--tau0")
    if tau0 < 0 or not (o["alpha"] >= 0):
        raise FingerpadError("--tau0 and --alpha must be non-negative")
    settings = DeflectionSettings(friction=o["friction"], mu_max=o["mu_max"], n_pressures=o["levels"],
                                  resolution=o["resolution"], time_limit=o["time_limit"])
    out = o["out"]
    if out is not None:
        from ..io import OutputFolder

        OutputFolder.check(out, _FILES)  # before the work: a bad --out costs nothing

    def progress(msg: str) -> None:
        print(f"  {msg}", file=sys.stderr, flush=True)

    curves = []
    for d in dirs:
        print(f"direction {d:g} deg", file=sys.stderr, flush=True)
        curves.append(directional_gain(geometry, mats, d, (lo, hi), tau0=tau0, alpha=o["alpha"], settings=settings,
                                       cache=not o["no_cache"], progress=progress))
    typer.echo(_table(curves))
    if out is None:
        return
    from ..io import OutputFolder, write_text
    from ..plotting.deflection import deflection_figure

    doc = {"texture": kind, "geometry": {k: getattr(geometry, k) for k in geometry.__dataclass_fields__},
           "materials": mats.as_dict(), "tau0": tau0, "alpha": o["alpha"],
           "settings": {k: getattr(settings, k) for k in settings.__dataclass_fields__},
           "units": "SI (m, Pa, N/m per unit depth); directions in degrees",
           "directions": [c.as_dict() for c in curves]}
    text = json.dumps(doc, indent=1, default=lambda v: None if isinstance(v, float) and not math.isfinite(v) else str(v))
    with OutputFolder(out, _FILES) as folder:  # replaced as a whole; errors name the user's path
        folder.write("deflection.json", lambda tmp: write_text(tmp, text))
        folder.write("deflection.nc", lambda tmp: as_dataset(curves).to_netcdf(tmp, engine="h5netcdf"))
        folder.write("deflection.png", lambda tmp: deflection_figure(curves, tmp))
        folder.commit()
    typer.echo(f"wrote {out / 'deflection.json'}, {out / 'deflection.nc'}, {out / 'deflection.png'}")


#: The files of ``--out`` (a folder holding only these, or written by fingerpad, is replaced).
_FILES = ("deflection.json", "deflection.nc", "deflection.png")


def register(app: typer.Typer) -> None:
    """Add ``fingerpad deflection`` to ``app``."""
    app.command("deflection")(deflection)


__all__ = ["deflection", "register"]
