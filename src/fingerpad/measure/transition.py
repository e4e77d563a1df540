"""Closed-form skin modulus from the transition load (docs/model.md Eqs. 3.4 and 3.6), and its inverse."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from scipy import optimize

from ..errors import FingerpadError
from ..materials import DEFAULT_SKIN_POISSON, reduced_modulus
from .micro_models import TextureGeometry


def _ridge_area_of(ridge_area: float | Callable[[float], float] | Any, load: float) -> float:
    if hasattr(ridge_area, "ridge_area"):
        return float(ridge_area.ridge_area(load))
    if callable(ridge_area):
        return float(ridge_area(load))
    return float(ridge_area)


def modulus_from_transition(
    critical_load: float,
    radius: float,
    height: float,
    spacing: float,
    ridge_area: float | Callable[[float], float] | Any,
    *,
    skin_poisson: float = DEFAULT_SKIN_POISSON,
    material_modulus: float | None = None,
    material_poisson: float = 0.35,
) -> float:
    """Skin modulus E_s from the transition load, closed form (docs/model.md Eq. 3.6 and 3.4).

    ``F_crit = (8/9) E1* sqrt(h^3 R) A_fr / lambda^2`` gives
    ``E1* = 9 F_crit lambda^2 / (8 sqrt(h^3 R) A_fr(F_crit))``, and Eq. 3.4 solved for E_s:
    ``E_s = (1 - nu_s^2) / (1/E1* - (1 - nu_m^2)/E_m)``.

    Parameters
    ----------
    critical_load
        F_crit, N.
    radius, height, spacing
        Asperity radius R, height h and lattice spacing lambda, m.
    ridge_area
        A_fr in m^2: a number, a callable of the load, or a finger (``ridge_area(load)``).

    Raises
    ------
    FingerpadError
        For non-positive input, or if E1* exceeds what the counter-surface alone allows.
    """
    geometry = TextureGeometry(radius, height, spacing, material_modulus, material_poisson)
    if not (math.isfinite(critical_load) and critical_load > 0):
        raise FingerpadError(f"critical load must be positive, got {critical_load!r}")
    a_fr = _ridge_area_of(ridge_area, critical_load)
    if not a_fr > 0:
        raise FingerpadError(f"ridge area must be positive, got {a_fr!r}")
    e1 = 9.0 * critical_load * spacing**2 / (8.0 * math.sqrt(height**3 * radius) * a_fr)
    compliance = 1.0 / e1
    if geometry.material_modulus is not None:
        compliance -= (1.0 - material_poisson**2) / geometry.material_modulus
    if compliance <= 0:
        raise FingerpadError(
            f"transition at {critical_load:.4g} N implies E1* = {e1:.4g} Pa, stiffer than the counter-surface allows"
        )
    return (1.0 - skin_poisson**2) / compliance


def transition_load(
    skin_modulus: float,
    radius: float,
    height: float,
    spacing: float,
    ridge_area: float | Callable[[float], float] | Any,
    *,
    skin_poisson: float = DEFAULT_SKIN_POISSON,
    material_modulus: float | None = None,
    material_poisson: float = 0.35,
    bracket: tuple[float, float] = (1e-6, 1e4),
) -> float:
    """Transition load F_crit for a skin modulus: Eq. 3.6 solved for F with A_fr(F).

    The inverse of :func:`modulus_from_transition`.

    Raises
    ------
    FingerpadError
        If no load in ``bracket`` satisfies Eq. 3.6.
    """
    e1 = reduced_modulus(skin_modulus, skin_poisson, material_modulus, material_poisson)
    TextureGeometry(radius, height, spacing)
    c = (8.0 / 9.0) * e1 * math.sqrt(height**3 * radius) / spacing**2

    def g(log_f: float) -> float:
        f = math.exp(log_f)
        return math.log(f) - math.log(c * _ridge_area_of(ridge_area, f))

    a, b = (math.log(x) for x in bracket)
    if g(a) * g(b) > 0:
        raise FingerpadError(f"no transition load within {bracket[0]:.3g}-{bracket[1]:.3g} N")
    return math.exp(optimize.brentq(g, a, b, xtol=1e-10))
