"""Hertz with a strain-stiffened secant modulus (Dzidek et al. 2017), Eqs. 2.6-2.7 (a pad model
of one file)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, as_loads, scalar_out
from ..params import Model, Param, check_fields
from ._base import PAD_MODULUS, PAD_RADIUS, hertz_area

__all__ = ["DzidekArea"]


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

    #: The declared fields (units, bounds), so study files can give "9mm", "40kPa", ...
    #: The publications of this model (:mod:`fingerpad.references` keys; the stiffened modulus; Hertz).
    REFERENCES: ClassVar[tuple[str, ...]] = ("dzidek2017", "johnson1985")
    #: ``area_checked`` is elementwise in the fields, with no arithmetic of the fields alone: many
    #: fingers' models of this class are evaluated as one with column arrays of the fields they
    #: differ in, each row the bits of its own model (fingerpad.coupling.members.FingerStack)
    STACKS: ClassVar[bool] = True
    PARAMS: ClassVar[tuple[Param, ...]] = (
        PAD_RADIUS,
        PAD_MODULUS,
        Param("stiffening", "ratio", "Dzidek's stiffening C (strain range eps < 1/C)", low=0, example=5,
              label="Dzidek stiffening C"),
        Param("exponent", "ratio", "Dzidek's exponent eta (docs/model.md: 3)", 3.0, low=0, low_open=True,
              label="Dzidek exponent eta"),
    )

    radius: float
    modulus: float
    stiffening: float
    exponent: float = 3.0

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)

    @property
    def phi(self) -> float:
        """``phi = 3 (0.2 C)^3 / (4 R^2 E*)`` of Eq. 2.7 (1/N; meaningful for eta = 3)."""
        return 3.0 * (0.2 * self.stiffening) ** 3 / (4.0 * self.radius**2 * self.modulus)

    def secant_modulus(self, load: ArrayLike) -> float | np.ndarray:
        """Stiffened modulus ``E_sfp* = E_fp* (1 + (C eps)^eta)``, Eq. 2.6, Pa."""
        return scalar_out(self._secant(as_loads(load)))

    def _secant(self, load: np.ndarray) -> np.ndarray:
        a_hertz = np.cbrt(3.0 * load * self.radius / (4.0 * self.modulus))
        strain = 0.2 * a_hertz / self.radius  # the contact strain estimate of Eq. 2.6
        return self.modulus * (1.0 + (self.stiffening * strain) ** self.exponent)

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2), Eq. 2.7."""
        return scalar_out(self.area_checked(as_loads(load)))

    def area_checked(self, load: np.ndarray) -> np.ndarray:
        """The same on loads already checked (a float array >= 0): the finger's path, so that a load is checked once."""
        return hertz_area(load, self.radius, self._secant(load))

    __call__ = area


MODELS = (
    Model("dzidek", DzidekArea, DzidekArea.PARAMS, "Hertz with Dzidek's strain-stiffened secant modulus, Eqs. 2.6-2.7",
          inherits={"radius": "finger.radius", "modulus": "finger.modulus"}),
)
