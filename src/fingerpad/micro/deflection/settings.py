"""Settings and materials of the deflection model's section solves (SI units).

:class:`DeflectionSettings` holds the numerical and modelling settings -- every one a
deterministic measure, except the optional wall-clock safety stop, which is kept out of the
cache key (:meth:`DeflectionSettings.key`) -- and :class:`SectionMaterials` the elastic
constants. Each decides the ranges of its own values, once (the ``deflection`` command passes
the user's values straight in).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ...errors import FingerpadError


@dataclass(frozen=True)
class DeflectionSettings:
    """Numerical and modelling settings of the section solves.

    Attributes
    ----------
    friction
        ``"package"`` (tau0 + alpha p shape, Eq. 2.3) or ``"coulomb"``.
    mu_max
        Largest shear level followed.
    n_pressures
        Pressure levels of the gain table (log-spaced over the pressure range).
    resolution
        Elements per asperity half-width.
    base_thickness
        Base layer thickness in units of the section period.
    fold_penalty
        Penalty stiffness of the fold-over contact, in units of the texture modulus.
    check_stability
        Compute the stability eigenvalue at every converged state (buckling flag).
    max_steps
        Largest number of shear steps of one ramp (a deterministic limit: the same ramp ends at
        the same state on every machine).
    time_limit
        Optional wall-clock safety stop of one shear ramp, s (default ``None``: off). It is not
        part of the result: a ramp it cuts is marked ``incomplete`` in every output and never
        cached, and the cache key does not contain it.
    """

    friction: str = "package"
    mu_max: float = 1.5
    n_pressures: int = 3
    resolution: int = 6
    base_thickness: float = 1.0
    fold_penalty: float = 20.0
    check_stability: bool = True
    max_steps: int = 300
    time_limit: float | None = None

    def __post_init__(self) -> None:
        # One place decides each range; the messages name the command's options too.
        if self.friction not in ("package", "coulomb"):
            raise FingerpadError(f"friction must be 'package' or 'coulomb', got {self.friction!r}")
        if not (_number(self.mu_max) and 0 < self.mu_max <= 5):
            raise FingerpadError(f"mu-max must lie in (0, 5], got {self.mu_max!r}")
        if not (_integer(self.n_pressures) and 1 <= self.n_pressures <= 20):
            raise FingerpadError(f"levels (pressure levels) must be a whole number in 1..20, got {self.n_pressures!r}")
        if not (_integer(self.resolution) and 2 <= self.resolution <= 32):
            raise FingerpadError("resolution must be a whole number in 2..32 elements per half-width, "
                                 f"got {self.resolution!r}")
        if not (_number(self.base_thickness) and 0 < self.base_thickness <= 100):
            raise FingerpadError(f"base_thickness must lie in (0, 100] periods, got {self.base_thickness!r}")
        if not (_number(self.fold_penalty) and self.fold_penalty > 0):
            raise FingerpadError(f"fold_penalty must be positive, got {self.fold_penalty!r}")
        if not (_integer(self.max_steps) and 1 <= self.max_steps <= 100_000):
            raise FingerpadError(f"max-steps must be a whole number in 1..100000, got {self.max_steps!r}")
        if self.time_limit is not None and not (_number(self.time_limit) and self.time_limit > 0):
            raise FingerpadError(f"time-limit must be a positive number of seconds (or omitted), got {self.time_limit!r}")

    def key(self) -> dict[str, Any]:
        """The settings that decide the numbers (the cache key): all but the safety stop."""
        out = asdict(self)
        out.pop("time_limit")
        return out


def _number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _integer(v: Any) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)


@dataclass(frozen=True)
class SectionMaterials:
    """Elastic constants (SI) of the texture (neo-Hookean) and the skin (linear half-space)."""

    texture_modulus: float | None
    texture_poisson: float
    skin_modulus: float
    skin_poisson: float

    @classmethod
    def from_materials(cls, materials: Any) -> SectionMaterials:
        """From a :class:`fingerpad.materials.Materials` (``material_modulus=None``: rigid)."""
        return cls(materials.material_modulus, materials.material_poisson, materials.skin_modulus,
                   materials.skin_poisson)

    def __post_init__(self) -> None:
        em = self.texture_modulus
        if em is not None and not (_number(em) and em > 0):
            raise FingerpadError(f"material modulus must be a positive stress (or None: rigid), got {em!r}")
        if not (_number(self.skin_modulus) and self.skin_modulus > 0):
            raise FingerpadError(f"skin modulus must be a positive stress, got {self.skin_modulus!r}")
        for name in ("texture_poisson", "skin_poisson"):
            v = getattr(self, name)
            if not (_number(v) and -1.0 < v <= 0.5):
                raise FingerpadError(f"{name.replace('_', ' ')} ratio must lie in (-1, 0.5], got {v!r}")

    @property
    def skin_plane_modulus(self) -> float:
        return self.skin_modulus / (1.0 - self.skin_poisson**2)


__all__ = ["DeflectionSettings", "SectionMaterials"]
