"""The thesis's friction law (Sergachev 2021, ch. 2.1; docs/model.md section 3), a law of one file:

* adhesion ``F_adh = tau A_re`` with ``tau = tau0 + alpha p_re``, Eqs. 2.2-2.3; with the mean
  real pressure ``p_re = F / A_re`` this is ``F_adh = tau0 A_re + alpha F``;
* hysteresis ``F_def`` (Greenwood-Tabor), Eq. 2.4, with the pad's radius and modulus;
* total ``F_f = F_adh + F_def``, Eq. 2.1.

SI units (m, N, Pa).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ._base import LawSpec

__all__ = ["ThesisFriction", "adhesion_term", "hysteresis_coefficient", "hysteresis_term"]


def adhesion_term(f: np.ndarray, a: np.ndarray, tau0: float, alpha: float) -> np.ndarray:
    """``tau0 A_re + alpha F`` (N), Eqs. 2.2-2.3 with ``p_re = F / A_re``."""
    return tau0 * a + alpha * f


def hysteresis_coefficient(radius: float, beta: float) -> float:
    """``beta (9 / (128 R))^(2/3)`` of Eq. 2.4 (a Python float: the same bits for one law and for
    a stack of them, :meth:`ThesisFriction.friction_of_many`)."""
    return beta * (9.0 / (128.0 * radius)) ** (2.0 / 3.0)


def hysteresis_term(f: np.ndarray, radius: float, modulus: float, beta: float) -> np.ndarray:
    """``beta (9 / (128 R))^(2/3) (F^4 / E0*)^(1/3)`` (N), Eq. 2.4."""
    return hysteresis_coefficient(radius, beta) * np.cbrt(f**4 / modulus)


@dataclass(frozen=True)
class ThesisFriction:
    """``F_f = (tau0 + alpha p_re) A_re + F_def``, Eqs. 2.1-2.4.

    Attributes
    ----------
    tau0, alpha
        Shear strength at zero pressure (Pa) and its pressure coefficient (-), Eq. 2.3.
    beta
        Viscoelastic loss fraction (-), Eq. 2.4.
    radius, modulus
        The pad's R_fp (m) and E_fp* (Pa) of Eq. 2.4.
    """

    #: The publications of the law (:mod:`fingerpad.references` keys): adhesion is the thesis'
    #: Eqs. 2.1-2.3, the hysteresis term Greenwood-Tabor's, Eq. 2.4.
    REFERENCES: ClassVar[tuple[str, ...]] = ("greenwood1958",)

    tau0: float
    alpha: float
    beta: float
    radius: float
    modulus: float
    name: str = "thesis"

    @classmethod
    def from_finger(cls, finger: Any) -> "ThesisFriction":
        """The law with the finger's ``tau0``, ``alpha``, ``beta``, ``radius`` and ``modulus``."""
        return cls(float(finger.tau0), float(finger.alpha), float(finger.beta), float(finger.radius),
                   float(finger.modulus))

    def shear_strength(self, real_pressure: np.ndarray) -> np.ndarray:
        return self.tau0 + self.alpha * np.asarray(real_pressure, dtype=float)

    def adhesion(self, load: np.ndarray, real_area: np.ndarray) -> np.ndarray:
        return adhesion_term(load, real_area, self.tau0, self.alpha)

    def hysteresis(self, load: np.ndarray) -> np.ndarray:
        return hysteresis_term(load, self.radius, self.modulus, self.beta)

    def friction(self, load: np.ndarray, real_area: np.ndarray) -> np.ndarray:
        return self.adhesion(load, real_area) + self.hysteresis(load)

    def affine_shear(self) -> tuple[float, float]:
        return self.tau0, self.alpha

    @staticmethod
    def friction_of_many(laws: Sequence["ThesisFriction"], load: np.ndarray, real_area: np.ndarray) -> np.ndarray:
        """:meth:`friction` of many laws at once: ``load`` and ``real_area`` are ``(laws, ...)``
        arrays, row ``i`` that of ``laws[i]``; each entry the bits of that law's own
        :meth:`friction` (its constants as column arrays, Eq. 2.4's field-only factor as Python
        floats, as for one law)."""
        def column(values: list[float]) -> np.ndarray:
            return np.array(values, dtype=float).reshape(-1, *([1] * (load.ndim - 1)))

        coef = column([hysteresis_coefficient(law.radius, law.beta) for law in laws])
        return (adhesion_term(load, real_area, column([law.tau0 for law in laws]),  # type: ignore[arg-type]
                              column([law.alpha for law in laws]))
                + coef * np.cbrt(load**4 / column([law.modulus for law in laws])))


LAWS = (
    LawSpec("thesis", ThesisFriction.from_finger, ("tau0", "alpha", "beta", "radius", "modulus"),
            "adhesion (tau0 + alpha p_re) on A_re plus Greenwood-Tabor hysteresis, Eqs. 2.1-2.4"),
)
