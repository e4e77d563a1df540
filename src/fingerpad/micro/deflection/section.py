"""From a texture and a sliding direction to the asperity section the model solves.

* **Ellipsoids** (semi-axes a along the asperity's own x', b along y', height h, lattice
  ``spacing_x x spacing_y``, rotated by ``orientation``): sliding at ``direction`` (degrees from
  the texture's x axis) shears the section through the asperity centre along that direction: a
  semi-ellipse of half-width ``r = (cos^2 phi / a^2 + sin^2 phi / b^2)^(-1/2)``
  (``phi = direction - orientation``) and height h, with neighbours at the period
  ``lambda = (cos^2 t / s_x^2 + sin^2 t / s_y^2)^(-1/2)`` (t = direction; at least 2r).
  Load: the section carries the asperity's force ``F_i = p s_x s_y`` (Eq. 3.2) spread over the
  asperity's mean width across the section, ``pi a b / (2 r)``, so that the section's mean
  footprint stress equals the asperity's: ``P = p s_x s_y 2 r / (pi a b)`` per unit depth.
* **Ridges** (circular profile, running along y): the section is the ridge's cross-section at
  its own period, loaded by ``P = p spacing`` exactly (a ridge is a 2-D body); only the shear
  component across the ridges deflects it: ``shear_factor = |cos direction|``.
* A circular asperity on a square lattice gives the same section in every direction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

from ...errors import FingerpadError


@dataclass(frozen=True)
class EllipsoidGeometry:
    """Half-ellipsoid asperities (as :func:`fingerpad.textures.ellipsoids`), SI units.

    ``orientation`` in radians (counter-clockwise from x).
    """

    semi_axis_x: float
    semi_axis_y: float
    height: float
    spacing_x: float
    spacing_y: float
    orientation: float = 0.0

    def __post_init__(self) -> None:
        for name in ("semi_axis_x", "semi_axis_y", "height", "spacing_x", "spacing_y"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise FingerpadError(f"ellipsoid {name} must be a positive length, got {v!r}")
        if not math.isfinite(self.orientation):
            raise FingerpadError("ellipsoid orientation must be finite")

    def section(self, direction_deg: float) -> Section:
        """The semi-elliptical section sheared when sliding at ``direction_deg`` (module docstring)."""
        t = _radians(direction_deg)
        phi = t - self.orientation
        r = 1.0 / math.sqrt(math.cos(phi) ** 2 / self.semi_axis_x**2 + math.sin(phi) ** 2 / self.semi_axis_y**2)
        lam = 1.0 / math.sqrt(math.cos(t) ** 2 / self.spacing_x**2 + math.sin(t) ** 2 / self.spacing_y**2)
        lam = max(lam, 2.0 * r)
        per_p = self.spacing_x * self.spacing_y * 2.0 * r / (math.pi * self.semi_axis_x * self.semi_axis_y)
        return Section("ellipse", r, self.height, lam, per_p, 1.0)

    def principal_directions(self) -> tuple[float, float]:
        """(parallel, perpendicular): along the long axis of the footprint and across it, degrees."""
        long = math.degrees(self.orientation) + (0.0 if self.semi_axis_x >= self.semi_axis_y else 90.0)
        return long % 180.0, (long + 90.0) % 180.0

    def hysteresis_factor(self, direction_deg: float) -> float:
        """The elliptical Greenwood-Tabor factor of the asperity tip (Eq. 2.4e over Eq. 2.4)."""
        from .hysteresis import hysteresis_direction_factor

        return hysteresis_direction_factor(self.semi_axis_x, self.semi_axis_y, self.height,
                                           math.radians(direction_deg) - self.orientation)


@dataclass(frozen=True)
class RidgeGeometry:
    """Parallel ridges along y (as :func:`fingerpad.textures.ridges`), SI units."""

    width: float
    height: float
    spacing: float
    profile: str = "circular"

    def __post_init__(self) -> None:
        for name in ("width", "height", "spacing"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise FingerpadError(f"ridge {name} must be a positive length, got {v!r}")
        if self.profile != "circular":
            raise FingerpadError(
                f"the deflection model supports circular ridges only, not {self.profile!r} "
                "(a sinusoidal ridge meets its base tangentially and a trapezoid has corners)")
        if self.height > self.width / 2 * (1 + 1e-9):
            raise FingerpadError("a circular ridge cannot be higher than half its width")

    def section(self, direction_deg: float) -> Section:
        """The ridge's cross-section; only the shear component across the ridges acts in it."""
        t = _radians(direction_deg)
        # |cos| of an angle that is an odd multiple of 90 deg is exactly 0 (not 6e-17)
        across = 0.0 if math.isclose(math.fmod(abs(direction_deg), 180.0), 90.0, abs_tol=1e-9) else abs(math.cos(t))
        return Section("circular", self.width / 2, self.height, self.spacing, self.spacing, across)

    def principal_directions(self) -> tuple[float, float]:
        """(parallel, perpendicular): along the ridges (y) and across them, degrees."""
        return 90.0, 0.0

    def hysteresis_factor(self, direction_deg: float) -> float:
        """Circular ridges have no elliptical contact: 1."""
        return 1.0


