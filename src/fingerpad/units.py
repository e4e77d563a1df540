"""Parsing of physical quantities with unit suffixes.

All of fingerpad works in SI units (m, N, Pa). The command line and study files accept
plain SI numbers (``0.002``) or numbers with a unit suffix (``50um``, ``0.3MPa``, ``2N``).
"""

from __future__ import annotations

import math
import re
from decimal import Decimal, InvalidOperation

from .errors import FingerpadError

#: Unit symbol -> (dimension, factor to SI).
UNITS: dict[str, tuple[str, float]] = {
    # length
    "m": ("length", 1.0),
    "cm": ("length", 1e-2),
    "mm": ("length", 1e-3),
    "um": ("length", 1e-6),
    "µm": ("length", 1e-6),
    "μm": ("length", 1e-6),
    "micron": ("length", 1e-6),
    "nm": ("length", 1e-9),
    # pressure / modulus
    "Pa": ("pressure", 1.0),
    "kPa": ("pressure", 1e3),
    "MPa": ("pressure", 1e6),
    "GPa": ("pressure", 1e9),
    # force
    "N": ("force", 1.0),
    "mN": ("force", 1e-3),
    "kN": ("force", 1e3),
    # angle
    "deg": ("angle", math.pi / 180.0),
    "rad": ("angle", 1.0),
    # speed (of a finger's stroke)
    "m/s": ("speed", 1.0),
    "cm/s": ("speed", 1e-2),
    "mm/s": ("speed", 1e-3),
    # surface energy (work of adhesion), J/m^2 = N/m
    "J/m2": ("surface energy", 1.0),
    "J/m^2": ("surface energy", 1.0),
    "mJ/m2": ("surface energy", 1e-3),
    "mJ/m^2": ("surface energy", 1e-3),
    "N/m": ("surface energy", 1.0),
    "mN/m": ("surface energy", 1e-3),
}



def _decimal_exponent(factor: float) -> int | None:
    """k if ``factor`` is exactly the float 10**k, else None."""
    k = round(math.log10(factor))
    return k if float(f"1e{k}") == factor else None


#: Decimal prefixes are applied by shifting the decimal exponent, not by a float product, so that
#: "50um" is the very float 5e-05 (50 * 1e-6 is 5.0000000000000004e-05): the same input written
#: either way gives the same numbers, the same cache keys and the same file names.
_EXPONENT = {unit: _decimal_exponent(factor) for unit, (_, factor) in UNITS.items()}

SI_SYMBOL = {"length": "m", "pressure": "Pa", "force": "N", "angle": "rad", "speed": "m/s",
             "surface energy": "J/m2"}

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
# a unit: letters, or a quotient such as J/m2, J/m^2, mN/m, mm/s
_QUANTITY = re.compile(rf"^\s*({_NUMBER})\s*([A-Za-zµμ]*(?:/[A-Za-z]+(?:\^?2)?)?)\s*$")


def parse_quantity(text: str | float | int, dimension: str, *, name: str = "value") -> float:
    """Parse ``text`` as a quantity of ``dimension`` and return it in SI units.

    Parameters
    ----------
    text
        A number (taken as SI) or a string such as ``"50um"``, ``"0.3 MPa"``, ``"2N"``, ``"1e-3"``.
    dimension
        One of ``"length"``, ``"pressure"``, ``"force"``, ``"angle"``, ``"speed"`` (m/s:
        ``20mm/s``), or ``"none"``.
    name
        The parameter's name, used in error messages.

    Raises
    ------
    FingerpadError
        For unparsable text, an unknown unit or a unit of the wrong dimension.
    """
    if isinstance(text, bool):
        raise FingerpadError(f"{name}: expected a number, got {text!r}")
    if isinstance(text, (int, float)):
        value = float(text)
    else:
        match = _QUANTITY.match(str(text))
        if not match:
            raise FingerpadError(f"{name}: cannot read {text!r} as a number with an optional unit")
        number, unit = match.groups()
        value = float(number)
        if unit:
            if unit not in UNITS:
                known = ", ".join(k for k, v in UNITS.items() if v[0] == dimension) or "none"
                raise FingerpadError(f"{name}: unknown unit {unit!r} in {text!r} (use one of: {known})")
            unit_dim, factor = UNITS[unit]
            if dimension != unit_dim:
                expected = "a plain number (no unit)" if dimension == "none" else f"a {dimension}"
                raise FingerpadError(f"{name}: {text!r} is a {unit_dim}, expected {expected}")
            exponent = _EXPONENT[unit]
            if exponent is None:
                value *= factor
            elif exponent:
                try:
                    value = float(Decimal(number).scaleb(exponent))
                except InvalidOperation:  # pragma: no cover - the pattern admits decimal numbers only
                    value *= factor
    if not math.isfinite(value):
        raise FingerpadError(f"{name}: {text!r} is not a finite number")
    return value


def parse_positive(text: str | float, dimension: str, *, name: str = "value") -> float:
    """Like :func:`parse_quantity` but the value must be strictly positive."""
    value = parse_quantity(text, dimension, name=name)
    if value <= 0:
        raise FingerpadError(f"{name}: must be positive, got {text!r}")
    return value


#: Most values a ``START:STOP:COUNT`` range may hold (checked before anything is allocated).
MAX_RANGE_COUNT = 1_000_000


