"""Micro scale and the coupling of the three scales (MODEL.md ch. 3.1-3.2 and [completion]).

* Per-asperity Hertz analysis (Eqs. 3.1-3.6) and the zone past the transition (3.8-3.10).
* :class:`UnitCellResponse`: what the coupling needs from a solved unit cell of the texture --
  the real-to-nominal area fraction ``psi(p)`` and the pressures of the transition and of full
  contact. :class:`HertzUnitCell` provides it analytically, :class:`PowerLawUnitCell` for tests;
  the numerical (BEM) unit cell implements the same protocol.
* :func:`couple`: ``A_re = int psi(p(r)) dA`` over the ridge contact disc with the spherical
  pad pressure (3.7), the contact zones and the state of the pad centre.
* :func:`critical_load` (any cell) and :func:`critical_load_hertz` (Eq. 3.6).
* :func:`adhesion_integral`: the friction integrand ``tau(p) dA_re`` integrated over the disc.
* :func:`predict_curve`: friction and areas against load for a finger on a texture.

SI units (m, N, Pa).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from scipy.optimize import brentq

from .errors import FingerpadError
from .finger import ArrayLike, Finger, _out, _positive, as_loads, disc_average, pad_pressure
from .friction import friction_coefficient, reference_friction_coefficient

#: Default load bracket (N) searched for critical loads: far beyond the 0.1-4 N of touch.
DEFAULT_LOAD_RANGE = (1e-6, 1e3)

RidgeArea = float | Callable[[float], float]

# ---------------------------------------------------------------------------------------------
# per-asperity Hertz analysis, Eqs. 3.1-3.6 and 3.8-3.10
# ---------------------------------------------------------------------------------------------


def _ridge_areas(ridge_area: ArrayLike) -> np.ndarray:
    arr = as_loads(ridge_area, "ridge area")
    if np.any(arr <= 0):
        raise FingerpadError("ridge area must be positive")
    return arr


def asperity_count(ridge_area: ArrayLike, spacing: float) -> float | np.ndarray:
    """Asperities in contact on a square lattice, ``N = A_fr / lambda^2``, Eq. 3.1."""
    lam = _positive(spacing, "asperity spacing")
    return _out(_ridge_areas(ridge_area) / lam**2)


def asperity_force(load: ArrayLike, ridge_area: ArrayLike, spacing: float) -> float | np.ndarray:
    """Mean force per asperity ``F_i = F lambda^2 / A_fr = p_mean lambda^2``, Eq. 3.2 (N)."""
    lam = _positive(spacing, "asperity spacing")
    return _out(as_loads(load) * lam**2 / _ridge_areas(ridge_area))


def centre_asperity_force(load: ArrayLike, ridge_area: ArrayLike, spacing: float) -> float | np.ndarray:
    """Force on the asperity at the pad centre, ``1.5 F lambda^2 / A_fr``, Eq. 3.5 (N)."""
    return _out(1.5 * np.asarray(asperity_force(load, ridge_area, spacing)))


def hertz_contact_radius(force: ArrayLike, radius: float, reduced_modulus: float) -> float | np.ndarray:
    """Hertz contact radius of one spherical asperity, ``a = (3 F R / (4 E1*))^(1/3)`` (m)."""
    r = _positive(radius, "asperity radius")
    e = _positive(reduced_modulus, "reduced modulus E1*")
    return _out(np.cbrt(3.0 * as_loads(force, "force") * r / (4.0 * e)))


def hertz_approach(force: ArrayLike, radius: float, reduced_modulus: float) -> float | np.ndarray:
    """Hertz approach (combined displacement) ``delta = (9 F^2 / (16 E1*^2 R))^(1/3)``, Eq. 3.3 (m)."""
    r = _positive(radius, "asperity radius")
    e = _positive(reduced_modulus, "reduced modulus E1*")
    f = as_loads(force, "force")
    return _out(np.cbrt(9.0 * f**2 / (16.0 * e**2 * r)))


def critical_asperity_force(height: float, radius: float, reduced_modulus: float) -> float:
    """Asperity force at which the Hertz approach equals the height, Eq. 3.3 solved for F:
    ``F_icrit = (4/3) E1* sqrt(R h^3)`` (N)."""
    h = _positive(height, "asperity height")
    r = _positive(radius, "asperity radius")
    e = _positive(reduced_modulus, "reduced modulus E1*")
    return 4.0 / 3.0 * e * math.sqrt(r * h**3)


def transition_area_fraction(
    load: ArrayLike, ridge_area: ArrayLike, spacing: float, critical_force: float
) -> float | np.ndarray:
    """Fraction of the ridge contact past the transition, Eqs. 3.8-3.9.

    ``A_trans / A_fr = 1 - ((2/3) F_icrit / F_i)^2`` with ``F_i = F lambda^2 / A_fr``, clipped
    at 0 (no zone while the centre asperity carries less than ``F_icrit``).
    """
    fc = _positive(critical_force, "critical asperity force")
    fi = np.asarray(asperity_force(load, ridge_area, spacing))
    with np.errstate(divide="ignore"):
        frac = 1.0 - (2.0 / 3.0 * fc / fi) ** 2
    return _out(np.clip(frac, 0.0, 1.0))


def transition_radius(
    load: ArrayLike, ridge_area: ArrayLike, spacing: float, critical_force: float
) -> float | np.ndarray:
    """Radius of the zone past the transition ``a_trans = a_fr (A_trans/A_fr)^(1/2)``, Eq. 3.10 (m)."""
    a_fr = np.sqrt(_ridge_areas(ridge_area) / math.pi)
    frac = np.asarray(transition_area_fraction(load, ridge_area, spacing, critical_force))
    return _out(a_fr * np.sqrt(frac))


def _area_function(ridge_area: RidgeArea) -> Callable[[float], float]:
    """Turn a constant or a callable ``A_fr(F)`` into a checked scalar callable."""
    if callable(ridge_area):
        def area(f: float) -> float:
            value = float(np.asarray(ridge_area(f)))  # type: ignore[operator]
            if not (math.isfinite(value) and value > 0):
                raise FingerpadError(f"ridge area A_fr({f:.4g} N) = {value!r} is not a positive area")
            return value

        return area
    const = _positive(ridge_area, "ridge area")
    return lambda f: const


def _solve_load(
    residual: Callable[[float], float],
    load_range: tuple[float, float],
    what: str,
    detail: Callable[[float, float], str],
) -> float:
    """Root of ``residual`` in ``load_range`` by Brent's method, or a FingerpadError."""
    lo, hi = (float(x) for x in load_range)
    if not (0 < lo < hi and math.isfinite(hi)):
        raise FingerpadError(f"load range must satisfy 0 < low < high, got {load_range!r}")
    g_lo, g_hi = residual(lo), residual(hi)
    if g_lo == 0:
        return lo
    if g_hi == 0:
        return hi
    if np.sign(g_lo) == np.sign(g_hi):
        raise FingerpadError(f"no {what} between {lo:.3g} N and {hi:.3g} N: {detail(lo, hi)}")
    # Relative tolerance at the float limit: tests compare with Eq. 3.6 to ~1e-12.
    return float(brentq(residual, lo, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500))


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
    lam = _positive(spacing, "asperity spacing")
    # (2/3) F_icrit / lambda^2 = (8/9) E1* sqrt(h^3 R) / lambda^2
    factor = 2.0 / 3.0 * critical_asperity_force(height, radius, reduced_modulus) / lam**2
    if not callable(ridge_area):
        return factor * _positive(ridge_area, "ridge area")
    area = _area_function(ridge_area)

    def detail(lo: float, hi: float) -> str:
        return (f"(8/9) E1* sqrt(h^3 R) A_fr/lambda^2 is {factor * area(lo):.3g} N at the low end and "
                f"{factor * area(hi):.3g} N at the high end")

    return _solve_load(lambda f: f - factor * area(f), load_range, "critical load (Eq. 3.6)", detail)


