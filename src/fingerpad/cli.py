"""The ``fingerpad`` command line.

Commands
--------
``fingerpad solve``
    Solve the skin/texture contact on one unit cell at one or more mean pressures.
``fingerpad textures``
    List the texture generators and their parameters.
``fingerpad run-default``
    Solve a default texture over a log range of pressures and write ``solve.json``,
    ``solve.nc`` and ``solve.png`` into ``--out`` (the target of ``make run``).

Every quantity accepts plain SI numbers or unit suffixes (``50um``, ``0.3MPa``, ``20kPa``).

Exit codes
----------
0
    Success.
1
    Every solve ran and all outputs were written, but at least one solve did not reach its
    tolerance (a warning names it; ``"converged": false`` in the JSON).
2
    A user error (bad option value, unknown unit, unreadable file, ...): one line
    ``error: <message>`` on stderr, nothing written.
"""

from __future__ import annotations

import contextlib
import inspect
import json
import math
import os
import pickle
import sys
import uuid
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Annotated, Any

import typer

from . import __version__
from .errors import FingerpadError
from .materials import DEFAULT_SKIN_MODULUS, DEFAULT_SKIN_POISSON, check_modulus, check_poisson, reduced_modulus
from .units import UNITS, format_quantity, parse_positive, parse_quantity, parse_range

EXIT_UNCONVERGED = 1
EXIT_USER_ERROR = 2

app = typer.Typer(
    name="fingerpad",
    help="Finger-pad contact on micro-textured surfaces (SI units; unit suffixes such as 50um, 0.3MPa accepted).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_show_locals=False,
)


# =============================================================================================
# Error and warning reporting
# =============================================================================================


def _one_line(text: str) -> str:
    return " ".join(part.strip() for part in str(text).splitlines() if part.strip()) or "unknown error"


def _describe_exception(exc: BaseException) -> str:
    if isinstance(exc, OSError) and not isinstance(exc, FingerpadError):
        what = exc.strerror or str(exc)
        return f"{what}: {exc.filename}" if exc.filename else what
    return str(exc)


@contextlib.contextmanager
def user_errors() -> Iterator[None]:
    """Turn user errors into ``error: <message>`` on one stderr line and exit code 2."""
    try:
        yield
    except (FingerpadError, OSError) as exc:
        sys.stderr.write(f"error: {_one_line(_describe_exception(exc))}\n")
        sys.stderr.flush()
        raise typer.Exit(EXIT_USER_ERROR) from None


def _stderr_console():
    from rich.console import Console

    return Console(file=sys.stderr, soft_wrap=True, highlight=False)


@contextlib.contextmanager
def _warnings_to(console: Any) -> Iterator[None]:
    """Show Python warnings as single ``warning: ...`` lines on ``console`` (stderr)."""
    seen: set[str] = set()

    def show(message, category, filename, lineno, file=None, line=None):  # noqa: ANN001
        text = f"warning: {_one_line(str(message))}"
        if text not in seen:
            seen.add(text)
            console.print(text, markup=False, highlight=False, soft_wrap=True)

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.filterwarnings("ignore", category=DeprecationWarning)
        warnings.filterwarnings("ignore", category=PendingDeprecationWarning)
        # SurfaceTopography's MPI layer announces its serial fallback on import: not for users.
        warnings.filterwarnings("ignore", message=".*mpi4py")
        warnings.showwarning = show
        yield


# =============================================================================================
# Parsing helpers (all values arrive as text so that every mistake is a one-line FingerpadError)
# =============================================================================================


def _parse_int(text: str, name: str, minimum: int = 1) -> int:
    try:
        value = int(str(text).strip())
    except ValueError:
        raise FingerpadError(f"{name}: expected an integer, got {text!r}") from None
    if value < minimum:
        raise FingerpadError(f"{name}: must be at least {minimum}, got {value}")
    return value


def _parse_float(text: str, name: str) -> float:
    return parse_quantity(text, "none", name=name)


def _parse_size(text: str) -> tuple[float, float]:
    parts = [p for p in str(text).split(",")]
    if len(parts) not in (1, 2) or any(not p.strip() for p in parts):
        raise FingerpadError(f"--size: expected LX or LX,LY, got {text!r}")
    values = [parse_positive(p, "length", name="--size") for p in parts]
    return (values[0], values[-1])


def _parse_pressures(texts: Sequence[str], log: bool) -> list[float]:
    pressures: list[float] = []
    for text in texts:
        for value in parse_range(text, "pressure", name="--pressure", log=log):
            if not (math.isfinite(value) and value > 0):
                raise FingerpadError(f"--pressure: must be positive, got {text!r}")
            pressures.append(value)
    if not pressures:
        raise FingerpadError("give at least one --pressure (e.g. --pressure 20kPa or --pressure 1kPa:100kPa:10 --log)")
    return pressures


# --------------------------------------------------------------------------------------------
# materials


