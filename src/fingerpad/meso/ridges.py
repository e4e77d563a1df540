"""Fingerprint-ridge contact area (meso scale, thesis ch. 2.2.2).

Every model has ``area(load, gross_area) -> A_fr`` (m^2; the :class:`RidgeAreaModel` protocol):
a constant fraction of the gross area, a power law, sinusoidal ridges (Westergaard per ridge),
circular ridges (Hertz line contact per ridge); the BEM on a fingerprint topography is
:class:`fingerpad.meso.fingerprint.FingerprintBEMRidges`. :data:`RIDGE_MODELS` names them for
study files (``[finger.ridges] model = "sinusoidal"``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Literal, Protocol, runtime_checkable

import numpy as np

from ..checks import ArrayLike, as_loads, positive, scalar_out
from ..errors import FingerpadError
from ..macro.gross import HertzArea
from ..macro.pressure import disc_average

__all__ = [
    "RIDGE_MODELS",
    "CircularRidges",
    "ConstantFractionRidges",
    "PowerLawRidges",
    "RidgeAreaModel",
    "SinusoidalRidges",
    "ridge_model_curves",
]


@runtime_checkable
class RidgeAreaModel(Protocol):
    """Ridge contact area from the load and the gross area: ``area(load, gross_area) -> A_fr``.

    Implementations are vectorised (load and gross area broadcast) and return
    ``0 <= A_fr <= A_g``. A BEM fingerprint model (``FingerprintBEMRidges``) plugs in here.
    """

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray: ...


def _load_and_gross(load: ArrayLike, gross_area: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    f = as_loads(load)
    ag = as_loads(gross_area, "gross area")
    return np.broadcast_arrays(f, ag)  # type: ignore[return-value]


@dataclass(frozen=True)
class ConstantFractionRidges:
    """Ridge area as a constant fraction of the gross area (van Kuilenburg; Duvefelt: 50 %).

    Attributes
    ----------
    fraction
        A_fr / A_g in (0, 1] (docs/model.md: 0.5 after Duvefelt).
    """

    #: Field -> dimension, so study files can give "9mm", "40kPa", ...
    QUANTITIES: ClassVar[dict[str, str]] = {'fraction': 'none'}

    fraction: float = 0.5

    def __post_init__(self) -> None:
        v = positive(self.fraction, "ridge fraction")
        if v > 1.0:
            raise FingerpadError(f"ridge fraction must lie in (0, 1], got {self.fraction!r}")

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """``fraction * A_g`` (m^2)."""
        _, ag = _load_and_gross(load, gross_area)
        return scalar_out(self.fraction * ag)


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

    #: Field -> dimension, so study files can give "9mm", "40kPa", ...
    QUANTITIES: ClassVar[dict[str, str]] = {'coefficient': 'none', 'exponent': 'none'}

    coefficient: float
    exponent: float

    def __post_init__(self) -> None:
        positive(self.coefficient, "ridge power-law coefficient k")
        positive(self.exponent, "ridge power-law exponent n")

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """``min(k F^n, A_g)`` (m^2)."""
        f, ag = _load_and_gross(load, gross_area)
        return scalar_out(np.minimum(self.coefficient * f**self.exponent, ag))


PressureDistribution = Literal["hertz", "uniform"]


@dataclass(frozen=True, kw_only=True)
class _ProfileRidges:
    """Parallel ridges across the gross contact, each a 1-D contact set by the local pressure.

    The ridge-area fraction at local nominal pressure p is :meth:`local_fraction`; the ridge
    area is its integral over the gross disc under the Hertzian gross pressure
    ``p(r) = 1.5 p_mean sqrt(1 - r^2/a^2)`` (``pressure_distribution="hertz"``, the ridges being
    much narrower than the gross contact) or ``A_g * local_fraction(p_mean)``
    (``"uniform"``). The disc integral uses :func:`disc_average` (relative error below 1e-13,
    checked against the closed forms quoted by the subclasses). Fields are keyword-only.
    """

    wavelength: float = 0.45e-3
    modulus: float = 100e3
    pressure_distribution: PressureDistribution = "hertz"

    def __post_init__(self) -> None:
        positive(self.wavelength, "ridge wavelength")
        positive(self.modulus, "ridge modulus")
        if self.pressure_distribution not in ("hertz", "uniform"):
            raise FingerpadError(
                f"pressure distribution must be 'hertz' or 'uniform', got {self.pressure_distribution!r}"
            )

    @property
    def full_contact_pressure(self) -> float:  # pragma: no cover - overridden
        raise NotImplementedError

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:  # pragma: no cover
        raise NotImplementedError

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """Ridge contact area A_fr (m^2) under the chosen gross pressure distribution."""
        f, ag = _load_and_gross(load, gross_area)
        shape = f.shape
        f, ag = f.ravel(), ag.ravel()
        with np.errstate(divide="ignore", invalid="ignore"):
            p_mean = np.where(ag > 0, f / ag, 0.0)
        if self.pressure_distribution == "uniform":
            frac = np.asarray(self.local_fraction(p_mean), dtype=float)
        else:
            frac = disc_average(self.local_fraction, 1.5 * p_mean, (self.full_contact_pressure,))
        return scalar_out((frac * ag).reshape(shape))


@dataclass(frozen=True, kw_only=True)
class SinusoidalRidges(_ProfileRidges):
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

    #: Field -> dimension, so study files can give "9mm", "40kPa", ...
    QUANTITIES: ClassVar[dict[str, str]] = {'wavelength': 'length', 'modulus': 'pressure', 'amplitude': 'length', 'pressure_distribution': 'text'}

    amplitude: float = 30e-6

    def __post_init__(self) -> None:
        super().__post_init__()
        positive(self.amplitude, "ridge amplitude")

    @property
    def full_contact_pressure(self) -> float:
        """Westergaard full-contact pressure ``p* = pi E* h_r / lambda_r``, Pa."""
        return math.pi * self.modulus * self.amplitude / self.wavelength

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:
        """Ridge contact fraction ``(2/pi) arcsin(sqrt(min(p/p*, 1)))`` at local pressure p."""
        p = np.asarray(pressure, dtype=float)
        ratio = np.clip(p / self.full_contact_pressure, 0.0, 1.0)
        return scalar_out((2.0 / math.pi) * np.arcsin(np.sqrt(ratio)))


@dataclass(frozen=True, kw_only=True)
class CircularRidges(_ProfileRidges):
    """Ridges as cylinders of radius R_r, each in Hertz line contact.

    Line load ``w = p lambda_r`` (local pressure times ridge spacing), half-width
    ``b = sqrt(4 w R_r / (pi E*))``, contact fraction ``min(2 b / lambda_r, 1)``, i.e.
    ``sqrt(p / p_c)`` with ``p_c = pi E* lambda_r / (16 R_r)``. Under the Hertzian gross pressure
    ``A_fr/A_g = (4/5) sqrt(k)`` for ``k = 1.5 p_mean / p_c <= 1`` and ``1 - 1/(5 k^2)`` above.

    Attributes
    ----------
    wavelength
        Ridge spacing lambda_r, m.
    ridge_radius
        Ridge tip radius R_r, m.
    modulus
        Reduced modulus E* of the ridge skin, Pa.
    pressure_distribution
        ``"hertz"`` (default) or ``"uniform"`` gross pressure.
    """

    #: Field -> dimension, so study files can give "9mm", "40kPa", ...
    QUANTITIES: ClassVar[dict[str, str]] = {'wavelength': 'length', 'modulus': 'pressure', 'ridge_radius': 'length', 'pressure_distribution': 'text'}

    ridge_radius: float = 0.1e-3

    def __post_init__(self) -> None:
        super().__post_init__()
        positive(self.ridge_radius, "ridge radius")

    @property
    def full_contact_pressure(self) -> float:
        """Pressure at which neighbouring line contacts meet, ``pi E* lambda / (16 R_r)``, Pa."""
        return math.pi * self.modulus * self.wavelength / (16.0 * self.ridge_radius)

    def half_width(self, pressure: ArrayLike) -> float | np.ndarray:
        """Hertz line-contact half-width ``b = sqrt(4 w R_r / (pi E*))``, ``w = p lambda``, m."""
        p = np.clip(np.asarray(pressure, dtype=float), 0.0, None)
        w = p * self.wavelength
        return scalar_out(np.sqrt(4.0 * w * self.ridge_radius / (math.pi * self.modulus)))

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:
        """Ridge contact fraction ``min(2 b / lambda_r, 1)`` at local pressure p."""
        b = np.asarray(self.half_width(pressure))
        return scalar_out(np.minimum(2.0 * b / self.wavelength, 1.0))



#: Ridge-area models by name (study files, command line).
RIDGE_MODELS: dict[str, type] = {
    "constant_fraction": ConstantFractionRidges,
    "power_law": PowerLawRidges,
    "sinusoidal": SinusoidalRidges,
    "circular": CircularRidges,
}


def ridge_model_curves(
    loads: ArrayLike,
    *,
    skin_modulus: float = 100e3,
    radius: float = 9e-3,
    wavelength: float = 0.45e-3,
    amplitude: float = 30e-6,
    ridge_radius: float = 0.1e-3,
    fraction: float = 0.5,
    power_exponent: float = 0.45,
    bem_loads: ArrayLike | None = None,
) -> dict[str, np.ndarray]:
    """Gross and ridge areas (m^2) of every model on the same inputs, for a plot or a table.

    With ``bem_loads`` the BEM fingerprint model (:class:`fingerpad.meso.fingerprint.FingerprintBEMRidges`,
    whorl ridges of the same wavelength and height, width 2/3 of the wavelength) is solved at
    those loads (a few seconds each) and returned as ``BEM load`` / ``BEM``.

    The power-law ridge model is anchored to the constant-fraction one at 1 N
    (``k = fraction * A_g(1 N)``) with the mid-range exponent ``power_exponent``.

    Returns
    -------
    dict
        ``load`` and one array per model: ``gross (Hertz)``, ``constant fraction``,
        ``power law``, ``sinusoidal``, ``circular``.
    """
    f = as_loads(loads, strict=True).ravel()
    hertz = HertzArea(radius, skin_modulus)
    ag = np.asarray(hertz.area(f))
    k = fraction * float(hertz.area(1.0))
    models: dict[str, RidgeAreaModel] = {
        "constant fraction": ConstantFractionRidges(fraction),
        "power law": PowerLawRidges(k, power_exponent),
        "sinusoidal": SinusoidalRidges(wavelength=wavelength, modulus=skin_modulus, amplitude=amplitude),
        "circular": CircularRidges(wavelength=wavelength, modulus=skin_modulus, ridge_radius=ridge_radius),
    }
    out = {"load": f, "gross (Hertz)": ag}
    for label, model in models.items():
        out[label] = np.asarray(model.area(f, ag))
    if bem_loads is not None:
        from .fingerprint import FingerprintBEMRidges

        fb = as_loads(bem_loads, strict=True).ravel()
        bem = FingerprintBEMRidges(
            pad_radius=radius, modulus=skin_modulus, wavelength=wavelength, width=2 * wavelength / 3,
            height=2 * amplitude, max_load=float(fb.max()),
        )
        out["BEM load"] = fb
        out["BEM"] = np.asarray(bem.area(fb))
    return out
