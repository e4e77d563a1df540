"""What every pad (gross-area) model shares: the :class:`GrossAreaModel` protocol, the Hertz area
of Eq. 2.5, and the declarations of the pad's radius and modulus (a helper module: it declares no
model)."""

from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

import numpy as np

from ..checks import ArrayLike
from ..params import Param

__all__ = ["PAD_MODULUS", "PAD_RADIUS", "GrossAreaModel", "hertz_area"]


@runtime_checkable
class GrossAreaModel(Protocol):
    """Gross contact area of the finger pad: ``area(load) -> A_g`` (m^2), vectorised."""

    def area(self, load: ArrayLike) -> float | np.ndarray: ...

    # A model may also define ``area_checked(f)``, the same on loads already checked (a float
    # array >= 0): the finger calls it when present, so that a load is checked once.


def hertz_area(load: np.ndarray, radius: float, modulus: np.ndarray | float) -> np.ndarray:
    """``pi (3 F R / (4 E*))^(2/3)`` (m^2), Eq. 2.5."""
    return math.pi * (3.0 * load * radius / (4.0 * modulus)) ** (2.0 / 3.0)


#: The pad radius R_fp and reduced modulus E_fp* (models that take them get the finger's).
PAD_RADIUS = Param("radius", "length", "equivalent pad radius R_fp (docs/model.md: 7-11 mm)", low=0, low_open=True,
                   example="9mm", label="pad radius R_fp", plausible="pad radius", symbol="R_fp")
PAD_MODULUS = Param("modulus", "pressure", "pad reduced modulus E_fp* (docs/model.md: 10-100 kPa)", low=0,
                    low_open=True, example="40kPa", label="pad modulus E_fp*", plausible="pad modulus",
                    symbol="E_fp*")