@dataclass
class MaterialsSpec:
    modulus: float  # reduced modulus E* (Pa)
    skin_modulus: float | None = None
    skin_poisson: float | None = None
    material_modulus: float | None = None  # None: rigid
    material_poisson: float | None = None

    def as_dict(self) -> dict[str, Any]:
        return {
            "reduced_modulus": self.modulus,
            "skin_modulus": self.skin_modulus,
            "skin_poisson": self.skin_poisson,
            "material_modulus": self.material_modulus,
            "material_poisson": self.material_poisson,
            "material_rigid": self.skin_modulus is not None and self.material_modulus is None,
        }


def parse_materials(
    modulus: str | None,
    skin_modulus: str | None,
    skin_poisson: str | None,
    material_modulus: str | None,
    material_poisson: str | None,
) -> MaterialsSpec:
    """Either ``--modulus`` (reduced E*) or the skin/material constants (Eq. 3.4), never both."""
    others = {
        "--skin-modulus": skin_modulus,
        "--skin-poisson": skin_poisson,
        "--material-modulus": material_modulus,
        "--material-poisson": material_poisson,
    }
    given = [k for k, v in others.items() if v is not None]
    if modulus is not None:
        if given:
            raise FingerpadError(
                f"give either --modulus (the reduced modulus E*) or {', '.join(given)}, not both"
            )
        e = parse_quantity(modulus, "pressure", name="--modulus")
        check_modulus(e, "--modulus")
        return MaterialsSpec(modulus=e)
    es = DEFAULT_SKIN_MODULUS if skin_modulus is None else parse_quantity(skin_modulus, "pressure", name="--skin-modulus")
    check_modulus(es, "--skin-modulus")
    nus = DEFAULT_SKIN_POISSON if skin_poisson is None else _parse_float(skin_poisson, "--skin-poisson")
    check_poisson(nus, "--skin-poisson")
    em: float | None = None
    num: float | None = None
    if material_modulus is not None and material_modulus.strip().lower() not in ("rigid", "inf", "infinity"):
        em = parse_quantity(material_modulus, "pressure", name="--material-modulus")
        check_modulus(em, "--material-modulus")
        num = 0.35 if material_poisson is None else _parse_float(material_poisson, "--material-poisson")
        check_poisson(num, "--material-poisson")
    elif material_poisson is not None:
        raise FingerpadError("--material-poisson needs --material-modulus (the default material is rigid)")
    e_star = reduced_modulus(es, nus, em, num if num is not None else 0.35)
    return MaterialsSpec(modulus=e_star, skin_modulus=es, skin_poisson=nus, material_modulus=em, material_poisson=num)


# --------------------------------------------------------------------------------------------
# texture parameters given as extra options


_ANGLE_NAMES = {"orientation", "angle", "rotation", "theta", "phi", "direction"}
_INT_NAMES = {"n", "nx", "ny", "grid", "count", "seed", "points", "resolution", "harmonics"}
_DIMENSIONLESS_NAMES = {"fraction", "ratio", "aspect", "aspect_ratio", "fill", "fill_fraction", "exponent",
                        "duty", "duty_cycle", "coverage", "density"}
_STR_NAMES = {"lattice", "profile", "shape", "kind", "pattern", "mode", "name"}
_GRID_NAMES = ("grid", "n", "resolution", "points", "nx")


def _annotation_text(annotation: Any) -> str:
    if annotation is inspect.Parameter.empty:
        return ""
    return annotation if isinstance(annotation, str) else getattr(annotation, "__name__", str(annotation))


def param_kind(name: str, param: inspect.Parameter | None = None) -> str:
    """How a generator parameter is read from the command line:
    ``length``, ``angle``, ``pressure``, ``none`` (plain float), ``int``, ``bool``, ``str``,
    or ``lengths`` (a comma-separated tuple of lengths)."""
    default = param.default if param is not None else inspect.Parameter.empty
    ann = _annotation_text(param.annotation) if param is not None else ""
    if isinstance(default, bool) or ann.startswith("bool"):
        return "bool"
    if isinstance(default, str) or ann in ("str", "str | None", "Literal") or ann.startswith("Literal"):
        return "str"
    if name in _STR_NAMES:
        return "str"
    if isinstance(default, tuple) or ann.startswith("tuple") or ann.startswith("Sequence"):
        return "lengths"
    if name in _ANGLE_NAMES or name.endswith("_angle") or name.endswith("_deg"):
        return "angle"
    if (isinstance(default, int) and not isinstance(default, bool)) or ann in ("int", "int | None") or name in _INT_NAMES:
        return "int"
    if name in _DIMENSIONLESS_NAMES or name.endswith("_fraction") or name.endswith("_ratio"):
        return "none"
    if name.endswith("modulus") or name.endswith("pressure"):
        return "pressure"
    return "length"


