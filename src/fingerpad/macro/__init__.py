"""The macro scale: the finger pad's gross contact and its nominal pressure distribution.

* :mod:`.gross` - gross-area models against load (Hertz Eq. 2.5, Dzidek Eqs. 2.6-2.7, power laws),
  selectable by name (:data:`GROSS_MODELS`);
* :mod:`.pressure` - the Hertzian pad pressure over the ridge contact (Eq. 3.7) and averages over
  the contact disc.
"""

from .gross import GROSS_MODELS, DzidekArea, GrossAreaModel, HertzArea, PowerLawArea, TwoRegimePowerLawArea
from .pressure import disc_average, pad_pressure

__all__ = ["GROSS_MODELS", "DzidekArea", "GrossAreaModel", "HertzArea", "PowerLawArea", "TwoRegimePowerLawArea",
           "disc_average", "pad_pressure"]
