"""The micro scale: the skin on the texture's asperities, one periodic unit cell at a time.

Every model gives the coupling the same thing (:class:`~fingerpad.micro.response.UnitCellResponse`):
the real-to-nominal area fraction psi(p) of the cell against the local nominal pressure, and the
pressures of the transition (the skin touches the texture's base) and of full contact.

* :mod:`.bem` - the numerical cell, :class:`BEMUnitCell`, from the FFT-BEM of :mod:`fingerpad.contact`;
* :mod:`.hertz` - the analytic per-asperity Hertz cell, :class:`HertzUnitCell` (Eqs. 3.1-3.6);
* :mod:`.loadcurve` - load curves and bracketed state pressures of a cell;
* :mod:`.cache` - the on-disk cache of computed curves;
* :mod:`.layered_cell` - the dimensionless layer of a layered skin's cell and its cache-key settings.
"""

from .bem import BEMUnitCell, ScaledResponse
from .hertz import HertzUnitCell, critical_load_hertz, hertz_cell_for
from .loadcurve import LoadCurve, critical_pressure, full_contact_pressure, load_curve
from .response import PowerLawUnitCell, UnitCellResponse

__all__ = [
    "BEMUnitCell",
    "HertzUnitCell",
    "LoadCurve",
    "PowerLawUnitCell",
    "ScaledResponse",
    "UnitCellResponse",
    "critical_load_hertz",
    "critical_pressure",
    "full_contact_pressure",
    "hertz_cell_for",
    "load_curve",
]
