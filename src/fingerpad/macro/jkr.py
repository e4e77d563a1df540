"""JKR (Johnson-Kendall-Roberts) gross area of an adhesive finger pad (a pad model of one file).

The pad is a sphere of radius ``R_fp`` and reduced modulus ``E_fp*`` on a flat, as for Hertz
(Eq. 2.5), with an interface that adheres with the pad's effective work of adhesion ``w``
(J/m^2; docs/model.md, section 7.6). The contact radius against the load (JKR 1971):

    a^3 = (3 R / (4 E*)) (F + 3 pi w R + sqrt(6 pi w R F + (3 pi w R)^2))        (3.15)

down to the pull-off load ``F_po = -1.5 pi w R`` (load control), where the root vanishes.
The load splits into a Hertzian part and an adhesive tension,

    F = F_H - F_A,   F_H = 4 E* a^3 / (3 R),   F_A = sqrt(8 pi w E* a^3),          (3.16)

whose pressures over the contact disc are ``(3 F_H / (2 pi a^2)) sqrt(1 - r^2/a^2)`` and
``-(F_A / (2 pi a^2)) / sqrt(1 - r^2/a^2)`` (:meth:`JKRArea.pressure_parts`). With ``w = 0`` it
is Hertz, Eq. 2.5, exactly. SI units.

Not a pad model chosen by name: a prediction builds it from the finger's Hertz pad (its radius
and modulus) and the pad's effective work of adhesion, which follows from the finger's
``work_of_adhesion`` and the texture's unit cell (docs/model.md 7.6); a helper module of this
package (:data:`fingerpad.macro.HELPER_MODULES`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import ArrayLike, scalar_out
from ..errors import FingerpadError
from ..params import Param, check_fields
from ._base import PAD_MODULUS, PAD_RADIUS

__all__ = ["PAD_WORK_OF_ADHESION", "JKRArea", "jkr_contact_radius", "jkr_load"]

#: The pad's effective work of adhesion (what a pull-off of the whole pad measures).
PAD_WORK_OF_ADHESION = Param("work_of_adhesion", "surface energy", "the pad's effective work of adhesion w "
                             "(docs/model.md 7.6)", 0.0, low=0, example="0.05J/m2",
                             label="pad work of adhesion w", symbol="w_pad")


def jkr_contact_radius(load: ArrayLike, radius: float, modulus: float, work: float) -> np.ndarray:
    """JKR contact radius (m), Eq. 3.15, for loads ``F >= -1.5 pi w R`` (N; NaN below)."""
    f = np.asarray(load, dtype=float)
    k = 3.0 * math.pi * work * radius
    with np.errstate(invalid="ignore"):
        root = np.sqrt(2.0 * k * f + k * k)
    return np.cbrt(3.0 * radius / (4.0 * modulus) * (f + k + root))


def jkr_load(a: ArrayLike, radius: float, modulus: float, work: float) -> np.ndarray:
    """The load (N) of a JKR contact of radius ``a`` (m), Eq. 3.16 (both branches)."""
    aa = np.asarray(a, dtype=float)
    return 4.0 * modulus * aa**3 / (3.0 * radius) - np.sqrt(8.0 * math.pi * work * modulus * aa**3)


@dataclass(frozen=True)
class JKRArea:
    """JKR gross area of an adhesive pad, Eqs. 3.15-3.16 (``work_of_adhesion = 0``: Hertz).

    Attributes
    ----------
    radius
        Equivalent pad radius R_fp, m.
    modulus
        Pad reduced modulus E_fp*, Pa.
    work_of_adhesion
        The pad's effective work of adhesion w, J/m^2 (docs/model.md 7.6).
    """

    PARAMS: ClassVar[tuple[Param, ...]] = (PAD_RADIUS, PAD_MODULUS, PAD_WORK_OF_ADHESION)
    #: The publications of this model (:mod:`fingerpad.references` keys).
    REFERENCES: ClassVar[tuple[str, ...]] = ("johnson1971",)

    radius: float
    modulus: float
    work_of_adhesion: float = 0.0

    def __post_init__(self) -> None:
        check_fields(self, self.PARAMS)

    @property
    def pull_off_force(self) -> float:
        """``1.5 pi w R_fp`` (N): the tension at which the pad comes off under load control."""
        return 1.5 * math.pi * self.work_of_adhesion * self.radius

    def contact_radius(self, load: ArrayLike) -> float | np.ndarray:
        """JKR contact radius (m) at ``load`` (N, down to minus the pull-off force)."""
        f = self._loads(load)
        return scalar_out(jkr_contact_radius(f, self.radius, self.modulus, self.work_of_adhesion))

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2) at ``load`` (N, down to minus the pull-off force)."""
        return scalar_out(self.area_checked(self._loads(load)))

    def area_checked(self, load: np.ndarray) -> np.ndarray:
        """The same on loads already checked (a float array)."""
        return math.pi * jkr_contact_radius(load, self.radius, self.modulus, self.work_of_adhesion) ** 2

    def pressure_parts(self, load: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """``(F_H, F_A)`` (N) of Eq. 3.16 at ``load``: the Hertzian force and the adhesive tension
        whose difference is the load."""
        a = jkr_contact_radius(self._loads(load), self.radius, self.modulus, self.work_of_adhesion)
        return (4.0 * self.modulus * a**3 / (3.0 * self.radius),
                np.sqrt(8.0 * math.pi * self.work_of_adhesion * self.modulus * a**3))

    def _loads(self, load: ArrayLike) -> np.ndarray:
        f = np.asarray(load, dtype=float)
        if not np.all(np.isfinite(f)):
            raise FingerpadError("loads must be finite numbers of newtons")
        if np.any(f < -self.pull_off_force * (1 + 1e-12)):
            raise FingerpadError(f"a load below the pad's pull-off force -{self.pull_off_force:.4g} N has no "
                                 "contact (JKR, load control)")
        return np.maximum(f, -self.pull_off_force)

    __call__ = area