# ---------------------------------------------------------------------------------------------
# the unit-cell interface
# ---------------------------------------------------------------------------------------------


@runtime_checkable
class UnitCellResponse(Protocol):
    """Response of one periodic texture unit cell to a nominal mean pressure.

    Attributes
    ----------
    transition_pressure
        Local nominal mean pressure (Pa) at which the skin first touches the texture's base.
    full_contact_pressure
        Pressure (Pa) from which the skin follows the whole texture (``psi`` constant); may be
        ``inf``.

    Both may be plain attributes or read-only properties.

    Notes
    -----
    An implementation may also define ``breakpoints``: a sequence of further pressures where
    ``psi`` has kinks; :func:`couple` splits its quadrature there for accuracy.
    """

    @property
    def transition_pressure(self) -> float: ...

    @property
    def full_contact_pressure(self) -> float: ...

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        """psi(p): real-to-nominal area fraction of the cell at nominal mean pressure ``p`` (Pa)."""
        ...


@dataclass(frozen=True)
class HertzUnitCell:
    """Square lattice of spherical caps, each in Hertz contact with the skin (Eqs. 3.1-3.3).

    ``F_i = p lambda^2``, ``a = (3 F_i R / (4 E1*))^(1/3)``, ``psi = min(1, pi a^2 / lambda^2)``.
    The transition is where the Hertz approach reaches the cap height (Eq. 3.3):
    ``p_t = (4/3) E1* sqrt(R h^3) / lambda^2``. Hertz ignores the neighbours and cannot follow the
    skin onto the base, so past ``p_t`` psi is the asperity-only extrapolation and
    ``full_contact_pressure`` is ``inf`` (MODEL.md ch. 3.1).

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

    radius: float
    height: float
    spacing: float
    reduced_modulus: float

    def __post_init__(self) -> None:
        r = _positive(self.radius, "asperity radius")
        h = _positive(self.height, "asperity height")
        _positive(self.spacing, "asperity spacing")
        _positive(self.reduced_modulus, "reduced modulus E1*")
        if h > r:
            raise FingerpadError(f"a spherical cap cannot be higher ({h:.3g} m) than its radius ({r:.3g} m)")

    @classmethod
    def for_finger(
        cls,
        finger: Finger,
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


@dataclass(frozen=True)
class PowerLawUnitCell:
    """Test cell ``psi = min(1, c p^m)``.

    Full contact at ``p_full = c^(-1/m)``; the transition at ``transition`` (Pa, default
    ``p_full``).

    Attributes
    ----------
    coefficient
        c, Pa^-m.
    exponent
        m.
    transition
        Transition pressure, Pa, or ``None`` for ``p_full``.
    """

    coefficient: float
    exponent: float
    transition: float | None = None

    def __post_init__(self) -> None:
        _positive(self.coefficient, "coefficient c")
        _positive(self.exponent, "exponent m")
        if self.transition is not None:
            t = _positive(self.transition, "transition pressure")
            if t > self.full_contact_pressure:
                raise FingerpadError("transition pressure must not exceed the full-contact pressure")

    @property
    def full_contact_pressure(self) -> float:
        """``c^(-1/m)``, where psi reaches 1, Pa."""
        return self.coefficient ** (-1.0 / self.exponent)

    @property
    def transition_pressure(self) -> float:
        return self.full_contact_pressure if self.transition is None else float(self.transition)

    def contact_fraction(self, p: np.ndarray) -> np.ndarray:
        pp = np.clip(np.asarray(p, dtype=float), 0.0, None)
        return np.minimum(self.coefficient * pp**self.exponent, 1.0)


def _check_cell(cell: Any) -> tuple[float, float, tuple[float, ...]]:
    if not isinstance(cell, UnitCellResponse):
        raise FingerpadError(
            f"{type(cell).__name__} is not a unit-cell response (needs contact_fraction, "
            "transition_pressure, full_contact_pressure)"
        )
    pt, pf = float(cell.transition_pressure), float(cell.full_contact_pressure)
    # 0 is allowed: a flat cell (BEMUnitCell on a flat texture) is in full contact at any pressure.
    if not (pt >= 0 and pf >= 0) or math.isnan(pt) or math.isnan(pf):
        raise FingerpadError(f"unit cell pressures must not be negative (transition {pt!r}, full {pf!r})")
    if pf < pt:
        raise FingerpadError(f"unit cell full-contact pressure {pf:.4g} Pa is below its transition {pt:.4g} Pa")
    extra = tuple(float(b) for b in getattr(cell, "breakpoints", ()) or ())
    return pt, pf, (pt, pf, *extra)


def _checked_psi(cell: UnitCellResponse) -> Callable[[np.ndarray], np.ndarray]:
    def psi(p: np.ndarray) -> np.ndarray:
        out = np.asarray(cell.contact_fraction(p), dtype=float)
        if out.shape != np.shape(p) or not np.all(np.isfinite(out)):
            raise FingerpadError(f"{type(cell).__name__}.contact_fraction returned a bad array")
        if np.any(out < -1e-9) or np.any(out > 1.0 + 1e-9):
            raise FingerpadError(f"{type(cell).__name__}.contact_fraction returned values outside [0, 1]")
        return np.clip(out, 0.0, 1.0)

    return psi


# ---------------------------------------------------------------------------------------------
# coupling
# ---------------------------------------------------------------------------------------------


def _zone_radius(a: np.ndarray, peak: np.ndarray, p_zone: float) -> np.ndarray:
    """Radius inside which p(r) = peak sqrt(1 - r^2/a^2) exceeds ``p_zone`` (0 if nowhere)."""
    if not math.isfinite(p_zone):
        return np.zeros_like(a)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(peak > 0, p_zone / peak, np.inf)
    return a * np.sqrt(np.clip(1.0 - ratio**2, 0.0, None))


@dataclass(frozen=True)
class CouplingResult:
    """Real contact of the finger pad on a texture, per load (arrays of one shape).

    Zones on the ridge disc: asperity contact for ``transition_radius < r < ridge_radius``,
    transition for ``full_contact_radius < r < transition_radius``, full contact inside
    ``full_contact_radius``.

    Attributes
    ----------
    load
        F, N.
    ridge_area, ridge_radius
        A_fr (m^2) and ``a_fr = sqrt(A_fr/pi)`` (m).
    mean_pressure, peak_pressure
        ``F/A_fr`` and the centre pressure ``1.5 F/A_fr`` (Pa), Eq. 3.7.
    real_area
        ``A_re = int psi(p(r)) dA`` (m^2).
    area_ratio
        ``A_re / A_fr``.
    real_pressure
        Mean real contact pressure ``p_re = F / A_re`` (Pa), Eq. 2.3.
    transition_radius, full_contact_radius
        Zone radii (m); 0 where the zone is absent.
    centre_past_transition, centre_in_full_contact
        Whether the centre pressure reaches the transition / full-contact pressure.
    """

    load: np.ndarray
    ridge_area: np.ndarray
    ridge_radius: np.ndarray
    mean_pressure: np.ndarray
    peak_pressure: np.ndarray
    real_area: np.ndarray
    area_ratio: np.ndarray
    real_pressure: np.ndarray
    transition_radius: np.ndarray
    full_contact_radius: np.ndarray
    centre_past_transition: np.ndarray
    centre_in_full_contact: np.ndarray


def couple(
    load: ArrayLike, ridge_area: ArrayLike, cell: UnitCellResponse, n_rings: int = 16
) -> CouplingResult:
    """Real contact area of the pad on a texture: the unit-cell response integrated over the
    ridge contact disc under the spherical pad pressure (Eq. 3.7, MODEL.md [completion]).

    With ``s = sqrt(1 - r^2/a_fr^2)``, ``p = 1.5 p_mean s`` and ``dA = 2 pi a_fr^2 s ds``:
    ``A_re = 2 pi a_fr^2 int_0^1 psi(1.5 p_mean s) s ds``. The integral is split where the
    pressure crosses the cell's transition, full-contact and extra ``breakpoints`` pressures and
    each piece is integrated with a Gauss-Legendre rule graded toward its ends
    (:func:`fingerpad.finger.disc_average`). Achieved accuracy: relative error below 1e-13 for
    psi analytic between breakpoints, including ``p^m`` behaviour at zero pressure (checked
    against the closed form ``2 pi a^2 c (1.5 p_mean)^m / (m + 2)`` in the tests).

    Parameters
    ----------
    load
        Normal load(s) F, N, positive.
    ridge_area
        Ridge contact area(s) A_fr, m^2 (broadcast against ``load``).
    cell
        The unit-cell response (:class:`UnitCellResponse`).
    n_rings
        Gauss-Legendre nodes (rings of the disc) per graded sub-interval; each piece between
        breakpoints has ``25 * n_rings`` rings.

    Returns
    -------
    CouplingResult
    """
    pt, pf, breaks = _check_cell(cell)
    if int(n_rings) < 2:
        raise FingerpadError(f"n_rings must be at least 2, got {n_rings!r}")
    f, ar = np.broadcast_arrays(as_loads(load, strict=True), _ridge_areas(ridge_area))
    shape = f.shape
    f, ar = f.ravel().astype(float), ar.ravel().astype(float)
    p_mean = f / ar
    peak = 1.5 * p_mean
    a = np.sqrt(ar / math.pi)
    ratio = disc_average(_checked_psi(cell), peak, breaks, n_nodes=int(n_rings))
    real = ratio * ar
    with np.errstate(divide="ignore"):
        p_re = np.where(real > 0, f / np.where(real > 0, real, 1.0), np.inf)

    def shaped(x: np.ndarray) -> np.ndarray:
        return x.reshape(shape)

    return CouplingResult(
        load=shaped(f),
        ridge_area=shaped(ar),
        ridge_radius=shaped(a),
        mean_pressure=shaped(p_mean),
        peak_pressure=shaped(peak),
        real_area=shaped(real),
        area_ratio=shaped(ratio),
        real_pressure=shaped(p_re),
        transition_radius=shaped(_zone_radius(a, peak, pt)),
        full_contact_radius=shaped(_zone_radius(a, peak, pf)),
        centre_past_transition=shaped(peak >= pt),
        centre_in_full_contact=shaped(peak >= pf),
    )


def critical_load(
    cell: UnitCellResponse, ridge_area: RidgeArea, load_range: tuple[float, float] = DEFAULT_LOAD_RANGE
) -> float:
    """Load at which the pad-centre pressure ``1.5 F / A_fr(F)`` reaches the cell's transition.

    Generalises Eq. 3.6 to any unit cell (for :class:`HertzUnitCell` it is Eq. 3.6). Solved with
    Brent's method in ``load_range``; ``ridge_area`` is a constant (m^2) or a callable ``A_fr(F)``.
    The centre pressure must cross the transition once in the range (it rises with load when
    ``A_fr`` grows slower than ``F``).

    Raises
    ------
    FingerpadError
        If the cell has no finite transition pressure or no crossing lies in ``load_range``.
    """
    pt, _, _ = _check_cell(cell)
    if not math.isfinite(pt):
        raise FingerpadError(f"{type(cell).__name__} has no finite transition pressure")
    area = _area_function(ridge_area)

    def detail(lo: float, hi: float) -> str:
        return (f"the centre pressure 1.5 F/A_fr runs from {1.5 * lo / area(lo):.4g} Pa to "
                f"{1.5 * hi / area(hi):.4g} Pa, the transition is at {pt:.4g} Pa")

    return _solve_load(lambda f: 1.5 * f / area(f) - pt, load_range, "critical load", detail)


def local_shear_strength(p: ArrayLike, cell: UnitCellResponse, tau0: float, alpha: float) -> np.ndarray:
    """Shear strength on the real contact at nominal pressure p: ``tau0 + alpha p / psi(p)``,
    Eq. 2.3 with the local real pressure ``p_re,local = p / psi`` (Pa; ``tau0`` where psi = 0)."""
    pp = np.asarray(p, dtype=float)
    psi = _checked_psi(cell)(pp)
    with np.errstate(divide="ignore", invalid="ignore"):
        p_local = np.where(psi > 0, pp / np.where(psi > 0, psi, 1.0), 0.0)
    return tau0 + alpha * p_local


def adhesion_integral(
    load: ArrayLike,
    ridge_area: ArrayLike,
    cell: UnitCellResponse,
    tau0: float,
    alpha: float,
    n_rings: int = 16,
) -> float | np.ndarray:
    """Adhesive friction integrated over the ridge disc, ``F_adh = int tau(p) dA_re`` (N).

    ``dA_re = psi(p) dA`` and ``tau = tau0 + alpha p / psi`` (:func:`local_shear_strength`), so
    the integrand is ``tau0 psi + alpha p``; it integrates to ``tau0 A_re + alpha F``, the
    global Eqs. 2.2-2.3, which the tests check. Same quadrature as :func:`couple`.
    """
    _, _, breaks = _check_cell(cell)
    f, ar = np.broadcast_arrays(as_loads(load, strict=True), _ridge_areas(ridge_area))
    shape = f.shape
    f, ar = f.ravel().astype(float), ar.ravel().astype(float)
    psi = _checked_psi(cell)

    def integrand(p: np.ndarray) -> np.ndarray:
        return local_shear_strength(p, cell, tau0, alpha) * psi(p)

    return _out((ar * disc_average(integrand, 1.5 * f / ar, breaks, n_nodes=int(n_rings))).reshape(shape))


# ---------------------------------------------------------------------------------------------
# friction-load curve
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CurvePrediction:
    """Areas, contact zones and friction of a finger on a texture against load (1-D arrays).

    Attributes
    ----------
    load, gross_area, ridge_area, real_area
        N, m^2.
    area_ratio
        ``A_re / A_fr``.
    real_pressure
        ``F / A_re``, Pa.
    ridge_radius, transition_radius, full_contact_radius
        Outer radii (m) of the asperity, transition and full-contact zones (see
        :class:`CouplingResult`).
    centre_past_transition
        Whether the pad centre is past the transition.
    mu
        Friction coefficient on the texture, Eq. 2.1.
    mu_ref, mu_normalised
        On the flat reference (``A_re = A_fr``) and ``mu / mu_ref``; ``None`` without a reference.
    critical_load
        Load (N) at which the centre reaches the cell's transition (:func:`critical_load`) with
        the finger's ``A_fr(F)``; NaN when there is none in :data:`DEFAULT_LOAD_RANGE`.
    critical_load_hertz
        Eq. 3.6 solved with ``A_fr(F)`` when the cell is a :class:`HertzUnitCell`, else ``None``
        (NaN when no solution lies in the range).
    """

    load: np.ndarray
    gross_area: np.ndarray
    ridge_area: np.ndarray
    real_area: np.ndarray
    area_ratio: np.ndarray
    real_pressure: np.ndarray
    ridge_radius: np.ndarray
    transition_radius: np.ndarray
    full_contact_radius: np.ndarray
    centre_past_transition: np.ndarray
    mu: np.ndarray
    mu_ref: np.ndarray | None
    mu_normalised: np.ndarray | None
    critical_load: float
    critical_load_hertz: float | None

    def as_dict(self) -> dict[str, Any]:
        """Fields as a plain dict."""
        return asdict(self)


def predict_curve(
    loads: ArrayLike, finger: Finger, cell: UnitCellResponse, reference: bool = True, n_rings: int = 16
) -> CurvePrediction:
    """Predict areas and friction of ``finger`` on the texture described by ``cell``.

    Chain: gross area (finger's model, Eqs. 2.5-2.7) -> ridge area (ch. 2.2.2) -> real area by
    :func:`couple` (Eq. 3.7 + psi) -> friction (Eqs. 2.1-2.4). With ``reference`` the flat
    reference of the same material (``A_re = A_fr``) and ``mu / mu_ref`` are added.

    Parameters
    ----------
    loads
        Normal loads, N (positive; flattened to 1-D).
    finger
        The person's parameters (:class:`fingerpad.finger.Finger`).
    cell
        Unit-cell response of the texture; its E1* should come from ``finger.micro_modulus``.
    reference
        Also compute the flat-reference friction and the normalised friction.
    n_rings
        Quadrature density, see :func:`couple`.
    """
    if not isinstance(finger, Finger):
        raise FingerpadError(f"finger must be a Finger, got {type(finger).__name__}")
    f = as_loads(loads, "loads", strict=True).ravel()
    if f.size == 0:
        raise FingerpadError("no loads given")
    gross = np.asarray(finger.gross_area(f), dtype=float)
    ridge = np.asarray(finger.ridge_area(f), dtype=float)
    res = couple(f, ridge, cell, n_rings=n_rings)
    mu = np.asarray(friction_coefficient(f, res.real_area, finger), dtype=float)
    mu_ref = mu_norm = None
    if reference:
        mu_ref = np.asarray(reference_friction_coefficient(f, finger), dtype=float)
        mu_norm = mu / mu_ref

    try:
        f_crit = critical_load(cell, finger.ridge_area)
    except FingerpadError:  # no crossing in range (or no transition): report as NaN
        f_crit = math.nan
    f_hertz: float | None = None
    if isinstance(cell, HertzUnitCell):
        try:
            f_hertz = cell.critical_load(finger.ridge_area)
        except FingerpadError:
            f_hertz = math.nan

    return CurvePrediction(
        load=f,
        gross_area=gross,
        ridge_area=ridge,
        real_area=res.real_area,
        area_ratio=res.area_ratio,
        real_pressure=res.real_pressure,
        ridge_radius=res.ridge_radius,
        transition_radius=res.transition_radius,
        full_contact_radius=res.full_contact_radius,
        centre_past_transition=res.centre_past_transition,
        mu=mu,
        mu_ref=mu_ref,
        mu_normalised=mu_norm,
        critical_load=f_crit,
        critical_load_hertz=f_hertz,
    )


__all__ = [
    "DEFAULT_LOAD_RANGE",
    "CouplingResult",
    "CurvePrediction",
    "HertzUnitCell",
    "PowerLawUnitCell",
    "UnitCellResponse",
    "adhesion_integral",
    "asperity_count",
    "asperity_force",
    "centre_asperity_force",
    "couple",
    "critical_asperity_force",
    "critical_load",
    "critical_load_hertz",
    "hertz_approach",
    "hertz_contact_radius",
    "local_shear_strength",
    "pad_pressure",
    "predict_curve",
    "transition_area_fraction",
    "transition_radius",
]
