"""Fingerprint ridges as cylinders in Hertz line contact (a ridge model of one file)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, scalar_out
from ..params import Model, Param
from ._base import PROFILE_PARAMS, ProfileRidges

__all__ = ["CircularRidges"]


@dataclass(frozen=True, kw_only=True)
class CircularRidges(ProfileRidges):
    """Ridges as cylinders of radius R_r, each in Hertz line contact.

    Line load ``w = p lambda_r`` (local pressure times ridge spacing), half-width
    ``b = sqrt(4 w R_r / (pi E*))``, contact fraction ``min(2 b / lambda_r, 1)``, i.e.
    ``sqrt(p / p_c)`` with ``p_c = pi E* lambda_r / (16 R_r)``. Under the Hertzian gross pressure
    ``A_fr/A_g = (4/5) sqrt(k)`` for ``k = 1.5 p_mean / p_c <= 1`` and ``1 - 1/(5 k^2)`` above.

    Attributes
    ----------
    wavelength
        Ridge spacing lambda_r, m.
    ridge_radius
        Ridge tip radius R_r, m.
    modulus
        Reduced modulus E* of the ridge skin, Pa.
    pressure_distribution
        ``"hertz"`` (default) or ``"uniform"`` gross pressure.
    """

    #: The declared fields (units, bounds), so study files can give "0.45mm", "100kPa", ...
    #: The publications of this model (:mod:`fingerpad.references` keys; Hertz line contact).
    REFERENCES: ClassVar[tuple[str, ...]] = ("johnson1985",)
    PARAMS: ClassVar[tuple[Param, ...]] = (
        *PROFILE_PARAMS,
        Param("ridge_radius", "length", "ridge tip radius R_r", 0.1e-3, low=0, low_open=True, label="ridge radius"),
    )

    ridge_radius: float = 0.1e-3

    @property
    def full_contact_pressure(self) -> float:
        """Pressure at which neighbouring line contacts meet, ``pi E* lambda / (16 R_r)``, Pa."""
        return math.pi * self.modulus * self.wavelength / (16.0 * self.ridge_radius)

    def half_width(self, pressure: ArrayLike) -> float | np.ndarray:
        """Hertz line-contact half-width ``b = sqrt(4 w R_r / (pi E*))``, ``w = p lambda``, m."""
        p = np.clip(np.asarray(pressure, dtype=float), 0.0, None)
        w = p * self.wavelength
        return scalar_out(np.sqrt(4.0 * w * self.ridge_radius / (math.pi * self.modulus)))

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:
        """Ridge contact fraction ``min(2 b / lambda_r, 1)`` at local pressure p."""
        b = np.asarray(self.half_width(pressure))
        return scalar_out(np.minimum(2.0 * b / self.wavelength, 1.0))


MODELS = (Model("circular", CircularRidges, CircularRidges.PARAMS, "circular ridges, Hertz line contact per ridge"),)
