"""Compliant asperities under sliding: a finite-element deflection model and directional friction.

A plane-strain, finite-strain, nearly incompressible neo-Hookean section of one asperity on its
base layer (:mod:`.mesh`, :mod:`.hyperelastic`) is pressed by the skin -- a periodic elastic
half-space coupled through its compliance (:mod:`.contact`) -- and sheared in full sliding with
the package's friction law (Eq. 2.3 shape) or Coulomb, by Newton's method with a primal-dual
active set (:mod:`.solve`) and tip-controlled path following (:mod:`.path`). The section of a
texture for a sliding direction is :mod:`.section`; the contact length against the shear level
gives the deflection gain of the real contact area (:mod:`.gain`), which enters the friction
through the fixed point of the local shear it creates (:mod:`.fixedpoint`); the elliptical
Greenwood-Tabor term (:mod:`.hysteresis`) gives the direction dependence of Eq. 2.4.

Public API
----------
directional_gain, directional_gains (several directions, the ramps in worker processes:
:mod:`.ramps`), GainCurve, DirectionalCell, solve_local_shear, texture_geometry, as_dataset,
EllipsoidGeometry, RidgeGeometry, Section, section_for, solve_section, DeflectionSettings,
SectionMaterials, PressureRamp, hertz_ellipse, elliptical_hysteresis_force,
hysteresis_direction_factor, run_deflection, DeflectionResult (the job :mod:`.job` that
``fingerpad deflection`` runs). Texture families give their asperity geometry through their
``deflection`` hook (:attr:`fingerpad.textures.TextureFamily.deflection`).
"""

from __future__ import annotations

from .fixedpoint import DirectionalCell, LocalShear, needed_shear, solve_local_shear
from .gain import (DeflectionSettings, GainCurve, PressureRamp, SectionMaterials, as_dataset, directional_gain,
                   directional_gains, solve_section)
from .section import EllipsoidGeometry, RidgeGeometry, Section, section_for, texture_geometry
from .hysteresis import elliptical_hysteresis_force, hertz_ellipse, hysteresis_direction_factor
from .job import DeflectionResult, run_deflection

__all__ = [
    "DeflectionResult",
    "DeflectionSettings",
    "DirectionalCell",
    "EllipsoidGeometry",
    "GainCurve",
    "LocalShear",
    "PressureRamp",
    "RidgeGeometry",
    "Section",
    "SectionMaterials",
    "as_dataset",
    "run_deflection",
    "directional_gain",
    "directional_gains",
    "elliptical_hysteresis_force",
    "hertz_ellipse",
    "hysteresis_direction_factor",
    "needed_shear",
    "section_for",
    "solve_local_shear",
    "solve_section",
    "texture_geometry",
]