def parse_param_value(name: str, text: str, kind: str) -> Any:
    label = "--" + name.replace("_", "-")
    if kind == "str":
        return text
    if kind == "bool":
        low = text.strip().lower()
        if low in ("1", "true", "yes", "on"):
            return True
        if low in ("0", "false", "no", "off"):
            return False
        raise FingerpadError(f"{label}: expected true or false, got {text!r}")
    if kind == "int":
        return _parse_int(text, label, minimum=-(2**62))
    if kind == "lengths":
        parts = str(text).split(",")
        return tuple(parse_quantity(p, "length", name=label) for p in parts)
    if "," in str(text):
        return tuple(parse_quantity(p, kind, name=label) for p in str(text).split(","))
    return parse_quantity(text, kind, name=label)


def split_extra_options(args: Sequence[str]) -> list[tuple[str, str]]:
    """``["--radius", "50um", "--lattice=hex"]`` -> ``[("radius", "50um"), ("lattice", "hex")]``."""
    pairs: list[tuple[str, str]] = []
    i = 0
    args = list(args)
    while i < len(args):
        token = args[i]
        if not token.startswith("--") or len(token) <= 2:
            raise FingerpadError(f"unexpected argument {token!r} (texture parameters are given as --NAME VALUE)")
        body = token[2:]
        if "=" in body:
            key, value = body.split("=", 1)
            i += 1
        else:
            key = body
            if i + 1 >= len(args) or args[i + 1].startswith("--"):
                raise FingerpadError(f"option {token} needs a value")
            value = args[i + 1]
            i += 2
        pairs.append((key.replace("-", "_"), value))
    return pairs


def _generators() -> dict[str, Callable[..., Any]]:
    from . import textures

    gens = getattr(textures, "GENERATORS", None)
    if not gens:
        raise FingerpadError("no texture generators available in this version of fingerpad")
    return dict(gens)


def _signature(fn: Callable[..., Any]) -> dict[str, inspect.Parameter]:
    try:
        return dict(inspect.signature(fn).parameters)
    except (TypeError, ValueError):
        return {}


def generator_params(fn: Callable[..., Any]) -> dict[str, inspect.Parameter]:
    """Keyword parameters of a generator (no ``*args``/``**kwargs``)."""
    return {
        k: p
        for k, p in _signature(fn).items()
        if p.kind in (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY)
    }


def _accepts_any_kwargs(fn: Callable[..., Any]) -> bool:
    return any(p.kind is inspect.Parameter.VAR_KEYWORD for p in _signature(fn).values())


def build_texture_params(
    name: str, extra: Sequence[str], grid: int | None = None, size: tuple[float, float] | None = None
) -> tuple[Callable[..., Any], dict[str, Any]]:
    """Generator and its keyword arguments (SI) from ``--texture NAME`` and the extra options."""
    gens = _generators()
    key = name.strip().lower()
    if key not in gens:
        raise FingerpadError(f"unknown texture {name!r} (choose from: {', '.join(sorted(gens))})")
    fn = gens[key]
    params = generator_params(fn)
    anykw = _accepts_any_kwargs(fn)
    kwargs: dict[str, Any] = {}
    for pname, text in split_extra_options(extra):
        if pname not in params and not anykw:
            known = ", ".join("--" + k.replace("_", "-") for k in params if k not in _GRID_NAMES) or "none"
            raise FingerpadError(f"texture {key!r} has no parameter --{pname.replace('_', '-')} (its parameters: {known})")
        if pname in kwargs:
            raise FingerpadError(f"texture parameter --{pname.replace('_', '-')} given twice")
        kwargs[pname] = parse_param_value(pname, text, param_kind(pname, params.get(pname)))
    if grid is not None:
        gname = next((g for g in _GRID_NAMES if g in params), None)
        if gname is None:
            if not anykw:
                raise FingerpadError(f"texture {key!r} takes no grid size")
            gname = "grid"
        if gname in kwargs:
            raise FingerpadError(f"give the grid size once (--grid), not as --{gname}")
        kwargs[gname] = grid
    if size is not None:
        if "size" not in params and not anykw:
            raise FingerpadError(
                f"--size applies to --surface files; texture {key!r} sets its own cell size from its parameters"
            )
        kwargs["size"] = size
    return fn, kwargs


def make_generated_texture(name: str, extra: Sequence[str], grid: int | None, size: tuple[float, float] | None):
    """Build a generated texture from ``--texture NAME`` and its ``--PARAM VALUE`` options."""
    from . import textures

    fn, kwargs = build_texture_params(name, extra, grid, size)
    missing = [
        "--" + k.replace("_", "-")
        for k, p in generator_params(fn).items()
        if p.default is inspect.Parameter.empty and k not in kwargs
    ]
    if missing:
        raise FingerpadError(f"texture {name.strip().lower()!r} needs {', '.join(missing)}")
    maker = getattr(textures, "make_texture", None)
    if maker is not None:
        return maker(name.strip().lower(), **kwargs)
    return fn(**kwargs)


