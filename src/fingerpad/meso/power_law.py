"""Empirical power-law ridge area ``A_fr = k F^n`` (a ridge model of one file)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, scalar_out
from ..params import Model, Param, check_fields
from ._base import load_and_gross

__all__ = ["PowerLawRidges"]


@dataclass(frozen=True)
class PowerLawRidges:
    """Empirical ridge area ``A_fr = k F^n`` (docs/model.md: n = 0.2-0.7, fitted per person).

    Capped at the gross area, since ridges cannot touch outside the gross contact.

    Attributes
    ----------
    coefficient
        k, m^2 / N^n.
    exponent
        n.
    """

    #: The declared fields (units, bounds).
    #: The publications of this model (:mod:`fingerpad.references` keys; an empirical law: the thesis, cited by every run).
    REFERENCES: ClassVar[tuple[str, ...]] = ()
    #: ``area_checked`` is elementwise in the fields, with no arithmetic of the fields alone: many
    #: fingers' models of this class are evaluated as one with column arrays of the fields they
    #: differ in, each row the bits of its own model (fingerpad.coupling.members.FingerStack)
    STACKS: ClassVar[bool] = True
    PARAMS: ClassVar[tuple[Param, ...]] = (
        Param("coefficient", "ratio", "k of A_fr = k F^n, m^2/N^n", low=0, low_open=True, example=5e-5,
              label="ridge power-law coefficient k"),
        Param("exponent", "ratio", "n of A_fr = k F^n (docs/model.md: 0.2-0.7)", low=0, low_open=True,
              example=0.45, label="ridge power-law exponent n"),
    )

    coefficient: float
    exponent: float

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """``min(k F^n, A_g)`` (m^2)."""
        return scalar_out(self.area_checked(*load_and_gross(load, gross_area)))

    def area_checked(self, f: np.ndarray, ag: np.ndarray) -> np.ndarray:
        """The same on loads and gross areas already checked and broadcast (float arrays >= 0): the finger's path, so that a load is checked once."""
        return np.minimum(self.coefficient * f**self.exponent, ag)


MODELS = (Model("power_law", PowerLawRidges, PowerLawRidges.PARAMS, "empirical power law A_fr = k F^n, capped at A_g"),)
