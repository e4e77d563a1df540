"""Reading study values: TOML values and command-line text alike (numbers SI, strings with units).

Every reader takes the name to show in its error message, so that a mistake in a study file names
``study.toml [loads] range`` and the same mistake on the command line names ``--loads``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import FingerpadError
from ..units import parse_int, parse_quantity, parse_range

__all__ = ["boolean", "integer", "material", "parse_loads", "quantity", "text"]

#: Most load values one study may ask for (each costs a coupling evaluation and a table row).
MAX_LOADS = 100_000


def quantity(value: Any, dimension: str, name: str) -> float:
    """A number (SI) or a quantity with a unit such as ``"1N"``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise FingerpadError(f"{name}: expected a number or a quantity such as '1N', got {value!r}")
    return parse_quantity(value, dimension, name=name)


def integer(value: Any, name: str, minimum: int = 1, maximum: int | None = None) -> int:
    """An integer in ``[minimum, maximum]`` (TOML integer, integral float or digits):
    :func:`fingerpad.units.parse_int`."""
    if not isinstance(value, (int, float, str)):
        raise FingerpadError(f"{name}: expected an integer, got {value!r}")
    return parse_int(value, name, minimum, maximum)


def boolean(value: Any, name: str) -> bool:
    """``true``/``false`` (also yes/no, on/off, 1/0 as text)."""
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.strip().lower() in ("1", "true", "yes", "on", "0", "false", "no", "off"):
        return value.strip().lower() in ("1", "true", "yes", "on")
    raise FingerpadError(f"{name}: expected true or false, got {value!r}")


def text(value: Any) -> str:
    """A TOML value as the text the command line would give (lists: comma-separated)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return ",".join(text(v) for v in value)
    return str(value)


def positive_loads(values: Sequence[float], name: str) -> np.ndarray:
    arr = np.asarray(list(values), dtype=float).ravel()
    if arr.size == 0:
        raise FingerpadError(f"{name}: no loads given")
    if not np.all(np.isfinite(arr)):
        raise FingerpadError(f"{name}: loads must be finite")
    if np.any(arr <= 0):
        raise FingerpadError(f"{name}: loads must be positive, got {arr.min():.4g} N")
    return arr


def _range_count(spec: str, name: str, cap: int) -> None:
    parts = spec.split(":")
    if len(parts) == 3:
        try:
            count = parse_int(parts[2], name)
        except FingerpadError:
            return  # parse_range reports it
        if count > cap:
            raise FingerpadError(f"{name}: {count} loads asked for; at most {cap} are allowed")


def _check_order(spec: str, name: str) -> None:
    """A range runs upward: ``STOP`` below ``START`` is a mistake, not a reversed sweep."""
    parts = spec.split(":")
    if len(parts) == 3:
        start = parse_quantity(parts[0], "force", name=name)
        stop = parse_quantity(parts[1], "force", name=name)
        if stop < start:
            raise FingerpadError(f"{name}: STOP {parts[1]!r} is below START {parts[0]!r} in {spec!r}")


def parse_loads(spec: Any, log: bool, name: str = "loads", max_count: int = MAX_LOADS) -> np.ndarray:
    """Loads (N) from ``"START:STOP:COUNT"`` (log-spaced if ``log``), one quantity, or a list of
    either (a list of ranges and values is concatenated), given as a sequence or as text separated
    by commas (``"0.1N,0.3N,1N:4N:3"``, as ``solve --pressure`` takes its pressures)."""
    given = list(spec) if isinstance(spec, (list, tuple, np.ndarray)) else [spec]
    items = [piece for item in given
             for piece in (item.split(",") if isinstance(item, str) else [item])]
    values: list[float] = []
    for item in items:
        if isinstance(item, str) and ":" in item:
            _range_count(item, name, max_count)
            _check_order(item, name)
            values += parse_range(item, "force", name=name, log=log)
        else:
            values.append(quantity(item, "force", name))
        if len(values) > max_count:
            raise FingerpadError(f"{name}: more than {max_count} loads asked for")
    return positive_loads(values, name)


def material(modulus: Any, poisson: Any, modulus_name: str, poisson_name: str) -> tuple[float | None, float | None]:
    """Counter-surface (E, nu); ``None`` modulus or ``"rigid"`` = rigid (then no Poisson ratio)."""
    said = isinstance(modulus, str) and modulus.strip().lower() in ("rigid", "inf", "infinity")
    if modulus is None or said:
        if poisson is not None:
            why = (f"{modulus_name} {modulus.strip()} is a rigid material, which has none" if said else
                   f"it needs a material modulus, {modulus_name} (the default material is rigid)")
            raise FingerpadError(f"{poisson_name}: a Poisson ratio is given, but {why}")
        return None, None
    from ..materials import MATERIAL_MODULUS, MATERIAL_POISSON

    em = MATERIAL_MODULUS.check(quantity(modulus, "pressure", modulus_name), modulus_name)
    num = MATERIAL_POISSON.default if poisson is None else \
        MATERIAL_POISSON.check(quantity(poisson, "none", poisson_name), poisson_name)
    return em, num