@runtime_checkable
class Geometry(Protocol):
    """What the deflection model needs of a texture's asperities (returned by the texture
    family's ``deflection`` hook, :attr:`fingerpad.textures.TextureFamily.deflection`).

    ``section(direction_deg)``: the :class:`Section` sheared when sliding at that direction;
    ``principal_directions()``: (parallel, perpendicular) directions in degrees;
    ``hysteresis_factor(direction_deg)``: the asperity-scale factor of the hysteresis term
    (1 where the family has none). Fields are SI and read by ``dataclasses.fields`` for outputs.
    """

    def section(self, direction_deg: float) -> Section: ...

    def principal_directions(self) -> tuple[float, float]: ...

    def hysteresis_factor(self, direction_deg: float) -> float: ...


def _radians(direction_deg: float) -> float:
    if not math.isfinite(direction_deg):
        raise FingerpadError("direction must be a finite angle in degrees")
    return math.radians(direction_deg)


def deflection_hook(family_name: str) -> Any:
    """The ``deflection`` hook of the registered texture family ``family_name``.

    Raises
    ------
    FingerpadError
        Unknown family, or a family without a deflection model (the message lists those with one).
    """
    from ... import textures  # noqa: F401 -- importing the package fills the family registry
    from ...textures.base import get_family, registry

    family = get_family(family_name)
    if family.deflection is None:
        known = ", ".join(sorted(n for n, f in registry().items() if f.deflection is not None))
        raise FingerpadError(f"texture {family.name!r} has no deflection model (directional friction and "
                             f"`fingerpad deflection` need one of: {known})")
    return family.deflection


def texture_geometry(texture: Any) -> Geometry:
    """The asperity geometry of a generated texture, from its family's ``deflection`` hook.

    Raises
    ------
    FingerpadError
        For a texture whose family has no deflection hook (directional friction needs a known
        asperity shape).
    """
    name = getattr(texture, "family", None) or getattr(texture, "name", None)
    hook = deflection_hook(str(name))
    try:
        return hook(dict(getattr(texture, "params", {}) or {}))
    except KeyError as exc:
        raise FingerpadError(f"texture {name!r} lacks the parameter {exc.args[0]!r}") from None


@dataclass(frozen=True)
class Section:
    """One asperity section in SI units and how the cell's nominal pressure loads it.

    ``load_per_pressure``: P / p (m), the section's normal load per unit depth per nominal
    pressure. ``shear_factor``: the fraction of the shear level acting in the section's plane.
    """

    profile: str
    half_width: float
    height: float
    period: float
    load_per_pressure: float
    shear_factor: float = 1.0


def section_for(geometry: Geometry, direction_deg: float) -> Section:
    """The section sheared when sliding at ``direction_deg`` (degrees from the texture's x axis)."""
    return geometry.section(float(direction_deg))


def principal_directions(geometry: Geometry) -> tuple[float, float]:
    """(parallel, perpendicular) sliding directions, degrees from the texture's x axis: along the
    asperities' long axis (for ridges: along the ridges, y) and across it."""
    return geometry.principal_directions()


__all__ = ["EllipsoidGeometry", "Geometry", "deflection_hook", "RidgeGeometry", "Section", "principal_directions", "section_for",
           "texture_geometry"]
