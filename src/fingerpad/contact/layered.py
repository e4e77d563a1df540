"""A layered skin: an elastic layer bonded to an elastic half-space (or to a rigid base).

The surface compliance of a layered body under a normal pressure ``p_q exp(i q.x)`` with no
surface shear is that of the homogeneous half-space of the layer times a factor of ``|q| t`` and
the moduli alone (docs/model.md, section 6.4 "Layered skin", for the derivation)::

    u_q = 2 K(|q| t) / (E1* |q|) p_q,      E1* = E1 / (1 - nu1^2)

With ``x = |q| t``, the shear-modulus ratio ``alpha = mu1/mu2`` and ``kappa_i = 3 - 4 nu_i``::

    m      = (alpha - 1) / (alpha + kappa1)
    lambda = 1 - 4 (1 - nu1) / (1 + alpha kappa2)
    K(x)   = (1 + 4 m x e^-2x - lambda m e^-4x)
             / (1 - (lambda + m + 4 m x^2) e^-2x + lambda m e^-4x)

A rigid bonded base is ``alpha = 0``; a rigid frictionless base has
``K = (1 - e^-2x)^2 / (1 - e^-4x + 4 x e^-2x)``. :func:`layer_factor` evaluates both in a form
where every term is non-negative (no cancellation at small ``x`` or large contrast, no overflow
at large ``x``).

:class:`Layer` describes the skin; :func:`spectral_factor` is what the elastic operators of
:mod:`fingerpad.contact.greens` multiply today's half-space kernel ``2 / (E* |q|)`` by. Physics
only: nothing here draws or writes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import FingerpadError
from ..materials import DEFAULT_SKIN_POISSON, check_modulus, check_poisson

__all__ = ["Layer", "effective_modulus", "layer_factor", "spectral_factor"]

BASES = ("bonded", "frictionless")


@dataclass(frozen=True)
class Layer:
    """An elastic layer on an elastic half-space or on a rigid base (the skin's structure).

    Parameters
    ----------
    thickness
        Layer thickness t (m), > 0.
    modulus
        Young's modulus E1 of the layer (Pa).
    poisson
        Poisson ratio nu1 of the layer.
    substrate_modulus
        Young's modulus E2 of the half-space under it (Pa); ``math.inf`` for a rigid base.
    substrate_poisson
        Poisson ratio nu2 of the half-space (unused for a rigid base).
    base
        ``"bonded"`` (perfect bonding, the default) or ``"frictionless"`` (the layer slides
        freely on the base; rigid base only).
    """

    thickness: float
    modulus: float
    poisson: float = DEFAULT_SKIN_POISSON
    substrate_modulus: float = math.inf
    substrate_poisson: float = DEFAULT_SKIN_POISSON
    base: str = "bonded"

    def __post_init__(self) -> None:
        t = self.thickness
        if not (isinstance(t, (int, float)) and math.isfinite(t) and t > 0):
            raise FingerpadError(f"layer thickness must be a positive number of metres, got {t!r}")
        check_modulus(self.modulus, "layer modulus")
        check_poisson(self.poisson, "layer Poisson ratio")
        e2 = self.substrate_modulus
        if not (isinstance(e2, (int, float)) and (e2 == math.inf or (math.isfinite(e2) and e2 > 0))):
            raise FingerpadError(f"substrate modulus must be a positive number of pascals or inf (rigid), got {e2!r}")
        check_poisson(self.substrate_poisson, "substrate Poisson ratio")
        if self.base not in BASES:
            raise FingerpadError(f"layer base must be one of {', '.join(BASES)}, got {self.base!r}")
        if self.base == "frictionless" and e2 != math.inf:
            raise FingerpadError("a frictionless base is a rigid one: set substrate_modulus=inf")

    @property
    def rigid_base(self) -> bool:
        return self.substrate_modulus == math.inf

    @property
    def reduced_modulus(self) -> float:
        """E1* = E1 / (1 - nu1^2) of the layer (Pa): the skin's modulus at short wavelengths."""
        return self.modulus / (1.0 - self.poisson**2)

    @property
    def substrate_reduced_modulus(self) -> float:
        """E2* = E2 / (1 - nu2^2) (Pa), ``inf`` for a rigid base: the skin's at long wavelengths."""
        return math.inf if self.rigid_base else self.substrate_modulus / (1.0 - self.substrate_poisson**2)

    def factor(self, x: np.ndarray | float) -> np.ndarray:
        """``K(|q| t)`` at ``x = |q| t``: the layered compliance over the layer's half-space one."""
        return layer_factor(x, self)

    def compliance(self, q: np.ndarray | float) -> np.ndarray:
        """Surface compliance ``u_q / p_q = 2 K(|q| t) / (E1* |q|)`` (m/Pa per rad/m), q > 0."""
        q = np.asarray(q, dtype=np.float64)
        return 2.0 * self.factor(q * self.thickness) / (self.reduced_modulus * q)


def _emx_sinh_minus(x: np.ndarray) -> np.ndarray:
    """g(x) = e^-x (sinh x - x) >= 0 without cancellation (a series below x = 0.5)."""
    x = np.asarray(x, dtype=np.float64)
    small = x < 0.5
    xs = np.where(small, x, 0.0)
    # sinh x - x = sum x^(2j+1)/(2j+1)!, j >= 1: at x = 0.5 the first omitted term (x^17/17!)
    # is ~1e-20 of the sum
    series = np.zeros_like(xs)
    term = xs**3 / 6.0
    for j in range(1, 8):
        series += term
        term = term * xs * xs / ((2 * j + 2) * (2 * j + 3))
    xl = np.where(small, 1.0, x)
    large = -0.5 * np.expm1(-2.0 * xl) - xl * np.exp(-xl)
    return np.where(small, np.exp(-xs) * series, large)


def layer_factor(x: np.ndarray | float, layer: Layer) -> np.ndarray:
    """Compliance factor ``K(x)``, ``x = |q| t >= 0``, of ``layer`` (docs/model.md, section 6.4).

    K -> 1 as x -> inf (the layer's half-space), K(0) = E1*/E2* on an elastic half-space (the
    substrate's), K -> 0 like the uniaxial strain of the layer on a rigid base.
    """
    x = np.asarray(x, dtype=np.float64)
    if np.any(x < 0) or not np.all(np.isfinite(x)):
        raise FingerpadError("|q| t must be finite and >= 0")
    e2 = np.exp(-2.0 * x)
    one_minus_e2 = -np.expm1(-2.0 * x)
    if layer.base == "frictionless":
        # K = (cosh 2x - 1) / (sinh 2x + 2x), times 2 e^-2x above and below
        num = one_minus_e2**2
        den = -np.expm1(-4.0 * x) + 4.0 * x * e2
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(x > 0, num / np.where(x > 0, den, 1.0), 0.0)
    nu1, nu2 = layer.poisson, layer.substrate_poisson
    k1, k2 = 3.0 - 4.0 * nu1, 3.0 - 4.0 * nu2
    # alpha = mu1/mu2 (0 for a rigid base); the combinations below are the non-negative ones the
    # expanded numerator and denominator are sums of (so nothing cancels):
    #   1 + m, 1 - m, 1 - lambda, 1 - lambda m
    if layer.rigid_base:
        one_m_lam = 4.0 * (1.0 - nu1)              # 1 - lambda
        one_m_m = (1.0 + k1) / k1                  # 1 - m, m = -1/kappa1
        one_p_m = (k1 - 1.0) / k1                  # 1 + m
        one_m_lm = 0.0                             # 1 - lambda m (lambda m = 1)
    else:
        alpha = (layer.modulus / (1.0 + nu1)) / (layer.substrate_modulus / (1.0 + nu2))
        one_m_lam = 4.0 * (1.0 - nu1) / (1.0 + alpha * k2)
        one_m_m = (1.0 + k1) / (alpha + k1)
        one_p_m = (2.0 * alpha + k1 - 1.0) / (alpha + k1)
        one_m_lm = alpha * (1.0 + k1) * (1.0 + k2) / ((1.0 + alpha * k2) * (alpha + k1))
    g1 = _emx_sinh_minus(x)          # e^-x (sinh x - x)
    g2 = _emx_sinh_minus(2.0 * x)    # e^-2x (sinh 2x - 2x)
    emx = np.exp(-x)
    # N = 2 e^-2x (sinh 2x - 2x) + 4 (1 + m) x e^-2x + (1 - lambda m) e^-4x
    num = 2.0 * g2 + 4.0 * one_p_m * x * e2 + one_m_lm * e2 * e2
    # D = 4 e^-2x (sinh^2 x - x^2) + 4 (1 - m) x^2 e^-2x + (2 - lambda - m)(1 - e^-2x) e^-2x
    #     + (1 - lambda)(1 - m) e^-4x
    den = (4.0 * g1 * (g1 + 2.0 * x * emx) + 4.0 * one_m_m * x * x * e2
           + (one_m_lam + one_m_m) * one_minus_e2 * e2 + one_m_lam * one_m_m * e2 * e2)
    return num / den


def spectral_factor(layer: Layer | None, q: np.ndarray, modulus: float) -> np.ndarray | None:
    """What the half-space compliance ``2 / (E* |q|)`` of the operators is multiplied by.

    ``modulus`` is the reduced modulus E* of the contact pair at short wavelengths: the layer's
    E1* for a rigid counter-surface, or ``1/E* = 1/E1* + 1/Em*`` with a deformable one. The
    counter-surface's compliance adds to the skin's (``2/(Em* |q|)``, a half-space), so the pair's
    compliance is ``2 / (E* |q|) [1 + w (K(|q| t) - 1)]`` with ``w = E*/E1* <= 1``. ``None`` (no
    layer) stays None: the homogeneous half-space, untouched.
    """
    if layer is None:
        return None
    w = modulus / layer.reduced_modulus
    if w > 1.0 + 1e-9:
        raise FingerpadError(
            f"reduced modulus {modulus:.6g} Pa exceeds the layer's own E1* = {layer.reduced_modulus:.6g} Pa: "
            "the pair's modulus is the layer's combined with the counter-surface's (Eq. 3.4)")
    w = min(w, 1.0)
    return 1.0 + w * (layer_factor(np.asarray(q, dtype=np.float64) * layer.thickness, layer) - 1.0)


def effective_modulus(layer: Layer, k: np.ndarray | float) -> np.ndarray:
    """The reduced modulus of the homogeneous half-space as stiff as ``layer`` at wavenumber ``k``.

    ``E*_eff(k) = E1* / K(|k| t)`` (Pa), ``k`` in rad/m: a sinusoidal pressure of wavenumber k
    deflects the layered body as much as it deflects this half-space (docs/model.md, section 6.4,
    "Westergaard generalised"). It runs from the substrate's E2* (``k t -> 0``) to the layer's
    E1* (``k t -> inf``); 0 at ``k = 0`` on a rigid base is returned as ``inf``.
    """
    k = np.abs(np.asarray(k, dtype=np.float64))
    factor = layer_factor(k * layer.thickness, layer)
    with np.errstate(divide="ignore"):
        return layer.reduced_modulus / factor
