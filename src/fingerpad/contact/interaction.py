"""Attractive interactions between the skin and the texture: the adhesive term of the contact energy.

A contact solve minimises the elastic energy of the skin under the non-penetration constraint
``g >= 0`` (docs/solver.md). Adhesion adds a local term: an interaction energy per unit area
``phi(g)`` of the gap ``g`` (m), with ``phi(0) = -w`` (``w`` the work of adhesion, J/m^2) and
``phi -> 0`` as the surfaces part. The solver is handed such a term as an object (an
:class:`Interaction`) and adds it to the energy it minimises; it never asks which law it is
(:mod:`fingerpad.contact.adhesive`). What it needs of a law:

* ``energy(g)`` -- ``phi(g)`` (J/m^2, i.e. Pa m);
* ``traction(g)`` -- ``phi'(g) >= 0``, the attraction (Pa): the tension the interaction pulls
  the skin toward the texture with;
* ``curvature(g)`` -- ``phi''(g)`` (Pa/m), used for the Newton start of the line search;
* ``peak_traction`` -- the largest attraction (Pa), the pressure scale of the convergence
  measure;
* ``scaled(length, modulus)`` -- the same law in the units of a unit cell (lengths over ``L``,
  pressures over ``E*``): ``w / (E* L)`` and ``rho / L`` (docs/solver.md, "One curve for every
  modulus and every scale").

Laws (docs/model.md, section 6.6):

* :class:`MaugisDugdale` -- a constant attraction ``w / rho`` while the gap is below ``rho``,
  none beyond (Maugis 1992): ``phi = -w (1 - g / rho)`` for ``g < rho``;
* :class:`Exponential` -- ``phi = -w exp(-g / rho)``, attraction ``(w / rho) exp(-g / rho)``.

Both have the peak attraction ``sigma0 = w / rho``. On skin the range ``rho`` is a
regularisation: its physical value (a nanometre) gives Tabor parameters of 1e3-1e4 on
micrometre asperities, the JKR limit, where the results do not depend on it as long as the
cohesive zone ``l_c = (pi / 4) E* rho^2 / w`` (Dugdale's, for a crack) is short against the
contact and spans a few pixels (:func:`resolved_range`). SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, ClassVar

import numpy as np

from ..errors import FingerpadError

__all__ = ["COHESIVE_PIXELS", "INTERACTION_LAWS", "TIP_PIXELS", "Exponential", "Interaction", "MaugisDugdale",
           "cohesive_length", "make_interaction", "regularised_interaction", "resolved_range", "tabor_parameter", "tip_zone"]

#: Pixels the cohesive zone ``l_c = (pi/4) E* rho^2 / w`` spans at the range :func:`resolved_range`
#: chooses (docs/model.md, section 6.6: the convergence study behind this number).
COHESIVE_PIXELS = 1.0
#: Half-width (pixels) of the zone around the contact where a regularised attraction acts
#: (``Interaction.tip_pixels``; docs/model.md 6.6, "Convergence past the transition"): in the
#: JKR limit the attraction acts only in the cohesive zone at the contact's edge; a smooth
#: surface approaching the texture out of contact feels none until it touches. With ``l_c`` of
#: one pixel the exponential law's cohesive zone releases its ``w`` within about 8 pixels of the
#: edge (Johnson's sinusoid: contact width within 1.8 % at 8 pixels, 4.3 % at 3).
TIP_PIXELS = 8


@dataclass(frozen=True)
class Interaction:
    """An attractive interaction law of work of adhesion ``work`` (J/m^2) and range ``range`` (m).

    Subclasses define :meth:`energy`, :meth:`traction` and :meth:`curvature` on arrays of gaps
    (any array namespace: they use the array's own methods). Gaps below zero (a trial point of
    the line search before its projection) are treated as zero gap with the attraction held:
    the energy is continued linearly, so the line search sees a function with a continuous slope.
    """

    work: float
    range: float
    #: Where the attraction acts: 0, wherever the gap is within its reach (a physical range);
    #: ``n > 0``, only within ``n`` pixels of the contact (a regularised range: the JKR limit's
    #: cohesive zone at the contact's edge, no attraction reaching out of contact; see
    #: :data:`TIP_PIXELS`).
    tip_pixels: int = 0

    #: The name a study file or ``--adhesion-law`` gives.
    name: ClassVar[str] = ""

    def __post_init__(self) -> None:
        w, r = self.work, self.range
        if not (isinstance(w, (int, float)) and math.isfinite(w) and w > 0):
            raise FingerpadError(f"work of adhesion must be a positive number of J/m^2, got {w!r}")
        if not (isinstance(r, (int, float)) and math.isfinite(r) and r > 0):
            raise FingerpadError(f"adhesion range must be a positive number of metres, got {r!r}")
        if not (isinstance(self.tip_pixels, int) and self.tip_pixels >= 0):
            raise FingerpadError(f"tip_pixels must be a whole number >= 0, got {self.tip_pixels!r}")

    @property
    def reach(self) -> float:
        """The gap (m) beyond which the attraction is negligible (below ~1e-4 of its peak)."""
        return self.range

    @property
    def peak_traction(self) -> float:
        """The largest attraction ``w / rho`` (Pa), at zero gap for both laws here."""
        return self.work / self.range

    def scaled(self, length: float, modulus: float) -> "Interaction":
        """The law in a unit cell's units: gaps over ``length`` (m), pressures over ``modulus``
        (Pa), so ``w -> w / (E* L)``, ``rho -> rho / L``."""
        return replace(self, work=self.work / (modulus * length), range=self.range / length)

    def energy(self, g: Any) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def traction(self, g: Any) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def curvature(self, g: Any) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def describe(self) -> dict[str, Any]:
        """JSON-ready: the law's name, ``work_of_adhesion`` (J/m^2), ``adhesion_range`` (m) and,
        for a regularised range acting at the contact's edge only, ``tip_pixels``."""
        out: dict[str, Any] = {"law": self.name, "work_of_adhesion": self.work, "adhesion_range": self.range}
        if self.tip_pixels:
            out["tip_pixels"] = self.tip_pixels
        return out


