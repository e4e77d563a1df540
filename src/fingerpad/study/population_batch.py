"""Every member of a population on one texture at once: the per-point population work of a sweep.

:func:`evaluate_members` takes a nominal :class:`~fingerpad.study.run.Prediction` (its unit cell
prepared) and the members' fingers, and returns each member's A_re/A_fr, mu, mu_ref,
mu/mu_ref at every load, its critical and full-contact loads and its pad-centre states: the
numbers :func:`~fingerpad.study.population.run_population` gives member by member, computed
across the members together:

* one cell for all. psi(p) at reduced modulus E* is the nominal cell's psi at ``p / k`` with
  ``k = E*_member / E*_nominal`` (docs/solver.md, "One curve for every modulus and every
  scale"), and its state pressures and kinks are ``k`` times the nominal cell's; this is
  :meth:`BEMUnitCell.at_modulus <fingerpad.micro.bem.BEMUnitCell.at_modulus>`, here for
  every member in one array;
* one quadrature for all: Eq. 3.11 (``A_re/A_fr = 2 int_0^1 psi(1.5 p_mean s) s ds``) with each
  member's own breakpoints, the rule of :func:`fingerpad.macro.pressure.disc_average`, over a
  ``(members x loads, nodes)`` array (in blocks, to bound memory);
* one root search for all: the loads at which the centre pressure ``1.5 F / A_fr(F)`` reaches a
  member's transition and full-contact pressures (Eq. 3.6 generalised), by tabulating each
  member's ``A_fr`` once on a log grid of loads, then Illinois (regula falsi) steps in
  ``log F`` for every member together: about ten calls of ``A_fr`` per member instead of about
  sixty scalar calls of Brent's method. Agreement with Brent: ~1e-13 relative.

A member whose finger and modulus are the study's own is the nominal prediction itself: its
numbers are the nominal's (bit for bit), so a population without spread gives exactly the
single-finger prediction. Identical members are computed once.

SI units (m, N, Pa).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..finger import Finger
from ..friction import mu_checked
from ..macro.pressure import _graded_rule
from ..micro.response import DEFAULT_LOAD_RANGE, check_cell, checked_psi

__all__ = ["STATES", "MemberValues", "evaluate_members", "member_quantiles", "population_fingers"]

#: Contact states at the pad centre, in the order of their codes (0, 1, 2).
STATES: tuple[str, ...] = ("asperity", "transition", "full")
#: Load grid (per decade) on which each member's ridge area is tabulated to bracket its roots.
_TABLE_PER_DECADE = 4
#: Bracket width in log F at which a root counts as found (relative error of F about 1e-13).
_ROOT_TOL = 1e-13


@dataclass
class MemberValues:
    """Each member's numbers on one texture (arrays, members first; SI units).

    Attributes
    ----------
    area_ratio, mu, mu_ref, mu_normalised
        ``(members, loads)``: A_re/A_fr, mu (Eq. 2.1), mu on the flat reference, mu/mu_ref.
    critical_load, full_contact_load
        ``(members,)``, N: the load at which the pad centre reaches the member's transition and
        full contact (``inf`` never; NaN none in :data:`~fingerpad.micro.response.DEFAULT_LOAD_RANGE`; full contact NaN
        with the Hertz cell, 0 on a flat texture).
    states
        ``(members, loads)`` int8 codes of :data:`STATES` at the pad centre.
    """

    area_ratio: np.ndarray
    mu: np.ndarray
    mu_ref: np.ndarray
    mu_normalised: np.ndarray
    critical_load: np.ndarray
    full_contact_load: np.ndarray
    states: np.ndarray


def evaluate_members(nominal: Any, fingers: Sequence[Finger], moduli: Sequence[float]) -> MemberValues:
    """The members' numbers on the nominal prediction's texture (see the module docstring).

    Parameters
    ----------
    nominal
        The study's :class:`~fingerpad.study.run.Prediction`; its primary cell (BEM if it ran,
        else Hertz) is read at each member's modulus. A BEM cell must already be prepared over
        the members' pressures (``cell.prepare``, as :func:`~fingerpad.study.population.run_population` does).
    fingers
        The members' fingers.
    moduli
        Their reduced moduli E1* (Pa), Eq. 3.4.

    Returns
    -------
    MemberValues
    """
    loads = np.asarray(nominal.study.loads, float)
    bem = nominal.bem is not None
    cell = nominal.cell if bem else nominal.hertz_cell
    curve = nominal.bem if bem else nominal.hertz
    e0 = float(cell.modulus if bem else cell.reduced_modulus)
    flat = bool(bem and cell.flat)
    m, nl = len(fingers), loads.size
    out = MemberValues(*(np.full((m, nl), np.nan) for _ in range(4)), np.full(m, np.nan), np.full(m, np.nan),
                       np.zeros((m, nl), np.int8))
    # identical members once; the study's own finger at the study's modulus is the nominal itself
    groups: dict[Any, list[int]] = {}
    for i, (f, e) in enumerate(zip(fingers, moduli, strict=True)):
        groups.setdefault(_key(f, float(e), i), []).append(i)
    nominal_key = _key(nominal.study.finger, e0, -1)
    todo = [key for key in groups if key != nominal_key]
    pt0, pf0, breaks0 = check_cell(cell)
    if nominal_key in groups:
        rows = groups[nominal_key]
        out.area_ratio[rows] = curve.area_ratio
        out.mu[rows] = curve.mu
        out.mu_ref[rows] = curve.mu_ref
        out.mu_normalised[rows] = curve.mu_normalised
        crit = nominal.critical_load.get("bem" if bem else "hertz")
        out.critical_load[rows] = math.nan if crit is None else crit
        full = nominal.full_contact_load.get("bem") if bem else None
        out.full_contact_load[rows] = math.nan if full is None else full
        peak = 1.5 * loads / curve.ridge_area
        out.states[rows] = _state_codes(peak[None, :], np.array([pt0]), np.array([pf0]))
    if bem and not flat and hasattr(cell, "for_skin"):
        # a member whose skin is not this cell's at another modulus (a layered skin with a
        # thickness or modulus ratio of its own) is a cell of its own: member by member, as
        # run_population does
        own = {}
        for key in todo:
            i = groups[key][0]
            mcell = _member_cell(cell, fingers[i], moduli[i], loads)
            if mcell is not None:
                own[key] = mcell
        for key, mcell in own.items():
            _one_member(out, groups[key], fingers[groups[key][0]], mcell, loads)
        todo = [key for key in todo if key not in own]
    if not todo:
        return out
    fs = [fingers[groups[key][0]] for key in todo]
    k = np.array([float(moduli[groups[key][0]]) for key in todo]) / e0  # E*_member / E*_nominal
    areas = [f.areas_checked(loads) for f in fs]
    ridge = np.array([a[1] for a in areas], float)
    peak = 1.5 * loads[None, :] / ridge
    ratio = _area_ratio_scaled(cell, checked_psi(cell), peak, k, breaks0)
    real = ratio * ridge
    mu = np.array([mu_checked(loads, real[j], f) for j, f in enumerate(fs)])
    mu_ref = np.array([mu_checked(loads, ridge[j], f) for j, f in enumerate(fs)])
    pt, pf = pt0 * k, pf0 * k
    if flat:
        crit, full = np.full(k.size, np.nan), np.zeros(k.size)
    else:
        roots = _centre_pressure_loads(fs, np.stack([pt, pf], axis=1))
        crit, full = roots[:, 0], (roots[:, 1] if bem else np.full(k.size, np.nan))
    states = _state_codes(peak, pt, pf)
    for j, key in enumerate(todo):
        rows = groups[key]
        out.area_ratio[rows], out.mu[rows], out.mu_ref[rows] = ratio[j], mu[j], mu_ref[j]
        out.mu_normalised[rows] = mu[j] / mu_ref[j]
        out.critical_load[rows], out.full_contact_load[rows] = crit[j], full[j]
        out.states[rows] = states[j]
    return out


def _member_cell(cell: Any, finger: Finger, modulus: float, loads: np.ndarray) -> Any:
    """The member's own cell when its skin is not the nominal cell's read at another modulus
    (``cell.for_skin``, a layered skin of other proportions), else ``None``."""
    from .run import P_HIGH, P_LOW

    layer = getattr(finger, "layer", None)
    if layer is None and getattr(cell, "layer", None) is None:
        return None
    p = loads / np.asarray(finger.ridge_area(loads), float)
    mcell = cell.for_skin(modulus, layer, (P_LOW * float(p.min()), P_HIGH * float(p.max())))
    return None if getattr(mcell, "base", None) is cell else mcell


def _one_member(out: MemberValues, rows: list[int], finger: Finger, mcell: Any, loads: np.ndarray) -> None:
    """One member on a cell of its own, as :func:`~fingerpad.study.population.run_population`
    computes it (BEM): its curve, critical and full-contact loads and centre states."""
    from ..coupling import predict_curve
    from .run import load_at_centre_pressure

    curve = predict_curve(loads, finger, mcell)
    out.area_ratio[rows], out.mu[rows], out.mu_ref[rows] = curve.area_ratio, curve.mu, curve.mu_ref
    out.mu_normalised[rows] = curve.mu_normalised
    out.critical_load[rows] = curve.critical_load
    out.full_contact_load[rows] = load_at_centre_pressure(finger, mcell.full_contact_pressure)
    peak = 1.5 * curve.load / curve.ridge_area
    out.states[rows] = _state_codes(peak[None, :], np.array([float(mcell.transition_pressure)]),
                                    np.array([float(mcell.full_contact_pressure)]))


def _key(finger: Finger, modulus: float, index: int) -> Any:
    """What makes two members the same: their finger and modulus; a finger whose models cannot
    be hashed (a ridge model holding arrays) is its own (``index``)."""
    try:
        hash(finger)
    except TypeError:
        return ("unhashable", index)
    return (finger, modulus)


def _state_codes(peak: np.ndarray, pt: np.ndarray, pf: np.ndarray) -> np.ndarray:
    """Codes of :data:`STATES` for centre pressures ``peak`` (rows: members) against each
    member's transition and full-contact pressures (as :func:`~fingerpad.study.run.centre_state`)."""
    return np.where(peak >= pf[:, None], 2, np.where(peak >= pt[:, None], 1, 0)).astype(np.int8)


