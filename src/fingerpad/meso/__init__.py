"""The meso scale: fingerprint ridges touching the surface (ridge contact area A_fr).

* :mod:`.ridges` - constant fraction, power law, sinusoidal (Westergaard) and circular (Hertz line
  contact) ridge models, selectable by name (:data:`RIDGE_MODELS`);
* :mod:`.fingerprint` - BEM on a synthetic or measured fingerprint topography.
"""

from .fingerprint import FingerprintBEMRidges, fingerprint_topography
from .ridges import (
    RIDGE_MODELS,
    CircularRidges,
    ConstantFractionRidges,
    PowerLawRidges,
    RidgeAreaModel,
    SinusoidalRidges,
    ridge_model_curves,
)

__all__ = ["RIDGE_MODELS", "CircularRidges", "ConstantFractionRidges", "FingerprintBEMRidges", "PowerLawRidges",
           "RidgeAreaModel", "SinusoidalRidges", "fingerprint_topography", "ridge_model_curves"]
