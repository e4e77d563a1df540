"""Warnings for numbers far outside the physical range of their role (a unit probably forgotten).

A bare number is SI, so ``--radius 50`` is a 50 m asperity: legal, but almost surely meant as
50 um. Such values are not refused (a user may mean them); they raise a
:class:`PlausibilityWarning`, which the command line prints as one ``warning:`` line.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

from .errors import FingerpadError
from .units import format_quantity

__all__ = ["RANGES", "PlausibilityWarning", "check_plausible", "check_plausible_range"]


class PlausibilityWarning(UserWarning):
    """A value far outside the physical range of its role."""


#: Role -> (low, high, dimension, what is typical). Wide on purpose: only a forgotten unit, or a
#: value no finger or texture can have, falls outside.
RANGES: dict[str, tuple[float, float, str, str]] = {
    "texture length": (10e-9, 10e-3, "length", "textures felt by a finger are 10 nm - 10 mm"),
    "load": (1e-3, 100.0, "force", "a finger presses with about 0.01-10 N"),
    "skin modulus": (1e3, 100e6, "pressure", "the skin's micro-scale modulus is about 0.2-0.5 MPa"),
    "pad modulus": (1e3, 10e6, "pressure", "a finger pad's reduced modulus is about 10-100 kPa"),
    # A layered skin (docs/model.md 6.5): the stratum corneum 1 MPa - 1 GPa in vitro, effective
    # values down to a few kPa in vivo; the tissue under it a few kPa to ~100 kPa.
    "skin layer modulus": (1e3, 10e9, "pressure",
                           "the stratum corneum's modulus is about 1 MPa - 1 GPa in vitro, kPa to MPa in vivo"),
    "skin substrate modulus": (100.0, 10e6, "pressure",
                               "the tissue under the stratum corneum is about 5-100 kPa"),
    "material modulus": (1e3, 1e12, "pressure", "materials range from soft gels (kPa) to diamond (1 TPa)"),
    "pressure": (1e-1, 1e9, "pressure", "contact pressures of skin are Pa to MPa"),
    "pad radius": (1e-3, 50e-3, "length", "a finger pad's equivalent radius is about 7-11 mm"),
    "friction coefficient": (0.02, 5.0, "none", "finger friction coefficients are about 0.1-3"),
}


def check_plausible(value: float, role: str, name: str) -> None:
    """Warn (:class:`PlausibilityWarning`) when ``value`` (SI) is outside the range of ``role``."""
    if role not in RANGES:
        raise FingerpadError(f"unknown plausibility role {role!r}")
    low, high, dimension, typical = RANGES[role]
    if not math.isfinite(value) or low <= abs(value) <= high:
        return
    shown = format_quantity(value, dimension) if dimension != "none" else f"{value:.4g}"
    side = "small" if abs(value) < low else "large"
    hint = " (a bare number is in SI units: did you forget a unit suffix such as um, kPa or N?)" \
        if dimension != "none" else ""
    warnings.warn(f"{name} = {shown} is very {side} for a {role}: {typical}{hint}", PlausibilityWarning,
                  stacklevel=3)


def check_plausible_range(values: Sequence[float], role: str, name: str) -> None:
    """One warning (:class:`PlausibilityWarning`) for the ``values`` (SI) of many draws (a
    population's members) outside the range of ``role``: how many, and their extremes."""
    if role not in RANGES:
        raise FingerpadError(f"unknown plausibility role {role!r}")
    low, high, dimension, typical = RANGES[role]
    finite = [abs(v) for v in values if math.isfinite(v)]
    outside = [v for v in finite if not low <= v <= high]
    if not outside:
        return

    def shown(v: float) -> str:
        return format_quantity(v, dimension) if dimension != "none" else f"{v:.4g}"

    warnings.warn(f"{name}: {len(outside)} of {len(finite)} values lie outside the plausible "
                  f"{shown(low)} - {shown(high)} for a {role} (from {shown(min(finite))} to {shown(max(finite))}): "
                  f"{typical}", PlausibilityWarning, stacklevel=3)
