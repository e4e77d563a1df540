"""Macro and meso scales of the finger pad: gross and ridge (fingerprint) contact areas.

The finger pad is a sphere of radius ``R_fp`` and reduced modulus ``E_fp*`` pressed on a flat
(MODEL.md, ch. 2.2.1); its gross contact ``A_g`` is covered in part by the fingerprint ridges,
whose contact ``A_fr`` (ch. 2.2.2) is the nominal area seen by the micro scale (ch. 3.2).

Two small interfaces, so that new models plug in without touching callers:

* :class:`GrossAreaModel` -- ``area(load) -> A_g``;
* :class:`RidgeAreaModel` -- ``area(load, gross_area) -> A_fr``.

A :class:`Finger` bundles one person's parameters; :data:`FINGER_PRESETS` holds named fingers.
SI units throughout (m, N, Pa).
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any, Literal, Protocol, runtime_checkable

import numpy as np

from .errors import FingerpadError
from .materials import (
    DEFAULT_SKIN_MODULUS,
    DEFAULT_SKIN_POISSON,
    check_poisson,
    reduced_modulus,
)

ArrayLike = float | np.ndarray | Sequence[float]

# ---------------------------------------------------------------------------------------------
# input checks
# ---------------------------------------------------------------------------------------------


def _positive(value: Any, name: str) -> float:
    """Return ``value`` as a float if finite and > 0, else raise a FingerpadError."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise FingerpadError(f"{name} must be a positive number, got {value!r}")
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise FingerpadError(f"{name} must be a positive number, got {value!r}")
    return v