def _area_ratio_scaled(cell: Any, psi: Any, peak: np.ndarray, k: np.ndarray, breaks: Sequence[float]) -> np.ndarray:
    """``A_re/A_fr`` (Eq. 3.11) of each row of ``peak`` (centre pressures, Pa) on the cell at
    ``k`` times the base modulus, whose psi is the base's at ``p / k``.

    With ``P = peak / k`` (the base cell's pressure), Eq. 3.11 reads
    ``A_re/A_fr = 2 int_0^1 psi(P s) s ds = 2 Phi(P) / P^2`` with ``Phi(P) = int_0^P psi(u) u du``:
    one function of one variable for every member and load. ``Phi`` is accumulated over the
    sorted ``P`` of all rows, split at the cell's kinks (``breaks``), at its computed nodes (the
    interpolant is smooth between them) and on a log grid (24 per decade), with an 8-point
    Gauss-Legendre rule per piece and the graded rule of
    :func:`~fingerpad.macro.pressure.disc_average` from zero to the first point (psi ~ p^m
    there). Cost: about 8 psi evaluations per member and load, against about 1200 for the
    per-member quadrature; agreement with it ~1e-13 relative.
    """
    rows, nl = peak.shape
    big_p = (peak / k[:, None]).ravel()
    top = float(big_p.max())
    bottom = float(big_p.min())
    marks = [float(b) for b in breaks if math.isfinite(b) and 0 < b < top]
    nodes = np.asarray(cell.curve()["pressure"], float) if hasattr(cell, "curve") else np.empty(0)
    decades = math.log10(top / bottom) if top > bottom else 0.0
    log_grid = np.geomspace(bottom, top, max(2, int(math.ceil(24 * decades)) + 1))
    pts = np.unique(np.concatenate([big_p, marks, nodes[(nodes > 0) & (nodes < top)], log_grid]))
    x0, w0 = _graded_rule(16, 12)
    first = pts[0]
    phi0 = first * first * float(np.sum(w0 * x0 * psi(first * x0)))
    xg, wg = np.polynomial.legendre.leggauss(8)
    a, b = pts[:-1, None], pts[1:, None]
    u = a + 0.5 * (b - a) * (xg[None, :] + 1.0)
    pieces = np.sum(0.5 * (b - a) * wg[None, :] * u * psi(u), axis=1)
    phi = np.concatenate([[phi0], phi0 + np.cumsum(pieces)])
    idx = np.searchsorted(pts, big_p)
    return (2.0 * phi[idx] / big_p**2).reshape(rows, nl)