def parse_range(text: str, dimension: str, *, name: str = "range", log: bool = False,
                max_count: int = MAX_RANGE_COUNT) -> list[float]:
    """Parse ``START:STOP:COUNT`` into a list of SI values (log-spaced if ``log``).

    A single quantity gives a one-element list. ``STOP`` below ``START`` and a ``COUNT`` above
    ``max_count`` are errors.
    """
    import numpy as np

    parts = str(text).split(":")
    if len(parts) == 1:
        return [parse_quantity(parts[0], dimension, name=name)]
    if len(parts) != 3:
        raise FingerpadError(f"{name}: expected START:STOP:COUNT, got {text!r}")
    start = parse_quantity(parts[0], dimension, name=name)
    stop = parse_quantity(parts[1], dimension, name=name)
    raw = parts[2].strip()
    if raw.isascii() and raw.isdigit() and len(raw.lstrip("0")) > MAX_INT_DIGITS:
        raise FingerpadError(f"{name}: COUNT of {len(raw)} digits is more than the {max_count} allowed here")
    try:
        count = int(raw)
    except ValueError:
        shown = raw if len(raw) <= 40 else raw[:30] + f"... ({len(raw)} characters)"
        raise FingerpadError(f"{name}: COUNT must be an integer, got {shown!r}") from None
    if count < 1:
        raise FingerpadError(f"{name}: COUNT must be at least 1, got {count}")
    if count > max_count:
        raise FingerpadError(f"{name}: COUNT {count} is more than the {max_count} allowed here")
    if stop < start:
        raise FingerpadError(f"{name}: STOP {parts[1]!r} is below START {parts[0]!r} (ranges run upward)")
    if log:
        if start <= 0 or stop <= 0:
            raise FingerpadError(f"{name}: a log-spaced range needs positive bounds, got {text!r}")
        return [float(v) for v in np.geomspace(start, stop, count)]
    return [float(v) for v in np.linspace(start, stop, count)]


def format_quantity(value: float, dimension: str, digits: int = 4) -> str:
    """Format an SI value with an engineering prefix, e.g. ``5e-5 m -> '50 um'``."""
    unit = SI_SYMBOL.get(dimension, "")
    if value == 0 or not math.isfinite(value) or dimension == "angle":
        return f"{value:.{digits}g} {unit}".strip()
    prefixes = [(1e9, "G"), (1e6, "M"), (1e3, "k"), (1.0, ""), (1e-3, "m"), (1e-6, "u"), (1e-9, "n")]
    for factor, prefix in prefixes:
        if abs(value) >= factor:
            return f"{value / factor:.{digits}g} {prefix}{unit}"
    return f"{value:.{digits}g} {unit}"


#: Digits an integer typed by a user may have: more than any count or seed here needs, and
#: far below Python's 4300-digit conversion limit (a 5000-digit --grid was a traceback).
MAX_INT_DIGITS = 30


def format_percent(error: float) -> str:
    """A relative error estimate in per cent, as every output that prints one writes it: two
    significant digits, ``100`` from 99.5 %, and ``>100`` beyond (there the number says only that
    the estimate does not resolve it; ``'1e+02'`` nowhere).

    Parameters
    ----------
    error : float
        The relative error (1 = 100 %).
    """
    if error > 1.0:
        return ">100"
    return "100" if error >= 0.995 else f"{100 * error:.2g}"


def parse_int(text: str | int | float, name: str, minimum: int = 1, maximum: int | None = None) -> int:
    """An integer in ``[minimum, maximum]`` from user input: a Python or NumPy integer, an
    integral float (``64.0`` from TOML) or digits; errors name ``name`` (the option or key).

    The one reader of counts and seeds typed by users (command-line options, study-file keys,
    the explorer's fields): the cap of a count is declared where its cost is known and passed
    as ``maximum``.

    Raises
    ------
    FingerpadError
        ``NAME: expected an integer, got ...`` (a long input shown shortened), or a value out of
        ``[minimum, maximum]``.
    """
    import numbers

    if isinstance(text, bool):
        raise FingerpadError(f"{name}: expected an integer, got {text!r}")
    if isinstance(text, numbers.Integral):
        value = int(text)
    elif isinstance(text, numbers.Real):
        if not (math.isfinite(text) and float(text).is_integer()):
            raise FingerpadError(f"{name}: expected an integer, got {text!r}")
        value = int(text)
    else:
        raw = str(text).strip()
        digits = raw.lstrip("+-")
        if not (digits.isascii() and digits.isdigit() and len(raw) - len(digits) <= 1):
            shown = raw if len(raw) <= 40 else raw[:30] + f"... ({len(raw)} characters)"
            raise FingerpadError(f"{name}: expected an integer, got {shown!r}")
        if len(digits.lstrip("0")) > MAX_INT_DIGITS:
            sign = "-" if raw.startswith("-") else ""
            bound = f"at least {minimum}" if sign else (f"at most {maximum}" if maximum is not None else
                                                         f"an integer of at most {MAX_INT_DIGITS} digits")
            raise FingerpadError(f"{name}: must be {bound}, got a {sign}number of {len(digits)} digits")
        value = int(raw)
    if value < minimum:
        raise FingerpadError(f"{name}: must be at least {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise FingerpadError(f"{name}: must be at most {maximum}, got {value}")
    return value


def parse_size(text: str, name: str = "--size") -> tuple[float, float]:
    """``LX`` or ``LX,LY`` (lengths with units) -> ``(lx, ly)`` in m; errors name ``name``."""
    parts = [p for p in str(text).split(",")]
    if len(parts) not in (1, 2) or any(not p.strip() for p in parts):
        raise FingerpadError(f"{name}: expected LX or LX,LY, got {text!r}")
    values = [parse_positive(p, "length", name=name) for p in parts]
    return (values[0], values[-1])