def _nonnegative(value: Any, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise FingerpadError(f"{name} must be a non-negative number, got {value!r}")
    v = float(value)
    if not (math.isfinite(v) and v >= 0):
        raise FingerpadError(f"{name} must be a non-negative number, got {value!r}")
    return v


def as_loads(load: ArrayLike, name: str = "load", *, strict: bool = False) -> np.ndarray:
    """Return ``load`` as a float array, checking it is finite and >= 0 (> 0 if ``strict``)."""
    try:
        arr = np.asarray(load, dtype=float)
    except (TypeError, ValueError):
        raise FingerpadError(f"{name} must be a number or an array of numbers, got {load!r}") from None
    if not np.all(np.isfinite(arr)):
        raise FingerpadError(f"{name} holds NaN or infinite values")
    if strict and np.any(arr <= 0):
        raise FingerpadError(f"{name} must be positive, got a minimum of {arr.min():.4g}")
    if np.any(arr < 0):
        raise FingerpadError(f"{name} must be non-negative, got a minimum of {arr.min():.4g}")
    return arr


def _out(arr: np.ndarray) -> float | np.ndarray:
    """Return a Python float for 0-d results so scalar in -> scalar out."""
    return float(arr) if np.ndim(arr) == 0 else arr


# ---------------------------------------------------------------------------------------------
# Hertzian pad pressure and integrals over the contact disc
# ---------------------------------------------------------------------------------------------


def pad_pressure(r: ArrayLike, load: float, ridge_area: float) -> float | np.ndarray:
    """Nominal pressure on the ridge contact at radius ``r``, Eq. 3.7.

    ``p(r) = 1.5 p_mean sqrt(1 - r^2/a_fr^2)`` with ``p_mean = F/A_fr`` and
    ``a_fr = sqrt(A_fr/pi)``; zero outside the disc.

    Parameters
    ----------
    r
        Radius from the pad centre, m (float or array).
    load
        Normal load F, N.
    ridge_area
        Ridge contact area A_fr, m^2.

    Returns
    -------
    float or ndarray
        Pressure, Pa, shaped like ``r``.
    """
    rr = np.asarray(r, dtype=float)
    if np.any(rr < 0) or not np.all(np.isfinite(rr)):
        raise FingerpadError("radius r must be finite and non-negative")
    f = _nonnegative(load, "load")
    area = _positive(ridge_area, "ridge area")
    a = math.sqrt(area / math.pi)
    s2 = np.clip(1.0 - (rr / a) ** 2, 0.0, None)
    return _out(1.5 * (f / area) * np.sqrt(s2))


@lru_cache(maxsize=16)
def _graded_rule(n_nodes: int, levels: int, ratio: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """Composite Gauss-Legendre rule on [0, 1], geometrically graded toward both ends.

    Sub-interval edges 0, r^L, ..., r, 1 - r, ..., 1 - r^L, 1: an algebraic end singularity
    (``p^m`` at zero pressure, ``sqrt`` at saturation) then costs only a few more levels
    instead of ruining the convergence of a single Gauss rule (hp-quadrature).
    """
    left = [ratio**k for k in range(levels, 0, -1)]
    edges = np.array([0.0, *left, *[1.0 - x for x in reversed(left)], 1.0])
    x, w = np.polynomial.legendre.leggauss(n_nodes)
    lo, hi = edges[:-1, None], edges[1:, None]
    nodes = (lo + 0.5 * (hi - lo) * (x + 1.0)).ravel()
    weights = (0.5 * (hi - lo) * w).ravel()
    return nodes, weights


def disc_average(
    func: Callable[[np.ndarray], np.ndarray],
    peak_pressure: ArrayLike,
    breakpoints: Sequence[float] = (),
    *,
    n_nodes: int = 16,
    levels: int = 12,
) -> np.ndarray:
    """Area-weighted mean of ``func(p(r))`` over a disc under the Hertzian pressure (3.7).

    With ``s = sqrt(1 - r^2/a^2)``, ``p = p_peak s`` and ``dA = 2 pi a^2 s ds``, so the mean is
    ``2 int_0^1 func(p_peak s) s ds``. The s-interval is split where ``p_peak s`` crosses one of
    ``breakpoints`` (pressures where ``func`` has a kink) and each piece gets the graded
    Gauss-Legendre rule of :func:`_graded_rule` (``(2 levels + 1) n_nodes`` nodes per piece).

    Accuracy: for ``func`` analytic between breakpoints, also with algebraic end behaviour such
    as ``p^m`` (m > -1) at zero pressure or ``sqrt`` saturation, the relative error is below
    1e-13 with the defaults (about 1e-15 against the closed forms of the tests).

    Parameters
    ----------
    func
        Vectorised function of pressure (Pa) -> ndarray of the same shape.
    peak_pressure
        Peak (centre) pressure ``1.5 p_mean`` per load, Pa.
    breakpoints
        Pressures (Pa) where ``func`` has kinks; non-finite or non-positive ones are ignored.

    Returns
    -------
    ndarray
        Mean of ``func`` over the disc, one value per entry of ``peak_pressure`` (1-D).
    """
    peak = np.atleast_1d(np.asarray(peak_pressure, dtype=float)).ravel()
    bps = sorted({float(b) for b in breakpoints if math.isfinite(b) and b > 0})
    with np.errstate(divide="ignore", invalid="ignore"):
        cuts = [np.where(peak > 0, np.clip(b / peak, 0.0, 1.0), 1.0) for b in bps]
    edges = [np.zeros_like(peak), *cuts, np.ones_like(peak)]
    x, w = _graded_rule(int(n_nodes), int(levels))
    s_parts, w_parts = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        width = (hi - lo)[:, None]  # zero-width pieces (breakpoint outside the disc) weigh 0
        s_parts.append(lo[:, None] + width * x[None, :])
        w_parts.append(width * w[None, :])
    s = np.concatenate(s_parts, axis=1)
    wt = np.concatenate(w_parts, axis=1)
    values = np.asarray(func(peak[:, None] * s), dtype=float)
    if values.shape != s.shape:
        values = np.broadcast_to(values, s.shape)
    return 2.0 * np.sum(wt * s * values, axis=1)


# ---------------------------------------------------------------------------------------------
# gross contact area (macro scale, ch. 2.2.1)
# ---------------------------------------------------------------------------------------------


@runtime_checkable
class GrossAreaModel(Protocol):
    """Gross contact area of the finger pad: ``area(load) -> A_g`` (m^2), vectorised."""

    def area(self, load: ArrayLike) -> float | np.ndarray: ...


def _hertz_area(load: np.ndarray, radius: float, modulus: np.ndarray | float) -> np.ndarray:
    return math.pi * (3.0 * load * radius / (4.0 * modulus)) ** (2.0 / 3.0)


@dataclass(frozen=True)
class HertzArea:
    """Hertz sphere-on-flat gross area, Eq. 2.5: ``A = pi (3 F R / (4 E*))^(2/3)``.

    Attributes
    ----------
    radius
        Equivalent pad radius R_fp, m (MODEL.md: 7-11 mm).
    modulus
        Reduced modulus E_fp*, Pa (MODEL.md: 10-100 kPa, 40 kPa typical).
    """

    radius: float
    modulus: float

    def __post_init__(self) -> None:
        _positive(self.radius, "pad radius R_fp")
        _positive(self.modulus, "pad modulus E_fp*")

    def contact_radius(self, load: ArrayLike) -> float | np.ndarray:
        """Hertz contact radius ``a = (3 F R / (4 E*))^(1/3)``, m."""
        f = as_loads(load)
        return _out(np.cbrt(3.0 * f * self.radius / (4.0 * self.modulus)))

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2), Eq. 2.5."""
        return _out(_hertz_area(as_loads(load), self.radius, self.modulus))

    __call__ = area


@dataclass(frozen=True)
class DzidekArea:
    """Hertz with a strain-stiffened secant modulus (Dzidek et al. 2017), Eqs. 2.6-2.7.

    ``E_sfp* = E_fp* (1 + (C eps)^eta)`` with the contact strain estimated from the Hertz radius,
    ``eps = 0.2 a_H / R_fp``. For ``eta = 3`` this is exactly Eq. 2.7:
    ``A_g = pi (3 R F / (4 E* (1 + phi F)))^(2/3)``, ``phi = 3 (0.2 C)^3 / (4 R^2 E*)``.
    Other ``eta`` use the same strain estimate. The local exponent ``d ln A / d ln F`` is
    ``(2/3) / (1 + phi F)``: it falls with load as the skin is pressed on the bone.

    Attributes
    ----------
    radius, modulus
        R_fp (m) and the unstiffened E_fp* (Pa).
    stiffening
        Dzidek's C (dimensionless; strain range ``eps < 1/C``).
    exponent
        eta (MODEL.md: 3).
    """

    radius: float
    modulus: float
    stiffening: float
    exponent: float = 3.0

    def __post_init__(self) -> None:
        _positive(self.radius, "pad radius R_fp")
        _positive(self.modulus, "pad modulus E_fp*")
        _nonnegative(self.stiffening, "Dzidek stiffening C")
        _positive(self.exponent, "Dzidek exponent eta")

    @property
    def phi(self) -> float:
        """``phi = 3 (0.2 C)^3 / (4 R^2 E*)`` of Eq. 2.7 (1/N; meaningful for eta = 3)."""
        return 3.0 * (0.2 * self.stiffening) ** 3 / (4.0 * self.radius**2 * self.modulus)

    def secant_modulus(self, load: ArrayLike) -> float | np.ndarray:
        """Stiffened modulus ``E_sfp* = E_fp* (1 + (C eps)^eta)``, Eq. 2.6, Pa."""
        f = as_loads(load)
        a_hertz = np.cbrt(3.0 * f * self.radius / (4.0 * self.modulus))
        strain = 0.2 * a_hertz / self.radius
        return _out(self.modulus * (1.0 + (self.stiffening * strain) ** self.exponent))

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2), Eq. 2.7."""
        f = as_loads(load)
        return _out(_hertz_area(f, self.radius, np.asarray(self.secant_modulus(f))))

    __call__ = area


@dataclass(frozen=True)
class PowerLawArea:
    """Empirical gross area ``A_g = c F^m`` (per-person fit; MODEL.md: m = 0.1-0.5 measured).

    Attributes
    ----------
    coefficient
        c, m^2 / N^m.
    exponent
        m.
    """

    coefficient: float
    exponent: float

    def __post_init__(self) -> None:
        _positive(self.coefficient, "power-law coefficient c")
        _positive(self.exponent, "power-law exponent m")

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """``c F^m`` (m^2)."""
        return _out(self.coefficient * as_loads(load) ** self.exponent)

    __call__ = area


@dataclass(frozen=True)
class TwoRegimePowerLawArea:
    """Two power laws joined continuously at a break load (Liu et al.: below/above ~2 N).

    ``A_g = c1 F^m1`` for ``F <= F_b`` and ``c1 F_b^m1 (F/F_b)^m2`` above, so the area is
    continuous at ``F_b`` and only the exponent changes.

    Attributes
    ----------
    coefficient
        c1 (m^2 / N^m1).
    exponent_low, exponent_high
        m1 below and m2 above the break load.
    break_load
        F_b, N (MODEL.md: ~2 N).
    """

    coefficient: float
    exponent_low: float
    exponent_high: float
    break_load: float = 2.0

    def __post_init__(self) -> None:
        _positive(self.coefficient, "power-law coefficient c1")
        _positive(self.exponent_low, "exponent m1")
        _positive(self.exponent_high, "exponent m2")
        _positive(self.break_load, "break load F_b")

    def area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross area (m^2) from the regime the load falls in."""
        f = as_loads(load)
        fb = self.break_load
        low = self.coefficient * f**self.exponent_low
        high = self.coefficient * fb**self.exponent_low * (f / fb) ** self.exponent_high
        return _out(np.where(f <= fb, low, high))

    __call__ = area


# ---------------------------------------------------------------------------------------------
# ridge (fingerprint) contact area (meso scale, ch. 2.2.2)
# ---------------------------------------------------------------------------------------------


@runtime_checkable
class RidgeAreaModel(Protocol):
    """Ridge contact area from the load and the gross area: ``area(load, gross_area) -> A_fr``.

    Implementations are vectorised (load and gross area broadcast) and return
    ``0 <= A_fr <= A_g``. A BEM fingerprint model (``FingerprintBEMRidges``) plugs in here.
    """

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray: ...


def _load_and_gross(load: ArrayLike, gross_area: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    f = as_loads(load)
    ag = as_loads(gross_area, "gross area")
    return np.broadcast_arrays(f, ag)  # type: ignore[return-value]


@dataclass(frozen=True)
class ConstantFractionRidges:
    """Ridge area as a constant fraction of the gross area (van Kuilenburg; Duvefelt: 50 %).

    Attributes
    ----------
    fraction
        A_fr / A_g in (0, 1] (MODEL.md: 0.5 after Duvefelt).
    """

    fraction: float = 0.5

    def __post_init__(self) -> None:
        v = _positive(self.fraction, "ridge fraction")
        if v > 1.0:
            raise FingerpadError(f"ridge fraction must lie in (0, 1], got {self.fraction!r}")

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """``fraction * A_g`` (m^2)."""
        _, ag = _load_and_gross(load, gross_area)
        return _out(self.fraction * ag)


@dataclass(frozen=True)
class PowerLawRidges:
    """Empirical ridge area ``A_fr = k F^n`` (MODEL.md: n = 0.2-0.7, fitted per person).

    Capped at the gross area, since ridges cannot touch outside the gross contact.

    Attributes
    ----------
    coefficient
        k, m^2 / N^n.
    exponent
        n.
    """

    coefficient: float
    exponent: float

    def __post_init__(self) -> None:
        _positive(self.coefficient, "ridge power-law coefficient k")
        _positive(self.exponent, "ridge power-law exponent n")

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """``min(k F^n, A_g)`` (m^2)."""
        f, ag = _load_and_gross(load, gross_area)
        return _out(np.minimum(self.coefficient * f**self.exponent, ag))


PressureDistribution = Literal["hertz", "uniform"]


@dataclass(frozen=True, kw_only=True)
class _ProfileRidges:
    """Parallel ridges across the gross contact, each a 1-D contact set by the local pressure.

    The ridge-area fraction at local nominal pressure p is :meth:`local_fraction`; the ridge
    area is its integral over the gross disc under the Hertzian gross pressure
    ``p(r) = 1.5 p_mean sqrt(1 - r^2/a^2)`` (``pressure_distribution="hertz"``, the ridges being
    much narrower than the gross contact) or ``A_g * local_fraction(p_mean)``
    (``"uniform"``). The disc integral uses :func:`disc_average` (relative error below 1e-13,
    checked against the closed forms quoted by the subclasses). Fields are keyword-only.
    """

    wavelength: float = 0.45e-3
    modulus: float = 100e3
    pressure_distribution: PressureDistribution = "hertz"

    def __post_init__(self) -> None:
        _positive(self.wavelength, "ridge wavelength")
        _positive(self.modulus, "ridge modulus")
        if self.pressure_distribution not in ("hertz", "uniform"):
            raise FingerpadError(
                f"pressure distribution must be 'hertz' or 'uniform', got {self.pressure_distribution!r}"
            )

    @property
    def full_contact_pressure(self) -> float:  # pragma: no cover - overridden
        raise NotImplementedError

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:  # pragma: no cover
        raise NotImplementedError

    def area(self, load: ArrayLike, gross_area: ArrayLike) -> float | np.ndarray:
        """Ridge contact area A_fr (m^2) under the chosen gross pressure distribution."""
        f, ag = _load_and_gross(load, gross_area)
        shape = f.shape
        f, ag = f.ravel(), ag.ravel()
        with np.errstate(divide="ignore", invalid="ignore"):
            p_mean = np.where(ag > 0, f / ag, 0.0)
        if self.pressure_distribution == "uniform":
            frac = np.asarray(self.local_fraction(p_mean), dtype=float)
        else:
            frac = disc_average(self.local_fraction, 1.5 * p_mean, (self.full_contact_pressure,))
        return _out((frac * ag).reshape(shape))


@dataclass(frozen=True, kw_only=True)
class SinusoidalRidges(_ProfileRidges):
    """Ridges as 1-D sinusoids (Westergaard; Rodriguez Urribarri et al.).

    Each ridge has wavelength ``lambda_r`` and amplitude ``h_r``; full contact needs
    ``p* = pi E* h_r / lambda_r`` and below it the contact fraction is
    ``(2/pi) arcsin(sqrt(p/p*))`` (Westergaard 1939; Johnson, Contact Mechanics 13.2).
    Under the Hertzian gross pressure the closed form is
    ``A_fr/A_g = 1 - 3/(8 k^2)`` for ``k = 1.5 p_mean / p* >= 1`` (used as a test).

    Attributes
    ----------
    wavelength
        Ridge wavelength lambda_r, m (MODEL.md: 0.4-0.5 mm).
    amplitude
        Sinusoid amplitude h_r (half the peak-to-valley height), m.
    modulus
        Reduced modulus E* of the ridge skin, Pa (thesis Fig. 2.4: 100 kPa).
    pressure_distribution
        ``"hertz"`` (default) or ``"uniform"`` gross pressure.
    """

    amplitude: float = 30e-6

    def __post_init__(self) -> None:
        super().__post_init__()
        _positive(self.amplitude, "ridge amplitude")

    @property
    def full_contact_pressure(self) -> float:
        """Westergaard full-contact pressure ``p* = pi E* h_r / lambda_r``, Pa."""
        return math.pi * self.modulus * self.amplitude / self.wavelength

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:
        """Ridge contact fraction ``(2/pi) arcsin(sqrt(min(p/p*, 1)))`` at local pressure p."""
        p = np.asarray(pressure, dtype=float)
        ratio = np.clip(p / self.full_contact_pressure, 0.0, 1.0)
        return _out((2.0 / math.pi) * np.arcsin(np.sqrt(ratio)))


@dataclass(frozen=True, kw_only=True)
class CircularRidges(_ProfileRidges):
    """Ridges as cylinders of radius R_r, each in Hertz line contact.

    Line load ``w = p lambda_r`` (local pressure times ridge spacing), half-width
    ``b = sqrt(4 w R_r / (pi E*))``, contact fraction ``min(2 b / lambda_r, 1)``, i.e.
    ``sqrt(p / p_c)`` with ``p_c = pi E* lambda_r / (16 R_r)``. Under the Hertzian gross pressure
    ``A_fr/A_g = (4/5) sqrt(k)`` for ``k = 1.5 p_mean / p_c <= 1`` and ``1 - 1/(5 k^2)`` above.

    Attributes
    ----------
    wavelength
        Ridge spacing lambda_r, m.
    ridge_radius
        Ridge tip radius R_r, m.
    modulus
        Reduced modulus E* of the ridge skin, Pa.
    pressure_distribution
        ``"hertz"`` (default) or ``"uniform"`` gross pressure.
    """

    ridge_radius: float = 0.1e-3

    def __post_init__(self) -> None:
        super().__post_init__()
        _positive(self.ridge_radius, "ridge radius")

    @property
    def full_contact_pressure(self) -> float:
        """Pressure at which neighbouring line contacts meet, ``pi E* lambda / (16 R_r)``, Pa."""
        return math.pi * self.modulus * self.wavelength / (16.0 * self.ridge_radius)

    def half_width(self, pressure: ArrayLike) -> float | np.ndarray:
        """Hertz line-contact half-width ``b = sqrt(4 w R_r / (pi E*))``, ``w = p lambda``, m."""
        p = np.clip(np.asarray(pressure, dtype=float), 0.0, None)
        w = p * self.wavelength
        return _out(np.sqrt(4.0 * w * self.ridge_radius / (math.pi * self.modulus)))

    def local_fraction(self, pressure: ArrayLike) -> float | np.ndarray:
        """Ridge contact fraction ``min(2 b / lambda_r, 1)`` at local pressure p."""
        b = np.asarray(self.half_width(pressure))
        return _out(np.minimum(2.0 * b / self.wavelength, 1.0))


# ---------------------------------------------------------------------------------------------
# the finger
# ---------------------------------------------------------------------------------------------

# Quantity kinds of Finger's numeric fields, so with_overrides accepts "9mm", "40kPa", ...
_FIELD_DIMENSIONS = {
    "radius": "length",
    "modulus": "pressure",
    "beta": "none",
    "tau0": "pressure",
    "alpha": "none",
    "skin_modulus": "pressure",
    "skin_poisson": "none",
}


@dataclass(frozen=True)
class Finger:
    """One person's finger pad: macro, meso and interface parameters (SI units).

    Attributes
    ----------
    radius
        Equivalent pad radius R_fp, m (Eqs. 2.4, 2.5).
    modulus
        Pad reduced modulus E_fp*, Pa (Eqs. 2.4, 2.5).
    ridges
        Ridge-area model (:class:`RidgeAreaModel`).
    gross
        Gross-area model; ``None`` means Hertz (Eq. 2.5) with ``radius`` and ``modulus``. A model
        with its own ``radius``/``modulus`` (Hertz, Dzidek) must agree with the finger's.
    beta
        Viscoelastic hysteresis loss fraction, Eq. 2.4, in [0, 1].
    tau0
        Interfacial shear strength at zero pressure, Pa, Eq. 2.3.
    alpha
        Pressure coefficient of the shear strength, Eq. 2.3.
    skin_modulus
        Effective micro-scale skin modulus E_s, Pa (thesis: 0.2-0.5 MPa), used in Eq. 3.4.
    skin_poisson
        Skin Poisson ratio (MODEL.md: 0.48-0.5).
    name, description
        Labels.
    """

    radius: float = 9e-3
    modulus: float = 40e3
    ridges: RidgeAreaModel = ConstantFractionRidges(0.5)
    gross: GrossAreaModel | None = None
    beta: float = 0.1
    tau0: float = 8.1e3
    alpha: float = 0.1
    skin_modulus: float = DEFAULT_SKIN_MODULUS
    skin_poisson: float = DEFAULT_SKIN_POISSON
    name: str = "custom"
    description: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        _positive(self.radius, "pad radius R_fp")
        _positive(self.modulus, "pad modulus E_fp*")
        beta = _nonnegative(self.beta, "hysteresis loss fraction beta")
        if beta > 1.0:
            raise FingerpadError(f"hysteresis loss fraction beta must lie in [0, 1], got {self.beta!r}")
        _nonnegative(self.tau0, "shear strength tau0")
        _nonnegative(self.alpha, "pressure coefficient alpha")
        _positive(self.skin_modulus, "skin modulus E_s")
        check_poisson(self.skin_poisson, "skin Poisson ratio")
        if not isinstance(self.ridges, RidgeAreaModel):
            raise FingerpadError(f"ridges must be a ridge-area model with area(load, gross_area), got {self.ridges!r}")
        if self.gross is not None:
            if not isinstance(self.gross, GrossAreaModel):
                raise FingerpadError(f"gross must be a gross-area model with area(load), got {self.gross!r}")
            # Eq. 2.4 uses R_fp and E_fp*: a Hertz-type gross model must not contradict them.
            for attr in ("radius", "modulus"):
                own = getattr(self.gross, attr, None)
                if own is not None and not math.isclose(own, getattr(self, attr), rel_tol=1e-12):
                    raise FingerpadError(
                        f"gross-area model {attr} {own:.6g} differs from the finger's {getattr(self, attr):.6g}"
                    )

    @property
    def gross_model(self) -> GrossAreaModel:
        """The gross-area model in use (Hertz with R_fp, E_fp* unless ``gross`` is set)."""
        return self.gross if self.gross is not None else HertzArea(self.radius, self.modulus)

    def gross_area(self, load: ArrayLike) -> float | np.ndarray:
        """Gross contact area A_g (m^2)."""
        return self.gross_model.area(load)

    def ridge_area(self, load: ArrayLike) -> float | np.ndarray:
        """Ridge contact area A_fr (m^2); a callable of the load, as Eq. 3.6 needs."""
        f = as_loads(load)
        return self.ridges.area(f, np.asarray(self.gross_model.area(f)))

    def ridge_radius(self, load: ArrayLike) -> float | np.ndarray:
        """Radius of the ridge contact disc ``a_fr = sqrt(A_fr/pi)``, Eq. 3.7, m."""
        return _out(np.sqrt(np.asarray(self.ridge_area(load)) / math.pi))

    def micro_modulus(self, material_modulus: float | None = None, material_poisson: float = 0.35) -> float:
        """Combined skin/texture modulus E1* (Pa), Eq. 3.4; ``None`` = rigid texture."""
        return reduced_modulus(self.skin_modulus, self.skin_poisson, material_modulus, material_poisson)

    def with_overrides(self, **kwargs: Any) -> Finger:
        """Return a copy with some fields replaced.

        Numeric fields also accept strings with units (``radius="9mm"``). Changing ``radius`` or
        ``modulus`` also updates a Hertz/Dzidek ``gross`` model so the two stay consistent.

        Raises
        ------
        FingerpadError
            For an unknown field name or an invalid value.
        """
        from .units import parse_quantity

        names = [f.name for f in dataclasses.fields(self)]
        unknown = sorted(set(kwargs) - set(names))
        if unknown:
            raise FingerpadError(f"unknown finger parameter(s) {', '.join(unknown)}; known: {', '.join(names)}")
        values = dict(kwargs)
        for key, dim in _FIELD_DIMENSIONS.items():
            if isinstance(values.get(key), str):
                values[key] = parse_quantity(values[key], dim, name=key)
        gross = values.get("gross", self.gross)
        sync = {k: values[k] for k in ("radius", "modulus") if k in values}
        if sync and "gross" not in values and gross is not None and dataclasses.is_dataclass(gross):
            own = {k: v for k, v in sync.items() if hasattr(gross, k)}
            if own:
                try:
                    values["gross"] = dataclasses.replace(gross, **own)
                except TypeError as exc:
                    raise FingerpadError(f"bad finger parameter: {exc}") from None
        try:
            return dataclasses.replace(self, **values)
        except TypeError as exc:  # e.g. arithmetic on a wrong type inside a model
            raise FingerpadError(f"bad finger parameter: {exc}") from None

    def as_dict(self) -> dict[str, Any]:
        """Flat description of the parameters (for file attributes)."""
        return {
            "name": self.name,
            "radius": self.radius,
            "modulus": self.modulus,
            "gross_model": repr(self.gross_model),
            "ridge_model": repr(self.ridges),
            "beta": self.beta,
            "tau0": self.tau0,
            "alpha": self.alpha,
            "skin_modulus": self.skin_modulus,
            "skin_poisson": self.skin_poisson,
        }


# Default finger, values and sources (MODEL.md, "Macro", "Meso", "Friction", "Micro"):
#   R_fp = 9 mm        middle of the 7-11 mm equivalent pad radius;
#   E_fp* = 40 kPa     the typical value of the 10-100 kPa range;
#   ridges 50 %        constant fraction after Duvefelt;
#   E_s = 0.3 MPa      inside the 0.2-0.5 MPa micro-scale modulus found by the thesis;
#   nu_s = 0.49        skin Poisson ratio 0.48-0.5;
#   beta = 0.1         assumed: MODEL.md gives no value; friction is "mostly adhesive", so the
#                      hysteresis term is kept small (1.2 % of the load at 1 N);
#   alpha = 0.1        assumed small pressure coefficient (no value in MODEL.md);
#   tau0 = 8.1 kPa     calibrated to dry mu ~ 0.5 on smooth surfaces (MODEL.md): on a flat sample
#                      A_re = A_fr, so mu(F) = tau0 A_fr/F + alpha + beta (3/16) a/R_fp. At 1 N:
#                      a = (3 * 1 * 9e-3 / (4 * 40e3))^(1/3) = 5.53 mm, A_g = 95.9 mm^2,
#                      A_fr = 48.0 mm^2, beta (3/16) a/R = 0.0115, hence
#                      tau0 = (0.5 - 0.1 - 0.0115) / 48.0e-6 = 8.1e3 Pa  ->  mu(1 N) = 0.500.
_DEFAULT = Finger(name="default", description="typical dry finger: R_fp 9 mm, E* 40 kPa, 50 % ridges")

#: Named fingers. Values not listed in a preset's comment are those of "default"; tau0, alpha and
#: beta are kept (interface properties), so mu on a smooth flat at 1 N differs by person:
#: default 0.50, soft 1.24 (wet-like, MODEL.md: > 1), stiff 0.29, stiffening 0.45, ridged 0.50.
FINGER_PRESETS: dict[str, Finger] = {
    "default": _DEFAULT,
    # soft, large pad: the soft/large ends of MODEL.md's ranges (E* 10 kPa, R_fp 11 mm).
    "soft": _DEFAULT.with_overrides(
        name="soft", radius=11e-3, modulus=10e3,
        description="soft, large pad: R_fp 11 mm, E* 10 kPa (ends of MODEL.md ranges)",
    ),
    # stiff, small pad: the stiff/small ends of MODEL.md's ranges (E* 100 kPa, R_fp 7 mm).
    "stiff": _DEFAULT.with_overrides(
        name="stiff", radius=7e-3, modulus=100e3,
        description="stiff, small pad: R_fp 7 mm, E* 100 kPa (ends of MODEL.md ranges)",
    ),
    # Dzidek stiffening (Eqs. 2.6-2.7), C = 5: the largest C for which the strain estimate
    # eps = 0.2 a/R_fp stays inside eps < 1/C whenever a < R_fp; phi = 0.23 /N.
    "stiffening": _DEFAULT.with_overrides(
        name="stiffening", gross=DzidekArea(9e-3, 40e3, 5.0),
        description="default pad with Dzidek secant-modulus stiffening, C = 5, eta = 3",
    ),
    # Sinusoidal ridges: lambda_r = 0.45 mm (MODEL.md 0.4-0.5 mm), E* = 100 kPa (thesis Fig. 2.4
    # input); amplitude 30 um is assumed, chosen so that A_fr/A_g runs from ~30 % at 0.1 N to
    # ~73 % at 4 N on this pad, i.e. inside MODEL.md's 10-70 % range over the exploration loads.
    "ridged": _DEFAULT.with_overrides(
        name="ridged", ridges=SinusoidalRidges(wavelength=0.45e-3, modulus=100e3, amplitude=30e-6),
        description="default pad with sinusoidal (Westergaard) fingerprint ridges, 0.45 mm, 30 um",
    ),
}


def get_finger(name: str) -> Finger:
    """Return the preset finger ``name`` (case-insensitive).

    Raises
    ------
    FingerpadError
        If there is no such preset; the message lists the presets.
    """
    key = str(name).strip().lower()
    if key not in FINGER_PRESETS:
        raise FingerpadError(f"unknown finger preset {name!r}; choose one of: {', '.join(FINGER_PRESETS)}")
    return FINGER_PRESETS[key]


# ---------------------------------------------------------------------------------------------
# figure: the ridge-area models side by side (idea of the thesis Fig. 2.4)
# ---------------------------------------------------------------------------------------------


def ridge_model_curves(
    loads: ArrayLike,
    *,
    skin_modulus: float = 100e3,
    radius: float = 9e-3,
    wavelength: float = 0.45e-3,
    amplitude: float = 30e-6,
    ridge_radius: float = 0.1e-3,
    fraction: float = 0.5,
    power_exponent: float = 0.45,
    bem_loads: ArrayLike | None = None,
) -> dict[str, np.ndarray]:
    """Gross and ridge areas (m^2) of every model on the same inputs, for a plot or a table.

    With ``bem_loads`` the BEM fingerprint model (:class:`fingerpad.fingerprint.FingerprintBEMRidges`,
    whorl ridges of the same wavelength and height, width 2/3 of the wavelength) is solved at
    those loads (a few seconds each) and returned as ``BEM load`` / ``BEM``.

    The power-law ridge model is anchored to the constant-fraction one at 1 N
    (``k = fraction * A_g(1 N)``) with the mid-range exponent ``power_exponent``.

    Returns
    -------
    dict
        ``load`` and one array per model: ``gross (Hertz)``, ``constant fraction``,
        ``power law``, ``sinusoidal``, ``circular``.
    """
    f = as_loads(loads, strict=True).ravel()
    hertz = HertzArea(radius, skin_modulus)
    ag = np.asarray(hertz.area(f))
    k = fraction * float(hertz.area(1.0))
    models: dict[str, RidgeAreaModel] = {
        "constant fraction": ConstantFractionRidges(fraction),
        "power law": PowerLawRidges(k, power_exponent),
        "sinusoidal": SinusoidalRidges(wavelength=wavelength, modulus=skin_modulus, amplitude=amplitude),
        "circular": CircularRidges(wavelength=wavelength, modulus=skin_modulus, ridge_radius=ridge_radius),
    }
    out = {"load": f, "gross (Hertz)": ag}
    for label, model in models.items():
        out[label] = np.asarray(model.area(f, ag))
    if bem_loads is not None:
        from .fingerprint import FingerprintBEMRidges

        fb = as_loads(bem_loads, strict=True).ravel()
        bem = FingerprintBEMRidges(
            pad_radius=radius, modulus=skin_modulus, wavelength=wavelength, width=2 * wavelength / 3,
            height=2 * amplitude, max_load=float(fb.max()),
        )
        out["BEM load"] = fb
        out["BEM"] = np.asarray(bem.area(fb))
    return out


def ridge_models_figure(
    path: str | os.PathLike[str],
    loads: ArrayLike | None = None,
    *,
    skin_modulus: float = 100e3,
    radius: float = 9e-3,
    wavelength: float = 0.45e-3,
    amplitude: float = 30e-6,
    ridge_radius: float = 0.1e-3,
    bem_loads: ArrayLike | None = None,
    dpi: int = 120,
) -> Path:
    """Plot gross area and the ridge-area models against load (idea of thesis Fig. 2.4).

    Left: gross area (Hertz, Eq. 2.5) and the ridge areas in mm^2; right: the ridge fractions
    A_fr/A_g. All models share the inputs (E_skin = 100 kPa by default). Written atomically as a
    PNG with matplotlib's Agg canvas (no global backend change).

    Parameters
    ----------
    path
        Output PNG path.
    loads
        Loads, N (default 30 log-spaced from 0.1 to 4 N, the exploration range).
    bem_loads
        Loads at which to add the BEM fingerprint model (markers; seconds per load).

    Returns
    -------
    Path
        The written file.
    """
    from matplotlib.figure import Figure

    from .io import atomic_write

    if loads is None:
        loads = np.geomspace(0.1, 4.0, 30)
    curves = ridge_model_curves(
        loads, skin_modulus=skin_modulus, radius=radius, wavelength=wavelength,
        amplitude=amplitude, ridge_radius=ridge_radius, bem_loads=bem_loads,
    )
    f = curves.pop("load")
    bem_f, bem_a = curves.pop("BEM load", None), curves.pop("BEM", None)
    order = np.argsort(f)
    ag = curves["gross (Hertz)"]
    fig = Figure(figsize=(10, 4.2), layout="constrained")
    ax_area, ax_frac = fig.subplots(1, 2)
    for label, area in curves.items():
        style = "k-" if label.startswith("gross") else "-"
        ax_area.plot(f[order], area[order] * 1e6, style, label=label)
        if not label.startswith("gross"):
            ax_frac.plot(f[order], (area / ag)[order] * 100, "-", label=label)
    if bem_f is not None:
        hertz_bem = HertzArea(radius, skin_modulus).area(bem_f)
        ax_area.plot(bem_f, bem_a * 1e6, "ko", mfc="none", label="BEM fingerprint")
        ax_frac.plot(bem_f, bem_a / hertz_bem * 100, "ko", mfc="none", label="BEM fingerprint")
    ax_area.set_xlabel("normal load F (N)")
    ax_area.set_ylabel("contact area (mm²)")
    ax_area.set_title("gross and ridge contact area")
    ax_frac.set_xlabel("normal load F (N)")
    ax_frac.set_ylabel("ridge area / gross area (%)")
    ax_frac.set_ylim(0, 105)
    ax_frac.set_title("ridge fraction")
    for ax in (ax_area, ax_frac):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
    fig.suptitle(
        f"Ridge-area models, same inputs: E_skin = {skin_modulus / 1e3:.3g} kPa, R_fp = {radius * 1e3:.3g} mm, "
        f"λ_r = {wavelength * 1e3:.3g} mm, h_r = {amplitude * 1e6:.3g} µm, R_r = {ridge_radius * 1e3:.3g} mm"
    )
    return atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi))


__all__ = [
    "FINGER_PRESETS",
    "CircularRidges",
    "ConstantFractionRidges",
    "DzidekArea",
    "Finger",
    "GrossAreaModel",
    "HertzArea",
    "PowerLawArea",
    "PowerLawRidges",
    "RidgeAreaModel",
    "SinusoidalRidges",
    "TwoRegimePowerLawArea",
    "disc_average",
    "get_finger",
    "pad_pressure",
    "ridge_model_curves",
    "ridge_models_figure",
]