def _centre_pressure_loads(fingers: Sequence[Finger], targets: np.ndarray) -> np.ndarray:
    """Loads (N) at which ``1.5 F / A_fr(F)`` of each finger reaches each of its ``targets``
    (Pa, ``(fingers, n)``): ``inf`` for an infinite target, NaN for a target that is not
    positive or not crossed in :data:`~fingerpad.micro.response.DEFAULT_LOAD_RANGE` (as Brent's method in
    :func:`~fingerpad.coupling.critical_load` and :func:`~fingerpad.study.run.load_at_centre_pressure`).

    Each finger's A_fr is tabulated on a log grid (one call), the first sign change brackets
    the root, and Illinois steps in log F refine all brackets together, one call of A_fr per
    finger and step.
    """
    m, n = targets.shape
    lo, hi = (math.log(v) for v in DEFAULT_LOAD_RANGE)
    grid = np.linspace(lo, hi, int(round((hi - lo) / math.log(10) * _TABLE_PER_DECADE)) + 1)
    out = np.full((m, n), np.nan)
    out[np.isinf(targets)] = np.inf
    live = np.isfinite(targets) & (targets > 0)
    if not live.any():
        return out
    loads = np.exp(grid)
    # log of the centre pressure on the grid, one call per finger
    table = np.array([np.log(1.5 * loads / np.asarray(f.ridge_area(loads), float)) for f in fingers])
    with np.errstate(divide="ignore", invalid="ignore"):
        log_t = np.log(np.where(live, targets, 1.0))
    h = table[:, None, :] - log_t[:, :, None]  # (fingers, n, grid)
    sign = np.sign(h)
    # no crossing between the ends of the range: NaN (as Brent's method refuses)
    live &= (sign[:, :, 0] != sign[:, :, -1]) | (sign[:, :, 0] == 0)
    at_lo = live & (sign[:, :, 0] == 0)
    out[at_lo] = loads[0]
    live &= ~at_lo
    change = sign[:, :, 1:] != sign[:, :, :1]
    j = np.argmax(change, axis=2)  # first grid interval whose end differs in sign from the start
    ii, tt = np.nonzero(live)
    jj = j[ii, tt]
    xa, xb = grid[jj], grid[jj + 1]
    ha, hb = h[ii, tt, jj], h[ii, tt, jj + 1]
    exact = hb == 0
    out[ii[exact], tt[exact]] = np.exp(xb[exact])
    keep = ~exact
    ii, tt, xa, xb, ha, hb = ii[keep], tt[keep], xa[keep], xb[keep], ha[keep], hb[keep]
    logt = log_t[ii, tt]
    for _ in range(200):
        if ii.size == 0:
            break
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = xb - hb * (xb - xa) / (hb - ha)
        mid = 0.5 * (xa + xb)
        bad = ~np.isfinite(xc) | (xc <= np.minimum(xa, xb)) | (xc >= np.maximum(xa, xb))
        xc = np.where(bad, mid, xc)
        hc = np.empty_like(xc)
        for f_index in np.unique(ii):
            sel = ii == f_index
            fl = np.exp(xc[sel])
            hc[sel] = np.log(1.5 * fl / np.asarray(fingers[f_index].ridge_area(fl), float)) - logt[sel]
        flip = np.sign(hc) != np.sign(hb)
        # Illinois: the end kept twice in a row has its residual halved (superlinear, bracketed)
        xa = np.where(flip, xb, xa)
        ha = np.where(flip, hb, 0.5 * ha)
        xb, hb = xc, hc
        done = (hc == 0) | (np.abs(xb - xa) <= _ROOT_TOL * np.maximum(1.0, np.abs(xb)))
        out[ii[done], tt[done]] = np.exp(xb[done])
        keep = ~done
        ii, tt, xa, xb, ha, hb, logt = ii[keep], tt[keep], xa[keep], xb[keep], ha[keep], hb[keep], logt[keep]
    return out


