"""What every friction law shares: the :class:`FrictionLaw` protocol and the declaration a law file
makes (:class:`LawSpec`). A helper module of :mod:`fingerpad.friction` (it declares no law)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

__all__ = ["FrictionLaw", "LawSpec"]


@runtime_checkable
class FrictionLaw(Protocol):
    """A friction law of the finger pad: the friction force from the load and the real contact area.

    Every user of friction asks the law (the coupling, the members' coupling of a population, the
    deflection model, the flat reference), so that a new law (a hydrated skin's, a lubricated
    contact's) is one file of :mod:`fingerpad.friction`.
    """

    #: The law's name (``[finger] friction_law``).
    name: str

    def shear_strength(self, real_pressure: np.ndarray) -> np.ndarray:
        """Interfacial shear strength ``tau`` (Pa) at the real contact pressure (Pa)."""
        ...

    def adhesion(self, load: np.ndarray, real_area: np.ndarray) -> np.ndarray:
        """Interfacial (adhesive) friction ``F_adh`` (N) at loads (N) and real areas (m^2), checked."""
        ...

    def hysteresis(self, load: np.ndarray) -> np.ndarray:
        """Deformation (hysteresis) friction ``F_def`` (N) at loads (N), checked."""
        ...

    def friction(self, load: np.ndarray, real_area: np.ndarray) -> np.ndarray:
        """Total friction force ``F_f`` (N), Eq. 2.1, at loads (N) and real areas (m^2), checked."""
        ...

    def affine_shear(self) -> tuple[float, float]:
        """``(tau0, alpha)`` when ``tau = tau0 + alpha p_re`` (Pa, -): what the deflection model
        of compliant asperities needs (its local shear fixed point is written for that form);
        a law of another form raises :class:`~fingerpad.errors.FingerpadError`."""
        ...


@dataclass(frozen=True)
class LawSpec:
    """A friction law a finger can name: its name, how it is built from the finger's fields
    (``build(finger) -> FrictionLaw``), the finger fields it reads, and one line for listings."""

    name: str
    build: Callable[[Any], FrictionLaw]
    fields: tuple[str, ...]
    summary: str