@dataclass(frozen=True)
class MaugisDugdale(Interaction):
    """Maugis-Dugdale: a constant attraction ``sigma0 = w / rho`` for gaps below ``rho``.

    ``phi(g) = -w (1 - g / rho)`` for ``0 <= g < rho``, 0 beyond (J/m^2); the attraction
    ``phi'`` is ``w / rho`` inside the range and 0 outside (a jump at ``rho``, which the solver's
    line search crosses exactly); ``phi'' = 0``.
    """

    name: ClassVar[str] = "maugis"

    def energy(self, g: Any) -> Any:
        return _xp(g).where(g < self.range, -self.work * (1.0 - g / self.range), 0.0)

    def traction(self, g: Any) -> Any:
        return _xp(g).where(g < self.range, self.work / self.range, 0.0)

    def curvature(self, g: Any) -> Any:
        return 0.0 * g


@dataclass(frozen=True)
class Exponential(Interaction):
    """Exponential: ``phi(g) = -w exp(-g / rho)`` (J/m^2), attraction ``(w / rho) exp(-g / rho)``."""

    name: ClassVar[str] = "exponential"

    @property
    def reach(self) -> float:
        """``10 rho``: the attraction there is ``exp(-10)`` ~ 5e-5 of its peak."""
        return 10.0 * self.range

    def _decay(self, g: Any) -> Any:
        # gaps below zero: the attraction held at its peak (linear continuation of the energy)
        xp = _xp(g)
        return xp.exp(-xp.maximum(g, 0.0) / self.range)

    def energy(self, g: Any) -> Any:
        # below zero gap phi(0) + phi'(0) g: continuous in value and slope
        return _xp(g).where(g < 0, -self.work + (self.work / self.range) * g, -self.work * self._decay(g))

    def traction(self, g: Any) -> Any:
        return (self.work / self.range) * self._decay(g)

    def curvature(self, g: Any) -> Any:
        return _xp(g).where(g < 0, 0.0, -(self.work / self.range**2) * self._decay(g))


