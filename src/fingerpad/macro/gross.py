"""Gross contact area of the finger pad against the load (macro scale, thesis ch. 2.2.1).

Every model has ``area(load) -> A_g`` (m^2, vectorised; the :class:`GrossAreaModel` protocol).
:data:`GROSS_MODELS` names them for study files and the command line
(``[finger.gross] model = "dzidek"``); a model that takes the pad's radius and modulus gets them
from the finger.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np

from ..checks import ArrayLike, as_loads, nonnegative, positive, scalar_out

__all__ = ["GROSS_MODELS", "DzidekArea", "GrossAreaModel", "HertzArea", "PowerLawArea", "TwoRegimePowerLawArea"]


@runtime_checkable
class GrossAreaModel(Protocol):
    """Gross contact area of the finger pad: ``area(load) -> A_g`` (m^2), vectorised."""

    def area(self, load: ArrayLike) -> float | np.ndarray: ...


def _hertz_area(load: np.ndarray, radius: float, modulus: np.ndarray | float) -> np.ndarray:
    return math.pi * (3.0 * load * radius / (4.0 * modulus)) ** (2.0 / 3.0)


@dataclass(frozen=True)
class HertzArea:
    """Hertz sphere-on-flat gross area, Eq. 2.5: ``A = pi (3 F R / (4 E*))^(2/3)``.

    Attributes
    ----------
    radius
        Equivalent pad radius R_fp, m (docs/model.md: 7-11 mm).
    modulus
        Reduced modulus E_fp*, Pa (docs/model.md: 10-100 kPa, 40 kPa typical).
    """

    #: Field -> dimension, so study files can give "9mm", "40kPa", ...
    QUANTITIES: ClassVar[dict[str, str]] = {'radius': 'length', 'modulus': 'pressure'}

    radius: float
    modulus: float

    def __post_init__(self) -> None:
        positive(self.radius, "pad radius R_fp")
        positive(self.modulus, "pad modulus E_fp*")

    def contact_radius(self, load: ArrayLike) -> float | np.ndarray:
        """Hertz contact radius ``a = (3 F R / (4 E*))^(1/3)``, m."""
        f = as_loads(load)
        return scalar_out(np.cbrt(3.0 * f * self.radius / (4.0 * self.modulus)))

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2), Eq. 2.5."""
        return scalar_out(_hertz_area(as_loads(load), self.radius, self.modulus))

    __call__ = area


@dataclass(frozen=True)
class DzidekArea:
    """Hertz with a strain-stiffened secant modulus (Dzidek et al. 2017), Eqs. 2.6-2.7.

    ``E_sfp* = E_fp* (1 + (C eps)^eta)`` with the contact strain estimated from the Hertz radius,
    ``eps = 0.2 a_H / R_fp``. For ``eta = 3`` this is exactly Eq. 2.7:
    ``A_g = pi (3 R F / (4 E* (1 + phi F)))^(2/3)``, ``phi = 3 (0.2 C)^3 / (4 R^2 E*)``.
    Other ``eta`` use the same strain estimate. The local exponent ``d ln A / d ln F`` is
    ``(2/3) / (1 + phi F)``: it falls with load as the skin is pressed on the bone.

    Attributes
    ----------
    radius, modulus
        R_fp (m) and the unstiffened E_fp* (Pa).
    stiffening
        Dzidek's C (dimensionless; strain range ``eps < 1/C``).
    exponent
        eta (docs/model.md: 3).
    """

    #: Field -> dimension, so study files can give "9mm", "40kPa", ...
    QUANTITIES: ClassVar[dict[str, str]] = {'radius': 'length', 'modulus': 'pressure', 'stiffening': 'none', 'exponent': 'none'}

    radius: float
    modulus: float
    stiffening: float
    exponent: float = 3.0

    def __post_init__(self) -> None:
        positive(self.radius, "pad radius R_fp")
        positive(self.modulus, "pad modulus E_fp*")
        nonnegative(self.stiffening, "Dzidek stiffening C")
        positive(self.exponent, "Dzidek exponent eta")

    @property
    def phi(self) -> float:
        """``phi = 3 (0.2 C)^3 / (4 R^2 E*)`` of Eq. 2.7 (1/N; meaningful for eta = 3)."""
        return 3.0 * (0.2 * self.stiffening) ** 3 / (4.0 * self.radius**2 * self.modulus)

    def secant_modulus(self, load: ArrayLike) -> float | np.ndarray:
        """Stiffened modulus ``E_sfp* = E_fp* (1 + (C eps)^eta)``, Eq. 2.6, Pa."""
        f = as_loads(load)
        a_hertz = np.cbrt(3.0 * f * self.radius / (4.0 * self.modulus))
        strain = 0.2 * a_hertz / self.radius
        return scalar_out(self.modulus * (1.0 + (self.stiffening * strain) ** self.exponent))

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2), Eq. 2.7."""
        f = as_loads(load)
        return scalar_out(_hertz_area(f, self.radius, np.asarray(self.secant_modulus(f))))

    __call__ = area


@dataclass(frozen=True)
class PowerLawArea:
    """Empirical gross area ``A_g = c F^m`` (per-person fit; docs/model.md: m = 0.1-0.5 measured).

    Attributes
    ----------
    coefficient
        c, m^2 / N^m.
    exponent
        m.
    """

    #: Field -> dimension, so study files can give "9mm", "40kPa", ...
    QUANTITIES: ClassVar[dict[str, str]] = {'coefficient': 'none', 'exponent': 'none'}

    coefficient: float
    exponent: float

    def __post_init__(self) -> None:
        positive(self.coefficient, "power-law coefficient c")
        positive(self.exponent, "power-law exponent m")

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """``c F^m`` (m^2)."""
        return scalar_out(self.coefficient * as_loads(load) ** self.exponent)

    __call__ = area


@dataclass(frozen=True)
class TwoRegimePowerLawArea:
    """Two power laws joined continuously at a break load (Liu et al.: below/above ~2 N).

    ``A_g = c1 F^m1`` for ``F <= F_b`` and ``c1 F_b^m1 (F/F_b)^m2`` above, so the area is
    continuous at ``F_b`` and only the exponent changes.

    Attributes
    ----------
    coefficient
        c1 (m^2 / N^m1).
    exponent_low, exponent_high
        m1 below and m2 above the break load.
    break_load
        F_b, N (docs/model.md: ~2 N).
    """

    #: Field -> dimension, so study files can give "9mm", "40kPa", ...
    QUANTITIES: ClassVar[dict[str, str]] = {'coefficient': 'none', 'exponent_low': 'none', 'exponent_high': 'none', 'break_load': 'force'}

    coefficient: float
    exponent_low: float
    exponent_high: float
    break_load: float = 2.0

    def __post_init__(self) -> None:
        positive(self.coefficient, "power-law coefficient c1")
        positive(self.exponent_low, "exponent m1")
        positive(self.exponent_high, "exponent m2")
        positive(self.break_load, "break load F_b")

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross area (m^2) from the regime the load falls in."""
        f = as_loads(load)
        fb = self.break_load
        low = self.coefficient * f**self.exponent_low
        high = self.coefficient * fb**self.exponent_low * (f / fb) ** self.exponent_high
        return scalar_out(np.where(f <= fb, low, high))

    __call__ = area


#: Gross-area models by name (study files, command line).
GROSS_MODELS: dict[str, type] = {
    "hertz": HertzArea,
    "dzidek": DzidekArea,
    "power_law": PowerLawArea,
    "two_regime": TwoRegimePowerLawArea,
}
