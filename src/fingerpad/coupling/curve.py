"""The coupling of the three scales: pad pressure x psi(p) -> real area, zones, critical loads.

* :func:`couple`: ``A_re = int psi(p(r)) dA`` over the ridge contact disc with the spherical
  pad pressure (Eq. 3.7 and Eq. 3.11), the contact zones and the state of the pad centre;
* :func:`critical_load`: the load at which the pad centre reaches the cell's transition pressure
  (Eq. 3.6 generalised to any unit cell);
* :func:`adhesion_integral`: the friction integrand ``tau(p) dA_re`` over the disc (Eq. 3.12);
* :func:`predict_curve`: areas and friction against load for a finger on a texture.

The unit cell is any :class:`~fingerpad.micro.response.UnitCellResponse` (BEM or Hertz).
SI units (m, N, Pa).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..cancel import check as check_cancelled
from ..checks import ArrayLike, as_areas, as_loads, scalar_out
from ..errors import FingerpadError
from ..finger import Finger
from ..friction import mu_checked
from ..macro.pressure import disc_average, pad_pressure
from ..micro.hertz import HertzUnitCell
from ..micro.response import (
    DEFAULT_LOAD_RANGE,
    RidgeArea,
    UnitCellResponse,
    area_function,
    check_cell,
    checked_psi,
    solve_load,
)
from .loads import FingerStack, centre_loads


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
    ridge contact disc under the spherical pad pressure (Eqs. 3.7, 3.11).

    With ``s = sqrt(1 - r^2/a_fr^2)``, ``p = 1.5 p_mean s`` and ``dA = 2 pi a_fr^2 s ds``:
    ``A_re = 2 pi a_fr^2 int_0^1 psi(1.5 p_mean s) s ds``. The integral is split where the
    pressure crosses the cell's transition, full-contact and extra ``breakpoints`` pressures and
    each piece is integrated with a Gauss-Legendre rule graded toward its ends
    (:func:`fingerpad.macro.pressure.disc_average`). Achieved accuracy: relative error below 1e-13 for
    psi analytic between breakpoints, including ``p^m`` behaviour at zero pressure (checked
    against the closed form ``2 pi a^2 c (1.5 p_mean)^m / (m + 2)`` in the tests). A BEM cell's
    interpolated curve is integrated exactly up to round-off through its antiderivative
    (:func:`disc_ratio`; checked against adaptive quadrature in the tests).

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
    f, ar = np.broadcast_arrays(as_loads(load, strict=True), as_areas(ridge_area))
    return _couple(f, ar, cell, n_rings)


def disc_ratio(cell: UnitCellResponse, peak: np.ndarray, breaks: tuple[float, ...] = (),
               n_rings: int = 16) -> np.ndarray:
    """``A_re / A_fr = 2 int_0^1 psi(peak s) s ds`` per centre pressure ``peak`` (Pa, 1-D), Eq. 3.11.

    A cell that interpolates a computed curve (:class:`~fingerpad.micro.bem.BEMUnitCell` and
    its scaled views) integrates its own piecewise interpolant exactly up to round-off
    (``cell.disc_fraction``: the antiderivative of ``psi(u) u`` at the curve's nodes). The
    graded disc quadrature split only at ``breaks`` missed the interpolant's kinks at its nodes
    and was off by up to a few 1e-3 relative on BEM cells; it stays for analytic cells (Hertz,
    power law), where it is accurate to 1e-13. Values checked as :func:`checked_psi` checks psi.
    """
    check_cancelled()  # once per curve or block of fingers: a population nobody waits for stops here
    method = getattr(cell, "disc_fraction", None)
    if method is None:
        return disc_average(checked_psi(cell), peak, breaks, n_nodes=int(n_rings))
    out = np.asarray(method(peak), dtype=float)
    if out.shape != np.shape(peak) or not np.all(np.isfinite(out)):
        raise FingerpadError(f"{type(cell).__name__}.disc_fraction returned a bad array")
    if np.any(out < -1e-9) or np.any(out > 1.0 + 1e-9):
        raise FingerpadError(f"{type(cell).__name__}.disc_fraction returned values outside [0, 1]")
    return np.clip(out, 0.0, 1.0)


def _couple(f: np.ndarray, ar: np.ndarray, cell: UnitCellResponse, n_rings: int) -> CouplingResult:
    """:func:`couple` on loads and ridge areas already checked and broadcast."""
    pt, pf, breaks = check_cell(cell)
    if int(n_rings) < 2:
        raise FingerpadError(f"n_rings must be at least 2, got {n_rings!r}")
    shape = f.shape
    f, ar = f.ravel().astype(float), ar.ravel().astype(float)
    p_mean = f / ar
    peak = 1.5 * p_mean
    a = np.sqrt(ar / math.pi)
    ratio = disc_ratio(cell, peak, breaks, int(n_rings))
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
    pt, _, _ = check_cell(cell)
    if not math.isfinite(pt):
        raise FingerpadError(f"{type(cell).__name__} has no finite transition pressure")
    area = area_function(ridge_area)

    def detail(lo: float, hi: float) -> str:
        return (f"the centre pressure 1.5 F/A_fr runs from {1.5 * lo / area(lo):.4g} Pa to "
                f"{1.5 * hi / area(hi):.4g} Pa, the transition is at {pt:.4g} Pa")

    return solve_load(lambda f: 1.5 * f / area(f) - pt, load_range, "critical load", detail)


def local_shear_strength(p: ArrayLike, cell: UnitCellResponse, tau0: float, alpha: float) -> np.ndarray:
    """Shear strength on the real contact at nominal pressure p: ``tau0 + alpha p / psi(p)``,
    Eq. 2.3 with the local real pressure ``p_re,local = p / psi`` (Pa; ``tau0`` where psi = 0)."""
    pp = np.asarray(p, dtype=float)
    psi = checked_psi(cell)(pp)
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
    _, _, breaks = check_cell(cell)
    f, ar = np.broadcast_arrays(as_loads(load, strict=True), as_areas(ridge_area))
    shape = f.shape
    f, ar = f.ravel().astype(float), ar.ravel().astype(float)
    psi = checked_psi(cell)

    def integrand(p: np.ndarray) -> np.ndarray:
        return local_shear_strength(p, cell, tau0, alpha) * psi(p)

    return scalar_out((ar * disc_average(integrand, 1.5 * f / ar, breaks, n_nodes=int(n_rings))).reshape(shape))


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
        Load (N) at which the centre reaches the cell's transition with the finger's ``A_fr(F)``
        (:func:`~fingerpad.coupling.loads.centre_loads`, the same root as :func:`critical_load`'s
        to 1e-12); NaN when there is none in :data:`DEFAULT_LOAD_RANGE`, inf for a cell that
        never reaches its transition.
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
    #: With an adhesive cell (:func:`predict_curve`): the pull-off force and the pad's work of
    #: adhesion, the real area without adhesion and the adhesive share of A_re per load, the
    #: threshold load; ``None`` without adhesion.
    adhesion: dict[str, Any] | None = None

    def as_dict(self) -> dict[str, Any]:
        """Fields as a plain dict."""
        return asdict(self)


def predict_curve(
    loads: ArrayLike, finger: Finger, cell: UnitCellResponse, reference: bool = True, n_rings: int = 16,
    plain: UnitCellResponse | None = None, *, critical_loads: bool = True,
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
    plain
        With an adhesive ``cell`` (:class:`~fingerpad.micro.adhesive_cell.AdhesiveUnitCell`):
        the same texture's non-adhesive cell, for the real area without adhesion, the adhesive
        share and the threshold load (:func:`_predict_adhesive`); ignored otherwise.
    critical_loads
        Find the critical loads (two root searches, some 20 % of a curve's time); ``False``
        leaves ``critical_load`` NaN and ``critical_load_hertz`` ``None`` (callers that read the
        friction alone, e.g. the E_s fits' model tables); the other fields are the same.
    """
    if not isinstance(finger, Finger):
        raise FingerpadError(f"finger must be a Finger, got {type(finger).__name__}")
    f = as_loads(loads, "loads", strict=True).ravel()
    if f.size == 0:
        raise FingerpadError("no loads given")
    if getattr(cell, "adhesive", False):
        return _predict_adhesive(f, finger, cell, reference, n_rings, plain)
    gross, ridge = finger.areas_checked(f)  # the loads are checked once, here
    if np.any(ridge <= 0):
        raise FingerpadError("the finger's ridge contact area must be positive at every load")
    res = _couple(f, ridge, cell, n_rings)
    mu = mu_checked(f, res.real_area, finger)
    mu_ref = mu_norm = None
    if reference:
        mu_ref = mu_checked(f, ridge, finger)  # on the flat the real area is the ridge area
        mu_norm = mu / mu_ref

    if not critical_loads:
        return CurvePrediction(
            load=f, gross_area=gross, ridge_area=ridge, real_area=res.real_area, area_ratio=res.area_ratio,
            real_pressure=res.real_pressure, ridge_radius=res.ridge_radius, transition_radius=res.transition_radius,
            full_contact_radius=res.full_contact_radius, centre_past_transition=res.centre_past_transition,
            mu=mu, mu_ref=mu_ref, mu_normalised=mu_norm, critical_load=math.nan, critical_load_hertz=None)
    # the package's one search of 1.5 F / A_fr(F) = p_t (a population's members take the same,
    # all at once: a member's critical load is the bits of its finger predicted alone); inf: the
    # cell never reaches its transition, NaN: no crossing in the (very wide) load range
    pt = float(check_cell(cell)[0])
    f_crit = float(centre_loads(FingerStack([finger]), [pt])[0]) if pt > 0 else math.nan
    f_hertz: float | None = None
    if isinstance(cell, HertzUnitCell):
        # Eq. 3.6's own solver; A_fr(F) built once for its ~25 calls
        ridge_law = finger.ridge_area_law()
        try:
            f_hertz = cell.critical_load(ridge_law)
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



def _predict_adhesive(f: np.ndarray, finger: Finger, cell: Any, reference: bool, n_rings: int,
                      plain: UnitCellResponse | None) -> CurvePrediction:
    """:func:`predict_curve` with an adhesive cell: the JKR pad of the finger's effective work of
    adhesion over the ridges, the cell's loading branch under its pressures (Eqs. 3.15-3.18,
    :mod:`fingerpad.micro.adhesive_pad`), the friction law on that real area; the flat reference
    is the same pad adhering with ``(A_fr / A_g) w`` (a flat's work of separation is ``w``)."""
    from ..macro.jkr import JKRArea
    from ..micro.adhesive_pad import adhesion_threshold, adhesive_pad, plain_real_area

    pad = adhesive_pad(finger, cell)
    gross, ridge = pad.areas(f)
    ratio = pad.area_ratio(f, ridge, n_rings)
    real = ratio * ridge
    with np.errstate(divide="ignore"):
        p_re = np.where(real > 0, f / np.where(real > 0, real, 1.0), np.inf)
    mu = mu_checked(f, real, finger)
    mu_ref = mu_norm = None
    if reference:
        flat = pad if pad.jkr is None else dataclasses.replace(
            pad, jkr=JKRArea(pad.jkr.radius, pad.jkr.modulus, pad.ridge_fraction * cell.work_of_adhesion))
        _, ridge_ref = flat.areas(f)
        mu_ref = mu_checked(f, ridge_ref, finger)  # on the flat the real area is the ridge area
        mu_norm = mu / mu_ref
    pt, pf = float(cell.transition_pressure), float(cell.full_contact_pressure)
    centre = pad.centre_pressure(f, ridge)

    def centre_at(load: float) -> float:
        arr = np.array([load])
        return float(pad.centre_pressure(arr, pad.areas(arr)[1])[0])

    f_crit = math.inf
    if math.isfinite(pt):
        f_crit = 0.0 if pt <= 0 else math.nan
        if pt > 0:
            try:
                f_crit = solve_load(lambda x: centre_at(x) - pt, DEFAULT_LOAD_RANGE, "critical load",
                                    lambda lo, hi: f"the centre pressure never reaches the transition at {pt:.4g} Pa")
            except FingerpadError:
                f_crit = math.nan
    info: dict[str, Any] = {**cell.describe(), **pad.describe(), "notes": list(pad.notes)}
    if plain is not None:
        without = plain_real_area(finger, plain, f, n_rings)
        info["real_area_without_adhesion"] = without
        info["adhesive_share"] = np.where(real > 0, 1.0 - without / np.where(real > 0, real, 1.0), 0.0)
        info["threshold_load"] = adhesion_threshold(pad, plain, n_rings)
    return CurvePrediction(
        load=f, gross_area=gross, ridge_area=ridge, real_area=real, area_ratio=ratio, real_pressure=p_re,
        ridge_radius=np.sqrt(ridge / math.pi), transition_radius=pad.zone_radius(f, ridge, pt),
        full_contact_radius=pad.zone_radius(f, ridge, pf), centre_past_transition=centre >= pt,
        mu=mu, mu_ref=mu_ref, mu_normalised=mu_norm, critical_load=f_crit, critical_load_hertz=None,
        adhesion=info,
    )


def model_references(finger: Finger, *cells: Any) -> tuple[str, ...]:
    """The publications of the model a prediction on ``finger`` with the unit cells ``cells``
    uses (:mod:`fingerpad.references` keys): the finger's pad and ridge models (Eq. 2.5's Hertz
    pad without one), the friction law, a layered skin's compliance, each cell's model (``None``
    skipped), an adhesive pad's JKR. The thesis and the package are always among them."""
    from ..macro.hertz import HertzArea
    from ..macro.jkr import JKRArea
    from ..references import keys_of

    adhesive = any(getattr(c, "adhesive", False) for c in cells)
    return keys_of(finger.gross if finger.gross is not None else HertzArea, finger.ridges, finger.friction,
                   "fingerpad-layered" if finger.layer is not None else None, JKRArea if adhesive else None, *cells)


__all__ = [
    "DEFAULT_LOAD_RANGE",
    "CouplingResult",
    "CurvePrediction",
    "UnitCellResponse",
    "adhesion_integral",
    "couple",
    "critical_load",
    "disc_ratio",
    "model_references",
    "local_shear_strength",
    "pad_pressure",
    "predict_curve",
]
