"""User input: quantities with units, texture specifications and surface files.

Shared by the command line (:mod:`fingerpad.cli`) and study files (:mod:`fingerpad.study`).
Every value arrives as text, so that every mistake becomes a one-line
:class:`~fingerpad.errors.FingerpadError` naming the command-line option at fault.
"""

from __future__ import annotations

import inspect
import os
import pickle
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from .errors import FingerpadError
from .units import UNITS, parse_positive, parse_quantity

__all__ = [
    "GRID_NAMES",
    "build_texture_params",
    "describe_exception",
    "generator_params",
    "generators",
    "make_generated_texture",
    "one_line",
    "param_kind",
    "parse_int",
    "parse_param_value",
    "parse_size",
    "read_surface_file",
    "split_extra_options",
]


# =============================================================================================
# Error text
# =============================================================================================


def one_line(text: str) -> str:
    """``text`` on one line (for ``error: ...`` and ``warning: ...`` messages)."""
    return " ".join(part.strip() for part in str(text).splitlines() if part.strip()) or "unknown error"


def describe_exception(exc: BaseException) -> str:
    """The message of ``exc``; for an :class:`OSError`, its reason and file name without the errno."""
    if isinstance(exc, OSError) and not isinstance(exc, FingerpadError):
        what = exc.strerror or str(exc)
        return f"{what}: {exc.filename}" if exc.filename else what
    return str(exc)


# =============================================================================================
# Numbers and sizes
# =============================================================================================


def parse_int(text: str, name: str, minimum: int = 1) -> int:
    """An integer of at least ``minimum`` from ``text``; errors name the option ``name``."""
    try:
        value = int(str(text).strip())
    except ValueError:
        raise FingerpadError(f"{name}: expected an integer, got {text!r}") from None
    if value < minimum:
        raise FingerpadError(f"{name}: must be at least {minimum}, got {value}")
    return value


def parse_size(text: str) -> tuple[float, float]:
    """``LX`` or ``LX,LY`` (lengths with units) -> ``(lx, ly)`` in m; errors name ``--size``."""
    parts = [p for p in str(text).split(",")]
    if len(parts) not in (1, 2) or any(not p.strip() for p in parts):
        raise FingerpadError(f"--size: expected LX or LX,LY, got {text!r}")
    values = [parse_positive(p, "length", name="--size") for p in parts]
    return (values[0], values[-1])


# =============================================================================================
# Texture parameters given as extra options (--NAME VALUE)
# =============================================================================================


_ANGLE_NAMES = {"orientation", "angle", "rotation", "theta", "phi", "direction"}
_INT_NAMES = {"n", "nx", "ny", "grid", "count", "seed", "points", "resolution", "harmonics"}
_DIMENSIONLESS_NAMES = {"fraction", "ratio", "aspect", "aspect_ratio", "fill", "fill_fraction", "exponent",
                        "duty", "duty_cycle", "coverage", "density"}
_STR_NAMES = {"lattice", "profile", "shape", "kind", "pattern", "mode", "name"}
GRID_NAMES = ("grid", "n", "resolution", "points", "nx")


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
        return parse_int(text, label, minimum=-(2**62))
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


def generators() -> dict[str, Callable[..., Any]]:
    """The texture generators by name (:data:`fingerpad.textures.GENERATORS`)."""
    from . import textures

    return dict(textures.GENERATORS)


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
    gens = generators()
    key = name.strip().lower()
    if key not in gens:
        raise FingerpadError(f"unknown texture {name!r} (choose from: {', '.join(sorted(gens))})")
    fn = gens[key]
    params = generator_params(fn)
    anykw = _accepts_any_kwargs(fn)
    kwargs: dict[str, Any] = {}
    for pname, text in split_extra_options(extra):
        if pname not in params and not anykw:
            known = ", ".join("--" + k.replace("_", "-") for k in params if k not in GRID_NAMES) or "none"
            raise FingerpadError(f"texture {key!r} has no parameter --{pname.replace('_', '-')} (its parameters: {known})")
        if pname in kwargs:
            raise FingerpadError(f"texture parameter --{pname.replace('_', '-')} given twice")
        kwargs[pname] = parse_param_value(pname, text, param_kind(pname, params.get(pname)))
    if grid is not None:
        gname = next((g for g in GRID_NAMES if g in params), None)
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
    return textures.make_texture(name.strip().lower(), **kwargs)


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
    try:
        return textures.read_surface(p, size=size, height_unit=factor, periodic=periodic, level=True,
                                     fill_missing=fill_missing)
    except FingerpadError as exc:
        # Name the command-line option rather than the Python keyword.
        text = str(exc).replace("pass fill_missing=True", "give --fill-missing")
        text = text.replace("pass size=(Lx, Ly) in metres", "give --size LX[,LY]")
        text = text.replace("pass height_unit", "give --height-unit")
        if text != str(exc):
            raise FingerpadError(text) from None
        raise
    except (OSError, ValueError, EOFError, pickle.UnpicklingError) as exc:
        raise FingerpadError(f"cannot read surface {path!r}: {one_line(describe_exception(exc))}") from None
    except Exception as exc:
        # SurfaceTopography's readers raise their own exception types on a bad file.
        if type(exc).__module__.split(".")[0] == "SurfaceTopography":
            raise FingerpadError(f"cannot read surface {path!r}: {one_line(str(exc))}") from None
        raise
