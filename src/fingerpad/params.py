"""One way to declare a parameter: name, kind and unit, bounds, default, meaning, a typical value.

Texture families (:mod:`fingerpad.textures`), pad (gross-area) and ridge models
(:mod:`fingerpad.macro`, :mod:`fingerpad.meso`), the finger's own fields
(:data:`fingerpad.finger.FINGER_PARAMS`) and the counter-surface material all declare their
parameters with :class:`Param`. Everything a user sees of a parameter is derived from that one
declaration: the command-line option and its placeholder, the unit shown by ``fingerpad textures``
and ``fingerpad fingers``, how study files and sweep axes read a value (``50um``, ``0.3MPa``,
``30deg``) and which values are allowed (the bounds are checked here, so the command line, study
files and sweeps give the same message), and the explorer's starting values (``example``).

A model found by adding one file declares itself with :class:`Model` (its class, its parameters,
and which values it takes from the finger or the study when they are not given).

This module is low in the layers: it imports only :mod:`fingerpad.units` and
:mod:`fingerpad.errors` (and :mod:`fingerpad.plausibility` when a value is read).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from .errors import FingerpadError
from .units import UNITS, parse_quantity

__all__ = ["DIMENSIONAL", "KINDS", "REQUIRED", "Model", "Param", "check_fields", "parse_angle"]

#: Parameter kinds: (unit shown to users, command-line placeholder, dimension of parse_quantity).
KINDS: dict[str, tuple[str, str, str | None]] = {
    "length": ("m", "LENGTH", "length"),
    "pressure": ("Pa", "PRESSURE", "pressure"),
    "force": ("N", "FORCE", "force"),
    "surface energy": ("J/m2", "ENERGY", "surface energy"),
    "angle": ("deg", "ANGLE", "angle"),
    "count": ("1", "INT", None),
    "ratio": ("1", "NUMBER", "none"),
    "choice": ("", "TEXT", None),
    "size": ("m", "LX[,LY]", None),
    "grid": ("points", "N", None),
}

#: Kinds whose bare numbers are SI values of a physical dimension: a sweep axis refuses them
#: without a unit (``spacing = 7`` would be 7 m).
DIMENSIONAL = frozenset({"length", "pressure", "force", "surface energy"})


class _Required:
    def __repr__(self) -> str:
        return "required"


#: Default of a parameter that must be given.
REQUIRED: Any = _Required()


def _is_bare_number(value: Any) -> bool:
    """Whether user input is a number without a unit (``7``, ``"7"``, ``"1e-4"``)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return True
    try:
        float(str(value).strip())
    except ValueError:
        return False
    return True