def member_quantiles(values: np.ndarray, levels: Sequence[float], drop_nan: bool = False) -> np.ndarray:
    """Quantiles (numpy's default linear interpolation) of ``values`` along its first axis,
    one row per level; infinite values are kept as such (numpy gives NaN between two infinities:
    here the quantile between two infinite members is ``inf``). ``drop_nan``: members with NaN
    are left out per column (a load that none reaches); all NaN gives NaN."""
    v = np.asarray(values, float)
    q = np.asarray(levels, float)
    if drop_nan:
        cols = v.reshape(v.shape[0], -1)
        res = np.full((q.size, cols.shape[1]), np.nan)
        for c in range(cols.shape[1]):
            finite = cols[~np.isnan(cols[:, c]), c]
            if finite.size:
                res[:, c] = member_quantiles(finite, q)
        return res.reshape((q.size, *v.shape[1:]))
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # inf - inf inside numpy's interpolation
        res = np.quantile(v, q, axis=0)
    lower = np.quantile(v, q, axis=0, method="lower")
    upper = np.quantile(v, q, axis=0, method="higher")
    pos = q * (v.shape[0] - 1)
    frac = (pos - np.floor(pos)).reshape((q.size,) + (1,) * (v.ndim - 1))
    fix = np.isnan(res) & ~np.isnan(lower) & ~np.isnan(upper)
    repl = np.where(lower == upper, lower, np.where(frac > 0, upper, lower))
    return np.where(fix, repl, res)


