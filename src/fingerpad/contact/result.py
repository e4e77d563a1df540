"""What a contact solve returns: the fields and numbers of one cell, and its contact state."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..textures import Texture

__all__ = ["ContactResult", "contact_state", "FULL_CONTACT_TOL"]

#: A cell is in *full contact* when at most this fraction of its area is out of contact. Not zero:
#: where a texture meets its base at an angle (the foot of a cap or a pillar) the skin fills the
#: corner only under a pressure that grows like log(grid) (a pixel there needs a pressure of the
#: order of the corner's logarithmic singularity), so "every pixel touches" never converges with
#: the grid; the pressure at which 1 % of the area is left open does (measured on the default
#: cell: 123, 160, 173, 179 kPa at grids 32-256, against 136, 188, 233, 260 kPa for every pixel).
FULL_CONTACT_TOL = 0.01


def contact_state(contact: np.ndarray, base: np.ndarray) -> str:
    """Contact state of a cell from its contact mask and the texture's base-level mask.

    ``"asperity"``: the skin does not touch the texture's base level (``base``: its lowest level for a
    generated texture, a noise-robust level for a measured map, see :meth:`Texture.base_mask`);
    ``"full"``: at most :data:`FULL_CONTACT_TOL` of the cell is out of contact;
    ``"transition"``: in between.
    """
    out_of_contact = 1.0 - float(np.count_nonzero(contact)) / contact.size
    if out_of_contact <= FULL_CONTACT_TOL:
        return "full"
    if np.any(contact & base):
        return "transition"
    return "asperity"


@dataclass
class ContactResult:
    """Solution of one contact problem on one cell (SI units).

    Fields are (nx, ny) arrays: ``pressure`` (Pa), ``gap`` (m, skin to texture), ``displacement``
    (m, skin surface displacement away from the texture, zero mean for periodic cells).
    """

    pressure: np.ndarray
    gap: np.ndarray
    displacement: np.ndarray
    mean_pressure: float
    approach: float
    contact_fraction: float
    real_contact_area: float
    max_pressure: float
    mean_gap: float
    iterations: int
    residual: float
    converged: bool
    seconds: float
    formulation: str
    contact_state: str
    texture: Texture = field(repr=False)
    modulus: float = 0.0
    tol: float = 0.0
    #: An adhesive solve's interaction and flags (:mod:`fingerpad.contact.adhesive`): ``law``,
    #: ``work_of_adhesion`` (J/m^2), ``adhesion_range`` (m), ``detached``, ``tensile_fraction``;
    #: ``None`` without adhesion.
    adhesion: dict[str, Any] | None = field(default=None, repr=False)

    @property
    def contact(self) -> np.ndarray:
        """Boolean contact mask: compressed pixels, or with adhesion closed gaps (a contact pixel
        may then carry tension)."""
        return self.pressure > 0 if self.adhesion is None else self.gap <= 0

    def summary(self) -> dict[str, Any]:
        """JSON-ready scalar results (SI units)."""
        return {
            "mean_pressure": float(self.mean_pressure),
            "contact_fraction": float(self.contact_fraction),
            "real_contact_area": float(self.real_contact_area),
            "max_pressure": float(self.max_pressure),
            "mean_gap": float(self.mean_gap),
            "approach": float(self.approach),
            "contact_state": self.contact_state,
            "iterations": int(self.iterations),
            "residual": float(self.residual),
            "converged": bool(self.converged),
            "seconds": float(self.seconds),
            "formulation": self.formulation,
            # an adhesive solve's interaction (a non-adhesive summary is as it always was)
            **({} if self.adhesion is None else
               {k: v for k, v in self.adhesion.items() if not k.startswith("_")}),
        }
