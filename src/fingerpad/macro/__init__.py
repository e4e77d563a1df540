"""The macro scale: the finger pad's gross contact and its nominal pressure distribution.

* pad (gross-area) models against load, one file each: :mod:`.hertz` (Eq. 2.5), :mod:`.dzidek`
  (Eqs. 2.6-2.7), :mod:`.power_law`, :mod:`.two_regime`. Each file declares its models in a
  module attribute ``MODELS = (Model(...),)`` (:class:`fingerpad.params.Model`: the class, its
  declared parameters, what it takes from the finger); this package finds them, so a new pad
  model is one file, selectable by name from a study file (``[finger] gross = "dzidek"``,
  :data:`GROSS_MODELS`);
* :mod:`.pressure` - the Hertzian pad pressure over the ridge contact (Eq. 3.7) and averages over
  the contact disc (a helper module, like :mod:`._base`, the protocol and shared declarations);
* :mod:`.jkr` - the adhesive pad (JKR, Eqs. 3.15-3.16), which a prediction with a work of
  adhesion builds from the Hertz pad (a helper module: not chosen by name).
"""

from ..params import Model
from ._base import GrossAreaModel
from .dzidek import DzidekArea
from .hertz import HertzArea
from .power_law import PowerLawArea
from .pressure import disc_average, pad_pressure
from .two_regime import TwoRegimePowerLawArea

#: Modules of this package that declare no model (``jkr``: the adhesive pad a prediction builds
#: from the finger's Hertz pad, not chosen by name).
HELPER_MODULES = frozenset({"pressure", "jkr"})


#: Pad (gross-area) models by name (study files), filled by :func:`discover_models`.
GROSS_MODELS: dict[str, Model] = {}


def discover_models() -> dict[str, Model]:
    """Find the pad models declared by the files of this package (``MODELS`` of each module of
    ``__path__``, helpers excepted) and fill :data:`GROSS_MODELS` with them; run on import.

    Raises
    ------
    fingerpad.discover.DiscoveryError
        A module that declares no ``MODELS`` (see :func:`fingerpad.discover.collect`).
    ValueError
        Two models of the same name.
    """
    from ..discover import fill_registry

    return fill_registry(GROSS_MODELS, __name__, __path__, "MODELS", Model, skip=HELPER_MODULES, what="pad model")


discover_models()

__all__ = ["GROSS_MODELS", "HELPER_MODULES", "DzidekArea", "GrossAreaModel", "HertzArea", "PowerLawArea",
           "TwoRegimePowerLawArea", "disc_average", "discover_models", "pad_pressure"]