def population_fingers(nominal: Any, members: Sequence[dict[str, float]]) -> tuple[list[Finger], list[float]]:
    """The members' fingers (the study's finger with each member's parameters, SI) and their
    reduced moduli E1* (Pa, Eq. 3.4); the nominal's BEM cell is prepared over the members'
    pressures in units of E* (no solve when the cache covers them), as
    :func:`~fingerpad.study.population.run_population` does.

    Raises
    ------
    FingerpadError
        A member's parameters that the study's finger cannot take (``ridge_fraction`` on a
        finger whose ridge model is not the constant fraction).
    """
    from .population import member_finger
    from .run import P_HIGH, P_LOW

    study = nominal.study
    fingers = [member_finger(study.finger, m) for m in members]
    mat_nu = study.material_poisson if study.material_poisson is not None else 0.35
    moduli = [f.micro_modulus(study.material_modulus, mat_nu) for f in fingers]
    cell = nominal.cell
    if nominal.bem is not None and not cell.flat:
        loads = study.loads
        lo, hi = math.inf, 0.0
        for f, e in zip(fingers, moduli, strict=True):
            p = loads / np.asarray(f.ridge_area(loads), float)
            lo, hi = min(lo, P_LOW * float(p.min()) / e), max(hi, P_HIGH * float(p.max()) / e)
        cell.prepare(lo * cell.modulus, hi * cell.modulus)
    return fingers, moduli
