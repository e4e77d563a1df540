"""Checks of numeric inputs shared by the physics modules (SI units).

Every check raises :class:`~fingerpad.errors.FingerpadError` with a message naming the quantity,
so that a user mistake never ends in a traceback or a silently wrong number.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .errors import FingerpadError

#: A scalar or an array of values (loads, areas, pressures).
ArrayLike = float | np.ndarray | Sequence[float]

__all__ = ["ArrayLike", "as_areas", "as_loads", "nonnegative", "positive", "scalar_out"]


def positive(value: Any, name: str) -> float:
    """Return ``value`` as a float if finite and > 0, else raise a FingerpadError."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise FingerpadError(f"{name} must be a positive number, got {value!r}")
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise FingerpadError(f"{name} must be a positive number, got {value!r}")
    return v


def nonnegative(value: Any, name: str) -> float:
    """Return ``value`` as a float if finite and >= 0, else raise a FingerpadError."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise FingerpadError(f"{name} must be a non-negative number, got {value!r}")
    v = float(value)
    if not (math.isfinite(v) and v >= 0):
        raise FingerpadError(f"{name} must be a non-negative number, got {value!r}")
    return v


def as_loads(load: ArrayLike, name: str = "load", *, strict: bool = False) -> np.ndarray:
    """Return ``load`` as a float array, checking it is finite and >= 0 (> 0 if ``strict``)."""
    try:
        arr = np.asarray(load, dtype=float)
    except (TypeError, ValueError):
        raise FingerpadError(f"{name} must be a number or an array of numbers, got {load!r}") from None
    if not np.all(np.isfinite(arr)):
        raise FingerpadError(f"{name} holds NaN or infinite values")
    if strict and np.any(arr <= 0):
        raise FingerpadError(f"{name} must be positive, got a minimum of {arr.min():.4g}")
    if np.any(arr < 0):
        raise FingerpadError(f"{name} must be non-negative, got a minimum of {arr.min():.4g}")
    return arr


def scalar_out(arr: np.ndarray) -> float | np.ndarray:
    """Return a Python float for 0-d results so scalar in -> scalar out."""
    return float(arr) if np.ndim(arr) == 0 else arr


def as_areas(value: ArrayLike, name: str = "ridge area") -> np.ndarray:
    """Return ``value`` as a float array of strictly positive areas (m^2), else raise."""
    arr = as_loads(value, name)
    if np.any(arr <= 0):
        raise FingerpadError(f"{name} must be positive")
    return arr
