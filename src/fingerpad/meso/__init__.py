"""The meso scale: fingerprint ridges touching the surface (ridge contact area A_fr).

Ridge-area models, one file each: :mod:`.constant_fraction`, :mod:`.power_law`,
:mod:`.sinusoidal` (Westergaard), :mod:`.circular` (Hertz line contact) and :mod:`.fingerprint`
(BEM on a synthetic or measured fingerprint topography). Each file declares its models in a
module attribute ``MODELS = (Model(...),)`` (:class:`fingerpad.params.Model`); this package finds
them, so a new ridge model is one file, selectable by name from a study file
(``[finger] ridges = { model = "sinusoidal", ... }``, :data:`RIDGE_MODELS`). Helper modules:
:mod:`._base` (the protocol, the profile models' common part) and :mod:`.compare`
(:func:`ridge_model_curves`, every model on the same inputs).
"""

from ..params import Model
from ._base import RidgeAreaModel
from .circular import CircularRidges
from .compare import ridge_model_curves
from .constant_fraction import ConstantFractionRidges
from .fingerprint import FingerprintBEMRidges, fingerprint_topography
from .power_law import PowerLawRidges
from .sinusoidal import SinusoidalRidges

#: Modules of this package that declare no model.
HELPER_MODULES = frozenset({"compare"})


#: Ridge-area models by name (study files), filled by :func:`discover_models`.
RIDGE_MODELS: dict[str, Model] = {}


def discover_models() -> dict[str, Model]:
    """Find the ridge models declared by the files of this package (``MODELS`` of each module of
    ``__path__``, helpers excepted) and fill :data:`RIDGE_MODELS` with them; run on import.

    Raises
    ------
    fingerpad.discover.DiscoveryError
        A module that declares no ``MODELS`` (see :func:`fingerpad.discover.collect`).
    ValueError
        Two models of the same name.
    """
    from ..discover import fill_registry

    return fill_registry(RIDGE_MODELS, __name__, __path__, "MODELS", Model, skip=HELPER_MODULES, what="ridge model")


discover_models()

__all__ = ["HELPER_MODULES", "RIDGE_MODELS", "CircularRidges", "ConstantFractionRidges", "FingerprintBEMRidges",
           "PowerLawRidges", "RidgeAreaModel", "SinusoidalRidges", "discover_models", "fingerprint_topography",
           "ridge_model_curves"]
