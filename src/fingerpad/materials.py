"""Elastic materials of the skin and the counter-surface (Eq. 3.4)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import FingerpadError
from .params import Param

#: Effective micro-scale skin modulus found by the thesis: 0.2-0.5 MPa (docs/model.md, micro scale).
DEFAULT_SKIN_MODULUS = 0.3e6
DEFAULT_SKIN_POISSON = 0.49

#: The counter-surface's declared values (``[material]`` of a study, its sweep axes); a missing
#: modulus is a rigid counter-surface.
MATERIAL_MODULUS = Param("modulus", "pressure", "Young's modulus E_m of the textured material (or rigid)", None,
                         low=0, low_open=True, example="0.5GPa", label="material modulus",
                         plausible="material modulus")
MATERIAL_POISSON = Param("poisson", "ratio", "Poisson ratio nu_m of the textured material", 0.35, low=-1,
                         low_open=True, high=0.5, example=0.4, label="material Poisson ratio")


def check_modulus(value: float, name: str = "modulus") -> float:
    """Return ``value`` if it is a finite, strictly positive modulus (Pa), else raise."""
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise FingerpadError(f"{name} must be a positive number of pascals, got {value!r}")
    return float(value)


def check_poisson(value: float, name: str = "Poisson ratio") -> float:
    """Return ``value`` if it is a Poisson ratio in [-1, 0.5], else raise."""
    if not (isinstance(value, (int, float)) and math.isfinite(value) and -1.0 < value <= 0.5):
        raise FingerpadError(f"{name} must lie in (-1, 0.5], got {value!r}")
    return float(value)


def reduced_modulus(
    skin_modulus: float,
    skin_poisson: float = DEFAULT_SKIN_POISSON,
    material_modulus: float | None = None,
    material_poisson: float = 0.35,
) -> float:
    """Combined (reduced) modulus E1* of skin and counter-surface, Eq. 3.4.

    ``1/E1* = (1 - nu_s^2)/E_s + (1 - nu_m^2)/E_m``; a rigid counter-surface
    (``material_modulus=None``) drops the second term.

    Parameters
    ----------
    skin_modulus, material_modulus
        Young's moduli in Pa.
    skin_poisson, material_poisson
        Poisson ratios.

    Returns
    -------
    float
        E1* in Pa.
    """
    es = check_modulus(skin_modulus, "skin modulus")
    nus = check_poisson(skin_poisson, "skin Poisson ratio")
    compliance = (1.0 - nus**2) / es
    if material_modulus is not None:
        em = check_modulus(material_modulus, "material modulus")
        num = check_poisson(material_poisson, "material Poisson ratio")
        compliance += (1.0 - num**2) / em
    return 1.0 / compliance


@dataclass(frozen=True)
class Materials:
    """Skin and counter-surface elastic constants (SI).

    ``material_modulus=None`` means a rigid counter-surface.
    """

    skin_modulus: float = DEFAULT_SKIN_MODULUS
    skin_poisson: float = DEFAULT_SKIN_POISSON
    material_modulus: float | None = None
    material_poisson: float = 0.35

    def __post_init__(self) -> None:
        reduced_modulus(self.skin_modulus, self.skin_poisson, self.material_modulus, self.material_poisson)

    @property
    def reduced_modulus(self) -> float:
        """E1* (Pa), Eq. 3.4."""
        return reduced_modulus(self.skin_modulus, self.skin_poisson, self.material_modulus, self.material_poisson)

    def as_dict(self) -> dict[str, float | None]:
        return {
            "skin_modulus": self.skin_modulus,
            "skin_poisson": self.skin_poisson,
            "material_modulus": self.material_modulus,
            "material_poisson": self.material_poisson,
            "reduced_modulus": self.reduced_modulus,
        }
