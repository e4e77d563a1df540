"""Empirical power-law gross area of the finger pad, ``A_g = c F^m`` (a pad model of one file)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, as_loads, scalar_out
from ..params import Model, Param, check_fields

__all__ = ["PowerLawArea"]


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

    #: The declared fields (units, bounds).
    #: The publications of this model (:mod:`fingerpad.references` keys; an empirical law: the thesis, cited by every run).
    REFERENCES: ClassVar[tuple[str, ...]] = ()
    #: ``area_checked`` is elementwise in the fields, with no arithmetic of the fields alone: many
    #: fingers' models of this class are evaluated as one with column arrays of the fields they
    #: differ in, each row the bits of its own model (fingerpad.coupling.members.FingerStack)
    STACKS: ClassVar[bool] = True
    PARAMS: ClassVar[tuple[Param, ...]] = (
        Param("coefficient", "ratio", "c of A_g = c F^m, m^2/N^m", low=0, low_open=True, example=1e-4,
              label="power-law coefficient c"),
        Param("exponent", "ratio", "m of A_g = c F^m (docs/model.md: 0.1-0.5)", low=0, low_open=True, example=0.3,
              label="power-law exponent m"),
    )

    coefficient: float
    exponent: float

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """``c F^m`` (m^2)."""
        return scalar_out(self.area_checked(as_loads(load)))

    def area_checked(self, load: np.ndarray) -> np.ndarray:
        """The same on loads already checked (a float array >= 0): the finger's path, so that a load is checked once."""
        return self.coefficient * load**self.exponent

    __call__ = area


MODELS = (Model("power_law", PowerLawArea, PowerLawArea.PARAMS, "empirical power law A_g = c F^m"),)
