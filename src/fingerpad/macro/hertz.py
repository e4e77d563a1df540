"""Hertz sphere-on-flat gross area of the finger pad, Eq. 2.5 (a pad model of one file)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, as_loads, scalar_out
from ..params import Model, Param, check_fields
from ._base import PAD_MODULUS, PAD_RADIUS, hertz_area

__all__ = ["HertzArea"]


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

    #: The declared fields (units, bounds), so study files can give "9mm", "40kPa", ...
    #: The publications of this model (:mod:`fingerpad.references` keys; Hertz contact of a sphere).
    REFERENCES: ClassVar[tuple[str, ...]] = ("johnson1985",)
    #: ``area_checked`` is elementwise in the fields, with no arithmetic of the fields alone: many
    #: fingers' models of this class are evaluated as one with column arrays of the fields they
    #: differ in, each row the bits of its own model (fingerpad.coupling.members.FingerStack)
    STACKS: ClassVar[bool] = True
    PARAMS: ClassVar[tuple[Param, ...]] = (PAD_RADIUS, PAD_MODULUS)

    radius: float
    modulus: float

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)

    def contact_radius(self, load: ArrayLike) -> float | np.ndarray:
        """Hertz contact radius ``a = (3 F R / (4 E*))^(1/3)``, m."""
        f = as_loads(load)
        return scalar_out(np.cbrt(3.0 * f * self.radius / (4.0 * self.modulus)))

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2), Eq. 2.5."""
        return scalar_out(self.area_checked(as_loads(load)))

    def area_checked(self, load: np.ndarray) -> np.ndarray:
        """The same on loads already checked (a float array >= 0): the finger's path, so that a load is checked once."""
        return hertz_area(load, self.radius, self.modulus)

    __call__ = area


MODELS = (
    Model("hertz", HertzArea, HertzArea.PARAMS, "Hertz sphere on a flat, Eq. 2.5",
          inherits={"radius": "finger.radius", "modulus": "finger.modulus"}),
)
