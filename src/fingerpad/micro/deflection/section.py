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
from typing import Any

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


Geometry = EllipsoidGeometry | RidgeGeometry


def texture_geometry(texture: Any) -> Geometry:
    """The asperity geometry of a generated ``ellipsoids`` or ``ridges`` texture.

    Raises
    ------
    FingerpadError
        For any other texture (directional friction needs a known asperity shape).
    """
    name = getattr(texture, "family", None) or getattr(texture, "name", None)
    params = dict(getattr(texture, "params", {}) or {})
    try:
        if name == "ellipsoids":
            return EllipsoidGeometry(float(params["semi_axis_x"]), float(params["semi_axis_y"]),
                                     float(params["height"]), float(params["spacing_x"]),
                                     float(params["spacing_y"]), float(params.get("orientation", 0.0)))
        if name == "ridges":
            return RidgeGeometry(float(params["width"]), float(params["height"]), float(params["spacing"]),
                                 str(params.get("profile", "circular")))
    except KeyError as exc:
        raise FingerpadError(f"texture {name!r} lacks the parameter {exc.args[0]!r}") from None
    raise FingerpadError(f"--direction needs an ellipsoids or ridges texture, not {name!r}")


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
    if not math.isfinite(direction_deg):
        raise FingerpadError("direction must be a finite angle in degrees")
    t = math.radians(direction_deg)
    if isinstance(geometry, RidgeGeometry):
        # |cos| of an angle that is an odd multiple of 90 deg is exactly 0 (not 6e-17)
        across = 0.0 if math.isclose(math.fmod(abs(direction_deg), 180.0), 90.0, abs_tol=1e-9) else abs(math.cos(t))
        return Section("circular", geometry.width / 2, geometry.height, geometry.spacing, geometry.spacing, across)
    g = geometry
    phi = t - g.orientation
    r = 1.0 / math.sqrt(math.cos(phi) ** 2 / g.semi_axis_x**2 + math.sin(phi) ** 2 / g.semi_axis_y**2)
    lam = 1.0 / math.sqrt(math.cos(t) ** 2 / g.spacing_x**2 + math.sin(t) ** 2 / g.spacing_y**2)
    lam = max(lam, 2.0 * r)
    per_p = g.spacing_x * g.spacing_y * 2.0 * r / (math.pi * g.semi_axis_x * g.semi_axis_y)
    return Section("ellipse", r, g.height, lam, per_p, 1.0)


def principal_directions(geometry: Geometry) -> tuple[float, float]:
    """(parallel, perpendicular) sliding directions, degrees from the texture's x axis: along the
    asperities' long axis (for ridges: along the ridges, y) and across it."""
    if isinstance(geometry, RidgeGeometry):
        return 90.0, 0.0
    long = math.degrees(geometry.orientation) + (0.0 if geometry.semi_axis_x >= geometry.semi_axis_y else 90.0)
    return long % 180.0, (long + 90.0) % 180.0


__all__ = ["EllipsoidGeometry", "Geometry", "RidgeGeometry", "Section", "principal_directions", "section_for",
           "texture_geometry"]
