"""Two power laws joined continuously at a break load (Liu et al.), a pad model of one file."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, as_loads, scalar_out
from ..params import Model, Param, check_fields

__all__ = ["TwoRegimePowerLawArea"]


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

    #: The declared fields (units, bounds).
    #: The publications of this model (:mod:`fingerpad.references` keys; an empirical law: the thesis, cited by every run).
    REFERENCES: ClassVar[tuple[str, ...]] = ()
    PARAMS: ClassVar[tuple[Param, ...]] = (
        Param("coefficient", "ratio", "c1 of A_g = c1 F^m1 below the break load, m^2/N^m1", low=0, low_open=True,
              example=1e-4, label="power-law coefficient c1"),
        Param("exponent_low", "ratio", "m1, the exponent below the break load", low=0, low_open=True, example=0.4,
              label="exponent m1"),
        Param("exponent_high", "ratio", "m2, the exponent above the break load", low=0, low_open=True, example=0.2,
              label="exponent m2"),
        Param("break_load", "force", "F_b, the load where the exponent changes (docs/model.md: ~2 N)", 2.0, low=0,
              low_open=True, label="break load F_b"),
    )

    coefficient: float
    exponent_low: float
    exponent_high: float
    break_load: float = 2.0

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross area (m^2) from the regime the load falls in."""
        return scalar_out(self.area_checked(as_loads(load)))

    def area_checked(self, load: np.ndarray) -> np.ndarray:
        """The same on loads already checked (a float array >= 0): the finger's path, so that a load is checked once."""
        f = load
        fb = self.break_load
        low = self.coefficient * f**self.exponent_low
        high = self.coefficient * fb**self.exponent_low * (f / fb) ** self.exponent_high
        return np.where(f <= fb, low, high)

    __call__ = area


MODELS = (
    Model("two_regime", TwoRegimePowerLawArea, TwoRegimePowerLawArea.PARAMS,
          "two power laws joined at a break load (Liu et al.)"),
)