def _xp(g: Any) -> Any:
    """The array namespace of ``g`` (NumPy for scalars and NumPy arrays)."""
    return g.__array_namespace__() if hasattr(g, "__array_namespace__") else np


#: The laws by the name a study file or ``--adhesion-law`` gives (the first is the default).
INTERACTION_LAWS: dict[str, type[Interaction]] = {"exponential": Exponential, "maugis": MaugisDugdale}


def make_interaction(law: str, work: float, range_: float, tip_pixels: int = 0) -> Interaction:
    """The law ``law`` (a name of :data:`INTERACTION_LAWS`, any case) with ``work`` (J/m^2),
    ``range_`` (m) and ``tip_pixels`` (:attr:`Interaction.tip_pixels`).

    Raises
    ------
    FingerpadError
        An unknown law (the message lists the laws) or a non-positive work or range.
    """
    key = str(law).strip().lower().replace("-", "_")
    if key in ("maugis_dugdale", "md", "dugdale"):
        key = "maugis"
    if key not in INTERACTION_LAWS:
        raise FingerpadError(f"unknown adhesion law {law!r}; choose one of: {', '.join(INTERACTION_LAWS)}")
    return INTERACTION_LAWS[key](float(work), float(range_), int(tip_pixels))


def tip_zone(contact: Any, pixels: int) -> Any:
    """The points within ``pixels`` pixels (a square, periodic) of a ``True`` of ``contact`` (a
    boolean field of any array namespace): where a regularised attraction acts."""
    xp = _xp(contact)
    out = contact
    for axis in (0, 1):
        grown = out
        for k in range(1, pixels + 1):
            grown = grown | xp.roll(out, k, axis=axis) | xp.roll(out, -k, axis=axis)
        out = grown
    return out


def cohesive_length(work: float, range_: float, modulus: float) -> float:
    """Dugdale's cohesive-zone length of a crack, ``l_c = (pi / 4) E* rho^2 / w`` (m): the width
    over which the attraction acts at the edge of a JKR-like contact (docs/model.md 6.6)."""
    return math.pi / 4.0 * modulus * range_**2 / work


def resolved_range(work: float, modulus: float, pixel: float, pixels: float = COHESIVE_PIXELS) -> float:
    """The range ``rho`` (m) whose cohesive zone spans ``pixels`` pixels of size ``pixel`` (m):
    ``rho = sqrt(4 pixels dx w / (pi E*))``. The JKR limit of skin (a nanometre of physical range)
    is solved with this regularised range; refining the grid shrinks both together
    (docs/model.md 6.6)."""
    if not (work > 0 and modulus > 0 and pixel > 0 and pixels > 0):
        raise FingerpadError("resolved_range needs a positive work of adhesion, modulus, pixel and pixel count")
    return math.sqrt(4.0 * pixels * pixel * work / (math.pi * modulus))


def regularised_interaction(law: str, work: float, range_: float, modulus: float, pixel: float) -> Interaction:
    """The law ``law`` as a grid of pixel ``pixel`` (m) solves it on a skin of reduced modulus
    ``modulus`` (Pa): the range the larger of ``range_`` (m) and :func:`resolved_range`; where the
    resolved one is taken (the JKR limit), the attraction acts within :data:`TIP_PIXELS` pixels
    of the contact only (docs/model.md 6.6)."""
    used = max(float(range_), resolved_range(work, modulus, pixel))
    return make_interaction(law, work, used, TIP_PIXELS if used > range_ else 0)


def tabor_parameter(work: float, range_: float, modulus: float, radius: float) -> float:
    """Maugis's transition parameter ``lambda = sigma0 (9 R / (2 pi w E*^2))^(1/3)``,
    ``sigma0 = w / rho`` (-): above ~5 a sphere of radius ``R`` (m) adheres as JKR says, below
    ~0.1 as DMT says (Maugis 1992; Tabor's ``mu`` is ``lambda / 1.16``)."""
    return (work / range_) * (9.0 * radius / (2.0 * math.pi * work * modulus**2)) ** (1.0 / 3.0)
