"""The ridge-area models side by side on the same inputs (thesis Fig. 2.4 idea), for a plot or a
table (a helper module: it declares no model)."""

from __future__ import annotations

import numpy as np

from ..checks import ArrayLike, as_loads
from ..macro.hertz import HertzArea
from ._base import RidgeAreaModel
from .circular import CircularRidges
from .constant_fraction import ConstantFractionRidges
from .power_law import PowerLawRidges
from .sinusoidal import SinusoidalRidges

__all__ = ["ridge_model_curves"]


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
