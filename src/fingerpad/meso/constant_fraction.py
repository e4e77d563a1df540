"""Ridge area as a constant fraction of the gross area (a ridge model of one file)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, scalar_out
from ..params import Model, Param, check_fields
from ._base import load_and_gross

__all__ = ["ConstantFractionRidges"]


@dataclass(frozen=True)
class ConstantFractionRidges:
    """Ridge area as a constant fraction of the gross area (van Kuilenburg; Duvefelt: 50 %).

    Attributes
    ----------
    fraction
        A_fr / A_g in (0, 1] (docs/model.md: 0.5 after Duvefelt).
    """

    #: The declared fields (units, bounds).
    #: The publications of this model (:mod:`fingerpad.references` keys; the thesis, cited by every run).
    REFERENCES: ClassVar[tuple[str, ...]] = ()
    #: ``area_checked`` is elementwise in the fields, with no arithmetic of the fields alone: many
    #: fingers' models of this class are evaluated as one with column arrays of the fields they
    #: differ in, each row the bits of its own model (fingerpad.coupling.members.FingerStack)
    STACKS: ClassVar[bool] = True
    PARAMS: ClassVar[tuple[Param, ...]] = (
        Param("fraction", "ratio", "A_fr / A_g (docs/model.md: 0.5 after Duvefelt)", 0.5, low=0, low_open=True,
              high=1.0, label="ridge fraction"),
    )

    fraction: float = 0.5

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """``fraction * A_g`` (m^2)."""
        return scalar_out(self.area_checked(*load_and_gross(load, gross_area)))

    def area_checked(self, f: np.ndarray, ag: np.ndarray) -> np.ndarray:
        """The same on loads and gross areas already checked and broadcast (float arrays >= 0): the finger's path, so that a load is checked once."""
        return self.fraction * ag


MODELS = (
    Model("constant_fraction", ConstantFractionRidges, ConstantFractionRidges.PARAMS,
          "a constant fraction of the gross area"),
)