_PLAIN_FORMATS = {".npy", ".txt", ".csv", ".dat", ".asc", ".tsv"}


def read_surface_file(
    path: str, size: tuple[float, float] | None, height_unit: str | None, periodic: bool,
    fill_missing: bool = False,
):
    """Read a measured or designed height map (see :func:`fingerpad.textures.read_surface`)."""
    from . import textures

    p = Path(path)
    if not p.exists():
        raise FingerpadError(f"cannot read surface {path!r}: no such file")
    if p.is_dir():
        raise FingerpadError(f"cannot read surface {path!r}: it is a directory")
    if not os.access(p, os.R_OK):
        raise FingerpadError(f"cannot read surface {path!r}: permission denied")
    if p.suffix.lower() in _PLAIN_FORMATS:
        missing = [opt for opt, v in (("--size", size), ("--height-unit", height_unit)) if v is None]
        if missing:
            raise FingerpadError(
                f"surface {p.name!r} stores bare numbers: give {' and '.join(missing)} "
                "(e.g. --size 200um,200um --height-unit um)"
            )
    factor: float | None = None
    if height_unit is not None:
        unit = height_unit.strip()
        if unit not in UNITS or UNITS[unit][0] != "length":
            known = ", ".join(k for k, v in UNITS.items() if v[0] == "length")
            raise FingerpadError(f"--height-unit: unknown length unit {height_unit!r} (use one of: {known})")
        factor = UNITS[unit][1]
    reader = getattr(textures, "read_surface", None)
    if reader is None:
        raise FingerpadError("reading surface files is not available in this version of fingerpad")
    try:
        return reader(p, size=size, height_unit=factor, periodic=periodic, level=True, fill_missing=fill_missing)
    except FingerpadError as exc:
        # Name the command-line option rather than the Python keyword.
        text = str(exc).replace("pass fill_missing=True", "give --fill-missing")
        text = text.replace("pass size=(Lx, Ly) in metres", "give --size LX[,LY]")
        text = text.replace("pass height_unit", "give --height-unit")
        if text != str(exc):
            raise FingerpadError(text) from None
        raise
    except (OSError, ValueError, EOFError, pickle.UnpicklingError) as exc:
        raise FingerpadError(f"cannot read surface {path!r}: {_one_line(_describe_exception(exc))}") from None
    except Exception as exc:
        # SurfaceTopography's readers raise their own exception types on a bad file.
        if type(exc).__module__.split(".")[0] == "SurfaceTopography":
            raise FingerpadError(f"cannot read surface {path!r}: {_one_line(str(exc))}") from None
        raise


# =============================================================================================
# Solving and writing
# =============================================================================================


@dataclass
class SolveJob:
    texture: Any
    materials: MaterialsSpec
    pressures: list[float]
    tol: float = 1e-8
    max_iter: int = 5000
    formulation: str = "auto"
    texture_source: dict[str, Any] = field(default_factory=dict)
    json_path: str | None = None
    save_path: str | None = None
    plot_path: str | None = None
    plot_at: float | None = None  # mean pressure whose maps are plotted (nearest solved); None: last
    show_table: bool = True

    def inputs(self) -> dict[str, Any]:
        from . import textures

        tex = self.texture
        describe = getattr(textures, "describe", None)
        return {
            "texture": {
                "name": tex.name,
                "description": describe(tex) if describe is not None else tex.name,
                **self.texture_source,
                "params": dict(tex.params),
                "size": list(tex.size),
                "grid": list(tex.shape),
                "periodic": bool(tex.periodic),
            },
            "materials": self.materials.as_dict(),
            "modulus": self.materials.modulus,
            "pressures": list(self.pressures),
            "tol": self.tol,
            "max_iter": self.max_iter,
            "formulation": self.formulation,
            "fingerpad_version": __version__,
        }

    def netcdf_attrs(self) -> dict[str, Any]:
        m = self.materials.as_dict()
        attrs: dict[str, Any] = {k: v for k, v in m.items() if k != "reduced_modulus"}
        attrs.update(
            {
                "texture_source": self.texture_source.get("source", "generator"),
                "surface_file": self.texture_source.get("file"),
                "requested_pressures": list(self.pressures),
                "max_iter": self.max_iter,
                "requested_formulation": self.formulation,
                "command": " ".join(["fingerpad", *sys.argv[1:]]) if sys.argv else "fingerpad",
            }
        )
        return attrs


def _check_outputs(job: SolveJob) -> None:
    from .io import check_writable

    seen: dict[str, str] = {}
    for opt, path in (("--json", job.json_path), ("--save", job.save_path), ("--plot", job.plot_path)):
        if path is None or (opt == "--json" and path == "-"):
            continue
        key = os.path.abspath(path)
        if key in seen:
            raise FingerpadError(f"{opt} and {seen[key]} name the same file {path!r}")
        seen[key] = opt
        check_writable(path, opt)


