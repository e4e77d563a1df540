"""What the ridge-area models share: the :class:`RidgeAreaModel` protocol and the parallel-ridge
profile models' common part (a helper module: it declares no model)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Literal, Protocol, runtime_checkable

import numpy as np

from ..checks import ArrayLike, as_loads, scalar_out
from ..macro.pressure import disc_average
from ..params import Param, check_fields

if TYPE_CHECKING:
    from ..contact.layered import Layer

__all__ = ["PROFILE_PARAMS", "PressureDistribution", "ProfileRidges", "RidgeAreaModel", "load_and_gross"]


@runtime_checkable
class RidgeAreaModel(Protocol):
    """Ridge contact area from the load and the gross area: ``area(load, gross_area) -> A_fr``.

    Implementations are vectorised (load and gross area broadcast) and return
    ``0 <= A_fr <= A_g``. A BEM fingerprint model (``FingerprintBEMRidges``) plugs in here.
    """

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray: ...

    # A model may also define ``area_checked(f, ag)``, the same on loads and gross areas already
    # checked and broadcast: the finger calls it when present, so that a load is checked once.


def load_and_gross(load: ArrayLike, gross_area: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Loads (N) and gross areas (m^2) checked and broadcast together."""
    f = as_loads(load)
    ag = as_loads(gross_area, "gross area")
    return np.broadcast_arrays(f, ag)  # type: ignore[return-value]


PressureDistribution = Literal["hertz", "uniform"]

#: The fields every parallel-ridge profile model declares.
PROFILE_PARAMS: tuple[Param, ...] = (
    Param("wavelength", "length", "ridge wavelength (spacing) lambda_r (docs/model.md: 0.4-0.5 mm)", 0.45e-3,
          low=0, low_open=True, label="ridge wavelength"),
    Param("modulus", "pressure", "reduced modulus E* of the ridge skin (thesis Fig. 2.4: 100 kPa)", 100e3, low=0,
          low_open=True, label="ridge modulus"),
    Param("pressure_distribution", "choice", "gross pressure over the contact disc", "hertz", ("hertz", "uniform"),
          label="pressure distribution"),
)


@dataclass(frozen=True, kw_only=True)
class ProfileRidges:
    """Parallel ridges across the gross contact, each a 1-D contact set by the local pressure.

    The ridge-area fraction at local nominal pressure p is :meth:`local_fraction`; the ridge
    area is its integral over the gross disc under the Hertzian gross pressure
    ``p(r) = 1.5 p_mean sqrt(1 - r^2/a^2)`` (``pressure_distribution="hertz"``, the ridges being
    much narrower than the gross contact) or ``A_g * local_fraction(p_mean)``
    (``"uniform"``). The disc integral uses :func:`disc_average` (relative error below 1e-13,
    checked against the closed forms quoted by the subclasses). Fields are keyword-only.
    """

    PARAMS: ClassVar[tuple[Param, ...]] = PROFILE_PARAMS

    wavelength: float = 0.45e-3
    modulus: float = 100e3
    pressure_distribution: PressureDistribution = "hertz"

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)

    @property
    def full_contact_pressure(self) -> float:  # pragma: no cover - overridden
        raise NotImplementedError

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:  # pragma: no cover
        raise NotImplementedError

    def with_layer(self, layer: "Layer") -> "ProfileRidges":
        """The model on a layered skin (docs/model.md, "A layered finger through the scales").

        The ridges' modulus becomes the layered skin's effective modulus at the ridge wavenumber,
        ``E*_eff(2 pi / lambda_r) = E1* / K(2 pi t / lambda_r)`` (Pa): exact for the full-contact
        pressure of a sinusoid (the deflection is one harmonic), an approximation below it, where
        the contact patches excite shorter wavelengths too (stiffer for a stiff layer).
        """
        from ..contact.layered import effective_modulus

        return dataclasses.replace(self, modulus=float(effective_modulus(layer, 2.0 * math.pi / self.wavelength)))

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """Ridge contact area A_fr (m^2) under the chosen gross pressure distribution."""
        return scalar_out(self.area_checked(*load_and_gross(load, gross_area)))

    def area_checked(self, f: np.ndarray, ag: np.ndarray) -> np.ndarray:
        """The same on loads and gross areas already checked and broadcast (float arrays >= 0): the finger's path, so that a load is checked once."""
        shape = f.shape
        f, ag = f.ravel(), ag.ravel()
        with np.errstate(divide="ignore", invalid="ignore"):
            p_mean = np.where(ag > 0, f / ag, 0.0)
        if self.pressure_distribution == "uniform":
            frac = np.asarray(self.local_fraction(p_mean), dtype=float)
        else:
            frac = disc_average(self.local_fraction, 1.5 * p_mean, (self.full_contact_pressure,))
        return (frac * ag).reshape(shape)
