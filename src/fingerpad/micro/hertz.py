"""The per-asperity Hertz model of the micro scale (thesis ch. 3.1, Eqs. 3.1-3.6 and 3.8-3.10).

Each asperity of a square lattice (spacing lambda) carries ``F_i = p lambda^2`` and touches the
skin as a Hertz sphere; the transition is where the Hertz approach reaches the asperity height.
Hertz ignores the neighbouring asperities and cannot follow the skin onto the base: the BEM cell
(:mod:`fingerpad.micro.bem`) does both, and finds the transition at a *higher* pressure than
isolated Hertz (neighbours hold the skin up at the cell corner).

:func:`hertz_cell_for` builds the :class:`HertzUnitCell` of any texture whose family declares an
asperity radius (:attr:`fingerpad.textures.TextureFamily.hertz`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..checks import ArrayLike, as_areas, as_loads, positive, scalar_out
from ..errors import FingerpadError
from .response import DEFAULT_LOAD_RANGE, RidgeArea, area_function, solve_load

if TYPE_CHECKING:
    from ..finger import Finger
    from ..textures import Texture

__all__ = [
    "HertzUnitCell",
    "asperity_count",
    "asperity_force",
    "centre_asperity_force",
    "critical_asperity_force",
    "critical_load_hertz",
    "hertz_approach",
    "hertz_cell_for",
    "hertz_contact_radius",
    "supports_hertz",
    "transition_area_fraction",
    "transition_radius",
]


def asperity_count(ridge_area: ArrayLike, spacing: float) -> float | np.ndarray:
    """Asperities in contact on a square lattice, ``N = A_fr / lambda^2``, Eq. 3.1."""
    lam = positive(spacing, "asperity spacing")
    return scalar_out(as_areas(ridge_area) / lam**2)


def asperity_force(load: ArrayLike, ridge_area: ArrayLike, spacing: float) -> float | np.ndarray:
    """Mean force per asperity ``F_i = F lambda^2 / A_fr = p_mean lambda^2``, Eq. 3.2 (N)."""
    lam = positive(spacing, "asperity spacing")
    return scalar_out(as_loads(load) * lam**2 / as_areas(ridge_area))


def centre_asperity_force(load: ArrayLike, ridge_area: ArrayLike, spacing: float) -> float | np.ndarray:
    """Force on the asperity at the pad centre, ``1.5 F lambda^2 / A_fr``, Eq. 3.5 (N)."""
    return scalar_out(1.5 * np.asarray(asperity_force(load, ridge_area, spacing)))


def hertz_contact_radius(force: ArrayLike, radius: float, reduced_modulus: float) -> float | np.ndarray:
    """Hertz contact radius of one spherical asperity, ``a = (3 F R / (4 E1*))^(1/3)`` (m)."""
    r = positive(radius, "asperity radius")
    e = positive(reduced_modulus, "reduced modulus E1*")
    return scalar_out(np.cbrt(3.0 * as_loads(force, "force") * r / (4.0 * e)))


def hertz_approach(force: ArrayLike, radius: float, reduced_modulus: float) -> float | np.ndarray:
    """Hertz approach (combined displacement) ``delta = (9 F^2 / (16 E1*^2 R))^(1/3)``, Eq. 3.3 (m)."""
    r = positive(radius, "asperity radius")
    e = positive(reduced_modulus, "reduced modulus E1*")
    f = as_loads(force, "force")
    return scalar_out(np.cbrt(9.0 * f**2 / (16.0 * e**2 * r)))


def critical_asperity_force(height: float, radius: float, reduced_modulus: float) -> float:
    """Asperity force at which the Hertz approach equals the height, Eq. 3.3 solved for F:
    ``F_icrit = (4/3) E1* sqrt(R h^3)`` (N)."""
    h = positive(height, "asperity height")
    r = positive(radius, "asperity radius")
    e = positive(reduced_modulus, "reduced modulus E1*")
    return 4.0 / 3.0 * e * math.sqrt(r * h**3)


def transition_area_fraction(
    load: ArrayLike, ridge_area: ArrayLike, spacing: float, critical_force: float
) -> float | np.ndarray:
    """Fraction of the ridge contact past the transition, Eqs. 3.8-3.9.

    ``A_trans / A_fr = 1 - ((2/3) F_icrit / F_i)^2`` with ``F_i = F lambda^2 / A_fr``, clipped
    at 0 (no zone while the centre asperity carries less than ``F_icrit``).
    """
    fc = positive(critical_force, "critical asperity force")
    fi = np.asarray(asperity_force(load, ridge_area, spacing))
    with np.errstate(divide="ignore"):
        frac = 1.0 - (2.0 / 3.0 * fc / fi) ** 2
    return scalar_out(np.clip(frac, 0.0, 1.0))


def transition_radius(
    load: ArrayLike, ridge_area: ArrayLike, spacing: float, critical_force: float
) -> float | np.ndarray:
    """Radius of the zone past the transition ``a_trans = a_fr (A_trans/A_fr)^(1/2)``, Eq. 3.10 (m)."""
    a_fr = np.sqrt(as_areas(ridge_area) / math.pi)
    frac = np.asarray(transition_area_fraction(load, ridge_area, spacing, critical_force))
    return scalar_out(a_fr * np.sqrt(frac))



def critical_load_hertz(
    ridge_area: RidgeArea,
    *,
    radius: float,
    height: float,
    spacing: float,
    reduced_modulus: float,
    load_range: tuple[float, float] = DEFAULT_LOAD_RANGE,
) -> float:
    """Critical load of the first transition by Hertz, Eq. 3.6.

    ``F_crit = (8/9) E1* sqrt(h^3 R) A_fr / lambda^2``. For a constant ``A_fr`` this is returned
    directly; for a load-dependent ``A_fr(F)`` (callable) the equation
    ``F = (8/9) E1* sqrt(h^3 R) A_fr(F) / lambda^2`` is solved with Brent's method in
    ``load_range``.

    Parameters
    ----------
    ridge_area
        A_fr in m^2, or a callable ``F -> A_fr``.
    radius, height, spacing
        Asperity radius R, height h and lattice spacing lambda, m.
    reduced_modulus
        E1*, Pa (Eq. 3.4).

    Raises
    ------
    FingerpadError
        If no solution lies in ``load_range``.
    """
    lam = positive(spacing, "asperity spacing")
    # (2/3) F_icrit / lambda^2 = (8/9) E1* sqrt(h^3 R) / lambda^2
    factor = 2.0 / 3.0 * critical_asperity_force(height, radius, reduced_modulus) / lam**2
    if not callable(ridge_area):
        return factor * positive(ridge_area, "ridge area")
    area = area_function(ridge_area)

    def detail(lo: float, hi: float) -> str:
        return (f"(8/9) E1* sqrt(h^3 R) A_fr/lambda^2 is {factor * area(lo):.3g} N at the low end and "
                f"{factor * area(hi):.3g} N at the high end")

    return solve_load(lambda f: f - factor * area(f), load_range, "critical load (Eq. 3.6)", detail)


# ---------------------------------------------------------------------------------------------
# the unit-cell interface
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class HertzUnitCell:
    """Square lattice of spherical caps, each in Hertz contact with the skin (Eqs. 3.1-3.3).

    ``F_i = p lambda^2``, ``a = (3 F_i R / (4 E1*))^(1/3)``, ``psi = min(1, pi a^2 / lambda^2)``.
    The transition is where the Hertz approach reaches the cap height (Eq. 3.3):
    ``p_t = (4/3) E1* sqrt(R h^3) / lambda^2``. Hertz ignores the neighbours and cannot follow the
    skin onto the base, so past ``p_t`` psi is the asperity-only extrapolation and
    ``full_contact_pressure`` is ``inf`` (thesis ch. 3.1).

    Attributes
    ----------
    radius
        Cap radius R, m.
    height
        Cap height h above the base, m (``h <= R``).
    spacing
        Lattice spacing lambda, m.
    reduced_modulus
        E1*, Pa (Eq. 3.4).
    """

    #: The publications of this model (:mod:`fingerpad.references` keys; Hertz contact per asperity).
    REFERENCES: ClassVar[tuple[str, ...]] = ("johnson1985",)

    radius: float
    height: float
    spacing: float
    reduced_modulus: float

    def __post_init__(self) -> None:
        r = positive(self.radius, "asperity radius")
        h = positive(self.height, "asperity height")
        positive(self.spacing, "asperity spacing")
        positive(self.reduced_modulus, "reduced modulus E1*")
        if h > r:
            raise FingerpadError(f"a spherical cap cannot be higher ({h:.3g} m) than its radius ({r:.3g} m)")

    @classmethod
    def for_finger(
        cls,
        finger: "Finger",
        *,
        radius: float,
        height: float,
        spacing: float,
        material_modulus: float | None = None,
        material_poisson: float = 0.35,
    ) -> HertzUnitCell:
        """Cell with E1* from the finger's skin and the texture material (Eq. 3.4)."""
        e1 = finger.micro_modulus(material_modulus, material_poisson)
        return cls(radius=radius, height=height, spacing=spacing, reduced_modulus=e1)

    @property
    def critical_force(self) -> float:
        """Asperity force at the transition, ``(4/3) E1* sqrt(R h^3)`` (Eq. 3.3), N."""
        return critical_asperity_force(self.height, self.radius, self.reduced_modulus)

    @property
    def transition_pressure(self) -> float:
        """``F_icrit / lambda^2``, Pa."""
        return self.critical_force / self.spacing**2

    @property
    def full_contact_pressure(self) -> float:
        """``inf``: Hertz cannot give full contact."""
        return math.inf

    @property
    def saturation_pressure(self) -> float:
        """Pressure at which ``pi a^2 = lambda^2`` and psi reaches its cap of 1, Pa."""
        a = self.spacing / math.sqrt(math.pi)
        return 4.0 * self.reduced_modulus * a**3 / (3.0 * self.radius) / self.spacing**2

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Kinks of psi: its saturation."""
        return (self.saturation_pressure,)

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        """``psi(p) = min(1, pi a^2 / lambda^2)``, Hertz ``a`` at ``F_i = p lambda^2``."""
        pp = np.clip(np.asarray(p, dtype=float), 0.0, None)
        a = np.cbrt(3.0 * pp * self.spacing**2 * self.radius / (4.0 * self.reduced_modulus))
        return np.minimum(math.pi * a**2 / self.spacing**2, 1.0)

    def critical_load(self, ridge_area: RidgeArea, load_range: tuple[float, float] = DEFAULT_LOAD_RANGE) -> float:
        """Eq. 3.6 for this cell (see :func:`critical_load_hertz`)."""
        return critical_load_hertz(
            ridge_area, radius=self.radius, height=self.height, spacing=self.spacing,
            reduced_modulus=self.reduced_modulus, load_range=load_range,
        )



def supports_hertz(texture: "Texture") -> bool:
    """Whether the texture's family declares the asperity the Hertz model needs."""
    from ..textures import registry

    family = registry().get(texture.family or "")
    if family is None or family.hertz is None:
        return False
    try:
        family.hertz(texture)
    except (KeyError, TypeError, ValueError):
        return False
    return True


def hertz_cell_for(texture: "Texture", reduced_modulus: float) -> tuple[HertzUnitCell, str | None]:
    """The per-asperity Hertz cell of a texture (Eqs. 3.1-3.3) and a note on its spacing.

    The texture's family provides the asperity radius, height and the square spacing of Eq. 3.1
    (:class:`fingerpad.textures.HertzAsperity`).

    Raises
    ------
    FingerpadError
        When the family declares no asperity radius (only e.g. spherical caps do).
    """
    from ..textures import registry

    if not supports_hertz(texture):
        with_hertz = sorted(n for n, f in registry().items() if f.hertz is not None)
        raise FingerpadError(
            f"the Hertz model (Eqs. 3.1-3.6) needs asperities with a radius, such as spherical caps "
            f"(textures: {', '.join(with_hertz)}); "
            f"texture {texture.name!r} needs --model bem"
        )
    family = registry()[texture.family]  # type: ignore[index]
    asp = family.hertz(texture)  # type: ignore[misc]
    return HertzUnitCell(asp.radius, asp.height, asp.spacing, reduced_modulus), asp.note