@dataclass(frozen=True)
class Param:
    """One declared parameter.

    Attributes
    ----------
    name
        Keyword of the generator or model field (``--name-with-dashes`` on the command line).
    kind
        ``"length"`` (m), ``"pressure"`` (Pa), ``"force"`` (N), ``"surface energy"`` (J/m^2, a
        work of adhesion), ``"angle"`` (degrees by default
        from user input, radians in SI), ``"count"`` (integer), ``"ratio"`` (dimensionless
        number), ``"choice"`` (one of ``choices``), ``"size"`` (``LX[,LY]``, m) or ``"grid"``
        (grid points, given as ``--grid``).
    doc
        One-line meaning, shown by ``fingerpad textures`` / ``fingerpad fingers``.
    default
        :data:`REQUIRED`, ``None`` (chosen automatically) or a value (SI).
    choices
        Allowed values of a ``"choice"``.
    low, high
        Bounds of a numeric value in SI (``None``: unbounded); ``low_open``/``high_open`` make
        them strict (``low=0, low_open=True`` is "positive").
    example
        A typical value as a user types it (``"100um"``): the explorer's starting value and
        the example of the docs (``None``: none).
    label
        How a message from the Python API names the value (``"pad radius R_fp"``; default the
        name). User input is named by what the user typed (the option or the study-file key).
    plausible
        A role of :data:`fingerpad.plausibility.RANGES`: a value read from user input outside
        its range is warned about (a forgotten unit).
    symbol
        The symbol of the equations (``R_fp``), for column heads; default the name.
    needs_unit
        A number typed as text without a unit (the command line, a quoted study-file value) is
        refused, as sweep axes refuse one: for a length whose SI reading of ``2`` (2 m) is never
        meant, e.g. the skin layer's thickness. Numbers (TOML, Python) stay SI.
    """

    name: str
    kind: str
    doc: str
    default: Any = REQUIRED
    choices: tuple[str, ...] = ()
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    example: Any = None
    label: str | None = None
    plausible: str | None = None
    symbol: str | None = None
    needs_unit: bool = False

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"unknown parameter kind {self.kind!r}")
        if self.kind == "choice" and not self.choices:
            raise ValueError(f"choice parameter {self.name!r} declares no choices")

    # ------------------------------------------------------------------ derived

    @property
    def option(self) -> str:
        """The command-line option, e.g. ``--semi-axis-x``."""
        return "--grid" if self.kind == "grid" else "--" + self.name.replace("_", "-")

    @property
    def unit(self) -> str:
        """The unit shown to users (``m``, ``Pa``, ``deg``; ``""`` for a choice)."""
        return KINDS[self.kind][0]

    @property
    def metavar(self) -> str:
        return KINDS[self.kind][1]

    @property
    def dimension(self) -> str:
        """The dimension of :func:`fingerpad.units.parse_quantity` (``length``, ``none``, ...)."""
        return KINDS[self.kind][2] or "none"

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    @property
    def dimensional(self) -> bool:
        """Whether a bare number of this parameter is a physical quantity in SI."""
        return self.kind in DIMENSIONAL

    def bounds_text(self) -> str:
        """The allowed range in words (``positive``, ``in [0, 1]``); ``""`` if unbounded."""
        lo, hi = self.low, self.high
        if lo is None and hi is None:
            return ""
        if hi is None:
            if lo == 0:
                return "positive" if self.low_open else "non-negative"
            return f"{'>' if self.low_open else '>='} {self._fmt(lo)}"
        if lo is None:
            return f"{'<' if self.high_open else '<='} {self._fmt(hi)}"
        return (f"in {'(' if self.low_open else '['}{self._fmt(lo)}, {self._fmt(hi)}"
                f"{')' if self.high_open else ']'}")

    def _fmt(self, value: float) -> str:
        if self.kind in DIMENSIONAL:
            from .units import format_quantity

            return format_quantity(value, self.dimension)
        return f"{value:g}"

    def default_text(self) -> str:
        """The default as listings show it: ``required``, ``auto``, ``30 deg``, ``9 mm``."""
        if self.default is REQUIRED:
            return "required"
        if self.default is None:
            return "auto"
        return self.format(self.default)

    def format(self, value: Any) -> str:
        """An SI value as listings show it: ``9 mm``, ``40 kPa``, ``30 deg``, ``0.1``."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return str(value)
        if self.kind == "angle":
            return f"{math.degrees(value):g} deg"
        if self.kind in DIMENSIONAL:
            from .units import format_quantity

            return format_quantity(float(value), self.dimension)
        return f"{value:g}"

    # ------------------------------------------------------------------ values

    def check(self, value: Any, where: str | None = None) -> Any:
        """``value`` (SI) if it is of this parameter's kind and within its bounds.

        The one place where bounds are checked: reading user input (:meth:`parse`) and the
        models' own ``__post_init__`` (:func:`check_fields`) both end here, so every route gives
        the same message, ``NAME: must be positive, got -1.0``.

        Raises
        ------
        FingerpadError
            Naming ``where`` (default: the label or name).
        """
        label = where or self.label or self.name
        if value is None and self.default is None:
            return None  # not given (a default of None: chosen automatically, or not used)
        if self.kind == "choice":
            text = str(value).strip().lower() if isinstance(value, str) else None
            if text not in self.choices:
                raise FingerpadError(f"{label}: must be one of {', '.join(self.choices)}, got {value!r}")
            return text
        if self.kind == "size":
            return value
        import numbers

        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise FingerpadError(f"{label}: expected a number, got {value!r}")
        number = float(value)
        if not math.isfinite(number):
            raise FingerpadError(f"{label}: must be a finite number, got {value!r}")
        lo, hi = self.low, self.high
        below = lo is not None and (number <= lo if self.low_open else number < lo)
        above = hi is not None and (number >= hi if self.high_open else number > hi)
        if below or above:
            shown = f"{value!r}" if not self.dimensional else f"{number!r} ({self._fmt(number)})"
            verb = "be" if hi is None or lo is None else "lie"
            raise FingerpadError(f"{label}: must {verb} {self.bounds_text()}, got {shown}")
        if self.kind in ("count", "grid"):
            if not number.is_integer():
                raise FingerpadError(f"{label}: expected an integer, got {value!r}")
            return int(number)
        return number

    def parse(self, value: Any, where: str | None = None, *, require_unit: bool = False) -> Any:
        """The SI value of user input ``value`` (text from the command line or a study-file value).

        Lengths, pressures, forces: SI numbers or quantities with a unit (``50um``, ``0.3MPa``);
        with ``require_unit`` (sweep axes) a bare number other than 0 is refused. Angles: a bare
        number is in degrees; ``30deg`` and ``0.5rad`` are explicit (radians returned). Counts:
        integers. Ratios: numbers. Choices: case-insensitive names. Sizes: ``LX`` or ``LX,LY``.
        The value is then checked against the bounds (:meth:`check`).

        Raises
        ------
        FingerpadError
            Naming ``where`` (default: the option) and the expected form.
        """
        label = where or self.option
        if isinstance(value, bool):
            raise FingerpadError(f"{label}: expected a {self.kind}, got {value!r}")
        if self.kind in DIMENSIONAL:
            # needs_unit: text typed without a unit (a number from TOML or Python is SI, as a
            # sweep axis passes its values)
            typed = self.needs_unit and isinstance(value, str)
            if _is_bare_number(value) and not math.isfinite(float(str(value).strip())):
                raise FingerpadError(f"{label}: must be a finite number, got {value!r}")  # not "nanm has no unit"
            if (require_unit or typed) and _is_bare_number(value) and float(str(value).strip()) != 0:
                units = ", ".join(u for u, (dim, _) in UNITS.items() if dim == self.dimension and u.isascii())
                raise FingerpadError(
                    f"{label}: {value!r} has no unit; a {self.kind} needs one here, e.g. "
                    f"\"{str(value).strip()}{self.unit}\" if SI was meant (units: {units})"
                )
            number = parse_quantity(value, self.dimension, name=label)
            if number != 0:
                self._warn_implausible(number, label)
            return self.check(number, label)
        if self.kind == "angle":
            return self.check(parse_angle(value, label), label)
        if self.kind in ("count", "grid"):
            from .units import MAX_INT_DIGITS, parse_int

            text = str(value).strip()
            if text.lstrip("+-").isdigit():  # digits: read exactly, however many (a 5000-digit one is refused)
                return self.check(parse_int(text, label, -10**MAX_INT_DIGITS), label)
            try:
                number = float(text)
            except ValueError:
                raise FingerpadError(f"{label}: expected an integer, got {value!r}") from None
            if not number.is_integer():
                raise FingerpadError(f"{label}: expected an integer, got {value!r}")
            return self.check(int(number), label)
        if self.kind == "ratio":
            number = parse_quantity(value, "none", name=label)
            self._warn_implausible(number, label)
            return self.check(number, label)
        if self.kind == "choice":
            return self.check(str(value) if not isinstance(value, str) else value, label)
        return self.parse_size(value, label)

    def parse_size(self, value: Any, label: str) -> tuple[float, float]:
        """``(Lx, Ly)`` in m from ``LX`` or ``LX,LY`` (lengths with units); a declaration that
        takes sizes in other forms (textures: a pair of numbers too) overrides this."""
        from .units import parse_size

        return parse_size(value, label)


    def _warn_implausible(self, number: float, label: str) -> None:
        """A PlausibilityWarning for a value outside the range of :attr:`plausible` (a role of the
        same dimension only: texture families declare every parameter with the length role)."""
        if not self.plausible:
            return
        from .plausibility import RANGES, check_plausible

        if self.plausible in RANGES and RANGES[self.plausible][2] == self.dimension:
            check_plausible(number, self.plausible, label)


def parse_angle(value: Any, name: str) -> float:
    """Radians from user input: a bare number is in degrees, ``deg``/``rad`` suffixes explicit."""
    import numbers

    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return math.radians(float(value))
    text = str(value).strip()
    try:
        return math.radians(float(text))
    except ValueError:
        pass
    unit = text.lstrip("+-.0123456789eE ")
    if unit and unit in UNITS and UNITS[unit][0] != "angle":
        raise FingerpadError(f"{name}: {value!r} is a {UNITS[unit][0]}, expected an angle (e.g. 30deg)")
    return parse_quantity(text, "angle", name=name)


def check_fields(obj: Any, params: tuple[Param, ...]) -> None:
    """Check every declared field of a model instance (its ``__post_init__``) with :meth:`Param.check`.

    Numbers given as NumPy scalars are stored back as floats.
    """
    for p in params:
        value = getattr(obj, p.name)
        if value is None and p.default is None:
            continue
        checked = p.check(value)
        if checked is not value and p.kind not in ("size",):
            object.__setattr__(obj, p.name, checked)


@dataclass(frozen=True)
class Model:
    """A pad (gross-area) or ridge-area model that a study file can name.

    A file of :mod:`fingerpad.macro` or :mod:`fingerpad.meso` declares its models in a module
    attribute ``MODELS = (Model(...),)``; the package finds them (a new model is one file).

    Attributes
    ----------
    name
        The name in study files (``[finger] gross = "dzidek"``); ``-`` and ``_`` are alike.
    factory
        The model class, called with keyword arguments in SI.
    params
        The declared parameters (the fields a study file may give).
    summary
        One line for listings and docs.
    inherits
        Field -> value of the context taken when the field is not given, e.g.
        ``{"radius": "finger.radius"}``: a Hertz pad takes the finger's radius, a BEM fingerprint
        model the study's largest load (``"loads.max"``).
    """

    name: str
    factory: Callable[..., Any]
    params: tuple[Param, ...]
    summary: str
    inherits: Mapping[str, str] = field(default_factory=dict)

    def param(self, name: str) -> Param | None:
        return next((p for p in self.params if p.name == name), None)

    def build(self, values: Mapping[str, Any], *, where: str, context: Mapping[str, Any] | None = None) -> Any:
        """The model from user values (study-file numbers or quantities with units).

        Raises
        ------
        FingerpadError
            Unknown or missing parameter, bad value, naming ``where`` and the parameter.
        """
        names = ", ".join(p.name for p in self.params) or "none"
        unknown = sorted(set(values) - {p.name for p in self.params})
        if unknown:
            raise FingerpadError(f"{where}: model {self.name!r} has no parameter(s) {', '.join(unknown)} "
                                 f"(its parameters: {names})")
        kwargs: dict[str, Any] = {}
        for key, value in values.items():
            par = self.param(key)
            assert par is not None
            if par.kind != "choice" and (isinstance(value, bool) or not isinstance(value, (int, float, str))):
                raise FingerpadError(f"{where} {key}: expected a number or a quantity, got {value!r}")
            kwargs[key] = par.parse(value, f"{where} {key}")
        for key, source in self.inherits.items():
            if key not in kwargs and context is not None and context.get(source) is not None:
                kwargs[key] = context[source]
        missing = [p.name for p in self.params if p.required and p.name not in kwargs]
        if missing:
            raise FingerpadError(f"{where}: model {self.name!r} needs {', '.join(missing)} (its parameters: {names})")
        return self.factory(**kwargs)
