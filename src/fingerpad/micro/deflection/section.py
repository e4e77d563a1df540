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

from typing import Any

from ...errors import FingerpadError
from ...textures.base import Geometry, Section
from ...textures.ellipsoids import EllipsoidGeometry
from ...textures.ridges import RidgeGeometry


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


def section_for(geometry: Geometry, direction_deg: float) -> Section:
    """The section sheared when sliding at ``direction_deg`` (degrees from the texture's x axis)."""
    return geometry.section(float(direction_deg))


def principal_directions(geometry: Geometry) -> tuple[float, float]:
    """(parallel, perpendicular) sliding directions, degrees from the texture's x axis: along the
    asperities' long axis (for ridges: along the ridges, y) and across it."""
    return geometry.principal_directions()


__all__ = ["EllipsoidGeometry", "Geometry", "deflection_hook", "RidgeGeometry", "Section", "principal_directions", "section_for",
           "texture_geometry"]
