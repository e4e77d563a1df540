"""Fingerprint ridges as 1-D sinusoids, Westergaard per ridge (a ridge model of one file)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, scalar_out
from ..params import Model, Param
from ._base import PROFILE_PARAMS, ProfileRidges

__all__ = ["SinusoidalRidges"]


@dataclass(frozen=True, kw_only=True)
class SinusoidalRidges(ProfileRidges):
    """Ridges as 1-D sinusoids (Westergaard; Rodriguez Urribarri et al.).

    Each ridge has wavelength ``lambda_r`` and amplitude ``h_r``; full contact needs
    ``p* = pi E* h_r / lambda_r`` and below it the contact fraction is
    ``(2/pi) arcsin(sqrt(p/p*))`` (Westergaard 1939; Johnson, Contact Mechanics 13.2).
    Under the Hertzian gross pressure the closed form is
    ``A_fr/A_g = 1 - 3/(8 k^2)`` for ``k = 1.5 p_mean / p* >= 1`` (used as a test).

    Attributes
    ----------
    wavelength
        Ridge wavelength lambda_r, m (docs/model.md: 0.4-0.5 mm).
    amplitude
        Sinusoid amplitude h_r (half the peak-to-valley height), m.
    modulus
        Reduced modulus E* of the ridge skin, Pa (thesis Fig. 2.4: 100 kPa).
    pressure_distribution
        ``"hertz"`` (default) or ``"uniform"`` gross pressure.
    """

    #: The declared fields (units, bounds), so study files can give "0.45mm", "100kPa", ...
    #: The publications of this model (:mod:`fingerpad.references` keys; Westergaard per ridge).
    REFERENCES: ClassVar[tuple[str, ...]] = ("westergaard1939", "johnson1985")
    PARAMS: ClassVar[tuple[Param, ...]] = (
        *PROFILE_PARAMS,
        Param("amplitude", "length", "sinusoid amplitude h_r (half the ridge height)", 30e-6, low=0, low_open=True,
              label="ridge amplitude"),
    )

    amplitude: float = 30e-6

    @property
    def full_contact_pressure(self) -> float:
        """Westergaard full-contact pressure ``p* = pi E* h_r / lambda_r``, Pa."""
        return math.pi * self.modulus * self.amplitude / self.wavelength

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:
        """Ridge contact fraction ``(2/pi) arcsin(sqrt(min(p/p*, 1)))`` at local pressure p."""
        p = np.asarray(pressure, dtype=float)
        ratio = np.clip(p / self.full_contact_pressure, 0.0, 1.0)
        return scalar_out((2.0 / math.pi) * np.arcsin(np.sqrt(ratio)))


MODELS = (Model("sinusoidal", SinusoidalRidges, SinusoidalRidges.PARAMS, "sinusoidal ridges, Westergaard per ridge"),)