class _Staging:
    """Write every output to a hidden temporary name first; move all into place at the end."""

    def __init__(self) -> None:
        self.staged: list[tuple[Path, Path]] = []

    def stage(self, final: str, write: Callable[[Path], Any]) -> None:
        target = Path(final)
        tmp = target.parent / f".{target.name}.{uuid.uuid4().hex[:8]}.part"
        self.staged.append((tmp, target))
        write(tmp)

    def commit(self) -> None:
        for tmp, target in self.staged:
            os.replace(tmp, target)
        self.staged.clear()

    def discard(self) -> None:
        for tmp, _ in self.staged:
            with contextlib.suppress(OSError):
                tmp.unlink()
        self.staged.clear()


def _solve_curve(job: SolveJob, err_console: Any):
    from .halfspace import HalfSpaceSolver
    from .unitcell import load_curve

    solver = HalfSpaceSolver(job.texture, job.materials.modulus, tol=job.tol, max_iter=job.max_iter,
                             formulation=job.formulation)
    n = len(job.pressures)
    if n == 1:
        return load_curve(solver, job.pressures)
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(
        TextColumn("solving"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(), console=err_console,
    ) as bar:
        task = bar.add_task("solve", total=n)

        def progress(i: int, total: int) -> None:
            bar.update(task, completed=min(i, total), total=total)

        curve = load_curve(solver, job.pressures, progress=progress)
        bar.update(task, completed=n)
    return curve


def _results_json(job: SolveJob, results: Sequence[Any]) -> dict[str, Any]:
    from .io import to_jsonable

    return to_jsonable(
        {
            "inputs": job.inputs(),
            "converged": all(bool(r.converged) for r in results),
            "results": [r.summary() for r in results],
        }
    )


def _print_table(results: Sequence[Any], texture: Any) -> None:
    from rich import box
    from rich.console import Console
    from rich.table import Table

    table = Table(
        title=f"{texture.name}: {texture.shape[0]}x{texture.shape[1]} px, "
              f"{format_quantity(texture.size[0], 'length')} x {format_quantity(texture.size[1], 'length')}"
              f"{'' if texture.periodic else ' (finite patch)'}",
        box=box.SIMPLE_HEAD,
    )
    columns = ("mean p", "psi", "A_re (m²)", "max p", "mean gap", "state", "iter", "conv", "time (s)")
    for col in columns:
        table.add_column(col, justify="left" if col == "state" else "right", no_wrap=True)
    for r in results:
        table.add_row(
            format_quantity(r.mean_pressure, "pressure", 3),
            f"{r.contact_fraction:.4f}",
            f"{r.real_contact_area:.3e}",
            format_quantity(r.max_pressure, "pressure", 3),
            format_quantity(r.mean_gap, "length", 3),
            str(r.contact_state),
            str(r.iterations),
            "yes" if r.converged else "NO",
            f"{r.seconds:.2f}",
        )
    console = Console(file=sys.stdout)
    if not console.is_terminal:  # piped or captured: do not squeeze the table into 80 columns
        console = Console(file=sys.stdout, width=max(console.width, 120))
    console.print(table)


def run_job(job: SolveJob) -> int:
    """Solve, write the outputs (all or none), report. Returns the exit code (0 or 1)."""
    from . import io as fio

    err = _stderr_console()
    _check_outputs(job)
    with _warnings_to(err):
        # Unconverged solves are reported below, once per pressure, with the exit code.
        warnings.filterwarnings("ignore", message="contact solve did not converge", category=RuntimeWarning)
        curve = _solve_curve(job, err)
    results = list(curve.results)
    payload = _results_json(job, results)
    staging = _Staging()
    try:
        if job.json_path is not None and job.json_path != "-":
            text = json.dumps(payload, indent=2) + "\n"
            staging.stage(job.json_path, lambda tmp: fio.write_text(tmp, text))
        if job.save_path is not None:
            attrs = job.netcdf_attrs()
            if len(results) == 1:
                staging.stage(job.save_path, lambda tmp: fio.save_result(results[0], tmp, attrs))
            else:
                staging.stage(job.save_path, lambda tmp: fio.save_load_curve(curve, tmp, attrs))
        if job.plot_path is not None:
            from .plotting import plot_solution

            index = -1
            if job.plot_at is not None:
                index = min(range(len(results)), key=lambda i: abs(math.log(results[i].mean_pressure / job.plot_at)))
            staging.stage(job.plot_path, lambda tmp: plot_solution(results, tmp, index=index))
        staging.commit()
    finally:
        staging.discard()
    if job.json_path == "-":
        sys.stdout.write(json.dumps(payload, indent=2) + "\n")
        sys.stdout.flush()
    elif job.show_table:
        _print_table(results, job.texture)
    bad = [r for r in results if not r.converged]
    for r in bad:
        err.print(
            f"warning: not converged at mean pressure {format_quantity(r.mean_pressure, 'pressure')} "
            f"(residual {r.residual:.3g} > tol {job.tol:.3g} after {r.iterations} iterations)",
            markup=False, highlight=False, soft_wrap=True,
        )
    if bad:
        err.print(f"warning: {len(bad)} of {len(results)} solves did not converge (exit code 1)",
                  markup=False, highlight=False, soft_wrap=True)
        return EXIT_UNCONVERGED
    return 0


# =============================================================================================
# Commands
# =============================================================================================

_EXTRA = {"allow_extra_args": True, "ignore_unknown_options": True}

_SURFACE, _MATERIALS, _LOADS, _NUMERICS, _OUTPUT = "Surface", "Materials", "Loads", "Numerics", "Output"

#: Help text of the `solve` options, by option name.
_HELP = {
    "--texture": "Texture generator (see `fingerpad textures`); its parameters follow as --NAME VALUE, "
                 "e.g. --radius 50um.",
    "--surface": "Height-map file instead of a generator (.npy, text, or a SurfaceTopography format).",
    "--size": "Physical size of the --surface map, e.g. 200um or 200um,150um.",
    "--height-unit": "Unit of the heights in a --surface file (m, mm, um, nm); required for .npy and text.",
    "--fill-missing": "Replace missing points (NaN) of a --surface map by the nearest valid height.",
    "--periodic": "Periodic unit cell (default: yes for generated textures, no for files).",
    "--grid": "Grid points along x, passed to the generator (default: the generator's choice).",
    "--modulus": "Reduced modulus E* of skin and material (Eq. 3.4), e.g. 0.4MPa. Excludes the skin/material "
                 "options.",
    "--skin-modulus": f"Skin Young's modulus (default {DEFAULT_SKIN_MODULUS / 1e6:g}MPa).",
    "--skin-poisson": f"Skin Poisson ratio (default {DEFAULT_SKIN_POISSON:g}).",
    "--material-modulus": "Counter-surface Young's modulus, or 'rigid' (default rigid).",
    "--material-poisson": "Counter-surface Poisson ratio (default 0.35).",
    "--pressure": "Mean nominal pressure over the cell; repeat it, or give a range START:STOP:COUNT.",
    "--log": "Log-spaced pressure ranges.",
    "--tol": "Relative residual at which a solve stops.",
    "--max-iter": "Iteration cap per solve.",
    "--formulation": "auto, primal (pressure unknowns) or dual (gap unknowns).",
    "--json": "Write results as JSON ('-' for stdout, which replaces the table).",
    "--save": "Write the fields (pressure, gap, displacement, contact, heights) to NetCDF.",
    "--plot": "Write pressure map, contact map and psi(p) to a PNG.",
    "--plot-at": "Pressure whose maps --plot shows (the nearest solved one; default: the last given).",
}


def _opt(*decls: str, panel: str, metavar: str | None = None, **kw: Any) -> Any:
    return typer.Option(*decls, help=_HELP[decls[0].split("/")[0]], rich_help_panel=panel, metavar=metavar, **kw)


@app.command(context_settings=_EXTRA)
def solve(
    ctx: typer.Context,
    texture: Annotated[str | None, _opt("--texture", "-t", panel=_SURFACE, metavar="NAME")] = None,
    surface: Annotated[str | None, _opt("--surface", panel=_SURFACE, metavar="FILE")] = None,
    size: Annotated[str | None, _opt("--size", panel=_SURFACE, metavar="LX[,LY]")] = None,
    height_unit: Annotated[str | None, _opt("--height-unit", panel=_SURFACE, metavar="UNIT")] = None,
    fill_missing: Annotated[bool, _opt("--fill-missing", panel=_SURFACE)] = False,
    periodic: Annotated[bool | None, _opt("--periodic/--no-periodic", panel=_SURFACE, show_default=False)] = None,
    modulus: Annotated[str | None, _opt("--modulus", panel=_MATERIALS, metavar="E*")] = None,
    skin_modulus: Annotated[str | None, _opt("--skin-modulus", panel=_MATERIALS, metavar="E")] = None,
    skin_poisson: Annotated[str | None, _opt("--skin-poisson", panel=_MATERIALS, metavar="NU")] = None,
    material_modulus: Annotated[str | None, _opt("--material-modulus", panel=_MATERIALS, metavar="E")] = None,
    material_poisson: Annotated[str | None, _opt("--material-poisson", panel=_MATERIALS, metavar="NU")] = None,
    pressure: Annotated[list[str] | None, _opt("--pressure", "-p", panel=_LOADS, metavar="P|START:STOP:COUNT")] = None,
    log: Annotated[bool, _opt("--log", panel=_LOADS)] = False,
    grid: Annotated[str | None, _opt("--grid", panel=_NUMERICS, metavar="N")] = None,
    tol: Annotated[str, _opt("--tol", panel=_NUMERICS, metavar="TOL")] = "1e-8",
    max_iter: Annotated[str, _opt("--max-iter", panel=_NUMERICS, metavar="N")] = "5000",
    formulation: Annotated[str, _opt("--formulation", panel=_NUMERICS, metavar="auto|primal|dual")] = "auto",
    json_path: Annotated[str | None, _opt("--json", panel=_OUTPUT, metavar="PATH")] = None,
    save: Annotated[str | None, _opt("--save", panel=_OUTPUT, metavar="PATH.nc")] = None,
    plot: Annotated[str | None, _opt("--plot", panel=_OUTPUT, metavar="PATH.png")] = None,
    plot_at: Annotated[str | None, _opt("--plot-at", panel=_OUTPUT, metavar="P")] = None,
) -> None:
    """Solve the skin contact on one texture cell at one or more mean pressures.

    Example: fingerpad solve --texture caps --radius 50um --height 10um --spacing 200um
    --lattice hexagonal --pressure 1kPa:100kPa:10 --log --json out.json

    Exit code 0 on success, 1 if some solve did not converge (outputs still written),
    2 on a user error (nothing written).
    """
    with user_errors():
        job = build_job(
            ctx_args=list(ctx.args), texture=texture, surface=surface, size=size, height_unit=height_unit,
            periodic=periodic, fill_missing=fill_missing, grid=grid, modulus=modulus, skin_modulus=skin_modulus,
            skin_poisson=skin_poisson, material_modulus=material_modulus, material_poisson=material_poisson, pressure=pressure or [],
            log=log, tol=tol, max_iter=max_iter, formulation=formulation, json_path=json_path, save=save,
            plot=plot, plot_at=plot_at,
        )
        code = run_job(job)
    if code:
        raise typer.Exit(code)


def build_job(
    *, ctx_args: Sequence[str], texture: str | None, surface: str | None, size: str | None,
    height_unit: str | None, periodic: bool | None, fill_missing: bool = False, grid: str | None,
    modulus: str | None, skin_modulus: str | None, skin_poisson: str | None, material_modulus: str | None,
    material_poisson: str | None, pressure: Sequence[str], log: bool, tol: str, max_iter: str,
    formulation: str, json_path: str | None, save: str | None, plot: str | None,
    plot_at: str | None = None,
) -> SolveJob:
    """Validate every option of ``fingerpad solve`` (cheap checks first) and build the texture."""
    if (texture is None) == (surface is None):
        raise FingerpadError("give exactly one of --texture NAME or --surface FILE")
    materials = parse_materials(modulus, skin_modulus, skin_poisson, material_modulus, material_poisson)
    pressures = _parse_pressures(pressure, log)
    tol_v = _parse_float(tol, "--tol")
    if not (0 < tol_v < 1):
        raise FingerpadError(f"--tol must lie in (0, 1), got {tol!r}")
    max_iter_v = _parse_int(max_iter, "--max-iter")
    if formulation not in ("auto", "primal", "dual"):
        raise FingerpadError(f"--formulation must be auto, primal or dual, got {formulation!r}")
    grid_v = _parse_int(grid, "--grid") if grid is not None else None
    size_v = _parse_size(size) if size is not None else None
    plot_at_v = parse_positive(plot_at, "pressure", name="--plot-at") if plot_at is not None else None
    if plot_at_v is not None and plot is None:
        raise FingerpadError("--plot-at needs --plot")
    job = SolveJob(texture=None, materials=materials, pressures=pressures, tol=tol_v, max_iter=max_iter_v,
                   formulation=formulation, json_path=json_path, save_path=save, plot_path=plot, plot_at=plot_at_v)
    _check_outputs(job)
    err = _stderr_console()
    with _warnings_to(err):
        if texture is not None:
            if height_unit is not None:
                raise FingerpadError("--height-unit applies to --surface files only")
            if fill_missing:
                raise FingerpadError("--fill-missing applies to --surface files only")
            tex = make_generated_texture(texture, ctx_args, grid_v, size_v)
            if periodic is False:
                tex = replace(tex, periodic=False)
            job.texture_source = {"source": "generator", "file": None}
        else:
            if ctx_args:
                raise FingerpadError(
                    f"unexpected arguments {' '.join(ctx_args)!r} (texture parameters need --texture)"
                )
            if grid_v is not None:
                raise FingerpadError("--grid applies to generated textures; a --surface file keeps its own grid")
            tex = read_surface_file(surface, size_v, height_unit, bool(periodic) if periodic is not None else False,
                                    fill_missing)
            job.texture_source = {"source": "file", "file": os.path.abspath(surface)}
    job.texture = tex
    return job


@app.command("textures")
def textures_command() -> None:
    """List the texture generators and their parameters (give them to `solve` as --NAME VALUE)."""
    from rich.console import Console
    from rich.table import Table

    with user_errors():
        gens = _generators()
    from rich.markup import escape

    table = Table(title="texture generators: fingerpad solve --texture NAME --PARAM VALUE ...", show_lines=True)
    table.add_column("texture", no_wrap=True)
    table.add_column("parameters (default)", no_wrap=True)
    table.add_column("description")
    metavars = {"length": "LENGTH", "angle": "ANGLE", "int": "INT", "str": "TEXT", "bool": "BOOL",
                "none": "NUMBER", "pressure": "PRESSURE", "lengths": "LENGTH[,LENGTH]"}
    for name, fn in gens.items():
        lines = []
        for pname, p in generator_params(fn).items():
            if pname in _GRID_NAMES:
                opt, meta = "--grid", "N"
            else:
                opt, meta = "--" + pname.replace("_", "-"), metavars.get(param_kind(pname, p), "VALUE")
                if pname == "size":
                    meta = "LX[,LY]"
            default = "required" if p.default is inspect.Parameter.empty else (
                "auto" if p.default is None else repr(p.default))
            lines.append(f"{opt} {meta} ({default})")
        doc = inspect.getdoc(fn) or ""
        summary = doc.splitlines()[0].replace("``", "") if doc else ""
        table.add_row(name, escape("\n".join(lines)), escape(summary))
    console = Console(file=sys.stdout)
    if not console.is_terminal:
        console = Console(file=sys.stdout, width=max(console.width, 120))
    console.print(table)
    console.print(
        "Lengths take unit suffixes (50um, 0.2mm) or metres; angles deg or rad; see the generator docstrings.",
        markup=False, highlight=False,
    )


# ---------------------------------------------------------------------------------------------
# run-default: the target of `make run`.
# >>> The lead replaces this with a prediction (`predict`, `run-default`); keep the signature. <<<
# ---------------------------------------------------------------------------------------------

#: Default texture of `run-default`: hexagonal spherical caps, R = 50 um, h = 10 um, 200 um apart
#: (the scale of the thesis' bump textures), skin 0.3 MPa on a rigid surface.
DEFAULT_TEXTURE = {"radius": "50um", "height": "10um", "spacing": "200um", "lattice": "hexagonal"}
DEFAULT_PRESSURES = "100Pa:300kPa:16"


@app.command("run-default")
def run_default(
    out: Annotated[str, typer.Option("--out", metavar="DIR", help="Output directory (created if missing).")] = "out",
    grid: Annotated[str, typer.Option("--grid", metavar="N", help="Grid points per axis.")] = "128",
    pressure: Annotated[
        str, typer.Option("--pressure", metavar="START:STOP:COUNT", help="Log-spaced pressure range.")
    ] = DEFAULT_PRESSURES,
) -> None:
    """Solve a default texture over a log range of pressures into DIR/solve.json, .nc, .png.

    The texture: hexagonal spherical caps R=50um, h=10um, spacing 200um; skin 0.3MPa on a rigid surface.
    """
    with user_errors():
        out_dir = Path(out)
        if out_dir.exists() and not out_dir.is_dir():
            raise FingerpadError(f"--out {out!r} exists and is not a directory")
        extra: list[str] = []
        for k, v in DEFAULT_TEXTURE.items():
            extra += [f"--{k}", v]
        job = build_job(
            ctx_args=extra, texture="caps", surface=None, size=None, height_unit=None, periodic=None, grid=grid,
            modulus=None, skin_modulus=None, skin_poisson=None, material_modulus=None, material_poisson=None,
            pressure=[pressure], log=True, tol="1e-8", max_iter="5000", formulation="auto",
            json_path=None, save=None, plot=None,
        )
        out_dir.mkdir(parents=True, exist_ok=True)
        job.json_path = str(out_dir / "solve.json")
        job.save_path = str(out_dir / "solve.nc")
        job.plot_path = str(out_dir / "solve.png")
        code = run_job(job)
        sys.stderr.write(f"wrote {job.json_path}, {job.save_path}, {job.plot_path}\n")
    if code:
        raise typer.Exit(code)


def _version_callback(value: bool) -> None:
    if value:
        sys.stdout.write(f"fingerpad {__version__}\n")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: Annotated[
        bool, typer.Option("--version", help="Show the version and exit.", is_eager=True, callback=_version_callback)
    ] = False,
) -> None:
    """Finger-pad contact on micro-textured surfaces (SI units; unit suffixes such as 50um, 0.3MPa)."""


def main() -> None:
    """Console-script entry point (``fingerpad``)."""
    app()


# =============================================================================================
# Commands from other modules. `fingerpad.cli_measurements.register(app)` adds the measurement
# commands when that module exists. The lead adds `predict` (and the final `run-default`) here.
# =============================================================================================


def _register_optional_commands() -> None:
    import importlib

    try:
        cli_measurements = importlib.import_module(f"{__package__}.cli_measurements")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__package__}.cli_measurements":
            raise
        return
    register = getattr(cli_measurements, "register", None)
    if callable(register):
        register(app)


_register_optional_commands()
