"""The coupling of the three scales: pad pressure x psi(p) -> real area, zones, critical loads.

* :mod:`.curve` - one finger on one unit cell: :func:`couple`, :func:`critical_load`,
  :func:`adhesion_integral`, :func:`predict_curve` (Eqs. 3.6-3.12);
* :mod:`.members` - many fingers on one unit cell at once, :func:`predict_members`: the
  vectorised twin of :func:`predict_curve`, bit for bit (an equation changed in one is changed
  in the other, here beside it);
* :mod:`.loads` - many fingers' areas as one (:class:`~.loads.FingerStack`) and the one search
  of the load at which a pad centre reaches a pressure (:func:`~.loads.centre_loads`).

SI units (m, N, Pa).
"""

from . import curve
from .curve import *  # noqa: F403 - the face hands on curve's public names
from .members import predict_members

__all__ = [*curve.__all__, "predict_members"]
